//! Readers and writers: the real Gale crater DEMs (shared data, and the crop kept in
//! this crate), round trips, and corrupt or truncated bytes.

use std::path::{Path, PathBuf};

use areo_terrain::{Dem, Georef, Projection, Spheroid, ascii, geotiff, pds3};
use proptest::prelude::*;

/// A DEM of `../shared/data/dem` (beside the repository), if it is there. Where the
/// data must be there — `.ci/run` sets `AREO_REQUIRE_SHARED_DATA` — a missing file
/// fails the test instead of skipping it.
pub(crate) fn shared(name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/dem").join(name);
    if !p.exists() && std::env::var_os("AREO_REQUIRE_SHARED_DATA").is_some() {
        panic!("{}: missing, and AREO_REQUIRE_SHARED_DATA says it must be there", p.display());
    }
    p.exists().then_some(p)
}

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

fn tmp(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/terrain-tests");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn min_max(dem: &Dem) -> (f32, f32) {
    dem.elevations().iter().fold((f32::MAX, f32::MIN), |(lo, hi), z| (lo.min(*z), hi.max(*z)))
}

#[test]
fn native_mola_geotiff_loads_with_its_published_size_cells_and_range() {
    let Some(path) = shared("gale_mola_463m.tif") else {
        eprintln!("shared/data/dem is not beside the repository: the crop test below covers the reader");
        return;
    };
    let dem = geotiff::read(&path).unwrap();
    assert_eq!((dem.cols(), dem.rows()), (897, 897));
    assert!((dem.dx() - 461.000_817_875_279_8).abs() < 1e-6 && (dem.dy() - 463.057_667_169_745_6).abs() < 1e-6);
    assert!((dem.x0() - 7_924_604.059_276_059).abs() < 1e-3 && (dem.y_top() + 112_523.013_122_248_17).abs() < 1e-3);
    // MOLA MEGDR window: crater floor −4648 m, highlands +2002 m, no nodata.
    assert_eq!(min_max(&dem), (-4648.0, 2002.0));
    assert!(dem.valid_mask().iter().all(|v| *v));
    // eqc on the MOLA sphere: the north-west corner is (134.296875°E, 1.8984375°S).
    let georef = dem.georef();
    assert!(matches!(georef.projection, Projection::Equirectangular { .. }), "{georef:?}");
    assert_eq!(georef.surface.equatorial_radius_m, 3_396_000.0);
    let (lat, lon) = dem.geographic(dem.x0(), dem.y_top()).unwrap();
    assert!((lat + 1.898_437_5).abs() < 1e-6 && (lon - 134.296_875).abs() < 1e-6, "{lat} {lon}");
}

#[test]
fn tempest_sized_float32_geotiff_loads_and_matches_the_native_heights() {
    let (Some(cubic), Some(native)) = (shared("gale_mola_cubic164m_2527x2356.tif"), shared("gale_mola_463m.tif"))
    else {
        return;
    };
    let dem = geotiff::read(&cubic).unwrap();
    assert_eq!((dem.cols(), dem.rows()), (2527, 2356));
    assert!((dem.dx() - 163.639_783_788_732_08).abs() < 1e-6 && (dem.dy() - 164.369_896_102_596_67).abs() < 1e-6);
    let native = geotiff::read(&native).unwrap();
    // Cubic resampling of the same data: heights agree with the native bilinear surface
    // to tens of metres away from cliffs.
    let mut diffs = Vec::new();
    for (c, r) in [(100, 100), (1263, 1178), (2000, 500), (700, 2000), (1500, 1500)] {
        let (x, y) = dem.cell_center(c, r);
        diffs.push((f64::from(dem.z(c, r).unwrap()) - native.height(x, y).unwrap()).abs());
    }
    diffs.sort_by(f64::total_cmp);
    assert!(diffs[2] < 30.0, "median difference {} m", diffs[2]);
}

#[test]
fn the_committed_crop_of_the_real_dem_loads() {
    let dem = geotiff::read(&data("gale_mola_crop_64.tif")).unwrap();
    assert_eq!((dem.cols(), dem.rows()), (64, 64));
    assert!((dem.dx() - 461.000_817_875_279_8).abs() < 1e-6);
    // Integral metres from the MOLA int16 source.
    assert!(dem.elevations().iter().all(|z| z.fract() == 0.0));
    let (lo, hi) = min_max(&dem);
    assert!(lo >= -4648.0 && hi <= 2002.0 && hi - lo > 100.0);
    if let Some(path) = shared("gale_mola_463m.tif") {
        let native = geotiff::read(&path).unwrap();
        let same = native.crop(400, 400, 64, 64).unwrap();
        assert_eq!(dem.elevations(), same.elevations());
        assert_eq!((dem.x0(), dem.y_top()), (same.x0(), same.y_top()));
    }
}

fn sample_dem() -> Dem {
    let mut dem = Dem::from_fn(13, 7, 2.5, 4.0, |x, y| 100.0 + x * 0.5 - y * 0.25 + (x * y).sin()).unwrap();
    let mut mask = vec![true; 91];
    mask[20] = false;
    dem = dem.with_mask(mask).unwrap();
    dem.with_georef(Georef {
        projection: Projection::Equirectangular { lat_ts_deg: -5.4, lon0_deg: 137.0 },
        surface: areo_terrain::Spheroid::MARS_MOLA_SPHERE,
    })
}

#[test]
fn geotiff_round_trip_keeps_values_mask_and_georeference() {
    let dem = sample_dem();
    let path = tmp("roundtrip.tif");
    geotiff::write(&dem, &path).unwrap();
    let back = geotiff::read(&path).unwrap();
    assert_eq!((back.cols(), back.rows(), back.dx(), back.dy(), back.x0(), back.y_top()), (13, 7, 2.5, 4.0, 0.0, 28.0));
    assert_eq!(back.valid_mask(), dem.valid_mask());
    for r in 0..7 {
        for c in 0..13 {
            assert_eq!(back.z(c, r), dem.z(c, r));
        }
    }
    assert_eq!(back.georef(), dem.georef());
}

