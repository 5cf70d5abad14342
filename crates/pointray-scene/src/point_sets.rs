//! Point sets for the scene: patch stores load as they are; points files go through `prep`,
//! whose result is cached as a patch store in a folder the caller names (never next to the
//! input, which may be read-only or shared).
//!
//! A cache file is `<cache_dir>/<stem>-<key>.patches`, where the key hashes the input's
//! canonical path, size, modification time and contents, how it is read (column spec,
//! classification colours), the prep options, prep's revision and this crate's version, so
//! that a changed input or setting never reuses a stale result, even a different input given
//! the old one's size and time (`cp -p`, `rsync -t`, `touch -r`). A cache file that cannot be
//! read (truncated, corrupted, from another format version) is regenerated.

use std::io::Read;
use std::path::{Path, PathBuf};

use pointray_io::PointCloud;
use pointray_io::formats::ColumnSpec;
use pointray_patches::patch_store::{self, StoreError};
use pointray_patches::{PatchSet, PrepSettings};
use pointray_surface::{PrepError, prep, prep_owned};

use crate::cache_folder;
use crate::classification_palette::classification_color;
use crate::error::SceneError;
use crate::load::LoadOptions;

/// How a points file is read before prep; it changes the points, so it is part of the
/// cache key.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadRequest {
    /// What each column holds, for files that do not name their columns (text, raw `.bin`).
    pub columns: Option<ColumnSpec>,
    /// Colour the points by their classification (ASPRS palette) instead of their RGB.
    pub classification_colors: bool,
}

/// Where a point set's patches came from.
#[derive(Clone, Debug, PartialEq)]
pub enum PointSetOrigin {
    /// The input was a patch store.
    PatchStore,
    /// Sampled on an analytic surface and prepped in memory.
    Procedural,
    /// Prepped now; `cache` is the file it was written to, if caching was asked for.
    Prepped { cache: Option<PathBuf> },
    /// Given in memory by the program that loads the scene (`LoadOptions::in_memory`).
    InMemory,
    /// Read from a valid cache file; prep did not run.
    CacheHit { cache: PathBuf },
    /// The cache file was unreadable (`problem`), so prep ran and replaced it.
    CacheRegenerated { cache: PathBuf, problem: String },
}

/// Why a point set could not be loaded; `in_scene` names the scene file and object.
#[derive(Debug)]
pub(crate) enum PointSetError {
    Input(pointray_io::IoError),
    Prep { file: PathBuf, source: PrepError },
    Store(StoreError),
    CacheDir { path: PathBuf, source: std::io::Error },
    StoreWithPrepSettings { file: PathBuf },
    NoClassifications { file: PathBuf },
}

impl PointSetError {
    pub fn in_scene(self, scene: &Path, key: &str) -> SceneError {
        let (scene, key) = (scene.to_path_buf(), key.to_string());
        match self {
            Self::Input(source) => SceneError::Input { scene, key, source },
            Self::Prep { file, source } => SceneError::Prep { scene, key, file, source },
            Self::Store(source) => SceneError::PatchStore { scene, key, source },
            Self::CacheDir { path, source } => SceneError::CacheDir { path, source },
            Self::StoreWithPrepSettings { file } => SceneError::Invalid {
                path: scene,
                key,
                problem: format!(
                    "{}: is a patch store, already prepped: `prep`, `columns` and \
                     `color_source = \"classification\"` apply only to points files",
                    file.display()
                ),
            },
            Self::NoClassifications { file } => SceneError::Invalid {
                path: scene,
                key: format!("{key}.material.color_source"),
                problem: format!(
                    "{}: the points have no classification, which `color_source = \
                     \"classification\"` needs (LAS, or a `classification` field or column); use \
                     \"points\", \"intensity\", \"height\" or \"fixed\"",
                    file.display()
                ),
            },
        }
    }
}

