//! Triangle proxies of a patch set, for the benchmark's ablation: each patch as two triangles
//! over the square that holds its support ellipse, their corners on its height field. Traced
//! as a mesh, they show what the traversal costs when the driver meets triangles instead of
//! boxes that call the intersection shader; the quadratic is not solved for their hits, so
//! their time is a bound from below on any layout of proxies that refines its hits.

use glam::{Vec2, Vec3};
use pointray_io::TriangleMesh;
use pointray_kernels::Patch;
use pointray_patches::PatchSet;
use pointray_patches::patch_bounds::evaluate;

/// Two triangles a patch, four corners each in the patch's order.
pub fn triangle_proxies(patches: &PatchSet) -> TriangleMesh {
    let mut mesh = TriangleMesh { positions: Vec::with_capacity(4 * patches.len()), triangles: Vec::new() };
    mesh.triangles.reserve(2 * patches.len());
    for hot in patches.hot.iter() {
        let patch = hot.decode();
        let first = mesh.positions.len() as u32;
        mesh.positions.extend(
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(u, v)| corner(&patch, Vec2::new(u, v) * patch.radii)),
        );
        mesh.triangles.extend([[first, first + 1, first + 2], [first, first + 2, first + 3]]);
    }
    mesh
}

/// The point of `patch`'s height field over local `uv`.
fn corner(patch: &Patch, uv: Vec2) -> Vec3 {
    patch.to_world(uv.extend(evaluate(&patch.coefficients, uv.x, uv.y)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use pointray_kernels::PatchHot;

    #[test]
    fn a_flat_patch_becomes_the_square_around_its_disk() {
        let hot = PatchHot::isotropic(Vec3::new(1.0, 2.0, 3.0), Vec3::X, Vec3::Z, [0.0; 6], 0.5);
        let set = PatchSet { hot: vec![hot].into(), ..PatchSet::default() };
        let mesh = triangle_proxies(&set);
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        for corner in &mesh.positions {
            assert!((corner.z - 3.0).abs() < 1e-6, "{corner}");
            assert!(
                ((corner.x - 1.0).abs() - 0.5).abs() < 1e-3 && ((corner.y - 2.0).abs() - 0.5).abs() < 1e-3
            );
        }
    }
}
