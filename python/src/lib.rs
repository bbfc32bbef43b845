//! `areo._areo`, the extension inside the Python package `areo`: the library crates'
//! answers as Python values and NumPy arrays, with no logic of their own beyond the
//! conversion. (`areo.open` and the plot helpers, which read a finished run's files
//! into pandas and xarray, are Python: `pysrc/areo`.)
//!
//! - `sun`, `sun_series`: where the Sun stands over a site on Mars, the Moon or the
//!   Earth (areo-ephemeris), at one instant or an array of them;
//! - `read_dem` → `PyDem` (heights as a NumPy array, cell size, geotransform, CRS),
//!   `read_layer` (any raster's values with its georeference), `shadow` and `horizon`
//!   (areo-terrain) as arrays;
//! - `PyScenario`: a scenario loaded, its fields set as a sweep sets them, run, and
//!   its facts and tables read back (`PyRunResult`); an unreachable goal raises
//!   `areo.Unreachable`;
//! - `rover_check`: a rover parameter file on a test terrain (areo-scenario).
//!
//! Errors are Python exceptions — `areo.AreoError`, and `areo.ScenarioError` for a
//! scenario's own mistakes — carrying `file`, `line`, `column` and `field` where the
//! library knows them. Long work runs with the GIL released; a scenario run polls for
//! Ctrl-C while it works.

use std::path::{Path, PathBuf};
use std::time::Duration;

use areo_ephemeris::{Body, Site, SunModel};
use areo_scenario::{Error, Failure, NoProgress, Outcome, RunOptions};
use areo_terrain::Dem;
use areo_terrain::horizon::HorizonMap;
use areo_terrain::shadow::{Curvature, GridSunDirection, Shadows};
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyDict, PyList};

create_exception!(areo, AreoError, PyException, "An areo library error: bad input or a failed run.");
create_exception!(
    areo,
    ScenarioError,
    AreoError,
    "A scenario file's mistake: bad RON, a value out of range, an inconsistent field."
);
create_exception!(areo, Unreachable, AreoError, "The run ended without a plan that reaches every goal.");
create_exception!(
    areo,
    BudgetSpent,
    AreoError,
    "The searches stopped at the work or memory budget before they had an answer: no plan, and no proof that none exists."
);

/// The exception for a library error, with `file`, `line`, `column` and `field` set
/// (None where the error does not say).
fn to_py(py: Python<'_>, e: &Error) -> PyErr {
    let (file, line, col, field): (Option<&Path>, Option<usize>, Option<usize>, Option<&str>) = match e {
        Error::Syntax { path, line, col, .. } => (Some(path), Some(*line), Some(*col), None),
        Error::Invalid { path, line, col, field, .. } => (Some(path), Some(*line), Some(*col), Some(field)),
        Error::Scenario { path, field, .. } | Error::Referenced { path, field, .. } => {
            (Some(path), None, None, Some(field))
        }
        Error::Read { path, .. }
        | Error::Grid { path, .. }
        | Error::Io { path, .. }
        | Error::WorkSpent { path, .. }
        | Error::MemorySpent { path, .. } => (Some(path), None, None, None),
        Error::Terrain(t) => (t.path(), None, None, None),
        _ => (None, None, None, None),
    };
    let scenario = matches!(e, Error::Syntax { .. } | Error::Invalid { .. } | Error::Scenario { .. });
    let spent = e.exit_code() == 4;
    let err = if scenario {
        ScenarioError::new_err(e.to_string())
    } else if spent {
        BudgetSpent::new_err(e.to_string())
    } else {
        AreoError::new_err(e.to_string())
    };
    let value = err.value(py);
    // Setting an attribute on a fresh exception cannot fail.
    let _ = value.setattr("file", file.map(|p| p.display().to_string()));
    let _ = value.setattr("field", field);
    let _ = value.setattr("line", line);
    let _ = value.setattr("column", col);
    err
}

fn body_of(name: &str) -> PyResult<Body> {
    Body::from_name(name).ok_or_else(|| PyValueError::new_err(format!("body {name:?}: allowed mars, moon, earth")))
}

