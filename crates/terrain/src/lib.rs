//! areo-terrain: the ground a rover plans over.
//!
//! TEMPEST's world model and the ground the LSR-1 physics stands on:
//!
//! - [`Dem`]: elevations (f32) with a nodata mask, cell sizes dx and dy, and a
//!   [`Georef`] (a [`Projection`] on a reference [`Spheroid`]); bilinear
//!   [`Dem::height`] and [`Dem::gradient`] that return `None` off the map or on missing
//!   data; [`GeographicCrs`], the one sphere and name a map's latitudes are on. The [`Ground`] trait (height and normal) is implemented by `Dem` and by the
//!   [`analytic`] test terrains.
//! - Readers and writers: [`geotiff`] (int16/uint16/float32, strips or tiles,
//!   georeference tags, GDAL_NODATA), [`ascii`] (ESRI ASCII grid) and [`pds3`] (PDS3
//!   `.IMG` with attached or detached label: MOLA, HiRISE, CTX).
//! - [`synth`]: terrain synthesised from a description (craters, hills, ridges,
//!   mountain chains with passes, ditches, rocks, tilts, seeded fractal noise).
//! - [`fill`]: nodata holes filled by a sparse Laplace solve (faer), with a mask of
//!   the filled cells.
//! - [`slope`]: Horn slope, aspect and normals with separate dx and dy.
//! - [`shadow`]: cast shadows from the Sun through one door, a
//!   [`shadow::Shadows`] question (Sun, curvature, method) asked of a map in memory or
//!   of one read tile by tile, with planetary
//!   curvature: by default every cell decided by its own ray on the triangulated
//!   surface (the brute force's answer on every cell at every azimuth tested,
//!   `tests/shadow_methods.rs`), or by one of
//!   two cheaper, approximate traces whose error is stated; shadow maps.
//! - `reference` (with the `reference` feature, and in every test): the brute-force references the tests hold every method to: one ray
//!   per cell, no trace, no shortcuts; and parry3d ray casts.
//! - [`los`]: surface-to-surface line of sight and viewsheds by parry3d ray casts.
//! - [`tiles`]: shadow, slope and horizon maps of DTMs too large to hold, tile by tile
//!   with the halo the longest shadow needs (the whole map's answer), read through
//!   [`geotiff::Windows`] and written as tiled GeoTIFFs as tiles finish
//!   ([`geotiff::write_u8_tiled`], [`geotiff::write_u16_planes_tiled`]; BigTIFF past
//!   4 GB); planning regions cut from them ([`tiles::region`]).
//! - [`read`]: any of those formats, told by the file's extension; [`read_values`]: a
//!   raster of values that are not heights (a mask, a class map), read exactly.
//! - [`hillshade`]: a shaded-relief picture (RGB) with cast shadows.
//! - [`horizon`]: horizon maps (K sectors, 2 bytes per cell per sector), the Sun's
//!   elevation above each cell's ground plane, and line-of-sight map sequences.
//!
//! Conventions: metres; x east, y north; rows stored north to south; azimuth clockwise
//! from north. Only this crate does index↔metre arithmetic.
//!
//! ```
//! use areo_terrain::{Dem, shadow::{Curvature, Shadows, GridSunDirection}};
//!
//! // A 10 m wall on flat ground; the Sun 45° up in the east: a 10 m shadow to the west.
//! let dem = Dem::from_fn(40, 3, 1.0, 1.0, |x, _| if (20.0..21.0).contains(&x) { 10.0 } else { 0.0 }).unwrap();
//! let shadowed = Shadows::new(GridSunDirection::new(90.0, 45.0), Curvature::Flat).cast(&dem);
//! let row = 1 * 40;
//! assert!(shadowed[row + 15] && !shadowed[row + 5] && !shadowed[row + 30]);
//! ```
//!
//! Architecture invariant: areo-terrain depends on no other areo crate but areo-body (the
//! reference spheroids), so a DEM loader or a shadow map can be reused alone.

mod crs;
mod dem;
mod error;
mod projection;
mod ray_lines;

pub mod hillshade;

pub mod ascii;
#[cfg(feature = "fill")]
pub mod fill;
pub mod geotiff;
pub mod horizon;
pub mod input;
#[cfg(feature = "line-of-sight")]
pub mod los;
pub mod pds3;
#[cfg(any(test, feature = "reference"))]
pub mod reference;
pub mod shadow;
pub mod size;
pub mod slope;
pub mod synth;
pub mod tiles;
pub mod values;

pub use areo_body::Spheroid;

pub use crate::{
    crs::{GeographicCrs, lon180},
    dem::{Dem, Extent, Georef, Ground, POLAR_PROJECTION_LAT_DEG, analytic, unit_normal},
    error::{Error, Result},
    projection::Projection,
    size::Size,
    values::{Values, read_values},
};

/// A DEM file format, told by the file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum DemFormat {
    /// `.tif`/`.tiff`: GeoTIFF ([`geotiff`]), readable window by window.
    GeoTiff,
    /// `.asc`: ESRI ASCII grid ([`ascii`]).
    EsriAscii,
    /// `.img`/`.lbl`: PDS3 image with an attached or detached label ([`pds3`]).
    Pds3,
}

impl DemFormat {
    /// The format of `path` by its extension (case-insensitive); `None` for any other.
    pub fn of(path: &std::path::Path) -> Option<DemFormat> {
        let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
        match ext.as_str() {
            "tif" | "tiff" => Some(DemFormat::GeoTiff),
            "asc" => Some(DemFormat::EsriAscii),
            "img" | "lbl" => Some(DemFormat::Pds3),
            _ => None,
        }
    }
}

/// Reads a DEM by its file's extension ([`DemFormat::of`]). Any other name is
/// [`Error::UnknownFormat`].
pub fn read(path: &std::path::Path) -> Result<Dem> {
    // What the file is comes before what its name says: a FIFO or a device is refused
    // as such, whatever it is called.
    if path.exists() {
        input::check(path, input::RASTER_LIMIT).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    }
    match DemFormat::of(path) {
        Some(DemFormat::GeoTiff) => geotiff::read(path),
        Some(DemFormat::EsriAscii) => ascii::read(path),
        Some(DemFormat::Pds3) => pds3::read(path),
        None => Err(Error::UnknownFormat {
            path: path.to_path_buf(),
            message: "unknown DEM format: use .tif/.tiff (GeoTIFF), .asc (ESRI ASCII) or .img/.lbl (PDS3)".into(),
        }),
    }
}
