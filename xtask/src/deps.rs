//! The dependency-direction lint: reads `cargo metadata` and checks every areo crate's
//! dependencies against the crate map of `docs/ARCHITECTURE.md`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Which areo crates each package may depend on (normal, build and dev
/// dependencies alike: a test that reaches up the map is still a cycle in spirit).
/// The binary (`areo`) reaches the libraries only through areo-scenario, so it
/// computes nothing of its own; xtask never links the binary.
const ALLOWED: &[(&str, &[&str])] = &[
    ("areo-body", &[]),
    ("areo-terrain", &["areo-body"]),
    ("areo-ephemeris", &["areo-body"]),
    ("areo-ise", &[]),
    ("areo-rover", &["areo-terrain", "areo-body"]),
    ("areo-actions", &["areo-rover", "areo-terrain", "areo-body"]),
    ("areo-mission", &["areo-ise", "areo-terrain", "areo-ephemeris", "areo-rover", "areo-body"]),
    (
        "areo-scenario",
        &["areo-ise", "areo-terrain", "areo-ephemeris", "areo-rover", "areo-actions", "areo-mission", "areo-body"],
    ),
    ("areo", &["areo-scenario"]),
    // The Python package converts what the libraries answer; it computes nothing.
    ("areo-python", &["areo-scenario", "areo-terrain", "areo-ephemeris"]),
    ("xtask", &["areo-scenario", "areo-terrain", "areo-ephemeris", "areo-rover", "areo-mission", "areo-body"]),
];

/// The command-line stack: flag parsing, progress bars, log output. Only the binary
/// depends on it, so the libraries and xtask stay free of it.
const CLI_STACK: &[&str] = &["clap", "indicatif", "tracing-subscriber"];

/// Every dependency that breaks the map, as a sentence.
pub(crate) fn check(root: &Path) -> Result<Vec<String>, String> {
    violations(&metadata(root, &["--no-deps"])?)
}

/// `cargo metadata` of the workspace at `root`, offline, with `args` added.
fn metadata(root: &Path, args: &[&str]) -> Result<serde_json::Value, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--offline"])
        .args(args)
        .current_dir(root)
        .output()
        .map_err(|e| format!("cargo metadata: {e}"))?;
    if !out.status.success() {
        return Err(format!("cargo metadata failed: {}", String::from_utf8_lossy(&out.stderr)));
    }
    serde_json::from_slice(&out.stdout).map_err(|e| format!("cargo metadata output: {e}"))
}

fn violations(meta: &serde_json::Value) -> Result<Vec<String>, String> {
    let packages = meta["packages"].as_array().ok_or("cargo metadata: no packages")?;
    let mut found = Vec::new();
    let mut seen = Vec::new();
    for pkg in packages {
        let name = pkg["name"].as_str().unwrap_or_default();
        let Some((_, allowed)) = ALLOWED.iter().find(|(n, _)| *n == name) else { continue };
        seen.push(name.to_string());
        for dep in pkg["dependencies"].as_array().into_iter().flatten() {
            let dep_name = dep["name"].as_str().unwrap_or_default();
            // A crate may name itself as a dev-dependency to turn on a feature for its
            // own tests (areo-terrain's `reference` oracles).
            if (dep_name == "areo" || dep_name.starts_with("areo-")) && dep_name != name && !allowed.contains(&dep_name)
            {
                found.push(format!("{name} must not depend on {dep_name} (allowed: {allowed:?})"));
            }
            if name != "areo" && CLI_STACK.contains(&dep_name) {
                found.push(format!("{name} must not depend on {dep_name} (only the areo binary parses flags)"));
            }
        }
    }
    for (name, _) in ALLOWED {
        if !seen.iter().any(|s| s == name) {
            found.push(format!("{name} is missing from the workspace"));
        }
    }
    Ok(found)
}

/// Libraries that run only inside the compiler (what proc-macros and build scripts are
/// built from) without being proc-macros themselves.
const COMPILE_TIME_LIBRARIES: &[&str] = &["syn", "pyo3-macros-backend", "cc"];

