//! PCD files written with `pcd-rs`'s own writer, for the readers' tests.

use std::path::Path;

use pcd_rs::{DataKind, DynRecord, DynWriter, Schema, ValueKind, WriterInit};

/// Writes `records` as a PCD file of the f32 `fields`, one row.
pub fn write_pcd_f32(
    path: &Path,
    data_kind: DataKind,
    fields: &[&str],
    records: impl ExactSizeIterator<Item = DynRecord>,
) {
    let schema = Schema::from_iter(fields.iter().map(|&name| (name, ValueKind::F32, 1)));
    let init = WriterInit {
        width: records.len() as u64,
        height: 1,
        viewpoint: Default::default(),
        data_kind,
        schema: Some(schema),
        version: None,
    };
    let mut writer: DynWriter<_> = init.create(path).unwrap();
    for record in records {
        writer.push(&record).unwrap();
    }
    writer.finish().unwrap();
}
