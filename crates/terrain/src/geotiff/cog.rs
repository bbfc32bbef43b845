//! Cloud-Optimized GeoTIFFs: tiled, with overviews, every IFD before the data, and
//! GDAL's structural metadata announcing that layout, so a map server (TiTiler, MMGIS's
//! tiles) fetches what a view needs with range requests and `gdalinfo` reports
//! `LAYOUT=COG`.
//!
//! The file is classic little-endian TIFF, each tile Deflate-compressed (TIFF
//! compression 8, the zlib stream GDAL writes with `COMPRESS=DEFLATE`), in tiles of [`COG_TILE`] (or
//! one tile the map's size, rounded up to 16, for a smaller map): the 8-byte header; GDAL's
//! "ghost" structural metadata (`LAYOUT=IFDS_BEFORE_DATA`, `BLOCK_ORDER=ROW_MAJOR`,
//! `BLOCK_LEADER=SIZE_AS_UINT4`, `BLOCK_TRAILER=LAST_4_BYTES_REPEATED`); the full-
//! resolution image's IFD (with the georeference) and each overview's (halving until
//! the image fits one tile); then the tiles, the smallest overview's first, each
//! preceded by its size as a 4-byte integer and followed by its last four bytes again,
//! as those keys promise. Overviews average float32 values (NaN left out) and take the
//! north-west sample of each 2 × 2 block of bytes (categorical maps stay categorical).

use super::*;

/// The largest tile side, pixels (a map smaller than a tile is one tile of its size
/// rounded up to 16 pixels).
pub const COG_TILE: usize = 256;

/// A sample type of a COG.
trait Sample: Copy {
    /// TIFF BitsPerSample.
    const BITS: u16;
    /// TIFF SampleFormat: 1 unsigned integer, 3 IEEE float.
    const FORMAT: u16;
    /// Appends the sample, little-endian.
    fn put(self, out: &mut Vec<u8>);
    /// An overview's sample from a 2 × 2 block (1 to 4 samples, north-west first).
    fn reduce(block: &[Self]) -> Self;
}

impl Sample for f32 {
    const BITS: u16 = 32;
    const FORMAT: u16 = 3;
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
    fn reduce(block: &[f32]) -> f32 {
        let (sum, n) =
            block.iter().filter(|v| !v.is_nan()).fold((0.0f64, 0u32), |(s, n), &v| (s + f64::from(v), n + 1));
        if n == 0 { f32::NAN } else { (sum / f64::from(n)) as f32 }
    }
}

impl Sample for u8 {
    const BITS: u16 = 8;
    const FORMAT: u16 = 1;
    fn put(self, out: &mut Vec<u8>) {
        out.push(self);
    }
    fn reduce(block: &[u8]) -> u8 {
        block[0]
    }
}

/// What a COG's one band holds, for the tools that open it: a description and a unit,
/// in the GDAL_METADATA tag where GDAL keeps them in a GeoTIFF (`gdalinfo` shows them
/// as the band's description and unit type, QGIS in its layer properties), and for a
/// byte map of codes a colour for each, as a TIFF colour map (GDAL's colour table,
/// which QGIS draws as a paletted layer).
#[derive(Debug, Clone, Copy, Default)]
pub struct Band<'a> {
    /// What the values are.
    pub description: &'a str,
    /// Their unit (`m`, `degree`; empty for codes and flags).
    pub unit: &'a str,
    /// For a byte map: each code's colour, (code, [red, green, blue]); codes not listed
    /// are black. Empty: a grey-scale band.
    pub colours: &'a [(u8, [u8; 3])],
}

/// Writes float32 `values` (row-major from the north-west corner, NaN no data) on
/// `grid` as a Cloud-Optimized GeoTIFF.
pub fn write_cog_f32(grid: &Grid, values: &[f32], band: &Band<'_>, path: &Path) -> Result<()> {
    write_cog(grid, values, (Some("nan".to_string()), None, band), f32::NAN, path)
}

