//! The ephemeris of the bodies areo plans on (defined in areo-body): where the Sun and
//! the Earth are in their skies.

use hifitime::Epoch;

use crate::sun::{Mars24, SunModel, SunState};

pub use areo_body::Body;

/// The Earth as seen from a body's centre (implemented for [`Body`], so that
/// `Body::Moon.earth(epoch)` reads as it means).
pub trait EarthFrom {
    /// The Earth from the body's centre at `epoch`; `None` on the Earth.
    fn earth(self, epoch: Epoch) -> Option<EarthView>;
}

impl EarthFrom for Body {
    fn earth(self, epoch: Epoch) -> Option<EarthView> {
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
