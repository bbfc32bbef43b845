//! Studies as sweeps, for the array schedulers users already have (Slurm job arrays,
//! Kubernetes Indexed Jobs): a sweep file names a base scenario and axes over its
//! fields; [`expand`] writes one scenario per task and a manifest, validating every one
//! up front; [`run_task`] runs task N (from `--index`, `SLURM_ARRAY_TASK_ID` or
//! `JOB_COMPLETION_INDEX`) into `DIR/out/ID/` atomically; [`collect`] merges the
//! finished tasks' facts into `results.csv` and lists the missing and failed ones;
//! [`slurm_script`] and [`k8s_job`] write the launch recipes.
//!
//! A sweep directory:
//! - `sweep.json`: the sweep's name, the base scenario's directory (relative files of
//!   the base resolve against it), the axes and the task count;
//! - `manifest.jsonl`: one line per task (`index`, `id`, the axis values, `scenario`);
//! - `tasks/ID.ron`: each task's scenario;
//! - `out/ID/`: a finished task's outputs (`facts.json` among them);
//! - `failed/ID.txt`: the error of a task that failed (removed when it later succeeds).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::format::ScenarioFile;
use crate::output::csv::Table;
use crate::output::write_file;

/// The sweep file format version this build reads.
pub const SWEEP_VERSION: u32 = 1;
/// The most tasks one sweep may expand to (a hundred times Slurm's default largest
/// job array).
pub const MAX_TASKS: usize = 100_000;

/// A sweep file (`*.sweep.ron`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
#[serde(rename = "Sweep")]
pub struct SweepFile {
    /// Format version (1).
    pub version: u32,
    /// The base scenario, relative to the sweep file.
    pub base: String,
    /// Task id pattern: `{AXIS}` is replaced by the axis value, `{index}` by the task
    /// index; characters other than letters, digits, `.`, `_` and `-` become `_`.
    /// Default `"{index}"`.
    #[serde(default = "default_pattern")]
    pub name: String,
    /// How the axes combine: every combination (`Product`, default) or element by
    /// element (`Zip`, equal lengths).
    #[serde(default)]
    pub combine: Combine,
    /// The axes.
    pub axes: Vec<Axis>,
}

fn default_pattern() -> String {
    "{index}".into()
}

/// How axes combine.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
pub enum Combine {
    /// Every combination, the last axis fastest.
    #[default]
    Product,
    /// The i-th value of every axis together.
    Zip,
}

/// One axis: a scenario field by its path and the values it takes.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    /// Name (1–64 of `A–Z a–z 0–9 _ -`), a column of `results.csv`.
    pub name: String,
    /// The field's path in the scenario, dotted, list elements as `[i]`: e.g.
    /// `job.execution.mu`, `job.start_utc`, `job.goals[1].x_m`. The base scenario must
    /// write the field out. No path: a label axis, a column of values zipped with the
    /// others (a number to plot against, say) that sets no field.
    #[serde(default)]
    pub path: Option<String>,
    /// The values, as RON literals (numbers, strings, booleans, tuples).
    #[serde(default)]
    pub values: Vec<ron::Value>,
    /// Or a range of numbers: (from, to, step), `to` included when the steps land on it.
    #[serde(default)]
    pub range: Option<(f64, f64, f64)>,
    /// Or RON text written into the scenario as it is: enum variants and tuples
    /// (`"Uniform"`, `"Centred(sigma: 2.0, uniform: 0.1)"`, `"(1, 1)"`), which RON
    /// values cannot carry.
    #[serde(default)]
    pub raw: Vec<String>,
}

impl Axis {
    /// The axis's values as RON text.
    fn literals(&self) -> std::result::Result<Vec<String>, String> {
        let given = usize::from(self.range.is_some())
            + usize::from(!self.values.is_empty())
            + usize::from(!self.raw.is_empty());
        if given != 1 {
            return Err("give exactly one of values (a list), range: (from, to, step) or raw (RON text)".into());
        }
        if !self.raw.is_empty() {
            if let Some(r) = self.raw.iter().find(|r| r.trim().is_empty() || r.contains(['\n', '\r'])) {
                return Err(format!("raw value {r:?}: one line of RON text, not empty"));
            }
            // Each replaces one field's value and nothing else.
            for r in &self.raw {
                crate::format::setting::one_value(r).map_err(|why| format!("raw value {r:?} {why}"))?;
            }
            return Ok(self.raw.clone());
        }
        let Some((from, to, step)) = self.range else {
            return self.values.iter().map(|v| ron::to_string(v).map_err(|e| e.to_string())).collect();
        };
        if !(from.is_finite() && to.is_finite() && step > 0.0 && to >= from) {
            return Err(format!("range ({from}, {to}, {step}): need finite from ≤ to and step > 0"));
        }
        // Counted in floating point first: a tiny step gives an infinite count, which
        // must not wrap to a small one on the way to an integer.
        let n = ((to - from) / step + 1e-9).floor() + 1.0;
        if !(n <= MAX_TASKS as f64) {
            return Err(format!("range ({from}, {to}, {step}) has {n:.3e} values: at most {MAX_TASKS}"));
        }
        Ok((0..n as usize).map(|k| number_literal(from + step * k as f64)).collect())
    }
}

