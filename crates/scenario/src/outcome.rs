//! What a job produced, as named facts, and the expectations the regression runner
//! (`cargo xtask scenarios`) checks them against.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// One named fact about a job's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Fact {
    /// A number, in the unit the fact's name gives.
    Number(f64),
    /// A count (actions, waypoints, expansions): written as a JSON integer.
    Count(u64),
    /// A yes/no fact (goal reached, feasible, …).
    Flag(bool),
    /// Text (an instant in ISO 8601 UTC, a status word, …).
    Text(String),
}

impl std::fmt::Display for Fact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Fact::Number(x) => write!(f, "{x:.6}"),
            Fact::Count(n) => write!(f, "{n}"),
            Fact::Flag(b) => write!(f, "{b}"),
            Fact::Text(s) => write!(f, "{s}"),
        }
    }
}

/// A job's result: its report, named facts, files written and a human summary.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// The job's report as plain data; the facts are read off it. (`None` only for an
    /// outcome built by hand.)
    pub report: Option<Box<crate::report::Report>>,
    /// Facts by name.
    pub facts: BTreeMap<String, Fact>,
    /// Lines for a person to read.
    pub summary: Vec<String>,
    /// Files the job wrote.
    pub files: Vec<PathBuf>,
    /// Set when the job ran but did not achieve its aim (an unreachable goal);
    /// `areo run` exits with its code after writing everything.
    pub failure: Option<Failure>,
}

/// Why a job that ran to its end did not achieve its aim.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Failure {
    /// No plan reaches the goals (exit 3).
    Unreachable {
        /// The binding constraint, found by relaxing constraints one at a time.
        binding: areo_mission::Binding,
        /// The planner's description of it.
        message: String,
        /// How many actions a simulated rover had executed when it gave up (`None`
        /// when no plan was found from the start).
        after_actions: Option<usize>,
    },
    /// Grid benchmarks with no path where the published length says there is one
    /// (exit 3).
    NoPath {
        /// How many.
        unreachable: usize,
        /// Of how many scenarios.
        scenarios: usize,
    },
    /// The searches stopped at the work or memory budget before they had an answer:
    /// no plan, and no proof that none exists (exit 4). The message names the scenario
    /// and the flag that raises the budget.
    Stopped {
        /// What stopped them, as the planner says it.
        message: String,
    },
    /// Grid benchmarks whose length differs from the published optimum (exit 1).
    Mismatched {
        /// How many.
        mismatched: usize,
        /// Of how many scenarios.
        scenarios: usize,
    },
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Unreachable { message, after_actions: None, .. } => {
                write!(f, "no plan reaches the goals: binding constraint: {message}")
            }
            Failure::Unreachable { message, after_actions: Some(n), .. } => {
                write!(f, "goal unreachable after {n} actions: binding constraint: {message}")
            }
            Failure::Stopped { message } => f.write_str(message),
            Failure::NoPath { unreachable, scenarios } => write!(
                f,
                "{unreachable} of {scenarios} scenarios: no path to the goal (the published length says there is one)"
            ),
            Failure::Mismatched { mismatched, scenarios } => {
                write!(f, "{mismatched} of {scenarios} scenarios mismatched")
            }
        }
    }
}

impl Fact {
    /// The fact's value as a number, for a number or a count.
    pub fn as_number(&self) -> Option<f64> {
        match *self {
            Fact::Number(x) => Some(x),
            Fact::Count(n) => Some(n as f64),
            Fact::Flag(_) | Fact::Text(_) => None,
        }
    }
}

impl Outcome {
    /// Records a count.
    pub fn count(&mut self, name: &str, value: u64) {
        self.facts.insert(name.to_string(), Fact::Count(value));
    }

    /// Records a numeric fact.
    pub fn number(&mut self, name: &str, value: f64) {
        self.facts.insert(name.to_string(), Fact::Number(value));
    }

    /// Records a text fact.
    pub fn text(&mut self, name: &str, value: impl Into<String>) {
        self.facts.insert(name.to_string(), Fact::Text(value.into()));
    }

