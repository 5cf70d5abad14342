//! One object's bottom level: a BVH over its patch boxes or its triangles, in object space.

use std::sync::Arc;
use std::time::Duration;

use glam::{Vec2, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use pointray_io::TriangleMesh;
use pointray_kernels::{Aabb, PatchAcceptance, Ray, intersect_patch};
use pointray_patches::PatchSet;
use pointray_patches::geometry_range::{box_in_range, first_vertex_out_of_range};
use pointray_patches::patch_tiles::tile_ranges;
use pointray_scene::Geometry;
use rayon::prelude::*;

use crate::triangle::intersect_triangle;

/// What a ray hit inside one object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectHit {
    pub t: f32,
    /// The patch or triangle index within the object (the whole set, not the tile).
    pub primitive: u32,
    /// Patch-local `(u, v)`; zero for triangles.
    pub uv: Vec2,
}

pub struct ObjectBvh {
    bvh: CwBvh,
    /// Each primitive's box. BVH leaves hold several primitives under one box; testing the
    /// ray against the primitive's own box first skips most quadratic solves, and matches
    /// the GPU, whose hardware calls the intersection shader only for boxes the ray enters.
    boxes: Vec<obvhs::aabb::Aabb>,
    /// The object's index of this BVH's first primitive: a tile of a large point set holds
    /// a run of its patches, and hits name them by their index in the whole set.
    first: u32,
    geometry: Geometry,
}

impl ObjectBvh {
    /// The BVHs of an object's tiles (`pointray_patches::patch_tiles`): a point set's
    /// patches in runs of at most `max_tile_patches`, a mesh whole. Empty for an object
    /// with nothing to hit, or whose records are inconsistent (a triangle naming a missing
    /// vertex, fewer boxes than patches): it is left out, with a warning, rather than crash
    /// the render.
    pub fn build_tiles(geometry: &Geometry, max_tile_patches: usize) -> Vec<Self> {
        if let Some(problem) = inconsistency(geometry) {
            tracing::warn!("CPU renderer: leaving an object out: {problem}");
            return Vec::new();
        }
        let boxes = primitive_boxes(geometry);
        let max_tile = match geometry {
            Geometry::Patches(_) => max_tile_patches,
            Geometry::Mesh(_) => boxes.len(),
        };
        tile_ranges(boxes.len(), max_tile)
            .into_par_iter()
            .map(|tile| {
                let boxes = boxes[tile.clone()].to_vec();
                Self { bvh: build_bvh(&boxes), boxes, first: tile.start as u32, geometry: geometry.clone() }
            })
            .collect()
    }

    /// The object-space box around every primitive.
    pub fn bounds(&self) -> Aabb {
        let total = &self.bvh.total_aabb;
        Aabb::new(total.min.into(), total.max.into())
    }

    /// The nearest hit in `[t_min, t_max]` of an object-space ray.
    pub fn closest_hit(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        acceptance: PatchAcceptance,
    ) -> Option<ObjectHit> {
        let mut nearest = None;
        let mut hit = obvhs::ray::RayHit::none();
        self.bvh.ray_traverse(traversal_ray(ray, t_min, t_max), &mut hit, |candidate, id| {
            let primitive = self.bvh.primitive_indices[id];
            match self.intersect(ray, candidate, primitive, acceptance) {
                Some(found) if found.t < candidate.tmax => {
                    nearest = Some(found);
                    found.t
                }
                _ => f32::INFINITY,
            }
        });
        nearest
    }

    /// Whether anything lies on the object-space ray within `[t_min, t_max]`.
    pub fn occludes(&self, ray: &Ray, t_min: f32, t_max: f32, acceptance: PatchAcceptance) -> bool {
        !self.bvh.ray_traverse_miss(traversal_ray(ray, t_min, t_max), |candidate, id| {
            let primitive = self.bvh.primitive_indices[id];
            self.intersect(ray, candidate, primitive, acceptance).map_or(f32::INFINITY, |found| found.t)
        })
    }

