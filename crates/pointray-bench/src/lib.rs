//! `pointray bench`: the paper's Table 1 (and any scene) timed on the Vulkan renderer: GPU
//! timestamps per frame (trace and whole frame), rays and intersection-shader calls counted
//! on the GPU, build times and memory, the mesh limit and the ablations; the scale suite (1M
//! to 1B points: prep, memory, store, load and frame rate, on either backend); and LiDAR
//! re-simulation on the GPU (sweeps per second); reports as JSON and markdown.

pub mod case_result;
pub mod data;
pub mod error;
pub mod markdown;
pub mod measure;
pub mod model_scene;
pub mod output;
pub mod report;
pub mod resimulation;
pub mod run;
pub mod scale;
pub mod scale_fit;
pub mod scale_render;
pub mod scale_report;
pub mod stand_in;
pub mod stats;
pub mod suite;
pub mod triangle_proxies;

pub use case_result::{CaseResult, Variant};
pub use error::BenchError;
pub use measure::FrameCounts;
pub use output::{write_json, write_text};
pub use report::{LimitRow, Report};
pub use resimulation::{ResimOptions, ResimReport, resim_markdown, run_resimulation};
pub use run::{BenchOptions, run_scene_file, run_suite};
pub use scale::{ScaleOptions, run_scale};
pub use scale_render::ScaleBackend;
pub use scale_report::{ScaleReport, ScaleRow, scale_markdown};
pub use suite::Suite;
