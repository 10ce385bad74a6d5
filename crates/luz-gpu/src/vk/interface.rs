//! Layouts from the shaders: descriptor set layouts, pools, pipeline layouts and descriptor writes
//! made from what build.rs read out of each SPIR-V module ([`super::shaders::INTERFACES`]), so no
//! pass restates `bindings.glsl` by hand.
//!
//! A pass names the modules that share one pipeline layout ([`Interface::of`]); the interface is
//! the union of their bindings, set by set, each visible to the stages whose modules declare it,
//! and the largest push-constant block, visible to every stage that declares one. A binding two
//! modules declare with different types is an error, as is a Rust push-constant type whose size
//! is not the shader's ([`Interface::check_push`]).

use std::collections::BTreeMap;
use std::sync::Arc;

use ash::vk;

pub use super::pipeline::LayoutBinding;
use super::pipeline::{DescriptorPool, DescriptorSetLayout, PipelineLayout};
use super::shaders::{ModuleInterface, INTERFACES};
use super::{Context, VkError};

/// The resource interface of a group of modules that share a pipeline layout.
#[derive(Debug, Clone)]
pub struct Interface {
    name: String,
    sets: BTreeMap<u32, Vec<LayoutBinding>>,
    push: Option<vk::PushConstantRange>,
}

/// The interface build.rs reflected for module `key` (`display.frag`, `forward.frag:phong`).
pub fn module_interface(key: &str) -> Result<&'static ModuleInterface, VkError> {
    INTERFACES
        .iter()
        .find(|(k, _)| *k == key)
        .map(|(_, i)| i)
        .ok_or_else(|| VkError::Setup(format!("no embedded shader named {key}")))
}

/// Every embedded module whose key starts with `prefix` (`forward.frag:` for every variant).
pub fn keys_with_prefix(prefix: &str) -> impl Iterator<Item = &'static str> + '_ {
    INTERFACES
        .iter()
        .map(|(k, _)| *k)
        .filter(move |k| k.starts_with(prefix))
}

impl Interface {
    /// The union of the interfaces of `keys` (named `name` in errors and debug names).
    pub fn of(name: &str, keys: &[&str]) -> Result<Self, VkError> {
        let modules = keys
            .iter()
            .map(|k| Ok((*k, module_interface(k)?)))
            .collect::<Result<Vec<_>, VkError>>()?;
        Self::from_modules(name, &modules)
    }

    /// The union of `modules`' interfaces.
    fn from_modules(name: &str, modules: &[(&str, &ModuleInterface)]) -> Result<Self, VkError> {
        let mut sets: BTreeMap<u32, Vec<LayoutBinding>> = BTreeMap::new();
        let mut push: Option<vk::PushConstantRange> = None;
        for (key, module) in modules {
            let stage = vk::ShaderStageFlags::from_raw(module.stage);
            for b in module.bindings {
                let ty = vk::DescriptorType::from_raw(b.ty as i32);
                let list = sets.entry(b.set).or_default();
                match list.iter_mut().find(|l| l.binding == b.binding) {
                    Some(l) if l.ty != ty || l.count != b.count => {
                        return Err(VkError::Setup(format!(
                            "{name}: set {} binding {} is {:?}[{}] `{}` in one shader and \
                             {ty:?}[{}] `{}` in {key}",
                            b.set, b.binding, l.ty, l.count, l.name, b.count, b.name
                        )))
                    }
                    Some(l) => l.stages |= stage,
                    None => list.push(LayoutBinding {
                        binding: b.binding,
                        ty,
                        count: b.count,
                        stages: stage,
                        name: b.name,
                    }),
                }
            }
            if module.push_size > 0 {
                let p = push.get_or_insert(vk::PushConstantRange {
                    stage_flags: vk::ShaderStageFlags::empty(),
                    offset: 0,
                    size: 0,
                });
                p.stage_flags |= stage;
                p.size = p.size.max(module.push_size);
            }
        }
        for list in sets.values_mut() {
            list.sort_by_key(|b| b.binding);
        }
        Ok(Self {
            name: name.to_string(),
            sets,
            push,
        })
    }

