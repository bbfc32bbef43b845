//! PDS3 images (`.IMG`) with an attached label or a detached `.LBL`: the format of
//! MOLA MEGDR, HiRISE and CTX DTMs.
//!
//! Read from the label: `RECORD_BYTES`, the `^IMAGE` pointer (a record number, a
//! `<BYTES>` offset, or a file name with either), and in `OBJECT = IMAGE`: `LINES`,
//! `LINE_SAMPLES`, `SAMPLE_TYPE` (MSB/LSB/PC/IEEE integers and reals), `SAMPLE_BITS`
//! (8, 16, 32, 64), `BANDS` (must be 1), `LINE_PREFIX_BYTES`/`LINE_SUFFIX_BYTES`,
//! `SCALING_FACTOR`, `OFFSET`, `MISSING_CONSTANT` (decimal or `16#…#` hex),
//! `VALID_MINIMUM`/`VALID_MAXIMUM` (stored values outside them are missing, as in HiRISE
//! DTMs); in
//! `OBJECT = IMAGE_MAP_PROJECTION`: `MAP_PROJECTION_TYPE` (equirectangular / simple
//! cylindrical, polar stereographic), `A_AXIS_RADIUS`, `B_AXIS_RADIUS`, `MAP_SCALE`
//! (`<KM/PIXEL>` or `<METERS/PIXEL>`), `MAP_RESOLUTION` (pixels/degree, when there is
//! no `MAP_SCALE`), `LINE_PROJECTION_OFFSET`, `SAMPLE_PROJECTION_OFFSET`,
//! `CENTER_LATITUDE`, `CENTER_LONGITUDE`. The projection offsets are read as the
//! 1-based (line, sample) pixel-centre coordinates of the projection origin, so the
//! upper-left corner is x = (0.5 − sample offset)·scale, y = (line offset − 0.5)·scale.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::dem::{Dem, Georef};
use crate::error::{Error, Result};
use crate::projection::Projection;
use crate::size::Size;
use areo_body::Spheroid;

/// The largest byte count or offset a label may give (1 TiB).
const MAX_BYTES: f64 = 1_099_511_627_776.0;

/// Reads a PDS3 image, its label attached or in a sibling `.LBL` (pass either file).
pub fn read(path: &Path) -> Result<Dem> {
    let io = |p: &Path, source| Error::Read { path: p.to_path_buf(), source };
    let bytes = crate::input::read(path, crate::input::RASTER_LIMIT).map_err(|e| io(path, e))?;
    let is_label = |b: &[u8]| {
        let head = String::from_utf8_lossy(&b[..b.len().min(4096)]).to_ascii_uppercase();
        head.trim_start().starts_with("PDS_VERSION_ID") || head.contains("^IMAGE")
    };
    if !is_label(&bytes) {
        // A bare image: look for its detached label.
        for ext in ["LBL", "lbl"] {
            let lbl = path.with_extension(ext);
            if lbl.exists() {
                let text = crate::input::read(&lbl, crate::input::TEXT_LIMIT).map_err(|e| io(&lbl, e))?;
                return parse(&text, Some(&bytes), &lbl, path.parent());
            }
        }
        return Err(Error::format(path, "no PDS3 label: neither attached nor a sibling .LBL"));
    }
    parse(&bytes, None, path, path.parent())
}

/// Every file reading `path` as a PDS3 image touches: the file itself, a sibling
/// detached label or image, and the file a label's `^IMAGE` names (so that no output
/// is written over any of them).
pub fn files_of(path: &Path) -> Vec<PathBuf> {
    let mut files = vec![path.to_path_buf()];
    for ext in ["LBL", "lbl", "IMG", "img"] {
        let sibling = path.with_extension(ext);
        if sibling.exists() {
            files.push(sibling);
        }
    }
    let labels: Vec<PathBuf> = files.clone();
    for label in labels {
        let Ok(bytes) = crate::input::read(&label, crate::input::TEXT_LIMIT) else { continue };
        let head = &bytes[..bytes.len().min(1 << 20)];
        if let Some(pointer) = Label::parse(head).get("", "^IMAGE")
            && let Some((Some(name), _)) = parse_pointer(pointer, 1)
        {
            let dir = label.parent().unwrap_or(Path::new("."));
            files.push(dir.join(&name));
            files.push(dir.join(name.to_lowercase()));
        }
    }
    files
}

