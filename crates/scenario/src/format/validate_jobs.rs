//! The range checks of every job of the format, each naming the field and what is
//! allowed.

use super::*;

impl Validate for Scenario {
    fn validate(&self, c: &mut Checks) {
        if self.version != FORMAT_VERSION {
            c.fail("version", format!("{} is not supported: allowed {FORMAT_VERSION}", self.version));
        }
        c.nested("job", |c| match &self.job {
            Job::SunTable(job) => job.validate(c),
            Job::TerrainShadow(job) => job.validate(c),
            Job::Tempest(job) => job.validate(c),
            Job::Actions(job) => job.validate(c),
        });
    }
}

impl Validate for SunTableJob {
    fn validate(&self, c: &mut Checks) {
        c.nested("site", |c| self.site.validate(c));
        if let Err(e) = areo_ephemeris::parse_utc(&self.start_utc) {
            c.fail("start_utc", e.to_string());
        }
        c.range("duration_h", self.duration_h, f64::MIN_POSITIVE, 24.0 * 800.0, "hours, > 0");
        c.range("step_min", self.step_min, 1.0 / 60.0, 1440.0, "minutes");
        c.range("tau", self.tau, 0.0, 10.0, "optical depth");
        if let Some(h) = &self.horizon_deg {
            if h.is_empty() {
                c.fail("horizon_deg", "is empty: give at least one sector elevation, or leave it out".into());
            } else if h.len() > 3600 {
                // One sector per tenth of a degree is finer than any horizon mask.
                c.fail("horizon_deg", format!("{} sectors: allowed 1..=3600", h.len()));
            }
            c.list("horizon_deg", h, |c, v| c.range_here(*v, -90.0, 90.0, "degrees"));
        }
    }
}

impl Validate for TerrainShadowJob {
    fn validate(&self, c: &mut Checks) {
        c.nested("site", |c| self.site.validate_mapped(c));
        if let Err(e) = areo_ephemeris::parse_utc(&self.utc) {
            c.fail("utc", e.to_string());
        }
        validate_terrain(c, "terrain", &self.terrain);
    }
}

/// `features[1].radius_m` → segments `features`, `[1]`, `radius_m`.
pub(super) fn field_segments(field: &str) -> Vec<String> {
    let mut segments: Vec<String> = Vec::new();
    for part in field.split('.') {
        match part.split_once('[') {
            Some((name, idx)) => {
                segments.push(name.to_string());
                segments.push(format!("[{idx}"));
            }
            None => segments.push(part.to_string()),
        }
    }
    segments
}

fn validate_terrain(c: &mut Checks, name: &str, terrain: &TerrainSource) {
    if let TerrainSource::Synth(spec) = terrain
        && let Err(areo_terrain::Error::BadSynth { field, value, allowed }) = spec.validate()
    {
        c.nested(name, |c| c.fail_at(&field_segments(&field), format!("{value} is out of range: allowed {allowed}")));
    }
}

