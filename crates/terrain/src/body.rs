//! Reference bodies and map projections: every DEM cell knows its latitude and
//! longitude.

use serde::{Deserialize, Serialize};

/// A reference ellipsoid of revolution (a sphere when the radii are equal).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Body {
    /// Equatorial radius, m.
    pub equatorial_radius_m: f64,
    /// Polar radius, m.
    pub polar_radius_m: f64,
}

impl Body {
    /// Mars, IAU 2015 ellipsoid (Archinal et al. 2018): 3396.19 km × 3376.20 km.
    pub const MARS_IAU2015: Body = Body { equatorial_radius_m: 3_396_190.0, polar_radius_m: 3_376_200.0 };
    /// The MOLA reference sphere of the MEGDR products, R = 3396 km.
    pub const MARS_MOLA_SPHERE: Body = Body { equatorial_radius_m: 3_396_000.0, polar_radius_m: 3_396_000.0 };
    /// The Moon's reference sphere of the LOLA products (and IAU mean radius),
    /// R = 1737.4 km.
    pub const MOON: Body = Body { equatorial_radius_m: 1_737_400.0, polar_radius_m: 1_737_400.0 };
    /// The Earth's WGS84 ellipsoid: a = 6378.137 km, 1/f = 298.257223563.
    pub const EARTH_WGS84: Body =
        Body { equatorial_radius_m: 6_378_137.0, polar_radius_m: 6_378_137.0 * (1.0 - 1.0 / 298.257_223_563) };

    /// The name of the body whose reference surface this is ("Mars", "Moon",
    /// "Earth"), or `None` for radii that are none of the shipped ones (within 1 km).
    pub fn name(&self) -> Option<&'static str> {
        let near = |r: f64, lo: f64, hi: f64| (lo - 1000.0..=hi + 1000.0).contains(&r);
        let (a, b) = (self.equatorial_radius_m, self.polar_radius_m);
        if near(a, 3_396_000.0, 3_396_190.0) && near(b, 3_376_200.0, 3_396_000.0) {
            Some("Mars")
        } else if near(a, 1_737_400.0, 1_737_400.0) && near(b, 1_737_400.0, 1_737_400.0) {
            Some("Moon")
        } else if near(a, 6_378_137.0, 6_378_137.0) && near(b, 6_356_752.0, 6_378_137.0) {
            Some("Earth")
        } else {
            None
        }
    }

    /// Mean radius (2a + b)/3, m: the radius used for the surface's curvature.
    pub fn mean_radius_m(&self) -> f64 {
        (2.0 * self.equatorial_radius_m + self.polar_radius_m) / 3.0
    }

    /// Body-fixed Cartesian position (m) of a point at planetocentric latitude and east
    /// longitude (degrees) and `height_m` above the ellipsoid along the radius.
    pub fn to_cartesian(&self, lat_deg: f64, lon_east_deg: f64, height_m: f64) -> [f64; 3] {
        let (sp, cp) = lat_deg.to_radians().sin_cos();
        let (sl, cl) = lon_east_deg.to_radians().sin_cos();
        let (a, b) = (self.equatorial_radius_m, self.polar_radius_m);
        // Radius of the ellipse at planetocentric latitude φ: ab / √(b²cos²φ + a²sin²φ).
        let r = a * b / ((b * cp).powi(2) + (a * sp).powi(2)).sqrt() + height_m;
        [r * cp * cl, r * cp * sl, r * sp]
    }

    /// Planetocentric latitude, east longitude (degrees) and height above the ellipsoid
    /// (m, along the radius) of a body-fixed position.
    pub fn from_cartesian(&self, p: [f64; 3]) -> (f64, f64, f64) {
        let rho = (p[0] * p[0] + p[1] * p[1]).sqrt();
        let lat = p[2].atan2(rho);
        let lon = p[1].atan2(p[0]).to_degrees().rem_euclid(360.0);
        let (sp, cp) = lat.sin_cos();
        let (a, b) = (self.equatorial_radius_m, self.polar_radius_m);
        let surface = a * b / ((b * cp).powi(2) + (a * sp).powi(2)).sqrt();
        (lat.to_degrees(), lon, (rho * rho + p[2] * p[2]).sqrt() - surface)
    }

    /// The local east, north and up unit vectors at a planetocentric latitude and east
    /// longitude; "up" is the ellipsoid normal.
    pub fn enu_axes(&self, lat_deg: f64, lon_east_deg: f64) -> [[f64; 3]; 3] {
        let k = (self.equatorial_radius_m / self.polar_radius_m).powi(2);
        let lat_g = if lat_deg.abs() >= 90.0 { lat_deg } else { (k * lat_deg.to_radians().tan()).atan().to_degrees() };
        let (sp, cp) = lat_g.to_radians().sin_cos();
        let (sl, cl) = lon_east_deg.to_radians().sin_cos();
        [[-sl, cl, 0.0], [-sp * cl, -sp * sl, cp], [cp * cl, cp * sl, sp]]
    }
}

