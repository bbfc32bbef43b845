//! `areo terrain …`: DEM files in, rasters and previews out.

use std::path::Path;

use areo_terrain::geotiff;
/// A DEM's size, cells and georeference without its heights (read from a header).
pub use areo_terrain::geotiff::Grid;
use areo_terrain::hillshade::hillshade_rgb;
use areo_terrain::horizon::HorizonMap;
pub use areo_terrain::shadow::Method as ShadowMethod;
use areo_terrain::shadow::{Curvature, GridSunDirection, Shadows};
use areo_terrain::slope::slope_aspect;
use areo_terrain::tiles::Source as _;
/// A DEM, and how its map metres relate to its body (for the binary and its tests).
pub use areo_terrain::{Dem, Georef, Projection, Spheroid};

use crate::error::{Error, Result};
use crate::output::png::write_map_png;
use crate::output::write_with;

/// Reads a DEM by its extension (see [`areo_terrain::read`]).
pub fn read_dem(path: &Path) -> Result<Dem> {
    Ok(areo_terrain::read(path)?)
}

/// The DEM a job's `field` names in scenario `file`, read relative to it, with the
/// checks every job makes of its ground (one validation for every job): heights within
/// ±1e7 m ([`Dem::new`]) and at least one cell that is not missing.
pub(crate) fn read_job_dem(file: &crate::format::ScenarioFile, rel: &Path, field: &str) -> Result<Dem> {
    let path = file.path.parent().unwrap_or(Path::new(".")).join(rel);
    let dem = read_dem(&path).map_err(|e| e.referenced_by(&file.path, field))?;
    if !dem.valid_mask().iter().any(|&v| v) {
        let empty = areo_terrain::Error::BadGrid(format!(
            "{}: every cell is missing (no-data): a job needs heights",
            path.display()
        ));
        return Err(crate::Error::from(empty).referenced_by(&file.path, field));
    }
    Ok(dem)
}

/// The grid of a GeoTIFF from its header alone (a DTM too large to read whole).
pub fn geotiff_grid(path: &Path) -> Result<Grid> {
    Ok(geotiff::Windows::open(path, 1)?.grid())
}

/// Where the Sun stands over the middle of a DEM at an instant (`areo terrain shadow
/// --utc`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct SunOver {
    /// The instant, UTC.
    pub utc: String,
    /// The body, from the DEM's reference sphere.
    pub body: String,
    /// The map's middle, degrees (planetocentric; geodetic on the Earth).
    pub lat_deg: f64,
    /// The map's middle, degrees east.
    pub lon_east_deg: f64,
    /// Sun azimuth there, degrees clockwise from true north.
    pub azimuth_deg: f64,
    /// The same direction on the grid, degrees clockwise from the grid's north (up in
    /// the image): what shadows are cast along. It differs from `azimuth_deg` where the
    /// map's meridians are not its columns (a polar map whose central meridian is not
    /// the middle's).
    pub grid_azimuth_deg: f64,
    /// Sun elevation there above the local horizontal, degrees.
    pub elevation_deg: f64,
}

