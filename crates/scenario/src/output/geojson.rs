//! GeoJSON through the `geojson` crate. Coordinates are [longitude east in −180..180,
//! latitude] in degrees on the map's body. GeoJSON (RFC 7946) assumes WGS 84, so every
//! collection names its body's CRS in the 2008 GeoJSON `crs` member —
//! `{"type": "name", "properties": {"name": "IAU_2015:49900"}}` on Mars — which GDAL
//! and QGIS read (GDAL 3.6 reports "Mars (2015) - Sphere / Ocentric"; JSON-FG's
//! `coordRefSys` is not read by the GeoJSON driver); a `body` member adds its radii.

use std::path::Path;

use areo_terrain::Spheroid;
use geojson::{Feature, FeatureCollection, Geometry, JsonObject, JsonValue};

use crate::error::{Error, Result};

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

/// The features as a collection on `body`: its geographic CRS by name
/// ([`areo_ephemeris::Body::geographic_crs`]; left out for radii of no known body) and
/// the body's radii and axes as foreign members.
pub(crate) fn collection(features: Vec<Feature>, body: &Spheroid) -> FeatureCollection {
    let mut members = JsonObject::new();
    members.insert(
        "body".into(),
        serde_json::json!({
            "name": body_name(body),
            "equatorial_radius_m": body.equatorial_radius_m,
            "polar_radius_m": body.polar_radius_m,
            "latitude": if body.body() == Some(areo_ephemeris::Body::Earth) { "geodetic" } else { "planetocentric" },
            "longitude": "east, -180..180",
        }),
    );
    if let Some(b) = body.body() {
        members
            .insert("crs".into(), serde_json::json!({ "type": "name", "properties": { "name": b.geographic_crs() } }));
    }
    let mut fc = FeatureCollection::new(features);
    // The crate's box of no features is `[]`, which RFC 7946 (section 5) does not allow:
    // a box has two numbers per dimension, or is left out.
    if fc.bbox.as_ref().is_some_and(Vec::is_empty) {
        fc.bbox = None;
    }
    fc.foreign_members = Some(members);
    fc
}

/// The body's name where its radii are a known reference body's.
pub(crate) fn body_name(body: &Spheroid) -> &'static str {
    body.body().map_or("unknown", areo_ephemeris::Body::iau_name)
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

    #[test]
    fn a_route_round_trips_with_its_body_and_names_intact() {
        let features = vec![
            feature(line([(-4.6, 137.4), (-4.5, 137.5)]), serde_json::json!({"name": "plan, \"initial\""})),
            feature(point((-4.5, 200.0)), serde_json::json!({"kind": "goal"})),
        ];
        let fc = collection(features, &Spheroid::MARS_MOLA_SPHERE);
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
        assert_eq!(v["crs"], serde_json::json!({"type": "name", "properties": {"name": "IAU_2015:49900"}}));
        let moon: serde_json::Value = serde_json::to_value(collection(Vec::new(), &Spheroid::MOON)).unwrap();
        assert_eq!(moon["crs"]["properties"]["name"], "IAU_2015:30100");
        let earth: serde_json::Value = serde_json::to_value(collection(Vec::new(), &Spheroid::EARTH_WGS84)).unwrap();
        assert_eq!(earth["crs"]["properties"]["name"], "urn:ogc:def:crs:OGC:1.3:CRS84");
        let odd = Spheroid { equatorial_radius_m: 2e6, polar_radius_m: 2e6 };
        assert!(serde_json::to_value(collection(Vec::new(), &odd)).unwrap().get("crs").is_none());
        // No features, no box (RFC 7946 allows none, not an empty one); with features,
        // none either unless each feature has one.
        assert!(moon.get("bbox").is_none(), "{moon}");
        assert!(v.get("bbox").is_none(), "{v}");
    }
}
