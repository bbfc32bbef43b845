//! GeoTIFF DEMs through the `tiff` crate: int16, uint16, int32, float32 and float64
//! samples, strips or tiles, uncompressed or compressed as GDAL writes them (LZW,
//! deflate with either predictor, PackBits, Zstandard); georeference from ModelPixelScale, ModelTiepoint and the
//! GeoKey directory; nodata from the GDAL_NODATA tag. Writes float32 elevation and
//! uint8 mask/shadow GeoTIFFs with the same georeference tags.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, Write};
use std::path::Path;

use tiff::decoder::{Decoder, DecodingResult, ifd::Value};
use tiff::encoder::{TiffEncoder, colortype};
use tiff::tags::Tag;

use crate::dem::{Dem, Georef};
use crate::error::{Error, Result};
use crate::projection::Projection;
use areo_body::Spheroid;

/// GeoKey ids used here (GeoTIFF 1.1, OGC 19-008r4).
mod cog;
mod palette;
mod tiled;

pub use cog::{Band, COG_TILE, write_cog_f32, write_cog_u8, write_cog_u8_at};
pub use tiled::{BIGTIFF_FROM_BYTES, TileSink, write_f32_tiled, write_u8_tiled, write_u16_planes_tiled};

mod key {
    pub(super) const MODEL_TYPE: u16 = 1024;
    /// GTModelTypeGeoKey's value for a grid in longitude and latitude.
    pub(super) const MODEL_PROJECTED: u16 = 1;
    pub(super) const MODEL_GEOGRAPHIC: u16 = 2;
    pub(super) const RASTER_TYPE: u16 = 1025;
    pub(super) const GT_CITATION: u16 = 1026;
    pub(super) const GEOGRAPHIC_TYPE: u16 = 2048;
    pub(super) const GEOG_CITATION: u16 = 2049;
    pub(super) const GEODETIC_DATUM: u16 = 2050;
    pub(super) const GEOG_ANGULAR_UNITS: u16 = 2054;
    pub(super) const ELLIPSOID: u16 = 2056;
    pub(super) const SEMI_MAJOR: u16 = 2057;
    pub(super) const SEMI_MINOR: u16 = 2058;
    pub(super) const INV_FLATTENING: u16 = 2059;
    pub(super) const PROJECTED_CS: u16 = 3072;
    pub(super) const PROJECTION: u16 = 3074;
    pub(super) const PROJ_LINEAR_UNITS: u16 = 3076;
    pub(super) const COORD_TRANS: u16 = 3075;
    pub(super) const STD_PARALLEL_1: u16 = 3078;
    pub(super) const NAT_ORIGIN_LONG: u16 = 3080;
    pub(super) const NAT_ORIGIN_LAT: u16 = 3081;
    pub(super) const CENTER_LONG: u16 = 3088;
    pub(super) const STRAIGHT_VERT_POLE_LONG: u16 = 3095;
    pub(super) const CT_EQUIRECTANGULAR: u16 = 17;
    pub(super) const CT_POLAR_STEREOGRAPHIC: u16 = 15;
    pub(super) const USER_DEFINED: u16 = 32767;
    /// EPSG unit codes: the metre and the degree.
    pub(super) const METRE: u16 = 9001;
    pub(super) const DEGREE: u16 = 9102;
}

/// Reads a GeoTIFF DEM.
pub fn read(path: &Path) -> Result<Dem> {
    let file = crate::input::open(path, crate::input::RASTER_LIMIT)
        .map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    read_from(BufReader::new(file), path)
}

/// Reads a GeoTIFF DEM from any reader; `path` labels errors.
pub fn read_from<R: Read + Seek>(reader: R, path: &Path) -> Result<Dem> {
    let tiff_err = |e: tiff::TiffError| Error::format(path, format!("not a readable TIFF: {e}"));
    let mut dec = Decoder::new(reader).map_err(tiff_err)?;
    let header = Header::parse(&mut dec, path)?;
    let image = dec.read_image().map_err(tiff_err)?;
    let z = samples(image, path)?;
    header.dem(0, 0, header.cols, header.rows, z, path)
}

/// Reads a GeoTIFF of values that are not heights (a mask, a class map) exactly, as
/// [`crate::Values`]: every sample as the f64 it is, of any magnitude; missing only
/// where it is NaN or the file's no-data.
pub fn read_values(path: &Path) -> Result<crate::Values> {
    let mut bytes = crate::input::read(path, crate::input::RASTER_LIMIT)
        .map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    palette::as_codes(&mut bytes);
    let tiff_err = |e: tiff::TiffError| Error::format(path, format!("not a readable TIFF: {e}"));
    let mut dec = Decoder::new(std::io::Cursor::new(bytes)).map_err(tiff_err)?;
    let header = Header::parse(&mut dec, path)?;
    let values: Vec<f64> = match dec.read_image().map_err(tiff_err)? {
        DecodingResult::I16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F64(v) => v,
        other => samples(other, path)?.into_iter().map(f64::from).collect(),
    };
    let nodata = header.nodata;
    let missing = |v: f64| v.is_nan() || nodata.is_some_and(|nd| v == nd || (nd.is_nan() && v.is_nan()));
    let values: Vec<f64> = values.into_iter().map(|v| if missing(v) { f64::NAN } else { v }).collect();
    let skeleton: Vec<f32> = values.iter().map(|v| if v.is_nan() { f32::NAN } else { 0.0 }).collect();
    let grid = header.dem(0, 0, header.cols, header.rows, skeleton, path)?;
    crate::Values::new(grid, values)
}

