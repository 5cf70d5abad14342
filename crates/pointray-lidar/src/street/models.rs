//! The scanned models that stand on the street when the data folder has them: the Stanford
//! bunny and the Cyberware horse, each scaled so that its largest side is a metre.

use std::path::{Path, PathBuf};

use glam::{Affine3A, Quat, Vec2, Vec3};
use pointray_io::TriangleMesh;

use crate::LidarError;
use crate::surface::Surface;

/// The models' largest side on the street.
const MODEL_SIZE: f32 = 1.0;

struct Model {
    name: &'static str,
    /// Under the data folder.
    file: &'static str,
    /// The file's up axis is +Y (turned to +Z here); otherwise it is already +Z.
    y_up: bool,
    /// Where its footprint's centre stands on the road.
    at: Vec2,
    reflectance: f32,
}

const MODELS: [Model; 2] = [
    Model { name: "bunny", file: "meshes/bunny.ply", y_up: true, at: Vec2::new(6.0, 1.8), reflectance: 0.7 },
    Model {
        name: "horse",
        file: "meshes/horse.ply",
        y_up: false,
        at: Vec2::new(-7.0, -1.8),
        reflectance: 0.45,
    },
];

/// The model files under `data_dir` that the street will stand on its road.
pub fn model_files(data_dir: &Path) -> Vec<PathBuf> {
    MODELS.iter().map(|model| data_dir.join(model.file)).filter(|path| path.is_file()).collect()
}

/// The models found under `data_dir`, placed on the road; a missing file leaves its model out,
/// a file that cannot be read is an error.
pub fn street_models(data_dir: &Path) -> Result<Vec<Surface>, LidarError> {
    let mut surfaces = Vec::new();
    for model in &MODELS {
        let path = data_dir.join(model.file);
        if !path.is_file() {
            continue;
        }
        let mut mesh = pointray_io::formats::read_triangle_mesh(&path)?;
        if mesh.triangles.is_empty() || mesh.positions.iter().any(|p| !p.is_finite()) {
            let problem = "no triangles, or a non-finite vertex".to_string();
            return Err(LidarError::Io(pointray_io::IoError::malformed(&path, problem)));
        }
        place(&mut mesh, model);
        surfaces.push(Surface::new(model.name, mesh, model.reflectance));
    }
    Ok(surfaces)
}

/// Stands the mesh up in +Z, scales it to `MODEL_SIZE` and puts its feet on the road at
/// `model.at`.
fn place(mesh: &mut TriangleMesh, model: &Model) {
    let upright =
        if model.y_up { Quat::from_rotation_x(std::f32::consts::FRAC_PI_2) } else { Quat::IDENTITY };
    let turned: Vec<Vec3> = mesh.positions.iter().map(|&p| upright * p).collect();
    let (min, max) = bounds(&turned);
    let scale = MODEL_SIZE / (max - min).max_element().max(f32::MIN_POSITIVE);
    let footprint = Vec3::new((min.x + max.x) * 0.5, (min.y + max.y) * 0.5, min.z);
    let placement = Affine3A::from_translation(model.at.extend(0.0))
        * Affine3A::from_scale(Vec3::splat(scale))
        * Affine3A::from_translation(-footprint);
    mesh.positions = turned.iter().map(|&p| placement.transform_point3(p)).collect();
}

fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)))
}