/// Writes one-byte `values` on `grid` as a Cloud-Optimized GeoTIFF, `nodata` named as
/// GDAL's no-data value.
pub fn write_cog_u8(grid: &Grid, values: &[u8], nodata: Option<u8>, band: &Band<'_>, path: &Path) -> Result<()> {
    write_cog(grid, values, (nodata.map(|v| v.to_string()), None, band), nodata.unwrap_or(0), path)
}

/// [`write_cog_u8`] for a map of one instant, `utc` (ISO 8601, `YYYY-MM-DDTHH:MM:SS…`),
/// written as the TIFF DateTime (`YYYY:MM:DD HH:MM:SS`, which GDAL reports as
/// `TIFFTAG_DATETIME`).
pub fn write_cog_u8_at(
    grid: &Grid,
    values: &[u8],
    nodata: Option<u8>,
    (utc, band): (&str, &Band<'_>),
    path: &Path,
) -> Result<()> {
    let stamp: String = utc.chars().take(19).collect::<String>().replacen('-', ":", 2).replace('T', " ");
    write_cog(grid, values, (nodata.map(|v| v.to_string()), Some(stamp), band), nodata.unwrap_or(0), path)
}

/// The GDAL_METADATA tag's XML for `band`'s description and unit (`None`: neither).
fn gdal_metadata(band: &Band<'_>) -> Option<String> {
    // The text is XML content: the three characters that could end or open markup
    // there are written as entities.
    let text = |s: &str| s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;");
    let mut items = String::new();
    for (role, name, value) in [("description", "DESCRIPTION", band.description), ("unittype", "UNITTYPE", band.unit)] {
        if !value.is_empty() {
            items.push_str(&format!("<Item name=\"{name}\" sample=\"0\" role=\"{role}\">{}</Item>", text(value)));
        }
    }
    (!items.is_empty()).then(|| format!("<GDALMetadata>{items}</GDALMetadata>"))
}

/// A TIFF colour map for 8-bit samples: 256 reds, then greens, then blues, 16 bits each.
fn colour_map(colours: &[(u8, [u8; 3])]) -> Vec<u16> {
    let mut map = vec![0u16; 3 * 256];
    for &(code, rgb) in colours {
        for (channel, &v) in rgb.iter().enumerate() {
            map[channel * 256 + usize::from(code)] = u16::from(v) * 257;
        }
    }
    map
}

/// A tile's bytes as a zlib stream. (Writing to a `Vec` cannot fail.)
fn deflate(bytes: &[u8]) -> Vec<u8> {
    use flate2::write::ZlibEncoder;
    let mut z = ZlibEncoder::new(Vec::with_capacity(bytes.len() / 4), flate2::Compression::new(1));
    let _ = z.write_all(bytes);
    z.finish().unwrap_or_default()
}

/// One image of the file: its size and samples.
struct Level<T> {
    cols: usize,
    rows: usize,
    values: Vec<T>,
}

impl<T: Sample> Level<T> {
    /// The image at half the size (rounded up).
    fn halved(&self) -> Level<T> {
        let (cols, rows) = (self.cols.div_ceil(2), self.rows.div_ceil(2));
        let mut values = Vec::with_capacity(cols * rows);
        let mut block = Vec::with_capacity(4);
        for r in 0..rows {
            for c in 0..cols {
                block.clear();
                for (dr, dc) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    let (rr, cc) = (2 * r + dr, 2 * c + dc);
                    if rr < self.rows && cc < self.cols {
                        block.push(self.values[rr * self.cols + cc]);
                    }
                }
                values.push(T::reduce(&block));
            }
        }
        Level { cols, rows, values }
    }

    /// The tiles, row-major, each `tile`² samples (edge tiles padded with `pad`).
    fn tiles(&self, pad: T, tile: usize) -> Vec<Vec<u8>> {
        let (across, down) = (self.cols.div_ceil(tile), self.rows.div_ceil(tile));
        let mut out = Vec::with_capacity(across * down);
        for ty in 0..down {
            for tx in 0..across {
                let mut bytes = Vec::with_capacity(tile * tile * usize::from(T::BITS / 8));
                for r in ty * tile..(ty + 1) * tile {
                    for c in tx * tile..(tx + 1) * tile {
                        let v = if r < self.rows && c < self.cols { self.values[r * self.cols + c] } else { pad };
                        v.put(&mut bytes);
                    }
                }
                out.push(bytes);
            }
        }
        out
    }
}

