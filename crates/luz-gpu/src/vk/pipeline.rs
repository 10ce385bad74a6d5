//! Pipelines, pipeline layouts, descriptor set layouts and pools, all destroyed on drop.

use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;

use super::shaders::ShaderModule;
use super::{Context, VkError};

const MAIN: &CStr = c"main";

/// One binding of a set layout: its number, type, array count, stages and GLSL name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LayoutBinding {
    pub binding: u32,
    pub ty: vk::DescriptorType,
    pub count: u32,
    pub stages: vk::ShaderStageFlags,
    pub name: &'static str,
}

/// A descriptor set layout, with the bindings it was made from (pools and writes read them).
/// Made from the shaders' reflected interface ([`super::interface::Interface::set_layout`]).
pub struct DescriptorSetLayout {
    pub raw: vk::DescriptorSetLayout,
    bindings: Vec<LayoutBinding>,
    name: String,
    /// Made for push descriptors (`VK_KHR_push_descriptor`): no set is allocated from it.
    pushed: bool,
    ctx: Arc<Context>,
}

impl DescriptorSetLayout {
    pub(super) fn from_bindings(
        ctx: &Arc<Context>,
        name: &str,
        bindings: Vec<LayoutBinding>,
    ) -> Result<Self, VkError> {
        Self::create(ctx, name, bindings, false)
    }

    /// A layout of `bindings`; `pushed`: for descriptors pushed into the command buffer
    /// ([`super::interface::PushSet`]), no set is allocated from it.
    pub(super) fn create(
        ctx: &Arc<Context>,
        name: &str,
        bindings: Vec<LayoutBinding>,
        pushed: bool,
    ) -> Result<Self, VkError> {
        let raw_bindings: Vec<_> = bindings
            .iter()
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b.binding)
                    .descriptor_type(b.ty)
                    .descriptor_count(b.count)
                    .stage_flags(b.stages)
            })
            .collect();
        let flags = if pushed {
            vk::DescriptorSetLayoutCreateFlags::PUSH_DESCRIPTOR_KHR
        } else {
            vk::DescriptorSetLayoutCreateFlags::empty()
        };
        let info = vk::DescriptorSetLayoutCreateInfo::default()
            .flags(flags)
            .bindings(&raw_bindings);
        // SAFETY: `info` and the `raw_bindings` slice it points to outlive the call; the device is
        // alive while `ctx` is, and was created with VK_KHR_push_descriptor (the flag's
        // extension: `device::REQUIRED_EXTENSIONS`).
        let raw = unsafe { ctx.device.create_descriptor_set_layout(&info, None) }?;
        ctx.set_name(raw, name);
        Ok(Self {
            raw,
            bindings,
            name: name.to_string(),
            pushed,
            ctx: ctx.clone(),
        })
    }

    /// A layout with no binding: a set index the pipelines built with it do not use.
    pub fn empty(ctx: &Arc<Context>, name: &str) -> Result<Self, VkError> {
        Self::from_bindings(ctx, name, Vec::new())
    }

    /// The bindings, sorted by number.
    pub fn bindings(&self) -> &[LayoutBinding] {
        &self.bindings
    }

    /// The debug name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Whether the layout is for push descriptors.
    pub fn is_pushed(&self) -> bool {
        self.pushed
    }
}

impl Drop for DescriptorSetLayout {
    fn drop(&mut self) {
        // SAFETY: `self.raw` was created from `self.ctx.device` (alive through `self.ctx`) and is
        // destroyed only here. A set layout may be destroyed while sets and pipeline layouts made
        // from it are still used; the passes that own one never update their sets after dropping it
        // (they drop it along with the sets' pool).
        unsafe {
            self.ctx
                .device
                .destroy_descriptor_set_layout(self.raw, None)
        };
    }
}

pub struct DescriptorPool {
    pub raw: vk::DescriptorPool,
    ctx: Arc<Context>,
}

