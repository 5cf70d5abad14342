//! Points files prepped into patches, for the tests of what draws prepped point sets.

use std::sync::Arc;

use glam::Affine3A;
use pointray_io::formats::ply::read_point_cloud;
use pointray_patches::{BoxKind, PrepSettings};
use pointray_scene::{Geometry, Material, SceneObject};
use pointray_surface::{NoProgress, prep};

/// A points file prepped into patches, placed back where its input was (prep recentres).
pub fn prepped_points(name: &str, path: &std::path::Path, material: Material) -> SceneObject {
    prepped_points_with_boxes(name, path, material, BoxKind::default())
}

/// As `prepped_points`, with `box_kind` boxes.
pub fn prepped_points_with_boxes(
    name: &str,
    path: &std::path::Path,
    material: Material,
    box_kind: BoxKind,
) -> SceneObject {
    let cloud = read_point_cloud(path).unwrap_or_else(|e| panic!("{} does not load: {e}", path.display()));
    let options = PrepSettings { boxes: box_kind, ..PrepSettings::default() };
    let (patches, _) = prep(&cloud, &options, &NoProgress).expect("prep succeeds");
    SceneObject {
        name: name.into(),
        transform: Affine3A::from_translation(patches.offset.as_vec3()),
        material,
        geometry: Geometry::Patches(Arc::new(patches)),
    }
}
