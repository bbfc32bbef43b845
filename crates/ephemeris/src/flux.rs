//! Solar flux at Mars and power on a panel.
//!
//! - Top of atmosphere: S0 / r², with S0 = 1361 W/m², the total solar irradiance at
//!   1 AU measured by SORCE/TIM (Kopp & Lean 2011, Geophys. Res. Lett. 38, L01706).
//! - Surface, [`Atmosphere::BeerLambert`]: the direct beam attenuated as exp(−τ·m),
//!   with τ the normal-incidence optical depth (≈ 0.3–1 in clear Martian skies, > 3 in
//!   dust storms) and m the air mass of a homogeneous spherical shell of scale height
//!   H = 11.1 km over a planet of radius R = 3389.5 km:
//!   m = √((R/H·μ)² + 2R/H + 1) − R/H·μ, μ = cos(zenith). This equals 1/μ for a high Sun
//!   and stays finite at the horizon. Diffuse sky light is not modelled, so this is a
//!   conservative (low) estimate for energy planning.
//! - [`Atmosphere::Baseline`]: TEMPEST's baseline — a constant peak beam flux, so a
//!   horizontal surface receives "peak flux × sin(elevation)".

/// Total solar irradiance at 1 AU, W/m² (Kopp & Lean 2011).
pub const SOLAR_CONSTANT_W_M2: f64 = 1361.0;
/// Atmospheric scale height used for the air mass, m.
const SCALE_HEIGHT_M: f64 = 11_100.0;

/// Flux at the top of Mars' atmosphere at `distance_au` from the Sun, W/m² normal to the beam.
pub fn top_of_atmosphere_w_m2(distance_au: f64) -> f64 {
    SOLAR_CONSTANT_W_M2 / (distance_au * distance_au)
}

/// Air mass of a homogeneous spherical shell atmosphere for a Sun at `elevation_deg`.
pub fn air_mass(elevation_deg: f64) -> f64 {
    shell_air_mass(elevation_deg, crate::Body::Mars.mean_radius_m(), SCALE_HEIGHT_M)
}

/// How the atmosphere turns top-of-atmosphere flux into surface flux.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Atmosphere {
    /// TEMPEST's baseline: the beam flux is `peak_w_m2` whenever the Sun is up.
    Baseline {
        /// Beam flux, W/m² normal to the beam.
        peak_w_m2: f64,
    },
    /// Beer–Lambert extinction of the direct beam with optical depth `tau` (Mars's
    /// shell: R = 3389.5 km, H = 11.1 km).
    BeerLambert {
        /// Normal-incidence optical depth, ≥ 0.
        tau: f64,
    },
    /// Beer–Lambert extinction in a spherical shell of any body's radius and scale
    /// height (the Earth: R = 6371 km, H = 8.43 km; see [`Atmosphere::for_body`]).
    Shell {
        /// Normal-incidence optical depth, ≥ 0.
        tau: f64,
        /// The body's mean radius, m.
        radius_m: f64,
        /// The atmosphere's scale height, m.
        scale_height_m: f64,
    },
    /// No atmosphere (the Moon): the top-of-atmosphere flux whenever the Sun is up.
    Airless,
}

/// The Earth's atmospheric scale height used for the air mass, m (the standard
/// atmosphere's density scale height near the ground).
pub const EARTH_SCALE_HEIGHT_M: f64 = 8_430.0;

impl Atmosphere {
    /// The surface flux model of `body` with optical depth `tau` (ignored on the Moon).
    pub fn for_body(body: crate::Body, tau: f64) -> Atmosphere {
        match body {
            crate::Body::Mars => Atmosphere::BeerLambert { tau },
            crate::Body::Moon => Atmosphere::Airless,
            crate::Body::Earth => Atmosphere::Shell {
                tau,
                radius_m: crate::Body::Earth.ellipsoid().mean_radius_m(),
                scale_height_m: EARTH_SCALE_HEIGHT_M,
            },
        }
    }
}

/// Air mass of a homogeneous spherical shell of scale height `h` over a body of radius
/// `r` for a Sun at `elevation_deg`.
pub fn shell_air_mass(elevation_deg: f64, r: f64, h: f64) -> f64 {
    let mu = elevation_deg.to_radians().sin();
    let k = r / h;
    ((k * mu).powi(2) + 2.0 * k + 1.0).sqrt() - k * mu
}

impl Atmosphere {
    /// Direct-beam flux at the surface, W/m² normal to the beam, for the Sun at
    /// `elevation_deg` and `distance_au`; 0 when the Sun is below the horizontal.
    pub fn beam_w_m2(&self, elevation_deg: f64, distance_au: f64) -> f64 {
        if elevation_deg <= 0.0 {
            return 0.0;
        }
        match *self {
            Atmosphere::Baseline { peak_w_m2 } => peak_w_m2,
            Atmosphere::BeerLambert { tau } => {
                top_of_atmosphere_w_m2(distance_au) * (-tau * air_mass(elevation_deg)).exp()
            }
            Atmosphere::Shell { tau, radius_m, scale_height_m } => {
                top_of_atmosphere_w_m2(distance_au)
                    * (-tau * shell_air_mass(elevation_deg, radius_m, scale_height_m)).exp()
            }
            Atmosphere::Airless => top_of_atmosphere_w_m2(distance_au),
        }
    }

