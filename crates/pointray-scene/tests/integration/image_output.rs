//! Images reach disk: the colour image by extension and each AOV next to it, all readable by
//! the `image` crate with the values that went in.

use std::path::Path;

use glam::Vec3;
use pointray_scene::image_output::aov_path;
use pointray_scene::{AovSelection, RenderedImage, SceneError, write_image};

/// 3x2 pixels: the top row hits objects 0, 1 and 2, the bottom row misses but for one pixel.
fn test_image() -> RenderedImage {
    let hit = [true, true, true, false, true, false];
    let pick = |i: usize, value: u32| if hit[i] { value } else { RenderedImage::MISS };
    RenderedImage {
        width: 3,
        height: 2,
        color: vec![
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::new(0.0, 0.0, 0.2159),
            Vec3::splat(2.0),
            Vec3::splat(0.25),
            Vec3::ZERO,
        ],
        depth: (0..6).map(|i| if hit[i] { 1.5 + i as f32 } else { f32::INFINITY }).collect(),
        normal: (0..6).map(|i| if hit[i] { Vec3::new(0.0, -0.6, 0.8) } else { Vec3::ZERO }).collect(),
        instance_id: (0..6).map(|i| pick(i, i as u32 % 3)).collect(),
        primitive_id: (0..6).map(|i| pick(i, 1000 * i as u32 + 7)).collect(),
        albedo: None,
    }
}

fn read_rgb32f(path: &Path) -> Vec<[f32; 3]> {
    let image = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).into_rgb32f();
    image.pixels().map(|p| p.0).collect()
}

#[test]
fn png_colour_and_every_aov_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.png");
    let image = test_image();
    let written = write_image(&image, &output, &AovSelection::ALL).unwrap();
    let names: Vec<String> =
        written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(
        names,
        [
            "out.png",
            "out.depth.exr",
            "out.normal.exr",
            "out.instance.exr",
            "out.primitive.exr",
            "out.mask.png"
        ]
    );

    let color = image::open(&output).unwrap().into_rgb8();
    assert_eq!(color.dimensions(), (3, 2));
    let pixels: Vec<[u8; 3]> = color.pixels().map(|p| p.0).collect();
    assert_eq!(pixels[0], [255, 0, 0]);
    assert_eq!(pixels[1], [0, 188, 0], "sRGB encoded, not linear");
    assert_eq!(pixels[2], [0, 0, 128]);
    assert_eq!(pixels[3], [255; 3], "clamped");

    let depth = read_rgb32f(&aov_path(&output, "depth.exr"));
    assert_eq!(depth[0][0], 1.5);
    assert_eq!(depth[4][0], 5.5);
    assert!(depth[3][0].is_infinite(), "a miss has infinite depth");

    let normal = read_rgb32f(&aov_path(&output, "normal.exr"));
    assert_eq!(normal[1], [0.0, -0.6, 0.8]);
    assert_eq!(normal[5], [0.0; 3]);

    let instance = read_rgb32f(&aov_path(&output, "instance.exr"));
    let instance: Vec<f32> = instance.iter().map(|p| p[0]).collect();
    assert_eq!(instance, [0.0, 1.0, 2.0, -1.0, 1.0, -1.0]);
    let primitive = read_rgb32f(&aov_path(&output, "primitive.exr"));
    assert_eq!(primitive[4][0], 4007.0);
    assert_eq!(primitive[5][0], -1.0);

    let mask = image::open(aov_path(&output, "mask.png")).unwrap().into_luma8();
    let mask: Vec<u8> = mask.pixels().map(|p| p.0[0]).collect();
    assert_eq!(mask, [255, 255, 255, 0, 255, 0]);
}

#[test]
fn exr_colour_is_linear_and_only_the_selected_aovs_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("render.EXR");
    let image = test_image();
    let selection = AovSelection { mask: true, ..AovSelection::default() };
    let written = write_image(&image, &output, &selection).unwrap();
    assert_eq!(written, [output.clone(), dir.path().join("render.mask.png")]);
    let color = read_rgb32f(&output);
    assert_eq!(color[2], [0.0, 0.0, 0.2159]);
    assert_eq!(color[3], [2.0; 3], "not clamped");
    let mut files: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    files.sort();
    assert_eq!(files, ["render.EXR", "render.mask.png"]);
}

#[test]
fn an_unknown_image_type_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.jpg");
    let error = write_image(&test_image(), &output, &AovSelection::ALL).unwrap_err();
    assert!(matches!(error, SceneError::ImageFormat { .. }), "{error:?}");
    assert!(error.to_string().contains("out.jpg"), "{error}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn ids_a_float_cannot_hold_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut image = test_image();
    image.primitive_id[0] = (1 << 24) + 1;
    let output = dir.path().join("out.png");
    let error = write_image(&image, &output, &AovSelection::ALL).unwrap_err();
    assert!(error.to_string().contains("primitive"), "{error}");
    // Without the primitive AOV the image is fine.
    let selection = AovSelection { primitive: false, ..AovSelection::ALL };
    write_image(&image, &output, &selection).unwrap();
}

#[test]
fn an_image_whose_buffers_do_not_match_its_size_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let mut image = test_image();
    image.color.pop();
    let error = write_image(&image, &dir.path().join("out.png"), &AovSelection::default()).unwrap_err();
    assert!(error.to_string().contains("out.png"), "{error}");
}

#[test]
fn the_albedo_is_written_only_where_the_image_has_one() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.png");
    let selection = AovSelection { albedo: true, ..AovSelection::default() };
    assert_eq!(write_image(&test_image(), &output, &selection).unwrap().len(), 1, "no albedo to write");
    let albedo = vec![Vec3::new(0.25, 0.5, 0.75); 6];
    let image = RenderedImage { albedo: Some(albedo), ..test_image() };
    let written = write_image(&image, &output, &selection).unwrap();
    assert_eq!(written, [output.clone(), dir.path().join("out.albedo.exr")]);
    assert_eq!(read_rgb32f(&written[1])[4], [0.25, 0.5, 0.75]);
}
