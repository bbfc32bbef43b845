//! `areo run`: the scenario's summary, facts and files, as text or JSON.

use std::collections::BTreeMap;
use std::path::PathBuf;

use areo_scenario::format::ScenarioFile;
use areo_scenario::{Fact, Outcome};

/// The run as JSON: the job's report, the facts with their JSON types (counts as integers), the summary lines, the files
/// written and why the aim was missed, if it was.
#[derive(serde::Serialize)]
pub(crate) struct RunJson<'a> {
    scenario: &'a str,
    description: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    report: Option<&'a areo_scenario::Report>,
    summary: &'a [String],
    facts: &'a BTreeMap<String, Fact>,
    files: &'a [PathBuf],
    failure: Option<String>,
}

impl<'a> RunJson<'a> {
    pub(crate) fn of(file: &'a ScenarioFile, outcome: &'a Outcome) -> RunJson<'a> {
        RunJson {
            scenario: &file.name,
            description: &file.scenario.description,
            report: outcome.report.as_deref(),
            summary: &outcome.summary,
            facts: &outcome.facts,
            files: &outcome.files,
            failure: outcome.failure.as_ref().map(ToString::to_string),
        }
    }
}

/// `text` with control characters (NUL, ESC: a description could hold terminal
/// escapes) shown as `\u{…}`, tabs and newlines as spaces.
pub(crate) fn printable(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '\t' | '\n' | '\r' => " ".to_string(),
            c if c.is_control() => c.escape_unicode().to_string(),
            c => c.to_string(),
        })
        .collect()
}

/// The summary under the scenario's name and description, then `wrote FILE` lines.
pub(crate) fn text(file: &ScenarioFile, outcome: &Outcome) -> String {
    let mut s = format!("{}: {}\n", printable(&file.name), printable(&file.scenario.description));
    for line in &outcome.summary {
        s += &format!("  {line}\n");
    }
    for f in &outcome.files {
        s += &format!("  wrote {}\n", f.display());
    }
    s
}
