//! One fidelity run: every view rendered twice (mesh, points) and compared.

use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;
use pointray_io::TriangleMesh;
use pointray_scene::{PatchAcceptance, RenderSettings};
use pointray_surface::PatchSet;

use crate::view_directions::view_directions;
use crate::{
    ComparisonScenes, FidelityError, FidelityReport, FidelitySetup, FrameRenderer, PixelComparison,
    ViewReport,
};

#[derive(Clone, Debug, PartialEq)]
pub struct FidelityOptions {
    /// From the model's centre toward each camera.
    pub directions: Vec<Vec3>,
    /// Square images of this many pixels a side.
    pub size: u32,
    pub acceptance: PatchAcceptance,
}

impl FidelityOptions {
    /// `views` cameras spread around the model (see `view_directions`).
    pub fn around(views: usize, size: u32, acceptance: PatchAcceptance) -> Result<Self, FidelityError> {
        Ok(Self { directions: view_directions(views)?, size, acceptance })
    }

    /// Primary hits plus shadows: reflections would mix other parts of the model into a
    /// pixel and blur what the PSNR says about the surface under it.
    fn render_settings(&self) -> RenderSettings {
        RenderSettings {
            width: self.size,
            height: self.size,
            samples_per_pixel: 1,
            max_depth: 1,
            shadows: true,
            acceptance: self.acceptance,
            ..RenderSettings::default()
        }
    }
}

/// Renders `mesh` and `patches` (prepped from points in the mesh's coordinates) from every
/// direction in `options` with `renderer`, and compares them per view and pooled.
pub fn measure_fidelity(
    patches: Arc<PatchSet>,
    mesh: Arc<TriangleMesh>,
    options: &FidelityOptions,
    renderer: &dyn FrameRenderer,
) -> Result<FidelityReport, FidelityError> {
    if options.directions.is_empty() {
        return Err(FidelityError::TooFewViews { requested: 0, minimum: 1 });
    }
    if options.size == 0 {
        return Err(FidelityError::EmptyImage(options.size));
    }
    let started = Instant::now();
    let setup = FidelitySetup::describe(&patches, &mesh, options, renderer.name());
    let scenes = ComparisonScenes::new(patches, mesh)?;
    let settings = options.render_settings();
    let mut pooled = PixelComparison::default();
    let mut views = Vec::with_capacity(options.directions.len());
    for (index, &direction) in options.directions.iter().enumerate() {
        let comparison = compare_view(&scenes, direction, index, &settings, renderer)?;
        views.push(ViewReport { direction: direction.to_array(), metrics: comparison.metrics() });
        pooled.merge(comparison);
    }
    Ok(FidelityReport { setup, views, overall: pooled.metrics(), seconds: started.elapsed().as_secs_f64() })
}

fn compare_view(
    scenes: &ComparisonScenes,
    direction: Vec3,
    view: usize,
    settings: &RenderSettings,
    renderer: &dyn FrameRenderer,
) -> Result<PixelComparison, FidelityError> {
    let pair = scenes.for_view(direction);
    let mesh = renderer.render(&pair.mesh, settings).map_err(|source| FidelityError::Render {
        what: "mesh",
        view,
        source,
    })?;
    let points = renderer.render(&pair.points, settings).map_err(|source| FidelityError::Render {
        what: "points",
        view,
        source,
    })?;
    PixelComparison::of_frames(&mesh, &points, scenes.diagonal())
}