impl DescriptorPool {
    /// A pool for `count` sets of each layout (and nothing more).
    pub fn for_sets(
        ctx: &Arc<Context>,
        name: &str,
        sets: &[(&DescriptorSetLayout, u32)],
    ) -> Result<Self, VkError> {
        let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
        for (layout, count) in sets {
            for b in layout.bindings() {
                match sizes.iter_mut().find(|s| s.ty == b.ty) {
                    Some(s) => s.descriptor_count += b.count * count,
                    None => sizes.push(vk::DescriptorPoolSize {
                        ty: b.ty,
                        descriptor_count: b.count * count,
                    }),
                }
            }
        }
        let max_sets = sets.iter().map(|(_, n)| n).sum::<u32>().max(1);
        Self::new(ctx, name, max_sets, &sizes)
    }

    fn new(
        ctx: &Arc<Context>,
        name: &str,
        max_sets: u32,
        sizes: &[vk::DescriptorPoolSize],
    ) -> Result<Self, VkError> {
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(max_sets)
            .pool_sizes(sizes);
        // SAFETY: `info` and the `sizes` slice it points to outlive the call.
        let raw = unsafe { ctx.device.create_descriptor_pool(&info, None) }?;
        ctx.set_name(raw, name);
        Ok(Self {
            raw,
            ctx: ctx.clone(),
        })
    }

    pub fn allocate(&self, layout: &DescriptorSetLayout) -> Result<vk::DescriptorSet, VkError> {
        let layouts = [layout.raw];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.raw)
            .set_layouts(&layouts);
        // SAFETY: `info` and `layouts` are locals that outlive the call; `self.raw` and
        // `layout.raw` are live objects of this device. The pool is externally synchronised: luz
        // uses pools only from the one thread that records and submits. An exhausted pool is an
        // error result, not undefined behaviour.
        Ok(unsafe { self.ctx.device.allocate_descriptor_sets(&info) }?[0])
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        // SAFETY: `self.raw` was created from `self.ctx.device` (alive through `self.ctx`) and is
        // destroyed only here, which also frees its sets; their owners never use those sets again.
        // No submitted command uses the sets any more (VUID-vkDestroyDescriptorPool-descriptorPool-00303):
        // owners drop passes only after waiting for their work (fences, `device_wait_idle`).
        unsafe { self.ctx.device.destroy_descriptor_pool(self.raw, None) };
    }
}

pub struct PipelineLayout {
    pub raw: vk::PipelineLayout,
    /// The push-constant range (at most one), if any.
    push: Option<vk::PushConstantRange>,
    ctx: Arc<Context>,
}

impl PipelineLayout {
    pub(super) fn new(
        ctx: &Arc<Context>,
        name: &str,
        sets: &[&DescriptorSetLayout],
        push: &[vk::PushConstantRange],
    ) -> Result<Self, VkError> {
        let max_push = ctx.info.limits.max_push_constants_size;
        for p in push {
            if p.offset + p.size > max_push {
                return Err(VkError::Limit {
                    what: format!("{name} push constants"),
                    requested: (p.offset + p.size) as u64,
                    limit: max_push as u64,
                    limit_name: "maxPushConstantsSize",
                });
            }
        }
        let raw_sets: Vec<_> = sets.iter().map(|s| s.raw).collect();
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&raw_sets)
            .push_constant_ranges(push);
        // SAFETY: `info`, `raw_sets` and `push` outlive the call; the set layouts are live objects
        // of this device (borrowed for the call), and every push-constant range fits
        // maxPushConstantsSize (checked above).
        let raw = unsafe { ctx.device.create_pipeline_layout(&info, None) }?;
        ctx.set_name(raw, name);
        Ok(Self {
            raw,
            push: push.first().copied(),
            ctx: ctx.clone(),
        })
    }

    /// The stages of the push-constant range (empty without one).
    pub fn push_stages(&self) -> vk::ShaderStageFlags {
        self.push
            .map_or(vk::ShaderStageFlags::empty(), |r| r.stage_flags)
    }

    /// The device the layout belongs to.
    pub fn device(&self) -> &ash::Device {
        &self.ctx.device
    }

    /// The context the layout was made on.
    pub(super) fn context(&self) -> &Context {
        &self.ctx
    }

    /// Records `vkCmdPushConstants` of `value` with this layout's range and stages.
    ///
    /// # Safety
    /// `cmd` must be recording, with pipelines made with this layout bound where they are used.
    pub unsafe fn push<T: bytemuck::Pod>(
        &self,
        cmd: vk::CommandBuffer,
        value: &T,
    ) -> Result<(), VkError> {
        // SAFETY: the caller's contract, the same.
        unsafe { self.push_bytes(cmd, bytemuck::bytes_of(value)) }
    }

    /// [`PipelineLayout::push`] of raw bytes (which must fill the range exactly).
    ///
    /// # Safety
    /// As [`PipelineLayout::push`].
    pub unsafe fn push_bytes(&self, cmd: vk::CommandBuffer, bytes: &[u8]) -> Result<(), VkError> {
        let range = self
            .push
            .filter(|r| r.size as usize == bytes.len())
            .ok_or_else(|| {
                VkError::Setup(format!(
                    "push constants of {} bytes for a layout whose range is {:?}",
                    bytes.len(),
                    self.push.map(|r| r.size)
                ))
            })?;
        // SAFETY: `bytes` is exactly the layout's one range, pushed with the range's stages
        // (VUID-vkCmdPushConstants-offset-01795/01796); `self.raw` is live. The caller's part is
        // in the contract.
        unsafe {
            self.ctx
                .device
                .cmd_push_constants(cmd, self.raw, range.stage_flags, 0, bytes)
        };
        Ok(())
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        // SAFETY: `self.raw` was created from `self.ctx.device` (alive through `self.ctx`) and is
        // destroyed only here. No command buffer that used it is still recording
        // (VUID-vkDestroyPipelineLayout-pipelineLayout-02004): recording happens within one
        // method call of the pass that owns the layout, so it cannot be dropped mid-recording.
        unsafe { self.ctx.device.destroy_pipeline_layout(self.raw, None) };
    }
}

