//! The GPU side of the sweep: `GpuEvaluator`, the Vulkan compute mirror of the CPU reference.

use std::sync::Arc;

use anyhow::Result;
use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use crate::brdf::GpuBrdfParams;
use crate::glsl::brdf_eval_comp as glsl;
use crate::vk::cmd::CommandPool;
use crate::vk::pipeline::Pipeline;
use crate::vk::shaders::ShaderModule;
use crate::vk::{Buffer, Context, SingleSet};

use super::{Batch, Case, Evaluator, Output};

/// The GPU mirror: `brdf_eval.comp` (brdf_eval / brdf_radiance of `models.glsl`), one invocation
/// per case, parameters packed by [`GpuBrdfParams::from_model`] as the renderer packs them.
pub struct GpuEvaluator {
    single: SingleSet,
    pipeline: Pipeline,
    pool: CommandPool,
    max_cases: usize,
    ctx: Arc<Context>,
}

// The buffers are written in binding order (params, cases, results) below.
const _: () =
    assert!(glsl::BINDING_PARAMS == 0 && glsl::BINDING_CASES == 1 && glsl::BINDING_RESULTS == 2);

/// The GLSL `BrdfCase` (std430, 96 bytes).
const CASE_BYTES: usize = 96;
const GROUP: u32 = 64;

impl GpuEvaluator {
    pub fn new(ctx: &Arc<Context>) -> Result<Self> {
        let single = SingleSet::new(ctx, "brdf_eval", &["brdf_eval.comp"])?;
        // One pipeline for every model: specialising per (model, D, G, F) was measured slower on
        // lavapipe (71 JIT compilations cost more than the branches they remove).
        let module = ShaderModule::new(ctx, "brdf_eval.comp")?;
        let pipeline = Pipeline::compute(ctx, &single.layout, "brdf_eval", &module, &[])?;
        let pool = CommandPool::new(ctx, "brdf_eval commands")?;
        // Results take 64 bytes per case, inputs 96: stay well inside maxStorageBufferRange.
        let range = ctx.info.limits.max_storage_buffer_range as usize;
        let max_cases = (range / CASE_BYTES).clamp(1024, 1 << 18);
        Ok(Self {
            single,
            pipeline,
            pool,
            max_cases,
            ctx: ctx.clone(),
        })
    }

    fn run_chunk(
        &mut self,
        params: &Buffer,
        cases: &[Case],
        intensities: [f32; 3],
        with_radiance: bool,
        out: &mut Vec<Output>,
    ) -> Result<()> {
        let ctx = &self.ctx;
        let mut bytes = Vec::with_capacity(cases.len() * CASE_BYTES);
        for c in cases {
            for v in [c.n, c.l, c.v, c.x, c.y] {
                for f in [v.x, v.y, v.z, 0.0] {
                    bytes.extend_from_slice(&f.to_ne_bytes());
                }
            }
            for u in [c.set, 0, 0, 0] {
                bytes.extend_from_slice(&u.to_ne_bytes());
            }
        }
        let case_buf = Buffer::with_data(
            ctx,
            "brdf_eval cases",
            &bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let per_case = if with_radiance { 4 } else { 1 };
        let results = Buffer::new(
            ctx,
            "brdf_eval results",
            (cases.len() * per_case * 16) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
        )?;
        let writes = [params, &case_buf, &results]
            .iter()
            .enumerate()
            .fold(self.single.writes(), |w, (i, b)| w.buffer(i as u32, b.raw));
        // SAFETY: no command buffer using the set is pending (the previous chunk's `one_shot`
        // waited); the buffers are live storage buffers.
        unsafe { writes.apply(ctx) }?;
        let count = cases.len() as u32;
        let max_groups = ctx.info.limits.max_compute_work_group_count[0].min(65_535);
        let d = ctx.device.clone();
        let (layout, pipeline, set) =
            (self.single.layout.raw, self.pipeline.raw, self.single.set());
        let results_raw = (results.raw, results.size);
        let record = move |cmd: vk::CommandBuffer| {
            // SAFETY: `cmd` is recording (the graph's pass, inside `one_shot`); the pipeline, layout
            // and set belong to this evaluator and outlive the submission, which `one_shot` waits
            // for.
            unsafe {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    layout,
                    0,
                    &[set],
                    &[],
                );
            }
            let mut base = 0u32;
            while base < count {
                let groups = (count - base).div_ceil(GROUP).min(max_groups);
                let mut push = Vec::with_capacity(32);
                for f in [intensities[0], intensities[1], intensities[2], 0.0] {
                    push.extend_from_slice(&f.to_ne_bytes());
                }
                for u in [base, count, with_radiance as u32, 0] {
                    push.extend_from_slice(&u.to_ne_bytes());
                }
                // SAFETY: `cmd` is recording (inside `one_shot`), the pipeline bound above uses `layout`, and
                // `push` is the 32 bytes of its COMPUTE push-constant range.
                unsafe {
                    d.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::COMPUTE, 0, &push);
                    d.cmd_dispatch(cmd, groups, 1, 1);
                }
                base += groups * GROUP;
            }
        };
        self.pool.one_shot(|cmd| {
            // One compute node writing the results, which the graph makes visible to the host.
            let mut g = crate::graph::FrameGraph::new();
            let out = g.import_buffer("brdf_eval results", results_raw.0, results_raw.1, None);
            g.buffer_after(out, crate::graph::Access::HostRead);
            g.pass("brdf_eval")
                .write(out, crate::graph::Access::ComputeStorageBufferWrite)
                .record(move |rc| {
                    rc.buffer(out)?;
                    record(rc.cmd());
                    Ok(())
                });
            let graph = g.compile()?;
            crate::render::frame::Transients::new(ctx).execute(ctx, graph, cmd, None)?;
            Ok(())
        })?;
        let mapped = results.mapped()?;
        let word = |i: usize| {
            f32::from_ne_bytes([
                mapped[4 * i],
                mapped[4 * i + 1],
                mapped[4 * i + 2],
                mapped[4 * i + 3],
            ])
        };
        let vec = |k: usize| Vec3::new(word(4 * k), word(4 * k + 1), word(4 * k + 2));
        for i in 0..cases.len() {
            out.push(if with_radiance {
                Output {
                    f: vec(4 * i),
                    radiance: [vec(4 * i + 1), vec(4 * i + 2), vec(4 * i + 3)],
                }
            } else {
                Output {
                    f: vec(i),
                    radiance: [Vec3::ZERO; 3],
                }
            });
        }
        Ok(())
    }
}

impl Evaluator for GpuEvaluator {
    fn name(&self) -> &str {
        "gpu"
    }

    fn evaluate(&mut self, batch: &Batch<'_>) -> Result<Vec<Output>> {
        let mut params = Vec::with_capacity(batch.sets.len() * GpuBrdfParams::SIZE);
        for m in batch.sets {
            params.extend_from_slice(&GpuBrdfParams::from_model(m).to_bytes());
        }
        let params = Buffer::with_data(
            &self.ctx,
            "brdf_eval params",
            &params,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let mut out = Vec::with_capacity(batch.cases.len());
        for chunk in batch.cases.chunks(self.max_cases) {
            self.run_chunk(
                &params,
                chunk,
                batch.intensities,
                batch.with_radiance,
                &mut out,
            )?;
        }
        Ok(out)
    }
}
