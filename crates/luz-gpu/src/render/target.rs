//! The HDR render target every frame draws into, headless or in a window: the declaration of
//! the frame's scene target in the frame graph. The single-sample colour (what the saturate,
//! tone-map and display passes and the readback use), depth and the multisampled colour are all
//! the graph's transients, pooled by description across frames.

use ash::vk;

use luz_graph::{FrameGraph, ImageDesc as GraphDesc};

use super::forward::TargetFormat;
use super::frame::SceneTarget;

/// The HDR colour format: full float so the EXR and the analytic tests see exact radiance.
pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The usage of the HDR colour: drawn (or resolved) into, stored and read by the saturation
/// kernels, sampled by the display and A/B passes, copied by read-backs. Stated in full so the
/// pooled image's description is the same whatever passes a frame has.
pub const COLOR_USAGE: vk::ImageUsageFlags = vk::ImageUsageFlags::from_raw(
    vk::ImageUsageFlags::COLOR_ATTACHMENT.as_raw()
        | vk::ImageUsageFlags::TRANSFER_SRC.as_raw()
        | vk::ImageUsageFlags::STORAGE.as_raw()
        | vk::ImageUsageFlags::SAMPLED.as_raw(),
);

/// The HDR scene target of a frame: its size, sample count and debug name. The images are the
/// frame graph's transients ([`HdrTarget::add_to`]).
#[derive(Debug, Clone)]
pub struct HdrTarget {
    extent: vk::Extent2D,
    samples: vk::SampleCountFlags,
    label: String,
}

impl HdrTarget {
    /// A target of `extent`; `label` prefixes the debug names.
    pub fn new(label: &str, extent: vk::Extent2D, samples: vk::SampleCountFlags) -> Self {
        Self {
            extent,
            samples,
            label: label.to_string(),
        }
    }

    /// The same target at another size (after a resize).
    pub fn resized(&self, extent: vk::Extent2D) -> Self {
        Self::new(&self.label, extent, self.samples)
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    pub fn samples(&self) -> vk::SampleCountFlags {
        self.samples
    }

    /// The formats pipelines drawing into this target are built for.
    pub fn format(&self) -> TargetFormat {
        TargetFormat {
            color: COLOR_FORMAT,
            depth: DEPTH_FORMAT,
            samples: self.samples,
        }
    }

    /// Declares this frame's scene target in `g`: the single-sample colour, depth and — when
    /// multisampled — the MSAA colour, all transients (contents discarded between frames).
    pub fn add_to(&self, g: &mut FrameGraph<'_>) -> SceneTarget {
        let extent = self.extent;
        let (w, h) = (extent.width, extent.height);
        let label = &self.label;
        let color = g.create_image(
            &format!("{label} hdr color"),
            GraphDesc::color(w, h, COLOR_FORMAT).usage(COLOR_USAGE),
        );
        let depth = g.create_image(
            &format!("{label} depth"),
            GraphDesc::depth(w, h, DEPTH_FORMAT).samples(self.samples),
        );
        if self.samples == vk::SampleCountFlags::TYPE_1 {
            return SceneTarget {
                color,
                resolve: None,
                depth,
                extent,
            };
        }
        let msaa = g.create_image(
            &format!("{label} hdr color msaa"),
            GraphDesc::color(w, h, COLOR_FORMAT).samples(self.samples),
        );
        SceneTarget {
            color: msaa,
            resolve: Some(color),
            depth,
            extent,
        }
    }
}
