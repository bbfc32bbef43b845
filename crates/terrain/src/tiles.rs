//! Maps of metre-scale DTMs in bounded memory: shadow, horizon and slope maps computed
//! tile by tile, each tile read through a window with a halo wide enough that it gives
//! exactly what the whole-map computation gives.
//!
//! - [`Source`]: a DEM read a window at a time — an in-memory [`Dem`] or a GeoTIFF
//!   through [`crate::geotiff::Windows`] (only the strips or tiles a window touches are
//!   decoded).
//! - [`relief`]: the lowest and highest elevation, one pass of windows.
//! - [`ShadowHalo`]: how far a shadow can reach, from the relief and the lowest Sun
//!   elevation: terrain further than (highest − lowest)/tan e toward the Sun cannot
//!   rise above a cell's ray. A tile read with that much terrain sun-ward (and two
//!   cells around, for the triangles and the Horn normal at its edge) sees every
//!   crossing of its cells' rays that can shadow them; with [`Method::OwnRay`](crate::shadow::Method::OwnRay), which
//!   decides each cell on its own ray alone, the tile's cells come out exactly as on
//!   the whole map (`tests::tiles_give_the_whole_maps_answer`).
//! - [`Shadows::by_tiles`] (cut by a [`Tiling`]), [`slope_by_tiles`]: row bands of results, north to south,
//!   handed to a sink as each band of tiles finishes (for
//!   [`crate::geotiff::write_u8_tiled`]).
//! - [`horizon_by_tiles`]: each tile's horizons as it finishes, read with the halo on
//!   every side and its ray lines laid where the whole map's lie: every horizon at or
//!   above the lowest Sun planned for is the whole map's, bit for bit;
//!   [`write_horizon_tiled`] writes them to a tiled GeoTIFF, a plane per sector.
//!
//! Results are written as tiled GeoTIFFs ([`crate::geotiff::write_u8_tiled`],
//! [`crate::geotiff::write_u16_planes_tiled`]) as tiles finish.
//!
//! Peak memory is a band of results (tile rows × map width) plus one tile with its halo
//! and the shadow method's working arrays (about 40 bytes a cell), and the reader's
//! chunk cache: not the map.

use crate::dem::Dem;
use crate::error::{Error, Result};
use crate::geotiff::{Grid, Windows};
use crate::horizon::HorizonMap;
use crate::shadow::{Curvature, GridSunDirection, Shadows};
use crate::slope::{SlopeAspect, slope_aspect};

/// A DEM read a window at a time.
pub trait Source {
    /// The whole map's grid.
    fn grid(&self) -> Grid;
    /// The window `cols` × `rows` from (`col0`, `row0`), placed where it lies.
    fn window(&mut self, col0: usize, row0: usize, cols: usize, rows: usize) -> Result<Dem>;
}

impl Source for Dem {
    fn grid(&self) -> Grid {
        Grid::of(self)
    }

    fn window(&mut self, col0: usize, row0: usize, cols: usize, rows: usize) -> Result<Dem> {
        self.crop(col0, row0, cols, rows)
    }
}

impl Source for Windows {
    fn grid(&self) -> Grid {
        Windows::grid(self)
    }

    fn window(&mut self, col0: usize, row0: usize, cols: usize, rows: usize) -> Result<Dem> {
        self.read(col0, row0, cols, rows)
    }
}

/// The lowest and highest valid elevation, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relief {
    /// Lowest, m.
    pub min_m: f64,
    /// Highest, m.
    pub max_m: f64,
}

/// The relief of the whole source, read `tile` × `tile` cells at a time; None if no
/// cell has data.
pub fn relief(src: &mut impl Source, tile: usize) -> Result<Option<Relief>> {
    let g = src.grid();
    let tile = tile.max(1);
    let mut r: Option<Relief> = None;
    for row0 in (0..g.rows).step_by(tile) {
        for col0 in (0..g.cols).step_by(tile) {
            let w = src.window(col0, row0, tile.min(g.cols - col0), tile.min(g.rows - row0))?;
            for (z, ok) in w.elevations().iter().zip(w.valid_mask()) {
                if *ok {
                    let z = f64::from(*z);
                    let e = r.get_or_insert(Relief { min_m: z, max_m: z });
                    e.min_m = e.min_m.min(z);
                    e.max_m = e.max_m.max(z);
                }
            }
        }
    }
    Ok(r)
}

