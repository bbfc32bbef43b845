//! The bounds the search's heuristic and its objective rest on: the most any action can
//! gain (E_max), the most the sources give while driving, the least a drive or a stay
//! can cost at any time. Each is a bound for every time, terrain the map may turn out
//! to have, and Sun of the table, so that the heuristic stays admissible when sensing
//! changes the map.

use areo_rover::resources::Load;

use super::{Action, ActionModel, DriveGeometry};
use crate::world::{GridSun, World};

impl ActionModel {
    /// An upper bound on the power any wait charges the battery with, W (the largest
    /// flux on the array facing the Sun, and the generator, through the battery's
    /// charge efficiency, no load drawn).
    pub(crate) fn charge_bound_w(&self, world: &World) -> f64 {
        let source =
            self.rover.nuclear_w + self.rover.solar.map_or(0.0, |a| world.max_beam_w_m2() * a.area_m2 * a.efficiency);
        source * self.rover.battery.charge_efficiency
    }

    /// An upper bound on the energy any single action can gain, Wh (TEMPEST's E_max,
    /// eq. 3, bounded from the largest flux on a panel facing the Sun), and the same
    /// bound for drives alone.
    pub fn gain_bounds(&self, world: &World) -> (f64, f64) {
        let source =
            self.rover.nuclear_w + self.rover.solar.map_or(0.0, |a| world.max_beam_w_m2() * a.area_m2 * a.efficiency);
        let b = &self.rover.battery;
        let gain_from = |source: f64, load_w: f64, duration_s: f64| {
            ((source - load_w) * duration_s / 3600.0 * b.charge_efficiency).max(0.0)
        };
        let gain = |load_w: f64, duration_s: f64| gain_from(source, load_w, duration_s);
        let longest = self.longest_drive_s(world);
        let drive_source = self.drive_source_bound_w(world);
        let drive = gain_from(drive_source, self.rover.electronics.power_w(Load::High), longest);
        let charge = gain(
            self.rover.electronics.power_w(self.config.charge_load.load()),
            self.quantise_time(self.config.charge_s),
        );
        let hibernate = gain_from(
            self.rover.nuclear_w,
            self.rover.electronics.power_w(Load::Low),
            self.quantise_time(self.config.hibernate_s),
        );
        // A wait's share of L is its duration over a Hibernate's: its gain per unit of L
        // is at most what the lesser of its loads gains from the most the sources give
        // over a Hibernate's duration.
        let wait = if self.config.wait_step_s.is_some() {
            let e = &self.rover.electronics;
            gain(e.power_w(Load::Low).min(e.power_w(self.config.charge_load.load())), self.config.hibernate_s)
        } else {
            0.0
        };
        let q = self.config.energy_quantum_wh;
        let all = drive.max(charge).max(hibernate).max(wait);
        // Quantised energies round to the nearest quantum: allow for half of one.
        (all + q / 2.0, drive + q / 2.0)
    }

    /// An upper bound on the power sources while driving, W. While driving the array
    /// points along the heading, tipped by the ground (at most the slope limit): its
    /// output is bounded by the best incidence any heading, any Sun of the table and
    /// any admissible tilt allow — far below a Sun-facing panel's for a steep array,
    /// which tightens the search's heuristic.
    pub(crate) fn drive_source_bound_w(&self, world: &World) -> f64 {
        let best = world
            .sun_table()
            .iter()
            .map(|sun| self.drive_solar_bound_w(sun, self.ground_tilt_bound_deg()))
            .fold(0.0, f64::max);
        self.rover.nuclear_w + best
    }