/// The compile-time-only crates that the root `Cargo.toml` does not compile at opt-level 0
/// in the dev profile. `[profile.dev.package."*"]` (opt-level 2, for the numerics the
/// tests run) outranks `build-override`, so each must be named: at opt-level 2 syn took
/// ~50 s of the CI machine's two cores, three times (docs/ARCHITECTURE.md, "Testing").
pub(crate) fn optimised_compile_time_crates(root: &Path) -> Result<Vec<String>, String> {
    let meta = metadata(root, &["--filter-platform", "x86_64-unknown-linux-gnu"])?;
    let manifest = root.join("Cargo.toml");
    let text = std::fs::read_to_string(&manifest).map_err(|e| format!("{}: {e}", manifest.display()))?;
    Ok(missing_opt_level_0(&text, &compile_time_crates(&meta)))
}

/// The proc-macro packages of the resolved graph, and [`COMPILE_TIME_LIBRARIES`].
fn compile_time_crates(meta: &serde_json::Value) -> Vec<String> {
    let resolved: Vec<&str> =
        meta["resolve"]["nodes"].as_array().into_iter().flatten().filter_map(|n| n["id"].as_str()).collect();
    let mut names: Vec<String> = meta["packages"]
        .as_array()
        .into_iter()
        .flatten()
        .filter(|p| p["id"].as_str().is_some_and(|id| resolved.contains(&id)))
        .filter(|p| {
            p["targets"]
                .as_array()
                .into_iter()
                .flatten()
                .any(|t| t["kind"].as_array().into_iter().flatten().any(|k| k.as_str() == Some("proc-macro")))
        })
        .filter_map(|p| p["name"].as_str().map(str::to_string))
        .chain(COMPILE_TIME_LIBRARIES.iter().map(|s| s.to_string()))
        .collect();
    names.sort();
    names.dedup();
    names
}

/// The names without a `[profile.dev.package.<name>]` table setting `opt-level = 0`.
fn missing_opt_level_0(manifest: &str, names: &[String]) -> Vec<String> {
    names
        .iter()
        .filter(|name| {
            let header = format!("[profile.dev.package.{name}]");
            let Some(at) = manifest.find(&header) else { return true };
            let table = &manifest[at + header.len()..];
            let table = &table[..table.find("\n[").unwrap_or(table.len())];
            !table.lines().any(|l| l.split('#').next().unwrap_or("").replace(' ', "") == "opt-level=0")
        })
        .cloned()
        .collect()
}

/// The source directories the checks read: every crate's `src/` but those of the crates
/// named in `except`, the binary's, xtask's and the Python module's.
fn source_dirs(root: &Path, except: &[&str]) -> Vec<PathBuf> {
    let crates = std::fs::read_dir(root.join("crates")).into_iter().flatten().filter_map(|e| Some(e.ok()?.path()));
    crates
        .filter(|p| !except.iter().any(|c| p.ends_with(c)))
        .map(|p| p.join("src"))
        .chain(["src", "xtask/src", "python/src"].iter().map(|d| root.join(d)))
        .collect()
}

/// The directories of Rust code the size checks read: every crate's `src`, `tests` and
/// `benches`, the binary's `src` and `tests`, xtask's and the Python module's sources.
fn code_dirs(root: &Path) -> Vec<PathBuf> {
    let crates = std::fs::read_dir(root.join("crates")).into_iter().flatten().filter_map(|e| Some(e.ok()?.path()));
    crates
        .flat_map(|p| ["src", "tests", "benches"].map(|d| p.join(d)))
        .chain(["src", "tests", "xtask/src", "python/src"].iter().map(|d| root.join(d)))
        .collect()
}

/// Every `.rs` file under `dirs` (those that exist), skipping directories named in
/// `skip` and `tests.rs` unit-test files, with its text: the one walk the source checks
/// below share.
fn rust_sources(dirs: &[PathBuf], skip: &[&str]) -> Result<Vec<(PathBuf, String)>, String> {
    let mut files = Vec::new();
    let mut stack: Vec<PathBuf> = dirs.iter().filter(|d| d.is_dir()).cloned().collect();
    while let Some(dir) = stack.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for entry in entries {
            let path = entry.map_err(|e| format!("{}: {e}", dir.display()))?.path();
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            if path.is_dir() {
                if !skip.contains(&name) {
                    stack.push(path);
                }
            } else if name.ends_with(".rs") && name != "tests.rs" {
                // A `tests.rs` under a source directory is a module's unit tests
                // (`#[cfg(test)] mod tests;`), exempt as the tests at a file's end are.
                let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
                files.push((path, text));
            }
        }
    }
    Ok(files)
}