/// What a GeoTIFF says of its grid: size, cells, georeference and nodata.
#[derive(Debug, Clone)]
struct Header {
    cols: usize,
    rows: usize,
    dx: f64,
    dy: f64,
    x0: f64,
    y_top: f64,
    nodata: Option<f64>,
    georef: Georef,
    /// A projected CRS areo does not read (the map is then a local frame), described.
    crs_not_read: Option<String>,
}

/// A projected CRS whose projection areo does not read, in words: its EPSG code if it
/// has one and the coordinate transformation's name.
fn describe_unread(geokeys: &GeoKeys) -> String {
    let name = match geokeys.short(key::COORD_TRANS) {
        Some(1) => "transverse Mercator".to_string(),
        Some(7) => "Mercator".to_string(),
        Some(8) => "Lambert conformal conic".to_string(),
        Some(10) => "Lambert azimuthal equal-area".to_string(),
        Some(11) => "Albers equal-area".to_string(),
        Some(12) => "azimuthal equidistant".to_string(),
        Some(14) => "stereographic".to_string(),
        Some(16) => "oblique stereographic".to_string(),
        Some(24) => "sinusoidal".to_string(),
        Some(ct) => format!("coordinate transformation {ct}"),
        None => match geokeys.short(key::PROJECTED_CS) {
            Some(code) if (32601..=32660).contains(&code) => format!("UTM zone {} N", code - 32600),
            Some(code) if (32701..=32760).contains(&code) => format!("UTM zone {} S", code - 32700),
            _ => "a projection".to_string(),
        },
    };
    match geokeys.short(key::PROJECTED_CS).filter(|&c| (1..key::USER_DEFINED).contains(&c)) {
        Some(code) => format!("EPSG:{code}, {name}"),
        None => name,
    }
}

/// Refuses, before decoding, a TIFF whose samples or compression areo does not read,
/// saying what it reads and how to rewrite the file. Shared by the whole-map and the
/// window readers, so they refuse the same files.
fn check_readable<R: Read + Seek>(dec: &mut Decoder<R>, path: &Path) -> Result<()> {
    let bad = |m: String| Error::format(path, m);
    let tiff_err = |e: tiff::TiffError| Error::format(path, format!("not a readable TIFF: {e}"));
    // Sample types areo reads, refused here so the whole-map and the window readers
    // refuse the same files.
    let bits = dec.find_tag_unsigned_vec::<u16>(Tag::BitsPerSample).map_err(tiff_err)?.unwrap_or_else(|| vec![1]);
    let format = dec.find_tag_unsigned_vec::<u16>(Tag::SampleFormat).map_err(tiff_err)?.unwrap_or_else(|| vec![1]);
    let (b, f) = (bits.first().copied().unwrap_or(1), format.first().copied().unwrap_or(1));
    let readable = matches!((f, b), (1 | 2, 8 | 16 | 32) | (3, 32 | 64));
    if !readable {
        let kind = match f {
            1 => "unsigned integer",
            2 => "signed integer",
            3 => "floating point",
            _ => "unknown",
        };
        return Err(bad(format!(
            "{b}-bit {kind} samples (BitsPerSample {b}, SampleFormat {f}): areo reads 8-, 16- and 32-bit integers and 32- and 64-bit floats"
        )));
    }
    // The schemes the decoder has, named before decoding: its own message for the
    // rest ("Unknown(34887) is unsupported", or "corrupt" for JPEG) says neither what
    // the file is nor what to do.
    let compression = dec.find_tag_unsigned::<u16>(Tag::Compression).map_err(tiff_err)?.unwrap_or(1);
    if !matches!(compression, 1 | 5 | 8 | 32946 | 32773 | 50000) {
        let name = match compression {
            2..=4 => "CCITT fax",
            6 | 7 => "JPEG",
            34712 => "JPEG 2000",
            34887 => "LERC",
            34925 => "LZMA",
            50001 => "WebP",
            50002 => "JPEG XL",
            _ => "an unknown scheme",
        };
        return Err(bad(format!(
            "compression {compression} ({name}): areo reads uncompressed, LZW, deflate, PackBits and Zstandard \
             GeoTIFFs; rewrite it, e.g. `gdal_translate -co COMPRESS=DEFLATE in.tif out.tif`"
        )));
    }
    Ok(())
}

