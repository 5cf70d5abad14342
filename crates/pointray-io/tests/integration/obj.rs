//! The OBJ reader: corner forms, relative indices, polygons, and its errors.

use crate::common;

use common::fixture;
use glam::Vec3;
use pointray_io::formats::{self, obj};

const QUAD_AND_TRIANGLE: &str = "# a quad and a triangle\nmtllib x.mtl\no thing\n\
    v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvn 0 0 1\nusemtl red\ns off\n\
    f 1/1/1 2/1/1 3/1/1 4/1/1\nv 0.5 0.5 1 0.2 0.4 0.6\nf -1 -4//1 -3/1\n";

#[test]
fn vertices_and_faces_of_every_form_are_read() {
    let (_dir, path) = fixture("thing.obj", QUAD_AND_TRIANGLE.as_bytes());
    let mesh = obj::read_triangle_mesh(&path).unwrap();
    assert_eq!(mesh.positions.len(), 5);
    assert_eq!(mesh.positions[4], Vec3::new(0.5, 0.5, 1.0));
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [4, 1, 2]]);
}

#[test]
fn the_generic_readers_dispatch_obj_by_content_and_extension() {
    let (_dir, path) = fixture("no_extension", QUAD_AND_TRIANGLE.as_bytes());
    assert_eq!(formats::read_triangle_mesh(&path).unwrap().triangles.len(), 3);
    assert_eq!(formats::read_point_cloud(&path).unwrap().len(), 5);
    // No recognisable first statement, but the extension says OBJ.
    let (_dir, path) = fixture("odd.obj", b"cstype bezier\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(formats::read_triangle_mesh(&path).unwrap().triangles, vec![[0, 1, 2]]);
}

#[test]
fn bad_obj_files_name_the_file_and_line() {
    let cases: [(&str, &str, &str); 7] = [
        ("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4"),
        ("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "index 0"),
        ("relative.obj", "v 0 0 0\nf -1 -2 -3\n", "line 2"),
        ("nan.obj", "v 0 0 0\nv nan 0 0\n", "line 2: non-finite x"),
        ("short.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "at least 3"),
        ("missing.obj", "v 0 0\n", "without a z"),
        ("novertices.obj", "# nothing\no empty\n", "no vertices"),
    ];
    for (name, text, expected) in cases {
        let (_dir, path) = fixture(name, text.as_bytes());
        let error = obj::read_triangle_mesh(&path).unwrap_err().to_string();
        assert!(error.contains(name) && error.contains(expected), "{name}: {error}");
    }
    let (_dir, path) = fixture("empty.obj", b"");
    assert!(obj::read_triangle_mesh(&path).unwrap_err().to_string().contains("empty file"));
    let (_dir, path) = fixture("binary.obj", &[b'v', b' ', 0xff, 0xfe, b'\n']);
    assert!(obj::read_triangle_mesh(&path).unwrap_err().to_string().contains("not a text file"));
}