/// Lines of library sources (before each file's `#[cfg(test)]`, outside `//` comments)
/// that contain any of `needles`, as sorted `path:line`.
fn lines_containing(root: &Path, dirs: &[PathBuf], skip: &[&str], needles: &[&str]) -> Result<Vec<String>, String> {
    let mut found = Vec::new();
    for (path, text) in rust_sources(dirs, skip)? {
        // Unit tests sit at the end of a file, after `#[cfg(test)]`: they are exempt.
        for (i, line) in text.lines().enumerate().take_while(|(_, l)| l.trim() != "#[cfg(test)]") {
            let code = line.split("//").next().unwrap_or_default();
            if needles.iter().any(|w| code.contains(w)) {
                found.push(format!("{}:{}", path.strip_prefix(root).unwrap_or(&path).display(), i + 1));
            }
        }
    }
    found.sort();
    Ok(found)
}

/// Libraries print nothing: every line of a library crate's sources that writes to
/// standard output or error, as `path:line`. (Clippy's print lints catch the macros;
/// this also catches direct handles and an `#[allow]` that would silence the lint.)
/// Tests, benches and a file's unit tests may print.
pub(crate) fn printing_in_libraries(root: &Path) -> Result<Vec<String>, String> {
    const WRITERS: &[&str] = &["print!(", "println!(", "eprint!(", "eprintln!(", "io::stdout(", "io::stderr(", "dbg!("];
    lines_containing(root, &[root.join("crates")], &["tests", "benches", "examples", "target"], WRITERS)
}

/// The bodies' constants are written only in areo-body: every numeric literal in another
/// crate's sources (the binary, xtask and the Python module included; not tests, nor
/// `#[cfg(test)]` modules) whose value is a body's radius — in metres or kilometres,
/// however it is spelt (`3396190.0`, `3_396_190`, `3.39619e6`, `3396.19`) — WGS84's
/// flattening, or the length of the Martian sol in seconds or days, as
/// `path:line value`. The files are parsed, so comments and strings do not count.
pub(crate) fn body_constants_outside_areo_body(root: &Path) -> Result<Vec<String>, String> {
    let dirs = source_dirs(root, &["body"]);
    let mut found = Vec::new();
    for (path, text) in rust_sources(&dirs, &["tests", "benches"])? {
        let file = syn::parse_file(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let shown = path.strip_prefix(root).unwrap_or(&path).display().to_string();
        let mut scan = BodyLiterals { path: &shown, found: Vec::new() };
        syn::visit::Visit::visit_file(&mut scan, &file);
        found.extend(scan.found);
    }
    found.sort();
    Ok(found)
}

/// The values [`body_constants_outside_areo_body`] looks for: the IAU radii of Mars (the
/// 2015 ellipsoid, MOLA's sphere, the mean), the Moon and the Earth (WGS84, the mean), in
/// metres and kilometres; WGS84's inverse flattening; the sol in seconds and days.
const BODY_VALUES: &[f64] = &[
    3_396_190.0,
    3_376_200.0,
    3_396_000.0,
    3_389_500.0,
    1_737_400.0,
    6_378_137.0,
    6_371_008.8,
    3396.19,
    3376.2,
    3389.5,
    1737.4,
    6378.137,
    6371.0088,
    298.257_223_563,
    88_775.244,
    1.027_491_251_7,
];

/// The visitor of [`body_constants_outside_areo_body`].
struct BodyLiterals<'a> {
    path: &'a str,
    found: Vec<String>,
}

impl<'ast> syn::visit::Visit<'ast> for BodyLiterals<'_> {
    fn visit_item_const(&mut self, c: &'ast syn::ItemConst) {
        // This check's own list of the values it looks for.
        if c.ident != "BODY_VALUES" {
            syn::visit::visit_item_const(self, c);
        }
    }

    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        if !cfg_test(&m.attrs) {
            syn::visit::visit_item_mod(self, m);
        }
    }

    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        if !f.attrs.iter().any(|a| a.path().is_ident("test")) {
            syn::visit::visit_item_fn(self, f);
        }
    }

    fn visit_lit(&mut self, lit: &'ast syn::Lit) {
        let value = match lit {
            syn::Lit::Float(f) => f.base10_parse::<f64>().ok(),
            syn::Lit::Int(i) => i.base10_parse::<u64>().ok().map(|v| v as f64),
            _ => None,
        };
        if let Some(v) = value
            && BODY_VALUES.iter().any(|b| (v - b).abs() <= 1e-6 * b.abs())
        {
            self.found.push(format!("{}:{} {v}", self.path, lit.span().start().line));
        }
    }
}