pub struct Pipeline {
    pub raw: vk::Pipeline,
    ctx: Arc<Context>,
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        // SAFETY: `self.raw` was created from `self.ctx.device` (alive through `self.ctx`) and is
        // destroyed only here. No submitted command uses it (VUID-vkDestroyPipeline-pipeline-00765):
        // owners drop pipelines only after waiting for their work (fences, `device_wait_idle`).
        unsafe { self.ctx.device.destroy_pipeline(self.raw, None) };
    }
}

/// Specialization constants: (constant id, u32 value); bools are 0/1.
pub type SpecValues = [(u32, u32)];

fn spec_info<'a>(
    values: &'a SpecValues,
    entries: &'a mut Vec<vk::SpecializationMapEntry>,
    data: &'a mut Vec<u8>,
) -> vk::SpecializationInfo<'a> {
    for (i, (id, v)) in values.iter().enumerate() {
        entries.push(vk::SpecializationMapEntry {
            constant_id: *id,
            offset: (i * 4) as u32,
            size: 4,
        });
        data.extend_from_slice(&v.to_ne_bytes());
    }
    vk::SpecializationInfo::default()
        .map_entries(entries)
        .data(data)
}

/// Everything a graphics pipeline for dynamic rendering needs.
pub struct GraphicsDesc<'a> {
    pub name: &'a str,
    pub vertex: &'a ShaderModule,
    pub fragment: &'a ShaderModule,
    pub spec: &'a SpecValues,
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    pub color_formats: &'a [vk::Format],
    pub depth_format: Option<vk::Format>,
    pub samples: vk::SampleCountFlags,
    pub cull: vk::CullModeFlags,
    pub depth_test: bool,
    pub depth_write: bool,
    pub depth_compare: vk::CompareOp,
    /// "Over" blending with the fragment's alpha (straight, not premultiplied): colour =
    /// src · a + dst · (1 − a), alpha = a + dst · (1 − a).
    pub blend: bool,
}

impl<'a> GraphicsDesc<'a> {
    /// A full-screen triangle (no vertex input, no culling) into one single-sampled colour
    /// attachment of `color_formats[0]`: no depth, no blending.
    pub fn fullscreen(
        name: &'a str,
        (vertex, fragment): (&'a ShaderModule, &'a ShaderModule),
        spec: &'a SpecValues,
        color_formats: &'a [vk::Format],
    ) -> Self {
        Self {
            name,
            vertex,
            fragment,
            spec,
            vertex_bindings: &[],
            vertex_attributes: &[],
            color_formats,
            depth_format: None,
            samples: vk::SampleCountFlags::TYPE_1,
            cull: vk::CullModeFlags::NONE,
            depth_test: false,
            depth_write: false,
            depth_compare: vk::CompareOp::ALWAYS,
            blend: false,
        }
    }
}

