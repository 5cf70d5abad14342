//! The GLSL twins against their Rust twins, on the device: thousands of random cases and the
//! edge cases of each, through the probes of `shaders/twins/`. GPU arithmetic may contract
//! `a * b + c` into one rounding and computes `pow`, `sqrt` and division to a few ulp, so
//! values agree within a stated relative bound, not bit for bit; a decision that hinges on a
//! rounding (a root of zero discriminant, a hit on a support's edge) may differ in at most
//! `BORDERLINE_FRACTION` of the cases, and only in a case that is borderline.

use std::sync::Arc;

use glam::{UVec2, Vec2, Vec3};
use pointray_kernels::bsdf::BSDF_PLASTIC;
use pointray_kernels::interpolate_color::{COLOR_NEIGHBORS, NO_NEIGHBOR, interpolate_color};
use pointray_kernels::light_source::LIGHT_QUAD;
use pointray_kernels::tangent_frame::{normal_bits, pack_normal, unpack_normal};
use pointray_kernels::{
    Bsdf, LightSource, PatchCold, bsdf_eval, bsdf_pdf, bsdf_sample, light_sample, random_next, random_next2,
    random_sequence,
};
use pointray_kernels::{
    Camera, PackedTangentFrame, PatchAcceptance, PatchHot, PhongSurface, Ray, TangentFrame, camera_ray,
    face_forward, intersect_patch, patch_normal, phong, quadratic_roots, sample_jitter, self_clearance,
    srgb_encode_rgba8,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::buffer::{Buffer, storage_usage};
use crate::context::GpuContext;
use crate::twin_probe::{self, probe_context, run_probe};

const CASES: usize = 4096;
/// The relative bound on values (about 80 ulp of f32).
const RELATIVE: f32 = 1e-5;
/// The relative bound on sampling densities, which amplify their directions' rounding.
const PDF_RELATIVE: f32 = 1e-3;
/// At most this fraction of the cases may decide differently, each of them borderline.
const BORDERLINE_FRACTION: f64 = 0.002;

fn close(gpu: f32, cpu: f32, scale: f32) -> bool {
    close_within(RELATIVE, gpu, cpu, scale)
}

fn close3(gpu: Vec3, cpu: Vec3, scale: f32) -> bool {
    (0..3).all(|i| close(gpu[i], cpu[i], scale))
}

fn close_within(relative: f32, gpu: f32, cpu: f32, scale: f32) -> bool {
    (gpu - cpu).abs() <= relative * scale.max(cpu.abs()).max(f32::MIN_POSITIVE)
}

fn xyz(v: [f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

fn word(bits: u32) -> f32 {
    f32::from_bits(bits)
}

fn unit(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v =
            Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        if (0.01..=1.0).contains(&v.length_squared()) {
            return v.normalize();
        }
    }
}

/// A magnitude from 1e-8 to 1e8, evenly in its logarithm, with a random sign; zero at times.
fn any_scale(rng: &mut ChaCha8Rng) -> f32 {
    if rng.random_range(0..16) == 0 {
        return 0.0;
    }
    let magnitude = 10f32.powf(rng.random_range(-8.0..8.0));
    if rng.random() { magnitude } else { -magnitude }
}

fn run(context: &Arc<GpuContext>, probe: &[u8], inputs: &[[f32; 4]], shape: (usize, usize)) -> Vec<[f32; 4]> {
    let outputs = run_probe(context, probe, inputs, shape).expect("the probe runs");
    assert_eq!(context.validation_messages(), 0, "the validation layer reported problems");
    outputs
}

fn assert_few_borderline(what: &str, borderline: usize) {
    let fraction = borderline as f64 / CASES as f64;
    assert!(
        fraction <= BORDERLINE_FRACTION,
        "{what}: {borderline} borderline cases of {CASES} decide differently"
    );
}

/// Record addresses past 4 GB from a buffer's start, and across the low word's carry, are the
/// 64-bit sums: a set of more than 134M patches reads its hot records there.
#[test]
fn record_addresses_agree_past_four_gigabytes() {
    let Some(context) = probe_context() else { return };
    let cases: [(u64, u32, u32); 6] = [
        (0x0000_0001_0000_0000, 0, 32),
        (0x0000_0001_0000_0000, 134_217_728, 32),
        (0x0000_0002_ffff_fff0, 1, 32),
        (0x0000_0003_0000_0040, 999_999_999, 44),
        (0x0000_0003_0000_0040, 999_999_999, 12),
        (0x0000_7fff_ffff_0000, 4_000_000_000, 64),
    ];
    let bits = |word: u32| f32::from_bits(word);
    let inputs: Vec<[f32; 4]> = cases
        .iter()
        .map(|&(base, index, size)| [bits(base as u32), bits((base >> 32) as u32), bits(index), bits(size)])
        .collect();
    let outputs = run(&context, twin_probe::RECORD_ADDRESS, &inputs, (1, 1));
    for (&(base, index, size), gpu) in cases.iter().zip(&outputs) {
        let found = u64::from(gpu[0].to_bits()) | (u64::from(gpu[1].to_bits()) << 32);
        let expected = base + u64::from(index) * u64::from(size);
        assert_eq!(found, expected, "base {base:#x}, index {index}, size {size}");
    }
}

#[test]
fn quadratic_roots_agree() {
    let Some(context) = probe_context() else { return };
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let edges = [
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 2.0, -1.0],
        [1.0, 2.0, 1.0],
        [1.0, 0.0, -4.0],
        [1.0, 0.0, 1.0],
        [1e-7, 1.0, 1.0],
        [-3.0, 0.0, 0.0],
    ];
    let mut cases: Vec<[f32; 3]> = edges.to_vec();
    cases.extend(
        (edges.len()..CASES).map(|_| [any_scale(&mut rng), any_scale(&mut rng), any_scale(&mut rng)]),
    );
    let inputs: Vec<[f32; 4]> = cases.iter().map(|&[a, b, c]| [a, b, c, 0.0]).collect();
    let outputs = run(&context, twin_probe::QUADRATIC_ROOTS, &inputs, (1, 1));
    let mut borderline = 0;
    for (index, (&[a, b, c], gpu)) in cases.iter().zip(&outputs).enumerate() {
        let cpu = quadratic_roots(a, b, c);
        let scale = cpu.as_slice().iter().fold(0.0f32, |m, r| m.max(r.abs()));
        if gpu[2] as u32 == cpu.count {
            for (k, &root) in cpu.as_slice().iter().enumerate() {
                assert!(
                    close(gpu[k], root, scale),
                    "case {index} ({a}, {b}, {c}): root {k} {} against {root}",
                    gpu[k]
                );
            }
            continue;
        }
        let discriminant = f64::from(b) * f64::from(b) - 4.0 * f64::from(a) * f64::from(c);
        let size = f64::from(b) * f64::from(b) + (4.0 * f64::from(a) * f64::from(c)).abs();
        let near_linear = (f64::from(a.abs()) - 1e-6 * f64::from(b.abs())).abs() <= 1e-5 * f64::from(a.abs());
        assert!(index >= edges.len(), "edge case ({a}, {b}, {c}): {} roots against {}", gpu[2], cpu.count);
        assert!(
            discriminant.abs() <= 1e-5 * size || near_linear,
            "case {index} ({a}, {b}, {c}) is no borderline case"
        );
        borderline += 1;
    }
    assert_few_borderline("quadratic roots", borderline);
}

/// A random patch about the origin and a ray from a few units away aimed near it.
fn patch_case(rng: &mut ChaCha8Rng) -> (PatchHot, PatchAcceptance, Ray, f32) {
    let normal = unit(rng);
    let radius = rng.random_range(0.1..1.0);
    let radii = Vec2::new(radius, radius * rng.random_range(0.2..=1.0));
    let coefficients = std::array::from_fn(|_| rng.random_range(-0.6..0.6));
    let origin =
        Vec3::new(rng.random_range(-0.2..0.2), rng.random_range(-0.2..0.2), rng.random_range(-0.2..0.2));
    let hot = PatchHot::new(
        origin,
        PackedTangentFrame::new(normal, unit(rng).cross(normal).normalize()),
        radii,
        coefficients,
    );
    let acceptance = if rng.random() { PatchAcceptance::Disk } else { PatchAcceptance::Box };
    let from = 3.0 * unit(rng);
    let toward = origin
        + radius
            * Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
    let t_max = if rng.random_range(0..4) == 0 { rng.random_range(0.5..4.0) } else { 100.0 };
    (hot, acceptance, Ray { origin: from, direction: (toward - from).normalize() }, t_max)
}

fn patch_inputs(hot: &PatchHot, acceptance: PatchAcceptance, ray: &Ray, t_max: f32) -> [[f32; 4]; 5] {
    let [x, y, z] = hot.origin;
    let [c2_c3, c4_c5] = hot.coefficients;
    [
        [x, y, z, hot.radius],
        [word(hot.frame), word(hot.aspect_c1), word(c2_c3), word(c4_c5)],
        [word(acceptance.code()), 0.0, 0.0, 0.0],
        [ray.origin.x, ray.origin.y, ray.origin.z, t_max],
        [ray.direction.x, ray.direction.y, ray.direction.z, 0.0],
    ]
}

#[test]
fn patch_intersection_and_normal_agree() {
    let Some(context) = probe_context() else { return };
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let cases: Vec<_> = (0..CASES).map(|_| patch_case(&mut rng)).collect();
    let inputs: Vec<[f32; 4]> = cases
        .iter()
        .flat_map(|(hot, acceptance, ray, t_max)| patch_inputs(hot, *acceptance, ray, *t_max))
        .collect();
    let outputs = run(&context, twin_probe::INTERSECT_PATCH, &inputs, (5, 2));
    let (mut hits, mut borderline) = (0, 0);
    for (index, ((hot, acceptance, ray, t_max), gpu)) in cases.iter().zip(outputs.chunks(2)).enumerate() {
        let patch = hot.decode();
        let cpu = intersect_patch(ray, &patch, 0.0, *t_max, *acceptance);
        match (cpu, gpu[0][0] == 1.0) {
            (Some(hit), true) => {
                hits += 1;
                let uv = Vec2::new(gpu[0][2], gpu[0][3]);
                if !close(gpu[0][1], hit.t, 1.0)
                    || !close(uv.x, hit.uv.x, hot.radius)
                    || !close(uv.y, hit.uv.y, hot.radius)
                {
                    // Two roots a rounding apart, or a root picked across the range's end.
                    borderline += 1;
                    continue;
                }
                let normal = patch_normal(&patch, hit.uv);
                assert!(
                    close3(xyz(gpu[1]), normal, 1.0),
                    "case {index}: normal {:?} against {normal}",
                    gpu[1]
                );
            }
            (None, false) => {}
            _ => borderline += 1,
        }
    }
    assert!(hits > CASES / 8, "only {hits} of {CASES} rays hit: the cases miss the point");
    assert_few_borderline("patch intersection", borderline);
}

#[test]
fn shading_encoding_clearance_and_frames_agree() {
    let Some(context) = probe_context() else { return };
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut cases = Vec::with_capacity(CASES);
    let mut inputs = Vec::with_capacity(CASES * 6);
    for case in 0..CASES {
        let (normal, to_viewer, to_light) = (unit(&mut rng), unit(&mut rng), unit(&mut rng));
        let radiance =
            Vec3::new(rng.random_range(0.0..2.0), rng.random_range(0.0..2.0), rng.random_range(0.0..2.0));
        let surface = PhongSurface {
            base_color: Vec3::new(rng.random(), rng.random(), rng.random()),
            specular: rng.random(),
            shininess: rng.random_range(1.0..128.0),
        };
        let radius = 10f32.powf(rng.random_range(-4.0..3.0));
        // Every eighth normal on the octahedron's equator, where a rounded z could flip the basis.
        let packed = if case % 8 == 0 { equator_code(&mut rng) } else { pack_normal(unit(&mut rng)) };
        let angle = rng.random_range(0.0..std::f32::consts::PI);
        inputs.extend([
            normal.extend(0.0).to_array(),
            to_viewer.extend(0.0).to_array(),
            to_light.extend(0.0).to_array(),
            radiance.extend(0.0).to_array(),
            surface.base_color.extend(surface.specular).to_array(),
            [surface.shininess, radius, word(packed), angle],
        ]);
        cases.push((normal, to_viewer, to_light, radiance, surface, radius, packed, angle));
    }
    let outputs = run(&context, twin_probe::SHADING, &inputs, (6, 3));
    for (index, (case, gpu)) in cases.iter().zip(outputs.chunks(3)).enumerate() {
        let &(normal, to_viewer, to_light, radiance, surface, radius, packed, angle) = case;
        let lit = phong(normal, to_viewer, to_light, radiance, &surface);
        assert!(close3(xyz(gpu[0]), lit, 1e-3), "case {index}: Phong {:?} against {lit}", gpu[0]);
        assert_eq!(xyz(gpu[1]), face_forward(normal, to_viewer), "case {index}: face_forward");
        let (gpu_bytes, cpu_bytes) =
            (gpu[1][3].to_bits().to_le_bytes(), srgb_encode_rgba8(radiance).to_le_bytes());
        let off_by = gpu_bytes.iter().zip(cpu_bytes).map(|(&g, c)| g.abs_diff(c)).max();
        assert!(off_by <= Some(1), "case {index}: sRGB {gpu_bytes:?} against {cpu_bytes:?}");
        assert!(close(gpu[2][3], self_clearance(radius), 0.0), "case {index}: self-clearance");
        let frame = TangentFrame::from_normal_and_angle(unpack_normal(packed), angle);
        assert!(
            close3(xyz(gpu[2]), frame.t1, 1.0),
            "case {index}: tangent {:?} against {}",
            gpu[2],
            frame.t1
        );
    }
}

/// A normal code whose octahedral `|a| + |b|` is 1023: a normal with z = 0.
fn equator_code(rng: &mut ChaCha8Rng) -> u32 {
    let a: i32 = rng.random_range(-1023..=1023);
    let b = (1023 - a.abs()) * if rng.random() { 1 } else { -1 };
    normal_bits(a, b)
}

#[test]
fn camera_rays_agree() {
    let Some(context) = probe_context() else { return };
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut cases = Vec::with_capacity(CASES);
    for _ in 0..CASES {
        let position = 10.0 * unit(&mut rng);
        let look_at =
            Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        let forward = (look_at - position).normalize();
        let up = (unit(&mut rng) - forward).normalize();
        let camera = Camera { position, look_at, up, vertical_fov_degrees: rng.random_range(5.0..150.0) };
        let size = UVec2::new(rng.random_range(1..4096), rng.random_range(1..4096));
        let pixel = UVec2::new(rng.random_range(0..size.x), rng.random_range(0..size.y));
        cases.push((camera, size, pixel));
    }
    let inputs: Vec<[f32; 4]> = cases
        .iter()
        .flat_map(|(camera, size, pixel)| {
            [
                camera.position.extend(camera.vertical_fov_degrees).to_array(),
                camera.look_at.extend(0.0).to_array(),
                camera.up.extend(0.0).to_array(),
                [word(size.x), word(size.y), word(pixel.x), word(pixel.y)],
            ]
        })
        .collect();
    let outputs = run(&context, twin_probe::CAMERA_RAY, &inputs, (4, 2));
    for (index, ((camera, size, pixel), gpu)) in cases.iter().zip(outputs.chunks(2)).enumerate() {
        let ray = camera_ray(camera, *size, *pixel, sample_jitter(index as u32 % 16));
        assert_eq!(xyz(gpu[0]), ray.origin, "case {index}: origin");
        assert!(
            close3(xyz(gpu[1]), ray.direction, 1.0),
            "case {index}: direction {:?} against {}",
            gpu[1],
            ray.direction
        );
    }
}

/// Patches scattered in a unit cube, each with a colour, a reach and its nearest patches as
/// colour neighbours (some slots empty).
fn coloured_patches(rng: &mut ChaCha8Rng, count: usize) -> (Vec<PatchHot>, Vec<PatchCold>, Vec<u32>) {
    let origins: Vec<Vec3> =
        (0..count).map(|_| Vec3::new(rng.random(), rng.random(), rng.random())).collect();
    let hot = origins
        .iter()
        .map(|&origin| {
            let normal = unit(rng);
            PatchHot::new(
                origin,
                PackedTangentFrame::new(normal, unit(rng).cross(normal).normalize()),
                Vec2::splat(0.1),
                [0.0; 6],
            )
        })
        .collect();
    let cold = (0..count)
        .map(|_| PatchCold {
            color_rgba8: rng.random(),
            intensity: rng.random(),
            color_reach: rng.random_range(0.0..0.3),
        })
        .collect();
    let neighbors = origins
        .iter()
        .enumerate()
        .flat_map(|(i, &origin)| {
            let mut others: Vec<usize> = (0..count).filter(|&j| j != i).collect();
            others.sort_by(|&a, &b| origin.distance(origins[a]).total_cmp(&origin.distance(origins[b])));
            let kept = rng.random_range(0..=COLOR_NEIGHBORS);
            (0..COLOR_NEIGHBORS).map(move |slot| if slot < kept { others[slot] as u32 } else { NO_NEIGHBOR })
        })
        .collect();
    (hot, cold, neighbors)
}

fn address_bits(buffer: &Buffer) -> [f32; 2] {
    let address = buffer.device_address();
    [word(address as u32), word((address >> 32) as u32)]
}

#[test]
fn colour_interpolation_agrees() {
    let Some(context) = probe_context() else { return };
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (hot, cold, neighbors) = coloured_patches(&mut rng, 256);
    let upload =
        |name, bytes: &[u8]| Buffer::host_with_data(&context, name, bytes, storage_usage()).expect("uploads");
    let hot_buffer = upload("twin hot patches", bytemuck::cast_slice(&hot));
    let cold_buffer = upload("twin cold patches", bytemuck::cast_slice(&cold));
    let neighbor_buffer = upload("twin colour neighbours", bytemuck::cast_slice(&neighbors));
    let [hot_low, hot_high] = address_bits(&hot_buffer);
    let [cold_low, cold_high] = address_bits(&cold_buffer);
    let queries: Vec<(Vec3, u32)> = (0..CASES)
        .map(|_| {
            let hit = rng.random_range(0..hot.len() as u32);
            let [x, y, z] = hot[hit as usize].origin;
            let jitter = Vec3::new(
                rng.random_range(-0.1..0.1),
                rng.random_range(-0.1..0.1),
                rng.random_range(-0.1..0.1),
            );
            (Vec3::new(x, y, z) + jitter, hit)
        })
        .collect();
    let mut inputs: Vec<[f32; 4]> = queries
        .iter()
        .flat_map(|&(position, hit)| {
            [position.extend(word(hit)).to_array(), [hot_low, hot_high, cold_low, cold_high]]
        })
        .collect();
    let [low, high] = address_bits(&neighbor_buffer);
    inputs.push([low, high, 0.0, 0.0]);
    let outputs = run(&context, twin_probe::INTERPOLATE_COLOR, &inputs, (2, 1));
    let (mut rounded, mut borderline) = (0, 0);
    for (index, (&(position, hit), gpu)) in queries.iter().zip(&outputs).enumerate() {
        let (gpu, cpu) = (
            gpu[0].to_bits().to_le_bytes(),
            interpolate_color(position, hit, &hot, &cold, &neighbors).to_le_bytes(),
        );
        match gpu.iter().zip(cpu).map(|(&g, c)| g.abs_diff(c)).max() {
            Some(0) => {}
            // A blend that lands on a byte's rounding edge.
            Some(1) => rounded += 1,
            // The walk to the nearest point took another turn at a distance tie.
            _ => borderline += 1,
        }
        assert!(borderline <= CASES / 100, "case {index}: colour {gpu:?} against {cpu:?}");
    }
    assert!(rounded <= CASES / 100, "{rounded} of {CASES} colours are a byte off: more than rounding");
    assert_few_borderline("colour interpolation", borderline);
}

/// The relative bounds on a BSDF's values and on its sample's pdf. GGX's
/// `1 + (α² - 1) cos²θ` cancels in f32 as the half vector nears the normal, so a few ulp of
/// a cosine move the lobe by 1e-4 of its value at usual roughness and by a few percent at
/// the smallest; there the pdf of a drawn direction (up to about 1e7) is ill-conditioned in
/// both twins alike, while the sample's weight, which the path carries, stays close.
fn bsdf_relative_bounds(bsdf: &Bsdf) -> (f32, f32) {
    if bsdf.kind == pointray_kernels::bsdf::BSDF_DIELECTRIC && bsdf.roughness == 0.0 {
        (RELATIVE, RELATIVE)
    } else if bsdf.roughness < 0.05 {
        (0.05, 0.5)
    } else {
        (2e-4, 2e-4)
    }
}

/// A random sequence's seed, pixel and sample.
type SequenceCase = (u32, UVec2, u32);

/// A BSDF, `wo`, `wi` and the sample's three numbers.
type BsdfCase = (Bsdf, Vec3, Vec3, Vec3);

/// A BSDF of any kind, rough or smooth, and two directions on either side.
fn bsdf_case(rng: &mut ChaCha8Rng) -> BsdfCase {
    let roughness = if rng.random_range(0..4) == 0 { 0.0 } else { rng.random_range(0.01..1.0) };
    let color = Vec3::new(rng.random(), rng.random(), rng.random());
    let bsdf = Bsdf { kind: rng.random_range(0..4), color, roughness, ior: rng.random_range(1.1..2.0) };
    let u = Vec3::new(rng.random(), rng.random(), rng.random());
    (bsdf, unit(rng), unit(rng), u)
}

#[test]
fn random_sequences_and_bsdfs_agree() {
    let Some(context) = probe_context() else { return };
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let cases: Vec<(SequenceCase, BsdfCase)> = (0..CASES)
        .map(|_| {
            (
                (
                    rng.random(),
                    UVec2::new(rng.random_range(0..8192), rng.random_range(0..8192)),
                    rng.random_range(0..65536),
                ),
                bsdf_case(&mut rng),
            )
        })
        .collect();
    let inputs: Vec<[f32; 4]> = cases
        .iter()
        .flat_map(|&((seed, pixel, sample), (bsdf, wo, wi, u))| {
            [
                [word(seed), word(pixel.x), word(pixel.y), word(sample)],
                [word(bsdf.kind), bsdf.color.x, bsdf.color.y, bsdf.color.z],
                [bsdf.roughness, bsdf.ior, u.x, u.y],
                wo.extend(u.z).to_array(),
                wi.extend(0.0).to_array(),
            ]
        })
        .collect();
    let outputs = run(&context, twin_probe::PATH_SAMPLING, &inputs, (5, 4));
    let mut borderline = 0;
    for (index, (&((seed, pixel, sample), (bsdf, wo, wi, u)), gpu)) in
        cases.iter().zip(outputs.chunks(4)).enumerate()
    {
        let mut sequence = random_sequence(seed, pixel, sample);
        let numbers = [random_next(&mut sequence), random_next(&mut sequence)];
        let pair = random_next2(&mut sequence);
        assert_eq!(gpu[0], [numbers[0], numbers[1], pair.x, pair.y], "case {index}: the random sequence");
        let (value, pdf) = (bsdf_eval(&bsdf, wo, wi), bsdf_pdf(&bsdf, wo, wi));
        let (value_bound, pdf_bound) = bsdf_relative_bounds(&bsdf);
        let near = |gpu: f32, cpu: f32| close_within(value_bound, gpu, cpu, cpu.abs().max(1.0));
        let evaluated = (0..3).all(|c| near(gpu[1][c], value[c])) && near(gpu[1][3], pdf);
        let drawn = bsdf_sample(&bsdf, wo, u);
        let sampled = (gpu[3][3] == 1.0) == drawn.delta
            && close3(xyz(gpu[2]), drawn.direction, 1.0)
            && close_within(pdf_bound, gpu[2][3], drawn.pdf, drawn.pdf.abs().max(1.0))
            && (0..3).all(|c| near(gpu[3][c], drawn.weight[c]));
        if !(evaluated && sampled) {
            // GGX near grazing angles, or a reflect-or-refract draw at its Fresnel edge.
            borderline += 1;
            assert!(
                borderline <= CASES / 100,
                "case {index} ({bsdf:?}): {gpu:?} against {value}, {pdf}, {drawn:?}"
            );
        }
    }
    assert_few_borderline("BSDF sampling and evaluation", borderline);
}

#[test]
fn draws_from_the_random_sequence_agree_for_plastic_and_a_quad_light() {
    let Some(context) = probe_context() else { return };
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let cases: Vec<([u32; 4], Vec3, f32)> = (0..CASES)
        .map(|_| {
            let key = [
                rng.random(),
                rng.random_range(0..8192),
                rng.random_range(0..8192),
                rng.random_range(0..1 << 16),
            ];
            let wo = unit(&mut rng);
            (key, Vec3::new(wo.x, wo.y, wo.z.abs().max(0.01)).normalize(), rng.random_range(0.05..1.0))
        })
        .collect();
    let inputs: Vec<[f32; 4]> = cases
        .iter()
        .flat_map(|(key, wo, roughness)| [key.map(word), wo.extend(*roughness).to_array()])
        .collect();
    let outputs = run(&context, twin_probe::PATH_DRAWS, &inputs, (2, 3));
    let quad = LightSource {
        kind: LIGHT_QUAD,
        position: Vec3::new(-0.5, 2.0, -0.5),
        edge_u: Vec3::X,
        edge_v: Vec3::Z,
        radius: 0.0,
        radiance: Vec3::ONE,
    };
    let mut borderline = 0;
    for (index, ((key, wo, roughness), gpu)) in cases.iter().zip(outputs.chunks(3)).enumerate() {
        let mut random = random_sequence(key[0], UVec2::new(key[1], key[2]), key[3]);
        let u: [f32; 4] = std::array::from_fn(|_| random_next(&mut random));
        assert_eq!(gpu[0].map(f32::to_bits), u.map(f32::to_bits), "case {index}: the random numbers");
        let plastic =
            Bsdf { kind: BSDF_PLASTIC, color: Vec3::new(0.8, 0.5, 0.3), roughness: *roughness, ior: 1.5 };
        let drawn = bsdf_sample(&plastic, *wo, Vec3::new(u[0], u[1], u[2]));
        // A narrow lobe's pdf turns the direction's last-ulp differences into a relative 1e-4.
        let pdf_close = (gpu[1][3] - drawn.pdf).abs() <= PDF_RELATIVE * drawn.pdf.max(1.0);
        let agrees = close3(xyz(gpu[1]), drawn.direction, 1.0) && pdf_close;
        if !agrees {
            // The lobe is chosen by u.z against a probability from Fresnel, computed to an ulp.
            let p = pointray_kernels::rough_plastic::rough_plastic_coat_probability(plastic.color, 1.5, *wo);
            assert!((u[2] - p).abs() < 1e-5, "case {index}: BSDF sample {:?} against {drawn:?}", gpu[1]);
            borderline += 1;
        }
        let arriving = light_sample(&quad, Vec3::ZERO, Vec2::new(u[2], u[3]));
        assert!(close3(xyz(gpu[2]), arriving.direction, 1.0), "case {index}: light direction {:?}", gpu[2]);
        assert!(
            close(gpu[2][3], arriving.pdf, 1.0),
            "case {index}: light pdf {} against {}",
            gpu[2][3],
            arriving.pdf
        );
    }
    assert_few_borderline("BSDF samples", borderline);
}
