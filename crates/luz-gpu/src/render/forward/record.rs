//! Recording the forward pass's draws: instanced runs, and draws split by where shadows can fall.

use ash::vk;

use super::{gpu, instances, shadow, ForwardPass, SET_MATERIAL};

impl ForwardPass {
    /// Binds the frame set `set` (and the environment set) and records, inside the caller's
    /// rendering instance, the draws of `order` (draw indices; entries from `first` on of the
    /// slot's order, whose instance buffer names their objects) at their LOD level (`levels`, by
    /// draw; 0 when empty) with `pipeline_of(draw index)`: one instanced draw per run of draws
    /// that share mesh, level, pipeline and material ([`instances::runs`]). A draw with a
    /// [`Draw::shadow_area`] is recorded with its own pipeline (the first of `pipeline_of`)
    /// inside that area and with the unshadowed one (the second) around it ([`split`]); `area`
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
            for (start, count) in instances::runs(&self.draws, (order, levels), self.instancing) {
                let i = order[start];
                let draw = &self.draws[i];
                let (pipeline, unshadowed) = pipeline_of(i);
                if bound_cull != Some(draw.cull) {
                    d.cmd_set_cull_mode(
                        cmd,
                        if draw.cull {
                            vk::CullModeFlags::BACK
                        } else {
                            vk::CullModeFlags::NONE
                        },
                    );
                    bound_cull = Some(draw.cull);
                }
                if bound_material != Some(draw.material) {
                    if let Some(&set) = self.materials.sets.get(draw.material) {
                        d.cmd_bind_descriptor_sets(
                            cmd,
                            vk::PipelineBindPoint::GRAPHICS,
                            self.layout.raw,
                            SET_MATERIAL,
                            &[set],
                            &[],
                        );
                    }
                    bound_material = Some(draw.material);
                }

                let m = &self.meshes[draw.mesh];
                // Objects sharing a mesh (grid49's 49 spheres) bind its buffers once.
                if bound_mesh != Some(draw.mesh) {
                    d.cmd_bind_vertex_buffers(cmd, 0, &[m.vertices.raw], &[0]);
                    if let Some(c) = &m.centroids {
                        d.cmd_bind_vertex_buffers(cmd, 1, &[c.raw], &[0]);
                    }
                    if let Some(c) = &m.colors {
                        d.cmd_bind_vertex_buffers(cmd, 2, &[c.raw], &[0]);
                    }
                    d.cmd_bind_index_buffer(cmd, m.indices.raw, 0, vk::IndexType::UINT32);
                    bound_mesh = Some(draw.mesh);
                }
                d.cmd_push_constants(
                    cmd,
                    self.layout.raw,
                    self.layout.push_stages(),
                    0,
                    bytemuck::bytes_of(&draw.push),
                );
                let level = m.levels[levels.get(i).copied().unwrap_or(0) as usize];
                let parts = match draw.shadow_area {
                    Some(ndc) => split(ndc, area),
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

/// The scissors a draw whose shadow lookups are needed only inside `ndc` (x0, y0, x1, y1 in
/// normalised device coordinates; empty when x0 ≥ x1 or y0 ≥ y1) is recorded with inside the
/// caller's `area`: the area's pixels that `ndc` touches, grown by a pixel (`true`: the shadowed
/// pipeline), and the bands around them (`false`: the unshadowed one). The parts tile `area`
/// without overlap, so each pixel is shaded once.
pub(super) fn split(ndc: [f32; 4], area: vk::Rect2D) -> Vec<(vk::Rect2D, bool)> {
    let (x, y) = (area.offset.x as i64, area.offset.y as i64);
    let (w, h) = (area.extent.width as i64, area.extent.height as i64);
    let px = |v: f32, size: i64, round: fn(f64) -> f64| {
        let p = round((f64::from(v) * 0.5 + 0.5) * size as f64) as i64;
        p.clamp(0, size)
    };
    let (x0, x1) = (px(ndc[0], w, f64::floor), px(ndc[2], w, f64::ceil));
    let (y0, y1) = (px(ndc[1], h, f64::floor), px(ndc[3], h, f64::ceil));
    // Nothing on screen (before growing by a pixel): one unshadowed part.
    let off = x0 >= x1 || y0 >= y1;
    let (x0, x1, y0, y1) = (
        (x0 - 1).max(0),
        (x1 + 1).min(w),
        (y0 - 1).max(0),
        (y1 + 1).min(h),
    );
    let rect = |(ax, ay, bx, by): (i64, i64, i64, i64), shadowed: bool| {
        (bx > ax && by > ay).then_some((
            vk::Rect2D {
                offset: vk::Offset2D {
                    x: (x + ax) as i32,
                    y: (y + ay) as i32,
                },
                extent: vk::Extent2D {
                    width: (bx - ax) as u32,
                    height: (by - ay) as u32,
                },
            },
            shadowed,
        ))
    };
    if off || ndc[0] >= ndc[2] || ndc[1] >= ndc[3] {
        return rect((0, 0, w, h), false).into_iter().collect();
    }
    [
        rect((x0, y0, x1, y1), true),
        rect((0, 0, w, y0), false),
        rect((0, y1, w, h), false),
        rect((0, y0, x0, y1), false),
        rect((x1, y0, w, y1), false),
    ]
    .into_iter()
    .flatten()
    .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(w: u32, h: u32) -> vk::Rect2D {
        vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: vk::Extent2D {
                width: w,
                height: h,
            },
        }
    }

    /// The parts of a split tile the area exactly: every pixel in one part, the shadowed part
    /// holding the NDC rectangle (grown by a pixel), an empty or off-screen rectangle leaving
    /// one unshadowed part, a rectangle over everything one shadowed part.
    #[test]
    fn split_parts_tile_the_area_once() {
        let (w, h) = (64u32, 36u32);
        let cases: [[f32; 4]; 5] = [
            [-0.5, -0.25, 0.5, 0.75],
            [-1.0, -1.0, 1.0, 1.0],
            [0.2, 0.2, 0.1, 0.9],
            [2.0, 2.0, 3.0, 3.0],
            [-3.0, 0.0, 0.0, 3.0],
        ];
        for ndc in cases {
            let parts = split(ndc, area(w, h));
            let mut hits = vec![0u8; (w * h) as usize];
            for (r, _) in &parts {
                for py in r.offset.y..r.offset.y + r.extent.height as i32 {
                    for px in r.offset.x..r.offset.x + r.extent.width as i32 {
                        hits[(py as u32 * w + px as u32) as usize] += 1;
                    }
                }
            }
            assert!(hits.iter().all(|&n| n == 1), "{ndc:?}: {parts:?}");
            let shadowed: Vec<_> = parts.iter().filter(|p| p.1).collect();
            let visible = ndc[0] < ndc[2] && ndc[1] < ndc[3] && ndc[0] < 1.0 && ndc[2] > -1.0;
            assert_eq!(shadowed.len(), usize::from(visible), "{ndc:?}");
        }
        let parts = split([-0.5, -0.25, 0.5, 0.75], area(w, h));
        let inside = parts.iter().find(|p| p.1).unwrap().0;
        // x: 16..48 grown to 15..49; y: 13.5..31.5 → 13..32 grown to 12..33.
        assert_eq!((inside.offset.x, inside.offset.y), (15, 12));
        assert_eq!((inside.extent.width, inside.extent.height), (34, 21));
        assert_eq!(
            split([-1.0, -1.0, 1.0, 1.0], area(w, h)),
            vec![(area(w, h), true)]
        );
    }
}
