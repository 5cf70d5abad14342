//! From a scene file to a `Scene`: read meshes, prep (or load from the cache) point sets,
//! build grounds and procedural objects, and place everything.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DAffine3, DVec3, Vec3};
use pointray_kernels::{Aabb, PatchCold};
use pointray_patches::geometry_range::{self, SCENE_EXTENTS, extent_problem};
use pointray_patches::{PatchSet, PrepSettings};
use pointray_surface::{NoProgress, PrepProgress};

use crate::checks;
use crate::error::{InvalidValue, SceneError};
use crate::ground::GroundPlacement;
use crate::material_spec::ColorSource;
use crate::object_spec::{ObjectSpec, ShapeSpec};
use crate::point_sets::{self, PointSetOrigin};
use crate::procedural;
use crate::render_space::{RenderSpace, WorldBounds, placed_bounds, recentred_mesh};
use crate::scene_file::SceneFile;
use crate::{Camera, Geometry, RenderSettings, Scene, SceneObject};

/// Without a `[camera]`, the objects are seen from the front (+Z), a little from the right and
/// above.
pub const DEFAULT_VIEW_DIRECTION: Vec3 = Vec3::new(0.35, 0.4, 1.0);
pub const DEFAULT_VFOV_DEGREES: f32 = 40.0;

#[derive(Clone, Copy)]
pub struct LoadOptions<'a> {
    /// Where point sets prepped from points files are cached. `None` preps them in memory on
    /// every load and writes nothing.
    pub cache_dir: Option<&'a Path>,
    pub progress: &'a dyn PrepProgress,
    /// Point sets already in memory (from a program, not a file), by object index: these
    /// points objects take them in place of reading their `path`, which then only names
    /// them in messages.
    pub in_memory: &'a [(usize, Arc<PatchSet>)],
}

impl Default for LoadOptions<'_> {
    fn default() -> Self {
        Self { cache_dir: None, progress: &NoProgress, in_memory: &[] }
    }
}

#[derive(Clone, Debug)]
pub struct LoadedScene {
    pub scene: Scene,
    /// `RenderSettings::default()` with the file's `[render]` table on top; command-line flags
    /// go on top of these.
    pub settings: RenderSettings,
    /// How each point-set object got its patches, by object index.
    pub point_sets: Vec<(usize, PointSetOrigin)>,
    /// Where the scene lies in the file's coordinates: it was recentred and scaled in f64
    /// (`RenderSpace::around`), so `file = origin + scale * scene`. Depths in a rendered space
    /// are in scene units: `scale` times them is file units.
    pub space: RenderSpace,
}

