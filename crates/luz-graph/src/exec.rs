//! Executing a compiled graph: allocating transients, recording barriers, timer scopes and the
//! passes' closures into one command buffer.

use ash::vk;

use crate::access::{Access, MemoryBarrier, WRITE_ACCESS};
use crate::error::{GraphError, PassError};
use crate::plan::{BarrierInfo, BufferInfo, ImageInfo, Plan};
use crate::pool::{ImageFactory, PooledImage, TransientPool};
use crate::resource::ImageSource;
use crate::resource::{BufferHandle, ImageDesc, ImageHandle, Resource, SubresourceRange};

/// An image barrier ready to record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageBarrier {
    /// The image.
    pub image: vk::Image,
    /// Aspects.
    pub aspect: vk::ImageAspectFlags,
    /// Absolute mips and layers.
    pub range: SubresourceRange,
    /// Layout before.
    pub old_layout: vk::ImageLayout,
    /// Layout after.
    pub new_layout: vk::ImageLayout,
    /// Its source and destination scopes.
    pub scopes: MemoryBarrier,
}

/// A buffer barrier ready to record (the whole buffer).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BufferBarrier {
    /// The buffer.
    pub buffer: vk::Buffer,
    /// Its source and destination scopes.
    pub scopes: MemoryBarrier,
}

/// Everything one `vkCmdPipelineBarrier2` records.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BarrierBatch {
    /// Global memory barriers.
    pub memory: Vec<MemoryBarrier>,
    /// Buffer barriers.
    pub buffers: Vec<BufferBarrier>,
    /// Image barriers.
    pub images: Vec<ImageBarrier>,
}

impl BarrierBatch {
    /// Whether there is nothing to record.
    pub fn is_empty(&self) -> bool {
        self.memory.is_empty() && self.buffers.is_empty() && self.images.is_empty()
    }
}

/// Where execution records its commands: [`AshRecorder`] on a real device, a logging fake in
/// tests.
pub trait Recorder {
    /// The device record closures record with.
    fn device(&self) -> &ash::Device;
    /// Records one pipeline barrier.
    fn pipeline_barrier(&mut self, cmd: vk::CommandBuffer, batch: &BarrierBatch);
}

/// Records with `device` (`cmd` must be in the recording state on the caller's thread).
pub struct AshRecorder<'d> {
    device: &'d ash::Device,
}

impl<'d> AshRecorder<'d> {
    /// A recorder for `device` (with synchronization2 enabled).
    pub fn new(device: &'d ash::Device) -> Self {
        Self { device }
    }
}

impl Recorder for AshRecorder<'_> {
    fn device(&self) -> &ash::Device {
        self.device
    }

    fn pipeline_barrier(&mut self, cmd: vk::CommandBuffer, batch: &BarrierBatch) {
        record_barriers(self.device, cmd, batch);
    }
}

/// Sets a synchronization2 barrier's four scope masks from a [`MemoryBarrier`].
macro_rules! with_scopes {
    ($barrier:expr, $b:expr) => {
        $barrier
            .src_stage_mask($b.src_stages)
            .src_access_mask($b.src_access)
            .dst_stage_mask($b.dst_stages)
            .dst_access_mask($b.dst_access)
    };
}

impl MemoryBarrier {
    /// As a `MemoryBarrier2`.
    fn to_vk(self) -> vk::MemoryBarrier2<'static> {
        with_scopes!(vk::MemoryBarrier2::default(), self)
    }
}

impl BufferBarrier {
    /// As a `BufferMemoryBarrier2`.
    fn to_vk(self) -> vk::BufferMemoryBarrier2<'static> {
        let whole = vk::BufferMemoryBarrier2::default()
            .buffer(self.buffer)
            .offset(0)
            .size(vk::WHOLE_SIZE);
        with_scopes!(whole, self.scopes)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
    }
}

impl ImageBarrier {
    /// As an `ImageMemoryBarrier2`.
    fn to_vk(self) -> vk::ImageMemoryBarrier2<'static> {
        let transition = vk::ImageMemoryBarrier2::default()
            .image(self.image)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: self.aspect,
                base_mip_level: self.range.base_mip,
                level_count: self.range.mip_count,
                base_array_layer: self.range.base_layer,
                layer_count: self.range.layer_count,
            })
            .old_layout(self.old_layout)
            .new_layout(self.new_layout);
        with_scopes!(transition, self.scopes)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
    }
}

