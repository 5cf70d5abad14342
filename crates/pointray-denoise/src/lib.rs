//! A denoiser for previews: the edge-avoiding à-trous wavelet filter of Dammertz et al.
//! (HPG 2010), guided by the render's AOVs. Never on by default: the converged image is the
//! reference, and this only makes a few samples a pixel easier to look at.

mod a_trous;
mod edge_stops;

pub use a_trous::{DenoiseSettings, denoise};
