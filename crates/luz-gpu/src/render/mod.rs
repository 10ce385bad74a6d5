//! The GPU renderer: one file per pass. Passes record into a command buffer for a given target and
//! own no swapchain, so the same pass draws offscreen or into a window.

pub mod compare;
pub mod display;
/// One draw list for every pass: culling, LOD, instancing, receiver splits and sort keys (CPU).
pub mod draws;
pub mod forward;
/// The frame as a graph: the glue to luz-graph and the building blocks of every frame.
pub mod frame;
/// Frustum planes, bounding spheres and culling, shared by the forward and shadow passes.
pub mod frustum;
pub mod gpu;
pub mod ibl;
pub mod material;
pub mod mesh;
pub mod saturate;
/// The scene's shared descriptor sets, made from the shaders' interfaces.
pub mod sets;
pub mod shadow;
pub mod target;
pub mod tonemap;

use ash::vk;

use crate::vk::pipeline::Pipeline;
use crate::vk::{Buffer, Context, VkError};

/// The pipeline prepared for `key` among `built`, or an error naming what (`what()`) was not
/// prepared: passes build their pipelines before recording and look them up while recording.
pub(crate) fn prepared<K: PartialEq>(
    built: &[(K, Pipeline)],
    key: &K,
    what: impl FnOnce() -> String,
) -> Result<vk::Pipeline, VkError> {
    built
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, p)| p.raw)
        .ok_or_else(|| VkError::Setup(format!("{} was not prepared", what())))
}

/// The sRGB encode table ([`crate::color::srgb_encode_table`]) in a storage buffer named `name`
/// (`include/srgb_lut.glsl` reads it).
pub(crate) fn srgb_table(ctx: &std::sync::Arc<Context>, name: &str) -> Result<Buffer, VkError> {
    Buffer::with_data(
        ctx,
        name,
        crate::color::srgb_encode_table().as_slice(),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )
}
