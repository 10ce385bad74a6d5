//! The viewer's display pass: a full-screen triangle whose fragment shader exposes, tone-maps and
//! sRGB-encodes the HDR image (the code of [`crate::render::tonemap`], `include/color.glsl`, with
//! the encode by [`crate::color::srgb_encode_table`] instead of a `pow`) and
//! writes the codes straight into an 8-bit UNORM colour attachment — the swapchain image — so the
//! viewer needs no intermediate 8-bit image and no blit. One pipeline per (operator, attachment
//! format), built on first use ([`DisplayPass::prepare`]).
//!
//! The caller records inside a dynamic rendering instance on the attachment, with the HDR image
//! readable by fragment shaders in the layout given at creation.

use std::sync::Arc;

use ash::vk;

use crate::color::{exposure_scale, Tonemap};
use crate::render::tonemap::tonemap_id;
use crate::vk::buffer::Buffer;
use crate::vk::pipeline::{GraphicsDesc, Pipeline};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, SingleSet, VkError};

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
    single: SingleSet,
    _srgb_table: Buffer,
    source_layout: vk::ImageLayout,
    ctx: Arc<Context>,
}

impl DisplayPass {
    /// A pass reading `source` (an HDR colour view with SAMPLED usage, kept in `source_layout`).
    pub fn new(
        ctx: &Arc<Context>,
        source: vk::ImageView,
        source_layout: vk::ImageLayout,
    ) -> Result<Self, VkError> {
        let single = SingleSet::new(ctx, "display", &["display.vert", "display.frag"])?;
        let srgb_table = super::srgb_table(ctx, "display sRGB encode table")?;
        // SAFETY: the set was just allocated and no command buffer has used it; `srgb_table` is
        // a live STORAGE_BUFFER-usage buffer, kept by the pass as long as the set.
        unsafe {
            single
                .writes()
                .buffer(BINDING_SRGB_TABLE, srgb_table.raw)
                .apply(ctx)
        }?;
        let mut pass = Self {
            pipelines: Vec::new(),
            vertex: ShaderModule::new(ctx, "display.vert")?,
            fragment: ShaderModule::new(ctx, "display.frag")?,
            single,
            _srgb_table: srgb_table,
            source_layout,
            ctx: ctx.clone(),
        };
        pass.set_source(source)?;
        Ok(pass)
    }

    /// Points the pass at another HDR view (a resized viewer). No command buffer that recorded
    /// this pass may still be pending.
    pub fn set_source(&mut self, source: vk::ImageView) -> Result<(), VkError> {
        let writes = self
            .single
            .writes()
            .view(BINDING_HDR, source, self.source_layout);
        // SAFETY: `&mut self` gives this call sole access to the set. The caller's part,
        // documented above and in `new`: `source` is a live view with SAMPLED usage, and no
        // pending command buffer recorded this pass (VUID-vkUpdateDescriptorSets-None-03047) —
        // the viewer waits for the device to go idle before it points the pass at a new image.
        unsafe { writes.apply(&self.ctx) }
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
            &self.single.layout,
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

    /// Draws the display image over `extent` (inside a rendering instance on an attachment of
    /// `format`, with the pipeline [`DisplayPass::prepare`]d).
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        tonemap: Tonemap,
        format: vk::Format,
        exposure_ev: f32,
        extent: vk::Extent2D,
    ) -> Result<(), VkError> {
        let all = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent,
        };
        self.record_clipped(cmd, (tonemap, format), exposure_ev, extent, all)
    }

    /// [`DisplayPass::record`] drawing only the pixels inside `clip` (the viewer's A/B split:
    /// one side's image left of the divider, the other's right of it).
    pub fn record_clipped(
        &self,
        cmd: vk::CommandBuffer,
        (tonemap, format): (Tonemap, vk::Format),
        exposure_ev: f32,
        extent: vk::Extent2D,
        clip: vk::Rect2D,
    ) -> Result<(), VkError> {
        let pipeline = super::prepared(&self.pipelines, &(tonemap, format), || {
            format!("display: the {} pipeline for {format:?}", tonemap.name())
        })?;
        let push = DisplayPush {
            exposure_scale: exposure_scale(exposure_ev),
        };
        // SAFETY: `pipeline` is this pass's prepared pipeline for (`tonemap`, `format`) (looked up
        // above) with viewport, scissor and cull mode dynamic, built with `self.single`'s layout.
        // The caller's part, documented above: `cmd` is recording inside a dynamic rendering
        // instance on one attachment of `format`, and the source image is in the layout given at
        // creation and readable by fragment shaders.
        unsafe {
            draw_fullscreen(
                cmd,
                (pipeline, &self.single, 0),
                (extent, clip),
                bytemuck::bytes_of(&push),
            )
        }
    }
}

/// Draws the full-screen triangle with `pipeline` (no vertex input; viewport, scissor and cull
/// mode dynamic) over `extent`, only inside `clip`, with `single`'s set copy `copy` as set 0 and `push`
/// (when not empty) as its layout's push constants.
///
/// # Safety
/// `cmd` is recording inside a dynamic rendering instance on attachments `pipeline` was built
/// for; `pipeline` was built with `single`'s layout, declares those three states dynamic and
/// reads only what the set binds, which must be live and in the layouts its shader expects.
pub unsafe fn draw_fullscreen(
    cmd: vk::CommandBuffer,
    (pipeline, single, copy): (vk::Pipeline, &SingleSet, usize),
    (extent, clip): (vk::Extent2D, vk::Rect2D),
    push: &[u8],
) -> Result<(), VkError> {
    let d = &single.layout.device();
    let (layout, set) = (single.layout.raw, single.sets[copy]);
    // SAFETY: the caller's contract above.
    unsafe {
        crate::vk::cmd::set_viewport(d, cmd, extent, clip);
        d.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, layout, 0, &[set], &[]);
        if !push.is_empty() {
            single.layout.push_bytes(cmd, push)?;
        }
        d.cmd_draw(cmd, 3, 1, 0, 0);
    }
    Ok(())
}