/// Records `batch` as one `vkCmdPipelineBarrier2`: the only place of the crate calling it.
///
/// Contract: `cmd` is in the recording state, externally synchronised by the caller, on a device
/// with synchronization2; the handles in `batch` are live resources of that device.
fn record_barriers(device: &ash::Device, cmd: vk::CommandBuffer, batch: &BarrierBatch) {
    if batch.is_empty() {
        return;
    }
    let memory: Vec<_> = batch.memory.iter().map(|b| b.to_vk()).collect();
    let buffers: Vec<_> = batch.buffers.iter().map(|b| b.to_vk()).collect();
    let images: Vec<_> = batch.images.iter().map(|b| b.to_vk()).collect();
    let dep = vk::DependencyInfo::default()
        .memory_barriers(&memory)
        .buffer_memory_barriers(&buffers)
        .image_memory_barriers(&images);
    // SAFETY: `dep` and the three barrier arrays are locals that outlive the call. The caller
    // guarantees (the contract of this function, upheld by `CompiledGraph::execute`'s contract)
    // that `cmd` is recording and externally synchronised, that synchronization2 is enabled and
    // that every image and buffer named is a live resource of `device`.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dep) };
}

/// A pass's recording: runs once at execution if the pass is live, borrowing the caller's state
/// for the graph's lifetime `'a`.
pub type RecordFn<'a> = Box<dyn FnOnce(&mut RecordContext<'_>) -> Result<(), PassError> + 'a>;

/// A graph ready to execute: the [`Plan`] and the live passes' record closures.
pub struct CompiledGraph<'a> {
    pub(crate) plan: Plan,
    pub(crate) records: Vec<Option<RecordFn<'a>>>,
}

impl CompiledGraph<'_> {
    /// The plan (passes, barriers) as data.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }
}

/// GPU timer scopes around passes (luz's `GpuTimer`).
pub trait PassTimer {
    /// Opens the scope of pass `name` (e.g. writes a timestamp); returns its query slot.
    fn begin(&mut self, cmd: vk::CommandBuffer, name: &'static str) -> Option<u32>;
    /// Closes the scope opened with `slot`.
    fn end(&mut self, cmd: vk::CommandBuffer, slot: Option<u32>);
}

/// An image as a pass sees it.
#[derive(Clone, Copy, Debug)]
pub struct ImageRef {
    /// The image.
    pub image: vk::Image,
    /// A view of all of it (imported: the caller's view).
    pub view: vk::ImageView,
    /// Size of mip 0.
    pub extent: vk::Extent2D,
    /// Format.
    pub format: vk::Format,
    /// Its full description.
    pub desc: ImageDesc,
    /// The absolute range this pass declared (the bounding box of its declarations).
    pub range: vk::ImageSubresourceRange,
}

/// A buffer as a pass sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BufferRef {
    /// The buffer.
    pub buffer: vk::Buffer,
    /// Its size in bytes.
    pub size: vk::DeviceSize,
}

/// An image resolved for execution.
#[derive(Clone, Copy, Debug)]
struct Resolved {
    image: vk::Image,
    view: vk::ImageView,
    /// Offset of the managed range.
    base_mip: u32,
    base_layer: u32,
    aspect: vk::ImageAspectFlags,
    pool_slot: Option<usize>,
}

impl Resolved {
    fn offset(&self, r: SubresourceRange) -> SubresourceRange {
        SubresourceRange::new(
            self.base_mip + r.base_mip,
            r.mip_count,
            self.base_layer + r.base_layer,
            r.layer_count,
        )
    }

    fn absolute(&self, r: SubresourceRange) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level: self.base_mip + r.base_mip,
            level_count: r.mip_count,
            base_array_layer: self.base_layer + r.base_layer,
            layer_count: r.layer_count,
        }
    }
}

/// What a pass may touch while it records: the command buffer, the device, and the resources it
/// declared (anything else is refused).
pub struct RecordContext<'r> {
    recorder: &'r mut dyn Recorder,
    cmd: vk::CommandBuffer,
    pass: &'static str,
    images: &'r [ImageInfo],
    resolved: &'r [Option<Resolved>],
    buffers: &'r [BufferInfo],
    declared_images: Vec<(ImageHandle, SubresourceRange)>,
    declared_buffers: Vec<BufferHandle>,
    violation: Option<GraphError>,
}

