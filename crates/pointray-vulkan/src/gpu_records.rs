//! Records the shaders read, byte for byte as `shaders/bindings.glsl` declares them.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use pointray_kernels::{PatchCold, PatchHot};
use pointray_scene::{Background, BufferLayout, Camera, Light, Material, RenderSettings};

use crate::trace_target::PixelOutput;

/// Hot and cold data of one patch interleaved (`BufferLayout::Combined`): 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct PatchCombined {
    hot: PatchHot,
    cold: PatchCold,
}

impl PatchCombined {
    pub(crate) fn new(hot: PatchHot, cold: PatchCold) -> Self {
        Self { hot, cold }
    }
}

/// Per TLAS instance (a mesh, a point set, or a tile of one): buffer addresses (zero where
/// the kind does not use them; a set's tiles share its buffers), material, and which object
/// and patches it is.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct ObjectRecord {
    pub(crate) hot: u64,
    pub(crate) cold: u64,
    pub(crate) combined: u64,
    pub(crate) vertices: u64,
    pub(crate) indices: u64,
    /// `COLOR_NEIGHBORS` patch indices per patch; 0 where the points have no colours.
    pub(crate) color_neighbors: u64,
    pub(crate) diffuse_ambient: [f32; 4],
    pub(crate) specular_shininess_reflect_colors: [f32; 4],
    /// The object's index in `Scene::objects`, which the instance AOV reports.
    pub(crate) object_index: u32,
    /// The patch index of the tile's primitive 0; 0 for meshes and untiled sets.
    pub(crate) first_patch: u32,
    pub(crate) pad: [u32; 2],
}

impl ObjectRecord {
    /// This record (its addresses) with `material`'s values.
    pub(crate) fn with_material(self, material: &Material) -> Self {
        let d = material.diffuse;
        Self {
            diffuse_ambient: [d.x, d.y, d.z, material.ambient],
            specular_shininess_reflect_colors: [
                material.specular,
                material.shininess,
                material.reflectivity,
                if material.use_point_colors { 1.0 } else { 0.0 },
            ],
            ..self
        }
    }

    /// This record for the tile of object `object_index` whose first patch is `first_patch`.
    pub(crate) fn for_tile(self, object_index: u32, first_patch: u32) -> Self {
        Self { object_index, first_patch, ..self }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct LightRecord {
    position_or_direction: [f32; 4],
    radiance: [f32; 4],
}

impl From<&Light> for LightRecord {
    fn from(light: &Light) -> Self {
        let (place, kind, color, intensity) = match *light {
            Light::Point { position, color, intensity } => (position, 0.0, color, intensity),
            Light::Directional { direction, color, intensity } => (direction, 1.0, color, intensity),
        };
        let radiance = color * intensity;
        Self {
            position_or_direction: [place.x, place.y, place.z, kind],
            radiance: [radiance.x, radiance.y, radiance.z, 0.0],
        }
    }
}

/// The uniform block `FrameUniforms` (std140).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct FrameUniforms {
    camera_position_fov: [f32; 4],
    camera_look_at: [f32; 4],
    camera_up: [f32; 4],
    background_top: [f32; 4],
    background_bottom: [f32; 4],
    light_count: u32,
    ray_epsilon: f32,
    pad: [u32; 2],
}

fn vec4(v: Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

impl FrameUniforms {
    pub(crate) fn new(camera: &Camera, background: &Background, light_count: u32, ray_epsilon: f32) -> Self {
        // A solid background is the gradient between two equal colours.
        let (top, bottom) = match *background {
            Background::Solid(color) => (color, color),
            Background::Gradient { top, bottom } => (top, bottom),
        };
        Self {
            camera_position_fov: vec4(camera.position, camera.vertical_fov_degrees),
            camera_look_at: vec4(camera.look_at, 0.0),
            camera_up: vec4(camera.up, 0.0),
            background_top: vec4(top, 0.0),
            background_bottom: vec4(bottom, 0.0),
            light_count,
            ray_epsilon,
            pad: [0; 2],
        }
    }
}

/// The push-constant block `TraceSettings`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct TraceSettings {
    width: u32,
    height: u32,
    samples_per_pixel: u32,
    max_depth: u32,
    shadows: u32,
    acceptance: u32,
    buffer_layout: u32,
    output_kind: u32,
}

impl TraceSettings {
    pub(crate) fn new(settings: &RenderSettings, output: PixelOutput) -> Self {
        Self {
            width: settings.width,
            height: settings.height,
            samples_per_pixel: settings.samples_per_pixel,
            max_depth: settings.max_depth,
            shadows: settings.shadows.into(),
            acceptance: settings.acceptance.code(),
            buffer_layout: match settings.buffer_layout {
                BufferLayout::Split => 0,
                BufferLayout::Combined => 1,
            },
            output_kind: match output {
                PixelOutput::Aovs => 0,
                PixelOutput::Display => 1,
                PixelOutput::DisplayBgra => 2,
            },
        }
    }
}

/// One pixel of the output buffer `Pixels`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct PixelRecord {
    pub(crate) color: [f32; 4],
    /// Face-forwarded world normal in xyz; depth in w, negative on a miss.
    pub(crate) normal_depth: [f32; 4],
    pub(crate) ids: [u32; 4],
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_have_the_glsl_sizes() {
        assert_eq!(std::mem::size_of::<PatchCombined>(), 48);
        assert_eq!(std::mem::size_of::<ObjectRecord>(), 96);
        assert_eq!(std::mem::size_of::<LightRecord>(), 32);
        assert_eq!(std::mem::size_of::<FrameUniforms>(), 96);
        assert_eq!(std::mem::size_of::<PixelRecord>(), 48);
    }
}
