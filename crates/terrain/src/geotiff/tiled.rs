//! Tiled GeoTIFFs written as they are made: a band of tiles in memory at a time, tiles
//! stored in the order they finish, BigTIFF past 4 GB.

use super::*;

/// Beyond this many bytes of samples a streamed raster is written as BigTIFF (classic
/// TIFF offsets are 32-bit).
pub const BIGTIFF_FROM_BYTES: u64 = 4_000_000_000;

/// Writes a one-byte-per-cell *tiled* GeoTIFF as it is made, so that only one band of
/// `tile` rows is ever in memory: `fill(row0, band)` fills rows `row0..` (the last band
/// may be shorter) in order, north to south, and each band is cut into `tile` × `tile`
/// TIFF tiles (edge tiles padded with `nodata`, or 0). `tile` must be a positive
/// multiple of 16 (TIFF 6.0, section 15). Past [`BIGTIFF_FROM_BYTES`] (or with `big`)
/// the file is BigTIFF. Returns whether it was.
pub fn write_u8_tiled(
    grid: &Grid,
    nodata: Option<u8>,
    tile: usize,
    big: bool,
    path: &Path,
    fill: impl FnMut(usize, &mut [u8]) -> Result<()>,
) -> Result<bool> {
    let text = nodata.map(|v| v.to_string());
    let layout = Layout { planes: 1, nodata: text.as_deref(), scale_offset: None, tile };
    write_tiled::<colortype::Gray8>(grid, layout, nodata.unwrap_or(0), big, path, bands_to_tiles(grid, tile, fill))
}

/// [`write_u8_tiled`] for float32 elevations (missing as NaN, GDAL_NODATA "nan"):
/// a DEM larger than memory, written as it is made.
pub fn write_f32_tiled(
    grid: &Grid,
    tile: usize,
    big: bool,
    path: &Path,
    fill: impl FnMut(usize, &mut [f32]) -> Result<()>,
) -> Result<bool> {
    let layout = Layout { planes: 1, nodata: Some("nan"), scale_offset: None, tile };
    write_tiled::<colortype::Gray32Float>(grid, layout, f32::NAN, big, path, bands_to_tiles(grid, tile, fill))
}

/// Where a tiled writer takes tiles: `sink(col0, row0, cols, rows, values)`.
pub type TileSink<'a, T> = dyn FnMut(usize, usize, usize, usize, &[T]) -> Result<()> + 'a;

/// Writes a uint16 tiled GeoTIFF of `planes` planes (PlanarConfiguration 2: plane
/// after plane, as GDAL reads bands) as its tiles are made, in any order, so that only
/// one tile is ever in memory. `produce(sink)` calls `sink(col0, row0, cols, rows,
/// values)` once for every tile of the `tile` × `tile` lattice, `values` holding the
/// tile's planes one after another, each `rows` × `cols` row-major (edge tiles are
/// smaller; they are padded in the file with `nodata`, or 0). `scale` and `offset`,
/// if given, are written as GDAL band metadata (value = code × scale + offset), so
/// that GDAL reads the planes in physical units. A tile given twice or never is an
/// error. Past [`BIGTIFF_FROM_BYTES`] (or with `big`) the file is BigTIFF; returns
/// whether it was.
#[allow(clippy::too_many_arguments)] // one file's layout, tags and producer
pub fn write_u16_planes_tiled(
    grid: &Grid,
    planes: usize,
    nodata: Option<u16>,
    scale_offset: Option<(f64, f64)>,
    tile: usize,
    big: bool,
    path: &Path,
    produce: impl FnOnce(&mut TileSink<'_, u16>) -> Result<()>,
) -> Result<bool> {
    let text = nodata.map(|v| v.to_string());
    let layout = Layout { planes, nodata: text.as_deref(), scale_offset, tile };
    write_tiled::<colortype::Gray16>(grid, layout, nodata.unwrap_or(0), big, path, produce)
}

/// How a tiled file is laid out and labelled.
struct Layout<'a> {
    planes: usize,
    nodata: Option<&'a str>,
    scale_offset: Option<(f64, f64)>,
    tile: usize,
}

