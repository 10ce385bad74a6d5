//! The deferred path of the forward pass, for scenes whose objects all share one lean Phong
//! variant (no maps, no environment, one sample per pixel; [`eligible`]).
//!
//! lavapipe runs a fragment shader on whole 4×4 blocks: a triangle of two pixels still pays for
//! sixteen lanes of lighting. On grid49 (221k triangles, ~2 covered pixels each) most of the
//! forward pass's lighting is spent on pixels no triangle covers. The deferred path draws the
//! geometry once into a G-buffer (normal, view depth, object slot: `deferred_gbuffer.frag`; and
//! the shading frame's tangent for KHR_materials_anisotropy), then
//! lights each covered pixel exactly once in a full-screen draw (`deferred_light.frag`) with the
//! forward pass's own shading code, and writes the same output (radiance or display codes).

use std::collections::BTreeMap;
use std::sync::Arc;

use ash::vk;

use super::variant::{variant_spec, vertex_input, ShadingKey};
use super::{DebugView, Output, TargetFormat, TermsKey, VariantKey};
use crate::render::gpu;
use luz_graph::{Access, FrameGraph, ImageDesc as GraphDesc, ImageHandle};

use crate::render::frame::SceneTarget;
use crate::render::shadow::SHADOW_READ;
use crate::vk::cmd::{color_attachment, depth_attachment, rendering_info, Load};
use crate::vk::pipeline::{DescriptorSetLayout, GraphicsDesc, Pipeline, PipelineLayout};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, Interface, SetWrites, VkError};

/// The G-buffer: octahedral normal (2 × f32 bits), view depth (f32 bits), object slot.
pub const GBUFFER_FORMAT: vk::Format = vk::Format::R32G32B32A32_UINT;
/// The second G-buffer image of a variant with a tangent frame (`PHONG_TANGENT`): the shading
/// frame's X, octahedral (2 × f32 bits).
pub const GBUFFER_TANGENT_FORMAT: vk::Format = vk::Format::R32G32_UINT;
const SET_GBUFFER: u32 = crate::glsl::deferred_light_frag::SET_GBUFFER as u32;
const BINDING_GBUFFER: u32 = crate::glsl::deferred_light_frag::BINDING_GBUFFER as u32;
const BINDING_GBUFFER_TANGENT: u32 =
    crate::glsl::deferred_light_frag::BINDING_GBUFFER_TANGENT as u32;

/// Which render path the forward pass takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RenderPath {
    /// Deferred where [`eligible`], forward otherwise.
    #[default]
    Auto,
    /// Always forward (for comparisons).
    Forward,
}

/// The one variant every draw uses, when the deferred path can draw the scene: a lean Phong
/// variant (no texture maps: the G-buffer keeps the normal, and the tangent's direction for
/// `PHONG_TANGENT`, not texture coordinates), fixed BRDF terms, no environment, no debug view
/// but `nan`, one sample per pixel.
pub fn eligible(variants: &[VariantKey], samples: vk::SampleCountFlags) -> Option<VariantKey> {
    let first = *variants.first()?;
    let ok = variants.iter().all(|v| *v == first)
        && samples == vk::SampleCountFlags::TYPE_1
        && first.shading == ShadingKey::Phong
        && !first.phong_maps()
        && first.ibl.is_none()
        && matches!(first.debug, DebugView::None | DebugView::Nan)
        && first.terms != TermsKey::Generic
        && first.alpha == super::AlphaKey::Opaque;
    ok.then_some(first)
}

pub(super) struct Deferred {
    variant: VariantKey,
    target: TargetFormat,
    gbuffer_pipeline: Pipeline,
    /// The lighting pass's variant this frame (the fixed shadow slots no receiver needs
    /// skipped) and the NDC rectangle its lookups are needed in (`None`: everywhere); around it
    /// the unshadowed variant lights ([`Deferred::set_receivers`]).
    lit: (VariantKey, Option<[f32; 4]>),
    light_pipelines: BTreeMap<(VariantKey, Output), Pipeline>,
    light_layout: PipelineLayout,
    light_vertex: ShaderModule,
    light_fragment: ShaderModule,
    /// Set 1 of the lighting layout, pushed at record time: the G-buffer is a transient of the
    /// frame graph.
    set_layout: DescriptorSetLayout,
    ctx: Arc<Context>,
}

