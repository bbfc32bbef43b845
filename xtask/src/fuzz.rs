//! `cargo xtask fuzz [--cases N] [--seed S] [--timeout-s T]`: the long, seeded part of
//! the robustness suite (the fast part is `crates/scenario/tests/robustness.rs` and
//! `tests/hostile.rs`). Each case runs the release binary on a hostile input in a fresh
//! directory and must end within the time bound with exit 0, 2, 3 or 4 — never a panic
//! (101), an abort (134), a signal, exit 1 or a file written outside its `--out`.
//!
//! Cases, drawn by a ChaCha8 generator from the seed: a number of a shipped scenario
//! replaced by a hostile value (NaN, ±inf, 0, −1, ±1e308, a subnormal, a huge integer,
//! random bits), a number of a shipped rover file likewise, a shipped scenario cut short,
//! DEM files (GeoTIFF, ESRI ASCII, PDS3) with bytes flipped or cut, and hostile flags
//! for `areo terrain` and `areo sun`, and files that are not what they seem (a FIFO or a
//! device as an input, nesting thousands deep, a sweep with a hostile name or count, an
//! output that is a link to the input).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use areo_scenario::format::locate;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const HOSTILE: &[&str] =
    &["NaN", "inf", "-inf", "0", "-1", "1e308", "-1e308", "5e-324", "18446744073709551615", "1e400", "0.5", "1e9"];

/// Options of one fuzz run.
pub(crate) struct Options {
    cases: usize,
    seed: u64,
    timeout: Duration,
}

impl Options {
    pub(crate) fn parse(args: &[String]) -> Result<Options, String> {
        // The binary's own calibration: 2e10 steps are 10–40 minutes of work, so the
        // 2e9 every case runs at are up to 4 minutes (seed 5 drew a case that took 194 s).
        let mut o = Options { cases: 300, seed: 1, timeout: Duration::from_secs(240) };
        let mut it = args.iter();
        while let Some(flag) = it.next() {
            let value = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
            let n = value.parse::<u64>().map_err(|_| format!("{flag} {value}: a whole number"))?;
            match flag.as_str() {
                "--cases" => o.cases = n as usize,
                "--seed" => o.seed = n,
                "--timeout-s" => o.timeout = Duration::from_secs(n),
                _ => return Err(format!("unknown flag {flag} (--cases, --seed, --timeout-s)")),
            }
        }
        Ok(o)
    }
}

/// What one case did.
#[derive(Debug)]
struct Outcome {
    kind: &'static str,
    what: String,
    /// The exit code, or `None` for a signal or a timeout.
    code: Option<i32>,
    timed_out: bool,
    outside: Vec<String>,
    stderr: String,
}

impl Outcome {
    /// Whether an error message places itself: a `FILE:LINE:COL:` prefix or a named
    /// field (what every exit 2 about a scenario or rover file must have).
    fn located(&self) -> bool {
        let has_line_col = self.stderr.match_indices(':').any(|(i, _)| {
            let rest = &self.stderr[i + 1..];
            let line = rest.bytes().take_while(u8::is_ascii_digit).count();
            line > 0
                && rest[line..].starts_with(':')
                && rest[line + 1..].bytes().next().is_some_and(|b| b.is_ascii_digit())
        });
        // A job over its budget, or stopped by it, names the flag that governs it.
        let budget = self.stderr.contains("--max-work") || self.stderr.contains("--max-memory-gb");
        has_line_col || self.stderr.contains("field `") || budget
    }

    /// Scenario and rover file cases whose exit-2 error must be located.
    fn must_locate(&self) -> bool {
        self.code == Some(2) && matches!(self.kind, "scenario number" | "scenario cut" | "rover number" | "rover check")
    }

