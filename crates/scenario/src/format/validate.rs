//! Range checks that remember where in the scenario they are.

/// A value that can check its own ranges.
pub trait Validate {
    /// Records every violation in `c`, with field names relative to `self`.
    fn validate(&self, c: &mut Checks);
}

/// Collects violations with their field paths (`["job", "goals", "[1]", "x"]`).
#[derive(Debug, Default)]
pub struct Checks {
    prefix: Vec<String>,
    violations: Vec<Violation>,
}

/// One out-of-range value.
#[derive(Debug, Clone, PartialEq)]
pub struct Violation {
    /// Path segments from the scenario root; list elements are `[i]`.
    pub path: Vec<String>,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl Violation {
    /// The path as written in messages: `job.goals[1].x`.
    pub fn dotted(&self) -> String {
        let mut s = String::new();
        for seg in &self.path {
            if !seg.starts_with('[') && !s.is_empty() {
                s.push('.');
            }
            s.push_str(seg);
        }
        s
    }
}

impl Checks {
    /// Checks the fields of a nested value under `field`.
    pub fn nested(&mut self, field: &str, f: impl FnOnce(&mut Checks)) {
        self.prefix.push(field.to_string());
        f(self);
        self.prefix.pop();
    }

    /// Checks each element of the list `field`.
    pub fn list<T>(&mut self, field: &str, items: &[T], mut f: impl FnMut(&mut Checks, &T)) {
        self.prefix.push(field.to_string());
        for (i, item) in items.iter().enumerate() {
            self.prefix.push(format!("[{i}]"));
            f(self, item);
            self.prefix.pop();
        }
        self.prefix.pop();
    }

    /// Records a violation of `field`.
    pub fn fail(&mut self, field: &str, message: String) {
        let mut path = self.prefix.clone();
        path.push(field.to_string());
        self.violations.push(Violation { path, message });
    }

    /// Records a violation at a path of several segments below the current one.
    pub fn fail_at(&mut self, segments: &[String], message: String) {
        let mut path = self.prefix.clone();
        path.extend(segments.iter().cloned());
        self.violations.push(Violation { path, message });
    }

    /// Requires `lo ≤ value ≤ hi` (and finite) for `field`.
    pub fn range(&mut self, field: &str, value: f64, lo: f64, hi: f64, unit: &str) {
        if !(value.is_finite() && value >= lo && value <= hi) {
            self.fail(field, out_of_range(value, lo, hi, unit));
        }
    }

    /// Like [`Checks::range`] for the current list element.
    pub fn range_here(&mut self, value: f64, lo: f64, hi: f64, unit: &str) {
        if !(value.is_finite() && value >= lo && value <= hi) {
            let path = self.prefix.clone();
            self.violations.push(Violation { path, message: out_of_range(value, lo, hi, unit) });
        }
    }

    /// The first violation, if any.
    pub fn into_first(self) -> Option<Violation> {
        self.violations.into_iter().next()
    }
}

fn out_of_range(value: f64, lo: f64, hi: f64, unit: &str) -> String {
    let show = |x: f64| if x == f64::MIN_POSITIVE { "0 (exclusive)".to_string() } else { format!("{x}") };
    format!("{value} is out of range: allowed {}..={} ({unit})", show(lo), show(hi))
}
