//! Display conversion on the GPU: exposure → tone map → clamp → sRGB encode → 8-bit, the same
//! pipeline as [`crate::color::to_display_rgba8`] (mirrored in `shaders_glsl/include/color.glsl`,
//! compared byte by byte in `tests/tonemap_gpu.rs`).
//!
//! The source is the renderer's HDR image (RGBA32F, read as a sampled image with `texelFetch`, so it
//! may sit in `GENERAL` or `SHADER_READ_ONLY_OPTIMAL`). The destination is an `R8G8B8A8_UNORM`
//! storage image: storage images of `*_SRGB` formats are not allowed, so the shader encodes sRGB
//! itself and writes the rounded code; the viewer then blits or copies that image to the swapchain.
//!
//! One pipeline per operator, specialised (`TONEMAP` constant) and built on first use
//! ([`TonemapPass::prepare`]): a CPU rasteriser such as lavapipe executes every side of a branch
//! under a mask, so one pipeline switching on a push constant ran all five operators per pixel
//! (13.9 ms at 1280×720 on lavapipe against ~3 ms specialised; `luz view --bench`). Exposure stays a
//! push constant: changing it needs no pipeline.
//!
//! The pass records no layout transitions: it owns image *views* only. Before [`TonemapPass::record`]
//! the caller puts the source in the layout given at creation ([`TonemapPass::source_access`]) and the
//! destination in `GENERAL` ([`DESTINATION_ACCESS`]), with the barriers that make earlier writes
//! visible; afterwards the destination was last written as [`DESTINATION_ACCESS`].

use std::sync::Arc;

use ash::vk;

use crate::color::{exposure_scale, Tonemap};
use crate::vk::pipeline::Pipeline;
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, SingleSet, VkError};

/// (layout, stage, access) of an image at a synchronisation point, as in [`crate::vk::cmd::Transition`].
pub type Access = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

/// The source format the pass is written for (the headless HDR target's format).
pub const SOURCE_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
/// The destination format: 8-bit UNORM holding sRGB-encoded codes.
pub const DESTINATION_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// Descriptor bindings of set 0 (mirrored in `shaders_glsl/tonemap.comp`).
pub const BINDING_SOURCE: u32 = crate::glsl::tonemap_comp::BINDING_SOURCE as u32;
pub const BINDING_DESTINATION: u32 = crate::glsl::tonemap_comp::BINDING_DESTINATION as u32;

/// The destination's state during (and right after) the pass.
pub const DESTINATION_ACCESS: Access = (
    vk::ImageLayout::GENERAL,
    vk::PipelineStageFlags2::COMPUTE_SHADER,
    vk::AccessFlags2::SHADER_STORAGE_WRITE,
);

/// Specialization constant id of the operator in `tonemap.comp`.
const SPEC_TONEMAP: u32 = crate::glsl::tonemap_comp::SPEC_TONEMAP;

/// Workgroup size of `tonemap.comp` in x and y.
const GROUP: u32 = 16;

/// Push constants of `tonemap.comp` (`TonemapPush`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TonemapPush {
    /// [`exposure_scale`] of the exposure in EV, computed on the CPU so both sides use one value.
    pub exposure_scale: f32,
    /// [`tonemap_id`] of the operator.
    pub tonemap: u32,
}

const _: () = assert!(std::mem::size_of::<TonemapPush>() <= 128);

/// The shader's id of an operator (`TONEMAP_*` in `shaders_glsl/include/color.glsl`).
pub fn tonemap_id(tonemap: Tonemap) -> u32 {
    use crate::glsl::include_color as c;
    match tonemap {
        Tonemap::None => c::TONEMAP_NONE,
        Tonemap::Reinhard => c::TONEMAP_REINHARD,
        Tonemap::Aces => c::TONEMAP_ACES,
        Tonemap::KhronosNeutral => c::TONEMAP_KHRONOS_NEUTRAL,
        Tonemap::Agx => c::TONEMAP_AGX,
    }
}

/// The source's state while the pass reads it, for a source kept in `layout`.
pub fn source_access_in(layout: vk::ImageLayout) -> Access {
    (
        layout,
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::SHADER_SAMPLED_READ,
    )
}

fn check_source_layout(layout: vk::ImageLayout) -> Result<(), VkError> {
    match layout {
        vk::ImageLayout::GENERAL
        | vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL
        | vk::ImageLayout::READ_ONLY_OPTIMAL => Ok(()),
        other => Err(VkError::Setup(format!(
            "tonemap: the source image must be in GENERAL or SHADER_READ_ONLY_OPTIMAL, not {other:?}"
        ))),
    }
}

/// The tone-map pass: one compute pipeline and one descriptor set (source, destination).
pub struct TonemapPass {
    /// Built on demand, one per operator used.
    pipelines: Vec<(Tonemap, Pipeline)>,
    module: ShaderModule,
    single: SingleSet,
    source_layout: vk::ImageLayout,
    extent: vk::Extent2D,
    // Last: the device outlives everything above.
    ctx: Arc<Context>,
}

