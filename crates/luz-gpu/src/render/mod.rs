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
/// The shape of a scene the passes are built for, and what an edit costs them (kept by the
/// forward pass, whose variant keys it is made of).
pub use forward::world;

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

/// Pushes `bytes` at offset 0 of `layout`'s push-constant range, with its stages.
///
/// # Safety
/// `cmd` is recording on `d`'s device, and `bytes` is the block `layout`'s range declares.
pub(crate) unsafe fn push_constants(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    layout: &crate::vk::pipeline::PipelineLayout,
    bytes: &[u8],
) {
    // SAFETY: the caller's contract.
    unsafe { d.cmd_push_constants(cmd, layout.raw, layout.push_stages(), 0, bytes) }
}

/// A mesh's buffers, as the passes record them (the forward pass owns them).
#[derive(Debug, Clone, Copy)]
pub struct MeshRef {
    pub vertices: vk::Buffer,
    /// Flat shading's triangle centroids (binding 1), for meshes drawn flat.
    pub centroids: Option<vk::Buffer>,
    /// Vertex colours (binding 2), for meshes that have them (alpha-tested casters read them).
    pub colors: Option<vk::Buffer>,
    pub indices: vk::Buffer,
    pub index_count: u32,
}

impl MeshRef {
    /// Binds the vertices (binding 0) and 32-bit indices, and the optional streams the pipeline
    /// reads: centroids (binding 1) and colours (binding 2) when `(centroids, colors)` ask and
    /// the mesh has them; nothing when `bound` already names this mesh (`index`), which it
    /// names afterwards: draws sharing a mesh (grid49's 49 spheres) bind its buffers once.
    ///
    /// # Safety
    /// `cmd` is recording on `d`'s device, and the buffers outlive its execution.
    pub unsafe fn bind(
        &self,
        (d, cmd): (&ash::Device, vk::CommandBuffer),
        (centroids, colors): (bool, bool),
        (bound, index): (&mut Option<usize>, usize),
    ) {
        if *bound == Some(index) {
            return;
        }
        *bound = Some(index);
        // SAFETY: the caller's contract; the buffers were made with VERTEX_BUFFER and
        // INDEX_BUFFER usage by the forward pass's uploader.
        unsafe {
            d.cmd_bind_vertex_buffers(cmd, 0, &[self.vertices], &[0]);
            let streams = [(1, self.centroids, centroids), (2, self.colors, colors)];
            for (binding, stream, wanted) in streams {
                if let (Some(b), true) = (stream, wanted) {
                    d.cmd_bind_vertex_buffers(cmd, binding, &[b], &[0]);
                }
            }
            d.cmd_bind_index_buffer(cmd, self.indices, 0, vk::IndexType::UINT32);
        }
    }
}
