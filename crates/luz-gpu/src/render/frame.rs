//! The frame as a graph ([`luz_graph`]): the glue between luz's Vulkan objects and the graph, and
//! the building blocks headless rendering and the viewer describe their frames with.
//!
//! A frame is declared each time it is recorded: the owner imports what it keeps between frames
//! (the HDR colour image, the swapchain image, the shadow maps, the readback buffer) and creates
//! what lives for one frame (depth, MSAA colour, the 8-bit display target) from its
//! [`Transients`] pool; each pass ([`crate::render::forward::ForwardPass::add_passes`],
//! [`crate::render::saturate::SaturatePass::add_pass`], [`add_readback`], …) declares what it
//! reads and writes; the graph orders, culls, places every barrier and opens one GPU timer scope
//! per pass (the rows of `luz bench`). Nothing outside the graph and the vk layer records a
//! pipeline barrier.

use std::cell::Cell;
use std::sync::Arc;

use ash::vk;
use luz_graph::{
    Access, BufferHandle, CompiledGraph, ExecReport, FrameGraph, GraphError, ImageDesc,
    ImageFactory, ImageHandle, ImageStateBefore, ImportedImage, PassTimer, Plan, PooledImage,
    TransientPool,
};

use crate::vk::timing::GpuTimer;
use crate::vk::{Buffer, Context, Image, VkError};

/// How the viewer's display pass samples an HDR colour image: in GENERAL, the layout the A/B
/// map kernels read it in too (one descriptor layout for both).
pub const HDR_DISPLAY_READ: Access = Access::Custom {
    name: "DisplaySampled (GENERAL)",
    layout: vk::ImageLayout::GENERAL,
    stages: vk::PipelineStageFlags2::FRAGMENT_SHADER,
    access: vk::AccessFlags2::SHADER_SAMPLED_READ,
    writes: false,
};

/// How the A/B map kernels read the two HDR colour images ([`crate::render::compare`]).
pub const HDR_COMPARE_READ: Access = Access::Custom {
    name: "ComputeSampled (GENERAL)",
    layout: vk::ImageLayout::GENERAL,
    stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
    access: vk::AccessFlags2::SHADER_SAMPLED_READ,
    writes: false,
};

/// `vkCmdFillBuffer`'s write (COPY or CLEAR, depending on the validation layer's version).
pub const TRANSFER_FILL: Access = Access::Custom {
    name: "TransferFill",
    layout: vk::ImageLayout::UNDEFINED,
    stages: vk::PipelineStageFlags2::ALL_TRANSFER,
    access: vk::AccessFlags2::TRANSFER_WRITE,
    writes: true,
};

/// Makes the graph's transient images as luz [`Image`]s (named, checked against the device's
/// limits).
pub struct Factory {
    ctx: Arc<Context>,
}

impl ImageFactory for Factory {
    type Image = Image;
    type Error = VkError;

    fn create(&mut self, name: &str, desc: &ImageDesc) -> Result<Image, VkError> {
        Image::new(&self.ctx, name, crate::vk::image::ImageDesc::of_graph(desc))
    }
}

impl PooledImage for Image {
    fn raw(&self) -> vk::Image {
        self.raw
    }

    fn view(&self) -> vk::ImageView {
        self.view
    }
}

/// The GPU timer as the graph's pass timer: one scope per live pass, named after it.
impl PassTimer for GpuTimer {
    fn begin(&mut self, cmd: vk::CommandBuffer, name: &'static str) -> Option<u32> {
        GpuTimer::begin(self, cmd, name)
    }

    fn end(&mut self, cmd: vk::CommandBuffer, slot: Option<u32>) {
        GpuTimer::end(self, cmd, slot)
    }
}

impl From<GraphError> for VkError {
    fn from(e: GraphError) -> Self {
        match e {
            // A pass's own error (a luz error boxed by `?` in its closure) keeps its message.
            GraphError::Pass { pass, source } => match source.downcast::<VkError>() {
                Ok(inner) => match *inner {
                    VkError::Setup(m) => VkError::Setup(m),
                    other => VkError::Setup(format!("{pass}: {other}")),
                },
                Err(other) => VkError::Setup(format!("{pass}: {other}")),
            },
            other => VkError::Setup(format!("frame graph: {other}")),
        }
    }
}

/// The images a frame owner lends the graph for one frame at a time, pooled by description
/// across frames (and shared within a frame by transients whose lifetimes do not overlap).
pub struct Transients {
    pool: TransientPool<Factory>,
    factory: Factory,
}

impl Transients {
    pub fn new(ctx: &Arc<Context>) -> Self {
        Self {
            pool: TransientPool::new(),
            factory: Factory { ctx: ctx.clone() },
        }
    }

