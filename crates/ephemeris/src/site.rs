use crate::body::Body;
use crate::error::{Error, Result};

/// A place on a [`Body`]: latitude and east longitude, degrees — planetocentric on Mars
/// and the Moon, geodetic (WGS84, as GPS gives it) on the Earth.
///
/// The local horizontal at a site is the tangent plane of the body's ellipsoid, so
/// "up" is the ellipsoid normal (planetographic latitude), not the radius vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site {
    lat_deg: f64,
    lon_east_deg: f64,
    body: Body,
}

impl Site {
    /// A site on Mars at planetocentric latitude `lat_deg` ∈ [−90, 90] and east
    /// longitude `lon_east_deg` (any finite value; wrapped to [0, 360)).
    pub fn new(lat_deg: f64, lon_east_deg: f64) -> Result<Site> {
        Site::on(Body::Mars, lat_deg, lon_east_deg)
    }

    /// A site on `body` (latitude planetocentric on Mars and the Moon, geodetic on the
    /// Earth), with the ranges of [`Site::new`].
    pub fn on(body: Body, lat_deg: f64, lon_east_deg: f64) -> Result<Site> {
        if !(-90.0..=90.0).contains(&lat_deg) {
            return Err(Error::OutOfRange {
                field: "lat_deg",
                value: lat_deg,
                allowed: "-90..=90 (planetocentric degrees)",
            });
        }
        if !lon_east_deg.is_finite() {
            return Err(Error::OutOfRange {
                field: "lon_east_deg",
                value: lon_east_deg,
                allowed: "a finite number of degrees east",
            });
        }
        Ok(Site { lat_deg, lon_east_deg: lon_east_deg.rem_euclid(360.0), body })
    }

    /// The body the site is on.
    pub fn body(&self) -> Body {
        self.body
    }

    /// Latitude as given (planetocentric, or geodetic on the Earth), degrees.
    pub fn lat_deg(&self) -> f64 {
        self.lat_deg
    }

    /// East longitude in [0, 360), degrees.
    pub fn lon_east_deg(&self) -> f64 {
        self.lon_east_deg
    }

    /// Planetographic (geodetic) latitude on the body's ellipsoid, degrees.
    pub fn planetographic_lat_deg(&self) -> f64 {
        match self.body {
            Body::Mars => planetocentric_to_planetographic_deg(self.lat_deg),
            Body::Moon | Body::Earth => self.lat_deg,
        }
    }

    /// The site's body-fixed position on the ellipsoid (height 0), m.
    pub fn position_m(&self) -> [f64; 3] {
        let (a, b) = (self.body.equatorial_radius_m(), self.body.polar_radius_m());
        let (sl, cl) = self.lon_east_deg.to_radians().sin_cos();
        if self.body == Body::Earth {
            // Geodetic latitude: prime-vertical radius N = a / √(1 − e² sin²φ).
            let (sp, cp) = self.lat_deg.to_radians().sin_cos();
            let e2 = 1.0 - (b / a).powi(2);
            let n = a / (1.0 - e2 * sp * sp).sqrt();
            return [n * cp * cl, n * cp * sl, n * (1.0 - e2) * sp];
        }
        let (sp, cp) = self.lat_deg.to_radians().sin_cos();
        let r = a * b / ((b * cp).powi(2) + (a * sp).powi(2)).sqrt();
        [r * cp * cl, r * cp * sl, r * sp]
    }

    /// The local east, north and up unit vectors in the body-fixed frame.
    pub fn enu_axes(&self) -> [[f64; 3]; 3] {
        let lat_g = self.planetographic_lat_deg().to_radians();
        let lon = self.lon_east_deg.to_radians();
        let (sl, cl) = lon.sin_cos();
        let (sp, cp) = lat_g.sin_cos();
        [[-sl, cl, 0.0], [-sp * cl, -sp * sl, cp], [cp * cl, cp * sl, sp]]
    }

    /// Azimuth (clockwise from north, [0, 360)) and elevation above the local
    /// horizontal, degrees, of a body-fixed direction `v` (need not be unit length).
    pub fn azimuth_elevation_deg(&self, v: [f64; 3]) -> (f64, f64) {
        let [e, n, u] = self.enu_axes();
        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let de = dot(e, v) / norm;
        let dn = dot(n, v) / norm;
        let du = (dot(u, v) / norm).clamp(-1.0, 1.0);
        let az = de.atan2(dn).to_degrees().rem_euclid(360.0);
        (az, du.asin().to_degrees())
    }
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// tan φg = (a/b)² tan φc on an ellipsoid of revolution.
pub(crate) fn planetocentric_to_planetographic_deg(lat_c_deg: f64) -> f64 {
    if lat_c_deg.abs() >= 90.0 {
        return lat_c_deg;
    }
    let k = (Body::Mars.equatorial_radius_m() / Body::Mars.polar_radius_m()).powi(2);
    (k * lat_c_deg.to_radians().tan()).atan().to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planetographic_latitude_is_larger_away_from_equator_and_pole() {
        assert_eq!(planetocentric_to_planetographic_deg(0.0), 0.0);
        assert_eq!(planetocentric_to_planetographic_deg(90.0), 90.0);
        // Flattening f ≈ 0.005886: φg − φc ≈ f·sin 2φ rad ≈ 0.337° at 45°.
        let d = planetocentric_to_planetographic_deg(45.0) - 45.0;
        assert!((d - 0.3385).abs() < 2e-3, "{d}");
    }

    #[test]
    fn enu_axes_are_orthonormal_and_right_handed() {
        let s = Site::new(-14.64, 175.298).unwrap();
        let [e, n, u] = s.enu_axes();
        for (a, b) in [(e, n), (n, u), (e, u)] {
            assert!(dot(a, b).abs() < 1e-12);
        }
        let cross = [e[1] * n[2] - e[2] * n[1], e[2] * n[0] - e[0] * n[2], e[0] * n[1] - e[1] * n[0]];
        for i in 0..3 {
            assert!((cross[i] - u[i]).abs() < 1e-12);
        }
    }

    #[test]
    fn rejects_latitude_out_of_range() {
        assert!(Site::new(90.5, 0.0).is_err());
        assert!(Site::new(0.0, f64::NAN).is_err());
        assert_eq!(Site::new(0.0, -10.0).unwrap().lon_east_deg(), 350.0);
    }
}
