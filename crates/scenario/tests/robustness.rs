//! Hostile input, the fast part (the long seeded run is `cargo xtask fuzz`): every
//! number of every shipped scenario replaced by NaN, ±inf, 0, −1, ±1e308, a subnormal
//! and a huge integer; every shipped scenario cut short at many offsets. Each case must
//! give a located error or a scenario whose numbers are all finite — never a panic.

use std::path::{Path, PathBuf};

use areo_scenario::Error;
use areo_scenario::format::planner::SearchSpec;
use areo_scenario::format::{locate, parse};

/// What replaces a number.
const HOSTILE: &[&str] =
    &["NaN", "inf", "-inf", "0", "-1", "1e308", "-1e308", "5e-324", "18446744073709551615", "1e400"];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn shipped() -> Vec<(PathBuf, String)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("scenarios"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    assert!(files.len() >= 8, "the shipped scenarios are there");
    files.into_iter().map(|p| (p.clone(), std::fs::read_to_string(&p).unwrap())).collect()
}

/// Parses `text` and checks the contract: no panic; an error is located; what is
/// accepted has only finite numbers.
fn check(path: &Path, text: &str, what: &str) -> Result<(), String> {
    let parsed = std::panic::catch_unwind(|| parse(path, text)).map_err(|_| format!("{what}: panicked"))?;
    match parsed {
        Ok(_) => {
            if let Some(s) = locate::scalars(text).iter().find(|s| s.value().is_some_and(|v| !v.is_finite())) {
                return Err(format!("{what}: accepted the non-finite `{}` at {}:{}", s.text, s.line, s.col));
            }
        }
        Err(Error::Invalid { line, col, field, message, .. }) => {
            if line == 0 || col == 0 || field.is_empty() || message.is_empty() {
                return Err(format!("{what}: error without its place: {line}:{col} `{field}` {message}"));
            }
        }
        Err(Error::Syntax { line, col, .. }) => {
            if line == 0 || col == 0 {
                return Err(format!("{what}: syntax error without its place"));
            }
        }
        Err(e) => return Err(format!("{what}: unexpected kind of error: {e}")),
    }
    Ok(())
}

#[test]
fn every_number_of_every_scenario_survives_hostile_values() {
    let mut failures = Vec::new();
    let (mut cases, mut accepted, mut refused) = (0, 0, 0);
    for (path, text) in shipped() {
        let numbers = locate::scalars(&text);
        assert!(numbers.len() >= 10, "{}: numbers found", path.display());
        for s in &numbers {
            for v in HOSTILE {
                let mutated = format!("{}{}{}", &text[..s.span.start], v, &text[s.span.end..]);
                let what = format!("{}:{}:{} `{}` → {v}", path.display(), s.line, s.col, s.path.join("."));
                cases += 1;
                match check(&path, &mutated, &what) {
                    Ok(()) => {
                        if parse(&path, &mutated).is_ok() {
                            accepted += 1;
                        } else {
                            refused += 1;
                        }
                    }
                    Err(e) => failures.push(e),
                }
            }
        }
    }
    assert!(failures.is_empty(), "{} of {cases} cases broke the contract:\n{}", failures.len(), failures.join("\n"));
    // Non-finite values are refused everywhere; most hostile values are out of range.
    assert!(cases > 4000, "{cases} cases");
    assert!(refused > accepted, "{refused} refused, {accepted} accepted");
}

#[test]
fn non_finite_numbers_are_refused_with_their_field_and_place() {
    let text = std::fs::read_to_string(root().join("scenarios/gale-sol-sun.ron")).unwrap();
    let s = locate::scalars(&text).into_iter().find(|s| s.path.last().is_some_and(|k| k == "tau")).unwrap();
    for v in ["NaN", "inf", "-inf", "1e999"] {
        let mutated = format!("{}{}{}", &text[..s.span.start], v, &text[s.span.end..]);
        let err = parse(Path::new("gale.ron"), &mutated).unwrap_err();
        let Error::Invalid { line, col, field, message, .. } = &err else { panic!("{err}") };
        assert_eq!((*line, *col), (s.line, s.col), "{err}");
        assert_eq!(field, "job.tau");
        assert!(message.contains(v) && message.contains("finite"), "{message}");
    }
}