/// Parses a label (and its attached data, or the `image` bytes if detached); `path`
/// labels errors and `dir` resolves a `^IMAGE` file name.
pub fn parse(label_bytes: &[u8], image: Option<&[u8]>, path: &Path, dir: Option<&Path>) -> Result<Dem> {
    let label = Label::parse(label_bytes);
    let f = Fields { label: &label, path };
    let layout = f.layout()?;
    let (file, offset) = f.image_file(layout.record_bytes)?;
    let owned;
    let data: &[u8] = match (file, image) {
        (Some(name), _) => {
            let p = dir.map_or_else(|| PathBuf::from(&name), |d| d.join(&name));
            let p = if p.exists() {
                p
            } else {
                dir.map_or_else(|| PathBuf::from(name.to_lowercase()), |d| d.join(name.to_lowercase()))
            };
            owned = crate::input::read(&p, crate::input::RASTER_LIMIT)
                .map_err(|source| Error::Read { path: p.clone(), source })?;
            &owned
        }
        (None, Some(img)) => img,
        (None, None) => label_bytes,
    };
    let (z, valid) = f.samples(&layout, data, offset)?;
    let (cols, rows) = (layout.cols, layout.rows);
    let ([dx, dy, x0, y_top], projection, body) = f.georeference(rows)?;
    Dem::new(cols, rows, dx, dy, x0, y_top, z)
        .and_then(|d| d.with_mask(valid))
        .map(|d| d.with_georef(Georef { projection, surface: body }))
        .map_err(|e| f.bad(e.to_string()))
}

/// How the samples lie in the image: its size, sample type, the bytes before and after
/// each line, and the record length that `^IMAGE` offsets count in.
struct ImageLayout {
    rows: usize,
    cols: usize,
    kind: SampleKind,
    prefix: u64,
    suffix: u64,
    record_bytes: u64,
}

/// A label's fields, read as numbers, with errors that name the file.
struct Fields<'a> {
    label: &'a Label,
    path: &'a Path,
}