/// A number as RON text: integral values without a fraction (so integer fields take
/// them), others in the shortest form that reads back exactly.
fn number_literal(v: f64) -> String {
    let r = (v * 1e9).round() / 1e9;
    if r.fract() == 0.0 && r.abs() < 1e15 { format!("{}", r as i64) } else { format!("{r}") }
}

/// One task of an expanded sweep (a line of `manifest.jsonl`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepTask {
    /// 0-based index (the array task id).
    pub index: usize,
    /// Id: the output directory's name.
    pub id: String,
    /// Axis name → the value as JSON: numbers and booleans as themselves, a RON string
    /// as its text, any other RON value (`Mars`, a tuple) as its RON text.
    pub values: BTreeMap<String, serde_json::Value>,
    /// The task's scenario, relative to the sweep directory.
    pub scenario: String,
}

/// `sweep.json`: what the sweep directory holds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SweepInfo {
    /// The sweep file's stem.
    pub name: String,
    /// The base scenario's directory: relative paths inside tasks resolve against it.
    pub base_dir: PathBuf,
    /// The base scenario's file stem.
    pub base_name: String,
    /// Axis names, in the file's order.
    pub axes: Vec<String>,
    /// How they combine.
    pub combine: Combine,
    /// Number of tasks.
    pub tasks: usize,
    /// A hash of the sweep file's and the base scenario's texts: the directory belongs
    /// to this sweep (empty in directories expanded before it was recorded).
    #[serde(default)]
    pub fingerprint: String,
}

/// Reads a sweep file.
pub fn load(path: &Path) -> Result<SweepFile> {
    let sweep: SweepFile = crate::format::read_ron(path)?;
    let bad = |field: String, message: String| Error::Scenario { path: path.to_path_buf(), field, message };
    if sweep.version != SWEEP_VERSION {
        return Err(bad("version".into(), format!("{} is not supported: allowed {SWEEP_VERSION}", sweep.version)));
    }
    if sweep.axes.is_empty() {
        return Err(bad("axes".into(), "is empty: give at least one axis".into()));
    }
    let mut names = BTreeSet::new();
    let mut paths = BTreeSet::new();
    for (i, a) in sweep.axes.iter().enumerate() {
        let ok = (1..=64).contains(&a.name.len())
            && a.name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
            && a.name != "index";
        if !ok {
            return Err(bad(
                format!("axes[{i}].name"),
                format!("{:?}: allowed 1 to 64 of A–Z a–z 0–9 _ - (not \"index\")", a.name),
            ));
        }
        if !names.insert(a.name.as_str()) {
            return Err(bad(format!("axes[{i}].name"), format!("{:?} is used twice", a.name)));
        }
        if let Some(p) = &a.path
            && !paths.insert(p.as_str())
        {
            return Err(bad(format!("axes[{i}].path"), format!("{p:?} is swept twice")));
        }
        a.literals().map_err(|m| bad(format!("axes[{i}]"), m))?;
    }
    Ok(sweep)
}

/// The byte range of the value written for `path` in RON `text`, if written.
pub(crate) fn value_span(text: &str, path: &[String]) -> Option<std::ops::Range<usize>> {
    let (line, col) = crate::format::locate::field_position(text, path)?;
    let line_start: usize = text.split_inclusive('\n').take(line - 1).map(str::len).sum();
    let at = line_start + text[line_start..].char_indices().nth(col - 1)?.0;
    let bytes = text.as_bytes();
    let mut i = at;
    // A key (`name:`) precedes the value of a struct field; a list element has none.
    let ident_end = text[at..].find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).map_or(text.len(), |n| at + n);
    let after = text[ident_end..].trim_start();
    if ident_end > at && after.starts_with(':') {
        i = text.len() - after.len() + 1;
    }
    while i < bytes.len() && bytes[i].is_ascii_whitespace() {
        i += 1;
    }
    let start = i;
    let mut depth = 0i32;
    while i < bytes.len() {
        match bytes[i] {
            b'"' => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' if depth == 0 => break,
            b')' | b']' | b'}' => depth -= 1,
            b',' if depth == 0 => break,
            b'/' if bytes.get(i + 1) == Some(&b'/') && depth == 0 => break,
            b'\n' if depth == 0 => break,
            _ => {}
        }
        i += 1;
        if depth == 0 && i > start && matches!(bytes[i - 1], b'"' | b')' | b']' | b'}') {
            break;
        }
    }
    let end = start + text[start..i].trim_end().len();
    (end > start).then_some(start..end)
}

