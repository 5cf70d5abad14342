//! Points on a triangle mesh's surface: the benchmark stand-ins for scanned models.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::ops::Range;

use glam::{DVec3, IVec3};
use pointray_io::{PointCloud, TriangleMesh};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Blue noise draws this many uniform candidates per wanted point, then thins them.
const BLUE_NOISE_OVERSAMPLING: usize = 5;

/// The memory `sample_mesh` and writing its points take per point wanted: the f64 position
/// and its f32 copy for writing, and with blue noise the candidates and their search tree.
pub fn bytes_per_sample(blue_noise: bool) -> u64 {
    let plain = 48;
    if blue_noise { plain + BLUE_NOISE_OVERSAMPLING as u64 * 64 } else { plain }
}

/// `count` points spread uniformly by area over `mesh`, the same for the same `seed`.
/// With `blue_noise`, the points are thinned from more candidates so that no two lie
/// closer than a radius close to the densest packing, as real scans are far more even
/// than random samples.
///
/// Triangles whose indices are out of range get no samples; a mesh without area gives
/// an empty cloud. Positions only: `prep` estimates the normals itself.
pub fn sample_mesh(mesh: &TriangleMesh, count: usize, seed: u64, blue_noise: bool) -> PointCloud {
    let Some(areas) = CumulativeAreas::of(mesh) else {
        return PointCloud::default();
    };
    if !blue_noise {
        return PointCloud::from_positions(uniform_samples(mesh, &areas, 0..count, seed, SAMPLES_PER_CHUNK));
    }
    let candidates = uniform_samples(
        mesh,
        &areas,
        0..count.saturating_mul(BLUE_NOISE_OVERSAMPLING),
        seed,
        SAMPLES_PER_CHUNK,
    );
    PointCloud::from_positions(thin_to_blue_noise(candidates, count, areas.total))
}

/// Part `index` of `parts` of the uniform sample `sample_mesh(mesh, count, seed, false)`:
/// its samples `count·index/parts` up to `count·(index+1)/parts`, drawn from their place in
/// the seed's stream, so the parts in order are the whole sample, and separate jobs can each
/// draw one. Blue noise thins the whole sample at once and has no parts.
pub fn sample_mesh_part(
    mesh: &TriangleMesh,
    count: usize,
    seed: u64,
    (index, parts): (usize, usize),
) -> PointCloud {
    let Some(areas) = CumulativeAreas::of(mesh) else {
        return PointCloud::default();
    };
    let share = |part: usize| (count as u128 * part as u128 / parts.max(1) as u128) as usize;
    let range = share(index.min(parts))..share((index + 1).min(parts));
    PointCloud::from_positions(uniform_samples(mesh, &areas, range, seed, SAMPLES_PER_CHUNK))
}

/// The running sum of triangle areas, for picking a triangle with probability
/// proportional to its area by binary search.
struct CumulativeAreas {
    running: Vec<f64>,
    total: f64,
}

impl CumulativeAreas {
    fn of(mesh: &TriangleMesh) -> Option<Self> {
        let mut total = 0.0;
        let running = (0..mesh.triangles.len())
            .map(|t| {
                total +=
                    triangle_corners(mesh, t).map_or(0.0, |[a, b, c]| 0.5 * (b - a).cross(c - a).length());
                total
            })
            .collect();
        (total > 0.0 && total.is_finite()).then_some(Self { running, total })
    }

    fn pick(&self, rng: &mut ChaCha8Rng) -> usize {
        let target = rng.random::<f64>() * self.total;
        self.running.partition_point(|&sum| sum <= target).min(self.running.len() - 1)
    }
}

fn triangle_corners(mesh: &TriangleMesh, triangle: usize) -> Option<[DVec3; 3]> {
    let corners = mesh.triangles[triangle].map(|i| mesh.positions.get(i as usize).map(|p| p.as_dvec3()));
    match corners {
        [Some(a), Some(b), Some(c)] => Some([a, b, c]),
        _ => None,
    }
}

/// Samples drawn on one core between jumps of the random stream.
const SAMPLES_PER_CHUNK: usize = 1 << 16;

