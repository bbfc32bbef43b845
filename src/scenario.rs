//! Scenario format v1: one RON file describes one job.
//!
//! ```ron
//! Scenario(
//!     version: 1,
//!     description: "A sol of sunlight at Gale crater",
//!     job: SunTable(
//!         site: (lat_deg: -4.5895, lon_east_deg: 137.4417),
//!         start_utc: "2012-08-06T05:17:57Z",
//!         duration_h: 24.66,
//!         step_min: 10,
//!     ),
//! )
//! ```
//!
//! Every struct denies unknown fields. Newtype variants may be written without their
//! inner parentheses (`SunTable(site: …)`), and optional fields without `Some(…)`.
//! Loading checks syntax, then value ranges; either kind of error names the file,
//! the line:column and the field. `docs/scenarios.md` documents every field.

mod locate;
mod validate;

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::Error;

pub use self::validate::{Checks, Validate};

/// The scenario format version this build reads.
pub const FORMAT_VERSION: u32 = 1;

/// A scenario file: a versioned job description.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Format version; must be [`FORMAT_VERSION`].
    pub version: u32,
    /// One line on what the scenario shows.
    #[serde(default)]
    pub description: String,
    /// What to run.
    pub job: Job,
}

/// The jobs areo can run. Later planners add variants.
#[derive(Debug, Clone, Deserialize)]
pub enum Job {
    /// The Sun over a site at regular steps: position, local time and flux.
    SunTable(SunTableJob),
    /// Terrain (synthesised or from a file) lit by the Sun of a given place and time:
    /// slope, shadows and a preview.
    TerrainShadow(TerrainShadowJob),
}

/// Where terrain comes from.
#[derive(Debug, Clone, Deserialize)]
pub enum TerrainSource {
    /// Synthesised from a description (see `docs/scenarios.md`).
    Synth(areo_terrain::synth::TerrainSpec),
    /// A DEM file (GeoTIFF, ESRI ASCII or PDS3), relative to the scenario file.
    File(String),
}

/// Shadows on terrain at one instant.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainShadowJob {
    /// The terrain.
    pub terrain: TerrainSource,
    /// Where on Mars the map lies (for the Sun's direction).
    pub site: SiteSpec,
    /// When, ISO 8601 UTC.
    pub utc: String,
    /// Ignore planetary curvature; default false.
    #[serde(default)]
    pub flat: bool,
}

/// A table of the Sun's position over a site (see [`crate::run`]).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SunTableJob {
    /// Where.
    pub site: SiteSpec,
    /// First instant, ISO 8601 UTC.
    pub start_utc: String,
    /// Length of the table, hours (0 < h ≤ 24 × 800, a bit over a Mars year).
    pub duration_h: f64,
    /// Step between rows, minutes (1/60 ≤ min ≤ 1440).
    pub step_min: f64,
    /// Atmospheric optical depth τ for the surface flux (0 ≤ τ ≤ 10); default 0.5.
    #[serde(default = "default_tau")]
    pub tau: f64,
    /// Horizon elevation per equal azimuth sector from north, degrees; default flat.
    #[serde(default)]
    pub horizon_deg: Option<Vec<f64>>,
}

fn default_tau() -> f64 {
    0.5
}

/// A place on Mars.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SiteSpec {
    /// Planetocentric latitude, degrees [−90, 90].
    pub lat_deg: f64,
    /// East longitude, degrees [−360, 360].
    pub lon_east_deg: f64,
}

impl Validate for Scenario {
    fn validate(&self, c: &mut Checks) {
        if self.version != FORMAT_VERSION {
            c.fail("version", format!("{} is not supported: allowed {FORMAT_VERSION}", self.version));
        }
        c.nested("job", |c| match &self.job {
            Job::SunTable(job) => job.validate(c),
            Job::TerrainShadow(job) => job.validate(c),
        });
    }
}

impl Validate for SunTableJob {
    fn validate(&self, c: &mut Checks) {
        c.nested("site", |c| self.site.validate(c));
        if let Err(e) = areo_ephemeris::parse_utc(&self.start_utc) {
            c.fail("start_utc", e.to_string());
        }
        c.range("duration_h", self.duration_h, f64::MIN_POSITIVE, 24.0 * 800.0, "hours, > 0");
        c.range("step_min", self.step_min, 1.0 / 60.0, 1440.0, "minutes");
        c.range("tau", self.tau, 0.0, 10.0, "optical depth");
        if let Some(h) = &self.horizon_deg {
            if h.is_empty() {
                c.fail("horizon_deg", "is empty: give at least one sector elevation, or leave it out".into());
            }
            c.list("horizon_deg", h, |c, v| c.range_here(*v, -90.0, 90.0, "degrees"));
        }
    }
}

impl Validate for TerrainShadowJob {
    fn validate(&self, c: &mut Checks) {
        c.nested("site", |c| self.site.validate(c));
        if let Err(e) = areo_ephemeris::parse_utc(&self.utc) {
            c.fail("utc", e.to_string());
        }
        if let TerrainSource::Synth(spec) = &self.terrain
            && let Err(areo_terrain::Error::BadSynth { field, value, allowed }) = spec.validate()
        {
            // `features[1].radius_m` → terrain.features[1].radius_m
            c.nested("terrain", |c| {
                let mut segments: Vec<String> = Vec::new();
                for part in field.split('.') {
                    match part.split_once('[') {
                        Some((name, idx)) => {
                            segments.push(name.to_string());
                            segments.push(format!("[{idx}"));
                        }
                        None => segments.push(part.to_string()),
                    }
                }
                c.fail_at(&segments, format!("{value} is out of range: allowed {allowed}"));
            });
        }
    }
}

impl Validate for SiteSpec {
    fn validate(&self, c: &mut Checks) {
        c.range("lat_deg", self.lat_deg, -90.0, 90.0, "planetocentric degrees");
        c.range("lon_east_deg", self.lon_east_deg, -360.0, 360.0, "degrees east");
    }
}

/// A scenario read from disk, with its name (the file stem) and path.
#[derive(Debug, Clone)]
pub struct ScenarioFile {
    /// Where it was read from.
    pub path: PathBuf,
    /// The file stem, used to name outputs (`out/NAME/`) and expectations.
    pub name: String,
    /// The parsed, validated scenario.
    pub scenario: Scenario,
}

/// Reads, parses and validates a scenario file.
pub fn load(path: &Path) -> Result<ScenarioFile, Error> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    let scenario = parse(path, &text)?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scenario".into());
    Ok(ScenarioFile { path: path.to_path_buf(), name, scenario })
}

/// Parses and validates scenario text; `path` only labels errors.
pub fn parse(path: &Path, text: &str) -> Result<Scenario, Error> {
    let scenario: Scenario = ron_options().from_str(text).map_err(|e| Error::Syntax {
        path: path.to_path_buf(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: e.code.to_string(),
    })?;
    let mut checks = Checks::default();
    scenario.validate(&mut checks);
    if let Some(v) = checks.into_first() {
        let (line, col) = locate::field_position(text, &v.path).unwrap_or((1, 1));
        return Err(Error::Invalid { path: path.to_path_buf(), line, col, field: v.dotted(), message: v.message });
    }
    Ok(scenario)
}

/// The RON options every areo file is read with.
pub fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(
        ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES | ron::extensions::Extensions::IMPLICIT_SOME,
    )
}
