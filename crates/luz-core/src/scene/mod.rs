//! The scene: file format (JSON), validation, camera, lights, materials, objects and meshes.
//!
//! Plain Rust, no Vulkan: the renderer turns a [`Scene`] into GPU data. The file format is
//! described in `docs/scene-format.md`. Every error message reads `<file>: <json path>: <reason>`
//! (see [`SceneError`]); no input makes this module panic.

pub mod area;
mod decode;
pub use decode::MATERIAL_MODELS;
/// The viewer's edit rules (no egui): changes that keep a scene valid.
pub mod edit;
mod encode;
mod environment;
mod error;
pub mod gltf;
pub mod json;
pub mod lod;
pub mod mesh;
mod mesh_cache;
pub mod model;
pub mod obj;
pub mod shadow;
pub mod tessellation;
mod textures;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3, Vec4};

pub use area::{AreaLight, AreaMethod, AreaShape};
pub use encode::{encode, save, to_json, Encoded};
pub use environment::{
    DiffuseMethod, EnvSource, Environment, SpecularMethod, DEFAULT_ENV_SAMPLES,
    DEFAULT_SUN_DIRECTION, DEFAULT_SUN_INTENSITY, MAX_ENV_SAMPLES, MAX_SUN_INTENSITY,
};
pub use error::SceneError;
pub use mesh::{
    Mesh, Vertex, MAX_ICOSPHERE_SUBDIVISIONS, MAX_PLANE_SUBDIVISIONS, MAX_PRIMITIVE_TRIANGLES,
    MAX_RINGS, MAX_SEGMENTS,
};
pub use shadow::{CascadeSplit, ObjectShadow, Shadow, ShadowMethod};
pub use tessellation::{Tessellation, DEFAULT_TESSELLATION_ERROR_PX};
pub use textures::{
    slots_for_model, AlphaMode, Filter, MaterialTextures, SamplerDesc, Sides, TextureRef,
    TextureSlot, Wrap,
};

/// Largest accepted output width or height.
pub const MAX_IMAGE_SIZE: u32 = 16384;

/// The built-in scene (`assets/scenes/default.json`), used when no scene file is given.
pub const DEFAULT_SCENE_JSON: &str = include_str!("../../../../assets/scenes/default.json");

/// A validated scene, ready to render.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The file the scene came from (`None` for the embedded default).
    pub source: Option<PathBuf>,
    /// Free text from the file's optional `description`.
    pub description: String,
    pub camera: Camera,
    pub output: Output,
    /// I_a of the classic models; for physically based models a uniform radiance seen by the
    /// diffuse term. Linear RGB.
    pub ambient: Vec3,
    pub lights: Vec<Light>,
    /// Area lights (issue 36), written in `lights` beside the punctual ones.
    pub area_lights: Vec<AreaLight>,
    /// The scene's materials in file order, then the ones made from OBJ/MTL files.
    pub materials: Vec<NamedMaterial>,
    /// Objects in file order; an OBJ with several parts expands into several objects.
    pub objects: Vec<Object>,
    pub fog: Option<Fog>,
    pub saturation: Saturation,
    /// Things the loader accepted but does not use (an MTL's `map_d`, texture-map options it
    /// ignores, …), one sentence each naming the file and line; tools print them.
    pub warnings: Vec<String>,
    /// Image-based lighting and background; `None`: no environment (black).
    pub environment: Option<Environment>,
    /// Cameras offered by the glTF files whose objects import them (`"cameras": true`), in
    /// world space: `--camera N` picks one ([`model::use_camera`]). `camera` is the one in use.
    pub cameras: Vec<gltf::GltfCamera>,
}

impl Scene {
    /// Overrides the output size; automatic tessellation is chosen again for a new height.
    pub fn override_size(&mut self, width: Option<u32>, height: Option<u32>) {
        if let Some(w) = width {
            self.output.width = w;
        }
        if let Some(h) = height {
            self.output.height = h;
            tessellation::resolve(self);
        }
    }