/// A RON literal as the JSON value a script reads: numbers and booleans as such, a
/// string as its text, anything else (`Mars`, a tuple) as its RON text.
fn json_value(literal: &str) -> serde_json::Value {
    let t = literal.trim();
    match t {
        "true" => return serde_json::Value::Bool(true),
        "false" => return serde_json::Value::Bool(false),
        _ => {}
    }
    if let Ok(n) = t.parse::<i64>() {
        return n.into();
    }
    if let Some(n) = t.parse::<f64>().ok().and_then(serde_json::Number::from_f64) {
        return serde_json::Value::Number(n);
    }
    match ron::from_str::<String>(t) {
        Ok(text) if t.starts_with('"') => serde_json::Value::String(text),
        _ => serde_json::Value::String(t.to_string()),
    }
}

/// Dotted path → segments (`a.b[2].c` → `a`, `b`, `[2]`, `c`).
pub(crate) fn segments(path: &str) -> Vec<String> {
    let mut out = Vec::new();
    for part in path.split('.') {
        match part.split_once('[') {
            Some((name, idx)) => {
                if !name.is_empty() {
                    out.push(name.to_string());
                }
                out.push(format!("[{idx}"));
            }
            None => out.push(part.to_string()),
        }
    }
    out
}

/// The task id for one combination.
fn task_id(pattern: &str, index: usize, values: &BTreeMap<String, String>) -> String {
    let mut id = pattern.replace("{index}", &index.to_string());
    for (name, v) in values {
        id = id.replace(&format!("{{{name}}}"), v.trim_matches('"'));
    }
    let id: String =
        id.chars().map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') { c } else { '_' }).collect();
    if id.starts_with('.') || id.is_empty() { format!("t{id}") } else { id }
}

/// The tasks' value indices, one per axis: zipped (the k-th of every axis) or every
/// combination (the last axis fastest), at most [`MAX_TASKS`].
fn combinations(
    sweep: &SweepFile,
    literals: &[Vec<String>],
    bad: &dyn Fn(String, String) -> Error,
) -> Result<Vec<Vec<usize>>> {
    Ok(match sweep.combine {
        Combine::Zip => {
            let n = literals[0].len();
            if let Some((i, l)) = literals.iter().enumerate().find(|(_, l)| l.len() != n) {
                return Err(bad(
                    format!("axes[{i}]"),
                    format!("{} values, axes[0] {n}: zipped axes must match", l.len()),
                ));
            }
            (0..n).map(|k| vec![k; literals.len()]).collect()
        }
        Combine::Product => {
            let total = literals.iter().try_fold(1usize, |acc, l| acc.checked_mul(l.len())).unwrap_or(usize::MAX);
            if total > MAX_TASKS {
                return Err(bad("axes".into(), format!("{total} combinations: at most {MAX_TASKS}")));
            }
            (0..total)
                .map(|mut t| {
                    let mut idx = vec![0; literals.len()];
                    for a in (0..literals.len()).rev() {
                        idx[a] = t % literals[a].len();
                        t /= literals[a].len();
                    }
                    idx
                })
                .collect()
        }
    })
}

/// Writes the expanded sweep: each task's scenario under `tasks/`, an empty `logs/`,
/// `manifest.jsonl` and `sweep.json`.
fn write_expansion(
    dir: &Path,
    sweep_path: &Path,
    base_path: &Path,
    sweep: &SweepFile,
    tasks: &[SweepTask],
    texts: &[String],
    fingerprint: &str,
) -> Result<()> {
    let base_name = base_path.file_stem().map_or_else(|| "base".into(), |s| s.to_string_lossy().into_owned());
    let io = |p: &Path| {
        let p = p.to_path_buf();
        move |source| Error::Io { path: p, source }
    };
    std::fs::create_dir_all(dir.join("tasks")).map_err(io(&dir.join("tasks")))?;
    // Schedulers open a task's log before it starts: the directory must exist.
    std::fs::create_dir_all(dir.join("logs")).map_err(io(&dir.join("logs")))?;
    for (t, text) in tasks.iter().zip(texts) {
        write_file(&dir.join(&t.scenario), text.as_bytes())?;
    }
    let mut manifest = String::new();
    for t in tasks {
        manifest += &serde_json::to_string(t).map_err(|e| io(&dir.join("manifest.jsonl"))(e.into()))?;
        manifest.push('\n');
    }
    write_file(&dir.join("manifest.jsonl"), manifest.as_bytes())?;
    let base_parent = base_path.parent().unwrap_or(Path::new("."));
    let base_dir = base_parent.canonicalize().unwrap_or_else(|_| base_parent.to_path_buf());
    let info = SweepInfo {
        name: sweep_path.file_name().map_or_else(String::new, |s| {
            s.to_string_lossy().trim_end_matches(".sweep.ron").trim_end_matches(".ron").to_string()
        }),
        base_dir,
        base_name,
        axes: sweep.axes.iter().map(|a| a.name.clone()).collect(),
        combine: sweep.combine,
        tasks: tasks.len(),
        fingerprint: fingerprint.to_string(),
    };
    let json = serde_json::to_string_pretty(&info).map_err(|e| io(&dir.join("sweep.json"))(e.into()))?;
    write_file(&dir.join("sweep.json"), json.as_bytes())?;
    Ok(())
}

