//! Device listing and selection against the real loader.

use crate::common;

use common::{assert_no_validation_messages, renderer};
use pointray_vulkan::{DeviceSelector, VulkanError, VulkanRenderer, list_devices};

#[test]
fn the_chosen_device_is_listed_usable_and_selectable_by_name_and_index() {
    let Some(auto) = renderer() else { return };
    let devices = list_devices().expect("the loader lists devices");
    let chosen = devices.iter().find(|d| d.name == auto.device_name()).expect("the chosen device is listed");
    assert!(chosen.rejection.is_none(), "{chosen}");
    let by_index = VulkanRenderer::with_validation(DeviceSelector::Index(chosen.index), true)
        .expect("selectable by index");
    assert_eq!(by_index.device_name(), auto.device_name());
    let by_name = VulkanRenderer::with_validation(DeviceSelector::Name(chosen.name.to_uppercase()), true)
        .expect("selectable by name, case-insensitively");
    assert_eq!(by_name.device_name(), auto.device_name());
    assert_no_validation_messages(&auto);
    assert_no_validation_messages(&by_index);
    assert_no_validation_messages(&by_name);
}

#[test]
fn an_unknown_device_is_an_error_that_lists_what_was_found() {
    let Some(_) = renderer() else { return };
    let devices = list_devices().expect("the loader lists devices");
    match VulkanRenderer::with_validation(DeviceSelector::Name("no such device anywhere".into()), true) {
        Err(VulkanError::NoSuitableDevice(message)) => {
            for device in &devices {
                assert!(message.contains(&device.name), "{message} does not name {}", device.name);
            }
        }
        Err(other) => panic!("expected NoSuitableDevice, got {other}"),
        Ok(renderer) => panic!("selected {} for a name nothing has", renderer.device_name()),
    }
}
