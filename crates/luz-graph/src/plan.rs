//! The compiled frame as plain data ([`Plan`]): passes live or culled with their barriers, images
//! and buffers with their lifetimes and final states. Tests assert on it without a GPU.

use ash::vk;

use crate::access::{Access, MemoryBarrier};
use crate::resource::{
    ImageDesc, ImageHandle, ImageSource, ImageStateBefore, Resource, SubresourceRange, Use,
};

/// One barrier the plan records, as plain data.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BarrierInfo {
    /// The resource's name.
    pub resource: String,
    /// The resource's handle.
    pub handle: Resource,
    /// Layout before (`UNDEFINED` for buffers).
    pub old_layout: vk::ImageLayout,
    /// Layout after (`UNDEFINED` for buffers).
    pub new_layout: vk::ImageLayout,
    /// Its source and destination scopes.
    pub scopes: MemoryBarrier,
    /// The part of an image (relative to the managed range); `None` for buffers.
    pub range: Option<SubresourceRange>,
    /// The first use of a transient this frame: at execution the source scope also gets the
    /// pooled image's last use (previous frame, or an earlier transient sharing the image).
    pub after_pool_use: bool,
}

/// A pass in the plan.
#[derive(Clone, Debug)]
pub struct PassPlan {
    /// Its name.
    pub name: &'static str,
    /// Whether it is recorded (false: culled).
    pub live: bool,
    /// Whether it was declared with a side effect.
    pub side_effect: bool,
    /// Its declarations.
    pub uses: Vec<Use>,
    /// The barriers recorded before it (empty when culled).
    pub barriers: Vec<BarrierInfo>,
}

/// An image in the plan.
#[derive(Clone, Debug)]
pub struct ImageInfo {
    /// Its name.
    pub name: String,
    /// Its description (for transients, with the usage its accesses need added).
    pub desc: ImageDesc,
    /// Whether it is imported (else transient).
    pub imported: bool,
    /// Its final state, if imported with one.
    pub after: Option<Access>,
    /// First and last live pass using it (indices into [`Plan::passes`]).
    pub lifetime: Option<(usize, usize)>,
    /// Its last use this frame as a source scope for whoever uses the image next.
    pub final_scope: (vk::PipelineStageFlags2, vk::AccessFlags2),
    /// Some of it was not used this frame, so the pooled image's older last use still counts.
    pub final_includes_previous: bool,
    /// The layout every part of it is in at the end (`None`: parts differ).
    pub end_layout: Option<vk::ImageLayout>,
    pub(crate) source: ImageSource,
    pub(crate) dims: (u32, u32),
}

/// A buffer in the plan.
#[derive(Clone, Debug)]
pub struct BufferInfo {
    /// Its name.
    pub name: String,
    /// The buffer.
    pub buffer: vk::Buffer,
    /// Its size in bytes.
    pub size: vk::DeviceSize,
    /// Its final state, if any.
    pub after: Option<Access>,
    /// First and last live pass using it.
    pub lifetime: Option<(usize, usize)>,
}

/// A compiled graph as data: every declared pass (live or culled) in execution order, with the
/// barriers recorded before each live one, and the final barriers.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Images by handle index.
    pub images: Vec<ImageInfo>,
    /// Buffers by handle index.
    pub buffers: Vec<BufferInfo>,
    /// Passes in declaration (= execution) order.
    pub passes: Vec<PassPlan>,
    /// Barriers after the last pass (imported resources' `after` states).
    pub final_barriers: Vec<BarrierInfo>,
}

impl Plan {
    /// The pass named `name` (the first, if several share it).
    pub fn pass(&self, name: &str) -> Option<&PassPlan> {
        self.passes.iter().find(|p| p.name == name)
    }

    /// The names of the live passes, in order.
    pub fn live_passes(&self) -> Vec<&'static str> {
        self.passes
            .iter()
            .filter(|p| p.live)
            .map(|p| p.name)
            .collect()
    }

    /// The names of the culled passes, in order.
    pub fn culled_passes(&self) -> Vec<&'static str> {
        self.passes
            .iter()
            .filter(|p| !p.live)
            .map(|p| p.name)
            .collect()
    }

    /// The state an imported image is left in, as the `before` of the next frame's import
    /// (e.g. a shadow map kept across frames): `Keep` of its final layout and last use. `None`
    /// for transients, or when parts of the image end in different layouts.
    pub fn end_state(&self, image: ImageHandle) -> Option<ImageStateBefore> {
        let im = self.images.get(image.index())?;
        if !im.imported {
            return None;
        }
        let layout = im.end_layout?;
        let (stages, access) = im.final_scope;
        Some(ImageStateBefore::Keep(Access::Custom {
            name: "last use",
            layout,
            stages,
            access,
            writes: !access.is_empty(),
        }))
    }

    /// The name of a resource.
    pub fn resource_name(&self, r: Resource) -> &str {
        match r {
            Resource::Image(h) => &self.images[h.index()].name,
            Resource::Buffer(h) => &self.buffers[h.index()].name,
        }
    }
}
