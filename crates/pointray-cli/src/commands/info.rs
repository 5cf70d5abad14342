//! `pointray info`: what a patch store holds, from its header alone.

use std::path::PathBuf;

use clap::Args;
use pointray_patches::patch_store::{self, Encoding, StoreDescription};

/// Describe a patch store: its patches, bytes a patch, records, coarse patches, prep settings
/// and the scan structure prep found.
#[derive(Args)]
pub struct InfoArgs {
    /// The store (`.patches`), as `pointray prep` writes it.
    store: PathBuf,
}

pub fn run(args: InfoArgs) -> anyhow::Result<()> {
    let description = patch_store::describe(&args.store)?;
    print!("{}", described(&args.store.display().to_string(), &description));
    Ok(())
}

/// The lines `info` prints for the store `name`.
fn described(name: &str, store: &StoreDescription) -> String {
    let per_patch = store.file_bytes as f64 / store.patches.max(1) as f64;
    let coarse_share = 100.0 * store.coarse_patches as f64 / store.patches.max(1) as f64;
    let records = match store.shape.encoding {
        Encoding::Compact if store.shape.colors => "compact, with colours and intensities",
        Encoding::Compact => "compact, without colours or intensities",
        Encoding::Full => "full",
    };
    let bounds = store.bounds.map_or("none".into(), |b| format!("{:?} to {:?}", b.min, b.max));
    let offset = store.offset;
    [
        format!("{name}: patch store version {}", patch_store::FORMAT_VERSION),
        format!("patches: {} ({} bytes, {per_patch:.2} a patch)", store.patches, store.file_bytes),
        format!("records: {records}; {} colour neighbours a patch", store.shape.neighbor_slots),
        format!("coarse patches: {} ({coarse_share:.1}% of the patches)", store.coarse_patches),
        format!("offset (input = local + offset): {}, {}, {}", offset.x, offset.y, offset.z),
        format!("origins' bounds (local): {bounds}"),
        format!("prep settings: {:?}", store.settings),
        format!("scan structure: {}", store.scan),
    ]
    .map(|line| line + "\n")
    .concat()
}
