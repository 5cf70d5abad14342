//! The mesh normals fidelity compares against: angle-weighted vertex normals, interpolated
//! across each triangle, are exact on a sphere mesh whose vertex normals are radial.

use std::sync::Arc;

use glam::{Affine3A, Vec3};
use pointray_fidelity::VertexNormals;
use pointray_io::TriangleMesh;
use pointray_scene::{
    Background, Camera, Geometry, Material, RenderSettings, RenderedImage, Scene, SceneObject,
};

/// The regular icosahedron on the unit sphere: by symmetry each vertex's angle-weighted
/// normal is radial, and between the vertices the interpolated normal of a point on a facet
/// is the blend of three radii, which is the radius through that point.
fn icosahedron() -> TriangleMesh {
    let phi = (1.0 + 5f32.sqrt()) / 2.0;
    let positions = [
        [-1.0, phi, 0.0],
        [1.0, phi, 0.0],
        [-1.0, -phi, 0.0],
        [1.0, -phi, 0.0],
        [0.0, -1.0, phi],
        [0.0, 1.0, phi],
        [0.0, -1.0, -phi],
        [0.0, 1.0, -phi],
        [phi, 0.0, -1.0],
        [phi, 0.0, 1.0],
        [-phi, 0.0, -1.0],
        [-phi, 0.0, 1.0],
    ]
    .map(|p| Vec3::from(p).normalize());
    let triangles = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    TriangleMesh { positions: positions.to_vec(), triangles }
}

fn render(mesh: &Arc<TriangleMesh>, camera: Camera, size: u32) -> RenderedImage {
    let object = SceneObject {
        name: "sphere".into(),
        transform: Affine3A::IDENTITY,
        material: Material::default(),
        geometry: Geometry::Mesh(mesh.clone()),
    };
    let scene =
        Scene { camera, lights: vec![], background: Background::Solid(Vec3::ZERO), objects: vec![object] };
    let settings = RenderSettings { width: size, height: size, max_depth: 1, ..RenderSettings::default() };
    pointray_cpu::render(&scene, &settings)
}

/// The largest angle in degrees between each hit pixel's normal and the radius through its
/// hit point, and the number of hit pixels. The angle is unsigned, as fidelity measures it:
/// near the silhouette of a coarse polyhedron the radius at a hit can face away from the
/// camera, and the image's normal is turned toward it.
fn worst_against_radius(image: &RenderedImage, camera: &Camera) -> (f32, usize) {
    let size = glam::UVec2::new(image.width, image.height);
    let mut worst = 0.0f32;
    let mut hits = 0;
    for pixel in (0..image.pixel_count()).filter(|&p| image.instance_id[p] != RenderedImage::MISS) {
        let coordinates = glam::UVec2::new(pixel as u32 % image.width, pixel as u32 / image.width);
        let ray = pointray_kernels::camera_ray(camera, size, coordinates, pointray_kernels::sample_jitter(0));
        let radius = ray.at(image.depth[pixel]).normalize();
        worst = worst.max(image.normal[pixel].dot(radius).abs().min(1.0).acos().to_degrees());
        hits += 1;
    }
    (worst, hits)
}

#[test]
fn interpolated_vertex_normals_are_exact_on_the_icosahedron() {
    let mesh = Arc::new(icosahedron());
    let normals = VertexNormals::angle_weighted(&mesh);
    for (vertex, position) in mesh.positions.iter().enumerate() {
        assert!(normals.of_vertex(vertex).distance(*position) < 1e-6, "vertex {vertex}");
    }
    for position in [Vec3::new(0.3, 2.0, 3.0), Vec3::new(-3.0, -0.5, 0.4)] {
        let camera = Camera { position, look_at: Vec3::ZERO, up: Vec3::Y, vertical_fov_degrees: 50.0 };
        let mut image = render(&mesh, camera, 96);
        let (flat, hits) = worst_against_radius(&image, &camera);
        assert!(hits > 2000, "the sphere fills too little: {hits} pixels");
        // The facets are 37° apart: their own normals are far off the sphere's.
        assert!(flat > 20.0, "face normals within {flat}° of the radius");
        normals.smooth_image(&mut image, &mesh, &camera).unwrap();
        let (smooth, _) = worst_against_radius(&image, &camera);
        assert!(smooth < 0.05, "interpolated normals within {smooth}° of the radius, not exact");
    }
}
