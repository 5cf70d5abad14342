//! docs/ARCHITECTURE.md's crate table names exactly the workspace's crates: a crate added,
//! renamed or removed without the table, or the other way round, fails here.

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
