//! The digital elevation model and the `Ground` trait.

use crate::crs::GeographicCrs;
use crate::error::{Error, Result};
use crate::projection::Projection;
use areo_body::Spheroid;

/// Where a DEM sits: its map projection and reference body.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Georef {
    /// How map metres relate to latitude and longitude.
    pub projection: Projection,
    /// The reference surface (radius for curvature and projections).
    pub surface: Spheroid,
}

impl Georef {
    /// The geographic CRS the map's latitudes and longitudes are on: the sphere of the
    /// surface's equatorial radius that areo projects on.
    pub fn geographic(&self) -> GeographicCrs {
        GeographicCrs::of(&self.surface)
    }

    /// The map's coordinate reference system as OGC WKT2 (ISO 19162:2019), for GIS
    /// tools and Python users: the projection on a sphere of the body's equatorial
    /// radius (as areo projects), its geographic base the [`GeographicCrs`] of every
    /// file of a run (planetocentric, east longitude); a local engineering frame in
    /// metres for a map with none.
    pub fn wkt(&self) -> String {
        let deg = r#"ANGLEUNIT["degree",0.0174532925199433]"#;
        let m = r#"LENGTHUNIT["metre",1]"#;
        let axes =
            format!(r#"CS[Cartesian,2],AXIS["easting (E)",east,ORDER[1],{m}],AXIS["northing (N)",north,ORDER[2],{m}]"#);
        let crs = self.geographic();
        let base = format!(r#"BASEGEOGCRS["{}",{}]"#, crs.name, crs.datum_wkt2());
        let param =
            |name: &str, v: f64, unit: &str, id: u32| format!(r#"PARAMETER["{name}",{v},{unit},ID["EPSG",{id}]]"#);
        let origin = [param("False easting", 0.0, m, 8806), param("False northing", 0.0, m, 8807)].join(",");
        match self.projection.written() {
            Projection::Local => {
                format!(r#"ENGCRS["local metric frame",EDATUM["local"],{axes}]"#)
            }
            Projection::Equirectangular { lat_ts_deg, lon0_deg } => format!(
                r#"PROJCRS["{} / Equirectangular",{base},CONVERSION["Equirectangular",METHOD["Equidistant Cylindrical",ID["EPSG",1028]],{},{},{origin}],{axes}]"#,
                crs.name,
                param("Latitude of 1st standard parallel", lat_ts_deg, deg, 8823),
                param("Longitude of natural origin", lon0_deg, deg, 8802),
            ),
            Projection::PolarStereographic { north, lon0_deg } => format!(
                r#"PROJCRS["{} / {} Polar Stereographic",{base},CONVERSION["Polar stereographic",METHOD["Polar Stereographic (variant A)",ID["EPSG",9810]],{},{},{},{origin}],{axes}]"#,
                crs.name,
                if north { "North" } else { "South" },
                param("Latitude of natural origin", if north { 90.0 } else { -90.0 }, deg, 8801),
                param("Longitude of natural origin", lon0_deg, deg, 8802),
                param("Scale factor at natural origin", 1.0, r#"SCALEUNIT["unity",1]"#, 8805),
            ),
        }
    }
}

impl Default for Georef {
    fn default() -> Georef {
        Georef { projection: Projection::Local, surface: Spheroid::MARS_IAU2015 }
    }
}

/// A grid of elevations (m, f32) with a nodata mask.
///
/// Rows run north to south (row 0 is the northernmost), columns west to east. Cell
/// (col, row) is centred at x = x0 + (col + 0.5)·dx, y = y_top − (row + 0.5)·dy; dx and
/// dy may differ. Heights between cell centres are bilinear; within half a cell of the
/// Latitude (degrees, either hemisphere) from which [`Dem::placed_at`] places a map in
/// polar stereographic instead of equirectangular: where a cylindrical projection's
/// scale starts to change noticeably across a few kilometres.
pub const POLAR_PROJECTION_LAT_DEG: f64 = 80.0;

/// map edge the edge cells' values continue (each cell covers its whole square).
#[derive(Debug, Clone, PartialEq)]
pub struct Dem {
    cols: usize,
    rows: usize,
    dx: f64,
    dy: f64,
    x0: f64,
    y_top: f64,
    z: Vec<f32>,
    valid: Vec<bool>,
    /// Every cell valid: height queries skip the mask (they are the rover planner's
    /// inner loop).
    all_valid: bool,
    /// 1/dx and 1/dy, so queries multiply instead of divide.
    inv_dx: f64,
    inv_dy: f64,
    georef: Georef,
    /// The wheel–ground friction coefficient the ground sets cell by cell (its terrain
    /// classes), row-major like the heights; NaN where it sets none. Crops and
    /// resamplings do not carry it.
    friction: Option<std::sync::Arc<[f32]>>,
}

/// Something a rover can stand on: height and unit normal at (x, y), metres.
pub trait Ground {
    /// Height at (x, y), or `None` off the terrain or on missing data.
    fn height(&self, x: f64, y: f64) -> Option<f64>;
    /// Upward unit normal at (x, y), or `None` off the terrain or on missing data.
    fn normal(&self, x: f64, y: f64) -> Option<[f64; 3]>;

    /// Height at (x, y) and its slope along the horizontal unit vector `dir` (m per m),
    /// together because a rover's contact search needs both at every step. The default
    /// differentiates [`Ground::height`] numerically (±10 µm, one-sided at an edge);
    /// terrains with a cheap exact gradient override it.
    fn height_slope(&self, x: f64, y: f64, dir: (f64, f64)) -> Option<(f64, f64)> {
        let h = self.height(x, y)?;
        let e = 1e-5;
        let ahead = self.height(x + dir.0 * e, y + dir.1 * e);
        let behind = self.height(x - dir.0 * e, y - dir.1 * e);
        let slope = match (ahead, behind) {
            (Some(a), Some(b)) => (a - b) / (2.0 * e),
            (Some(a), None) => (a - h) / e,
            (None, Some(b)) => (h - b) / e,
            (None, None) => 0.0,
        };
        Some((h, slope))
    }

    /// The wheel–ground friction coefficient μ the ground itself sets at (x, y) — a
    /// terrain class's — or `None` where the motion's own μ holds (the default).
    fn friction(&self, _x: f64, _y: f64) -> Option<f64> {
        None
    }

    /// Heights at `out.len()` evenly spaced points (x0 + k·step.0, y0 + k·step.1), m —
    /// a wheel rim's samples along its line of travel. `false` if any point is off the
    /// terrain or on missing data (`out` is then unspecified). The default asks
    /// [`Ground::height`] per point; a DEM walks its grid without re-checking bounds.
    fn heights_along(&self, start: (f64, f64), step: (f64, f64), out: &mut [f64]) -> bool {
        for (k, h) in out.iter_mut().enumerate() {
            let t = k as f64;
            match self.height(start.0 + step.0 * t, start.1 + step.1 * t) {
                Some(z) => *h = z,
                None => return false,
            }
        }
        true
    }
}

/// A DEM's edges in its frame, metres (x east, y north).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    /// The west edge.
    pub x_min: f64,
    /// The east edge.
    pub x_max: f64,
    /// The south edge.
    pub y_min: f64,
    /// The north edge.
    pub y_max: f64,
}

/// The largest height a DEM may hold, m (10 000 km).
pub(crate) const MAX_HEIGHT_M: f32 = 1e7;

impl Dem {
    /// Bytes a DEM holds per cell: an f32 height and a validity byte (for memory
    /// estimates made before a map is read).
    pub const BYTES_PER_CELL: u64 = 5;

    /// A DEM from row-major elevations (row 0 north); every cell valid. Cell sizes must
    /// be positive and finite and `z` must hold cols × rows values.
    pub fn new(cols: usize, rows: usize, dx: f64, dy: f64, x0: f64, y_top: f64, z: Vec<f32>) -> Result<Dem> {
        if cols == 0 || rows == 0 {
            return Err(Error::BadGrid(format!("{cols} x {rows} cells: both must be at least 1")));
        }
        // A micrometre to 100 000 km: beyond either, no product of a cell size with the
        // grid's extent or a slope is meaningful (or finite).
        if !((1e-6..=1e8).contains(&dx) && (1e-6..=1e8).contains(&dy)) {
            return Err(Error::BadGrid(format!("cell size {dx} x {dy} m: both must be within 1e-6..=1e8 m")));
        }
        if !(x0.abs() <= 1e13 && y_top.abs() <= 1e13) {
            return Err(Error::BadGrid(format!("origin ({x0}, {y_top}) m: both must be within ±1e13 m")));
        }
        if z.len() != cols * rows {
            return Err(Error::BadGrid(format!("{} elevations for {cols} x {rows} cells", z.len())));
        }
        // Beyond 10 000 km a value is no height of any body's surface (a DEM of radii in
        // metres stays under 7e6): an undeclared no-data value such as f32::MAX, whose
        // differences would overflow.
        if let Some(i) = z.iter().position(|v| v.is_finite() && v.abs() > MAX_HEIGHT_M) {
            return Err(Error::BadGrid(format!(
                "height {:e} m at column {}, row {}: heights must be within ±{MAX_HEIGHT_M:e} m (an undeclared no-data value? declare it as the file's no-data)",
                z[i],
                i % cols,
                i / cols
            )));
        }
        let valid: Vec<bool> = z.iter().map(|v| v.is_finite()).collect();
        let all_valid = valid.iter().all(|&v| v);
        Ok(Dem {
            cols,
            rows,
            dx,
            dy,
            x0,
            y_top,
            z,
            valid,
            all_valid,
            inv_dx: 1.0 / dx,
            inv_dy: 1.0 / dy,
            georef: Georef::default(),
            friction: None,
        })
    }

    /// A DEM sampled from `f(x, y)` at cell centres, with the north-west corner at (0, rows·dy).
    pub fn from_fn(cols: usize, rows: usize, dx: f64, dy: f64, f: impl Fn(f64, f64) -> f64) -> Result<Dem> {
        let y_top = rows as f64 * dy;
        let mut z = Vec::with_capacity(cols * rows);
        for r in 0..rows {
            for c in 0..cols {
                z.push(f(((c as f64) + 0.5) * dx, y_top - ((r as f64) + 0.5) * dy) as f32);
            }
        }
        Dem::new(cols, rows, dx, dy, 0.0, y_top, z)
    }

    /// Another raster on this DEM's grid and georeference: `values` row-major, cols ×
    /// rows of them, non-finite values marking missing cells (a slope map, a horizon
    /// band, a filled copy).
    pub fn with_values(&self, values: Vec<f32>) -> Result<Dem> {
        Ok(Dem::new(self.cols, self.rows, self.dx, self.dy, self.x0, self.y_top, values)?.with_georef(self.georef))
    }

    /// The map's edges in its frame, metres.
    pub fn extent(&self) -> Extent {
        Extent {
            x_min: self.x0,
            x_max: self.x0 + self.cols as f64 * self.dx,
            y_min: self.y_top - self.rows as f64 * self.dy,
            y_max: self.y_top,
        }
    }

    /// A map with no georeference (a synthesised one) placed at a site: centred on
    /// (`lat_deg`, `lon_east_deg`) on `surface`, so every cell has a latitude and
    /// longitude — equirectangular with true scale at the site's latitude, or polar
    /// stereographic (the LOLA polar products' projection, the site's meridian as grid
    /// north) at or beyond [`POLAR_PROJECTION_LAT_DEG`]. A georeferenced map is
    /// returned as it is. Missing cells stay missing.
    pub fn placed_at(self, surface: Spheroid, lat_deg: f64, lon_east_deg: f64) -> Result<Dem> {
        if self.georef.projection != Projection::Local {
            return Ok(self);
        }
        if !(lat_deg.abs() < 90.0 && lon_east_deg.is_finite()) {
            return Err(Error::BadGrid(format!(
                "site ({lat_deg}°, {lon_east_deg}°E): latitude must be inside -90..90, longitude finite"
            )));
        }
        let e = self.extent();
        let (w, h) = (e.x_max - e.x_min, e.y_max - e.y_min);
        // Near a pole, polar stereographic as the LOLA and MOLA polar products use it,
        // with the site's meridian along the grid's north (so the grid's axes are the
        // site's east and north); elsewhere equirectangular, true scale at the site.
        let projection = if lat_deg.abs() >= POLAR_PROJECTION_LAT_DEG {
            Projection::PolarStereographic { north: lat_deg > 0.0, lon0_deg: lon_east_deg }
        } else {
            Projection::Equirectangular { lat_ts_deg: lat_deg, lon0_deg: lon_east_deg }
        };
        let (x_mid, y_mid) = projection.from_geographic(&surface, lat_deg, lon_east_deg).unwrap_or((0.0, 0.0));
        let z: Vec<f32> = self.z.iter().zip(&self.valid).map(|(z, v)| if *v { *z } else { f32::NAN }).collect();
        let georef = Georef { projection, surface };
        Ok(Dem::new(self.cols, self.rows, self.dx, self.dy, x_mid - w / 2.0, y_mid + h / 2.0, z)?.with_georef(georef))
    }

    /// Sets the georeference.
    pub fn with_georef(mut self, georef: Georef) -> Dem {
        self.georef = georef;
        self
    }

    /// Gives the ground its own wheel–ground friction coefficient μ cell by cell
    /// (row-major, cols × rows; NaN where it has none, and the motion's μ holds there;
    /// else 0.01..=5).
    pub fn with_friction(mut self, mu: Vec<f32>) -> Result<Dem> {
        if mu.len() != self.z.len() {
            return Err(Error::BadGrid(format!("friction of {} cells for {} cells", mu.len(), self.z.len())));
        }
        if let Some(bad) = mu.iter().find(|m| !m.is_nan() && !(0.01..=5.0).contains(*m)) {
            return Err(Error::BadGrid(format!("a friction coefficient of {bad}: allowed 0.01..=5")));
        }
        self.friction = mu.iter().any(|m| !m.is_nan()).then(|| mu.into());
        Ok(self)
    }

    /// The friction coefficient the ground sets in the cell holding (x, y), if it sets
    /// one there ([`Dem::with_friction`]).
    pub fn friction_at(&self, x: f64, y: f64) -> Option<f64> {
        let mu = self.friction.as_ref()?;
        let (c, r) = self.cell_at(x, y)?;
        let m = mu[self.index(c, r)];
        (!m.is_nan()).then_some(f64::from(m))
    }

    /// Marks cells as missing where `valid` is false (length cols × rows).
    pub fn with_mask(mut self, valid: Vec<bool>) -> Result<Dem> {
        if valid.len() != self.z.len() {
            return Err(Error::BadGrid(format!("mask of {} for {} cells", valid.len(), self.z.len())));
        }
        for (v, z) in valid.iter().zip(&self.z) {
            if *v && !z.is_finite() {
                return Err(Error::BadGrid("a cell marked valid holds a non-finite elevation".into()));
            }
        }
        self.all_valid = valid.iter().all(|&v| v);
        self.valid = valid;
        Ok(self)
    }

    /// Number of columns (west to east).
    pub fn cols(&self) -> usize {
        self.cols
    }
    /// Number of rows (north to south).
    pub fn rows(&self) -> usize {
        self.rows
    }
    /// Cell size west–east, m.
    pub fn dx(&self) -> f64 {
        self.dx
    }
    /// Cell size north–south, m.
    pub fn dy(&self) -> f64 {
        self.dy
    }
    /// x of the west edge, m.
    pub fn x0(&self) -> f64 {
        self.x0
    }
    /// y of the north edge, m.
    pub fn y_top(&self) -> f64 {
        self.y_top
    }
    /// The georeference.
    pub fn georef(&self) -> &Georef {
        &self.georef
    }
    /// Elevations, row-major from the north-west corner (missing cells hold any value).
    pub fn elevations(&self) -> &[f32] {
        &self.z
    }
    /// The nodata mask: true where a cell has data.
    pub fn valid_mask(&self) -> &[bool] {
        &self.valid
    }

    /// Flat index of (col, row).
    #[inline]
    pub fn index(&self, col: usize, row: usize) -> usize {
        row * self.cols + col
    }

    /// Centre (x, y) of cell (col, row), m.
    #[inline]
    pub fn cell_center(&self, col: usize, row: usize) -> (f64, f64) {
        (self.x0 + (col as f64 + 0.5) * self.dx, self.y_top - (row as f64 + 0.5) * self.dy)
    }

    /// The cell containing (x, y), if on the map.
    pub fn cell_at(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let c = ((x - self.x0) / self.dx).floor();
        let r = ((self.y_top - y) / self.dy).floor();
        (c >= 0.0 && r >= 0.0 && (c as usize) < self.cols && (r as usize) < self.rows)
            .then_some((c as usize, r as usize))
    }

    /// Elevation of cell (col, row), or `None` if missing or off the grid.
    #[inline]
    pub fn z(&self, col: usize, row: usize) -> Option<f32> {
        (col < self.cols && row < self.rows && self.valid[self.index(col, row)]).then(|| self.z[self.index(col, row)])
    }

    /// Bilinear patch at (x, y): the four corner cells, the fractions, and the cell
    /// sizes; `None` off the map or if any corner is missing.
    #[inline(always)]
    fn patch(&self, x: f64, y: f64) -> Option<([f64; 4], f64, f64)> {
        let fx = (x - self.x0) * self.inv_dx;
        let fy = (self.y_top - y) * self.inv_dy;
        let (cols, rows) = (self.cols as f64, self.rows as f64);
        if !(fx >= 0.0 && fy >= 0.0 && fx <= cols && fy <= rows) {
            return None;
        }
        // Position relative to cell centres, clamped so the edge half-cells take the
        // edge values.
        let u = (fx - 0.5).max(0.0).min(cols - 1.0);
        let v = (fy - 0.5).max(0.0).min(rows - 1.0);
        // u, v ≥ 0, so truncation is the floor (and much cheaper than `floor`); through
        // i64, which converts from f64 in fewer instructions than usize.
        let c0 = (u as i64 as usize).min(self.cols.saturating_sub(2));
        let r0 = (v as i64 as usize).min(self.rows.saturating_sub(2));
        let dc = usize::from(self.cols > 1);
        let dr = if self.rows > 1 { self.cols } else { 0 };
        let i = r0 * self.cols + c0;
        let corners = [i, i + dc, i + dr, i + dr + dc];
        if !self.all_valid && !corners.iter().all(|&k| self.valid[k]) {
            return None;
        }
        let z = |k: usize| f64::from(self.z[k]);
        Some(([z(corners[0]), z(corners[1]), z(corners[2]), z(corners[3])], u - c0 as f64, v - r0 as f64))
    }

    /// Bilinear height at (x, y), m; `None` off the map or next to missing data.
    #[inline]
    pub fn height(&self, x: f64, y: f64) -> Option<f64> {
        let ([a, b, c, d], s, t) = self.patch(x, y)?;
        Some(a * (1.0 - s) * (1.0 - t) + b * s * (1.0 - t) + c * (1.0 - s) * t + d * s * t)
    }

    /// Gradient (∂z/∂x east, ∂z/∂y north) of the bilinear surface at (x, y).
    pub fn gradient(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let ([a, b, c, d], s, t) = self.patch(x, y)?;
        let dzds = (b - a) * (1.0 - t) + (d - c) * t;
        let dzdt = (c - a) * (1.0 - s) + (d - b) * s;
        // s grows east (per dx), t grows south (per dy).
        let gx = if self.cols > 1 { dzds / self.dx } else { 0.0 };
        let gy = if self.rows > 1 { -dzdt / self.dy } else { 0.0 };
        Some((gx, gy))
    }

    /// Latitude and east longitude (degrees) of map point (x, y), if georeferenced.
    pub fn geographic(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        self.georef.projection.to_geographic(&self.georef.surface, x, y)
    }

    /// A sub-grid: `cols` × `rows` cells starting at (col0, row0).
    pub fn crop(&self, col0: usize, row0: usize, cols: usize, rows: usize) -> Result<Dem> {
        if cols == 0 || rows == 0 || col0 + cols > self.cols || row0 + rows > self.rows {
            return Err(Error::BadGrid(format!(
                "crop {cols} x {rows} at ({col0}, {row0}) does not fit in {} x {}",
                self.cols, self.rows
            )));
        }
        let mut z = Vec::with_capacity(cols * rows);
        let mut valid = Vec::with_capacity(cols * rows);
        for r in row0..row0 + rows {
            let i = self.index(col0, r);
            z.extend_from_slice(&self.z[i..i + cols]);
            valid.extend_from_slice(&self.valid[i..i + cols]);
        }
        let x0 = self.x0 + col0 as f64 * self.dx;
        let y_top = self.y_top - row0 as f64 * self.dy;
        Dem::new(cols, rows, self.dx, self.dy, x0, y_top, z)?.with_mask(valid).map(|d| d.with_georef(self.georef))
    }

    /// The same area resampled bilinearly to cells of `dx` × `dy` m.
    pub fn resample(&self, dx: f64, dy: f64) -> Result<Dem> {
        if !(dx > 0.0 && dy > 0.0) {
            return Err(Error::BadGrid(format!("cell size {dx} x {dy} m must be positive")));
        }
        let cols = ((self.cols as f64 * self.dx) / dx).round().max(1.0) as usize;
        let rows = ((self.rows as f64 * self.dy) / dy).round().max(1.0) as usize;
        let mut z = Vec::with_capacity(cols * rows);
        let mut valid = Vec::with_capacity(cols * rows);
        for r in 0..rows {
            for c in 0..cols {
                let (x, y) = (self.x0 + (c as f64 + 0.5) * dx, self.y_top - (r as f64 + 0.5) * dy);
                match self.height(x, y) {
                    Some(h) => {
                        z.push(h as f32);
                        valid.push(true);
                    }
                    None => {
                        z.push(f32::NAN);
                        valid.push(false);
                    }
                }
            }
        }
        Dem::new(cols, rows, dx, dy, self.x0, self.y_top, z)?.with_mask(valid).map(|d| d.with_georef(self.georef))
    }
}

impl Ground for Dem {
    #[inline]
    fn height(&self, x: f64, y: f64) -> Option<f64> {
        Dem::height(self, x, y)
    }
    fn friction(&self, x: f64, y: f64) -> Option<f64> {
        self.friction_at(x, y)
    }
    fn normal(&self, x: f64, y: f64) -> Option<[f64; 3]> {
        let (gx, gy) = self.gradient(x, y)?;
        Some(unit_normal(gx, gy))
    }
    /// One bilinear patch for both: the slope is the patch's exact gradient.
    #[inline]
    fn height_slope(&self, x: f64, y: f64, dir: (f64, f64)) -> Option<(f64, f64)> {
        let ([a, b, c, d], s, t) = self.patch(x, y)?;
        let h = a * (1.0 - s) * (1.0 - t) + b * s * (1.0 - t) + c * (1.0 - s) * t + d * s * t;
        let gx = if self.cols > 1 { ((b - a) * (1.0 - t) + (d - c) * t) * self.inv_dx } else { 0.0 };
        let gy = if self.rows > 1 { -((c - a) * (1.0 - s) + (d - b) * s) * self.inv_dy } else { 0.0 };
        Some((h, gx * dir.0 + gy * dir.1))
    }
    /// Both ends on the map ⇒ every point between is (the map is a box); the per-point
    /// work is then the bilinear blend alone, which is what makes a rim scan cheap.
    #[inline]
    fn heights_along(&self, start: (f64, f64), step: (f64, f64), out: &mut [f64]) -> bool {
        let n = out.len();
        if n == 0 {
            return true;
        }
        let fx0 = (start.0 - self.x0) * self.inv_dx;
        let fy0 = (self.y_top - start.1) * self.inv_dy;
        let (dfx, dfy) = (step.0 * self.inv_dx, -step.1 * self.inv_dy);
        let (cols, rows) = (self.cols as f64, self.rows as f64);
        let inside = |fx: f64, fy: f64| fx >= 0.0 && fy >= 0.0 && fx <= cols && fy <= rows;
        let last = (n - 1) as f64;
        if !inside(fx0, fy0) || !inside(fx0 + dfx * last, fy0 + dfy * last) {
            return false;
        }
        if !self.all_valid || self.cols < 2 || self.rows < 2 {
            // Masks and one-cell-wide grids take the general path.
            for (k, h) in out.iter_mut().enumerate() {
                let t = k as f64;
                match Dem::height(self, start.0 + step.0 * t, start.1 + step.1 * t) {
                    Some(z) => *h = z,
                    None => return false,
                }
            }
            return true;
        }
        // Signed integers convert to and from f64 in one instruction each (usize does
        // not); every value here is clamped into the grid first.
        let (cmax, rmax) = ((self.cols - 2) as i64, (self.rows - 2) as i64);
        let stride = self.cols as i64;
        let (x1, y1) = (cols - 1.0, rows - 1.0);
        let (u0, v0) = (fx0 - 0.5, fy0 - 0.5);
        // The bilinear height in the patch whose top-left corner is (c0, r0), at
        // fractions (s, w); one bounds check for the four corners.
        let blend = |c0: i64, r0: i64, s: f64, w: f64| {
            let i = (r0 * stride + c0) as usize;
            let quad = &self.z[i..i + self.cols + 2];
            let (a, b) = (f64::from(quad[0]), f64::from(quad[1]));
            let (c, d) = (f64::from(quad[self.cols]), f64::from(quad[self.cols + 1]));
            let top = a + (b - a) * s;
            top + (c + (d - c) * s - top) * w
        };
        // Between the cell centres no clamping is needed, and the grid coordinates can
        // step in fixed point (F fractional bits, as many as the grid size leaves in an
        // i64): the cell is then a shift and the fraction a mask, where floating point
        // needs a saturating conversion per axis and sample. The fixed-point positions
        // differ from `start + k·step` by under k·2^-F cells, so the ends must sit
        // that far inside.
        let bits = 64 - (self.cols.max(self.rows) as u64).leading_zeros();
        let f = 62 - bits;
        let (one, inv_one) = ((1u64 << f) as f64, 1.0 / (1u64 << f) as f64);
        let margin = (n as f64 + 1.0) * inv_one;
        let (u_end, v_end) = (u0 + dfx * last, v0 + dfy * last);
        let interior = |u: f64, v: f64| u >= margin && v >= margin && u < x1 - margin && v < y1 - margin;
        if interior(u0, v0) && interior(u_end, v_end) {
            let mask = (1i64 << f) - 1;
            // Truncation moves a position by under one unit, 2^-F cells.
            let fixed = |a: f64| (a * one) as i64;
            let (mut uu, mut vv, du, dv) = (fixed(u0), fixed(v0), fixed(dfx), fixed(dfy));
            for h in out.iter_mut() {
                let (s, w) = ((uu & mask) as f64 * inv_one, (vv & mask) as f64 * inv_one);
                *h = blend(uu >> f, vv >> f, s, w);
                uu += du;
                vv += dv;
            }
            return true;
        }
        for (k, h) in out.iter_mut().enumerate() {
            let t = k as i64 as f64;
            // Clamped exactly as `patch` clamps, so the edge half-cells hold their values.
            let u = (u0 + dfx * t).max(0.0).min(x1);
            let v = (v0 + dfy * t).max(0.0).min(y1);
            let (c0, r0) = ((u as i64).min(cmax), (v as i64).min(rmax));
            *h = blend(c0, r0, u - c0 as f64, v - r0 as f64);
        }
        true
    }
}

/// The upward unit normal of a surface with gradient (gx, gy).
pub fn unit_normal(gx: f64, gy: f64) -> [f64; 3] {
    let n = (gx * gx + gy * gy + 1.0).sqrt();
    [-gx / n, -gy / n, 1.0 / n]
}

/// Analytic test terrains implementing [`Ground`].
pub mod analytic {
    use super::{Ground, unit_normal};

    /// The plane z = z0 + gx·x + gy·y.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct Plane {
        /// Height at the origin, m.
        pub z0: f64,
        /// ∂z/∂x.
        pub gx: f64,
        /// ∂z/∂y.
        pub gy: f64,
    }

    impl Ground for Plane {
        fn height(&self, x: f64, y: f64) -> Option<f64> {
            Some(self.z0 + self.gx * x + self.gy * y)
        }
        fn normal(&self, _x: f64, _y: f64) -> Option<[f64; 3]> {
            Some(unit_normal(self.gx, self.gy))
        }
    }

    /// The paraboloid z = a·x² + b·y².
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct Paraboloid {
        /// Coefficient of x², 1/m.
        pub a: f64,
        /// Coefficient of y², 1/m.
        pub b: f64,
    }

    impl Ground for Paraboloid {
        fn height(&self, x: f64, y: f64) -> Option<f64> {
            Some(self.a * x * x + self.b * y * y)
        }
        fn normal(&self, x: f64, y: f64) -> Option<[f64; 3]> {
            Some(unit_normal(2.0 * self.a * x, 2.0 * self.b * y))
        }
    }

    /// A vertical step: `low_m` for x < `x_step`, `high_m` beyond (a wall, for contact
    /// tests).
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct Wall {
        /// Where the wall stands, m.
        pub x_step: f64,
        /// Height west of the wall, m.
        pub low_m: f64,
        /// Height east of the wall, m.
        pub high_m: f64,
    }

    impl Ground for Wall {
        fn height(&self, x: f64, _y: f64) -> Option<f64> {
            Some(if x < self.x_step { self.low_m } else { self.high_m })
        }
        fn normal(&self, _x: f64, _y: f64) -> Option<[f64; 3]> {
            Some([0.0, 0.0, 1.0])
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CRS names the body its reference surface is (one rule: [`Spheroid::body`])
    /// and the sphere it is projected on, no body for a radius that is none of them, and
    /// its central meridian in −180..180.
    #[test]
    fn the_crs_names_the_body_of_its_reference_surface() {
        let projection = Projection::Equirectangular { lat_ts_deg: 0.0, lon0_deg: 270.5 };
        let cases = [
            (Spheroid::MARS_IAU2015, "Mars (2015) - Sphere", 3_396_190.0),
            (Spheroid::MARS_MOLA_SPHERE, "Mars - Sphere, R = 3396000 m", 3_396_000.0),
            (Spheroid::MOON, "Moon (2015) - Sphere", 1_737_400.0),
            (Spheroid::EARTH_WGS84, "Earth - Sphere, R = 6378137 m", 6_378_137.0),
            (
                Spheroid { equatorial_radius_m: 2_634_100.0, polar_radius_m: 2_634_100.0 },
                "Sphere, R = 2634100 m",
                2_634_100.0,
            ),
        ];
        for (surface, sphere, r) in cases {
            let wkt = Georef { projection, surface }.wkt();
            assert!(wkt.starts_with(&format!("PROJCRS[\"{sphere} / Ocentric / Equirectangular\"")), "{sphere}: {wkt}");
            assert!(wkt.contains(&format!("ELLIPSOID[\"{sphere}\",{r},0,")), "{sphere}: {wkt}");
            assert!(wkt.contains("\"Longitude of natural origin\",-89.5,"), "{sphere}: {wkt}");
        }
    }

    #[test]
    fn heights_along_a_line_equal_the_pointwise_heights() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        // Rough, non-square cells; lines inside, through the edge half-cells and off.
        let z: Vec<f32> = (0..17 * 11).map(|_| rng.random_range(-0.5f32..0.5)).collect();
        let dem = Dem::new(17, 11, 0.02, 0.03, 1.0, 2.0, z).unwrap();
        let (w, h) = (17.0 * 0.02, 11.0 * 0.03);
        let mut out = [0.0; 25];
        let (mut inside, mut off) = (0, 0);
        for _ in 0..4000 {
            let start = (rng.random_range(0.95..1.0 + w + 0.05), rng.random_range(2.0 - h - 0.05..2.05));
            let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let step = 0.008 * if rng.random_bool(0.1) { 0.0 } else { 1.0 };
            let step = (step * a.cos(), step * a.sin());
            let pointwise: Option<Vec<f64>> =
                (0..25).map(|k| dem.height(start.0 + step.0 * k as f64, start.1 + step.1 * k as f64)).collect();
            let ok = dem.heights_along(start, step, &mut out);
            assert_eq!(ok, pointwise.is_some(), "{start:?} {step:?}");
            if let Some(p) = pointwise {
                inside += 1;
                for k in 0..25 {
                    assert!((out[k] - p[k]).abs() < 1e-12, "{start:?} {step:?} {k}: {} vs {}", out[k], p[k]);
                }
            } else {
                off += 1;
            }
        }
        assert!(inside > 500 && off > 500, "{inside} {off}");
        // With missing data the answer is refused exactly where a point is.
        let mut mask = vec![true; 17 * 11];
        mask[dem.index(8, 5)] = false;
        let holed = dem.clone().with_mask(mask).unwrap();
        let (x, y) = holed.cell_center(8, 5);
        assert!(!holed.heights_along((x - 0.1, y), (0.01, 0.0), &mut out[..21]));
        assert!(holed.heights_along((x - 0.1, y + 0.06), (0.01, 0.0), &mut out[..21]));
        assert!((out[10] - holed.height(x, y + 0.06).unwrap()).abs() < 1e-12);
    }

    #[test]
    fn bilinear_reproduces_a_plane_and_refuses_off_map_and_nodata() {
        let dem = Dem::from_fn(6, 4, 10.0, 20.0, |x, y| 3.0 + 0.5 * x - 0.25 * y).unwrap();
        for (x, y) in [(5.0, 70.0), (33.3, 41.7), (12.0, 18.0), (55.0, 75.0)] {
            let h = dem.height(x, y).unwrap();
            // Inside the centre hull the plane is exact; in edge half-cells it is held.
            if (5.0..=55.0).contains(&x) && (10.0..=70.0).contains(&y) {
                assert!((h - (3.0 + 0.5 * x - 0.25 * y)).abs() < 1e-4, "{x},{y}: {h}");
                let (gx, gy) = dem.gradient(x, y).unwrap();
                assert!((gx - 0.5).abs() < 1e-6 && (gy + 0.25).abs() < 1e-6);
            }
        }
        assert!(dem.height(-0.1, 10.0).is_none());
        assert!(dem.height(10.0, 80.1).is_none());
        let mut mask = vec![true; 24];
        mask[dem.index(2, 1)] = false;
        let holed = dem.clone().with_mask(mask).unwrap();
        let (x, y) = holed.cell_center(2, 1);
        assert!(holed.height(x, y).is_none());
        assert!(holed.height(x + 5.0, y).is_none(), "a patch touching the hole has no height");
        assert!(holed.height(5.0, 75.0).is_some());
    }

    #[test]
    fn index_and_metre_conversions_agree() {
        let dem = Dem::new(3, 2, 2.0, 5.0, 100.0, 50.0, vec![0.0; 6]).unwrap();
        assert_eq!(dem.cell_center(0, 0), (101.0, 47.5));
        assert_eq!(dem.cell_center(2, 1), (105.0, 42.5));
        assert_eq!(dem.cell_at(105.9, 40.1), Some((2, 1)));
        assert_eq!(dem.cell_at(106.1, 40.1), None);
        assert!(Dem::new(3, 2, 0.0, 1.0, 0.0, 0.0, vec![0.0; 6]).is_err());
        assert!(Dem::new(3, 2, 1.0, 1.0, 0.0, 0.0, vec![0.0; 5]).is_err());
    }

    #[test]
    fn crop_and_resample_keep_positions() {
        let dem = Dem::from_fn(10, 8, 4.0, 4.0, |x, y| x + 2.0 * y).unwrap();
        let c = dem.crop(2, 3, 4, 2).unwrap();
        let (x, y) = c.cell_center(0, 0);
        assert_eq!((x, y), dem.cell_center(2, 3));
        assert_eq!(c.z(0, 0), dem.z(2, 3));
        assert!(dem.crop(8, 0, 4, 2).is_err());
        let r = dem.resample(2.0, 2.0).unwrap();
        assert_eq!((r.cols(), r.rows()), (20, 16));
        let (x, y) = r.cell_center(7, 7);
        assert!((r.height(x, y).unwrap() - dem.height(x, y).unwrap()).abs() < 1e-4);
    }
}