impl Pipeline {
    pub fn graphics(
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        desc: &GraphicsDesc<'_>,
    ) -> Result<Self, VkError> {
        // Cull mode is dynamic (core in Vulkan 1.3): closed meshes cull back faces, open ones not.
        Self::graphics_from(
            ctx,
            layout,
            &GraphicsState {
                name: desc.name,
                shaders: (desc.vertex, Some(desc.fragment)),
                spec: desc.spec,
                input: (desc.vertex_bindings, desc.vertex_attributes),
                raster: (desc.cull, false),
                samples: desc.samples,
                depth: (desc.depth_test, desc.depth_write, desc.depth_compare),
                color: (desc.color_formats, desc.blend),
                depth_format: desc.depth_format.unwrap_or(vk::Format::UNDEFINED),
                dynamic: vk::DynamicState::CULL_MODE,
            },
        )
    }

    /// A depth-only graphics pipeline (no colour attachment) over triangle lists of `vertex`,
    /// with no fragment stage or a `fragment` stage that only discards: no culling, depth test and write with `compare`, and dynamic viewport,
    /// scissor and depth bias (the shadow maps).
    pub fn depth_only(
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        name: &str,
        shaders: (&ShaderModule, Option<&ShaderModule>),
        input: (
            &[vk::VertexInputBindingDescription],
            &[vk::VertexInputAttributeDescription],
        ),
        (depth_format, compare): (vk::Format, vk::CompareOp),
    ) -> Result<Self, VkError> {
        // A fragment stage only to discard (alpha-tested shadow casters): no colour output.
        Self::graphics_from(
            ctx,
            layout,
            &GraphicsState {
                name,
                shaders,
                spec: &[],
                input,
                raster: (vk::CullModeFlags::NONE, true),
                samples: vk::SampleCountFlags::TYPE_1,
                depth: (true, true, compare),
                color: (&[], false),
                depth_format,
                dynamic: vk::DynamicState::DEPTH_BIAS,
            },
        )
    }