/// The Sun over the middle of `grid` (the DEM `file`'s) at `utc`: the body is the one
/// whose reference sphere the DEM's georeference names, the Sun that body's model
/// (Mars24, the lunar or the terrestrial ephemeris). One direction for the whole map,
/// as `--sun-azimuth` and `--sun-elevation` give. A map without a georeference or on
/// an unknown sphere is refused, naming what to give instead.
pub fn sun_over(file: &Path, grid: &Grid, utc: &str) -> Result<SunOver> {
    let unusable = |why: String| {
        Error::usage(
            format!("--utc {utc}"),
            format!("{}: {why}; give --sun-azimuth and --sun-elevation", file.display()),
        )
    };
    let g = grid.georef;
    if g.projection == Projection::Local {
        return Err(unusable("the DEM has no georeference (a local frame), so no place on a body".into()));
    }
    let body = g.surface.body().ok_or_else(|| {
        unusable(format!(
            "its sphere (a = {} m, b = {} m) is none of Mars, the Moon or the Earth",
            g.surface.equatorial_radius_m, g.surface.polar_radius_m
        ))
    })?;
    let (x, y) = (grid.x0 + 0.5 * grid.cols as f64 * grid.dx, grid.y_top - 0.5 * grid.rows as f64 * grid.dy);
    let (lat, lon) = g
        .projection
        .to_geographic(&g.surface, x, y)
        .ok_or_else(|| unusable("its middle has no latitude and longitude".into()))?;
    let epoch = areo_ephemeris::parse_utc(utc)?;
    let site = areo_ephemeris::Site::on(body, lat, lon)?;
    let at = areo_ephemeris::SunModel::sun(&body, epoch).at_site(&site);
    Ok(SunOver {
        utc: areo_ephemeris::format_utc(epoch),
        body: body.iau_name().to_string(),
        lat_deg: site.lat_deg(),
        lon_east_deg: site.lon_east_deg(),
        azimuth_deg: at.azimuth_deg,
        grid_azimuth_deg: g.projection.grid_azimuth_deg(at.azimuth_deg, site.lon_east_deg()),
        elevation_deg: at.elevation_deg,
    })
}

/// Checks an output path before anything is computed: a GeoTIFF name (`.tif` or
/// `.tiff`, since a PNG preview is written beside it under the `.png` name), and neither
/// it nor its preview the input file itself.
pub fn check_output(input: &Path, out: &Path) -> Result<()> {
    if areo_terrain::DemFormat::of(out) != Some(areo_terrain::DemFormat::GeoTiff) {
        return Err(Error::usage(
            format!("-o {}", out.display()),
            "the output is a GeoTIFF, name it NAME.tif (its preview goes to NAME.png)",
        ));
    }
    let same = |a: &Path, b: &Path| -> bool {
        // The output may not exist yet: compare its directory's real path and its name;
        // if it does, compare the files themselves (a link to the input is the input).
        let real = |p: &Path| {
            let dir = p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            dir.canonicalize().ok().map(|d| d.join(p.file_name().unwrap_or_default()))
        };
        areo_terrain::input::same_file(a, b) || matches!((real(a), real(b)), (Some(x), Some(y)) if x == y)
    };
    // A PDS3 input reads its label and the image its label names too.
    let inputs = areo_terrain::pds3::files_of(input);
    for candidate in [out.to_path_buf(), out.with_extension("png"), out.with_extension("pgw")] {
        if let Some(hit) = inputs.iter().find(|i| same(i, &candidate)) {
            return Err(Error::usage(
                format!("-o {}", out.display()),
                format!("writing {} would overwrite the input {}", candidate.display(), hit.display()),
            ));
        }
    }
    Ok(())
}

/// What `areo terrain info` reports of a DEM: plain names and units, for text or JSON.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DemInfo {
    /// The file read.
    pub file: std::path::PathBuf,
    /// Columns and rows.
    pub cols: usize,
    /// Rows.
    pub rows: usize,
    /// Cells with an elevation.
    pub valid_cells: usize,
    /// Cells without one.
    pub missing_cells: usize,
    /// Cell size east–west and north–south, m.
    pub cell_m: [f64; 2],
    /// Extent in the DEM's projected metres: west, east, south, north.
    pub extent_m: [f64; 4],
    /// Lowest, highest and mean elevation, m (`None` when every cell is missing).
    pub elevation_m: Option<[f64; 3]>,
    /// The projection by name (`local`, `equirectangular`, `polar stereographic`).
    pub projection: &'static str,
    /// Standard parallel (equirectangular), degrees.
    pub lat_ts_deg: Option<f64>,
    /// Central meridian, degrees east.
    pub lon0_deg: Option<f64>,
    /// North or south (polar stereographic).
    pub pole: Option<&'static str>,
    /// The body the radii are (`Mars`, `Moon`, `Earth`), if any.
    pub body: Option<&'static str>,
    /// Equatorial and polar radius, m.
    pub radii_m: [f64; 2],
    /// Latitude and east longitude of the map's centre, degrees (`None` for a local
    /// frame).
    pub centre_deg: Option<[f64; 2]>,
    /// The file's projected CRS when areo does not read its projection (the map is
    /// then `local`), e.g. "EPSG:32616, UTM zone 16 N".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crs_not_read: Option<String>,
}

