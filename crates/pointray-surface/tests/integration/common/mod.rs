//! Point sets with known surfaces, shared by the integration tests.

use glam::DVec3;
use pointray_io::PointCloud;
use pointray_kernels::PatchHot;

/// `n x n` points over `[-1, 1]²`, each jittered within its cell by a fixed
/// pseudo-random offset, lifted to `z = height(x, y)` and moved by `shift`.
pub fn height_field(n: usize, shift: DVec3, height: impl Fn(f64, f64) -> f64) -> PointCloud {
    let cell = 2.0 / n as f64;
    let positions = (0..n * n)
        .map(|i| {
            let (jx, jy) = (jitter(2 * i), jitter(2 * i + 1));
            let x = -1.0 + cell * ((i % n) as f64 + 0.5 + 0.6 * jx);
            let y = -1.0 + cell * ((i / n) as f64 + 0.5 + 0.6 * jy);
            DVec3::new(x, y, height(x, y)) + shift
        })
        .collect();
    PointCloud::from_positions(positions)
}

/// A deterministic value in [-0.5, 0.5) (a 64-bit mix of `i`).
pub fn jitter(i: usize) -> f64 {
    let mut z = (i as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

/// `n` points evenly spread over the sphere of `radius` around `centre` (a Fibonacci
/// sphere, as even as a good scan).
pub fn sphere(n: usize, radius: f64, centre: DVec3) -> PointCloud {
    let golden_angle = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let positions = (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden_angle * i as f64;
            centre + radius * DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect();
    PointCloud::from_positions(positions)
}

/// Points of patch `patch`'s surface over its support disk (centre and rings), in the
/// input's coordinates.
pub fn surface_over_disk(patch: &PatchHot, offset: DVec3) -> Vec<DVec3> {
    let coefficients = patch.decode().coefficients;
    let f = |u: f32, v: f32| {
        let [c0, c1, c2, c3, c4, c5] = coefficients;
        c0 + c1 * u + c2 * v + c3 * u * u + c4 * u * v + c5 * v * v
    };
    let mut uv = vec![(0.0f32, 0.0f32)];
    for ring in 1..=4 {
        let r = patch.radius() * ring as f32 / 4.0;
        for step in 0..12 {
            let angle = step as f32 * std::f32::consts::TAU / 12.0;
            uv.push((r * angle.cos(), r * angle.sin()));
        }
    }
    uv.into_iter()
        .map(|(u, v)| patch.decode().to_world(glam::Vec3::new(u, v, f(u, v))).as_dvec3() + offset)
        .collect()
}