    /// Index of the material called `name`.
    pub fn material_index(&self, name: &str) -> Option<usize> {
        self.materials.iter().position(|m| m.name == name)
    }

    /// The scene's file for messages, or "embedded default".
    pub fn display_name(&self) -> String {
        self.source
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_else(|| "embedded default".into())
    }

    /// Total number of triangles over all objects.
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.triangle_count()).sum()
    }

    /// World-space bounding box of all objects (corners of each object's transformed local
    /// box); `None` without objects.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut out: Option<(Vec3, Vec3)> = None;
        for o in &self.objects {
            for p in box_corners(o.transform.matrix(), o.mesh.bounds()) {
                out = Some(match out {
                    None => (p, p),
                    Some((a, b)) => (a.min(p), b.max(p)),
                });
            }
        }
        out
    }
}

/// The eight corners of object-space bounds `(lo, hi)` under `model`.
pub fn box_corners(model: Mat4, (lo, hi): (Vec3, Vec3)) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        let pick = |bit: usize, a: f32, b: f32| if k & bit == 0 { a } else { b };
        model.transform_point3(Vec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        ))
    })
}

/// How a camera projects: perspective (rays from the eye point, `fov_y_deg`) or orthographic
/// (parallel rays along the view direction through a view rectangle `2 · half_height` tall; the
/// width follows the image's aspect).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Projection {
    #[default]
    Perspective,
    /// Half the height of the view rectangle in world units, > 0.
    Orthographic { half_height: f32 },
}

/// A camera looking from `position` at `target`, perspective or orthographic ([`Projection`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub target: Vec3,
    /// Unit length; never parallel to the view direction.
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180) (perspective only; kept but unused by an
    /// orthographic camera).
    pub fov_y_deg: f32,
    /// Distances to the clip planes, 0 < near < far.
    pub near: f32,
    pub far: f32,
    pub projection: Projection,
}

impl Camera {
    /// World → view matrix (right-handed look-at: the camera looks down −z in view space, so
    /// view-space depth is −z).
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.position, self.target, self.up)
    }

    /// View → clip matrix, `glam::Mat4::perspective_rh` or `orthographic_rh`: depth in [0, 1] as
    /// Vulkan wants, but y up in clip space (a Vulkan renderer flips y, e.g. with a negative
    /// viewport height).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        match self.projection {
            Projection::Perspective => {
                Mat4::perspective_rh(self.fov_y_deg.to_radians(), aspect, self.near, self.far)
            }
            Projection::Orthographic { half_height: h } => {
                let w = h * aspect;
                Mat4::orthographic_rh(-w, w, -h, h, self.near, self.far)
            }
        }
    }

    /// Unit vector from the camera towards the target.
    pub fn forward(&self) -> Vec3 {
        (self.target - self.position).normalize()
    }

    /// The half-height of an orthographic camera's view rectangle; `None` for perspective.
    pub fn ortho_half_height(&self) -> Option<f32> {
        match self.projection {
            Projection::Perspective => None,
            Projection::Orthographic { half_height } => Some(half_height),
        }
    }

    /// Half the width and height of the view volume's cross-section at view depth `depth` on an
    /// image of aspect `aspect`: `depth · tan(fov/2)` (× aspect) in perspective, the constant
    /// view rectangle in orthographic.
    pub fn half_extent(&self, depth: f32, aspect: f32) -> (f32, f32) {
        match self.projection {
            Projection::Perspective => {
                let t = (self.fov_y_deg.to_radians() * 0.5).tan();
                (depth * (t * aspect), depth * t)
            }
            Projection::Orthographic { half_height: h } => (h * aspect, h),
        }
    }

    /// The ray through normalised device coordinates (`ndc_x`, `ndc_y` in [−1, 1], y down as in
    /// Vulkan) at `aspect`: `(origin, direction)` in world space, the direction scaled so its
    /// view-space z is −1 (the ray parameter is the view-space depth). Perspective rays start at
    /// the eye; orthographic ones are parallel (the view direction), starting in the plane
    /// through the eye square to it.
    pub fn ray(&self, ndc_x: f32, ndc_y: f32, aspect: f32) -> (Vec3, Vec3) {
        let inv = self.view().inverse();
        match self.projection {
            Projection::Perspective => {
                let t = (0.5 * self.fov_y_deg.to_radians()).tan();
                let d = Vec3::new(ndc_x * t * aspect, -ndc_y * t, -1.0);
                (self.position, inv.transform_vector3(d))
            }
            Projection::Orthographic { half_height: h } => {
                let o = Vec3::new(ndc_x * h * aspect, -ndc_y * h, 0.0);
                (inv.transform_point3(o), inv.transform_vector3(Vec3::NEG_Z))
            }
        }
    }

    /// The eye as the shaders take it (`FrameData.camera_pos`): the point (position, 1) in
    /// perspective, the direction towards the viewer (−forward, 0) in orthographic, so that
    /// `V = normalize(camera_pos.xyz − P · camera_pos.w)` is the view vector in both.
    pub fn eye_homogeneous(&self) -> Vec4 {
        match self.projection {
            Projection::Perspective => self.position.extend(1.0),
            Projection::Orthographic { .. } => (-self.forward()).extend(0.0),
        }
    }
}

