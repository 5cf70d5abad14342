//! A COPC file's octree, for prep that walks it in place of a survey and a sort: the cube
//! the COPC info VLR gives, each node's box, points and place in the file's point order,
//! and the points of any set of nodes decoded in parallel.
//!
//! A chunked read learns the whole file's attribute ranges (colour depth, intensity range,
//! whether classes are filled) in a first pass before it scales any attribute. Walking the
//! octree makes one pass, so the ranges are taken from its top levels, which COPC fills with
//! points spread over the whole cloud, and every decoded point widens the ranges seen:
//! `scales_as_predicted` says, once every node is decoded, whether the whole file scales as
//! the top levels did, and so whether the points came out as a chunked read gives them.

use std::path::Path;
use std::sync::Mutex;

use glam::DVec3;
use las::copc::Entry;
use rayon::prelude::*;

use super::copc::CopcFile;
use super::las_chunks::LasRanges;
use crate::{IoError, PointCloud};

/// A node of the octree that holds points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OctreeNode {
    /// The node's box (min, max) in the file's coordinates, from its key and the cube.
    pub bounds: (DVec3, DVec3),
    pub points: u64,
    /// Its first point's index in the file's point order, as `PointStream` numbers points.
    pub first_point: u64,
    /// Its level in the octree (0 for the root).
    pub level: i32,
}

pub struct CopcOctree {
    file: CopcFile,
    cube: (DVec3, DVec3),
    /// The nodes, in the file's order: node `i` is the file's chunk `i`.
    nodes: Vec<OctreeNode>,
    sample: Vec<DVec3>,
    predicted: LasRanges,
    seen: Mutex<LasRanges>,
}

/// Bytes of the COPC info VLR's centre (three f64) before its half size (f64).
const HALF_SIZE_AT: usize = 24;

impl CopcOctree {
    /// The octree of the COPC file at `path`, its hierarchy checked, with the points of its
    /// top levels read: whole levels from the root down until they hold `sample_points`
    /// points or the octree ends.
    pub fn open(path: &Path, sample_points: u64) -> Result<Self, IoError> {
        let file = CopcFile::open(path)?;
        let cube = cube_of(file.header(), path)?;
        let mut first_point = 0;
        let nodes = file
            .chunks()
            .iter()
            .map(|chunk| {
                let node = OctreeNode {
                    bounds: node_box(cube, chunk),
                    points: chunk.point_count as u64,
                    first_point,
                    level: chunk.key.l,
                };
                first_point += node.points;
                node
            })
            .collect();
        let mut octree = Self {
            file,
            cube,
            nodes,
            sample: Vec::new(),
            predicted: LasRanges::default(),
            seen: Mutex::new(LasRanges::default()),
        };
        octree.read_top_levels(sample_points)?;
        Ok(octree)
    }

    pub fn path(&self) -> &Path {
        self.file.path()
    }

    /// The octree's cube (min, max) in the file's coordinates.
    pub fn cube(&self) -> (DVec3, DVec3) {
        self.cube
    }

    /// The nodes that hold points, in the file's order.
    pub fn nodes(&self) -> &[OctreeNode] {
        &self.nodes
    }

    pub fn points(&self) -> u64 {
        self.nodes.iter().map(|node| node.points).sum()
    }

    /// The positions of the top levels' points.
    pub fn sample(&self) -> &[DVec3] {
        &self.sample
    }

    /// The points of `nodes` (indices into `nodes()`), each node's as a cloud in the file's
    /// order, decoded in parallel, their attributes scaled as the top levels predict.
    pub fn decode(&self, nodes: &[usize]) -> Result<Vec<PointCloud>, IoError> {
        let chunks: Vec<Entry> = nodes.iter().map(|&node| self.file.chunks()[node]).collect();
        let decoded = self.file.decode_each(&chunks)?;
        let (clouds, ranges): (Vec<PointCloud>, Vec<LasRanges>) = decoded
            .par_iter()
            .map(|data| {
                let mut ranges = LasRanges::default();
                ranges.include(data);
                (self.predicted.scaled(data, positions_of(data)), ranges)
            })
            .unzip();
        let mut seen = self.seen.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        ranges.iter().for_each(|ranges| seen.join(ranges));
        Ok(clouds)
    }

    /// Whether the attributes of every point decoded so far scale as the top levels
    /// predicted: once every node is decoded, whether they came out as a chunked read of
    /// the file gives them.
    pub fn scales_as_predicted(&self) -> bool {
        self.seen.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).scales_as(&self.predicted)
    }

    fn read_top_levels(&mut self, sample_points: u64) -> Result<(), IoError> {
        let mut levels: Vec<i32> = self.nodes.iter().map(|node| node.level).collect();
        levels.sort_unstable();
        levels.dedup();
        let mut taken = 0;
        let deepest = levels
            .iter()
            .copied()
            .find(|&level| {
                taken +=
                    self.nodes.iter().filter(|node| node.level == level).map(|node| node.points).sum::<u64>();
                taken >= sample_points
            })
            .or(levels.last().copied());
        let top: Vec<Entry> = (self.file.chunks().iter().zip(&self.nodes))
            .filter(|(_, node)| deepest.is_some_and(|deepest| node.level <= deepest))
            .map(|(chunk, _)| *chunk)
            .collect();
        for data in self.file.decode_each(&top)? {
            self.predicted.include(&data);
            self.sample.extend(positions_of(&data));
        }
        Ok(())
    }
}

fn positions_of(data: &las::PointData) -> Vec<DVec3> {
    data.x().zip(data.y()).zip(data.z()).map(|((x, y), z)| DVec3::new(x, y, z)).collect()
}

/// The cube (min, max) the COPC info VLR gives by its centre and half size.
fn cube_of(header: &las::Header, origin: &Path) -> Result<(DVec3, DVec3), IoError> {
    let info = header.vlrs().iter().find(|vlr| vlr.is_copc_info());
    let f64_at = |data: &[u8], at: usize| Some(f64::from_le_bytes(data.get(at..at + 8)?.try_into().ok()?));
    let cube = info.and_then(|info| {
        let centre = DVec3::new(f64_at(&info.data, 0)?, f64_at(&info.data, 8)?, f64_at(&info.data, 16)?);
        let half = f64_at(&info.data, HALF_SIZE_AT)?;
        Some((centre - half, centre + half))
    });
    cube.ok_or_else(|| IoError::malformed(origin, "COPC info VLR is missing or too short"))
}

/// The box of `chunk`'s node: the cube halved `level` times, at the key's place.
fn node_box((low, high): (DVec3, DVec3), chunk: &Entry) -> (DVec3, DVec3) {
    let key = &chunk.key;
    let side = (high - low) / 2f64.powi(key.l);
    let corner = low + side * DVec3::new(f64::from(key.x), f64::from(key.y), f64::from(key.z));
    (corner, corner + side)
}