/// The body named and the site on it (planetocentric latitude, east longitude, °).
fn place(body: &str, lat_deg: f64, lon_east_deg: f64) -> PyResult<(Body, Site)> {
    let body = body_of(body)?;
    let site = Site::on(body, lat_deg, lon_east_deg).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((body, site))
}

/// An instant: ISO 8601 UTC text, or seconds since 1970-01-01T00:00:00 UTC.
fn epoch_of(time: &Bound<'_, PyAny>) -> PyResult<hifitime::Epoch> {
    if let Ok(text) = time.extract::<String>() {
        return areo_ephemeris::parse_utc(&text).map_err(|e| PyValueError::new_err(e.to_string()));
    }
    let s: f64 =
        time.extract().map_err(|_| PyValueError::new_err("time: ISO 8601 UTC text or Unix seconds (a number)"))?;
    Ok(hifitime::Epoch::from_unix_seconds(s))
}

/// The Sun's place for one instant: (azimuth °, elevation °, distance AU, sub-solar
/// latitude °, sub-solar longitude ° east, local solar time h).
fn sun_at(body: Body, site: &Site, at: hifitime::Epoch) -> [f64; 6] {
    let state = body.sun(at);
    let p = state.at_site(site);
    let (lat, lon) = state.subsolar_deg();
    [p.azimuth_deg, p.elevation_deg, state.distance_au, lat, lon, state.local_solar_time_hours(site.lon_east_deg())]
}

const SUN_KEYS: [&str; 6] =
    ["azimuth_deg", "elevation_deg", "distance_au", "subsolar_lat_deg", "subsolar_lon_east_deg", "local_solar_time_h"];

/// The Sun over a site at one instant: a dict of `azimuth_deg` (clockwise from north),
/// `elevation_deg` (above the site's horizontal, geometric), `distance_au`,
/// `subsolar_lat_deg`, `subsolar_lon_east_deg`, `local_solar_time_h` and `utc`.
/// `time` is ISO 8601 UTC text or Unix seconds; latitude and east longitude in
/// degrees (planetocentric); `body` is "mars", "moon" or "earth".
#[pyfunction]
#[pyo3(signature = (time, lat_deg, lon_east_deg, body = "mars"))]
fn sun<'py>(
    py: Python<'py>,
    time: &Bound<'py, PyAny>,
    lat_deg: f64,
    lon_east_deg: f64,
    body: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let (body, site) = place(body, lat_deg, lon_east_deg)?;
    let at = epoch_of(time)?;
    let d = PyDict::new(py);
    for (k, v) in SUN_KEYS.iter().zip(sun_at(body, &site, at)) {
        d.set_item(k, v)?;
    }
    d.set_item("utc", areo_ephemeris::format_utc(at))?;
    Ok(d)
}

/// [`sun`] over an array of instants (Unix seconds, float64): a dict of float64
/// arrays with the same keys (no `utc`).
#[pyfunction]
#[pyo3(signature = (unix_s, lat_deg, lon_east_deg, body = "mars"))]
fn sun_series<'py>(
    py: Python<'py>,
    unix_s: PyReadonlyArray1<'py, f64>,
    lat_deg: f64,
    lon_east_deg: f64,
    body: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let (body, site) = place(body, lat_deg, lon_east_deg)?;
    let times = unix_s.as_slice()?.to_vec();
    let rows: Vec<[f64; 6]> =
        py.detach(|| times.iter().map(|&s| sun_at(body, &site, hifitime::Epoch::from_unix_seconds(s))).collect());
    let d = PyDict::new(py);
    for (j, k) in SUN_KEYS.iter().enumerate() {
        d.set_item(k, PyArray1::from_vec(py, rows.iter().map(|r| r[j]).collect()))?;
    }
    Ok(d)
}

/// A digital elevation model read by areo (GeoTIFF, PDS3, ASCII grid).
#[pyclass(name = "Dem", frozen, module = "areo")]
struct PyDem {
    dem: Dem,
    /// The file it was read from (named in errors).
    path: PathBuf,
    /// The heights as NumPy holds them: made once when read, handed out as is.
    heights: Py<PyArray2<f32>>,
}

