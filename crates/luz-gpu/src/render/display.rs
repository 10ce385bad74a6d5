//! The viewer's display pass: a full-screen triangle whose fragment shader exposes, tone-maps and
//! sRGB-encodes the HDR image (the code of [`crate::render::tonemap`], `include/color.glsl`, with
//! the encode by [`crate::color::srgb_encode_table`] instead of a `pow`) and
//! writes the codes straight into an 8-bit UNORM colour attachment — the swapchain image — so the
//! viewer needs no intermediate 8-bit image and no blit. One pipeline per (operator, attachment
//! format), built on first use ([`DisplayPass::prepare`]).
//!
//! The caller records inside a dynamic rendering instance on the attachment, with the HDR image
//! readable by fragment shaders in the layout given at creation. The HDR view is pushed with each
//! draw (`VK_KHR_push_descriptor`): it is a transient of the frame graph.

use std::sync::Arc;

use ash::vk;

use crate::color::{exposure_scale, Tonemap};
use crate::render::tonemap::tonemap_id;
use crate::vk::buffer::Buffer;
use crate::vk::pipeline::{GraphicsDesc, Pipeline};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, PushSet, SetWrites, VkError};

/// Bindings of `display.frag` (its `BINDING_*`).
const BINDING_HDR: u32 = crate::glsl::display_frag::BINDING_HDR as u32;
const BINDING_SRGB_TABLE: u32 = crate::glsl::display_frag::BINDING_SRGB_TABLE as u32;

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct DisplayPush {
    exposure_scale: f32,
}

pub struct DisplayPass {
    pipelines: Vec<((Tonemap, vk::Format), Pipeline)>,
    vertex: ShaderModule,
    fragment: ShaderModule,
    /// The layout; the HDR view (a frame graph transient) and the table are pushed per draw.
    push: PushSet,
    srgb_table: Buffer,
    source_layout: vk::ImageLayout,
    ctx: Arc<Context>,
}

impl DisplayPass {
    /// A pass reading HDR colour views (SAMPLED usage) kept in `source_layout` when drawn.
    pub fn new(ctx: &Arc<Context>, source_layout: vk::ImageLayout) -> Result<Self, VkError> {
        Ok(Self {
            pipelines: Vec::new(),
            vertex: ShaderModule::new(ctx, "display.vert")?,
            fragment: ShaderModule::new(ctx, "display.frag")?,
            push: PushSet::new(ctx, "display", &["display.vert", "display.frag"])?,
            srgb_table: super::srgb_table(ctx, "display sRGB encode table")?,
            source_layout,
            ctx: ctx.clone(),
        })
    }

    /// The stage and access the HDR image must be made visible to before [`DisplayPass::record`].
    pub fn source_access(&self) -> (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2) {
        (
            self.source_layout,
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
        )
    }

    /// Builds the pipeline for `tonemap` into attachments of `format` unless it exists.
    pub fn prepare(&mut self, tonemap: Tonemap, format: vk::Format) -> Result<(), VkError> {
        if self.pipelines.iter().any(|(k, _)| *k == (tonemap, format)) {
            return Ok(());
        }
        let name = format!("display[{}, {format:?}]", tonemap.name());
        let pipeline = Pipeline::graphics(
            &self.ctx,
            &self.push.layout,
            &GraphicsDesc::fullscreen(
                &name,
                (&self.vertex, &self.fragment),
                &[(crate::glsl::display_frag::SPEC_TONEMAP, tonemap_id(tonemap))],
                &[format],
            ),
        )?;
        self.pipelines.push(((tonemap, format), pipeline));
        Ok(())
    }

    /// Draws the display image of `source` over `extent` (inside a rendering instance on an
    /// attachment of `format`, with the pipeline [`DisplayPass::prepare`]d).
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        source: vk::ImageView,
        (tonemap, format): (Tonemap, vk::Format),
        exposure_ev: f32,
        extent: vk::Extent2D,
    ) -> Result<(), VkError> {
        let all = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent,
        };
        self.record_clipped(cmd, source, (tonemap, format), exposure_ev, (extent, all))
    }

    /// [`DisplayPass::record`] drawing only the pixels inside `clip` (the viewer's A/B split:
    /// one side's image left of the divider, the other's right of it).
    pub fn record_clipped(
        &self,
        cmd: vk::CommandBuffer,
        source: vk::ImageView,
        (tonemap, format): (Tonemap, vk::Format),
        exposure_ev: f32,
        (extent, clip): (vk::Extent2D, vk::Rect2D),
    ) -> Result<(), VkError> {
        let pipeline = super::prepared(&self.pipelines, &(tonemap, format), || {
            format!("display: the {} pipeline for {format:?}", tonemap.name())
        })?;
        let push = DisplayPush {
            exposure_scale: exposure_scale(exposure_ev),
        };
        let writes = self
            .push
            .writes()
            .view(BINDING_HDR, source, self.source_layout)
            .buffer(BINDING_SRGB_TABLE, self.srgb_table.raw);
        // SAFETY: `pipeline` is this pass's prepared pipeline for (`tonemap`, `format`) (looked up
        // above) with viewport, scissor and cull mode dynamic, built with `self.push`'s layout;
        // the table is the pass's own. The caller's part, documented above: `cmd` is recording
        // inside a dynamic rendering instance on one attachment of `format`, and `source` is a
        // live SAMPLED view in the layout given at creation, readable by fragment shaders.
        unsafe {
            draw_fullscreen(
                cmd,
                (pipeline, &self.push, writes),
                (extent, clip),
                bytemuck::bytes_of(&push),
            )
        }
    }
}

/// Draws the full-screen triangle with `pipeline` (no vertex input; viewport, scissor and cull
/// mode dynamic) over `extent`, only inside `clip`, with `writes` pushed as set 0 of `layout`
/// and `push` (when not empty) as its push constants.
///
/// # Safety
/// `cmd` is recording inside a dynamic rendering instance on attachments `pipeline` was built
/// for; `pipeline` was built with `layout`'s pipeline layout, declares those three states
/// dynamic and reads only what `writes` binds, which must be live and in the layouts its shader
/// expects.
pub unsafe fn draw_fullscreen(
    cmd: vk::CommandBuffer,
    (pipeline, layout, writes): (vk::Pipeline, &PushSet, SetWrites<'_>),
    (extent, clip): (vk::Extent2D, vk::Rect2D),
    push: &[u8],
) -> Result<(), VkError> {
    let d = layout.layout.device();
    // SAFETY: the caller's contract above.
    unsafe {
        crate::vk::cmd::set_viewport(d, cmd, extent, clip);
        d.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        layout.push(cmd, vk::PipelineBindPoint::GRAPHICS, writes)?;
        if !push.is_empty() {
            layout.layout.push_bytes(cmd, push)?;
        }
        d.cmd_draw(cmd, 3, 1, 0, 0);
    }
    Ok(())
}