/// The random words one sample draws: three f64, two words each. Sample `i` starts at word
/// `6 i` of the seed's stream, so chunks drawn in parallel give the points one stream gives.
const WORDS_PER_SAMPLE: u128 = 6;

/// The samples `indices` of the seed's stream, drawn in chunks of `chunk` on every core.
fn uniform_samples(
    mesh: &TriangleMesh,
    areas: &CumulativeAreas,
    indices: Range<usize>,
    seed: u64,
    chunk: usize,
) -> Vec<DVec3> {
    let chunk = chunk.max(1);
    let mut points = vec![DVec3::ZERO; indices.len()];
    points.par_chunks_mut(chunk).enumerate().for_each(|(index, points)| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_word_pos((indices.start + index * chunk) as u128 * WORDS_PER_SAMPLE);
        for point in points {
            *point = uniform_sample(mesh, areas, &mut rng);
        }
    });
    points
}

fn uniform_sample(mesh: &TriangleMesh, areas: &CumulativeAreas, rng: &mut ChaCha8Rng) -> DVec3 {
    let triangle = areas.pick(rng);
    // A zero-area pick has probability zero, but a triangle with bad indices sits at the
    // same running sum as its predecessor; fall back to its first corner.
    let [a, b, c] = triangle_corners(mesh, triangle).unwrap_or([DVec3::ZERO; 3]);
    // sqrt warps the first coordinate so that the density is uniform over the area.
    let s = rng.random::<f64>().sqrt();
    let t = rng.random::<f64>();
    a * (1.0 - s) + b * (s * (1.0 - t)) + c * (s * t)
}

/// Dart throwing over the candidates (already in random order): a candidate is kept when
/// no kept point lies within `radius`. The radius starts near the densest packing of
/// `count` disks on `area` and shrinks until enough are kept; the first `count` kept
/// points are returned.
fn thin_to_blue_noise(candidates: Vec<DVec3>, count: usize, area: f64) -> Vec<DVec3> {
    if count == 0 {
        return Vec::new();
    }
    // Hexagonal packing of `count` disks of diameter r covers `area` at r² = 2/√3 · area / count.
    let densest = (2.0 / 3f64.sqrt() * area / count as f64).sqrt();
    // Random sequential packing saturates near 0.78 of the densest radius; 0.65 leaves
    // room to reach `count` in one pass over 5x candidates almost always.
    let mut radius = 0.65 * densest;
    loop {
        let kept = dart_throw(&candidates, radius, count);
        if kept.len() >= count || radius < 1e-3 * densest {
            return kept.into_iter().map(|i| candidates[i]).collect();
        }
        radius *= 0.9;
    }
}

/// Indices of the candidates kept at `radius`, at most `count` of them.
fn dart_throw(candidates: &[DVec3], radius: f64, count: usize) -> Vec<usize> {
    let cell_of = |p: DVec3| (p / radius).floor().as_ivec3();
    let mut grid: HashMap<IVec3, Vec<usize>, BuildHasherDefault<CellHasher>> =
        HashMap::with_capacity_and_hasher(count, BuildHasherDefault::default());
    let mut kept = Vec::with_capacity(count);
    let radius_squared = radius * radius;
    for (i, &p) in candidates.iter().enumerate() {
        let cell = cell_of(p);
        let crowded = neighbour_cells(cell).any(|c| {
            grid.get(&c).is_some_and(|points| {
                points.iter().any(|&j| candidates[j].distance_squared(p) < radius_squared)
            })
        });
        if !crowded {
            grid.entry(cell).or_default().push(i);
            kept.push(i);
            if kept.len() == count {
                break;
            }
        }
    }
    kept
}

