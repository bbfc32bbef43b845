//! Sunrise, solar noon and sunset; daylight and Earth-visibility intervals.
//!
//! Rise and set are the instants when the centre of the Sun (or Earth) crosses the
//! horizon: the local horizontal by default, or a [`HorizonMask`] giving the terrain's
//! horizon elevation per azimuth (areo-terrain's horizon maps plug in here). Intervals
//! are found by scanning at a fixed step (default 5 min, far shorter than any real
//! daylight period) and refining each crossing by bisection to 10 ms.

use hifitime::Epoch;

use crate::earth::earth_from_mars;
use crate::error::{Error, Result};
use crate::site::Site;
use crate::sun::SolarGeometry;
use crate::time::{J2000_JD_TT, MarsTime, SOL_IN_DAYS, epoch_from_jd_tt, utc_at_ltst};

/// The elevation of the horizon around a site, in equal azimuth sectors.
#[derive(Debug, Clone, PartialEq)]
pub struct HorizonMask {
    elevations_deg: Vec<f64>,
}

impl HorizonMask {
    /// A flat horizon: elevation 0° all round.
    pub fn flat() -> HorizonMask {
        HorizonMask { elevations_deg: vec![0.0] }
    }

    /// A mask of K sectors: `elevations_deg[i]` is the horizon elevation at azimuth
    /// i·360°/K (clockwise from north); between sector centres it is interpolated
    /// linearly. Values must be finite and within [−90, 90].
    pub fn new(elevations_deg: Vec<f64>) -> Result<HorizonMask> {
        if elevations_deg.is_empty() {
            return Err(Error::BadHorizonMask("no sectors"));
        }
        if elevations_deg.iter().any(|e| !e.is_finite() || e.abs() > 90.0) {
            return Err(Error::BadHorizonMask("elevations must be finite and within -90..=90 degrees"));
        }
        Ok(HorizonMask { elevations_deg })
    }

    /// Horizon elevation at `azimuth_deg`, degrees.
    pub fn elevation_at(&self, azimuth_deg: f64) -> f64 {
        let k = self.elevations_deg.len();
        let pos = azimuth_deg.rem_euclid(360.0) / 360.0 * k as f64;
        let i = (pos.floor() as usize).min(k - 1);
        let frac = pos - i as f64;
        let a = self.elevations_deg[i];
        let b = self.elevations_deg[(i + 1) % k];
        a + (b - a) * frac
    }
}

/// Sunrise, solar noon and sunset of one local sol at a site.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolarDay {
    /// Local sol number (see [`crate::local_sol`]).
    pub sol: i64,
    /// When the Sun's centre rises above the horizon mask; `None` in polar day or night.
    pub sunrise: Option<Epoch>,
    /// Local true solar noon (LTST 12:00).
    pub noon: Epoch,
    /// When the Sun's centre sets below the horizon mask; `None` in polar day or night.
    pub sunset: Option<Epoch>,
    /// The Sun's elevation at noon, degrees.
    pub noon_elevation_deg: f64,
}

impl SolarDay {
    /// Length of daylight, seconds (0 when the Sun does not rise; a full sol when it does
    /// not set).
    pub fn daylight_s(&self) -> f64 {
        match (self.sunrise, self.sunset) {
            (Some(r), Some(s)) => (s - r).to_seconds(),
            _ if self.noon_elevation_deg > 0.0 => SOL_IN_DAYS * 86_400.0,
            _ => 0.0,
        }
    }
}

/// The Sun's elevation over the mask at `site` (on the site's body).
fn sun_margin(site: &Site, mask: &HorizonMask, jd_tt: f64) -> f64 {
    let state = match site.body() {
        crate::Body::Mars => SolarGeometry::at_days_since_j2000(jd_tt - J2000_JD_TT).state(),
        other => crate::SunModel::sun(&other, epoch_from_jd_tt(jd_tt)),
    };
    let pos = state.at_site(site);
    pos.elevation_deg - mask.elevation_at(pos.azimuth_deg)
}

