//! Counting the validation messages the renderer's own Vulkan instance reports while it is
//! dropped: leaked objects are reported by `vkDestroyDevice` and `vkDestroyInstance`.
//!
//! `VulkanRenderer` counts its messages in a counter that its instance owns and frees, so what
//! the layer reports during the drop can no longer be read from it afterwards. But its
//! messenger (`pointray_vulkan::validation`) also emits every message it counts as a `tracing`
//! event with the target `pointray_vulkan::validation`, synchronously, on the thread that called
//! Vulkan. So the renderer is dropped under a thread-local subscriber that counts those events
//! and passes every event and span on to the subscriber that was in place.
//!
//! A workaround: if pointray-vulkan shares its counter (an `Arc<MessageCounter>` the caller
//! can keep past the drop, as the presenter's instance does), this module can go.

use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

use tracing::dispatcher::{self, Dispatch};
use tracing::span::{Attributes, Id, Record};
use tracing::subscriber::Interest;
use tracing::{Event, Metadata, Subscriber};
use tracing_core::span::Current;

/// The target of the events `pointray_vulkan::validation`'s messenger emits.
const VALIDATION_TARGET: &str = "pointray_vulkan::validation";

/// Runs `teardown` (on this thread) and says how many validation messages it caused.
pub(crate) fn count_validation_messages(teardown: impl FnOnce()) -> u32 {
    let count = Arc::new(AtomicU32::new(0));
    let previous = dispatcher::get_default(Dispatch::clone);
    let counter = Dispatch::new(CountingSubscriber { previous, count: Arc::clone(&count) });
    dispatcher::with_default(&counter, teardown);
    count.load(Ordering::Relaxed)
}

/// Counts validation events; forwards everything to `previous`.
struct CountingSubscriber {
    previous: Dispatch,
    count: Arc<AtomicU32>,
}

fn is_validation(metadata: &Metadata<'_>) -> bool {
    metadata.target() == VALIDATION_TARGET
}

impl Subscriber for CountingSubscriber {
    fn register_callsite(&self, metadata: &'static Metadata<'static>) -> Interest {
        if is_validation(metadata) { Interest::always() } else { self.previous.register_callsite(metadata) }
    }

    fn enabled(&self, metadata: &Metadata<'_>) -> bool {
        is_validation(metadata) || self.previous.enabled(metadata)
    }

    fn event(&self, event: &Event<'_>) {
        if is_validation(event.metadata()) {
            self.count.fetch_add(1, Ordering::Relaxed);
        }
        if self.previous.enabled(event.metadata()) {
            self.previous.event(event);
        }
    }

    fn new_span(&self, span: &Attributes<'_>) -> Id {
        self.previous.new_span(span)
    }

    fn record(&self, span: &Id, values: &Record<'_>) {
        self.previous.record(span, values);
    }

    fn record_follows_from(&self, span: &Id, follows: &Id) {
        self.previous.record_follows_from(span, follows);
    }

    fn enter(&self, span: &Id) {
        self.previous.enter(span);
    }

    fn exit(&self, span: &Id) {
        self.previous.exit(span);
    }

    fn clone_span(&self, id: &Id) -> Id {
        self.previous.clone_span(id)
    }

    fn try_close(&self, id: Id) -> bool {
        self.previous.try_close(id)
    }

    fn current_span(&self) -> Current {
        self.previous.current_span()
    }
}

#[cfg(test)]
mod tests {
    use ash::vk;
    use pointray_vulkan::validation::{self, MessageCounter};

    use super::*;

    #[test]
    fn counts_validation_events_only() {
        let counted = count_validation_messages(|| {
            tracing::error!(target: "pointray_vulkan::validation", "one");
            tracing::error!(target: "pointray_vulkan::trace", "not a validation message");
            tracing::warn!(target: "pointray_vulkan::validation", "two");
        });
        assert_eq!(counted, 2);
        assert_eq!(count_validation_messages(|| tracing::error!("elsewhere")), 0);
    }

    fn skip_or_fail(what: &str) {
        assert!(!std::env::var("CI").is_ok_and(|v| v == "true"), "CI=true but {what}");
        eprintln!("note: skipping, {what}");
    }

    /// A device destroyed with a semaphore still alive: the layer reports the leak during
    /// `vkDestroyDevice`, through pointray-vulkan's messenger, and it is counted here too.
    #[test]
    fn counts_a_leak_reported_by_pointray_vulkans_messenger() {
        // SAFETY: loads the system Vulkan loader.
        let Ok(entry) = (unsafe { ash::Entry::load() }) else { return skip_or_fail("no Vulkan loader") };
        if !validation::layer_available(&entry) {
            return skip_or_fail("no validation layer");
        }
        let counter = Box::<MessageCounter>::default();
        let layers = [validation::VALIDATION_LAYER.as_ptr()];
        let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_1);
        let mut messenger = validation::messenger_info(&counter);
        let info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions)
            .push_next(&mut messenger);
        // SAFETY: every pointer in `info` lives until the call returns; `counter` outlives the
        // instance, destroyed at the end of this test.
        let instance = unsafe { entry.create_instance(&info, None) }.expect("an instance");
        // The chained messenger only hears instance creation and destruction.
        let debug_utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
        // SAFETY: `counter` outlives the messenger, destroyed below.
        let messenger =
            unsafe { debug_utils.create_debug_utils_messenger(&validation::messenger_info(&counter), None) }
                .expect("a messenger");
        // SAFETY: plain query on the live instance.
        let physical = unsafe { instance.enumerate_physical_devices() }.unwrap_or_default();
        let Some(&physical) = physical.first() else {
            // SAFETY: nothing but the messenger was made from the instance.
            unsafe {
                debug_utils.destroy_debug_utils_messenger(messenger, None);
                instance.destroy_instance(None);
            }
            return skip_or_fail("no Vulkan device");
        };
        let priorities = [1.0];
        let queues =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(0).queue_priorities(&priorities)];
        let device_info = vk::DeviceCreateInfo::default().queue_create_infos(&queues);
        // SAFETY: plain creations on a live instance; the leak below is the point of the test.
        unsafe {
            let device = instance.create_device(physical, &device_info, None).expect("a device");
            device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None).expect("a semaphore");
            let before = counter.count();
            let counted = count_validation_messages(|| device.destroy_device(None));
            let reported = counter.count() - before;
            debug_utils.destroy_debug_utils_messenger(messenger, None);
            instance.destroy_instance(None);
            assert!(reported >= 1, "the layer reported no leak");
            assert_eq!(counted, reported, "the teardown count misses messages the messenger counted");
        }
    }
}