impl Deferred {
    /// Pipelines for `variant`: the geometry pass in the forward layout, the lighting pass in a
    /// layout of the frame set and the G-buffer set.
    pub(super) fn new(
        ctx: &Arc<Context>,
        forward_layout: &PipelineLayout,
        frameset_layout: &DescriptorSetLayout,
        (empty_layout, shadow_layout): (&DescriptorSetLayout, &DescriptorSetLayout),
        target: TargetFormat,
        variant: VariantKey,
    ) -> Result<Self, VkError> {
        const _: () = assert!(SET_GBUFFER == 1 && gpu::SET_FRAME == 0);
        const _: () = assert!(crate::render::shadow::SET_SHADOW == 3);
        // The modules of the variant: with a tangent frame, the G-buffer's second image.
        let (geometry_vs, geometry_fs, light_fs) = if variant.phong_tangent() {
            (
                "forward.vert:gbuffer_tangent",
                "deferred_gbuffer.frag:tangent",
                "deferred_light.frag:tangent",
            )
        } else {
            (
                "forward.vert:gbuffer",
                "deferred_gbuffer.frag:plain",
                "deferred_light.frag:plain",
            )
        };
        let interface = Interface::of("deferred lighting", &["skybox.vert", light_fs])?;
        let set_layout = interface.push_set_layout(ctx, SET_GBUFFER)?;
        let light_layout = interface.pipeline_layout(
            ctx,
            &[frameset_layout, &set_layout, empty_layout, shadow_layout],
        )?;
        let vs = ShaderModule::new(ctx, geometry_vs)?;
        let fs = ShaderModule::new(ctx, geometry_fs)?;
        let (bindings, attributes) = vertex_input(variant);
        let gbuffer_pipeline = Pipeline::graphics(
            ctx,
            forward_layout,
            &GraphicsDesc {
                name: &format!("deferred geometry {variant}"),
                vertex: &vs,
                fragment: &fs,
                spec: &variant_spec(variant),
                vertex_bindings: &bindings,
                vertex_attributes: &attributes,
                color_formats: if variant.phong_tangent() {
                    &[GBUFFER_FORMAT, GBUFFER_TANGENT_FORMAT]
                } else {
                    &[GBUFFER_FORMAT]
                },
                depth_format: Some(target.depth),
                samples: vk::SampleCountFlags::TYPE_1,
                cull: vk::CullModeFlags::NONE,
                depth_test: true,
                depth_write: true,
                depth_compare: vk::CompareOp::LESS,
                blend: false,
            },
        )?;
        Ok(Self {
            variant,
            lit: (variant, None),
            target,
            gbuffer_pipeline,
            light_pipelines: BTreeMap::new(),
            light_layout,
            light_vertex: ShaderModule::new(ctx, "skybox.vert")?,
            light_fragment: ShaderModule::new(ctx, light_fs)?,
            set_layout,
            ctx: ctx.clone(),
        })
    }

    /// Sets the lighting pass's shadow lookups for the frame: the lights of bit k of `lights`
    /// (fixed slot k) may darken some receiver, and only inside NDC rectangle `area` (`None`:
    /// anywhere). The lookups of the other slots are compiled out, and the pass lights with no
    /// lookup around the rectangle (`ForwardPass::receive_slots`).
    pub(super) fn set_receivers(&mut self, lights: u32, area: Option<[f32; 4]>) {
        let v = self.variant.receiving(lights);
        self.lit = (v, area.filter(|_| v.unshadowed() != v));
    }

    /// The lighting pass's variant and the rectangle its lookups are limited to.
    pub(super) fn receivers(&self) -> (VariantKey, Option<[f32; 4]>) {
        self.lit
    }

    /// The lighting variants of the frame: the shadowed one, and the unshadowed one when the
    /// lookups are limited to a rectangle.
    fn lit_variants(&self) -> Vec<VariantKey> {
        let (v, area) = self.lit;
        std::iter::once(v)
            .chain(area.map(|_| v.unshadowed()))
            .collect()
    }

    /// Builds the lighting pipelines writing `output` that do not exist yet.
    pub(super) fn prepare(&mut self, output: Output) -> Result<(), VkError> {
        for v in self.lit_variants() {
            self.prepare_variant(v, output)?;
        }
        Ok(())
    }

