//! Cast shadows from the Sun, and shadow maps (cast shadow plus slopes facing away).
//!
//! One door: a [`Shadows`] question — the Sun, the world's curvature and a [`Method`] —
//! asked of a source: [`Shadows::cast`] and [`Shadows::map`] for a map in memory,
//! [`Shadows::by_tiles`] and [`Shadows::band`] for one read tile by tile
//! ([`crate::tiles`]). The surface is the DEM's
//! triangulated surface — cell centres joined by the grid lines and by each quad's
//! south-west–north-east diagonal, the split parry3d's `HeightField` uses — and a cell
//! is in cast shadow when terrain stands above the ray from its centre toward the Sun.
//! With planetary curvature an occluder d metres away sits d²/2R lower as seen from
//! the cell. Terrain beyond the DEM's edge never shadows, so the sun-side border is
//! lit. The [`Method`]s:
//!
//! | method | decides each cell by | against its own ray (`reference`) |
//! |---|---|---|
//! | [`Method::OwnRay`] (default) | its own ray, with certified shortcuts | every cell at every azimuth tested (`tests/shadow_methods.rs`, `own_ray` unit tests: the Gale MOLA map, full and cropped, 75 azimuths, flat and curved; synthesised terrain, 72 azimuths) |
//! | [`Method::Sheared`] | a trace; beyond the first step, rays up to a third of a cell aside lend their occluders | 0 differ on cardinal azimuths; at most 0.25 % of cells at a Sun ≥ 5° up, 0.5 % at 2° (measured on the full Gale map: ≤ 0.112 % and ≤ 0.196 %) |
//! | [`Method::Interpolated`] | a trace on the coarser grid-line surface, envelopes interpolated | ≥ 99.5 % of cells of its own surface (`reference::horizon_on_grid_lines`), disagreements within 1° of grazing |
//!
//! Speeds on the 2527 × 2356 Gale map are in docs/benchmarks.md
//! (`cargo bench -p areo-terrain`, `cargo xtask bench`).
//!
//! A [`ShadowMap`] ([`Shadows::map`]) also darkens cells whose own slope faces away
//! from the Sun (`facing_away`, from the Horn normal): these are not cast shadows, and
//! at a low Sun they are many.
//!
//! | source | how | tiling |
//! |---|---|---|
//! | a [`Dem`] in memory | [`Shadows::cast`], [`Shadows::map`] | whole map |
//! | a [`crate::tiles::Source`] too large to hold (a GeoTIFF read by windows) | [`Shadows::by_tiles`], [`Shadows::band`] | [`crate::tiles::Tiling`]: tile side and halo; with [`Method::OwnRay`] the whole map's answer |
//! | many Suns over one map's precomputed horizons | [`crate::horizon::HorizonMap::shadowed`] | whole map |
//!
//! The brute-force oracles are in `reference`, compiled for tests and with the
//! `reference` feature.

mod interpolated;
mod own_ray;
mod sheared;

use crate::dem::Dem;
use crate::slope::horn_gradient;

/// The Sun's direction on the map's grid: azimuth clockwise from the grid's north (up
/// in the image, the direction shadows are cast along — true north only where the
/// map's meridians are its columns; [`crate::Projection::true_north_on_grid_deg`]
/// turns one into the other) and elevation above the local horizontal, degrees.
/// areo-ephemeris's `TrueSunDirection` is the same Sun clockwise from true north.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSunDirection {
    /// Degrees clockwise from the grid's north.
    pub azimuth_deg: f64,
    /// Degrees above the local horizontal; at or below 0 every cell is in shadow.
    pub elevation_deg: f64,
}

impl GridSunDirection {
    /// The Sun at `azimuth_deg` (clockwise from the grid's north), `elevation_deg` up.
    pub fn new(azimuth_deg: f64, elevation_deg: f64) -> GridSunDirection {
        GridSunDirection { azimuth_deg, elevation_deg }
    }
}

/// How [`Shadows`] decides each cell; see the module docs for what each agrees with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Each cell by its own ray, as the brute force does.
    #[default]
    OwnRay,
    /// A trace that lends a cell the occluders of the rays beside it: approximate off
    /// the cardinal azimuths.
    Sheared,
    /// A trace on the grid-line surface that interpolates envelopes between rays:
    /// the cheapest, approximate.
    Interpolated,
}

/// A shadow question: where the Sun stands, whether the world curves, and how each
/// cell is decided. Ask it of a source with [`Shadows::cast`], [`Shadows::map`] (a map
/// in memory) or [`Shadows::by_tiles`] (a map read tile by tile).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shadows {
    /// The Sun's direction.
    pub sun: GridSunDirection,
    /// Flat or curved world.
    pub curvature: Curvature,
    /// How each cell is decided ([`Method::OwnRay`] unless set).
    pub method: Method,
}

