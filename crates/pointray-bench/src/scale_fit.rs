//! Whether a rung of the scale suite fits this machine: enough memory to prep it, disk for
//! its points and store, and a device that can hold and build it (in tiles where one BLAS
//! cannot hold it). A rung that does not fit
//! is skipped with the reason, before anything is generated.

use std::path::Path;

use pointray_io::MemoryBudget;
use pointray_io::disk_space::{file_system, free_bytes};
use pointray_kernels::{Aabb, PatchCold, PatchHot};
use pointray_patches::PrepSettings;
use pointray_surface::prep_memory::{PrepRoute, prep_route};
use pointray_vulkan::DeviceInfo;

/// Host memory per point of loading the store for the GPU, with a margin: a compact store's
/// records are decoded into the process's own memory (boxes, hot and cold records; a billion
/// points loaded at a peak of 96.3 GiB, the mapped 30.7 GB store included). Prep needs no
/// limit here: a cloud whose single pass does not fit the budget is prepped in tiles.
pub fn gpu_load_bytes_per_point() -> u64 {
    decoded_bytes_per_point() + 4
}

/// Scratch disk per point of prep in tiles at its largest, beside the points file and the
/// store: the points sorted along the curve (the sorted runs give their room back as the
/// merge reads them).
pub const STREAMED_SCRATCH_BYTES_PER_POINT: u64 = 36;

/// Peak memory of the process's own per point of loading the store and rendering on the CPU
/// backend, with a margin: the BVH build over the mapped store's patches; measured at 296
/// bytes on 10M points.
pub const CPU_RENDER_BYTES_PER_POINT: u64 = 320;

/// A stand-in's points file: binary PLY with float positions.
pub const POINTS_FILE_BYTES_PER_POINT: u64 = 12;

/// A patch store's bytes per point when the cloud has no colours, with a margin: the compact
/// records and the coarse level (30.71 at 100M and at 1B points).
pub const STORE_BYTES_PER_POINT: u64 = 32;

/// What a point set's decoded records take per patch: its boxes, hot and cold records.
fn decoded_bytes_per_point() -> u64 {
    (size_of::<Aabb>() + size_of::<PatchHot>() + size_of::<PatchCold>()) as u64
}

/// GPU memory per patch of a ready scene, which is also its peak while built: tiles are
/// split until one tile's build (boxes, uncompacted structure, scratch) takes no more than
/// the records uploaded after it. The hot records the trace reads (the suite's material does
/// not colour by the points, so the cold ones stay in memory) and the compacted BLAS, 20
/// bytes a patch on the devices measured so far, with a margin.
pub fn gpu_build_bytes_per_point() -> u64 {
    size_of::<PatchHot>() as u64 + 28
}

/// The limits that decide which rungs run.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineLimits {
    /// `MemAvailable` of `/proc/meminfo`, in bytes.
    pub available_memory: Option<u64>,
    /// The most memory per point any step takes: loading the store for the GPU, or
    /// rendering on the CPU.
    pub memory_per_point: u64,
    /// `pointray prep`'s default budget, which decides whether a rung is prepped in tiles
    /// (and so needs scratch disk).
    pub prep_budget: MemoryBudget,
    /// Free bytes on the cache folder's file system.
    pub free_disk: Option<u64>,
    /// Free bytes on the scratch folder's file system, where it is not the cache's.
    pub free_scratch: Option<u64>,
    /// The Vulkan device, when the suite renders on one.
    pub device: Option<DeviceLimits>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceLimits {
    pub device_local_bytes: u64,
    pub max_blas_primitives: u64,
}

impl From<&DeviceInfo> for DeviceLimits {
    fn from(info: &DeviceInfo) -> Self {
        Self { device_local_bytes: info.device_local_bytes, max_blas_primitives: info.max_blas_primitives }
    }
}

impl MachineLimits {
    /// This machine's limits now, for a suite caching in `cache` (which must exist), sorting
    /// prep's points in `scratch` (the cache when `None`) and rendering on `device`, or on the
    /// CPU when there is none.
    pub fn now((cache, scratch): (&Path, Option<&Path>), device: Option<DeviceLimits>) -> Self {
        let apart = scratch.filter(|&scratch| file_system(scratch) != file_system(cache));
        Self {
            available_memory: pointray_io::available_memory(),
            memory_per_point: memory_per_point(device.is_some()),
            prep_budget: MemoryBudget::half_of_this_machine(),
            free_disk: free_bytes(cache),
            free_scratch: apart.and_then(free_bytes),
            device,
        }
    }

    /// Why a rung of `points` points cannot run here; `None` when it fits. `cached_bytes` is
    /// what the rung already has in the cache (its points file), which needs no new room.
    pub fn why_not(&self, points: u64, cached_bytes: u64) -> Option<String> {
        let gigabytes = |bytes: u64| bytes as f64 / 1e9;
        let memory = points.saturating_mul(self.memory_per_point);
        if let Some(available) = self.available_memory.filter(|&available| memory > available) {
            let step = if self.device.is_some() { "loading the store" } else { "rendering on the CPU" };
            return Some(format!(
                "{step} needs about {:.1} GB of memory ({} B a point), {:.1} GB is available",
                gigabytes(memory),
                self.memory_per_point,
                gigabytes(available)
            ));
        }
        let streamed =
            prep_route(points, &PrepSettings::default(), 0, self.prep_budget) == PrepRoute::Streamed;
        let scratch = points.saturating_mul(if streamed { STREAMED_SCRATCH_BYTES_PER_POINT } else { 0 });
        if let Some(free) = self.free_scratch.filter(|&free| scratch > free) {
            return Some(format!(
                "prep's scratch files need {:.1} GB in the scratch folder, {:.1} GB is free",
                gigabytes(scratch),
                gigabytes(free)
            ));
        }
        let beside = if self.free_scratch.is_some() { 0 } else { scratch };
        let files = points.saturating_mul(POINTS_FILE_BYTES_PER_POINT + STORE_BYTES_PER_POINT);
        let disk = files.saturating_add(beside).saturating_sub(cached_bytes);
        if let Some(free) = self.free_disk.filter(|&free| disk > free) {
            return Some(format!(
                "its points file, patch store and prep's scratch files need {:.1} GB more disk in the cache folder, {:.1} GB is free",
                gigabytes(disk),
                gigabytes(free)
            ));
        }
        // Point sets beyond the device's BLAS primitive limit are split into tiles.
        let device = self.device?;
        let gpu = points.saturating_mul(gpu_build_bytes_per_point());
        (gpu > device.device_local_bytes).then(|| {
            format!(
                "building it needs about {:.1} GB of GPU memory ({} B a point), the device has {:.1} GB",
                gigabytes(gpu),
                gpu_build_bytes_per_point(),
                gigabytes(device.device_local_bytes)
            )
        })
    }
}

