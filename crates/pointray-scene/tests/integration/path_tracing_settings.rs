//! The path integrator's settings in a scene file: the integrator and its seed, the
//! materials' BSDFs and the area lights, and the errors that name the file and the key.

use glam::Vec3;
use pointray_kernels::bsdf::{BSDF_DIELECTRIC, BSDF_DIFFUSE, BSDF_PLASTIC};
use pointray_scene::load::load_scene_file;
use pointray_scene::{Integrator, Light, LoadOptions, SurfaceKind};

use crate::scene_file_parsing::{error_message, parse};

const SPHERE: &str = "[[objects]]\ntype = \"sphere_points\"\nradius = 1.0\ncount = 200\n";

#[test]
fn the_integrator_and_seed_come_from_the_render_table() {
    let file = parse("[render]\nintegrator = \"path\"\nseed = 9\nspp = 64\nmax_depth = 8\n").unwrap();
    let settings = file.render_settings().unwrap();
    assert_eq!((settings.integrator, settings.seed, settings.max_depth), (Integrator::Path, 9, 8));
    let default = parse("").unwrap().render_settings().unwrap();
    assert_eq!((default.integrator, default.seed), (Integrator::Whitted, 0));
    let message = error_message("[render]\nintegrator = \"photon\"\n");
    assert!(message.contains("test/scene.toml") && message.contains("photon"), "{message}");
    assert_eq!("path".parse::<Integrator>(), Ok(Integrator::Path));
    assert!("bdpt".parse::<Integrator>().unwrap_err().contains("whitted"));
}

#[test]
fn materials_give_their_bsdf_and_phong_materials_a_documented_default() {
    let text = format!(
        "{SPHERE}[objects.material]\nbsdf = \"dielectric\"\nroughness = 0.0\nior = 1.33\ndiffuse = [0.9, 1.0, 1.0]\n\
         emission = [2.0, 2.0, 2.0]\n{SPHERE}{SPHERE}[objects.material]\nreflectivity = 0.4\n"
    );
    let file = parse(&text).unwrap();
    let scene = load_scene_file(&file, &LoadOptions::default()).unwrap().scene;
    let glass = &scene.objects[0].material;
    assert_eq!((glass.surface, glass.ior, glass.emission), (SurfaceKind::Dielectric, 1.33, Vec3::splat(2.0)));
    let bsdf = glass.bsdf(glass.diffuse);
    assert_eq!((bsdf.kind, bsdf.roughness, bsdf.color), (BSDF_DIELECTRIC, 0.0, Vec3::new(0.9, 1.0, 1.0)));
    let phong = &scene.objects[1].material;
    assert_eq!(phong.bsdf(phong.diffuse).kind, BSDF_DIFFUSE);
    let reflective = &scene.objects[2].material;
    assert_eq!(reflective.bsdf(reflective.diffuse).kind, BSDF_PLASTIC);
}

#[test]
fn bad_material_values_name_their_key() {
    // An unknown BSDF is named by its value, with the list of those known.
    for (key, line) in [
        ("roughness", "roughness = 1.5"),
        ("ior", "ior = 0.0"),
        ("emission", "emission = [1.0, -1.0, 0.0]"),
        ("velvet", "bsdf = \"velvet\""),
    ] {
        let message = error_message(&format!("{SPHERE}[objects.material]\n{line}\n"));
        assert!(message.contains("test/scene.toml") && message.contains(key), "{key}: {message}");
    }
}

#[test]
fn sphere_and_quad_lights_parse_and_bad_ones_are_refused() {
    let text = "[[lights]]\ntype = \"sphere\"\ncenter = [0.0, 2.0, 0.0]\nradius = 0.25\nintensity = 4.0\n\
                [[lights]]\ntype = \"quad\"\ncorner = [-0.5, 2.0, -0.5]\nedge_u = [1.0, 0.0, 0.0]\n\
                edge_v = [0.0, 0.0, 1.0]\ncolor = [1.0, 0.9, 0.8]\n";
    let file = parse(&format!("{text}{SPHERE}")).unwrap();
    let scene = load_scene_file(&file, &LoadOptions::default()).unwrap().scene;
    assert!(
        matches!(scene.lights[0], Light::Sphere { radius, intensity, .. } if radius == 0.25 && intensity == 4.0)
    );
    let Light::Quad { edge_u, edge_v, .. } = scene.lights[1] else { panic!("a quad light") };
    assert_eq!(edge_u.cross(edge_v), Vec3::NEG_Y, "this quad faces down");
    assert_eq!(scene.lights[1].source().radiance, Vec3::new(1.0, 0.9, 0.8));
    let parallel = "[[lights]]\ntype = \"quad\"\ncorner = [0.0, 0.0, 0.0]\nedge_u = [1.0, 0.0, 0.0]\nedge_v = [2.0, 0.0, 0.0]\n";
    let message = error_message(parallel);
    assert!(message.contains("lights[0].edge_v") && message.contains("parallel"), "{message}");
    let message = error_message("[[lights]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = -1.0\n");
    assert!(message.contains("lights[0].radius"), "{message}");
}
