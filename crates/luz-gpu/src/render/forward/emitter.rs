//! Area-light emitters seen by the camera (issue 36; docs/area-lights.md): each visible area
//! light drawn as its shape with radiance L = colour · intensity (`emitter.vert`/`emitter.frag`),
//! depth-tested against the opaque scene and writing depth, after the opaque draws and the skybox
//! and before glass and blended draws (in the forward pass), or as a pass of its own after the
//! deferred path's lighting. A scene without visible area lights has none of it: no pipeline, no
//! draw, no pass.

use std::collections::BTreeMap;
use std::sync::Arc;

use ash::vk;

use super::{gpu, shadow, ForwardPass, Output, TargetFormat, SET_MATERIAL};
use crate::scene::{AreaShape, Scene};
use crate::vk::pipeline::{GraphicsDesc, Pipeline, PipelineLayout};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, VkError};

/// Segments of a round shape's polygon and stacks of a sphere's (`emitter.vert`'s
/// `EMITTER_SEGMENTS`, `EMITTER_STACKS`).
const SEGMENTS: u32 = 48;
const STACKS: u32 = 24;

/// The vertices `emitter.vert` draws for `shape` (a triangle list).
pub(super) fn vertex_count(shape: &AreaShape) -> u32 {
    match shape {
        AreaShape::Rect { .. } => 6,
        AreaShape::Disk { .. } => 3 * SEGMENTS,
        AreaShape::Sphere { .. } => 6 * SEGMENTS * STACKS,
        AreaShape::Tube { .. } => 6 * SEGMENTS,
    }
}

/// The emitters of a scene's visible area lights, and their pipelines by output.
pub(super) struct Emitters {
    /// (vertex count, index among the area lights) of each visible area light.
    draws: Vec<(u32, u32)>,
    fog: bool,
    modules: Option<(ShaderModule, ShaderModule)>,
    pipelines: BTreeMap<Output, Pipeline>,
}

impl Emitters {
    /// `None` when no area light of `scene` is visible.
    pub(super) fn new(scene: &Scene) -> Option<Self> {
        let draws: Vec<(u32, u32)> = scene
            .area_lights
            .iter()
            .enumerate()
            .filter(|(_, l)| l.visible)
            .map(|(k, l)| (vertex_count(&l.shape), k as u32))
            .collect();
        (!draws.is_empty()).then(|| Self {
            draws,
            fog: scene.fog.is_some(),
            modules: None,
            pipelines: BTreeMap::new(),
        })
    }

    /// Builds the pipeline for `output` unless it is built.
    pub(super) fn prepare(
        &mut self,
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        target: TargetFormat,
        output: Output,
    ) -> Result<(), VkError> {
        if self.pipelines.contains_key(&output) {
            return Ok(());
        }
        if self.modules.is_none() {
            self.modules = Some((
                ShaderModule::new(ctx, "emitter.vert")?,
                ShaderModule::new(ctx, "emitter.frag")?,
            ));
        }
        let (vs, fs) = self.modules.as_ref().expect("loaded above");
        let mut spec = output.spec().to_vec();
        spec.push((gpu::SPEC_FOG, self.fog as u32));
        let pipeline = Pipeline::graphics(
            ctx,
            layout,
            &GraphicsDesc {
                name: "emitter",
                vertex: vs,
                fragment: fs,
                spec: &spec,
                vertex_bindings: &[],
                vertex_attributes: &[],
                color_formats: &[output.color_format(target.color)],
                depth_format: Some(target.depth),
                samples: target.samples,
                cull: vk::CullModeFlags::NONE,
                depth_test: true,
                // Later glass and blended draws are hidden behind an emitter as behind a surface.
                depth_write: true,
                depth_compare: vk::CompareOp::LESS,
                blend: false,
            },
        )?;
        self.pipelines.insert(output, pipeline);
        Ok(())
    }

    pub(super) fn pipeline(&self, output: Output) -> Option<vk::Pipeline> {
        self.pipelines.get(&output).map(|p| p.raw)
    }
}

impl ForwardPass {
    /// Records, inside the caller's rendering instance (on attachments of `pipeline`'s formats),
    /// one draw per visible emitter with `pipeline` (from [`Emitters::pipeline`]), binding the
    /// forward layout's sets first (frame `set`, `shadow_set`, the environment and a material
    /// set: the shaders share the forward interface).
    pub(super) fn record_emitters(
        &self,
        cmd: vk::CommandBuffer,
        (set, shadow_set): (vk::DescriptorSet, vk::DescriptorSet),
        pipeline: vk::Pipeline,
    ) {
        let Some(emitters) = &self.emitters else {
            return;
        };
        let d = &self.ctx.device;
        let mut sets = vec![(gpu::SET_FRAME, set), (shadow::SET_SHADOW, shadow_set)];
        if let Some(env) = self.env_set {
            sets.push((gpu::SET_ENV, env));
        }
        if let Some(&m) = self.materials.sets.first() {
            sets.push((SET_MATERIAL, m));
        }
        // SAFETY: `cmd` is recording inside a rendering instance on attachments of the
        // pipeline's formats (both callers); the pipeline and every set belong to this pass,
        // were made with (or for) its layout and outlive the command buffer's execution; the
        // pipeline has no vertex input and reads no push constants; viewport and scissor are
        // set by the caller, the cull mode here.
        unsafe {
            for (index, s) in sets {
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.layout.raw,
                    index,
                    &[s],
                    &[],
                );
            }
            d.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            for &(count, index) in &emitters.draws {
                d.cmd_draw(cmd, count, 1, 0, index);
            }
        }
    }
}