/// Expands `sweep_path` into `dir`: one validated scenario per task, `manifest.jsonl`
/// and `sweep.json`. A task whose scenario is invalid is an error naming the task, its
/// axis values and the field, before anything is written.
pub fn expand(sweep_path: &Path, dir: &Path) -> Result<Vec<SweepTask>> {
    expand_within(sweep_path, dir, crate::budget::Budget::for_this_machine(), false)
}

/// [`expand`] under a budget: the tasks' scenario texts are held and parsed before
/// anything is written, so their count times the base scenario's size is checked
/// first. A directory holding another sweep's expansion is refused unless `force`.
pub fn expand_within(
    sweep_path: &Path,
    dir: &Path,
    budget: crate::budget::Budget,
    force: bool,
) -> Result<Vec<SweepTask>> {
    let sweep = load(sweep_path)?;
    let here = sweep_path.parent().unwrap_or(Path::new("."));
    let base_path = here.join(&sweep.base);
    let base_text = crate::read_text(&base_path).map_err(|source| Error::Read { path: base_path.clone(), source })?;
    let bad = |field: String, message: String| Error::Scenario { path: sweep_path.to_path_buf(), field, message };
    crate::format::parse(&base_path, &base_text)?;
    let mut spans = Vec::new();
    let mut literals = Vec::new();
    for (i, a) in sweep.axes.iter().enumerate() {
        let span = match &a.path {
            None => None,
            Some(p) => Some(value_span(&base_text, &segments(p)).ok_or_else(|| {
                bad(
                    format!("axes[{i}].path"),
                    format!("{p:?} is not written in {}: write the field out (any value) to sweep it", sweep.base),
                )
            })?),
        };
        spans.push(span);
        literals.push(a.literals().map_err(|m| bad(format!("axes[{i}]"), m))?);
    }
    refuse_overlaps(&sweep, &spans, &bad)?;
    let combos = combinations(&sweep, &literals, &bad)?;
    let fingerprint = admit(sweep_path, &base_text, combos.len(), budget)?;
    // Replacements are applied from the end of the text so earlier spans stay valid.
    let mut order: Vec<usize> = (0..spans.len()).filter(|&a| spans[a].is_some()).collect();
    order.sort_by_key(|&a| std::cmp::Reverse(spans[a].as_ref().map_or(0, |s| s.start)));
    let mut tasks = Vec::with_capacity(combos.len());
    let mut texts = Vec::with_capacity(combos.len());
    let mut ids = BTreeSet::new();
    for (index, combo) in combos.iter().enumerate() {
        let mut text = base_text.clone();
        for &a in &order {
            if let Some(span) = &spans[a] {
                text.replace_range(span.clone(), &literals[a][combo[a]]);
            }
        }
        let values: BTreeMap<String, String> = sweep
            .axes
            .iter()
            .zip(combo)
            .enumerate()
            .map(|(a, (axis, &k))| (axis.name.clone(), literals[a][k].clone()))
            .collect();
        let id = task_id(&sweep.name, index, &values);
        if !is_task_id(&id) {
            return Err(bad(
                "name".into(),
                format!("{:?} gives the id {id:?}: ids are at most 200 characters", sweep.name),
            ));
        }
        if !ids.insert(id.clone()) {
            return Err(bad(
                "name".into(),
                format!("{:?} gives the id {id:?} to two tasks: add {{index}} or an axis", sweep.name),
            ));
        }
        crate::format::parse(&base_path.with_file_name(format!("{id}.ron")), &text).map_err(|e| {
            let at: Vec<String> = values.iter().map(|(k, v)| format!("{k} = {v}")).collect();
            bad(format!("task {index} ({})", at.join(", ")), e.to_string())
        })?;
        let values = values.into_iter().map(|(k, v)| (k, json_value(&v))).collect();
        tasks.push(SweepTask { index, id: id.clone(), values, scenario: format!("tasks/{id}.ron") });
        texts.push(text);
    }
    // Every task is valid: claim the directory. Racing expansions into one directory
    // take turns, so the second finds the first's expansion.
    let _lock = crate::output::lock::lock_dir(dir)?;
    claim(dir, &fingerprint, force)?;
    write_expansion(dir, sweep_path, &base_path, &sweep, &tasks, &texts, &fingerprint)?;
    Ok(tasks)
}

/// Refuses two axes whose fields overlap (one inside the other, or the same field):
/// each axis sets its own field and nothing else.
fn refuse_overlaps(
    sweep: &SweepFile,
    spans: &[Option<std::ops::Range<usize>>],
    bad: &dyn Fn(String, String) -> Error,
) -> Result<()> {
    for (a, sa) in spans.iter().enumerate() {
        for (b, sb) in spans.iter().enumerate().skip(a + 1) {
            if let (Some(sa), Some(sb)) = (sa, sb)
                && sa.start < sb.end
                && sb.start < sa.end
            {
                let path = |i: usize| sweep.axes[i].path.clone().unwrap_or_default();
                return Err(bad(
                    format!("axes[{b}].path"),
                    format!("{:?} overlaps axes[{a}]'s {:?}: each axis sets a field of its own", path(b), path(a)),
                ));
            }
        }
    }
    Ok(())
}