    fn finding(&self) -> Option<String> {
        let why = if self.timed_out {
            "did not end within the time bound".to_string()
        } else if !self.outside.is_empty() {
            format!("wrote outside --out: {:?}", self.outside)
        } else {
            match self.code {
                Some(2) if self.must_locate() && !self.located() => "exit 2 without a field or line:column".into(),
                Some(0 | 2 | 3 | 4) => return None,
                Some(c) => format!("exit {c}"),
                None => "killed by a signal".into(),
            }
        };
        let first =
            self.stderr.lines().find(|l| !l.trim().is_empty()).unwrap_or("").chars().take(300).collect::<String>();
        Some(format!("[{}] {}: {why}\n      {first}", self.kind, self.what))
    }
}

pub(crate) fn run(root: &Path, opts: &Options) -> Result<bool, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .args(["build", "--quiet", "--release", "--bin", "areo"])
        .current_dir(root)
        .status()
        .map_err(|e| format!("cargo build: {e}"))?;
    if !status.success() {
        return Err("cargo build --release failed".into());
    }
    let bin = root.join("target/release/areo");
    let work = root.join("target/fuzz");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).map_err(|e| format!("{}: {e}", work.display()))?;
    let corpus = Corpus::load(root)?;
    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    let started = Instant::now();
    let mut outcomes = Vec::new();
    for i in 0..opts.cases {
        let dir = work.join(format!("case-{i:05}"));
        std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
        let case = corpus.draw(&mut rng, &dir)?;
        outcomes.push(execute(&bin, &dir, case, opts.timeout));
        // Keep the disk small: only a failing case's directory is kept.
        if outcomes.last().is_some_and(|o: &Outcome| o.finding().is_none()) {
            let _ = std::fs::remove_dir_all(&dir);
        }
    }
    let findings: Vec<String> = outcomes.iter().filter_map(Outcome::finding).collect();
    let mut report = String::new();
    let _ = writeln!(
        report,
        "fuzz: {} cases, seed {}, {:.0} s, time bound {} s",
        outcomes.len(),
        opts.seed,
        started.elapsed().as_secs_f64(),
        opts.timeout.as_secs()
    );
    let mut kinds: Vec<&str> = outcomes.iter().map(|o| o.kind).collect();
    kinds.sort_unstable();
    kinds.dedup();
    for kind in kinds {
        let of: Vec<&Outcome> = outcomes.iter().filter(|o| o.kind == kind).collect();
        let count = |c: i32| of.iter().filter(|o| o.code == Some(c) && !o.timed_out).count();
        let _ = writeln!(
            report,
            "  {kind:<18} {:>5} cases: exit 0 {:>4}, exit 2 {:>4}, exit 3 {:>3}, findings {}",
            of.len(),
            count(0),
            count(2),
            count(3),
            of.iter().filter(|o| o.finding().is_some()).count()
        );
    }
    let must: Vec<&Outcome> = outcomes.iter().filter(|o| o.must_locate()).collect();
    let _ = writeln!(
        report,
        "located: {} of {} exit-2 errors about scenario and rover files name a field or line:column",
        must.iter().filter(|o| o.located()).count(),
        must.len()
    );
    let _ = writeln!(report, "findings: {}", findings.len());
    for f in &findings {
        let _ = writeln!(report, "  {f}");
    }
    print!("{report}");
    std::fs::write(work.join("report.txt"), &report).map_err(|e| e.to_string())?;
    Ok(findings.is_empty())
}

/// One command to run in its case directory.
struct Case {
    kind: &'static str,
    what: String,
    args: Vec<String>,
}

fn execute(bin: &Path, dir: &Path, case: Case, timeout: Duration) -> Outcome {
    let before = listing(dir);
    let child = Command::new(bin)
        .args(&case.args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            return Outcome {
                kind: case.kind,
                what: case.what,
                code: None,
                timed_out: false,
                outside: vec![],
                stderr: e.to_string(),
            };
        }
    };
    let start = Instant::now();
    let (code, timed_out) = loop {
        match child.try_wait() {
            Ok(Some(status)) => break (status.code(), false),
            Ok(None) if start.elapsed() > timeout => {
                let _ = child.kill();
                let _ = child.wait();
                break (None, true);
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(_) => break (None, false),
        }
    };
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    // Everything new in the case directory must be under out/.
    let outside = listing(dir).into_iter().filter(|p| !before.contains(p) && !p.starts_with("out")).collect();
    Outcome { kind: case.kind, what: case.what, code, timed_out, outside, stderr }
}

