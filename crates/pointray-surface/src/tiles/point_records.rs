//! Points as fixed-size little-endian records in the scratch files of out-of-core prep: the
//! Morton code and input index first (the sort key), then the f64 position and whichever
//! attributes the cloud carries.

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;

/// Bytes of the key: the Morton code (u64) and the input index (u32).
const KEY_BYTES: usize = 12;

/// Bytes of a record before its attributes: the key and the f64 position. Each attribute
/// then takes the bytes it takes in a `PointCloud` (`pointray_io::AttributeBytes`).
pub(crate) const KEYED_POSITION_BYTES: u64 = (KEY_BYTES + 24) as u64;

/// Which attributes the records carry, the same for every point of a cloud.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct RecordLayout {
    normals: bool,
    colors: bool,
    intensities: bool,
    classifications: bool,
    rings: bool,
    sensor_origins: bool,
}

/// A record's sort key: along the curve, ties in input order.
pub(crate) type RecordKey = (u64, u32);

impl RecordLayout {
    pub(crate) fn of(cloud: &PointCloud) -> Self {
        Self {
            normals: cloud.normals.is_some(),
            colors: cloud.colors.is_some(),
            intensities: cloud.intensities.is_some(),
            classifications: cloud.classifications.is_some(),
            rings: cloud.rings.is_some(),
            sensor_origins: cloud.sensor_origins.is_some(),
        }
    }

    /// The attributes as bits, in the order of the fields, for a kept sort's index.
    pub(crate) fn flags(&self) -> u8 {
        [self.normals, self.colors, self.intensities, self.classifications, self.rings, self.sensor_origins]
            .iter()
            .enumerate()
            .map(|(bit, &has)| u8::from(has) << bit)
            .sum()
    }

    /// The layout of `flags`; none when a bit past the six attributes is set.
    pub(crate) fn of_flags(flags: u8) -> Option<Self> {
        let has = |bit: u8| flags & (1 << bit) != 0;
        (flags < 1 << 6).then(|| Self {
            normals: has(0),
            colors: has(1),
            intensities: has(2),
            classifications: has(3),
            rings: has(4),
            sensor_origins: has(5),
        })
    }

    /// The bytes a point's attributes take in a `PointCloud`, and in a record.
    pub(crate) fn attribute_bytes(&self) -> u64 {
        pointray_io::AttributeBytes {
            normals: self.normals,
            colors: self.colors,
            intensities: self.intensities,
            classifications: self.classifications,
            rings: self.rings,
            sensor_origins: self.sensor_origins,
        }
        .per_point()
    }

    pub(crate) fn bytes(&self) -> usize {
        (KEYED_POSITION_BYTES + self.attribute_bytes()) as usize
    }

    /// Appends point `i` of `cloud` (whose layout this is) with its key to `out`.
    pub(crate) fn encode(&self, cloud: &PointCloud, i: usize, key: RecordKey, out: &mut Vec<u8>) {
        out.extend(key.0.to_le_bytes());
        out.extend(key.1.to_le_bytes());
        cloud.positions[i].to_array().iter().for_each(|v| out.extend(v.to_le_bytes()));
        if let Some(normals) = &cloud.normals {
            normals[i].to_array().iter().for_each(|v| out.extend(v.to_le_bytes()));
        }
        if let Some(colors) = &cloud.colors {
            out.extend(colors[i]);
        }
        if let Some(intensities) = &cloud.intensities {
            out.extend(intensities[i].to_le_bytes());
        }
        if let Some(classifications) = &cloud.classifications {
            out.push(classifications[i]);
        }
        if let Some(rings) = &cloud.rings {
            out.extend(rings[i].to_le_bytes());
        }
        if let Some(origins) = &cloud.sensor_origins {
            origins[i].to_array().iter().for_each(|v| out.extend(v.to_le_bytes()));
        }
    }

