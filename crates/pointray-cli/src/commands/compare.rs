//! `pointray compare`: how far a render is from a reference of the same view.

use std::path::PathBuf;

use anyhow::bail;
use clap::Args;
use pointray_fidelity::image_difference::{DARK_FLOOR, ImageDifference};
use pointray_io::read_linear_image;

/// Compare a linear render (.exr or .hdr) with a reference of the same size: RMSE, mean
/// relative error, PSNR and the ratio of their means.
#[derive(Args)]
pub struct CompareArgs {
    /// The render measured.
    image: PathBuf,
    /// What it is measured against (a converged render, or another renderer's).
    reference: PathBuf,
}

pub fn run(args: CompareArgs) -> anyhow::Result<()> {
    let image = read_linear_image(&args.image, |_, _| Ok(()))?;
    let reference = read_linear_image(&args.reference, |_, _| Ok(()))?;
    if (image.width, image.height) != (reference.width, reference.height) {
        bail!(
            "{} is {}x{} but {} is {}x{}; compare renders of one size",
            args.image.display(),
            image.width,
            image.height,
            args.reference.display(),
            reference.width,
            reference.height
        );
    }
    let difference = ImageDifference::of(&image.pixels, &reference.pixels);
    println!(
        "{} against {} ({}x{}): RMSE {:.6}, mean relative error {:.6} (dark floor {DARK_FLOOR}), \
         PSNR {:.2} dB, energy {:.4}",
        args.image.display(),
        args.reference.display(),
        image.width,
        image.height,
        difference.rmse,
        difference.mean_relative_error,
        difference.psnr_db,
        difference.energy_ratio
    );
    if difference.non_finite > 0 {
        println!("{} pixels of {} are NaN or infinite", difference.non_finite, args.image.display());
    }
    Ok(())
}