impl Shadows {
    /// Shadows of the Sun at `sun` on a world of `curvature`, each cell by its own ray.
    pub fn new(sun: GridSunDirection, curvature: Curvature) -> Shadows {
        Shadows { sun, curvature, method: Method::default() }
    }

    /// The same question decided by `method`.
    pub fn method(self, method: Method) -> Shadows {
        Shadows { method, ..self }
    }

    /// Cast shadow (true = shadowed) of every cell of `dem`, row-major like the DEM.
    pub fn cast(&self, dem: &Dem) -> Vec<bool> {
        cast_shadows(dem, self.sun, self.curvature, self.method)
    }

    /// The shadow map of `dem`: cast shadows, and the cells facing away from the Sun.
    pub fn map(&self, dem: &Dem) -> ShadowMap {
        shadow_map_from(dem, self.sun, self.cast(dem))
    }
}

/// Cast shadow (true = shadowed) of every cell, row-major like the DEM.
pub(crate) fn cast_shadows(dem: &Dem, sun: GridSunDirection, curvature: Curvature, method: Method) -> Vec<bool> {
    let (az, el) = (sun.azimuth_deg, sun.elevation_deg);
    if el <= 0.0 {
        // Below the local horizontal the Sun is behind the surface everywhere.
        return vec![true; dem.cols() * dem.rows()];
    }
    match method {
        Method::OwnRay => own_ray::cast(dem, az, el, curvature),
        Method::Sheared => sheared::cast(dem, az, el, curvature),
        Method::Interpolated => interpolated::cast(dem, az, el, curvature),
    }
}

/// Whether shadows account for the surface curving away.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Curvature {
    /// A flat world.
    Flat,
    /// A sphere of this radius, m.
    Sphere {
        /// Radius, m.
        radius_m: f64,
    },
}

impl Curvature {
    /// The sphere a body's ground drops away on: its published mean radius
    /// ([`areo_body::Body::mean_radius_m`]: Mars 3389.5 km, the Moon 1737.4 km, the
    /// Earth 6371.0088 km). The one rule for horizons, shadows and lines of sight, in
    /// the terrain tools and the planner alike.
    pub fn of_body(body: areo_body::Body) -> Curvature {
        Curvature::Sphere { radius_m: body.mean_radius_m() }
    }

    /// The curvature of the body a reference surface belongs to
    /// ([`Curvature::of_body`]); a surface of no known body drops away on its own mean
    /// radius.
    pub fn of_surface(surface: areo_body::Spheroid) -> Curvature {
        surface.body().map_or(Curvature::Sphere { radius_m: surface.mean_radius_m() }, Curvature::of_body)
    }

    /// The curvature of the DEM's reference surface's body ([`Curvature::of_surface`]).
    pub fn of(dem: &Dem) -> Curvature {
        Curvature::of_surface(dem.georef().surface)
    }

    /// 1/2R (0 for a flat world): an occluder at distance d sits d²·(1/2R) lower.
    pub(crate) fn inv_2r(self) -> f64 {
        match self {
            Curvature::Flat => 0.0,
            Curvature::Sphere { radius_m } => 0.5 / radius_m,
        }
    }
}

/// The lighting of every cell for one source direction.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadowMap {
    /// Cast shadow: terrain between the cell and the source.
    pub cast: Vec<bool>,
    /// The cell's own slope faces away (incidence on the Horn normal ≥ 90°).
    pub facing_away: Vec<bool>,
    /// Cells with data.
    pub valid: Vec<bool>,
}

impl ShadowMap {
    /// Direct sun on cell `i`: valid, not cast-shadowed and not facing away.
    pub fn direct_sun(&self, i: usize) -> bool {
        self.valid[i] && !self.cast[i] && !self.facing_away[i]
    }

    /// Fraction of valid cells in direct sun.
    pub fn lit_fraction(&self) -> f64 {
        let valid = self.valid.iter().filter(|v| **v).count();
        let lit = (0..self.cast.len()).filter(|&i| self.direct_sun(i)).count();
        lit as f64 / valid.max(1) as f64
    }

    /// As bytes: 1 in direct sun, 0 shadowed, 255 no data.
    pub fn to_u8(&self) -> Vec<u8> {
        (0..self.cast.len()).map(|i| if !self.valid[i] { 255 } else { u8::from(self.direct_sun(i)) }).collect()
    }
}

