//! GPU-side data layouts, mirrored in `shaders_glsl/include/bindings.glsl`.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};

use crate::scene::{Falloff, Light, LightKind, Material, Scene};

pub const SET_FRAME: u32 = 0;
pub const BINDING_FRAME: u32 = 0;
pub const BINDING_LIGHTS: u32 = 1;
pub const BINDING_OBJECTS: u32 = 2;

pub const LIGHT_DIRECTIONAL: u32 = 0;
pub const LIGHT_POINT: u32 = 1;
pub const LIGHT_SPOT: u32 = 2;
pub const FALLOFF_NONE: u32 = 0;
pub const FALLOFF_INVERSE_SQUARE: u32 = 1;
pub const FALLOFF_CLASSIC: u32 = 2;

/// Material model ids (specialization constant 0): the CPU reference's codes.
pub use crate::brdf::model_code;

/// Specialization constant ids.
pub const SPEC_MODEL: u32 = 0;
pub const SPEC_FOG: u32 = 1;
pub const SPEC_SPECULAR_METHOD: u32 = 2;
pub const SPEC_DIFFUSE_FROM_SH: u32 = 3;
pub const SPEC_ENERGY_COMPENSATION: u32 = 4;
pub const SPEC_IBL_SAMPLES: u32 = 5;
pub const SPEC_MIP_FILTERED: u32 = 6;
pub const SPEC_DEBUG_VIEW: u32 = 7;
pub const SPEC_SEL_DISTRIBUTION: u32 = 8;
pub const SPEC_SEL_GEOMETRY: u32 = 9;
pub const SPEC_SEL_FRESNEL: u32 = 10;
pub const SPEC_MAPS: u32 = 11;
pub const SPEC_LIGHT_KINDS: u32 = 12;
/// `SEL_DIFFUSE`: the diffuse selector of Cook-Torrance / metal-rough ([`material_diffuse_key`]).
pub const SPEC_SEL_DIFFUSE: u32 = 13;
/// `LK_*` bits of `shaders_glsl/include/bindings.glsl`.
pub const LK_DIRECTIONAL: u32 = 1;
pub const LK_POINT: u32 = 2;
pub const LK_SPOT: u32 = 4;
pub const LK_FALLOFF_NONE: u32 = 8;
pub const LK_FALLOFF_INVERSE_SQUARE: u32 = 16;
pub const LK_FALLOFF_CLASSIC: u32 = 32;

/// The light types and falloffs `lights` use, as `LK_*` bits (the shader leaves out the rest).
pub fn light_kinds(lights: &[Light]) -> u32 {
    lights.iter().fold(0, |bits, l| {
        bits | match l.kind {
            LightKind::Directional => LK_DIRECTIONAL,
            LightKind::Point => LK_POINT,
            LightKind::Spot => LK_SPOT,
        } | match l.falloff {
            Falloff::None => LK_FALLOFF_NONE,
            Falloff::InverseSquare => LK_FALLOFF_INVERSE_SQUARE,
            Falloff::Classic { .. } => LK_FALLOFF_CLASSIC,
        }
    })
}

/// The model and the (distribution, geometry, Fresnel) selectors of a material, as the shader
/// sees them: what its pipeline variant is specialised for.
pub fn material_key(m: &Material) -> (i32, [i32; 3]) {
    let packed = crate::brdf::GpuBrdfParams::from_model(&m.to_brdf());
    (packed.sel[0], [packed.sel[1], packed.sel[2], packed.sel[3]])
}

/// The material's diffuse selector (`brdf::Diffuse` code: 0 Lambert, 1 Burley) as the shader's
/// `SEL_DIFFUSE` sees it, or -1 for models without one (the shader then ignores it).
pub fn material_diffuse_key(m: &Material) -> i32 {
    crate::brdf::GpuBrdfParams::diffuse_selector(&m.to_brdf().sanitized()).unwrap_or(-1)
}

/// Names of a diffuse selector value in pipeline-variant names (`None` for -1).
pub fn diffuse_key_name(key: i32) -> Option<&'static str> {
    crate::brdf::Diffuse::ALL
        .iter()
        .find(|d| **d as i32 == key)
        .map(|d| d.name())
}

/// `FrameData` (std140).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub struct FrameData {
    pub view: Mat4,
    pub proj: Mat4,
    pub view_proj: Mat4,
    pub camera_pos: Vec4,
    pub ambient: Vec4,
    pub fog_color: Vec4,
    pub fog: Vec4,
    pub counts: [u32; 4],
    pub inv_view_proj: Mat4,
}