/// Sunrise, noon and sunset at `site` on local sol `sol`, with a horizon `mask`.
pub fn solar_day(sol: i64, site: &Site, mask: &HorizonMask) -> Result<SolarDay> {
    let noon = utc_at_ltst(sol, site, 12.0)?;
    let noon_jd = MarsTime::from_epoch(noon).jd_tt;
    let f = |jd: f64| sun_margin(site, mask, jd);
    let half_sol = SOL_IN_DAYS / 2.0;
    let rise = crossing(&f, noon_jd - half_sol, noon_jd, true);
    let set = crossing(&f, noon_jd, noon_jd + half_sol, false);
    let noon_elevation_deg = SolarGeometry::at(noon).state().at_site(site).elevation_deg;
    Ok(SolarDay {
        sol,
        sunrise: rise.map(epoch_from_jd_tt),
        noon,
        sunset: set.map(epoch_from_jd_tt),
        noon_elevation_deg,
    })
}

/// The intervals between `start` and `end` during which the Sun's centre is above the
/// horizon `mask` at `site` (on the site's body).
pub fn daylight_intervals(site: &Site, mask: &HorizonMask, start: Epoch, end: Epoch) -> Vec<(Epoch, Epoch)> {
    intervals_above(|jd| sun_margin(site, mask, jd), start, end)
}

/// The intervals between `start` and `end` during which the Earth is above the horizon
/// `mask` at `site` (direct-to-Earth communication windows); none on the Earth. On
/// the Moon the Earth is seen from the site (topocentric).
pub fn earth_visible_intervals(site: &Site, mask: &HorizonMask, start: Epoch, end: Epoch) -> Vec<(Epoch, Epoch)> {
    intervals_above(
        |jd| {
            let t = epoch_from_jd_tt(jd);
            let (az, el) = match site.body() {
                crate::Body::Mars => site.azimuth_elevation_deg(earth_from_mars(t).direction_body_fixed),
                other => match crate::EarthFrom::earth(other, t) {
                    Some(e) => e.at_site(site),
                    None => return -1.0,
                },
            };
            el - mask.elevation_at(az)
        },
        start,
        end,
    )
}

/// The intervals between `start` and `end` during which the Sun's centre is at or below
/// the horizon `mask` at `site`: the complement of [`daylight_intervals`] there.
pub fn night_intervals(site: &Site, mask: &HorizonMask, start: Epoch, end: Epoch) -> Vec<(Epoch, Epoch)> {
    let mut out = Vec::new();
    let mut from = start;
    for (rise, set) in daylight_intervals(site, mask, start, end) {
        if rise > from {
            out.push((from, rise));
        }
        from = set;
    }
    if end > from {
        out.push((from, end));
    }
    out
}

/// One direct-to-Earth session per sol: for each sol-long window from `start` (the
/// last one cut at `end`), a session of `duration_s` seconds centred on the Earth's
/// highest elevation in that window, kept if that elevation is at least
/// `min_elevation_deg` and clipped to [`start`, `end`]. The culmination is found by
/// scanning at 5 min and refining by golden-section search to 10 ms.
pub fn communication_windows(
    site: &Site,
    start: Epoch,
    end: Epoch,
    min_elevation_deg: f64,
    duration_s: f64,
) -> Vec<(Epoch, Epoch)> {
    let elevation = |jd: f64| {
        let e = earth_from_mars(epoch_from_jd_tt(jd));
        site.azimuth_elevation_deg(e.direction_body_fixed).1
    };
    let (t0, t1) = (MarsTime::from_epoch(start).jd_tt, MarsTime::from_epoch(end).jd_tt);
    let half_days = 0.5 * duration_s / 86_400.0;
    let mut out = Vec::new();
    let mut sol_start = t0;
    // A window shorter than the scan tolerance is rounding, not a sol.
    while sol_start < t1 - TOLERANCE_DAYS {
        let sol_end = (sol_start + SOL_IN_DAYS).min(t1);
        let (peak, el) = maximum(&elevation, sol_start, sol_end);
        if el >= min_elevation_deg {
            let (a, b) = ((peak - half_days).max(t0), (peak + half_days).min(t1));
            if b > a {
                out.push((epoch_from_jd_tt(a), epoch_from_jd_tt(b)));
            }
        }
        sol_start += SOL_IN_DAYS;
    }
    out
}