impl Header {
    fn parse<R: Read + Seek>(dec: &mut Decoder<R>, path: &Path) -> Result<Header> {
        let bad = |m: String| Error::format(path, m);
        let tiff_err = |e: tiff::TiffError| Error::format(path, format!("not a readable TIFF: {e}"));
        let (w, h) = dec.dimensions().map_err(tiff_err)?;
        let samples = dec.find_tag_unsigned::<u16>(Tag::SamplesPerPixel).map_err(tiff_err)?.unwrap_or(1);
        if samples != 1 {
            return Err(bad(format!("{samples} samples per pixel; a DEM has one band")));
        }
        check_readable(dec, path)?;
        if dec.find_tag(Tag::Unknown(MODEL_TRANSFORMATION)).map_err(tiff_err)?.is_some() {
            return Err(bad(
                "ModelTransformationTag (a rotated or sheared grid) is not read: warp the DEM to a north-up grid first (gdalwarp)"
                    .into(),
            ));
        }
        let scale = f64_vec(dec, Tag::ModelPixelScaleTag).map_err(tiff_err)?;
        let tie = f64_vec(dec, Tag::ModelTiepointTag).map_err(tiff_err)?;
        match (&scale, &tie) {
            (None, None) => {}
            (Some(s), Some(t)) if s.len() >= 2 && t.len() >= 6 => {
                if let Some(v) = s[..2].iter().chain(&t[..6]).find(|v| !v.is_finite()) {
                    return Err(bad(format!("ModelPixelScale / ModelTiepoint value {v}: must be finite")));
                }
            }
            (s, t) => {
                return Err(bad(format!(
                    "ModelPixelScale of {} values and ModelTiepoint of {} values: need 2+ and 6+ (or neither, for 1 m cells)",
                    s.as_ref().map_or(0, Vec::len),
                    t.as_ref().map_or(0, Vec::len)
                )));
            }
        }
        let keys = dec.find_tag_unsigned_vec::<u16>(Tag::GeoKeyDirectoryTag).map_err(tiff_err)?.unwrap_or_default();
        let doubles = f64_vec(dec, Tag::GeoDoubleParamsTag).map_err(tiff_err)?.unwrap_or_default();
        let geokeys = GeoKeys::parse(&keys, &doubles);
        let (dx, dy, x0, y_top) = match (scale, tie) {
            (Some(s), Some(t)) if s.len() >= 2 && t.len() >= 6 => {
                let (dx, dy) = (s[0], s[1]);
                // Tiepoint (i, j) ↔ (x, y): the raster's origin follows. PixelIsPoint
                // rasters tie pixel centres, so shift by half a pixel to reach the corner.
                let half = if geokeys.short(key::RASTER_TYPE) == Some(2) { 0.5 } else { 0.0 };
                (dx, dy, t[3] - (t[0] + half) * dx, t[4] + (t[1] + half) * dy)
            }
            _ => (1.0, 1.0, 0.0, h as f64),
        };
        if !(dx > 0.0 && dy > 0.0 && dx.is_finite() && dy.is_finite()) {
            return Err(bad(format!("ModelPixelScale {dx} x {dy}: cell sizes must be positive")));
        }
        let nodata: Option<f64> = match dec.find_tag(Tag::GdalNodata).map_err(tiff_err)? {
            Some(Value::Ascii(s)) => {
                let t = s.trim_matches(char::from(0)).trim();
                Some(t.parse::<f64>().map_err(|_| bad(format!("GDAL_NODATA {t:?} is not a number")))?)
            }
            _ => None,
        };
        let georef = geokeys.georef().map_err(bad)?;
        let crs_not_read = (geokeys.short(key::MODEL_TYPE) == Some(key::MODEL_PROJECTED)
            && georef.projection == Projection::Local)
            .then(|| describe_unread(&geokeys));
        let header = Header { cols: w as usize, rows: h as usize, dx, dy, x0, y_top, nodata, georef, crs_not_read };
        if let Some(u) = geokeys.short(key::PROJ_LINEAR_UNITS).filter(|&u| u != key::METRE && u != key::USER_DEFINED) {
            return Err(bad(format!(
                "projected coordinates in linear unit {u} (ProjLinearUnitsGeoKey): areo reads metres (9001); \
                 rewrite it, e.g. `gdalwarp -t_srs '<the same CRS with +units=m>' in.tif out.tif`"
            )));
        }
        if geokeys.short(key::MODEL_TYPE) == Some(key::MODEL_GEOGRAPHIC) {
            return header.geographic_as_equirectangular(geokeys.short(key::GEOG_ANGULAR_UNITS)).map_err(bad);
        }
        header.at_true_scale().map_err(bad)
    }

    /// An equirectangular map at true scale where its standard parallel is far from it
    /// ([`crate::projection::equirectangular_at_true_scale`]); any other as it is.
    fn at_true_scale(self) -> std::result::Result<Header, String> {
        let Projection::Equirectangular { lat_ts_deg, lon0_deg } = self.georef.projection else { return Ok(self) };
        let ([dx, dy, x0, y_top], projection) = crate::projection::equirectangular_at_true_scale(
            self.rows,
            [self.dx, self.dy, self.x0, self.y_top],
            (lat_ts_deg, lon0_deg),
            &self.georef.surface,
        )?;
        Ok(Header { dx, dy, x0, y_top, georef: Georef { projection, surface: self.georef.surface }, ..self })
    }