/// A TIFF field: its tag, type (2 ASCII, 3 SHORT, 4 LONG, 12 DOUBLE), count and value
/// bytes.
struct Field {
    tag: u16,
    kind: u16,
    count: u32,
    bytes: Vec<u8>,
}

impl Field {
    fn shorts(tag: u16, values: &[u16]) -> Field {
        Field { tag, kind: 3, count: values.len() as u32, bytes: values.iter().flat_map(|v| v.to_le_bytes()).collect() }
    }
    fn longs(tag: u16, values: &[u32]) -> Field {
        Field { tag, kind: 4, count: values.len() as u32, bytes: values.iter().flat_map(|v| v.to_le_bytes()).collect() }
    }
    fn doubles(tag: u16, values: &[f64]) -> Field {
        Field {
            tag,
            kind: 12,
            count: values.len() as u32,
            bytes: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        }
    }
    fn ascii(tag: u16, text: &str) -> Field {
        let mut bytes = text.as_bytes().to_vec();
        bytes.push(0);
        Field { tag, kind: 2, count: bytes.len() as u32, bytes }
    }
}

/// An IFD at byte `at` with `fields` (sorted by tag), pointing to `next`: the entries,
/// then the values that do not fit in an entry, each at an even offset.
fn ifd(at: u32, fields: &[Field], next: u32) -> Vec<u8> {
    let table = 2 + 12 * fields.len() + 4;
    let mut head = Vec::with_capacity(table);
    let mut tail: Vec<u8> = Vec::new();
    head.extend_from_slice(&(fields.len() as u16).to_le_bytes());
    for f in fields {
        head.extend_from_slice(&f.tag.to_le_bytes());
        head.extend_from_slice(&f.kind.to_le_bytes());
        head.extend_from_slice(&f.count.to_le_bytes());
        if f.bytes.len() <= 4 {
            let mut inline = f.bytes.clone();
            inline.resize(4, 0);
            head.extend_from_slice(&inline);
        } else {
            let offset = at + (table + tail.len()) as u32;
            head.extend_from_slice(&offset.to_le_bytes());
            tail.extend_from_slice(&f.bytes);
            if tail.len() % 2 == 1 {
                tail.push(0);
            }
        }
    }
    head.extend_from_slice(&next.to_le_bytes());
    head.extend(tail);
    head
}

/// GDAL's structural metadata, padded so the first IFD starts at an even offset.
fn ghost() -> Vec<u8> {
    let mut body = String::from(
        "LAYOUT=IFDS_BEFORE_DATA\nBLOCK_ORDER=ROW_MAJOR\nBLOCK_LEADER=SIZE_AS_UINT4\n\
         BLOCK_TRAILER=LAST_4_BYTES_REPEATED\nKNOWN_INCOMPATIBLE_EDITION=NO\n",
    );
    let head = |n: usize| format!("GDAL_STRUCTURAL_METADATA_SIZE={n:06} bytes\n");
    if (head(body.len()).len() + body.len()) % 2 == 1 {
        body.push(' ');
    }
    format!("{}{body}", head(body.len())).into_bytes()
}

