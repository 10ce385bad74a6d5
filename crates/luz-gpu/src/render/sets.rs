//! The scene's shared descriptor sets as the shaders declare them (a leaf of `render`: the glsl
//! numbers and the vk layer only).

use crate::glsl::include_bindings as b;
use crate::vk::interface::keys_with_prefix;
use crate::vk::{Interface, VkError};

/// The per-frame set (`bindings.glsl`).
const SET_FRAME: u32 = b::SET_FRAME as u32;
/// The shadow maps' set (`shadows.glsl`).
const SET_SHADOW: u32 = crate::glsl::include_shadows::SET_SHADOW as u32;

/// The interface of the scene's shared sets — frame (0), environment (1), materials (2) and
/// shadows (3) — as every module drawn with them declares it: the forward, G-buffer, skybox
/// and alpha-tested shadow modules, and the deferred lighting pass's frame and shadow sets (its
/// set 1 is the G-buffer's). Each of these set layouts is made from it, once for all the pipeline
/// layouts that share it.
pub fn scene_interface() -> Result<Interface, VkError> {
    let keys: Vec<&str> = [
        "forward.",
        "skybox.",
        "emitter.",
        "shadow_mask.",
        "deferred_gbuffer.",
    ]
    .into_iter()
    .flat_map(keys_with_prefix)
    .collect();
    let lighting: Vec<&str> = keys_with_prefix("deferred_light.frag").collect();
    Interface::of("scene", &keys)?.with(&lighting, &[SET_FRAME, SET_SHADOW])
}