impl PyDem {
    fn new(py: Python<'_>, dem: Dem, path: PathBuf) -> PyResult<PyDem> {
        let z: Vec<f32> =
            dem.elevations().iter().zip(dem.valid_mask()).map(|(&z, &ok)| if ok { z } else { f32::NAN }).collect();
        // The vector becomes the array's buffer (no copy); read-only, as the shadows and
        // horizons computed from this Dem use the heights as read.
        let heights = PyArray1::from_vec(py, z).reshape([dem.rows(), dem.cols()])?;
        heights.call_method("setflags", (), Some(&[("write", false)].into_py_dict(py)?))?;
        Ok(PyDem { dem, path, heights: heights.unbind() })
    }
}

#[pymethods]
impl PyDem {
    /// Heights, m, as a read-only (rows, cols) float32 array, row 0 the northernmost;
    /// NaN where the file has no data. The same array at every access (made once when
    /// the DEM was read); `heights.copy()` for one to change.
    #[getter]
    fn heights<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        self.heights.bind(py).clone()
    }

    /// Columns (west to east).
    #[getter]
    fn cols(&self) -> usize {
        self.dem.cols()
    }

    /// Rows (north to south).
    #[getter]
    fn rows(&self) -> usize {
        self.dem.rows()
    }

    /// Cell size (dx, dy), m.
    #[getter]
    fn cell_size(&self) -> (f64, f64) {
        (self.dem.dx(), self.dem.dy())
    }

    /// The GDAL geotransform (x0, dx, 0, y_top, 0, −dy): map metres of cell corners.
    #[getter]
    fn geotransform(&self) -> (f64, f64, f64, f64, f64, f64) {
        let d = &self.dem;
        (d.x0(), d.dx(), 0.0, d.y_top(), 0.0, -d.dy())
    }

    /// The map's coordinate reference system as OGC WKT2 (the body's sphere or
    /// ellipsoid and the projection the file declared; a local engineering frame for a
    /// map with none).
    #[getter]
    fn crs(&self) -> String {
        self.dem.georef().wkt()
    }

    /// Where the Sun stands over the map's middle at `utc` (ISO 8601), on the body the
    /// map's georeference names — what `areo terrain shadow --utc` uses: a dict of
    /// `utc`, `body`, `lat_deg`, `lon_east_deg`, `azimuth_deg` (clockwise from true
    /// north), `grid_azimuth_deg` (clockwise from the grid's north, up in the image:
    /// the azimuth `shadow` takes; it differs on a polar map whose central meridian is
    /// not the middle's) and `elevation_deg`.
    fn sun_over<'py>(&self, py: Python<'py>, utc: &str) -> PyResult<Bound<'py, PyDict>> {
        let grid = areo_scenario::terrain::Grid::of(&self.dem);
        let sun = areo_scenario::terrain::sun_over(&self.path, &grid, utc).map_err(|e| to_py(py, &e))?;
        let out = PyDict::new(py);
        out.set_item("utc", sun.utc)?;
        out.set_item("body", sun.body)?;
        out.set_item("lat_deg", sun.lat_deg)?;
        out.set_item("lon_east_deg", sun.lon_east_deg)?;
        out.set_item("azimuth_deg", sun.azimuth_deg)?;
        out.set_item("grid_azimuth_deg", sun.grid_azimuth_deg)?;
        out.set_item("elevation_deg", sun.elevation_deg)?;
        Ok(out)
    }

    fn __repr__(&self) -> String {
        let d = &self.dem;
        format!("Dem({} × {} cells of {} × {} m)", d.cols(), d.rows(), d.dx(), d.dy())
    }
}

/// Reads a DEM (GeoTIFF, PDS3 `.img`/`.lbl`, ESRI ASCII grid).
#[pyfunction]
fn read_dem(py: Python<'_>, path: PathBuf) -> PyResult<PyDem> {
    let read = py.detach(|| areo_scenario::terrain::read_dem(&path));
    PyDem::new(py, read.map_err(|e| to_py(py, &e))?, path)
}

