//! `areo rover check`: the report as aligned text or JSON.

use std::fmt::Write as _;

use areo_scenario::rover_check::{ResourceReport, RoverCheckReport};

/// The report as aligned text.
pub(crate) fn text(report: &RoverCheckReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{} on {} with μ = {} ({})",
        report.rover,
        report.terrain,
        report.mu,
        if report.moving { "driving" } else { "holding still" }
    );
    let _ = writeln!(s, "verdict: {}", report.verdict);
    if let Some(p) = &report.pose {
        let _ = writeln!(
            s,
            "pose: pitch {:.2}°, roll {:.2}°, body {:.3} m up; α1..α4 = {:.2}°, {:.2}°, {:.2}°, {:.2}°",
            p.pitch_deg, p.roll_deg, p.body_height_m, p.alpha_deg[0], p.alpha_deg[1], p.alpha_deg[2], p.alpha_deg[3]
        );
    }
    if !report.wheels.is_empty() {
        let _ = writeln!(s, "{:<13} {:>9} {:>10} {:>10} {:>8}  binding", "wheel", "N (N)", "T (N)", "τ (N·m)", "γ (°)");
        for w in &report.wheels {
            let _ = writeln!(
                s,
                "{:<13} {:>9.3} {:>10.3} {:>10.4} {:>8.2}  {}",
                w.wheel,
                w.normal_n,
                w.traction_n,
                w.torque_nm,
                w.contact_deg,
                if w.binding.is_empty() { "-".to_string() } else { w.binding.join(", ") }
            );
        }
        let total: f64 = report.wheels.iter().map(|w| w.normal_n).sum();
        let _ = writeln!(s, "sum of normal loads {total:.3} N; weight {:.3} N", report.weight_n);
    }
    if let Some(pct) = report.stability_pct {
        let _ = writeln!(s, "stability margin: {pct:.1} % of flat ground");
    }
    match report.mu_needed {
        Some(m) => {
            let _ = writeln!(s, "smallest μ that holds here: {m:.4}");
        }
        None => {
            let _ = writeln!(s, "no μ ≤ 5 holds here");
        }
    }
    climb_text(&mut s, report);
    s
}

/// The climb over a step, if the report has one, as aligned text.
fn climb_text(s: &mut String, report: &RoverCheckReport) {
    let Some(c) = &report.climb else { return };
    let _ = writeln!(
        s,
        "climb over the step ({} poses, every {} m): {}",
        c.poses,
        c.step_m,
        if c.over {
            format!("every wheel on top after {:.2} m", c.distance_m)
        } else {
            format!("stopped at {:.2} m ({})", c.distance_m, c.stop.as_deref().unwrap_or("?"))
        }
    );
    match c.mu_needed {
        Some(m) => {
            let _ = writeln!(
                s,
                "smallest μ that holds every pose: {m:.3}, needed at {:.2} m ({} wheels up)",
                c.mu_needed_at_m,
                if c.wheels_on_top_there.is_empty() { "no" } else { &c.wheels_on_top_there }
            );
        }
        None => {
            let _ = writeln!(s, "no μ ≤ 5 holds every pose");
        }
    }
    if c.min_stability_pct.is_finite() {
        let _ =
            writeln!(s, "least stability margin {:.1} %, largest pitch {:.1}°", c.min_stability_pct, c.max_pitch_deg);
    }
}

/// A resource model's figures as aligned text.
pub(crate) fn resources_text(r: &ResourceReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{} (TEMPEST resource model), gravity {} m/s² ({})", r.rover, r.gravity_m_s2, r.gravity_from);
    let _ = writeln!(
        s,
        "{:<22} {:>8} {:>13} {:>14} {:>12} {:>9}",
        "driving", "m/s", "locomotion W", "electronics W", "battery W", "Wh/km"
    );
    for d in &r.drives {
        let _ = writeln!(
            s,
            "{:<22} {:>8.3} {:>13.1} {:>14.1} {:>12.1} {:>9.1}",
            d.ground, d.speed_m_s, d.locomotion_w, d.electronics_w, d.battery_w, d.wh_per_km
        );
    }
    let _ = writeln!(s, "  (battery W: the load less the generator, with no sunlight; Wh/km likewise)");
    if r.array_w_per_w_m2 > 0.0 {
        let _ =
            writeln!(s, "array: {:.3} W per W/m² of beam at normal incidence (area × efficiency)", r.array_w_per_w_m2);
    } else {
        let _ = writeln!(s, "array: none");
    }
    if r.nuclear_w > 0.0 {
        let _ = writeln!(s, "generator: {} W", r.nuclear_w);
    }
    let [low, medium, high] = r.electronics_w;
    let _ = writeln!(s, "electronics: {low} W hibernating, {medium} W idle or charging, {high} W driving");
    let _ = writeln!(
        s,
        "battery: {} Wh, {:.1} Wh between its charge limits, {:.1} Wh delivered",
        r.capacity_wh, r.usable_wh, r.deliverable_wh
    );
    let hours =
        |h: Option<f64>| h.map_or("indefinitely (the generator covers it)".to_string(), |h| format!("{h:.1} h"));
    let _ = writeln!(
        s,
        "a full battery with no sunlight lasts {} hibernating, {} idle; drives {} on flat ground",
        hours(r.hibernate_h),
        hours(r.idle_h),
        r.range_flat_km.map_or("indefinitely".to_string(), |k| format!("{k:.2} km"))
    );
    s
}
