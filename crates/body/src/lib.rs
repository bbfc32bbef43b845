//! The bodies areo plans on — Mars, the Moon and the Earth — as plain constants: their
//! shape, gravity, rotation and identifiers. Every other areo crate takes its radii
//! from here, so a body is defined once.
//!
//! - [`Body`]: which body (scenario files write `Mars`, `Moon` or `Earth`), with its
//!   radii, flattening, surface gravity, sidereal rotation, mean solar day and its NAIF
//!   and IAU identifiers;
//! - [`Spheroid`]: a reference ellipsoid of revolution that maps are referenced to
//!   (the IAU 2015 Mars ellipsoid, the MOLA and LOLA spheres, WGS84), with
//!   body-fixed Cartesian conversions and local east-north-up axes.
//!
//! ```
//! use areo_body::{Body, Spheroid};
//! assert_eq!(Body::Mars.naif_id(), 499);
//! assert_eq!(Body::Mars.reference_surface(), Spheroid::MARS_MOLA_SPHERE);
//! assert_eq!(Spheroid::MOON.body(), Some(Body::Moon));
//! ```
//!
//! Architecture invariant: areo-body depends on no other areo crate; it holds published
//! constants and the geometry of an ellipsoid, nothing that moves with time.

mod spheroid;

pub use crate::spheroid::{Spheroid, WGS84_INVERSE_FLATTENING};

/// A mean Mars solar day (sol), s: 1.0274912517 Earth days (Allison & McEwen 2000, as
/// Mars24 uses).
pub const SOL_S: f64 = SOL_IN_DAYS * 86_400.0;

/// A mean Mars solar day in Earth days (Mars24, 2018 constants).
pub const SOL_IN_DAYS: f64 = 1.027_491_251_7;

/// A body a rover can drive on (scenario files write `Mars`, `Moon` or `Earth`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize)]
pub enum Body {
    /// Mars: IAU 2015 ellipsoid, planetocentric latitudes.
    #[default]
    Mars,
    /// The Moon: a sphere of 1737.4 km, selenographic (planetocentric) latitudes.
    Moon,
    /// The Earth: the WGS84 ellipsoid, geodetic latitudes.
    Earth,
}

impl Body {
    /// Every body, in the order the CLI lists them.
    pub const ALL: [Body; 3] = [Body::Mars, Body::Moon, Body::Earth];