/// A raster areo wrote or reads (GeoTIFF of any sample type, ESRI ASCII grid) as its
/// values: a dict of `values` (a (rows, cols) float64 array, row 0 the northernmost,
/// NaN where the file has no data), `geotransform` (GDAL order: map metres of cell
/// corners) and `crs` (OGC WKT2) — what `areo.open` turns into an xarray DataArray.
#[pyfunction]
fn read_layer<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let read = py.detach(|| areo_terrain::read_values(&path).map_err(Error::Terrain));
    let layer = read.map_err(|e| to_py(py, &e))?;
    let g = &layer.grid;
    let (cols, rows) = (g.cols(), g.rows());
    let values: Vec<f64> = (0..rows)
        .flat_map(|r| (0..cols).map(move |c| (c, r)))
        .map(|(c, r)| layer.at(c, r).unwrap_or(f64::NAN))
        .collect();
    let out = PyDict::new(py);
    out.set_item("values", PyArray1::from_vec(py, values).reshape([rows, cols])?)?;
    out.set_item("geotransform", (g.x0(), g.dx(), 0.0, g.y_top(), 0.0, -g.dy()))?;
    out.set_item("crs", g.georef().wkt())?;
    Ok(out)
}

fn curvature(dem: &Dem, curved: bool) -> Curvature {
    if curved { Curvature::of(dem) } else { Curvature::Flat }
}

/// The direct-sun map for a Sun at (azimuth °, clockwise from the grid's north — up in
/// the image, true north unless the map is polar with another central meridian
/// (`Dem.sun_over` gives both); elevation °):
/// a (rows, cols) uint8 array, 1 lit, 0 in shadow (cast or self), 255 no data — the
/// values `areo terrain shadow` writes. `curved`: the ground drops away on the body's
/// sphere (else a flat world).
#[pyfunction]
#[pyo3(signature = (dem, azimuth_deg, elevation_deg, curved = true))]
fn shadow<'py>(
    py: Python<'py>,
    dem: &PyDem,
    azimuth_deg: f64,
    elevation_deg: f64,
    curved: bool,
) -> PyResult<Bound<'py, PyArray2<u8>>> {
    if !(azimuth_deg.is_finite() && (-90.0..=90.0).contains(&elevation_deg)) {
        return Err(PyValueError::new_err(format!(
            "Sun at azimuth {azimuth_deg}°, elevation {elevation_deg}°: allowed a finite azimuth and −90..=90°"
        )));
    }
    let d = &dem.dem;
    let map = py.detach(|| {
        Shadows::new(GridSunDirection::new(azimuth_deg, elevation_deg), curvature(d, curved)).map(d).to_u8()
    });
    PyArray1::from_vec(py, map).reshape([d.rows(), d.cols()])
}

/// The horizon in `sectors` azimuth sectors (16..=360; sector k centred on k·360°/K):
/// a (sectors, rows, cols) float32 array of the terrain's horizon elevation, degrees.
#[pyfunction]
#[pyo3(signature = (dem, sectors, curved = true))]
fn horizon<'py>(py: Python<'py>, dem: &PyDem, sectors: usize, curved: bool) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let d = &dem.dem;
    let map = py
        .detach(|| HorizonMap::compute(d, sectors, curvature(d, curved)))
        .map_err(|e| to_py(py, &Error::Terrain(e)))?;
    let cells = d.cols() * d.rows();
    let mut out = vec![0f32; sectors * cells];
    for i in 0..cells {
        for (s, v) in map.cell_profile(i).into_iter().enumerate() {
            out[s * cells + i] = v;
        }
    }
    PyArray1::from_vec(py, out).reshape([sectors, d.rows(), d.cols()])
}

/// A scenario file, with the fields set on it so far.
#[pyclass(name = "Scenario", module = "areo")]
struct PyScenario {
    path: PathBuf,
    sets: Vec<String>,
}

