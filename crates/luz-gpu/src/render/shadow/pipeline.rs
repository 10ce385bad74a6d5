//! The shadow pass's pipelines and the recording of one map layer: the depth-only pipeline
//! (`shadow.vert`, no fragment stage) for opaque casters and, only in scenes with alpha-tested
//! casters, [`MaskPipelines`] (`shadow_mask.vert` / `shadow_mask.frag`), which discard where the
//! base colour's alpha is below the caster's cutoff.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};

use super::{MeshRef, FORMAT, VERTEX_STRIDE};
use crate::render::draws::DepthDraw;
use crate::render::gpu::glsl::include_shadow_mask as m;
use crate::vk::cmd::{depth_attachment, rendering_info, Load};
use crate::vk::interface::keys_with_prefix;
use crate::vk::pipeline::{DescriptorSetLayout, Pipeline, PipelineLayout};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, Interface, VkError};

// The mask shaders bind the forward pass's material set as it is (src/render/material.rs).
const _: () = assert!(
    m::SHADOW_MASK_SET as u32 == crate::render::material::SET_MATERIAL
        && m::SHADOW_MASK_BINDING_EXTRA as u32 == crate::render::material::BINDING_EXTRA
        && m::SHADOW_MASK_MAP_BASE_COLOR
            == crate::render::gpu::glsl::include_bindings::MAP_BASE_COLOR
);

/// `ShadowMaskPush` of include/shadow_mask.glsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct MaskPush {
    clip_from_object: Mat4,
    /// x: the alpha cutoff.
    params: Vec4,
}