/// Output image settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Output {
    /// Pixels, 1..=16384.
    pub width: u32,
    pub height: u32,
    /// Linear RGB shown where no object is.
    pub background: Vec3,
    /// Where no object (and no environment background) is, the image is transparent: the HDR
    /// image's alpha is the coverage (0 there, fractional on anti-aliased edges) and PNGs are
    /// written RGBA with straight alpha. The Khronos fidelity renderers' `renderSkybox: false`.
    pub transparent: bool,
    /// Exposure in EV: linear colour is multiplied by 2^exposure before tone mapping.
    pub exposure: f32,
    pub tonemap: crate::color::Tonemap,
    /// Samples per pixel: 1, 2, 4 or 8.
    pub msaa: u32,
    /// Budget of automatic tessellation: how many pixels a silhouette may be off
    /// ([`tessellation`]).
    pub tessellation_error_px: f32,
    /// `luz golden`'s tolerances for this scene (`output.golden`; a sidecar overrides them:
    /// docs/golden.md).
    pub golden: crate::diff::ToleranceOverrides,
    /// How the GPU draws transmissive materials (KHR_materials_transmission; issue 35).
    pub refraction: Refraction,
}

/// How the GPU draws what a transmissive material lets through (`output.refraction`): the
/// screen-space methods sample a copy of the opaque scene's HDR colour (with its mips) where the
/// refracted ray leaves the object; the copy's mip level is the method's blur policy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum Refraction {
    /// `"screen"`: the Khronos Sample Renderer's policy: level log2(width) · roughness ·
    /// clamp(2 ior − 2, 0, 1).
    #[default]
    Screen,
    /// `"screen_filament"`: Filament's policy: level 2 log2(roughness) + log2(width).
    ScreenFilament,
    /// `"screen_sharp"`: level 0 whatever the roughness (no blur).
    ScreenSharp,
    /// `"thin"`: every transmissive surface thin-walled (no bending, no attenuation), blurred as
    /// `"screen"`.
    Thin,
    /// `"none"`: transmission off: transmissive materials drawn opaque (their diffuse keeps
    /// what the transmission took), no copy of the scene.
    None,
    /// `"environment"`: no copy of the scene: the ray is followed through a sphere whose
    /// diameter is the thickness (Filament's "solid" refraction) and the environment is read
    /// along the direction it leaves in (needs an environment; without one, as `"screen"`).
    Environment,
}

impl Refraction {
    /// Every method, in the scene format's names.
    pub const ALL: [Refraction; 6] = [
        Refraction::Screen,
        Refraction::ScreenFilament,
        Refraction::ScreenSharp,
        Refraction::Thin,
        Refraction::Environment,
        Refraction::None,
    ];

