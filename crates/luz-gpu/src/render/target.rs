//! The HDR render target every frame draws into, headless or in a window: the single-sample
//! colour image (what the saturate, tone-map and display passes and the readback use), and the
//! declaration of the frame's scene target in the frame graph (depth and the multisampled colour
//! are the graph's transients).

use std::sync::Arc;

use ash::vk;

use luz_graph::{FrameGraph, ImageDesc as GraphDesc, Plan};

use super::forward::TargetFormat;
use super::frame::{self, Carried, SceneTarget};
use crate::vk::image::ImageDesc;
use crate::vk::{Context, Image, VkError};

/// The HDR colour format: full float so the EXR and the analytic tests see exact radiance.
pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The HDR colour image a frame's scene passes write (through the MSAA image when `msaa` > 1),
/// kept by its owner across frames because later passes bind it in descriptor sets (saturation,
/// display, the A/B maps); depth and the MSAA colour are the graph's transients, pooled by
/// description ([`HdrTarget::add_to`]).
pub struct HdrTarget {
    /// Single-sample colour (the resolve target when multisampled).
    pub color: Image,
    /// Its last use in the previous frame (the first use of the next waits for it).
    last_use: Carried,
    samples: vk::SampleCountFlags,
    label: String,
}

impl HdrTarget {
    /// Allocates the colour image; `label` prefixes the debug names.
    pub fn new(
        ctx: &Arc<Context>,
        label: &str,
        extent: vk::Extent2D,
        samples: vk::SampleCountFlags,
    ) -> Result<Self, VkError> {
        let (w, h) = (extent.width, extent.height);
        Ok(Self {
            color: Image::new(
                ctx,
                &format!("{label} hdr color"),
                ImageDesc::color_target(w, h, COLOR_FORMAT),
            )?,
            last_use: Carried::default(),
            samples,
            label: label.to_string(),
        })
    }

    /// The same target at another size (after a resize); the old image is dropped by the caller
    /// once no frame uses it.
    pub fn resized(&self, ctx: &Arc<Context>, extent: vk::Extent2D) -> Result<Self, VkError> {
        Self::new(ctx, &self.label, extent, self.samples)
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.color.extent()
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

    /// Declares this frame's scene target in `g`: the colour image imported (its contents
    /// discarded, after the previous frame's last use), depth and — when multisampled — the MSAA
    /// colour as transients.
    pub fn add_to(&self, g: &mut FrameGraph<'_>) -> SceneTarget {
        let extent = self.extent();
        let (w, h) = (extent.width, extent.height);
        let label = &self.label;
        let color = frame::import(
            g,
            &format!("{label} hdr color"),
            &self.color,
            self.last_use.discard(),
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

    /// Keeps the state `plan` leaves the colour image in, for the next frame (call after
    /// compiling the graph `target` was declared in).
    pub fn remember(&self, plan: &Plan, target: &SceneTarget) {
        self.last_use.remember(plan, target.output());
    }
}
