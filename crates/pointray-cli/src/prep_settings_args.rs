//! `pointray prep`'s settings as flags: one group, flattened into every command that preps
//! points (`prep`, `fidelity`, `consistency`), so that each flag means the same everywhere.

use clap::Args;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use glam::DVec3;
use pointray_patches::{BoxKind, OutlierFilter, PrepSettings, RadiusMode, ScanMode};
use pointray_surface::PrepError;
use pointray_surface::input_validation::validate_settings;
use serde::de::DeserializeOwned;
use serde::de::value::{Error as ValueError, StrDeserializer};

use crate::point_arg::parse_finite;

#[derive(Args)]
pub struct PrepSettingsArgs {
    /// Neighbours for the support radius and the quadratic fit.
    #[arg(long, default_value_t = PrepSettings::default().k)]
    k: u32,
    /// Neighbours for the PCA normal.
    #[arg(long, default_value_t = PrepSettings::default().normal_k)]
    normal_k: u32,
    /// Recompute normals even when the file carries them.
    #[arg(long)]
    recompute_normals: bool,
    /// Where the scan's sensor stood, `x,y,z` in the file's coordinates; overrides the
    /// file's. Normals face it (and `fidelity`'s sensor views and `consistency`'s rays start
    /// there).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    sensor: Option<DVec3>,
    /// Drop statistical outliers first, `K,N`: points whose mean distance to their K nearest
    /// neighbours is more than N standard deviations above the mean (e.g. `8,2`).
    #[arg(long, value_name = "K,N", value_parser = parse_outlier_filter)]
    remove_outliers: Option<OutlierFilter>,
    /// The support radius: by default each disk just covers its point's Voronoi cell (less
    /// false surface and a faster trace than the paper's); `paper` is the farthest of the k
    /// neighbours; `adaptive` grows each disk over the part of its cell that no other disk
    /// covers, held to a band around the neighbourhood's median: fewer holes on scan-line
    /// data, more false surface (bench/FIDELITY.md).
    #[arg(long, default_value = "cell", value_parser = choice::<RadiusMode>(&["cell", "paper", "adaptive"]))]
    radius: RadiusMode,
    /// How far each patch reaches, as a fraction of its support radius (the fit still uses
    /// all k neighbours).
    #[arg(long, default_value_t = PrepSettings::default().disk_scale)]
    disk_scale: f32,
    /// The box around each patch: a tight box around the patch over its disk, or the paper's
    /// cube of half-size d_i.
    #[arg(long, default_value = "tight", value_parser = choice::<BoxKind>(&["tight", "cube"]))]
    boxes: BoxKind,
    /// LiDAR scans: `auto` shapes elliptical patches along the scan lines (from a ring field,
    /// or beams recovered from elevations) whenever the sensor position is known (the file's,
    /// or `--sensor`); `off` treats every cloud as unstructured points.
    #[arg(long, default_value = "auto", value_parser = choice::<ScanMode>(&["auto", "off"]))]
    scan: ScanMode,
}

impl PrepSettingsArgs {
    /// The settings, checked before anything is read; an error names the flag.
    pub fn settings(&self) -> anyhow::Result<PrepSettings> {
        let settings = PrepSettings {
            k: self.k,
            normal_k: self.normal_k,
            recompute_normals: self.recompute_normals,
            sensor: self.sensor,
            remove_outliers: self.remove_outliers,
            radius: self.radius,
            disk_scale: self.disk_scale,
            boxes: self.boxes,
            scan: self.scan,
            ..PrepSettings::default()
        };
        validate_settings(&settings).map_err(flag_error)?;
        Ok(settings)
    }

    /// `--sensor`, for the commands that also place views or cast rays from it.
    pub fn sensor(&self) -> Option<DVec3> {
        self.sensor
    }
}

/// One of `names`, read as the scene file reads it (the same names, through serde), so that
/// a flag and a scene key cannot drift apart.
fn choice<T: DeserializeOwned + Clone + Send + Sync + 'static>(
    names: &'static [&'static str],
) -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(names).map(|name: String| {
        T::deserialize(StrDeserializer::<ValueError>::new(&name)).expect("every listed name deserializes")
    })
}

/// A prep setting's error, named by the flag that sets it.
pub fn flag_error(error: PrepError) -> anyhow::Error {
    match error {
        PrepError::InvalidSetting { setting, problem } => {
            let flag = setting.split('.').next().unwrap_or(setting).replace('_', "-");
            anyhow::anyhow!("--{flag}: {problem}")
        }
        other => other.into(),
    }
}

/// Parses `K,N` for `--remove-outliers`.
fn parse_outlier_filter(text: &str) -> Result<OutlierFilter, String> {
    let (neighbors, sigmas) = text.split_once(',').ok_or_else(|| format!("expected K,N, got `{text}`"))?;
    let filter = OutlierFilter {
        neighbors: neighbors.trim().parse().map_err(|e| format!("K `{neighbors}`: {e}"))?,
        sigmas: sigmas.trim().parse().map_err(|e| format!("N `{sigmas}`: {e}"))?,
    };
    Ok(filter)
}

#[cfg(test)]
mod tests {
    use clap::{CommandFactory, Parser};

    use super::*;

    #[derive(Parser)]
    struct Flags {
        #[command(flatten)]
        prep: PrepSettingsArgs,
    }

    #[test]
    fn the_defaults_are_prep_settings_defaults() {
        Flags::command().debug_assert();
        let flags = Flags::try_parse_from(["pointray"]).unwrap();
        assert_eq!(flags.prep.settings().unwrap(), PrepSettings::default());
    }

    #[test]
    fn every_listed_name_parses() {
        let args =
            ["pointray", "--radius", "adaptive", "--boxes", "cube", "--scan", "off", "--sensor", "1,-2,3"];
        let settings = Flags::try_parse_from(args).unwrap().prep.settings().unwrap();
        assert_eq!(
            (settings.radius, settings.boxes, settings.scan, settings.sensor),
            (RadiusMode::Adaptive, BoxKind::Cube, ScanMode::Off, Some(DVec3::new(1.0, -2.0, 3.0)))
        );
        for radius in ["cell", "paper"] {
            assert!(Flags::try_parse_from(["pointray", "--radius", radius]).is_ok(), "{radius}");
        }
        assert!(Flags::try_parse_from(["pointray", "--boxes", "tight"]).is_ok());
        assert!(Flags::try_parse_from(["pointray", "--scan", "auto"]).is_ok());
        assert!(Flags::try_parse_from(["pointray", "--radius", "huge"]).is_err());
    }
}
