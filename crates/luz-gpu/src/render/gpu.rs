//! GPU-side data layouts, mirrored in `shaders_glsl/include/bindings.glsl`; the numbers shared with
//! GLSL come from it ([`glsl`]).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};

use crate::scene::{AreaLight, AreaMethod, AreaShape, Falloff, Light, LightKind, Material, Scene};

pub use crate::glsl;

use glsl::include_bindings as b;

pub const SET_FRAME: u32 = b::SET_FRAME as u32;
pub const BINDING_FRAME: u32 = b::BINDING_FRAME as u32;
pub const BINDING_LIGHTS: u32 = b::BINDING_LIGHTS as u32;
pub const BINDING_OBJECTS: u32 = b::BINDING_OBJECTS as u32;
pub const BINDING_SRGB_TABLE: u32 = b::BINDING_SRGB_TABLE as u32;
pub const BINDING_DEFERRED_MATERIALS: u32 = b::BINDING_DEFERRED_MATERIALS as u32;
/// Clustered light culling: the grid and clusters, and the light index list.
pub const BINDING_CLUSTERS: u32 = b::BINDING_CLUSTERS as u32;
pub const BINDING_CLUSTER_LIGHTS: u32 = b::BINDING_CLUSTER_LIGHTS as u32;
pub const BINDING_INSTANCES: u32 = b::BINDING_INSTANCES as u32;
/// Area lights and the LTC table (`shaders_glsl/include/area.glsl`).
pub const BINDING_AREA: u32 = b::BINDING_AREA as u32;
/// The copy of the opaque scene transmissive draws read (`shaders_glsl/include/transmission.glsl`).
pub const BINDING_TRANSMISSION: u32 = b::BINDING_TRANSMISSION as u32;
/// The environment's set (`shaders_glsl/include/ibl.glsl`).
pub const SET_ENV: u32 = glsl::include_ibl::SET_ENV as u32;
/// The material maps' set.
pub const SET_MATERIAL: u32 = b::SET_MATERIAL as u32;

pub const LIGHT_DIRECTIONAL: u32 = b::LIGHT_DIRECTIONAL;
pub const LIGHT_POINT: u32 = b::LIGHT_POINT;
pub const LIGHT_SPOT: u32 = b::LIGHT_SPOT;
pub const FALLOFF_NONE: u32 = b::FALLOFF_NONE;
pub const FALLOFF_INVERSE_SQUARE: u32 = b::FALLOFF_INVERSE_SQUARE;
pub const FALLOFF_CLASSIC: u32 = b::FALLOFF_CLASSIC;

// The forward pipeline layout lists its set layouts in index order (frame, environment,
// materials; `render::forward`).
const _: () = assert!(SET_FRAME == 0 && SET_ENV == 1 && SET_MATERIAL == 2 && SET_SHADOW == 3);

/// The shadow maps' set (`shaders_glsl/include/shadows.glsl`).
pub const SET_SHADOW: u32 = glsl::include_shadows::SET_SHADOW as u32;

/// Material model ids (specialization constant 0): the CPU reference's codes.
pub use crate::brdf::model_code;