    /// The graphics pipeline of `state` for dynamic rendering.
    fn graphics_from(
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        state: &GraphicsState<'_>,
    ) -> Result<Self, VkError> {
        let (mut e, mut d) = (Vec::new(), Vec::new());
        let spec = spec_info(state.spec, &mut e, &mut d);
        let (vertex, fragment) = state.shaders;
        let stages: Vec<_> = [(vk::ShaderStageFlags::VERTEX, vertex)]
            .into_iter()
            .chain(fragment.map(|f| (vk::ShaderStageFlags::FRAGMENT, f)))
            .map(|(stage, module)| shader_stage(stage, module).specialization_info(&spec))
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(state.input.0)
            .vertex_attribute_descriptions(state.input.1);
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(state.raster.0)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .depth_bias_enable(state.raster.1)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(state.samples);
        let (depth_test, depth_write, depth_compare) = state.depth;
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(depth_test)
            .depth_write_enable(depth_write)
            .depth_compare_op(depth_compare);
        let (color_formats, blend) = state.color;
        let blend_attachments: Vec<_> = color_formats
            .iter()
            .map(|_| {
                vk::PipelineColorBlendAttachmentState::default()
                    .color_write_mask(vk::ColorComponentFlags::RGBA)
                    .blend_enable(blend)
                    .src_color_blend_factor(vk::BlendFactor::SRC_ALPHA)
                    .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
                    .color_blend_op(vk::BlendOp::ADD)
                    .src_alpha_blend_factor(vk::BlendFactor::ONE)
                    .dst_alpha_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
                    .alpha_blend_op(vk::BlendOp::ADD)
            })
            .collect();
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [
            vk::DynamicState::VIEWPORT,
            vk::DynamicState::SCISSOR,
            state.dynamic,
        ];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(color_formats)
            .depth_attachment_format(state.depth_format);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout.raw)
            .push_next(&mut rendering);
        let (_cache_lock, cache) = ctx.pipeline_cache();
        // SAFETY: `info` and everything it points to (`stages` with `spec`, `e` and `d`, the state
        // structs, `blend_attachments`, `dynamic_states`, `rendering` with the colour formats) are
        // locals or borrows of `state` that outlive the call. The shader modules and `layout` are
        // live objects of this device (borrowed). Dynamic rendering is enabled by `Context::new`,
        // so a null render pass with `rendering` chained is allowed; a pipeline without a fragment
        // stage (or with one that writes no colour) and without colour attachments is valid. Each
        // specialization entry reads 4 bytes at `4 * i` of `d`, which holds 4 bytes per entry.
        // That the layout matches the shaders' interface is the caller's part (each pass builds
        // both together). `cache` is this device's pipeline cache (or null), its read lock held.
        let raw = unsafe { ctx.device.create_graphics_pipelines(cache, &[info], None) }
            .map_err(|(_, e)| e)?[0];
        Ok(Self::named(ctx, raw, state.name))
    }

    pub fn compute(
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        name: &str,
        module: &ShaderModule,
        spec: &SpecValues,
    ) -> Result<Self, VkError> {
        let (mut e, mut d) = (Vec::new(), Vec::new());
        let spec = spec_info(spec, &mut e, &mut d);
        let stage = shader_stage(vk::ShaderStageFlags::COMPUTE, module).specialization_info(&spec);
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.raw);
        let (_cache_lock, cache) = ctx.pipeline_cache();
        // SAFETY: `info` and what it points to (`stage` with `spec`, `e`, `d` and the `'static`
        // entry name) outlive the call; `module` and `layout` are live objects of this device
        // (borrowed). Each specialization entry reads 4 bytes at `4 * i` of `d`, which holds 4
        // bytes per entry. That the layout matches the shader's interface is the caller's part
        // (each pass builds both together). `cache` is this device's pipeline cache (or null), its
        // read lock held.
        let raw = unsafe { ctx.device.create_compute_pipelines(cache, &[info], None) }
            .map_err(|(_, e)| e)?[0];
        Ok(Self::named(ctx, raw, name))
    }

    /// Owns `raw`, a pipeline just created on `ctx`'s device, and gives it its debug name.
    fn named(ctx: &Arc<Context>, raw: vk::Pipeline, name: &str) -> Self {
        ctx.pipeline_created();
        ctx.set_name(raw, name);
        Self {
            raw,
            ctx: ctx.clone(),
        }
    }
}

/// What luz's graphics pipelines choose; the rest is the same for all of them: triangle lists,
/// filled polygons with counter-clockwise front faces, dynamic viewport and scissor (one each).
struct GraphicsState<'a> {
    name: &'a str,
    /// The vertex stage and the fragment stage, if any.
    shaders: (&'a ShaderModule, Option<&'a ShaderModule>),
    /// Specialization constants of both stages.
    spec: &'a SpecValues,
    /// Vertex bindings and attributes.
    input: (
        &'a [vk::VertexInputBindingDescription],
        &'a [vk::VertexInputAttributeDescription],
    ),
    /// The cull mode, and whether depth bias is enabled.
    raster: (vk::CullModeFlags, bool),
    samples: vk::SampleCountFlags,
    /// Depth test, depth write and the compare op.
    depth: (bool, bool, vk::CompareOp),
    /// The colour attachments' formats, and whether they blend "over" ([`GraphicsDesc::blend`]).
    color: (&'a [vk::Format], bool),
    /// `UNDEFINED` without a depth attachment.
    depth_format: vk::Format,
    /// The state that is dynamic besides the viewport and scissor.
    dynamic: vk::DynamicState,
}

/// The shader stage `stage` running `module`'s `main`.
fn shader_stage(
    stage: vk::ShaderStageFlags,
    module: &ShaderModule,
) -> vk::PipelineShaderStageCreateInfo<'static> {
    vk::PipelineShaderStageCreateInfo::default()
        .stage(stage)
        .module(module.raw)
        .name(MAIN)
}