    /// A grid in longitude and latitude (GTModelTypeGeoKey 2: MOLA and LOLA products,
    /// many global mosaics) as the equirectangular grid it is
    /// ([`crate::projection::equirectangular_from_degrees`]); before, its degrees were
    /// read as metres (cells of 0.008 m).
    fn geographic_as_equirectangular(self, units: Option<u16>) -> std::result::Result<Header, String> {
        if let Some(u) = units.filter(|&u| u != key::DEGREE && u != key::USER_DEFINED) {
            return Err(format!(
                "geographic coordinates in angular unit {u} (GeogAngularUnitsGeoKey): areo reads degrees (9102)"
            ));
        }
        let ([dx, dy, x0, y_top], projection) = crate::projection::equirectangular_from_degrees(
            (self.cols, self.rows),
            (self.x0, self.y_top),
            (self.dx, self.dy),
            &self.georef.surface,
        )?;
        Ok(Header { dx, dy, x0, y_top, georef: Georef { projection, surface: self.georef.surface }, ..self })
    }

    /// The DEM of the window (`col0`, `row0`, `cols` × `rows`) from its samples.
    fn dem(&self, col0: usize, row0: usize, cols: usize, rows: usize, z: Vec<f32>, path: &Path) -> Result<Dem> {
        let bad = |m: String| Error::format(path, m);
        if z.len() != cols * rows {
            return Err(bad(format!("{} samples for {cols} x {rows} pixels", z.len())));
        }
        let nodata = self.nodata;
        let valid: Vec<bool> = z
            .iter()
            .map(|&v| {
                v.is_finite()
                    && v.abs() <= MAX_ABS_ELEVATION_M
                    && nodata.is_none_or(|nd| !(f64::from(v) == nd || (nd.is_nan() && v.is_nan())))
            })
            .collect();
        let z = z.into_iter().zip(&valid).map(|(v, ok)| if *ok { v } else { f32::NAN }).collect();
        let (x0, y_top) = (self.x0 + col0 as f64 * self.dx, self.y_top - row0 as f64 * self.dy);
        Dem::new(cols, rows, self.dx, self.dy, x0, y_top, z)
            .and_then(|d| d.with_mask(valid))
            .map(|d| d.with_georef(self.georef))
            .map_err(|e| bad(e.to_string()))
    }
}

pub use crate::projection::GEOGRAPHIC_MAX_SCALE_ERROR;

/// ModelTransformationTag, which areo refuses (it only reads north-up grids).
const MODEL_TRANSFORMATION: u16 = 34264;

/// Elevations beyond this many metres are fill values (HiRISE's −3.4028227e38, say),
/// not heights: no body has relief of 10 000 km.
const MAX_ABS_ELEVATION_M: f32 = 1e7;

/// Decoded samples as f32 elevations.
fn samples(image: DecodingResult, path: &Path) -> Result<Vec<f32>> {
    Ok(match image {
        DecodingResult::I16(v) => v.into_iter().map(f32::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f32::from).collect(),
        DecodingResult::I32(v) => v.into_iter().map(|x| x as f32).collect(),
        DecodingResult::U32(v) => v.into_iter().map(|x| x as f32).collect(),
        DecodingResult::I8(v) => v.into_iter().map(f32::from).collect(),
        DecodingResult::U8(v) => v.into_iter().map(f32::from).collect(),
        DecodingResult::F32(v) => v,
        DecodingResult::F64(v) => v.into_iter().map(|x| x as f32).collect(),
        _ => {
            return Err(Error::format(
                path,
                "64-bit integer or other unusual samples: areo reads 8-, 16- and 32-bit integers and 32- and 64-bit floats",
            ));
        }
    })
}

impl std::fmt::Debug for Windows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Windows")
            .field("path", &self.path)
            .field("size", &self.size())
            .field("chunk", &self.chunk)
            .finish()
    }
}

/// A GeoTIFF read a window at a time: only the strips or tiles a window touches are
/// decoded, and the decoded ones are kept up to a byte budget (least recently used
/// first out), so a pass of windows across a map decodes each chunk about once and
/// memory follows the window, not the map.
pub struct Windows {
    dec: Decoder<BufReader<File>>,
    path: std::path::PathBuf,
    header: Header,
    /// Chunk width and height (a strip is the image's width).
    chunk: (usize, usize),
    across: usize,
    cache: std::collections::HashMap<usize, (Vec<f32>, usize, u64)>,
    cache_bytes: usize,
    budget_bytes: usize,
    clock: u64,
}

impl Windows {
    /// Opens `path`, keeping at most `budget_bytes` of decoded chunks.
    pub fn open(path: &Path, budget_bytes: usize) -> Result<Windows> {
        let file = crate::input::open(path, crate::input::RASTER_LIMIT)
            .map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
        let tiff_err = |e: tiff::TiffError| Error::format(path, format!("not a readable TIFF: {e}"));
        let mut dec = Decoder::new(BufReader::new(file)).map_err(tiff_err)?;
        let header = Header::parse(&mut dec, path)?;
        let (cw, ch) = dec.chunk_dimensions();
        let chunk = (cw as usize, ch as usize);
        if chunk.0 == 0 || chunk.1 == 0 {
            return Err(Error::format(path, format!("chunks of {} x {} pixels", chunk.0, chunk.1)));
        }
        let across = header.cols.div_ceil(chunk.0);
        Ok(Windows {
            dec,
            path: path.to_path_buf(),
            header,
            chunk,
            across,
            cache: std::collections::HashMap::new(),
            cache_bytes: 0,
            budget_bytes,
            clock: 0,
        })
    }