/// Specialization constant ids.
pub const SPEC_MODEL: u32 = b::SPEC_MODEL;
pub const SPEC_FOG: u32 = b::SPEC_FOG;
pub const SPEC_ALPHA_MODE: u32 = b::SPEC_ALPHA_MODE;
pub const SPEC_SPECULAR_METHOD: u32 = glsl::include_ibl::SPEC_SPECULAR_METHOD;
pub const SPEC_DIFFUSE_FROM_SH: u32 = glsl::include_ibl::SPEC_DIFFUSE_FROM_SH;
pub const SPEC_ENERGY_COMPENSATION: u32 = glsl::include_ibl::SPEC_ENERGY_COMPENSATION;
pub const SPEC_IBL_SAMPLES: u32 = glsl::include_ibl::SPEC_IBL_SAMPLES;
pub const SPEC_MIP_FILTERED: u32 = glsl::include_ibl::SPEC_MIP_FILTERED_SAMPLES;
pub const SPEC_DEBUG_VIEW: u32 = b::SPEC_DEBUG_VIEW;
pub const SPEC_SEL_DISTRIBUTION: u32 = b::SPEC_SEL_DISTRIBUTION;
pub const SPEC_SEL_GEOMETRY: u32 = b::SPEC_SEL_GEOMETRY;
pub const SPEC_SEL_FRESNEL: u32 = b::SPEC_SEL_FRESNEL;
pub const SPEC_MAPS: u32 = b::SPEC_MAPS;
pub const SPEC_REFRACTION: u32 = b::SPEC_REFRACTION;
pub const SPEC_LIGHT_KINDS: u32 = b::SPEC_LIGHT_KINDS;
pub const SPEC_OUTPUT: u32 = glsl::include_output::SPEC_OUTPUT;
pub const SPEC_OUTPUT_TONEMAP: u32 = glsl::include_output::SPEC_OUTPUT_TONEMAP;
pub const SPEC_OUTPUT_CLAMP: u32 = glsl::include_output::SPEC_OUTPUT_CLAMP;
/// `SEL_DIFFUSE`: the diffuse selector of Cook-Torrance / metal-rough ([`crate::render::forward::material_key`]).
pub const SPEC_SEL_DIFFUSE: u32 = b::SPEC_SEL_DIFFUSE;
/// `LOBES`: the glTF extension layers compiled in (`VariantKey::lobes`).
pub const SPEC_LOBES: u32 = b::SPEC_LOBES;
/// `CLUSTERED`: the fragment stage loops over its cluster's lights only.
pub const SPEC_CLUSTERED: u32 = b::SPEC_CLUSTERED;
/// `SHADOW_FIXED_0..3` of shadows.glsl: the shadowed lights packed whole
/// ([`crate::render::shadow::fixed_slots`]).
pub const SPEC_SHADOW_FIXED_0: u32 = glsl::include_shadows::SPEC_SHADOW_FIXED_0;
pub const SPEC_SHADOW_FIXED_1: u32 = glsl::include_shadows::SPEC_SHADOW_FIXED_1;
pub const SPEC_SHADOW_FIXED_2: u32 = glsl::include_shadows::SPEC_SHADOW_FIXED_2;
pub const SPEC_SHADOW_FIXED_3: u32 = glsl::include_shadows::SPEC_SHADOW_FIXED_3;
/// `LK_*` bits of `shaders_glsl/include/bindings.glsl`.
pub const LK_DIRECTIONAL: u32 = b::LK_DIRECTIONAL;
pub const LK_POINT: u32 = b::LK_POINT;
pub const LK_SPOT: u32 = b::LK_SPOT;
pub const LK_FALLOFF_NONE: u32 = b::LK_FALLOFF_NONE;
pub const LK_FALLOFF_INVERSE_SQUARE: u32 = b::LK_FALLOFF_INVERSE_SQUARE;
pub const LK_FALLOFF_CLASSIC: u32 = b::LK_FALLOFF_CLASSIC;
pub const LK_RANGE: u32 = b::LK_RANGE;
pub const LK_SHADOW_HARD: u32 = b::LK_SHADOW_HARD;
pub const LK_SHADOW_PCF: u32 = b::LK_SHADOW_PCF;
pub const LK_SHADOW_PCSS: u32 = b::LK_SHADOW_PCSS;
pub const LK_AREA_LTC: u32 = b::LK_AREA_LTC;
pub const LK_AREA_RP: u32 = b::LK_AREA_RP;
pub const LK_AREA_SAMPLED: u32 = b::LK_AREA_SAMPLED;
pub const LK_AREA_SPHERE: u32 = b::LK_AREA_SPHERE;
pub const LK_AREA_TUBE: u32 = b::LK_AREA_TUBE;
pub const LK_AREA_DISK: u32 = b::LK_AREA_DISK;
pub const LK_AREA_SHADOW_HARD: u32 = b::LK_AREA_SHADOW_HARD;
pub const LK_AREA_SHADOW_PCF: u32 = b::LK_AREA_SHADOW_PCF;
pub const LK_AREA_SHADOW_PCSS: u32 = b::LK_AREA_SHADOW_PCSS;
const _: () = assert!(
    LK_AREA_SHADOW_HARD == LK_SHADOW_HARD << b::LK_AREA_SHADOW_SHIFT
        && LK_AREA_SHADOW_PCF == LK_SHADOW_PCF << b::LK_AREA_SHADOW_SHIFT
        && LK_AREA_SHADOW_PCSS == LK_SHADOW_PCSS << b::LK_AREA_SHADOW_SHIFT
);
pub const LK_AREA_LTC_TUBE: u32 = b::LK_AREA_LTC_TUBE;
// Every LIGHT_KINDS bit of area lights is its own (two branches once both took 65536).
const _: () = {
    let bits = [
        LK_AREA_LTC,
        LK_AREA_RP,
        LK_AREA_SAMPLED,
        LK_AREA_SPHERE,
        LK_AREA_TUBE,
        LK_AREA_DISK,
        LK_AREA_SHADOW_HARD,
        LK_AREA_SHADOW_PCF,
        LK_AREA_SHADOW_PCSS,
        LK_AREA_LTC_TUBE,
        b::LK_DIRECTIONAL,
        b::LK_POINT,
        b::LK_SPOT,
        b::LK_FALLOFF_NONE,
        b::LK_FALLOFF_INVERSE_SQUARE,
        b::LK_FALLOFF_CLASSIC,
        b::LK_RANGE,
        LK_SHADOW_HARD,
        LK_SHADOW_PCF,
        LK_SHADOW_PCSS,
    ];
    let mut seen = 0u32;
    let mut i = 0;
    while i < bits.len() {
        assert!(bits[i].count_ones() == 1 && seen & bits[i] == 0);
        seen |= bits[i];
        i += 1;
    }
};

