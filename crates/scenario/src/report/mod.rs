//! What a job returns: a report of plain data (numbers, text, tables as rows, rasters
//! as arrays), computed completely in the job and serialisable with serde.
//!
//! The report is the crate's answer to the binary, Python and downstream code. The
//! writers in [`output`](crate::output) and the summary lines read nothing else, and a
//! job's facts are the report's scalar fields named by their paths: the fact
//! `first_sunrise.ltst_hours` is the field `ltst_hours` of [`SunTableReport`]'s
//! `first_sunrise` ([`Report::facts`]).

pub mod actions;
pub mod actions_view;
mod facts;
pub mod plots;
mod sun_table;
pub mod tempest;
mod terrain_shadow;
pub mod view;

use std::collections::BTreeMap;

use serde::Serialize;

pub use actions::ActionsReport;
use actions::SensitivityFigures;
pub use sun_table::{SunTableReport, SunTableRow, Sunrise};
pub use tempest::TempestReport;
pub use terrain_shadow::{ShadowSun, TerrainShadowReport};

use crate::outcome::Fact;

/// East longitude in −180..180, degrees: the one convention of every longitude a run
/// writes (a longitude of 0..360 from a projection or the ephemeris is turned into it).
pub use areo_terrain::lon180;

/// The body and geographic CRS that every file of a run names — the GeoTIFFs' keys,
/// GeoJSON's and CZML's `crs`, the KML's data, a table's `.prj`, STAC: latitudes
/// planetocentric and longitudes east in −180..180 ([`lon180`]) on the sphere the map
/// is projected on (`areo_terrain::GeographicCrs`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Geography {
    /// The body: `Mars`, `Moon`, `Earth`, or `unknown` for radii of no known body.
    pub body: String,
    /// The sphere's radius, m.
    pub radius_m: f64,
    /// The geographic CRS's name (`Mars (2015) - Sphere / Ocentric`).
    pub crs_name: String,
    /// Its IAU 2015 code where the sphere is the IAU's (`IAU_2015:49900`).
    pub crs_code: Option<String>,
    /// The CRS as OGC WKT2.
    pub crs_wkt2: String,
}

impl Geography {
    /// What a run's latitudes are, as the files say it.
    pub const LATITUDE: &'static str = "planetocentric";
    /// What a run's longitudes are, as the files say it.
    pub const LONGITUDE: &'static str = "east, -180..180";

    /// The geography of a map projected on `surface`.
    pub fn of(surface: &areo_terrain::Spheroid) -> Geography {
        let crs = areo_terrain::GeographicCrs::of(surface);
        Geography {
            body: crs.body_name().to_string(),
            radius_m: crs.radius_m,
            crs_name: crs.name.clone(),
            crs_code: crs.iau_code.clone(),
            crs_wkt2: crs.wkt2(),
        }
    }

    /// What names the CRS where a format holds one string: the IAU code where there is
    /// one, else the WKT2 (GDAL reads either).
    pub fn crs_code_or_wkt2(&self) -> &str {
        self.crs_code.as_deref().unwrap_or(&self.crs_wkt2)
    }
}

/// A job's report.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "job")]
#[non_exhaustive]
pub enum Report {
    /// The Sun over a site at a fixed step.
    SunTable(SunTableReport),
    /// A map lit by the Sun at one instant.
    TerrainShadow(TerrainShadowReport),
    /// A TEMPEST plan or simulated run (boxed: its figures outweigh the others').
    Tempest(Box<TempestReport>),
    /// A GA action plan for the LSR-1-type rover, and its studies.
    Actions(Box<ActionsReport>),
}

/// A raster as plain data: `rows` × `cols` values, row-major from the north-west
/// corner, on the grid its report names.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Raster<T> {
    /// Columns (west to east).
    pub cols: usize,
    /// Rows (north to south).
    pub rows: usize,
    /// The values, `rows * cols` of them.
    pub values: Vec<T>,
}

impl Report {
    /// The report's facts: every scalar field, named by its path from the report's top
    /// (`sun.elevation_deg`; a flattened group's fields by their own names). Tables and
    /// rasters (arrays) are not facts, nor are absent values, nor the TEMPEST plan and
    /// run themselves nor the actions job's best plans in full (data whose figures the
    /// report holds); an unsigned integer is a count, any other number a number.
    pub fn facts(&self) -> BTreeMap<String, Fact> {
        match self {
            Report::SunTable(r) => facts::of(r, &[]),
            Report::TerrainShadow(r) => facts::of(r, &[]),
            Report::Actions(r) => facts::of(r, &["best_plans"]),
            Report::Tempest(r) => facts::of(r, &["plan", "simulation", "view"]),
        }
    }