    fn prepare_variant(&mut self, variant: VariantKey, output: Output) -> Result<(), VkError> {
        if self.light_pipelines.contains_key(&(variant, output)) {
            return Ok(());
        }
        let mut spec = variant_spec(variant);
        spec.extend(output.spec());
        let pipeline = Pipeline::graphics(
            &self.ctx,
            &self.light_layout,
            &GraphicsDesc {
                name: &format!("deferred lighting {variant} {output:?}"),
                vertex: &self.light_vertex,
                fragment: &self.light_fragment,
                spec: &spec,
                vertex_bindings: &[],
                vertex_attributes: &[],
                color_formats: &[output.color_format(self.target.color)],
                depth_format: Some(self.target.depth),
                samples: vk::SampleCountFlags::TYPE_1,
                cull: vk::CullModeFlags::NONE,
                // The full-screen triangle lies at depth 1: it passes only where the geometry
                // pass drew (the cleared background stays at 1).
                depth_test: true,
                depth_write: false,
                depth_compare: vk::CompareOp::GREATER,
                blend: false,
            },
        )?;
        self.light_pipelines.insert((variant, output), pipeline);
        Ok(())
    }

    /// The lighting pipelines for `output` are built.
    pub(super) fn ready(&self, output: Output) -> bool {
        self.lit_variants()
            .iter()
            .all(|v| self.light_pipelines.contains_key(&(*v, output)))
    }