    /// Adds the bindings `keys` declare in `sets` (not their other sets nor their push block):
    /// modules that share some of these sets in a pipeline layout of their own.
    pub fn with(mut self, keys: &[&str], sets: &[u32]) -> Result<Self, VkError> {
        let other = Self::of(&self.name, keys)?;
        for set in sets {
            for b in other.bindings(*set) {
                let list = self.sets.entry(*set).or_default();
                match list.iter_mut().find(|l| l.binding == b.binding) {
                    Some(l) if l.ty != b.ty || l.count != b.count => {
                        return Err(VkError::Setup(format!(
                            "{}: set {set} binding {} is {:?} `{}` in one shader and {:?} `{}` \
                             in another",
                            self.name, b.binding, l.ty, l.name, b.ty, b.name
                        )))
                    }
                    Some(l) => l.stages |= b.stages,
                    None => list.push(b.clone()),
                }
            }
            if let Some(list) = self.sets.get_mut(set) {
                list.sort_by_key(|b| b.binding);
            }
        }
        Ok(self)
    }

    /// Refuses an interface with a set other than 0.
    fn only_set_0(&self) -> Result<(), VkError> {
        match self.sets.keys().find(|s| **s != 0) {
            Some(s) => Err(VkError::Setup(format!(
                "{}: set {s} declared; one set expected",
                self.name
            ))),
            None => Ok(()),
        }
    }

    /// The bindings of set `set` (empty if no module declares it).
    pub fn bindings(&self, set: u32) -> &[LayoutBinding] {
        self.sets.get(&set).map(Vec::as_slice).unwrap_or(&[])
    }

    /// The push-constant range, if any module declares a block.
    pub fn push_range(&self) -> Option<vk::PushConstantRange> {
        self.push
    }

    /// Checks that `T`, the Rust side of the push-constant block, has the shader's size (no
    /// block at all counts as 0 bytes).
    pub fn check_push<T>(&self) -> Result<(), VkError> {
        let shader = self.push.map_or(0, |p| p.size) as usize;
        let rust = std::mem::size_of::<T>();
        if shader != rust {
            return Err(VkError::Setup(format!(
                "{}: the shaders' push-constant block is {shader} bytes, the Rust type {} is {rust}",
                self.name,
                std::any::type_name::<T>()
            )));
        }
        Ok(())
    }

    /// The layout of set `set`.
    pub fn set_layout(&self, ctx: &Arc<Context>, set: u32) -> Result<DescriptorSetLayout, VkError> {
        DescriptorSetLayout::from_bindings(
            ctx,
            &format!("{} set {set} layout", self.name),
            self.bindings(set).to_vec(),
        )
    }

    /// The layout of set `set` for push descriptors ([`SetWrites::push`]).
    pub fn push_set_layout(
        &self,
        ctx: &Arc<Context>,
        set: u32,
    ) -> Result<DescriptorSetLayout, VkError> {
        DescriptorSetLayout::create(
            ctx,
            &format!("{} set {set} layout (pushed)", self.name),
            self.bindings(set).to_vec(),
            true,
        )
    }

    /// The layouts of sets 0 to the highest declared, an empty layout for each set no module
    /// declares.
    pub fn set_layouts(&self, ctx: &Arc<Context>) -> Result<Vec<DescriptorSetLayout>, VkError> {
        let count = self.sets.keys().next_back().map_or(0, |s| s + 1);
        (0..count).map(|s| self.set_layout(ctx, s)).collect()
    }

    /// The pipeline layout over `sets` (in set order) with this interface's push range.
    pub fn pipeline_layout(
        &self,
        ctx: &Arc<Context>,
        sets: &[&DescriptorSetLayout],
    ) -> Result<PipelineLayout, VkError> {
        // An empty layout stands for a set the pipelines built with this layout do not use
        // (the environment's without one).
        for (i, layout) in sets
            .iter()
            .enumerate()
            .filter(|(_, l)| !l.bindings().is_empty())
        {
            for b in self.bindings(i as u32) {
                if !layout
                    .bindings()
                    .iter()
                    .any(|l| l.binding == b.binding && l.ty == b.ty && l.stages.contains(b.stages))
                {
                    return Err(VkError::Setup(format!(
                        "{}: set {i}'s layout lacks binding {} `{}` ({:?}, {:?})",
                        self.name, b.binding, b.name, b.ty, b.stages
                    )));
                }
            }
        }
        check_stage_samplers(&self.name, ctx, sets)?;
        PipelineLayout::new(
            ctx,
            &format!("{} layout", self.name),
            sets,
            self.push.as_slice(),
        )
    }
}