impl<'r> RecordContext<'r> {
    /// The command buffer being recorded.
    pub fn cmd(&self) -> vk::CommandBuffer {
        self.cmd
    }

    /// The device.
    pub fn device(&self) -> &ash::Device {
        self.recorder.device()
    }

    /// The pass's name.
    pub fn pass(&self) -> &'static str {
        self.pass
    }

    fn refuse(&mut self, r: Resource) -> GraphError {
        let resource = match r {
            Resource::Image(h) => self.images.get(h.index()).map(|i| i.name.clone()),
            Resource::Buffer(h) => self.buffers.get(h.index()).map(|b| b.name.clone()),
        }
        .unwrap_or_else(|| format!("{r:?}"));
        let e = GraphError::Undeclared {
            pass: self.pass,
            resource: resource.clone(),
        };
        self.violation.get_or_insert(GraphError::Undeclared {
            pass: self.pass,
            resource,
        });
        e
    }

    fn declared_image(
        &mut self,
        h: ImageHandle,
    ) -> Result<(Resolved, SubresourceRange), GraphError> {
        let found = self
            .declared_images
            .iter()
            .find(|(d, _)| *d == h)
            .map(|&(_, r)| r);
        match (found, self.resolved.get(h.index()).copied().flatten()) {
            (Some(r), Some(res)) => Ok((res, r)),
            _ => Err(self.refuse(Resource::Image(h))),
        }
    }

    /// The image `h`, if this pass declared it; otherwise [`GraphError::Undeclared`] (and the
    /// execution fails even if the closure ignores the error).
    pub fn image(&mut self, h: ImageHandle) -> Result<ImageRef, GraphError> {
        let (res, range) = self.declared_image(h)?;
        let desc = self.images[h.index()].desc;
        Ok(ImageRef {
            image: res.image,
            view: res.view,
            extent: desc.extent(),
            format: desc.format,
            desc,
            range: res.absolute(range),
        })
    }

    /// The buffer `h`, if this pass declared it; otherwise [`GraphError::Undeclared`].
    pub fn buffer(&mut self, h: BufferHandle) -> Result<BufferRef, GraphError> {
        if !self.declared_buffers.contains(&h) {
            return Err(self.refuse(Resource::Buffer(h)));
        }
        let b = &self.buffers[h.index()];
        Ok(BufferRef {
            buffer: b.buffer,
            size: b.size,
        })
    }

    /// A barrier on the range this pass declared of `h`, between two of its own uses (e.g.
    /// dispatches of a reduction). The pass must leave the image in its declared access.
    pub fn barrier(&mut self, h: ImageHandle, from: Access, to: Access) -> Result<(), GraphError> {
        let (_, range) = self.declared_image(h)?;
        self.barrier_range(h, range, from, to)
    }

    /// A barrier on `range` (relative, within what this pass declared) of `h`.
    pub fn barrier_range(
        &mut self,
        h: ImageHandle,
        range: SubresourceRange,
        from: Access,
        to: Access,
    ) -> Result<(), GraphError> {
        let (res, _) = self.declared_image(h)?;
        self.own_barrier(Own::Image(res, range), from, to);
        Ok(())
    }

    /// A barrier on buffer `h` between two of this pass's own uses.
    pub fn buffer_barrier(
        &mut self,
        h: BufferHandle,
        from: Access,
        to: Access,
    ) -> Result<(), GraphError> {
        let b = self.buffer(h)?;
        self.own_barrier(Own::Buffer(b.buffer), from, to);
        Ok(())
    }

    /// A global memory barrier between two of this pass's own uses.
    pub fn memory_barrier(&mut self, from: Access, to: Access) {
        self.own_barrier(Own::Memory, from, to);
    }

    /// Records one barrier between two of this pass's own uses on `what`: the source scope is
    /// `from`'s stages and writes, the destination scope `to`'s stages and accesses.
    fn own_barrier(&mut self, what: Own, from: Access, to: Access) {
        let scopes = MemoryBarrier {
            src_stages: from.stages(),
            src_access: from.access() & WRITE_ACCESS,
            dst_stages: to.stages(),
            dst_access: to.access(),
        };
        let mut batch = BarrierBatch::default();
        match what {
            Own::Image(res, range) => batch.images.push(ImageBarrier {
                image: res.image,
                aspect: res.aspect,
                range: res.offset(range),
                old_layout: from.layout(),
                new_layout: to.layout(),
                scopes,
            }),
            Own::Buffer(buffer) => batch.buffers.push(BufferBarrier { buffer, scopes }),
            Own::Memory => batch.memory.push(scopes),
        }
        self.recorder.pipeline_barrier(self.cmd, &batch);
    }
}