impl Fields<'_> {
    fn bad(&self, m: String) -> Error {
        Error::format(self.path, m)
    }

    /// `key` of `obj` as a number (`None`: absent).
    fn num(&self, obj: &str, key: &str) -> Result<Option<f64>> {
        match self.label.get(obj, key) {
            None => Ok(None),
            Some(v) => parse_number(v).map(Some).ok_or_else(|| self.bad(format!("{key} = {v:?} is not a number"))),
        }
    }

    /// `key` of `obj` as a number, required.
    fn need(&self, obj: &str, key: &str) -> Result<f64> {
        self.num(obj, key)?.ok_or_else(|| self.bad(format!("label lacks {key}")))
    }

    /// A length of the map projection object in metres (labels give kilometres unless
    /// the unit says metres).
    fn km_or_m(&self, key: &str) -> Result<Option<f64>> {
        let Some(raw) = self.label.get("IMAGE_MAP_PROJECTION", key) else { return Ok(None) };
        let v = parse_number(raw).ok_or_else(|| self.bad(format!("{key} = {raw:?} is not a number")))?;
        let unit = raw.to_ascii_uppercase();
        Ok(Some(if unit.contains("<M") || unit.contains("METER") { v } else { v * 1000.0 }))
    }

    /// The image's size, sample type and line layout.
    fn layout(&self) -> Result<ImageLayout> {
        let lines = self.need("IMAGE", "LINES")?;
        let samples = self.need("IMAGE", "LINE_SAMPLES")?;
        let bits = self.need("IMAGE", "SAMPLE_BITS")?;
        let bands = self.num("IMAGE", "BANDS")?.unwrap_or(1.0);
        if bands != 1.0 {
            return Err(self.bad(format!("BANDS = {bands}; a DEM has one band")));
        }
        if !(lines >= 1.0 && samples >= 1.0 && lines * samples <= 4e9 && lines.fract() == 0.0 && samples.fract() == 0.0)
        {
            return Err(self.bad(format!("LINES = {lines}, LINE_SAMPLES = {samples}: need positive whole numbers")));
        }
        let (rows, cols) = (lines as usize, samples as usize);
        let sample_type = self
            .label
            .get("IMAGE", "SAMPLE_TYPE")
            .ok_or_else(|| self.bad("label lacks SAMPLE_TYPE".into()))?
            .trim_matches('"')
            .to_ascii_uppercase();
        let kind = SampleKind::from_label(&sample_type, bits).ok_or_else(|| {
            self.bad(format!(
                "SAMPLE_TYPE {sample_type} with SAMPLE_BITS {bits} is not read: allowed MSB_/LSB_/PC_/SUN_/MAC_ INTEGER or \
                 UNSIGNED_INTEGER of 8, 16 or 32 bits, IEEE_REAL or PC_REAL of 32 or 64 bits"
            ))
        })?;
        // Byte counts from the label: whole numbers up to 2^40, so no sum or product of them
        // can wrap.
        let count = |key: &str, value: Option<f64>, default: f64| -> Result<u64> {
            let v = value.unwrap_or(default);
            if (0.0..=MAX_BYTES).contains(&v) && v.fract() == 0.0 {
                Ok(v as u64)
            } else {
                Err(self.bad(format!("{key} = {v}: allowed a whole number of bytes, 0..=2^40")))
            }
        };
        let prefix = count("LINE_PREFIX_BYTES", self.num("IMAGE", "LINE_PREFIX_BYTES")?, 0.0)?;
        let suffix = count("LINE_SUFFIX_BYTES", self.num("IMAGE", "LINE_SUFFIX_BYTES")?, 0.0)?;
        let record_bytes = count("RECORD_BYTES", self.num("", "RECORD_BYTES")?, 1.0)?;
        Ok(ImageLayout { rows, cols, kind, prefix, suffix, record_bytes })
    }

    /// Where the pixels are: a detached file's name (`None`: in the label's own file or
    /// the bytes given) and the byte offset of the first line.
    fn image_file(&self, record_bytes: u64) -> Result<(Option<String>, u64)> {
        let pointer = self.label.get("", "^IMAGE").ok_or_else(|| self.bad("label lacks ^IMAGE".into()))?.to_string();
        let (file, offset) = parse_pointer(&pointer, record_bytes).ok_or_else(|| {
            self.bad(format!("cannot read ^IMAGE = {pointer}: need a record or byte offset ≥ 1, within 2^40 bytes"))
        })?;
        Ok((file, offset))
    }

    /// The samples of `data` from `offset`, scaled and offset, and which are valid.
    fn samples(&self, layout: &ImageLayout, data: &[u8], offset: u64) -> Result<(Vec<f32>, Vec<bool>)> {
        let (rows, cols, kind, prefix, suffix) = (layout.rows, layout.cols, layout.kind, layout.prefix, layout.suffix);
        let width = kind.bytes();
        let line_bytes = Size::new(prefix) + Size::from(cols) * Size::from(width) + Size::new(suffix);
        let needed = Size::new(offset) + Size::from(rows) * line_bytes;
        if !needed.at_most(data.len() as u64) {
            return Err(
                self.bad(format!("image truncated: {} bytes, {needed} needed for {cols} x {rows} samples", data.len()))
            );
        }
        // Both fit in the data's length, so in usize.
        let (Some(line_bytes), Some(offset)) = (line_bytes.as_usize(), Size::new(offset).as_usize()) else {
            return Err(self.bad(format!("^IMAGE offset {offset} and lines of {line_bytes} bytes: too large here")));
        };
        let scale = self.num("IMAGE", "SCALING_FACTOR")?.unwrap_or(1.0);
        let add = self.num("IMAGE", "OFFSET")?.unwrap_or(0.0);
        if !(scale.is_finite() && scale != 0.0 && add.is_finite()) {
            return Err(
                self.bad(format!("SCALING_FACTOR = {scale}, OFFSET = {add}: need finite values, a non-zero factor"))
            );
        }
        let missing = self.num("IMAGE", "MISSING_CONSTANT")?;
        // HiRISE DTMs also bound the good values: stored values outside
        // VALID_MINIMUM..=VALID_MAXIMUM are missing (their fill is −3.4028227e38).
        let (valid_min, valid_max) = (self.num("IMAGE", "VALID_MINIMUM")?, self.num("IMAGE", "VALID_MAXIMUM")?);
        let mut z = Vec::with_capacity(rows * cols);
        let mut valid = Vec::with_capacity(rows * cols);
        let prefix = prefix as usize;
        for r in 0..rows {
            let start = offset + r * line_bytes + prefix;
            for c in 0..cols {
                let raw = kind.decode(&data[start + c * width..start + (c + 1) * width]);
                let is_missing = missing.is_some_and(|m| raw == m || (kind.is_float() && (raw as f32) == (m as f32)))
                    || !raw.is_finite()
                    || valid_min.is_some_and(|v| raw < v)
                    || valid_max.is_some_and(|v| raw > v);
                valid.push(!is_missing);
                z.push(if is_missing { f32::NAN } else { (raw * scale + add) as f32 });
            }
        }
        Ok((z, valid))
    }

    /// The map's cell sizes and corner, projection and body from its map projection
    /// object (a local 1 m grid without one).
    #[allow(clippy::type_complexity)]
    fn georeference(&self, rows: usize) -> Result<([f64; 4], Projection, Spheroid)> {
        let proj_obj = "IMAGE_MAP_PROJECTION";
        let a = self.km_or_m("A_AXIS_RADIUS")?;
        let b = self.km_or_m("B_AXIS_RADIUS")?.or(a);
        let body = match (a, b) {
            (Some(a), Some(b)) if (1e3..=1e8).contains(&a) && (1e3..=1e8).contains(&b) => {
                Spheroid { equatorial_radius_m: a, polar_radius_m: b }
            }
            (None, None) => Spheroid::MARS_IAU2015,
            (a, b) => {
                return Err(self.bad(format!(
                    "A_AXIS_RADIUS = {a:?} m, B_AXIS_RADIUS = {b:?} m: allowed 1 km..=100 000 km (a body's radius)"
                )));
            }
        };
        let center_lat = self.num(proj_obj, "CENTER_LATITUDE")?.unwrap_or(0.0);
        let center_lon = self.num(proj_obj, "CENTER_LONGITUDE")?.unwrap_or(0.0);
        if !(center_lat.abs() <= 90.0 && center_lon.abs() <= 360.0) {
            return Err(self.bad(format!(
                "CENTER_LATITUDE = {center_lat}, CENTER_LONGITUDE = {center_lon}: allowed -90..=90 and -360..=360 degrees"
            )));
        }
        let map_scale_m = match self.km_or_m("MAP_SCALE")? {
            Some(s) => Some(s),
            None => match self.num(proj_obj, "MAP_RESOLUTION")? {
                Some(r) if r > 0.0 && r.is_finite() => {
                    Some(body.equatorial_radius_m * std::f64::consts::PI / 180.0 / r)
                }
                Some(r) => return Err(self.bad(format!("MAP_RESOLUTION = {r}: allowed > 0 pixels per degree"))),
                None => None,
            },
        };
        if let Some(s) = map_scale_m
            && !(1e-3..=1e7).contains(&s)
        {
            return Err(self.bad(format!("MAP_SCALE = {s} m: allowed 0.001..=1e7 m per pixel")));
        }
        let ptype =
            self.label.get(proj_obj, "MAP_PROJECTION_TYPE").unwrap_or("").trim_matches('"').to_ascii_uppercase();
        let projection = if ptype.contains("EQUIRECTANGULAR") || ptype.contains("SIMPLE CYLINDRICAL") {
            Projection::Equirectangular { lat_ts_deg: center_lat, lon0_deg: center_lon }
        } else if ptype.contains("POLAR STEREOGRAPHIC") {
            Projection::PolarStereographic { north: center_lat >= 0.0, lon0_deg: center_lon }
        } else {
            Projection::Local
        };
        let (dx, x0, y_top) = match map_scale_m {
            Some(s) if s > 0.0 => {
                let line_off = self.num(proj_obj, "LINE_PROJECTION_OFFSET")?.unwrap_or(0.0);
                let sample_off = self.num(proj_obj, "SAMPLE_PROJECTION_OFFSET")?.unwrap_or(0.0);
                (s, (0.5 - sample_off) * s, (line_off - 0.5) * s)
            }
            _ => (1.0, 0.0, rows as f64),
        };
        if !(x0.abs() <= 1e12 && y_top.abs() <= 1e12) {
            return Err(
                self.bad("LINE_PROJECTION_OFFSET, SAMPLE_PROJECTION_OFFSET: the map's corner is beyond 1e12 m".into())
            );
        }
        // A simple cylindrical map's MAP_SCALE holds at CENTER_LATITUDE (the equator for
        // MEGDR tiles): at true scale where that is far from the map.
        let ([dx, dy, x0, y_top], projection) = match projection {
            Projection::Equirectangular { lat_ts_deg, lon0_deg } => crate::projection::equirectangular_at_true_scale(
                rows,
                [dx, dx, x0, y_top],
                (lat_ts_deg, lon0_deg),
                &body,
            )
            .map_err(|m| self.bad(m))?,
            other => ([dx, dx, x0, y_top], other),
        };
        Ok(([dx, dy, x0, y_top], projection, body))
    }
}

