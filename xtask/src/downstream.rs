//! `cargo xtask downstream`: areo's library crates as a downstream project meets them.
//!
//! Builds scratch crates outside the workspace (in `target/downstream/`, with their
//! own lock file copied from the workspace's and their own target directory), each
//! depending on one areo crate by path and calling it, and reports each one's
//! dependency count — so a user of the ephemeris alone, or of DEMs and shadows without
//! the heavy solvers, is shown to need nothing else.

use std::path::{Path, PathBuf};
use std::process::Command;

/// One scratch crate: its name, the dependency line, the program, and crates that must
/// not be in its tree.
struct Scratch {
    name: &'static str,
    dependency: &'static str,
    main: &'static str,
    must_not_pull: &'static [&'static str],
}

const SCRATCHES: &[Scratch] = &[
    Scratch {
        name: "ephemeris-only",
        dependency: r#"areo-ephemeris = { path = "../../../crates/ephemeris" }"#,
        main: r#"fn main() {
    use areo_ephemeris::{Body, Site, SunModel};
    let site = Site::on(Body::Mars, -4.6, 137.4).expect("a site");
    let at = areo_ephemeris::parse_utc("2012-08-06T22:15:00Z").expect("a time");
    let p = Body::Mars.sun(at).at_site(&site);
    assert!(p.elevation_deg > 0.0 && p.elevation_deg < 90.0);
}
"#,
        must_not_pull: &["faer", "parry3d", "rayon", "nalgebra", "areo-terrain"],
    },
    Scratch {
        name: "terrain-core",
        dependency: r#"areo-terrain = { path = "../../../crates/terrain", default-features = false }"#,
        main: r#"fn main() {
    use areo_terrain::shadow::{Curvature, Shadows, GridSunDirection};
    let dem = areo_terrain::Dem::from_fn(40, 30, 10.0, 10.0, |x, y| 0.02 * x + 5.0 * (y / 50.0).sin())
        .expect("a DEM");
    let slope = areo_terrain::slope::slope_aspect(&dem);
    assert!(slope.slope_deg.iter().all(|s| s.is_finite()));
    let lit = Shadows::new(GridSunDirection::new(90.0, 5.0), Curvature::Flat).map(&dem).lit_fraction();
    assert!(lit > 0.0 && lit <= 1.0);
}
"#,
        must_not_pull: &["faer", "parry3d", "nalgebra"],
    },
];

/// What one scratch crate needed.
#[derive(Debug)]
pub(crate) struct Built {
    pub name: &'static str,
    /// Distinct packages in its dependency tree, itself excluded.
    pub dependencies: usize,
    /// Crates it must not pull in but did.
    pub unwanted: Vec<String>,
}

/// Builds every scratch crate (offline: the workspace's build has the sources) and
/// counts its dependencies.
pub(crate) fn check(root: &Path) -> Result<Vec<Built>, String> {
    let base = root.join("target").join("downstream");
    let mut out = Vec::new();
    for s in SCRATCHES {
        let dir = base.join(s.name);
        write_scratch(root, &dir, s)?;
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let target = base.join("target");
        let build = Command::new(&cargo)
            .args(["build", "--offline", "--quiet", "--target-dir"])
            .arg(&target)
            .current_dir(&dir)
            .output()
            .map_err(|e| format!("{}: cargo build: {e}", s.name))?;
        if !build.status.success() {
            return Err(format!("{}: cargo build failed:\n{}", s.name, String::from_utf8_lossy(&build.stderr)));
        }
        let run = Command::new(target.join("debug").join(s.name))
            .output()
            .map_err(|e| format!("{}: running it: {e}", s.name))?;
        if !run.status.success() {
            return Err(format!("{}: the program failed:\n{}", s.name, String::from_utf8_lossy(&run.stderr)));
        }
        let tree = Command::new(&cargo)
            .args(["tree", "--offline", "--edges", "normal,build", "--prefix", "none", "--format", "{p}"])
            .current_dir(&dir)
            .output()
            .map_err(|e| format!("{}: cargo tree: {e}", s.name))?;
        if !tree.status.success() {
            return Err(format!("{}: cargo tree failed:\n{}", s.name, String::from_utf8_lossy(&tree.stderr)));
        }
        let mut packages: Vec<String> = String::from_utf8_lossy(&tree.stdout)
            .lines()
            .filter_map(|l| l.split_whitespace().next().map(str::to_string))
            .filter(|p| p != s.name)
            .collect();
        packages.sort();
        packages.dedup();
        let unwanted =
            s.must_not_pull.iter().filter(|u| packages.iter().any(|p| p == *u)).map(|u| u.to_string()).collect();
        out.push(Built { name: s.name, dependencies: packages.len(), unwanted });
    }
    Ok(out)
}