/// The project describes itself as it is: every line of its text files (sources,
/// scenarios, docs, scripts; not `target/` or `.git/`) that names a work session or an
/// issue by number ("session" or "issue", singular or plural, any case, then a
/// number), or dates a measurement or a change ([`dates_the_work`]), as sorted
/// `path:line`. History lives in git.
pub(crate) fn history_references(root: &Path) -> Result<Vec<String>, String> {
    const TEXT: &[&str] = &["rs", "md", "ron", "py", "pyi", "toml", "sh", "yml", "yaml", "html", "js", "txt"];
    let mut found = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for entry in entries {
            let path = entry.map_err(|e| format!("{}: {e}", dir.display()))?.path();
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            if path.is_dir() {
                if !["target", ".git", "node_modules"].contains(&name) && !name.starts_with("ci-") {
                    stack.push(path);
                }
                continue;
            }
            let ext = path.extension().and_then(|e| e.to_str()).unwrap_or_default();
            let script = path.parent().and_then(|p| p.file_name()).is_some_and(|n| n == ".ci");
            if !TEXT.contains(&ext) && !script {
                continue;
            }
            let Ok(text) = std::fs::read_to_string(&path) else { continue };
            let lines: Vec<&str> = text.lines().collect();
            for (i, line) in lines.iter().enumerate() {
                if names_history(line)
                    || dates_the_work(line)
                    || lines.get(i + 1).is_some_and(|next| names_history(&joined(line, next)))
                {
                    found.push(format!("{}:{}", path.strip_prefix(root).unwrap_or(&path).display(), i + 1));
                }
            }
        }
    }
    found.sort();
    Ok(found)
}

/// `line` and the text of `next`, as one line: a sentence wrapped between "issue" and
/// its number in a comment or a paragraph names history all the same.
fn joined(line: &str, next: &str) -> String {
    let end = line.trim_end().to_lowercase();
    if !["session", "sessions", "issue", "issues"].iter().any(|w| end.ends_with(w)) {
        return String::new();
    }
    let text = next.trim_start().trim_start_matches(['/', '#', '!', '*', '>']).trim_start();
    format!("{} {text}", line.trim_end())
}

/// Whether `line` holds a calendar date of the project's own years (2026–2099) that is
/// not an instant (`YYYY-MM-DD` not followed by `T`) nor a quoted value: "measured on
/// such a day", "until that day it read…". Instants a scenario plans at carry their
/// time (`…T22:15:00Z`), a day given to a command is quoted, and dates of data (an
/// ephemeris, a DEM's acquisition) lie before the project.
fn dates_the_work(line: &str) -> bool {
    let b = line.as_bytes();
    (0..b.len().saturating_sub(9)).any(|i| {
        let d = &b[i..i + 10];
        let digits = |r: std::ops::Range<usize>| d[r].iter().all(u8::is_ascii_digit);
        let year = std::str::from_utf8(&d[..4]).ok().and_then(|y| y.parse::<u32>().ok());
        (i == 0 || !(b[i - 1].is_ascii_digit() || b[i - 1] == b'"'))
            && digits(0..4)
            && d[4] == b'-'
            && digits(5..7)
            && d[7] == b'-'
            && digits(8..10)
            && year.is_some_and(|y| (2026..2100).contains(&y))
            && b.get(i + 10).is_none_or(|&c| c != b'T' && !c.is_ascii_digit())
    })
}

/// Whether `line` has "session" or "issue" (plural too, any case) as a word followed by
/// a space and a digit.
fn names_history(line: &str) -> bool {
    let lower = line.to_lowercase();
    let bytes = lower.as_bytes();
    ["session", "issue"].iter().any(|word| {
        lower.match_indices(word).any(|(at, _)| {
            let before = at.checked_sub(1).map(|b| bytes[b]);
            if before.is_some_and(|b| b.is_ascii_alphanumeric()) {
                return false;
            }
            let mut rest = &lower[at + word.len()..];
            rest = rest.strip_prefix('s').unwrap_or(rest);
            rest.strip_prefix(' ').is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit()))
        })
    })
}