/// Every file and directory under `dir`, relative to it.
fn listing(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for e in entries.flatten() {
            let p = e.path();
            out.push(p.strip_prefix(dir).unwrap_or(&p).to_string_lossy().into_owned());
            if p.is_dir() {
                stack.push(p);
            }
        }
    }
    out
}

/// The shipped inputs that cases are made from.
struct Corpus {
    scenarios: Vec<(String, String)>,
    rovers: Vec<(String, String)>,
    lsr1: String,
    dems: Vec<(&'static str, Vec<u8>)>,
    rover_dir: PathBuf,
}

impl Corpus {
    fn load(root: &Path) -> Result<Corpus, String> {
        let read = |p: &Path| std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()));
        let ron_files = |dir: &Path| -> Result<Vec<(String, String)>, String> {
            let mut v = Vec::new();
            for e in std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?.flatten() {
                let p = e.path();
                if p.extension().is_some_and(|x| x == "ron") {
                    v.push((p.file_name().unwrap_or_default().to_string_lossy().into_owned(), read(&p)?));
                }
            }
            v.sort();
            Ok(v)
        };
        let tif = root.join("crates/terrain/tests/data/gale_mola_crop_64.tif");
        let tif = std::fs::read(&tif).map_err(|e| format!("{}: {e}", tif.display()))?;
        let mut asc = String::from("ncols 8\nnrows 6\nxllcorner 100\nyllcorner 200\ncellsize 10\nNODATA_value -9999\n");
        for r in 0..6 {
            let row: Vec<String> = (0..8).map(|c| format!("{}", (r * 8 + c) * 3 % 17)).collect();
            asc += &(row.join(" ") + "\n");
        }
        let mut pds =
            "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 512\r\nLABEL_RECORDS = 1\r\n\
             ^IMAGE = 2\r\nOBJECT = IMAGE\r\n  LINES = 4\r\n  LINE_SAMPLES = 5\r\n  SAMPLE_TYPE = MSB_INTEGER\r\n\
             SAMPLE_BITS = 16\r\n  SCALING_FACTOR = 0.5\r\n  MISSING_CONSTANT = -32768\r\nEND_OBJECT = IMAGE\r\n\
             OBJECT = IMAGE_MAP_PROJECTION\r\n  MAP_PROJECTION_TYPE = \"SIMPLE CYLINDRICAL\"\r\n\
             A_AXIS_RADIUS = 3396.0 <KM>\r\n  B_AXIS_RADIUS = 3396.0 <KM>\r\n  MAP_SCALE = 0.4630 <KM/PIXEL>\r\n\
             CENTER_LATITUDE = 0.0 <DEGREE>\r\n  CENTER_LONGITUDE = 90.0 <DEGREE>\r\n\
             LINE_PROJECTION_OFFSET = -10.5 <PIXEL>\r\n  SAMPLE_PROJECTION_OFFSET = 20.5 <PIXEL>\r\n\
             END_OBJECT = IMAGE_MAP_PROJECTION\r\nEND\r\n"
                .to_string()
                .into_bytes();
        pds.resize(512, b' ');
        for i in 0..20i16 {
            pds.extend_from_slice(&(i * 7 - 30).to_be_bytes());
        }
        Ok(Corpus {
            scenarios: ron_files(&root.join("scenarios"))?,
            rovers: ron_files(&root.join("scenarios/rovers"))?,
            lsr1: read(&root.join("crates/rover/params/lsr1.ron"))?,
            dems: vec![("dem.tif", tif), ("dem.asc", asc.into_bytes()), ("dem.img", pds)],
            rover_dir: root.join("scenarios/rovers"),
        })
    }

    /// Draws a case and writes its inputs into `dir`.
    fn draw(&self, rng: &mut ChaCha8Rng, dir: &Path) -> Result<Case, String> {
        let write = |name: &str, bytes: &[u8]| write_in(dir, name, bytes);
        // Every scenario may name a rover file: give each case the shipped ones.
        std::fs::create_dir_all(dir.join("rovers")).map_err(|e| e.to_string())?;
        for (name, text) in &self.rovers {
            write(&format!("rovers/{name}"), text.as_bytes())?;
        }
        let _ = &self.rover_dir;
        let pick = rng.random_range(0..100u32);
        Ok(if pick < 45 {
            let (name, text) = &self.scenarios[rng.random_range(0..self.scenarios.len())];
            let (mutated, what) = mutate_number(rng, text);
            write(name, mutated.as_bytes())?;
            Case { kind: "scenario number", what: format!("{name}: {what}"), args: run_args(name) }
        } else if pick < 60 {
            let (name, text) = &self.scenarios[rng.random_range(0..self.scenarios.len())];
            let mut cut = rng.random_range(0..text.len());
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            write(name, &text.as_bytes()[..cut])?;
            Case { kind: "scenario cut", what: format!("{name} cut at byte {cut}"), args: run_args(name) }
        } else if pick < 72 {
            self.rover_case(rng, dir)?
        } else if pick < 78 {
            let (mutated, what) = mutate_number(rng, &self.lsr1);
            write("lsr1.ron", mutated.as_bytes())?;
            let terrain = ["flat", "slope:20", "side-slope:15", "step:0.2"][rng.random_range(0..4)];
            Case {
                kind: "rover check",
                what: format!("lsr1.ron: {what}, {terrain}"),
                args: ["rover", "check", "lsr1.ron", "--terrain", terrain].map(String::from).to_vec(),
            }
        } else if pick < 92 {
            self.dem_case(rng, dir)?
        } else if pick < 96 {
            self.file_case(rng, dir)?
        } else {
            self.flag_case(rng, dir)?
        })
    }
}

