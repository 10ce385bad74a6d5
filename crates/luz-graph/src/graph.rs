//! Declaring a frame: resources, then passes in execution order with what each reads and writes.

use ash::vk;

use crate::access::Access;
use crate::error::PassError;
use crate::exec::{RecordContext, RecordFn};
use crate::resource::{
    BufferHandle, ImageDesc, ImageHandle, ImageSource, ImageStateBefore, ImportedImage, Resource,
    SubresourceRange, Use, UseMode,
};

pub(crate) struct ImageEntry {
    pub name: String,
    pub desc: ImageDesc,
    pub source: ImageSource,
}

impl ImageEntry {
    /// (mips, layers) the graph tracks.
    pub fn dims(&self) -> (u32, u32) {
        match &self.source {
            ImageSource::Transient => (self.desc.mip_levels.max(1), self.desc.layers.max(1)),
            ImageSource::Imported(i) => {
                let mips = if i.range.level_count == vk::REMAINING_MIP_LEVELS {
                    self.desc.mip_levels.saturating_sub(i.range.base_mip_level)
                } else {
                    i.range.level_count
                };
                let layers = if i.range.layer_count == vk::REMAINING_ARRAY_LAYERS {
                    self.desc.layers.saturating_sub(i.range.base_array_layer)
                } else {
                    i.range.layer_count
                };
                (mips.max(1), layers.max(1))
            }
        }
    }
}

pub(crate) struct BufferEntry {
    pub name: String,
    pub buffer: vk::Buffer,
    pub size: vk::DeviceSize,
    pub before: Option<Access>,
    pub after: Option<Access>,
}

pub(crate) struct PassEntry<'a> {
    pub name: &'static str,
    pub uses: Vec<Use>,
    pub side_effect: bool,
    pub record: Option<RecordFn<'a>>,
}

/// A frame being declared: resources and passes. Passes run in declaration order.
#[derive(Default)]
pub struct FrameGraph<'a> {
    pub(crate) images: Vec<ImageEntry>,
    pub(crate) buffers: Vec<BufferEntry>,
    pub(crate) passes: Vec<PassEntry<'a>>,
}

impl<'a> FrameGraph<'a> {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// A transient image: allocated from the [`crate::TransientPool`] at execution, contents
    /// discarded between frames.
    pub fn create_image(&mut self, name: &str, desc: ImageDesc) -> ImageHandle {
        self.images.push(ImageEntry {
            name: name.to_string(),
            desc,
            source: ImageSource::Transient,
        });
        ImageHandle((self.images.len() - 1) as u32)
    }

    /// An image owned by the caller, in `image.before` state at the start and left in
    /// `image.after` (if any) at the end.
    pub fn import_image(&mut self, name: &str, image: ImportedImage) -> ImageHandle {
        self.images.push(ImageEntry {
            name: name.to_string(),
            desc: image.desc,
            source: ImageSource::Imported(image),
        });
        ImageHandle((self.images.len() - 1) as u32)
    }

    /// A buffer owned by the caller. `before` is its last use before this graph's work (`None`:
    /// nothing to wait for, e.g. host-written uniforms, which the submission makes visible).
    pub fn import_buffer(
        &mut self,
        name: &str,
        buffer: vk::Buffer,
        size: vk::DeviceSize,
        before: Option<Access>,
    ) -> BufferHandle {
        self.buffers.push(BufferEntry {
            name: name.to_string(),
            buffer,
            size,
            before,
            after: None,
        });
        BufferHandle((self.buffers.len() - 1) as u32)
    }

    /// Leaves an imported buffer in `after` at the end (a final barrier, e.g. `HostRead` for a
    /// readback buffer); a pass writing it then counts as having an output.
    pub fn buffer_after(&mut self, buffer: BufferHandle, after: Access) {
        if let Some(b) = self.buffers.get_mut(buffer.index()) {
            b.after = Some(after);
        }
    }

