//! Recording the forward pass's draws: instanced runs, and draws split by where shadows can fall.

use ash::vk;

use super::{draws, gpu, shadow, ForwardPass, SET_MATERIAL};

impl ForwardPass {
    /// Binds the frame set `set` (and the environment set) and records, inside the caller's
    /// rendering instance, the draws of `order` (draw indices; entries from `first` on of the
    /// slot's order, whose instance buffer names their objects) at their LOD level (`levels`, by
    /// draw; 0 when empty) with `pipeline_of(draw index)`: one instanced draw per run of draws
    /// that share mesh, level, pipeline and material ([`ForwardPass::runs`]). A draw with a
    /// `shadow_area` is recorded with its own pipeline (the first of `pipeline_of`) inside that
    /// area and with the unshadowed one (the second) around it ([`draws::split::split`]); `area`
    /// is the scissor the caller set, restored after each split draw.
    pub(super) fn record_draws(
        &self,
        cmd: vk::CommandBuffer,
        (set, shadow_set, (order, levels, first)): (
            vk::DescriptorSet,
            vk::DescriptorSet,
            (&[usize], &[u8], usize),
        ),
        pipeline_of: impl Fn(usize) -> (vk::Pipeline, vk::Pipeline),
        area: vk::Rect2D,
    ) {
        let d = &self.ctx.device;
        // SAFETY: `cmd` is recording inside a rendering instance on attachments of the pipelines'
        // formats (both callers); every pipeline, set and buffer bound here belongs to this pass
        // and outlives the command buffer's execution (the owner waits before dropping it); the
        // push-constant bytes are a `MaterialPush`, the layout's range (`forward_interface` checks
        // the size), pushed with its stages.
        unsafe {
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout.raw,
                gpu::SET_FRAME,
                &[set],
                &[],
            );
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout.raw,
                shadow::SET_SHADOW,
                &[shadow_set],
                &[],
            );
            if let Some(env) = self.env_set {
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.layout.raw,
                    gpu::SET_ENV,
                    &[env],
                    &[],
                );
            }
            let mut bound: Option<vk::Pipeline> = None;
            let mut bound_material: Option<usize> = None;
            let mut bound_cull: Option<bool> = None;
            let mut bound_mesh: Option<usize> = None;
            for (start, count) in self.runs(order, levels) {
                let i = order[start];
                let (draw, item) = (&self.draws[i], &self.list.items[i]);
                let (pipeline, unshadowed) = pipeline_of(i);
                if bound_cull != Some(item.cull) {
                    d.cmd_set_cull_mode(
                        cmd,
                        if item.cull {
                            vk::CullModeFlags::BACK
                        } else {
                            vk::CullModeFlags::NONE
                        },
                    );
                    bound_cull = Some(item.cull);
                }
                if bound_material != Some(item.material) {
                    if let Some(&set) = self.materials.sets.get(item.material) {
                        d.cmd_bind_descriptor_sets(
                            cmd,
                            vk::PipelineBindPoint::GRAPHICS,
                            self.layout.raw,
                            SET_MATERIAL,
                            &[set],
                            &[],
                        );
                    }
                    bound_material = Some(item.material);
                }

                let mesh = self.meshes[item.shape].raw();
                mesh.bind((d, cmd), (true, true), (&mut bound_mesh, item.shape));
                crate::render::push_constants(d, cmd, &self.layout, bytemuck::bytes_of(&draw.push));
                let level = self.list.shapes[item.shape].levels
                    [levels.get(i).copied().unwrap_or(0) as usize];
                let parts = match draw.shadow_area {
                    Some(ndc) => draws::split::split(ndc, area),
                    None => vec![(area, true)],
                };
                for (scissor, shadowed) in &parts {
                    let p = if *shadowed { pipeline } else { unshadowed };
                    if bound != Some(p) {
                        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p);
                        bound = Some(p);
                    }
                    if draw.shadow_area.is_some() {
                        d.cmd_set_scissor(cmd, 0, &[*scissor]);
                    }
                    d.cmd_draw_indexed(
                        cmd,
                        level.index_count,
                        count as u32,
                        level.first_index,
                        0,
                        (first + start) as u32,
                    );
                }
                if draw.shadow_area.is_some() {
                    d.cmd_set_scissor(cmd, 0, &[area]);
                }
            }
        }
    }
}
