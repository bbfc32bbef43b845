//! The geographic CRS a map's latitudes and longitudes are on, named once for every
//! file a run writes.
//!
//! areo's projections are spherical on the equatorial radius of the map's reference
//! surface ([`crate::Projection`]), so the latitude and longitude of a map point are
//! angles on that sphere: planetocentric latitude, east longitude. That sphere is the
//! datum every output names — the GeoTIFF keys' citations, a map's WKT2, the GeoJSON
//! and CZML `crs`, a CSV's `.prj` — even where the body's own ellipsoid is flattened
//! (the Earth's WGS 84): a GIS tool then computes the latitudes areo reports. The names
//! follow the IAU 2015 CRS database as GDAL and PROJ spell it (`Mars (2015) - Sphere /
//! Ocentric`), whose spheres are the bodies' equatorial radii; another radius is named
//! with its value (`Mars - Sphere, R = 3396000 m / Ocentric`, the MOLA sphere).

use areo_body::{Body, Spheroid};

/// How close (m) a sphere's radius must be to an IAU 2015 sphere's to take its name
/// and code: the IAU radii are given to the metre.
const SAME_RADIUS_M: f64 = 0.5;

/// East longitude in −180..180, degrees: the one convention of every longitude written
/// (GeoJSON's range; a projection's central meridian as well as a route's points).
pub fn lon180(lon: f64) -> f64 {
    let l = lon.rem_euclid(360.0);
    if l > 180.0 { l - 360.0 } else { l }
}

/// The sphere a map's latitudes and longitudes are on, and its names.
#[derive(Debug, Clone, PartialEq)]
pub struct GeographicCrs {
    /// The body, where the radius is a known body's ([`Spheroid::body`]).
    pub body: Option<Body>,
    /// The sphere's radius, m (the surface's equatorial radius).
    pub radius_m: f64,
    /// The sphere's (ellipsoid's and datum's) name: `Mars (2015) - Sphere`.
    pub sphere: String,
    /// The geographic CRS's name: `Mars (2015) - Sphere / Ocentric`.
    pub name: String,
    /// Its IAU 2015 code where the sphere is the IAU's (`IAU_2015:49900`), as PROJ ≥ 8.2
    /// knows it.
    pub iau_code: Option<String>,
}

impl GeographicCrs {
    /// The geographic CRS of maps projected on `surface` (on the sphere of its
    /// equatorial radius).
    pub fn of(surface: &Spheroid) -> GeographicCrs {
        let a = surface.equatorial_radius_m;
        let body = surface.body();
        // The IAU 2015 Earth is a sphere of 6 378 136.6 m, not WGS 84's radius: only Mars
        // and the Moon share areo's spheres.
        let iau = body
            .filter(|b| matches!(b, Body::Mars | Body::Moon) && (a - b.equatorial_radius_m()).abs() < SAME_RADIUS_M);
        let sphere = match (iau, body) {
            (Some(b), _) => format!("{} (2015) - Sphere", b.iau_name()),
            (None, Some(b)) => format!("{} - Sphere, R = {a} m", b.iau_name()),
            (None, None) => format!("Sphere, R = {a} m"),
        };
        GeographicCrs {
            body,
            radius_m: a,
            name: format!("{sphere} / Ocentric"),
            sphere,
            iau_code: iau.map(|b| format!("IAU_2015:{}", b.naif_id() * 100)),
        }
    }

    /// The body's name (`Mars`, `Moon`, `Earth`), or `unknown`.
    pub fn body_name(&self) -> &'static str {
        self.body.map_or("unknown", Body::iau_name)
    }

    /// The datum and prime meridian as WKT2 (ISO 19162:2019) nodes, the part a
    /// geographic and a projected CRS share.
    pub fn datum_wkt2(&self) -> String {
        let s = &self.sphere;
        format!(
            r#"DATUM["{s}",ELLIPSOID["{s}",{},0,LENGTHUNIT["metre",1]]],PRIMEM["Reference Meridian",0,ANGLEUNIT["degree",0.0174532925199433]]"#,
            self.radius_m
        )
    }

    /// The geographic CRS as WKT2: latitude and east longitude in degrees on the sphere.
    pub fn wkt2(&self) -> String {
        let deg = r#"ANGLEUNIT["degree",0.0174532925199433]"#;
        format!(
            r#"GEOGCRS["{}",{},CS[ellipsoidal,2],AXIS["latitude",north,ORDER[1],{deg}],AXIS["longitude",east,ORDER[2],{deg}]]"#,
            self.name,
            self.datum_wkt2()
        )
    }

    /// What names the CRS where a format holds one string (GeoJSON's `crs` name): the
    /// IAU code where there is one, else the WKT2 (GDAL reads either).
    pub fn name_or_wkt2(&self) -> String {
        self.iau_code.clone().unwrap_or_else(|| self.wkt2())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_iau_spheres_take_their_codes_and_other_radii_are_named_by_their_value() {
        let mars = GeographicCrs::of(&Spheroid::MARS_IAU2015);
        assert_eq!(mars.name, "Mars (2015) - Sphere / Ocentric");
        assert_eq!(mars.iau_code.as_deref(), Some("IAU_2015:49900"));
        assert_eq!(mars.radius_m, 3_396_190.0);
        let mola = GeographicCrs::of(&Spheroid::MARS_MOLA_SPHERE);
        assert_eq!(mola.name, "Mars - Sphere, R = 3396000 m / Ocentric");
        assert_eq!(mola.iau_code, None);
        assert!(mola.name_or_wkt2().starts_with(r#"GEOGCRS["Mars - Sphere, R = 3396000 m / Ocentric",DATUM["#));
        assert!(mola.wkt2().contains(r#"ELLIPSOID["Mars - Sphere, R = 3396000 m",3396000,0,"#));
        let moon = GeographicCrs::of(&Spheroid::MOON);
        assert_eq!(moon.iau_code.as_deref(), Some("IAU_2015:30100"));
        assert_eq!(moon.body_name(), "Moon");
        // The Earth's maps are projected on the sphere of WGS 84's equatorial radius: the
        // sphere, not WGS 84 (no IAU code: the IAU's Earth is not areo's).
        let earth = GeographicCrs::of(&Spheroid::EARTH_WGS84);
        assert_eq!(earth.name, "Earth - Sphere, R = 6378137 m / Ocentric");
        assert_eq!(earth.iau_code, None);
        let odd = GeographicCrs::of(&Spheroid { equatorial_radius_m: 2e6, polar_radius_m: 2e6 });
        assert_eq!((odd.name.as_str(), odd.body_name()), ("Sphere, R = 2000000 m / Ocentric", "unknown"));
    }
}
