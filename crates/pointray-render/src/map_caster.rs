//! Rays cast into a prepped map on the chosen backend, for LiDAR re-simulation: through the
//! CPU renderer's BVHs (`LidarScene`), or as a Vulkan ray list into the map uploaded once.

use std::sync::{Arc, Mutex, PoisonError};

use glam::{Affine3A, DVec3};
use pointray_kernels::Ray;
use pointray_lidar::{LidarError, LidarScene, MapCaster, SENSOR_ACCEPTANCE, map_scene};
use pointray_patches::PatchSet;
use pointray_vulkan::{
    ListedRay, PreparedScene, RayHit, RayListTarget, RayPose, TraceTiming, VulkanRenderer,
};
use rayon::prelude::*;

use crate::backend::Backend;
use crate::error::BackendError;

/// A map on a Vulkan device, cast into by ray lists.
pub struct GpuMapCaster<'a> {
    renderer: &'a VulkanRenderer,
    map: PreparedScene,
    /// The patches' offset: the map's coordinates of the prepared scene's origin.
    centre: DVec3,
    target: Mutex<RayListTarget>,
    last_timing: Mutex<Option<TraceTiming>>,
}

impl<'a> GpuMapCaster<'a> {
    /// Uploads `patches` to `renderer`'s device and builds their acceleration structures.
    pub fn new(renderer: &'a VulkanRenderer, patches: Arc<PatchSet>) -> Result<Self, BackendError> {
        let centre = patches.offset;
        let map = renderer.prepare(&map_scene(patches))?;
        Ok(Self {
            renderer,
            map,
            centre,
            target: Mutex::new(RayListTarget::new()),
            last_timing: Mutex::new(None),
        })
    }

    /// How long the last cast took: on the GPU, and in all (upload and read-back included).
    pub fn last_timing(&self) -> Option<TraceTiming> {
        *self.last_timing.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

impl MapCaster for GpuMapCaster<'_> {
    fn centre(&self) -> DVec3 {
        self.centre
    }

    fn cast(&self, rays: &[Ray], poses: &[Affine3A], max_range: f32) -> Result<Vec<Option<f32>>, LidarError> {
        let listed: Vec<ListedRay> = rays.par_iter().map(|ray| ListedRay::new(ray, 0.0, max_range)).collect();
        let poses: Vec<RayPose> = poses.iter().map(RayPose::new).collect();
        let mut target = self.target.lock().unwrap_or_else(PoisonError::into_inner);
        let timing = self
            .renderer
            .cast_rays(&self.map, &listed, &poses, SENSOR_ACCEPTANCE, &mut target)
            .map_err(|error| LidarError::Cast(Box::new(error)))?;
        *self.last_timing.lock().unwrap_or_else(PoisonError::into_inner) = Some(timing);
        Ok(target.hits().par_iter().map(RayHit::distance).collect())
    }
}

impl Backend {
    /// A caster into the prepped map `patches` on this backend: its patches uploaded to the
    /// Vulkan device, or the CPU renderer's BVHs built over them.
    pub fn map_caster(&self, patches: Arc<PatchSet>) -> Result<Box<dyn MapCaster + '_>, BackendError> {
        Ok(match self {
            Backend::Vulkan(renderer) => Box::new(GpuMapCaster::new(renderer, patches)?),
            Backend::Cpu => Box::new(
                LidarScene::from_patches(patches).map_err(|error| BackendError::Lidar(Box::new(error)))?,
            ),
        })
    }
}