/// Cells beyond the halo a tile is read with on every side: the triangles a ray
/// crosses at the tile's edge, and the Horn normal's neighbours.
const MARGIN: usize = 2;

/// How far shadows reach, and the halo a tile is read with toward the Sun.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowHalo {
    /// The longest possible shadow, m: relief / tan(lowest Sun elevation).
    pub metres: f64,
    /// The halo in columns (the shadow's reach, plus two cells of margin).
    pub cols: usize,
    /// Rows.
    pub rows: usize,
}

impl ShadowHalo {
    /// The halo for Suns at `lowest_elevation_deg` or higher over `relief` on `grid`.
    /// A Sun at or below the horizon needs none (every cell is in shadow).
    pub fn new(relief: Relief, grid: &Grid, lowest_elevation_deg: f64) -> Result<ShadowHalo> {
        if !lowest_elevation_deg.is_finite() {
            return Err(Error::BadGrid(format!("lowest Sun elevation {lowest_elevation_deg}: must be finite")));
        }
        let metres = if lowest_elevation_deg <= 0.0 {
            0.0
        } else {
            (relief.max_m - relief.min_m).max(0.0) / lowest_elevation_deg.to_radians().tan()
        };
        let cells = |cell_m: f64| (metres / cell_m).ceil().min(1e9) as usize + MARGIN;
        Ok(ShadowHalo { metres, cols: cells(grid.dx), rows: cells(grid.dy) })
    }
}

/// The window a tile is read through: the tile grown by the halo toward the Sun and by
/// the margin all round, clipped to the map. Returns (col0, row0, cols, rows).
fn window_for(
    g: &Grid,
    tile: (usize, usize, usize, usize),
    sun: GridSunDirection,
    halo: &ShadowHalo,
) -> (usize, usize, usize, usize) {
    let (c0, r0, w, h) = tile;
    let (sa, ca) = sun.azimuth_deg.to_radians().sin_cos();
    // East of the tile if the Sun is east; north (lower rows) if it is north.
    let (east, west) = if sa > 1e-12 {
        (halo.cols, MARGIN)
    } else if sa < -1e-12 {
        (MARGIN, halo.cols)
    } else {
        (MARGIN, MARGIN)
    };
    let (north, south) = if ca > 1e-12 {
        (halo.rows, MARGIN)
    } else if ca < -1e-12 {
        (MARGIN, halo.rows)
    } else {
        (MARGIN, MARGIN)
    };
    let a = c0.saturating_sub(west);
    let b = (c0 + w + east).min(g.cols);
    let top = r0.saturating_sub(north);
    let bottom = (r0 + h + south).min(g.rows);
    (a, top, b - a, bottom - top)
}

/// How a map read tile by tile is cut: the tile side and the halo each tile is read
/// with toward the Sun.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tiling {
    /// Tile side, cells.
    pub tile: usize,
    /// The halo each tile is read with (at least for the Sun's elevation asked).
    pub halo: ShadowHalo,
}

impl Shadows {
    /// The direct-sun map (1 lit, 0 shadowed, 255 no data, as
    /// [`crate::shadow::ShadowMap::to_u8`]) of a map read tile by tile: `band(row0,
    /// values)` receives rows `row0..` of the whole map's width, `tiling.tile` rows at a
    /// time (fewer at the end), north to south; `progress(done, total)` counts tiles.
    /// With [`Method::OwnRay`](crate::shadow::Method::OwnRay) every value is the whole map's ([`Shadows::map`]).
    pub fn by_tiles(
        &self,
        src: &mut impl Source,
        tiling: Tiling,
        mut band: impl FnMut(usize, &[u8]) -> Result<()>,
        mut progress: impl FnMut(usize, usize),
    ) -> Result<()> {
        let g = src.grid();
        let tile = tiling.tile.max(1);
        let mut out = vec![255u8; tile * g.cols];
        for row0 in (0..g.rows).step_by(tile) {
            let n = tile.min(g.rows - row0) * g.cols;
            self.band(src, tiling, row0, &mut out[..n], &mut progress)?;
            band(row0, &out[..n])?;
        }
        Ok(())
    }