/// Functions longer than `max` lines (from `fn` to the closing brace) in the sources of
/// every crate, the binary, xtask and the Python module and in their tests and benches,
/// as `path:line name (n lines)`: code, test code too, stays a set of small steps. The
/// files are parsed (`syn`), so every form counts — free functions, methods, a trait's
/// default bodies, functions inside functions, `#[test]` functions and those of
/// `#[cfg(test)]` modules, whatever their visibility (`pub(super)`, `pub(in …)`) or
/// qualifiers (`const`, `async`, `unsafe`, `extern`).
pub(crate) fn long_functions(root: &Path, max: usize) -> Result<Vec<String>, String> {
    let dirs = code_dirs(root);
    let mut found = Vec::new();
    for (path, text) in rust_sources(&dirs, &[])? {
        let file = syn::parse_file(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let shown = path.strip_prefix(root).unwrap_or(&path).display().to_string();
        let mut scan = LongFunctions { max, path: &shown, found: Vec::new() };
        syn::visit::Visit::visit_file(&mut scan, &file);
        found.extend(scan.found);
    }
    found.sort();
    Ok(found)
}

/// The writers of reports (`crates/scenario/src/output/reports.rs` and any module under
/// `output/reports/`) name nothing but report types, the output modules, the error
/// type, the Sun table's CSV header and areo-terrain's GeoTIFF writer: a file shows what
/// the report holds and is never computed from a world, a map or a plan. Every path
/// naming something outside that list, as `path:line path`.
pub(crate) fn writers_outside_reports(root: &Path) -> Result<Vec<String>, String> {
    let dir = root.join("crates/scenario/src/output");
    let mut sources = Vec::new();
    if dir.join("reports.rs").exists() {
        sources.push(dir.join("reports.rs"));
    }
    sources.extend(rust_sources(&[dir.join("reports")], &[])?.into_iter().map(|(p, _)| p));
    let mut found = Vec::new();
    for path in sources {
        let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let file = syn::parse_file(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let shown = path.strip_prefix(root).unwrap_or(&path).display().to_string();
        let mut scan = ReportPaths { path: &shown, found: Vec::new() };
        syn::visit::Visit::visit_file(&mut scan, &file);
        found.extend(scan.found);
    }
    Ok(found)
}

/// What a report writer may name: (first segment, second segment or "" for any).
const WRITER_PATHS: &[(&str, &str)] = &[
    ("crate", "report"),
    ("crate", "output"),
    ("crate", "error"),
    ("crate", "sun::CSV_HEADER"),
    ("areo_terrain", "geotiff"),
];

/// The visitor of [`writers_outside_reports`].
struct ReportPaths<'a> {
    path: &'a str,
    found: Vec<String>,
}

impl ReportPaths<'_> {
    fn check(&mut self, segments: &[String], line: usize) {
        let Some(first) = segments.first() else { return };
        // A lone `crate` is a visibility (`pub(crate)`), not a path into the crate.
        let watched = (first == "crate" && segments.len() > 1) || first.starts_with("areo");
        if !watched {
            return;
        }
        let rest = segments[1..].join("::");
        let allowed =
            WRITER_PATHS.iter().any(|(a, b)| a == first && (rest == *b || rest.starts_with(&format!("{b}::"))));
        if !allowed {
            self.found.push(format!("{}:{line} {}", self.path, segments.join("::")));
        }
    }

    /// Every path a `use` tree names, with `prefix` before it.
    fn use_tree(&mut self, tree: &syn::UseTree, prefix: &mut Vec<String>, line: usize) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(&p.tree, prefix, line);
                prefix.pop();
            }
            syn::UseTree::Name(n) => self.check(&[prefix.clone(), vec![n.ident.to_string()]].concat(), line),
            syn::UseTree::Rename(r) => self.check(&[prefix.clone(), vec![r.ident.to_string()]].concat(), line),
            syn::UseTree::Glob(_) => self.check(&[prefix.clone(), vec!["*".into()]].concat(), line),
            syn::UseTree::Group(g) => g.items.iter().for_each(|t| self.use_tree(t, prefix, line)),
        }
    }
}

impl<'ast> syn::visit::Visit<'ast> for ReportPaths<'_> {
    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        self.use_tree(&u.tree, &mut Vec::new(), u.use_token.span.start().line);
    }

    fn visit_path(&mut self, p: &'ast syn::Path) {
        let segments: Vec<String> = p.segments.iter().map(|s| s.ident.to_string()).collect();
        let line = p.segments.first().map_or(0, |s| s.ident.span().start().line);
        self.check(&segments, line);
        syn::visit::visit_path(self, p);
    }
}

