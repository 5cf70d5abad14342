//! One fidelity run: every view rendered twice (mesh, points) and compared.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;
use pointray_io::TriangleMesh;
use pointray_patches::PatchSet;
use pointray_scene::{PatchAcceptance, RenderSettings};

use crate::vertex_normals::VertexNormals;
use crate::view_images::write_view_images;
use crate::view_placement::{View, ViewSetting, place_views, validate_setting};
use crate::{
    ComparisonScenes, FidelityError, FidelityReport, FidelitySetup, ImageRenderer, PixelComparison,
    SensorPose, SensorVisibility, ViewReport, ViewSpec,
};

/// LiDAR scans (KITTI, nuScenes, LAS, E57) have z up.
pub const DEFAULT_UP: Vec3 = Vec3::Z;
/// The lens of explicit and `above` views: from 20 m up it takes in a street 23 m across.
pub const DEFAULT_FOV_DEGREES: f32 = 60.0;

#[derive(Clone, Debug, PartialEq)]
pub struct FidelityOptions {
    pub views: Vec<ViewSpec>,
    /// Images are this many pixels wide, and square but for sensor views.
    pub size: u32,
    pub acceptance: PatchAcceptance,
    /// The scan's up axis: `above` looks down it, sensor views level with it, and explicit
    /// views keep it up in the image.
    pub up: Vec3,
    /// The vertical field of view of explicit and `above` views.
    pub fov_degrees: f32,
    /// The scan's sensor, for sensor views and for counting only what it could see.
    pub sensor: Option<SensorPose>,
    /// Each view's images (`view_images`) go into this folder when given.
    pub image_folder: Option<PathBuf>,
    /// The centre of the points' bounds, which `above` views look down on. Without it, the
    /// centre of the bounds of the patches' centres, which a scan's patches cut back on one
    /// side move off their returns.
    pub points_centre: Option<Vec3>,
}

impl FidelityOptions {
    /// `views` cameras spread around the model (see `view_directions`).
    pub fn around(views: usize, size: u32, acceptance: PatchAcceptance) -> Result<Self, FidelityError> {
        let options = Self::with_views(vec![ViewSpec::Around { count: views }], size, acceptance);
        options.views[0].validate()?;
        Ok(options)
    }

    /// `views`, with the default up axis and lens and no sensor.
    pub fn with_views(views: Vec<ViewSpec>, size: u32, acceptance: PatchAcceptance) -> Self {
        Self {
            views,
            size,
            acceptance,
            up: DEFAULT_UP,
            fov_degrees: DEFAULT_FOV_DEGREES,
            sensor: None,
            image_folder: None,
            points_centre: None,
        }
    }

    /// Primary hits plus shadows: reflections would mix other parts of the model into a
    /// pixel and blur what the PSNR says about the surface under it.
    fn render_settings(&self, view: &View) -> RenderSettings {
        RenderSettings {
            width: view.width,
            height: view.height,
            samples_per_pixel: 1,
            max_depth: 1,
            shadows: true,
            acceptance: self.acceptance,
            ..RenderSettings::default()
        }
    }
}

/// Renders `mesh` and `patches` (prepped from points in the mesh's coordinates) from every
/// view in `options` with `renderer`, and compares them per view and pooled. Normals are
/// compared against the mesh's interpolated vertex normals (`VertexNormals`).
pub fn measure_fidelity(
    patches: Arc<PatchSet>,
    mesh: Arc<TriangleMesh>,
    options: &FidelityOptions,
    renderer: &dyn ImageRenderer,
) -> Result<FidelityReport, FidelityError> {
    validate_setting(options.up, options.fov_degrees, options.size)?;
    let started = Instant::now();
    let setup = FidelitySetup::describe(&patches, &mesh, options, renderer.name());
    let scenes = ComparisonScenes::new(patches, mesh.clone())?;
    let setting = ViewSetting {
        mesh_bounds: &scenes.bounds(),
        points_centre: options.points_centre.unwrap_or_else(|| scenes.points_centre()),
        up: options.up.normalize(),
        fov_degrees: options.fov_degrees,
        size: options.size,
        sensor: options.sensor.as_ref(),
    };
    let views = place_views(&options.views, &setting)?;
    if views.is_empty() {
        return Err(FidelityError::NoViews);
    }
    let normals = VertexNormals::angle_weighted(&mesh);
    let visibility = options.sensor.map(|sensor| {
        let mesh_scene = scenes.for_camera(views[0].camera).mesh;
        SensorVisibility::new(&mesh_scene, sensor, setting.up)
    });
    let mut pooled = PixelComparison::default();
    let truth = Truth { mesh: &mesh, normals: &normals, visibility: visibility.as_ref() };
    let mut reports = Vec::with_capacity(views.len());
    for (index, view) in views.into_iter().enumerate() {
        let comparison = compare_view(&scenes, &truth, &view, index, options, renderer)?;
        reports.push(ViewReport::new(view, comparison.metrics()));
        pooled.merge(comparison);
    }
    Ok(FidelityReport {
        setup,
        views: reports,
        overall: pooled.metrics(),
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// What the points are measured against: the mesh, its smooth normals and, for a scan, what
/// its sensor could see of it.
struct Truth<'a> {
    mesh: &'a TriangleMesh,
    normals: &'a VertexNormals,
    visibility: Option<&'a SensorVisibility>,
}

fn compare_view(
    scenes: &ComparisonScenes,
    truth: &Truth,
    view: &View,
    index: usize,
    options: &FidelityOptions,
    renderer: &dyn ImageRenderer,
) -> Result<PixelComparison, FidelityError> {
    let pair = scenes.for_camera(view.camera);
    let settings = options.render_settings(view);
    let render_error = |what| move |source| FidelityError::Render { what, view: index, source };
    let mut mesh_image = renderer.render(&pair.mesh, &settings).map_err(render_error("mesh"))?;
    truth.normals.smooth_image(&mut mesh_image, truth.mesh, &view.camera)?;
    let points_image = renderer.render(&pair.points, &settings).map_err(render_error("points"))?;
    let mut comparison = PixelComparison::of_images(&mesh_image, &points_image, scenes.diagonal())?;
    let seen = truth.visibility.map(|visibility| visibility.seen_pixels(&mesh_image, &view.camera));
    if let Some(seen) = &seen {
        comparison.count_seen(&points_image, seen);
    }
    if let Some(folder) = &options.image_folder {
        write_view_images(folder, index, &mesh_image, &points_image, seen.as_deref())?;
    }
    Ok(comparison)
}