/// The `LK_AREA_*` method and shape bits (and `LK_RANGE`) area lights need, as `area.glsl`'s
/// `area_shade` picks a method: sampled where asked; representative point for spheres and tubes
/// that ask for it; LTC for the rest (rect and disk always, unless sampled): the facing ribbon
/// for tubes (`LK_AREA_LTC_TUBE`), the polygon form for the other shapes (`LK_AREA_LTC`); and the
/// `LK_AREA_SHADOW_*` filter of each area light's shadow.
pub fn area_kinds(lights: &[AreaLight]) -> u32 {
    lights.iter().fold(0, |bits, l| {
        bits | match (l.shape, l.method) {
            (_, AreaMethod::Sampled { .. }) => LK_AREA_SAMPLED,
            (
                AreaShape::Tube { .. } | AreaShape::Sphere { .. },
                AreaMethod::RepresentativePoint,
            ) => LK_AREA_RP,
            (AreaShape::Tube { .. }, AreaMethod::Ltc) => LK_AREA_LTC_TUBE,
            _ => LK_AREA_LTC,
        } | match l.shape {
            AreaShape::Rect { .. } => 0,
            AreaShape::Disk { .. } => LK_AREA_DISK,
            AreaShape::Sphere { .. } => LK_AREA_SPHERE,
            AreaShape::Tube { .. } => LK_AREA_TUBE,
        } | if l.range.is_some() { LK_RANGE } else { 0 }
            | match l.shadow.map(|s| s.method) {
                None => 0,
                Some(crate::scene::ShadowMethod::Hard) => LK_AREA_SHADOW_HARD,
                Some(crate::scene::ShadowMethod::Pcf) => LK_AREA_SHADOW_PCF,
                Some(crate::scene::ShadowMethod::Pcss) => LK_AREA_SHADOW_PCSS,
            }
    })
}

/// The `LK_*` bits of a scene's punctual and area lights.
pub fn scene_light_kinds(scene: &Scene) -> u32 {
    light_kinds(&scene.lights) | area_kinds(&scene.area_lights)
}

/// `vec4`s per area light in `area_data` (`AREA_VEC4S`).
pub const AREA_VEC4S: usize = b::AREA_VEC4S as usize;
const _: () = assert!(b::LTC_SIZE as usize == crate::brdf::LTC_SIZE);

/// Where the first area light starts in `area_data`, in `vec4`s: after the LTC table when some
/// light is shaded by LTC.
pub fn area_offset(scene: &Scene) -> usize {
    if area_kinds(&scene.area_lights) & (LK_AREA_LTC | LK_AREA_LTC_TUBE) != 0 {
        crate::brdf::LTC_SIZE * crate::brdf::LTC_SIZE * 2
    } else {
        0
    }
}