/// A GeoTIFF's projected CRS in words when areo does not read its projection (then the
/// map is a local frame); `None` for other files, CRSs areo reads, and files it cannot
/// open (their reader says why).
pub fn crs_not_read(file: &Path) -> Option<String> {
    if areo_terrain::DemFormat::of(file) != Some(areo_terrain::DemFormat::GeoTiff) {
        return None;
    }
    geotiff::Windows::open(file, 1).ok()?.crs_not_read().map(String::from)
}

/// A summary of the DEM read from `file`.
pub fn info(file: &Path, dem: &Dem) -> DemInfo {
    let valid: Vec<f32> = dem.elevations().iter().zip(dem.valid_mask()).filter(|(_, v)| **v).map(|(z, _)| *z).collect();
    let (lo, hi) = valid.iter().fold((f32::MAX, f32::MIN), |(a, b), z| (a.min(*z), b.max(*z)));
    let mean = valid.iter().map(|z| f64::from(*z)).fold(0.0, |a, b| a + b) / valid.len().max(1) as f64;
    let e = dem.extent();
    let g = dem.georef();
    let (projection, lat_ts_deg, lon0_deg, pole) = match g.projection {
        Projection::Local => ("local", None, None, None),
        Projection::Equirectangular { lat_ts_deg, lon0_deg } => {
            ("equirectangular", Some(lat_ts_deg), Some(lon0_deg), None)
        }
        Projection::PolarStereographic { north, lon0_deg } => {
            ("polar stereographic", None, Some(lon0_deg), Some(if north { "north" } else { "south" }))
        }
    };
    let (cx, cy) = ((e.x_min + e.x_max) / 2.0, (e.y_min + e.y_max) / 2.0);
    DemInfo {
        file: file.to_path_buf(),
        cols: dem.cols(),
        rows: dem.rows(),
        valid_cells: valid.len(),
        missing_cells: dem.cols() * dem.rows() - valid.len(),
        cell_m: [dem.dx(), dem.dy()],
        extent_m: [e.x_min, e.x_max, e.y_min, e.y_max],
        elevation_m: (!valid.is_empty()).then_some([f64::from(lo), f64::from(hi), mean]),
        projection,
        lat_ts_deg,
        lon0_deg,
        pole,
        body: g.surface.body().map(areo_ephemeris::Body::iau_name),
        radii_m: [g.surface.equatorial_radius_m, g.surface.polar_radius_m],
        centre_deg: dem.geographic(cx, cy).map(|(lat, lon)| [lat, lon]),
        crs_not_read: crs_not_read(file),
    }
}

/// Writes the slope (degrees, float32 GeoTIFF) of a DEM, and a hillshade preview PNG
/// beside it.
pub fn write_slope(dem: &Dem, out: &Path) -> Result<Vec<std::path::PathBuf>> {
    let sa = slope_aspect(dem);
    let slope_dem = dem.with_values(sa.slope_deg.clone())?;
    write_with(out, |tmp| Ok(geotiff::write(&slope_dem, tmp)?))?;
    let mut files = vec![out.to_path_buf()];
    files.extend(write_map_png(&out.with_extension("png"), dem, &hillshade_rgb(dem, &sa, None, 315.0, 45.0))?);
    Ok(files)
}

