//! Sorting a COPC cloud along the Morton curve without a sorting pass. The curve is laid
//! over the octree's own cube, so each node's points lie between its box's corners along
//! the curve. The nodes are read once, in the order their boxes begin along the curve; after
//! each batch of nodes, the points read that no node still unread can precede are sorted in
//! memory and written on. A point waits only while a node that begins before it is unread:
//! the top levels' points, and those of nodes on the faces where the curve jumps.
//!
//! The sort is declined, and the cloud sorted out of core instead, when the waiting points
//! could outgrow the budget, when a point lies outside its node's box, or when the
//! attributes do not scale as the top levels predicted (`CopcOctree`).

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::ops::Range;
use std::path::Path;

use glam::DVec3;
use pointray_io::PointCloud;
use pointray_io::formats::copc_octree::{CopcOctree, OctreeNode};
use rayon::prelude::*;

use crate::morton::MortonGrid;
use crate::prep_progress::{PrepProgress, Stage};
use crate::tiles::point_records::{RecordKey, RecordLayout};
use crate::tiles::sorted_points::{BlockBounds, SortedFile, SortedPoints};
use crate::tiles::stream_error::StreamError;

/// A node's box is widened by this share of the cube's side on every face before its
/// corners are placed on the curve, so that a point the writer placed on a face, rounded on
/// its way to local coordinates, still lies within it: four cells of the curve's grid.
const BOX_MARGIN: f64 = 1.0 / (1u64 << 19) as f64;

/// Bytes a waiting record's sort key and place take beside it.
const WAITING_KEY_BYTES: u64 = 16;

/// Records each thread writes at a time.
const WRITE_BATCH_RECORDS: usize = 1 << 15;

/// How a COPC cloud is sorted along its octree.
pub(crate) struct OctreeSortPlan<'a> {
    pub grid: MortonGrid,
    pub offset: DVec3,
    /// Points decoded at a time (at least one node).
    pub batch_points: u64,
    /// Bytes that records waiting to be written may take, with their keys.
    pub waiting_bytes: u64,
    /// Bytes a record is expected to take.
    pub record_bytes: u64,
    pub folder: &'a Path,
}

pub(crate) enum OctreeSort {
    /// The sorted points and the box (min, max) of the cloud's points.
    Sorted { bounds: (DVec3, DVec3), sorted: SortedPoints },
    /// Why the octree could not be walked.
    Declined(String),
}

/// The curve laid over `octree`'s cube, recentred by `offset`; none when the cube has no
/// finite, positive size.
pub(crate) fn octree_grid(octree: &CopcOctree, offset: DVec3) -> Option<MortonGrid> {
    let (low, high) = octree.cube();
    let side = (high - low).max_element();
    (low.is_finite() && high.is_finite() && side > 0.0)
        .then(|| MortonGrid::over((low - offset).as_vec3(), (high - offset).as_vec3()))
}

