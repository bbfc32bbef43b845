//! The Sun over Gale crater through MSL's first sol, hour by hour (Mars24):
//! `cargo run -p areo-ephemeris --example sol_at_gale`.

#![allow(clippy::print_stdout)] // an example prints what it shows

use areo_ephemeris::{Body, SOL_S, Site, SunModel, parse_utc};

fn main() -> Result<(), areo_ephemeris::Error> {
    let site = Site::on(Body::Mars, -4.5895, 137.4417)?;
    let landing = parse_utc("2012-08-06T05:17:57Z")?;
    println!("{:>6} {:>8} {:>10} {:>10}", "hour", "LTST h", "azimuth°", "elevation°");
    for k in 0..=24 {
        let at = landing + hifitime::Duration::from_seconds(f64::from(k) * SOL_S / 24.0);
        let sun = Body::Mars.sun(at);
        let p = sun.at_site(&site);
        let ltst = sun.local_solar_time_hours(site.lon_east_deg());
        println!("{k:>6} {ltst:>8.2} {:>10.1} {:>10.1}", p.azimuth_deg, p.elevation_deg);
    }
    Ok(())
}
