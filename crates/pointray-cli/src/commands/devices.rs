//! `pointray devices`: what the Vulkan loader sees, and why a device can't be used.

use clap::Args;

/// List Vulkan devices and whether each can ray trace point sets.
#[derive(Args)]
pub struct DevicesArgs {}

pub fn run(_args: DevicesArgs) -> anyhow::Result<()> {
    let devices = pointray_vulkan::list_devices()?;
    if devices.is_empty() {
        println!(
            "no Vulkan devices found (is a Vulkan driver installed? see scripts/install-system-deps.sh)"
        );
    }
    for device in devices {
        println!("{device}");
    }
    Ok(())
}