/// Source files of every crate, the binary, xtask and the Python module longer than
/// `max` lines, as `path (n lines)`: a file holds one subject a reader can take in.
pub(crate) fn long_files(root: &Path, max: usize) -> Result<Vec<String>, String> {
    let dirs = code_dirs(root);
    let mut found: Vec<String> = rust_sources(&dirs, &[])?
        .into_iter()
        .filter(|(_, text)| text.lines().count() > max)
        .map(|(path, text)| {
            format!("{} ({} lines)", path.strip_prefix(root).unwrap_or(&path).display(), text.lines().count())
        })
        .collect();
    found.sort();
    Ok(found)
}

/// The visitor of [`long_functions`].
struct LongFunctions<'a> {
    max: usize,
    path: &'a str,
    found: Vec<String>,
}

impl LongFunctions<'_> {
    fn check(&mut self, sig: &syn::Signature, block: &syn::Block) {
        let first = sig.fn_token.span.start().line;
        let last = block.brace_token.span.close().end().line;
        let lines = last + 1 - first;
        if lines > self.max {
            self.found.push(format!("{}:{first} {} ({lines} lines)", self.path, sig.ident));
        }
    }
}

/// Whether `attrs` hold `#[cfg(test)]`.
fn cfg_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| a.path().is_ident("cfg") && a.parse_args::<syn::Ident>().is_ok_and(|i| i == "test"))
}