    /// Flux on a horizontal surface, W/m².
    pub fn horizontal_w_m2(&self, elevation_deg: f64, distance_au: f64) -> f64 {
        self.beam_w_m2(elevation_deg, distance_au) * elevation_deg.to_radians().sin().max(0.0)
    }
}

/// A flat solar panel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Panel {
    /// Active area, m².
    pub area_m2: f64,
    /// Conversion efficiency, 0..1.
    pub efficiency: f64,
}

impl Panel {
    /// Electrical power, W, for a beam of `beam_w_m2` arriving from unit direction
    /// `sun_enu` on a panel whose unit normal is `normal_enu` (both local ENU). A panel
    /// lit from behind produces nothing.
    pub fn power_w(&self, beam_w_m2: f64, sun_enu: [f64; 3], normal_enu: [f64; 3]) -> f64 {
        let cos_i = sun_enu[0] * normal_enu[0] + sun_enu[1] * normal_enu[1] + sun_enu[2] * normal_enu[2];
        beam_w_m2 * cos_i.max(0.0) * self.area_m2 * self.efficiency
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flux_at_mars_mean_distance() {
        // 1361 / 1.523679² = 586.2 W/m², the textbook mean solar flux at Mars.
        assert!((top_of_atmosphere_w_m2(1.523_679) - 586.2).abs() < 0.1);
    }

    #[test]
    fn air_mass_is_secant_for_high_sun_and_finite_at_horizon() {
        assert!((air_mass(90.0) - 1.0).abs() < 1e-9);
        let sec60 = 1.0 / 30f64.to_radians().sin();
        assert!((air_mass(30.0) - sec60).abs() / sec60 < 1e-2);
        assert!(air_mass(30.0) < sec60);
        let m0 = air_mass(0.0);
        // √(2R/H + 1) at the horizon.
        assert!((m0 - (2.0 * 3_389_500.0 / 11_100.0 + 1.0f64).sqrt()).abs() < 1e-9);
    }

    #[test]
    fn baseline_gives_peak_times_sine_of_elevation() {
        let a = Atmosphere::Baseline { peak_w_m2: 500.0 };
        assert!((a.horizontal_w_m2(30.0, 1.5) - 250.0).abs() < 1e-9);
        assert_eq!(a.horizontal_w_m2(-1.0, 1.5), 0.0);
    }

    #[test]
    fn beer_lambert_attenuates_by_exp_minus_tau_at_zenith() {
        let a = Atmosphere::BeerLambert { tau: 0.5 };
        let expect = top_of_atmosphere_w_m2(1.5) * (-0.5f64).exp();
        assert!((a.beam_w_m2(90.0, 1.5) - expect).abs() < 1e-9);
    }

    #[test]
    fn the_moon_gets_the_solar_constant_and_the_earth_its_clear_sky_beam() {
        let moon = Atmosphere::for_body(crate::Body::Moon, 0.5);
        assert_eq!(moon.beam_w_m2(0.5, 1.0), SOLAR_CONSTANT_W_M2);
        assert_eq!(moon.beam_w_m2(-0.5, 1.0), 0.0);
        // Earth, τ = 0.1 broadband: exp(−0.1) of 1361 at the zenith; Kasten & Young's
        // relative air mass at 10° elevation is 5.60, the shell's 5.6 ± 0.1.
        let earth = Atmosphere::for_body(crate::Body::Earth, 0.1);
        assert!((earth.beam_w_m2(90.0, 1.0) - 1361.0 * (-0.1f64).exp()).abs() < 1e-9);
        let m10 = shell_air_mass(10.0, crate::Body::Earth.ellipsoid().mean_radius_m(), EARTH_SCALE_HEIGHT_M);
        assert!((m10 - 5.60).abs() < 0.1, "{m10}");
    }

    #[test]
    fn panel_power_follows_cosine_of_incidence() {
        let p = Panel { area_m2: 2.0, efficiency: 0.25 };
        let s = 60f64.to_radians();
        // Sun 30° above the horizon to the north; horizontal panel.
        let sun = [0.0, s.sin(), s.cos()];
        assert!((p.power_w(400.0, sun, [0.0, 0.0, 1.0]) - 400.0 * 0.5 * 0.5).abs() < 1e-9);
        assert_eq!(p.power_w(400.0, sun, [0.0, 0.0, -1.0]), 0.0);
    }
}