/// Sorts `octree`'s points along `plan.grid` into `plan.folder`.
pub(crate) fn sort_along_octree(
    octree: &CopcOctree,
    plan: &OctreeSortPlan,
    progress: &dyn PrepProgress,
) -> Result<OctreeSort, StreamError> {
    let spans = node_spans(octree, plan);
    let order = walk_order(octree.nodes(), &spans);
    let batches = batches(octree.nodes(), &order, plan.batch_points);
    let waiting = most_waiting(octree.nodes(), &spans, &order, &batches);
    if waiting.saturating_mul(plan.record_bytes + WAITING_KEY_BYTES) > plan.waiting_bytes {
        return Ok(OctreeSort::Declined(format!(
            "up to {waiting} of its points would wait in memory for the nodes before them along the curve, \
             more than the memory budget holds"
        )));
    }
    progress.stage_started(Stage::SortOctree, octree.points());
    let started = std::time::Instant::now();
    let path = plan.folder.join("octree-sorted");
    let mut walk = Walk {
        octree,
        plan,
        margin: box_margin(octree),
        file: None,
        waiting: Vec::new(),
        written: 0,
        blocks: Vec::new(),
    };
    let walked = std::thread::scope(|scope| {
        // The next batch is decoded while one is sorted and written.
        let (sender, decoded) = std::sync::mpsc::sync_channel(0);
        scope.spawn(|| {
            let sender = sender;
            for batch in &batches {
                if sender.send(octree.decode(&order[batch.clone()])).is_err() {
                    break;
                }
            }
        });
        let mut bounds = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for (i, (batch, clouds)) in batches.iter().zip(decoded).enumerate() {
            let nodes = &order[batch.clone()];
            let run = match walk.encode(nodes, &clouds?, &path)? {
                Ok(run) => run,
                Err(why) => return Ok(Err(why)),
            };
            bounds = (bounds.0.min(run.bounds.0), bounds.1.max(run.bounds.1));
            walk.waiting.push(run);
            let unread_start = batches.get(i + 1).map_or(u64::MAX, |next| spans[order[next.start]].0);
            walk.write_before(unread_start)?;
            progress.advanced(nodes.iter().map(|&node| octree.nodes()[node].points).sum());
        }
        Ok::<_, StreamError>(Ok(bounds))
    })?;
    let bounds = match walked {
        Ok(bounds) => bounds,
        Err(why) => return walk.declined(&path, why),
    };
    if !octree.scales_as_predicted() {
        return walk.declined(&path, "its attributes do not scale as its top levels' do".into());
    }
    let Walk { file, blocks, .. } = walk;
    let Some(file) = file else {
        return Ok(OctreeSort::Declined("it holds no points".into()));
    };
    progress.stage_finished(Stage::SortOctree, started.elapsed());
    Ok(OctreeSort::Sorted { bounds, sorted: file.finish(blocks, None) })
}

/// How far each node's box is widened on every face.
fn box_margin(octree: &CopcOctree) -> f64 {
    let (low, high) = octree.cube();
    (high - low).max_element() * BOX_MARGIN
}

fn widened((low, high): (DVec3, DVec3), margin: f64) -> (DVec3, DVec3) {
    (low - margin, high + margin)
}

/// Each node's stretch of the curve: the codes of its widened box's corners.
fn node_spans(octree: &CopcOctree, plan: &OctreeSortPlan) -> Vec<(u64, u64)> {
    let margin = box_margin(octree);
    let code = |p: DVec3| plan.grid.code((p - plan.offset).as_vec3());
    octree
        .nodes()
        .iter()
        .map(|node| {
            let (low, high) = widened(node.bounds, margin);
            (code(low), code(high))
        })
        .collect()
}

/// The nodes in the order their stretches begin, ties in the file's order.
fn walk_order(nodes: &[OctreeNode], spans: &[(u64, u64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..nodes.len()).collect();
    order.sort_unstable_by_key(|&node| (spans[node].0, nodes[node].first_point));
    order
}

/// Consecutive stretches of `order` that hold at most `batch_points` points, or one node.
fn batches(nodes: &[OctreeNode], order: &[usize], batch_points: u64) -> Vec<Range<usize>> {
    let mut batches = Vec::new();
    let (mut start, mut points) = (0, 0);
    for (i, &node) in order.iter().enumerate() {
        if i > start && points + nodes[node].points > batch_points {
            batches.push(start..i);
            (start, points) = (i, 0);
        }
        points += nodes[node].points;
    }
    if start < order.len() {
        batches.push(start..order.len());
    }
    batches
}

/// The most points held at once, at worst: a node's points are held from its batch until
/// the walk passes the end of its stretch.
fn most_waiting(
    nodes: &[OctreeNode],
    spans: &[(u64, u64)],
    order: &[usize],
    batches: &[Range<usize>],
) -> u64 {
    let (mut held, mut most) = (0u64, 0u64);
    let mut ends: BinaryHeap<Reverse<(u64, u64)>> = BinaryHeap::new();
    for (i, batch) in batches.iter().enumerate() {
        for &node in &order[batch.clone()] {
            held += nodes[node].points;
            ends.push(Reverse((spans[node].1, nodes[node].points)));
        }
        most = most.max(held);
        let unread_start = batches.get(i + 1).map_or(u64::MAX, |next| spans[order[next.start]].0);
        while ends.peek().is_some_and(|Reverse((end, _))| *end < unread_start) {
            let Reverse((_, points)) = ends.pop().expect("a stretch was peeked");
            held -= points;
        }
    }
    most
}

/// The records of one batch that wait to be written: sorted by key, those before `next`
/// written already.
struct WaitingRun {
    records: Vec<u8>,
    keys: Vec<(RecordKey, u32)>,
    next: usize,
    bounds: (DVec3, DVec3),
}

/// One node's points as records, with their codes and box (min, max).
struct EncodedNode {
    records: Vec<u8>,
    codes: Vec<u64>,
    bounds: (DVec3, DVec3),
}

/// The walk's state: the sorted file (made with the first batch's layout), the runs
/// waiting, and what was written.
struct Walk<'a> {
    octree: &'a CopcOctree,
    plan: &'a OctreeSortPlan<'a>,
    margin: f64,
    file: Option<SortedFile>,
    waiting: Vec<WaitingRun>,
    written: u64,
    blocks: Vec<Vec<(u64, BlockBounds)>>,
}