pub fn load_scene(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneError> {
    load_scene_file(&SceneFile::read(path)?, options)
}

pub fn load_scene_file(file: &SceneFile, options: &LoadOptions) -> Result<LoadedScene, SceneError> {
    let in_file = |invalid: InvalidValue| invalid.in_file(&file.path);
    let settings = file.render_settings()?;

    // Grounds are sized and placed from the other objects, so they are built last, but they
    // keep their place in the object list: renderers report object indices as instance ids.
    let is_ground = |spec: &ObjectSpec| matches!(spec.shape, ShapeSpec::Ground { .. });
    let mut slots: Vec<Option<(SceneObject, DAffine3)>> = vec![None; file.objects.len()];
    let mut point_sets = Vec::new();
    let mut loaded = LoadedPointSets::default();
    for (index, spec) in file.objects.iter().enumerate().filter(|(_, spec)| !is_ground(spec)) {
        let (object, placement, origin) =
            load_object(file, (index, spec), options, &mut loaded, (None, RenderSpace::FILE))?;
        point_sets.extend(origin.map(|origin| (index, origin)));
        slots[index] = Some((object, placement));
    }
    let bounds = slots.iter().flatten().filter_map(|(o, placement)| placed_bounds(&o.geometry, placement));
    let bounds = bounds.reduce(WorldBounds::union);
    if let Some(problem) =
        bounds.and_then(|b| extent_problem("the scene's objects", b.diagonal(), &SCENE_EXTENTS))
    {
        return Err(SceneError::Invalid { path: file.path.clone(), key: "objects".into(), problem });
    }
    let space = RenderSpace::around(bounds);
    for (object, placement) in slots.iter_mut().flatten() {
        object.transform = space.transform(placement);
    }
    let others =
        slots.iter().flatten().filter_map(|(object, _)| object.world_bounds()).reduce(|a, b| a.union(&b));
    for (index, spec) in file.objects.iter().enumerate().filter(|(_, spec)| is_ground(spec)) {
        let (mut ground, placement, _) =
            load_object(file, (index, spec), options, &mut loaded, (others.as_ref(), space))?;
        ground.transform = space.transform(&placement);
        slots[index] = Some((ground, placement));
    }
    let objects: Vec<SceneObject> = slots.into_iter().flatten().map(|(object, _)| object).collect();
    if objects.is_empty() {
        // A background alone is a scene, but rarely the one meant (a missing `[[objects]]`).
        tracing::warn!(
            "{}: the scene has no objects; the image shows only its background",
            file.path.display()
        );
    }

    let lights = file
        .lights
        .iter()
        .enumerate()
        .map(|(i, light)| light.to_light(&space).map_err(|e| e.within(&format!("lights[{i}]"))))
        .collect::<Result<_, _>>()
        .map_err(in_file)?;
    let camera = match &file.camera {
        Some(camera) => camera.to_camera(&space).map_err(|e| in_file(e.within("camera")))?,
        None => default_camera(others.as_ref(), &settings),
    };
    let background = file.background()?;
    Ok(LoadedScene { scene: Scene { camera, lights, background, objects }, settings, point_sets, space })
}

fn default_camera(bounds: Option<&Aabb>, settings: &RenderSettings) -> Camera {
    let unit_box = Aabb::new(Vec3::splat(-0.5), Vec3::splat(0.5));
    let aspect = settings.aspect();
    Scene::framing_camera(bounds.unwrap_or(&unit_box), DEFAULT_VIEW_DIRECTION, DEFAULT_VFOV_DEGREES, aspect)
}

/// The point sets a scene has read, so that objects naming one points file, prepped and read
/// alike, share one copy in memory: three copies of a billion-point store in a scene hold its
/// records once on the host.
#[derive(Default)]
struct LoadedPointSets(Vec<(PointSetKey, Arc<PatchSet>, PointSetOrigin)>);

/// What makes a points file's patches: the file, its prep and how it is read.
type PointSetKey = (PathBuf, Option<PrepSettings>, point_sets::ReadRequest);

impl LoadedPointSets {
    fn get(&self, key: &PointSetKey) -> Option<(Arc<PatchSet>, PointSetOrigin)> {
        let found = self.0.iter().find(|(loaded, ..)| loaded == key);
        found.map(|(_, patches, origin)| (patches.clone(), origin.clone()))
    }
}

/// Loads one object, with its local-to-file placement in f64, and says where a point set's
/// patches came from. A ground is fitted to `others`, the bounds of every other object in the
/// render space, the last member.
fn load_object(
    file: &SceneFile,
    (index, spec): (usize, &ObjectSpec),
    options: &LoadOptions,
    loaded: &mut LoadedPointSets,
    (others, space): (Option<&Aabb>, RenderSpace),
) -> Result<(SceneObject, DAffine3, Option<PointSetOrigin>), SceneError> {
    let key = object_key(index, spec);
    let transform =
        spec.transform.to_daffine().map_err(|e| e.within(&format!("{key}.transform")).in_file(&file.path))?;
    let in_material = |e: InvalidValue| e.within(&format!("{key}.material")).in_file(&file.path);
    let mut material = spec.material.to_material().map_err(in_material)?;
    let source = spec.material.color_source().map_err(in_material)?;
    let color_error = |problem: String| SceneError::Invalid {
        path: file.path.clone(),
        key: format!("{key}.material.color_source"),
        problem: format!("{}: {problem}", described_source(file, spec)),
    };
    check_color_source(source, &spec.shape).map_err(color_error)?;
    let (geometry, point_set_origin, default_name): LoadedGeometry = match &spec.shape {
        ShapeSpec::Mesh { path } => {
            let path = existing_file(file, &key, path)?;
            let mesh = pointray_io::formats::read_triangle_mesh(&path)
                .map_err(|source| SceneError::Input { scene: file.path.clone(), key: key.clone(), source })?;
            if let Some(vertex) = geometry_range::first_vertex_out_of_range(&mesh) {
                return Err(SceneError::Invalid {
                    path: file.path.clone(),
                    key: format!("{key}.path"),
                    problem: format!("{}: vertex {vertex} is not finite or out of range", path.display()),
                });
            }
            (Geometry::Mesh(Arc::new(mesh)), None, file_stem(&path))
        }
        ShapeSpec::Points { path, .. } if let Some(patches) = in_memory(options, index) => {
            (Geometry::Patches(patches.clone()), Some(PointSetOrigin::InMemory), path.display().to_string())
        }
        ShapeSpec::Points { path, prep, columns } => {
            let path = existing_file(file, &key, path)?;
            let read = point_sets::ReadRequest {
                columns: columns.clone(),
                classification_colors: source == ColorSource::Classification,
            };
            let point_set = (path.clone(), *prep, read);
            let (patches, origin) = match loaded.get(&point_set) {
                Some(shared) => shared,
                None => {
                    let (patches, origin) =
                        point_sets::load_points_file(&path, prep.as_ref(), &point_set.2, options)
                            .map_err(|e| e.in_scene(&file.path, &key))?;
                    let patches = Arc::new(patches);
                    loaded.0.push((point_set, patches.clone(), origin.clone()));
                    (patches, origin)
                }
            };
            (Geometry::Patches(patches), Some(origin), file_stem(&path))
        }
        ShapeSpec::SpherePoints { center, radius, count } => {
            procedural_fits(*count).map_err(|e| e.in_scene(&file.path, &key))?;
            let cloud = procedural::sphere_points(Vec3::from(*center), *radius, *count);
            procedural_object(&cloud, "sphere", options).map_err(|e| e.in_scene(&file.path, &key))?
        }
        ShapeSpec::TorusPoints { center, major_radius, minor_radius, count } => {
            procedural_fits(*count).map_err(|e| e.in_scene(&file.path, &key))?;
            let cloud = procedural::torus_points(Vec3::from(*center), *major_radius, *minor_radius, *count);
            procedural_object(&cloud, "torus", options).map_err(|e| e.in_scene(&file.path, &key))?
        }
        &ShapeSpec::Ground { auto, height, size } => {
            let in_space = |value: f64, name: &str| {
                checks::placeable(name, DVec3::splat(value))
                    .map(|v| v.x)
                    .map_err(|e| e.within(&key).in_file(&file.path))
            };
            let height = height
                .map(|h| in_space((f64::from(h) - space.origin.y) / space.scale, "height"))
                .transpose()?;
            let size = size.map(|s| in_space(f64::from(s) / space.scale, "size")).transpose()?;
            let mesh = GroundPlacement::new(others, auto, height, size).mesh();
            (Geometry::Mesh(Arc::new(mesh)), None, "ground".to_string())
        }
    };
    let source = resolved_color_source(source, &geometry);
    material.use_point_colors = source != ColorSource::Fixed;
    let ramp = spec.material.ramp(source).map_err(in_material)?;
    // The ramp's colours go into the patches' cold records, where both renderers already
    // read point colours.
    let geometry = match (geometry, ramp) {
        (Geometry::Patches(mut patches), Some(ramp)) => {
            let values = match source {
                ColorSource::Height => heights(&patches, &transform),
                _ => intensities(&patches).map_err(|problem| color_error(problem.into()))?,
            };
            let recolored = Arc::make_mut(&mut patches);
            ramp.recolor(&mut recolored.cold, values);
            // The stored coarse level holds the points' own colours; the renderer makes one
            // of the ramp's.
            recolored.coarse = None;
            Geometry::Patches(patches)
        }
        (geometry, _) => geometry,
    };
    let (geometry, local_to_model) = match geometry {
        // prep recentred the points (`input = local + offset`); put them back where they were.
        Geometry::Patches(patches) => {
            let offset = DAffine3::from_translation(patches.offset);
            (Geometry::Patches(patches), offset)
        }
        // A ground is built in the render space.
        Geometry::Mesh(mesh) if matches!(spec.shape, ShapeSpec::Ground { .. }) => {
            (Geometry::Mesh(mesh), space.to_file())
        }
        Geometry::Mesh(mesh) => {
            let (mesh, offset) = recentred_mesh(Arc::unwrap_or_clone(mesh));
            (Geometry::Mesh(Arc::new(mesh)), DAffine3::from_translation(offset))
        }
    };
    let placement = transform * local_to_model;
    let name = spec.name.clone().unwrap_or(default_name);
    let object = SceneObject { name, transform: RenderSpace::FILE.transform(&placement), material, geometry };
    Ok((object, placement, point_set_origin))
}

/// Refuses a colour source the object cannot give: only point sets have point colours to
/// replace, and only points files have classifications.
fn check_color_source(source: ColorSource, shape: &ShapeSpec) -> Result<(), String> {
    let name = match source {
        ColorSource::Fixed | ColorSource::Points | ColorSource::Auto => return Ok(()),
        ColorSource::Intensity => "intensity",
        ColorSource::Height => "height",
        ColorSource::Classification => "classification",
    };
    let kind = shape.type_name();
    match shape {
        ShapeSpec::Mesh { .. } | ShapeSpec::Ground { .. } => {
            Err(format!("`color_source = \"{name}\"` applies to point sets, not a {kind} object"))
        }
        ShapeSpec::SpherePoints { .. } | ShapeSpec::TorusPoints { .. }
            if source == ColorSource::Classification =>
        {
            Err(format!(
                "a {kind} object has no classification, which `color_source = \"classification\"` needs"
            ))
        }
        _ => Ok(()),
    }
}

fn in_memory<'a>(options: &LoadOptions<'a>, index: usize) -> Option<&'a Arc<PatchSet>> {
    options.in_memory.iter().find(|(object, _)| *object == index).map(|(_, patches)| patches)
}

