"""areo for Python: the Sun over a site, DEMs and their shadows and horizons as NumPy
arrays, scenarios run from Python, and a finished run opened as pandas and xarray.

The computing is the extension `areo._areo` (the library crates the `areo` binary
calls, with no logic of their own); `areo.open` reads a run's files back
(`areo.run`), and `areo.plot` draws the route and the battery with matplotlib.
"""

from ._areo import (
    AreoError,
    BudgetSpent,
    Dem,
    RunResult,
    Scenario,
    ScenarioError,
    Unreachable,
    __version__,
    horizon,
    read_dem,
    read_layer,
    rover_check,
    shadow,
    sun,
    sun_series,
)
from .run import Run, open

__all__ = [
    "AreoError",
    "BudgetSpent",
    "Dem",
    "Run",
    "RunResult",
    "Scenario",
    "ScenarioError",
    "Unreachable",
    "__version__",
    "horizon",
    "open",
    "read_dem",
    "read_layer",
    "rover_check",
    "shadow",
    "sun",
    "sun_series",
]