impl Walk<'_> {
    /// The records of `nodes`' points (decoded as `clouds`), sorted; or why a point does not
    /// fit its node.
    fn encode(
        &mut self,
        nodes: &[usize],
        clouds: &[PointCloud],
        path: &Path,
    ) -> Result<Result<WaitingRun, String>, StreamError> {
        let Some(first) = clouds.first() else { return Ok(Err("it holds no points".into())) };
        let layout = RecordLayout::of(first);
        if self.file.is_none() {
            self.file = Some(SortedFile::create(path, layout, self.plan.offset, self.octree.points())?);
        }
        let encoded: Vec<Result<EncodedNode, String>> = nodes
            .par_iter()
            .zip(clouds)
            .map(|(&node, cloud)| self.encode_node(node, cloud, layout))
            .collect();
        let size = layout.bytes();
        let mut run = WaitingRun {
            records: Vec::new(),
            keys: Vec::new(),
            next: 0,
            bounds: (DVec3::INFINITY, DVec3::NEG_INFINITY),
        };
        for (node_records, &node) in encoded.into_iter().zip(nodes) {
            let EncodedNode { records, codes, bounds } = match node_records {
                Ok(encoded) => encoded,
                Err(why) => return Ok(Err(why)),
            };
            let first_point = self.octree.nodes()[node].first_point;
            let start = (run.records.len() / size) as u32;
            run.keys.extend(
                codes
                    .iter()
                    .enumerate()
                    .map(|(i, &code)| ((code, (first_point + i as u64) as u32), start + i as u32)),
            );
            run.records.extend(records);
            run.bounds = (run.bounds.0.min(bounds.0), run.bounds.1.max(bounds.1));
        }
        run.keys.par_sort_unstable();
        Ok(Ok(run))
    }

    /// The records of node `node`'s points, their codes and box; or why they do not fit the
    /// node: too few or too many, or a point outside its widened box.
    fn encode_node(
        &self,
        node: usize,
        cloud: &PointCloud,
        layout: RecordLayout,
    ) -> Result<EncodedNode, String> {
        let info = &self.octree.nodes()[node];
        if cloud.len() as u64 != info.points {
            return Err(format!(
                "a node of level {} holds {} points, not the {} its hierarchy declares",
                info.level,
                cloud.len(),
                info.points
            ));
        }
        let (low, high) = widened(info.bounds, self.margin);
        let mut records = Vec::with_capacity(cloud.len() * layout.bytes());
        let mut codes = Vec::with_capacity(cloud.len());
        let mut bounds = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for (i, &p) in cloud.positions.iter().enumerate() {
            // Within the widened box, a point's code lies in the node's stretch: the way to
            // local coordinates and onto the grid never reverses an order.
            if !(p.cmpge(low).all() && p.cmple(high).all()) {
                return Err(format!(
                    "point {} lies outside the box of its octree node (level {})",
                    info.first_point + i as u64,
                    info.level
                ));
            }
            let code = self.plan.grid.code((p - self.plan.offset).as_vec3());
            let input = (info.first_point + i as u64) as u32;
            layout.encode(cloud, i, (code, input), &mut records);
            codes.push(code);
            bounds = (bounds.0.min(p), bounds.1.max(p));
        }
        Ok(EncodedNode { records, codes, bounds })
    }

    /// Writes every waiting record whose code lies before `unread_start`, in order.
    fn write_before(&mut self, unread_start: u64) -> Result<(), StreamError> {
        let ready = self.ready_in_order(unread_start);
        let file = self.file.as_ref().expect("a batch made the file");
        let size = file.record_bytes();
        let first = self.written;
        let waiting = &self.waiting;
        let pieces = ready
            .par_chunks(WRITE_BATCH_RECORDS)
            .enumerate()
            .map(|(part, records)| {
                let mut piece = file.piece(first + (part * WRITE_BATCH_RECORDS) as u64, records.len() * size);
                for &(run, record) in records {
                    let record = record as usize;
                    piece.push(&waiting[run].records[record * size..(record + 1) * size])?;
                }
                piece.finish()
            })
            .collect::<Result<Vec<_>, StreamError>>()?;
        self.blocks.extend(pieces);
        self.written += ready.len() as u64;
        for run in &mut self.waiting {
            run.next = run.keys.partition_point(|(key, _)| key.0 < unread_start);
        }
        self.waiting.retain(|run| run.next < run.keys.len());
        self.waiting.iter_mut().for_each(|run| run.compact(size));
        Ok(())
    }

    /// The waiting records whose codes lie before `unread_start`, as (run, record), in
    /// order: each run's are in order already, so they are merged, not sorted.
    fn ready_in_order(&self, unread_start: u64) -> Vec<(usize, u32)> {
        let stretches: Vec<&[(RecordKey, u32)]> = self
            .waiting
            .iter()
            .map(|run| &run.keys[run.next..run.keys.partition_point(|(key, _)| key.0 < unread_start)])
            .collect();
        let mut ready = Vec::with_capacity(stretches.iter().map(|stretch| stretch.len()).sum());
        let mut heads: BinaryHeap<Reverse<(RecordKey, usize, usize)>> = stretches
            .iter()
            .enumerate()
            .filter_map(|(run, stretch)| stretch.first().map(|&(key, _)| Reverse((key, run, 0))))
            .collect();
        while let Some(Reverse((_, run, at))) = heads.pop() {
            ready.push((run, stretches[run][at].1));
            if let Some(&(key, _)) = stretches[run].get(at + 1) {
                heads.push(Reverse((key, run, at + 1)));
            }
        }
        ready
    }

    /// Gives the scratch file back and says why the walk stopped.
    fn declined(self, path: &Path, why: String) -> Result<OctreeSort, StreamError> {
        drop(self.file);
        let _ = std::fs::remove_file(path);
        Ok(OctreeSort::Declined(why))
    }
}