impl Corpus {
    /// A rover file with a number mutated, checked by the cheapest scenario that uses it.
    fn rover_case(&self, rng: &mut ChaCha8Rng, dir: &Path) -> Result<Case, String> {
        let write = |name: &str, bytes: &[u8]| write_in(dir, name, bytes);
        // A rover file of the scenario that uses it.
        let (rover, text) = &self.rovers[rng.random_range(0..self.rovers.len())];
        let (mutated, what) = mutate_number(rng, text);
        write(&format!("rovers/{rover}"), mutated.as_bytes())?;
        let user = self
            .scenarios
            .iter()
            .filter(|(_, t)| t.contains(rover.as_str()))
            // The cheapest user, so that the rover's numbers are checked by a run
            // the fuzz's work budget admits.
            .min_by_key(|(n, t)| {
                areo_scenario::format::parse(Path::new(n), t)
                    .ok()
                    .and_then(|s| areo_scenario::budget::estimate(&s))
                    .map_or(u64::MAX, |e| e.work_steps)
            })
            .ok_or_else(|| format!("no scenario uses rovers/{rover}"))?;
        write(&user.0, user.1.as_bytes())?;
        Ok(Case { kind: "rover number", what: format!("rovers/{rover}: {what}"), args: run_args(&user.0) })
    }