    /// The report's tables, each named as the CSV it is written to (its path under the
    /// output directory without `.csv`: `plan`, `monte_carlo`, `seeds`, `RUN/ga` where
    /// a job has several runs), as a list of rows; the Sun table is `sun`.
    pub fn tables(&self) -> Vec<(String, serde_json::Value)> {
        let mut out = Vec::new();
        let mut put = |name: &str, rows: &dyn erased::Rows| out.push((name.to_string(), rows.value()));
        match self {
            Report::SunTable(r) => put("sun", &r.table),
            Report::TerrainShadow(_) => {}
            Report::Tempest(r) => {
                let t = &r.tables;
                put("plan", &t.plan);
                let optional = [
                    ("executed", t.executed.as_ref().map(|r| r as &dyn erased::Rows)),
                    ("replans", t.replans.as_ref().map(|r| r as &dyn erased::Rows)),
                    ("waits", t.waits.as_ref().map(|r| r as &dyn erased::Rows)),
                    ("monte_carlo", t.monte_carlo.as_ref().map(|r| r as &dyn erased::Rows)),
                    ("pareto_front", t.pareto_front.as_ref().map(|r| r as &dyn erased::Rows)),
                ];
                for (name, rows) in optional {
                    if let Some(rows) = rows {
                        put(name, rows);
                    }
                }
            }
            Report::Actions(r) => {
                let seeds: Vec<&actions::SeedRow> = (r.run_order.iter())
                    .filter_map(|name| r.runs.get(name)?.study.as_ref())
                    .flat_map(|s| &s.seed_rows)
                    .collect();
                if !seeds.is_empty() {
                    put("seeds", &seeds);
                }
                if let Some(c) = &r.climb {
                    put("climb", &c.climb_poses);
                }
                if let Some(s) = &r.scan {
                    put("scan", &s.scan_points);
                }
                if let Some(s) = &r.scan_seeds {
                    put("scan_seeds", &s.scan_seed_rows);
                }
                if let Some(s) = &r.replay {
                    put("replay", &s.replay_points);
                }
                let sensitivity: Vec<&SensitivityFigures> = (r.sensitivity_order.iter())
                    .filter_map(|(field, value)| r.sensitivity.get(field)?.get(value))
                    .collect();
                if !sensitivity.is_empty() {
                    put("sensitivity", &sensitivity);
                }
                for name in &r.run_order {
                    let Some(best) = r.best_plans.get(name) else { continue };
                    let dir = if r.run_order.len() == 1 { String::new() } else { format!("{name}/") };
                    put(&format!("{dir}plan"), &best.plan.trace);
                    put(&format!("{dir}ga"), &best.plan.generations);
                    put(&format!("{dir}commands"), &best.commands.commands);
                }
            }
        }
        out
    }
}

/// Tables of any row type, as JSON values.
mod erased {
    /// A table's rows.
    pub(super) trait Rows {
        /// The rows as a JSON array.
        fn value(&self) -> serde_json::Value;
    }