/// One area light as `area.glsl`'s `area_light` reads it.
pub fn gpu_area_light(l: &AreaLight) -> [Vec4; AREA_VEC4S] {
    use glam::Vec3;
    let n = l.direction.normalize_or_zero();
    let (shape, ex, ey, radius) = match l.shape {
        AreaShape::Rect { .. } => {
            let (x, y) = l.rect_axes().unwrap_or((Vec3::ZERO, Vec3::ZERO));
            (b::AREA_RECT, x, y, 0.0)
        }
        AreaShape::Disk { radius } => {
            let t = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
            let x = n.cross(t).normalize();
            (b::AREA_DISK, x * radius, n.cross(x) * radius, radius)
        }
        AreaShape::Sphere { radius } => (b::AREA_SPHERE, Vec3::ZERO, Vec3::ZERO, radius),
        AreaShape::Tube { length, radius } => {
            (b::AREA_TUBE, n * (0.5 * length), Vec3::ZERO, radius)
        }
    };
    let (method, samples) = match l.method {
        AreaMethod::Ltc => (b::AREA_LTC, 0),
        AreaMethod::RepresentativePoint => (b::AREA_RP, 0),
        AreaMethod::Sampled { samples } => (b::AREA_SAMPLED, samples),
    };
    [
        l.position.extend(shape as f32),
        n.extend((method | samples << 2) as f32),
        l.radiance().extend(l.range.unwrap_or(0.0)),
        ex.extend(if l.two_sided { 1.0 } else { 0.0 }),
        ey.extend(radius),
    ]
}

/// The area lights' part of `area_data`.
pub fn area_lights_data(scene: &Scene) -> Vec<Vec4> {
    scene.area_lights.iter().flat_map(gpu_area_light).collect()
}

/// The whole of `area_data`: the LTC table when needed, then the lights (at least one `vec4`:
/// Vulkan wants a non-zero range).
pub fn area_data(scene: &Scene) -> Vec<Vec4> {
    let mut data = Vec::new();
    if area_offset(scene) > 0 {
        let table = crate::brdf::ltc_table();
        data.extend(
            table
                .chunks_exact(4)
                .map(|c| Vec4::new(c[0], c[1], c[2], c[3])),
        );
    }
    data.extend(area_lights_data(scene));
    if data.is_empty() {
        data.push(Vec4::ZERO);
    }
    data
}

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
        } | if l.range.is_some() { LK_RANGE } else { 0 }
            | match l.shadow.map(|s| s.method) {
                None => 0,
                Some(crate::scene::ShadowMethod::Hard) => LK_SHADOW_HARD,
                Some(crate::scene::ShadowMethod::Pcf) => LK_SHADOW_PCF,
                Some(crate::scene::ShadowMethod::Pcss) => LK_SHADOW_PCSS,
            }
    })
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
    /// x: `color::exposure_scale` of the scene's exposure, for the display output.
    pub display: Vec4,
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
/// [`crate::brdf::GpuBrdfParams`] (112 bytes), then the object's index (128 bytes in all:
/// lavapipe's limit).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub struct MaterialPush {
    pub brdf: [u32; 28],
    pub object_index: u32,
    pub flags: u32,
    /// 1: shadow maps darken the object (`ObjectShadow::receive`).
    pub receive_shadow: u32,
    /// 1: a back face is lit with the flipped normal (`Sides::Double`, glTF `doubleSided`).
    pub double_sided: u32,
}

/// `DeferredMaterial` (std430) of `deferred_light.frag`: one per object slot, the push constants
/// and the extra block its material has in the forward pass.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub struct DeferredMaterial {
    pub push: MaterialPush,
    pub extra: crate::render::material::MaterialExtra,
}

const _: () = assert!(std::mem::size_of::<MaterialPush>() == 128);
const _: () = assert!(std::mem::size_of::<DeferredMaterial>() == 224);

/// Vulkan guarantees 128 bytes of push constants; lavapipe offers exactly that.
const _: () = assert!(std::mem::size_of::<MaterialPush>() <= 128);
const _: () = assert!(std::mem::size_of::<GpuLight>() == 80);
const _: () = assert!(std::mem::size_of::<FrameData>() == 4 * 64 + 4 * 16 + 16 + 16);

/// The vertex colour stream (binding 2, one RGBA32F per vertex, read at location 5) of the
/// forward pass's `*_color` modules and of the alpha-tested shadow depth pass.
pub fn vertex_color_input() -> (
    ash::vk::VertexInputBindingDescription,
    ash::vk::VertexInputAttributeDescription,
) {
    (
        ash::vk::VertexInputBindingDescription {
            binding: 2,
            stride: 16,
            input_rate: ash::vk::VertexInputRate::VERTEX,
        },
        ash::vk::VertexInputAttributeDescription {
            location: 5,
            binding: 2,
            format: ash::vk::Format::R32G32B32A32_SFLOAT,
            offset: 0,
        },
    )
}

