//! What `prep` carries from the input: normals (kept, recomputed, oriented toward a
//! sensor, repaired), colours and intensities, through the Morton reordering.

use crate::common;

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;
use pointray_patches::{PatchSet, PrepSettings};
use pointray_surface::{NoProgress, PrepReport, prep};

const CENTRE: DVec3 = DVec3::new(10.0, 20.0, -5.0);

fn sphere_with_normals(count: usize) -> PointCloud {
    let mut cloud = common::sphere(count, 1.0, CENTRE);
    // Outward and deliberately not unit length: prep must normalise them.
    cloud.normals = Some(cloud.positions.iter().map(|p| ((*p - CENTRE) * 3.0).as_vec3()).collect());
    cloud
}

fn outward(patches: &PatchSet, i: usize) -> Vec3 {
    (patches.hot[i].origin().as_dvec3() + patches.offset - CENTRE).normalize().as_vec3()
}

fn run(cloud: &PointCloud, options: &PrepSettings) -> (PatchSet, PrepReport) {
    prep(cloud, options, &NoProgress).expect("a sphere preps")
}

#[test]
fn input_normals_are_kept_and_normalised() {
    let (patches, report) = run(&sphere_with_normals(2000), &PrepSettings::default());
    assert_eq!(report.replaced_input_normals, 0);
    for (i, patch) in patches.hot.iter().enumerate() {
        assert!((patch.normal().length() - 1.0).abs() < 1e-5);
        assert!(patch.normal().dot(outward(&patches, i)) > 0.99999, "patch {i} lost its input normal");
    }
}

#[test]
fn recomputed_normals_face_the_sensor() {
    let options = PrepSettings { recompute_normals: true, sensor: Some(CENTRE), ..PrepSettings::default() };
    let (patches, _) = run(&sphere_with_normals(2000), &options);
    for i in 0..patches.len() {
        assert!(
            patches.hot[i].normal().dot(outward(&patches, i)) < -0.99,
            "patch {i} does not face the centre"
        );
    }
}

#[test]
fn broken_input_normals_are_replaced_and_agree_with_their_neighbours() {
    let mut cloud = sphere_with_normals(2000);
    let normals = cloud.normals.as_mut().unwrap();
    for i in (0..2000).step_by(100) {
        normals[i] = if i % 200 == 0 { Vec3::ZERO } else { Vec3::NAN };
    }
    let (patches, report) = run(&cloud, &PrepSettings::default());
    assert_eq!(report.replaced_input_normals, 20);
    for i in 0..patches.len() {
        assert!(patches.hot[i].normal().dot(outward(&patches, i)) > 0.99, "patch {i}");
    }
}

#[test]
fn colours_and_intensities_follow_their_points() {
    let mut cloud = common::sphere(4000, 1.0, CENTRE);
    // Channels of 0 or 255 are the same in sRGB and linear, so they can be compared exactly.
    let colour_of = |i: usize| [0, 1, 2].map(|bit| if i >> bit & 1 == 1 { 255u8 } else { 0 });
    cloud.colors = Some((0..4000).map(colour_of).collect());
    cloud.intensities = Some((0..4000).map(|i| i as f32 / 4000.0).collect());
    let (patches, report) = run(&cloud, &PrepSettings::default());
    assert_eq!(report.patch_sources.len(), patches.len());
    assert!(report.patch_sources.windows(2).any(|w| w[1] < w[0]), "Morton order differs from input order");
    for (cold, &source) in patches.cold.iter().zip(&report.patch_sources) {
        let [r, g, b, a] = cold.color_rgba8.to_le_bytes();
        assert_eq!([r, g, b], colour_of(source as usize));
        assert_eq!(a, 255);
        assert_eq!(cold.intensity, source as f32 / 4000.0);
    }
    let input = |i: u32| cloud.positions[i as usize];
    for (patch, &source) in patches.hot.iter().zip(&report.patch_sources) {
        assert!((patch.origin().as_dvec3() + patches.offset - input(source)).length() < 1e-6);
    }
}
