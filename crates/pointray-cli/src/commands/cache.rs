//! `pointray cache clean`: removes the point sets that `render` and `view` cached.

use std::path::PathBuf;

use clap::{Args, Subcommand};

/// Manage the cache of prepared point sets.
#[derive(Args)]
pub struct CacheArgs {
    #[command(subcommand)]
    action: CacheAction,
}

#[derive(Subcommand)]
enum CacheAction {
    /// Remove the point sets the cache wrote in the folder (stale entries are never pruned on
    /// their own); a folder the cache did not make is refused, and the user's files are kept.
    Clean {
        /// The cache folder: `.pointray-cache` beside the images `render` wrote.
        #[arg(default_value = ".pointray-cache")]
        dir: PathBuf,
    },
}

pub fn run(args: CacheArgs) -> anyhow::Result<()> {
    match args.action {
        CacheAction::Clean { dir } => {
            let (files, bytes) = pointray_scene::clean_cache(&dir)?;
            println!(
                "removed {files} cached point sets ({:.1} MiB) from {}",
                bytes as f64 / (1 << 20) as f64,
                dir.display()
            );
            Ok(())
        }
    }
}