/// A synthesised map placed at the lunar south pole is polar stereographic on the LOLA
/// sphere (R = 1737.4 km, true scale at the pole, the site's meridian as grid north);
/// it goes through a GeoTIFF and back as the Moon, and its cells' latitudes are the
/// stereographic projection's: 2R·tan(c/2) from the pole for colatitude c.
#[test]
fn lunar_polar_map_is_lola_polar_stereographic_through_a_geotiff() {
    let flat = Dem::from_fn(50, 40, 20.0, 20.0, |x, y| 0.01 * x - 0.02 * y).unwrap();
    let dem = flat.clone().placed_at(areo_terrain::Spheroid::MOON, -89.5, 45.0).unwrap();
    assert_eq!(dem.georef().projection, Projection::PolarStereographic { north: false, lon0_deg: 45.0 });
    let e = dem.extent();
    let (xc, yc) = ((e.x_min + e.x_max) / 2.0, (e.y_min + e.y_max) / 2.0);
    let (lat, lon) = dem.geographic(xc, yc).unwrap();
    assert!((lat + 89.5).abs() < 1e-9 && (lon - 45.0).abs() < 1e-9, "{lat} {lon}");
    // The centre lies 2R tan(0.25°) = 15.163 km from the pole along grid +y.
    assert!(xc.abs() < 1e-6 && (yc - 2.0 * 1_737_400.0 * 0.25f64.to_radians().tan()).abs() < 1e-3, "{xc} {yc}");
    // Grid north at the site is geographic north: 400 m up is 400 / R rad farther
    // from the pole (the stereographic scale at 89.5° S is 1.00002).
    let (lat_n, lon_n) = dem.geographic(xc, yc + 400.0).unwrap();
    assert!((lat_n - (-89.5 + (400.0 / 1_737_400.0f64).to_degrees())).abs() < 1e-5, "{lat_n}");
    assert!((lon_n - 45.0).abs() < 1e-9);
    let path = tmp("lunar-polar.tif");
    geotiff::write(&dem, &path).unwrap();
    let back = geotiff::read(&path).unwrap();
    assert_eq!(back.georef(), dem.georef());
    assert_eq!(back.georef().surface, areo_terrain::Spheroid::MOON);
    // Below 80° the placement stays equirectangular.
    let low = flat.placed_at(areo_terrain::Spheroid::MOON, -79.0, 45.0).unwrap();
    assert!(matches!(low.georef().projection, Projection::Equirectangular { .. }));
}

#[test]
fn ascii_round_trip_and_centre_registration() {
    let dem = sample_dem();
    let path = tmp("roundtrip.asc");
    ascii::write(&dem, &path).unwrap();
    let back = ascii::read(&path).unwrap();
    assert_eq!((back.cols(), back.rows(), back.dx(), back.dy()), (13, 7, 2.5, 4.0));
    assert_eq!(back.valid_mask(), dem.valid_mask());
    for i in 0..91 {
        if dem.valid_mask()[i] {
            assert!((back.elevations()[i] - dem.elevations()[i]).abs() < 1e-4);
        }
    }
    let text = "ncols 2\nnrows 2\nxllcenter 10\nyllcenter 20\ncellsize 2\nNODATA_value -1\n1 2\n-1 4\n";
    let d = ascii::parse(text, Path::new("x.asc")).unwrap();
    assert_eq!((d.x0(), d.y_top()), (9.0, 23.0));
    assert_eq!(d.z(0, 1), None);
    assert_eq!(d.z(1, 1), Some(4.0));
}

#[test]
fn bad_files_are_errors_naming_the_file() {
    let err = ascii::parse("ncols 2\nnrows 2\ncellsize 1\nxllcorner 0\nyllcorner 0\n1 2 3\n", Path::new("short.asc"))
        .unwrap_err();
    assert!(err.to_string().contains("short.asc") && err.to_string().contains("3 values"), "{err}");
    let err = geotiff::read(Path::new("no/such.tif")).unwrap_err();
    assert!(err.to_string().contains("no/such.tif"));
    let err = geotiff::read_from(std::io::Cursor::new(b"II*\0garbage".to_vec()), Path::new("junk.tif")).unwrap_err();
    assert!(err.to_string().contains("junk.tif"));
}

#[test]
fn any_format_is_read_by_its_extension_and_others_are_refused() {
    let dem = sample_dem();
    let (tif, asc) = (tmp("by-ext.TIF"), tmp("by-ext.asc"));
    geotiff::write(&dem, &tif).unwrap();
    ascii::write(&dem, &asc).unwrap();
    assert_eq!(areo_terrain::read(&tif).unwrap().valid_mask(), dem.valid_mask());
    assert_eq!(areo_terrain::read(&asc).unwrap().cols(), 13);
    let err = areo_terrain::read(Path::new("elevations.xyz")).unwrap_err();
    assert!(matches!(err, areo_terrain::Error::UnknownFormat { .. }), "{err:?}");
    assert!(err.to_string().contains("elevations.xyz") && err.to_string().contains(".asc"), "{err}");
}

#[test]
fn extent_values_and_placement_keep_the_grid() {
    let dem = sample_dem();
    let e = dem.extent();
    assert_eq!((e.x_min, e.x_max, e.y_min, e.y_max), (0.0, 32.5, 0.0, 28.0));
    // Another raster on the same grid and georeference; NaN marks missing cells.
    let mut v: Vec<f32> = (0..91).map(|i| i as f32).collect();
    v[5] = f32::NAN;
    let other = dem.with_values(v).unwrap();
    assert_eq!(other.extent(), e);
    assert_eq!(other.georef(), dem.georef());
    assert_eq!((other.z(5, 0), other.z(6, 0)), (None, Some(6.0)));
    assert!(dem.with_values(vec![0.0; 90]).is_err());
    // A georeferenced map stays where it is.
    assert_eq!(dem.clone().placed_at(areo_terrain::Spheroid::MARS_MOLA_SPHERE, 10.0, 20.0).unwrap(), dem);
    // A local map is centred on the site: its centre cell is at the site's latitude and
    // longitude, and a cell 1 km north is 1 km / R radians further north.
    let local = Dem::from_fn(21, 21, 100.0, 100.0, |x, _| x).unwrap();
    let body = areo_terrain::Spheroid::MARS_MOLA_SPHERE;
    let placed = local.placed_at(body, -4.6, 137.4).unwrap();
    let (cx, cy) = placed.cell_center(10, 10);
    let (lat, lon) = placed.geographic(cx, cy).unwrap();
    assert!((lat + 4.6).abs() < 1e-9 && (lon - 137.4).abs() < 1e-9, "{lat} {lon}");
    let (lat_n, _) = placed.geographic(cx, cy + 1000.0).unwrap();
    let expected = (1000.0 / body.equatorial_radius_m).to_degrees();
    assert!((lat_n - lat - expected).abs() < 1e-9, "{}", lat_n - lat);
    assert_eq!(placed.z(3, 4), Some(350.0));
}

/// A PDS3 label for a 3 × 2 image.
fn pds_label(pointer: &str, sample_type: &str, bits: u32, extra: &str) -> String {
    format!(
        "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 1024\r\nLABEL_RECORDS = 1\r\n\
         ^IMAGE = {pointer}\r\nOBJECT = IMAGE\r\n  LINES = 2\r\n  LINE_SAMPLES = 3\r\n  SAMPLE_TYPE = {sample_type}\r\n\
         SAMPLE_BITS = {bits}\r\n{extra}END_OBJECT = IMAGE\r\nOBJECT = IMAGE_MAP_PROJECTION\r\n\
         MAP_PROJECTION_TYPE = \"SIMPLE CYLINDRICAL\"\r\n  A_AXIS_RADIUS = 3396.0 <KM>\r\n  B_AXIS_RADIUS = 3396.0 <KM>\r\n\
         MAP_SCALE = 0.4630 <KM/PIXEL>\r\n  CENTER_LATITUDE = 0.0 <DEGREE>\r\n  CENTER_LONGITUDE = 90.0 <DEGREE>\r\n\
         LINE_PROJECTION_OFFSET = -10.5 <PIXEL>\r\n  SAMPLE_PROJECTION_OFFSET = 20.5 <PIXEL>\r\n\
         END_OBJECT = IMAGE_MAP_PROJECTION\r\nEND\r\n"
    )
}