/// A RON literal for a Python value: numbers and booleans as such; text as given (RON
/// text: `"\"words\""` for a string, `Moon` for a variant).
fn ron_literal(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(b) = value.extract::<bool>() {
        return Ok(b.to_string());
    }
    if let Ok(i) = value.extract::<i64>() {
        return Ok(i.to_string());
    }
    if let Ok(x) = value.extract::<f64>() {
        if !x.is_finite() {
            return Err(PyValueError::new_err(format!("{x}: a field's value must be finite")));
        }
        // `{:?}` keeps a decimal point, so RON reads a float.
        return Ok(format!("{x:?}"));
    }
    value.extract::<String>().map_err(|_| PyValueError::new_err("a value: a number, a bool or RON text"))
}

#[pymethods]
impl PyScenario {
    /// Loads and validates a scenario file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<PyScenario> {
        let loaded = py.detach(|| areo_scenario::format::load(&path));
        loaded.map_err(|e| to_py(py, &e))?;
        Ok(PyScenario { path, sets: Vec::new() })
    }

    /// Sets a field, as `areo run --set` and a sweep's axis do (`job.tau`,
    /// `job.goals[0].x_m`), and validates the scenario with it: a bad path or value
    /// raises `ScenarioError` naming the field. Returns the scenario, so calls chain.
    fn set<'py>(slf: Bound<'py, Self>, field: &str, value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, Self>> {
        let py = slf.py();
        let literal = ron_literal(value)?;
        let (path, mut sets) = {
            let me = slf.borrow();
            (me.path.clone(), me.sets.clone())
        };
        sets.push(format!("{field}={literal}"));
        areo_scenario::format::load_set(&path, &sets).map_err(|e| to_py(py, &e))?;
        slf.borrow_mut().sets = sets;
        Ok(slf)
    }

    /// The fields set so far, as `PATH=VALUE`.
    #[getter]
    fn sets(&self) -> Vec<String> {
        self.sets.clone()
    }

    /// Runs the scenario, writing its outputs into `out` (a new temporary directory
    /// when None), with the GIL released; Ctrl-C raises KeyboardInterrupt at once (the
    /// run's thread finishes its current job in the background; its outputs are not
    /// read). Returns a `RunResult`; a run that ends without reaching every goal
    /// raises `Unreachable` (its `.binding`, `.message` and `.result`). `max_work`
    /// (elementary steps) and `max_memory_gb` (GiB) are the CLI's `--max-work` and
    /// `--max-memory-gb`: a job estimated over them is refused before it starts, and
    /// its searches stop where the work budget ends (`BudgetSpent`, with `.result`: the
    /// facts the run had).
    #[pyo3(signature = (out = None, max_work = None, max_memory_gb = None))]
    fn run(
        &self,
        py: Python<'_>,
        out: Option<PathBuf>,
        max_work: Option<f64>,
        max_memory_gb: Option<f64>,
    ) -> PyResult<PyRunResult> {
        let mut budget = areo_scenario::budget::Budget::for_this_machine();
        if let Some(steps) = max_work {
            if !(1.0..=1e18).contains(&steps) {
                return Err(PyValueError::new_err(format!("max_work {steps}: allowed 1..=1e18 steps")));
            }
            budget.work_steps = steps as u64;
        }
        if let Some(gb) = max_memory_gb {
            if !(gb > 0.0 && gb <= 1e6) {
                return Err(PyValueError::new_err(format!("max_memory_gb {gb}: allowed 0 (exclusive)..=1000000")));
            }
            budget.memory_bytes = (gb * f64::from(1u32 << 30)) as u64;
        }
        let file = areo_scenario::format::load_set(&self.path, &self.sets).map_err(|e| to_py(py, &e))?;
        let out = match out {
            Some(o) => o,
            None => temp_out(&file.name).map_err(|e| AreoError::new_err(e.to_string()))?,
        };
        let dir = out.clone();
        let worker = std::thread::spawn(move || {
            let options = RunOptions { out_dir: Some(&dir), progress: &NoProgress, budget };
            areo_scenario::run(&file, options)
        });
        while !worker.is_finished() {
            py.detach(|| std::thread::sleep(Duration::from_millis(20)));
            // Ctrl-C (KeyboardInterrupt) or any other signal handler's exception.
            py.check_signals()?;
        }
        let outcome = worker.join().map_err(|_| AreoError::new_err("the run panicked"))?;
        let outcome = outcome.map_err(|e| to_py(py, &e))?;
        let result = PyRunResult::from_outcome(outcome, out)?;
        if let Some(failure @ Failure::Unreachable { binding, message, .. }) = &result.failure {
            let err = Unreachable::new_err(failure.to_string());
            let v = err.value(py);
            v.setattr("binding", format!("{binding:?}"))?;
            v.setattr("message", message.clone())?;
            v.setattr("result", Py::new(py, result.clone())?)?;
            return Err(err);
        }
        if let Some(failure @ Failure::Stopped { .. }) = &result.failure {
            let err = BudgetSpent::new_err(failure.to_string());
            let v = err.value(py);
            v.setattr("file", self.path.display().to_string())?;
            for attr in ["field", "line", "column"] {
                v.setattr(attr, py.None())?;
            }
            v.setattr("result", Py::new(py, result.clone())?)?;
            return Err(err);
        }
        Ok(result)
    }

    fn __repr__(&self) -> String {
        format!("Scenario({:?}, sets={:?})", self.path.display().to_string(), self.sets)
    }
}