/// `Light` (std430, 80 bytes).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub struct GpuLight {
    pub position_type: Vec4,
    pub direction_falloff: Vec4,
    pub radiance: Vec4,
    pub atten: Vec4,
    pub cone: Vec4,
}

/// `ObjectData` (std430, 128 bytes).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub struct ObjectData {
    pub model: Mat4,
    pub normal_matrix: Mat4,
}

/// `MaterialPush`: per-material parameters as push constants: the packed BRDF parameters of
/// [`crate::brdf::GpuBrdfParams`] (96 bytes), then the object's index.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub struct MaterialPush {
    pub brdf: [u32; 24],
    pub object_index: u32,
    pub flags: u32,
    pub reserved: [u32; 2],
}

/// Vulkan guarantees 128 bytes of push constants; lavapipe offers exactly that.
const _: () = assert!(std::mem::size_of::<MaterialPush>() <= 128);
const _: () = assert!(std::mem::size_of::<GpuLight>() == 80);
const _: () = assert!(std::mem::size_of::<FrameData>() == 4 * 64 + 4 * 16 + 16);

/// One vertex: position, normal, uv, tangent (xyz + handedness).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, Default)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    pub tangent: [f32; 4],
}

impl GpuLight {
    pub fn from_light(l: &Light) -> Self {
        let ty = match l.kind {
            LightKind::Directional => LIGHT_DIRECTIONAL,
            LightKind::Point => LIGHT_POINT,
            LightKind::Spot => LIGHT_SPOT,
        };
        let (falloff, c) = match l.falloff {
            Falloff::None => (FALLOFF_NONE, [0.0; 3]),
            Falloff::InverseSquare => (FALLOFF_INVERSE_SQUARE, [0.0; 3]),
            Falloff::Classic { c1, c2, c3 } => (FALLOFF_CLASSIC, [c1, c2, c3]),
        };
        let cos_umbra = l.umbra_deg.to_radians().cos();
        let (cos_inner, smooth) = match l.inner_deg {
            Some(inner) => (inner.to_radians().cos(), 1.0),
            None => (cos_umbra, 0.0),
        };
        Self {
            position_type: l.position.extend(ty as f32),
            direction_falloff: l.direction.normalize_or_zero().extend(falloff as f32),
            radiance: (l.color * l.intensity).extend(0.0),
            atten: Vec4::new(c[0], c[1], c[2], l.exponent),
            cone: Vec4::new(cos_umbra, cos_inner, smooth, 0.0),
        }
    }
}

/// The model code (specialization constant) and push constants for a material.
pub fn material_push(m: &Material) -> (i32, MaterialPush) {
    let packed = crate::brdf::GpuBrdfParams::from_model(&m.to_brdf());
    let bytes = packed.to_bytes();
    let mut brdf = [0u32; 24];
    for (w, c) in brdf.iter_mut().zip(bytes.chunks_exact(4)) {
        *w = u32::from_ne_bytes([c[0], c[1], c[2], c[3]]);
    }
    (
        packed.sel[0],
        MaterialPush {
            brdf,
            object_index: 0,
            flags: 0,
            reserved: [0; 2],
        },
    )
}

/// Vulkan clip space from a right-handed view: y down, depth in [0, 1].
pub fn projection(fov_y_deg: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let mut p = Mat4::perspective_rh(fov_y_deg.to_radians(), aspect, near, far);
    p.y_axis.y = -p.y_axis.y;
    p
}

pub fn frame_data(scene: &Scene, aspect: f32, light_count: u32) -> FrameData {
    let view = scene.camera.view();
    let proj = projection(
        scene.camera.fov_y_deg,
        aspect,
        scene.camera.near,
        scene.camera.far,
    );
    let (fog_color, fog) = match &scene.fog {
        Some(f) => (f.color.extend(0.0), Vec4::new(f.z_a, f.z_b, f.s_a, f.s_b)),
        None => (Vec4::ZERO, Vec4::ZERO),
    };
    FrameData {
        view,
        proj,
        view_proj: proj * view,
        camera_pos: scene.camera.position.extend(1.0),
        ambient: scene.ambient.extend(0.0),
        fog_color,
        fog,
        counts: [light_count, 0, 0, 0],
        inv_view_proj: (proj * view).inverse(),
    }
}

pub fn object_data(model: Mat4) -> ObjectData {
    let n3 = glam::Mat3::from_mat4(model).inverse().transpose();
    ObjectData {
        model,
        normal_matrix: Mat4::from_mat3(n3),
    }
}
