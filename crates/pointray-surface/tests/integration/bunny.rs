//! The Stanford bunny: finite patches, positive radii, and
//! oriented normals that agree with the mesh's.

use crate::normals_support::area_weighted_vertex_normals;
use pointray_test_support::data_dir;

use pointray_io::formats::ply;
use pointray_patches::PrepSettings;
use pointray_surface::{NoProgress, prep};

#[test]
fn bunny_patches_are_finite_and_normals_agree_with_the_mesh() {
    let data = data_dir();
    let (points, mesh) = (data.join("points/bunny.ply"), data.join("meshes/bunny.ply"));
    let cloud = ply::read_point_cloud(&points).expect("the bunny points read");
    let mesh = ply::read_triangle_mesh(&mesh).expect("the bunny mesh reads");
    let (patches, report) = prep(&cloud, &PrepSettings::default(), &NoProgress).expect("the bunny preps");
    for (i, patch) in patches.hot.iter().enumerate() {
        assert!(patch.decode().coefficients.iter().all(|c| c.is_finite()), "patch {i}: {patch:?}");
        assert!(patch.radius() > 0.0 && patch.radius().is_finite(), "patch {i}: {patch:?}");
    }
    let mesh_normals = area_weighted_vertex_normals(&mesh);
    let (mut agree, mut compared) = (0usize, 0usize);
    for (patch, &source) in patches.hot.iter().zip(&report.patch_sources) {
        let reference = mesh_normals[source as usize];
        if reference.length_squared() > 0.0 {
            compared += 1;
            agree += usize::from(patch.normal().dot(reference) > 0.0);
        }
    }
    let best = agree.max(compared - agree) as f64 / compared as f64;
    println!(
        "{agree} of {compared} normals agree with the mesh ({:.3}% after the best global flip)",
        100.0 * best
    );
    assert!(compared > 34_000, "only {compared} patches have a mesh normal");
    assert!(best >= 0.99, "only {:.3}% agree", 100.0 * best);
}

/// One junk point far off (a stray return) must not make the bunny's own points duplicates:
/// the tolerance follows the f32 spacing at each point, and the cloud is recentred on its
/// own points, not on the middle of the box the stray point stretches.
#[test]
fn a_far_stray_point_merges_none_of_the_bunny_but_exact_copies_still_merge() {
    let mut cloud = ply::read_point_cloud(&data_dir().join("points/bunny.ply")).expect("the bunny reads");
    let bunny = cloud.len();
    let copies: Vec<_> = cloud.positions[..500].to_vec();
    cloud.positions.extend(copies);
    cloud.positions.push(glam::DVec3::new(1e4, 0.0, 0.0));
    let (patches, report) = prep(&cloud, &PrepSettings::default(), &NoProgress).expect("the cloud preps");
    let (kept, merged) = (patches.hot.len(), report.merged_duplicates);
    assert_eq!(merged, 500, "the exact copies merge, and nothing else");
    assert_eq!(kept, bunny + 1, "every bunny point and the stray point keep their patches");
}