/// Writes the direct-sun map (uint8 GeoTIFF: 1 lit, 0 shadowed, 255 no data) for a Sun
/// at (azimuth, elevation), and a hillshade-with-shadows preview PNG beside it; cast
/// shadows decided by `method`. Returns the files and the lit fraction.
pub fn write_shadow(
    dem: &Dem,
    azimuth_deg: f64,
    elevation_deg: f64,
    flat: bool,
    method: ShadowMethod,
    out: &Path,
) -> Result<(Vec<std::path::PathBuf>, f64)> {
    let curvature = if flat { Curvature::Flat } else { Curvature::of(dem) };
    let map = Shadows::new(GridSunDirection::new(azimuth_deg, elevation_deg), curvature).method(method).map(dem);
    write_with(out, |tmp| Ok(geotiff::write_u8(dem, &map.to_u8(), Some(255), tmp)?))?;
    let sa = slope_aspect(dem);
    let dark: Vec<bool> = (0..map.cast.len()).map(|i| !map.direct_sun(i)).collect();
    let mut files = vec![out.to_path_buf()];
    let rgb = hillshade_rgb(dem, &sa, Some(&dark), azimuth_deg, elevation_deg);
    files.extend(write_map_png(&out.with_extension("png"), dem, &rgb)?);
    Ok((files, map.lit_fraction()))
}

/// What a tiled shadow run did.
#[derive(Debug, Clone, PartialEq)]
pub struct TiledShadow {
    /// The file written.
    pub file: std::path::PathBuf,
    /// Fraction of valid cells in direct sun.
    pub lit_fraction: f64,
    /// The longest possible shadow, m, and the halo read around each tile, cells.
    pub halo_m: f64,
    /// Halo columns and rows.
    pub halo_cells: (usize, usize),
    /// Tiles computed.
    pub tiles: usize,
    /// Written as BigTIFF (past 4 GB).
    pub bigtiff: bool,
}

/// The direct-sun map of a DEM file too large to hold, tile by tile: a GeoTIFF is read
/// a window at a time (other formats are read whole, then tiled), each `tile` × `tile`
/// tile with the halo its longest possible shadow needs, and the uint8 result is
/// written as a tiled GeoTIFF (`tile`-cell TIFF tiles; BigTIFF past 4 GB) as bands of
/// tiles finish. No preview PNG (the map may be 10⁸ cells). With the own-ray method
/// every cell is the whole-map answer.
#[allow(clippy::too_many_arguments)] // `areo terrain shadow --tile`'s options, as given
pub fn write_shadow_tiled(
    input: &Path,
    sun: (f64, f64),
    flat: bool,
    method: ShadowMethod,
    tile: usize,
    out: &Path,
    budget: &crate::budget::Budget,
    progress: &dyn crate::Progress,
) -> Result<TiledShadow> {
    use areo_terrain::tiles::{ShadowHalo, Tiling, relief};
    check_tile(tile)?;
    let (mut src, held_bytes) = Opened::open(input)?;
    let grid = src.grid();
    let Some(relief) = relief(&mut src, tile)? else {
        return Err(Error::usage(input.display().to_string(), "no cell has data"));
    };
    let curvature = if flat { Curvature::Flat } else { Curvature::of_surface(grid.georef.surface) };
    let halo = ShadowHalo::new(relief, &grid, sun.1)?;
    // A low Sun over high relief needs a wide halo: refuse before a window outgrows
    // the machine (the message names the estimate; a higher Sun or a smaller tile help).
    let window = ((tile + halo.cols + 4).min(grid.cols) as u64) * ((tile + halo.rows + 4).min(grid.rows) as u64);
    budget.check(&crate::budget::tiled_shadow(
        (grid.cols * grid.rows) as u64,
        tile as u64,
        window,
        (tile * grid.cols) as u64,
        held_bytes as u64,
    ))?;
    let shadows = Shadows::new(GridSunDirection::new(sun.0, sun.1), curvature).method(method);
    progress.start((grid.rows.div_ceil(tile) * grid.cols.div_ceil(tile)) as u64, "tiles");
    let (mut lit, mut valid, mut tiles, mut bigtiff) = (0u64, 0u64, 0usize, false);
    write_with(out, |tmp| {
        bigtiff = areo_terrain::geotiff::write_u8_tiled(&grid, Some(255), tile, false, tmp, |row0, band| {
            shadows.band(&mut src, Tiling { tile, halo }, row0, band, |done, _| {
                tiles = done;
                progress.advance(1);
            })?;
            for v in band.iter() {
                valid += u64::from(*v != 255);
                lit += u64::from(*v == 1);
            }
            Ok(())
        })?;
        Ok(())
    })?;
    progress.finish();
    Ok(TiledShadow {
        file: out.to_path_buf(),
        lit_fraction: lit as f64 / valid.max(1) as f64,
        halo_m: halo.metres,
        halo_cells: (halo.cols, halo.rows),
        tiles,
        bigtiff,
    })
}

