//! The Vulkan instance, with the validation layer and its message counter when asked for,
//! and the window system's surface extensions when a window is to be presented to.

use std::ffi::c_char;
use std::sync::Arc;

use ash::vk;
use raw_window_handle::RawDisplayHandle;

use crate::error::{VkContext, VulkanError};
use crate::validation::{MessageCounter, VALIDATION_LAYER, layer_available, messenger_info};

struct Messenger {
    loader: ash::ext::debug_utils::Instance,
    handle: vk::DebugUtilsMessengerEXT,
}

/// Owns the instance; destroys the messenger and then the instance on drop.
pub(crate) struct Instance {
    // Keeps libvulkan loaded for as long as the instance lives.
    pub(crate) entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    messenger: Option<Messenger>,
    /// Shared, so that a caller keeps counting the messages of the instance's own teardown
    /// (leaked objects reported by `vkDestroyDevice`) after the renderer is gone.
    counter: Arc<MessageCounter>,
    /// Whether the surface extensions were enabled (see `create_instance`).
    pub(crate) presents: bool,
}

impl Instance {
    pub(crate) fn validation_messages(&self) -> u32 {
        self.counter.count()
    }

    pub(crate) fn message_counter(&self) -> Arc<MessageCounter> {
        Arc::clone(&self.counter)
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: every child object was destroyed by the owners that borrow this instance.
        unsafe {
            if let Some(messenger) = self.messenger.take() {
                messenger.loader.destroy_debug_utils_messenger(messenger.handle, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// A Vulkan 1.2 instance; with `validation`, the Khronos layer and a counting messenger;
/// with `display`, the surface extensions its window system needs.
pub(crate) fn create_instance(
    validation: bool,
    display: Option<RawDisplayHandle>,
) -> Result<Instance, VulkanError> {
    // SAFETY: loading libvulkan runs its initialisers; nothing else is loaded concurrently.
    let entry = unsafe { ash::Entry::load() }?;
    if validation && !layer_available(&entry) {
        return Err(VulkanError::ValidationLayerMissing);
    }
    let counter = Arc::<MessageCounter>::default();
    let app = vk::ApplicationInfo::default()
        .application_name(c"pointray")
        .engine_name(c"pointray")
        .api_version(vk::API_VERSION_1_2);
    let layers = [VALIDATION_LAYER.as_ptr()];
    let mut extensions: Vec<*const c_char> = match display {
        Some(display) => ash_window::enumerate_required_extensions(display)
            .during("listing the window system's surface extensions")?
            .to_vec(),
        None => Vec::new(),
    };
    if validation {
        extensions.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    let mut create_info =
        vk::InstanceCreateInfo::default().application_info(&app).enabled_extension_names(&extensions);
    // Chained so that instance creation and destruction are validated too.
    let mut instance_messenger = messenger_info(&counter);
    if validation {
        create_info = create_info.enabled_layer_names(&layers).push_next(&mut instance_messenger);
    }
    // SAFETY: the create info and everything it points to outlive the call.
    let instance =
        unsafe { entry.create_instance(&create_info, None) }.during("creating the Vulkan instance")?;
    let mut owned = Instance { entry, instance, messenger: None, counter, presents: display.is_some() };
    if validation {
        let loader = ash::ext::debug_utils::Instance::new(&owned.entry, &owned.instance);
        // SAFETY: the counter is shared and outlives the messenger (destroyed first in Drop).
        let handle = unsafe { loader.create_debug_utils_messenger(&messenger_info(&owned.counter), None) }
            .during("creating the validation messenger")?;
        owned.messenger = Some(Messenger { loader, handle });
    }
    Ok(owned)
}