    /// Records a flag.
    pub fn flag(&mut self, name: &str, value: bool) {
        self.facts.insert(name.to_string(), Fact::Flag(value));
    }
}

/// The expected outcome of a scenario: `scenarios/expected/NAME.ron`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expected {
    /// Run the scenario with every re-plan compared with the same problem searched
    /// afresh (a simulated TEMPEST job's `compare_fresh`), so that the facts can check
    /// `replans_above_fresh` and `replan_fresh_cost_difference`.
    #[serde(default)]
    pub compare_fresh: bool,
    /// Expected facts by name; facts not listed are not checked.
    pub facts: BTreeMap<String, Expect>,
}

/// One expectation.
#[derive(Debug, Clone, Deserialize)]
pub enum Expect {
    /// |fact − value| ≤ tol.
    Near {
        /// Expected value.
        value: f64,
        /// Absolute tolerance, ≥ 0.
        tol: f64,
    },
    /// min ≤ fact ≤ max.
    Between {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// The flag has this value.
    Is(bool),
    /// The text is exactly this.
    Equals(String),
    /// The text is one of these.
    OneOf(Vec<String>),
}

/// A fact that did not meet its expectation.
#[derive(Debug, Clone, PartialEq)]
pub struct Mismatch {
    /// The fact's name.
    pub fact: String,
    /// What was expected, in words.
    pub expected: String,
    /// What was found, or "missing".
    pub found: String,
}

impl Expected {
    /// Reads an expectation file.
    pub fn load(path: &Path) -> Result<Expected, crate::Error> {
        crate::format::read_ron(path)
    }

    /// Every expectation the outcome fails.
    pub fn check(&self, outcome: &Outcome) -> Vec<Mismatch> {
        let mut out = Vec::new();
        for (name, expect) in &self.facts {
            let found = outcome.facts.get(name);
            let ok = match (expect, found) {
                (Expect::Near { value, tol }, Some(f)) if f.as_number().is_some() => {
                    f.as_number().is_some_and(|x| (x - value).abs() <= *tol)
                }
                (Expect::Between { min, max }, Some(f)) if f.as_number().is_some() => {
                    f.as_number().is_some_and(|x| x >= *min && x <= *max)
                }
                (Expect::Is(b), Some(Fact::Flag(x))) => x == b,
                (Expect::Equals(s), Some(Fact::Text(x))) => x == s,
                (Expect::OneOf(v), Some(Fact::Text(x))) => v.contains(x),
                _ => false,
            };
            if !ok {
                out.push(Mismatch {
                    fact: name.clone(),
                    expected: match expect {
                        Expect::Near { value, tol } => format!("{value} ± {tol}"),
                        Expect::Between { min, max } => format!("in [{min}, {max}]"),
                        Expect::Is(b) => format!("{b}"),
                        Expect::Equals(s) => format!("{s:?}"),
                        Expect::OneOf(v) => format!("one of {v:?}"),
                    },
                    found: found.map_or_else(|| "missing".to_string(), |f| f.to_string()),
                });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expectations_catch_wrong_missing_and_mistyped_facts() {
        let mut o = Outcome::default();
        o.number("a", 1.0);
        o.number("b", 5.0);
        o.flag("c", true);
        o.text("d", "yes");
        o.text("f", "slip");
        let text = r#"(facts: {"a": Near(value: 1.05, tol: 0.1), "b": Between(min: 0, max: 4), "c": Is(true), "d": Equals("yes"), "e": Is(false), "a2": Is(true), "f": OneOf(["stability", "slip"]), "g": OneOf(["no"]), "d2": OneOf(["no"])})"#;
        let exp: Expected = crate::format::ron_options().from_str(text).unwrap();
        let bad: Vec<String> = exp.check(&o).into_iter().map(|m| m.fact).collect();
        assert_eq!(bad, vec!["a2", "b", "d2", "e", "g"]);
    }
}