    /// The scene format's name.
    pub fn name(self) -> &'static str {
        match self {
            Refraction::Screen => "screen",
            Refraction::ScreenFilament => "screen_filament",
            Refraction::ScreenSharp => "screen_sharp",
            Refraction::Thin => "thin",
            Refraction::Environment => "environment",
            Refraction::None => "none",
        }
    }

    /// The method called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|r| r.name() == name)
    }
}

impl Output {
    /// How a render of this output becomes display codes (exposure, tone map, alpha).
    pub fn encoding(&self) -> crate::imageio::Encoding {
        crate::imageio::Encoding {
            exposure_ev: self.exposure,
            tonemap: self.tonemap,
            transparent: self.transparent,
        }
    }

    /// width / height.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }
}

/// The kind of a punctual light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LightKind {
    Directional,
    Point,
    Spot,
}

/// A punctual light.
///
/// Units: a directional light's `intensity` is the irradiance on a surface facing it; a point or
/// spot light's `intensity` is a radiant intensity, so E = intensity / r² under
/// [`Falloff::InverseSquare`] and E = intensity · f_at(r) under [`Falloff::Classic`]. The
/// colour multiplies the intensity per channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    /// Unit vector, the way the light travels: l = −direction for a directional light; a spot's
    /// axis points from the light into the scene. (0, −1, 0) for point lights.
    pub direction: Vec3,
    /// Where a point or spot light is (unused by directional lights).
    pub position: Vec3,
    /// Linear RGB, each channel ≥ 0.
    pub color: Vec3,
    /// ≥ 0; see the type's documentation for units.
    pub intensity: f32,
    /// Distance falloff of point and spot lights ([`Falloff::None`] for directional lights).
    pub falloff: Falloff,
    /// Spot cut-off (umbra) half-angle in degrees, in (0, 90]; 180 for other kinds, so that a
    /// spot formula applied to a point light changes nothing.
    pub umbra_deg: f32,
    /// Spot inner half-angle in degrees, in [0, umbra_deg): full intensity inside it, a
    /// smoothstep in cos θ between inner and umbra (glTF-style). `None`: hard edge at the umbra.
    pub inner_deg: Option<f32>,
    /// Spot exponent s: intensity × (cos θ_s)^s inside the umbra (0 for other kinds).
    pub exponent: f32,
    /// Range of a point or spot light in metres (`None`: infinite, no cut-off). Within it the
    /// falloff is multiplied by [`range_window`]; beyond it the light delivers nothing.
    pub range: Option<f32>,
    /// The light's shadow (`None`: it lights everything it reaches, as without shadows).
    pub shadow: Option<Shadow>,
    /// Point and spot lights: the radius in metres of the sphere that emits (0: a point). Only
    /// shadows see it: PCSS and the reference's soft shadows; shading stays punctual.
    pub radius: f32,
    /// Directional lights: the angular radius in degrees of the emitting disc (the sun: 0.27).
    /// Only shadows see it, as `radius`.
    pub angular_radius_deg: f32,
}

impl Light {
    /// The factor E / I at distance `d`: the falloff times the range window.
    pub fn distance_factor(&self, d: f32) -> f32 {
        self.falloff.factor(d) * range_window(d, self.range)
    }
}

/// glTF KHR_lights_punctual's recommended range window, W(d) = clamp(1 − (d/range)⁴, 0, 1)²: 1 at
/// the light, 0 from `range` on, smooth in between; 1 everywhere without a range.
pub fn range_window(d: f32, range: Option<f32>) -> f32 {
    match range {
        None => 1.0,
        Some(r) => {
            let x = d / r;
            let w = (1.0 - x * x * x * x).clamp(0.0, 1.0);
            w * w
        }
    }
}