fn parse_number(v: &str) -> Option<f64> {
    let v = v.trim().trim_matches('"');
    // Radix form 16#FF7FFFFB# (an IEEE float's bits, or an integer).
    if let Some(rest) = v.strip_prefix("16#") {
        let hex = rest.trim_end_matches('#');
        let bits = u64::from_str_radix(hex, 16).ok()?;
        return Some(if hex.len() == 8 { f64::from(f32::from_bits(bits as u32)) } else { bits as f64 });
    }
    let head = v.split(|c: char| c.is_whitespace() || c == '<').next()?;
    head.parse::<f64>().ok()
}

/// `^IMAGE` forms: `12`, `12 <BYTES>`, `"F.IMG"`, `("F.IMG", 12)`, `("F.IMG", 12 <BYTES>)`.
fn parse_pointer(v: &str, record_bytes: u64) -> Option<(Option<String>, u64)> {
    let v = v.trim().trim_start_matches('(').trim_end_matches(')');
    let mut parts = v.split(',').map(str::trim);
    let first = parts.next()?;
    let (file, loc) = if first.starts_with('"') {
        (Some(first.trim_matches('"').to_string()), parts.next())
    } else {
        (None, Some(first))
    };
    let offset = match loc {
        None => 0,
        Some(l) => {
            let n = parse_number(l)?;
            if !((1.0..=MAX_BYTES).contains(&n) && n.fract() == 0.0) {
                return None;
            }
            let n = n as u64 - 1;
            if l.to_ascii_uppercase().contains("<BYTES>") {
                n
            } else {
                n.checked_mul(record_bytes).filter(|o| *o as f64 <= MAX_BYTES)?
            }
        }
    };
    Some((file, offset))
}