/// What [`RecordContext::own_barrier`] synchronises.
enum Own {
    /// A range (relative to the pass's declaration) of a resolved image.
    Image(Resolved, SubresourceRange),
    /// A whole buffer.
    Buffer(vk::Buffer),
    /// All memory.
    Memory,
}

/// What an execution did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ExecReport {
    /// Passes recorded, in order.
    pub recorded: Vec<&'static str>,
    /// Passes culled.
    pub culled: Vec<&'static str>,
    /// `vkCmdPipelineBarrier2` calls made by the graph (not counting the passes' own).
    pub barrier_calls: usize,
    /// Transient images created this time.
    pub images_created: usize,
    /// Transients served by an image already in the pool.
    pub images_reused: usize,
    /// Pooled images dropped for being unused too long.
    pub images_released: usize,
}

/// Turns plan barriers into a batch with raw handles.
fn resolve_batch(
    barriers: &[BarrierInfo],
    resolved: &[Option<Resolved>],
    buffers: &[BufferInfo],
    pool_scopes: &[(vk::PipelineStageFlags2, vk::AccessFlags2)],
) -> BarrierBatch {
    let mut batch = BarrierBatch::default();
    for b in barriers {
        match b.handle {
            Resource::Image(h) => {
                let Some(res) = resolved[h.index()] else {
                    continue;
                };
                let mut scopes = b.scopes;
                if b.after_pool_use {
                    let (s, a) = pool_scopes[h.index()];
                    scopes.src_stages |= s;
                    scopes.src_access |= a;
                }
                batch.images.push(ImageBarrier {
                    image: res.image,
                    aspect: res.aspect,
                    range: res.offset(b.range.unwrap_or(SubresourceRange::new(0, 1, 0, 1))),
                    old_layout: b.old_layout,
                    new_layout: b.new_layout,
                    scopes,
                });
            }
            Resource::Buffer(h) => batch.buffers.push(BufferBarrier {
                buffer: buffers[h.index()].buffer,
                scopes: b.scopes,
            }),
        }
    }
    batch
}

/// The bounding box of two ranges.
fn union(a: SubresourceRange, b: SubresourceRange) -> SubresourceRange {
    let m0 = a.base_mip.min(b.base_mip);
    let m1 = (a.base_mip + a.mip_count).max(b.base_mip + b.mip_count);
    let l0 = a.base_layer.min(b.base_layer);
    let l1 = (a.base_layer + a.layer_count).max(b.base_layer + b.layer_count);
    SubresourceRange::new(m0, m1 - m0, l0, l1 - l0)
}