/// The sweep directory's description.
pub fn info(dir: &Path) -> Result<SweepInfo> {
    let path = dir.join("sweep.json");
    let text = crate::read_text(&path).map_err(|source| Error::Read { path: path.clone(), source })?;
    serde_json::from_str(&text).map_err(|e| Error::Scenario {
        path,
        field: "sweep.json".into(),
        message: e.to_string(),
    })
}

/// Every task of an expanded sweep.
pub fn tasks(dir: &Path) -> Result<Vec<SweepTask>> {
    let path = dir.join("manifest.jsonl");
    let text = crate::read_text(&path).map_err(|source| Error::Read { path: path.clone(), source })?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            let syntax = |col: usize, message: String| Error::Syntax { path: path.clone(), line: i + 1, col, message };
            let task: SweepTask = serde_json::from_str(l).map_err(|e| syntax(e.column(), e.to_string()))?;
            // Ids name directories and files under the sweep: plain names only, so no
            // id reaches outside it or over another task's files.
            if !is_task_id(&task.id) {
                return Err(syntax(
                    1,
                    format!("task id {:?}: allowed 1 to 200 of A–Z a–z 0–9 . _ -, not starting with .", task.id),
                ));
            }
            let scenario = format!("tasks/{}.ron", task.id);
            if task.scenario != scenario {
                return Err(syntax(
                    1,
                    format!("task {:?}: its scenario must be {scenario:?}, not {:?}", task.id, task.scenario),
                ));
            }
            Ok(task)
        })
        .collect()
}

/// A task's facts if it finished: its `facts.json` reads as a JSON object. `run` and
/// `collect` both ask this, so they agree on what is finished.
fn finished(dir: &Path, id: &str) -> Option<serde_json::Map<String, serde_json::Value>> {
    let text = crate::read_text(&dir.join("out").join(id).join("facts.json")).ok()?;
    serde_json::from_str(&text).ok()
}

/// Why a task whose outputs are there has no result: its facts.json damaged (a task
/// whose outputs are not there is missing, not failed).
fn damaged(dir: &Path, id: &str) -> Option<String> {
    let path = dir.join("out").join(id).join("facts.json");
    let text = match crate::read_text(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return None,
        Err(e) => return Some(format!("{}: {e}", path.display())),
    };
    match serde_json::from_str::<serde_json::Map<String, serde_json::Value>>(&text) {
        Ok(_) => None,
        Err(e) => Some(format!("{}: a damaged result ({e}); run the task again with --force", path.display())),
    }
}

/// Refuses a manifest that disagrees with `sweep.json` on the number of tasks or their
/// indices.
fn agree(dir: &Path, info: &SweepInfo, all: &[SweepTask]) -> Result<()> {
    let in_order = all.iter().enumerate().all(|(i, t)| t.index == i);
    if all.len() != info.tasks || !in_order {
        return Err(Error::Scenario {
            path: dir.join("manifest.jsonl"),
            field: "manifest.jsonl".into(),
            message: format!(
                "{} tasks{}, while sweep.json says {}: the directory is damaged; expand the sweep again",
                all.len(),
                if in_order { "" } else { " out of order" },
                info.tasks
            ),
        });
    }
    Ok(())
}

/// Admits an expansion of `tasks` tasks of `base_text` within the budget (the tasks'
/// texts are held and parsed before anything is written; the directory is claimed,
/// see [`claim`], once they are). Returns the fingerprint.
fn admit(sweep_path: &Path, base_text: &str, tasks: usize, budget: crate::budget::Budget) -> Result<String> {
    let per_task = base_text.len() as u64 + 512;
    budget.check(&crate::budget::Estimate {
        what: format!("expanding {tasks} tasks of a {}-byte scenario", base_text.len()),
        memory_bytes: tasks as u64 * per_task * 4,
        work_steps: tasks as u64 * per_task,
        work_unit: "scenario bytes parsed",
    })?;
    Ok(fingerprint(&sweep_text(sweep_path)?, base_text))
}

/// The sweep file's text (for its fingerprint).
fn sweep_text(path: &Path) -> Result<String> {
    crate::read_text(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })
}

/// A 64-bit FNV-1a hash of the sweep's and the base scenario's texts, as hex.
fn fingerprint(sweep: &str, base: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in sweep.bytes().chain([0u8]).chain(base.bytes()) {
        h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Claims `dir` for the sweep of `fingerprint`: a directory holding another sweep's
/// expansion (or one from before fingerprints) is refused unless `force`, which clears
/// its tasks, outputs and records.
fn claim(dir: &Path, fingerprint: &str, force: bool) -> Result<()> {
    let Ok(old) = info(dir) else { return Ok(()) };
    if old.fingerprint == fingerprint {
        return Ok(());
    }
    if !force {
        return Err(Error::usage(
            format!("sweep expand … -o {}", dir.display()),
            format!(
                "the directory holds the expansion of another sweep ({}): expand into a new directory, or give --force to replace it and its outputs",
                printable(&old.name)
            ),
        ));
    }
    for sub in ["tasks", "out", "failed", "logs"] {
        match std::fs::remove_dir_all(dir.join(sub)) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(Error::Io { path: dir.join(sub), source: e });
            }
            _ => {}
        }
    }
    Ok(())
}

