//! A TEMPEST report's route in time, for the tools mission teams scrub through it
//! with: `route_time.geojson` — MMGIS's enhanced GeoJSON, the route as one LineString
//! whose vertices carry their instant, battery and Sun (`coord_properties`), and one
//! feature per action with `start_utc` and `end_utc` for a time slider — and
//! `route.czml`, the traverse as a Cesium animation (a clock, the rover's time-tagged
//! path, the goals), with `route.cesium.html`, a page that loads it in CesiumJS on the
//! body it names.

use serde_json::{Value, json};

use crate::output::geojson::{collection, lon180};
use crate::report::tempest::{RoutePlaces, RouteVertex, TempestReport};

/// The names of a vertex's values in `route_time.geojson`, in their order: MMGIS's
/// enhanced GeoJSON reads the first three by these names (the elevation in metres on
/// the body's reference sphere).
pub(super) const COORD_PROPERTIES: [&str; 7] =
    ["longitude", "latitude", "elevation", "unix_s", "t_h", "battery_wh", "sun_elevation_deg"];

/// `route_time.geojson`: the route in time on the report's body.
pub(super) fn route_time_geojson(r: &TempestReport, route: &RoutePlaces) -> Value {
    let executed = r.simulation.is_some();
    let v = &route.timeline;
    let coordinates: Vec<Value> = v
        .iter()
        .map(|p| {
            json!([lon180(p.lon_deg), p.lat_deg, p.elevation_m, p.unix_s, p.t_h, p.battery_wh, p.sun_elevation_deg])
        })
        .collect();
    let mut features = vec![json!({
        "type": "Feature",
        "properties": {
            "name": if executed { "executed route" } else { "initial plan" },
            "coord_properties": COORD_PROPERTIES,
            "utc": v.iter().map(|p| p.utc.as_str()).collect::<Vec<_>>(),
            "activity": v.iter().map(|p| p.activity.as_str()).collect::<Vec<_>>(),
            "start_utc": v.first().map(|p| p.utc.as_str()),
            "end_utc": v.last().map(|p| p.utc.as_str()),
        },
        "geometry": { "type": "LineString", "coordinates": coordinates },
    })];
    features.extend(v.windows(2).enumerate().map(|(k, w)| action_feature(k, &w[0], &w[1], executed)));
    let mut fc = serde_json::to_value(collection(Vec::new(), &route.geography)).unwrap_or_else(|_| json!({}));
    fc["features"] = Value::Array(features);
    fc
}

/// The action from vertex `a` to vertex `b`: a LineString where the rover moved, a Point
/// where it stayed. An executed route's vertex names what brought the rover there, a
/// plan's what it does next.
fn action_feature(k: usize, a: &RouteVertex, b: &RouteVertex, executed: bool) -> Value {
    let activity = if executed { &b.activity } else { &a.activity };
    let (pa, pb) = ([lon180(a.lon_deg), a.lat_deg], [lon180(b.lon_deg), b.lat_deg]);
    let geometry = if pa == pb {
        json!({ "type": "Point", "coordinates": pa })
    } else {
        json!({ "type": "LineString", "coordinates": [pa, pb] })
    };
    json!({
        "type": "Feature",
        "properties": {
            "kind": "action", "index": k, "activity": activity,
            "start_utc": a.utc, "end_utc": b.utc, "start_unix_s": a.unix_s, "end_unix_s": b.unix_s,
            "duration_s": b.unix_s - a.unix_s,
            "battery_start_wh": a.battery_wh, "battery_end_wh": b.battery_wh,
        },
        "geometry": geometry,
    })
}

/// `route_time.mmgis.json`: an MMGIS vector layer for `route_time.geojson` (a layer
/// object of a mission's configuration, its URL the file's name beside it), named
/// `name`: filtered by time on each feature's `start_utc`–`end_utc` (the whole route's
/// vertices over the route's span, each action over its own), the route drawn as a
/// gradient of the battery at each vertex (`coord_properties`' `battery_wh`, red when
/// low, green when high), with the Sun's elevation and the hours since the start
/// offered beside it.
pub(super) fn route_time_mmgis_layer(name: &str) -> Value {
    json!({
        "name": format!("{name}: route in time"),
        "type": "vector",
        "url": "route_time.geojson",
        "visibility": true,
        "initialOpacity": 1,
        "time": { "enabled": true, "type": "local", "startProp": "start_utc", "endProp": "end_utc" },
        "style": { "color": "#ffffff", "weight": 2, "fillColor": "#2f7ed8", "fillOpacity": 0.8, "radius": 4 },
        "variables": {
            "pathAttachments": {
                "gradient": {
                    "colorWithProp": "battery_wh",
                    "dropdownColorWithProp": ["sun_elevation_deg", "t_h"],
                    "colorRamp": ["#d7191c", "#fdae61", "#ffffbf", "#a6d96a", "#1a9641"],
                    "weight": 4,
                },
            },
        },
    })
}

