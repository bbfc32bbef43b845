//! What a job returns: a report of plain data (numbers, text, tables as rows, rasters
//! as arrays), computed completely in the job and serialisable with serde.
//!
//! The report is the crate's answer to the binary, Python and downstream code. The
//! writers in [`output`](crate::output) and the summary lines read nothing else, and a
//! job's facts are the report's scalar fields named by their paths: the fact
//! `first_sunrise.ltst_hours` is the field `ltst_hours` of [`SunTableReport`]'s
//! `first_sunrise` ([`facts`]).

pub mod actions;
mod sun_table;
pub mod tempest;
mod terrain_shadow;

use std::collections::BTreeMap;

use serde::Serialize;

pub use actions::ActionsReport;
pub use sun_table::{SunTableReport, SunTableRow, Sunrise};
pub use tempest::TempestReport;
pub use terrain_shadow::{ShadowSun, TerrainShadowReport};

use crate::outcome::Fact;

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
#[derive(Debug, Clone, PartialEq, Serialize)]
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
    /// run themselves (data whose figures the report holds); an unsigned integer is a
    /// count, any other number a number.
    pub fn facts(&self) -> BTreeMap<String, Fact> {
        let value = match self {
            Report::SunTable(r) => serde_json::to_value(r),
            Report::TerrainShadow(r) => serde_json::to_value(r),
            Report::Actions(r) => serde_json::to_value(r),
            Report::Tempest(r) => serde_json::to_value(r).map(|mut v| {
                if let Some(fields) = v.as_object_mut() {
                    fields.remove("plan");
                    fields.remove("simulation");
                }
                v
            }),
        };
        let mut facts = BTreeMap::new();
        // Plain data always serialises: a map with non-string keys is the only way
        // out, and no report holds one.
        if let Ok(value) = value {
            flatten(&value, "", &mut facts);
        }
        facts
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Inner {
        ltst_hours: f64,
        utc: String,
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
    }

    #[test]
    fn facts_are_the_scalars_named_by_their_paths() {
        let outer = Outer {
            rows: 3,
            lit: true,
            offset_m: -2,
            first: Some(Inner { ltst_hours: 6.25, utc: "2012-08-06T05:17:57Z".into() }),
            missing: None,
            table: vec![Inner { ltst_hours: 1.0, utc: String::new() }],
            raster: Raster { cols: 2, rows: 1, values: vec![1, 0] },
        };
        let mut facts = BTreeMap::new();
        flatten(&serde_json::to_value(&outer).unwrap(), "", &mut facts);
        let names: Vec<&str> = facts.keys().map(String::as_str).collect();
        assert_eq!(names, ["first.ltst_hours", "first.utc", "lit", "offset_m", "raster.cols", "raster.rows", "rows"]);
        assert_eq!(facts["rows"], Fact::Count(3));
        assert_eq!(facts["offset_m"], Fact::Number(-2.0));
        assert_eq!(facts["first.ltst_hours"], Fact::Number(6.25));
        assert_eq!(facts["lit"], Fact::Flag(true));
        assert_eq!(facts["first.utc"], Fact::Text("2012-08-06T05:17:57Z".into()));
    }
}
