"""Type stubs for `areo._areo`, the extension module (PyO3) the package `areo`
re-exports. Units are in the names: _deg degrees, _m metres, _s seconds, _h hours, _wh
watt-hours, _au astronomical units."""

from os import PathLike
from typing import Any, Literal, Optional, Union

import numpy as np
import numpy.typing as npt

__version__: str

Body = Literal["mars", "moon", "earth"]
StrPath = Union[str, PathLike[str]]

class AreoError(Exception):
    """An areo error: bad input or a failed run. `file`, `line`, `column` and `field`
    are set where the library knows them (else None)."""
    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    field: Optional[str]

class ScenarioError(AreoError):
    """A scenario file's mistake: bad RON, a value out of range, an inconsistent field."""

class Unreachable(AreoError):
    """The run ended without a plan that reaches every goal."""
    binding: str
    """The binding constraint (`Battery`, `Darkness`, `Slope`, …)."""
    message: str
    """The planner's words, with "(not a proof: …)" where the verdict holds only at the
    scenario's classes (`result.facts["unreachable_proven"]` is False)."""
    result: RunResult
    """What the run wrote before it gave up."""

class BudgetSpent(AreoError):
    """The searches stopped at the work or memory budget (`max_work`, the memory
    limit) before they had an answer: no plan, and no proof that none exists — the CLI's
    exit code 4."""
    result: RunResult
    """What the run wrote before it stopped (`facts["status"]` is "stopped")."""

def sun(time: Union[str, float], lat_deg: float, lon_east_deg: float, body: Body = "mars") -> dict[str, Any]:
    """The Sun over a site at one instant (ISO 8601 UTC text or Unix seconds):
    azimuth_deg (clockwise from north), elevation_deg (geometric), distance_au,
    subsolar_lat_deg, subsolar_lon_east_deg, local_solar_time_h, utc."""

def sun_series(
    unix_s: npt.NDArray[np.float64], lat_deg: float, lon_east_deg: float, body: Body = "mars"
) -> dict[str, npt.NDArray[np.float64]]:
    """`sun` over an array of Unix seconds: a dict of float64 arrays (no `utc`)."""

class Dem:
    """A digital elevation model (GeoTIFF, PDS3, ESRI ASCII grid)."""
    @property
    def heights(self) -> npt.NDArray[np.float32]:
        """(rows, cols) heights, m, row 0 northernmost; NaN where no data. Read-only,
        the same array at every access (`.copy()` for one to change)."""
    @property
    def cols(self) -> int: ...
    @property
    def rows(self) -> int: ...
    @property
    def cell_size(self) -> tuple[float, float]:
        """(dx, dy), m."""
    @property
    def geotransform(self) -> tuple[float, float, float, float, float, float]:
        """GDAL's (x0, dx, 0, y_top, 0, -dy), map metres."""
    @property
    def crs(self) -> str:
        """The coordinate reference system, OGC WKT2."""
    def sun_over(self, utc: str) -> dict[str, Any]:
        """The Sun over the map's middle at `utc` on the body the map names (`areo terrain
        shadow --utc`): `utc`, `body`, `lat_deg`, `lon_east_deg`, `azimuth_deg` (from true
        north), `grid_azimuth_deg` (from the grid's north: what `shadow` takes; it
        differs on a polar map whose central meridian is not the middle's),
        `elevation_deg`. Raises `AreoError` for a map with no place on a known body."""

def read_dem(path: StrPath) -> Dem: ...
def read_layer(path: StrPath) -> dict[str, Any]:
    """Any raster's values: `values` ((rows, cols) float64, NaN no data), `geotransform`
    (GDAL order, map metres of cell corners), `crs` (OGC WKT2)."""
def shadow(dem: Dem, azimuth_deg: float, elevation_deg: float, curved: bool = True) -> npt.NDArray[np.uint8]:
    """(rows, cols): 1 lit, 0 in shadow, 255 no data; `curved`: on the body's sphere.
    `azimuth_deg` is clockwise from the grid's north (`Dem.sun_over(...)["grid_azimuth_deg"]`)."""
def horizon(dem: Dem, sectors: int, curved: bool = True) -> npt.NDArray[np.float32]:
    """(sectors, rows, cols) horizon elevation, degrees; sector k centred on k·360°/K."""

class RunResult:
    """What a scenario run produced."""
    @property
    def facts(self) -> dict[str, Any]:
        """Named facts (numbers in the unit their name gives, counts, flags, text): the
        report's scalar fields by path (`a.b` is `report["a"]["b"]`)."""
    @property
    def report(self) -> Optional[dict[str, Any]]:
        """The job's report as `areo run --json` prints it: tables as dicts of NumPy
        columns, rasters as `(rows, cols)` arrays, `report["job"]` the job's name."""
    @property
    def summary(self) -> list[str]: ...
    @property
    def files(self) -> list[PathLike[str]]: ...
    @property
    def out(self) -> PathLike[str]: ...
    @property
    def tables(self) -> dict[str, dict[str, Any]]:
        """The report's tables (plan, executed, replans, monte_carlo, seeds, …, named as
        the CSV each is written to), each a dict of columns: NumPy arrays for numbers
        (absent: NaN) and flags, lists for text."""
    def table(self, name: str) -> dict[str, Any]:
        """One of `tables` by name; KeyError if the report has none."""
    def table_array(self, name: str) -> np.recarray:
        """One table as a NumPy record array: float64 columns for numbers (absent:
        NaN), bool for flags, text columns for text."""

class Scenario:
    """A scenario file and the fields set on it."""
    @staticmethod
    def load(path: StrPath) -> Scenario: ...
    def set(self, field: str, value: Union[float, int, bool, str]) -> Scenario:
        """Set a field as `areo run --set` does (`job.tau`, `job.goals[0].x_m`); text is
        RON (`'"words"'` for a string). Raises ScenarioError naming a bad field."""
    @property
    def sets(self) -> list[str]: ...
    def run(
        self,
        out: Optional[StrPath] = None,
        max_work: Optional[float] = None,
        max_memory_gb: Optional[float] = None,
    ) -> RunResult:
        """Run with the GIL released (Ctrl-C interrupts); raises Unreachable.
        `max_work` (elementary steps, 1..1e18) and `max_memory_gb` (GiB) are the CLI's
        --max-work and --max-memory-gb: over them a job is refused before it starts,
        and its searches stop where the work or the memory budget ends (AreoError)."""

def rover_check(
    params_path: StrPath,
    terrain: str = "flat",
    mu: float = 0.6,
    moving: bool = False,
    body: Body = "mars",
) -> dict[str, Any]:
    """A rover file on a test terrain (flat, slope:DEG, side-slope:DEG, step:HEIGHT_M):
    the report `areo rover check --format json` prints. A parameter file gets wheel
    loads and the friction that holds (mu, moving); a TEMPEST resource model (flat or
    a slope) its drive power and Wh/km, array and battery figures, in `body`'s
    gravity where the file gives none."""
