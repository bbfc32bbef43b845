//! areo-terrain: the ground a rover plans over.
//!
//! TEMPEST's world model and the ground the LSR-1 physics stands on:
//!
//! - [`Dem`]: elevations (f32) with a nodata mask, cell sizes dx and dy, and a
//!   [`Georef`] (a [`Projection`] on a reference [`Body`]); bilinear
//!   [`Dem::height`] and [`Dem::gradient`] that return `None` off the map or on missing
//!   data. The [`Ground`] trait (height and normal) is implemented by `Dem` and by the
//!   [`analytic`] test terrains.
//! - Readers and writers: [`geotiff`] (int16/uint16/float32, strips or tiles,
//!   georeference tags, GDAL_NODATA), [`ascii`] (ESRI ASCII grid) and [`pds3`] (PDS3
//!   `.IMG` with attached or detached label: MOLA, HiRISE, CTX).
//! - [`synth`]: terrain synthesised from a description (craters, hills, ridges,
//!   mountain chains with passes, ditches, rocks, tilts, seeded fractal noise).
//! - [`fill`]: nodata holes filled by a sparse Laplace solve (faer), with a mask of
//!   the filled cells.
//! - [`slope`]: Horn slope, aspect and normals with separate dx and dy.
//! - [`shadow`]: cast shadows from the Sun by one sweep per map, with planetary
//!   curvature: swept on the triangulated surface (the sweep lives in [`tin`], with its
//!   per-cell ray-cast reference; every cell as its own ray says at cardinal azimuths,
//!   99.89–99.996 % elsewhere on the Gale map), or a faster approximate sweep; shadow
//!   maps.
//! - [`los`]: surface-to-surface line of sight and viewsheds by parry3d ray casts.
//! - [`read`]: any of those formats, told by the file's extension.
//! - [`hillshade`]: a shaded-relief picture (RGB) with cast shadows.
//! - [`horizon`]: horizon maps (K sectors, 2 bytes per cell per sector), the Sun's
//!   elevation above each cell's ground plane, and line-of-sight map sequences.
//!
//! Conventions: metres; x east, y north; rows stored north to south; azimuth clockwise
//! from north. Only this crate does index↔metre arithmetic.
//!
//! ```
//! use areo_terrain::{Dem, shadow::{Curvature, cast_shadows}};
//!
//! // A 10 m wall on flat ground; the Sun 45° up in the east: a 10 m shadow to the west.
//! let dem = Dem::from_fn(40, 3, 1.0, 1.0, |x, _| if (20.0..21.0).contains(&x) { 10.0 } else { 0.0 }).unwrap();
//! let shadowed = cast_shadows(&dem, 90.0, 45.0, Curvature::Flat);
//! let row = 1 * 40;
//! assert!(shadowed[row + 15] && !shadowed[row + 5] && !shadowed[row + 30]);
//! ```
//!
//! Architecture invariant: areo-terrain depends on no other areo crate, so a DEM loader
//! or a shadow map can be reused alone.

mod body;
mod dem;
mod error;
mod lines;

pub mod hillshade;

pub mod ascii;
pub mod fill;
pub mod geotiff;
pub mod horizon;
pub mod los;
pub mod pds3;
pub mod shadow;
pub mod slope;
pub mod synth;
pub mod tin;

pub use crate::{
    body::{Body, Projection},
    dem::{Dem, Extent, Georef, Ground, analytic, unit_normal},
    error::{Error, Result},
};

/// Reads a DEM by its file's extension: `.tif`/`.tiff` GeoTIFF, `.asc` ESRI ASCII grid,
/// `.img`/`.lbl` PDS3 (case-insensitive). Any other name is [`Error::UnknownFormat`].
pub fn read(path: &std::path::Path) -> Result<Dem> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    match ext.as_str() {
        "tif" | "tiff" => geotiff::read(path),
        "asc" => ascii::read(path),
        "img" | "lbl" => pds3::read(path),
        _ => Err(Error::UnknownFormat {
            path: path.to_path_buf(),
            message: "unknown DEM format: use .tif/.tiff (GeoTIFF), .asc (ESRI ASCII) or .img/.lbl (PDS3)".into(),
        }),
    }
}
