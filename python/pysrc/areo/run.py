"""A finished run read back from its directory, without running it again.

`areo.open("out/NAME")` gives a `Run`: its facts (`facts.json`) as a dict, every CSV
table as a pandas DataFrame whose `utc` and `*_utc` columns are datetime64 (UTC), every
map as an xarray DataArray with x/y coordinates (map metres of cell centres), units, a
description and the CRS in a `spatial_ref` coordinate (the CF grid-mapping convention
that rioxarray and GDAL read), and the shadow series as one time-indexed DataArray.
pandas and xarray are needed only here (`pip install "areo[data]"`).
"""

from __future__ import annotations

import builtins
import json
from pathlib import Path
import os
from typing import Any, Union

import numpy as np

from ._areo import AreoError, read_layer

# What each map a run writes holds: its units (UDUNITS; "1" for a code or a flag) and
# a description — docs/outputs.md gives the same meanings.
LAYERS = {
    "dem": ("m", "elevation of the planner's map (as sensed, after a simulated run)"),
    "slope": ("degree", "slope of the planner's map"),
    "direct_sun": ("1", "direct sun on the true terrain: 1 lit, 0 in shadow or night"),
    "no_go": ("1", "what keeps a cell out: 0 free, 1 the mask, 2 within its inflation, 3 cut off from the start"),
    "classes": ("1", "terrain class id (the scenario's terrain_classes)"),
}

StrPath = Union[str, "os.PathLike[str]"]


def _needs(module: str):
    try:
        return __import__(module)
    except ImportError as e:
        raise ImportError(f"areo.open needs {module}: pip install 'areo[data]' ({e})") from e


def open(path: StrPath) -> "Run":  # noqa: A001 - `areo.open`, as `xarray.open_dataset`
    """Opens the run written to `path`: the directory holding its `facts.json`
    (`out/NAME`), or an output directory holding one run's directory (`out`)."""
    return Run(path)


class Run:
    """A finished run's outputs: facts, tables, maps and the shadow series (see the
    module's documentation)."""

    def __init__(self, path: StrPath):
        given = Path(path)
        if not given.is_dir():
            raise AreoError(f"{given}: not a directory (a run's outputs: out/NAME, holding facts.json)")
        runs = [given] if (given / "facts.json").is_file() else sorted(p.parent for p in given.glob("*/facts.json"))
        if len(runs) != 1:
            found = ", ".join(p.name for p in runs) or "none"
            raise AreoError(f"{given}: expected one run's outputs (a facts.json here or in one directory below); found {found}")
        self.path: Path = runs[0]
        """The run's directory."""
        self.name: str = self.path.name
        """The run's name: its directory's (`areo run` names it after the scenario file)."""
        with builtins.open(self.path / "facts.json", encoding="utf-8") as f:
            self.facts: dict[str, Any] = json.load(f)
            """The run's facts by name, as `facts.json` holds them."""
        self._tables: dict[str, Any] = {}
        self._shadows: Any = None

    def __repr__(self) -> str:
        return f"Run({self.name!r}: {len(self.facts)} facts, tables {self.table_names}, maps {self.layer_names})"

    @property
    def table_names(self) -> list[str]:
        """The CSV tables the run wrote, by name (`plan`, `replans`, `monte_carlo`, …)."""
        return sorted(p.stem for p in self.path.glob("*.csv"))

    def table(self, name: str):
        """The table `NAME.csv` as a pandas DataFrame: numbers as numbers, the `utc`
        and `*_utc` columns as datetime64[ns, UTC]. KeyError if the run has none."""
        if name not in self._tables:
            pd = _needs("pandas")
            path = self.path / f"{name}.csv"
            if not path.is_file():
                raise KeyError(f"{name}: the run wrote no {path.name} (its tables: {', '.join(self.table_names)})")
            df = pd.read_csv(path)
            for column in df.columns:
                if column == "utc" or column.endswith("_utc"):
                    df[column] = pd.to_datetime(df[column], utc=True, format="ISO8601")
            self._tables[name] = df
        return self._tables[name]

    @property
    def plan(self):
        """The plan's waypoints (`plan.csv`) as a DataFrame ([`Run.table`])."""
        return self.table("plan")

    @property
    def layer_names(self) -> list[str]:
        """The maps the run wrote (`dem`, `slope`, `direct_sun`, …)."""
        return sorted(p.stem for p in self.path.glob("*.tif"))

    def layer(self, name: str):
        """The map `NAME.tif` as an xarray DataArray: dims (y, x), coordinates in the
        map's metres at cell centres (y falling southward), float64 with NaN where the
        file has no data, `units` and `long_name` attributes, the CRS as OGC WKT2 in
        the `spatial_ref` coordinate. KeyError if the run wrote no such map."""
        path = self.path / f"{name}.tif"
        if not path.is_file():
            raise KeyError(f"{name}: the run wrote no {path.name} (its maps: {', '.join(self.layer_names)})")
        return _data_array(path, name)

    @property
    def shadows(self):
        """The direct sun through the run (`shadows/`) as one DataArray of dims
        (time, y, x): float32 (1 lit, 0 in shadow, NaN no data), `time` in
        datetime64[ns] UTC from `shadows/index.json` (read once). None if the run wrote no
        series."""
        index = self.path / "shadows" / "index.json"
        if not index.is_file():
            return None
        if self._shadows is not None:
            return self._shadows
        xr, pd = _needs("xarray"), _needs("pandas")
        with builtins.open(index, encoding="utf-8") as f:
            entries = json.load(f)
        frames = [_data_array(index.parent / e["file"], "direct_sun") for e in entries]
        times = pd.to_datetime([e["unix_s"] for e in entries], unit="s")
        series = xr.concat([f.astype(np.float32) for f in frames], dim=pd.Index(times, name="time"))
        series.attrs = frames[0].attrs | {"source": str(index)}
        self._shadows = series
        return series

    def plot_route(self, ax=None, layer: str = "dem"):
        """The route over the map's hillshade (`areo.plot.route`)."""
        from . import plot

        return plot.route(self, ax=ax, layer=layer)

    def plot_battery(self, ax=None):
        """The battery over time (`areo.plot.battery`)."""
        from . import plot

        return plot.battery(self, ax=ax)


