# %% [markdown]
# # areo from Python: Gale's shadows and a traverse under two skies
#
# A notebook as a plain script (`# %%` cells: VS Code, Jupytext and Spyder run them as
# cells; CI runs the file). It loads a MOLA crop of Gale crater, draws its shadows at a
# low morning Sun, then plans TEMPEST's valley-detour traverse under a clear and a dusty
# sky and compares what the two plans cost.
#
# Run from the repository's root: `python python/examples/gale_shadows_and_valley.py
# [OUT_DIR]` (default: a temporary directory).

# %%
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files, not windows: runs anywhere
import matplotlib.pyplot as plt
import numpy as np

import areo

ROOT = Path(__file__).resolve().parents[2]
OUT = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="areo-example-"))
OUT.mkdir(parents=True, exist_ok=True)

# %% The DEM: heights as a NumPy array, its cell size and its CRS.
dem = areo.read_dem(ROOT / "crates/terrain/tests/data/gale_mola_crop_64.tif")
z = dem.heights
print(dem, f"heights {np.nanmin(z):.0f} .. {np.nanmax(z):.0f} m")
print(dem.crs[:60], "…")

# %% Where the Sun stands over Gale on MSL's landing morning, and the shadows it casts.
sun = areo.sun("2012-08-06T21:00:00Z", -5.27, 137.67)
print(f"Sun at azimuth {sun['azimuth_deg']:.1f}°, elevation {sun['elevation_deg']:.1f}°, "
      f"{sun['local_solar_time_h']:.2f} h local solar time")
elevation = max(sun["elevation_deg"], 5.0)
lit = areo.shadow(dem, sun["azimuth_deg"], elevation)
dx, dy = dem.cell_size
extent = [0, dem.cols * dx / 1000, 0, dem.rows * dy / 1000]
fig, ax = plt.subplots(1, 2, figsize=(10, 4.5))
ax[0].imshow(z, cmap="terrain", extent=extent)
ax[0].set_title("Gale (MOLA), heights")
ax[1].imshow(np.where(lit == 255, np.nan, lit), cmap="gray", extent=extent)
ax[1].set_title(f"Direct sun at {sun['azimuth_deg']:.0f}°, {elevation:.1f}° up")
for a in ax:
    a.set_xlabel("km east")
    a.set_ylabel("km north")
fig.tight_layout()
fig.savefig(OUT / "gale_shadows.png", dpi=100)
print(f"shadowed: {np.mean(lit == 0):.1%} of cells; wrote {OUT / 'gale_shadows.png'}")

# %% Valley-detour under a clear sky (τ = 0.5, as shipped) and a dustier one (τ = 0.7).
# The initial plans only (`job.simulate` off: the traverse itself, with its re-plans as the
# rover finds the pass closed, is what `areo run scenarios/valley-detour.ron` simulates).
# Both are exact on the scenario's 60 s tick; if a sky left no way to the goals, areo
# would raise `Unreachable`, which carries what the run wrote and what binds.
rows = []
for tau in (0.5, 0.7):
    scenario = areo.Scenario.load(ROOT / "scenarios/valley-detour.ron").set("job.tau", tau).set("job.simulate", "None")
    try:
        result, why = scenario.run(out=OUT / f"tau_{tau}"), "planned"
    except areo.Unreachable as stop:
        result, why = stop.result, f"unreachable: {stop.binding}"
    f = result.facts
    rows.append((tau, f.get("initial_plan_duration_h", float("nan")), f.get("initial_plan_wait_steps", 0), why))
print(f"{'tau':>5} {'plan h':>8} {'waits':>6}  outcome")
for tau, hours, waits, why in rows:
    print(f"{tau:>5} {hours:>8.2f} {waits:>6}  {why}")
# A dustier sky gives the array less: the initial plan cannot be faster.
assert rows[1][1] >= rows[0][1] - 1e-9, rows