/// Whether `id` is a task id as [`expand`] makes them.
fn is_task_id(id: &str) -> bool {
    (1..=200).contains(&id.len())
        && !id.starts_with('.')
        && id.bytes().all(|b| b.is_ascii_alphanumeric() || matches!(b, b'.' | b'_' | b'-'))
}

/// The array index of this task: `index` if given, else `SLURM_ARRAY_TASK_ID`, else
/// `JOB_COMPLETION_INDEX` (Kubernetes Indexed Jobs).
pub fn task_index(index: Option<usize>) -> Result<usize> {
    if let Some(i) = index {
        return Ok(i);
    }
    for var in ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"] {
        if let Ok(v) = std::env::var(var) {
            return v.trim().parse().map_err(|_| Error::usage(format!("{var}={v:?}"), "is not a task index"));
        }
    }
    Err(Error::usage(
        "no task index",
        "give --index N, or run under a Slurm job array (SLURM_ARRAY_TASK_ID) or a Kubernetes Indexed Job (JOB_COMPLETION_INDEX)",
    ))
}

/// Threads for a task: `SLURM_CPUS_PER_TASK` when set (the allocation), capped at this
/// machine's cores (a larger figure is a mistake, not a reason to start 100 000
/// threads), else every core. Sets rayon's global pool once; later calls change
/// nothing. Returns the threads and, when capped, what the environment asked for.
pub fn configure_threads() -> Option<(usize, Option<String>)> {
    let asked = std::env::var("SLURM_CPUS_PER_TASK").ok()?;
    let n: usize = asked.trim().parse().ok().filter(|&n| n > 0)?;
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
    let used = n.min(cores);
    let capped = (used < n).then(|| format!("SLURM_CPUS_PER_TASK={n} is more than this machine's {cores} cores"));
    rayon::ThreadPoolBuilder::new().num_threads(used).build_global().ok().map(|_| (used, capped))
}

/// What running a task did.
#[derive(Debug)]
pub enum TaskRun {
    /// It had finished before (its `facts.json` exists) and `force` was not given.
    Skipped(SweepTask),
    /// It ran; its outputs are in `DIR/out/ID/`.
    Ran(SweepTask, crate::Outcome),
}

/// Runs task `index` of the sweep in `dir` into `DIR/out/ID/` (staged and renamed on
/// success, so a preempted or retried task replaces its outputs as a set); skips a
/// finished task unless `force`. A failure is recorded in `DIR/failed/ID.txt`.
pub fn run_task(
    dir: &Path,
    index: usize,
    force: bool,
    progress: &dyn crate::Progress,
    budget: crate::budget::Budget,
) -> Result<TaskRun> {
    let info = info(dir)?;
    let all = tasks(dir)?;
    agree(dir, &info, &all)?;
    let task = all.into_iter().find(|t| t.index == index).ok_or_else(|| {
        Error::usage(
            format!("task {index}"),
            format!("the sweep in {} has tasks 0..={}", dir.display(), info.tasks.saturating_sub(1)),
        )
    })?;
    let out = dir.join("out");
    if !force && finished(dir, &task.id).is_some() {
        return Ok(TaskRun::Skipped(task));
    }
    let path = dir.join(&task.scenario);
    // The task runs as if it sat beside the base scenario, so its relative files resolve.
    let as_if = info.base_dir.join(format!("{}.ron", task.id));
    let failed = dir.join("failed").join(format!("{}.txt", task.id));
    let result =
        crate::read_text(&path).map_err(|source| Error::Read { path: path.clone(), source }).and_then(|text| {
            let scenario = crate::format::parse(&as_if, &text)?;
            let file = ScenarioFile { path: as_if.clone(), name: task.id.clone(), scenario, text };
            crate::run_into(&file, &out, progress, budget)
        });
    match result {
        Ok(outcome) => {
            if failed.exists() {
                std::fs::remove_file(&failed).map_err(|source| Error::Io { path: failed.clone(), source })?;
            }
            Ok(TaskRun::Ran(task, outcome))
        }
        Err(e) => {
            std::fs::create_dir_all(dir.join("failed"))
                .map_err(|source| Error::Io { path: dir.join("failed"), source })?;
            write_file(&failed, format!("{e}\n").as_bytes())?;
            Err(e)
        }
    }
}

