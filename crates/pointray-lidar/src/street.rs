//! A procedural street that needs no data files, Z up as LiDAR frames are, running along X:
//! a road with kerbs, raised sidewalks, building blocks on both sides (set back by different
//! depths, some with a bay), parked and driving cars, lamp poles and, when the data folder is
//! there, the scanned bunny and horse standing on the road.
//!
//! It is fixed: the same street every time, so that it can serve as ground truth.

mod models;
mod shapes;

use std::path::Path;

use glam::Vec3;
use pointray_io::TriangleMesh;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::LidarError;
use crate::surface::Surface;
pub use models::model_files;
use shapes::{push_bevelled_box, push_box, push_cylinder, push_face};

/// The street runs from x = −HALF_LENGTH to +HALF_LENGTH.
pub const HALF_LENGTH: f32 = 100.0;
/// The road spans |y| ≤ ROAD_HALF_WIDTH at z = 0 (two lanes).
pub const ROAD_HALF_WIDTH: f32 = 5.0;
/// The sidewalks' height above the road.
pub const KERB_HEIGHT: f32 = 0.15;
/// The sidewalks run from the kerb to |y| = SIDEWALK_EDGE, under the buildings.
const SIDEWALK_EDGE: f32 = 10.0;
/// The front of a block that is not set back.
const FACADE_LINE: f32 = 8.0;
const BUILDING_BACK: f32 = 20.0;
/// The blocks' widths, heights and setbacks come from this stream, so the street never changes.
const LAYOUT_SEED: u64 = 0x57_12ee7;

/// The street's surfaces; the models are looked for under `data_dir` (see `models.rs`).
pub fn street(data_dir: Option<&Path>) -> Result<Vec<Surface>, LidarError> {
    let mut surfaces = vec![
        Surface::new("road", road(), 0.12),
        Surface::new("kerb", kerbs(), 0.35),
        Surface::new("sidewalk", sidewalks(), 0.3),
        Surface::new("building blocks", buildings(), 0.5),
        Surface::new("poles", poles(), 0.4),
    ];
    surfaces.extend(cars());
    if let Some(data_dir) = data_dir {
        surfaces.extend(models::street_models(data_dir)?);
    }
    Ok(surfaces)
}

/// A horizontal rectangle at height `z`, facing up.
fn push_ground(mesh: &mut TriangleMesh, (y0, y1): (f32, f32), z: f32) {
    let corner = |x: f32, y: f32| Vec3::new(x, y, z);
    let (x0, x1) = (-HALF_LENGTH, HALF_LENGTH);
    let corners = [corner(x0, y0), corner(x1, y0), corner(x1, y1), corner(x0, y1)];
    push_face(mesh, &corners, Vec3::new(0.0, (y0 + y1) * 0.5, z - 1.0));
}

fn road() -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    push_ground(&mut mesh, (-ROAD_HALF_WIDTH, ROAD_HALF_WIDTH), 0.0);
    mesh
}

/// The kerbs' vertical faces, facing the road.
fn kerbs() -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for side in [-1.0, 1.0] {
        let y = side * ROAD_HALF_WIDTH;
        let corner = |x: f32, z: f32| Vec3::new(x, y, z);
        let (x0, x1) = (-HALF_LENGTH, HALF_LENGTH);
        let corners = [corner(x0, 0.0), corner(x1, 0.0), corner(x1, KERB_HEIGHT), corner(x0, KERB_HEIGHT)];
        push_face(&mut mesh, &corners, Vec3::new(0.0, y + side, 0.0));
    }
    mesh
}

fn sidewalks() -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    push_ground(&mut mesh, (ROAD_HALF_WIDTH, SIDEWALK_EDGE), KERB_HEIGHT);
    push_ground(&mut mesh, (-SIDEWALK_EDGE, -ROAD_HALF_WIDTH), KERB_HEIGHT);
    mesh
}

