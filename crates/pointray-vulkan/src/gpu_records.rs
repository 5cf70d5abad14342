//! Records the shaders read, byte for byte as `shaders/bindings.glsl` declares them.

use std::ops::Range;

use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, Vec3};
use pointray_kernels::{PatchAcceptance, PatchCold, PatchHot, Ray};
use pointray_scene::light::WhittedLight;
use pointray_scene::{BufferLayout, Light, Material, RenderSettings};

use crate::acceleration::BlasLayout;

/// Hot and cold data of one patch interleaved (`BufferLayout::Combined`): 44 bytes.
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
    /// The path integrator's BSDF (`pointray_kernels::bsdf::BSDF_*`) and its GGX alpha.
    pub(crate) bsdf_kind: u32,
    pub(crate) roughness: f32,
    /// Emitted radiance in rgb, the index of refraction in a.
    pub(crate) emission_ior: [f32; 4],
    /// One past the tile's last patch index; 0 for meshes.
    pub(crate) patch_end: u32,
    /// How many consecutive patches one box of the tile's bottom level bounds (`BlasLayout`).
    pub(crate) patches_per_box: u32,
    /// The record's std430 size is a multiple of its vec4s' alignment.
    pub(crate) padding: [u32; 2],
}

impl ObjectRecord {
    /// This record (its addresses) with `material`'s values.
    pub(crate) fn with_material(self, material: &Material) -> Self {
        let d = material.diffuse;
        // The kind, roughness and index do not depend on the colour, which a hit supplies.
        let bsdf = material.bsdf(d);
        Self {
            bsdf_kind: bsdf.kind,
            roughness: bsdf.roughness,
            emission_ior: vec4(material.emission, bsdf.ior),
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

    /// This record for the tile of object `object_index` that holds `patches`, whose bottom
    /// level is in `layout`.
    pub(crate) fn for_tile(self, object_index: u32, patches: Range<usize>, layout: BlasLayout) -> Self {
        Self {
            object_index,
            first_patch: patches.start as u32,
            patch_end: patches.end as u32,
            patches_per_box: layout.patches_per_box(),
            ..self
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct LightRecord {
    position_or_direction: [f32; 4],
    whitted_radiance: [f32; 4],
    radiance: [f32; 4],
    origin_radius: [f32; 4],
    edge_u: [f32; 4],
    edge_v: [f32; 4],
}

impl From<&Light> for LightRecord {
    fn from(light: &Light) -> Self {
        // Area lights shine from their centres under the Whitted integrator.
        let (place, kind, color, intensity) = match light.as_whitted() {
            WhittedLight::Point { position, color, intensity } => (position, 0.0, color, intensity),
            WhittedLight::Directional { direction, color, intensity } => (direction, 1.0, color, intensity),
        };
        let source = light.source();
        Self {
            position_or_direction: [place.x, place.y, place.z, kind],
            whitted_radiance: vec4(color * intensity, 0.0),
            radiance: vec4(source.radiance, source.kind as f32),
            origin_radius: vec4(source.position, source.radius),
            edge_u: vec4(source.edge_u, 0.0),
            edge_v: vec4(source.edge_v, 0.0),
        }
    }
}

/// The uniform block `FrameUniforms` (std140).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct FrameUniforms {
    pub(crate) camera_position_fov: [f32; 4],
    pub(crate) camera_look_at: [f32; 4],
    pub(crate) camera_up: [f32; 4],
    pub(crate) background_top: [f32; 4],
    pub(crate) background_bottom: [f32; 4],
    pub(crate) light_count: u32,
    pub(crate) ray_epsilon: f32,
    pub(crate) sky_lit: u32,
    pub(crate) sky_is_map: u32,
    pub(crate) sky_texels: u64,
    pub(crate) sky_distribution: u64,
    pub(crate) sky_width: u32,
    pub(crate) sky_height: u32,
    pub(crate) sky_rotation: f32,
    pub(crate) emissive_count: u32,
    pub(crate) emissive_records: u64,
    pub(crate) emissive_distribution: u64,
    pub(crate) emissive_total_area: f32,
    pub(crate) pad: [u32; 3],
}

pub(crate) fn vec4(v: Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
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
    seed: u32,
    first_sample: u32,
}

impl TraceSettings {
    /// The push constants of a trace with `settings`, writing pixels of the kind
    /// `output_kind` (`PixelOutput::code`).
    pub(crate) fn new(settings: &RenderSettings, output_kind: u32) -> Self {
        Self {
            width: settings.width,
            height: settings.height,
            samples_per_pixel: settings.samples_per_pixel,
            max_depth: settings.max_depth,
            shadows: settings.shadows.into(),
            acceptance: settings.acceptance.code(),
            buffer_layout: layout_code(settings.buffer_layout),
            output_kind,
            seed: settings.seed,
            first_sample: settings.first_sample,
        }
    }

    /// The push constants of a ray list's cast: only the hit shaders' settings count.
    pub(crate) fn for_ray_list(acceptance: PatchAcceptance, buffer_layout: BufferLayout) -> Self {
        Self { acceptance: acceptance.code(), buffer_layout: layout_code(buffer_layout), ..Self::zeroed() }
    }
}

/// One ray of a ray list (`ListedRay` in bindings.glsl), in the frame its poses place in the
/// scene: hits are reported between `t_min` and `t_max` along `direction` once posed, in the
/// scene's units.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ListedRay {
    pub origin: [f32; 3],
    pub t_min: f32,
    pub direction: [f32; 3],
    pub t_max: f32,
}

/// What a listed ray met (`RayHit` in bindings.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RayHit {
    /// The distance along the ray; negative on a miss.
    pub t: f32,
    /// The object's index in the scene; `RenderedImage::MISS` on a miss.
    pub object_index: u32,
    /// The patch's index in its whole set, or the triangle's; `RenderedImage::MISS` on a miss.
    pub primitive: u32,
}

impl ListedRay {
    /// `ray` (a unit direction gives distances in the scene's units) between `t_min` and
    /// `t_max`.
    pub fn new(ray: &Ray, t_min: f32, t_max: f32) -> Self {
        Self { origin: ray.origin.to_array(), t_min, direction: ray.direction.to_array(), t_max }
    }
}

/// Where a ray list is cast from (`RayPose` in bindings.glsl): an affine map from the list's
/// frame into the prepared scene's, by rows.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct RayPose {
    rows: [[f32; 4]; 3],
}

impl RayPose {
    pub fn new(pose: &Affine3A) -> Self {
        let (m, t) = (pose.matrix3, pose.translation);
        let row = |i: usize| [m.x_axis[i], m.y_axis[i], m.z_axis[i], t[i]];
        Self { rows: [row(0), row(1), row(2)] }
    }
}

impl RayHit {
    /// The distance along the ray, `None` on a miss.
    pub fn distance(&self) -> Option<f32> {
        (self.t >= 0.0).then_some(self.t)
    }
}

/// The value the shaders receive for `layout` (`LAYOUT_*` in bindings.glsl).
fn layout_code(layout: BufferLayout) -> u32 {
    match layout {
        BufferLayout::Split => 0,
        BufferLayout::Combined => 1,
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
    use std::mem::{offset_of, size_of};

    use pointray_kernels::interpolate_color::{COLOR_NEIGHBORS, COLOR_WALK_SCANS, NO_NEIGHBOR};
    use pointray_kernels::{bsdf, light_source};
    use pointray_scene::RenderedImage;

    use super::*;
    use crate::spirv_reflection::Reflection;
    use crate::trace_target::PixelOutput;

    fn probe() -> Reflection {
        Reflection::of(crate::shaders::INTERFACE_PROBE_RGEN)
    }

    fn assert_members(reflection: &Reflection, glsl_struct: &str, rust: &[(&str, usize)]) {
        let expected: Vec<(String, u32)> =
            rust.iter().map(|&(name, offset)| (name.to_owned(), offset as u32)).collect();
        assert_eq!(reflection.member_offsets(glsl_struct), expected, "{glsl_struct}: members and offsets");
    }

    #[test]
    fn every_record_has_the_compiled_shaders_offsets_and_size() {
        let probe = probe();
        assert_members(
            &probe,
            "PatchHot",
            &[
                ("origin_x", offset_of!(PatchHot, origin)),
                ("origin_y", offset_of!(PatchHot, origin) + 4),
                ("origin_z", offset_of!(PatchHot, origin) + 8),
                ("radius", offset_of!(PatchHot, radius)),
                ("frame", offset_of!(PatchHot, frame)),
                ("aspect_c1", offset_of!(PatchHot, aspect_c1)),
                ("c2_c3", offset_of!(PatchHot, coefficients)),
                ("c4_c5", offset_of!(PatchHot, coefficients) + 4),
            ],
        );
        assert_members(
            &probe,
            "PatchCold",
            &[
                ("color_rgba8", offset_of!(PatchCold, color_rgba8)),
                ("intensity", offset_of!(PatchCold, intensity)),
                ("color_reach", offset_of!(PatchCold, color_reach)),
            ],
        );
        assert_members(
            &probe,
            "PatchCombined",
            &[("hot", offset_of!(PatchCombined, hot)), ("cold", offset_of!(PatchCombined, cold))],
        );
        assert_members(
            &probe,
            "ObjectRecord",
            &[
                ("hot", offset_of!(ObjectRecord, hot)),
                ("cold", offset_of!(ObjectRecord, cold)),
                ("combined", offset_of!(ObjectRecord, combined)),
                ("vertices", offset_of!(ObjectRecord, vertices)),
                ("indices", offset_of!(ObjectRecord, indices)),
                ("color_neighbors", offset_of!(ObjectRecord, color_neighbors)),
                ("diffuse_ambient", offset_of!(ObjectRecord, diffuse_ambient)),
                (
                    "specular_shininess_reflect_colors",
                    offset_of!(ObjectRecord, specular_shininess_reflect_colors),
                ),
                ("object_index", offset_of!(ObjectRecord, object_index)),
                ("first_patch", offset_of!(ObjectRecord, first_patch)),
                ("bsdf_kind", offset_of!(ObjectRecord, bsdf_kind)),
                ("roughness", offset_of!(ObjectRecord, roughness)),
                ("emission_ior", offset_of!(ObjectRecord, emission_ior)),
                ("patch_end", offset_of!(ObjectRecord, patch_end)),
                ("patches_per_box", offset_of!(ObjectRecord, patches_per_box)),
            ],
        );
        assert_members(
            &probe,
            "LightRecord",
            &[
                ("position_or_direction", offset_of!(LightRecord, position_or_direction)),
                ("whitted_radiance", offset_of!(LightRecord, whitted_radiance)),
                ("radiance", offset_of!(LightRecord, radiance)),
                ("origin_radius", offset_of!(LightRecord, origin_radius)),
                ("edge_u", offset_of!(LightRecord, edge_u)),
                ("edge_v", offset_of!(LightRecord, edge_v)),
            ],
        );
        assert_members(
            &probe,
            "PixelRecord",
            &[
                ("color", offset_of!(PixelRecord, color)),
                ("normal_depth", offset_of!(PixelRecord, normal_depth)),
                ("ids", offset_of!(PixelRecord, ids)),
            ],
        );
        assert_members(
            &probe,
            "ListedRay",
            &[
                ("origin", offset_of!(ListedRay, origin)),
                ("t_min", offset_of!(ListedRay, t_min)),
                ("direction", offset_of!(ListedRay, direction)),
                ("t_max", offset_of!(ListedRay, t_max)),
            ],
        );
        assert_members(
            &probe,
            "RayHit",
            &[
                ("t", offset_of!(RayHit, t)),
                ("object_index", offset_of!(RayHit, object_index)),
                ("primitive", offset_of!(RayHit, primitive)),
            ],
        );
        assert_members(&probe, "RayPose", &[("rows", offset_of!(RayPose, rows))]);
        for (glsl_struct, size) in [
            ("RayPose", size_of::<RayPose>()),
            ("ListedRay", size_of::<ListedRay>()),
            ("RayHit", size_of::<RayHit>()),
            ("PatchHot", size_of::<PatchHot>()),
            ("PatchCold", size_of::<PatchCold>()),
            ("PatchCombined", size_of::<PatchCombined>()),
            ("ObjectRecord", size_of::<ObjectRecord>()),
            ("LightRecord", size_of::<LightRecord>()),
            ("PixelRecord", size_of::<PixelRecord>()),
        ] {
            assert_eq!(
                probe.array_stride_of(glsl_struct),
                size as u32,
                "{glsl_struct}: size (its array stride)"
            );
        }
    }

    #[test]
    fn the_uniform_and_push_constant_blocks_have_the_compiled_shaders_offsets() {
        let probe = probe();
        assert_members(
            &probe,
            "FrameUniforms",
            &[
                ("camera_position_fov", offset_of!(FrameUniforms, camera_position_fov)),
                ("camera_look_at", offset_of!(FrameUniforms, camera_look_at)),
                ("camera_up", offset_of!(FrameUniforms, camera_up)),
                ("background_top", offset_of!(FrameUniforms, background_top)),
                ("background_bottom", offset_of!(FrameUniforms, background_bottom)),
                ("light_count", offset_of!(FrameUniforms, light_count)),
                ("ray_epsilon", offset_of!(FrameUniforms, ray_epsilon)),
                ("sky_lit", offset_of!(FrameUniforms, sky_lit)),
                ("sky_is_map", offset_of!(FrameUniforms, sky_is_map)),
                ("sky_texels", offset_of!(FrameUniforms, sky_texels)),
                ("sky_distribution", offset_of!(FrameUniforms, sky_distribution)),
                ("sky_width", offset_of!(FrameUniforms, sky_width)),
                ("sky_height", offset_of!(FrameUniforms, sky_height)),
                ("sky_rotation", offset_of!(FrameUniforms, sky_rotation)),
                ("emissive_count", offset_of!(FrameUniforms, emissive_count)),
                ("emissive_records", offset_of!(FrameUniforms, emissive_records)),
                ("emissive_distribution", offset_of!(FrameUniforms, emissive_distribution)),
                ("emissive_total_area", offset_of!(FrameUniforms, emissive_total_area)),
                ("pad0", offset_of!(FrameUniforms, pad)),
                ("pad1", offset_of!(FrameUniforms, pad) + 4),
                ("pad2", offset_of!(FrameUniforms, pad) + 8),
            ],
        );
        assert_eq!(
            size_of::<FrameUniforms>(),
            offset_of!(FrameUniforms, pad) + 12,
            "FrameUniforms ends with its pad"
        );
        assert_members(
            &probe,
            "TraceSettings",
            &[
                ("width", offset_of!(TraceSettings, width)),
                ("height", offset_of!(TraceSettings, height)),
                ("samples_per_pixel", offset_of!(TraceSettings, samples_per_pixel)),
                ("max_depth", offset_of!(TraceSettings, max_depth)),
                ("shadows", offset_of!(TraceSettings, shadows)),
                ("acceptance", offset_of!(TraceSettings, acceptance)),
                ("buffer_layout", offset_of!(TraceSettings, buffer_layout)),
                ("output_kind", offset_of!(TraceSettings, output_kind)),
                ("seed", offset_of!(TraceSettings, seed)),
                ("first_sample", offset_of!(TraceSettings, first_sample)),
            ],
        );
        assert_eq!(size_of::<TraceSettings>(), offset_of!(TraceSettings, first_sample) + 4);
    }

    #[test]
    fn a_ray_pose_holds_its_affine_map_by_rows() {
        let pose = Affine3A::from_rotation_z(0.3) * Affine3A::from_translation(Vec3::new(1.0, -2.0, 3.5));
        let record = RayPose::new(&pose);
        let point = Vec3::new(0.25, 4.0, -1.5);
        let by_rows =
            Vec3::from_array(record.rows.map(|row| Vec3::from_slice(&row[..3]).dot(point) + row[3]));
        assert!(by_rows.distance(pose.transform_point3(point)) < 1e-5, "{by_rows} against the map");
    }

    #[test]
    fn every_shared_code_has_the_compiled_shaders_value() {
        // In the order interface_probe.rgen stores them.
        let host = [
            ("OUTPUT_AOVS", PixelOutput::Aovs.code()),
            ("OUTPUT_DISPLAY", PixelOutput::Display.code()),
            ("OUTPUT_DISPLAY_BGRA", PixelOutput::DisplayBgra.code()),
            ("LAYOUT_SPLIT", layout_code(BufferLayout::Split)),
            ("LAYOUT_COMBINED", layout_code(BufferLayout::Combined)),
            ("ACCEPTANCE_BOX", PatchAcceptance::Box.code()),
            ("ACCEPTANCE_DISK", PatchAcceptance::Disk.code()),
            ("COLOR_NEIGHBORS", COLOR_NEIGHBORS as u32),
            ("NO_NEIGHBOR", NO_NEIGHBOR),
            ("COLOR_WALK_SCANS", COLOR_WALK_SCANS),
            ("MISS_ID", RenderedImage::MISS),
            ("BSDF_DIFFUSE", bsdf::BSDF_DIFFUSE),
            ("BSDF_CONDUCTOR", bsdf::BSDF_CONDUCTOR),
            ("BSDF_PLASTIC", bsdf::BSDF_PLASTIC),
            ("BSDF_DIELECTRIC", bsdf::BSDF_DIELECTRIC),
            ("LIGHT_POINT", light_source::LIGHT_POINT),
            ("LIGHT_DIRECTIONAL", light_source::LIGHT_DIRECTIONAL),
            ("LIGHT_SPHERE", light_source::LIGHT_SPHERE),
            ("LIGHT_QUAD", light_source::LIGHT_QUAD),
        ];
        let stored = probe().stored_constants("ProbeCodes");
        assert_eq!(stored.len(), host.len(), "the probe stores every code once: {stored:?}");
        for (index, (name, value)) in host.into_iter().enumerate() {
            assert_eq!(stored.get(&(index as u32)), Some(&value), "{name}");
        }
    }
}
