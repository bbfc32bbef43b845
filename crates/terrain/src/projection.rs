//! Map projections on a reference spheroid (areo-body's [`Spheroid`]): every DEM cell
//! knows its latitude and longitude.

use areo_body::Spheroid;
use serde::{Deserialize, Serialize};

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

/// How far a grid in longitude and latitude may stray from true east–west scale, over
/// its rows, when it is read as equirectangular at its middle latitude: 1 % (the MOLA
/// MEGDR window of Gale crater, 7° tall, strays 0.8 %; a polar map strays without bound).
pub const GEOGRAPHIC_MAX_SCALE_ERROR: f64 = 0.01;

/// A grid in longitude and latitude — `cols` × `rows` cells of `dlon_deg` × `dlat_deg`
/// from its north-west corner (`lon_w_deg`, `lat_n_deg`) — as the equirectangular grid
/// it is (x = R·(λ − λ0)·cos φts, y = R·φ, linear in λ and φ), with φts its middle
/// latitude and λ0 its middle longitude: the same cells in metres, not resampled.
/// Returns (dx, dy, x0, y_top) in metres and the projection; a grid whose rows' scale
/// would stray more than [`GEOGRAPHIC_MAX_SCALE_ERROR`] is refused with what to do.
pub(crate) fn equirectangular_from_degrees(
    (cols, rows): (usize, usize),
    (lon_w_deg, lat_n_deg): (f64, f64),
    (dlon_deg, dlat_deg): (f64, f64),
    surface: &Spheroid,
) -> std::result::Result<([f64; 4], Projection), String> {
    let (lon_w, lat_n) = (lon_w_deg, lat_n_deg);
    let (lon_e, lat_s) = (lon_w + cols as f64 * dlon_deg, lat_n - rows as f64 * dlat_deg);
    if !(lat_n <= 90.0 + 1e-9 && lat_s >= -90.0 - 1e-9 && lon_e - lon_w <= 360.0 + 1e-9) {
        return Err(format!(
            "geographic grid from {lat_s}° to {lat_n}° latitude and {lon_w}° to {lon_e}° longitude: \
             latitudes must lie within ±90° and longitudes span at most 360°"
        ));
    }
    let lat_ts = 0.5 * (lat_n + lat_s);
    let scale = rows_at_one_scale("geographic grid", lat_n, lat_s)?;
    let lon0 = 0.5 * (lon_w + lon_e);
    let metres_per_degree = surface.equatorial_radius_m * 1f64.to_radians();
    Ok((
        [
            dlon_deg * metres_per_degree * scale,
            dlat_deg * metres_per_degree,
            (lon_w - lon0) * metres_per_degree * scale,
            lat_n * metres_per_degree,
        ],
        Projection::Equirectangular { lat_ts_deg: lat_ts, lon0_deg: lon0 },
    ))
}

/// The east–west scale, cos φ, at the middle of the latitudes `lat_n`..`lat_s`
/// (degrees), if every row's true scale lies within [`GEOGRAPHIC_MAX_SCALE_ERROR`] of
/// it; else what to do, naming `what`.
fn rows_at_one_scale(what: &str, lat_n: f64, lat_s: f64) -> std::result::Result<f64, String> {
    let lat_ts = 0.5 * (lat_n + lat_s);
    let widest = if lat_s <= 0.0 && lat_n >= 0.0 { 1.0 } else { lat_n.abs().min(lat_s.abs()).to_radians().cos() };
    let narrowest = lat_n.abs().max(lat_s.abs()).min(90.0).to_radians().cos();
    let scale = lat_ts.to_radians().cos();
    let error = (widest / scale - 1.0).max(1.0 - narrowest / scale);
    if error > GEOGRAPHIC_MAX_SCALE_ERROR {
        return Err(format!(
            "{what} from {lat_s:.4}° to {lat_n:.4}° latitude: read as equirectangular at {lat_ts:.4}° its \
             east–west scale would be off by up to {:.1} % (allowed {:.0} %); reproject it first, e.g. \
             `gdalwarp -t_srs '+proj=stere +lat_0=-90 +R=<radius>' in.tif out.tif` near a pole or \
             `+proj=eqc +lat_ts=<middle latitude> +R=<radius>` for a long north–south strip",
            100.0 * error,
            100.0 * GEOGRAPHIC_MAX_SCALE_ERROR
        ));
    }
    Ok(scale)
}

/// An equirectangular grid — `cols` × `rows` cells of `dx` × `dy` map metres from its
/// north-west corner (`x0`, `y_top`), standard parallel `lat_ts_deg` — at true scale.
/// Its map metres are ground metres east–west only at the standard parallel: a global
/// mosaic's (φts = 0, as MOLA MEGDR tiles and the HRSC–MOLA blend come) stretches a
/// map at 40° by 31 % and at 68° (Phoenix) by 2.7×, and slopes, shadows and drives
/// would follow. Where that stretch exceeds [`GEOGRAPHIC_MAX_SCALE_ERROR`], the same
/// cells are relabelled at the grid's middle latitude (x scaled by cos φmid / cos φts:
/// the same projection with another standard parallel, not resampled); within it the
/// grid stays as written, so outputs keep the input's CRS. A grid too tall for one
/// scale is refused with what to do. Returns (dx, dy, x0, y_top) and the projection.
pub(crate) fn equirectangular_at_true_scale(
    rows: usize,
    [dx, dy, x0, y_top]: [f64; 4],
    (lat_ts_deg, lon0_deg): (f64, f64),
    surface: &Spheroid,
) -> std::result::Result<([f64; 4], Projection), String> {
    let as_written = ([dx, dy, x0, y_top], Projection::Equirectangular { lat_ts_deg, lon0_deg });
    let r = surface.equatorial_radius_m;
    let (lat_n, lat_s) = ((y_top / r).to_degrees(), ((y_top - rows as f64 * dy) / r).to_degrees());
    if !(lat_n <= 90.0 + 1e-9 && lat_s >= -90.0 - 1e-9) {
        return Err(format!(
            "equirectangular grid from {lat_s}° to {lat_n}° latitude (y / R): latitudes must lie within ±90°"
        ));
    }
    let stretch = (0.5 * (lat_n + lat_s)).to_radians().cos() / lat_ts_deg.to_radians().cos();
    if (stretch - 1.0).abs() <= GEOGRAPHIC_MAX_SCALE_ERROR {
        return Ok(as_written);
    }
    let what = format!("equirectangular grid with its standard parallel at {lat_ts_deg}°");
    rows_at_one_scale(&what, lat_n, lat_s)?;
    let lat_mid = 0.5 * (lat_n + lat_s);
    Ok(([dx * stretch, dy, x0 * stretch, y_top], Projection::Equirectangular { lat_ts_deg: lat_mid, lon0_deg }))
}

