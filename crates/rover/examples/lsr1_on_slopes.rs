//! LSR-1 standing and driving on ever steeper slopes (quasi-static pose, wheel forces,
//! force-angle stability): `cargo run -p areo-rover --example lsr1_on_slopes`.

#![allow(clippy::print_stdout)] // an example prints what it shows

use areo_rover::RoverParams;
use areo_rover::arm::ArmState;
use areo_rover::evaluation::{Conditions, Evaluator, Place};
use areo_terrain::analytic::Plane;

fn main() {
    let params = RoverParams::lsr1();
    let evaluator = Evaluator::new(&params);
    let arm = ArmState::stowed(&params);
    let climbing = Conditions { mu: 0.6, direction: 1.0 };
    for deg in [0.0, 10.0, 20.0, 25.0, 30.0, 35.0] {
        // Heading north up a plane rising to the north.
        let ground = Plane { z0: 0.0, gx: 0.0, gy: f64::to_radians(deg).tan() };
        match evaluator.evaluate(&ground, Place { x: 0.0, y: 0.0, heading: 0.0 }, &arm, &climbing, None) {
            Ok(e) => println!(
                "{deg:>4}°: climbs; pitch {:.1}°, stability {:.0} %",
                e.pose.pitch.to_degrees(),
                100.0 * e.stability
            ),
            Err(why) => println!("{deg:>4}°: cannot ({why})"),
        }
    }
}
