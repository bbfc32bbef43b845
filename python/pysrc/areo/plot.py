"""Plots of a finished run (`areo.open`) with matplotlib: the route over the map's
hillshade, and the battery over time. Each draws on `ax` (a new figure's axes when
None) and returns it, so that a notebook can add to it."""

from __future__ import annotations

import numpy as np

from .run import Run, cell_centres


def hillshade(heights: np.ndarray, dx: float, dy: float, azimuth_deg: float = 315.0, altitude_deg: float = 45.0):
    """Lambertian shading of `heights` (rows north to south, cells `dx` × `dy` m) lit
    from `azimuth_deg` (clockwise from grid north) at `altitude_deg`: 0 to 1, NaN where
    a height is missing."""
    dz_drow, dz_dcol = np.gradient(heights, dy, dx)
    # Rows run southward: the northward slope is minus the slope along the rows.
    east, north = dz_dcol, -dz_drow
    az, alt = np.radians(azimuth_deg), np.radians(altitude_deg)
    light = np.array([np.sin(az) * np.cos(alt), np.cos(az) * np.cos(alt), np.sin(alt)])
    norm = np.sqrt(east**2 + north**2 + 1.0)
    return np.clip((-east * light[0] - north * light[1] + light[2]) / norm, 0.0, 1.0)


def _axes(ax):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    return plt.subplots(figsize=(7, 5))[1]


def route(run: Run, ax=None, layer: str = "dem"):
    """The plan's route (its waypoints' cells, `plan.csv`'s `col` and `row`) over the
    hillshade of `layer`, in the map's metres; the start and each goal marked."""
    ax = _axes(ax)
    dem = run.layer(layer)
    x, y = dem["x"].values, dem["y"].values
    dx, dy = abs(x[1] - x[0]) if len(x) > 1 else 1.0, abs(y[1] - y[0]) if len(y) > 1 else 1.0
    shade = hillshade(dem.values, dx, dy) if layer == "dem" else dem.values
    extent = (x[0] - dx / 2, x[-1] + dx / 2, y[-1] - dy / 2, y[0] + dy / 2)
    ax.imshow(shade, cmap="gray", extent=extent, origin="upper", interpolation="nearest")
    plan = run.plan
    px, py = cell_centres(dem, plan["col"].to_numpy(), plan["row"].to_numpy())
    ax.plot(px, py, color="tab:orange", lw=1.5, label="route")
    ax.plot(px[:1], py[:1], "o", color="tab:green", label="start")
    goals = plan["goal"].notna().to_numpy()
    ax.plot(px[goals], py[goals], "*", color="tab:red", ms=12, label="goal")
    for gx, gy, name in zip(px[goals], py[goals], plan["goal"][goals]):
        ax.annotate(str(name), (gx, gy), textcoords="offset points", xytext=(6, 6))
    ax.set(xlabel="x, m", ylabel="y, m", title=f"{run.name}: route over {layer}")
    ax.set_aspect("equal")
    ax.legend(loc="best")
    return ax


def battery(run: Run, ax=None):
    """The battery (`plan.csv`'s `battery_wh`, at each waypoint's start) over UTC, the
    goals marked where they are reached."""
    ax = _axes(ax)
    plan = run.plan
    ax.plot(plan["utc"], plan["battery_wh"], color="tab:blue", label="battery")
    reached = plan[plan["goal"].notna()]
    for when, name in zip(reached["utc"], reached["goal"]):
        ax.axvline(when, color="tab:red", lw=0.8, ls="--")
        ax.annotate(str(name), (when, plan["battery_wh"].max()), rotation=90, va="top", ha="right")
    ax.set(xlabel="UTC", ylabel="battery, Wh", title=f"{run.name}: battery")
    ax.legend(loc="best")
    return ax