/// `"auto"` as the geometry allows: colours where a point set has any (white everywhere is
/// what prep stores for none), else intensities, else the material's own colour.
fn resolved_color_source(source: ColorSource, geometry: &Geometry) -> ColorSource {
    match (source, geometry) {
        (ColorSource::Auto, Geometry::Patches(patches)) => {
            let white = PatchCold::default().color_rgba8;
            if patches.cold.iter().any(|record| record.color_rgba8 != white) {
                ColorSource::Points
            } else if has_intensities(patches) {
                ColorSource::Intensity
            } else {
                ColorSource::Fixed
            }
        }
        (ColorSource::Auto, _) => ColorSource::Fixed,
        (source, _) => source,
    }
}

/// The readers report an all-zero intensity field as absent, and prep stores 0 for absent.
fn has_intensities(patches: &PatchSet) -> bool {
    patches.cold.iter().any(|record| record.intensity != 0.0)
}

fn intensities(patches: &PatchSet) -> Result<Vec<f32>, &'static str> {
    if !has_intensities(patches) {
        return Err("the points have no intensity, or every intensity is 0 (prep stores 0 for none, \
                    so the two are one), which `color_source = \"intensity\"` needs; use \"points\", \
                    \"height\" or \"fixed\"");
    }
    Ok(patches.cold.iter().map(|record| record.intensity).collect())
}