impl Validate for ActionsJob {
    fn validate(&self, c: &mut Checks) {
        validate_terrain(c, "terrain", &self.terrain);
        if let Err(areo_actions::Error::Config { field, message }) = areo_actions::Task::from(&self.task).validate() {
            c.nested("task", |c| c.fail_at(&field_segments(&field), message));
        }
        if let Err(areo_actions::Error::Config { field, message }) = areo_actions::GaConfig::from(&self.ga).validate() {
            c.nested("ga", |c| c.fail_at(&field_segments(&field), message));
        }
        if let Err(areo_actions::Error::Config { field, message }) =
            areo_actions::Weights::from(&self.weights).validate()
        {
            c.nested("weights", |c| c.fail_at(&field_segments(&field), message));
        }
        validate_feature_classes(c, self);
        c.nested("execution", |c| {
            c.range("mu", self.execution.mu, 0.01, 2.0, "friction coefficient");
            c.range("stability_floor", self.execution.stability_floor, 0.0, 0.99, "fraction of the flat-ground margin");
            let (a, b, h) = self.execution.body_half_m;
            if !([a, b, h].iter().all(|v| *v > 0.0 && *v <= 10.0)) {
                c.fail("body_half_m", format!("({a}, {b}, {h}): each half extent 0 (exclusive)..=10 m"));
            }
        });
        c.list("runs", &self.runs, |c, r| {
            check_identifier(c, &r.name);
            if let Some(codes) = &r.inventory
                && let Err(code) = areo_actions::Inventory::from_codes(codes)
            {
                c.fail("inventory", format!("{code} is not a Table 1 module code"));
            }
            if let Some(mu) = r.mu {
                c.range("mu", mu, 0.01, 2.0, "friction coefficient");
            }
            if let Some(how) = r.crossover
                && let Err(areo_actions::Error::Config { message, .. }) =
                    (areo_actions::GaConfig { crossover: how.into(), ..areo_actions::GaConfig::from(&self.ga) })
                        .validate()
            {
                c.fail("crossover", message);
            }
            if let Some((a, b)) = r.seeds
                && !(a <= b && b - a < 1000)
            {
                c.fail("seeds", format!("({a}, {b}): allowed (first, last) with first ≤ last and at most 1000 seeds"));
            }
        });
        check_unique(c, "runs", self.runs.iter().map(|r| r.name.as_str()));
        if let Some(y) = self.ditch_far_edge_y_m {
            c.range("ditch_far_edge_y_m", y, -1e4, 1e4, "m");
        }
        for (field, range) in [("mu_scan", self.mu_scan), ("mu_replay", self.mu_replay)] {
            if let Some((a, b, step)) = range
                && !(a >= 0.01 && b >= a && b <= 2.0 && step > 0.0 && (b - a) / step <= 100.0)
            {
                c.fail(field, format!("({a}, {b}, {step}): need 0.01 ≤ from ≤ to ≤ 2, step > 0, at most 100 steps"));
            }
        }
        self.validate_studies(c);
        if let Some((step, length)) = self.climb_profile
            && !((0.001..=1.0).contains(&step) && length > 0.0 && length <= 100.0 && length / step <= 10_000.0)
        {
            c.fail(
                "climb_profile",
                format!("({step}, {length}): need a step of 0.001..=1 m, a length of 0 (exclusive)..=100 m and at most 10 000 poses"),
            );
        }
    }
}

impl ActionsJob {
    /// The studies around the GA's runs: the scan's seeds, the sensitivity study.
    fn validate_studies(&self, c: &mut Checks) {
        if !self.sensitivity.is_empty() && self.climb_profile.is_none() {
            c.fail("sensitivity", "needs a climb_profile to repeat".to_string());
        }
        let values: usize = self.sensitivity.iter().map(|(_, v)| v.len()).sum();
        if values > 200 {
            c.fail("sensitivity", format!("{values} values: allowed at most 200 in all"));
        }
        if let Some((a, b)) = self.mu_scan_seeds {
            if !(a <= b && b - a < 100) {
                c.fail(
                    "mu_scan_seeds",
                    format!("({a}, {b}): allowed (first, last) with first ≤ last and at most 100 seeds"),
                );
            } else if self.mu_scan.is_none() {
                c.fail("mu_scan_seeds", "needs a mu_scan to repeat".to_string());
            }
        }
    }
}

/// The `uncertainty` and `monte_carlo` fields of a TEMPEST job.
fn validate_uncertainty(c: &mut Checks, job: &TempestJob) {
    if let Some(u) = &job.uncertainty {
        c.nested("uncertainty", |c| {
            c.range("confidence", u.confidence, 0.5, 0.999, "probability");
            for (name, v) in [
                ("drive_time_sigma", u.drive_time_sigma),
                ("power_draw_sigma", u.power_draw_sigma),
                ("solar_sigma", u.solar_sigma),
            ] {
                c.range(name, v, 0.0, 0.5, "a fraction of the nominal value");
            }
            c.range("action_delay_sigma_s", u.action_delay_sigma_s, 0.0, 3600.0, "s");
            c.range("start_delay_sigma_s", u.start_delay_sigma_s, 0.0, 86_400.0, "s");
            c.range("terrain_sigma_m", u.terrain_sigma_m, 0.0, 100.0, "m");
            c.range("terrain_correlation_m", u.terrain_correlation_m, f64::MIN_POSITIVE, 1e6, "m, > 0");
            if u.terrain_clones > 100 {
                c.fail("terrain_clones", format!("{}: allowed 0..=100", u.terrain_clones));
            }
            if u.terrain_plan_clones > 100 {
                c.fail("terrain_plan_clones", format!("{}: allowed 0..=100", u.terrain_plan_clones));
            } else if u.terrain_plan_clones > 0 && u.terrain_sigma_m == 0.0 {
                c.fail(
                    "terrain_plan_clones",
                    format!("{}: needs a height error (terrain_sigma_m > 0)", u.terrain_plan_clones),
                );
            }
        });
    }
    if let Some(mc) = &job.monte_carlo {
        if job.uncertainty.is_none() {
            c.fail("monte_carlo", "needs `uncertainty` (what the executions draw from)".into());
        }
        if !(1..=100_000).contains(&mc.runs) {
            c.fail("monte_carlo.runs", format!("{}: allowed 1..=100000", mc.runs));
        }
        if mc.closed_loop_runs > 10_000 {
            c.fail("monte_carlo.closed_loop_runs", format!("{}: allowed 0..=10000", mc.closed_loop_runs));
        }
    }
    if let Some(f) = &job.pareto_front {
        if job.goals.len() != 1 {
            c.fail(
                "pareto_front",
                format!("the front is searched for a single goal; this job has {}: allowed with one", job.goals.len()),
            );
        }
        if let Some(step) = f.margin_step_wh {
            match job.planner.search.tick_s() {
                Some(tick) => c.fail(
                    "pareto_front.margin_step_wh",
                    format!(
                        "not used with `tick_s` (the front is exact at the tick of {tick} s: every plan no \
                         other beats in arrival, energy used and margin) — remove `margin_step_wh`"
                    ),
                ),
                None => c.range("pareto_front.margin_step_wh", step, 0.001, 1000.0, "Wh"),
            }
        }
    }
}

