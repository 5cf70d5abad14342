//! Writing PLY files through ply-rs-bw, atomically.

use std::io::Write;
use std::path::Path;

use glam::DVec3;

use ply_rs_bw::ply::{
    Addable, ElementDef, Encoding, Header, PropertyAccess, PropertyDef, PropertyType, ScalarType,
};
use ply_rs_bw::writer::Writer;

use super::face::{FaceRecord, WRITTEN_INDEX_NAME};
use super::vertex::{VertexRecord, records_of};
use crate::{IoError, PointCloud, TriangleMesh, write_atomically};

/// Beyond this magnitude f32 keeps less than a centimetre of a metre-scale coordinate, so
/// positions are written as double (geo-referenced scans).
const DOUBLE_PRECISION_THRESHOLD: f64 = 1e5;

/// Points whose positions are encoded at a time.
const POSITION_BATCH: usize = 1 << 16;

pub(super) fn write_cloud(path: &Path, cloud: &PointCloud, encoding: Encoding) -> Result<(), IoError> {
    check_cloud(cloud).map_err(|problem| IoError::unwritable(path, problem))?;
    let needs_double = cloud.positions.iter().any(|p| p.abs().max_element() > DOUBLE_PRECISION_THRESHOLD);
    let position_type = if needs_double { ScalarType::Double } else { ScalarType::Float };
    let mut vertex = element("vertex", cloud.len(), &["x", "y", "z"], position_type);
    if cloud.normals.is_some() {
        add_scalars(&mut vertex, &["nx", "ny", "nz"], &ScalarType::Float);
    }
    if cloud.colors.is_some() {
        add_scalars(&mut vertex, &["red", "green", "blue"], &ScalarType::UChar);
    }
    if cloud.intensities.is_some() {
        add_scalars(&mut vertex, &["intensity"], &ScalarType::Float);
    }
    if cloud.rings.is_some() {
        add_scalars(&mut vertex, &["ring"], &ScalarType::UShort);
    }
    if cloud.classifications.is_some() {
        add_scalars(&mut vertex, &["classification"], &ScalarType::UChar);
    }
    if cloud.sensor_origins.is_some() {
        add_scalars(&mut vertex, &["sensor_x", "sensor_y", "sensor_z"], &ScalarType::Double);
    }
    let header = header(encoding, [vertex]);
    // Positions alone are written straight from the cloud: through the per-point records a
    // billion-point sample took 140 bytes a point and more than a 128 GiB machine holds.
    if cloud.attribute_bytes_per_point() == 0 && encoding == Encoding::BinaryLittleEndian {
        return write_atomically(path, |out| {
            Writer::<VertexRecord>::new().write_header(out, &header)?;
            write_positions(out, &cloud.positions, needs_double)
        });
    }
    let records = records_of(cloud);
    write_atomically(path, |out| {
        Writer::<VertexRecord>::new().write_header(out, &header)?;
        write_payload(out, &records, &header.elements["vertex"], &header)
    })
}

pub(super) fn write_mesh(path: &Path, mesh: &TriangleMesh, encoding: Encoding) -> Result<(), IoError> {
    check_mesh(mesh).map_err(|problem| IoError::unwritable(path, problem))?;
    let vertex = element("vertex", mesh.positions.len(), &["x", "y", "z"], ScalarType::Float);
    let mut face = ElementDef::new("face".into());
    face.count = mesh.triangles.len();
    let index_list = PropertyType::List(ScalarType::UChar, ScalarType::UInt);
    face.properties.add(PropertyDef::new(WRITTEN_INDEX_NAME.into(), index_list));
    let header = header(encoding, [vertex, face]);
    let vertices: Vec<VertexRecord> = mesh
        .positions
        .iter()
        .map(|p| VertexRecord { position: p.as_dvec3().to_array(), ..VertexRecord::default() })
        .collect();
    let faces: Vec<FaceRecord> = mesh.triangles.iter().map(|t| FaceRecord::triangle(*t)).collect();
    write_atomically(path, |out| {
        Writer::<VertexRecord>::new().write_header(out, &header)?;
        write_payload(out, &vertices, &header.elements["vertex"], &header)?;
        write_payload(out, &faces, &header.elements["face"], &header)
    })
}

/// The positions as the binary little-endian body of a vertex element of `x y z` (float, or
/// double where `double`), a batch of points at a time.
fn write_positions(out: &mut impl Write, positions: &[DVec3], double: bool) -> std::io::Result<()> {
    let mut body = Vec::with_capacity(POSITION_BATCH * 24);
    for batch in positions.chunks(POSITION_BATCH) {
        body.clear();
        for p in batch {
            if double {
                p.to_array().iter().for_each(|v| body.extend(v.to_le_bytes()));
            } else {
                p.as_vec3().to_array().iter().for_each(|v| body.extend(v.to_le_bytes()));
            }
        }
        out.write_all(&body)?;
    }
    Ok(())
}

fn write_payload<E: PropertyAccess>(
    out: &mut impl Write,
    records: &Vec<E>,
    element: &ElementDef,
    header: &Header,
) -> std::io::Result<()> {
    Writer::<E>::new().write_payload_of_element(out, records, element, header).map(|_| ())
}

fn element(name: &str, count: usize, properties: &[&str], scalar: ScalarType) -> ElementDef {
    let mut element = ElementDef::new(name.into());
    element.count = count;
    add_scalars(&mut element, properties, &scalar);
    element
}

fn add_scalars(element: &mut ElementDef, names: &[&str], scalar: &ScalarType) {
    for name in names {
        element.properties.add(PropertyDef::new((*name).into(), PropertyType::Scalar(scalar.clone())));
    }
}

fn header<const N: usize>(encoding: Encoding, elements: [ElementDef; N]) -> Header {
    let mut header = Header::new();
    header.encoding = encoding;
    header.comments.push("written by pointray".into());
    for element in elements {
        header.elements.add(element);
    }
    header
}

/// A file we could not read back is not worth writing.
fn check_cloud(cloud: &PointCloud) -> Result<(), String> {
    let count = cloud.len();
    let lengths = [
        ("normals", cloud.normals.as_ref().map(Vec::len)),
        ("colours", cloud.colors.as_ref().map(Vec::len)),
        ("intensities", cloud.intensities.as_ref().map(Vec::len)),
        ("rings", cloud.rings.as_ref().map(Vec::len)),
        ("classifications", cloud.classifications.as_ref().map(Vec::len)),
        ("sensor origins", cloud.sensor_origins.as_ref().map(Vec::len)),
    ];
    for (what, length) in lengths {
        if let Some(length) = length.filter(|&length| length != count) {
            return Err(format!("the cloud has {count} points but {length} {what}"));
        }
    }
    if let Some(index) = cloud.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("point {index} has a non-finite coordinate {}", cloud.positions[index]));
    }
    let origins = cloud.sensor_origins.as_deref().unwrap_or_default();
    match origins.iter().position(|p| !p.is_finite()) {
        Some(index) => Err(format!("point {index} has a non-finite sensor position {}", origins[index])),
        None => Ok(()),
    }
}

fn check_mesh(mesh: &TriangleMesh) -> Result<(), String> {
    if let Some(index) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("vertex {index} has a non-finite coordinate {}", mesh.positions[index]));
    }
    let count = mesh.positions.len();
    match mesh.triangles.iter().position(|t| t.iter().any(|&i| i as usize >= count)) {
        Some(triangle) => Err(format!(
            "triangle {triangle} refers to a vertex beyond the {count} vertices: {:?}",
            mesh.triangles[triangle]
        )),
        None => Ok(()),
    }
}
