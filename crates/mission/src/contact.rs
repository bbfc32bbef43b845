//! Earth contact and safe havens: the Communicate sessions a mission schedules on any
//! body (they feed [`ActionModel::with_sessions`]), the Earth in view along a plan
//! (checked independently of the planner's constraint, by sampling), and where a rover
//! can wait out a shadow or a loss of the Earth — the haven map and a plan's waits.

use areo_ephemeris::events::communication_windows;
use hifitime::Duration;

use crate::action_model::{Action, ActionModel};
use crate::plan::MissionPlan;
use crate::world::World;

/// When the rover must stand and talk to the Earth.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    /// Session length, minutes.
    pub duration_min: f64,
    /// Lowest Earth elevation for a once-a-sol session, degrees.
    pub min_earth_elevation_deg: f64,
    /// A session ending every this many hours, instead of once a sol.
    pub every_h: Option<f64>,
    /// Contact deadlines, hours after the epoch: a session ends at each.
    pub deadlines_h: Vec<f64>,
}

/// Communicate sessions over the world's span, s after the epoch: one ending at every
/// `every_h` hours and at each deadline when given, else one per sol centred on the
/// Earth's culmination (Mars's relay-free direct-to-Earth pass).
pub fn sessions(world: &World, com: &Schedule) -> Vec<(f64, f64)> {
    let length = com.duration_min * 60.0;
    if com.every_h.is_some() || !com.deadlines_h.is_empty() {
        let periodic = com.every_h.map_or(Vec::new(), |every_h| {
            (1..).map(|k| k as f64 * every_h * 3600.0).take_while(|&end| end <= world.span_s() + 1e-6).collect()
        });
        let mut ends: Vec<f64> = periodic.into_iter().chain(com.deadlines_h.iter().map(|h| h * 3600.0)).collect();
        ends.sort_by(f64::total_cmp);
        ends.dedup();
        return ends.into_iter().map(|end| (end - length, end)).collect();
    }
    let (start, end) = (world.epoch(), world.epoch() + Duration::from_seconds(world.span_s()));
    communication_windows(&world.site(), start, end, com.min_earth_elevation_deg, length)
        .into_iter()
        .map(|(a, b)| ((a - start).to_seconds(), (b - start).to_seconds()))
        .collect()
}

/// Where the rover is at time `t` on a plan: at a waypoint's cell while its action
/// runs, switching to the next cell halfway through a drive.
pub(crate) fn cell_at(plan: &MissionPlan, t: f64) -> u32 {
    let w = &plan.waypoints;
    let k = w.partition_point(|p| p.t_s <= t).saturating_sub(1);
    match (w[k].action, w.get(k + 1)) {
        (Some(Action::Drive(_)), Some(next)) if t >= 0.5 * (w[k].t_s + next.t_s) => next.cell,
        _ => w[k].cell,
    }
}

/// The Earth in view along a plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// Longest stretch without `min_contact_s` of continuous Earth view, from the plan's
    /// start to its end, hours.
    pub max_gap_h: f64,
    /// Share of the plan's time with the Earth in view from where the rover is.
    pub in_view_fraction: f64,
    /// Contact windows (at least `min_contact_s` of view), hours since the epoch.
    pub windows_h: Vec<(f64, f64)>,
}

/// Samples the plan every `step_s` and finds the contact windows (continuous Earth
/// view of at least `min_contact_s`) and the longest gap between them.
pub fn contact_along(world: &World, plan: &MissionPlan, min_contact_s: f64, step_s: f64) -> Contact {
    let (Some(first), Some(last)) = (plan.waypoints.first(), plan.waypoints.last()) else {
        return Contact { max_gap_h: 0.0, in_view_fraction: 0.0, windows_h: Vec::new() };
    };
    let (t0, t1) = (first.t_s, last.t_s);
    let n = (((t1 - t0) / step_s).ceil() as usize).max(1);
    let at = |k: usize| t0 + (t1 - t0) * k as f64 / n as f64;
    let seen: Vec<bool> = (0..=n).map(|k| world.earth_visible(cell_at(plan, at(k)), at(k))).collect();
    let mut windows = Vec::new();
    let mut k = 0;
    while k <= n {
        if seen[k] {
            let a = k;
            while k < n && seen[k + 1] {
                k += 1;
            }
            if at(k) - at(a) >= min_contact_s - 1e-6 {
                windows.push((at(a), at(k)));
            }
        }
        k += 1;
    }
    let mut gap = 0.0f64;
    let mut from = t0;
    for &(a, b) in &windows {
        gap = gap.max(a - from);
        from = b;
    }
    gap = gap.max(t1 - from);
    Contact {
        max_gap_h: gap / 3600.0,
        in_view_fraction: seen.iter().filter(|&&s| s).count() as f64 / seen.len() as f64,
        windows_h: windows.iter().map(|&(a, b)| (a / 3600.0, b / 3600.0)).collect(),
    }
}