impl Projection {
    /// The same projection with its central meridian in −180..180, as every longitude
    /// a run writes is.
    pub(crate) fn written(self) -> Projection {
        match self {
            Projection::Equirectangular { lat_ts_deg, lon0_deg } => {
                Projection::Equirectangular { lat_ts_deg, lon0_deg: crate::lon180(lon0_deg) }
            }
            Projection::PolarStereographic { north, lon0_deg } => {
                Projection::PolarStereographic { north, lon0_deg: crate::lon180(lon0_deg) }
            }
            Projection::Local => Projection::Local,
        }
    }

    /// Where true north points on the grid at east longitude `lon_east_deg`: the
    /// clockwise angle from the grid's north (its +y axis, up in the image) to the
    /// meridian's north, degrees in (−180, 180]. A direction of true azimuth A has grid
    /// azimuth A + this. Zero on a local frame and on an equirectangular map, whose
    /// meridians are its columns; on a polar stereographic map the meridians fan out
    /// from the pole, so it is λ − λ0 in the south and λ0 − λ in the north — a LOLA
    /// polar map (λ0 = 0) turns the Sun of a site at 90°E by a quarter turn.
    pub fn true_north_on_grid_deg(&self, lon_east_deg: f64) -> f64 {
        let turn = match *self {
            Projection::Local | Projection::Equirectangular { .. } => return 0.0,
            Projection::PolarStereographic { north: false, lon0_deg } => lon_east_deg - lon0_deg,
            Projection::PolarStereographic { north: true, lon0_deg } => lon0_deg - lon_east_deg,
        };
        180.0 - (180.0 - turn).rem_euclid(360.0)
    }

    /// The grid azimuth (degrees clockwise from the grid's north, in [0, 360)) of a
    /// direction of true azimuth `true_azimuth_deg` seen from east longitude
    /// `lon_east_deg` ([`Projection::true_north_on_grid_deg`]).
    pub fn grid_azimuth_deg(&self, true_azimuth_deg: f64, lon_east_deg: f64) -> f64 {
        (true_azimuth_deg + self.true_north_on_grid_deg(lon_east_deg)).rem_euclid(360.0)
    }

    /// Planetocentric latitude and east longitude (degrees) of map point (x, y), m.
    pub fn to_geographic(&self, body: &Spheroid, x: f64, y: f64) -> Option<(f64, f64)> {
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
    pub fn from_geographic(&self, body: &Spheroid, lat_deg: f64, lon_east_deg: f64) -> Option<(f64, f64)> {
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
    fn true_north_on_a_polar_grid_is_the_meridian_through_the_point() {
        // Against the projection itself: a small step north along the meridian, read
        // as a grid direction, points where the offset says.
        let body = Spheroid::MOON;
        for (proj, lat) in [
            (Projection::PolarStereographic { north: false, lon0_deg: 0.0 }, -89.3),
            (Projection::PolarStereographic { north: true, lon0_deg: 40.0 }, 85.0),
            (Projection::Equirectangular { lat_ts_deg: -5.0, lon0_deg: 137.0 }, -5.0),
        ] {
            for lon in [0.0, 45.0, 90.0, 137.5, 180.0, 222.7, 300.0] {
                let (x0, y0) = proj.from_geographic(&body, lat, lon).unwrap();
                let (x1, y1) = proj.from_geographic(&body, lat + 1e-4, lon).unwrap();
                let grid_az = (x1 - x0).atan2(y1 - y0).to_degrees();
                let offset = proj.true_north_on_grid_deg(lon);
                let gap = (grid_az - offset + 540.0).rem_euclid(360.0) - 180.0;
                assert!(gap.abs() < 1e-6, "{proj:?} at {lon}°E: grid azimuth {grid_az}, offset {offset}");
                assert!(offset > -180.0 && offset <= 180.0);
            }
        }
        assert_eq!(Projection::Local.true_north_on_grid_deg(90.0), 0.0);
        // Azimuths wrap into [0, 360): 350° true at 30° E on a λ0 = 0 south polar grid.
        let south = Projection::PolarStereographic { north: false, lon0_deg: 0.0 };
        assert!((south.grid_azimuth_deg(350.0, 30.0) - 20.0).abs() < 1e-12);
        assert!((south.grid_azimuth_deg(10.0, 330.0) - 340.0).abs() < 1e-12);
    }

    #[test]
    fn projections_round_trip_and_match_mola_spacing() {
        let body = Spheroid::MARS_MOLA_SPHERE;
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