#[test]
fn pds3_attached_msb_int16_with_scaling_and_missing_constant() {
    let mut bytes = pds_label(
        "2",
        "MSB_INTEGER",
        16,
        "  SCALING_FACTOR = 0.5\r\n  OFFSET = -100\r\n  MISSING_CONSTANT = -32768\r\n",
    )
    .into_bytes();
    bytes.resize(1024, b' ');
    for v in [10i16, 20, 30, -32768, 50, 60] {
        bytes.extend_from_slice(&v.to_be_bytes());
    }
    let path = tmp("attached.IMG");
    std::fs::write(&path, &bytes).unwrap();
    let dem = pds3::read(&path).unwrap();
    assert_eq!((dem.cols(), dem.rows()), (3, 2));
    assert_eq!(dem.z(0, 0), Some(-95.0));
    assert_eq!(dem.z(2, 0), Some(-85.0));
    assert_eq!(dem.z(0, 1), None, "MISSING_CONSTANT");
    assert_eq!(dem.z(2, 1), Some(-70.0));
    assert!((dem.dx() - 463.0).abs() < 1e-9);
    // Origin pixel centre at (line −10.5, sample 20.5), 1-based.
    assert!((dem.x0() - (0.5 - 20.5) * 463.0).abs() < 1e-6 && (dem.y_top() - (-10.5 - 0.5) * 463.0).abs() < 1e-6);
    assert_eq!(dem.georef().projection, Projection::Equirectangular { lat_ts_deg: 0.0, lon0_deg: 90.0 });
    assert_eq!(dem.georef().surface.equatorial_radius_m, 3_396_000.0);
}