/// Hours of driving with the Sun hidden from where the rover is, sampled every
/// `step_s` along each drive.
pub fn shadowed_drive_h(world: &World, plan: &MissionPlan, step_s: f64) -> f64 {
    let mut dark = 0.0;
    for w in plan.waypoints.windows(2) {
        if !matches!(w[0].action, Some(Action::Drive(_))) {
            continue;
        }
        let (a, b) = (w[0].t_s, w[1].t_s);
        let n = (((b - a) / step_s).ceil() as usize).max(1);
        for k in 0..n {
            let t = a + (b - a) * (k as f64 + 0.5) / n as f64;
            if !world.lit(cell_at(plan, t), &world.sun(t)) {
                dark += (b - a) / n as f64;
            }
        }
    }
    dark / 3600.0
}

/// Per-cell light and Earth over a span: where a rover can wait.
#[derive(Debug, Clone)]
pub struct Havens {
    /// Longest continuous shadow per cell, hours.
    pub longest_shadow_h: Vec<f32>,
    /// Longest continuous loss of the Earth per cell, hours.
    pub longest_earth_loss_h: Vec<f32>,
    /// Whether the cell is a safe haven.
    pub haven: Vec<bool>,
    /// Hours a hibernating rover lasts in shadow on a full battery.
    pub survive_h: f64,
}

/// The haven map over [0, `span_s`] sampled every `step_s`: a cell is a safe haven if
/// it is passable, its longest shadow is shorter than a full battery lasts hibernating
/// (usable capacity over the low electronics load less any generator), and — when
/// `contact_every_h` is given — the Earth is never out of its view longer than that.
pub fn havens(world: &World, model: &ActionModel, span_s: f64, step_s: f64, contact_every_h: Option<f64>) -> Havens {
    let n = ((span_s / step_s).ceil() as usize).max(1);
    let times: Vec<f64> = (0..=n).map(|k| span_s * k as f64 / n as f64).collect();
    let suns: Vec<_> = times.iter().map(|&t| world.sun(t)).collect();
    let dt_h = span_s / n as f64 / 3600.0;
    let rover = model.rover();
    let drain_w = rover.electronics.power_w(areo_rover::resources::Load::Low) - rover.nuclear_w;
    let survive_h = if drain_w > 0.0 { model.capacity_wh() / drain_w } else { f64::INFINITY };
    let longest = |hit: &dyn Fn(usize) -> bool| {
        let (mut run, mut best) = (0usize, 0usize);
        for k in 0..times.len() {
            run = if hit(k) { run + 1 } else { 0 };
            best = best.max(run);
        }
        (best as f64 * dt_h) as f32
    };
    let cells = world.cells();
    let (mut shadow, mut loss, mut haven) = (Vec::with_capacity(cells), Vec::with_capacity(cells), Vec::new());
    for c in 0..cells as u32 {
        let s = longest(&|k| !world.lit(c, &suns[k]));
        let e = longest(&|k| !world.earth_visible(c, times[k]));
        let ok =
            world.passable(c) && f64::from(s) <= survive_h && contact_every_h.is_none_or(|every| f64::from(e) <= every);
        shadow.push(s);
        loss.push(e);
        haven.push(ok);
    }
    Havens { longest_shadow_h: shadow, longest_earth_loss_h: loss, haven, survive_h }
}

