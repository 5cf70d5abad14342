//! Running a suite (or one scene file): for each model and size, the point set, its mesh
//! (the limit) and, when asked, the ablations.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pointray_patches::{BoxKind, PrepSettings, RadiusMode};
use pointray_scene::load::{LoadOptions, load_scene};
use pointray_scene::{
    BufferLayout, Geometry, HotRecords, Integrator, PatchAcceptance, RenderSettings, Scene,
};
use pointray_surface::NoProgress;
use pointray_vulkan::{BlasLayout, PixelOutput, SceneLayout, VulkanError, VulkanRenderer};

use crate::case_result::{CaseLabel, CaseResult, Variant};
use crate::data::ensure_cache_dir;
use crate::error::BenchError;
use crate::measure::{FrameCounts, Measurement, measure, measure_prepared};
use crate::model_scene::{ModelGeometry, load_model_scene, model_points};
use crate::report::{Report, limit_rows};
use crate::stand_in::stand_in_label;
use crate::suite::{ModelSpec, Suite};
use crate::triangle_proxies::triangle_proxies;

/// The ablations that rebuild per box or re-prep (one geometry per AABB, cube boxes, k = 6)
/// only run on models up to this many points, to keep a suite run short.
pub const PER_BOX_ABLATION_MAX_POINTS: usize = 200_000;

pub struct BenchOptions<'a> {
    pub data: PathBuf,
    /// Stand-in points, prep results and generated scene files.
    pub cache: PathBuf,
    pub frames: FrameCounts,
    /// Replaces every model's sizes.
    pub size: Option<(u32, u32)>,
    /// Replaces every scene's integrator (one sample a pixel a frame under `Path`, so that
    /// frames per second are samples per second).
    pub integrator: Option<Integrator>,
    /// Replaces every scene's patches a box (`RenderSettings::patches_per_box`).
    pub patches_per_box: Option<u32>,
    /// Replaces every scene's hot records (`RenderSettings::hot_records`).
    pub hot_records: Option<HotRecords>,
    /// Time the mesh twin of each model (the limit).
    pub limit: bool,
    pub ablations: bool,
    /// A renderer with shader execution reordering on the same device, for its ablation.
    pub reordering: Option<&'a VulkanRenderer>,
    /// Only the models with these names (all when empty).
    pub models: Vec<String>,
    /// Called with each case as it completes.
    pub on_case: &'a dyn Fn(&CaseResult),
}

/// Everything one model contributes at one size.
struct ModelRun<'a> {
    renderer: &'a VulkanRenderer,
    options: &'a BenchOptions<'a>,
    model: &'a ModelSpec,
    stand_in: Option<String>,
    cases: Vec<CaseResult>,
}

pub fn run_suite(
    renderer: &VulkanRenderer,
    suite: &Suite,
    options: &BenchOptions,
) -> Result<Report, BenchError> {
    ensure_cache_dir(&options.cache)?;
    let wanted = |m: &&ModelSpec| options.models.is_empty() || options.models.iter().any(|n| n == &m.name);
    let mut cases = Vec::new();
    for model in suite.models.iter().filter(wanted) {
        let stand_in = model.stand_in.as_ref().map(stand_in_label);
        let mut run = ModelRun { renderer, options, model, stand_in, cases: Vec::new() };
        run.all_sizes()?;
        cases.append(&mut run.cases);
    }
    Ok(report(renderer, &suite.name, options, cases))
}

/// One scene file, timed at its own size (or `options.size`); no paper numbers.
pub fn run_scene_file(
    renderer: &VulkanRenderer,
    path: &Path,
    options: &BenchOptions,
) -> Result<Report, BenchError> {
    ensure_cache_dir(&options.cache)?;
    let loaded =
        load_scene(path, &LoadOptions { cache_dir: Some(&options.cache), ..LoadOptions::default() })?;
    let (width, height) = options.size.unwrap_or((loaded.settings.width, loaded.settings.height));
    let settings = options.applied(RenderSettings { width, height, ..loaded.settings });
    let name = path.display().to_string();
    let failed = |source| BenchError::Vulkan { case: name.clone(), source };
    // As `render` makes it ready: grouped to fit, or streamed, where it does not fit whole.
    let mut prepared =
        renderer.prepare_with_layout(&loaded.scene, SceneLayout::for_frames(&settings)).map_err(failed)?;
    if let Some(tiles) = prepared.stream_tiles(settings.aspect(), None).map_err(failed)? {
        println!(
            "{name}: streamed, {} of {} tiles on the GPU in full and {} coarse ({:.2} GB)",
            tiles.resident,
            tiles.tiles,
            tiles.coarse,
            tiles.resident_bytes as f64 / 1e9
        );
    }
    let built = prepared.build_report();
    println!(
        "{name}: {} patches a box, {} hot records, {:.2} GB on the GPU ({} bottom levels)",
        built.patches_per_box,
        built.hot_records.name(),
        built.gpu_bytes() as f64 / 1e9,
        built.blas_count
    );
    let measured = measure_prepared(renderer, &prepared, &settings, PixelOutput::Display, options.frames)
        .map_err(failed)?;
    let label = CaseLabel {
        model: &name,
        stand_in: None,
        variant: Variant::Points,
        primitives: loaded.scene.objects.iter().map(|o| primitive_count(&o.geometry)).sum(),
        paper_fps: None,
    };
    let case = CaseResult::new(label, width, height, options.frames.timed, &measured);
    (options.on_case)(&case);
    Ok(report(renderer, &name, options, vec![case]))
}