    /// One band of [`Shadows::by_tiles`]: the tiles of rows `row0..` into `out` (the
    /// band's rows × the map's width), for a writer that asks for bands in turn.
    pub fn band(
        &self,
        src: &mut impl Source,
        tiling: Tiling,
        row0: usize,
        out: &mut [u8],
        mut progress: impl FnMut(usize, usize),
    ) -> Result<()> {
        let Tiling { tile, halo } = tiling;
        let g = src.grid();
        let tile = tile.max(1);
        let h = out.len() / g.cols.max(1);
        if row0 + h > g.rows || h * g.cols != out.len() {
            return Err(Error::BadGrid(format!(
                "band of {} values at row {row0} of a {} x {} map",
                out.len(),
                g.cols,
                g.rows
            )));
        }
        let per_band = g.cols.div_ceil(tile);
        let total = g.rows.div_ceil(tile) * per_band;
        for (k, col0) in (0..g.cols).step_by(tile).enumerate() {
            let w = tile.min(g.cols - col0);
            let (wc, wr, ww, wh) = window_for(&g, (col0, row0, w, h), self.sun, &halo);
            let dem = src.window(wc, wr, ww, wh)?;
            let map = self.map(&dem).to_u8();
            for r in 0..h {
                let from = &map[(row0 + r - wr) * ww + (col0 - wc)..][..w];
                out[r * g.cols + col0..][..w].copy_from_slice(from);
            }
            progress((row0 / tile) * per_band + k + 1, total);
        }
        Ok(())
    }
}

/// What [`horizon_by_tiles`] computes, and in what pieces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HorizonTiles {
    /// Azimuth sectors (16..=360), as [`HorizonMap::compute`].
    pub sectors: usize,
    /// Flat or curved world.
    pub curvature: Curvature,
    /// The lowest horizon kept, degrees: lower horizons are stored as this one, so the
    /// map answers for Suns at or above it. The halo must be [`ShadowHalo::new`] for it.
    pub lowest_deg: f64,
    /// The halo each tile is read with, on every side (horizons look every way).
    pub halo: ShadowHalo,
    /// Tile side, cells.
    pub tile: usize,
}

/// A horizon map tile by tile: `each(col0, row0, cols, rows, codes)` receives each
/// tile's encoded horizons (as [`HorizonMap`] stores them, 2 bytes a cell and sector),
/// sector after sector, row-major within the tile, as the tile finishes — a horizon map
/// of a 10⁸-cell DTM is gigabytes, so nothing larger than a tile is held. Every horizon
/// at or above `lowest_deg` is the whole map's bit for bit (the ray lines are laid
/// where the whole map's lie, and terrain beyond the halo cannot rise that high); lower
/// ones are stored as `lowest_deg`, on the whole map as here.
pub fn horizon_by_tiles(
    src: &mut impl Source,
    plan: &HorizonTiles,
    mut each: impl FnMut(usize, usize, usize, usize, &[u16]) -> Result<()>,
) -> Result<()> {
    let g = src.grid();
    let tile = plan.tile.max(1);
    let floor = crate::horizon::encode(plan.lowest_deg);
    let mut out = Vec::new();
    for row0 in (0..g.rows).step_by(tile) {
        let h = tile.min(g.rows - row0);
        for col0 in (0..g.cols).step_by(tile) {
            let w = tile.min(g.cols - col0);
            let (wc, wr) = (col0.saturating_sub(plan.halo.cols), row0.saturating_sub(plan.halo.rows));
            let ww = (col0 + w + plan.halo.cols).min(g.cols) - wc;
            let wh = (row0 + h + plan.halo.rows).min(g.rows) - wr;
            let dem = src.window(wc, wr, ww, wh)?;
            let map = HorizonMap::compute_at(&dem, plan.sectors, plan.curvature, (wc, wr))?;
            out.clear();
            for s in 0..plan.sectors {
                let codes = map.sector_codes(s);
                for r in 0..h {
                    let from = &codes[(row0 + r - wr) * ww + (col0 - wc)..][..w];
                    out.extend(from.iter().map(|f| (*f).max(floor)));
                }
            }
            drop(map);
            each(col0, row0, w, h, &out)?;
        }
    }
    Ok(())
}