/// A tiled horizon map written to a file.
#[derive(Debug, Clone)]
pub struct TiledHorizon {
    /// The file written: uint16 codes, a plane per sector.
    pub file: std::path::PathBuf,
    /// Sectors (planes).
    pub sectors: usize,
    /// The lowest horizon kept, degrees (lower ones are stored as it).
    pub lowest_deg: f64,
    /// The halo read around each tile, m and cells (columns, rows).
    pub halo_m: f64,
    /// Halo columns and rows.
    pub halo_cells: (usize, usize),
    /// Tiles computed.
    pub tiles: usize,
    /// Written as BigTIFF (past 4 GB).
    pub bigtiff: bool,
}

/// The horizon map of a DEM file too large to hold, tile by tile, for Suns at or above
/// `lowest_deg` (lower horizons are stored as it; the halo follows from it and the
/// relief): one tiled GeoTIFF of uint16 codes, a plane per sector (sector k centred on
/// azimuth k·360°/K; degrees = code × 180/65535 − 90, also written as GDAL band scale and
/// offset), each tile written as it finishes.
#[allow(clippy::too_many_arguments)] // `areo terrain horizon --tile`'s options, as given
pub fn write_horizon_tiled(
    input: &Path,
    sectors: usize,
    lowest_deg: f64,
    tile: usize,
    out: &Path,
    budget: &crate::budget::Budget,
    progress: &dyn crate::Progress,
) -> Result<TiledHorizon> {
    use areo_terrain::tiles::{HorizonTiles, ShadowHalo, relief, write_horizon_tiled};
    check_tile(tile)?;
    if !(16..=360).contains(&sectors) {
        return Err(Error::usage(format!("--sectors {sectors}"), "allowed 16..=360"));
    }
    if !(0.5..=89.0).contains(&lowest_deg) {
        return Err(Error::usage(
            format!("--lowest-sun {lowest_deg}"),
            "allowed 0.5..=89 degrees (the halo grows as 1/tan of it)",
        ));
    }
    let (mut src, held_bytes) = Opened::open(input)?;
    let grid = src.grid();
    let Some(relief) = relief(&mut src, tile)? else {
        return Err(Error::usage(input.display().to_string(), "no cell has data"));
    };
    let curvature = Curvature::of_surface(grid.georef.surface);
    let halo = ShadowHalo::new(relief, &grid, lowest_deg)?;
    let window = ((tile + 2 * halo.cols).min(grid.cols) as u64) * ((tile + 2 * halo.rows).min(grid.rows) as u64);
    budget.check(&crate::budget::tiled_horizon(
        (grid.cols * grid.rows) as u64,
        sectors as u64,
        tile as u64,
        window,
        held_bytes as u64,
    ))?;
    let plan = HorizonTiles { sectors, curvature, lowest_deg, halo, tile };
    progress.start((grid.rows.div_ceil(tile) * grid.cols.div_ceil(tile)) as u64, "tiles");
    let (mut tiles, mut bigtiff) = (0usize, false);
    write_with(out, |tmp| {
        bigtiff = write_horizon_tiled(&mut src, &plan, tmp, |done, _| {
            tiles = done;
            progress.advance(1);
        })?;
        Ok(())
    })?;
    progress.finish();
    Ok(TiledHorizon {
        file: out.to_path_buf(),
        sectors,
        lowest_deg,
        halo_m: halo.metres,
        halo_cells: (halo.cols, halo.rows),
        tiles,
        bigtiff,
    })
}

