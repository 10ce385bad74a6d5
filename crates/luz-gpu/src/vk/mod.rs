//! The Vulkan layer: instance and debug messenger, device context, RAII resources, pipelines, timing.
//! Nothing here knows about windows; the viewer adds a surface on top.

pub mod buffer;
pub mod cmd;
pub mod device;
pub mod host;
pub mod image;
pub mod instance;
pub mod interface;
pub mod limits;
pub mod pipeline;
pub mod pipeline_cache;
pub mod shaders;
pub mod timing;

pub use buffer::Buffer;
pub use device::{Context, ContextDesc, DeviceInfo};
pub use image::Image;
pub use instance::{InstanceDesc, ValidationLog};
pub use interface::{Interface, PushSet, SetWrites, SingleSet};
pub use limits::Limits;

use ash::vk;

/// Errors from the Vulkan layer.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    #[error("cannot load the Vulkan loader (libvulkan.so.1): {0}; on Debian install libvulkan1 and mesa-vulkan-drivers")]
    Loader(String),
    #[error("Vulkan call failed: {0}")]
    Vk(#[from] vk::Result),
    #[error("GPU memory allocation failed: {0}")]
    Alloc(#[from] gpu_allocator::AllocationError),
    #[error("{0}")]
    Setup(String),
    #[error("{what} of {requested} exceeds the device limit of {limit} ({limit_name})")]
    Limit {
        what: String,
        requested: u64,
        limit: u64,
        limit_name: &'static str,
    },
}