/// Cuts bands of `tile` rows, filled in order by `fill`, into tiles.
fn bands_to_tiles<T: Copy + Default>(
    grid: &Grid,
    tile: usize,
    mut fill: impl FnMut(usize, &mut [T]) -> Result<()>,
) -> impl FnOnce(&mut TileSink<'_, T>) -> Result<()> {
    let (cols, rows) = (grid.cols, grid.rows);
    move |sink| {
        if tile == 0 {
            return Ok(()); // write_tiled refuses it with a message
        }
        let mut band = vec![T::default(); tile * cols];
        let mut block = Vec::with_capacity(tile * tile);
        for row0 in (0..rows).step_by(tile) {
            let h = tile.min(rows - row0);
            fill(row0, &mut band[..h * cols])?;
            for col0 in (0..cols).step_by(tile) {
                let w = tile.min(cols - col0);
                block.clear();
                for r in 0..h {
                    block.extend_from_slice(&band[r * cols + col0..][..w]);
                }
                sink(col0, row0, w, h, &block)?;
            }
        }
        Ok(())
    }
}

fn write_tiled<C: colortype::ColorType>(
    grid: &Grid,
    layout: Layout<'_>,
    pad: C::Inner,
    big: bool,
    path: &Path,
    produce: impl FnOnce(&mut TileSink<'_, C::Inner>) -> Result<()>,
) -> Result<bool>
where
    [C::Inner]: tiff::encoder::TiffValue,
    C::Inner: Default + Copy,
{
    let tile = layout.tile;
    if tile == 0 || !tile.is_multiple_of(16) {
        return Err(Error::BadGrid(format!("TIFF tile of {tile} cells: allowed a positive multiple of 16")));
    }
    if grid.cols == 0 || grid.rows == 0 || layout.planes == 0 {
        return Err(Error::BadGrid(format!(
            "{} × {} cells, {} planes: nothing to write",
            grid.cols, grid.rows, layout.planes
        )));
    }
    // Padded edge tiles count: the file holds whole tiles.
    let padded = (grid.cols.div_ceil(tile) * grid.rows.div_ceil(tile) * tile * tile * layout.planes) as u64;
    let big = big || padded * std::mem::size_of::<C::Inner>() as u64 > BIGTIFF_FROM_BYTES;
    let io = |e: std::io::Error| Error::Io { path: path.to_path_buf(), source: e };
    let mut out = BufWriter::new(File::create(path).map_err(io)?);
    if big {
        write_tiles::<_, tiff::encoder::TiffKindBig, C>(&mut out, grid, &layout, pad, path, produce)?;
    } else {
        write_tiles::<_, tiff::encoder::TiffKindStandard, C>(&mut out, grid, &layout, pad, path, produce)?;
    }
    out.flush().map_err(io)?;
    Ok(big)
}

fn write_tiles<W: Write + Seek, K: tiff::encoder::TiffKind, C: colortype::ColorType>(
    out: W,
    grid: &Grid,
    layout: &Layout<'_>,
    pad: C::Inner,
    path: &Path,
    produce: impl FnOnce(&mut TileSink<'_, C::Inner>) -> Result<()>,
) -> Result<()>
where
    [C::Inner]: tiff::encoder::TiffValue,
    C::Inner: Default + Copy,
{
    let tiff_err = |e: tiff::TiffError| match e {
        tiff::TiffError::IoError(source) => Error::Io { path: path.to_path_buf(), source },
        other => Error::Io { path: path.to_path_buf(), source: std::io::Error::other(other) },
    };
    let (tile, planes) = (layout.tile, layout.planes);
    let (across, down) = (grid.cols.div_ceil(tile), grid.rows.div_ceil(tile));
    let per_plane = across * down;
    let mut enc = TiffEncoder::<W, K>::new_generic(out).map_err(tiff_err)?;
    let mut dir = enc.image_directory().map_err(tiff_err)?;
    let tile_bytes = tile * tile * std::mem::size_of::<C::Inner>();
    // TIFF numbers tiles plane by plane, then row of tiles by row of tiles; the data
    // may lie anywhere in the file, so tiles are stored in the order they finish.
    let mut offsets: Vec<Option<K::OffsetType>> = (0..per_plane * planes).map(|_| None).collect();
    let mut block = vec![pad; tile * tile];
    produce(&mut |col0, row0, w, h, values| {
        let fits = col0.is_multiple_of(tile)
            && row0.is_multiple_of(tile)
            && col0 < grid.cols
            && row0 < grid.rows
            && w == tile.min(grid.cols - col0)
            && h == tile.min(grid.rows - row0)
            && values.len() == w * h * planes;
        if !fits {
            return Err(Error::BadGrid(format!(
                "tile at column {col0}, row {row0} of {w} × {h} cells with {} values: not a tile of the {tile}-cell lattice on {} × {} cells with {planes} planes",
                values.len(),
                grid.cols,
                grid.rows
            )));
        }
        let index = (row0 / tile) * across + col0 / tile;
        for (p, plane) in values.chunks_exact(w * h).enumerate() {
            if w < tile || h < tile {
                block.fill(pad);
            }
            for r in 0..h {
                block[r * tile..][..w].copy_from_slice(&plane[r * w..][..w]);
            }
            let slot = &mut offsets[p * per_plane + index];
            if slot.is_some() {
                return Err(Error::BadGrid(format!("tile at column {col0}, row {row0} written twice")));
            }
            let at = dir.write_data(&block[..]).map_err(tiff_err)?;
            *slot = Some(K::convert_offset(at).map_err(tiff_err)?);
        }
        Ok(())
    })?;
    let offsets: Vec<K::OffsetType> = match offsets.into_iter().collect::<Option<Vec<_>>>() {
        Some(v) => v,
        None => return Err(Error::BadGrid("a tile was never written".into())),
    };
    let counts: Vec<K::OffsetType> = (0..offsets.len())
        .map(|_| K::OffsetType::try_from(tile_bytes))
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| tiff_err(e.into()))?;
    write_tile_tags::<W, K, C>(&mut dir, grid, layout, &offsets, &counts).map_err(tiff_err)?;
    dir.finish().map_err(tiff_err)
}

/// The tags of a tiled file: its grid, sample layout, tile offsets and byte counts,
/// georeference, no-data value and per-band scale and offset.
fn write_tile_tags<W: Write + Seek, K: tiff::encoder::TiffKind, C: colortype::ColorType>(
    dir: &mut tiff::encoder::DirectoryEncoder<'_, W, K>,
    grid: &Grid,
    layout: &Layout<'_>,
    offsets: &[K::OffsetType],
    counts: &[K::OffsetType],
) -> tiff::TiffResult<()> {
    use tiff::tags::{CompressionMethod, PhotometricInterpretation, PlanarConfiguration};
    let (tile, planes) = (layout.tile, layout.planes);
    dir.write_tag(Tag::ImageWidth, grid.cols as u32)?;
    dir.write_tag(Tag::ImageLength, grid.rows as u32)?;
    let bits = vec![C::BITS_PER_SAMPLE[0]; planes];
    dir.write_tag(Tag::BitsPerSample, &bits[..])?;
    let formats = vec![C::SAMPLE_FORMAT[0].to_u16(); planes];
    dir.write_tag(Tag::SampleFormat, &formats[..])?;
    dir.write_tag(Tag::SamplesPerPixel, planes as u16)?;
    dir.write_tag(Tag::Compression, CompressionMethod::None.to_u16())?;
    dir.write_tag(Tag::PhotometricInterpretation, PhotometricInterpretation::BlackIsZero.to_u16())?;
    let planar = if planes > 1 { PlanarConfiguration::Planar } else { PlanarConfiguration::Chunky };
    dir.write_tag(Tag::PlanarConfiguration, planar.to_u16())?;
    if planes > 1 {
        // Planes beyond the first are data, not alpha (TIFF 6.0, ExtraSamples 0).
        dir.write_tag(Tag::ExtraSamples, &vec![0u16; planes - 1][..])?;
    }
    dir.write_tag(Tag::TileWidth, tile as u32)?;
    dir.write_tag(Tag::TileLength, tile as u32)?;
    dir.write_tag(Tag::TileOffsets, K::convert_slice(offsets))?;
    dir.write_tag(Tag::TileByteCounts, K::convert_slice(counts))?;
    dir.write_tag(Tag::ModelPixelScaleTag, &[grid.dx, grid.dy, 0.0][..])?;
    dir.write_tag(Tag::ModelTiepointTag, &[0.0, 0.0, 0.0, grid.x0, grid.y_top, 0.0][..])?;
    geokeys_for(&grid.georef).write(dir)?;
    if let Some(nd) = layout.nodata {
        dir.write_tag(Tag::GdalNodata, nd)?;
    }
    if let Some((scale, offset)) = layout.scale_offset {
        dir.write_tag(Tag::Unknown(GDAL_METADATA), &gdal_scale_offset(planes, scale, offset)[..])?;
    }
    Ok(())
}