/// The Sun's highest point over `mask`-free flat ground at `site` between `start` and
/// `end` (on the site's body): the instant and the elevation, degrees. Scanned every
/// 5 min and refined to 10 ms.
pub fn culmination(site: &Site, start: Epoch, end: Epoch) -> (Epoch, f64) {
    let flat = HorizonMask::flat();
    let (t0, t1) = (MarsTime::from_epoch(start).jd_tt, MarsTime::from_epoch(end).jd_tt);
    let (jd, el) = maximum(&|jd| sun_margin(site, &flat, jd), t0, t1);
    // Where the highest point is an end of the window (a polar Sun still climbing or
    // sinking), the round trip through the Julian date can land a millisecond
    // outside it.
    let at = epoch_from_jd_tt(jd);
    (at.max(start).min(end), el)
}

/// The largest value of `f` on [a, b] and where: the best scan sample, refined by
/// golden-section search between its neighbours.
fn maximum(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let n = ((b - a) / SCAN_STEP_DAYS).ceil().max(1.0) as usize;
    let step = (b - a) / n as f64;
    let (mut best_i, mut best) = (0, f(a));
    for i in 1..=n {
        let v = f(a + step * i as f64);
        if v > best {
            (best_i, best) = (i, v);
        }
    }
    let (mut lo, mut hi) = ((a + step * best_i as f64 - step).max(a), (a + step * best_i as f64 + step).min(b));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    while hi - lo > TOLERANCE_DAYS {
        if f1 < f2 {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        } else {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        }
    }
    let x = 0.5 * (lo + hi);
    let fx = f(x);
    if fx >= best { (x, fx) } else { (a + step * best_i as f64, best) }
}

const SCAN_STEP_DAYS: f64 = 300.0 / 86_400.0;
const TOLERANCE_DAYS: f64 = 0.01 / 86_400.0;

fn intervals_above(f: impl Fn(f64) -> f64, start: Epoch, end: Epoch) -> Vec<(Epoch, Epoch)> {
    let t0 = MarsTime::from_epoch(start).jd_tt;
    let t1 = MarsTime::from_epoch(end).jd_tt;
    let mut out: Vec<(f64, f64)> = Vec::new();
    if t1 <= t0 {
        return Vec::new();
    }
    let mut open = if f(t0) > 0.0 { Some(t0) } else { None };
    let mut a = t0;
    let mut fa = f(t0);
    while a < t1 {
        let b = (a + SCAN_STEP_DAYS).min(t1);
        let fb = f(b);
        if (fa > 0.0) != (fb > 0.0) {
            let x = bisect(&f, a, b, fa > 0.0);
            match open.take() {
                Some(s) => out.push((s, x)),
                None => open = Some(x),
            }
        }
        a = b;
        fa = fb;
    }
    if let Some(s) = open {
        out.push((s, t1));
    }
    out.into_iter().map(|(s, e)| (epoch_from_jd_tt(s), epoch_from_jd_tt(e))).collect()
}

/// The first crossing of `f` through zero in [a, b], upward (`rising`) or downward.
fn crossing(f: &impl Fn(f64) -> f64, a: f64, b: f64, rising: bool) -> Option<f64> {
    let n = ((b - a) / SCAN_STEP_DAYS).ceil().max(1.0) as usize;
    let step = (b - a) / n as f64;
    let mut x0 = a;
    let mut f0 = f(a);
    for i in 1..=n {
        let x1 = a + step * i as f64;
        let f1 = f(x1);
        let hit = if rising { f0 <= 0.0 && f1 > 0.0 } else { f0 > 0.0 && f1 <= 0.0 };
        if hit {
            return Some(bisect(f, x0, x1, f0 > 0.0));
        }
        x0 = x1;
        f0 = f1;
    }
    None
}

fn bisect(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, positive_at_a: bool) -> f64 {
    while b - a > TOLERANCE_DAYS {
        let m = 0.5 * (a + b);
        if (f(m) > 0.0) == positive_at_a {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mask_interpolates_between_sector_centres_and_wraps() {
        let m = HorizonMask::new(vec![0.0, 10.0, 20.0, 10.0]).unwrap();
        assert_eq!(m.elevation_at(0.0), 0.0);
        assert_eq!(m.elevation_at(90.0), 10.0);
        assert_eq!(m.elevation_at(135.0), 15.0);
        assert_eq!(m.elevation_at(315.0), 5.0);
        assert_eq!(m.elevation_at(-45.0), 5.0);
        assert!(HorizonMask::new(vec![]).is_err());
        assert!(HorizonMask::new(vec![95.0]).is_err());
    }
}
