//! Reference ellipsoids of revolution and the geometry on them.

use serde::{Deserialize, Serialize};

use crate::Body;

/// WGS84's defining inverse flattening 1/f.
pub const WGS84_INVERSE_FLATTENING: f64 = 298.257_223_563;

/// A reference ellipsoid of revolution (a sphere when the radii are equal), m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Spheroid {
    /// Equatorial radius, m.
    pub equatorial_radius_m: f64,
    /// Polar radius, m.
    pub polar_radius_m: f64,
}

impl Spheroid {
    /// Mars, IAU 2015 ellipsoid (Archinal et al. 2018): 3396.19 km × 3376.20 km.
    pub const MARS_IAU2015: Spheroid = Spheroid { equatorial_radius_m: 3_396_190.0, polar_radius_m: 3_376_200.0 };
    /// The MOLA reference sphere of the MEGDR products, R = 3396 km.
    pub const MARS_MOLA_SPHERE: Spheroid = Spheroid { equatorial_radius_m: 3_396_000.0, polar_radius_m: 3_396_000.0 };
    /// The Moon's reference sphere of the LOLA products (and IAU mean radius),
    /// R = 1737.4 km.
    pub const MOON: Spheroid = Spheroid { equatorial_radius_m: 1_737_400.0, polar_radius_m: 1_737_400.0 };
    /// The Earth's WGS84 ellipsoid: a = 6378.137 km, 1/f = 298.257223563.
    pub const EARTH_WGS84: Spheroid = Spheroid {
        equatorial_radius_m: 6_378_137.0,
        polar_radius_m: 6_378_137.0 * (1.0 - 1.0 / WGS84_INVERSE_FLATTENING),
    };

    /// The body whose reference surface this is, or `None` for radii that are none of
    /// the shipped ones (within 1 km).
    pub fn body(&self) -> Option<Body> {
        let near = |r: f64, lo: f64, hi: f64| (lo - 1000.0..=hi + 1000.0).contains(&r);
        let (a, b) = (self.equatorial_radius_m, self.polar_radius_m);
        if near(a, 3_396_000.0, 3_396_190.0) && near(b, 3_376_200.0, 3_396_000.0) {
            Some(Body::Mars)
        } else if near(a, 1_737_400.0, 1_737_400.0) && near(b, 1_737_400.0, 1_737_400.0) {
            Some(Body::Moon)
        } else if near(a, 6_378_137.0, 6_378_137.0) && near(b, 6_356_752.0, 6_378_137.0) {
            Some(Body::Earth)
        } else {
            None
        }
    }

    /// Flattening (a − b)/a.
    pub fn flattening(&self) -> f64 {
        (self.equatorial_radius_m - self.polar_radius_m) / self.equatorial_radius_m
    }

    /// Mean radius (2a + b)/3, m.
    pub fn mean_radius_m(&self) -> f64 {
        (2.0 * self.equatorial_radius_m + self.polar_radius_m) / 3.0
    }

    /// Body-fixed Cartesian position (m) of a point at planetocentric latitude and east
    /// longitude (degrees) and `height_m` above the ellipsoid along the radius.
    pub fn to_cartesian(&self, lat_deg: f64, lon_east_deg: f64, height_m: f64) -> [f64; 3] {
        let (sp, cp) = lat_deg.to_radians().sin_cos();
        let (sl, cl) = lon_east_deg.to_radians().sin_cos();
        let r = self.radius_at(sp, cp) + height_m;
        [r * cp * cl, r * cp * sl, r * sp]
    }

    /// Planetocentric latitude, east longitude (degrees) and height above the ellipsoid
    /// (m, along the radius) of a body-fixed position.
    pub fn from_cartesian(&self, p: [f64; 3]) -> (f64, f64, f64) {
        let rho = (p[0] * p[0] + p[1] * p[1]).sqrt();
        let lat = p[2].atan2(rho);
        let lon = p[1].atan2(p[0]).to_degrees().rem_euclid(360.0);
        let (sp, cp) = lat.sin_cos();
        (lat.to_degrees(), lon, (rho * rho + p[2] * p[2]).sqrt() - self.radius_at(sp, cp))
    }

    /// Radius of the meridian ellipse at planetocentric latitude φ (given as sin φ,
    /// cos φ): ab / √(b²cos²φ + a²sin²φ).
    fn radius_at(&self, sp: f64, cp: f64) -> f64 {
        let (a, b) = (self.equatorial_radius_m, self.polar_radius_m);
        a * b / ((b * cp).powi(2) + (a * sp).powi(2)).sqrt()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cartesian_round_trip_on_the_ellipsoid() {
        let s = Spheroid::MARS_IAU2015;
        for (lat, lon, h) in [(0.0, 0.0, 0.0), (-4.59, 137.44, -4500.0), (85.0, 300.0, 1200.0), (-45.0, 10.0, 21_000.0)]
        {
            let (la, lo, hh) = s.from_cartesian(s.to_cartesian(lat, lon, h));
            assert!((la - lat).abs() < 1e-9 && (lo - lon).abs() < 1e-9 && (hh - h).abs() < 1e-6);
        }
        // The equator and pole sit at the published radii.
        assert!((s.to_cartesian(0.0, 0.0, 0.0)[0] - 3_396_190.0).abs() < 1e-6);
        assert!((s.to_cartesian(90.0, 0.0, 0.0)[2] - 3_376_200.0).abs() < 1e-6);
    }

    #[test]
    fn each_shipped_surface_names_its_body() {
        assert_eq!(Spheroid::MARS_IAU2015.body(), Some(Body::Mars));
        assert_eq!(Spheroid::MARS_MOLA_SPHERE.body(), Some(Body::Mars));
        assert_eq!(Spheroid::EARTH_WGS84.body(), Some(Body::Earth));
        assert_eq!(Spheroid { equatorial_radius_m: 2e6, polar_radius_m: 2e6 }.body(), None);
        for b in Body::ALL {
            assert_eq!(b.ellipsoid().body(), Some(b));
            assert_eq!(b.reference_surface().body(), Some(b));
        }
    }

    #[test]
    fn up_is_the_ellipsoid_normal() {
        // At 45° planetocentric on Mars the normal leans poleward of the radius by
        // atan(k tan φ) − φ with k = (a/b)²: about 0.338°.
        let s = Spheroid::MARS_IAU2015;
        let up = s.enu_axes(45.0, 0.0)[2];
        let geographic = up[2].asin().to_degrees();
        let k = (3_396_190.0f64 / 3_376_200.0).powi(2);
        assert!((geographic - k.atan().to_degrees()).abs() < 1e-12);
        assert!((geographic - 45.0 - 0.338).abs() < 1e-3, "{geographic}");
    }
}
