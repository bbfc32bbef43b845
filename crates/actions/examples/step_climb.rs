//! Can LSR-1 climb a step? The climb simulated pose by pose on the quasi-static model,
//! for steps of 10 to 50 cm: `cargo run -p areo-actions --example step_climb`.

#![allow(clippy::print_stdout)] // an example prints what it shows

use areo_rover::RoverParams;
use areo_rover::arm::ArmState;
use areo_rover::evaluation::Evaluator;

fn main() {
    let params = RoverParams::lsr1();
    let evaluator = Evaluator::new(&params);
    let arm = ArmState::stowed(&params);
    for cm in [10.0, 20.0, 30.0, 40.0, 50.0] {
        let climb = areo_actions::step_climb(&evaluator, &arm, cm / 100.0, 0.6, 1.0);
        let verdict = if climb.over { "over" } else { "stopped" };
        println!("{cm:>4} cm step at μ 0.6: {verdict} after {:.2} m, {} poses", climb.distance_m, climb.poses);
    }
}
