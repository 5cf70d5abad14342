//! The PLY `face` element: one polygon of vertex indices per record.

use ply_rs_bw::ply::{ElementDef, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType};

use crate::TriangleMesh;

/// Files name the index list either way.
const INDEX_NAMES: [&str; 2] = ["vertex_indices", "vertex_index"];
/// The name this crate writes.
pub(super) const WRITTEN_INDEX_NAME: &str = "vertex_indices";

/// Checks that the face element holds an integer index list and returns the name it uses.
pub(super) fn index_property_name(element: &ElementDef) -> Result<&'static str, String> {
    let (name, definition) = INDEX_NAMES
        .iter()
        .find_map(|name| element.properties.get(*name).map(|p| (*name, p)))
        .ok_or("the face element has no 'vertex_indices' list")?;
    match definition.data_type {
        PropertyType::List(_, ScalarType::Float | ScalarType::Double) | PropertyType::Scalar(_) => {
            Err(format!("face property '{name}' must be a list of integers"))
        }
        PropertyType::List(..) => Ok(name),
    }
}

/// One polygon. A negative index is kept aside so that it can be reported, not wrapped.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct FaceRecord {
    indices: Vec<u32>,
    negative_index: Option<i64>,
}

impl FaceRecord {
    /// A record for writing one triangle.
    pub fn triangle(triangle: [u32; 3]) -> Self {
        Self { indices: triangle.to_vec(), negative_index: None }
    }

    fn set_signed(&mut self, values: impl Iterator<Item = i64>) {
        self.indices.clear();
        for value in values {
            match u32::try_from(value) {
                Ok(index) => self.indices.push(index),
                Err(_) => self.negative_index = Some(value),
            }
        }
    }
}

impl PropertyAccess for FaceRecord {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if !INDEX_NAMES.contains(&name) {
            return PropertyAccessResult::Ignored;
        }
        match property {
            Property::ListChar(v) => self.set_signed(v.into_iter().map(i64::from)),
            Property::ListShort(v) => self.set_signed(v.into_iter().map(i64::from)),
            Property::ListInt(v) => self.set_signed(v.into_iter().map(i64::from)),
            Property::ListUChar(v) => self.indices = v.into_iter().map(u32::from).collect(),
            Property::ListUShort(v) => self.indices = v.into_iter().map(u32::from).collect(),
            Property::ListUInt(v) => self.indices = v,
            _ => return PropertyAccessResult::UnsupportedType,
        }
        PropertyAccessResult::Set
    }

    fn get_list_uint(&self, name: &str) -> Option<&[u32]> {
        (name == WRITTEN_INDEX_NAME).then_some(self.indices.as_slice())
    }
}

/// Adds every face to `mesh` (fan-triangulated), checking indices against its vertex count;
/// an error names the face.
pub(super) fn append_faces(records: &[FaceRecord], mesh: &mut TriangleMesh) -> Result<(), String> {
    let vertex_count = mesh.positions.len();
    for (face, record) in records.iter().enumerate() {
        if let Some(index) = record.negative_index {
            return Err(format!("face {face} refers to vertex {index}, a negative index"));
        }
        if record.indices.len() < 3 {
            return Err(format!(
                "face {face} has {} vertices; a face needs at least 3",
                record.indices.len()
            ));
        }
        if let Some(index) = record.indices.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(format!(
                "face {face} refers to vertex {index}, but there are only {vertex_count} vertices"
            ));
        }
        mesh.push_polygon(&record.indices);
    }
    Ok(())
}