#[derive(Debug, Clone, Copy)]
enum SampleKind {
    U8,
    I16 { big: bool },
    U16 { big: bool },
    I32 { big: bool },
    F32 { big: bool },
    F64 { big: bool },
}

impl SampleKind {
    fn from_label(t: &str, bits: f64) -> Option<SampleKind> {
        // The PDS3 data types a DEM can hold (Standards Reference, appendix C); VAX
        // reals are not IEEE and are refused with the rest.
        let (big, real, unsigned) = match t {
            "MSB_INTEGER" | "INTEGER" | "SUN_INTEGER" | "MAC_INTEGER" => (true, false, false),
            "MSB_UNSIGNED_INTEGER" | "UNSIGNED_INTEGER" | "SUN_UNSIGNED_INTEGER" | "MAC_UNSIGNED_INTEGER" => {
                (true, false, true)
            }
            "LSB_INTEGER" | "PC_INTEGER" | "VAX_INTEGER" => (false, false, false),
            "LSB_UNSIGNED_INTEGER" | "PC_UNSIGNED_INTEGER" | "VAX_UNSIGNED_INTEGER" => (false, false, true),
            "IEEE_REAL" | "SUN_REAL" | "MAC_REAL" | "FLOAT" | "REAL" => (true, true, false),
            "PC_REAL" => (false, true, false),
            _ => return None,
        };
        let bits = if [8.0, 16.0, 32.0, 64.0].contains(&bits) { bits as u32 } else { return None };
        Some(match (bits, real, unsigned) {
            (8, false, _) => SampleKind::U8,
            (16, false, false) => SampleKind::I16 { big },
            (16, false, true) => SampleKind::U16 { big },
            (32, false, false) => SampleKind::I32 { big },
            (32, true, _) => SampleKind::F32 { big },
            (64, true, _) => SampleKind::F64 { big },
            _ => return None,
        })
    }