    /// An empty cloud with this layout's attributes, for `decode_into`.
    pub(crate) fn empty_cloud(&self, sensor_position: Option<DVec3>) -> PointCloud {
        PointCloud {
            positions: Vec::new(),
            normals: self.normals.then(Vec::new),
            colors: self.colors.then(Vec::new),
            intensities: self.intensities.then(Vec::new),
            classifications: self.classifications.then(Vec::new),
            rings: self.rings.then(Vec::new),
            sensor_origins: self.sensor_origins.then(Vec::new),
            sensor_position,
        }
    }

    /// Appends the record's point to `cloud` (made by `empty_cloud`) and returns its key.
    pub(crate) fn decode_into(&self, record: &[u8], cloud: &mut PointCloud) -> RecordKey {
        let mut fields = Fields(record);
        let key = (u64::from_le_bytes(fields.take()), u32::from_le_bytes(fields.take()));
        cloud.positions.push(fields.dvec3());
        if let Some(normals) = &mut cloud.normals {
            normals.push(Vec3::from_array([0; 3].map(|_| f32::from_le_bytes(fields.take()))));
        }
        if let Some(colors) = &mut cloud.colors {
            colors.push(fields.take());
        }
        if let Some(intensities) = &mut cloud.intensities {
            intensities.push(f32::from_le_bytes(fields.take()));
        }
        if let Some(classifications) = &mut cloud.classifications {
            classifications.push(fields.take::<1>()[0]);
        }
        if let Some(rings) = &mut cloud.rings {
            rings.push(u16::from_le_bytes(fields.take()));
        }
        if let Some(origins) = &mut cloud.sensor_origins {
            origins.push(fields.dvec3());
        }
        key
    }
}

/// The key of the record at `position` of a file of `record_bytes`-byte records.
pub(crate) fn key_at(file: &std::fs::File, record_bytes: usize, position: u64) -> std::io::Result<RecordKey> {
    use std::os::unix::fs::FileExt;
    let mut record = vec![0u8; record_bytes];
    file.read_exact_at(&mut record, position * record_bytes as u64)?;
    Ok(record_key(&record))
}

/// The key of an encoded record.
pub(crate) fn record_key(record: &[u8]) -> RecordKey {
    let mut fields = Fields(record);
    (u64::from_le_bytes(fields.take()), u32::from_le_bytes(fields.take()))
}

/// The position of an encoded record.
pub(crate) fn record_position(record: &[u8]) -> DVec3 {
    Fields(&record[KEY_BYTES..]).dvec3()
}

/// A record read field by field.
struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let (field, rest) = self.0.split_at(N);
        self.0 = rest;
        field.try_into().expect("split at N")
    }

    fn dvec3(&mut self) -> DVec3 {
        DVec3::from_array([0; 3].map(|_| f64::from_le_bytes(self.take())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_holds_its_point_and_key() {
        let cloud = PointCloud {
            normals: Some(vec![Vec3::new(0.0, 0.6, 0.8)]),
            colors: Some(vec![[1, 2, 3]]),
            intensities: Some(vec![0.25]),
            classifications: Some(vec![6]),
            rings: Some(vec![31]),
            sensor_origins: Some(vec![DVec3::new(1.0, 2.0, 3.0)]),
            ..PointCloud::from_positions(vec![DVec3::new(1e6, -2.5, 0.125)])
        };
        let layout = RecordLayout::of(&cloud);
        let mut bytes = Vec::new();
        layout.encode(&cloud, 0, (0xfeed, 42), &mut bytes);
        assert_eq!(bytes.len(), layout.bytes());
        assert_eq!(record_key(&bytes), (0xfeed, 42));
        assert_eq!(record_position(&bytes), cloud.positions[0]);
        let mut decoded = layout.empty_cloud(None);
        assert_eq!(layout.decode_into(&bytes, &mut decoded), (0xfeed, 42));
        assert_eq!(decoded, cloud);
    }
}