/// What [`collect`] found.
#[derive(Debug, Clone, Serialize)]
pub struct Collected {
    /// Tasks with outputs.
    pub finished: usize,
    /// Ids of tasks with neither outputs nor a recorded failure.
    pub missing: Vec<String>,
    /// Failed tasks: id and error.
    pub failed: Vec<(String, String)>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// The plot of one fact against one axis over the finished tasks
/// (`FACT_vs_AXIS.svg`/`.png`).
fn plot_against(
    dir: &Path,
    info: &SweepInfo,
    all: &[SweepTask],
    facts: &[Option<serde_json::Map<String, serde_json::Value>>],
    names: &BTreeSet<String>,
    (fact, axis): (&str, &str),
) -> Result<Vec<PathBuf>> {
    if !info.axes.iter().any(|a| a == axis) {
        return Err(Error::usage(
            format!("--against {axis}"),
            format!("the sweep's axes are {}", info.axes.join(", ")),
        ));
    }
    if !names.contains(fact) {
        return Err(Error::usage(format!("--plot {fact}"), "no finished task reported that fact"));
    }
    let mut points: Vec<(f64, f64)> = all
        .iter()
        .zip(facts)
        .filter_map(|(t, f)| {
            // Numbers as they are, booleans as 0 and 1.
            let x: f64 = match t.values.get(axis)? {
                serde_json::Value::Bool(b) => f64::from(u8::from(*b)),
                v => v.as_f64()?,
            };
            let y = f.as_ref()?.get(fact)?.as_f64()?;
            Some((x, y))
        })
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    if points.is_empty() {
        return Err(Error::usage(format!("--plot {fact} --against {axis}"), "no numeric values to plot"));
    }
    let (lo, hi) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p.0), h.max(p.0)));
    let (ylo, yhi) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p.1), h.max(p.1)));
    // A span past ~1e300 overflows the axis's arithmetic (and its ticks never end).
    for (what, a, b) in [(format!("--against {axis}"), lo, hi), (format!("--plot {fact}"), ylo, yhi)] {
        if !((b - a).is_finite() && a.abs() < 1e300 && b.abs() < 1e300) {
            return Err(Error::usage(what, format!("values from {a:e} to {b:e} cannot be plotted: |value| < 1e300")));
        }
    }
    let plot = crate::report::plots::TimePlot {
        title: format!("{}: {fact} against {axis}", info.name),
        x_label: axis.to_string(),
        y_label: fact.to_string(),
        series: vec![crate::report::plots::Series { label: fact.to_string(), points, rgb: (30, 90, 220), width: 2 }],
        nights: Vec::new(),
        x_range: (lo, if hi > lo { hi } else { lo + 1.0 }),
        windows: Vec::new(),
        windows_label: String::new(),
        dots: true,
        x_ticks: Default::default(),
    };
    crate::output::plots::write(dir, &crate::report::plots::Plot::time(format!("{fact}_vs_{axis}"), plot))
}

/// Merges every finished task's facts into `DIR/results.csv` (one row per task: index,
/// id, the axis values, status, then every fact any task reported, by name; a fact
/// named as an axis as `fact.NAME`), and with
/// `plot: Some((fact, axis))` plots that fact against that axis (`DIR/FACT_vs_AXIS`).
pub fn collect(dir: &Path, plot: Option<(&str, &str)>) -> Result<Collected> {
    let info = info(dir)?;
    let _lock = crate::output::lock::lock_dir(dir)?;
    let all = tasks(dir)?;
    let mut facts: Vec<Option<serde_json::Map<String, serde_json::Value>>> = Vec::with_capacity(all.len());
    let (mut missing, mut failed) = (Vec::new(), Vec::new());
    let mut names = BTreeSet::new();
    agree(dir, &info, &all)?;
    for t in &all {
        match finished(dir, &t.id) {
            Some(map) => {
                names.extend(map.keys().cloned());
                facts.push(Some(map));
            }
            None => {
                facts.push(None);
                match crate::read_text(&dir.join("failed").join(format!("{}.txt", t.id))) {
                    Ok(err) => failed.push((t.id.clone(), err.trim().to_string())),
                    Err(_) => match damaged(dir, &t.id) {
                        Some(why) => failed.push((t.id.clone(), why)),
                        None => missing.push(t.id.clone()),
                    },
                }
            }
        }
    }
    let failed_ids: BTreeSet<&str> = failed.iter().map(|(id, _)| id.as_str()).collect();
    let mut header: Vec<String> = vec!["index".into(), "id".into()];
    header.extend(info.axes.iter().cloned());
    header.push("status".into());
    // A fact named as one of the columns before it (a sweep over `tau` of a job that
    // reports its `tau`) keeps its own column, as `fact.NAME`.
    let leading: BTreeSet<String> = header.iter().cloned().collect();
    header.extend(names.iter().map(|n| if leading.contains(n) { format!("fact.{n}") } else { n.clone() }));
    let mut table = Table::new(header.iter().map(String::as_str));
    let cell = |v: &serde_json::Value| match v {
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    };
    for (t, f) in all.iter().zip(&facts) {
        let mut row = vec![t.index.to_string(), t.id.clone()];
        row.extend(info.axes.iter().map(|a| t.values.get(a).map_or(String::new(), cell)));
        row.push(match f {
            Some(_) => "done".into(),
            None if failed_ids.contains(t.id.as_str()) => "failed".into(),
            None => "missing".into(),
        });
        row.extend(names.iter().map(|n| f.as_ref().and_then(|m| m.get(n)).map_or(String::new(), cell)));
        table.push(row);
    }
    let mut files = vec![dir.join("results.csv")];
    table.write(&files[0])?;
    if let Some((fact, axis)) = plot {
        files.extend(plot_against(dir, &info, &all, &facts, &names, (fact, axis))?);
    }
    Ok(Collected { finished: facts.iter().filter(|f| f.is_some()).count(), missing, failed, files })
}

