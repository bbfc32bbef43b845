//! The shadow series as a STAC catalogue beside `shadows/index.json`: a Collection
//! (`shadows/collection.json`, the series' place and span) and an Item per file
//! (`shadows/direct_sun_NNN.json`, its instant as `datetime`, the file as its `data`
//! asset), all links relative, so that a STAC browser, pystac or a map server's STAC
//! reader lists the series by time. STAC 1.1.0, with the Solar System extension naming
//! the body (`ssys:targets`: a footprint in longitude and latitude is on that body, not
//! the Earth) and the projection extension giving the files' grid (`proj:wkt2`,
//! `proj:shape`, `proj:transform`).

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::error::Result;
use crate::output::{json_for, write_file};
use crate::report::tempest::ShadowSeries;
use areo_terrain::geotiff::Grid;

const STAC_VERSION: &str = "1.1.0";
const EXTENSIONS: [&str; 2] = [
    "https://stac-extensions.github.io/ssys/v1.1.0/schema.json",
    "https://stac-extensions.github.io/projection/v2.0.0/schema.json",
];
const COG: &str = "image/tiff; application=geotiff; profile=cloud-optimized";

/// The collection's id: the series is one per run, in the run's own directory.
const COLLECTION: &str = "direct-sun";

/// Writes the collection and an item per `(utc, file)` of `series` into `folder`, the
/// files on `grid`. Returns the files.
pub(super) fn write(
    folder: &Path,
    grid: &Grid,
    series: &ShadowSeries,
    frames: &[(String, String)],
) -> Result<Vec<PathBuf>> {
    let bbox = series.bbox;
    let geometry = if series.footprint.is_empty() {
        Value::Null
    } else {
        json!({ "type": "Polygon", "coordinates": [series.footprint] })
    };
    let geographic = grid.georef.geographic();
    let body = geographic.body_name();
    let links = |rel: &str| json!({ "rel": rel, "href": "./collection.json", "type": "application/json" });
    let mut files = Vec::new();
    let mut item_links = vec![links("root")];
    for (utc, file) in frames {
        let stem = file.trim_end_matches(".tif");
        let item = json!({
            "type": "Feature",
            "stac_version": STAC_VERSION,
            "stac_extensions": EXTENSIONS,
            "id": stem,
            "collection": COLLECTION,
            "geometry": geometry,
            "bbox": bbox,
            "properties": {
                "datetime": utc,
                "title": format!("direct sun at {utc}"),
                "ssys:targets": [body],
                "proj:code": Value::Null,
                "proj:wkt2": grid.georef.wkt(),
                "proj:shape": [grid.rows, grid.cols],
                "proj:transform": [grid.dx, 0.0, grid.x0, 0.0, -grid.dy, grid.y_top],
            },
            "links": [links("root"), links("parent"), links("collection")],
            "assets": {
                "data": { "href": format!("./{file}"), "type": COG, "roles": ["data"],
                          "title": "direct sun: 1 lit, 0 in shadow or night, 255 no data" },
            },
        });
        let path = folder.join(format!("{stem}.json"));
        write_file(&path, json_for(&path, &item, true)?.as_bytes())?;
        files.push(path);
        item_links.push(json!({ "rel": "item", "href": format!("./{stem}.json"), "type": "application/geo+json" }));
    }
    let span = [frames.first().map(|f| f.0.as_str()), frames.last().map(|f| f.0.as_str())];
    let collection = json!({
        "type": "Collection",
        "stac_version": STAC_VERSION,
        "stac_extensions": [EXTENSIONS[0]],
        "id": COLLECTION,
        "title": "direct sun through the run",
        "description": format!("The true terrain's direct sun on {body} at the Sun table's instants through the run, one Cloud-Optimized GeoTIFF each (1 lit, 0 in shadow or night, 255 no data). Longitudes east in -180..180 and planetocentric latitudes on {}.", geographic.name),
        "license": "other",
        "ssys:targets": [body],
        "extent": { "spatial": { "bbox": [bbox] }, "temporal": { "interval": [span] } },
        "links": item_links,
    });
    let path = folder.join("collection.json");
    write_file(&path, json_for(&path, &collection, true)?.as_bytes())?;
    files.push(path);
    Ok(files)
}
