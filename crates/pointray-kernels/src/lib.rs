//! The maths that the CPU renderer, the tests and the GLSL shaders share.
//!
//! Every function here has a twin of the same name in `shaders/NAME.glsl`; the file
//! `src/NAME.rs` and `shaders/NAME.glsl` describe the same maths. Change both together.
//! `Patch` and its decoding from `PatchHot` (`src/layout.rs`) have their twins in
//! `shaders/patch_frame.glsl`; `src/packing.rs` twins the GLSL packing built-ins. The shader
//! stages that include these twins belong to the crate that builds their pipeline.

pub mod background;
pub mod bsdf;
pub mod bsdf_sample;
pub mod camera_ray;
pub mod dielectric;
mod distribution;
pub mod emissive_triangles;
pub mod environment_map;
pub mod face_forward;
pub mod fresnel;
pub mod interpolate_color;
pub mod intersect_patch;
pub mod lambert;
pub mod layout;
pub mod light_source;
pub mod microfacet;
pub mod packing;
pub mod patch_normal;
pub mod phong;
pub mod quadratic_roots;
pub mod random_sequence;
pub mod ray;
pub mod rough_conductor;
pub mod rough_plastic;
pub mod sampling;
pub mod self_clearance;
pub mod srgb_encode;
pub mod tangent_frame;
pub mod unpacked_patch;

pub use background::background;
pub use bsdf::{Bsdf, bsdf_eval, bsdf_is_two_sided, bsdf_pdf, bsdf_sample, bsdf_samples_lights};
pub use bsdf_sample::BsdfSample;
pub use camera_ray::{Camera, camera_ray, sample_jitter};
pub use emissive_triangles::{EmissiveTriangles, emissive_pdf, emissive_sample};
pub use environment_map::{
    EnvironmentMap, environment_direction, environment_pdf, environment_radiance, environment_sample,
    environment_uv,
};
pub use face_forward::face_forward;
pub use interpolate_color::{COLOR_NEIGHBORS, COLOR_WALK_SCANS, NO_NEIGHBOR, interpolate_color};
pub use intersect_patch::{PatchAcceptance, PatchHit, intersect_patch};
pub use layout::{Aabb, PackedTangentFrame, Patch, PatchCold, PatchHot};
pub use light_source::{
    LightSample, LightSource, light_emitted, light_hit, light_is_delta, light_pdf, light_sample,
};
pub use patch_normal::patch_normal;
pub use phong::{PhongSurface, phong};
pub use quadratic_roots::{QuadraticRoots, quadratic_roots};
pub use random_sequence::{RandomSequence, random_next, random_next2, random_sequence};
pub use ray::Ray;
pub use self_clearance::{path_ray_offset, self_clearance};
pub use srgb_encode::{srgb_encode, srgb_encode_rgba8};
pub use tangent_frame::TangentFrame;
pub use unpacked_patch::PatchUnpacked;

/// The folder of the GLSL twins, for the build scripts that compile shaders including them.
pub const SHADER_FOLDER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
