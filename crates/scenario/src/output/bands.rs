//! What each map layer's band holds, as its GeoTIFF tells GIS tools: a description and
//! a unit on every layer, on the maps of codes (`direct_sun.tif` and the shadow
//! series, `no_go.tif`, `classes.tif`) a colour for each code in the file, and on the
//! last two each code's name in GDAL's sidecar (`NAME.tif.aux.xml`, the Persistent Auxiliary Metadata GDAL reads beside any raster:
//! `gdalinfo` lists the names as the band's categories, QGIS labels a paletted layer's
//! classes with them). docs/outputs.md gives the same meanings.

use areo_terrain::geotiff::Band;

use super::escape;

/// `dem.tif`: heights as the map gives them.
pub(crate) const ELEVATION: Band<'static> =
    Band { description: "elevation of the planner's map", unit: "m", colours: &[] };

/// `slope.tif`.
pub(crate) const SLOPE: Band<'static> =
    Band { description: "slope of the planner's map", unit: "degree", colours: &[] };

/// `direct_sun.tif` and the shadow series: 0 none, 1 direct sun (255, no data, is
/// the file's no-data value).
pub(crate) const DIRECT_SUN: Band<'static> = Band {
    description: "direct sun on the true terrain: 1 lit, 0 in shadow or night",
    unit: "",
    colours: &[(0, [40, 44, 72]), (1, [250, 214, 92])],
};

/// `no_go.tif`'s codes: what keeps a cell out.
pub(crate) const NO_GO: Band<'static> = Band {
    description: "what keeps a cell out of the plan",
    unit: "",
    colours: &[(0, [235, 235, 235]), (1, [213, 94, 0]), (2, [230, 159, 0]), (3, [204, 121, 167])],
};

/// The names of [`NO_GO`]'s codes.
pub(crate) const NO_GO_NAMES: [&str; 4] =
    ["free", "marked by the mask", "within the mask's inflation", "cut off from the start"];

/// `classes.tif`'s description.
pub(crate) const CLASSES: &str = "terrain class id (the scenario's terrain_classes)";

/// Colours for terrain classes, taken in the order of their ids: Okabe and Ito's
/// palette, told apart with any colour vision.
const CLASS_COLOURS: [[u8; 3]; 7] =
    [[0, 114, 178], [230, 159, 0], [0, 158, 115], [204, 121, 167], [86, 180, 233], [213, 94, 0], [240, 228, 66]];

/// The colour of each class id (ids in increasing order take the palette's colours in
/// turn).
pub(crate) fn class_colours(ids: &[u8]) -> Vec<(u8, [u8; 3])> {
    let mut sorted = ids.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    sorted.iter().enumerate().map(|(i, &id)| (id, CLASS_COLOURS[i % CLASS_COLOURS.len()])).collect()
}

/// GDAL's sidecar naming a byte map's codes: `names` as (code, name); codes between
/// them unnamed.
pub(crate) fn category_sidecar(names: &[(u8, &str)]) -> String {
    let last = names.iter().map(|&(code, _)| usize::from(code)).max().map_or(0, |m| m + 1);
    let mut categories = String::new();
    for code in 0..last {
        match names.iter().find(|&&(c, _)| usize::from(c) == code) {
            Some((_, name)) => categories.push_str(&format!("      <Category>{}</Category>\n", escape::xml(name))),
            None => categories.push_str("      <Category />\n"),
        }
    }
    format!(
        "<PAMDataset>\n  <PAMRasterBand band=\"1\">\n    <CategoryNames>\n{categories}    </CategoryNames>\n  \
         </PAMRasterBand>\n</PAMDataset>\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sidecar_lists_a_name_at_each_codes_place_and_escapes_it() {
        let xml = category_sidecar(&[(1, "smooth"), (3, "a<b & c")]);
        let doc = roxmltree::Document::parse(&xml).unwrap();
        let names: Vec<String> = doc
            .descendants()
            .filter(|n| n.has_tag_name("Category"))
            .map(|n| n.text().unwrap_or_default().to_string())
            .collect();
        assert_eq!(names, ["", "smooth", "", "a<b & c"]);
    }

    #[test]
    fn classes_take_the_palettes_colours_in_the_order_of_their_ids() {
        let colours = class_colours(&[3, 1, 2, 1]);
        assert_eq!(colours.iter().map(|c| c.0).collect::<Vec<_>>(), [1, 2, 3]);
        assert_eq!(colours[0].1, CLASS_COLOURS[0]);
        assert_eq!(colours[2].1, CLASS_COLOURS[2]);
    }
}