fn memory_per_point(gpu: bool) -> u64 {
    if gpu { gpu_load_bytes_per_point() } else { CPU_RENDER_BYTES_PER_POINT }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn machine(memory: u64, disk: u64, device: Option<DeviceLimits>) -> MachineLimits {
        MachineLimits {
            available_memory: Some(memory),
            memory_per_point: memory_per_point(device.is_some()),
            prep_budget: MemoryBudget { bytes: memory / 2 },
            free_disk: Some(disk),
            free_scratch: None,
            device,
        }
    }

    #[test]
    fn each_limit_names_itself() {
        let roomy = machine(1 << 40, 1 << 40, None);
        assert_eq!(roomy.why_not(1_000_000, 0), None);
        let reason = machine(24e9 as u64, 1 << 40, None).why_not(100_000_000, 0).expect("too little memory");
        assert!(reason.contains("rendering on the CPU needs about 32.0 GB"), "{reason}");
        let gpu = Some(DeviceLimits { device_local_bytes: 1 << 40, max_blas_primitives: u64::MAX });
        assert_eq!(
            machine(24e9 as u64, 1 << 40, gpu).why_not(100_000_000, 0),
            None,
            "prep fits, the GPU renders"
        );
        // A compact store's records are decoded on loading: a billion points take 72 GB,
        // which a 128 GiB machine holds and a 64 GB one does not.
        assert_eq!(machine(128 << 30, 1 << 40, gpu).why_not(1_000_000_000, 0), None);
        let reason = machine(64e9 as u64, 1 << 40, gpu).why_not(1_000_000_000, 0).expect("too little memory");
        assert!(reason.contains("loading the store needs about 72.0 GB"), "{reason}");
        // Prep in tiles needs scratch disk: 250M points take 11 GB prepped in memory (a
        // 128 GiB machine), 20 GB in tiles (a 64 GiB one).
        assert_eq!(machine(128 << 30, 15e9 as u64, gpu).why_not(250_000_000, 0), None);
        let reason = machine(64 << 30, 15e9 as u64, gpu).why_not(250_000_000, 0).expect("scratch");
        assert!(reason.contains("scratch"), "{reason}");
        let reason = machine(1 << 40, 40e9 as u64, None).why_not(1_000_000_000, 0).expect("too little disk");
        assert!(reason.contains("disk"), "{reason}");
        // A billion points on a 128 GiB machine with 64 GB of disk: streamed, their 44 GB of
        // points and store fit the disk, and their 36 GB of scratch fit a scratch folder
        // elsewhere with room, but not one without.
        let h200 = Some(DeviceLimits { device_local_bytes: 139 << 30, max_blas_primitives: (1 << 29) - 1 });
        let disk_only = machine(128 << 30, 64e9 as u64, h200);
        assert!(disk_only.why_not(1_000_000_000, 0).is_some_and(|reason| reason.contains("disk")));
        let in_memory_scratch = MachineLimits { free_scratch: Some(100e9 as u64), ..disk_only.clone() };
        assert_eq!(in_memory_scratch.why_not(1_000_000_000, 0), None);
        let small_scratch = MachineLimits { free_scratch: Some(30e9 as u64), ..disk_only };
        let reason = small_scratch.why_not(1_000_000_000, 0).expect("too little scratch");
        assert!(reason.contains("scratch folder"), "{reason}");
        let cached = 1_000_000_000 * POINTS_FILE_BYTES_PER_POINT;
        let small_blas = DeviceLimits { device_local_bytes: 1 << 40, max_blas_primitives: 16_777_215 };
        assert_eq!(
            machine(1 << 40, 1 << 40, Some(small_blas)).why_not(1_000_000_000, cached),
            None,
            "tiles take what one BLAS cannot"
        );
        let little_gpu = DeviceLimits { device_local_bytes: 1 << 30, max_blas_primitives: u64::MAX };
        let reason = machine(1 << 40, 1 << 40, Some(little_gpu)).why_not(100_000_000, 0).expect("GPU");
        assert!(reason.contains("GPU memory"), "{reason}");
        // The records and the compacted structures: a billion points fit an 80 GB card.
        let card = DeviceLimits { device_local_bytes: 80 << 30, max_blas_primitives: (1 << 29) - 1 };
        assert_eq!(machine(1 << 40, 1 << 40, Some(card)).why_not(1_000_000_000, cached), None);
    }

    #[test]
    fn this_machine_reports_its_memory_and_disk() {
        let limits = MachineLimits::now((Path::new("."), None), None);
        assert!(limits.available_memory.is_some_and(|bytes| bytes > 0), "{limits:?}");
        assert!(limits.free_disk.is_some(), "{limits:?}");
    }
}
