//! The dependency-direction lint: reads `cargo metadata` and checks every areo crate's
//! dependencies against the crate map of `docs/ARCHITECTURE.md`.

use std::path::Path;
use std::process::Command;

/// Which areo crates each library crate may depend on (normal, build and dev
/// dependencies alike: a test that reaches up the map is still a cycle in spirit).
const ALLOWED: &[(&str, &[&str])] = &[
    ("areo-terrain", &[]),
    ("areo-ephemeris", &[]),
    ("areo-ise", &[]),
    ("areo-rover", &["areo-terrain"]),
    ("areo-actions", &["areo-rover", "areo-terrain"]),
    ("areo-mission", &["areo-ise", "areo-terrain", "areo-ephemeris", "areo-rover"]),
];

/// Every dependency that breaks the map, as a sentence.
pub(crate) fn check(root: &Path) -> Result<Vec<String>, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--no-deps", "--offline"])
        .current_dir(root)
        .output()
        .map_err(|e| format!("cargo metadata: {e}"))?;
    if !out.status.success() {
        return Err(format!("cargo metadata failed: {}", String::from_utf8_lossy(&out.stderr)));
    }
    let meta: serde_json::Value =
        serde_json::from_slice(&out.stdout).map_err(|e| format!("cargo metadata output: {e}"))?;
    violations(&meta)
}

fn violations(meta: &serde_json::Value) -> Result<Vec<String>, String> {
    let packages = meta["packages"].as_array().ok_or("cargo metadata: no packages")?;
    let mut found = Vec::new();
    let mut seen = Vec::new();
    for pkg in packages {
        let name = pkg["name"].as_str().unwrap_or_default();
        let Some((_, allowed)) = ALLOWED.iter().find(|(n, _)| *n == name) else { continue };
        seen.push(name.to_string());
        for dep in pkg["dependencies"].as_array().into_iter().flatten() {
            let dep_name = dep["name"].as_str().unwrap_or_default();
            if (dep_name == "areo" || dep_name.starts_with("areo-")) && !allowed.contains(&dep_name) {
                found.push(format!("{name} must not depend on {dep_name} (allowed: {allowed:?})"));
            }
        }
    }
    for (name, _) in ALLOWED {
        if !seen.iter().any(|s| s == name) {
            found.push(format!("{name} is missing from the workspace"));
        }
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workspace_dependencies_point_down() {
        let v = check(&crate::project_root()).unwrap();
        assert!(v.is_empty(), "{v:#?}");
    }

    #[test]
    fn an_upward_dependency_is_reported() {
        let mut meta: serde_json::Value = serde_json::json!({"packages": []});
        let pkgs = meta["packages"].as_array_mut().unwrap();
        for (name, _) in ALLOWED {
            pkgs.push(serde_json::json!({"name": name, "dependencies": []}));
        }
        pkgs[2]["dependencies"] = serde_json::json!([{"name": "areo-mission"}, {"name": "serde"}]);
        let v = violations(&meta).unwrap();
        assert_eq!(v, vec!["areo-ise must not depend on areo-mission (allowed: [])".to_string()]);
    }
}