    impl<T: serde::Serialize> Rows for Vec<T> {
        fn value(&self) -> serde_json::Value {
            // Rows are structs of numbers, text and flags: nothing JSON cannot hold.
            serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Inner {
        ltst_hours: f64,
        utc: String,
    }

    #[derive(Serialize)]
    enum Kind {
        Local,
        Polar { lat_ts_deg: f64 },
    }

    #[derive(Serialize)]
    struct Group {
        group_count: u64,
        group_label: Option<String>,
    }

    #[derive(Serialize)]
    struct Outer {
        rows: usize,
        lit: bool,
        offset_m: i32,
        first: Option<Inner>,
        missing: Option<Inner>,
        table: Vec<Inner>,
        raster: Raster<u8>,
        not_a_number: f64,
        kind: Kind,
        projection: Kind,
        by_name: BTreeMap<String, Inner>,
        pair: (f64, f64),
        #[serde(flatten)]
        group: Option<Group>,
        skipped: Inner,
    }

    fn outer() -> Outer {
        let inner = |ltst_hours: f64, utc: &str| Inner { ltst_hours, utc: utc.into() };
        Outer {
            rows: 3,
            lit: true,
            offset_m: -2,
            first: Some(inner(6.25, "2012-08-06T05:17:57Z")),
            missing: None,
            table: vec![inner(1.0, "")],
            raster: Raster { cols: 2, rows: 1, values: vec![1, 0] },
            not_a_number: f64::NAN,
            kind: Kind::Local,
            projection: Kind::Polar { lat_ts_deg: -90.0 },
            by_name: [("west_slope".to_string(), inner(9.5, "w"))].into_iter().collect(),
            pair: (1.0, 2.0),
            group: Some(Group { group_count: 7, group_label: None }),
            skipped: inner(0.0, "never a fact"),
        }
    }

    #[test]
    fn facts_are_the_scalars_named_by_their_paths() {
        let facts = facts::of(&outer(), &["skipped"]);
        let names: Vec<&str> = facts.keys().map(String::as_str).collect();
        assert_eq!(
            names,
            [
                "by_name.west_slope.ltst_hours",
                "by_name.west_slope.utc",
                "first.ltst_hours",
                "first.utc",
                "group_count",
                "kind",
                "lit",
                "offset_m",
                "projection.Polar.lat_ts_deg",
                "raster.cols",
                "raster.rows",
                "rows",
            ]
        );
        assert_eq!(facts["rows"], Fact::Count(3));
        assert_eq!(facts["offset_m"], Fact::Number(-2.0));
        assert_eq!(facts["first.ltst_hours"], Fact::Number(6.25));
        assert_eq!(facts["lit"], Fact::Flag(true));
        assert_eq!(facts["kind"], Fact::Text("Local".into()));
        assert_eq!(facts["first.utc"], Fact::Text("2012-08-06T05:17:57Z".into()));
    }

    /// The facts read through JSON: the whole value held, then walked.
    fn through_json(value: &impl Serialize, skip: &[&str]) -> BTreeMap<String, Fact> {
        let mut value = serde_json::to_value(value).unwrap();
        if let Some(fields) = value.as_object_mut() {
            for name in skip {
                fields.remove(*name);
            }
        }
        let mut facts = BTreeMap::new();
        flatten(&value, "", &mut facts);
        facts
    }

    /// The scalars under `value`, their names prefixed with `path`.
    fn flatten(value: &serde_json::Value, path: &str, facts: &mut BTreeMap<String, Fact>) {
        use serde_json::Value;
        let fact = match value {
            Value::Object(fields) => {
                for (name, v) in fields {
                    let path = if path.is_empty() { name.clone() } else { format!("{path}.{name}") };
                    flatten(v, &path, facts);
                }
                return;
            }
            Value::Array(_) | Value::Null => return,
            Value::Bool(b) => Fact::Flag(*b),
            Value::String(s) => Fact::Text(s.clone()),
            Value::Number(n) => match n.as_u64() {
                Some(count) => Fact::Count(count),
                None => Fact::Number(n.as_f64().unwrap_or(f64::NAN)),
            },
        };
        facts.insert(path.to_string(), fact);
    }

    #[test]
    fn the_sink_names_what_the_json_of_the_report_holds() {
        assert_eq!(facts::of(&outer(), &["skipped"]), through_json(&outer(), &["skipped"]));
        // And on a report: flattened groups and maps keyed by name.
        let tempest = TempestReport {
            status: "planned".into(),
            run: Some(tempest::RunFigures {
                goals: [("goal2".to_string(), tempest::GoalArrival { arrival_h: 31.5, ..Default::default() })].into(),
                median_replan_s: Some(0.25),
                ..Default::default()
            }),
            initial_plan: Some(tempest::PlanFigures { initial_plan_tick_s: Some(60.0), ..Default::default() }),
            ..Default::default()
        };
        let facts = facts::of(&tempest, &["plan", "simulation"]);
        assert_eq!(facts, through_json(&tempest, &["plan", "simulation"]));
        assert_eq!(facts["goals.goal2.arrival_h"], Fact::Number(31.5));
        assert_eq!(facts["initial_plan_tick_s"], Fact::Number(60.0));
        assert_eq!(facts["status"], Fact::Text("planned".into()));
    }
}