impl Validate for TempestJob {
    fn validate(&self, c: &mut Checks) {
        validate_terrain(c, "terrain", &self.terrain);
        validate_truth(c, &self.truth);
        c.nested("site", |c| self.site.validate_mapped(c));
        if let Err(e) = areo_ephemeris::parse_utc(&self.start_utc) {
            c.fail("start_utc", e.to_string());
        }
        if let Some(s) = &self.shadow_utc
            && let Err(e) = areo_ephemeris::parse_utc(s)
        {
            c.fail("shadow_utc", e.to_string());
        }
        c.range("horizon_h", self.horizon_h, 1e-3, 2400.0, "hours");
        c.range("sun_step_min", self.sun_step_min, 1.0 / 60.0, 60.0, "minutes");
        if self.horizon_sectors != 0 && !(16..=360).contains(&self.horizon_sectors) {
            c.fail("horizon_sectors", format!("{}: allowed 0 (no shadows) or 16..=360", self.horizon_sectors));
        }
        c.range("tau", self.tau, 0.0, 10.0, "optical depth");
        if let Some(b) = self.battery_capacity_wh {
            c.range("battery_capacity_wh", b, 1e-3, 1e7, "Wh");
        }
        c.range(
            "start_battery_above_floor_wh",
            self.start_battery_above_floor_wh,
            0.0,
            1e7,
            "Wh above the battery floor",
        );
        c.range("start_window_min", self.start_window_min, 0.0, 1e5, "minutes");
        validate_uncertainty(c, self);
        if self.goals.is_empty() {
            c.fail("goals", "is empty: give at least one goal".into());
        }
        c.list("goals", &self.goals, |c, g| {
            check_label(c, &g.name);
            check_position(c, g.x_m, g.y_m);
        });
        check_unique(c, "goals", self.goals.iter().map(|g| g.name.as_str()));
        c.list("regions", &self.regions, |c, r| {
            check_identifier(c, &r.name);
            check_position(c, r.x_m, r.y_m);
            c.range("radius_m", r.radius_m, f64::MIN_POSITIVE, 1e7, "m, > 0");
        });
        check_unique(c, "regions", self.regions.iter().map(|r| r.name.as_str()));
        if let Some(n) = &self.no_go {
            c.nested("no_go", |c| c.range("inflate_m", n.inflate_m, 0.0, 1e4, "m"));
        }
        if let Some(t) = &self.terrain_classes {
            c.nested("terrain_classes", |c| validate_classes(c, t));
        }
        c.nested("start", |c| check_position(c, self.start.x_m, self.start.y_m));
        if let Some(r) = &self.plan_region {
            c.nested("plan_region", |c| {
                for (name, (lo, hi)) in [("x_m", r.x_m), ("y_m", r.y_m)] {
                    if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && lo < hi && hi <= 1e8) {
                        c.fail(name, format!("({lo}, {hi}): allowed (low, high) m with 0 ≤ low < high ≤ 1e8"));
                    }
                }
                c.range("lowest_sun_deg", r.lowest_sun_deg, 0.5, 89.0, "degrees");
            });
            if !matches!(self.truth, Truth::Map) {
                c.fail("plan_region", "a region is planned on the map as true (truth: Map, the default)".into());
            }
        }
        if let Err(areo_mission::Error::Config { field, message }) =
            areo_mission::PlannerConfig::from(&self.planner).validate()
        {
            c.nested("planner", |c| c.fail_at(&field_segments(field), message));
        }
        if let Some(com) = &self.communicate {
            validate_communicate(c, com, self.horizon_h, self.body.model());
        }
        if let Some(sim) = &self.simulate
            && let Err(areo_mission::Error::Config { field, message }) = areo_mission::SimConfig::from(sim).validate()
        {
            c.nested("simulate", |c| c.fail_at(&field_segments(field), message));
        }
    }
}