/// A fresh directory for a run's outputs under the system's temporary directory.
fn temp_out(name: &str) -> std::io::Result<PathBuf> {
    let base = std::env::temp_dir();
    for k in 0u32.. {
        let dir = base.join(format!("areo-{name}-{}-{k}", std::process::id()));
        match std::fs::create_dir(&dir) {
            Ok(()) => return Ok(dir),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
    unreachable!("an unbounded range ends only by returning")
}

/// What a run produced.
#[pyclass(name = "RunResult", frozen, module = "areo")]
#[derive(Clone)]
struct PyRunResult {
    facts_json: String,
    /// The job's report, converted to Python values when asked for.
    report: Option<std::sync::Arc<areo_scenario::Report>>,
    summary: Vec<String>,
    files: Vec<PathBuf>,
    out: PathBuf,
    failure: Option<Failure>,
}

impl PyRunResult {
    fn from_outcome(o: Outcome, out: PathBuf) -> PyResult<PyRunResult> {
        let error = |e: serde_json::Error| AreoError::new_err(e.to_string());
        let facts_json = serde_json::to_string(&o.facts).map_err(error)?;
        let report = o.report.map(|r| std::sync::Arc::new(*r));
        Ok(PyRunResult { facts_json, report, summary: o.summary, files: o.files, out, failure: o.failure })
    }
}

/// A report's value as Python data: a table (a list of records) as a dict of columns,
/// a list of numbers or a numeric column as a float64 array (an absent value NaN), a
/// raster (`cols`, `rows`, `values`) as a `(rows, cols)` array, or `(rows, cols, k)`
/// for `k` values per cell.
fn report_value<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    match value {
        Value::Null => Ok(py.None().into_bound(py)),
        Value::Bool(b) => Ok(pyo3::types::PyBool::new(py, *b).to_owned().into_any()),
        Value::Number(n) => match n.as_i64() {
            Some(i) => Ok(i.into_pyobject(py)?.into_any()),
            None => Ok(n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()),
        },
        Value::String(s) => Ok(s.into_pyobject(py)?.into_any()),
        Value::Object(fields) => {
            if let Some(array) = raster(py, fields)? {
                return Ok(array);
            }
            let d = PyDict::new(py);
            for (k, v) in fields {
                d.set_item(k, report_value(py, v)?)?;
            }
            Ok(d.into_any())
        }
        Value::Array(items) => {
            if let Some(xs) = numbers(items) {
                return Ok(PyArray1::from_vec(py, xs).into_any());
            }
            if !items.is_empty() && items.iter().all(Value::is_boolean) {
                let flags: Vec<bool> = items.iter().map(|v| v.as_bool() == Some(true)).collect();
                return Ok(PyArray1::from_vec(py, flags).into_any());
            }
            match items.first() {
                // Rows (objects of one shape) as columns; objects of several shapes (a
                // report's plots of different kinds) stay a list.
                Some(Value::Object(first))
                    if items.iter().all(|v| v.as_object().is_some_and(|o| o.keys().eq(first.keys()))) =>
                {
                    let d = PyDict::new(py);
                    for k in first.keys() {
                        let column: Vec<Value> =
                            items.iter().map(|r| r.get(k).cloned().unwrap_or(Value::Null)).collect();
                        d.set_item(k, report_value(py, &Value::Array(column))?)?;
                    }
                    Ok(d.into_any())
                }
                _ => {
                    let l = PyList::empty(py);
                    for v in items {
                        l.append(report_value(py, v)?)?;
                    }
                    Ok(l.into_any())
                }
            }
        }
    }
}

/// Every item a number (or absent, as NaN), not all absent.
fn numbers(items: &[serde_json::Value]) -> Option<Vec<f64>> {
    let numeric = items.iter().all(|v| v.is_number() || v.is_null()) && items.iter().any(serde_json::Value::is_number);
    numeric.then(|| items.iter().map(|v| v.as_f64().unwrap_or(f64::NAN)).collect())
}

/// A raster's fields as a NumPy array of its shape, if they are one.
fn raster<'py>(
    py: Python<'py>,
    fields: &serde_json::Map<String, serde_json::Value>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let (Some(cols), Some(rows), Some(serde_json::Value::Array(values))) = (
        fields.get("cols").and_then(|v| v.as_u64()),
        fields.get("rows").and_then(|v| v.as_u64()),
        fields.get("values"),
    ) else {
        return Ok(None);
    };
    if fields.len() != 3 || values.len() as u64 != cols * rows {
        return Ok(None);
    }
    let (flat, per_cell) = match values.first() {
        Some(serde_json::Value::Array(first)) => {
            let k = first.len();
            let flat: Vec<serde_json::Value> =
                values.iter().flat_map(|v| v.as_array().cloned().unwrap_or_default()).collect();
            if flat.len() != values.len() * k {
                return Ok(None);
            }
            (flat, Some(k))
        }
        _ => (values.clone(), None),
    };
    let Some(xs) = numbers(&flat).or_else(|| flat.is_empty().then(Vec::new)) else {
        return Ok(None);
    };
    let array = PyArray1::from_vec(py, xs).into_any();
    let shape = match per_cell {
        Some(k) => vec![rows as usize, cols as usize, k],
        None => vec![rows as usize, cols as usize],
    };
    Ok(Some(array.call_method1("reshape", (shape,))?))
}