    fn bytes(self) -> usize {
        match self {
            SampleKind::U8 => 1,
            SampleKind::I16 { .. } | SampleKind::U16 { .. } => 2,
            SampleKind::I32 { .. } | SampleKind::F32 { .. } => 4,
            SampleKind::F64 { .. } => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, SampleKind::F32 { .. } | SampleKind::F64 { .. })
    }

    fn decode(self, b: &[u8]) -> f64 {
        macro_rules! get {
            ($t:ty, $big:expr) => {{
                let a = b.try_into().unwrap_or_default();
                if $big { <$t>::from_be_bytes(a) } else { <$t>::from_le_bytes(a) }
            }};
        }
        match self {
            SampleKind::U8 => f64::from(b[0]),
            SampleKind::I16 { big } => f64::from(get!(i16, big)),
            SampleKind::U16 { big } => f64::from(get!(u16, big)),
            SampleKind::I32 { big } => f64::from(get!(i32, big)),
            SampleKind::F32 { big } => f64::from(get!(f32, big)),
            SampleKind::F64 { big } => get!(f64, big),
        }
    }
}

/// `KEY = VALUE` pairs by enclosing `OBJECT` ("" at the top level).
struct Label {
    values: HashMap<(String, String), String>,
}

impl Label {
    fn parse(bytes: &[u8]) -> Label {
        // The label ends at END on its own line; the rest is pixels.
        let head = &bytes[..bytes.len().min(1 << 20)];
        let text = String::from_utf8_lossy(head);
        let mut values = HashMap::new();
        let mut objects: Vec<String> = Vec::new();
        let mut lines = text.lines().peekable();
        while let Some(line) = lines.next() {
            let line = line.split("/*").next().unwrap_or("").trim();
            if line == "END" {
                break;
            }
            let Some((key, value)) = line.split_once('=') else { continue };
            let key = key.trim().to_ascii_uppercase();
            let mut value = value.trim().to_string();
            // Values in parentheses or quotes may run over several lines. The quotes are
            // counted as lines are added (not recounted), so an unclosed quote costs one
            // pass over the label, not one per line.
            let mut quotes = value.matches('"').count();
            while (value.starts_with('(') && !value.ends_with(')')) || (value.starts_with('"') && quotes % 2 == 1) {
                match lines.next() {
                    Some(more) => {
                        let more = more.trim();
                        quotes += more.matches('"').count();
                        value.push(' ');
                        value.push_str(more);
                    }
                    None => break,
                }
            }
            match key.as_str() {
                "OBJECT" => objects.push(value.to_ascii_uppercase()),
                "END_OBJECT" => {
                    objects.pop();
                }
                _ => {
                    let scope = objects.last().cloned().unwrap_or_default();
                    values.entry((scope, key)).or_insert(value);
                }
            }
        }
        Label { values }
    }

    fn get(&self, object: &str, key: &str) -> Option<&str> {
        self.values.get(&(object.to_string(), key.to_string())).map(String::as_str)
    }
}
