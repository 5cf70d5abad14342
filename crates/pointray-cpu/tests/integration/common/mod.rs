//! Hand-built scenes for the renderer tests (`pointray_test_support::analytic_scenes`):
//! analytic patches, so that each test knows exactly where the surface is.

pub use pointray_test_support::analytic_scenes::*;