/// `--tile`: TIFF tiles are multiples of 16 cells.
fn check_tile(tile: usize) -> Result<()> {
    if tile < 16 || !tile.is_multiple_of(16) || tile > 65536 {
        return Err(Error::usage(
            format!("--tile {tile}"),
            "allowed a multiple of 16 in 16..=65536 (a TIFF tile's side)",
        ));
    }
    Ok(())
}

/// A DEM file opened for reading a window at a time: a GeoTIFF through its chunks,
/// other formats read whole.
enum Opened {
    Tiff(Box<areo_terrain::geotiff::Windows>),
    Whole(Dem),
}

impl Opened {
    /// The source and the bytes it holds (decoded chunks, or the whole DEM).
    fn open(input: &Path) -> Result<(Opened, usize)> {
        if areo_terrain::DemFormat::of(input) == Some(areo_terrain::DemFormat::GeoTiff) {
            let src = areo_terrain::geotiff::Windows::open(input, CHUNK_CACHE_BYTES)?;
            // The cache never holds more than the decoded map.
            let (cols, rows) = src.size();
            Ok((Opened::Tiff(Box::new(src)), CHUNK_CACHE_BYTES.min(cols * rows * 4)))
        } else {
            let dem = read_dem(input)?;
            let held = dem.cols() * dem.rows() * 5;
            Ok((Opened::Whole(dem), held))
        }
    }
}

impl areo_terrain::tiles::Source for Opened {
    fn grid(&self) -> areo_terrain::geotiff::Grid {
        match self {
            Opened::Tiff(w) => areo_terrain::tiles::Source::grid(w.as_ref()),
            Opened::Whole(d) => areo_terrain::tiles::Source::grid(d),
        }
    }
    fn window(&mut self, col0: usize, row0: usize, cols: usize, rows: usize) -> areo_terrain::Result<Dem> {
        match self {
            Opened::Tiff(w) => areo_terrain::tiles::Source::window(w.as_mut(), col0, row0, cols, rows),
            Opened::Whole(d) => areo_terrain::tiles::Source::window(d, col0, row0, cols, rows),
        }
    }
}

/// Decoded GeoTIFF chunks kept by a tiled run: enough for a band of tiles of strips.
const CHUNK_CACHE_BYTES: usize = 512 << 20;

/// Writes a horizon map: the directory `out` of one float32 GeoTIFF per sector
/// (`s000.tif`, `s001.tif`, …, degrees), since GeoTIFF readers expect single-band
/// DEM-like rasters here. The set is written into a staging directory beside `out`
/// and put in its place in one step, as a run's outputs are
/// (`output::staging::put_in_place`): a process killed at any moment leaves
/// the previous set or the new one, whole.
pub fn write_horizon(
    dem: &Dem,
    sectors: usize,
    out: &Path,
    progress: &dyn crate::Progress,
) -> Result<Vec<std::path::PathBuf>> {
    use crate::output::staging;
    progress.start(1, "horizon");
    let map = HorizonMap::compute(dem, sectors, Curvature::of(dem))?;
    progress.finish();
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    staging::clear_stale(out);
    let staged = staging::staging_path(out, "partial");
    std::fs::create_dir_all(&staged).map_err(io(&staged))?;
    let written = horizon_paths(&staged, sectors).iter().enumerate().try_for_each(|(s, path)| {
        let az = s as f64 * 360.0 / sectors as f64;
        let band: Vec<f32> = (0..dem.cols() * dem.rows()).map(|i| map.horizon_deg(i, az) as f32).collect();
        geotiff::write(&dem.with_values(band)?, path).map_err(Error::from)
    });
    let placed = written.and_then(|()| {
        staging::pause_for_tests(&staged);
        staging::put_in_place(&staged, out).map_err(io(out))
    });
    if placed.is_err() {
        // Best effort: a staging directory is of no use to anyone.
        let _ = std::fs::remove_dir_all(&staged);
    }
    placed.map(|()| horizon_paths(out, sectors))
}