def _data_array(path: Path, name: str):
    xr = _needs("xarray")
    read = read_layer(str(path))
    values, transform, wkt = read["values"], read["geotransform"], read["crs"]
    x0, dx, _, y_top, _, minus_dy = transform
    rows, cols = values.shape
    units, description = LAYERS.get(name, ("1", name))
    # CF's grid mapping, as rioxarray writes it: the WKT under both names it reads and
    # GDAL's geotransform (cell corners) beside it.
    spatial_ref = xr.DataArray(
        0, attrs={"crs_wkt": wkt, "spatial_ref": wkt, "GeoTransform": " ".join(repr(float(v)) for v in transform)}
    )
    x = xr.DataArray(x0 + dx * (np.arange(cols) + 0.5), dims="x", attrs={"units": "m", "axis": "X"})
    y = xr.DataArray(y_top + minus_dy * (np.arange(rows) + 0.5), dims="y", attrs={"units": "m", "axis": "Y"})
    attrs = {"units": units, "long_name": description, "grid_mapping": "spatial_ref", "source": str(path)}
    attrs.update(_categories(path))
    return xr.DataArray(values, dims=("y", "x"), coords={"y": y, "x": x, "spatial_ref": spatial_ref}, name=name, attrs=attrs)


def _categories(path: Path) -> dict[str, Any]:
    """A map of codes' names from GDAL's sidecar (`NAME.tif.aux.xml`), as CF's
    `flag_values` and `flag_meanings` (names with spaces joined by underscores) and as
    `categories` ({code: name}); nothing without a sidecar."""
    import xml.etree.ElementTree as ElementTree

    sidecar = path.with_name(path.name + ".aux.xml")
    if not sidecar.is_file():
        return {}
    names = [c.text or "" for c in ElementTree.parse(sidecar).getroot().iter("Category")]
    named = {code: name for code, name in enumerate(names) if name}
    return {
        "categories": named,
        "flag_values": np.array(list(named), dtype=np.uint8),
        "flag_meanings": " ".join(name.replace(" ", "_") for name in named.values()),
    }


def cell_centres(layer, cols, rows) -> tuple[np.ndarray, np.ndarray]:
    """The map coordinates of cells (`cols`, `rows`: arrays of indices) on `layer`'s
    grid, m."""
    x0, dx, _, y_top, _, minus_dy = (float(v) for v in layer["spatial_ref"].attrs["GeoTransform"].split())
    return x0 + dx * (np.asarray(cols) + 0.5), y_top + minus_dy * (np.asarray(rows) + 0.5)