/// The textures one stage of a layout of `sets` reads, against the device's
/// `maxPerStageDescriptorSamplers` and `maxPerStageDescriptorSampledImages` (Vulkan guarantees
/// 16; the forward pass's material set alone has 22 maps): a clear error instead of a layout
/// the device cannot make.
fn check_stage_samplers(
    name: &str,
    ctx: &Context,
    sets: &[&DescriptorSetLayout],
) -> Result<(), VkError> {
    let l = &ctx.info.limits;
    let bindings: Vec<&LayoutBinding> = sets.iter().flat_map(|s| s.bindings()).collect();
    let limits = (
        l.max_per_stage_descriptor_samplers,
        l.max_per_stage_descriptor_sampled_images,
    );
    match stage_sampler_excess(&bindings, limits) {
        None => Ok(()),
        Some((stage, used)) => Err(VkError::Setup(format!(
            "{name}: the {stage:?} stage reads {used} textures; {} allows {} per stage \
             (maxPerStageDescriptorSamplers {}, maxPerStageDescriptorSampledImages {})",
            ctx.info.name,
            limits.0.min(limits.1),
            limits.0,
            limits.1
        ))),
    }
}

/// The first stage whose combined image samplers in `bindings` exceed `(samplers, images)`
/// per stage, with how many it reads.
fn stage_sampler_excess(
    bindings: &[&LayoutBinding],
    (samplers, images): (u32, u32),
) -> Option<(vk::ShaderStageFlags, u32)> {
    [
        vk::ShaderStageFlags::VERTEX,
        vk::ShaderStageFlags::FRAGMENT,
        vk::ShaderStageFlags::COMPUTE,
    ]
    .into_iter()
    .map(|stage| {
        let used = bindings
            .iter()
            .filter(|b| {
                b.stages.contains(stage) && b.ty == vk::DescriptorType::COMBINED_IMAGE_SAMPLER
            })
            .map(|b| b.count)
            .sum();
        (stage, used)
    })
    .find(|&(_, used)| used > samplers.min(images))
}

/// Descriptor writes into one set, each binding's type taken from the set's layout.
pub struct SetWrites<'a> {
    layout: &'a DescriptorSetLayout,
    set: vk::DescriptorSet,
    images: Vec<(u32, vk::DescriptorImageInfo)>,
    buffers: Vec<(u32, vk::DescriptorBufferInfo)>,
}

impl<'a> SetWrites<'a> {
    pub fn new(layout: &'a DescriptorSetLayout, set: vk::DescriptorSet) -> Self {
        Self {
            layout,
            set,
            images: Vec::new(),
            buffers: Vec::new(),
        }
    }

    /// An image view (with `sampler` for combined image samplers, else null) in `layout`.
    pub fn image(
        mut self,
        binding: u32,
        view: vk::ImageView,
        layout: vk::ImageLayout,
        sampler: vk::Sampler,
    ) -> Self {
        self.images.push((
            binding,
            vk::DescriptorImageInfo {
                sampler,
                image_view: view,
                image_layout: layout,
            },
        ));
        self
    }

    /// An image view without a sampler (sampled or storage images) in `layout`.
    pub fn view(self, binding: u32, view: vk::ImageView, layout: vk::ImageLayout) -> Self {
        self.image(binding, view, layout, vk::Sampler::null())
    }

    /// A whole buffer.
    pub fn buffer(self, binding: u32, buffer: vk::Buffer) -> Self {
        self.buffer_range(binding, buffer, 0, vk::WHOLE_SIZE)
    }

    /// `range` bytes of a buffer from `offset`.
    pub fn buffer_range(
        mut self,
        binding: u32,
        buffer: vk::Buffer,
        offset: vk::DeviceSize,
        range: vk::DeviceSize,
    ) -> Self {
        self.buffers.push((
            binding,
            vk::DescriptorBufferInfo {
                buffer,
                offset,
                range,
            },
        ));
        self
    }