/// One vertex: position, normal, uv, tangent (xyz + handedness).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, Default, PartialEq)]
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
            // 0: no range (the shader skips the window).
            cone: Vec4::new(cos_umbra, cos_inner, smooth, l.range.unwrap_or(0.0)),
        }
    }
}

/// The push constants of a material (its packed BRDF parameters).
pub fn material_push(m: &Material) -> MaterialPush {
    let packed = crate::brdf::GpuBrdfParams::from_model(m);
    let bytes = packed.to_bytes();
    let mut brdf = [0u32; 28];
    for (w, c) in brdf.iter_mut().zip(bytes.chunks_exact(4)) {
        *w = u32::from_ne_bytes([c[0], c[1], c[2], c[3]]);
    }
    MaterialPush {
        brdf,
        object_index: 0,
        flags: 0,
        receive_shadow: 1,
        double_sided: 0,
    }
}

/// Vulkan clip space from a right-handed view: y down, depth in [0, 1] (near 0, far 1; the
/// camera's perspective or orthographic projection, [`crate::scene::Camera::projection`]).
pub fn projection(camera: &crate::scene::Camera, aspect: f32) -> Mat4 {
    let mut p = camera.projection(aspect);
    p.y_axis.y = -p.y_axis.y;
    p
}

pub fn frame_data(scene: &Scene, aspect: f32, light_count: u32) -> FrameData {
    let view = scene.camera.view();
    let proj = projection(&scene.camera, aspect);
    let (fog_color, fog) = match &scene.fog {
        Some(f) => (f.color.extend(0.0), Vec4::new(f.z_a, f.z_b, f.s_a, f.s_b)),
        None => (Vec4::ZERO, Vec4::ZERO),
    };
    FrameData {
        view,
        proj,
        view_proj: proj * view,
        camera_pos: scene.camera.eye_homogeneous(),
        ambient: scene.ambient.extend(0.0),
        fog_color,
        fog,
        counts: [
            light_count,
            scene.area_lights.len() as u32,
            area_offset(scene) as u32,
            0,
        ],
        inv_view_proj: (proj * view).inverse(),
        display: Vec4::new(
            crate::color::exposure_scale(scene.output.exposure),
            0.0,
            0.0,
            0.0,
        ),
    }
}

pub fn object_data(model: Mat4) -> ObjectData {
    let n3 = glam::Mat3::from_mat4(model).inverse().transpose();
    ObjectData {
        model,
        normal_matrix: Mat4::from_mat3(n3),
    }
}

#[cfg(test)]
mod tests {
    use super::glsl;
    use crate::render::forward::DebugView;
    use crate::scene::TextureSlot;

    /// Every debug view has its GLSL code `DEBUG_VIEW_<NAME>`, the codes are dense in `ALL` order,
    /// and each name parses back to its view.
    #[test]
    fn debug_view_codes_names_and_glsl_agree() {
        let generated = include_str!(concat!(env!("OUT_DIR"), "/glsl_constants.rs"));
        for (i, v) in DebugView::ALL.iter().enumerate() {
            assert_eq!(v.id(), i as u32, "{v:?}");
            let line = format!(
                "pub const DEBUG_VIEW_{}: u32 = {i};",
                v.name().to_ascii_uppercase()
            );
            assert!(generated.contains(&line), "{line} not generated");
            assert_eq!(DebugView::from_name(v.name()), Some(*v));
            assert_eq!(DebugView::from_name(&v.name().to_uppercase()), Some(*v));
        }
        assert_eq!(DebugView::from_name("bogus"), None);
        assert_eq!(
            generated.matches("pub const DEBUG_VIEW_").count(),
            DebugView::ALL.len()
        );
    }

