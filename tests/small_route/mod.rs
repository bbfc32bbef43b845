//! The small route the tests that read a run's files with outside tools share
//! (`tests/tempest/small-route.ron.in`; pytest reads the same file).

/// A plan of about 1.5 km across a small synthesised map at `site` (latitude, east
/// longitude, degrees) on `body`, starting at `utc`.
pub(crate) fn scenario(body: &str, (lat, lon): (f64, f64), utc: &str) -> String {
    include_str!("../tempest/small-route.ron.in")
        .replace("@BODY@", body)
        .replace("@LAT@", &format!("{lat:?}"))
        .replace("@LON@", &format!("{lon:?}"))
        .replace("@UTC@", utc)
}