    /// An upper bound on the array's power while driving under `sun`, W: the best
    /// incidence any heading and ground tipped at most `tilt_deg` allow (widened beyond
    /// the ground's tilt, it holds for a Sun anywhere within the difference of this one).
    pub(crate) fn drive_solar_bound_w(&self, sun: &GridSun, tilt_deg: f64) -> f64 {
        let Some(a) = &self.rover.solar else { return 0.0 };
        if sun.elevation_deg <= 0.0 {
            return 0.0;
        }
        let tilt = tilt_deg.to_radians();
        let mut best: f64 = 0.0;
        for n in &self.level_normals {
            let cos = (n[0] * sun.enu[0] + n[1] * sun.enu[1] + n[2] * sun.enu[2]).clamp(-1.0, 1.0);
            let incidence = (cos.acos() - tilt).max(0.0);
            best = best.max(sun.beam_w_m2 * incidence.cos());
        }
        best * a.area_m2 * a.efficiency
    }

    /// The factor the planning margins put on every load ([`super::Perturbation::draw_factor`]).
    pub(crate) fn draw_factor(&self) -> f64 {
        self.margins.draw_factor
    }

    /// The steepest ground the rover may stand on after a drive, degrees: the slope
    /// limit under the slope rule, any ground without it.
    pub(crate) fn ground_tilt_bound_deg(&self) -> f64 {
        if self.config.drive.max_slope { self.max_slope_deg } else { 90.0 }
    }

    /// An upper bound on the array's power while the rover stands under `sun` on ground
    /// tipped at most `ground_deg`, W: standing, the array is turned to the Sun's
    /// azimuth at its own tilt ([`ActionModel::source_w`] with no heading), so it sees
    /// the Sun at the difference of the two zenith angles, and the ground turns it at
    /// most `ground_deg` toward the Sun.
    pub(crate) fn stay_solar_bound_w(&self, sun: &GridSun, ground_deg: f64) -> f64 {
        let Some(a) = &self.rover.solar else { return 0.0 };
        if sun.elevation_deg <= 0.0 {
            return 0.0;
        }
        let apart = (90.0 - sun.elevation_deg - a.tilt_deg).abs();
        let incidence = (apart - ground_deg).clamp(0.0, 90.0);
        sun.beam_w_m2.max(0.0) * incidence.to_radians().cos() * a.area_m2 * a.efficiency
    }

    /// Lower bounds on the battery energy of one drive, Wh, whatever the time, the
    /// terrain's relief and the Sun: east–west, north–south and diagonal. Each is the
    /// least, over the slopes a drive may have, of the loads over the drive's duration
    /// less the most the sources can give meanwhile (negative: a drive can gain). The
    /// search's heuristic adds E_max per step; being independent of the terrain's
    /// relief (its classes enter by their extreme factors), the bounds stay valid when
    /// sensing changes the map.
    pub fn drive_energy_floors_wh(&self, world: &World) -> [f64; 3] {
        let source = self.drive_source_bound_w(world);
        let loco = &self.rover.locomotor;
        let electronics = self.rover.electronics.power_w(Load::High);
        let limit = if self.config.drive.max_slope { self.max_slope_deg.min(89.0) } else { 89.0 };
        let dem = world.dem();
        let (slowest, fastest) = world.speed_factor_range();
        let least_power = world.least_power_factor();
        let floor = |run: f64| {
            // The energy is smooth in the slope; a 0.05° grid and a 0.1 % margin keep the
            // sampled minimum below the true one.
            let steps = (2.0 * limit / 0.05).ceil() as usize;
            let mut least = f64::INFINITY;
            for k in 0..=steps {
                let slope = -limit + 2.0 * limit * k as f64 / steps as f64;
                // The locomotion energy does not depend on the speed, the rest is linear
                // in the duration: the least is at the slowest or the fastest class.
                for factor in [slowest, fastest] {
                    let speed = loco.speed_on_slope_m_s(slope) * factor;
                    let duration = run / slope.to_radians().cos() / speed;
                    // Durations are rounded up to the time quantum; a gain grows with them.
                    let net = loco.power_w(speed, slope) * least_power + electronics - source;
                    let longer = duration + self.config.time_quantum_s.max(0.0);
                    least = least.min(self.battery_wh(net, duration)).min(self.battery_wh(net, longer));
                }
            }
            let q = self.config.energy_quantum_wh.max(0.0);
            least - 1e-3 * least.abs() - q / 2.0
        };
        [floor(dem.dx()), floor(dem.dy()), floor(dem.dx().hypot(dem.dy()))]
    }

