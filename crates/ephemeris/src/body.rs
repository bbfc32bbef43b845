//! The bodies areo plans on — Mars, the Moon and the Earth — with their shape, gravity,
//! day length and the ephemeris that says where the Sun (and the Earth) are in their
//! skies.

use hifitime::Epoch;

use crate::sun::{Mars24, SunModel, SunState};

/// A body a rover can drive on (scenario files write `Mars`, `Moon` or `Earth`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize)]
pub enum Body {
    /// Mars: Mars24 time and Sun (Allison & McEwen 2000), IAU 2015 ellipsoid,
    /// planetocentric latitudes.
    #[default]
    Mars,
    /// The Moon: Meeus's truncated ELP-2000/82 and solar theory, the IAU WGCCRE
    /// rotation, a sphere of 1737.4 km, selenographic (planetocentric) latitudes.
    Moon,
    /// The Earth: Meeus's solar theory with nutation, apparent sidereal time with
    /// UT1 = UTC, the WGS84 ellipsoid, geodetic latitudes.
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

    /// Equatorial radius, m (Mars IAU 2015, Moon IAU mean sphere, Earth WGS84).
    pub fn equatorial_radius_m(self) -> f64 {
        match self {
            Body::Mars => crate::site::MARS_EQUATORIAL_RADIUS_M,
            Body::Moon => 1_737_400.0,
            Body::Earth => crate::terrestrial::WGS84_A_M,
        }
    }

    /// Polar radius, m.
    pub fn polar_radius_m(self) -> f64 {
        match self {
            Body::Mars => crate::site::MARS_POLAR_RADIUS_M,
            Body::Moon => 1_737_400.0,
            Body::Earth => crate::terrestrial::WGS84_A_M * (1.0 - crate::terrestrial::WGS84_F),
        }
    }

    /// Mean radius (2a + b)/3, m: the sphere used for the ground's curvature.
    pub fn mean_radius_m(self) -> f64 {
        (2.0 * self.equatorial_radius_m() + self.polar_radius_m()) / 3.0
    }

    /// Surface gravity, m/s² (Mars 3.711, Moon 1.622, Earth standard 9.80665).
    pub fn surface_gravity_m_s2(self) -> f64 {
        match self {
            Body::Mars => 3.711,
            Body::Moon => 1.622,
            Body::Earth => 9.806_65,
        }
    }

    /// The mean solar day, s: a sol on Mars, a synodic month (29.530589 d) on the Moon,
    /// 86 400 s on the Earth.
    pub fn solar_day_s(self) -> f64 {
        match self {
            Body::Mars => crate::SOL_S,
            Body::Moon => 29.530_588_853 * 86_400.0,
            Body::Earth => 86_400.0,
        }
    }

    /// Whether the body has an atmosphere that dims the Sun (the Moon has none).
    pub fn has_atmosphere(self) -> bool {
        self != Body::Moon
    }

    /// The Earth from the body's centre at `epoch`; `None` on the Earth.
    pub fn earth(self, epoch: Epoch) -> Option<EarthView> {
        match self {
            Body::Mars => {
                let e = crate::earth::earth_from_mars(epoch);
                Some(EarthView {
                    direction_body_fixed: e.direction_body_fixed,
                    distance_km: e.distance_au * crate::earth::AU_M / 1000.0,
                })
            }
            Body::Moon => Some(crate::moon::sky(epoch).earth),
            Body::Earth => None,
        }
    }
}

impl std::fmt::Display for Body {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl SunModel for Body {
    fn sun(&self, epoch: Epoch) -> SunState {
        match self {
            Body::Mars => Mars24.sun(epoch),
            Body::Moon => crate::moon::sky(epoch).sun,
            Body::Earth => crate::terrestrial::sun(epoch),
        }
    }

    fn body(&self) -> Body {
        *self
    }
}

/// The Earth seen from another body's centre at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EarthView {
    /// Unit vector from the body's centre to the Earth's, body-fixed frame.
    pub direction_body_fixed: [f64; 3],
    /// Centre-to-centre distance, km.
    pub distance_km: f64,
}

impl EarthView {
    /// The Earth's azimuth (clockwise from north) and elevation (degrees) at `site`,
    /// topocentric: seen from the site, not from the body's centre (on the Moon the
    /// site's 1737 km offset moves the Earth by up to 0.26°).
    pub fn at_site(&self, site: &crate::Site) -> (f64, f64) {
        let p = site.position_m();
        let d = self.distance_km * 1000.0;
        let v: [f64; 3] = std::array::from_fn(|i| self.direction_body_fixed[i] * d - p[i]);
        site.azimuth_elevation_deg(v)
    }

    /// Latitude and east longitude (−180, 180] of the sub-Earth point on the body,
    /// degrees: on the Moon, the libration in latitude and longitude.
    pub fn sub_point_deg(&self) -> (f64, f64) {
        let v = self.direction_body_fixed;
        let lat = v[2].clamp(-1.0, 1.0).asin().to_degrees();
        let lon = v[1].atan2(v[0]).to_degrees();
        (lat, lon)
    }
}
