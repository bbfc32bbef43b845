//! areo-ephemeris: Mars time, where the Sun and the Earth are in the sky of Mars, the
//! Moon or the Earth, and how much sunlight reaches a panel.
//!
//! TEMPEST used CSPICE for the Sun's position; this crate gives the same answers with
//! no data files, from the Mars24 algorithm (Allison & McEwen 2000; NASA GISS "Mars24
//! Sunclock — Algorithm and Worked Examples", 2018 constants) on top of `hifitime` for
//! UTC ↔ TT with leap seconds.
//!
//! - [`MarsTime`]: Julian dates, Mars Sol Date, Coordinated Mars Time; local mean and
//!   true solar time at a [`Site`]; [`utc_at_ltst`] inverts local true solar time.
//! - [`SolarGeometry`]: every step of the algorithm (mean anomaly, fictitious mean Sun,
//!   the seven perturbations, equation of centre, Ls, equation of time, sub-solar
//!   point, heliocentric distance) and the Sun's unit vector in the body-fixed and local
//!   east-north-up frames ([`TrueSunDirection`]).
//! - [`SunModel`]: time → Sun direction and distance, with [`Mars24`] as the built-in
//!   implementation; planners depend on the trait only.
//! - [`events`]: sunrise, solar noon and sunset; daylight intervals under a
//!   [`HorizonMask`]; Earth-above-horizon windows.
//! - [`earth`]: the direction from a Mars site to the Earth (Keplerian heliocentric
//!   orbits of both planets, IAU Mars rotation, light time).
//! - [`flux`]: top-of-atmosphere and surface solar flux, and panel power.
//! - [`Body`] (areo-body's, re-exported): Mars, the Moon or the Earth, with a
//!   [`SunModel`] each and the Earth in their skies ([`EarthFrom`]): [`moon`] (Meeus's truncated ELP-2000/82 and solar theory, the IAU
//!   lunar rotation; the Earth seen from the Moon; [`moon::SkyTable`], the same sky as
//!   Chebyshev series a day at a time) and [`terrestrial`] (the Sun at a
//!   WGS84 site, UTC as UT1), both on [`geocentric`].
//!
//! Angles at the API are degrees in fields whose names say so (`ls_deg`); latitudes
//! are planetocentric and longitudes east unless the name says otherwise; azimuth is
//! clockwise from north.
//!
//! ```
//! use areo_ephemeris::{parse_utc, Mars24, Site, SunModel};
//!
//! // Curiosity's landing: the Sun over Gale crater in the Martian afternoon.
//! let t = parse_utc("2012-08-06T05:17:57Z").unwrap();
//! let gale = Site::new(-4.5895, 137.4417).unwrap();
//! let sun = Mars24.sun(t).at_site(&gale);
//! assert!(sun.elevation_deg > 0.0 && sun.elevation_deg < 90.0);
//! ```
//!
//! Architecture invariant: areo-ephemeris depends on no other areo crate but areo-body
//! (the bodies' constants) and reads no files.

mod body;
mod error;
mod site;
mod sun;
mod time;

pub mod earth;
pub mod events;
pub mod flux;
pub mod geocentric;
pub mod moon;
pub mod terrestrial;

pub use crate::{
    body::{Body, EarthFrom, EarthView},
    error::{Error, Result},
    events::HorizonMask,
    site::Site,
    sun::{Mars24, SolarGeometry, SunModel, SunState, TrueSunDirection},
    time::{MarsTime, SOL_S, VALID_SOLS, VALID_YEARS, format_utc, local_sol, parse_utc, utc_at_ltst},
};
