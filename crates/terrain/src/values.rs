//! Rasters of values that are not heights — a no-go mask, a terrain-class map — read
//! exactly: a sample is the number the file holds (a 32-bit integer of 4e9, a float of
//! 1e30, a class id of 2.000000001), never clipped to what heights may be nor rounded
//! to f32, and missing only where the file says (NaN or its no-data).

use std::path::Path;

use crate::dem::Dem;
use crate::error::{Error, Result};
use crate::{DemFormat, ascii, geotiff};

/// A raster of values on a grid.
#[derive(Debug, Clone)]
pub struct Values {
    /// The grid: its cells, extent and georeference (its heights are 0 where a value is
    /// given and missing where none is; the values are [`Values::at`]).
    pub grid: Dem,
    values: Vec<f64>,
}

impl Values {
    /// Values on `grid`, row-major (row 0 north), NaN where missing.
    pub fn new(grid: Dem, values: Vec<f64>) -> Result<Values> {
        if values.len() != grid.cols() * grid.rows() {
            return Err(Error::BadGrid(format!("{} values for {} x {} cells", values.len(), grid.cols(), grid.rows())));
        }
        Ok(Values { grid, values })
    }

    /// The value at (`col`, `row`), or `None` where the raster has none.
    pub fn at(&self, col: usize, row: usize) -> Option<f64> {
        let v = *self.values.get(row * self.grid.cols() + col)?;
        (!v.is_nan() && col < self.grid.cols()).then_some(v)
    }
}

/// Reads a raster of values by its file's extension (GeoTIFF or ESRI ASCII grid).
pub fn read_values(path: &Path) -> Result<Values> {
    if path.exists() {
        crate::input::check(path, crate::input::RASTER_LIMIT)
            .map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    }
    match DemFormat::of(path) {
        Some(DemFormat::GeoTiff) => geotiff::read_values(path),
        Some(DemFormat::EsriAscii) => ascii::read_values(path),
        _ => Err(Error::UnknownFormat {
            path: path.to_path_buf(),
            message: "unknown raster format for values (a mask, a class map): use .tif/.tiff (GeoTIFF) or .asc \
                      (ESRI ASCII)"
                .into(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_beyond_any_height_and_fractions_are_read_as_written() {
        let dir = std::env::temp_dir().join(format!("areo-values-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let asc = dir.join("v.asc");
        std::fs::write(
            &asc,
            "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 10\nNODATA_value -1\n4e9 1e30 2.000000001\n-1 0 -3e38\n",
        )
        .unwrap();
        let v = read_values(&asc).unwrap();
        assert_eq!((v.at(0, 0), v.at(1, 0), v.at(2, 0)), (Some(4e9), Some(1e30), Some(2.000000001)));
        assert_eq!((v.at(0, 1), v.at(1, 1), v.at(2, 1)), (None, Some(0.0), Some(-3e38)));
        assert_eq!(v.at(3, 0), None, "off the grid");
        // As heights the same file is refused: 4e9 m is no height.
        assert!(crate::read(&asc).is_err());
        // GeoTIFFs of f64 and of u32 samples keep them exactly.
        let grid = geotiff::Grid::of(&Dem::new(2, 1, 1.0, 1.0, 0.0, 1.0, vec![0.0, 0.0]).unwrap());
        let tif = dir.join("v.tif");
        geotiff::write_f64_on(&grid, &[4_000_000_001.0, 2.000000001], &tif).unwrap();
        let v = read_values(&tif).unwrap();
        assert_eq!((v.at(0, 0), v.at(1, 0)), (Some(4_000_000_001.0), Some(2.000000001)));
        assert_eq!(v.grid.georef(), &grid.georef);
        let u32_tif = dir.join("u.tif");
        {
            let file = std::fs::File::create(&u32_tif).unwrap();
            let mut enc = tiff::encoder::TiffEncoder::new(file).unwrap();
            enc.write_image::<tiff::encoder::colortype::Gray32>(2, 1, &[4_000_000_000u32, 7]).unwrap();
        }
        let v = read_values(&u32_tif).unwrap();
        assert_eq!((v.at(0, 0), v.at(1, 0)), (Some(4e9), Some(7.0)));
        assert!(crate::read(&u32_tif).is_ok_and(|d| d.z(0, 0).is_none()), "as heights 4e9 is no height");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