    /// A DEM cut short, with bits flipped or with random bytes, read by a terrain command.
    fn dem_case(&self, rng: &mut ChaCha8Rng, dir: &Path) -> Result<Case, String> {
        let (name, bytes) = &self.dems[rng.random_range(0..self.dems.len())];
        let mut b = bytes.clone();
        let what = match rng.random_range(0..3u32) {
            0 => {
                let cut = rng.random_range(0..b.len());
                b.truncate(cut);
                format!("{name} cut at byte {cut}")
            }
            1 => {
                let n = rng.random_range(1..8usize);
                // Headers matter most: flip within the first 600 bytes half the time.
                let span = if rng.random_range(0..2u32) == 0 { b.len().min(600) } else { b.len() };
                for _ in 0..n {
                    let i = rng.random_range(0..span);
                    b[i] ^= 1 << rng.random_range(0..8u32);
                }
                format!("{name} with {n} bits flipped")
            }
            _ => {
                let i = rng.random_range(0..b.len());
                let n = rng.random_range(1..16usize).min(b.len() - i);
                for k in 0..n {
                    b[i + k] = rng.random::<u8>();
                }
                format!("{name} with {n} random bytes at {i}")
            }
        };
        write_in(dir, name, &b)?;
        let args: Vec<String> = match rng.random_range(0..3u32) {
            0 => vec!["terrain".into(), "info".into(), (*name).into()],
            1 => ["terrain", "shadow", name, "--sun-azimuth", "100", "--sun-elevation", "5", "-o", "out/s.tif"]
                .map(String::from)
                .to_vec(),
            _ => ["terrain", "horizon", name, "--sectors", "16", "-o", "out/h.tif"].map(String::from).to_vec(),
        };
        std::fs::create_dir_all(dir.join("out")).map_err(|e| e.to_string())?;
        Ok(Case { kind: "dem bytes", what: format!("{what}: {}", args[1]), args })
    }

    /// Hostile values in the command-line flags.
    fn flag_case(&self, rng: &mut ChaCha8Rng, dir: &Path) -> Result<Case, String> {
        let values: Vec<String> = (0..3).map(|_| HOSTILE[rng.random_range(0..HOSTILE.len())].to_string()).collect();
        let v = |i: usize| values[i].clone();
        let (tif_name, tif) = &self.dems[0];
        write_in(dir, tif_name, tif)?;
        std::fs::create_dir_all(dir.join("out")).map_err(|e| e.to_string())?;
        let args: Vec<String> = match rng.random_range(0..4u32) {
            0 => vec![
                "terrain".into(),
                "shadow".into(),
                (*tif_name).into(),
                format!("--sun-azimuth={}", v(0)),
                format!("--sun-elevation={}", v(1)),
                "-o".into(),
                "out/s.tif".into(),
            ],
            1 => vec![
                "terrain".into(),
                "viewshed".into(),
                (*tif_name).into(),
                format!("--from={},{},{}", v(0), v(1), v(2)),
                "-o".into(),
                "out/v.tif".into(),
            ],
            2 => vec![
                "terrain".into(),
                "horizon".into(),
                (*tif_name).into(),
                format!("--sectors={}", v(0)),
                "-o".into(),
                "out/h.tif".into(),
            ],
            _ => {
                vec!["sun".into(), format!("--sol={}", v(0)), format!("--lat={}", v(1)), format!("--lon={}", v(2))]
            }
        };
        Ok(Case { kind: "flags", what: args.join(" "), args })
    }
}

/// Writes `bytes` as `dir`/`name`.
fn write_in(dir: &Path, name: &str, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(dir.join(name), bytes).map_err(|e| format!("{}: {e}", dir.join(name).display()))
}

/// `areo run` of scenario `name` at a tenth of the default work budget (2·10⁹ steps, 1–4
/// minutes, lunar-south-pole-10m's plan of ~10 M expansions within it): it is what makes
/// a mutated search that floods its map end within the time bound — the default budget
/// is 10–40 minutes.
fn run_args(name: &str) -> Vec<String> {
    ["-q", "run", name, "--out", "out", "--max-work", "2e9"].map(String::from).to_vec()
}

