//! The keyboard: which key does what, and the list printed at start.

use std::collections::HashSet;

use glam::Vec3;
use winit::keyboard::KeyCode;

/// A key press that changes the view or does something once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Action {
    ToggleShadows,
    ToggleReflections,
    /// Changes the reflection depth by this many segments.
    ReflectionDepth(i32),
    /// Turns the lights by (yaw, pitch) degrees about the look-at point.
    TurnLights(f32, f32),
    ResetCamera,
    Screenshot,
    ToggleVsync,
    Quit,
}

pub const KEY_HELP: &str = "\
pointray view keys:
  left drag        orbit            right/middle drag  pan
  wheel            zoom             W A S D / Q E      fly (forward, left, back, right / down, up)
  H                shadows on/off   F                  reflections on/off
  + / -            reflection depth arrows             move the light
  R                reset camera     P                  save a PNG screenshot
  V                vsync on/off     Esc                quit";

/// Degrees the lights turn per arrow key press.
const LIGHT_STEP_DEGREES: f32 = 15.0;

pub(crate) fn action_for(key: KeyCode) -> Option<Action> {
    Some(match key {
        KeyCode::KeyH => Action::ToggleShadows,
        KeyCode::KeyF => Action::ToggleReflections,
        KeyCode::Equal | KeyCode::NumpadAdd => Action::ReflectionDepth(1),
        KeyCode::Minus | KeyCode::NumpadSubtract => Action::ReflectionDepth(-1),
        KeyCode::ArrowLeft => Action::TurnLights(-LIGHT_STEP_DEGREES, 0.0),
        KeyCode::ArrowRight => Action::TurnLights(LIGHT_STEP_DEGREES, 0.0),
        KeyCode::ArrowUp => Action::TurnLights(0.0, LIGHT_STEP_DEGREES),
        KeyCode::ArrowDown => Action::TurnLights(0.0, -LIGHT_STEP_DEGREES),
        KeyCode::KeyR => Action::ResetCamera,
        KeyCode::KeyP => Action::Screenshot,
        KeyCode::KeyV => Action::ToggleVsync,
        KeyCode::Escape => Action::Quit,
        _ => return None,
    })
}

/// The flight direction (right, up, forward) of the held keys; zero when none is held.
pub(crate) fn fly_direction(held: &HashSet<KeyCode>) -> Vec3 {
    let axis = |minus: KeyCode, plus: KeyCode| {
        held.contains(&plus) as i32 as f32 - held.contains(&minus) as i32 as f32
    };
    Vec3::new(
        axis(KeyCode::KeyA, KeyCode::KeyD),
        axis(KeyCode::KeyQ, KeyCode::KeyE),
        axis(KeyCode::KeyS, KeyCode::KeyW),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opposite_keys_cancel_and_wasd_map_to_axes() {
        let held: HashSet<KeyCode> = [KeyCode::KeyW, KeyCode::KeyA, KeyCode::KeyQ, KeyCode::KeyE].into();
        assert_eq!(fly_direction(&held), Vec3::new(-1.0, 0.0, 1.0));
        assert_eq!(fly_direction(&HashSet::new()), Vec3::ZERO);
    }

    #[test]
    fn every_listed_action_has_a_key() {
        assert_eq!(action_for(KeyCode::KeyR), Some(Action::ResetCamera));
        assert_eq!(action_for(KeyCode::KeyP), Some(Action::Screenshot));
        assert_eq!(action_for(KeyCode::KeyW), None, "flight keys are held, not actions");
    }
}