fn validate_feature_classes(c: &mut Checks, job: &ActionsJob) {
    let features = match &job.terrain {
        TerrainSource::Synth(spec) => spec.features.len(),
        TerrainSource::File(_) if !job.feature_classes.is_empty() => {
            c.fail("feature_classes", "classes go on a synthesised terrain's features: the terrain is a file".into());
            return;
        }
        TerrainSource::File(_) => 0,
    };
    let mut mu_of: std::collections::HashMap<String, f64> = std::collections::HashMap::new();
    c.list("feature_classes", &job.feature_classes, |c, k| {
        if k.feature >= features {
            c.fail("feature", format!("{}: the terrain has {features} features (0..{features})", k.feature));
        }
        if !(1..=64).contains(&k.class.len())
            || !k.class.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
        {
            c.fail("class", format!("{:?}: allowed 1 to 64 ASCII letters, digits, `_` or `-`", k.class));
        }
        c.range("mu", k.mu, 0.01, 2.0, "friction coefficient");
        if let Some(&m) = mu_of.get(k.class.as_str())
            && m != k.mu
        {
            c.fail("mu", format!("{}: class {:?} has μ {m} on another feature: one μ per class", k.mu, k.class));
        }
        mu_of.insert(k.class.clone(), k.mu);
    });
}

fn validate_classes(c: &mut Checks, t: &crate::format::TerrainClassesSpec) {
    if t.classes.is_empty() {
        c.fail("classes", "is empty: list every class id the raster holds".into());
    }
    if t.classes.len() > 254 {
        c.fail("classes", format!("{} classes: allowed at most 254", t.classes.len()));
    }
    c.list("classes", &t.classes, |c, k| {
        check_identifier(c, &k.name);
        if !(0..=254).contains(&k.id) {
            c.fail("id", format!("{}: allowed 0..=254 (255 is the class layer's no-data)", k.id));
        }
        c.range("speed_factor", k.speed_factor, 0.01, 10.0, "times the rover's speed");
        c.range("power_factor", k.power_factor, 0.01, 10.0, "times the rover's locomotion power");
        if let Some(s) = k.max_slope_deg
            && !(s > 0.0 && s < 90.0)
        {
            c.fail("max_slope_deg", format!("{s}: allowed 0..90 degrees (exclusive)"));
        }
    });
    check_unique(c, "classes", t.classes.iter().map(|k| k.name.as_str()));
    let mut ids: Vec<i64> = t.classes.iter().map(|k| k.id).collect();
    ids.sort_unstable();
    if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
        c.fail("classes", format!("id {} is listed twice: each id names one class", w[0]));
    }
}

/// The true terrain: a terrain source, or landforms checked as a synthesised map would.
fn validate_truth(c: &mut Checks, truth: &Truth) {
    match truth {
        Truth::Map => {}
        Truth::Terrain(t) => c.nested("truth", |c| validate_terrain(c, "Terrain", t)),
        Truth::AddFeatures(features) => {
            // Check the landforms as a synthesised map would.
            let spec = areo_terrain::synth::TerrainSpec {
                cols: 2,
                rows: 2,
                cell_m: 1.0,
                base_m: 0.0,
                seed: 0,
                noise: None,
                features: features.iter().map(synth::FeatureSpec::to_feature).collect(),
            };
            if let Err(areo_terrain::Error::BadSynth { field, value, allowed }) = spec.validate() {
                let mut seg = field_segments(&field);
                if seg.first().is_some_and(|s| s == "features") {
                    seg[0] = "AddFeatures".into();
                }
                c.nested("truth", |c| c.fail_at(&seg, format!("{value} is out of range: allowed {allowed}")));
            }
        }
    }
}

