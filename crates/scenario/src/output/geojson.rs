//! GeoJSON through the `geojson` crate. Coordinates are [longitude east in −180..180,
//! latitude] in degrees on the run's [`Geography`]. GeoJSON (RFC 7946) assumes WGS 84,
//! so every collection names the run's CRS in the 2008 GeoJSON `crs` member — its IAU
//! code (`{"type": "name", "properties": {"name": "IAU_2015:49900"}}` on Mars's IAU
//! sphere) or else its WKT2 — which GDAL and QGIS read (GDAL 3.6 reports "Mars (2015) -
//! Sphere / Ocentric", or the WKT's sphere; JSON-FG's `coordRefSys` is not read by the
//! GeoJSON driver); a `body` member adds the sphere's radius.

use std::path::Path;

use geojson::{Feature, FeatureCollection, Geometry, JsonObject, JsonValue};

use crate::error::{Error, Result};
use crate::report::Geography;

pub(crate) use crate::report::lon180;

/// A feature with `geometry` and the properties of a JSON object (`serde_json::json!`);
/// anything else gives no properties.
pub(crate) fn feature(geometry: Geometry, properties: JsonValue) -> Feature {
    Feature {
        geometry: Some(geometry),
        properties: match properties {
            JsonValue::Object(map) => Some(map),
            _ => None,
        },
        ..Feature::default()
    }
}

/// A point at (latitude, longitude east), degrees.
pub(crate) fn point((lat, lon): (f64, f64)) -> Geometry {
    Geometry::new_point([lon180(lon), lat])
}

/// A line through (latitude, longitude east) points, degrees.
pub(crate) fn line(points: impl IntoIterator<Item = (f64, f64)>) -> Geometry {
    Geometry::new_line_string(points.into_iter().map(|(lat, lon)| [lon180(lon), lat]).collect::<Vec<_>>())
}

/// The features as a collection on the run's geography: its CRS by code or WKT2
/// ([`Geography::crs_code_or_wkt2`]) and a `body` member with the sphere's radii (equal:
/// a Cesium or three.js user builds the ellipsoid from them).
pub(crate) fn collection(features: Vec<Feature>, geography: &Geography) -> FeatureCollection {
    let mut members = JsonObject::new();
    members.insert("body".into(), body_member(geography));
    members.insert(
        "crs".into(),
        serde_json::json!({ "type": "name", "properties": { "name": geography.crs_code_or_wkt2() } }),
    );
    let mut fc = FeatureCollection::new(features);
    // The crate's box of no features is `[]`, which RFC 7946 (section 5) does not allow:
    // a box has two numbers per dimension, or is left out.
    if fc.bbox.as_ref().is_some_and(Vec::is_empty) {
        fc.bbox = None;
    }
    fc.foreign_members = Some(members);
    fc
}

/// The body, its sphere and the conventions of the coordinates, as a JSON object.
pub(crate) fn body_member(g: &Geography) -> JsonValue {
    serde_json::json!({
        "name": g.body,
        "crs_name": g.crs_name,
        "equatorial_radius_m": g.radius_m,
        "polar_radius_m": g.radius_m,
        "latitude": Geography::LATITUDE,
        "longitude": Geography::LONGITUDE,
    })
}

/// Writes the collection as pretty JSON (atomically, see [`super::write_file`]).
pub(crate) fn write(path: &Path, fc: &FeatureCollection) -> Result<()> {
    let text = serde_json::to_string_pretty(fc)
        .map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) })?;
    super::write_file(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use areo_terrain::Spheroid;

    #[test]
    fn a_route_round_trips_with_its_body_and_names_intact() {
        let features = vec![
            feature(line([(-4.6, 137.4), (-4.5, 137.5)]), serde_json::json!({"name": "plan, \"initial\""})),
            feature(point((-4.5, 200.0)), serde_json::json!({"kind": "goal"})),
        ];
        let mola = Geography::of(&Spheroid::MARS_MOLA_SPHERE);
        let fc = collection(features, &mola);
        let text = serde_json::to_string(&fc).unwrap();
        let back: geojson::GeoJson = text.parse().unwrap();
        let geojson::GeoJson::FeatureCollection(back) = back else { panic!("not a collection") };
        assert_eq!(back.features.len(), 2);
        assert_eq!(back.features[0].property("name").and_then(JsonValue::as_str), Some("plan, \"initial\""));
        // 200°E is −160° in GeoJSON's range; latitude second.
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["features"][1]["geometry"]["coordinates"], serde_json::json!([-160.0, -4.5]));
        assert_eq!(v["body"]["name"], "Mars");
        assert_eq!(v["body"]["equatorial_radius_m"], 3_396_000.0);
        assert_eq!(v["body"]["latitude"], "planetocentric");
        // The MOLA sphere is not the IAU's (3 396 190 m): named by its WKT2, as the
        // GeoTIFFs name it.
        assert_eq!(v["crs"]["properties"]["name"], mola.crs_wkt2.as_str());
        assert_eq!(v["body"]["polar_radius_m"], 3_396_000.0);
        let iau = serde_json::to_value(collection(Vec::new(), &Geography::of(&Spheroid::MARS_IAU2015))).unwrap();
        assert_eq!(iau["crs"], serde_json::json!({"type": "name", "properties": {"name": "IAU_2015:49900"}}));
        assert_eq!(iau["body"]["polar_radius_m"], 3_396_190.0, "the sphere areo projects on, not the ellipsoid");
        let moon = serde_json::to_value(collection(Vec::new(), &Geography::of(&Spheroid::MOON))).unwrap();
        assert_eq!(moon["crs"]["properties"]["name"], "IAU_2015:30100");
        let earth = serde_json::to_value(collection(Vec::new(), &Geography::of(&Spheroid::EARTH_WGS84))).unwrap();
        assert!(
            earth["crs"]["properties"]["name"]
                .as_str()
                .unwrap()
                .starts_with(r#"GEOGCRS["Earth - Sphere, R = 6378137 m"#)
        );
        assert_eq!(earth["body"]["polar_radius_m"], 6_378_137.0);
        // No features, no box (RFC 7946 allows none, not an empty one); with features,
        // none either unless each feature has one.
        assert!(moon.get("bbox").is_none(), "{moon}");
        assert!(v.get("bbox").is_none(), "{v}");
    }
}