    /// The writes, each binding's type checked against the layout: refuses a binding the
    /// layout lacks or a resource of the wrong kind for it (an image for a buffer binding or the
    /// reverse). The writes point into `self`.
    fn checked(&self) -> Result<Vec<vk::WriteDescriptorSet<'_>>, VkError> {
        let ty_of = |binding: u32, image: bool| -> Result<vk::DescriptorType, VkError> {
            let b = self
                .layout
                .bindings()
                .iter()
                .find(|b| b.binding == binding)
                .ok_or_else(|| {
                    VkError::Setup(format!(
                        "{}: no binding {binding} to write",
                        self.layout.name()
                    ))
                })?;
            let is_image = matches!(
                b.ty,
                vk::DescriptorType::SAMPLED_IMAGE
                    | vk::DescriptorType::STORAGE_IMAGE
                    | vk::DescriptorType::COMBINED_IMAGE_SAMPLER
            );
            if is_image != image {
                return Err(VkError::Setup(format!(
                    "{}: binding {binding} `{}` is {:?}",
                    self.layout.name(),
                    b.name,
                    b.ty
                )));
            }
            Ok(b.ty)
        };
        let mut writes = Vec::with_capacity(self.images.len() + self.buffers.len());
        let write = |binding: u32, image: bool| -> Result<vk::WriteDescriptorSet, VkError> {
            Ok(vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(binding)
                .descriptor_type(ty_of(binding, image)?))
        };
        for (binding, info) in &self.images {
            writes.push(write(*binding, true)?.image_info(std::slice::from_ref(info)));
        }
        for (binding, info) in &self.buffers {
            writes.push(write(*binding, false)?.buffer_info(std::slice::from_ref(info)));
        }
        Ok(writes)
    }

    /// Writes every descriptor given into the set ([`SetWrites::checked`]'s checks).
    ///
    /// # Safety
    /// No pending command buffer may use the set (VUID-vkUpdateDescriptorSets-None-03047), and
    /// every view, sampler and buffer given must be live, with the usage its binding's type
    /// needs, for as long as the set is used.
    pub unsafe fn apply(self, ctx: &Context) -> Result<(), VkError> {
        if self.layout.is_pushed() {
            return Err(VkError::Setup(format!(
                "{}: a push-descriptor layout has no set to write",
                self.layout.name()
            )));
        }
        let writes = self.checked()?;
        // SAFETY: `writes` and the infos they point to (in `self`) outlive the call; each write's
        // type is its binding's in the set's layout (checked above). The caller's part is in the
        // function's contract: the set is not in use and the resources are live and fit.
        unsafe { ctx.device.update_descriptor_sets(&writes, &[]) };
        Ok(())
    }

    /// Records the descriptors given into `cmd` as set `set` of `layout` at `bind_point`
    /// (`vkCmdPushDescriptorSetKHR`), with [`SetWrites::checked`]'s checks. The set layout must
    /// be a push layout ([`Interface::push_set_layout`]), set `set` of `layout`.
    ///
    /// # Safety
    /// `cmd` must be recording; every view, sampler and buffer given must be live, with the
    /// usage its binding's type needs, until the commands that use them have completed, and in
    /// the layouts given when they execute.
    pub unsafe fn push(
        self,
        cmd: vk::CommandBuffer,
        bind_point: vk::PipelineBindPoint,
        layout: &PipelineLayout,
        set: u32,
    ) -> Result<(), VkError> {
        if !self.layout.is_pushed() {
            return Err(VkError::Setup(format!(
                "{}: not a push-descriptor layout",
                self.layout.name()
            )));
        }
        let writes = self.checked()?;
        // SAFETY: `writes` and the infos they point to outlive the call; each write's type is its
        // binding's in the push layout, which is set `set` of `layout` (the caller's part, with
        // the resources' liveness and layouts). The device has VK_KHR_push_descriptor
        // (`device::REQUIRED_EXTENSIONS`).
        unsafe {
            layout
                .context()
                .push_descriptor
                .cmd_push_descriptor_set(cmd, bind_point, layout.raw, set, &writes)
        };
        Ok(())
    }
}

/// A pipeline layout over one push-descriptor set (set 0): the shape of the passes that read
/// the frame graph's transient images, whose views are known only at record time
/// ([`SetWrites::push`]).
pub struct PushSet {
    pub layout: PipelineLayout,
    pub set_layout: DescriptorSetLayout,
}

impl PushSet {
    /// The layout of the modules `keys` (named `name`), which may declare set 0 only.
    pub fn new(ctx: &Arc<Context>, name: &str, keys: &[&str]) -> Result<Self, VkError> {
        let interface = Interface::of(name, keys)?;
        interface.only_set_0()?;
        let set_layout = interface.push_set_layout(ctx, 0)?;
        let layout = interface.pipeline_layout(ctx, &[&set_layout])?;
        Ok(Self { layout, set_layout })
    }

    /// Descriptors to push as set 0 ([`PushSet::push`]).
    pub fn writes(&self) -> SetWrites<'_> {
        SetWrites::new(&self.set_layout, vk::DescriptorSet::null())
    }

    /// Records `writes` (from [`PushSet::writes`]) as set 0 at `bind_point`.
    ///
    /// # Safety
    /// As [`SetWrites::push`].
    pub unsafe fn push(
        &self,
        cmd: vk::CommandBuffer,
        bind_point: vk::PipelineBindPoint,
        writes: SetWrites<'_>,
    ) -> Result<(), VkError> {
        // SAFETY: the caller's contract; `writes` are for `self.set_layout`, set 0 of `self.layout`.
        unsafe { writes.push(cmd, bind_point, &self.layout, 0) }
    }
}