/// Communicate sessions: their length, elevation, deadlines and interval within the
/// horizon, and whether the body has an Earth to talk to.
fn validate_communicate(c: &mut Checks, com: &CommunicateSpec, horizon_h: f64, body: areo_ephemeris::Body) {
    c.nested("communicate", |c| {
            c.range("duration_min", com.duration_min, 1.0, 720.0, "minutes");
            c.range("min_earth_elevation_deg", com.min_earth_elevation_deg, -90.0, 90.0, "degrees");
            let lo = com.duration_min / 60.0;
            if com.deadlines_h.len() > 1000 {
                c.fail("deadlines_h", format!("{} deadlines: at most 1000", com.deadlines_h.len()));
            }
            c.list("deadlines_h", &com.deadlines_h, |c, d| {
                c.range_here(
                    *d,
                    lo,
                    horizon_h.max(lo),
                    "hours after the start, at least one session long and within the horizon",
                )
            });
            if let Some(every) = com.every_h {
                // At least an hour apart: a session costs a scan of the schedule in
                // every stationary action, so thousands would slow every search.
                let lo = (com.duration_min / 60.0).max(1.0);
                if !(every >= lo && every <= horizon_h.max(lo)) {
                    c.fail(
                        "every_h",
                        format!(
                            "{every}: allowed at least an hour and more than the session ({} h), at most the horizon ({} h)",
                            com.duration_min / 60.0,
                            horizon_h
                        ),
                    );
                }
                if every * 60.0 <= com.duration_min {
                    c.fail("every_h", format!("{every} h: a session ({} min) must fit between two", com.duration_min));
                }
            }
        });
    if body == areo_ephemeris::Body::Earth {
        c.fail("communicate", "on the Earth there is no Earth to talk to: leave communicate out".into());
    }
    if body == areo_ephemeris::Body::Moon && com.every_h.is_none() && com.deadlines_h.is_empty() {
        c.fail(
            "communicate",
            "on the Moon a solar day is a month: give every_h (a session every so many hours) or deadlines_h".into(),
        );
    }
}

/// A name that becomes part of a file or fact name: 1 to 64 ASCII letters, digits,
/// `_` or `-`, starting with a letter or digit (so it can never be a path).
fn check_identifier(c: &mut Checks, name: &str) {
    let ok = (1..=64).contains(&name.len())
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
        && name.as_bytes()[0].is_ascii_alphanumeric();
    if !ok {
        c.fail(
            "name",
            format!("{name:?}: allowed 1 to 64 ASCII letters, digits, `_` or `-`, starting with a letter or digit"),
        );
    }
}

/// A name shown in reports and plots (each writer escapes it for its format,
/// `output::escape`): 1 to 100 characters, none a control character or a Unicode
/// non-character (U+FFFE, U+FFFF, …: no text format may carry them; XML forbids two).
fn check_label(c: &mut Checks, name: &str) {
    let bad = |ch: char| ch.is_control() || crate::output::escape::non_character(ch);
    if !(1..=100).contains(&name.chars().count()) || name.chars().any(bad) {
        c.fail(
            "name",
            format!("{name:?}: allowed 1 to 100 characters, no control characters (tab, newline, …) or non-characters"),
        );
    }
}

/// Names must differ: the second use of a name is the error.
fn check_unique<'a>(c: &mut Checks, list: &str, names: impl IntoIterator<Item = &'a str>) {
    let mut seen = std::collections::HashSet::new();
    for (i, name) in names.into_iter().enumerate() {
        if !seen.insert(name) {
            c.fail_at(
                &[list.to_string(), format!("[{i}]"), "name".into()],
                format!("{name:?} is used twice: names must be unique"),
            );
        }
    }
}

/// A position in a map's frame, m.
fn check_position(c: &mut Checks, x: f64, y: f64) {
    c.range("x_m", x, -1e7, 1e7, "m");
    c.range("y_m", y, -1e7, 1e7, "m");
}

impl Validate for SiteSpec {
    fn validate(&self, c: &mut Checks) {
        c.range("lat_deg", self.lat_deg, -90.0, 90.0, "planetocentric degrees");
        c.range("lon_east_deg", self.lon_east_deg, -360.0, 360.0, "degrees east");
    }
}

impl SiteSpec {
    /// A site a map is placed around: not the pole itself, where the map's north is
    /// undefined.
    fn validate_mapped(&self, c: &mut Checks) {
        c.range(
            "lat_deg",
            self.lat_deg,
            -89.999,
            89.999,
            "planetocentric degrees; a map is placed around its site, which cannot be the pole itself",
        );
        c.range("lon_east_deg", self.lon_east_deg, -360.0, 360.0, "degrees east");
    }
}