    /// The map's projected CRS in words when areo does not read its projection
    /// (transverse Mercator, Lambert, …): the map is then a local frame, which a scenario
    /// places at its site. `None` for every CRS areo reads, and for maps with none.
    pub fn crs_not_read(&self) -> Option<&str> {
        self.header.crs_not_read.as_deref()
    }

    /// Columns and rows of the whole map.
    pub fn size(&self) -> (usize, usize) {
        (self.header.cols, self.header.rows)
    }

    /// The map's grid: size, cells, placement, georeference.
    pub fn grid(&self) -> Grid {
        let h = &self.header;
        Grid { cols: h.cols, rows: h.rows, dx: h.dx, dy: h.dy, x0: h.x0, y_top: h.y_top, georef: h.georef }
    }

    /// The window `cols` × `rows` from (`col0`, `row0`) as a DEM, placed where it lies
    /// in the map.
    pub fn read(&mut self, col0: usize, row0: usize, cols: usize, rows: usize) -> Result<Dem> {
        let (w, h) = self.size();
        if cols == 0 || rows == 0 || col0 + cols > w || row0 + rows > h {
            return Err(Error::format(
                &self.path,
                format!("window {cols} x {rows} at ({col0}, {row0}) does not fit in {w} x {h}"),
            ));
        }
        let (cw, ch) = self.chunk;
        let mut z = vec![f32::NAN; cols * rows];
        for cr in row0 / ch..=(row0 + rows - 1) / ch {
            for cc in col0 / cw..=(col0 + cols - 1) / cw {
                let index = cr * self.across + cc;
                let (data, data_w) = self.chunk(index)?;
                let (c_lo, r_lo) = (cc * cw, cr * ch);
                let data_h = data.len() / data_w.max(1);
                for r in r_lo.max(row0)..(r_lo + data_h).min(row0 + rows) {
                    let (a, b) = (c_lo.max(col0), (c_lo + data_w).min(col0 + cols));
                    if a >= b {
                        continue;
                    }
                    let src = &data[(r - r_lo) * data_w + (a - c_lo)..][..b - a];
                    z[(r - row0) * cols + (a - col0)..][..b - a].copy_from_slice(src);
                }
            }
        }
        self.header.dem(col0, row0, cols, rows, z, &self.path)
    }

    /// Chunk `index` decoded (and its data width), from the cache or the file.
    fn chunk(&mut self, index: usize) -> Result<(&[f32], usize)> {
        self.clock += 1;
        if !self.cache.contains_key(&index) {
            let path = self.path.clone();
            let tiff_err = |e: tiff::TiffError| Error::format(&path, format!("chunk {index}: {e}"));
            let count = match self.dec.get_chunk_type() {
                tiff::decoder::ChunkType::Tile => self.dec.tile_count(),
                tiff::decoder::ChunkType::Strip => self.dec.strip_count(),
            }
            .map_err(tiff_err)? as usize;
            if index >= count {
                return Err(Error::format(
                    &path,
                    format!("chunk {index} of {count}: the file's chunks do not cover it"),
                ));
            }
            let (data_w, _) = self.dec.chunk_data_dimensions(index as u32);
            let data_w = data_w as usize;
            let data = samples(self.dec.read_chunk(index as u32).map_err(tiff_err)?, &path)?;
            let bytes = data.len() * 4;
            while self.cache_bytes + bytes > self.budget_bytes && !self.cache.is_empty() {
                let oldest = self.cache.iter().min_by_key(|(_, v)| v.2).map(|(k, _)| *k);
                if let Some(k) = oldest.and_then(|k| self.cache.remove(&k)) {
                    self.cache_bytes -= k.0.len() * 4;
                }
            }
            self.cache_bytes += bytes;
            self.cache.insert(index, (data, data_w, 0));
        }
        let clock = self.clock;
        let entry = self.cache.get_mut(&index).expect("just inserted");
        entry.2 = clock;
        Ok((&entry.0, entry.1))
    }
}

fn f64_vec<R: Read + Seek>(dec: &mut Decoder<R>, tag: Tag) -> tiff::TiffResult<Option<Vec<f64>>> {
    match dec.find_tag(tag)? {
        Some(v) => Ok(Some(v.into_f64_vec()?)),
        None => Ok(None),
    }
}

/// The GeoKey directory: (key, short value or index into the double params).
struct GeoKeys {
    entries: Vec<(u16, u16, u16)>,
    doubles: Vec<f64>,
}