/// The fields of level `k` of `levels`, its tiles at `offsets` of `sizes` bytes.
fn fields<T: Sample>(
    (grid, tile): (&Grid, usize),
    (k, level): (usize, &Level<T>),
    (offsets, sizes): (&[u32], &[u32]),
    (nodata, datetime, band): (Option<&str>, Option<&str>, &Band<'_>),
) -> Vec<Field> {
    // A palette only where there are colours and samples of a byte.
    let palette = !band.colours.is_empty() && T::BITS == 8;
    let mut f = vec![
        Field::longs(254, &[u32::from(k > 0)]),
        Field::longs(256, &[level.cols as u32]),
        Field::longs(257, &[level.rows as u32]),
        Field::shorts(258, &[T::BITS]),
        Field::shorts(259, &[8]),
        Field::shorts(262, &[if palette { 3 } else { 1 }]),
        Field::shorts(277, &[1]),
        Field::shorts(284, &[1]),
    ];
    if let Some(stamp) = datetime {
        f.push(Field::ascii(306, stamp));
    }
    if palette {
        f.push(Field::shorts(320, &colour_map(band.colours)));
    }
    f.extend([
        Field::longs(322, &[tile as u32]),
        Field::longs(323, &[tile as u32]),
        Field::longs(324, offsets),
        Field::longs(325, sizes),
        Field::shorts(339, &[T::FORMAT]),
    ]);
    if k == 0 {
        let geo = geokeys_for(&grid.georef);
        f.push(Field::doubles(33550, &[grid.dx, grid.dy, 0.0]));
        f.push(Field::doubles(33922, &[0.0, 0.0, 0.0, grid.x0, grid.y_top, 0.0]));
        f.push(Field::shorts(34735, &geo.keys));
        f.push(Field::doubles(34736, &geo.doubles));
        f.push(Field::ascii(34737, &geo.ascii));
        if let Some(xml) = gdal_metadata(band) {
            f.push(Field::ascii(42112, &xml));
        }
    }
    if let Some(nd) = nodata {
        f.push(Field::ascii(42113, nd));
    }
    f
}

fn write_cog<T: Sample>(
    grid: &Grid,
    values: &[T],
    (nodata, datetime, band): (Option<String>, Option<String>, &Band<'_>),
    pad: T,
    path: &Path,
) -> Result<()> {
    if values.len() != grid.cols * grid.rows {
        return Err(Error::BadGrid(format!("{} values for {} cells", values.len(), grid.cols * grid.rows)));
    }
    let tile = COG_TILE.min(grid.cols.max(grid.rows).next_multiple_of(16));
    let mut levels = vec![Level { cols: grid.cols, rows: grid.rows, values: values.to_vec() }];
    while let Some(last) = levels.last().filter(|l| l.cols > tile || l.rows > tile) {
        let next = last.halved();
        levels.push(next);
    }
    let tiles: Vec<Vec<Vec<u8>>> =
        levels.iter().map(|l| l.tiles(pad, tile).iter().map(|t| deflate(t)).collect()).collect();
    let tags = (nodata.as_deref(), datetime.as_deref(), band);
    // The IFDs' sizes do not depend on the offsets they hold: measure them with zeros,
    // then place the data after them, the smallest overview's tiles first.
    let ghost = ghost();
    let first_ifd = 8 + ghost.len();
    let sizes: Vec<Vec<u32>> = tiles.iter().map(|t| t.iter().map(|b| b.len() as u32).collect()).collect();
    let zeros: Vec<Vec<u32>> = sizes.iter().map(|s| vec![0; s.len()]).collect();
    let ifd_lens: Vec<usize> = (levels.iter().enumerate())
        .map(|(k, l)| ifd(0, &fields((grid, tile), (k, l), (&zeros[k], &sizes[k]), tags), 0).len())
        .collect();
    let data_start = first_ifd + ifd_lens.iter().sum::<usize>();
    let mut offsets: Vec<Vec<u32>> = zeros.clone();
    let mut at = data_start as u64;
    for k in (0..levels.len()).rev() {
        for (i, t) in tiles[k].iter().enumerate() {
            offsets[k][i] = (at + 4) as u32;
            at += 4 + t.len() as u64 + 4;
        }
    }
    if at > u64::from(u32::MAX) {
        return Err(Error::BadGrid(format!(
            "{} × {} cells are too large for a classic TIFF COG",
            grid.cols, grid.rows
        )));
    }
    let mut file = Vec::with_capacity(at as usize);
    file.extend_from_slice(b"II");
    file.extend_from_slice(&42u16.to_le_bytes());
    file.extend_from_slice(&(first_ifd as u32).to_le_bytes());
    file.extend_from_slice(&ghost);
    for (k, l) in levels.iter().enumerate() {
        let here = file.len() as u32;
        let next = if k + 1 < levels.len() { here + ifd_lens[k] as u32 } else { 0 };
        file.extend(ifd(here, &fields((grid, tile), (k, l), (&offsets[k], &sizes[k]), tags), next));
    }
    for k in (0..levels.len()).rev() {
        for t in &tiles[k] {
            file.extend_from_slice(&(t.len() as u32).to_le_bytes());
            file.extend_from_slice(t);
            file.extend_from_slice(&t[t.len() - 4..]);
        }
    }
    debug_assert_eq!(file.len() as u64, at);
    let io = |e: std::io::Error| Error::Io { path: path.to_path_buf(), source: e };
    let mut out = BufWriter::new(File::create(path).map_err(io)?);
    out.write_all(&file).map_err(io)?;
    out.flush().map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(cols: usize, rows: usize) -> Grid {
        Grid {
            cols,
            rows,
            dx: 10.0,
            dy: 10.0,
            x0: 1000.0,
            y_top: 5000.0,
            georef: Georef { projection: Projection::Local, surface: Spheroid::MARS_MOLA_SPHERE },
        }
    }

    #[test]
    fn a_cog_reads_back_with_its_values_georeference_and_overviews() {
        let (cols, rows) = (600, 530);
        let values: Vec<f32> = (0..cols * rows)
            .map(|i| if i % 97 == 0 { f32::NAN } else { (i % cols) as f32 * 0.5 - (i / cols) as f32 })
            .collect();
        let path = std::env::temp_dir().join(format!("areo-cog-{}.tif", std::process::id()));
        write_cog_f32(&grid(cols, rows), &values, &Band::default(), &path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        // The structural metadata right after the header, the first IFD after it.
        assert_eq!(&bytes[8..38], b"GDAL_STRUCTURAL_METADATA_SIZE=");
        let first_ifd = u32::from_le_bytes(bytes[4..8].try_into().unwrap()) as usize;
        assert!(first_ifd.is_multiple_of(2) && first_ifd > 8 + 100);
        // Read back through the tiff crate: every value, the geotransform.
        let dem = read(&path).unwrap();
        assert_eq!((dem.cols(), dem.rows()), (cols, rows));
        assert_eq!((dem.x0(), dem.y_top(), dem.dx()), (1000.0, 5000.0, 10.0));
        for (a, b) in dem.elevations().iter().zip(&values) {
            assert!(a == b || (a.is_nan() && b.is_nan()), "{a} vs {b}");
        }
        // Three images: 600 × 530, 300 × 265, 150 × 133; each tile's leader is its size
        // and its trailer its last four bytes.
        let mut dec = Decoder::new(std::io::Cursor::new(&bytes)).unwrap();
        let main_offsets = dec.get_tag_u32_vec(Tag::TileOffsets).unwrap();
        let mut sizes = vec![dec.dimensions().unwrap()];
        while dec.more_images() {
            dec.next_image().unwrap();
            sizes.push(dec.dimensions().unwrap());
        }
        assert_eq!(sizes, [(600, 530), (300, 265), (150, 133)]);
        let offsets = dec.get_tag_u32_vec(Tag::TileOffsets).unwrap();
        let counts = dec.get_tag_u32_vec(Tag::TileByteCounts).unwrap();
        for (&o, &n) in offsets.iter().zip(&counts) {
            let (o, n) = (o as usize, n as usize);
            assert_eq!(u32::from_le_bytes(bytes[o - 4..o].try_into().unwrap()) as usize, n);
            assert_eq!(bytes[o + n - 4..o + n], bytes[o + n..o + n + 4]);
        }
        // The smallest overview's tiles come first in the file, the full image's last.
        assert!(offsets.iter().max() < main_offsets.iter().min());
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn overviews_average_floats_without_nan_and_keep_a_bytes_north_west_sample() {
        let level = Level { cols: 3, rows: 2, values: vec![1.0f32, 3.0, f32::NAN, 5.0, f32::NAN, 7.0] };
        let half = level.halved();
        assert_eq!((half.cols, half.rows), (2, 1));
        assert_eq!(half.values, [3.0, 7.0]);
        let bytes = Level { cols: 2, rows: 2, values: vec![1u8, 0, 0, 0] };
        assert_eq!(bytes.halved().values, [1]);
    }
}
