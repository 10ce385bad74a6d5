//! Resource handles and descriptions: transient images, imported images and imported buffers.

use ash::vk;

use crate::access::Access;

/// A typed handle to an image of one [`crate::FrameGraph`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ImageHandle(pub(crate) u32);

/// A typed handle to a buffer of one [`crate::FrameGraph`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BufferHandle(pub(crate) u32);

impl ImageHandle {
    /// The index of the image in its graph (declaration order).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl BufferHandle {
    /// The index of the buffer in its graph (declaration order).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Either kind of resource handle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Resource {
    /// An image.
    Image(ImageHandle),
    /// A buffer.
    Buffer(BufferHandle),
}

impl From<ImageHandle> for Resource {
    fn from(h: ImageHandle) -> Self {
        Resource::Image(h)
    }
}

impl From<BufferHandle> for Resource {
    fn from(h: BufferHandle) -> Self {
        Resource::Buffer(h)
    }
}

/// What an image is: transients are pooled by equal descriptions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ImageDesc {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texel format.
    pub format: vk::Format,
    /// Usage flags; the graph adds the flags its declared accesses need before allocating.
    pub usage: vk::ImageUsageFlags,
    /// Sample count.
    pub samples: vk::SampleCountFlags,
    /// Mip levels (at least 1).
    pub mip_levels: u32,
    /// Array layers (at least 1; 6 for a cube).
    pub layers: u32,
    /// The aspects barriers cover (`COLOR`, `DEPTH`, `DEPTH | STENCIL`).
    pub aspect: vk::ImageAspectFlags,
}

impl ImageDesc {
    /// A single-sample 2D colour image with one mip and one layer.
    pub fn color(width: u32, height: u32, format: vk::Format) -> Self {
        Self {
            width,
            height,
            format,
            usage: vk::ImageUsageFlags::empty(),
            samples: vk::SampleCountFlags::TYPE_1,
            mip_levels: 1,
            layers: 1,
            aspect: vk::ImageAspectFlags::COLOR,
        }
    }

    /// A single-sample 2D depth image with one mip and one layer.
    pub fn depth(width: u32, height: u32, format: vk::Format) -> Self {
        Self {
            aspect: vk::ImageAspectFlags::DEPTH,
            ..Self::color(width, height, format)
        }
    }

    /// The same with `mip_levels` mips.
    pub fn mips(self, mip_levels: u32) -> Self {
        Self { mip_levels, ..self }
    }

    /// The same with `layers` array layers.
    pub fn layers(self, layers: u32) -> Self {
        Self { layers, ..self }
    }

    /// The same with `samples` samples.
    pub fn samples(self, samples: vk::SampleCountFlags) -> Self {
        Self { samples, ..self }
    }

    /// The same with `usage` added.
    pub fn usage(self, usage: vk::ImageUsageFlags) -> Self {
        Self {
            usage: self.usage | usage,
            ..self
        }
    }

    /// The size of mip 0.
    pub fn extent(&self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.width,
            height: self.height,
        }
    }

    /// Every mip and layer.
    pub fn full_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level: 0,
            level_count: self.mip_levels,
            base_array_layer: 0,
            layer_count: self.layers,
        }
    }
}

/// A part of an image a pass declares: mips `base_mip..base_mip + mip_count`, layers
/// `base_layer..base_layer + layer_count` (relative to the range the graph manages).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SubresourceRange {
    /// First mip.
    pub base_mip: u32,
    /// Number of mips.
    pub mip_count: u32,
    /// First layer.
    pub base_layer: u32,
    /// Number of layers.
    pub layer_count: u32,
}

impl SubresourceRange {
    /// Mips `base_mip..+mip_count`, layers `base_layer..+layer_count`.
    pub fn new(base_mip: u32, mip_count: u32, base_layer: u32, layer_count: u32) -> Self {
        Self {
            base_mip,
            mip_count,
            base_layer,
            layer_count,
        }
    }

