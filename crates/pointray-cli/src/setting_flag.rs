//! Render-setting flags (`--width`, `--spp`, ...) checked by the same rule as the scene file's
//! `[render]` table, when the command line is parsed.

use pointray_scene::RenderSetting;

/// The parser of a flag that sets `setting`.
pub fn setting_flag(setting: RenderSetting) -> impl Fn(&str) -> Result<u32, String> + Clone {
    move |text| setting.parse(text)
}