/// A stretch of a plan during which the rover stays on one cell.
#[derive(Debug, Clone, PartialEq)]
pub struct Wait {
    /// The cell.
    pub cell: u32,
    /// Start and end, hours since the epoch.
    pub from_h: f64,
    /// End, hours since the epoch.
    pub to_h: f64,
    /// Lowest predicted charge during it, Wh above the floor.
    pub lowest_battery_above_floor_wh: f64,
    /// Whether the cell is a safe haven.
    pub haven: bool,
}

/// The plan's waits of at least `min_s`: runs of stationary actions on one cell.
pub fn waits(plan: &MissionPlan, havens: &Havens, floor_wh: f64, min_s: f64) -> Vec<Wait> {
    let w = &plan.waypoints;
    let mut out = Vec::new();
    let mut k = 0;
    while k + 1 < w.len() {
        if matches!(w[k].action, Some(Action::Drive(_)) | None) {
            k += 1;
            continue;
        }
        let a = k;
        while k + 1 < w.len() && w[k].action.is_some_and(|x| !matches!(x, Action::Drive(_))) {
            k += 1;
        }
        let lowest = w[a..=k].iter().map(|p| p.battery_wh - floor_wh).fold(f64::INFINITY, f64::min);
        if w[k].t_s - w[a].t_s >= min_s {
            out.push(Wait {
                cell: w[a].cell,
                from_h: w[a].t_s / 3600.0,
                to_h: w[k].t_s / 3600.0,
                lowest_battery_above_floor_wh: lowest,
                haven: havens.haven[w[a].cell as usize],
            });
        }
        if k == a {
            k += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::WorldConfig;
    use areo_ephemeris::flux::Atmosphere;
    use areo_ephemeris::{Body, Site, parse_utc};
    use areo_terrain::Dem;

    fn lunar_world(span_h: f64) -> World {
        let dem = Dem::from_fn(20, 20, 30.0, 30.0, |_, _| 0.0).unwrap();
        let config = WorldConfig {
            epoch: parse_utc("2025-01-10T00:00:00Z").unwrap(),
            span_s: span_h * 3600.0,
            sun_step_s: 600.0,
            horizon_sectors: Some(16),
            atmosphere: Atmosphere::Airless,
            site: Some(Site::on(Body::Moon, -89.45, 30.0).unwrap()),
        };
        World::new(dem, &config, &Body::Moon).unwrap()
    }

    #[test]
    fn sessions_end_every_interval_and_at_each_deadline() {
        let world = lunar_world(24.0);
        let com = Schedule {
            duration_min: 30.0,
            min_earth_elevation_deg: 10.0,
            every_h: Some(8.0),
            deadlines_h: vec![5.0, 16.0],
        };
        let ends: Vec<f64> = sessions(&world, &com).iter().map(|s| s.1 / 3600.0).collect();
        assert_eq!(ends, vec![5.0, 8.0, 16.0, 24.0]);
        assert!(sessions(&world, &com).iter().all(|(a, b)| (b - a - 1800.0).abs() < 1e-9));
    }

    #[test]
    fn on_open_ground_near_the_pole_in_lunar_summer_every_cell_is_a_haven() {
        // Flat ground, the Sun 1.9–2.0° up all day and the Earth 6° up: no shadow, no
        // loss of the Earth, so every cell is a haven whatever the battery.
        let world = lunar_world(48.0);
        let mut rover = areo_rover::resources::ResourceModel::hyperion();
        rover.battery.capacity_wh = 100.0;
        let model = ActionModel::new(rover, crate::action_model::ActionConfig::default());
        let h = havens(&world, &model, world.span_s(), 1800.0, Some(8.0));
        assert!(h.haven.iter().all(|&x| x));
        assert!(h.longest_shadow_h.iter().chain(&h.longest_earth_loss_h).all(|&x| x == 0.0));
        // 90 Wh usable over Hyperion's 20 W low load less no generator: 4.5 h.
        assert!((h.survive_h - 90.0 / 20.0).abs() < 1e-9, "{}", h.survive_h);
    }
}
