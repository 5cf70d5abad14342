//! Wavefront OBJ, as a triangle mesh: `v` and `f` lines only (texture coordinates, normals,
//! groups and materials are skipped). Faces accept `a`, `a/b`, `a//c` and `a/b/c` corners and
//! negative (relative) indices; polygons are fan-triangulated.

use std::path::Path;

use glam::DVec3;

use crate::{IoError, PointCloud, TriangleMesh};

/// Whether a file starting with `start` looks like OBJ: its first line that is neither blank
/// nor a comment starts with an OBJ statement.
pub fn has_signature(start: &[u8]) -> bool {
    const STATEMENTS: [&str; 9] = ["v", "vt", "vn", "f", "o", "g", "s", "mtllib", "usemtl"];
    let text = String::from_utf8_lossy(start);
    let first = text.lines().map(str::trim).find(|line| !line.is_empty() && !line.starts_with('#'));
    first.and_then(|line| line.split_whitespace().next()).is_some_and(|word| STATEMENTS.contains(&word))
}

/// Reads the vertices and faces of an OBJ file.
pub fn read_triangle_mesh(path: &Path) -> Result<TriangleMesh, IoError> {
    let text = read_text(path)?;
    let parsed = parse(&text).map_err(|e| IoError::malformed(path, e))?;
    Ok(TriangleMesh {
        positions: parsed.positions.iter().map(|p| p.as_vec3()).collect(),
        triangles: parsed.triangles,
    })
}

/// Reads the vertices of an OBJ file as a point cloud (faces are checked, then dropped).
pub fn read_point_cloud(path: &Path) -> Result<PointCloud, IoError> {
    let text = read_text(path)?;
    let parsed = parse(&text).map_err(|e| IoError::malformed(path, e))?;
    Ok(PointCloud::from_positions(parsed.positions))
}

fn read_text(path: &Path) -> Result<String, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::os(path, e))?;
    if bytes.is_empty() {
        return Err(IoError::malformed(path, "empty file"));
    }
    String::from_utf8(bytes).map_err(|e| IoError::malformed(path, format!("not a text file: {e}")))
}

/// Positions stay f64 until the caller decides, as for the other point formats.
struct ParsedObj {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

/// Parses the text; errors name the 1-based line.
fn parse(text: &str) -> Result<ParsedObj, String> {
    let mut mesh = TriangleMesh::default();
    let mut positions = Vec::new();
    let mut polygon = Vec::new();
    for (line_index, line) in text.lines().enumerate() {
        let at_line = |problem: String| format!("line {}: {problem}", line_index + 1);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => positions.push(vertex(words).map_err(at_line)?),
            Some("f") => {
                polygon.clear();
                for corner in words {
                    polygon.push(corner_index(corner, positions.len()).map_err(at_line)?);
                }
                if polygon.len() < 3 {
                    return Err(at_line(format!(
                        "a face needs at least 3 vertices, this one has {}",
                        polygon.len()
                    )));
                }
                mesh.push_polygon(&polygon);
            }
            _ => {}
        }
    }
    if positions.is_empty() {
        return Err("no vertices ('v' lines)".into());
    }
    Ok(ParsedObj { positions, triangles: mesh.triangles })
}

/// `v x y z [w]`; a trailing colour (`v x y z r g b`, a common extension) is ignored.
fn vertex<'a>(mut words: impl Iterator<Item = &'a str>) -> Result<DVec3, String> {
    let mut coordinate = |axis| -> Result<f64, String> {
        let word = words.next().ok_or_else(|| format!("vertex without a {axis} coordinate"))?;
        // The word itself is not quoted: a file named by mistake must not have its contents printed.
        let value: f64 = word.parse().map_err(|_| format!("the {axis} coordinate is not a number"))?;
        if value.is_finite() { Ok(value) } else { Err(format!("non-finite {axis} coordinate '{word}'")) }
    };
    Ok(DVec3::new(coordinate("x")?, coordinate("y")?, coordinate("z")?))
}

/// The 0-based vertex index of a face corner `v`, `v/t`, `v//n` or `v/t/n`; negative `v`
/// counts back from the latest vertex (-1 is the last one defined so far).
fn corner_index(corner: &str, defined: usize) -> Result<u32, String> {
    let word = corner.split('/').next().unwrap_or_default();
    let index: i64 = word.parse().map_err(|_| "a face corner is not a vertex index".to_string())?;
    let resolved = match index {
        0 => return Err("vertex index 0 (OBJ counts from 1)".into()),
        positive if positive > 0 => positive - 1,
        negative => defined as i64 + negative,
    };
    if resolved < 0 || resolved >= defined as i64 {
        return Err(format!("face refers to vertex {index}, but only {defined} vertices are defined so far"));
    }
    u32::try_from(resolved).map_err(|_| format!("vertex index {index} is too large"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_forms_and_relative_indices_resolve() {
        assert_eq!(corner_index("3", 5), Ok(2));
        assert_eq!(corner_index("3/1", 5), Ok(2));
        assert_eq!(corner_index("3//7", 5), Ok(2));
        assert_eq!(corner_index("3/1/7", 5), Ok(2));
        assert_eq!(corner_index("-1", 5), Ok(4));
        assert_eq!(corner_index("-5/2", 5), Ok(0));
        assert!(corner_index("-6", 5).is_err());
        assert!(corner_index("6", 5).is_err());
        assert!(corner_index("0", 5).is_err());
        assert!(corner_index("/2", 5).is_err());
    }

    #[test]
    fn obj_signature_skips_comments() {
        assert!(has_signature(b"# Blender\n\nmtllib cube.mtl\no Cube\n"));
        assert!(has_signature(b"v 0 0 0\n"));
        assert!(!has_signature(b"0.1 0.2 0.3\n"));
        assert!(!has_signature(b"ply\n"));
    }
}
