//! The HDR render target every frame draws into, headless or in a window: the single-sample
//! colour image (what the saturate, tone-map and display passes and the readback use), the
//! multisampled colour it resolves from when `msaa` > 1, and the depth buffer. One owner of the
//! three images, their views, the barriers that start a frame, and rebuilding at a new size.

use std::sync::Arc;

use ash::vk;

use super::forward::{TargetFormat, TargetViews};
use crate::vk::cmd::{transition, Transition};
use crate::vk::image::ImageDesc;
use crate::vk::{Context, Image, VkError};

/// The HDR colour format: full float so the EXR and the analytic tests see exact radiance.
pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The state of the colour attachments while the forward pass draws.
pub const COLOR_ATTACHMENT: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2) = (
    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
);

/// What came before a frame on the queue, for the first scope of [`HdrTarget::begin_frame`]'s
/// barriers (the images' contents are discarded either way).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameStart {
    /// Nothing that still runs: the host waited for the previous frame (headless).
    Idle,
    /// Frames in flight (the window): the previous frame's last uses must finish first — the
    /// colour image was last read at `color_read_stages`, depth and MSAA colour as attachments.
    AfterPrevious {
        color_read_stages: vk::PipelineStageFlags2,
    },
}

/// Colour, MSAA colour and depth at one size and sample count.
pub struct HdrTarget {
    /// Single-sample colour (the resolve target when multisampled).
    pub color: Image,
    /// Multisampled colour, when `samples` > 1.
    pub msaa: Option<Image>,
    pub depth: Image,
    samples: vk::SampleCountFlags,
    label: String,
}

impl HdrTarget {
    /// Allocates the images; `label` prefixes their debug names.
    pub fn new(
        ctx: &Arc<Context>,
        label: &str,
        extent: vk::Extent2D,
        samples: vk::SampleCountFlags,
    ) -> Result<Self, VkError> {
        let (w, h) = (extent.width, extent.height);
        let msaa = if samples != vk::SampleCountFlags::TYPE_1 {
            Some(Image::new(
                ctx,
                &format!("{label} hdr color msaa"),
                ImageDesc::msaa_color(w, h, COLOR_FORMAT, samples),
            )?)
        } else {
            None
        };
        Ok(Self {
            color: Image::new(
                ctx,
                &format!("{label} hdr color"),
                ImageDesc::color_target(w, h, COLOR_FORMAT),
            )?,
            msaa,
            depth: Image::new(
                ctx,
                &format!("{label} depth"),
                ImageDesc::depth(w, h, DEPTH_FORMAT, samples),
            )?,
            samples,
            label: label.to_string(),
        })
    }

    /// The same target at another size (after a resize); the old images are dropped by the
    /// caller once no frame uses them.
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

    /// The attachments as the forward pass takes them (after [`HdrTarget::begin_frame`]).
    pub fn views(&self) -> TargetViews {
        match &self.msaa {
            Some(m) => TargetViews {
                color: m.view,
                resolve: Some(self.color.view),
                depth: self.depth.view,
                extent: self.extent(),
            },
            None => TargetViews {
                color: self.color.view,
                resolve: None,
                depth: self.depth.view,
                extent: self.extent(),
            },
        }
    }

    /// Records the barriers that start a frame: every image from `UNDEFINED` (its contents are
    /// discarded) to its attachment layout, colour in [`COLOR_ATTACHMENT`] state.
    pub fn begin_frame(&self, device: &ash::Device, cmd: vk::CommandBuffer, start: FrameStart) {
        let fragment_tests = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        let idle = (
            vk::ImageLayout::UNDEFINED,
            vk::PipelineStageFlags2::TOP_OF_PIPE,
            vk::AccessFlags2::NONE,
        );
        let (color_from, depth_from, msaa_from) = match start {
            FrameStart::Idle => (idle, idle, idle),
            FrameStart::AfterPrevious { color_read_stages } => (
                (
                    vk::ImageLayout::UNDEFINED,
                    color_read_stages,
                    vk::AccessFlags2::NONE,
                ),
                (
                    vk::ImageLayout::UNDEFINED,
                    fragment_tests,
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                ),
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
            ),
        };
        let mut begin = vec![
            Transition {
                image: self.color.raw,
                range: self.color.subresource_range(),
                from: color_from,
                to: COLOR_ATTACHMENT,
            },
            Transition {
                image: self.depth.raw,
                range: self.depth.subresource_range(),
                from: depth_from,
                to: (
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                    fragment_tests,
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
                ),
            },
        ];
        if let Some(m) = &self.msaa {
            begin.push(Transition {
                image: m.raw,
                range: m.subresource_range(),
                from: msaa_from,
                to: COLOR_ATTACHMENT,
            });
        }
        transition(device, cmd, &begin);
    }
}