#[pymethods]
impl PyRunResult {
    /// The job's facts by name (numbers in the unit their name gives, counts, flags,
    /// text) — what `facts.json` holds.
    #[getter]
    fn facts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (&self.facts_json,))
    }

    /// The job's report, as `areo run --json` prints it: plain data whose scalar fields
    /// are the facts (a fact `a.b` is `report["a"]["b"]`), tables as dicts of columns
    /// and rasters as NumPy arrays of shape `(rows, cols)`. A TEMPEST report holds the
    /// plan (`report["plan"]["waypoints"]`) and a simulated run (`report["simulation"]`).
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match &self.report {
            Some(r) => report_value(py, &serde_json::to_value(&**r).map_err(|e| AreoError::new_err(e.to_string()))?),
            None => Ok(py.None().into_bound(py)),
        }
    }

    /// The summary lines `areo run` prints.
    #[getter]
    fn summary(&self) -> Vec<String> {
        self.summary.clone()
    }

    /// Every file the run wrote.
    #[getter]
    fn files(&self) -> Vec<PathBuf> {
        self.files.clone()
    }

    /// The directory the outputs are in.
    #[getter]
    fn out(&self) -> PathBuf {
        self.out.clone()
    }

    /// The report's tables by name (`plan`, `executed`, `replans`, `monte_carlo`,
    /// `seeds`, …; named as the CSV each is written to), each a dict of columns: NumPy
    /// arrays for numbers (absent: NaN) and flags, lists for text.
    #[getter]
    fn tables<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, rows) in self.report.as_ref().map(|r| r.tables()).unwrap_or_default() {
            d.set_item(name, report_value(py, &rows)?)?;
        }
        Ok(d)
    }

    /// One table by name, as [`tables`](Self::tables) gives it; KeyError if the report
    /// has none of that name.
    fn table<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let rows = (self.report.as_ref().map(|r| r.tables()).unwrap_or_default().into_iter())
            .find(|(n, _)| n == name)
            .map(|(_, rows)| rows)
            .ok_or_else(|| pyo3::exceptions::PyKeyError::new_err(name.to_string()))?;
        report_value(py, &rows)
    }

    /// One table as a NumPy record array (`numpy.rec.fromarrays`): float64 columns for
    /// numbers (absent: NaN), bool for flags, text columns for text.
    fn table_array<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let table = self.table(py, name)?;
        let np = py.import("numpy")?;
        let (mut names, columns) = (Vec::new(), PyList::empty(py));
        if let Ok(table) = table.cast::<PyDict>() {
            for (k, column) in table.iter() {
                names.push(k.extract::<String>()?);
                // Text (a list) as a NumPy text column, an absent text as "".
                let column = if column.cast::<PyList>().is_ok() {
                    let texts: Vec<String> = column
                        .try_iter()?
                        .map(|v| {
                            let v = v?;
                            if v.is_none() { Ok(String::new()) } else { v.str()?.extract() }
                        })
                        .collect::<PyResult<_>>()?;
                    np.call_method1("array", (texts,))?
                } else {
                    column
                };
                columns.append(column)?;
            }
        }
        let kwargs = [("names", names.join(","))].into_py_dict(py)?;
        np.getattr("rec")?.call_method("fromarrays", (columns,), Some(&kwargs))
    }

    fn __repr__(&self) -> String {
        format!(
            "RunResult({} facts, {} files in {})",
            self.facts_json.matches("\":").count(),
            self.files.len(),
            self.out.display()
        )
    }
}