/// A pipeline layout over one descriptor set (set 0), with copies of the set (one per frame
/// slot, or just one) allocated from a pool of its own: the shape of luz's compute and
/// full-screen passes.
pub struct SingleSet {
    pub layout: PipelineLayout,
    pub set_layout: DescriptorSetLayout,
    pub sets: Vec<vk::DescriptorSet>,
    _pool: DescriptorPool,
}

impl SingleSet {
    /// The layout of the modules `keys` (named `name`), which may declare set 0 only, and one
    /// set.
    pub fn new(ctx: &Arc<Context>, name: &str, keys: &[&str]) -> Result<Self, VkError> {
        Self::with_copies(ctx, name, keys, 1)
    }

    /// [`SingleSet::new`] with `copies` sets.
    pub fn with_copies(
        ctx: &Arc<Context>,
        name: &str,
        keys: &[&str],
        copies: usize,
    ) -> Result<Self, VkError> {
        let interface = Interface::of(name, keys)?;
        interface.only_set_0()?;
        let set_layout = interface.set_layout(ctx, 0)?;
        let layout = interface.pipeline_layout(ctx, &[&set_layout])?;
        let pool = DescriptorPool::for_sets(
            ctx,
            &format!("{name} pool"),
            &[(&set_layout, copies as u32)],
        )?;
        let sets = (0..copies)
            .map(|_| pool.allocate(&set_layout))
            .collect::<Result<_, _>>()?;
        Ok(Self {
            layout,
            set_layout,
            sets,
            _pool: pool,
        })
    }

    /// The first (or only) set.
    pub fn set(&self) -> vk::DescriptorSet {
        self.sets[0]
    }

    /// Writes into the first set ([`SetWrites::apply`]).
    pub fn writes(&self) -> SetWrites<'_> {
        self.writes_to(0)
    }

    /// Writes into set copy `i`.
    pub fn writes_to(&self, i: usize) -> SetWrites<'_> {
        SetWrites::new(&self.set_layout, self.sets[i])
    }

    /// Records binding set copy `i` as set 0 at `bind_point`.
    ///
    /// # Safety
    /// `cmd` must be recording; the set's resources must be live and in the layouts the
    /// pipelines bound with it expect.
    pub unsafe fn bind(&self, cmd: vk::CommandBuffer, bind_point: vk::PipelineBindPoint, i: usize) {
        // SAFETY: the caller's contract; the set matches set 0 of `self.layout`.
        unsafe {
            self.layout.device().cmd_bind_descriptor_sets(
                cmd,
                bind_point,
                self.layout.raw,
                0,
                &[self.sets[i]],
                &[],
            )
        };
    }
}

#[cfg(test)]
#[path = "interface_tests.rs"]
mod tests;

#[cfg(test)]
mod sampler_limit_tests {
    use super::*;

    /// The scene's sets (frame, material, shadow, environment) read more textures in the
    /// fragment stage than Vulkan's guaranteed 16 and fit lavapipe's limits; either limit below
    /// the count is reported with the first stage over it and its count.
    #[test]
    fn the_scene_layout_is_checked_against_the_per_stage_limits() {
        let scene = crate::render::sets::scene_interface().unwrap();
        let refs: Vec<&LayoutBinding> = (0..4).flat_map(|s| scene.bindings(s)).collect();
        let count = |stage: vk::ShaderStageFlags| -> u32 {
            refs.iter()
                .filter(|b| {
                    b.stages.contains(stage) && b.ty == vk::DescriptorType::COMBINED_IMAGE_SAMPLER
                })
                .map(|b| b.count)
                .sum()
        };
        let (vertex, fragment) = (
            count(vk::ShaderStageFlags::VERTEX),
            count(vk::ShaderStageFlags::FRAGMENT),
        );
        assert!(fragment > 21 && vertex > 16, "{vertex} {fragment}");
        assert_eq!(stage_sampler_excess(&refs, (1 << 20, 1 << 20)), None);
        for limits in [(16, 1 << 20), (1 << 20, 16)] {
            assert_eq!(
                stage_sampler_excess(&refs, limits),
                Some((vk::ShaderStageFlags::VERTEX, vertex))
            );
        }
        assert_eq!(
            stage_sampler_excess(&refs, (vertex, vertex)),
            (fragment > vertex).then_some((vk::ShaderStageFlags::FRAGMENT, fragment))
        );
    }
}
