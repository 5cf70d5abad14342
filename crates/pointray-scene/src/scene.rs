//! A loaded scene, ready for any backend.

use std::sync::Arc;

use glam::Affine3A;
use pointray_io::TriangleMesh;
use pointray_patches::PatchSet;

use crate::{Background, Camera, Light, Material};

#[derive(Clone, Debug)]
pub enum Geometry {
    /// Patches in their local coordinates; the object's transform places them.
    Patches(Arc<PatchSet>),
    Mesh(Arc<TriangleMesh>),
}

#[derive(Clone, Debug)]
pub struct SceneObject {
    pub name: String,
    /// Object to world.
    pub transform: Affine3A,
    pub material: Material,
    pub geometry: Geometry,
}

#[derive(Clone, Debug)]
pub struct Scene {
    pub camera: Camera,
    pub lights: Vec<Light>,
    pub background: Background,
    pub objects: Vec<SceneObject>,
}