    /// One mip of a single-layer image (layer 0).
    pub fn mip(mip: u32) -> Self {
        Self::new(mip, 1, 0, 1)
    }

    /// Layers `base..base + count` of mip 0.
    pub fn layers(base: u32, count: u32) -> Self {
        Self::new(0, 1, base, count)
    }

    /// Everything of an image with `mips` mips and `layers` layers.
    pub fn whole(mips: u32, layers: u32) -> Self {
        Self::new(0, mips, 0, layers)
    }
}

/// The state an imported image is in when the graph's work starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ImageStateBefore {
    /// Contents undefined and no earlier GPU work to wait for (the host waited, or the image is
    /// new). The first use transitions from `UNDEFINED` with no source scope.
    Undefined,
    /// Contents discarded, but the first use must wait for this earlier use (its stages and
    /// writes form the source scope; the transition is from `UNDEFINED`). For a swapchain image
    /// acquired with a semaphore waited at `COLOR_ATTACHMENT_OUTPUT`, use
    /// `Discard(Access::ColorAttachmentWrite)` so the barrier chains with the semaphore wait.
    Discard(Access),
    /// Contents kept: the image is in this access's layout, last used this way (its stages and
    /// writes form the source scope). The graph never transitions it from `UNDEFINED`.
    Keep(Access),
}

/// An image owned outside the graph (swapchain image, shadow maps, IBL cubes, readback source).
#[derive(Clone, Copy, Debug)]
pub struct ImportedImage {
    /// The image.
    pub image: vk::Image,
    /// A view of `range` (what [`crate::RecordContext::image`] hands out).
    pub view: vk::ImageView,
    /// Size, format, mips, layers, aspect.
    pub desc: ImageDesc,
    /// The part of the image the graph manages; passes' ranges are relative to it.
    pub range: vk::ImageSubresourceRange,
    /// The state at the start.
    pub before: ImageStateBefore,
    /// The state to leave it in at the end (a final barrier), e.g. `Present`.
    pub after: Option<Access>,
}

impl ImportedImage {
    /// The whole image, contents undefined at the start, no final state.
    pub fn new(image: vk::Image, view: vk::ImageView, desc: ImageDesc) -> Self {
        Self {
            image,
            view,
            desc,
            range: desc.full_range(),
            before: ImageStateBefore::Undefined,
            after: None,
        }
    }

    /// The same with `before` as the starting state.
    pub fn before(self, before: ImageStateBefore) -> Self {
        Self { before, ..self }
    }

    /// The same with a final state.
    pub fn after(self, after: Access) -> Self {
        Self {
            after: Some(after),
            ..self
        }
    }

    /// The same managing only `range` of the image.
    pub fn range(self, range: vk::ImageSubresourceRange) -> Self {
        Self { range, ..self }
    }
}

/// How a pass uses what it declares (the dependency; the synchronisation comes from the
/// [`Access`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UseMode {
    /// Reads the current contents.
    Read,
    /// Overwrites the declared range entirely (clear, don't-care load, full overwrite): the
    /// previous contents are not needed.
    Write,
    /// Reads the current contents and writes (load + store, blending, read-modify-write).
    ReadWrite,
}

impl UseMode {
    /// Whether the previous contents are needed.
    pub fn reads(self) -> bool {
        !matches!(self, UseMode::Write)
    }

    /// Whether the pass changes the contents.
    pub fn writes(self) -> bool {
        !matches!(self, UseMode::Read)
    }
}

/// One declaration of a pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Use {
    /// The resource.
    pub resource: Resource,
    /// The kind of use.
    pub access: Access,
    /// Read, write or both.
    pub mode: UseMode,
    /// The part of an image (`None`: all of it; always `None` for buffers).
    pub range: Option<SubresourceRange>,
}

/// Where an image comes from.
#[derive(Clone, Copy, Debug)]
pub(crate) enum ImageSource {
    Transient,
    Imported(ImportedImage),
}