    /// The material set binds map `TextureSlot::ALL[i]` at binding i = its GLSL `MAP_*`, then the
    /// extra uniforms.
    #[test]
    fn material_map_bindings_follow_the_slots() {
        use glsl::include_bindings as b;
        let maps = [
            b::MAP_BASE_COLOR,
            b::MAP_SPECULAR,
            b::MAP_METALLIC,
            b::MAP_ROUGHNESS,
            b::MAP_ORM,
            b::MAP_NORMAL,
            b::MAP_OCCLUSION,
            b::MAP_EMISSIVE,
            b::MAP_TRANSMISSION,
            b::MAP_THICKNESS,
            b::MAP_DIFFUSE_TRANSMISSION,
            b::MAP_DIFFUSE_TRANSMISSION_COLOR,
            b::MAP_ANISOTROPY,
            b::MAP_CLEARCOAT,
            b::MAP_CLEARCOAT_ROUGHNESS,
            b::MAP_SHEEN_COLOR,
            b::MAP_SHEEN_ROUGHNESS,
            b::MAP_SPECULAR_FACTOR,
            b::MAP_SPECULAR_COLOR,
            b::MAP_IRIDESCENCE,
            b::MAP_IRIDESCENCE_THICKNESS,
            b::MAP_CLEARCOAT_NORMAL,
        ];
        assert_eq!(maps.len(), TextureSlot::ALL.len());
        assert_eq!(crate::render::material::SLOT_COUNT, TextureSlot::ALL.len());
        for (i, (slot, map)) in TextureSlot::ALL.iter().zip(maps).enumerate() {
            assert_eq!(map, i as i32, "{slot:?}");
        }
        assert_eq!(
            crate::render::material::BINDING_EXTRA,
            TextureSlot::ALL.len() as u32
        );
    }

    /// The forward pass's specialization constants have distinct ids (across `bindings.glsl` and
    /// `ibl.glsl`, which share the pipeline), and the Rust names point at them.
    #[test]
    fn specialization_ids_are_distinct_and_named() {
        let ids = [
            super::SPEC_MODEL,
            super::SPEC_FOG,
            super::SPEC_SPECULAR_METHOD,
            super::SPEC_DIFFUSE_FROM_SH,
            super::SPEC_ENERGY_COMPENSATION,
            super::SPEC_IBL_SAMPLES,
            super::SPEC_MIP_FILTERED,
            super::SPEC_DEBUG_VIEW,
            super::SPEC_SEL_DISTRIBUTION,
            super::SPEC_SEL_GEOMETRY,
            super::SPEC_SEL_FRESNEL,
            super::SPEC_MAPS,
            super::SPEC_LIGHT_KINDS,
            super::SPEC_SEL_DIFFUSE,
            super::SPEC_OUTPUT,
            super::SPEC_OUTPUT_TONEMAP,
            super::SPEC_OUTPUT_CLAMP,
            super::SPEC_CLUSTERED,
        ];
        let mut sorted = ids.to_vec();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), ids.len(), "{ids:?}");
        assert_eq!(sorted, (0..ids.len() as u32).collect::<Vec<_>>());
        // The LK_* bits are distinct single bits.
        let lk = [
            super::LK_DIRECTIONAL,
            super::LK_POINT,
            super::LK_SPOT,
            super::LK_FALLOFF_NONE,
            super::LK_FALLOFF_INVERSE_SQUARE,
            super::LK_FALLOFF_CLASSIC,
        ];
        assert!(lk.iter().all(|b| b.is_power_of_two()));
        assert_eq!(lk.iter().fold(0, |a, b| a | b).count_ones(), 6);
    }

    /// The generator reads what the sources say: a few values checked against the GLSL text.
    #[test]
    fn generated_constants_match_the_sources() {
        let bindings = include_str!("../../../../shaders_glsl/include/bindings.glsl");
        assert!(bindings.contains("#define SET_MATERIAL 2\n"));
        assert_eq!(glsl::include_bindings::SET_MATERIAL, 2);
        assert!(bindings.contains("layout(constant_id = 13) const int SEL_DIFFUSE"));
        assert_eq!(glsl::include_bindings::SPEC_SEL_DIFFUSE, 13);
        assert!(bindings.contains("#define LK_FALLOFF_CLASSIC 32u\n"));
        assert_eq!(glsl::include_bindings::LK_FALLOFF_CLASSIC, 32);
        let ibl = include_str!("../../../../shaders_glsl/include/ibl.glsl");
        assert!(ibl.contains("#define SET_ENV 1\n"));
        assert_eq!(super::SET_ENV, 1);
        let color = include_str!("../../../../shaders_glsl/include/color.glsl");
        assert!(color.contains("#define TONEMAP_AGX 4u\n"));
        assert_eq!(glsl::include_color::TONEMAP_AGX, 4);
    }
}