/// How a DEM's metric grid maps to latitude and longitude.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Projection {
    /// A local metric frame with no geographic reference (synthesised terrain).
    Local,
    /// Equirectangular (simple cylindrical) on a sphere of the body's equatorial radius:
    /// x = R·(λ − λ0)·cos φts, y = R·φ (MOLA MEGDR, many HiRISE/CTX DTMs).
    Equirectangular {
        /// Standard parallel φts, degrees.
        lat_ts_deg: f64,
        /// Central meridian λ0, degrees east.
        lon0_deg: f64,
    },
    /// Polar stereographic on a sphere of the body's equatorial radius, true scale at
    /// the pole (scale factor 1 there), north or south.
    PolarStereographic {
        /// True for the north pole, false for the south.
        north: bool,
        /// Longitude along the grid's negative y axis (north) / positive y axis
        /// (south), degrees east.
        lon0_deg: f64,
    },
}

impl Projection {
    /// Planetocentric latitude and east longitude (degrees) of map point (x, y), m.
    pub fn to_geographic(&self, body: &Body, x: f64, y: f64) -> Option<(f64, f64)> {
        let r = body.equatorial_radius_m;
        match *self {
            Projection::Local => None,
            Projection::Equirectangular { lat_ts_deg, lon0_deg } => {
                let lat = (y / r).to_degrees();
                let lon = lon0_deg + (x / (r * lat_ts_deg.to_radians().cos())).to_degrees();
                Some((lat, lon.rem_euclid(360.0)))
            }
            Projection::PolarStereographic { north, lon0_deg } => {
                let rho = (x * x + y * y).sqrt();
                let c = 2.0 * (rho / (2.0 * r)).atan();
                let lat = if north { 90.0 - c.to_degrees() } else { c.to_degrees() - 90.0 };
                let lon = if north { lon0_deg + x.atan2(-y).to_degrees() } else { lon0_deg + x.atan2(y).to_degrees() };
                Some((lat, lon.rem_euclid(360.0)))
            }
        }
    }

    /// Map point (x, y), m, of a planetocentric latitude and east longitude (degrees).
    pub fn from_geographic(&self, body: &Body, lat_deg: f64, lon_east_deg: f64) -> Option<(f64, f64)> {
        let r = body.equatorial_radius_m;
        match *self {
            Projection::Local => None,
            Projection::Equirectangular { lat_ts_deg, lon0_deg } => {
                let dlon = (lon_east_deg - lon0_deg + 180.0).rem_euclid(360.0) - 180.0;
                Some((r * dlon.to_radians() * lat_ts_deg.to_radians().cos(), r * lat_deg.to_radians()))
            }
            Projection::PolarStereographic { north, lon0_deg } => {
                let c = if north { 90.0 - lat_deg } else { lat_deg + 90.0 };
                let rho = 2.0 * r * (c.to_radians() / 2.0).tan();
                let t = (lon_east_deg - lon0_deg).to_radians();
                Some(if north { (rho * t.sin(), -rho * t.cos()) } else { (rho * t.sin(), rho * t.cos()) })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cartesian_round_trip_on_the_ellipsoid() {
        for (lat, lon, h) in [(0.0, 0.0, 0.0), (-4.59, 137.44, -4500.0), (85.0, 300.0, 1200.0), (-45.0, 10.0, 21_000.0)]
        {
            let p = Body::MARS_IAU2015.to_cartesian(lat, lon, h);
            let (la, lo, hh) = Body::MARS_IAU2015.from_cartesian(p);
            assert!((la - lat).abs() < 1e-9 && (lo - lon).abs() < 1e-9 && (hh - h).abs() < 1e-6);
        }
        // The equator and pole sit at the published radii.
        assert!((Body::MARS_IAU2015.to_cartesian(0.0, 0.0, 0.0)[0] - 3_396_190.0).abs() < 1e-6);
        assert!((Body::MARS_IAU2015.to_cartesian(90.0, 0.0, 0.0)[2] - 3_376_200.0).abs() < 1e-6);
    }

    #[test]
    fn projections_round_trip_and_match_mola_spacing() {
        let body = Body::MARS_MOLA_SPHERE;
        let eqc = Projection::Equirectangular { lat_ts_deg: -5.40234375, lon0_deg: 0.0 };
        // MEGDR: 1/128° of latitude is 463.0577 m on R = 3396 km (README of the data).
        let (_, y1) = eqc.from_geographic(&body, -1.8984375, 134.296875).unwrap();
        let (_, y2) = eqc.from_geographic(&body, -1.8984375 - 1.0 / 128.0, 134.296875).unwrap();
        assert!(((y1 - y2) - 463.0577).abs() < 1e-3);
        for proj in [
            eqc,
            Projection::PolarStereographic { north: true, lon0_deg: 0.0 },
            Projection::PolarStereographic { north: false, lon0_deg: 90.0 },
        ] {
            let lat = match proj {
                Projection::PolarStereographic { north: true, .. } => 80.0,
                Projection::PolarStereographic { north: false, .. } => -75.0,
                _ => -5.0,
            };
            let (x, y) = proj.from_geographic(&body, lat, 137.0).unwrap();
            let (la, lo) = proj.to_geographic(&body, x, y).unwrap();
            assert!((la - lat).abs() < 1e-9 && (lo - 137.0).abs() < 1e-9, "{proj:?}: {la} {lo}");
        }
    }
}
