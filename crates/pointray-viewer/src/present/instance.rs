//! The presenter's Vulkan instance, with the window system's surface extensions and, on
//! request, the validation layer and a counting messenger. Dropping it destroys both.

use std::ffi::c_char;
use std::sync::Arc;

use ash::vk;
use raw_window_handle::RawDisplayHandle;

use crate::error::ViewerError;
use pointray_vulkan::validation::{self, MessageCounter};

pub(crate) struct PresentInstance {
    pub(crate) entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    // Declared last, dropped after `Drop::drop` has destroyed the instance that points at it.
    counter: Arc<MessageCounter>,
}

impl PresentInstance {
    pub(crate) fn new(display: RawDisplayHandle, validation: bool) -> Result<Self, ViewerError> {
        // SAFETY: loads the system Vulkan loader; touches no other Vulkan state.
        let entry = unsafe { ash::Entry::load() }
            .map_err(|e| ViewerError::PresentSetup(format!("cannot load libvulkan.so.1: {e}")))?;
        if validation && !validation::layer_available(&entry) {
            return Err(ViewerError::PresentSetup(
                "POINTRAY_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not installed".into(),
            ));
        }
        let counter = Arc::<MessageCounter>::default();
        let mut extensions: Vec<*const c_char> = ash_window::enumerate_required_extensions(display)
            .map_err(ViewerError::vk("listing the surface extensions"))?
            .to_vec();
        let mut layers: Vec<*const c_char> = Vec::new();
        if validation {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
            layers.push(validation::VALIDATION_LAYER.as_ptr());
        }
        let app = vk::ApplicationInfo::default()
            .application_name(c"pointray view")
            .api_version(vk::API_VERSION_1_1);
        // Chained into the create info too, so instance creation and destruction are checked.
        let mut instance_messenger = validation::messenger_info(&counter);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_extension_names(&extensions)
            .enabled_layer_names(&layers);
        if validation {
            info = info.push_next(&mut instance_messenger);
        }
        // SAFETY: every pointer in `info` lives until the call returns.
        let instance =
            unsafe { entry.create_instance(&info, None) }.map_err(ViewerError::vk("vkCreateInstance"))?;
        let mut owner = Self { entry, instance, messenger: None, counter };
        if validation {
            let debug_utils = ash::ext::debug_utils::Instance::new(&owner.entry, &owner.instance);
            let info = validation::messenger_info(&owner.counter);
            // SAFETY: the counter outlives the messenger (destroyed in `Drop`).
            let messenger = unsafe { debug_utils.create_debug_utils_messenger(&info, None) }
                .map_err(ViewerError::vk("vkCreateDebugUtilsMessengerEXT"))?;
            owner.messenger = Some((debug_utils, messenger));
        }
        Ok(owner)
    }

    pub(crate) fn message_counter(&self) -> Arc<MessageCounter> {
        Arc::clone(&self.counter)
    }
}

impl Drop for PresentInstance {
    fn drop(&mut self) {
        // SAFETY: every child object (surface, device) is destroyed by its owner first.
        unsafe {
            if let Some((debug_utils, messenger)) = self.messenger.take() {
                debug_utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
