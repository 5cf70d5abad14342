//! Holes and seams as numbers: a point set's patches and the triangle mesh it came from are
//! rendered from the same cameras, and the two frames are compared pixel by pixel (hole rate,
//! false-surface rate, depth and normal error, PSNR of the shaded images).

pub mod comparison_scenes;
pub mod error;
pub mod frame_renderer;
pub mod measure;
pub mod metrics;
pub mod percentile;
pub mod pixel_comparison;
pub mod report;
pub mod report_json;
pub mod report_table;
pub mod view_directions;

pub use comparison_scenes::ComparisonScenes;
pub use error::FidelityError;
pub use frame_renderer::{CpuFrameRenderer, FrameRenderer, RenderError};
pub use measure::{FidelityOptions, measure_fidelity};
pub use metrics::FidelityMetrics;
pub use pixel_comparison::PixelComparison;
pub use report::{FidelityReport, FidelitySetup, ViewReport};
pub use view_directions::view_directions;
