//! What the user changes while viewing: the camera, the lights and the render toggles.

use glam::{Quat, Vec3};
use pointray_scene::{Light, RenderSettings, Scene};

use crate::camera_rig::CameraRig;
use crate::controls::Action;

/// Deepest reflection path the keys allow.
const MAX_REFLECTION_DEPTH: u32 = 8;

pub(crate) struct ViewState {
    pub(crate) scene: Scene,
    pub(crate) settings: RenderSettings,
    pub(crate) rig: CameraRig,
    home: CameraRig,
    /// The depth reflections return to when toggled back on.
    reflection_depth: u32,
}

impl ViewState {
    pub(crate) fn new(scene: Scene, settings: RenderSettings) -> Self {
        let rig = CameraRig::from_camera(&scene.camera);
        let reflection_depth = settings.max_depth.max(2);
        Self { scene, settings, rig, home: rig, reflection_depth }
    }

    /// The scene with the rig's camera, as it should be rendered now.
    pub(crate) fn sync_camera(&mut self) {
        self.scene.camera = self.rig.camera();
    }

    /// Applies a view-changing action; says whether the image changes.
    pub(crate) fn apply(&mut self, action: Action) -> bool {
        match action {
            Action::ToggleShadows => self.settings.shadows = !self.settings.shadows,
            Action::ToggleReflections => {
                self.settings.max_depth = if self.settings.max_depth > 1 { 1 } else { self.reflection_depth }
            }
            Action::ReflectionDepth(change) => {
                self.reflection_depth =
                    (self.reflection_depth as i32 + change).clamp(2, MAX_REFLECTION_DEPTH as i32) as u32;
                self.settings.max_depth = self.reflection_depth;
            }
            Action::TurnLights(yaw, pitch) => self.turn_lights(yaw, pitch),
            Action::ResetCamera => self.rig = self.home,
            Action::Screenshot | Action::ToggleVsync | Action::Quit => return false,
        }
        println!(
            "shadows {}, max depth {}",
            if self.settings.shadows { "on" } else { "off" },
            self.settings.max_depth
        );
        true
    }

    fn turn_lights(&mut self, yaw_degrees: f32, pitch_degrees: f32) {
        let camera = self.rig.camera();
        let right = (camera.look_at - camera.position).cross(camera.up).normalize_or(Vec3::X);
        let turn = Quat::from_axis_angle(camera.up.normalize_or(Vec3::Y), yaw_degrees.to_radians())
            * Quat::from_axis_angle(right, pitch_degrees.to_radians());
        for light in &mut self.scene.lights {
            *light = turned(light, camera.look_at, turn);
        }
    }
}

/// A point or area light moves about `pivot`; a directional light turns its direction.
fn turned(light: &Light, pivot: Vec3, turn: Quat) -> Light {
    match *light {
        Light::Sphere { center, radius, color, intensity } => {
            Light::Sphere { center: pivot + turn * (center - pivot), radius, color, intensity }
        }
        Light::Quad { corner, edge_u, edge_v, color, intensity } => Light::Quad {
            corner: pivot + turn * (corner - pivot),
            edge_u: turn * edge_u,
            edge_v: turn * edge_v,
            color,
            intensity,
        },
        Light::Point { position, color, intensity, space_scale } => {
            Light::Point { position: pivot + turn * (position - pivot), color, intensity, space_scale }
        }
        Light::Directional { direction, color, intensity } => {
            Light::Directional { direction: turn * direction, color, intensity }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turning_keeps_the_light_distance_and_changes_its_place() {
        let light = Light::point(Vec3::new(2.0, 3.0, 0.0), Vec3::ONE, 1.0);
        let turn = Quat::from_axis_angle(Vec3::Y, 90f32.to_radians());
        let Light::Point { position, .. } = turned(&light, Vec3::ZERO, turn) else { panic!("kind changed") };
        assert!((position.length() - Vec3::new(2.0, 3.0, 0.0).length()).abs() < 1e-5);
        assert!(position.abs_diff_eq(Vec3::new(0.0, 3.0, -2.0), 1e-5), "{position:?}");
    }
}
