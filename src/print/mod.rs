//! Printers: typed results from areo-scenario as text, CSV or JSON on standard output.
//! They format; they compute nothing.

pub(crate) mod grid;
pub(crate) mod rover;
pub(crate) mod run;
pub(crate) mod sun;
pub(crate) mod terrain;

use std::path::Path;

use areo_scenario::Error;

/// `value` as pretty JSON for standard output.
pub(crate) fn json(value: &impl serde::Serialize) -> Result<String, Error> {
    // The terminal's characters escaped as JSON escapes: the same strings, nothing
    // raw that a terminal would act on.
    serde_json::to_string_pretty(value)
        .map(|json| areo_scenario::output::escape::json_console(&json).into_owned())
        .map_err(|e| Error::Io { path: "(standard output)".into(), source: std::io::Error::other(e) })
}

/// A CSV table for standard output (quoted as the file writers quote).
pub(crate) fn csv(table: &areo_scenario::output::csv::Table) -> Result<String, Error> {
    table.to_csv(Path::new("<stdout>"))
}