fn report(renderer: &VulkanRenderer, suite: &str, options: &BenchOptions, cases: Vec<CaseResult>) -> Report {
    let info = renderer.device_info();
    Report {
        suite: suite.to_string(),
        device: info.name.clone(),
        driver: info.driver.clone(),
        vulkan_api: info.api_version.clone(),
        warmup_frames: options.frames.warmup,
        timed_frames: options.frames.timed,
        limits: limit_rows(&cases),
        cases,
    }
}

fn primitive_count(geometry: &Geometry) -> usize {
    match geometry {
        Geometry::Patches(patches) => patches.len(),
        Geometry::Mesh(mesh) => mesh.triangles.len(),
    }
}

/// The model object (the suite's first) of a loaded model scene.
fn model_primitives(scene: &Scene) -> usize {
    scene.objects.first().map(|o| primitive_count(&o.geometry)).unwrap_or(0)
}

impl ModelRun<'_> {
    fn all_sizes(&mut self) -> Result<(), BenchError> {
        let sizes = self.options.size.map(|s| vec![s]).unwrap_or_else(|| self.model.size_list());
        // A point set always loads (or fails with its reason); only a mesh may be absent.
        let (base, file_settings) =
            self.load(ModelGeometry::Points)?.ok_or_else(|| BenchError::InvalidModel {
                path: self.options.cache.clone(),
                model: self.model.name.clone(),
                problem: "its point set did not load".into(),
            })?;
        let mesh = if self.options.limit { self.load(ModelGeometry::Mesh)? } else { None };
        for (index, &(width, height)) in sizes.iter().enumerate() {
            let settings = self.options.applied(RenderSettings { width, height, ..file_settings });
            self.time(&base, &settings, Variant::Points)?;
            if let Some((mesh_scene, _)) = &mesh {
                self.time(mesh_scene, &settings, Variant::Mesh)?;
            }
            // Ablations at the first size only: they compare layouts, not sizes.
            if self.options.ablations && index == 0 {
                self.ablations(&base, &settings)?;
            }
        }
        Ok(())
    }

    fn load(&self, geometry: ModelGeometry) -> Result<Option<(Scene, RenderSettings)>, BenchError> {
        let loaded = load_model_scene(self.model, geometry, &self.options.data, &self.options.cache)?;
        Ok(loaded.map(|l| (l.scene, l.settings)))
    }

    fn ablations(&mut self, base: &Scene, settings: &RenderSettings) -> Result<(), BenchError> {
        let combined = RenderSettings { buffer_layout: BufferLayout::Combined, ..*settings };
        self.time(base, &combined, Variant::CombinedBuffers)?;
        let box_test = RenderSettings { acceptance: PatchAcceptance::Box, ..*settings };
        self.time(base, &box_test, Variant::BoxAcceptance)?;
        self.time(base, settings, Variant::AovOutput)?;
        self.time(base, settings, Variant::PackedRecords)?;
        if let Some(reordering) = self.options.reordering {
            self.time_on(reordering, base, settings, Variant::HitReordering)?;
        }
        let smaller = self.reprepped(base, PrepSettings { disk_scale: 0.7, ..PrepSettings::default() })?;
        self.time(&smaller, settings, Variant::SmallerDisks)?;
        let paper_radii = self.reprepped(base, paper_radius(PrepSettings::default()))?;
        self.time(&paper_radii, settings, Variant::PaperRadius)?;
        self.time(&with_triangle_proxies(base), settings, Variant::TriangleProxies)?;
        if model_primitives(base) > PER_BOX_ABLATION_MAX_POINTS {
            return Ok(());
        }
        self.time(base, settings, Variant::GeometryPerAabb)?;
        let cubes = self.reprepped(base, PrepSettings { boxes: BoxKind::Cube, ..PrepSettings::default() })?;
        self.time(&cubes, settings, Variant::CubeBoxes)?;
        let paper_cubes = self.reprepped(
            base,
            paper_radius(PrepSettings { boxes: BoxKind::Cube, ..PrepSettings::default() }),
        )?;
        self.time(&paper_cubes, &box_test, Variant::PaperConfiguration)?;
        let six = self.reprepped(base, PrepSettings { k: 6, ..PrepSettings::default() })?;
        self.time(&six, settings, Variant::SixNeighbours)
    }

    /// The scene with the model re-prepped with `options`.
    fn reprepped(&self, base: &Scene, options: PrepSettings) -> Result<Scene, BenchError> {
        let points = model_points(self.model, &self.options.data, &self.options.cache)?;
        let cloud = pointray_io::formats::read_point_cloud(&points)?;
        let (patches, _) = pointray_surface::prep(&cloud, &options, &NoProgress)
            .map_err(|source| BenchError::Prep { case: self.model.name.clone(), source })?;
        let mut scene = base.clone();
        if let Some(model) = scene.objects.first_mut() {
            model.geometry = Geometry::Patches(Arc::new(patches));
        }
        Ok(scene)
    }

    fn time(&mut self, scene: &Scene, settings: &RenderSettings, variant: Variant) -> Result<(), BenchError> {
        let output = if variant == Variant::AovOutput { PixelOutput::Aovs } else { PixelOutput::Display };
        let layout = variant_layout(variant, settings);
        let measured = measure(self.renderer, scene, settings, layout, output, self.options.frames);
        self.record(scene, settings, variant, measured)
    }

    /// As `time` with the default layout and output, on another renderer.
    fn time_on(
        &mut self,
        renderer: &VulkanRenderer,
        scene: &Scene,
        settings: &RenderSettings,
        variant: Variant,
    ) -> Result<(), BenchError> {
        let layout = variant_layout(variant, settings);
        let measured = measure(renderer, scene, settings, layout, PixelOutput::Display, self.options.frames);
        self.record(scene, settings, variant, measured)
    }

    fn record(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
        variant: Variant,
        measured: Result<Measurement, VulkanError>,
    ) -> Result<(), BenchError> {
        let (width, height) = (settings.width, settings.height);
        let case = format!("{} {width}x{height} {}", self.model.name, variant.label());
        let measured = measured.map_err(|source| BenchError::Vulkan { case, source })?;
        let label = CaseLabel {
            model: &self.model.name,
            stand_in: self.stand_in.clone(),
            variant,
            primitives: model_primitives(scene),
            paper_fps: (variant == Variant::Points).then(|| self.model.paper_fps_at(width, height)).flatten(),
        };
        let result = CaseResult::new(label, width, height, self.options.frames.timed, &measured);
        (self.options.on_case)(&result);
        self.cases.push(result);
        Ok(())
    }
}