/// Blocks 10–18 m wide and 6–18 m high, set back 0–1.5 m from the façade line; half of them
/// have a bay 0.6 m deep on their upper floors.
fn buildings() -> TriangleMesh {
    let mut rng = ChaCha8Rng::seed_from_u64(LAYOUT_SEED);
    let mut mesh = TriangleMesh::default();
    for side in [-1.0f32, 1.0] {
        let mut x0 = -HALF_LENGTH;
        while x0 < HALF_LENGTH {
            let x1 = (x0 + rng.random_range(10.0..18.0)).min(HALF_LENGTH);
            let front = FACADE_LINE + rng.random_range(0.0..1.5);
            let height = rng.random_range(6.0..18.0);
            push_side_box(&mut mesh, side, (x0, x1), (front, BUILDING_BACK), (KERB_HEIGHT, height));
            if rng.random_bool(0.5) {
                let middle = (x0 + x1) * 0.5;
                push_side_box(
                    &mut mesh,
                    side,
                    (middle - 1.5, middle + 1.5),
                    (front - 0.6, front),
                    (3.0, height - 1.0),
                );
            }
            x0 = x1;
        }
    }
    mesh
}

/// A box over `xs`, `zs` and the distances `ys` from the street's axis on `side` (±1).
fn push_side_box(mesh: &mut TriangleMesh, side: f32, xs: (f32, f32), ys: (f32, f32), zs: (f32, f32)) {
    let (y0, y1) = (side * ys.0, side * ys.1);
    push_box(mesh, Vec3::new(xs.0, y0.min(y1), zs.0), Vec3::new(xs.1, y0.max(y1), zs.1));
}

/// Lamp posts 6 m high along both sidewalks, 20 m apart and staggered, and a few thin sign
/// posts.
fn poles() -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    let pole_y = ROAD_HALF_WIDTH + 0.6;
    for i in 0..10 {
        let x = -90.0 + 20.0 * i as f32;
        push_cylinder(&mut mesh, Vec3::new(x, pole_y, KERB_HEIGHT), Vec3::Z, 0.08, 6.0, 12);
        push_cylinder(&mut mesh, Vec3::new(x + 10.0, -pole_y, KERB_HEIGHT), Vec3::Z, 0.08, 6.0, 12);
    }
    for x in [-17.0, 3.0, 23.0] {
        push_cylinder(&mut mesh, Vec3::new(x, -pole_y, KERB_HEIGHT), Vec3::Z, 0.04, 2.5, 8);
    }
    mesh
}

/// Cars parked along both kerbs and two in the lanes, each `(x, y, reflectance)`: dark, mid
/// and white paint.
const CARS: [(f32, f32, f32); 10] = [
    (-30.0, -3.9, 0.6),
    (-14.0, -3.9, 0.15),
    (11.0, -3.9, 0.8),
    (26.0, -3.9, 0.6),
    (-22.0, 3.9, 0.8),
    (-9.0, 3.9, 0.6),
    (17.0, 3.9, 0.15),
    (35.0, 3.9, 0.6),
    (14.0, -1.6, 0.6),
    (-40.0, 1.6, 0.8),
];

fn cars() -> Vec<Surface> {
    CARS.iter()
        .enumerate()
        .map(|(i, &(x, y, reflectance))| Surface::new(format!("car {i}"), car(x, y), reflectance))
        .collect()
}

/// A car 4.4 m long and 1.8 m wide, heading along X: a bevelled body and cabin on four wheels.
fn car(x: f32, y: f32) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    let at = Vec3::new(x, y, 0.0);
    push_bevelled_box(&mut mesh, at + Vec3::new(-2.2, -0.9, 0.3), at + Vec3::new(2.2, 0.9, 1.0), 0.12);
    push_bevelled_box(&mut mesh, at + Vec3::new(-1.2, -0.8, 1.0), at + Vec3::new(0.9, 0.8, 1.45), 0.15);
    for (wheel_x, wheel_y) in [(-1.4, -0.92), (-1.4, 0.7), (1.4, -0.92), (1.4, 0.7)] {
        push_cylinder(&mut mesh, at + Vec3::new(wheel_x, wheel_y, 0.32), Vec3::Y, 0.32, 0.22, 16);
    }
    mesh
}