/// The files of a horizon map of `sectors` sectors in the directory `out`:
/// `out/s000.tif`, `out/s001.tif`, …
pub fn horizon_paths(out: &Path, sectors: usize) -> Vec<std::path::PathBuf> {
    (0..sectors).map(|s| out.join(format!("s{s:03}.tif"))).collect()
}

/// Refuses `out` as the directory of a horizon map computed from `input`: a name
/// ending in a GeoTIFF's extension (the tiled map's single file) or the input itself.
pub fn check_horizon_dir(input: &Path, out: &Path) -> Result<()> {
    if areo_terrain::DemFormat::of(out).is_some() {
        return Err(Error::usage(
            format!("-o {}", out.display()),
            "without --tile the horizon map is a directory of one GeoTIFF per sector (s000.tif, …): name a \
             directory, e.g. -o horizon (with --tile, one GeoTIFF: -o horizon.tif)",
        ));
    }
    if out.is_file() || areo_terrain::input::same_file(input, out) {
        return Err(Error::usage(
            format!("-o {}", out.display()),
            "is a file: the horizon map is a directory (s000.tif, …), put in its place whole",
        ));
    }
    Ok(())
}

/// Writes the viewshed from a point `height_m` above the ground at (x, y) (uint8
/// GeoTIFF: 1 visible, 0 hidden, 255 no data) and a preview PNG beside it; returns the
/// files and the visible fraction.
pub fn write_viewshed(dem: &Dem, x: f64, y: f64, height_m: f64, out: &Path) -> Result<(Vec<std::path::PathBuf>, f64)> {
    if !(height_m > 0.0 && height_m <= 1e5) {
        return Err(Error::usage(
            format!("--from height {height_m} m"),
            "allowed 0 (exclusive)..=100000 m above the ground",
        ));
    }
    if dem.cols() < 2 || dem.rows() < 2 {
        return Err(Error::usage(
            format!("terrain viewshed on {} × {} cells", dem.cols(), dem.rows()),
            "a viewshed needs a DEM of at least 2 x 2 cells",
        ));
    }
    let e = dem.extent();
    if !(x >= e.x_min && x <= e.x_max && y >= e.y_min && y <= e.y_max) {
        return Err(Error::usage(
            format!("--from ({x}, {y})"),
            format!("off the map (x {} .. {} m, y {} .. {} m)", e.x_min, e.x_max, e.y_min, e.y_max),
        ));
    }
    let seen = areo_terrain::los::viewshed(dem, x, y, height_m, Curvature::of(dem))?;
    let bytes: Vec<u8> =
        seen.iter().zip(dem.valid_mask()).map(|(s, ok)| if !ok { 255 } else { u8::from(*s) }).collect();
    write_with(out, |tmp| Ok(geotiff::write_u8(dem, &bytes, Some(255), tmp)?))?;
    let sa = slope_aspect(dem);
    let hidden: Vec<bool> = seen.iter().map(|s| !s).collect();
    let mut files = vec![out.to_path_buf()];
    files.extend(write_map_png(&out.with_extension("png"), dem, &hillshade_rgb(dem, &sa, Some(&hidden), 315.0, 45.0))?);
    let valid = dem.valid_mask().iter().filter(|v| **v).count().max(1);
    Ok((files, seen.iter().filter(|s| **s).count() as f64 / valid as f64))
}