/// The library crates a downstream project may depend on.
pub(crate) const LIBRARY_CRATES: &[&str] = &[
    "areo-body",
    "areo-ephemeris",
    "areo-terrain",
    "areo-rover",
    "areo-ise",
    "areo-actions",
    "areo-mission",
    "areo-scenario",
];

/// `cargo package --list` for each library crate: the warnings cargo prints about its
/// manifest (missing description, licence, documentation, readme …), one entry per
/// crate that has any. `--list` checks the metadata and the file list without needing
/// the areo crates it depends on to be on a registry (they are `publish = false`).
pub(crate) fn package_warnings(root: &Path) -> Result<Vec<(String, Vec<String>)>, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut out = Vec::new();
    for name in LIBRARY_CRATES {
        let run = Command::new(&cargo)
            .args(["package", "--list", "--offline", "--allow-dirty", "-p", name])
            .current_dir(root)
            .output()
            .map_err(|e| format!("{name}: cargo package: {e}"))?;
        if !run.status.success() {
            return Err(format!("{name}: cargo package --list failed:\n{}", String::from_utf8_lossy(&run.stderr)));
        }
        let warnings: Vec<String> = String::from_utf8_lossy(&run.stderr)
            .lines()
            .filter(|l| l.trim_start().starts_with("warning"))
            .map(str::to_string)
            .collect();
        if !warnings.is_empty() {
            out.push((name.to_string(), warnings));
        }
    }
    Ok(out)
}

/// Writes the scratch crate `s` into `dir`, with the workspace's lock file so that it
/// resolves to the versions the workspace builds (offline).
fn write_scratch(root: &Path, dir: &Path, s: &Scratch) -> Result<(), String> {
    let io = |p: PathBuf| move |e: std::io::Error| format!("{}: {e}", p.display());
    std::fs::create_dir_all(dir.join("src")).map_err(io(dir.join("src")))?;
    let manifest = format!(
        "[package]\nname = \"{}\"\nversion = \"0.0.0\"\nedition = \"2024\"\npublish = false\n\n\
         # Not a member of the areo workspace: a downstream project.\n[workspace]\n\n[dependencies]\n{}\n",
        s.name, s.dependency
    );
    std::fs::write(dir.join("Cargo.toml"), manifest).map_err(io(dir.join("Cargo.toml")))?;
    std::fs::write(dir.join("src").join("main.rs"), s.main).map_err(io(dir.join("src/main.rs")))?;
    std::fs::copy(root.join("Cargo.lock"), dir.join("Cargo.lock")).map_err(io(dir.join("Cargo.lock")))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_downstream_crate_builds_on_one_areo_crate_without_the_heavy_ones() {
        let built = super::check(&crate::project_root()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(built.len(), 2);
        for b in &built {
            assert!(b.unwanted.is_empty(), "{}: pulls in {:?}", b.name, b.unwanted);
        }
        // (Measured: the ephemeris alone 23 packages, the terrain core 36; areo-terrain
        // with its default features has 103.)
        let count = |name: &str| built.iter().find(|b| b.name == name).map_or(0, |b| b.dependencies);
        assert!(count("ephemeris-only") < 40 && count("terrain-core") < 80, "{built:?}");
    }

    #[test]
    fn every_library_crate_packages_without_a_metadata_warning() {
        let warned = super::package_warnings(&crate::project_root()).unwrap_or_else(|e| panic!("{e}"));
        assert!(warned.is_empty(), "cargo package warns: {warned:?}");
    }
}