#[test]
fn every_truncation_of_every_scenario_is_a_located_error() {
    let mut failures = Vec::new();
    for (path, text) in shipped() {
        // Every character boundary for the first 200 bytes, then every 7th.
        // (A cut that only drops trailing whitespace leaves the whole scenario.)
        let cuts = (0..text.len())
            .filter(|&i| text.is_char_boundary(i) && (i < 200 || i % 7 == 0) && !text[i..].trim().is_empty());
        for cut in cuts {
            let what = format!("{} cut at {cut}", path.display());
            match std::panic::catch_unwind(|| parse(&path, &text[..cut])) {
                Err(_) => failures.push(format!("{what}: panicked")),
                Ok(Ok(_)) => failures.push(format!("{what}: accepted")),
                Ok(Err(Error::Syntax { line, col, .. } | Error::Invalid { line, col, .. })) if line > 0 && col > 0 => {}
                Ok(Err(e)) => failures.push(format!("{what}: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_shipped_scenarios_fit_the_default_budget_and_fine_classes_are_not_refused_on_a_guess() {
    use areo_scenario::budget::{Budget, DEFAULT_WORK_STEPS, EXPANSION_STEPS, SearchMap, expected_expansions, tempest};
    use areo_scenario::format::Job;
    let budget = Budget { memory_bytes: 16 << 30, work_steps: DEFAULT_WORK_STEPS };
    for (path, text) in shipped() {
        let scenario = parse(&path, &text).unwrap();
        if let Some(e) = areo_scenario::budget::estimate(&scenario) {
            budget.check(&e).unwrap_or_else(|err| panic!("{}: {err}", path.display()));
        }
        if let Job::Tempest(job) = &scenario.job
            && let areo_scenario::format::TerrainSource::Synth(spec) = &job.terrain
        {
            let map = SearchMap { cells: (spec.cols * spec.rows) as u64, cell_m2: spec.cell_m * spec.cell_m };
            budget.check(&tempest(job, map)).unwrap_or_else(|err| panic!("{}: {err}", path.display()));
        }
    }
    // A tick of a second over sun-synchronous-traverse's 110 h: the searches are
    // expected to expand 396 000 ticks over the three legs' ellipses, but that
    // is no refusal — only the horizon rays are certain; the searches are held to the
    // budget as they run.
    let text = std::fs::read_to_string(root().join("scenarios/sun-synchronous-traverse.ron")).unwrap();
    let text = text.replacen("tick_s: 300", "tick_s: 1", 1);
    let scenario = parse(Path::new("s.ron"), &text).unwrap();
    let Job::Tempest(job) = &scenario.job else { panic!("a TEMPEST job") };
    let map = SearchMap { cells: 160 * 120, cell_m2: 50.0 * 50.0 };
    let labels = expected_expansions(job, map);
    assert!(labels > 160 * 120 * 396_000 && labels <= 160 * 120 * 396_000 * 3, "{labels}");
    assert!(labels * EXPANSION_STEPS > DEFAULT_WORK_STEPS);
    let e = tempest(job, map);
    assert_eq!(e.work_steps, 160 * 120 * 64);
    budget.check(&e).unwrap();
}

#[test]
fn a_number_of_the_wrong_type_names_its_field() {
    let text = std::fs::read_to_string(root().join("scenarios/crater-morning-shadows.ron")).unwrap();
    for (from, to, field) in [("cols: ", "cols: -", "cols"), ("octaves: 3", "octaves: 99999999999", "octaves")] {
        let mutated = text.replacen(from, to, 1);
        let err = parse(Path::new("c.ron"), &mutated).unwrap_err();
        let Error::Syntax { message, line, .. } = &err else { panic!("{err}") };
        assert!(*line > 1 && message.contains(&format!("{field}`")), "{err}");
    }
}

#[test]
fn every_number_of_every_rover_file_survives_hostile_values() {
    use areo_scenario::format::rover_files::{load_params, load_resources};
    use areo_scenario::rover_check::{TestTerrain, check};
    let dir = std::env::temp_dir().join(format!("areo-rover-robustness-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files = [
        ("crates/rover/params/lsr1.ron", true),
        ("scenarios/rovers/lsr1-instrument-arm.ron", true),
        ("crates/rover/params/hyperion.ron", false),
        ("scenarios/rovers/mock-solar-rover.ron", false),
    ];
    let (mut cases, mut accepted, mut failures) = (0, 0, Vec::new());
    for (file, lsr1_style) in files {
        let text = std::fs::read_to_string(root().join(file)).unwrap();
        let numbers = locate::scalars(&text);
        assert!(numbers.len() >= 10, "{file}: numbers found");
        for s in &numbers {
            for v in HOSTILE {
                cases += 1;
                let path = dir.join(format!("case-{cases}.ron"));
                std::fs::write(&path, format!("{}{}{}", &text[..s.span.start], v, &text[s.span.end..])).unwrap();
                let what = format!("{file}:{}:{} `{}` → {v}", s.line, s.col, s.path.join("."));
                // Loading and, for an LSR-1 file, a pose with forces and stability on flat
                // ground — where a mass of 1e308 used to panic.
                let result = std::panic::catch_unwind(|| {
                    if lsr1_style {
                        check(&path, TestTerrain::Flat, 0.6, false).map(|_| ())
                    } else {
                        load_resources(&path).map(|_| ())
                    }
                });
                match result {
                    Err(_) => failures.push(format!("{what}: panicked")),
                    Ok(Ok(())) => accepted += 1,
                    Ok(Err(Error::Invalid { line, col, field, .. })) if line > 0 && col > 0 && !field.is_empty() => {}
                    Ok(Err(Error::Rover(areo_rover::Error::Syntax { line, col, .. }))) if line > 0 && col > 0 => {}
                    Ok(Err(e)) => failures.push(format!("{what}: {e}")),
                }
                // What is accepted holds only finite numbers.
                if lsr1_style && load_params(&path).is_ok() && ["NaN", "inf", "-inf", "1e400"].contains(v) {
                    failures.push(format!("{what}: accepted a non-finite number"));
                }
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(failures.is_empty(), "{} of {cases} cases broke the contract:\n{}", failures.len(), failures.join("\n"));
    assert!(cases > 1000 && accepted > 0 && accepted < cases, "{accepted} of {cases} accepted");
}

/// Off Mars, Communicate sessions are refused with the field and the rule: on the Moon
/// a schedule is required (its solar day is a month), sessions at least an hour apart,
/// and on the Earth there is no Earth to talk to.
#[test]
fn communicate_off_mars_is_checked_with_its_rule() {
    let base = std::fs::read_to_string(root().join("scenarios/lunar-south-pole.ron")).unwrap();
    let path = root().join("scenarios/lunar-south-pole.ron");
    assert!(areo_scenario::format::parse(&path, &base).is_ok());
    for (from, to, needle) in [
        ("communicate: (duration_min: 30, every_h: 8),", "communicate: (duration_min: 30),", "every_h"),
        (
            "communicate: (duration_min: 30, every_h: 8),",
            "communicate: (duration_min: 30, every_h: 0.25),",
            "at least an hour",
        ),
        ("communicate: (duration_min: 30, every_h: 8),", "communicate: (duration_min: 60, every_h: 1),", "must fit"),
        (
            "communicate: (duration_min: 30, every_h: 8),",
            "communicate: (duration_min: 30, deadlines_h: [500]),",
            "deadlines_h",
        ),
        ("body: Moon,", "body: Earth,", "no Earth to talk to"),
        ("body: Moon,", "body: Venus,", "Venus"),
    ] {
        assert!(base.contains(from), "{from}");
        let text = base.replace(from, to);
        let e = areo_scenario::format::parse(&path, &text).unwrap_err().to_string();
        assert!(e.contains(needle), "{to}: {e}");
        assert!(e.contains("lunar-south-pole.ron:"), "{e}");
    }
}

/// The straight climb's step and length are checked with their rule, located.
#[test]
fn a_climb_profile_out_of_range_names_its_field_and_rule() {
    let path = root().join("scenarios/steep-face.ron");
    let base = std::fs::read_to_string(&path).unwrap();
    let from = "climb_profile: (0.01, 1.2),";
    assert!(base.contains(from) && areo_scenario::format::parse(&path, &base).is_ok());
    for to in [
        "climb_profile: (0, 1.2),",
        "climb_profile: (0.01, 0),",
        "climb_profile: (0.001, 50),",
        "climb_profile: (2, 5),",
    ] {
        let e = areo_scenario::format::parse(&path, &base.replace(from, to)).unwrap_err().to_string();
        assert!(e.contains("steep-face.ron:") && e.contains("climb_profile"), "{to}: {e}");
        assert!(e.contains("at most 10 000 poses"), "{to}: {e}");
    }
}

/// The friction replay, the sweep's seeds and the sensitivity study are checked with
/// their rules, located.
#[test]
fn a_friction_replay_scan_seeds_or_sensitivity_out_of_range_names_its_field_and_rule() {
    let path = root().join("scenarios/friction-scan.ron");
    let base = std::fs::read_to_string(&path).unwrap();
    let (replay, seeds, sweep) =
        ("mu_replay: (0.30, 0.90, 0.05),", "mu_scan_seeds: (1, 8),", "mu_scan: (0.50, 0.80, 0.05),");
    assert!(base.contains(replay) && base.contains(seeds) && base.contains(sweep));
    assert!(areo_scenario::format::parse(&path, &base).is_ok());
    for (from, to, field, rule) in [
        (replay, "mu_replay: (0.005, 0.9, 0.05),", "mu_replay", "0.01 ≤ from ≤ to ≤ 2"),
        (replay, "mu_replay: (0.3, 0.9, 0.001),", "mu_replay", "at most 100 steps"),
        (seeds, "mu_scan_seeds: (8, 1),", "mu_scan_seeds", "first ≤ last"),
        (seeds, "mu_scan_seeds: (1, 200),", "mu_scan_seeds", "at most 100 seeds"),
        (sweep, "", "mu_scan_seeds", "needs a mu_scan"),
        (replay, "sensitivity: [(CgHeightM, [0.3])],", "sensitivity", "needs a climb_profile"),
    ] {
        let e = areo_scenario::format::parse(&path, &base.replace(from, to)).unwrap_err().to_string();
        assert!(e.contains("friction-scan.ron:") && e.contains(field) && e.contains(rule), "{to}: {e}");
    }
}

/// The format owns its types: every shipped scenario written back out from them and
/// read again is the same scenario, and an actions job's task and settings convert
/// into the library's types with every value carried over.
#[test]
fn every_shipped_scenario_round_trips_through_the_format_types() {
    use areo_scenario::format::Job;
    for (path, text) in shipped() {
        let scenario = parse(&path, &text).unwrap();
        // Written in the dialect the files are read in (areo-rover's RON options).
        let written = areo_rover::ron_options()
            .to_string_pretty(&scenario, ron::ser::PrettyConfig::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let again = parse(&path, &written).unwrap_or_else(|e| panic!("{}: {e}\n{written}", path.display()));
        assert_eq!(again, scenario, "{}", path.display());
        if let Job::Actions(job) = &scenario.job {
            let task = areo_actions::Task::from(&job.task);
            assert_eq!(
                (task.start, task.target, task.samples.len()),
                (job.task.start, job.task.target, job.task.samples.len())
            );
            let ga = areo_actions::GaConfig::from(&job.ga);
            assert_eq!((ga.population, ga.generations, ga.seed), (job.ga.population, job.ga.generations, job.ga.seed));
            assert_eq!(areo_actions::ExecConfig::from(&job.execution).mu, job.execution.mu);
        }
        let terrain = match &scenario.job {
            Job::Tempest(job) => Some(&job.terrain),
            Job::Actions(job) => Some(&job.terrain),
            Job::TerrainShadow(job) => Some(&job.terrain),
            _ => None,
        };
        if let Some(areo_scenario::format::TerrainSource::Synth(spec)) = terrain {
            let lib = spec.to_spec();
            assert_eq!(
                (lib.cols, lib.rows, lib.seed, lib.features.len()),
                (spec.cols, spec.rows, spec.seed, spec.features.len())
            );
            assert_eq!(lib.noise.map(|n| n.octaves), spec.noise.map(|n| n.octaves));
        }
        if let Job::Tempest(job) = &scenario.job {
            let planner = areo_mission::PlannerConfig::from(&job.planner);
            match (planner.search, job.planner.search) {
                (areo_mission::SearchMode::Exact { tick_s }, SearchSpec::Exact { tick_s: spec }) => {
                    assert_eq!(tick_s, spec);
                }
                (areo_mission::SearchMode::Approximate(lib), SearchSpec::Approximate(spec)) => {
                    assert_eq!((lib.resolution.time_s, lib.goal_times), (spec.resolution.time_s, spec.goal_times));
                }
                (lib, spec) => panic!("{lib:?} against {spec:?}"),
            }
            assert_eq!(planner.actions.charge_s, job.planner.actions.charge_s);
        }
    }
    // Defaults are the library's.
    let d = areo_scenario::format::ga::GaSpec::default();
    assert_eq!(areo_actions::GaConfig::from(&d), areo_actions::GaConfig::default());
    let w = areo_scenario::format::ga::WeightsSpec::default();
    assert_eq!(areo_actions::Weights::from(&w), areo_actions::Weights::default());
    let e = areo_scenario::format::ga::ExecSpec::default();
    assert_eq!(areo_actions::ExecConfig::from(&e), areo_actions::ExecConfig::default());
    let p = areo_scenario::format::planner::PlannerSpec::default();
    assert_eq!(areo_mission::PlannerConfig::from(&p), areo_mission::PlannerConfig::default());
    let s = areo_scenario::format::planner::SimSpec::default();
    assert_eq!(areo_mission::SimConfig::from(&s), areo_mission::SimConfig::default());
}

#[test]
fn uncertainty_out_of_range_names_its_field_and_rule() {
    let text = std::fs::read_to_string(root().join("scenarios/uncertain-dawn.ron")).unwrap();
    let path = Path::new("uncertain-dawn.ron");
    parse(path, &text).expect("the shipped scenario is valid");
    let line = "confidence: 0.95,\n            drive_time_sigma: 0.10,";
    assert!(text.contains(line));
    for (bad, field, rule) in [
        ("confidence: 1.2,", "job.uncertainty.confidence", "0.5"),
        ("confidence: 0.95,\n            drive_time_sigma: 0.8,", "job.uncertainty.drive_time_sigma", "fraction"),
    ] {
        let mutated = text.replacen(
            line,
            &line
                .replace("confidence: 0.95,", bad)
                .replace("drive_time_sigma: 0.10,", if bad.contains("drive") { "" } else { "drive_time_sigma: 0.10," }),
            1,
        );
        let err = parse(path, &mutated).unwrap_err();
        let Error::Invalid { field: f, message, .. } = &err else { panic!("{err}") };
        assert_eq!(f, field, "{err}");
        assert!(message.contains(rule), "{message}");
    }
    // Monte Carlo needs something to draw from.
    let start = text.find("        uncertainty: (").unwrap();
    let end = start + text[start..].find("        ),\n").unwrap() + "        ),\n".len();
    let err = parse(path, &format!("{}{}", &text[..start], &text[end..])).unwrap_err();
    let Error::Invalid { field, message, .. } = &err else { panic!("{err}") };
    assert_eq!(field, "job.monte_carlo");
    assert!(message.contains("uncertainty"), "{message}");
}

#[test]
fn a_pareto_front_needs_one_goal_and_a_step_in_range() {
    let text = std::fs::read_to_string(root().join("scenarios/pareto-front.ron")).unwrap();
    let path = Path::new("pareto-front.ron");
    let goal = r#"(name: "outcrop", x_m: 250, y_m: 230),"#;
    assert!(text.contains(goal));
    let two = text.replace(goal, &format!("{goal}\n            (name: \"cache\", x_m: 100, y_m: 50),"));
    let err = parse(path, &two).unwrap_err();
    let Error::Invalid { field, message, .. } = &err else { panic!("{err}") };
    assert_eq!(field, "job.pareto_front");
    assert!(message.contains("single goal") && message.contains('2'), "{message}");
    // The approximate search's margin step: out of range is refused with its range; on
    // a tick, where the front is exact, any step is refused naming `tick_s`.
    let (on_tick, front) = ("planner: (tick_s: 600)", "pareto_front: ()");
    assert!(text.contains(on_tick) && text.contains(front));
    let approximate = text.replace(on_tick, "planner: (approximate: true, resolution: (time_s: 600))");
    let err = parse(path, &approximate.replace(front, "pareto_front: (margin_step_wh: 0)")).unwrap_err();
    let Error::Invalid { field, message, .. } = &err else { panic!("{err}") };
    assert_eq!(field, "job.pareto_front.margin_step_wh");
    assert!(message.contains("0.001"), "{message}");
    parse(path, &approximate.replace(front, "pareto_front: (margin_step_wh: 2)")).unwrap();
    let err = parse(path, &text.replace(front, "pareto_front: (margin_step_wh: 2)")).unwrap_err();
    let Error::Invalid { field, message, .. } = &err else { panic!("{err}") };
    assert_eq!(field, "job.pareto_front.margin_step_wh");
    assert!(message.contains("tick_s") && message.contains("600"), "{message}");
}

#[test]
fn plan_clones_need_a_height_error_and_a_count_in_range() {
    let text = std::fs::read_to_string(root().join("scenarios/uncertain-ridge.ron")).unwrap();
    let path = Path::new("uncertain-ridge.ron");
    assert!(text.contains("terrain_sigma_m: 0.5") && text.contains("terrain_plan_clones: 20"));
    let err = parse(path, &text.replace("terrain_sigma_m: 0.5", "terrain_sigma_m: 0")).unwrap_err();
    let Error::Invalid { field, message, .. } = &err else { panic!("{err}") };
    assert_eq!(field, "job.uncertainty.terrain_plan_clones");
    assert!(message.contains("terrain_sigma_m > 0"), "{message}");
    let err = parse(path, &text.replace("terrain_plan_clones: 20", "terrain_plan_clones: 101")).unwrap_err();
    let Error::Invalid { field, message, .. } = &err else { panic!("{err}") };
    assert_eq!(field, "job.uncertainty.terrain_plan_clones");
    assert!(message.contains("0..=100"), "{message}");
}

/// Every RON reader refuses a deeply nested 100 KB file where it passes the nesting
/// limit, at once: the scenario, the rover's two files, a sweep, an expectation file and
/// a `--set` value.
#[test]
fn every_ron_reader_refuses_deep_nesting_where_it_starts() {
    use areo_scenario::format::rover_files::{load_params, load_resources};
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("deep-readers");
    std::fs::create_dir_all(&dir).unwrap();
    let deep = |head: &str| format!("{head}(a: {}1{})", "[".repeat(50_000), "]".repeat(50_000));
    let write = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let clock = std::time::Instant::now();
    let errors: Vec<(&str, Result<(), Error>)> = vec![
        ("scenario", areo_scenario::format::load(&write("s.ron", deep("Scenario"))).map(|_| ())),
        ("rover", load_params(&write("r.ron", deep("RoverParams"))).map(|_| ())),
        ("resources", load_resources(&write("m.ron", deep("ResourceModel"))).map(|_| ())),
        ("sweep", areo_scenario::sweep::expand(&write("w.sweep.ron", deep("Sweep")), &dir.join("run")).map(|_| ())),
        ("expected", areo_scenario::outcome::Expected::load(&write("e.expected.ron", deep(""))).map(|_| ())),
    ];
    for (reader, result) in errors {
        match result {
            Err(Error::Syntax { line: 1, col, message, .. }) => {
                assert!(message.contains("nested deeper than 64") && col < 100, "{reader}: {col} {message}")
            }
            other => panic!("{reader}: {other:?}"),
        }
    }
    // Each is one pass over the text (the rover reader took 81 s before its guard ran
    // first); ten seconds for all five is a hang's bound, not a speed target.
    assert!(clock.elapsed().as_secs_f64() < 10.0, "{:?}", clock.elapsed());
    let small = root().join("tests/tempest/small.ron");
    let set = format!("job.horizon_h={}1{}", "[".repeat(100), "]".repeat(100));
    let err = areo_scenario::format::load_with(&small, &[set]).unwrap_err().to_string();
    assert!(err.contains("nested deeper than 64"), "{err}");
}
