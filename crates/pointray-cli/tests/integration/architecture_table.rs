//! docs/ARCHITECTURE.md's crate table names exactly the workspace's crates: a crate added,
//! renamed or removed without the table, or the other way round, fails here. And the layering
//! the table states that no build would catch: the renderers do not depend on prep
//! (pointray-surface), even for their tests.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The crates the table lists: the first cell of each row that starts "| `pointray-".
fn crates_in_table(architecture: &str) -> BTreeSet<String> {
    architecture
        .lines()
        .filter_map(|line| line.strip_prefix("| `"))
        .filter(|rest| rest.starts_with("pointray-"))
        .filter_map(|rest| rest.split('`').next())
        .map(str::to_owned)
        .collect()
}

/// The folders under `crates/` that hold a `Cargo.toml` (the fuzz crates lie deeper).
fn crates_in_workspace(root: &Path) -> BTreeSet<String> {
    std::fs::read_dir(root.join("crates"))
        .expect("crates/ can be listed")
        .map(|entry| entry.expect("an entry of crates/").path())
        .filter(|path| path.join("Cargo.toml").is_file())
        .map(|path| path.file_name().expect("a folder name").to_string_lossy().into_owned())
        .collect()
}

#[test]
fn the_crate_table_lists_every_crate_and_no_other() {
    let root = repo_root();
    let architecture =
        std::fs::read_to_string(root.join("docs/ARCHITECTURE.md")).expect("docs/ARCHITECTURE.md is readable");
    let table = crates_in_table(&architecture);
    let workspace = crates_in_workspace(&root);
    let missing_from_table: Vec<_> = workspace.difference(&table).collect();
    let missing_from_crates: Vec<_> = table.difference(&workspace).collect();
    assert!(
        missing_from_table.is_empty() && missing_from_crates.is_empty(),
        "crates missing from docs/ARCHITECTURE.md's table: {missing_from_table:?}; \
         crates in the table but not in crates/: {missing_from_crates:?}"
    );
}

/// The renderers whose manifests may not name prep in any dependency table.
const RENDERERS: [&str; 2] = ["pointray-cpu", "pointray-vulkan"];

/// Every dependency table of a manifest, with its name: `[dependencies]`,
/// `[dev-dependencies]` and `[build-dependencies]`, and their `[target.'…'.*]` forms.
fn dependency_tables(manifest: &toml::Table) -> Vec<(String, &toml::Table)> {
    let mut tables = dependency_kinds(manifest, "");
    let targets = manifest.get("target").and_then(toml::Value::as_table).into_iter().flatten();
    for (target, value) in targets {
        if let Some(table) = value.as_table() {
            tables.extend(dependency_kinds(table, &format!("target.{target}.")));
        }
    }
    tables
}

fn dependency_kinds<'a>(table: &'a toml::Table, prefix: &str) -> Vec<(String, &'a toml::Table)> {
    ["dependencies", "dev-dependencies", "build-dependencies"]
        .into_iter()
        .filter_map(|kind| Some((format!("{prefix}{kind}"), table.get(kind)?.as_table()?)))
        .collect()
}

/// Whether a dependency entry brings pointray-surface: named so (or renamed from it), or
/// pointray-scene with its feature `load` (on by default), which preps the clouds it loads.
fn brings_prep(name: &str, entry: &toml::Value) -> bool {
    let package = entry.get("package").and_then(toml::Value::as_str).unwrap_or(name);
    let default_features = entry.get("default-features").and_then(toml::Value::as_bool).unwrap_or(true);
    let features = entry.get("features").and_then(toml::Value::as_array).into_iter().flatten();
    let load = default_features || features.filter_map(toml::Value::as_str).any(|feature| feature == "load");
    package == "pointray-surface" || (package == "pointray-scene" && load)
}

/// The renderers draw patches and never prep them; their tests that need prep (points prepped
/// into patches, scene files loaded) live in pointray-render.
#[test]
fn the_renderers_do_not_depend_on_prep_even_for_their_tests() {
    let root = repo_root();
    for renderer in RENDERERS {
        let path = root.join("crates").join(renderer).join("Cargo.toml");
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let manifest: toml::Table =
            toml::from_str(&text).unwrap_or_else(|e| panic!("{} does not parse: {e}", path.display()));
        let tables = dependency_tables(&manifest);
        assert!(tables.iter().any(|(kind, _)| kind == "dependencies"), "{renderer} has no [dependencies]");
        for (kind, table) in tables {
            let prep: Vec<&String> =
                table.iter().filter(|(name, entry)| brings_prep(name, entry)).map(|(name, _)| name).collect();
            assert!(
                prep.is_empty(),
                "{renderer}'s [{kind}] brings pointray-surface through {prep:?}: what needs prep, a test \
                 included, belongs in pointray-render"
            );
        }
    }
}