impl GeoKeys {
    fn parse(dir: &[u16], doubles: &[f64]) -> GeoKeys {
        let mut entries = Vec::new();
        if dir.len() >= 4 {
            let n = dir[3] as usize;
            for k in 0..n {
                let at = 4 + 4 * k;
                if at + 3 < dir.len() {
                    // (key, location tag, count, value-or-offset)
                    entries.push((dir[at], dir[at + 1], dir[at + 3]));
                }
            }
        }
        GeoKeys { entries, doubles: doubles.to_vec() }
    }

    fn short(&self, key: u16) -> Option<u16> {
        self.entries.iter().find(|e| e.0 == key && e.1 == 0).map(|e| e.2)
    }

    fn double(&self, key: u16) -> Option<f64> {
        let e = self.entries.iter().find(|e| e.0 == key && e.1 == 34736)?;
        self.doubles.get(e.2 as usize).copied()
    }

    /// The georeference the keys describe, every value checked (finite, in range) with
    /// its key named.
    fn georef(&self) -> std::result::Result<Georef, String> {
        let check = |name: &str, key: u16, lo: f64, hi: f64| -> std::result::Result<Option<f64>, String> {
            match self.double(key) {
                Some(v) if !(v.is_finite() && (lo..=hi).contains(&v)) => {
                    Err(format!("{name} (GeoKey {key}) = {v}: allowed {lo}..={hi}"))
                }
                v => Ok(v),
            }
        };
        check("GeogSemiMajorAxisGeoKey", key::SEMI_MAJOR, 1e3, 1e8)?;
        check("GeogSemiMinorAxisGeoKey", key::SEMI_MINOR, 1e3, 1e8)?;
        check("GeogInvFlatteningGeoKey", key::INV_FLATTENING, 0.0, 1e9)?;
        check("ProjCenterLongGeoKey", key::CENTER_LONG, -360.0, 360.0)?;
        check("ProjNatOriginLongGeoKey", key::NAT_ORIGIN_LONG, -360.0, 360.0)?;
        check("ProjStraightVertPoleLongGeoKey", key::STRAIGHT_VERT_POLE_LONG, -360.0, 360.0)?;
        check("ProjNatOriginLatGeoKey", key::NAT_ORIGIN_LAT, -90.0, 90.0)?;
        // The standard parallel of an equirectangular map divides by its cosine.
        check("ProjStdParallel1GeoKey", key::STD_PARALLEL_1, -89.9, 89.9)?;
        let a = self.double(key::SEMI_MAJOR);
        let b = self.double(key::SEMI_MINOR).or_else(|| {
            let inv_f = self.double(key::INV_FLATTENING)?;
            Some(a? * (1.0 - if inv_f == 0.0 { 0.0 } else { 1.0 / inv_f }))
        });
        // A CRS named only by its EPSG code (a UTM zone, WGS84 itself — what GDAL
        // writes for terrestrial data) is the Earth's: every EPSG code is. Planetary
        // CRSs come user-defined, with their axes given.
        let epsg = [key::GEOGRAPHIC_TYPE, key::PROJECTED_CS]
            .iter()
            .any(|&k| self.short(k).is_some_and(|code| (1..key::USER_DEFINED).contains(&code)));
        let body = match (a, b) {
            (Some(a), Some(b)) if a > 0.0 && b > 0.0 => Spheroid { equatorial_radius_m: a, polar_radius_m: b },
            (Some(a), None) if a > 0.0 => Spheroid { equatorial_radius_m: a, polar_radius_m: a },
            _ if epsg => Spheroid::EARTH_WGS84,
            _ => Spheroid::MARS_IAU2015,
        };
        let lon0 = self
            .double(key::CENTER_LONG)
            .or_else(|| self.double(key::NAT_ORIGIN_LONG))
            .or_else(|| self.double(key::STRAIGHT_VERT_POLE_LONG))
            .unwrap_or(0.0);
        let projection = match self.short(key::COORD_TRANS) {
            Some(key::CT_EQUIRECTANGULAR) => Projection::Equirectangular {
                lat_ts_deg: self.double(key::STD_PARALLEL_1).unwrap_or(0.0),
                lon0_deg: lon0,
            },
            Some(key::CT_POLAR_STEREOGRAPHIC) => {
                let lat = self.double(key::NAT_ORIGIN_LAT).unwrap_or(90.0);
                Projection::PolarStereographic { north: lat >= 0.0, lon0_deg: lon0 }
            }
            _ => Projection::Local,
        };
        Ok(Georef { projection, surface: body })
    }
}

/// What a GeoTIFF says of its coordinate system: the GeoKey directory, its double
/// parameters and its ASCII parameters (the citations, each ended by `|`).
struct GeoTags {
    keys: Vec<u16>,
    doubles: Vec<f64>,
    ascii: String,
}

impl GeoTags {
    fn write<W: Write + Seek, K: tiff::encoder::TiffKind>(
        &self,
        dir: &mut tiff::encoder::DirectoryEncoder<'_, W, K>,
    ) -> tiff::TiffResult<()> {
        dir.write_tag(Tag::GeoKeyDirectoryTag, &self.keys[..])?;
        dir.write_tag(Tag::GeoDoubleParamsTag, &self.doubles[..])?;
        dir.write_tag(Tag::GeoAsciiParamsTag, &self.ascii[..])
    }
}