impl<'ast> syn::visit::Visit<'ast> for LongFunctions<'_> {
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        self.check(&f.sig, &f.block);
        syn::visit::visit_item_fn(self, f);
    }

    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        self.check(&f.sig, &f.block);
        syn::visit::visit_impl_item_fn(self, f);
    }

    fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
        if let Some(block) = &f.default {
            self.check(&f.sig, block);
        }
        syn::visit::visit_trait_item_fn(self, f);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workspace_dependencies_point_down() {
        let v = check(&crate::project_root()).unwrap();
        assert!(v.is_empty(), "{v:#?}");
    }

    #[test]
    fn compile_time_crates_are_compiled_unoptimised() {
        let missing = optimised_compile_time_crates(&crate::project_root()).unwrap();
        assert!(missing.is_empty(), "name them in Cargo.toml with opt-level = 0: {missing:?}");
        // The check sees a crate left out, or left at another level.
        let names = vec!["serde_derive".to_string(), "syn".to_string()];
        let manifest = "[profile.dev.package.\"*\"]\nopt-level = 2\n[profile.dev.package.syn]\nopt-level = 0\n";
        assert_eq!(missing_opt_level_0(manifest, &names), vec!["serde_derive".to_string()]);
        let manifest =
            "[profile.dev.package.serde_derive]\nopt-level = 2\n[profile.dev.package.syn]\nopt-level = 0 # why\n";
        assert_eq!(missing_opt_level_0(manifest, &names), vec!["serde_derive".to_string()]);
        // The real graph has the proc-macros this was written for.
        let meta: serde_json::Value = serde_json::from_slice(
            &std::process::Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
                .args([
                    "metadata",
                    "--format-version",
                    "1",
                    "--offline",
                    "--filter-platform",
                    "x86_64-unknown-linux-gnu",
                ])
                .current_dir(crate::project_root())
                .output()
                .unwrap()
                .stdout,
        )
        .unwrap();
        let found = compile_time_crates(&meta);
        for name in ["serde_derive", "thiserror-impl", "clap_derive", "syn"] {
            assert!(found.iter().any(|f| f == name), "{name} not among {found:?}");
        }
    }

    #[test]
    fn body_constants_live_in_areo_body_alone() {
        let found = body_constants_outside_areo_body(&crate::project_root()).unwrap();
        assert!(found.is_empty(), "radii, flattening and the sol are areo-body's: {found:#?}");
        // The scan sees them however they are spelt, and not in comments, strings or
        // tests.
        let dir = std::env::temp_dir().join(format!("areo-body-scan-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("crates/x/src")).unwrap();
        let text = "// 3_389_500 in a comment\nconst R: f64 = 1_737_400.0;\nconst S: f64 = 3.39619e6;\n\
                    const K: f64 = 3396.19;\nconst SOL: f64 = 88775.244;\nconst N: &str = \"6378137\";\n\
                    const F: f64 = 298.257223563;\nconst OK: f64 = 3396.5;\n\
                    #[cfg(test)]\nmod tests {\n    const T: f64 = 1737400.0;\n}\n";
        std::fs::write(dir.join("crates/x/src/lib.rs"), text).unwrap();
        let found = body_constants_outside_areo_body(&dir).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let lines: Vec<&str> = found.iter().map(|f| f.split(' ').next().unwrap()).collect();
        assert_eq!(
            lines,
            [
                "crates/x/src/lib.rs:2",
                "crates/x/src/lib.rs:3",
                "crates/x/src/lib.rs:4",
                "crates/x/src/lib.rs:5",
                "crates/x/src/lib.rs:7"
            ],
            "{found:#?}"
        );
    }

    #[test]
    fn no_session_or_issue_numbers_in_the_project() {
        let found = history_references(&crate::project_root()).unwrap();
        assert!(found.is_empty(), "the project describes itself as it is; history lives in git: {found:#?}");
        // The scan sees them when they are there, and not where the words stand alone.
        let (s, i) = ("Session", "issues");
        assert!(names_history(&format!("// {s} 12 measured it")));
        assert!(names_history(&format!("see {i} 3 and 4")));
        assert!(names_history(&format!("({} 65)", "issue")));
        assert!(!names_history(&format!("a {} of 3 sols", "session")));
        assert!(!names_history(&format!("Communicate {}s: 2", "session")));
        assert!(!names_history(&format!("re{} 5", "issue")));
        let day = ["2026", "11", "25"].join("-");
        assert!(dates_the_work(&format!("// measured {day}: 1.83°")));
        assert!(dates_the_work(&format!("(until {day} it read 35°)")));
        assert!(!dates_the_work(&format!("start_utc: \"{day}T22:15:00Z\"")));
        assert!(!dates_the_work("the LOLA product of 2025-01-10, 100 h"));
        assert!(!dates_the_work("valid 1600–2600"));
        assert!(!dates_the_work("areo sun --day \"2600-12-31\""));
        let dir = std::env::temp_dir().join(format!("areo-history-scan-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("docs")).unwrap();
        std::fs::write(dir.join("docs/a.md"), format!("fine\nas of {} 9\n", "session")).unwrap();
        std::fs::write(dir.join("docs/b.ron"), format!("// checked ({}\n    // 34): equal\nfine\n", "issue")).unwrap();
        assert_eq!(history_references(&dir).unwrap(), vec!["docs/a.md:2".to_string(), "docs/b.ron:1".to_string()]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn no_source_file_over_a_thousand_lines() {
        let found = long_files(&crate::project_root(), 1000).unwrap();
        assert!(found.is_empty(), "source files stay under 1 000 lines: {found:#?}");
        let dir = std::env::temp_dir().join(format!("areo-long-file-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("crates/x/src")).unwrap();
        std::fs::write(dir.join("crates/x/src/lib.rs"), "// a line\n".repeat(1001)).unwrap();
        std::fs::write(dir.join("crates/x/src/ok.rs"), "// a line\n".repeat(1000)).unwrap();
        let found = long_files(&dir, 1000).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(found, vec!["crates/x/src/lib.rs (1001 lines)".to_string()]);
    }

    #[test]
    fn no_long_functions_anywhere() {
        let found = long_functions(&crate::project_root(), 80).unwrap();
        assert!(found.is_empty(), "functions stay under 80 lines: {found:#?}");
    }

    /// Every form of function is seen, whatever its visibility and qualifiers; tests
    /// are not.
    #[test]
    fn the_length_check_sees_every_form_of_function() {
        let dir = std::env::temp_dir().join(format!("areo-long-fn-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("crates/x/src")).unwrap();
        let body = "    let x = 1;\n".repeat(79);
        let forms = [
            "fn a() {B}",
            "pub(super) fn b() {B}",
            "pub(in crate::m) fn c() {B}",
            "pub async fn d() {B}",
            "pub(crate) const fn e() {B}",
            "unsafe fn f() {B}",
            "pub extern \"C\" fn x() {B}",
            "struct S;\nimpl S {\n    pub fn g(&self) {B}\n}",
            "trait T {\n    fn h(&self) {B}\n}",
            "#[test]\nfn t() {B}",
            "#[cfg(test)]\nmod tests {\n    fn u() {B}\n}",
            "fn short() {\n}",
        ];
        let text: String = forms.iter().map(|f| f.replace('B', &format!("\n{body}")) + "\n").collect();
        std::fs::write(dir.join("crates/x/src/lib.rs"), &text).unwrap();
        let found = long_functions(&dir, 80).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let mut names: Vec<&str> = found.iter().map(|f| f.split(' ').nth(1).unwrap()).collect();
        names.sort_unstable();
        // Test code counts too: a `#[test]` function and one in a `#[cfg(test)]` module.
        assert_eq!(names, ["a", "b", "c", "d", "e", "f", "g", "h", "t", "u", "x"], "{found:#?}");
        assert!(found.iter().all(|f| f.ends_with("(81 lines)")), "{found:#?}");
        assert!(found.iter().any(|f| f.starts_with("crates/x/src/lib.rs:1 a ")), "{found:#?}");
    }

    #[test]
    fn report_writers_name_only_reports_and_output_libraries() {
        let found = writers_outside_reports(&crate::project_root()).unwrap();
        assert!(found.is_empty(), "a report's writers read the report alone: {found:#?}");
        // The scan finds a world, a plan or a job module named however it is written.
        let dir = std::env::temp_dir().join(format!("areo-writer-scan-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("crates/scenario/src/output/reports")).unwrap();
        std::fs::write(
            dir.join("crates/scenario/src/output/reports.rs"),
            "use crate::report::Report;\nuse crate::{output::csv::Table, jobs::tempest};\nuse areo_terrain::geotiff;\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("crates/scenario/src/output/reports/plan.rs"),
            "fn f(w: &areo_mission::World) {\n    let s = crate::sun::CSV_HEADER;\n    let _ = crate::terrain::read_dem(p);\n}\n",
        )
        .unwrap();
        let found = writers_outside_reports(&dir).unwrap();
        assert_eq!(
            found,
            [
                "crates/scenario/src/output/reports.rs:2 crate::jobs::tempest",
                "crates/scenario/src/output/reports/plan.rs:1 areo_mission::World",
                "crates/scenario/src/output/reports/plan.rs:3 crate::terrain::read_dem",
            ],
            "{found:#?}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn no_library_prints() {
        let found = printing_in_libraries(&crate::project_root()).unwrap();
        assert!(found.is_empty(), "libraries print nothing; the binary does: {found:#?}");
        // The scan itself finds a print where there is one.
        let dir = std::env::temp_dir().join(format!("areo-print-scan-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("crates/x/src")).unwrap();
        std::fs::write(
            dir.join("crates/x/src/lib.rs"),
            "// println!(\"ok\")\nfn f() { println!(\"hi\"); }\n#[cfg(test)]\nfn g() { println!(\"in a test\"); }\n",
        )
        .unwrap();
        assert_eq!(printing_in_libraries(&dir).unwrap(), vec!["crates/x/src/lib.rs:2".to_string()]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_upward_dependency_is_reported() {
        let mut meta: serde_json::Value = serde_json::json!({"packages": []});
        let pkgs = meta["packages"].as_array_mut().unwrap();
        for (name, _) in ALLOWED {
            pkgs.push(serde_json::json!({"name": name, "dependencies": []}));
        }
        pkgs[3]["dependencies"] = serde_json::json!([{"name": "areo-mission"}, {"name": "serde"}]);
        let v = violations(&meta).unwrap();
        assert_eq!(v, vec!["areo-ise must not depend on areo-mission (allowed: [])".to_string()]);
    }

    #[test]
    fn the_cli_stack_outside_the_binary_is_reported() {
        let mut meta: serde_json::Value = serde_json::json!({"packages": []});
        let pkgs = meta["packages"].as_array_mut().unwrap();
        for (name, _) in ALLOWED {
            let deps = if *name == "areo" || *name == "areo-scenario" {
                serde_json::json!([{"name": "clap"}])
            } else {
                serde_json::json!([])
            };
            pkgs.push(serde_json::json!({"name": name, "dependencies": deps}));
        }
        let v = violations(&meta).unwrap();
        assert_eq!(v, vec!["areo-scenario must not depend on clap (only the areo binary parses flags)".to_string()]);
    }
}
