//! Rover files (LSR-1 parameters, TEMPEST resource models) read with the scenario's
//! guarantees: every number finite, and a range error placed at its line:column.

use std::path::Path;

use areo_rover::RoverParams;
use areo_rover::resources::ResourceModel;

use super::locate;
use crate::error::{Error, Result};

/// Reads and validates an LSR-1-style parameter file.
pub fn load_params(path: &Path) -> Result<RoverParams> {
    load(path, RoverParams::parse)
}

/// Reads and validates a TEMPEST resource-model file.
pub fn load_resources(path: &Path) -> Result<ResourceModel> {
    load(path, ResourceModel::parse)
}

fn load<T>(path: &Path, parse: impl Fn(&str, &str) -> areo_rover::Result<T>) -> Result<T> {
    let text = crate::read_text(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    // The shape first: the number scan below walks every bracket's path.
    super::refuse_hostile_shape(path, &text)?;
    super::refuse_non_finite(path, &text, "a rover file")?;
    parse(&text, &path.display().to_string()).map_err(|e| match e {
        areo_rover::Error::Invalid { field, value, why, .. } => {
            let segments: Vec<String> = field.split('.').map(str::to_string).collect();
            let (line, col) = locate::field_position(&text, &segments).unwrap_or((1, 1));
            Error::Invalid {
                path: path.to_path_buf(),
                line,
                col,
                field: field.to_string(),
                message: format!("{}: {why}", show(value)),
            }
        }
        other => Error::Rover(other),
    })
}

/// A value as a person would write it: 1e308, not three hundred digits.
fn show(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e9 || v.abs() < 1e-6) { format!("{v:e}") } else { format!("{v}") }
}