impl BenchOptions<'_> {
    /// `settings` with this run's replacements.
    fn applied(&self, settings: RenderSettings) -> RenderSettings {
        RenderSettings {
            integrator: self.integrator.unwrap_or(settings.integrator),
            patches_per_box: self.patches_per_box.or(settings.patches_per_box),
            hot_records: self.hot_records.or(settings.hot_records),
            ..settings
        }
    }
}

/// How `variant` puts a scene traced with `settings` onto the GPU: as `render` would, but
/// for the ablations of the layout itself.
fn variant_layout(variant: Variant, settings: &RenderSettings) -> SceneLayout {
    let layout = SceneLayout::for_settings(settings);
    match variant {
        Variant::GeometryPerAabb => SceneLayout { blas: BlasLayout::GeometryPerAabb, ..layout },
        Variant::PackedRecords => SceneLayout { unpack_to_fit: false, ..layout },
        _ => layout,
    }
}

/// `scene` with each point set replaced by its triangle proxies, traced as a mesh.
fn with_triangle_proxies(scene: &Scene) -> Scene {
    let mut proxied = scene.clone();
    for object in &mut proxied.objects {
        if let Geometry::Patches(patches) = &object.geometry {
            object.geometry = Geometry::Mesh(Arc::new(triangle_proxies(patches)));
        }
    }
    proxied
}

fn paper_radius(settings: PrepSettings) -> PrepSettings {
    PrepSettings { radius: RadiusMode::Paper, ..settings }
}
