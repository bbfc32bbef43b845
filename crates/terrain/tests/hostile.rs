//! Every DEM reader on hostile bytes: random bytes, and valid files with
//! bytes flipped, overwritten or cut, must give a DEM or an error — never a panic, and
//! never an allocation larger than the file could fill.

use std::io::Cursor;
use std::path::Path;

use areo_terrain::{ascii, geotiff, pds3};
use proptest::prelude::*;

fn gale_tif() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gale_mola_crop_64.tif")).unwrap()
}

fn asc() -> Vec<u8> {
    let mut s = String::from("ncols 6\nnrows 4\nxllcorner 100\nyllcorner 200\ncellsize 10\nNODATA_value -9999\n");
    for r in 0..4 {
        let row: Vec<String> = (0..6).map(|c| format!("{}.5", (r * 6 + c) * 7 % 19)).collect();
        s += &(row.join(" ") + "\n");
    }
    s.into_bytes()
}

fn pds() -> Vec<u8> {
    let mut b = "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 512\r\nLABEL_RECORDS = 1\r\n\
         ^IMAGE = 2\r\nOBJECT = IMAGE\r\n  LINES = 3\r\n  LINE_SAMPLES = 4\r\n  SAMPLE_TYPE = MSB_INTEGER\r\n\
         SAMPLE_BITS = 16\r\n  LINE_PREFIX_BYTES = 0\r\n  MISSING_CONSTANT = -32768\r\nEND_OBJECT = IMAGE\r\n\
         OBJECT = IMAGE_MAP_PROJECTION\r\n  MAP_PROJECTION_TYPE = \"SIMPLE CYLINDRICAL\"\r\n\
         A_AXIS_RADIUS = 3396.0 <KM>\r\n  MAP_SCALE = 0.4630 <KM/PIXEL>\r\nEND_OBJECT = IMAGE_MAP_PROJECTION\r\nEND\r\n"
        .to_string()
        .into_bytes();
    b.resize(512, b' ');
    for i in 0..12i16 {
        b.extend_from_slice(&(i * 11 - 40).to_be_bytes());
    }
    b
}

/// Runs every reader on `bytes`; a panic fails the property.
fn read_all(bytes: &[u8]) {
    let p = Path::new("fuzz.bin");
    let _ = geotiff::read_from(Cursor::new(bytes), p);
    let _ = pds3::parse(bytes, None, p, None);
    if let Ok(text) = std::str::from_utf8(bytes) {
        let _ = ascii::parse(text, p);
    }
}

#[test]
fn the_seed_files_read() {
    assert!(geotiff::read_from(Cursor::new(gale_tif()), Path::new("g.tif")).is_ok());
    assert_eq!(ascii::parse(std::str::from_utf8(&asc()).unwrap(), Path::new("a.asc")).unwrap().cols(), 6);
    let dem = pds3::parse(&pds(), None, Path::new("p.img"), None).unwrap();
    assert_eq!((dem.cols(), dem.rows(), dem.z(1, 0), dem.z(3, 0)), (4, 3, Some(-29.0), Some(-7.0)));
}

#[test]
fn hostile_pds3_labels_are_errors() {
    let base = String::from_utf8(pds()[..512].to_vec()).unwrap();
    let data = pds()[512..].to_vec();
    for (from, to, says) in [
        ("LINE_PREFIX_BYTES = 0", "LINE_PREFIX_BYTES = 18446744073709551615", "LINE_PREFIX_BYTES"),
        ("^IMAGE = 2", "^IMAGE = 18446744073709551615", "^IMAGE"),
        ("SAMPLE_TYPE = MSB_INTEGER", "SAMPLE_TYPE = CHARACTER", "SAMPLE_TYPE"),
        ("MAP_SCALE = 0.4630 <KM/PIXEL>", "MAP_SCALE = -0.4630 <KM/PIXEL>", "MAP_SCALE"),
        ("MAP_SCALE = 0.4630 <KM/PIXEL>", "MAP_SCALE = NaN <KM/PIXEL>", "MAP_SCALE"),
        ("LINES = 3", "LINES = 3000000", "truncated"),
    ] {
        let label = base.replacen(from, to, 1);
        let mut bytes = label.into_bytes();
        bytes.resize(512.max(bytes.len()), b' ');
        bytes.extend_from_slice(&data);
        let err = pds3::parse(&bytes, None, Path::new("x.img"), None).unwrap_err().to_string();
        assert!(err.contains(says), "{to}: {err}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2048)) {
        read_all(&bytes);
    }

    #[test]
    fn damaged_files_never_panic(
        which in 0..3usize,
        edits in proptest::collection::vec((any::<u16>(), any::<u8>()), 1..12),
        cut in proptest::option::of(any::<u16>()),
    ) {
        let mut bytes = match which { 0 => gale_tif(), 1 => asc(), _ => pds() };
        for (at, v) in edits {
            // Headers matter most: half the edits land in the first 600 bytes.
            let span = if at % 2 == 0 { bytes.len().min(600) } else { bytes.len() };
            let i = at as usize % span;
            bytes[i] = v;
        }
        if let Some(c) = cut {
            bytes.truncate(c as usize % (bytes.len() + 1));
        }
        read_all(&bytes);
    }
}