/// An `sbatch` script running the sweep in `dir` as a job array, at most `parallel`
/// tasks at once, `cpus` cores each; `areo` is the binary's path as the nodes see it.
pub fn slurm_script(dir: &Path, areo: &Path, parallel: usize, cpus: usize) -> Result<String> {
    let info = info(dir)?;
    let dir = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    if info.tasks == 0 {
        return Err(Error::usage(format!("sweep slurm {}", dir.display()), "the sweep has no tasks"));
    }
    let last = info.tasks - 1;
    let logs = dir.join("logs");
    let (logs, areo, dir) = (directive_path(&logs)?, shell_path(areo)?, shell_path(&dir)?);
    Ok(format!(
        "#!/bin/bash\n\
         # areo sweep {name}: {n} tasks as a Slurm job array ({parallel} at a time).\n\
         #SBATCH --job-name=areo-{job}\n\
         #SBATCH --array=0-{last}%{parallel}\n\
         #SBATCH --cpus-per-task={cpus}\n\
         #SBATCH --output={logs}\n\
         set -euo pipefail\n\
         exec {areo} -v sweep run {dir}\n",
        name = printable(&info.name),
        job = info
            .name
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '-' })
            .collect::<String>(),
        n = info.tasks,
    ))
}

/// `text` with control characters (a newline would end a comment line and start a
/// command) shown as `?`.
fn printable(text: &str) -> String {
    text.chars().map(|c| if c.is_control() { '?' } else { c }).collect()
}

/// A path as one shell word: single-quoted, `'` written `'\''`. A path with a control
/// character is refused: no script line should hold one.
fn shell_path(path: &Path) -> Result<String> {
    let text = path.to_str().filter(|t| !t.chars().any(char::is_control)).ok_or_else(|| {
        Error::usage(path.display().to_string(), "a path with control characters or not UTF-8 cannot go in a script")
    })?;
    Ok(format!("'{}'", text.replace('\'', "'\\''")))
}

/// The logs path for an `#SBATCH --output` line, double-quoted as sbatch reads its
/// directives; a path with a double quote or a control character is refused.
fn directive_path(logs: &Path) -> Result<String> {
    let text = logs.join("%A_%a.out").to_str().map(str::to_string).unwrap_or_default();
    if text.is_empty() || text.contains('"') || text.chars().any(char::is_control) {
        return Err(Error::usage(
            logs.display().to_string(),
            "a sweep directory whose path holds a double quote, a control character or is not UTF-8 cannot go in an #SBATCH line",
        ));
    }
    Ok(format!("\"{text}\""))
}

/// A string as a YAML double-quoted scalar (JSON's escapes are YAML's).
fn yaml_string(text: &str) -> String {
    serde_json::Value::String(text.to_string()).to_string()
}

/// A Kubernetes Indexed Job running the sweep in `dir` (mounted at the same path in
/// the container from a volume claim `claim`), `parallel` pods at a time.
pub fn k8s_job(dir: &Path, image: &str, claim: &str, parallel: usize) -> Result<String> {
    let info = info(dir)?;
    if info.tasks == 0 {
        return Err(Error::usage(format!("sweep k8s {}", dir.display()), "the sweep has no tasks"));
    }
    let dir = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    let name: String =
        info.name.to_ascii_lowercase().chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '-' }).collect();
    let text = |p: &Path| -> Result<String> {
        p.to_str()
            .map(yaml_string)
            .ok_or_else(|| Error::usage(p.display().to_string(), "a path that is not UTF-8 cannot go in YAML"))
    };
    Ok(format!(
        "# areo sweep {sweep}: {n} tasks as a Kubernetes Indexed Job ({parallel} at a time).\n\
         apiVersion: batch/v1\n\
         kind: Job\n\
         metadata:\n  name: areo-{name}\n\
         spec:\n  completions: {n}\n  parallelism: {parallel}\n  completionMode: Indexed\n  backoffLimitPerIndex: 2\n  maxFailedIndexes: {n}\n\
         \x20 template:\n    spec:\n      restartPolicy: Never\n      containers:\n      - name: areo\n        image: {image}\n        \
         command: [\"areo\", \"sweep\", \"run\", {dir}]\n        volumeMounts:\n        - name: sweep\n          mountPath: {mount}\n      \
         volumes:\n      - name: sweep\n        persistentVolumeClaim:\n          claimName: {claim}\n",
        sweep = printable(&info.name),
        n = info.tasks,
        image = yaml_string(image),
        claim = yaml_string(claim),
        dir = text(&dir)?,
        mount = text(dir.parent().unwrap_or(&dir))?,
    ))
}
