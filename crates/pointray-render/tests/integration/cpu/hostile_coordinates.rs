//! Properties over hostile coordinates: random clouds and scenes at scales from 1e-30 to 1e30
//! and offsets up to 1e9, with NaN or infinite values mixed in. `prep` and the scene loader
//! either give a result the CPU renderer draws as a sane image (every pixel finite), or a clear
//! error naming the problem; never a panic, and never a hang (each case has a time bound).

use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

use glam::DVec3;
use pointray_io::PointCloud;
use pointray_patches::PrepSettings;
use pointray_scene::{LoadOptions, RenderSettings, load_scene};
use pointray_surface::{NoProgress, prep};
use proptest::prelude::*;

/// Far above what a case takes on a 2-core machine; only a hang reaches it.
const CASE_TIME_BOUND: Duration = Duration::from_secs(60);

/// Runs `work` on its own thread and fails the case if it does not finish in time.
fn within_bound<T: Send + 'static>(work: impl FnOnce() -> T + Send + 'static) -> T {
    let (sender, receiver) = mpsc::channel();
    std::thread::spawn(move || sender.send(work()));
    receiver.recv_timeout(CASE_TIME_BOUND).expect("the case finished within its time bound")
}

/// A coordinate value: mostly ordinary numbers, sometimes NaN or an infinity.
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => -1.0f64..1.0,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
    ]
}

/// `10^e` for `e` in [-30, 30].
fn scale() -> impl Strategy<Value = f64> {
    (-30i32..=30).prop_map(|exponent| 10f64.powi(exponent))
}

fn offset() -> impl Strategy<Value = DVec3> {
    prop::array::uniform3(-1e9f64..1e9).prop_map(DVec3::from)
}

/// A wavy 12x12 sheet, scaled and moved, with an occasional non-finite coordinate.
fn hostile_cloud() -> impl Strategy<Value = PointCloud> {
    (scale(), offset(), prop::collection::vec((0usize..144, coordinate()), 0..2)).prop_map(
        |(scale, offset, spoilers)| {
            let mut positions: Vec<DVec3> = (0..144)
                .map(|i| {
                    let (x, z) = (f64::from(i % 12) / 11.0, f64::from(i / 12) / 11.0);
                    offset + scale * DVec3::new(x, 0.2 * (3.0 * x).sin() * (2.0 * z).cos(), z)
                })
                .collect();
            for (index, value) in spoilers.into_iter().filter(|(_, v)| !v.is_finite()) {
                positions[index].y = value;
            }
            PointCloud::from_positions(positions)
        },
    )
}

fn render_is_sane(scene: &pointray_scene::Scene) -> Result<(), TestCaseError> {
    let settings = RenderSettings { width: 12, height: 9, ..RenderSettings::default() };
    let image = pointray_cpu::render(scene, &settings);
    prop_assert!(image.color.iter().all(|c| c.is_finite()), "a pixel is not finite");
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn prep_gives_traceable_patches_or_a_clear_error(cloud in hostile_cloud()) {
        let result = within_bound(move || prep(&cloud, &PrepSettings::default(), &NoProgress).map(|(p, _)| p));
        match result {
            Ok(patches) => prop_assert_eq!(patches.check(), Ok(())),
            Err(error) => prop_assert!(!error.to_string().is_empty()),
        }
    }

    #[test]
    fn scenes_load_and_render_sanely_or_fail_clearly(
        cloud in hostile_cloud(),
        object_scale in scale(),
        translate in prop::array::uniform3(coordinate()),
        translate_scale in scale(),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let finite = cloud.positions.iter().all(|p| p.is_finite());
        if finite {
            pointray_io::formats::ply::write_point_cloud(&dir.path().join("cloud.ply"), &cloud).unwrap();
        } else {
            // The writer refuses non-finite positions; a text file carries them as the user would.
            let text: String = cloud.positions.iter().map(|p| format!("{} {} {}\n", p.x, p.y, p.z)).collect();
            std::fs::write(dir.path().join("cloud.ply"), format!("ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\nend_header\n{text}", cloud.len())).unwrap();
        }
        let toml_number = |v: f64| if v.is_nan() { "nan".to_string() } else if v.is_infinite() { format!("{}inf", if v < 0.0 { "-" } else { "+" }) } else { format!("{v:e}") };
        let [tx, ty, tz] = translate.map(|t| toml_number(t * translate_scale));
        let scene = dir.path().join("scene.toml");
        std::fs::write(&scene, format!(
            "[[lights]]\ntype = \"directional\"\ndirection = [-0.4, -1.0, -0.5]\n\n\
             [[objects]]\ntype = \"points\"\npath = \"cloud.ply\"\n[objects.transform]\nscale = {}\ntranslate = [{tx}, {ty}, {tz}]\n\n\
             [[objects]]\ntype = \"ground\"\nauto = true\n",
            toml_number(object_scale.min(f64::from(f32::MAX))),
        )).unwrap();
        let loaded = within_bound(move || load_scene(&scene, &LoadOptions::default()).map(|l| l.scene).map_err(|e| e.to_string()));
        match loaded {
            Ok(scene) => render_is_sane(&scene)?,
            Err(message) => prop_assert!(message.contains(&display(dir.path())), "the error names the scene: {}", message),
        }
    }
}

fn display(dir: &Path) -> String {
    dir.join("scene.toml").display().to_string()
}
