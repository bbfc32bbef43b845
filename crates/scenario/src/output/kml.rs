//! KML 2.2 of a route for Google Earth and xGDS-style tools: lines and named points in
//! longitude, latitude (degrees, −180..180). Google Earth's Mars and Moon modes take a
//! file as theirs by the root's `hint="target=mars"` / `"target=moon"`; Earth files
//! carry no hint. KML has no CRS but WGS 84's, so the document's `ExtendedData` names the
//! run's body, CRS (name and WKT2) and longitude convention, as the other files do.

use std::fmt::Write as _;
use std::path::Path;

use super::geojson::lon180;
use crate::error::Result;
use crate::report::Geography;

/// A KML document being built: placemarks in order.
pub(crate) struct Kml {
    name: String,
    geography: Geography,
    placemarks: String,
}

impl Kml {
    /// An empty document called `name` on `geography` (a body of unknown radii gets no
    /// hint).
    pub(crate) fn new(name: &str, geography: &Geography) -> Kml {
        Kml { name: name.to_string(), geography: geography.clone(), placemarks: String::new() }
    }

    /// A line through (latitude, east longitude) points, degrees, drawn in `abgr`
    /// (KML's colour order: alpha, blue, green, red, hex).
    pub(crate) fn line(&mut self, name: &str, abgr: &str, points: impl IntoIterator<Item = (f64, f64)>) {
        let coords: Vec<String> = points.into_iter().map(|(lat, lon)| format!("{},{lat}", lon180(lon))).collect();
        let _ = writeln!(
            self.placemarks,
            "<Placemark><name>{}</name><Style><LineStyle><color>{abgr}</color><width>3</width></LineStyle></Style>\
             <LineString><tessellate>1</tessellate><coordinates>{}</coordinates></LineString></Placemark>",
            escape(name),
            coords.join(" ")
        );
    }

    /// A named point at (latitude, east longitude), degrees, with a description.
    pub(crate) fn point(&mut self, name: &str, description: &str, (lat, lon): (f64, f64)) {
        let _ = writeln!(
            self.placemarks,
            "<Placemark><name>{}</name><description>{}</description><Point><coordinates>{},{lat}</coordinates></Point></Placemark>",
            escape(name),
            escape(description),
            lon180(lon)
        );
    }

    /// The document's text.
    pub(crate) fn text(&self) -> String {
        let g = &self.geography;
        let hint = match g.body.as_str() {
            "Mars" => " hint=\"target=mars\"",
            "Moon" => " hint=\"target=moon\"",
            _ => "",
        };
        let data: String = [
            ("body", g.body.as_str()),
            ("crs_name", g.crs_name.as_str()),
            ("crs", g.crs_code_or_wkt2()),
            ("radius_m", &g.radius_m.to_string()),
            ("latitude", Geography::LATITUDE),
            ("longitude", Geography::LONGITUDE),
        ]
        .iter()
        .map(|(k, v)| format!("<Data name=\"{k}\"><value>{}</value></Data>", escape(v)))
        .collect();
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<kml xmlns=\"http://www.opengis.net/kml/2.2\"{hint}>\n\
             <Document><name>{}</name>\n<ExtendedData>{data}</ExtendedData>\n{}</Document>\n</kml>\n",
            escape(&self.name),
            self.placemarks
        )
    }

    /// Writes the document to `path`.
    pub(crate) fn write(&self, path: &Path) -> Result<()> {
        super::write_file(path, self.text().as_bytes())
    }
}

/// XML text escaping (names come from scenario files): [`super::escape::xml`].
fn escape(text: &str) -> String {
    super::escape::xml(text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use areo_terrain::Spheroid;

    #[test]
    fn a_mars_route_is_hinted_as_mars_and_parses_as_kml() {
        let mars = Geography::of(&Spheroid::MARS_MOLA_SPHERE);
        let mut kml = Kml::new("valley <detour>", &mars);
        kml.line("executed route", "ff2820dc", [(-4.5, 137.4), (-4.6, 222.0)]);
        kml.point("goal \"A\" & B", "t = 3 h", (-4.6, 137.5));
        let text = kml.text();
        let doc = roxmltree::Document::parse(&text).unwrap();
        let root = doc.root_element();
        assert_eq!(root.tag_name().namespace(), Some("http://www.opengis.net/kml/2.2"));
        assert_eq!(root.attribute("hint"), Some("target=mars"));
        let names: Vec<&str> = doc.descendants().filter(|n| n.has_tag_name("name")).filter_map(|n| n.text()).collect();
        assert_eq!(names, ["valley <detour>", "executed route", "goal \"A\" & B"]);
        let line = doc.descendants().find(|n| n.has_tag_name("coordinates")).unwrap().text().unwrap();
        // Longitude first, wrapped into −180..180.
        assert_eq!(line, "137.4,-4.5 -138,-4.6");
        let data = |name: &str| {
            let d = doc.descendants().find(|n| n.has_tag_name("Data") && n.attribute("name") == Some(name)).unwrap();
            d.children().find(|n| n.has_tag_name("value")).and_then(|v| v.text()).unwrap().to_string()
        };
        assert_eq!(data("crs_name"), "Mars - Sphere, R = 3396000 m / Ocentric");
        assert_eq!(data("crs"), mars.crs_wkt2, "the WKT2 read back through XML escaping");
        assert_eq!(data("radius_m"), "3396000");
        assert!(!Kml::new("e", &Geography::of(&Spheroid::EARTH_WGS84)).text().contains("hint"));
        assert!(Kml::new("m", &Geography::of(&Spheroid::MOON)).text().contains("hint=\"target=moon\""));
    }
}