/// A multiplicative hash for grid cells: the default SipHash made blue-noise thinning
/// several times slower, and cell keys need no protection against adversarial input.
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }

    fn write_i32(&mut self, value: i32) {
        self.write_u64(u64::from(value as u32));
    }

    fn write_u64(&mut self, value: u64) {
        self.0 = (self.0.rotate_left(5) ^ value).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

fn neighbour_cells(cell: IVec3) -> impl Iterator<Item = IVec3> {
    (-1..=1).flat_map(move |x| (-1..=1).flat_map(move |y| (-1..=1).map(move |z| cell + IVec3::new(x, y, z))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Two triangles: a unit square at z = 0 and a 2x2 square at z = 5 (4x the area).
    fn two_squares() -> TriangleMesh {
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::new(2.0, 0.0, 5.0),
            Vec3::new(2.0, 2.0, 5.0),
            Vec3::new(0.0, 2.0, 5.0),
        ];
        TriangleMesh { positions, triangles: vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]] }
    }

    #[test]
    fn deterministic_for_a_seed_and_different_across_seeds() {
        let mesh = two_squares();
        let a = sample_mesh(&mesh, 1000, 7, false);
        assert_eq!(a, sample_mesh(&mesh, 1000, 7, false));
        assert_ne!(a, sample_mesh(&mesh, 1000, 8, false));
        assert_eq!(a.len(), 1000);
    }

    /// The stream one core draws, sample after sample, as the stand-ins were first made.
    fn one_stream(mesh: &TriangleMesh, count: usize, seed: u64) -> Vec<DVec3> {
        let areas = CumulativeAreas::of(mesh).expect("area");
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..count).map(|_| uniform_sample(mesh, &areas, &mut rng)).collect()
    }

    #[test]
    fn chunks_drawn_in_parallel_give_the_one_stream() {
        let mesh = two_squares();
        let areas = CumulativeAreas::of(&mesh).expect("area");
        let serial = one_stream(&mesh, 10_007, 3);
        for chunk in [1, 7, 64, 10_007, 1 << 20] {
            assert_eq!(uniform_samples(&mesh, &areas, 0..10_007, 3, chunk), serial, "chunks of {chunk}");
        }
    }

    #[test]
    fn parts_in_order_are_the_whole_sample() {
        let mesh = two_squares();
        let whole = sample_mesh(&mesh, 1001, 5, false).positions;
        for parts in [1, 3, 7, 1001, 1500] {
            let joined: Vec<DVec3> = (0..parts)
                .flat_map(|index| sample_mesh_part(&mesh, 1001, 5, (index, parts)).positions)
                .collect();
            assert_eq!(joined, whole, "{parts} parts");
        }
    }

    #[test]
    fn density_follows_area() {
        let cloud = sample_mesh(&two_squares(), 50_000, 1, false);
        let upper = cloud.positions.iter().filter(|p| p.z > 2.5).count() as f64 / 50_000.0;
        assert!((upper - 0.8).abs() < 0.01, "upper share {upper}");
        let left_half = cloud.positions.iter().filter(|p| p.z < 2.5 && p.x < 0.5).count() as f64 / 50_000.0;
        assert!((left_half - 0.1).abs() < 0.01, "left half of the small square {left_half}");
        assert!(cloud.positions.iter().all(|p| p.x >= 0.0 && p.y >= 0.0 && p.x <= 2.0 && p.y <= 2.0));
    }

    #[test]
    fn blue_noise_keeps_the_count_and_spreads_points_out() {
        let mesh = two_squares();
        let nearest = |cloud: &PointCloud| {
            let p = &cloud.positions;
            (0..p.len())
                .map(|i| {
                    (0..p.len()).filter(|&j| j != i).map(|j| p[i].distance(p[j])).fold(f64::MAX, f64::min)
                })
                .fold(f64::MAX, f64::min)
        };
        let blue = sample_mesh(&mesh, 500, 3, true);
        let white = sample_mesh(&mesh, 500, 3, false);
        assert_eq!(blue.len(), 500);
        assert_eq!(blue, sample_mesh(&mesh, 500, 3, true));
        assert!(nearest(&blue) > 3.0 * nearest(&white), "{} vs {}", nearest(&blue), nearest(&white));
    }

    #[test]
    fn degenerate_meshes_give_no_points() {
        let flat = TriangleMesh { positions: vec![Vec3::ZERO; 3], triangles: vec![[0, 1, 2]] };
        assert!(sample_mesh(&flat, 10, 0, false).is_empty());
        let dangling = TriangleMesh { positions: vec![Vec3::ZERO], triangles: vec![[0, 5, 9]] };
        assert!(sample_mesh(&dangling, 10, 0, true).is_empty());
    }
}