/// The GeoTIFF keys describing `georef`: a user-defined projected CRS in metres whose
/// citations name the map's [`crate::GeographicCrs`] (GDAL reads them into the WKT names): the sphere of
/// the equatorial radius that areo's projections use. A local frame keeps the body's
/// radii and cites itself as local.
fn geokeys_for(georef: &Georef) -> GeoTags {
    let surface = georef.surface;
    let crs = georef.geographic();
    let mut ascii = String::new();
    let mut cite = |text: &str| -> [u16; 2] {
        let at = ascii.len() as u16;
        ascii.push_str(text);
        ascii.push('|');
        [(text.len() + 1) as u16, at]
    };
    let a = surface.equatorial_radius_m;
    let projection = georef.projection.written();
    let (projected, minor) = match projection {
        Projection::Local => {
            let body = surface.body().map_or("an unnamed body", areo_body::Body::iau_name);
            (format!("areo local frame on {body}, metres"), surface.polar_radius_m)
        }
        Projection::Equirectangular { lat_ts_deg, lon0_deg } => {
            (format!("{} / Equirectangular, lat_ts = {lat_ts_deg}, clon = {lon0_deg}", crs.name), a)
        }
        Projection::PolarStereographic { north, lon0_deg } => (
            format!("{} / {} Polar Stereographic, clon = {lon0_deg}", crs.name, if north { "North" } else { "South" }),
            a,
        ),
    };
    let mut doubles = vec![a, minor];
    let pcs = cite(&projected);
    let mut keys: Vec<[u16; 4]> = vec![
        [key::MODEL_TYPE, 0, 1, 1],  // projected
        [key::RASTER_TYPE, 0, 1, 1], // PixelIsArea
        [key::GT_CITATION, 34737, pcs[0], pcs[1]],
        [key::SEMI_MAJOR, 34736, 1, 0],
        [key::SEMI_MINOR, 34736, 1, 1],
        [key::PROJECTED_CS, 0, 1, key::USER_DEFINED],
        [key::PROJ_LINEAR_UNITS, 0, 1, key::METRE],
    ];
    if projection != Projection::Local {
        let gcs = cite(&format!(
            "GCS Name = {}|Datum = {}|Ellipsoid = {}|Primem = Reference Meridian|",
            crs.name, crs.sphere, crs.sphere
        ));
        keys.extend([
            [key::GEOGRAPHIC_TYPE, 0, 1, key::USER_DEFINED],
            [key::GEOG_CITATION, 34737, gcs[0], gcs[1]],
            [key::GEODETIC_DATUM, 0, 1, key::USER_DEFINED],
            [key::GEOG_ANGULAR_UNITS, 0, 1, key::DEGREE],
            [key::ELLIPSOID, 0, 1, key::USER_DEFINED],
            [key::PROJECTION, 0, 1, key::USER_DEFINED],
        ]);
    }
    match projection {
        Projection::Local => {}
        Projection::Equirectangular { lat_ts_deg, lon0_deg } => {
            keys.push([key::COORD_TRANS, 0, 1, key::CT_EQUIRECTANGULAR]);
            doubles.push(lat_ts_deg);
            keys.push([key::STD_PARALLEL_1, 34736, 1, (doubles.len() - 1) as u16]);
            doubles.push(lon0_deg);
            keys.push([key::CENTER_LONG, 34736, 1, (doubles.len() - 1) as u16]);
        }
        Projection::PolarStereographic { north, lon0_deg } => {
            keys.push([key::COORD_TRANS, 0, 1, key::CT_POLAR_STEREOGRAPHIC]);
            doubles.push(if north { 90.0 } else { -90.0 });
            keys.push([key::NAT_ORIGIN_LAT, 34736, 1, (doubles.len() - 1) as u16]);
            doubles.push(lon0_deg);
            keys.push([key::STRAIGHT_VERT_POLE_LONG, 34736, 1, (doubles.len() - 1) as u16]);
        }
    }
    keys.sort_by_key(|k| k[0]);
    let mut dir = vec![1, 1, 0, keys.len() as u16];
    for k in keys {
        dir.extend_from_slice(&k);
    }
    GeoTags { keys: dir, doubles, ascii }
}

/// Writes a DEM as a float32 GeoTIFF (missing cells as NaN, GDAL_NODATA "nan").
pub fn write(dem: &Dem, path: &Path) -> Result<()> {
    let z: Vec<f32> =
        dem.elevations().iter().zip(dem.valid_mask()).map(|(z, ok)| if *ok { *z } else { f32::NAN }).collect();
    write_raster::<colortype::Gray32Float>(&Grid::of(dem), &z, Some("nan"), path)
}

/// Writes float32 values on `grid` (NaN where there is no value, GDAL_NODATA "nan"):
/// a raster held as plain data, without its DEM.
pub fn write_f32_on(grid: &Grid, values: &[f32], path: &Path) -> Result<()> {
    write_raster::<colortype::Gray32Float>(grid, values, Some("nan"), path)
}

