//! `areo rover check`: the report as aligned text or JSON.

use std::fmt::Write as _;

use areo_scenario::rover_check::Report;

/// The report as aligned text.
pub(crate) fn text(report: &Report) -> String {
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
    if let Some(c) = &report.climb {
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
            let _ = writeln!(
                s,
                "least stability margin {:.1} %, largest pitch {:.1}°",
                c.min_stability_pct, c.max_pitch_deg
            );
        }
    }
    s
}