/// Each patch's height in the world (Y, after the object's transform) as a fraction of the
/// object's vertical extent, 0 at its lowest point and 1 at its highest; computed in f64, as
/// geo-referenced offsets are large. A flat object is all 0.5.
fn heights(patches: &PatchSet, transform: &DAffine3) -> Vec<f32> {
    let matrix = transform.matrix3;
    let y_row = DVec3::new(matrix.x_axis.y, matrix.y_axis.y, matrix.z_axis.y);
    let world_y = |local: Vec3| y_row.dot(local.as_dvec3() + patches.offset) + transform.translation.y;
    let heights: Vec<f64> = patches.hot.iter().map(|hot| world_y(hot.origin())).collect();
    let (low, high) =
        heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), &h| (low.min(h), high.max(h)));
    let span = high - low;
    heights.iter().map(|&h| if span > 0.0 { ((h - low) / span) as f32 } else { 0.5 }).collect()
}

/// The object's points file, or its type when it has none: for messages.
fn described_source(file: &SceneFile, spec: &ObjectSpec) -> String {
    match &spec.shape {
        ShapeSpec::Points { path, .. } | ShapeSpec::Mesh { path } => file.resolve(path).display().to_string(),
        shape => format!("a {} object", shape.type_name()),
    }
}

/// The parts `load_object` needs: geometry, where its patches came from, a default name.
type LoadedGeometry = (Geometry, Option<PointSetOrigin>, String);

fn procedural_object(
    cloud: &pointray_io::PointCloud,
    name: &str,
    options: &LoadOptions,
) -> Result<LoadedGeometry, point_sets::PointSetError> {
    let patches = point_sets::prep_in_memory(cloud, options)?;
    Ok((Geometry::Patches(Arc::new(patches)), Some(PointSetOrigin::Procedural), name.to_string()))
}

/// Whether sampling and prepping `count` procedural points fits in memory, asked before
/// sampling them.
fn procedural_fits(count: u32) -> Result<(), point_sets::PointSetError> {
    let budget = pointray_io::MemoryBudget::of_this_machine();
    pointray_surface::input_validation::validate_size(count as usize, &Default::default(), 0, &budget)
        .map_err(|source| point_sets::PointSetError::Prep { file: "(procedural points)".into(), source })
}

fn object_key(index: usize, spec: &ObjectSpec) -> String {
    format!("objects[{index}] (type \"{}\")", spec.shape.type_name())
}

/// The file's path resolved against the scene's folder; an error naming it when it is missing,
/// a folder or a device.
fn existing_file(file: &SceneFile, key: &str, relative: &Path) -> Result<std::path::PathBuf, SceneError> {
    let path = file.resolve(relative);
    pointray_io::ensure_readable_file(&path).map_err(|source| SceneError::Input {
        scene: file.path.clone(),
        key: format!("{key}.path"),
        source,
    })?;
    Ok(path)
}

fn file_stem(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}