    /// The lower-case name (`mars`, `moon`, `earth`).
    pub fn name(self) -> &'static str {
        match self {
            Body::Mars => "mars",
            Body::Moon => "moon",
            Body::Earth => "earth",
        }
    }

    /// The body of a lower-case or capitalised name.
    pub fn from_name(name: &str) -> Option<Body> {
        Body::ALL.into_iter().find(|b| b.name().eq_ignore_ascii_case(name))
    }

    /// The name the IAU and the planetary GIS registries use ("Mars", "Moon", "Earth").
    pub fn iau_name(self) -> &'static str {
        match self {
            Body::Mars => "Mars",
            Body::Moon => "Moon",
            Body::Earth => "Earth",
        }
    }

    /// The NAIF SPICE integer code (499, 301, 399); the IAU planetary CRS codes are built
    /// on it (for example `IAU_2015:49900` for Mars).
    pub fn naif_id(self) -> u32 {
        match self {
            Body::Mars => 499,
            Body::Moon => 301,
            Body::Earth => 399,
        }
    }

    /// The body's ellipsoid: IAU 2015 for Mars (Archinal et al. 2018), the IAU mean
    /// sphere for the Moon, WGS84 for the Earth.
    pub fn ellipsoid(self) -> Spheroid {
        match self {
            Body::Mars => Spheroid::MARS_IAU2015,
            Body::Moon => Spheroid::MOON,
            Body::Earth => Spheroid::EARTH_WGS84,
        }
    }

    /// The surface elevation products are referenced to: the MOLA sphere (MEGDR) on
    /// Mars, the LOLA sphere on the Moon, WGS84 on the Earth.
    pub fn reference_surface(self) -> Spheroid {
        match self {
            Body::Mars => Spheroid::MARS_MOLA_SPHERE,
            Body::Moon => Spheroid::MOON,
            Body::Earth => Spheroid::EARTH_WGS84,
        }
    }

    /// Equatorial radius of [`Body::ellipsoid`], m.
    pub fn equatorial_radius_m(self) -> f64 {
        self.ellipsoid().equatorial_radius_m
    }

    /// Polar radius of [`Body::ellipsoid`], m.
    pub fn polar_radius_m(self) -> f64 {
        self.ellipsoid().polar_radius_m
    }

    /// Flattening (a − b)/a of [`Body::ellipsoid`].
    pub fn flattening(self) -> f64 {
        self.ellipsoid().flattening()
    }

    /// The published mean radius, m, the sphere used for the ground's curvature: Mars
    /// 3389.5 km (IAU 2015 volumetric mean), the Moon 1737.4 km, the Earth 6371.0088 km
    /// (IUGG R1 = (2a + b)/3 of WGS84).
    pub fn mean_radius_m(self) -> f64 {
        match self {
            Body::Mars => 3_389_500.0,
            Body::Moon => 1_737_400.0,
            Body::Earth => 6_371_008.8,
        }
    }

    /// Surface gravity, m/s² (Mars 3.711, Moon 1.622, Earth standard 9.80665).
    pub fn surface_gravity_m_s2(self) -> f64 {
        match self {
            Body::Mars => 3.711,
            Body::Moon => 1.622,
            Body::Earth => 9.806_65,
        }
    }

    /// Sidereal rotation period, s: Mars 1.025 956 75 d (IAU 2015: 350.891 982 26° per
    /// day), the Moon 27.321 661 d (synchronous), the Earth 86 164.0905 s.
    pub fn sidereal_rotation_s(self) -> f64 {
        match self {
            Body::Mars => 360.0 / 350.891_982_26 * 86_400.0,
            Body::Moon => 27.321_661 * 86_400.0,
            Body::Earth => 86_164.090_5,
        }
    }

    /// The mean solar day, s: a sol on Mars, a synodic month (29.530589 d) on the Moon,
    /// 86 400 s on the Earth.
    pub fn solar_day_s(self) -> f64 {
        match self {
            Body::Mars => SOL_S,
            Body::Moon => 29.530_588_853 * 86_400.0,
            Body::Earth => 86_400.0,
        }
    }

    /// Whether the body has an atmosphere that dims the Sun (the Moon has none).
    pub fn has_atmosphere(self) -> bool {
        self != Body::Moon
    }
}

impl std::fmt::Display for Body {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn published_shapes_and_days() {
        // WGS84: b = 6356752.314 m; the IUGG mean radius is (2a + b)/3.
        assert!((Body::Earth.polar_radius_m() - 6_356_752.314).abs() < 1e-3);
        let e = Body::Earth.ellipsoid();
        assert!(((2.0 * e.equatorial_radius_m + e.polar_radius_m) / 3.0 - Body::Earth.mean_radius_m()).abs() < 0.05);
        // Mars IAU 2015: f = (3396.19 − 3376.20)/3396.19 = 1/169.9.
        assert!((1.0 / Body::Mars.flattening() - 169.894).abs() < 1e-2);
        // A sol is longer than Mars's sidereal day by about 2.3 minutes.
        let extra = Body::Mars.solar_day_s() - Body::Mars.sidereal_rotation_s();
        assert!((extra - 132.6).abs() < 1.0, "{extra}");
        // The solar day from the sidereal one and the orbit: 1/s = 1/r − 1/P (Earth: 365.256 d).
        let solar = 1.0 / (1.0 / Body::Earth.sidereal_rotation_s() - 1.0 / (365.256_363 * 86_400.0));
        assert!((solar - Body::Earth.solar_day_s()).abs() < 0.1, "{solar}");
        assert_eq!(Body::from_name("Moon"), Some(Body::Moon));
        assert_eq!(Body::from_name("pluto"), None);
        assert_eq!(Body::ALL.map(Body::naif_id), [499, 301, 399]);
    }
}