/// The most irradiance the range window takes away from an inverse-square light, as a multiple
/// of I / range²: max over d of (I / d²)(1 − W(d)) / (I / range²) = max over x = d / range in
/// (0, 1] of 2x² − x⁶ (at x⁴ = 2/3), and 1 at and beyond the range.
pub const RANGE_CUT_ERROR: f32 = 1.088_662_1;

/// The range at which cutting an inverse-square light of radiant intensity `intensity` (times its
/// brightest colour channel) changes the irradiance anywhere by at most `threshold`:
/// √(RANGE_CUT_ERROR · I / threshold). `None` unless both are positive and finite.
pub fn range_for_threshold(intensity: f32, threshold: f32) -> Option<f32> {
    let ok = |v: f32| v.is_finite() && v > 0.0;
    (ok(intensity) && ok(threshold)).then(|| (RANGE_CUT_ERROR * intensity / threshold).sqrt())
}

/// Distance falloff of a point or spot light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Falloff {
    /// Physical: E = I / d².
    InverseSquare,
    /// No distance attenuation: E = I.
    None,
    /// The classic f_at = min(1 / (c1 + c2·d + c3·d²), 1); E = I · f_at. All c ≥ 0.
    Classic { c1: f32, c2: f32, c3: f32 },
}

impl Falloff {
    /// The factor E / I at distance `d`.
    pub fn factor(&self, d: f32) -> f32 {
        match *self {
            Falloff::InverseSquare => 1.0 / (d * d),
            Falloff::None => 1.0,
            Falloff::Classic { c1, c2, c3 } => {
                let denom = c1 + c2 * d + c3 * d * d;
                if denom <= 1.0 {
                    1.0
                } else {
                    1.0 / denom
                }
            }
        }
    }
}

/// A material with its name (unique within the scene).
#[derive(Debug, Clone, PartialEq)]
pub struct NamedMaterial {
    pub name: String,
    pub material: Material,
    /// Texture maps (all optional) and emission.
    pub textures: MaterialTextures,
}

/// A material's reflection model and its parameters: the CPU reference's [`crate::brdf::Model`]
/// itself, so the scene, the reference and the GPU packing share one type (no conversion).
///
/// To add a model: add a variant to `brdf::Model` (and `brdf::ModelKind`), a decoder in
/// `decode/material.rs` (`MATERIAL_MODELS` and `decoder`), and a section in `docs/scene-format.md`.
pub type Material = crate::brdf::Model;

/// A drawable: a mesh with a material, a transform and a shading frequency.
#[derive(Debug, Clone)]
pub struct Object {
    pub name: String,
    /// What the mesh was made from (for OBJ parts: the OBJ file, resolved against the scene's
    /// folder).
    pub desc: MeshDesc,
    /// Shared between objects made from the same description.
    pub mesh: Arc<Mesh>,
    /// Index into [`Scene::materials`].
    pub material: usize,
    pub transform: Transform,
    pub shading: Shading,
    /// Whether `desc`'s segments came from the file or from [`tessellation::resolve`].
    pub tessellation: Tessellation,
    /// Whether it casts and receives shadows.
    pub shadow: ObjectShadow,
}

/// Object → world: scale, then rotate about X, then Y, then Z, then translate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    pub position: Vec3,
    /// Degrees about X, Y and Z, applied X first: R = Rz · Ry · Rx.
    pub rotation_deg: Vec3,
    /// Per-axis scale, every component > 0.
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform {
            position: Vec3::ZERO,
            rotation_deg: Vec3::ZERO,
            scale: Vec3::ONE,
        }
    }
}

impl Transform {
    /// T · Rz · Ry · Rx · S.
    pub fn matrix(&self) -> Mat4 {
        let r = self.rotation_deg * (std::f32::consts::PI / 180.0);
        Mat4::from_translation(self.position)
            * Mat4::from_rotation_z(r.z)
            * Mat4::from_rotation_y(r.y)
            * Mat4::from_rotation_x(r.x)
            * Mat4::from_scale(self.scale)
    }