    /// Records `graph` into `cmd` (timed on `timer`, which the caller reset). The pool owns the
    /// graph's transient images: keep it alive until the submission of `cmd` has completed (a
    /// pool made and dropped inside a one-shot recording frees them before the GPU runs).
    pub fn execute(
        &mut self,
        ctx: &Context,
        graph: CompiledGraph<'_>,
        cmd: vk::CommandBuffer,
        timer: Option<&mut GpuTimer>,
    ) -> Result<ExecReport, VkError> {
        let timer = timer.map(|t| t as &mut dyn PassTimer);
        Ok(graph.execute(&ctx.device, cmd, &mut self.pool, &mut self.factory, timer)?)
    }

    /// Images the pool holds.
    pub fn len(&self) -> usize {
        self.pool.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pool.is_empty()
    }
}

/// The state an image its owner keeps across frames was last left in by a graph: the `before` of
/// its next import. Contents discarded each frame ([`Carried::discard`]: the HDR colour, the
/// G-buffer) or kept ([`Carried::keep`]: the shadow maps).
#[derive(Debug, Default)]
pub struct Carried(Cell<Option<Access>>);

impl Carried {
    /// Import state for an image whose contents this frame does not need: from `UNDEFINED`,
    /// after the previous frame's last use (nothing before the first frame).
    pub fn discard(&self) -> ImageStateBefore {
        match self.0.get() {
            Some(a) => ImageStateBefore::Discard(a),
            None => ImageStateBefore::Undefined,
        }
    }

    /// Import state for an image whose contents are kept (must have been set before).
    pub fn keep(&self) -> ImageStateBefore {
        match self.0.get() {
            Some(a) => ImageStateBefore::Keep(a),
            None => ImageStateBefore::Undefined,
        }
    }

    /// Takes the state `plan` leaves `image` in, for the next frame (after compiling, before
    /// executing).
    pub fn remember(&self, plan: &Plan, image: ImageHandle) {
        if let Some(ImageStateBefore::Keep(a)) = plan.end_state(image) {
            self.0.set(Some(a));
        }
    }
}

/// Imports a luz image (all of it) with `before`.
pub fn import(
    g: &mut FrameGraph<'_>,
    name: &str,
    image: &Image,
    before: ImageStateBefore,
) -> ImageHandle {
    g.import_image(
        name,
        ImportedImage::new(image.raw, image.view, image.desc.image)
            .range(image.subresource_range())
            .before(before),
    )
}

/// Leaves a new image (contents undefined) in `access`, in one submission: the state a pass
/// binds it in before any frame has written it (the shadow maps, the IBL images).
pub fn settle(
    ctx: &Arc<Context>,
    pool: &crate::vk::cmd::CommandPool,
    image: &Image,
    access: Access,
) -> Result<(), VkError> {
    pool.one_shot(|cmd| {
        let mut g = FrameGraph::new();
        let h = import(&mut g, "new image", image, ImageStateBefore::Undefined);
        g.image_after(h, access);
        let graph = g.compile()?;
        Transients::new(ctx).execute(ctx, graph, cmd, None)?;
        Ok(())
    })
}

/// Copies `source` (mip 0, layer 0, over `extent`) into `buffer` and makes the copy visible to
/// the host after the submission's fence: the readback of headless frames, screenshots and the
/// lab's read-backs. Timed as `name`.
pub fn add_readback<'a>(
    g: &mut FrameGraph<'a>,
    name: &'static str,
    source: ImageHandle,
    buffer: &'a Buffer,
    extent: vk::Extent2D,
) -> BufferHandle {
    let out = g.import_buffer(name, buffer.raw, buffer.size, None);
    g.buffer_after(out, Access::HostRead);
    g.pass(name)
        .read(source, Access::TransferSrc)
        .write(out, Access::TransferDst)
        .side_effect()
        .record(move |rc| {
            let image = rc.image(source)?.image;
            rc.buffer(out)?;
            crate::vk::cmd::copy_image_to_buffer(
                rc.device(),
                rc.cmd(),
                image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer,
                extent,
            );
            Ok(())
        });
    out
}

/// The frame's scene target as the graph sees it: the colour the scene passes write (the MSAA
/// image when multisampled, resolving into `resolve`), and depth.
#[derive(Debug, Clone, Copy)]
pub struct SceneTarget {
    pub color: ImageHandle,
    /// The single-sample image a multisampled `color` resolves into.
    pub resolve: Option<ImageHandle>,
    pub depth: ImageHandle,
    pub extent: vk::Extent2D,
}

impl SceneTarget {
    /// The image later passes read: the resolve target, or the colour itself.
    pub fn output(&self) -> ImageHandle {
        self.resolve.unwrap_or(self.color)
    }
}