/// Vertex positions (binding 0, location 0) and, for the mask pipelines, texture coordinates
/// (location 2) and the vertex colours (binding 2, location 5), as the forward pass reads them.
fn vertex_input(
    uv: bool,
    color: bool,
) -> (
    Vec<vk::VertexInputBindingDescription>,
    Vec<vk::VertexInputAttributeDescription>,
) {
    let mut bindings = vec![vk::VertexInputBindingDescription {
        binding: 0,
        stride: VERTEX_STRIDE,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let mut attributes = vec![vk::VertexInputAttributeDescription {
        location: 0,
        binding: 0,
        format: vk::Format::R32G32B32_SFLOAT,
        offset: 0,
    }];
    if uv {
        attributes.push(vk::VertexInputAttributeDescription {
            location: 2,
            binding: 0,
            format: vk::Format::R32G32_SFLOAT,
            offset: std::mem::offset_of!(crate::render::gpu::Vertex, uv) as u32,
        });
    }
    if color {
        let (binding, attribute) = crate::render::gpu::vertex_color_input();
        bindings.push(binding);
        attributes.push(attribute);
    }
    (bindings, attributes)
}

/// A depth pipeline of `vertex` (and `fragment`) with `layout`. Reversed depth: the nearest
/// surface to the light has the largest value.
fn depth_pipeline(
    ctx: &Arc<Context>,
    layout: &PipelineLayout,
    name: &str,
    modules: (&ShaderModule, Option<&ShaderModule>),
    (uv, color): (bool, bool),
) -> Result<Pipeline, VkError> {
    let (bindings, attributes) = vertex_input(uv, color);
    Pipeline::depth_only(
        ctx,
        layout,
        name,
        modules,
        (&bindings, &attributes),
        (FORMAT, vk::CompareOp::GREATER_OR_EQUAL),
    )
}

pub(super) struct DepthPipeline {
    pipeline: Pipeline,
    layout: PipelineLayout,
    _module: ShaderModule,
    ctx: Arc<Context>,
}

/// The alpha-tested casters' pipelines: one for meshes without vertex colours and, when some
/// alpha-tested caster has them, one reading their alpha too. Set 2 is the forward pass's
/// material set (base colour map and `MaterialExtra`, bound as the forward pass binds them).
pub(super) struct MaskPipelines {
    plain: Pipeline,
    color: Option<Pipeline>,
    layout: PipelineLayout,
    _empty: DescriptorSetLayout,
    _modules: Vec<ShaderModule>,
}

impl MaskPipelines {
    /// The pipelines over `materials` (the forward pass's material set layout); `color`: also
    /// the one for meshes with vertex colours.
    pub(super) fn new(
        ctx: &Arc<Context>,
        materials: &DescriptorSetLayout,
        color: bool,
    ) -> Result<Self, VkError> {
        let vert = ShaderModule::new(ctx, "shadow_mask.vert:plain")?;
        let frag = ShaderModule::new(ctx, "shadow_mask.frag")?;
        let interface = Interface::of(
            "shadow mask",
            &keys_with_prefix("shadow_mask.").collect::<Vec<_>>(),
        )?;
        interface.check_push::<MaskPush>()?;
        // Sets 0 and 1 unused: empty, so the material set keeps its index.
        let empty = DescriptorSetLayout::empty(ctx, "shadow mask empty set layout")?;
        let layout = interface.pipeline_layout(ctx, &[&empty, &empty, materials])?;
        let plain = depth_pipeline(
            ctx,
            &layout,
            "shadow pass (alpha-tested)",
            (&vert, Some(&frag)),
            (true, false),
        )?;
        let mut modules = vec![vert, frag];
        let color = if color {
            let vert = ShaderModule::new(ctx, "shadow_mask.vert:color")?;
            let p = depth_pipeline(
                ctx,
                &layout,
                "shadow pass (alpha-tested, vertex colours)",
                (&vert, Some(&modules[1])),
                (true, true),
            )?;
            modules.push(vert);
            Some(p)
        } else {
            None
        };
        Ok(Self {
            plain,
            color,
            layout,
            _empty: empty,
            _modules: modules,
        })
    }
}

impl DepthPipeline {
    pub(super) fn new(ctx: &Arc<Context>) -> Result<Self, VkError> {
        let module = ShaderModule::new(ctx, "shadow.vert")?;
        let interface = Interface::of("shadow pass", &["shadow.vert"])?;
        interface.check_push::<Mat4>()?;
        let layout = interface.pipeline_layout(ctx, &[])?;
        let pipeline =
            depth_pipeline(ctx, &layout, "shadow pass", (&module, None), (false, false))?;
        Ok(Self {
            pipeline,
            layout,
            _module: module,
            ctx: ctx.clone(),
        })
    }

    /// Clears `view` (one layer) and draws `draws` into its top-left `resolution`² texels,
    /// pushed away from the light by `slope_bias` per unit of depth slope: the opaque casters
    /// with this pipeline, then the alpha-tested ones with `masked`'s, each with its material's
    /// set of `masked.1` (by material index), then the visible emitters of `emitters` (their
    /// unit shapes' mesh and the draws) with this pipeline.
    pub(super) fn record_layer(
        &self,
        cmd: vk::CommandBuffer,
        view: vk::ImageView,
        (resolution, slope_bias): (u32, f32),
        (draws, meshes): (&[DepthDraw], &[MeshRef]),
        masked: Option<(&MaskPipelines, &[vk::DescriptorSet])>,
        emitters: Option<(&MeshRef, &[super::emitters::EmitterDraw])>,
    ) {
        let d = &self.ctx.device;
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D {
                width: resolution,
                height: resolution,
            },
        };
        let depth = depth_attachment(view, Load::depth(0.0), true);
        let info = rendering_info(area, &[], Some(&depth));
        // A draw's mesh, when it has indices to draw.
        let mesh_of = |draw: &DepthDraw| {
            let (_, count) = draw.range;
            meshes.get(draw.mesh).filter(|_| count > 0)
        };
        // SAFETY: `cmd` is recording outside any rendering instance (ShadowMaps::record, before
        // the frame's passes) with `view`'s layer in DEPTH_ATTACHMENT_OPTIMAL (its barrier just
        // before); `info` and `depth` outlive the calls; the pipelines, their layouts, every
        // mesh buffer and the material sets belong to live objects that outlive the command
        // buffer's execution (the owners wait before dropping them); each push matches its
        // layout's range with its stages (one Mat4; a MaskPush for the mask layout; sizes checked
        // when the layouts were made); the material
        // sets were allocated with the material set layout the mask layout's set 2 is, and their
        // images are in SHADER_READ_ONLY_OPTIMAL since their upload; a mesh with vertex colours
        // drawn with the colour pipeline binds its colour buffer at binding 2; the render area
        // lies inside the layer (resolution ≤ the image's size). Viewport, scissor and depth
        // bias are dynamic in every pipeline, so they stay set across the pipeline binds.
        unsafe {
            d.cmd_begin_rendering(cmd, &info);
            crate::vk::cmd::set_viewport(d, cmd, area.extent, area);
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
            // Reversed depth: away from the light is towards 0.
            d.cmd_set_depth_bias(cmd, 0.0, 0.0, -slope_bias);
            let mut bound = None;
            for draw in draws.iter().filter(|dr| dr.alpha.is_none()) {
                let Some(mr) = mesh_of(draw) else { continue };
                mr.bind((d, cmd), (false, false), (&mut bound, draw.mesh));
                crate::render::push_constants(d, cmd, &self.layout, bytemuck::bytes_of(&draw.clip));
                d.cmd_draw_indexed(cmd, draw.range.1, 1, draw.range.0, 0, 0);
            }
            if let Some((mask, sets)) = masked {
                let (mut bound_mesh, mut bound_pipeline, mut bound_set) = (None, None, None);
                for draw in draws {
                    let Some((material, cutoff)) = draw.alpha else {
                        continue;
                    };
                    let (Some(mr), Some(&set)) = (mesh_of(draw), sets.get(material)) else {
                        continue;
                    };
                    let (pipeline, colors) = match (&mask.color, mr.colors) {
                        (Some(p), Some(_)) => (p.raw, true),
                        _ => (mask.plain.raw, false),
                    };
                    if bound_pipeline != Some(pipeline) {
                        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                        bound_pipeline = Some(pipeline);
                    }
                    if bound_set != Some(set) {
                        d.cmd_bind_descriptor_sets(
                            cmd,
                            vk::PipelineBindPoint::GRAPHICS,
                            mask.layout.raw,
                            m::SHADOW_MASK_SET as u32,
                            &[set],
                            &[],
                        );
                        bound_set = Some(set);
                    }
                    mr.bind((d, cmd), (false, colors), (&mut bound_mesh, draw.mesh));
                    let push = MaskPush {
                        clip_from_object: draw.clip,
                        params: Vec4::new(cutoff, 0.0, 0.0, 0.0),
                    };
                    crate::render::push_constants(d, cmd, &mask.layout, bytemuck::bytes_of(&push));
                    d.cmd_draw_indexed(cmd, draw.range.1, 1, draw.range.0, 0, 0);
                }
            }
            // The emitters' buffer holds 32-bit indices in range of its vertices and lives as
            // long as the maps (emitters.rs).
            if let Some((mesh, draws)) = emitters.filter(|(_, e)| !e.is_empty()) {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
                mesh.bind((d, cmd), (false, false), (&mut None, usize::MAX));
                for e in draws {
                    crate::render::push_constants(
                        d,
                        cmd,
                        &self.layout,
                        bytemuck::bytes_of(&e.clip),
                    );
                    d.cmd_draw_indexed(cmd, e.range.1, 1, e.range.0, 0, 0);
                }
            }
            d.cmd_end_rendering(cmd);
        }
    }
}