impl WaitingRun {
    /// Once most of the run is written, keeps only the rest, so that a run that waits on a
    /// few points does not hold the memory of all the others.
    fn compact(&mut self, size: usize) {
        if self.next * 2 < self.keys.len() {
            return;
        }
        let keys = &self.keys[self.next..];
        let mut records = Vec::with_capacity(keys.len() * size);
        let mut kept = Vec::with_capacity(keys.len());
        for (i, &(key, record)) in keys.iter().enumerate() {
            records.extend_from_slice(&self.records[record as usize * size..(record as usize + 1) * size]);
            kept.push((key, i as u32));
        }
        (self.records, self.keys, self.next) = (records, kept, 0);
    }
}

#[cfg(test)]
mod tests {
    use pointray_io::{MemoryBudget, PointStream};

    use super::*;
    use crate::prep_progress::NoProgress;
    use crate::tiles::out_of_core_sort::{SortPlan, sort_points};
    use crate::trimmed_centre::{CENTRE_SAMPLE_POINTS, trimmed_centre};

    const AUTZEN_COPC: &str = "scans/autzen_trim.copc.laz";

    fn open_stream() -> PointStream {
        let path = pointray_test_support::data_file(AUTZEN_COPC);
        PointStream::open(&path, None, MemoryBudget { bytes: 1 << 30 }).unwrap()
    }