impl TonemapPass {
    /// A pass reading `source` (RGBA32F, kept in `source_layout`: `GENERAL` or
    /// `SHADER_READ_ONLY_OPTIMAL`; its image needs `SAMPLED` usage) and writing `destination`
    /// (an [`DESTINATION_FORMAT`] view of an image with `STORAGE` usage, in `GENERAL` when recorded)
    /// over `extent`. Pixels outside either image are not touched.
    pub fn new(
        ctx: &Arc<Context>,
        source: vk::ImageView,
        source_layout: vk::ImageLayout,
        destination: vk::ImageView,
        extent: vk::Extent2D,
    ) -> Result<Self, VkError> {
        check_source_layout(source_layout)?;
        let single = SingleSet::new(ctx, "tonemap", &["tonemap.comp"])?;
        let module = ShaderModule::new(ctx, "tonemap.comp")?;
        let mut pass = Self {
            pipelines: Vec::new(),
            module,
            single,
            source_layout,
            extent,
            ctx: ctx.clone(),
        };
        pass.write_set(source, destination)?;
        Ok(pass)
    }

    /// Points the pass at other images (a resized viewer). The descriptor set is rewritten in
    /// place: no command buffer that recorded this pass may still be pending.
    pub fn set_images(
        &mut self,
        source: vk::ImageView,
        source_layout: vk::ImageLayout,
        destination: vk::ImageView,
        extent: vk::Extent2D,
    ) -> Result<(), VkError> {
        check_source_layout(source_layout)?;
        self.source_layout = source_layout;
        self.extent = extent;
        self.write_set(source, destination)
    }

    fn write_set(
        &mut self,
        source: vk::ImageView,
        destination: vk::ImageView,
    ) -> Result<(), VkError> {
        let writes = self
            .single
            .writes()
            .view(BINDING_SOURCE, source, self.source_layout)
            .view(BINDING_DESTINATION, destination, vk::ImageLayout::GENERAL);
        // SAFETY: `&mut self` gives this call sole access to the set. The caller's part,
        // documented on `new` and `set_images`: both views are live, with SAMPLED and STORAGE
        // usage, and no pending command buffer recorded this pass
        // (VUID-vkUpdateDescriptorSets-None-03047).
        unsafe { writes.apply(&self.ctx) }
    }

    /// Name for GPU timers and logs.
    pub fn name(&self) -> &'static str {
        "tonemap"
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// The source's state while the pass reads it (the layout given at creation).
    pub fn source_access(&self) -> Access {
        source_access_in(self.source_layout)
    }

    /// Builds the pipeline of `tonemap` unless it exists (call outside command recording).
    pub fn prepare(&mut self, tonemap: Tonemap) -> Result<(), VkError> {
        if self.pipelines.iter().any(|(t, _)| *t == tonemap) {
            return Ok(());
        }
        let name = format!("tonemap[{}]", tonemap.name());
        let pipeline = Pipeline::compute(
            &self.ctx,
            &self.single.layout,
            &name,
            &self.module,
            &[(SPEC_TONEMAP, tonemap_id(tonemap))],
        )?;
        self.pipelines.push((tonemap, pipeline));
        Ok(())
    }

    /// Records the conversion with exposure `exposure_ev` (stops) and `tonemap`, whose pipeline
    /// [`TonemapPass::prepare`] built. The caller has made the source readable as
    /// [`TonemapPass::source_access`] and the destination writable as [`DESTINATION_ACCESS`]; the
    /// destination is left as [`DESTINATION_ACCESS`].
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        exposure_ev: f32,
        tonemap: Tonemap,
    ) -> Result<(), VkError> {
        let d = &self.ctx.device;
        let pipeline = super::prepared(&self.pipelines, &tonemap, || {
            format!("tonemap: the {} pipeline", tonemap.name())
        })?;
        let push = TonemapPush {
            exposure_scale: exposure_scale(exposure_ev),
            tonemap: tonemap_id(tonemap),
        };
        // SAFETY: `pipeline` is this pass's prepared compute pipeline for `tonemap` (looked up
        // above), built with `self.single.layout`, whose set 0 is the one bound and whose push
        // range is a `TonemapPush` (checked by `push`). The dispatch covers `extent`, and the
        // shader skips pixels outside either image. The caller's part, documented above: `cmd`
        // is recording outside a render pass, and the source and destination are in the states
        // `source_access` and `DESTINATION_ACCESS` describe.
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            self.single.bind(cmd, vk::PipelineBindPoint::COMPUTE, 0);
            self.single.layout.push(cmd, &push)?;
            d.cmd_dispatch(
                cmd,
                self.extent.width.div_ceil(GROUP),
                self.extent.height.div_ceil(GROUP),
                1,
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_distinct_and_dense() {
        let mut ids: Vec<u32> = Tonemap::ALL.iter().map(|&t| tonemap_id(t)).collect();
        ids.sort();
        assert_eq!(ids, [0, 1, 2, 3, 4]);
    }
}