    /// The least battery energy the drive with `geometry` can use at any time, Wh, with
    /// `source_w` ([`ActionModel::drive_source_bound_w`]) bounding the sources while
    /// driving: the drive's energy is two half-durations of its load less the sources
    /// at each end, increasing in the net load, then rounded to the energy quantum.
    pub(crate) fn drive_energy_floor_wh(&self, geometry: &DriveGeometry, source_w: f64) -> f64 {
        let least = self.battery_wh(geometry.load_w - source_w, geometry.duration_s);
        // The Sun is interpolated between the table's entries that bound the source: a
        // 0.1 % margin, as for the terrain-free floors.
        least - 1e-3 * least.abs() - self.config.energy_quantum_wh.max(0.0) / 2.0
    }

    /// An upper bound on a drive's duration, s: a diagonal up the steepest slope
    /// allowed, at the slowest speed on the slowest terrain class.
    pub(crate) fn longest_drive_s(&self, world: &World) -> f64 {
        let dem = world.dem();
        let slowest = self.rover.locomotor.speed_m_s / 3.0 * world.speed_factor_range().0;
        let run = dem.dx().hypot(dem.dy());
        let longest = run / slowest / self.max_slope_deg.to_radians().cos().max(0.05) * self.margins.duration_factor
            + self.margins.delay_s;
        self.quantise_time(longest) + 1.0
    }

    /// A lower bound on the cost per second (Wh/s), in the Energy objective (energy
    /// plus `e_max` per unit of L), of any action overlapping an instant: a charge (its
    /// load against the generator and `charge_solar_w`, the most the array can give
    /// within a charge's duration of the instant), a hibernation (the generator alone)
    /// or a drive (at least `drive_units` of L and the high electronics load, against
    /// the smaller of `drive_source_w` and the generator plus `drive_solar_w`, the most
    /// within the longest drive's duration; at most that duration). Energies round to
    /// the quantum: half of one is allowed for.
    pub(crate) fn cost_rate_floor(
        &self,
        world: &World,
        e_max: f64,
        drive_units: f64,
        (charge_solar_w, drive_solar_w): (f64, f64),
        drive_source_w: f64,
    ) -> f64 {
        let half_quantum = self.config.energy_quantum_wh.max(0.0) / 2.0;
        // Per second a drive costs (E_max·units − ½q)/d plus its net load's energy rate:
        // least at the longest d.
        let net_w =
            self.rover.electronics.power_w(Load::High) - drive_source_w.min(self.rover.nuclear_w + drive_solar_w);
        let per_hour = self.battery_wh(net_w, 3600.0);
        let drive = (e_max * drive_units - half_quantum).max(0.0) / self.longest_drive_s(world)
            + (per_hour - 1e-9 * per_hour.abs()) / 3600.0;
        self.stay_rate_floor(e_max, charge_solar_w).min(drive).max(0.0)
    }