#[test]
fn pds3_detached_label_with_pc_real_and_hex_missing_constant() {
    let label = pds_label("\"DETACHED.IMG\"", "PC_REAL", 32, "  MISSING_CONSTANT = 16#FF7FFFFB#\r\n");
    let missing = f32::from_bits(0xFF7F_FFFB);
    let mut img = Vec::new();
    for v in [1.5f32, missing, 3.25, 4.0, 5.0, -6.5] {
        img.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(tmp("DETACHED.IMG"), &img).unwrap();
    std::fs::write(tmp("DETACHED.LBL"), label.as_bytes()).unwrap();
    for p in ["DETACHED.LBL", "DETACHED.IMG"] {
        let dem = pds3::read(&tmp(p)).unwrap();
        assert_eq!(dem.z(0, 0), Some(1.5));
        assert_eq!(dem.z(1, 0), None);
        assert_eq!(dem.z(2, 1), Some(-6.5));
    }
    // A truncated image is an error naming the label.
    std::fs::write(tmp("DETACHED.IMG"), &img[..10]).unwrap();
    let err = pds3::read(&tmp("DETACHED.LBL")).unwrap_err().to_string();
    assert!(err.contains("DETACHED.LBL") && err.contains("truncated"), "{err}");
}

#[test]
fn pds3_hirise_style_valid_minimum_and_polar_stereographic() {
    // A HiRISE-style DTM label: PC_REAL, MISSING_CONSTANT 16#FF7FFFFB#, VALID_MINIMUM
    // −8000 (values below it are fill, here −1e30), polar stereographic at the south
    // pole with metre cells.
    let label = "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 12\r\n\
        ^IMAGE = \"HIRISE.IMG\"\r\nOBJECT = IMAGE\r\n  LINES = 2\r\n  LINE_SAMPLES = 3\r\n\
        SAMPLE_TYPE = PC_REAL\r\n  SAMPLE_BITS = 32\r\n  MISSING_CONSTANT = 16#FF7FFFFB#\r\n\
        VALID_MINIMUM = -8000.0\r\n  VALID_MAXIMUM = 30000.0\r\nEND_OBJECT = IMAGE\r\n\
        OBJECT = IMAGE_MAP_PROJECTION\r\n  MAP_PROJECTION_TYPE = \"POLAR STEREOGRAPHIC\"\r\n\
        A_AXIS_RADIUS = 3396.19 <KM>\r\n  B_AXIS_RADIUS = 3376.2 <KM>\r\n  MAP_SCALE = 1.0 <METERS/PIXEL>\r\n\
        CENTER_LATITUDE = -90.0 <DEGREE>\r\n  CENTER_LONGITUDE = 0.0 <DEGREE>\r\n\
        LINE_PROJECTION_OFFSET = 100.5 <PIXEL>\r\n  SAMPLE_PROJECTION_OFFSET = -50.5 <PIXEL>\r\n\
        END_OBJECT = IMAGE_MAP_PROJECTION\r\nEND\r\n";
    let mut img = Vec::new();
    for v in [-4100.25f32, -1e30, -4099.0, f32::from_bits(0xFF7F_FFFB), 31000.0, -4098.5] {
        img.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(tmp("HIRISE.IMG"), &img).unwrap();
    std::fs::write(tmp("HIRISE.LBL"), label.as_bytes()).unwrap();
    let dem = pds3::read(&tmp("HIRISE.LBL")).unwrap();
    assert_eq!(dem.z(0, 0), Some(-4100.25));
    assert_eq!(dem.z(1, 0), None, "below VALID_MINIMUM");
    assert_eq!(dem.z(0, 1), None, "MISSING_CONSTANT");
    assert_eq!(dem.z(1, 1), None, "above VALID_MAXIMUM");
    assert_eq!(dem.z(2, 1), Some(-4098.5));
    assert_eq!((dem.dx(), dem.dy()), (1.0, 1.0));
    assert!(matches!(dem.georef().projection, Projection::PolarStereographic { north: false, .. }));
}

fn tiff_bytes() -> Vec<u8> {
    let path = tmp("prop.tif");
    geotiff::write(&sample_dem(), &path).unwrap();
    std::fs::read(path).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn readers_never_panic_on_random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        let _ = geotiff::read_from(std::io::Cursor::new(bytes.clone()), Path::new("random.tif"));
        let _ = ascii::parse(&String::from_utf8_lossy(&bytes), Path::new("random.asc"));
        let _ = pds3::parse(&bytes, None, Path::new("random.img"), None);
        let mut labelled = pds_label("2", "MSB_INTEGER", 16, "").into_bytes();
        labelled.extend_from_slice(&bytes);
        let _ = pds3::parse(&labelled, None, Path::new("random.img"), None);
    }

    #[test]
    fn readers_never_panic_on_truncated_or_corrupted_files(cut in 0usize..2000, flip in 0usize..2000, byte in any::<u8>()) {
        let mut bytes = tiff_bytes();
        let n = bytes.len();
        if flip < n {
            bytes[flip] = byte;
        }
        bytes.truncate(cut.min(n));
        let r = geotiff::read_from(std::io::Cursor::new(bytes), Path::new("cut.tif"));
        if let Err(e) = r {
            prop_assert!(e.to_string().contains("cut.tif"));
        }
        let text = std::fs::read_to_string({ let p = tmp("prop.asc"); ascii::write(&sample_dem(), &p).unwrap(); p }).unwrap();
        let _ = ascii::parse(&text[..cut.min(text.len())], Path::new("cut.asc"));
    }
}

/// A little-endian tiled TIFF built by hand: `cols` × `rows` uint16 samples in 16 × 16
/// tiles (the edge tiles padded, as the format requires), ModelPixelScale,
/// ModelTiepoint and GDAL_NODATA.
fn tiled_uint16_tiff(cols: u32, rows: u32, value: impl Fn(u32, u32) -> u16, nodata: &str) -> Vec<u8> {
    tiled_uint16_tiff_compressed(cols, rows, value, nodata, 1)
}

/// The side of [`tiled_uint16_tiff`]'s tiles.
const TILE: u32 = 16;

/// The tiles of a `cols` × `rows` image of `value`, row by row, each packed with
/// `compression` (see [`tiled_uint16_tiff_compressed`]), and each tile's size in bytes.
fn packed_tiles(cols: u32, rows: u32, value: impl Fn(u32, u32) -> u16, compression: u32) -> (Vec<u8>, Vec<usize>) {
    let (across, down) = (cols.div_ceil(TILE), rows.div_ceil(TILE));
    let (mut tiles, mut sizes) = (Vec::new(), Vec::new());
    for ty in 0..down {
        for tx in 0..across {
            let mut raw = Vec::new();
            for y in 0..TILE {
                for x in 0..TILE {
                    let (c, r) = (tx * TILE + x, ty * TILE + y);
                    let v = if c < cols && r < rows { value(c, r) } else { 0 };
                    raw.extend_from_slice(&v.to_le_bytes());
                }
            }
            let packed = match compression {
                5 => weezl::encode::Encoder::with_tiff_size_switch(weezl::BitOrder::Msb, 8).encode(&raw).unwrap(),
                8 => {
                    use std::io::Write;
                    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
                    z.write_all(&raw).unwrap();
                    z.finish().unwrap()
                }
                50000 => zstd::encode_all(&raw[..], 3).unwrap(),
                _ => raw,
            };
            sizes.push(packed.len());
            tiles.extend_from_slice(&packed);
        }
    }
    (tiles, sizes)
}

/// [`tiled_uint16_tiff`] with each tile compressed: 1 none, 5 LZW (MSB-first codes,
/// as TIFF 6.0 specifies), 8 deflate (zlib stream, Adobe's code), 50000 Zstandard
/// (GDAL's `COMPRESS=ZSTD`).
fn tiled_uint16_tiff_compressed(
    cols: u32,
    rows: u32,
    value: impl Fn(u32, u32) -> u16,
    nodata: &str,
    compression: u32,
) -> Vec<u8> {
    let (tiles, sizes) = packed_tiles(cols, rows, value, compression);
    let n_tiles = sizes.len();
    let scale: Vec<u8> = [2.0f64, 3.0, 0.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let tie: Vec<u8> = [0.0f64, 0.0, 0.0, 1000.0, 5000.0, 0.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut ascii = nodata.as_bytes().to_vec();
    ascii.push(0);
    // Layout: header, pixel data, out-of-line values, IFD.
    let data_at = 8usize;
    let offsets_at = data_at + tiles.len();
    let counts_at = offsets_at + 4 * n_tiles;
    let scale_at = counts_at + 4 * n_tiles;
    let tie_at = scale_at + scale.len();
    let ascii_at = tie_at + tie.len();
    let ifd_at = (ascii_at + ascii.len()).next_multiple_of(2);
    let mut out = Vec::new();
    out.extend_from_slice(b"II");
    out.extend_from_slice(&42u16.to_le_bytes());
    out.extend_from_slice(&(ifd_at as u32).to_le_bytes());
    out.extend_from_slice(&tiles);
    let mut at = data_at;
    for size in &sizes {
        out.extend_from_slice(&(at as u32).to_le_bytes());
        at += size;
    }
    for size in &sizes {
        out.extend_from_slice(&(*size as u32).to_le_bytes());
    }
    out.extend_from_slice(&scale);
    out.extend_from_slice(&tie);
    out.extend_from_slice(&ascii);
    out.resize(ifd_at, 0);
    // (tag, type, count, value or offset): SHORT 3, LONG 4, DOUBLE 12, ASCII 2.
    let entries: [(u16, u16, u32, u32); 15] = [
        (256, 4, 1, cols),
        (257, 4, 1, rows),
        (258, 3, 1, 16),
        (259, 3, 1, compression),
        (262, 3, 1, 1),
        (277, 3, 1, 1),
        (284, 3, 1, 1),
        (322, 3, 1, TILE),
        (323, 3, 1, TILE),
        (324, 4, n_tiles as u32, offsets_at as u32),
        (325, 4, n_tiles as u32, counts_at as u32),
        (339, 3, 1, 1),
        (33550, 12, 3, scale_at as u32),
        (33922, 12, 6, tie_at as u32),
        (42113, 2, ascii.len() as u32, ascii_at as u32),
    ];
    out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    for (tag, kind, count, value) in entries {
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&count.to_le_bytes());
        out.extend_from_slice(&value.to_le_bytes());
    }
    out.extend_from_slice(&0u32.to_le_bytes());
    out
}

#[test]
fn tiled_uint16_geotiff_with_nodata_loads() {
    // 37 × 21: three tiles across and two down, the last of each partly padding.
    let value = |c: u32, r: u32| if (c, r) == (5, 17) { 65535 } else { (c * 100 + r) as u16 };
    let path = tmp("tiled_u16.tif");
    std::fs::write(&path, tiled_uint16_tiff(37, 21, value, "65535")).unwrap();
    let dem = geotiff::read(&path).unwrap();
    assert_eq!((dem.cols(), dem.rows(), dem.dx(), dem.dy()), (37, 21, 2.0, 3.0));
    assert_eq!((dem.x0(), dem.y_top()), (1000.0, 5000.0));
    for r in 0..21 {
        for c in 0..37 {
            let want = if (c, r) == (5, 17) { None } else { Some((c * 100 + r) as f32) };
            assert_eq!(dem.z(c as usize, r as usize), want, "({c}, {r})");
        }
    }
    assert_eq!(dem.valid_mask().iter().filter(|v| !**v).count(), 1);
}

#[test]
fn windows_of_tiled_and_stripped_geotiffs_equal_crops_of_the_whole() {
    // The hand-built 16 × 16-tiled file (padded edge tiles), and the Gale crop as our
    // writer stores it (strips), read through windows of every awkward shape.
    let value = |c: u32, r: u32| if (c, r) == (5, 17) { 65535 } else { (c * 100 + r) as u16 };
    let tiled = tmp("tiled_u16_windows.tif");
    std::fs::write(&tiled, tiled_uint16_tiff(37, 21, value, "65535")).unwrap();
    for path in [tiled, data("gale_mola_crop_64.tif")] {
        let whole = geotiff::read(&path).unwrap();
        // A budget of one chunk: every window evicts and re-reads.
        for budget in [1usize, 1 << 20] {
            let mut w = geotiff::Windows::open(&path, budget).unwrap();
            assert_eq!(w.size(), (whole.cols(), whole.rows()));
            for (c0, r0, c, r) in
                [(0, 0, 1, 1), (3, 2, 17, 19), (15, 15, 2, 2), (16, 0, 5, 21), (0, 5, 37, 1), (20, 4, 17, 17)]
            {
                let (c, r) = (c.min(whole.cols() - c0), r.min(whole.rows() - r0));
                let got = w.read(c0, r0, c, r).unwrap();
                let want = whole.crop(c0, r0, c, r).unwrap();
                assert_eq!(got.valid_mask(), want.valid_mask(), "{}: window ({c0}, {r0}) {c} x {r}", path.display());
                let same =
                    got.elevations().iter().zip(want.elevations()).all(|(a, b)| a == b || (a.is_nan() && b.is_nan()));
                assert!(same, "{}: window ({c0}, {r0}) {c} x {r}", path.display());
                assert_eq!((got.x0(), got.y_top(), got.georef()), (want.x0(), want.y_top(), want.georef()));
            }
        }
        let mut w = geotiff::Windows::open(&path, 1 << 20).unwrap();
        assert!(w.read(60, 0, 10, 1).is_err(), "a window past the edge is an error, not a panic");
    }
}

#[test]
fn deflate_lzw_and_zstd_tiles_read_whole_and_through_windows() {
    let value = |c: u32, r: u32| if (c, r) == (30, 3) { 65535 } else { (c * 37 + r * 11) as u16 };
    // Zstandard: GDAL writes it for `COMPRESS=ZSTD`, common on recent DTMs.
    for (compression, name) in [(8, "deflate"), (5, "lzw"), (50000, "zstd")] {
        let path = tmp(&format!("tiled_{name}.tif"));
        let bytes = tiled_uint16_tiff_compressed(37, 21, value, "65535", compression);
        assert!(bytes.len() < tiled_uint16_tiff(37, 21, value, "65535").len(), "{name}: the tiles are compressed");
        std::fs::write(&path, bytes).unwrap();
        let dem = geotiff::read(&path).unwrap();
        for r in 0..21 {
            for c in 0..37 {
                let want = if (c, r) == (30, 3) { None } else { Some((c * 37 + r * 11) as f32) };
                assert_eq!(dem.z(c as usize, r as usize), want, "{name} ({c}, {r})");
            }
        }
        let mut w = geotiff::Windows::open(&path, 1).unwrap();
        let win = w.read(14, 2, 20, 17).unwrap();
        assert_eq!(win.elevations().len(), 20 * 17);
        assert_eq!(win.z(0, 0), dem.z(14, 2));
        assert_eq!(win.z(16, 1), None, "{name}: nodata inside a window");
    }
}

/// A grid in longitude and latitude (GDAL: `+proj=longlat`, as MOLA and LOLA products
/// come) is the same cells in metres on the equirectangular grid at its middle latitude:
/// every cell centre at the latitude and longitude of the projected crop's, 1/128° of
/// latitude 463.0577 m (the MEGDR's README), east–west true at the middle. Before,
/// degrees were read as metres (cells of 0.0078 m).
#[test]
fn a_longitude_latitude_grid_reads_as_metres_at_its_middle_latitude() {
    let plain = geotiff::read(&data("gale_mola_crop_64.tif")).unwrap();
    let lonlat = geotiff::read(&data("gale_mola_crop_64_lonlat.tif")).unwrap();
    assert!((lonlat.dy() - 463.0577).abs() < 1e-3, "{}", lonlat.dy());
    let middle: f64 = -5.0234375 - 32.0 / 128.0;
    assert!((lonlat.dx() - 463.0577 * middle.to_radians().cos()).abs() < 1e-3, "{}", lonlat.dx());
    for (c, r) in [(0, 0), (63, 0), (0, 63), (63, 63), (17, 40)] {
        let (x, y) = plain.cell_center(c, r);
        let (lat, lon) = plain.geographic(x, y).unwrap();
        let (x, y) = lonlat.cell_center(c, r);
        let (lat2, lon2) = lonlat.geographic(x, y).unwrap();
        assert!((lat - lat2).abs() < 1e-9 && (lon - lon2).abs() < 1e-9, "({c}, {r}): {lat}, {lon} vs {lat2}, {lon2}");
        assert_eq!(plain.z(c, r), lonlat.z(c, r));
    }
    // The corner the file ties, by the MEGDR's own numbers: column 400, row 400 of the
    // window that starts at 134.296875° E, 1.8984375° S, 1/128° per cell.
    let (lat, lon) = lonlat.geographic(lonlat.x0(), lonlat.y_top()).unwrap();
    assert!((lat - (-1.8984375 - 400.0 / 128.0)).abs() < 1e-9 && (lon - (134.296875 + 400.0 / 128.0)).abs() < 1e-9);
    // Windows read it the same way.
    let mut w = geotiff::Windows::open(&data("gale_mola_crop_64_lonlat.tif"), 1 << 20).unwrap();
    let win = w.read(5, 6, 10, 10).unwrap();
    assert_eq!((win.dx(), win.dy()), (lonlat.dx(), lonlat.dy()));
    let (a, b) = (win.cell_center(0, 0), lonlat.cell_center(5, 6));
    assert!((a.0 - b.0).abs() < 1e-6 && (a.1 - b.1).abs() < 1e-6, "{a:?} vs {b:?}");
    assert_eq!(win.z(3, 4), lonlat.z(8, 10));
    // A polar grid in degrees would be 98 % off at its edge: refused, with what to do;
    // so is a projected grid in kilometres.
    let polar = geotiff::read(&data("lonlat_polar_64.tif")).unwrap_err().to_string();
    assert!(polar.contains("off by up to 98.0 %") && polar.contains("+proj=stere"), "{polar}");
    let km = geotiff::read(&data("eqc_km_64.tif")).unwrap_err().to_string();
    assert!(km.contains("linear unit 9036") && km.contains("metres"), "{km}");
}

/// An equirectangular map whose standard parallel is the equator (a global mosaic's,
/// a MEGDR tile's) cropped at 40° N: its map metres are 1/cos 40° = 1.31 ground metres
/// east–west. It reads as the same cells at true scale, relabelled at its middle
/// latitude (not 31 % stretched in slopes, shadows and drives); a map
/// within 1 % of its standard parallel stays as written; one too tall for one scale is
/// refused with what to do; a PDS3 label reads alike.
#[test]
fn an_equirectangular_map_far_from_its_standard_parallel_reads_at_true_scale() {
    let plain = geotiff::read(&data("gale_mola_crop_64.tif")).unwrap();
    let far = geotiff::read(&data("eqc_lat_ts0_at40n_64.tif")).unwrap();
    // Relabelled at its middle latitude, 40° (to the millimetres GDAL was given).
    let Projection::Equirectangular { lat_ts_deg, lon0_deg } = far.georef().projection else { panic!() };
    assert!((lat_ts_deg - 40.0).abs() < 1e-7 && lon0_deg == 0.0, "{lat_ts_deg}");
    assert!((far.dx() - 463.0577 * 40f64.to_radians().cos()).abs() < 1e-3, "{}", far.dx());
    assert!((far.dy() - 463.0577).abs() < 1e-3);
    // GDAL's own numbers (gdalinfo, and gdalwarp to lat_ts = 40): the corner at
    // 137.4° E, 40.25° N, which is x = 6 238 579.998 m at true scale at 40°.
    assert!((far.x0() - 6_238_579.998).abs() < 0.01, "{}", far.x0());
    let (lat, lon) = far.geographic(far.x0(), far.y_top()).unwrap();
    assert!((lat - 40.25).abs() < 1e-7 && (lon - 137.4).abs() < 1e-7, "{lat}, {lon}");
    let (lat, lon) = far.geographic(far.x0() + 64.0 * far.dx(), far.y_top() - 64.0 * far.dy()).unwrap();
    assert!((lat - 39.75).abs() < 1e-7 && (lon - 137.9).abs() < 1e-7, "{lat}, {lon}");
    for (c, r) in [(0, 0), (63, 63), (17, 40)] {
        assert_eq!(far.z(c, r), plain.z(c, r));
    }
    // Windows read it the same way.
    let mut w = geotiff::Windows::open(&data("eqc_lat_ts0_at40n_64.tif"), 1 << 20).unwrap();
    let win = w.read(5, 6, 10, 10).unwrap();
    let (a, b) = (win.cell_center(0, 0), far.cell_center(5, 6));
    assert!((win.dx() - far.dx()).abs() < 1e-9 && (a.0 - b.0).abs() < 1e-6 && (a.1 - b.1).abs() < 1e-6);
    // Gale's crop: its standard parallel (−5.40°) is 0.02 % from its middle: as written.
    assert_eq!(plain.georef().projection, Projection::Equirectangular { lat_ts_deg: -5.40234375, lon0_deg: 0.0 });
    // 20° to 60° N on one standard parallel: no one scale holds it.
    let tall = tmp("eqc_tall.tif");
    let r = 3_396_000.0f64;
    let dem = Dem::new(64, 64, 40_000.0, (r * 40f64.to_radians()) / 64.0, 0.0, r * 60f64.to_radians(), vec![0.0; 4096])
        .unwrap()
        .with_georef(Georef {
            projection: Projection::Equirectangular { lat_ts_deg: 0.0, lon0_deg: 0.0 },
            surface: Spheroid::MARS_MOLA_SPHERE,
        });
    geotiff::write(&dem, &tall).unwrap();
    let e = geotiff::read(&tall).unwrap_err().to_string();
    assert!(e.contains("standard parallel at 0°") && e.contains("reproject it first"), "{e}");
    // A MEGDR-style PDS3 label (CENTER_LATITUDE = 0) placed at 40° N.
    let label = pds_label("2", "MSB_INTEGER", 16, "").replace(
        "LINE_PROJECTION_OFFSET = -10.5",
        &format!("LINE_PROJECTION_OFFSET = {}", r * 40f64.to_radians() / 463.0 + 0.5),
    );
    let mut bytes = label.into_bytes();
    bytes.resize(1024, b' ');
    for v in [10i16, 20, 30, 40, 50, 60] {
        bytes.extend_from_slice(&v.to_be_bytes());
    }
    let path = tmp("megdr_40n.IMG");
    std::fs::write(&path, &bytes).unwrap();
    let pds = pds3::read(&path).unwrap();
    let Projection::Equirectangular { lat_ts_deg, lon0_deg } = pds.georef().projection else { panic!() };
    // Its middle latitude: 40° less one row of 463 m.
    assert!((lat_ts_deg - (40.0 - (463.0 / r).to_degrees())).abs() < 1e-9 && lon0_deg == 90.0, "{lat_ts_deg}");
    assert!((pds.dx() - 463.0 * lat_ts_deg.to_radians().cos()).abs() < 1e-6 && pds.dy() == 463.0, "{}", pds.dx());
    let (lat, lon) = pds.geographic(pds.x0(), pds.y_top()).unwrap();
    assert!(
        (lat - 40.0).abs() < 1e-9
            && (lon - (90.0 + (0.5 - 20.5) * 463.0 / r * 180.0 / std::f64::consts::PI)).abs() < 1e-9
    );
}

/// A terrestrial CRS named only by its EPSG code (UTM zone 16 N, EPSG:32616, as GDAL
/// writes it) is the Earth's WGS84, not Mars (the default for a map with no axes),
/// whose sphere would make `terrain info` say "Mars" and shadows drop away. Its transverse Mercator is not read: a local frame, and
/// the reader says so.
#[test]
fn an_epsg_coded_map_is_on_the_earth() {
    let utm = geotiff::read(&data("utm16n_epsg_64.tif")).unwrap();
    assert_eq!(utm.georef().surface, Spheroid::EARTH_WGS84);
    assert_eq!(utm.georef().projection, Projection::Local);
    assert_eq!((utm.dx(), utm.x0(), utm.y_top()), (100.0, 400_000.0, 8_370_000.0));
    // What was not read is said, for reports to pass on.
    let w = geotiff::Windows::open(&data("utm16n_epsg_64.tif"), 1 << 20).unwrap();
    assert_eq!(w.crs_not_read(), Some("EPSG:32616, UTM zone 16 N"));
    let w = geotiff::Windows::open(&data("gale_mola_crop_64.tif"), 1 << 20).unwrap();
    assert_eq!(w.crs_not_read(), None);
    // A user-defined CRS with no axes stays on the default body, Mars.
    let plain = geotiff::read(&data("gale_mola_crop_64.tif")).unwrap();
    assert_eq!(plain.georef().surface.body(), Some(areo_body::Body::Mars));
}

/// An ESRI ASCII grid in degrees with GDAL's `.prj` beside it (a WKT GEOGCS) reads as
/// the geographic GeoTIFF of the same cells does; without the `.prj` it stays in its
/// own units with no place on a body, and a GEOGCS with no sphere is refused by name.
#[test]
fn an_ascii_grid_in_degrees_with_its_prj_reads_as_the_geographic_geotiff() {
    let lonlat = geotiff::read(&data("gale_mola_crop_64_lonlat.tif")).unwrap();
    let mut text = String::from("ncols 64\nnrows 64\nxllcorner 137.421875\nyllcorner -5.5234375\ncellsize 0.0078125\n");
    for r in 0..64 {
        let row: Vec<String> = (0..64).map(|c| lonlat.z(c, r).unwrap().to_string()).collect();
        text.push_str(&row.join(" "));
        text.push('\n');
    }
    let asc = tmp("lonlat_64.asc");
    std::fs::write(&asc, &text).unwrap();
    let prj = asc.with_extension("prj");
    let _ = std::fs::remove_file(&prj);
    let bare = ascii::read(&asc).unwrap();
    assert_eq!((bare.dx(), bare.georef().projection), (0.0078125, Projection::Local));
    std::fs::write(
        &prj,
        r#"GEOGCS["GCS_unknown",DATUM["D_unknown",SPHEROID["unknown",3396000.0,0.0]],PRIMEM["Reference_meridian",0.0],UNIT["Degree",0.0174532925199433]]"#,
    )
    .unwrap();
    let dem = ascii::read(&asc).unwrap();
    assert_eq!(dem.georef(), lonlat.georef());
    for (a, b) in
        [(dem.dx(), lonlat.dx()), (dem.dy(), lonlat.dy()), (dem.x0(), lonlat.x0()), (dem.y_top(), lonlat.y_top())]
    {
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }
    assert_eq!(dem.elevations(), lonlat.elevations());
    std::fs::write(&prj, r#"GEOGCS["GCS_unknown",DATUM["D_unknown"],UNIT["Degree",0.0174532925199433]]"#).unwrap();
    let err = ascii::read(&asc).unwrap_err().to_string();
    assert!(err.contains("lonlat_64.prj") && err.contains("SPHEROID"), "{err}");
    std::fs::remove_file(&prj).unwrap();
}

/// A scheme areo does not decode is named, with what to do, by both readers (the
/// decoder alone said "Unknown(34887) is unsupported").
#[test]
fn an_unread_compression_is_named_with_a_remedy() {
    let value = |c: u32, r: u32| (c + r) as u16;
    for (compression, name) in [(34887, "LERC"), (34925, "LZMA"), (7, "JPEG")] {
        let path = tmp(&format!("tiled_{name}.tif"));
        std::fs::write(&path, tiled_uint16_tiff_compressed(20, 20, value, "65535", compression)).unwrap();
        let whole = geotiff::read(&path).unwrap_err().to_string();
        let windows = geotiff::Windows::open(&path, 1).expect_err("refused").to_string();
        for message in [whole, windows] {
            assert!(message.contains(&format!("compression {compression} ({name})")), "{message}");
            assert!(message.contains("gdal_translate -co COMPRESS=DEFLATE"), "{message}");
            assert!(message.contains(&path.display().to_string()), "{message}");
        }
    }
}

/// GDAL's own compressed outputs of the 64-cell Gale crop (tests/data/README.md):
/// floating-point and horizontal predictors, int16 samples, Zstandard tiles — each
/// reads back as the uncompressed file, cell for cell, with its georeference.
#[test]
fn gdal_compressed_geotiffs_read_as_the_uncompressed_one() {
    let plain = geotiff::read(&data("gale_mola_crop_64.tif")).unwrap();
    for name in
        ["gale_mola_crop_64_deflate_fp.tif", "gale_mola_crop_64_lzw_int16.tif", "gale_mola_crop_64_zstd_tiled.tif"]
    {
        let dem = geotiff::read(&data(name)).unwrap();
        assert_eq!((dem.cols(), dem.rows()), (64, 64), "{name}");
        assert_eq!(
            (dem.x0(), dem.y_top(), dem.dx(), dem.georef()),
            (plain.x0(), plain.y_top(), plain.dx(), plain.georef())
        );
        for r in 0..64 {
            for c in 0..64 {
                assert_eq!(dem.z(c, r), plain.z(c, r), "{name} ({c}, {r})");
            }
        }
        // Windows decode the same chunks.
        let mut w = geotiff::Windows::open(&data(name), 1 << 20).unwrap();
        let win = w.read(10, 20, 30, 25).unwrap();
        assert_eq!((win.z(0, 0), win.z(29, 24)), (plain.z(10, 20), plain.z(39, 44)), "{name}");
    }
}

#[test]
fn tiled_writes_read_back_as_tiff_and_bigtiff() {
    let dem = geotiff::read(&data("gale_mola_crop_64.tif")).unwrap();
    // 50 × 37 cells in 16-cell tiles: ragged tiles on the east and south edges.
    let grid = geotiff::Grid { cols: 50, rows: 37, ..geotiff::Grid::of(&dem) };
    let values: Vec<u8> = (0..50 * 37).map(|i| (i % 7) as u8).collect();
    for big in [false, true] {
        let path = tmp(if big { "tiles_big.tif" } else { "tiles.tif" });
        let mut bands = 0;
        let was_big = geotiff::write_u8_tiled(&grid, Some(255), 16, big, &path, |row0, band| {
            assert_eq!(row0, 16 * bands, "bands in order");
            bands += 1;
            band.copy_from_slice(&values[row0 * 50..][..band.len()]);
            Ok(())
        })
        .unwrap();
        assert_eq!((was_big, bands), (big, 3));
        let bytes = std::fs::read(&path).unwrap();
        // Classic TIFF says 42 in its header, BigTIFF 43.
        assert_eq!(bytes[2], if big { 43 } else { 42 });
        let mut dec = tiff::decoder::Decoder::new(std::fs::File::open(&path).unwrap()).unwrap();
        assert_eq!((dec.chunk_dimensions(), dec.tile_count().unwrap()), ((16, 16), 4 * 3), "a tiled file");
        let back = geotiff::read(&path).unwrap();
        assert_eq!((back.cols(), back.rows()), (50, 37));
        assert_eq!(
            (back.x0(), back.y_top(), back.dx(), back.georef()),
            (dem.x0(), dem.y_top(), dem.dx(), dem.georef())
        );
        for (i, v) in values.iter().enumerate() {
            assert_eq!(back.z(i % 50, i / 50), Some(f32::from(*v)), "cell {i}");
        }
        // And through windows, a chunk at a time.
        let mut win = geotiff::Windows::open(&path, 1 << 20).unwrap();
        let part = win.read(13, 9, 30, 20).unwrap();
        for r in 0..20 {
            for c in 0..30 {
                assert_eq!(part.z(c, r), Some(f32::from(values[(9 + r) * 50 + 13 + c])));
            }
        }
    }
    // Elevations with holes, float32.
    let path = tmp("tiles_f32.tif");
    let z = |i: usize| if i % 11 == 3 { f32::NAN } else { -2000.0 + i as f32 * 0.25 };
    geotiff::write_f32_tiled(&grid, 32, false, &path, |row0, band| {
        for (k, v) in band.iter_mut().enumerate() {
            *v = z(row0 * 50 + k);
        }
        Ok(())
    })
    .unwrap();
    let back = geotiff::read(&path).unwrap();
    for i in 0..50 * 37 {
        let want = if z(i).is_nan() { None } else { Some(z(i)) };
        assert_eq!(back.z(i % 50, i / 50), want, "cell {i}");
    }
    // A tile TIFF cannot hold is refused with the rule.
    let err = geotiff::write_u8_tiled(&grid, None, 20, false, &path, |_, _| Ok(())).unwrap_err().to_string();
    assert!(err.contains("multiple of 16"), "{err}");
}

/// The GeoTIFF's ASCII parameters (the citations GDAL turns into the CRS's names).
fn citations(path: &Path) -> String {
    let mut dec = tiff::decoder::Decoder::new(std::fs::File::open(path).unwrap()).unwrap();
    match dec.find_tag(tiff::tags::Tag::GeoAsciiParamsTag).unwrap() {
        Some(tiff::decoder::ifd::Value::Ascii(s)) => s,
        other => panic!("no GeoAsciiParams in {}: {other:?}", path.display()),
    }
}

/// A map placed on Mars's IAU 2015 ellipsoid is projected on the sphere of its
/// equatorial radius, so the GeoTIFF says that sphere and names it as the IAU 2015 CRS
/// database does ("Mars (2015) - Sphere / Ocentric"), in metres; other radii are named
/// by body and radius. Read back, the projection is the same and the surface the sphere
/// the projection used; a local frame keeps the body's two radii.
#[test]
fn geotiff_names_the_body_sphere_and_metres_it_was_projected_on() {
    let flat = Dem::from_fn(20, 10, 30.0, 30.0, |x, y| 0.01 * x - 0.02 * y).unwrap();
    let mars = flat.clone().placed_at(areo_terrain::Spheroid::MARS_IAU2015, -4.59, 137.44).unwrap();
    let path = tmp("mars-iau.tif");
    geotiff::write(&mars, &path).unwrap();
    let text = citations(&path);
    assert!(
        text.starts_with("Mars (2015) - Sphere / Ocentric / Equirectangular, lat_ts = -4.59, clon = 137.44|"),
        "{text}"
    );
    assert!(text.contains("|GCS Name = Mars (2015) - Sphere / Ocentric|Datum = Mars (2015) - Sphere|"), "{text}");
    let back = geotiff::read(&path).unwrap();
    assert_eq!(back.georef().projection, mars.georef().projection);
    assert_eq!(back.georef().surface.polar_radius_m, 3_396_190.0);
    // Same cells at the same places: the geographic position of a corner is unchanged.
    let (lat, lon) = mars.geographic(mars.x0(), mars.y_top()).unwrap();
    let (lat2, lon2) = back.geographic(back.x0(), back.y_top()).unwrap();
    assert!((lat - lat2).abs() < 1e-12 && (lon - lon2).abs() < 1e-12);

    let mola = sample_dem();
    let path = tmp("mola.tif");
    geotiff::write(&mola, &path).unwrap();
    assert!(citations(&path).contains("GCS Name = Mars - Sphere, R = 3396000 m / Ocentric|"), "{}", citations(&path));

    let moon = flat.clone().placed_at(areo_terrain::Spheroid::MOON, -89.5, 45.0).unwrap();
    let path = tmp("moon-pole.tif");
    geotiff::write(&moon, &path).unwrap();
    assert!(citations(&path).starts_with("Moon (2015) - Sphere / Ocentric / South Polar Stereographic, clon = 45|"));

    let local =
        flat.with_georef(Georef { projection: Projection::Local, surface: areo_terrain::Spheroid::MARS_IAU2015 });
    let path = tmp("local.tif");
    geotiff::write(&local, &path).unwrap();
    assert!(citations(&path).starts_with("areo local frame on Mars, metres|"), "{}", citations(&path));
    assert_eq!(geotiff::read(&path).unwrap().georef(), local.georef());
}

/// A 3 × 2 TIFF of `C` samples with a 10 m grid, plus `extra` tags, at `name`.
fn small_tiff<C: tiff::encoder::colortype::ColorType>(
    name: &str,
    data: &[C::Inner],
    extra: &[(u16, Vec<f64>)],
) -> PathBuf
where
    [C::Inner]: tiff::encoder::TiffValue,
{
    let path = tmp(name);
    let mut file = std::fs::File::create(&path).unwrap();
    let mut enc = tiff::encoder::TiffEncoder::new(&mut file).unwrap();
    let mut img = enc.new_image::<C>(3, 2).unwrap();
    let e = img.encoder();
    e.write_tag(tiff::tags::Tag::ModelPixelScaleTag, &[10.0, 10.0, 0.0][..]).unwrap();
    e.write_tag(tiff::tags::Tag::ModelTiepointTag, &[0.0, 0.0, 0.0, 100.0, 200.0, 0.0][..]).unwrap();
    for (tag, values) in extra {
        e.write_tag(tiff::tags::Tag::Unknown(*tag), &values[..]).unwrap();
    }
    img.write_data(data).unwrap();
    path
}

/// Unsigned 32-bit heights are read; a rotated grid (ModelTransformationTag) and 64-bit
/// integers are refused by name — by the whole-map reader and the window reader alike.
#[test]
fn tiff_sample_types_and_transformations_are_read_or_refused_by_name() {
    let heights = small_tiff::<tiff::encoder::colortype::Gray32>("u32.tif", &[1, 2, 3, 4, 5, 4_000_000], &[]);
    let dem = geotiff::read(&heights).unwrap();
    assert_eq!((dem.z(0, 0), dem.z(2, 1), dem.dx(), dem.x0()), (Some(1.0), Some(4_000_000.0), 10.0, 100.0));
    let rotated = small_tiff::<tiff::encoder::colortype::Gray32>(
        "rotated.tif",
        &[1, 2, 3, 4, 5, 6],
        &[(34264, vec![10.0, 1.0, 0.0, 100.0, 1.0, -10.0, 0.0, 200.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])],
    );
    for e in [geotiff::read(&rotated).unwrap_err(), geotiff::Windows::open(&rotated, 1 << 20).unwrap_err()] {
        assert!(e.to_string().contains("ModelTransformationTag"), "{e}");
    }
    let wide = small_tiff::<tiff::encoder::colortype::Gray64>("u64.tif", &[1, 2, 3, 4, 5, 6], &[]);
    for e in [geotiff::read(&wide).unwrap_err(), geotiff::Windows::open(&wide, 1 << 20).unwrap_err()] {
        assert!(e.to_string().contains("64-bit unsigned integer samples"), "{e}");
    }
}
