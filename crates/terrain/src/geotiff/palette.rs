//! Class maps with a colour table. A palette image's samples are the codes its colour
//! map colours (a class map GDAL or QGIS wrote with a colour table, areo's own
//! `classes.tif`), but the tiff crate decodes no palette image: its Photometric tag is
//! read as grey (BlackIsZero) instead, which leaves every sample the code it is.

/// TIFF's PhotometricInterpretation tag, and its values for grey and a palette.
const PHOTOMETRIC: u16 = 262;
const GREY: u16 = 1;
const PALETTE: u16 = 3;
/// TIFF's field type SHORT.
const SHORT: u64 = 3;

/// Rewrites, in a TIFF's bytes (classic or BigTIFF, either byte order), each image's
/// palette Photometric tag as grey. Bytes that are no TIFF, or a chain of images that
/// runs off the file, are left for the decoder to refuse.
pub(super) fn as_codes(bytes: &mut [u8]) {
    let little = match bytes.get(..2) {
        Some(b"II") => true,
        Some(b"MM") => false,
        _ => return,
    };
    let read = |b: &[u8], at: usize, n: usize| -> Option<u64> {
        let s = b.get(at..at.checked_add(n)?)?;
        let fold = |acc: u64, (i, &x): (usize, &u8)| acc | u64::from(x) << (8 * if little { i } else { n - 1 - i });
        Some(s.iter().enumerate().fold(0, fold))
    };
    // Classic TIFF: 4-byte offsets, 2-byte entry counts, 12-byte entries; BigTIFF: 8, 8, 20.
    let (offset, count, entry, value_at) = match read(bytes, 2, 2) {
        Some(42) => (4, 2, 12, 8),
        Some(43) => (8, 8, 20, 12),
        _ => return,
    };
    let Some(mut ifd) = read(bytes, offset, offset) else { return };
    // A chain that loops is cut after as many images as the file could hold.
    for _ in 0..bytes.len() / entry {
        let Ok(at) = usize::try_from(ifd) else { return };
        if at == 0 {
            return;
        }
        let Some(n) = read(bytes, at, count) else { return };
        for k in 0..n as usize {
            let e = at + count + k * entry;
            if read(bytes, e, 2) == Some(u64::from(PHOTOMETRIC))
                && read(bytes, e + 2, 2) == Some(SHORT)
                && read(bytes, e + value_at, 2) == Some(u64::from(PALETTE))
            {
                let grey = if little { GREY.to_le_bytes() } else { GREY.to_be_bytes() };
                bytes[e + value_at..e + value_at + 2].copy_from_slice(&grey);
            }
        }
        let Some(next) = read(bytes, at + count + n as usize * entry, offset) else { return };
        ifd = next;
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Band, Grid, read_values, write_cog_u8};
    use crate::{Georef, Projection, Spheroid};

    /// A class map written with a colour table reads back as its codes.
    #[test]
    fn a_palette_class_map_reads_as_its_codes() {
        let grid = Grid {
            cols: 5,
            rows: 3,
            dx: 10.0,
            dy: 10.0,
            x0: 0.0,
            y_top: 30.0,
            georef: Georef { projection: Projection::Local, surface: Spheroid::MARS_MOLA_SPHERE },
        };
        let codes: Vec<u8> = (0..15).map(|i| [1, 2, 3, 255][i % 4]).collect();
        let band = Band { description: "classes", unit: "", colours: &[(1, [0, 114, 178]), (2, [230, 159, 0])] };
        let path = std::env::temp_dir().join(format!("areo-palette-{}.tif", std::process::id()));
        write_cog_u8(&grid, &codes, Some(255), &band, &path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let photometric = tiff::decoder::Decoder::new(std::io::Cursor::new(&bytes))
            .unwrap()
            .get_tag_u32(tiff::tags::Tag::PhotometricInterpretation)
            .unwrap();
        assert_eq!(photometric, 3, "written as a palette image");
        let values = read_values(&path).unwrap();
        for (i, &code) in codes.iter().enumerate() {
            let expected = (code != 255).then_some(f64::from(code));
            assert_eq!(values.at(i % 5, i / 5), expected, "cell {i}");
        }
        let _ = std::fs::remove_file(&path);
    }
}