    /// `ray` and `candidate` are the same ray; `candidate` carries the current `[t_min, t_max]`.
    fn intersect(
        &self,
        ray: &Ray,
        candidate: &obvhs::ray::Ray,
        primitive: u32,
        acceptance: PatchAcceptance,
    ) -> Option<ObjectHit> {
        if !enters_box(&self.boxes[primitive as usize], candidate) {
            return None;
        }
        let primitive = self.first + primitive;
        let index = primitive as usize;
        let (t_min, t_max) = (candidate.tmin, candidate.tmax);
        match &self.geometry {
            Geometry::Patches(patches) => {
                intersect_patch(ray, &patches.hot[index].decode(), t_min, t_max, acceptance)
                    .map(|hit| ObjectHit { t: hit.t, primitive, uv: hit.uv })
            }
            Geometry::Mesh(mesh) => intersect_triangle(ray, triangle_corners(mesh, index), t_min, t_max)
                .map(|t| ObjectHit { t, primitive, uv: Vec2::ZERO }),
        }
    }

    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }
}

/// Whether the ray passes through the box within its `[tmin, tmax]` (the slab test).
fn enters_box(bounds: &obvhs::aabb::Aabb, ray: &obvhs::ray::Ray) -> bool {
    let t1 = (bounds.min - ray.origin) * ray.inv_direction;
    let t2 = (bounds.max - ray.origin) * ray.inv_direction;
    let entry = t1.min(t2).max_element().max(ray.tmin);
    let exit = t1.max(t2).min_element().min(ray.tmax);
    entry <= exit
}

/// Records the BVH builder cannot take: it panics on NaN or infinite boxes.
fn inconsistency(geometry: &Geometry) -> Option<String> {
    match geometry {
        Geometry::Patches(patches) if patches.aabbs.len() != patches.hot.len() => {
            Some(format!("{} patch boxes for {} patches", patches.aabbs.len(), patches.hot.len()))
        }
        Geometry::Patches(patches) => {
            let bad = patches.aabbs.iter().position(|aabb| !box_in_range(aabb))?;
            Some(format!("patch box {bad} is not finite or out of range"))
        }
        Geometry::Mesh(mesh) => {
            let vertices = mesh.positions.len();
            if let Some(bad) = first_vertex_out_of_range(mesh) {
                return Some(format!("vertex {bad} is not finite or out of range"));
            }
            let bad = mesh.triangles.iter().position(|t| t.iter().any(|&i| i as usize >= vertices))?;
            Some(format!("triangle {bad} names a vertex beyond the mesh's {vertices}"))
        }
    }
}

pub fn triangle_corners(mesh: &TriangleMesh, triangle: usize) -> [Vec3; 3] {
    mesh.triangles[triangle].map(|i| mesh.positions[i as usize])
}

/// A compressed wide BVH over `boxes` (non-empty), primitive `i` being box `i`.
pub fn build_bvh(boxes: &[obvhs::aabb::Aabb]) -> CwBvh {
    build_cwbvh(boxes, BvhBuildParams::medium_build(), &mut Duration::default())
}

/// The obvhs form of a ray and its `[t_min, t_max]`.
pub fn traversal_ray(ray: &Ray, t_min: f32, t_max: f32) -> obvhs::ray::Ray {
    obvhs::ray::Ray::new(Vec3A::from(ray.origin), Vec3A::from(ray.direction), t_min, t_max)
}

fn primitive_boxes(geometry: &Geometry) -> Vec<obvhs::aabb::Aabb> {
    match geometry {
        Geometry::Patches(patches) => patch_boxes(patches),
        Geometry::Mesh(mesh) => triangle_boxes(mesh),
    }
}

fn patch_boxes(patches: &Arc<PatchSet>) -> Vec<obvhs::aabb::Aabb> {
    patches.aabbs.iter().map(|b| obvhs::aabb::Aabb::new(b.min.into(), b.max.into())).collect()
}

fn triangle_boxes(mesh: &Arc<TriangleMesh>) -> Vec<obvhs::aabb::Aabb> {
    (0..mesh.triangles.len())
        .map(|i| {
            let points = triangle_corners(mesh, i).map(Vec3A::from);
            obvhs::aabb::Aabb::from_points(&points)
        })
        .collect()
}