impl CompiledGraph<'_> {
    /// Records the graph into `cmd` with `device`: allocates transients from `pool` (creating
    /// images with `factory`), then per live pass one barrier, its timer scope and its closure,
    /// then the final barriers.
    ///
    /// Contract: `cmd` is in the recording state, outside a render pass, on this thread; the
    /// device has synchronization2; imported handles are live. Graphs sharing `pool` must be
    /// submitted to one queue in the order they execute.
    pub fn execute<F: ImageFactory>(
        self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pool: &mut TransientPool<F>,
        factory: &mut F,
        timer: Option<&mut dyn PassTimer>,
    ) -> Result<ExecReport, GraphError> {
        self.execute_with(&mut AshRecorder::new(device), cmd, pool, factory, timer)
    }

    /// [`CompiledGraph::execute`] through any [`Recorder`].
    pub fn execute_with<F: ImageFactory>(
        self,
        recorder: &mut dyn Recorder,
        cmd: vk::CommandBuffer,
        pool: &mut TransientPool<F>,
        factory: &mut F,
        timer: Option<&mut dyn PassTimer>,
    ) -> Result<ExecReport, GraphError> {
        pool.begin();
        let result = self.run(recorder, cmd, pool, factory, timer);
        if result.is_err() {
            pool.poison_in_use();
        }
        let released = pool.end();
        result.map(|mut r| {
            r.images_released = released;
            r
        })
    }

    fn run<F: ImageFactory>(
        self,
        recorder: &mut dyn Recorder,
        cmd: vk::CommandBuffer,
        pool: &mut TransientPool<F>,
        factory: &mut F,
        mut timer: Option<&mut dyn PassTimer>,
    ) -> Result<ExecReport, GraphError> {
        let CompiledGraph { plan, records } = self;
        let mut report = ExecReport {
            culled: plan.culled_passes(),
            ..Default::default()
        };
        let none = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
        let mut pool_scopes = vec![none; plan.images.len()];
        let mut resolved: Vec<Option<Resolved>> = plan
            .images
            .iter()
            .map(|im| match im.source {
                ImageSource::Imported(imp) => Some(Resolved {
                    image: imp.image,
                    view: imp.view,
                    base_mip: imp.range.base_mip_level,
                    base_layer: imp.range.base_array_layer,
                    aspect: imp.range.aspect_mask,
                    pool_slot: None,
                }),
                ImageSource::Transient => None,
            })
            .collect();

        for ((pi, pass), record) in plan.passes.iter().enumerate().zip(records) {
            if !pass.live {
                continue;
            }
            // Transients whose lifetime starts here.
            for (i, im) in plan.images.iter().enumerate() {
                if im.imported || im.lifetime.map(|l| l.0) != Some(pi) {
                    continue;
                }
                let got = pool.acquire(factory, &im.name, &im.desc).map_err(|e| {
                    GraphError::Allocation {
                        resource: im.name.clone(),
                        source: Box::new(e),
                    }
                })?;
                if got.created {
                    report.images_created += 1;
                } else {
                    report.images_reused += 1;
                }
                pool_scopes[i] = got.previous_scope;
                let img = pool.image(got.slot);
                resolved[i] = Some(Resolved {
                    image: img.raw(),
                    view: img.view(),
                    base_mip: 0,
                    base_layer: 0,
                    aspect: im.desc.aspect,
                    pool_slot: Some(got.slot),
                });
            }

            let slot = timer.as_deref_mut().and_then(|t| t.begin(cmd, pass.name));
            let batch = resolve_batch(&pass.barriers, &resolved, &plan.buffers, &pool_scopes);
            if !batch.is_empty() {
                recorder.pipeline_barrier(cmd, &batch);
                report.barrier_calls += 1;
            }

            let mut declared_images: Vec<(ImageHandle, SubresourceRange)> = Vec::new();
            let mut declared_buffers = Vec::new();
            for u in &pass.uses {
                match u.resource {
                    Resource::Image(h) => {
                        let (mips, layers) = plan.images[h.index()].dims;
                        let r = u.range.unwrap_or(SubresourceRange::whole(mips, layers));
                        match declared_images.iter_mut().find(|(d, _)| *d == h) {
                            Some((_, d)) => *d = union(*d, r),
                            None => declared_images.push((h, r)),
                        }
                    }
                    Resource::Buffer(h) => declared_buffers.push(h),
                }
            }
            if let Some(f) = record {
                let mut rc = RecordContext {
                    recorder: &mut *recorder,
                    cmd,
                    pass: pass.name,
                    images: &plan.images,
                    resolved: &resolved,
                    buffers: &plan.buffers,
                    declared_images,
                    declared_buffers,
                    violation: None,
                };
                let result = f(&mut rc);
                if let Some(v) = rc.violation.take() {
                    return Err(v);
                }
                result.map_err(|source| GraphError::Pass {
                    pass: pass.name,
                    source,
                })?;
            }
            if let Some(t) = timer.as_deref_mut() {
                t.end(cmd, slot);
            }
            report.recorded.push(pass.name);

            // Transients whose lifetime ends here go back to the pool.
            for (i, im) in plan.images.iter().enumerate() {
                if im.imported || im.lifetime.map(|l| l.1) != Some(pi) {
                    continue;
                }
                if let Some(slot) = resolved[i].and_then(|r| r.pool_slot) {
                    pool.release(slot, im.final_scope, im.final_includes_previous);
                }
            }
        }

        let batch = resolve_batch(&plan.final_barriers, &resolved, &plan.buffers, &pool_scopes);
        if !batch.is_empty() {
            recorder.pipeline_barrier(cmd, &batch);
            report.barrier_calls += 1;
        }
        Ok(report)
    }
}