/// Writes float64 values on `grid` (NaN where there is no value, GDAL_NODATA "nan"):
/// values that f32 would round, such as a class map's ids or a mask's codes.
pub fn write_f64_on(grid: &Grid, values: &[f64], path: &Path) -> Result<()> {
    write_raster::<colortype::Gray64Float>(grid, values, Some("nan"), path)
}

/// Writes one byte per cell on `grid`, with an optional nodata value.
pub fn write_u8_on(grid: &Grid, values: &[u8], nodata: Option<u8>, path: &Path) -> Result<()> {
    let nd = nodata.map(|v| v.to_string());
    write_raster::<colortype::Gray8>(grid, values, nd.as_deref(), path)
}

/// Writes a one-byte-per-cell raster on the DEM's grid (masks, shadow maps), with an
/// optional nodata value.
pub fn write_u8(dem: &Dem, values: &[u8], nodata: Option<u8>, path: &Path) -> Result<()> {
    write_u8_on(&Grid::of(dem), values, nodata, path)
}

fn write_raster<C: colortype::ColorType>(
    grid: &Grid,
    data: &[C::Inner],
    nodata: Option<&str>,
    path: &Path,
) -> Result<()>
where
    [C::Inner]: tiff::encoder::TiffValue,
{
    let io = |e: std::io::Error| Error::Io { path: path.to_path_buf(), source: e };
    // Writing can only fail in the file system (the values were checked): an I/O
    // failure while running, not a malformed input.
    let tiff_err = |e: tiff::TiffError| match e {
        tiff::TiffError::IoError(source) => Error::Io { path: path.to_path_buf(), source },
        other => Error::Io { path: path.to_path_buf(), source: std::io::Error::other(other) },
    };
    if data.len() != grid.cols * grid.rows {
        return Err(Error::BadGrid(format!("{} values for {} cells", data.len(), grid.cols * grid.rows)));
    }
    let mut out = BufWriter::new(File::create(path).map_err(io)?);
    {
        let mut enc = TiffEncoder::new(&mut out).map_err(tiff_err)?;
        let mut img = enc.new_image::<C>(grid.cols as u32, grid.rows as u32).map_err(tiff_err)?;
        let e = img.encoder();
        e.write_tag(Tag::ModelPixelScaleTag, &[grid.dx, grid.dy, 0.0][..]).map_err(tiff_err)?;
        e.write_tag(Tag::ModelTiepointTag, &[0.0, 0.0, 0.0, grid.x0, grid.y_top, 0.0][..]).map_err(tiff_err)?;
        geokeys_for(&grid.georef).write(e).map_err(tiff_err)?;
        if let Some(nd) = nodata {
            e.write_tag(Tag::GdalNodata, nd).map_err(tiff_err)?;
        }
        img.write_data(data).map_err(tiff_err)?;
    }
    out.flush().map_err(io)
}

/// A raster's grid without its values: what a writer needs to place it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Grid {
    /// Columns.
    pub cols: usize,
    /// Rows.
    pub rows: usize,
    /// Cell size east–west, m.
    pub dx: f64,
    /// Cell size north–south, m.
    pub dy: f64,
    /// West edge, m.
    pub x0: f64,
    /// North edge, m.
    pub y_top: f64,
    /// Projection and body.
    pub georef: Georef,
}

impl Grid {
    /// The grid of `dem`.
    pub fn of(dem: &Dem) -> Grid {
        Grid {
            cols: dem.cols(),
            rows: dem.rows(),
            dx: dem.dx(),
            dy: dem.dy(),
            x0: dem.x0(),
            y_top: dem.y_top(),
            georef: *dem.georef(),
        }
    }
}

/// GDAL's metadata tag: XML items, here each band's scale and offset.
const GDAL_METADATA: u16 = 42112;

fn gdal_scale_offset(planes: usize, scale: f64, offset: f64) -> String {
    let mut xml = String::from("<GDALMetadata>");
    for p in 0..planes {
        xml.push_str(&format!(
            "<Item name=\"SCALE\" sample=\"{p}\" role=\"scale\">{scale:e}</Item><Item name=\"OFFSET\" sample=\"{p}\" role=\"offset\">{offset}</Item>"
        ));
    }
    xml.push_str("</GDALMetadata>");
    xml
}

/// The GDAL band scale and offset of a file written with them, if any (first band).
pub fn gdal_scale_offset_of(path: &Path) -> Result<Option<(f64, f64)>> {
    let io = |e: std::io::Error| Error::Io { path: path.to_path_buf(), source: e };
    let mut dec = Decoder::new(BufReader::new(crate::input::open(path, crate::input::RASTER_LIMIT).map_err(io)?))
        .map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) })?;
    let Ok(Some(xml)) = dec.find_tag(Tag::Unknown(GDAL_METADATA)).map(|v| v.and_then(|v| v.into_string().ok())) else {
        return Ok(None);
    };
    let item = |role: &str| -> Option<f64> {
        let at = xml.find(&format!("sample=\"0\" role=\"{role}\">"))?;
        let rest = &xml[at..];
        let from = rest.find('>')? + 1;
        let to = rest.find("</Item>")?;
        rest[from..to].trim().parse().ok()
    };
    Ok(item("scale").zip(item("offset")))
}