/// Writes [`horizon_by_tiles`]'s map as one tiled GeoTIFF of uint16 codes, a plane
/// per sector (sector k centred on azimuth k·360°/K), each tile written as it
/// finishes; the file carries GDAL's band scale and offset
/// ([`crate::horizon::CODE_STEP_DEG`], [`crate::horizon::CODE_OFFSET_DEG`]) so that GDAL
/// reads degrees. `tile` must be a multiple of 16 (TIFF tiles). `progress(done, total)`
/// after each tile. Returns whether the file is BigTIFF.
pub fn write_horizon_tiled(
    src: &mut impl Source,
    plan: &HorizonTiles,
    path: &std::path::Path,
    mut progress: impl FnMut(usize, usize),
) -> Result<bool> {
    use crate::horizon::{CODE_OFFSET_DEG, CODE_STEP_DEG};
    let grid = src.grid();
    let total = grid.cols.div_ceil(plan.tile.max(1)) * grid.rows.div_ceil(plan.tile.max(1));
    crate::geotiff::write_u16_planes_tiled(
        &grid,
        plan.sectors,
        None,
        Some((CODE_STEP_DEG, CODE_OFFSET_DEG)),
        plan.tile,
        false,
        path,
        |sink| {
            let mut done = 0;
            horizon_by_tiles(src, plan, |col0, row0, w, h, codes| {
                sink(col0, row0, w, h, codes)?;
                done += 1;
                progress(done, total);
                Ok(())
            })
        },
    )
}

/// A planning region cut from a map too large to hold: its DEM, slope and horizon map
/// carry the whole map's values (the slope from the region read with the Horn
/// kernel's ring, the horizons from the region read with the halo on every side,
/// floored at the lowest Sun planned for), so memory follows the region and its halo,
/// not the map.
#[derive(Debug, Clone)]
pub struct Region {
    /// The region's DEM, placed where it lies in the map.
    pub dem: Dem,
    /// Slope, aspect and gradients, cell for cell the whole map's.
    pub slope: SlopeAspect,
    /// The horizon map, if asked for: every horizon at or above the lowest Sun is the
    /// whole map's, lower ones are stored as the lowest Sun.
    pub horizon: Option<HorizonMap>,
}

/// How a [`Region`]'s horizon map is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionHorizon {
    /// Azimuth sectors (16..=360).
    pub sectors: usize,
    /// Flat or curved world.
    pub curvature: Curvature,
    /// The lowest Sun planned for, degrees; the halo follows from it and the relief.
    pub lowest_deg: f64,
    /// The halo, [`ShadowHalo::new`] for `lowest_deg`.
    pub halo: ShadowHalo,
}

/// Reads the region `cols` × `rows` from (`col0`, `row0`) of `src` with what a planner
/// needs of it; see [`Region`].
pub fn region(
    src: &mut impl Source,
    (col0, row0, cols, rows): (usize, usize, usize, usize),
    horizon: Option<RegionHorizon>,
) -> Result<Region> {
    let g = src.grid();
    if cols == 0 || rows == 0 || col0 + cols > g.cols || row0 + rows > g.rows {
        return Err(Error::BadGrid(format!(
            "region {cols} x {rows} at ({col0}, {row0}) does not fit in the {} x {} map",
            g.cols, g.rows
        )));
    }
    // Grows the region by (halo cols, halo rows), clipped: (window, the region's place in it).
    let grow = |hc: usize, hr: usize| {
        let (wc, wr) = (col0.saturating_sub(hc), row0.saturating_sub(hr));
        let (ww, wh) = ((col0 + cols + hc).min(g.cols) - wc, (row0 + rows + hr).min(g.rows) - wr);
        ((wc, wr, ww, wh), (col0 - wc, row0 - wr, cols, rows))
    };
    let dem = src.window(col0, row0, cols, rows)?;
    let ((wc, wr, ww, wh), inner) = grow(1, 1);
    let ring = slope_aspect(&src.window(wc, wr, ww, wh)?);
    let cut = |v: &[f32]| -> Vec<f32> {
        (inner.1..inner.1 + rows).flat_map(|r| v[r * ww + inner.0..][..cols].iter().copied()).collect()
    };
    let slope = SlopeAspect {
        slope_deg: cut(&ring.slope_deg),
        aspect_deg: cut(&ring.aspect_deg),
        dzdx: cut(&ring.dzdx),
        dzdy: cut(&ring.dzdy),
    };
    let horizon = match horizon {
        None => None,
        Some(h) => {
            let ((wc, wr, ww, wh), inner) = grow(h.halo.cols, h.halo.rows);
            let window = src.window(wc, wr, ww, wh)?;
            let map = HorizonMap::compute_at(&window, h.sectors, h.curvature, (wc, wr))?;
            Some(map.window(inner, Some(h.lowest_deg)))
        }
    };
    Ok(Region { dem, slope, horizon })
}