/// `route.czml`: a document packet with the clock over the route's span and the body's
/// ellipsoid named, the rover's path with a position per vertex (seconds after the
/// first, degrees, metres on the body's reference sphere), and the goals.
pub(super) fn route_czml(r: &TempestReport, route: &RoutePlaces) -> Value {
    let v = &route.timeline;
    let (Some(first), Some(last)) = (v.first(), v.last()) else { return json!([]) };
    let interval = format!("{}/{}", first.utc, last.utc);
    let body = serde_json::to_value(collection(Vec::new(), &route.geography)).unwrap_or_else(|_| json!({}));
    let mut positions = Vec::with_capacity(4 * v.len());
    for p in v {
        positions.extend([p.unix_s - first.unix_s, lon180(p.lon_deg), p.lat_deg, p.elevation_m]);
    }
    let mut packets = vec![
        json!({
            "id": "document",
            "name": if r.simulation.is_some() { "areo: executed route" } else { "areo: initial plan" },
            "version": "1.0",
            "clock": {
                "interval": interval, "currentTime": first.utc, "multiplier": 600,
                "range": "LOOP_STOP", "step": "SYSTEM_CLOCK_MULTIPLIER",
            },
            "properties": {
                "body": body["body"],
                "crs": body["crs"],
                "heights": "metres above the body's reference sphere (the map's elevations)",
            },
        }),
        json!({
            "id": "rover",
            "name": "rover",
            "availability": interval,
            "position": { "epoch": first.utc, "cartographicDegrees": positions },
            "path": {
                "material": { "solidColor": { "color": { "rgba": [220, 30, 40, 255] } } },
                "width": 3, "leadTime": 0, "trailTime": 1e12, "resolution": 60,
            },
            "point": { "pixelSize": 10, "color": { "rgba": [255, 255, 255, 255] } },
            "description": "The rover. Properties through time: battery_wh (the battery, Wh), \
                sun_elevation_deg (the Sun above the horizontal, degrees), activity (what brought it to \
                each vertex, or for a plan what it does next).",
            "properties": rover_properties(v),
        }),
    ];
    for (i, g) in route.goals.iter().enumerate() {
        let reached = match &g.utc {
            Some(t) => format!("reached by the plan at {t}"),
            None => "not reached by the plan".to_string(),
        };
        packets.push(json!({
            "id": format!("goal {}", g.name),
            "name": g.name,
            "description": format!("Goal {} of {}, {reached}; elevation {:.1} m on the map.", i + 1, route.goals.len(),
                g.elevation_m.unwrap_or(f64::NAN)),
            "position": { "cartographicDegrees": [lon180(g.lon_deg), g.lat_deg, g.elevation_m.unwrap_or(0.0)] },
            "point": { "pixelSize": 12, "color": { "rgba": [250, 220, 40, 255] } },
            "label": { "text": g.name, "pixelOffset": { "cartesian2": [0, -18] } },
            "properties": { "order": i + 1, "reached_utc": g.utc },
        }));
    }
    Value::Array(packets)
}

/// The rover's time-tagged values at the route's vertices, as CZML custom properties:
/// numbers sampled at seconds after the first vertex (Cesium interpolates between
/// them), the activity as one interval per vertex up to the next.
fn rover_properties(v: &[RouteVertex]) -> Value {
    let Some(first) = v.first() else { return json!({}) };
    let sampled = |value: fn(&RouteVertex) -> f64| {
        let samples: Vec<f64> = v.iter().flat_map(|p| [p.unix_s - first.unix_s, value(p)]).collect();
        json!({ "epoch": first.utc, "number": samples })
    };
    let activity: Vec<Value> = v
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let end = v.get(k + 1).unwrap_or(p);
            json!({ "interval": format!("{}/{}", p.utc, end.utc), "string": p.activity })
        })
        .collect();
    json!({
        "battery_wh": sampled(|p| p.battery_wh),
        "sun_elevation_deg": sampled(|p| p.sun_elevation_deg),
        "activity": activity,
    })
}

/// The page that shows `czml` in CesiumJS on its body (the default ellipsoid set from
/// the document packet's radii before the data source is loaded), the CZML inside it,
/// Cesium taken from where the user keeps it (two lines at the top of the page).
pub(super) fn route_cesium_page(path: &std::path::Path, czml: &Value) -> crate::error::Result<String> {
    let json = crate::output::json_for(path, czml, false)?;
    // Nothing in the data may close, comment out or open a script element.
    Ok(include_str!("route_cesium.html").replace("__CZML__", &crate::output::escape::script_json(&json)))
}