impl Corpus {
    /// Files that are not what they seem: a FIFO or a device as an input, a
    /// scenario nested deep, a sweep with a hostile name or count, an output that is a
    /// link to the input.
    fn file_case(&self, rng: &mut ChaCha8Rng, dir: &Path) -> Result<Case, String> {
        let write = |name: &str, bytes: &[u8]| {
            std::fs::write(dir.join(name), bytes).map_err(|e| format!("{}: {e}", dir.join(name).display()))
        };
        std::fs::create_dir_all(dir.join("out")).map_err(|e| e.to_string())?;
        let strings = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<String>>();
        Ok(match rng.random_range(0..5u32) {
            0 => {
                let status = Command::new("mkfifo").arg(dir.join("pipe.tif")).status().map_err(|e| e.to_string())?;
                if !status.success() {
                    return Err("mkfifo failed".into());
                }
                Case {
                    kind: "special file",
                    what: "a FIFO as the DEM".into(),
                    args: strings(&["terrain", "info", "pipe.tif"]),
                }
            }
            1 => {
                let device = ["/dev/zero", "/dev/null", "/dev/urandom"][rng.random_range(0..3)];
                Case {
                    kind: "special file",
                    what: format!("{device} as the instants"),
                    args: strings(&["sun", "--times-file", device]),
                }
            }
            2 => {
                let depth = rng.random_range(60..20_000usize);
                let text = format!(
                    "Scenario(version: 1, description: \"deep\", job: SunTable(site: {}1{}))",
                    "(".repeat(depth),
                    ")".repeat(depth)
                );
                write("deep.ron", text.as_bytes())?;
                Case {
                    kind: "special file",
                    what: format!("nesting {depth} deep"),
                    args: strings(&["-q", "run", "deep.ron", "--out", "out"]),
                }
            }
            3 => {
                let (name, text) =
                    self.scenarios.iter().find(|(n, _)| n == "gale-sol-sun.ron").ok_or("no gale-sol-sun.ron")?;
                write(name, text.as_bytes())?;
                let step = ["1e-320", "1e-9", "0.5", "-1", "inf"][rng.random_range(0..5)];
                let sweep = format!(
                    "Sweep(version: 1, base: \"{name}\", name: \"x{{index}}\\n$(touch pwned)\", axes: [(name: \"t\", path: \"job.tau\", range: (0.1, 0.9, {step}))])"
                );
                write("s.sweep.ron", sweep.as_bytes())?;
                Case {
                    kind: "special file",
                    what: format!("a sweep of step {step} with a hostile name"),
                    args: strings(&["sweep", "expand", "s.sweep.ron", "-o", "out/sweep"]),
                }
            }
            _ => {
                let (tif_name, tif) = &self.dems[0];
                write_in(dir, tif_name, tif)?;
                #[cfg(unix)]
                std::os::unix::fs::symlink(tif_name, dir.join("out/link.tif")).map_err(|e| e.to_string())?;
                Case {
                    kind: "special file",
                    what: "an output that is a link to the input".into(),
                    args: strings(&["terrain", "slope", tif_name, "-o", "out/link.tif"]),
                }
            }
        })
    }
}

/// Replaces one number of `text` by a hostile value (or random bits).
fn mutate_number(rng: &mut ChaCha8Rng, text: &str) -> (String, String) {
    let numbers = locate::scalars(text);
    if numbers.is_empty() {
        return (text.to_string(), "no numbers".into());
    }
    let s = &numbers[rng.random_range(0..numbers.len())];
    let value = if rng.random_range(0..5u32) == 0 {
        let v = f64::from_bits(rng.random::<u64>());
        if v.is_finite() { format!("{v:e}") } else { "NaN".into() }
    } else {
        HOSTILE[rng.random_range(0..HOSTILE.len())].to_string()
    };
    let what = format!("{}:{} `{}` {} → {value}", s.line, s.col, s.path.join("."), s.text);
    (format!("{}{}{}", &text[..s.span.start], value, &text[s.span.end..]), what)
}