/// Horn slope in degrees tile by tile, bands as in [`Shadows::by_tiles`]; each tile is
/// read with the one-cell ring the Horn kernel needs, so every value is the whole
/// map's.
pub fn slope_by_tiles(
    src: &mut impl Source,
    tile: usize,
    mut band: impl FnMut(usize, &[f32]) -> Result<()>,
) -> Result<()> {
    let g = src.grid();
    let tile = tile.max(1);
    let mut out = vec![f32::NAN; tile * g.cols];
    for row0 in (0..g.rows).step_by(tile) {
        let h = tile.min(g.rows - row0);
        for col0 in (0..g.cols).step_by(tile) {
            let w = tile.min(g.cols - col0);
            let (wc, wr) = (col0.saturating_sub(1), row0.saturating_sub(1));
            let (ww, wh) = ((col0 + w + 1).min(g.cols) - wc, (row0 + h + 1).min(g.rows) - wr);
            let dem = src.window(wc, wr, ww, wh)?;
            let slope = slope_aspect(&dem).slope_deg;
            for r in 0..h {
                let from = &slope[(row0 + r - wr) * ww + (col0 - wc)..][..w];
                out[r * g.cols + col0..][..w].copy_from_slice(from);
            }
        }
        band(row0, &out[..h * g.cols])?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::Method;
    fn whole_map(dem: &Dem, sun: GridSunDirection, curvature: Curvature, method: Method) -> crate::shadow::ShadowMap {
        Shadows::new(sun, curvature).method(method).map(dem)
    }

    /// 161 × 119 cells of 10 m: noise and two small hills (relief about 70 m).
    fn terrain() -> Dem {
        use crate::synth::{Feature, Noise, TerrainSpec};
        TerrainSpec {
            cols: 161,
            rows: 119,
            cell_m: 10.0,
            base_m: 0.0,
            seed: 6,
            noise: Some(Noise { amplitude_m: 12.0, wavelength_m: 250.0, octaves: 4, persistence: 0.5 }),
            features: vec![
                Feature::Hill { x_m: 500.0, y_m: 400.0, radius_m: 110.0, slope_deg: 22.0 },
                Feature::Hill { x_m: 1100.0, y_m: 800.0, radius_m: 90.0, slope_deg: 28.0 },
            ],
        }
        .build()
        .unwrap()
    }

    #[test]
    fn tiles_give_the_whole_maps_answer() {
        // 161 × 119 cells of rough terrain with holes, in 16 × 16 tiles: 88 tiles, the
        // halo reaching over several of them.
        let dem = terrain();
        let valid: Vec<bool> = (0..161 * 119).map(|i| i % 31 != 7).collect();
        let mut dem = dem.with_mask(valid).unwrap();
        let relief = relief(&mut dem, 16).unwrap().unwrap();
        let grid = Grid::of(&dem);
        for (az, el, curvature) in [
            (0.0, 12.0, Curvature::Flat),
            (77.0, 6.0, Curvature::Flat),
            (135.0, 9.0, Curvature::Sphere { radius_m: 5.0e4 }),
            (250.0, 20.0, Curvature::Flat),
        ] {
            let sun = GridSunDirection::new(az, el);
            let halo = ShadowHalo::new(relief, &grid, el).unwrap();
            assert!(halo.cols < 60 && halo.rows < 60, "az {az}: a halo of {halo:?} would hide the tiling");
            let whole = whole_map(&dem, sun, curvature, Method::OwnRay).to_u8();
            let mut tiled = Vec::new();
            let mut tiles = 0;
            Shadows::new(sun, curvature)
                .by_tiles(
                    &mut dem,
                    Tiling { tile: 16, halo },
                    |row0, band| {
                        assert_eq!(row0 * 161, tiled.len(), "bands arrive in order");
                        tiled.extend_from_slice(band);
                        Ok(())
                    },
                    |done, total| {
                        tiles = done;
                        assert_eq!(total, 88);
                    },
                )
                .unwrap();
            assert_eq!(tiles, 88);
            let differ = whole.iter().zip(&tiled).filter(|(a, b)| a != b).count();
            assert_eq!(differ, 0, "az {az} el {el}: the tiles must give the whole map's answer");
            // Some shadow at all, or the test proves nothing.
            assert!(whole.iter().filter(|v| **v == 0).count() > 100, "az {az}");
        }
        let whole = slope_aspect(&dem).slope_deg;
        let mut tiled = Vec::new();
        slope_by_tiles(&mut dem, 16, |_, band| {
            tiled.extend_from_slice(band);
            Ok(())
        })
        .unwrap();
        assert!(whole.iter().zip(&tiled).all(|(a, b)| a == b || (a.is_nan() && b.is_nan())));
    }

    #[test]
    fn horizon_tiles_give_the_whole_maps_horizons_above_the_lowest_sun() {
        let mut dem = terrain();
        let (cols, rows) = (dem.cols(), dem.rows());
        let relief = relief(&mut dem, 16).unwrap().unwrap();
        let lowest = 12.0;
        let halo = ShadowHalo::new(relief, &Grid::of(&dem), lowest).unwrap();
        for curvature in [Curvature::Flat, Curvature::Sphere { radius_m: 5.0e4 }] {
            let plan = HorizonTiles { sectors: 16, curvature, lowest_deg: lowest, halo, tile: 24 };
            let whole = HorizonMap::compute(&dem, 16, curvature).unwrap();
            let floor = crate::horizon::encode(lowest);
            let mut tiled = vec![vec![0u16; cols * rows]; 16];
            let mut tiles = 0;
            horizon_by_tiles(&mut dem, &plan, |col0, row0, w, h, codes| {
                tiles += 1;
                for (s, t) in tiled.iter_mut().enumerate() {
                    for r in 0..h {
                        t[(row0 + r) * cols + col0..][..w].copy_from_slice(&codes[s * w * h + r * w..][..w]);
                    }
                }
                Ok(())
            })
            .unwrap();
            assert_eq!(tiles, 7 * 5);
            let mut above = 0;
            for (s, t) in tiled.iter().enumerate() {
                assert_eq!(t.len(), cols * rows);
                for (i, (a, b)) in whole.sector_codes(s).iter().zip(t).enumerate() {
                    assert_eq!((*a).max(floor), *b, "{curvature:?} sector {s} cell {i}");
                    above += usize::from(*a > floor);
                }
            }
            // Enough horizons above the floor for the identity to mean something.
            assert!(above > 1000, "{curvature:?}: {above}");
        }
    }

    #[test]
    fn a_tiled_horizon_file_holds_the_whole_maps_horizons() {
        use tiff::decoder::{Decoder, DecodingResult};
        let mut dem = terrain();
        let (cols, rows) = (dem.cols(), dem.rows());
        let relief = relief(&mut dem, 16).unwrap().unwrap();
        let lowest = 12.0;
        let halo = ShadowHalo::new(relief, &Grid::of(&dem), lowest).unwrap();
        let curvature = Curvature::Flat;
        // 32-cell tiles on 161 × 119 cells: ragged edge tiles both ways.
        let plan = HorizonTiles { sectors: 16, curvature, lowest_deg: lowest, halo, tile: 32 };
        let path = std::env::temp_dir().join(format!("areo_horizon_tiles_{}.tif", std::process::id()));
        let mut last = (0, 0);
        let big = write_horizon_tiled(&mut dem, &plan, &path, |done, total| last = (done, total)).unwrap();
        assert!(!big);
        assert_eq!(last, (6 * 4, 6 * 4));
        let whole = HorizonMap::compute(&dem, 16, curvature).unwrap();
        let floor = crate::horizon::encode(lowest);
        let mut dec = Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap())).unwrap();
        assert_eq!(dec.dimensions().unwrap(), (cols as u32, rows as u32));
        assert_eq!(dec.chunk_dimensions(), (32, 32), "a tiled file");
        assert_eq!(dec.tile_count().unwrap(), 16 * 6 * 4, "a plane of tiles per sector");
        for s in 0..16 {
            for t in 0..24usize {
                let DecodingResult::U16(v) = dec.read_chunk((s * 24 + t) as u32).unwrap() else {
                    panic!("uint16 codes")
                };
                let (c0, r0) = ((t % 6) * 32, (t / 6) * 32);
                let (w, _) = dec.chunk_data_dimensions((s * 24 + t) as u32);
                for r in 0..32.min(rows - r0) {
                    for c in 0..32.min(cols - c0) {
                        let j = (r0 + r) * cols + c0 + c;
                        assert_eq!(v[r * w as usize + c], whole.sector_codes(s)[j].max(floor), "sector {s} cell {j}");
                    }
                }
            }
        }
        let (step, offset) = crate::geotiff::gdal_scale_offset_of(&path).unwrap().expect("GDAL scale and offset");
        assert_eq!((step, offset), (crate::horizon::CODE_STEP_DEG, crate::horizon::CODE_OFFSET_DEG));
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn a_region_carries_the_whole_maps_slope_and_horizons() {
        let mut dem = terrain();
        let relief = relief(&mut dem, 64).unwrap().unwrap();
        let lowest = 12.0;
        let halo = ShadowHalo::new(relief, &Grid::of(&dem), lowest).unwrap();
        let curvature = Curvature::Flat;
        let whole_slope = slope_aspect(&dem);
        let whole_horizon = HorizonMap::compute(&dem, 16, curvature).unwrap();
        let floor = crate::horizon::encode(lowest);
        for (c0, r0, w, h) in [(40, 30, 50, 40), (0, 0, 30, 20), (130, 100, 31, 19)] {
            let plan = RegionHorizon { sectors: 16, curvature, lowest_deg: lowest, halo };
            let reg = region(&mut dem, (c0, r0, w, h), Some(plan)).unwrap();
            let map = reg.horizon.as_ref().unwrap();
            assert_eq!((reg.dem.cols(), reg.dem.rows()), (w, h));
            assert_eq!(reg.dem.cell_center(0, 0), dem.cell_center(c0, r0));
            for r in 0..h {
                for c in 0..w {
                    let (i, j) = (r * w + c, (r0 + r) * dem.cols() + c0 + c);
                    assert_eq!(
                        reg.slope.slope_deg[i].to_bits(),
                        whole_slope.slope_deg[j].to_bits(),
                        "slope ({c}, {r})"
                    );
                    assert_eq!(reg.slope.dzdx[i].to_bits(), whole_slope.dzdx[j].to_bits());
                    for s in 0..16 {
                        assert_eq!(
                            map.sector_codes(s)[i],
                            whole_horizon.sector_codes(s)[j].max(floor),
                            "sector {s} ({c}, {r})"
                        );
                    }
                }
            }
        }
        assert!(region(&mut dem, (150, 0, 20, 5), None).is_err(), "a region off the map is an error");
    }

    #[test]
    fn a_halo_too_short_is_what_makes_tiles_differ() {
        // The same check with the halo cut to the margin: long shadows are lost at the
        // tiles' sun-ward edges — the halo is what the identity rests on.
        let mut dem = terrain();
        let sun = GridSunDirection::new(77.0, 4.0);
        let short = ShadowHalo { metres: 0.0, cols: MARGIN, rows: MARGIN };
        let whole = whole_map(&dem, sun, Curvature::Flat, Method::OwnRay).to_u8();
        let mut tiled = Vec::new();
        Shadows::new(sun, Curvature::Flat)
            .by_tiles(
                &mut dem,
                Tiling { tile: 16, halo: short },
                |_, band| {
                    tiled.extend_from_slice(band);
                    Ok(())
                },
                |_, _| {},
            )
            .unwrap();
        assert!(whole.iter().zip(&tiled).filter(|(a, b)| a != b).count() > 10);
    }
}
