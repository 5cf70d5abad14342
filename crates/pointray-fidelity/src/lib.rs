//! Holes and seams as numbers: a point set's patches and the triangle mesh it came from are
//! rendered from the same cameras, and the two images are compared pixel by pixel (hole rate,
//! false-surface rate, depth and normal error, PSNR of the shaded images). For scans with no
//! mesh, each return's ray from its sensor is checked against the patches instead.

pub mod beam_spacing;
pub mod comparison_scenes;
pub mod consistency_report;
pub mod error;
pub mod image_difference;
pub mod image_renderer;
pub mod local_spacing;
pub mod measure;
pub mod metrics;
pub mod percentile;
pub mod pixel_comparison;
pub mod pixel_rays;
pub mod range_tolerance;
pub mod report;
pub mod report_json;
pub mod report_table;
pub mod return_origins;
pub mod sensor_pixel_consistency;
pub mod sensor_pose;
pub mod sensor_ray_consistency;
pub mod sensor_views;
pub mod sensor_visibility;
pub mod vertex_normals;
pub mod view_directions;
pub mod view_images;
pub mod view_placement;
pub mod view_spec;

pub use beam_spacing::{SupportReport, support_against_beam_spacing};
pub use comparison_scenes::ComparisonScenes;
pub use consistency_report::{ConsistencyCounts, ConsistencyReport};
pub use error::FidelityError;
pub use image_renderer::{CpuImageRenderer, ImageRenderer, RenderError};
pub use measure::{FidelityOptions, measure_fidelity};
pub use metrics::FidelityMetrics;
pub use pixel_comparison::{PixelComparison, SeenCounts};
pub use range_tolerance::RangeTolerance;
pub use report::{FidelityReport, FidelitySetup, ViewReport};
pub use return_origins::ReturnOrigins;
pub use sensor_pixel_consistency::PixelConsistency;
pub use sensor_pose::SensorPose;
pub use sensor_ray_consistency::{ConsistencyOptions, FirstHit, RayOutcome, sensor_ray_consistency};
pub use sensor_visibility::SensorVisibility;
pub use vertex_normals::VertexNormals;
pub use view_directions::view_directions;
pub use view_placement::View;
pub use view_spec::ViewSpec;