    /// The matrix for normals: inverse transpose of the upper 3×3 (renormalise after use).
    pub fn normal_matrix(&self) -> Mat3 {
        Mat3::from_mat4(self.matrix()).inverse().transpose()
    }
}

/// How an object's mesh was described in the scene file.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshDesc {
    Sphere {
        radius: f32,
        segments: u32,
        rings: u32,
    },
    Icosphere {
        radius: f32,
        subdivisions: u32,
    },
    Plane {
        size: [f32; 2],
        subdivisions: u32,
    },
    Cube {
        size: f32,
    },
    Cone {
        radius: f32,
        height: f32,
        segments: u32,
    },
    Cylinder {
        radius: f32,
        height: f32,
        segments: u32,
    },
    /// Resolved against the scene file's folder.
    Obj {
        path: PathBuf,
    },
    /// A glTF 2.0 file (`.gltf` or `.glb`), resolved against the scene file's folder: the
    /// node hierarchy of scene `scene` (the file's default scene when `None`), baked into one
    /// mesh per node and primitive. `lights` and `cameras`: whether the file's
    /// KHR_lights_punctual lights and its cameras join the scene; `light_shadow`: the imported
    /// lights cast shadows (each with its kind's default settings).
    Gltf {
        path: PathBuf,
        scene: Option<u32>,
        lights: bool,
        cameras: bool,
        light_shadow: bool,
    },
}

impl MeshDesc {
    /// The mesh's `"type"` in the scene file (also the default object name's stem).
    pub fn type_name(&self) -> &'static str {
        match self {
            MeshDesc::Sphere { .. } => "sphere",
            MeshDesc::Icosphere { .. } => "icosphere",
            MeshDesc::Plane { .. } => "plane",
            MeshDesc::Cube { .. } => "cube",
            MeshDesc::Cone { .. } => "cone",
            MeshDesc::Cylinder { .. } => "cylinder",
            MeshDesc::Obj { .. } => "obj",
            MeshDesc::Gltf { .. } => "gltf",
        }
    }

    /// Segments around a sphere, cone or cylinder (`None` for other meshes).
    pub fn segments(&self) -> Option<u32> {
        match *self {
            MeshDesc::Sphere { segments, .. }
            | MeshDesc::Cone { segments, .. }
            | MeshDesc::Cylinder { segments, .. } => Some(segments),
            _ => None,
        }
    }

    /// Triangle count of a built-in primitive (`None` for OBJ and glTF), computed without overflow.
    pub fn triangle_count(&self) -> Option<u64> {
        Some(match *self {
            MeshDesc::Sphere {
                segments, rings, ..
            } => 2 * u64::from(segments) * u64::from(rings.saturating_sub(1)),
            MeshDesc::Icosphere { subdivisions, .. } => 20u64 << (2 * subdivisions.min(20)),
            MeshDesc::Plane { subdivisions, .. } => 2 * u64::from(subdivisions).pow(2),
            MeshDesc::Cube { .. } => 12,
            MeshDesc::Cone { segments, .. } => 2 * u64::from(segments),
            MeshDesc::Cylinder { segments, .. } => 4 * u64::from(segments),
            MeshDesc::Obj { .. } | MeshDesc::Gltf { .. } => return None,
        })
    }

    /// Builds a built-in primitive (`None` for OBJ and glTF).
    pub fn build(&self) -> Option<Mesh> {
        Some(match *self {
            MeshDesc::Sphere {
                radius,
                segments,
                rings,
            } => Mesh::sphere(radius, segments, rings),
            MeshDesc::Icosphere {
                radius,
                subdivisions,
            } => Mesh::icosphere(radius, subdivisions),
            MeshDesc::Plane { size, subdivisions } => Mesh::plane(size, subdivisions),
            MeshDesc::Cube { size } => Mesh::cube(size),
            MeshDesc::Cone {
                radius,
                height,
                segments,
            } => Mesh::cone(radius, height, segments),
            MeshDesc::Cylinder {
                radius,
                height,
                segments,
            } => Mesh::cylinder(radius, height, segments),
            MeshDesc::Obj { .. } | MeshDesc::Gltf { .. } => return None,
        })
    }

    /// The model file of an OBJ or glTF mesh.
    pub fn file(&self) -> Option<&Path> {
        match self {
            MeshDesc::Obj { path } | MeshDesc::Gltf { path, .. } => Some(path),
            _ => None,
        }
    }
}