    /// The Autzen tile sorted along its octree a batch of `batch_points` at a time, and the
    /// same tile sorted out of core along the same curve.
    fn both_sorts(batch_points: u64, folder: &Path) -> (SortedPoints, SortedPoints) {
        let mut stream = open_stream();
        let octree = stream.copc_octree(CENTRE_SAMPLE_POINTS).unwrap().expect("a COPC file");
        let offset = trimmed_centre(octree.sample());
        let grid = octree_grid(&octree, offset).unwrap();
        let (walked, runs) = (folder.join("walked"), folder.join("runs"));
        std::fs::create_dir_all(&walked).unwrap();
        std::fs::create_dir_all(&runs).unwrap();
        let plan = OctreeSortPlan {
            grid,
            offset,
            batch_points,
            waiting_bytes: 1 << 30,
            record_bytes: 64,
            folder: &walked,
        };
        let OctreeSort::Sorted { bounds, sorted } = sort_along_octree(&octree, &plan, &NoProgress).unwrap()
        else {
            panic!("the walk was declined");
        };
        let cloud = pointray_io::formats::read_point_cloud(octree.path()).unwrap();
        assert_eq!(bounds, crate::prep::bounds_of(&cloud.positions));
        let plan = SortPlan { grid, offset, chunk_points: 10_000, run_bytes: 1 << 20, folder: &runs };
        (sorted, sort_points(&mut stream, &plan, &NoProgress).unwrap())
    }

    #[test]
    fn the_walk_writes_the_records_and_blocks_the_out_of_core_sort_writes() {
        let dir = tempfile::tempdir().unwrap();
        // One node a batch: the top levels and the nodes on the curve's jumps wait longest.
        for batch_points in [1, 20_000, u64::MAX] {
            let (walked, sorted) = both_sorts(batch_points, dir.path());
            assert_eq!(walked.len(), 110_000);
            let bytes = |points: &SortedPoints| std::fs::read(points.path()).unwrap();
            assert!(bytes(&walked) == bytes(&sorted), "the same records in the same order ({batch_points})");
            assert_eq!(walked.blocks(), sorted.blocks());
            std::fs::remove_dir_all(dir.path().join("walked")).unwrap();
            std::fs::remove_dir_all(dir.path().join("runs")).unwrap();
        }
    }

    fn node(points: u64, first_point: u64) -> OctreeNode {
        OctreeNode { bounds: (DVec3::ZERO, DVec3::ONE), points, first_point, level: 1 }
    }

    #[test]
    fn batches_hold_at_most_their_points_or_one_node() {
        let nodes = [node(5, 0), node(5, 5), node(20, 10), node(1, 30)];
        let order = [0, 1, 2, 3];
        assert_eq!(batches(&nodes, &order, 10), vec![0..2, 2..3, 3..4]);
        assert_eq!(batches(&nodes, &order, 100), vec![0..4]);
    }

    #[test]
    fn a_node_waits_until_the_walk_passes_its_stretch() {
        // A root spanning the whole curve and two children one after the other.
        let nodes = [node(10, 0), node(100, 10), node(100, 110)];
        let spans = [(0, 1000), (0, 499), (500, 1000)];
        let order = walk_order(&nodes, &spans);
        assert_eq!(order, vec![0, 1, 2]);
        let one_at_a_time = batches(&nodes, &order, 1);
        // The root waits to the end; the first child is written before the second is read.
        assert_eq!(most_waiting(&nodes, &spans, &order, &one_at_a_time), 110);
        // A first child whose stretch reaches past the second's start waits for it.
        let overlapping = [(0, 1000), (0, 600), (500, 1000)];
        assert_eq!(most_waiting(&nodes, &overlapping, &order, &one_at_a_time), 210);
    }
}
