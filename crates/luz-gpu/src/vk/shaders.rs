//! SPIR-V compiled by build.rs from `shaders_glsl/`, embedded in the binary.

use std::io::Cursor;
use std::sync::Arc;

use ash::vk;

use super::{Context, VkError};

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The SPIR-V bytes for a key such as `forward.frag:phong`.
pub fn spirv(key: &str) -> Option<&'static [u8]> {
    SPIRV.iter().find(|(k, _)| *k == key).map(|(_, b)| *b)
}

/// Every embedded module's key.
pub fn keys() -> impl Iterator<Item = &'static str> {
    SPIRV.iter().map(|(k, _)| *k)
}

/// A shader module, destroyed on drop.
pub struct ShaderModule {
    pub raw: vk::ShaderModule,
    pub key: &'static str,
    ctx: Arc<Context>,
}

impl ShaderModule {
    pub fn new(ctx: &Arc<Context>, key: &str) -> Result<Self, VkError> {
        let (key, bytes) = SPIRV
            .iter()
            .find(|(k, _)| *k == key)
            .ok_or_else(|| VkError::Setup(format!("no embedded shader named {key}")))?;
        // read_spv copes with the byte slice's alignment.
        let words = ash::util::read_spv(&mut Cursor::new(bytes))
            .map_err(|e| VkError::Setup(format!("bad SPIR-V in {key}: {e}")))?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: `info` points to `words`, a local that outlives the call, holding whole u32 words
        // (`read_spv` rejects a length that is not a multiple of 4). The code is SPIR-V that
        // build.rs compiled from `shaders_glsl/` with shaderc for Vulkan 1.3, embedded unchanged.
        let raw = unsafe { ctx.device.create_shader_module(&info, None) }?;
        ctx.set_name(raw, key);
        Ok(Self {
            raw,
            key,
            ctx: ctx.clone(),
        })
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        // SAFETY: `self.raw` was created from `self.ctx.device` (alive through `self.ctx`) and is
        // destroyed only here. A module may be destroyed while pipelines built from it are in use
        // (it is only read during pipeline creation), so there is no other requirement.
        unsafe { self.ctx.device.destroy_shader_module(self.raw, None) };
    }
}

/// One descriptor binding a module declares, as build.rs read it from the SPIR-V.
#[derive(Debug, Clone, Copy)]
pub struct ReflectedBinding {
    pub set: u32,
    pub binding: u32,
    /// A `VkDescriptorType` value.
    pub ty: u32,
    pub count: u32,
    /// The GLSL name (of the block or the variable).
    pub name: &'static str,
}

/// A module's resource interface: its stage (a `VkShaderStageFlags` bit), its descriptor bindings
/// and its push-constant block's size in bytes (0 without one).
#[derive(Debug, Clone, Copy)]
pub struct ModuleInterface {
    pub stage: u32,
    pub push_size: u32,
    pub bindings: &'static [ReflectedBinding],
}