/// Shading frequency.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Shading {
    /// One normal per triangle, lit once per triangle (at its centroid).
    Flat,
    /// Lit per vertex, colours interpolated.
    Gouraud,
    /// Normals interpolated and renormalised, lit per fragment.
    #[default]
    Phong,
}

/// Depth cueing: S = s_a for z < z_a, s_b for z > z_b, linear between; I' = (1 − S)·I + S·color.
/// z is view-space depth (distance along the camera's forward axis), not Euclidean distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fog {
    pub z_a: f32,
    pub z_b: f32,
    pub s_a: f32,
    pub s_b: f32,
    pub color: Vec3,
}

impl Fog {
    /// S at view-space depth z.
    pub fn factor(&self, z: f32) -> f32 {
        if z <= self.z_a {
            self.s_a
        } else if z >= self.z_b {
            self.s_b
        } else {
            self.s_a + (z - self.z_a) * (self.s_b - self.s_a) / (self.z_b - self.z_a)
        }
    }
}

/// What to do with a channel above 1 (the slides' two options for the classic models), applied
/// to the linear image before exposure and tone mapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Saturation {
    /// Clamp each channel to 1.
    #[default]
    Clamp,
    /// Divide the whole image by its largest channel value (when that exceeds 1).
    Normalize,
    /// Leave the linear image alone (for scenes whose tone mapping handles values above 1).
    None,
}

/// Reads, parses and validates a scene file, loading its OBJ meshes (paths relative to the file).
/// A model file ([`model::is_model`]: `.obj`, `.gltf`, `.glb`) is a scene too: the model with the default rig and
/// a camera that frames it ([`model::model_scene`]).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    if model::is_model(path) {
        return model::model_scene(path);
    }
    let bytes = crate::files::read_input(path).map_err(|e| SceneError::Read {
        file: path.to_path_buf(),
        reason: format!("cannot read the scene file: {e}"),
    })?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        SceneError::Read {
            file: path.to_path_buf(),
            reason: format!("not UTF-8 text (invalid byte on line {line})"),
        }
    })?;
    parse(text, path)
}

/// Parses and validates scene text. `origin` names the file in messages and is the base for
/// relative OBJ paths (its parent folder).
pub fn parse(text: &str, origin: &Path) -> Result<Scene, SceneError> {
    let root = json::parse(text).map_err(|e| SceneError::Syntax {
        file: origin.to_path_buf(),
        path: e.path,
        line: e.line,
        column: e.column,
        reason: e.reason,
    })?;
    let base = origin.parent().unwrap_or(Path::new(""));
    let mut scene = decode::decode(&root, base).map_err(|e| e.into_scene_error(origin))?;
    scene.source = Some(origin.to_path_buf());
    Ok(scene)
}

/// The scene file at `path`, or the embedded default scene when there is none.
pub fn load_or_default(path: Option<&Path>) -> Result<Scene, SceneError> {
    match path {
        Some(p) => load(p),
        None => Ok(default_scene()),
    }
}

/// The embedded default scene.
pub fn default_scene() -> Scene {
    match parse(DEFAULT_SCENE_JSON, Path::new("assets/scenes/default.json")) {
        Ok(mut scene) => {
            scene.source = None;
            scene
        }
        // The unit test `default_scene_parses` keeps this unreachable.
        Err(e) => unreachable!("the embedded default scene is invalid: {e}"),
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod material_tests;

#[cfg(test)]
mod environment_tests;

#[cfg(test)]
mod area_tests;