    /// A lower bound on the cost per second (Wh/s, the Energy objective) of a stay
    /// overlapping an instant, with `charge_solar_w` the most the array can give within
    /// a charge's duration of it: a charge (its load against the generator and the
    /// array) or a hibernation (the generator alone); or a wait, charging or asleep,
    /// whichever drains less. Never negative.
    pub(crate) fn stay_rate_floor(&self, e_max: f64, charge_solar_w: f64) -> f64 {
        let half_quantum = self.config.energy_quantum_wh.max(0.0) / 2.0;
        let stay = |action: Action, source_w: f64, load: Load| {
            let d = self.stay_duration_s(action);
            let e = self.battery_wh(self.rover.electronics.power_w(load) - source_w, d);
            // (A relative hair below, for rounding in the sums the plan makes.)
            (e_max + e - 1e-9 * e.abs() - half_quantum).max(0.0) / d
        };
        let rate = if self.config.wait_step_s.is_some() {
            let d = self.stay_duration_s(Action::Wait);
            let e = &self.rover.electronics;
            let charging = e.power_w(self.config.charge_load.load()) - self.rover.nuclear_w - charge_solar_w;
            let net = charging.min(e.power_w(Load::Low) - self.rover.nuclear_w);
            let e = self.battery_wh(net, d);
            (e_max * self.stay_units(Action::Wait) + e - 1e-9 * e.abs() - half_quantum).max(0.0) / d
        } else {
            let charge = stay(Action::Charge, self.rover.nuclear_w + charge_solar_w, self.config.charge_load.load());
            charge.min(stay(Action::Hibernate, self.rover.nuclear_w, Load::Low))
        };
        rate.max(0.0)
    }

    /// A lower bound on what a drive overlapping an instant costs per second above its
    /// floor ([`ActionModel::drive_energy_floor_wh`] with `drive_source_w`), Wh/s: the
    /// floor credits the drive with `drive_source_w` throughout, the sources give at
    /// most the generator and `drive_solar_w` (the most the array can give within the
    /// longest drive's duration of the instant), and every watt short of the credit is
    /// energy the battery does not get — at least at the smaller of the charge
    /// efficiency and the discharge's inverse, the slopes of
    /// [`ActionModel::battery_wh`]. Only where [`ActionModel::drive_floors_unclamped`]:
    /// a floor clamped at zero would not pay the credit back.
    pub(crate) fn drive_shortfall_rate(&self, drive_solar_w: f64, drive_source_w: f64) -> f64 {
        let short_w = (drive_source_w - (self.rover.nuclear_w + drive_solar_w)).max(0.0);
        let b = &self.rover.battery;
        short_w * b.charge_efficiency.min(1.0 / b.discharge_efficiency) / 3600.0 * (1.0 - 1e-9)
    }

    /// Whether no drive's cost floor, its energy floor plus E_max per unit of L (its
    /// planar length in cells), is clamped at zero.
    pub(crate) fn drive_floors_unclamped(&self, world: &World, e_max: f64) -> bool {
        let (dx, dy) = (world.dem().dx(), world.dem().dy());
        let units = [dx, dy, dx.hypot(dy)].map(|run| run / dx.min(dy));
        let floors = self.drive_energy_floors_wh(world);
        floors.iter().zip(units).all(|(floor, units)| floor + e_max * units >= 0.0)
    }

    /// The most the array can give under a beam of `beam_w_m2` (facing it squarely), W.
    pub(crate) fn solar_peak_w(&self, beam_w_m2: f64) -> f64 {
        self.rover.solar.map_or(0.0, |a| beam_w_m2.max(0.0) * a.area_m2 * a.efficiency)
    }

    /// The least battery energy a stationary `action` uses in the dark, Wh: its load
    /// against the generator alone (sessions only add the radio's), rounded to the
    /// energy quantum.
    pub(crate) fn dark_stay_floor_wh(&self, action: Action) -> f64 {
        if action == Action::Wait {
            let e = self.dark_wait_floor_wh(self.stay_duration_s(action));
            return e - 1e-9 * e.abs() - self.config.energy_quantum_wh.max(0.0) / 2.0;
        }
        let load = match action {
            Action::Charge => self.config.charge_load.load(),
            _ => Load::Low,
        };
        let e =
            self.battery_wh(self.rover.electronics.power_w(load) - self.rover.nuclear_w, self.stay_duration_s(action));
        e - 1e-9 * e.abs() - self.config.energy_quantum_wh.max(0.0) / 2.0
    }
}
