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

use crate::color::{exposure_scale, srgb_encode_table, Tonemap};
use crate::render::tonemap::tonemap_id;
use crate::vk::buffer::Buffer;
use crate::vk::pipeline::{
    DescriptorPool, DescriptorSetLayout, GraphicsDesc, Pipeline, PipelineLayout,
};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, VkError};

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
    layout: PipelineLayout,
    set: vk::DescriptorSet,
    _srgb_table: Buffer,
    _pool: DescriptorPool,
    _set_layout: DescriptorSetLayout,
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
        let binding = |index, ty| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(index)
                .descriptor_type(ty)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT)
        };
        let bindings = [
            binding(BINDING_HDR, vk::DescriptorType::SAMPLED_IMAGE),
            binding(BINDING_SRGB_TABLE, vk::DescriptorType::STORAGE_BUFFER),
        ];
        let set_layout = DescriptorSetLayout::new(ctx, "display set layout", &bindings)?;
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::FRAGMENT,
            offset: 0,
            size: std::mem::size_of::<DisplayPush>() as u32,
        }];
        let layout = PipelineLayout::new(ctx, "display layout", &[&set_layout], &push)?;
        let pool = DescriptorPool::new(
            ctx,
            "display pool",
            1,
            &[
                vk::DescriptorPoolSize {
                    ty: vk::DescriptorType::SAMPLED_IMAGE,
                    descriptor_count: 1,
                },
                vk::DescriptorPoolSize {
                    ty: vk::DescriptorType::STORAGE_BUFFER,
                    descriptor_count: 1,
                },
            ],
        )?;
        let set = pool.allocate(&set_layout)?;
        let srgb_table = Buffer::with_data(
            ctx,
            "display sRGB encode table",
            srgb_encode_table().as_slice(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let table_info = [vk::DescriptorBufferInfo {
            buffer: srgb_table.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(BINDING_SRGB_TABLE)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
            .buffer_info(&table_info);
        // SAFETY: `write` and the `table_info` it points to outlive the call. `set` was just
        // allocated from `pool` and no command buffer has used it; binding 1 is a STORAGE_BUFFER
        // in `set_layout`, and `srgb_table` is a live STORAGE_BUFFER-usage buffer, kept by the pass
        // as long as the set.
        unsafe { ctx.device.update_descriptor_sets(&[write], &[]) };
        let mut pass = Self {
            pipelines: Vec::new(),
            vertex: ShaderModule::new(ctx, "display.vert")?,
            fragment: ShaderModule::new(ctx, "display.frag")?,
            layout,
            set,
            _srgb_table: srgb_table,
            _pool: pool,
            _set_layout: set_layout,
            source_layout,
            ctx: ctx.clone(),
        };
        pass.set_source(source);
        Ok(pass)
    }

    /// Points the pass at another HDR view (a resized viewer). No command buffer that recorded
    /// this pass may still be pending.
    pub fn set_source(&mut self, source: vk::ImageView) {
        let info = [vk::DescriptorImageInfo {
            sampler: vk::Sampler::null(),
            image_view: source,
            image_layout: self.source_layout,
        }];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(BINDING_HDR)
            .descriptor_type(vk::DescriptorType::SAMPLED_IMAGE)
            .image_info(&info);
        // SAFETY: `write` and `info` outlive the call; binding 0 of `self.set` is a SAMPLED_IMAGE.
        // `&mut self` gives this call sole access to the set. The caller's part, documented above
        // and in `new`: `source` is a live view with SAMPLED usage, and no pending command buffer
        // recorded this pass (VUID-vkUpdateDescriptorSets-None-03047) — the viewer waits for the
        // device to go idle before it points the pass at a new image.
        unsafe { self.ctx.device.update_descriptor_sets(&[write], &[]) };
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
            &self.layout,
            &GraphicsDesc {
                name: &name,
                vertex: &self.vertex,
                fragment: &self.fragment,
                spec: &[(crate::glsl::display_frag::SPEC_TONEMAP, tonemap_id(tonemap))],
                vertex_bindings: &[],
                vertex_attributes: &[],
                color_formats: &[format],
                depth_format: None,
                samples: vk::SampleCountFlags::TYPE_1,
                cull: vk::CullModeFlags::NONE,
                depth_test: false,
                depth_write: false,
                depth_compare: vk::CompareOp::ALWAYS,
                blend: false,
            },
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
        let pipeline = self
            .pipelines
            .iter()
            .find(|(k, _)| *k == (tonemap, format))
            .map(|(_, p)| p.raw)
            .ok_or_else(|| {
                VkError::Setup(format!(
                    "display: the {} pipeline for {format:?} was not prepared",
                    tonemap.name()
                ))
            })?;
        let d = &self.ctx.device;
        let push = DisplayPush {
            exposure_scale: exposure_scale(exposure_ev),
        };
        let area = clip;
        // SAFETY: `pipeline` is this pass's prepared pipeline for (`tonemap`, `format`) (looked up
        // above) with viewport, scissor and cull mode dynamic; `self.set` matches set 0 of
        // `self.layout`, and the push-constant bytes are a `DisplayPush`, the FRAGMENT range of
        // the layout. The caller's part, documented above: `cmd` is recording inside a dynamic
        // rendering instance on one attachment of `format`, and the source image is in the layout
        // given at creation and readable by fragment shaders.
        unsafe {
            draw_fullscreen(
                d,
                cmd,
                (pipeline, self.layout.raw, self.set),
                (extent, area),
                bytemuck::bytes_of(&push),
            )
        };
        Ok(())
    }
}

/// Draws the full-screen triangle with `pipeline` (no vertex input; viewport, scissor and cull
/// mode dynamic) over `extent`, only inside `clip`, with `set` as set 0 of `layout` and `push`
/// (when not empty) as FRAGMENT push constants at offset 0.
///
/// # Safety
/// `cmd` is recording inside a dynamic rendering instance on attachments `pipeline` was built
/// for; `pipeline` was built with `layout`, declares those three states dynamic and reads only
/// what `set` binds, which must be live and in the layouts its shader expects; `push` fits the
/// layout's FRAGMENT range.
pub unsafe fn draw_fullscreen(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    (pipeline, layout, set): (vk::Pipeline, vk::PipelineLayout, vk::DescriptorSet),
    (extent, clip): (vk::Extent2D, vk::Rect2D),
    push: &[u8],
) {
    // SAFETY: the caller's contract above.
    unsafe {
        d.cmd_set_viewport(
            cmd,
            0,
            &[vk::Viewport {
                x: 0.0,
                y: 0.0,
                width: extent.width as f32,
                height: extent.height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            }],
        );
        d.cmd_set_scissor(cmd, 0, &[clip]);
        d.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, layout, 0, &[set], &[]);
        if !push.is_empty() {
            d.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::FRAGMENT, 0, push);
        }
        d.cmd_draw(cmd, 3, 1, 0, 0);
    }
}