    /// Declares both passes in `g`: "gbuffer" (the geometry of `draw_geometry`, which records the
    /// draws with the pipeline it is given, into the G-buffer and `target`'s depth) and
    /// "lighting" (one full-screen pass over the covered pixels into `target`'s colour, cleared
    /// to `clear`). `shadow`: the shadow maps both may sample. Nothing when the pipelines for
    /// `output` are missing ([`Deferred::ready`] says so first).
    pub(super) fn add_passes<'a>(
        &'a self,
        g: &mut FrameGraph<'a>,
        (target, names): (SceneTarget, super::PassNames),
        (output, clear, keep_depth): (Output, vk::ClearValue, bool),
        (frame_set, shadow_set, shadow): (
            vk::DescriptorSet,
            vk::DescriptorSet,
            Option<ImageHandle>,
        ),
        draw_geometry: impl FnOnce(vk::CommandBuffer, vk::Pipeline) + 'a,
    ) {
        let (lit, shadow_area) = self.lit;
        let pipeline = |v: VariantKey| self.light_pipelines.get(&(v, output)).map(|p| p.raw);
        let (Some(light), Some(unshadowed)) = (
            pipeline(lit),
            pipeline(if shadow_area.is_some() {
                lit.unshadowed()
            } else {
                lit
            }),
        ) else {
            return;
        };
        let area = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: target.extent,
        };
        // Written and read within the frame: a transient.
        let (w, h) = (target.extent.width, target.extent.height);
        let gb = g.create_image(
            "g-buffer",
            GraphDesc::color(w, h, GBUFFER_FORMAT)
                .usage(vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED),
        );
        let tangent = self.variant.phong_tangent().then(|| {
            g.create_image(
                "g-buffer tangent",
                GraphDesc::color(w, h, GBUFFER_TANGENT_FORMAT)
                    .usage(vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED),
            )
        });
        let mut pass = g
            .pass(names.gbuffer)
            .write(gb, Access::ColorAttachmentWrite)
            .write(target.depth, Access::DepthAttachmentWrite);
        if let Some(t) = tangent {
            pass = pass.write(t, Access::ColorAttachmentWrite);
        }
        if let Some(s) = shadow {
            pass = pass.read(s, SHADOW_READ);
        }
        let gbuffer_pipeline = self.gbuffer_pipeline.raw;
        pass.record(move |rc| {
            let view = rc.image(gb)?.view;
            let depth_view = rc.image(target.depth)?.view;
            // Background pixels are never read (the lighting pass's depth test skips them): no
            // clear.
            // With a tangent frame, the second image too.
            let tangent_view = match tangent {
                Some(t) => Some(rc.image(t)?.view),
                None => None,
            };
            let colors = [
                color_attachment(view, Load::DontCare, true),
                color_attachment(tangent_view.unwrap_or(view), Load::DontCare, true),
            ];
            let used = if tangent_view.is_some() { 2 } else { 1 };
            let (d, cmd) = (rc.device(), rc.cmd());
            let depth = depth_attachment(depth_view, Load::depth(1.0), true);
            let info = rendering_info(area, &colors[..used], Some(&depth));
            // SAFETY: `cmd` is recording outside a rendering instance (the graph records passes
            // one after another); the graph put the G-buffer (both images with a tangent) in
            // COLOR_ATTACHMENT_OPTIMAL and depth in DEPTH_ATTACHMENT_OPTIMAL (the accesses
            // declared above); `info` and what it points to outlive the call, which is closed
            // after the draws below.
            unsafe { d.cmd_begin_rendering(cmd, &info) };
            set_viewport(d, cmd, area);
            draw_geometry(cmd, gbuffer_pipeline);
            // SAFETY: closes the rendering instance begun above, in the same command buffer.
            unsafe { d.cmd_end_rendering(cmd) };
            Ok(())
        });
        // Depth is tested, not written, but its store op (don't care) counts as a write.
        let mut pass = g
            .pass(names.lighting)
            .read(gb, Access::FragmentSampled)
            .read_write(target.depth, Access::DepthAttachmentWrite)
            .write(target.color, Access::ColorAttachmentWrite);
        if let Some(s) = shadow {
            pass = pass.read(s, SHADOW_READ);
        }
        if let Some(t) = tangent {
            pass = pass.read(t, Access::FragmentSampled);
        }
        pass.record(move |rc| {
            let mut gbuffer = SetWrites::new(&self.set_layout, vk::DescriptorSet::null()).view(
                BINDING_GBUFFER,
                rc.image(gb)?.view,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            );
            if let Some(t) = tangent {
                gbuffer = gbuffer.view(
                    BINDING_GBUFFER_TANGENT,
                    rc.image(t)?.view,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                );
            }
            let color_view = rc.image(target.color)?.view;
            let depth_view = rc.image(target.depth)?.view;
            let (d, cmd) = (rc.device(), rc.cmd());
            let colors = [color_attachment(color_view, Load::Clear(clear), true)];
            // Stored when a pass after this one draws against it (the emitters, issue 36).
            let depth = depth_attachment(depth_view, Load::Keep, keep_depth);
            let info = rendering_info(area, &colors, Some(&depth));
            // SAFETY: as above: the graph put the output in COLOR_ATTACHMENT_OPTIMAL, depth in
            // DEPTH_ATTACHMENT_OPTIMAL after the geometry's writes and the G-buffer (both images
            // with a tangent) in SHADER_READ_ONLY_OPTIMAL. The lighting pipeline belongs to this
            // pass, its layout's set 0 is the frame set layout `frame_set` was allocated with,
            // set 1 the push layout `self.set_layout` (the G-buffer's views, every binding the
            // variant's module declares, live while the frame runs) and set 3 the
            // shadow set layout `shadow_set` was allocated with; it has no vertex input and no
            // push constants. Viewport, scissor and cull mode (dynamic) are set before the draw.
            unsafe {
                d.cmd_begin_rendering(cmd, &info);
                set_viewport(d, cmd, area);
                d.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.light_layout.raw,
                    0,
                    &[frame_set],
                    &[],
                );
                gbuffer.push(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    &self.light_layout,
                    SET_GBUFFER,
                )?;
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.light_layout.raw,
                    crate::render::shadow::SET_SHADOW,
                    &[shadow_set],
                    &[],
                );
                // With the lookups limited to a rectangle: shadowed inside, unshadowed around it
                // (the parts tile the target: each pixel is lit once).
                let parts = match shadow_area {
                    Some(ndc) => crate::render::draws::split::split(ndc, area),
                    None => vec![(area, true)],
                };
                for (scissor, shadowed) in parts {
                    let p = if shadowed { light } else { unshadowed };
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p);
                    d.cmd_set_scissor(cmd, 0, &[scissor]);
                    d.cmd_draw(cmd, 3, 1, 0, 0);
                }
                d.cmd_end_rendering(cmd);
            }
            Ok(())
        });
    }
}

fn set_viewport(d: &ash::Device, cmd: vk::CommandBuffer, area: vk::Rect2D) {
    // SAFETY: `cmd` is recording inside a rendering instance with dynamic viewport and scissor
    // (both callers above).
    unsafe { crate::vk::cmd::set_viewport(d, cmd, area.extent, area) }
}
