//! The three bodies areo plans on, side by side: `cargo run -p areo-body --example bodies`.

#![allow(clippy::print_stdout)] // an example prints what it shows

use areo_body::Body;

fn main() {
    println!("{:<6} {:>14} {:>14} {:>10} {:>12}", "body", "equatorial km", "mean km", "g m/s²", "solar day h");
    for b in Body::ALL {
        println!(
            "{:<6} {:>14.3} {:>14.3} {:>10.3} {:>12.3}",
            b.iau_name(),
            b.equatorial_radius_m() / 1000.0,
            b.mean_radius_m() / 1000.0,
            b.surface_gravity_m_s2(),
            b.solar_day_s() / 3600.0
        );
    }
}