    /// Changes the final state of an imported image.
    pub fn image_after(&mut self, image: ImageHandle, after: Access) {
        if let Some(ImageEntry {
            source: ImageSource::Imported(i),
            ..
        }) = self.images.get_mut(image.index())
        {
            i.after = Some(after);
        }
    }

    /// Starts declaring a pass named `name` (its GPU timer scope and bench row).
    pub fn pass(&mut self, name: &'static str) -> PassBuilder<'_, 'a> {
        self.passes.push(PassEntry {
            name,
            uses: Vec::new(),
            side_effect: false,
            record: None,
        });
        let index = self.passes.len() - 1;
        PassBuilder { graph: self, index }
    }

    /// The name of an image.
    pub fn image_name(&self, image: ImageHandle) -> Option<&str> {
        self.images.get(image.index()).map(|i| i.name.as_str())
    }

    /// The name of a buffer.
    pub fn buffer_name(&self, buffer: BufferHandle) -> Option<&str> {
        self.buffers.get(buffer.index()).map(|b| b.name.as_str())
    }
}

/// Declares one pass's uses; obtained from [`FrameGraph::pass`]. Errors in declarations are
/// reported by [`FrameGraph::compile`].
pub struct PassBuilder<'g, 'a> {
    graph: &'g mut FrameGraph<'a>,
    index: usize,
}

impl<'a> PassBuilder<'_, 'a> {
    fn add(
        self,
        resource: Resource,
        access: Access,
        mode: UseMode,
        range: Option<SubresourceRange>,
    ) -> Self {
        self.graph.passes[self.index].uses.push(Use {
            resource,
            access,
            mode,
            range,
        });
        self
    }

    /// Reads all of `resource` (an image or a buffer).
    pub fn read(self, resource: impl Into<Resource>, access: Access) -> Self {
        self.add(resource.into(), access, UseMode::Read, None)
    }

    /// Overwrites all of `resource` (previous contents not needed).
    pub fn write(self, resource: impl Into<Resource>, access: Access) -> Self {
        self.add(resource.into(), access, UseMode::Write, None)
    }

    /// Reads and writes all of `resource`.
    pub fn read_write(self, resource: impl Into<Resource>, access: Access) -> Self {
        self.add(resource.into(), access, UseMode::ReadWrite, None)
    }

    /// Reads `range` of `image`.
    pub fn read_range(self, image: ImageHandle, range: SubresourceRange, access: Access) -> Self {
        self.add(image.into(), access, UseMode::Read, Some(range))
    }

    /// Overwrites `range` of `image`.
    pub fn write_range(self, image: ImageHandle, range: SubresourceRange, access: Access) -> Self {
        self.add(image.into(), access, UseMode::Write, Some(range))
    }

    /// Reads and writes `range` of `image`.
    pub fn read_write_range(
        self,
        image: ImageHandle,
        range: SubresourceRange,
        access: Access,
    ) -> Self {
        self.add(image.into(), access, UseMode::ReadWrite, Some(range))
    }

    /// Marks the pass as needed even if nobody reads what it writes (readback, present, UI).
    pub fn side_effect(self) -> Self {
        self.graph.passes[self.index].side_effect = true;
        self
    }

    /// Sets what the pass records; called once at execution if the pass is live.
    pub fn record(self, f: impl FnOnce(&mut RecordContext<'_>) -> Result<(), PassError> + 'a) {
        self.graph.passes[self.index].record = Some(Box::new(f));
    }
}

/// A resource's name for messages.
pub(crate) fn resource_name(
    images: &[ImageEntry],
    buffers: &[BufferEntry],
    r: Resource,
) -> Option<String> {
    match r {
        Resource::Image(h) => images.get(h.index()).map(|i| i.name.clone()),
        Resource::Buffer(h) => buffers.get(h.index()).map(|b| b.name.clone()),
    }
}

impl ImageStateBefore {
    /// Whether the contents are defined at the start.
    pub(crate) fn defined(self) -> bool {
        matches!(self, ImageStateBefore::Keep(_))
    }
}