/// Loads a patch store, or reads a points file as `read` says and preps it with `settings`
/// (the defaults when `None`) through the cache in `options.cache_dir`.
pub(crate) fn load_points_file(
    path: &Path,
    settings: Option<&PrepSettings>,
    read: &ReadRequest,
    options: &LoadOptions,
) -> Result<(PatchSet, PointSetOrigin), PointSetError> {
    if is_patch_store(path) {
        if settings.is_some() || *read != ReadRequest::default() {
            return Err(PointSetError::StoreWithPrepSettings { file: path.to_path_buf() });
        }
        return Ok((patch_store::read(path).map_err(PointSetError::Store)?, PointSetOrigin::PatchStore));
    }
    let settings = settings.copied().unwrap_or_default();
    let Some(cache_dir) = options.cache_dir else {
        let patches = stored(&prep_file(path, &settings, read, options)?, path)?;
        return Ok((patches, PointSetOrigin::Prepped { cache: None }));
    };
    let cache = cache_dir.join(cache_file_name(path, &settings, read).map_err(PointSetError::Input)?);
    let regenerated_because = match patch_store::read(&cache) {
        Ok(patches) => return Ok((patches, PointSetOrigin::CacheHit { cache })),
        Err(StoreError::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => None,
        Err(problem) => {
            tracing::warn!("{problem}; regenerating it");
            Some(problem.to_string())
        }
    };
    let prepped = prep_file(path, &settings, read, options)?;
    // Made only now, so that a failed load leaves no empty cache folder behind.
    cache_folder::make(cache_dir)
        .map_err(|source| PointSetError::CacheDir { path: cache_dir.to_path_buf(), source })?;
    patch_store::write(&cache, &prepped).map_err(PointSetError::Store)?;
    drop(prepped);
    let name = cache.file_name().map(|name| name.to_string_lossy().into_owned()).unwrap_or_default();
    cache_folder::record(cache_dir, &name)
        .map_err(|source| PointSetError::CacheDir { path: cache_dir.to_path_buf(), source })?;
    // The patches as the compact store holds them, so that a scene renders the same whether
    // its cache was there or not.
    let patches = patch_store::read(&cache).map_err(PointSetError::Store)?;
    let origin = match regenerated_because {
        Some(problem) => PointSetOrigin::CacheRegenerated { cache, problem },
        None => PointSetOrigin::Prepped { cache: Some(cache) },
    };
    Ok((patches, origin))
}

/// Preps a procedural cloud with default settings; nothing is cached, since sampling and prep
/// are cheap at demo sizes.
pub(crate) fn prep_in_memory(cloud: &PointCloud, options: &LoadOptions) -> Result<PatchSet, PointSetError> {
    let file = PathBuf::from("(procedural points)");
    let (patches, _report) = prep(cloud, &PrepSettings::default(), options.progress)
        .map_err(|source| PointSetError::Prep { file: file.clone(), source })?;
    stored(&patches, &file)
}

/// `patches` as a patch store holds them, as every point set the loader gives is: a scene
/// renders the same whether its points were prepped now or read from a store or the cache.
fn stored(patches: &PatchSet, source: &Path) -> Result<PatchSet, PointSetError> {
    patch_store::as_stored(patches, source).map_err(PointSetError::Store)
}

fn prep_file(
    path: &Path,
    settings: &PrepSettings,
    read: &ReadRequest,
    options: &LoadOptions,
) -> Result<PatchSet, PointSetError> {
    let mut cloud = pointray_io::formats::read_point_cloud_with(path, read.columns.as_ref())
        .map_err(PointSetError::Input)?;
    if read.classification_colors {
        let classes = cloud
            .classifications
            .as_ref()
            .ok_or(PointSetError::NoClassifications { file: path.to_path_buf() })?;
        cloud.colors = Some(classes.iter().map(|&class| classification_color(class)).collect());
    }
    let (patches, report) = prep_owned(cloud, settings, options.progress)
        .map_err(|source| PointSetError::Prep { file: path.to_path_buf(), source })?;
    tracing::info!("prepped {}:\n{report}", path.display());
    Ok(patches)
}

/// Recognised by content, so that a store renamed to any extension still loads as one.
fn is_patch_store(path: &Path) -> bool {
    let mut magic = [0u8; 8];
    std::fs::File::open(path).and_then(|mut file| file.read_exact(&mut magic)).is_ok()
        && magic == patch_store::MAGIC
}

fn cache_file_name(
    input: &Path,
    settings: &PrepSettings,
    read: &ReadRequest,
) -> Result<String, pointray_io::IoError> {
    let os_error = |source| pointray_io::IoError::os(input, source);
    let canonical = input.canonicalize().map_err(os_error)?;
    let metadata = std::fs::metadata(&canonical).map_err(os_error)?;
    let modified = metadata
        .modified()
        .ok()
        .and_then(|time| time.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |since| since.as_nanos());
    let mut key = Fnv1a::default();
    key.write(canonical.as_os_str().as_encoded_bytes());
    key.write(&metadata.len().to_le_bytes());
    key.write(&modified.to_le_bytes());
    key.write(&content_checksum(&canonical).map_err(os_error)?.to_le_bytes());
    // Debug covers every setting, including ones added later, without listing them here.
    key.write(format!("{settings:?}").as_bytes());
    // Left out when default, so that caches of files read the plain way stay valid.
    if *read != ReadRequest::default() {
        key.write(format!("{read:?}").as_bytes());
    }
    key.write(&pointray_surface::PREP_REVISION.to_le_bytes());
    key.write(env!("CARGO_PKG_VERSION").as_bytes());
    let stem = input.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    Ok(format!("{stem}-{:016x}.patches", key.0))
}

/// The CRC-32 of every byte of the file at `path`. It reads the whole input on every load,
/// at the speed of the disk or page cache: on a 2-core machine, 0.2 s for 1 GB from the page
/// cache, where prepping a PLY of that size (83M points) takes about 5 minutes (3.4 s for 1M
/// points), and a cache hit reads the store, which is larger.
fn content_checksum(path: &Path) -> std::io::Result<u32> {
    let mut file = std::fs::File::open(path)?;
    let mut hasher = crc32fast::Hasher::new();
    let mut buffer = vec![0; 1 << 20];
    loop {
        match file.read(&mut buffer) {
            Ok(0) => return Ok(hasher.finalize()),
            Ok(read) => hasher.update(&buffer[..read]),
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => {}
            Err(error) => return Err(error),
        }
    }
}

/// 64-bit FNV-1a: a hash that stays the same across builds and platforms (std's
/// `DefaultHasher` promises neither), which a cache key on disk needs.
struct Fnv1a(u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    /// Hashes the length first, so that ("ab", "c") and ("a", "bc") differ.
    fn write(&mut self, bytes: &[u8]) {
        for &byte in (bytes.len() as u64).to_le_bytes().iter().chain(bytes) {
            self.0 = (self.0 ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
}