/// [`Shadows::map`] around a cast-shadow map already computed for the same Sun.
pub(crate) fn shadow_map_from(dem: &Dem, sun: GridSunDirection, cast: Vec<bool>) -> ShadowMap {
    let valid = dem.valid_mask().to_vec();
    let (gx, gy) = horn_gradient(dem);
    let (sa, ca) = sun.azimuth_deg.to_radians().sin_cos();
    let (se, ce) = sun.elevation_deg.to_radians().sin_cos();
    let sun = [ce * sa, ce * ca, se];
    let facing_away = gx
        .iter()
        .zip(&gy)
        .map(|(&x, &y)| {
            let n = crate::dem::unit_normal(f64::from(x), f64::from(y));
            !(n[0] * sun[0] + n[1] * sun[1] + n[2] * sun[2] > 0.0)
        })
        .collect();
    ShadowMap { cast, facing_away, valid }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One curvature rule: a DEM on any of Mars's reference surfaces (the MOLA sphere,
    /// the IAU ellipsoid) drops away on Mars's published mean radius, the one the
    /// planner's horizon maps use; a sphere of no known body on its own radius.
    #[test]
    fn a_dem_curves_with_its_bodys_mean_radius() {
        use crate::{Georef, Projection, Spheroid};
        let projection = Projection::Equirectangular { lat_ts_deg: 0.0, lon0_deg: 0.0 };
        let on = |surface: Spheroid| {
            let dem = Dem::from_fn(4, 4, 10.0, 10.0, |_, _| 0.0).unwrap().with_georef(Georef { projection, surface });
            Curvature::of(&dem)
        };
        let mars = Curvature::Sphere { radius_m: 3_389_500.0 };
        assert_eq!(on(Spheroid::MARS_MOLA_SPHERE), mars);
        assert_eq!(on(Spheroid::MARS_IAU2015), mars);
        assert_eq!(on(Spheroid::MOON), Curvature::Sphere { radius_m: 1_737_400.0 });
        assert_eq!(on(Spheroid::EARTH_WGS84), Curvature::Sphere { radius_m: 6_371_008.8 });
        let ganymede = Spheroid { equatorial_radius_m: 2_634_100.0, polar_radius_m: 2_634_100.0 };
        assert_eq!(on(ganymede), Curvature::Sphere { radius_m: 2_634_100.0 });
    }

    #[test]
    fn every_method_puts_a_walls_shadow_h_over_tan_e_behind_it() {
        // A 20 m wall along x = 50 on flat ground; Sun in the west at 30°: 34.6 m east.
        let (h, e) = (20.0, 30.0f64);
        let dem = Dem::from_fn(200, 20, 1.0, 1.0, |x, _| if (50.0..51.0).contains(&x) { h } else { 0.0 }).unwrap();
        for method in [Method::OwnRay, Method::Sheared, Method::Interpolated] {
            let s = cast_shadows(&dem, GridSunDirection::new(270.0, e), Curvature::Flat, method);
            let len = (51..200).take_while(|&c| s[10 * 200 + c]).count() as f64;
            assert!((len - h / e.to_radians().tan()).abs() <= 1.0, "{method:?}: shadow {len} m");
            assert!((0..50).all(|c| !s[10 * 200 + c]), "{method:?}: the sun side is lit");
        }
    }

    #[test]
    fn sun_side_border_is_lit_and_a_sun_below_the_horizon_lights_nothing() {
        let dem = Dem::from_fn(30, 30, 1.0, 1.0, |x, y| (x * 0.7).sin() * 5.0 + (y * 0.3).cos() * 5.0).unwrap();
        for method in [Method::OwnRay, Method::Sheared, Method::Interpolated] {
            let s = cast_shadows(&dem, GridSunDirection::new(0.0, 5.0), Curvature::Flat, method);
            assert!((0..30).all(|c| !s[c]), "{method:?}: the northern border faces a northern Sun unobstructed");
        }
        let m = Shadows::new(GridSunDirection::new(0.0, -1.0), Curvature::Flat).map(&dem);
        assert_eq!(m.lit_fraction(), 0.0);
    }

    #[test]
    fn a_distant_peak_below_the_curved_horizon_casts_no_shadow() {
        // A 1000 m peak 100 km west of a plain, Sun in the west at 0.3°: on a flat world
        // its shadow reaches 191 km; on Mars the surface drops d²/2R ≈ 1.47 km at
        // 100 km, hiding it.
        let dem = Dem::from_fn(1101, 3, 100.0, 100.0, |x, _| if x < 100.0 { 1000.0 } else { 0.0 }).unwrap();
        let target = 2 * 1101 + 1000;
        let mars = Curvature::Sphere { radius_m: 3_389_500.0 };
        for method in [Method::OwnRay, Method::Sheared, Method::Interpolated] {
            assert!(
                cast_shadows(&dem, GridSunDirection::new(270.0, 0.3), Curvature::Flat, method)[target],
                "{method:?}"
            );
            assert!(!cast_shadows(&dem, GridSunDirection::new(270.0, 0.3), mars, method)[target], "{method:?}");
        }
    }
}
