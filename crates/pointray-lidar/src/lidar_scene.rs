//! What a sensor scans: the CPU renderer's acceleration structures over a scene, with each
//! object's reflectance and class.

use std::path::Path;
use std::sync::Arc;

use glam::{Affine3A, DVec3, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_kernels::Ray;
use pointray_patches::PatchSet;
use pointray_scene::{Background, Geometry, LoadOptions, Material, Scene, SceneObject};

use crate::resimulation::SENSOR_ACCEPTANCE;
use crate::surface::{Surface, reflectance_of};
use crate::{Classification, LidarError, UpAxis};

/// How an object answers the laser.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Response {
    reflectance: f32,
    class: Classification,
}

/// A surface point met by a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub range: f64,
    /// The cosine of the angle between the ray and the surface normal, in [0, 1].
    pub cos_incidence: f64,
    pub reflectance: f32,
    pub class: Classification,
}

pub struct LidarScene {
    renderer: CpuRenderer,
    responses: Vec<Response>,
    up: UpAxis,
    /// Where the renderer's origin lies in the scene's coordinates: a prepped map keeps its
    /// patches recentred, and rays are moved there instead.
    offset: DVec3,
}

impl LidarScene {
    /// Meshes in world coordinates.
    pub fn from_surfaces(surfaces: &[Surface], up: UpAxis) -> Result<Self, LidarError> {
        if let Some((surface, problem)) = surfaces.iter().find_map(|s| s.problem().map(|p| (s, p))) {
            return Err(LidarError::BadSurface { name: surface.name.clone(), problem });
        }
        let objects = surfaces
            .iter()
            .map(|surface| SceneObject {
                name: surface.name.clone(),
                transform: Affine3A::IDENTITY,
                material: Material { diffuse: Vec3::splat(surface.reflectance), ..Material::default() },
                geometry: Geometry::Mesh(Arc::new(surface.mesh.clone())),
            })
            .collect();
        Self::from_scene(&scene_of(objects), up)
    }

    /// A loaded scene (meshes and point sets): each object's reflectance is the luminance of
    /// its diffuse colour, its class comes from its name.
    pub fn from_scene(scene: &Scene, up: UpAxis) -> Result<Self, LidarError> {
        if scene.objects.is_empty() {
            return Err(LidarError::EmptyScene);
        }
        let responses = scene
            .objects
            .iter()
            .map(|object| Response {
                reflectance: reflectance_of(object.material.diffuse),
                class: Classification::of_object_named(&object.name),
            })
            .collect();
        Ok(Self { renderer: CpuRenderer::new(scene), responses, up, offset: DVec3::ZERO })
    }

    /// A prepped map (Z up, as LiDAR frames are) in the coordinates of the points it was
    /// prepped from.
    pub fn from_patches(patches: Arc<PatchSet>) -> Result<Self, LidarError> {
        let offset = patches.offset;
        Ok(Self { offset, ..Self::from_scene(&map_scene(patches), UpAxis::Z)? })
    }

    /// A pointray scene file, Y up as all of them are. Point sets in it are prepped in memory.
    pub fn from_scene_file(path: &Path) -> Result<Self, LidarError> {
        let loaded = pointray_scene::load_scene(path, &LoadOptions::default())?;
        Self::from_scene(&loaded.scene, UpAxis::Y)
    }

    pub fn up(&self) -> UpAxis {
        self.up
    }

    /// Where the renderer's origin lies in the scene's coordinates (`MapCaster::centre`).
    pub fn centre(&self) -> DVec3 {
        self.offset
    }

    /// The first surface along a unit `direction` from `origin` within `max_range`.
    pub fn first_hit(&self, origin: DVec3, direction: DVec3, max_range: f64) -> Option<SurfaceHit> {
        let ray = Ray::new((origin - self.offset).as_vec3(), direction.as_vec3());
        let hit = self.renderer_hit(&ray, max_range as f32)?;
        let response = self.responses[hit.object as usize];
        Some(SurfaceHit {
            range: f64::from(hit.t),
            cos_incidence: f64::from(hit.normal.dot(-ray.direction)).clamp(0.0, 1.0),
            reflectance: response.reflectance,
            class: response.class,
        })
    }

    /// The renderer's first hit on `ray`, in its frame (the scene's less `centre`), as
    /// sensors see surfaces: from t = 0, patches accepted over their support.
    pub(crate) fn renderer_hit(&self, ray: &Ray, max_range: f32) -> Option<pointray_cpu::RayHit> {
        self.renderer.first_hit(ray, 0.0, max_range, SENSOR_ACCEPTANCE)
    }
}

/// A prepped map as a scene of one object, in its patches' recentred frame: what
/// `LidarScene::from_patches` casts into, and what a GPU caster uploads.
pub fn map_scene(patches: Arc<PatchSet>) -> Scene {
    let object = SceneObject {
        name: "map".to_owned(),
        transform: Affine3A::IDENTITY,
        material: Material::default(),
        geometry: Geometry::Patches(patches),
    };
    scene_of(vec![object])
}

/// A scene of bare objects: scans need no camera or lights, but a `Scene` carries them.
fn scene_of(objects: Vec<SceneObject>) -> Scene {
    let camera = pointray_scene::Camera {
        position: Vec3::ONE,
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        vertical_fov_degrees: 40.0,
    };
    Scene { camera, lights: Vec::new(), background: Background::Solid(Vec3::ZERO), objects }
}
