//! The shadow pass's depth-only pipeline (`shadow.vert`, no fragment stage) and the recording of
//! one map layer.

use std::sync::Arc;

use ash::vk;
use glam::Mat4;

use super::{MeshRef, FORMAT, VERTEX_STRIDE};
use crate::vk::pipeline::{Pipeline, PipelineLayout};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, VkError};

pub(super) struct DepthPipeline {
    pipeline: Pipeline,
    layout: PipelineLayout,
    _module: ShaderModule,
    ctx: Arc<Context>,
}

impl DepthPipeline {
    pub(super) fn new(ctx: &Arc<Context>) -> Result<Self, VkError> {
        let module = ShaderModule::new(ctx, "shadow.vert")?;
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX,
            offset: 0,
            size: std::mem::size_of::<Mat4>() as u32,
        }];
        let layout = PipelineLayout::new(ctx, "shadow pass layout", &[], &push)?;
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: VERTEX_STRIDE,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attributes = [vk::VertexInputAttributeDescription {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 0,
        }];
        // Reversed depth: the nearest surface to the light has the largest value.
        let pipeline = Pipeline::depth_only(
            ctx,
            &layout,
            "shadow pass",
            &module,
            (&bindings, &attributes),
            (FORMAT, vk::CompareOp::GREATER_OR_EQUAL),
        )?;
        Ok(Self {
            pipeline,
            layout,
            _module: module,
            ctx: ctx.clone(),
        })
    }

    /// Clears `view` (one layer) and draws `draws` (mesh, index range, clip-from-object) into its top-left
    /// `resolution`² texels, pushed away from the light by `slope_bias` per unit of depth slope.
    pub(super) fn record_layer(
        &self,
        cmd: vk::CommandBuffer,
        view: vk::ImageView,
        (resolution, slope_bias): (u32, f32),
        draws: &[super::LayerDraw],
        meshes: &[MeshRef],
    ) {
        let d = &self.ctx.device;
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D {
                width: resolution,
                height: resolution,
            },
        };
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 0.0,
                    stencil: 0,
                },
            });
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .depth_attachment(&depth);
        // SAFETY: `cmd` is recording outside any rendering instance (ShadowMaps::record, before
        // the frame's passes) with `view`'s layer in DEPTH_ATTACHMENT_OPTIMAL (its barrier just
        // before); `info` and `depth` outlive the calls; the pipeline, its layout and every mesh
        // buffer belong to live objects that outlive the command buffer's execution (the owners
        // wait before dropping them); the pushed bytes are one Mat4, the layout's range; the
        // render area lies inside the layer (resolution ≤ the image's size).
        unsafe {
            d.cmd_begin_rendering(cmd, &info);
            d.cmd_set_viewport(
                cmd,
                0,
                &[vk::Viewport {
                    x: 0.0,
                    y: 0.0,
                    width: resolution as f32,
                    height: resolution as f32,
                    min_depth: 0.0,
                    max_depth: 1.0,
                }],
            );
            d.cmd_set_scissor(cmd, 0, &[area]);
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
            // Reversed depth: away from the light is towards 0.
            d.cmd_set_depth_bias(cmd, 0.0, 0.0, -slope_bias);
            let mut bound = None;
            for (mesh, (first, count), m) in draws {
                let Some(mr) = meshes.get(*mesh) else {
                    continue;
                };
                if *count == 0 {
                    continue;
                }
                if bound != Some(*mesh) {
                    d.cmd_bind_vertex_buffers(cmd, 0, &[mr.vertices], &[0]);
                    d.cmd_bind_index_buffer(cmd, mr.indices, 0, vk::IndexType::UINT32);
                    bound = Some(*mesh);
                }
                d.cmd_push_constants(
                    cmd,
                    self.layout.raw,
                    vk::ShaderStageFlags::VERTEX,
                    0,
                    bytemuck::bytes_of(m),
                );
                d.cmd_draw_indexed(cmd, *count, 1, *first, 0, 0);
            }
            d.cmd_end_rendering(cmd);
        }
    }
}
