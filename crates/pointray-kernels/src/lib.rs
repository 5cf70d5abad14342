//! The maths that the CPU renderer, the tests and the GLSL shaders share.
//!
//! Every function here has a twin of the same name in `shaders/NAME.glsl`; the file
//! `src/NAME.rs` and `shaders/NAME.glsl` describe the same maths. Change both together.

pub mod layout;

pub use layout::{Aabb, PatchCold, PatchHot};
