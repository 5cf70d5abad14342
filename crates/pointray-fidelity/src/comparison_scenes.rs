//! The two scenes compared: the mesh alone and the patches alone, with the same camera,
//! lights and background, and no floor (a floor would count as surface in both).

use std::sync::Arc;

use glam::{Affine3A, Vec3};
use pointray_io::TriangleMesh;
use pointray_kernels::Aabb;
use pointray_patches::PatchSet;
use pointray_scene::bounds::{bounds_of_points, center, diagonal};
use pointray_scene::{Background, Camera, Geometry, Light, Material, Scene, SceneObject};

use crate::FidelityError;

/// The light comes from over the camera's shoulder (up and to the right of the view), so
/// every view is lit from the front and the shadows it casts fall where the camera sees them.
const LIGHT_UP_OFFSET: f32 = 0.5;
const LIGHT_RIGHT_OFFSET: f32 = 0.3;
/// With the default material (ambient 0.1, diffuse 0.8, specular 0.3) a fully lit pixel
/// stays under 1, so differences are not clipped away before the PSNR sees them.
const LIGHT_INTENSITY: f32 = 0.8;

pub struct ComparisonScenes {
    mesh: SceneObject,
    points: SceneObject,
    bounds: Aabb,
    points_centre: Vec3,
}

/// One view's pair of scenes.
pub struct ViewScenes {
    pub mesh: Scene,
    pub points: Scene,
}

impl ComparisonScenes {
    /// `patches` must come from points in the mesh's coordinates: they are placed back there
    /// by a translation by `patches.offset` (prep recentres them).
    pub fn new(patches: Arc<PatchSet>, mesh: Arc<TriangleMesh>) -> Result<Self, FidelityError> {
        if patches.is_empty() {
            return Err(FidelityError::EmptyPatchSet);
        }
        let bounds = bounds_of_points(mesh.positions.iter().copied())
            .filter(|_| !mesh.triangles.is_empty())
            .ok_or(FidelityError::EmptyMesh)?;
        let offset = Affine3A::from_translation(patches.offset.as_vec3());
        let local_bounds = bounds_of_points(patches.hot.iter().map(|patch| patch.origin()));
        let points_centre =
            (local_bounds.map_or(Vec3::ZERO, |b| center(&b)).as_dvec3() + patches.offset).as_vec3();
        Ok(Self {
            mesh: object("mesh", Affine3A::IDENTITY, Geometry::Mesh(mesh)),
            points: object("points", offset, Geometry::Patches(patches)),
            bounds,
            points_centre,
        })
    }

    /// The mesh's bounds, which every camera frames.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The centre of the box around the points (the patches' origins), in the mesh's
    /// coordinates.
    pub fn points_centre(&self) -> Vec3 {
        self.points_centre
    }

    /// The mesh's bounding-box diagonal: the unit of the depth error.
    pub fn diagonal(&self) -> f32 {
        diagonal(&self.bounds)
    }

    /// Both scenes seen by `camera`.
    pub fn for_camera(&self, camera: Camera) -> ViewScenes {
        let scene_of = |object: &SceneObject| Scene {
            camera,
            lights: vec![shoulder_light(&camera)],
            background: Background::Solid(Vec3::ZERO),
            objects: vec![object.clone()],
        };
        ViewScenes { mesh: scene_of(&self.mesh), points: scene_of(&self.points) }
    }
}

fn object(name: &str, transform: Affine3A, geometry: Geometry) -> SceneObject {
    SceneObject { name: name.to_owned(), transform, material: Material::default(), geometry }
}

fn shoulder_light(camera: &Camera) -> Light {
    let toward_camera = (camera.position - camera.look_at).normalize_or(Vec3::Z);
    let right = (-toward_camera).cross(camera.up).normalize_or(Vec3::X);
    let up = right.cross(-toward_camera);
    let toward_light = toward_camera + up * LIGHT_UP_OFFSET + right * LIGHT_RIGHT_OFFSET;
    Light::Directional { direction: -toward_light.normalize(), color: Vec3::ONE, intensity: LIGHT_INTENSITY }
}
