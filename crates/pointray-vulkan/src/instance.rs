//! The Vulkan instance, with the validation layer and its message counter when asked for.

use ash::vk;

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
    counter: Box<MessageCounter>,
}

impl Instance {
    pub(crate) fn validation_messages(&self) -> u32 {
        self.counter.count()
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

/// A Vulkan 1.2 instance; with `validation`, the Khronos layer and a counting messenger.
pub(crate) fn create_instance(validation: bool) -> Result<Instance, VulkanError> {
    // SAFETY: loading libvulkan runs its initialisers; nothing else is loaded concurrently.
    let entry = unsafe { ash::Entry::load() }?;
    if validation && !layer_available(&entry) {
        return Err(VulkanError::ValidationLayerMissing);
    }
    let counter = Box::<MessageCounter>::default();
    let app = vk::ApplicationInfo::default()
        .application_name(c"pointray")
        .engine_name(c"pointray")
        .api_version(vk::API_VERSION_1_2);
    let layers = [VALIDATION_LAYER.as_ptr()];
    let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
    let mut create_info = vk::InstanceCreateInfo::default().application_info(&app);
    // Chained so that instance creation and destruction are validated too.
    let mut instance_messenger = messenger_info(&counter);
    if validation {
        create_info = create_info
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions)
            .push_next(&mut instance_messenger);
    }
    // SAFETY: the create info and everything it points to outlive the call.
    let instance =
        unsafe { entry.create_instance(&create_info, None) }.during("creating the Vulkan instance")?;
    let mut owned = Instance { entry, instance, messenger: None, counter };
    if validation {
        let loader = ash::ext::debug_utils::Instance::new(&owned.entry, &owned.instance);
        // SAFETY: the counter is boxed and outlives the messenger (destroyed first in Drop).
        let handle = unsafe { loader.create_debug_utils_messenger(&messenger_info(&owned.counter), None) }
            .during("creating the validation messenger")?;
        owned.messenger = Some(Messenger { loader, handle });
    }
    Ok(owned)
}