/// Checks a rover file (RON) on a test terrain — `flat`, `slope:DEG`, `side-slope:DEG`
/// or `step:HEIGHT_M` — the report `areo rover check --format json` prints, as a dict:
/// a parameter file with wheel–ground friction `mu`, standing or `moving`; a TEMPEST
/// resource model (flat or a slope) in `body`'s gravity where it gives none.
#[pyfunction]
#[pyo3(signature = (params_path, terrain = "flat", mu = 0.6, moving = false, body = "mars"))]
fn rover_check<'py>(
    py: Python<'py>,
    params_path: PathBuf,
    terrain: &str,
    mu: f64,
    moving: bool,
    body: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let terrain: areo_scenario::rover_check::TestTerrain =
        terrain.parse().map_err(|m: String| PyValueError::new_err(format!("terrain: {m}")))?;
    let body = body_of(body)?;
    let report = py
        .detach(|| areo_scenario::rover_check::check_file(&params_path, terrain, mu, moving, body))
        .map_err(|e| to_py(py, &e))?;
    let json = serde_json::to_string(&report).map_err(|e| AreoError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (json,))
}

/// The extension module `areo._areo`, which the package `areo` re-exports.
#[pymodule]
fn _areo(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("AreoError", py.get_type::<AreoError>())?;
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("Unreachable", py.get_type::<Unreachable>())?;
    m.add("BudgetSpent", py.get_type::<BudgetSpent>())?;
    m.add_class::<PyDem>()?;
    m.add_class::<PyScenario>()?;
    m.add_class::<PyRunResult>()?;
    m.add_function(wrap_pyfunction!(sun, m)?)?;
    m.add_function(wrap_pyfunction!(sun_series, m)?)?;
    m.add_function(wrap_pyfunction!(read_dem, m)?)?;
    m.add_function(wrap_pyfunction!(read_layer, m)?)?;
    m.add_function(wrap_pyfunction!(shadow, m)?)?;
    m.add_function(wrap_pyfunction!(horizon, m)?)?;
    m.add_function(wrap_pyfunction!(rover_check, m)?)?;
    Ok(())
}
