//! The reference renderer's core: the scene made ready for ray casting, primary rays with the
//! GPU path's camera, closest hits, and the shading of `shaders_glsl/include/lighting.glsl`
//! (`surface_at`, `ambient_term`, `light_incidence`, `brdf_radiance`, `apply_fog`) evaluated per
//! pixel on the exact surface, plus a Monte Carlo estimate of the environment's light.

use std::collections::HashMap;
use std::sync::Arc;

use anyhow::{Context as _, Result};
use glam::{BVec3, Mat3, Mat4, Vec2, Vec3, Vec4, Vec4Swizzles};

use super::geometry::{LocalSurface, MeshAccel, Part, Ray, Shape};
use super::sampling::{cmj, hash, mix64, unit_float, EnvDistribution};
use super::texture::{CpuTexture, Texels};
use super::ReferenceOptions;
use crate::brdf::{radical_inverse_vdc, sampling_lobes, Lobe, MetalRoughParams, Model};
use crate::env::{env_rotation, Equirect};
use crate::scene::mesh::bounds_of;
use crate::scene::{
    AlphaMode, AreaLight, Fog, Light, LightKind, MeshDesc, Scene, Sides, TextureSlot,
};

/// A material as the reference shades it: the sanitised model and its decoded maps.
struct RefMaterial {
    model: Model,
    maps: HashMap<TextureSlot, Arc<CpuTexture>>,
    normal_scale: f32,
    clearcoat_normal_scale: f32,
    occlusion_strength: f32,
    emissive_factor: Vec3,
    alpha_mode: AlphaMode,
    alpha: f32,
    sides: Sides,
}

/// Most surfaces one primary ray looks through (cut-out, culled or blended ones) before it
/// stops.
const MAX_LAYERS: usize = 64;

/// A ray's hit: object, ray parameter, part, the ray in the object's space.
type Hit = (usize, f32, Part, Ray);

/// An object: its ideal shape and transforms.
struct RefObject {
    shape: Shape,
    to_world: Mat4,
    to_local: Mat4,
    /// Inverse transpose of the upper 3×3 (for normals).
    normal_matrix: Mat3,
    /// Upper 3×3 of `to_world` (for tangents).
    linear: Mat3,
    /// World-space bounding box (slightly padded).
    lo: Vec3,
    hi: Vec3,
    material: usize,
    /// Blocks shadow rays; is darkened by them.
    cast_shadow: bool,
    receive_shadow: bool,
}

/// The environment: its image in environment space, the rotation, and an importance-sampling
/// distribution (none for a constant environment).
struct RefEnv {
    eq: Equirect,
    to_env: Mat3,
    show_background: bool,
    dist: Option<EnvDistribution>,
}

impl RefEnv {
    /// Radiance arriving from world direction `d` (unit): bilinear, as the GPU's sampler reads
    /// the image.
    fn radiance(&self, d: Vec3) -> Vec3 {
        self.eq.sample(self.to_env * d)
    }
}

/// The scene, ready for ray casting.
pub struct Prepared {
    pub width: u32,
    pub height: u32,
    camera: crate::scene::Camera,
    /// [`crate::scene::Camera::eye_homogeneous`]: V = eye.xyz − p · eye.w, as the shaders.
    eye: glam::Vec4,
    aspect: f32,
    near: f32,
    far: f32,
    objects: Vec<RefObject>,
    materials: Vec<RefMaterial>,
    lights: Vec<Light>,
    area_lights: Vec<crate::scene::AreaLight>,
    ambient: Vec3,
    fog: Option<Fog>,
    background: Vec3,
    env: Option<RefEnv>,
}

/// Whether a material needs per-vertex tangents on a mesh (normal map or anisotropy).
fn needs_tangents(scene: &Scene, material: usize) -> bool {
    scene.materials.get(material).is_some_and(|m| {
        m.textures.normal.is_some()
            || matches!(&m.material, crate::scene::Material::Principled(p) if p.anisotropic > 0.0)
    })
}

impl Prepared {
    /// Loads textures and the environment, builds the meshes' BVHs.
    pub fn new(scene: &Scene) -> Result<Self> {
        // Textures: each file decoded once per slot (colour space) and channel.
        type Key = (std::path::PathBuf, TextureSlot, Option<u8>);
        let mut cache: HashMap<Key, Arc<Texels>> = HashMap::new();
        let mut materials = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            let mut maps = HashMap::new();
            for (slot, r) in m.textures.maps() {
                let key = (r.path.clone(), slot, r.channel);
                let data = match cache.get(&key) {
                    Some(t) => t.clone(),
                    None => {
                        let t = Arc::new(Texels::load(r, slot).with_context(|| {
                            format!("material {:?}: {} map", m.name, slot.name())
                        })?);
                        cache.insert(key, t.clone());
                        t
                    }
                };
                maps.insert(slot, Arc::new(CpuTexture::new(data, r)));
            }
            let mut model = m.material.sanitized();
            // The environment's energy compensation is the metal-rough model's (brdf::energy),
            // for its light as for every light, as on the GPU.
            if let Model::MetalRough(p) = &mut model {
                p.energy_compensation = scene
                    .environment
                    .as_ref()
                    .is_some_and(|e| e.energy_compensation);
            }
            materials.push(RefMaterial {
                model,
                maps,
                normal_scale: m.textures.normal_scale,
                clearcoat_normal_scale: m.textures.clearcoat_normal_scale,
                occlusion_strength: m.textures.occlusion_strength,
                emissive_factor: m.textures.emissive_factor,
                alpha_mode: m.textures.alpha_mode,
                alpha: m.textures.alpha,
                sides: m.textures.sides,
            });
        }
        // Meshes: one BVH per shared mesh.
        let mut tangent_meshes: HashMap<*const crate::scene::Mesh, bool> = HashMap::new();
        for o in &scene.objects {
            if matches!(o.desc, MeshDesc::Obj { .. } | MeshDesc::Gltf { .. }) {
                *tangent_meshes.entry(Arc::as_ptr(&o.mesh)).or_default() |=
                    needs_tangents(scene, o.material);
            }
        }
        let mut accels: HashMap<*const crate::scene::Mesh, Arc<MeshAccel>> = HashMap::new();
        let mut objects = Vec::with_capacity(scene.objects.len());
        for o in &scene.objects {
            let shape = match &o.desc {
                MeshDesc::Sphere { radius, .. } | MeshDesc::Icosphere { radius, .. } => {
                    Shape::Sphere { radius: *radius }
                }
                MeshDesc::Plane { size, .. } => Shape::Plane {
                    half_x: 0.5 * size[0],
                    half_z: 0.5 * size[1],
                },
                MeshDesc::Cube { size } => Shape::Cube { half: 0.5 * size },
                MeshDesc::Cylinder { radius, height, .. } => Shape::Cylinder {
                    radius: *radius,
                    half_height: 0.5 * height,
                },
                MeshDesc::Cone { radius, height, .. } => Shape::Cone {
                    radius: *radius,
                    half_height: 0.5 * height,
                },
                MeshDesc::Obj { .. } | MeshDesc::Gltf { .. } => {
                    let ptr = Arc::as_ptr(&o.mesh);
                    let accel = accels.entry(ptr).or_insert_with(|| {
                        let tangents = tangent_meshes.get(&ptr).copied().unwrap_or(false);
                        Arc::new(MeshAccel::new(o.mesh.clone(), tangents))
                    });
                    Shape::Mesh(accel.clone())
                }
            };
            let to_world = o.transform.matrix();
            let to_local = to_world.inverse();
            if !to_local.is_finite() {
                anyhow::bail!("object {:?}: its transform cannot be inverted", o.name);
            }
            let (lo, hi) = shape.bounds();
            let corners = (0..8).map(|i| {
                let upper = BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0);
                to_world.transform_point3(Vec3::select(upper, hi, lo))
            });
            let (wlo, whi) = bounds_of(&corners.collect::<Vec<_>>());
            let pad = (whi - wlo).max_element().max(1e-6) * 1e-5;
            objects.push(RefObject {
                shape,
                to_world,
                to_local,
                normal_matrix: o.transform.normal_matrix(),
                linear: Mat3::from_mat4(to_world),
                lo: wlo - Vec3::splat(pad),
                hi: whi + Vec3::splat(pad),
                material: o.material,
                cast_shadow: o.shadow.cast,
                receive_shadow: o.shadow.receive,
            });
        }
        let env = match &scene.environment {
            None => None,
            Some(e) => {
                let eq = crate::env::load_equirect(e, crate::imageio::MAX_DIMENSION)
                    .context("environment")?;
                let dist = EnvDistribution::new(&eq, e.rotation_deg);
                Some(RefEnv {
                    eq,
                    to_env: env_rotation(-e.rotation_deg),
                    show_background: e.show_background,
                    dist,
                })
            }
        };
        let cam = &scene.camera;
        Ok(Prepared {
            width: scene.output.width,
            height: scene.output.height,
            camera: *cam,
            eye: cam.eye_homogeneous(),
            aspect: scene.output.aspect(),
            near: cam.near,
            far: cam.far,
            objects,
            materials,
            lights: scene.lights.clone(),
            area_lights: scene.area_lights.clone(),
            ambient: scene.ambient,
            fog: scene.fog,
            background: scene.output.background,
            env,
        })
    }

    /// The primary ray through continuous pixel coordinates `(px, py)` (pixel `(x, y)` spans
    /// `[x, x + 1] × [y, y + 1]`, y = 0 at the top), as the GPU's projection (Vulkan clip space,
    /// y down) maps it. The direction's view-space z is −1, so the ray parameter is the view-space
    /// depth.
    pub fn primary_ray(&self, px: f32, py: f32) -> (Vec3, Vec3) {
        let ndc_x = 2.0 * px / self.width as f32 - 1.0;
        let ndc_y = 2.0 * py / self.height as f32 - 1.0;
        self.camera.ray(ndc_x, ndc_y, self.aspect)
    }

    /// The closest hit with view depth in `[t_min, far]` that is seen: not the back face of a
    /// single-sided material (culled, as on the GPU), not cut out by an alpha mask.
    fn trace(&self, o: Vec3, d: Vec3, t_min: f32) -> Option<Hit> {
        let mut t0 = t_min;
        for _ in 0..MAX_LAYERS {
            let hit = self.closest(o, d, t0)?;
            if self.seen(&hit) {
                return Some(hit);
            }
            t0 = next_t(hit.1);
        }
        None
    }

    /// Whether a hit is drawn: a front face or a face of a material that is not single-sided,
    /// and not below its alpha mask's cutoff.
    fn seen(&self, (i, t, part, local): &Hit) -> bool {
        let obj = &self.objects[*i];
        let Some(mat) = self.materials.get(obj.material) else {
            return true;
        };
        if mat.sides == Sides::Single && back_face(obj, *part, local) {
            return false;
        }
        match mat.alpha_mode {
            AlphaMode::Mask { cutoff } => self.alpha_at(obj, mat, (*t, *part, local)) >= cutoff,
            _ => true,
        }
    }

    /// Base colour alpha at a hit: factor × map alpha × vertex colour alpha.
    fn alpha_at(
        &self,
        obj: &RefObject,
        mat: &RefMaterial,
        (t, part, local): (f32, Part, &Ray),
    ) -> f32 {
        let uv = obj.shape.surface(local, t, part).uv;
        let map = mat
            .maps
            .get(&TextureSlot::BaseColor)
            .map_or(1.0, |m| m.sample(uv).w);
        mat.alpha * map * vertex_color(obj, part).w
    }

    /// The closest hit with view depth in `[t_min, far]`: (object, t, part, local ray).
    fn closest(&self, o: Vec3, d: Vec3, t_min: f32) -> Option<Hit> {
        let inv = Vec3::ONE / d;
        let mut best: Option<(usize, f32, Part, Ray)> = None;
        let mut t_best = self.far;
        for (i, obj) in self.objects.iter().enumerate() {
            let a = (obj.lo - o) * inv;
            let b = (obj.hi - o) * inv;
            let enter = a.min(b).max_element().max(t_min);
            let exit = a.max(b).min_element().min(t_best);
            if enter > exit {
                continue;
            }
            let local = Ray {
                o: obj.to_local.transform_point3(o),
                d: obj.to_local.transform_vector3(d),
            };
            if let Some((t, part)) = obj.shape.intersect(&local, t_min, t_best) {
                t_best = t;
                best = Some((i, t, part, local));
            }
        }
        best
    }

    /// The pixel's radiance: `opts.spp` primary rays (the pixel centre for 1, correlated
    /// multi-jittered points otherwise), averaged.
    pub fn pixel(&self, x: u32, y: u32, opts: &ReferenceOptions) -> Vec3 {
        let index = u64::from(y) * u64::from(self.width) + u64::from(x);
        let spp = opts.spp.max(1);
        if spp == 1 {
            return self.radiance(
                x as f32 + 0.5,
                y as f32 + 0.5,
                [opts.seed, index, 0],
                (opts.samples, opts.shadow_samples),
            );
        }
        let pattern = hash(&[opts.seed, index, 0x6a09_e667]) as u32;
        let per = opts.samples.div_ceil(spp).max(1);
        let mut sum = Vec3::ZERO;
        for s in 0..spp {
            let off = cmj(s, spp, pattern);
            sum += self.radiance(
                x as f32 + off.x,
                y as f32 + off.y,
                [opts.seed, index, u64::from(s) + 1],
                (per, opts.shadow_samples),
            );
        }
        sum / spp as f32
    }

    fn radiance(&self, px: f32, py: f32, key: [u64; 3], samples: (u32, u32)) -> Vec3 {
        let (o, d) = self.primary_ray(px, py);
        self.radiance_along(o, d, self.near, key, samples, 0)
    }

    /// The radiance along the ray `o + t d` from `t_min` on: the first seen surface's, and for a
    /// blended one (alpha a) a · its radiance + (1 − a) · what is behind it, in exact depth
    /// order per ray (the GPU sorts per draw).
    fn radiance_along(
        &self,
        o: Vec3,
        d: Vec3,
        t_min: f32,
        key: [u64; 3],
        samples: (u32, u32),
        layer: usize,
    ) -> Vec3 {
        let hit = self.trace(o, d, t_min);
        // A visible emitter nearer than the surface (issue 36): its radiance L, fogged as one.
        if let Some((l, t)) = self.emitter_seen(o, d, t_min, hit.as_ref().map_or(self.far, |h| h.1))
        {
            return self.apply_fog(l, t);
        }
        let Some((i, t, part, local)) = hit else {
            return match &self.env {
                Some(e) if e.show_background => e.radiance(d.normalize_or(Vec3::NEG_Z)),
                _ => self.background,
            };
        };
        let c = self.shade(i, t, part, &local, key, samples)
            + self.transmission(&(i, t, part, local), d, key, samples, layer)
            + self.diffuse_transmission(&(i, t, part, local), d, key, samples);
        let c = self.apply_fog(c, t);
        let obj = &self.objects[i];
        let Some(mat) = self.materials.get(obj.material) else {
            return c;
        };
        if mat.alpha_mode != AlphaMode::Blend || layer >= MAX_LAYERS {
            return c;
        }
        let a = self.alpha_at(obj, mat, (t, part, &local)).clamp(0.0, 1.0);
        let behind = self.radiance_along(o, d, next_t(t), key, samples, layer + 1);
        c * a + behind * (1.0 - a)
    }

    /// World-space shading frame at a hit: point, normal, tangent frame, uv.
    fn world_surface(
        &self,
        obj: &RefObject,
        part: Part,
        ls: &LocalSurface,
    ) -> (Vec3, Vec3, Vec3, Vec3, Vec2) {
        let p = obj.to_world.transform_point3(ls.p);
        let n = match (&obj.shape, part) {
            // As the GPU: each vertex normal through the normal matrix and normalised, then
            // interpolated and normalised again.
            (Shape::Mesh(m), Part::Triangle { index, b1, b2 }) => {
                let vn = m.vertex_normals(index);
                let w = [1.0 - b1 - b2, b1, b2];
                let mut n = Vec3::ZERO;
                for k in 0..3 {
                    n += (obj.normal_matrix * vn[k]).normalize_or(Vec3::Y) * w[k];
                }
                n.normalize_or((obj.normal_matrix * ls.n).normalize_or(Vec3::Y))
            }
            _ => (obj.normal_matrix * ls.n).normalize_or(Vec3::Y),
        };
        let t = obj.linear * Vec3::new(ls.tangent[0], ls.tangent[1], ls.tangent[2]);
        let (x, y) = glsl_tangent_frame(n, t, ls.tangent[3]);
        (p, n, x, y, ls.uv)
    }

    fn shade(
        &self,
        i: usize,
        t: f32,
        part: Part,
        local: &Ray,
        key: [u64; 3],
        (samples, shadow_samples): (u32, u32),
    ) -> Vec3 {
        let obj = &self.objects[i];
        let ls = obj.shape.surface(local, t, part);
        let (p, mut n, mut x, mut y, uv) = self.world_surface(obj, part, &ls);
        let Some(mat) = self.materials.get(obj.material) else {
            return Vec3::ZERO;
        };
        // Double-sided: a back face is lit with the flipped normal and tangent frame.
        if mat.sides == Sides::Double && back_face(obj, part, local) {
            (n, x, y) = (-n, -x, -y);
        }
        let mut s = surface_at(mat, n, x, y, uv);
        tint(&mut s.model, vertex_color(obj, part).xyz());
        let v = (self.eye.truncate() - p * self.eye.w).normalize_or(n);
        let mut c = s.occlusion * ambient_term(&s.model, self.ambient);
        for (k, light) in self.lights.iter().enumerate() {
            let (l, mut e) = light_incidence(light, p);
            if obj.receive_shadow && light.shadow.is_some() && e != Vec3::ZERO {
                let key = [key[0], key[1], key[2] ^ ((k as u64 + 1) << 40)];
                e *= self.light_visibility(light, (p, n, l), obj, key, shadow_samples);
            }
            c += crate::brdf::radiance(&s.model, s.n, l, v, s.x, s.y, e);
        }
        if !self.area_lights.is_empty() {
            // Shadow rays leave the surface by a few ulps of the scene around it.
            let o = p + s.n * ((obj.hi - obj.lo).length().max(p.abs().max_element()) * 2e-5);
            for (k, light) in self.area_lights.iter().enumerate() {
                let shadowed = obj.receive_shadow && light.shadow.is_some();
                let blocked = |dir: Vec3, dist: f32| {
                    shadowed
                        && (self.occluded(o, dir * dist, 1.0 - 1e-4)
                            || self.emitter_blocks(o, dir * dist, 1.0 - 1e-4, Some(k)))
                };
                let key = [key[0], key[1], key[2] ^ ((k as u64 + 1) << 48)];
                c += area::area_light_radiance(light, &s, (p, v), key, samples, &blocked);
            }
        }
        if let Some(env) = &self.env {
            c += s.occlusion * env_light(env, &s, v, key, samples);
        }
        c + s.emission
    }

    /// The fraction of `light` that reaches `p` (normal `n`, unit direction `l` towards the
    /// light) past the shadow-casting objects: one ray for a point-like light, `samples` rays
    /// to stratified points of its disc (as seen from `p`) for a light with a radius or angular
    /// radius. Shading stays punctual: only visibility sees the size.
    fn light_visibility(
        &self,
        light: &Light,
        (p, n, l): (Vec3, Vec3, Vec3),
        obj: &RefObject,
        key: [u64; 3],
        samples: u32,
    ) -> f32 {
        // Leave the surface towards the light's side by a few ulps of the scene around it.
        let scale = (obj.hi - obj.lo).length().max(p.abs().max_element());
        let side = if n.dot(l) >= 0.0 { n } else { -n };
        let o = p + side * (scale * 2e-5);
        let (a, b) = orthonormal_basis(l);
        // The light's size (tangent of the angular radius, or radius), how far a ray may go
        // (to infinity, or to just short of the light) and the sample pattern's salt.
        let (size, t_max, salt) = match light.kind {
            LightKind::Directional => (
                light.angular_radius_deg.to_radians().tan(),
                f32::INFINITY,
                0x5ad0,
            ),
            _ => (light.radius, 1.0 - 1e-5, 0x5ad1),
        };
        // The ray towards the light's centre (`None`) or towards the point `d` of its unit disc.
        let ray = |d: Option<Vec2>| match (light.kind, d) {
            (LightKind::Directional, None) => l,
            (LightKind::Directional, Some(d)) => l + (a * d.x + b * d.y) * size,
            (_, None) => light.position - o,
            (_, Some(d)) => {
                let d = d * size;
                light.position + a * d.x + b * d.y - o
            }
        };
        if size <= 0.0 {
            let r = ray(None);
            return if self.occluded(o, r, t_max) || self.emitter_blocks(o, r, t_max, None) {
                0.0
            } else {
                1.0
            };
        }
        let pattern = hash(&[key[0], key[1], key[2], salt]) as u32;
        let lit = (0..samples)
            .filter(|&s| {
                let d = concentric_disc(cmj(s, samples, pattern));
                let r = ray(Some(d));
                !(self.occluded(o, r, t_max) || self.emitter_blocks(o, r, t_max, None))
            })
            .count();
        lit as f32 / samples as f32
    }

    /// The nearest visible area light (issue 36) that the ray `o + t d` meets from its emitting
    /// side (either side of a `two_sided` rect or disk; a sphere from outside; a tube's side, inside
    /// or out, as [`area::intersect`] sees the emitter) at t in [`t_min`, `t_max`]: its radiance L
    /// and t. A one-sided rect or disk seen from behind is not seen (rays pass through it).
    fn emitter_seen(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<(Vec3, f32)> {
        let len = d.length();
        if self.area_lights.is_empty() || len <= 0.0 || !len.is_finite() {
            return None;
        }
        let dir = d / len;
        let mut best: Option<(Vec3, f32)> = None;
        for light in self.area_lights.iter().filter(|l| l.visible) {
            let Some((dist, _)) = area::intersect(light, o, dir) else {
                continue;
            };
            let t = dist / len;
            if t >= t_min && t <= best.map_or(t_max, |b| b.1) {
                best = Some((light.radiance(), t));
            }
        }
        best
    }

    /// Whether a visible area light other than `own` (its index in the scene's area lights)
    /// meets the shadow ray `o + t d` for t in (0, `t_max`): visible emitters block the shadow
    /// rays of the other lights from either side (a one-sided emitter's back is not drawn but is
    /// still solid, as a single-sided material's back face casts shadows), never their own.
    fn emitter_blocks(&self, o: Vec3, d: Vec3, t_max: f32, own: Option<usize>) -> bool {
        let len = d.length();
        if self.area_lights.is_empty() || len <= 0.0 || !len.is_finite() {
            return false;
        }
        let dir = d / len;
        self.area_lights.iter().enumerate().any(|(k, light)| {
            if !light.visible || Some(k) == own {
                return false;
            }
            let solid = AreaLight {
                two_sided: true,
                ..*light
            };
            area::intersect(&solid, o, dir).is_some_and(|(dist, _)| dist / len < t_max)
        })
    }

    /// Whether a shadow-casting object meets the ray `o + t d` for t in (0, `t_max`) where it
    /// casts: everywhere for an opaque material, where its alpha reaches
    /// [`AlphaMode::shadow_cutoff`] for a mask or a blended one (the ray goes on through the
    /// cut-out parts, as the GPU's depth pass discards them).
    fn occluded(&self, o: Vec3, d: Vec3, t_max: f32) -> bool {
        let inv = Vec3::ONE / d;
        self.objects.iter().any(|obj| {
            if !obj.cast_shadow {
                return false;
            }
            let a = (obj.lo - o) * inv;
            let b = (obj.hi - o) * inv;
            let enter = a.min(b).max_element().max(0.0);
            let exit = a.max(b).min_element().min(t_max);
            if enter > exit || enter.is_nan() || exit.is_nan() {
                return false;
            }
            let local = Ray {
                o: obj.to_local.transform_point3(o),
                d: obj.to_local.transform_vector3(d),
            };
            let cut = self
                .materials
                .get(obj.material)
                .and_then(|m| m.alpha_mode.shadow_cutoff().map(|c| (m, c)));
            let mut t0 = 0.0;
            // Each pass starts past the last hit, so the loop ends after the surfaces on the ray.
            while let Some((t, part)) = obj.shape.intersect(&local, t0, t_max) {
                match cut {
                    Some((mat, cutoff)) if self.alpha_at(obj, mat, (t, part, &local)) < cutoff => {
                        t0 = next_t(t);
                    }
                    _ => return true,
                }
            }
            false
        })
    }

    /// Depth cueing, as `apply_fog`: S from the view-space depth z.
    fn apply_fog(&self, c: Vec3, z: f32) -> Vec3 {
        let Some(f) = &self.fog else {
            return c;
        };
        let s = if z < f.z_a {
            f.s_a
        } else if z > f.z_b {
            f.s_b
        } else if f.z_b > f.z_a {
            f.s_a + (z - f.z_a) * (f.s_b - f.s_a) / (f.z_b - f.z_a)
        } else {
            f.s_a
        };
        c * (1.0 - s) + f.color * s
    }
}

/// GLSL `tangent_frame`: Gram-Schmidt of the tangent against the normal (any perpendicular when
/// degenerate), then Y = w (N × X).
fn glsl_tangent_frame(n: Vec3, t: Vec3, w: f32) -> (Vec3, Vec3) {
    let mut t = t - n * n.dot(t);
    let mut len2 = t.dot(t);
    if len2 < 1e-12 || !len2.is_finite() {
        t = if n.x.abs() < 0.9 {
            n.cross(Vec3::X)
        } else {
            n.cross(Vec3::Y)
        };
        len2 = t.dot(t);
    }
    let x = t / len2.sqrt();
    let y = n.cross(x) * if w < 0.0 { -1.0 } else { 1.0 };
    (x, y)
}

/// What the maps make of a material at one point (`surface_at`).
struct Surface {
    model: Model,
    n: Vec3,
    x: Vec3,
    y: Vec3,
    occlusion: f32,
    emission: Vec3,
}

fn surface_at(mat: &RefMaterial, n: Vec3, x: Vec3, y: Vec3, uv: Vec2) -> Surface {
    let mut s = Surface {
        model: mat.model,
        n,
        x,
        y,
        occlusion: 1.0,
        emission: mat.emissive_factor,
    };
    if mat.maps.is_empty() {
        return s;
    }
    let sample = |slot: TextureSlot| mat.maps.get(&slot).map(|t| t.sample(uv));
    if let Some(c) = sample(TextureSlot::BaseColor) {
        tint(&mut s.model, c.xyz());
    }
    if let Some(c) = sample(TextureSlot::Specular) {
        if let Model::Phong(p) = &mut s.model {
            p.specular_color *= c.xyz();
        }
    }
    let scale_metallic = |model: &mut Model, k: f32| match model {
        Model::MetalRough(p) => p.metallic *= k,
        Model::Principled(p) => p.metallic *= k,
        _ => {}
    };
    let scale_roughness = |model: &mut Model, k: f32| match model {
        Model::CookTorrance(p) => p.roughness *= k,
        Model::MetalRough(p) => p.roughness *= k,
        Model::Principled(p) => p.roughness *= k,
        _ => {}
    };
    if let Some(c) = sample(TextureSlot::Metallic) {
        scale_metallic(&mut s.model, c.x);
    }
    if let Some(c) = sample(TextureSlot::Roughness) {
        scale_roughness(&mut s.model, c.x);
    }
    let mut occ = 1.0;
    if let Some(c) = sample(TextureSlot::Orm) {
        occ = c.x;
        scale_roughness(&mut s.model, c.y);
        scale_metallic(&mut s.model, c.z);
    }
    if let Some(c) = sample(TextureSlot::Occlusion) {
        occ = c.x;
    }
    s.occlusion = 1.0 + mat.occlusion_strength * (occ - 1.0);
    if let Some(c) = sample(TextureSlot::Emissive) {
        s.emission *= c.xyz();
    }
    if let Model::MetalRough(p) = &mut s.model {
        let t = &mut p.transmission;
        if let Some(c) = sample(TextureSlot::Transmission) {
            t.factor *= c.x;
        }
        // The reference walks the object's real surface; the thickness is the GPU's estimate
        // of that walk, kept here so both read the same material.
        if let Some(c) = sample(TextureSlot::Thickness) {
            t.thickness *= c.x;
        }
        if let Some(c) = sample(TextureSlot::DiffuseTransmission) {
            t.diffuse *= c.x;
        }
        if let Some(c) = sample(TextureSlot::DiffuseTransmissionColor) {
            t.diffuse_color *= c.xyz();
        }
    }
    if let Some(c) = sample(TextureSlot::Normal) {
        let mut t = c.xyz() * 2.0 - Vec3::ONE;
        t.x *= mat.normal_scale;
        t.y *= mat.normal_scale;
        let nm = (x * t.x + y * t.y + n * t.z).normalize_or_zero();
        let xm = x - nm * nm.dot(x);
        let len2 = xm.dot(xm);
        if len2 > 1e-12 && nm != Vec3::ZERO {
            s.x = xm / len2.sqrt();
            let flip = if n.cross(x).dot(y) < 0.0 { -1.0 } else { 1.0 };
            s.y = nm.cross(s.x) * flip;
            s.n = nm;
        }
    }
    if let (Some(c), Model::MetalRough(p)) = (sample(TextureSlot::Anisotropy), &mut s.model) {
        // KHR_materials_anisotropy's map: RG the direction in the tangent frame, which becomes
        // the frame's x (the rotation turns it further in the BRDF); B scales the strength.
        let t = s.x * (2.0 * c.x - 1.0) + s.y * (2.0 * c.y - 1.0);
        if t.length_squared() > 1e-12 {
            s.x = t.normalize();
            s.y = s.n.cross(s.x);
        }
        p.anisotropy_strength *= c.z;
    }
    if let Model::MetalRough(p) = &mut s.model {
        layer_maps(p, &sample);
        // KHR_materials_clearcoat's normal: its map's in the geometric frame, else the
        // geometric normal where the base's map bent the shading one.
        if let Some(c) = sample(TextureSlot::ClearcoatNormal) {
            let mut t = c.xyz() * 2.0 - Vec3::ONE;
            t.x *= mat.clearcoat_normal_scale;
            t.y *= mat.clearcoat_normal_scale;
            p.clearcoat_normal = Some((x * t.x + y * t.y + n * t.z).normalize_or(n));
        } else if s.n != n {
            p.clearcoat_normal = Some(n);
        }
    }
    s
}

/// The layers' maps of a metal_rough material (`surface_at` in lighting.glsl), each multiplying
/// its factor (the loader moved glTF's channel to R): clear coat and its roughness, sheen colour
/// and roughness, specular colour (× the clamped F0) and factor (× F0 and F90), iridescence, and
/// the film's thickness between the minimum (texel 0) and the maximum (texel 1).
fn layer_maps(p: &mut MetalRoughParams, sample: &dyn Fn(TextureSlot) -> Option<Vec4>) {
    if let Some(c) = sample(TextureSlot::Clearcoat) {
        p.clearcoat *= c.x;
    }
    if let Some(c) = sample(TextureSlot::ClearcoatRoughness) {
        p.clearcoat_roughness *= c.x;
    }
    if let Some(c) = sample(TextureSlot::SheenColor) {
        p.sheen_color *= c.xyz();
    }
    if let Some(c) = sample(TextureSlot::SheenRoughness) {
        p.sheen_roughness *= c.x;
    }
    if let Some(c) = sample(TextureSlot::SpecularColor) {
        p.dielectric_f0 *= c.xyz();
    }
    if let Some(c) = sample(TextureSlot::SpecularFactor) {
        p.dielectric_f0 *= c.x;
        p.dielectric_f90 *= c.x;
    }
    if let Some(c) = sample(TextureSlot::Iridescence) {
        p.iridescence *= c.x;
    }
    if let Some(c) = sample(TextureSlot::IridescenceThickness) {
        let (lo, hi) = (p.iridescence_thickness_min, p.iridescence_thickness_max);
        p.iridescence_thickness_max = lo + (hi - lo) * c.x;
    }
}

/// The model's base colour multiplied by `c` (a base colour map, vertex colours).
fn tint(model: &mut Model, c: Vec3) {
    match model {
        Model::Lambert(p) => p.albedo *= c,
        Model::Phong(p) => p.diffuse_color *= c,
        Model::CookTorrance(p) => p.color *= c,
        Model::MetalRough(p) => p.base_color *= c,
        Model::Principled(p) => p.base_color *= c,
        Model::OrenNayar(p) => p.albedo *= c,
    }
}

/// The ray parameter just past `t`, to look behind a surface hit at `t`.
fn next_t(t: f32) -> f32 {
    t + (t.abs() * 1e-5).max(1e-6)
}

/// Whether the hit is on a triangle's back side (its winding seen clockwise): the ray in the
/// object's space runs along the face normal. Analytic shapes are seen from outside.
fn back_face(obj: &RefObject, part: Part, local: &Ray) -> bool {
    match (&obj.shape, part) {
        (Shape::Mesh(m), Part::Triangle { index, .. }) => m.face_normal(index).dot(local.d) > 0.0,
        _ => false,
    }
}

/// The interpolated vertex colour at a hit (white without vertex colours).
fn vertex_color(obj: &RefObject, part: Part) -> Vec4 {
    match (&obj.shape, part) {
        (Shape::Mesh(m), Part::Triangle { index, b1, b2 }) => m.vertex_color(index, b1, b2),
        _ => Vec4::ONE,
    }
}

/// `ambient_term`: the slides' I_a k_a O_d for the classic models, the diffuse albedo × the
/// ambient radiance for the others.
fn ambient_term(model: &Model, ambient: Vec3) -> Vec3 {
    match model {
        Model::Phong(p) => ambient * p.ka * p.diffuse_color,
        Model::CookTorrance(p) => ambient * p.kd * p.color,
        Model::MetalRough(p) => {
            let t = p.transmission;
            ambient * (1.0 - p.metallic) * (1.0 - t.factor) * (1.0 - t.diffuse) * p.base_color
        }
        Model::Principled(p) => ambient * (1.0 - p.metallic) * p.base_color,
        Model::Lambert(p) => ambient * p.albedo,
        Model::OrenNayar(p) => ambient * p.albedo,
    }
}

/// GLSL `smoothstep`.
/// Two unit vectors completing `n` (unit) to an orthonormal basis.
fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let a = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let t = (a - n * n.dot(a)).normalize();
    (t, n.cross(t))
}

/// Shirley and Chiu's concentric map of the unit square onto the unit disc (area-preserving).
fn concentric_disc(u: Vec2) -> Vec2 {
    let a = 2.0 * u - Vec2::ONE;
    if a == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, phi) = if a.x.abs() > a.y.abs() {
        (a.x, std::f32::consts::FRAC_PI_4 * (a.y / a.x))
    } else {
        (
            a.y,
            std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (a.x / a.y),
        )
    };
    Vec2::new(r * phi.cos(), r * phi.sin())
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// `light_incidence`: the direction towards the light and the irradiance it delivers on a
/// surface facing it, at `p`.
fn light_incidence(light: &Light, p: Vec3) -> (Vec3, Vec3) {
    let radiance = light.color * light.intensity;
    if light.kind == LightKind::Directional {
        return (-light.direction.normalize_or_zero(), radiance);
    }
    let to_light = light.position - p;
    let d = to_light.length();
    let l = if d > 0.0 { to_light / d } else { Vec3::Y };
    let falloff = match light.falloff {
        crate::scene::Falloff::InverseSquare => 1.0 / (d * d).max(1e-8),
        crate::scene::Falloff::Classic { c1, c2, c3 } => {
            let q = c1 + c2 * d + c3 * d * d;
            if q > 1.0 {
                1.0 / q
            } else {
                1.0
            }
        }
        crate::scene::Falloff::None => 1.0,
    } * crate::scene::range_window(d, light.range);
    let mut e = radiance * falloff;
    if light.kind == LightKind::Spot {
        let cos_s = light.direction.normalize_or_zero().dot(-l);
        let cos_umbra = light.umbra_deg.to_radians().cos();
        let cone = match light.inner_deg {
            Some(inner) => smoothstep(cos_umbra, inner.to_radians().cos(), cos_s),
            None => {
                if cos_s >= cos_umbra {
                    1.0
                } else {
                    0.0
                }
            }
        };
        let shape = if light.exponent > 0.0 {
            cos_s.max(0.0).powf(light.exponent)
        } else {
            1.0
        };
        e *= cone * shape;
    }
    (l, e)
}

/// A sampling strategy of the environment integral.
#[derive(Clone, Copy)]
enum Strategy {
    /// A BRDF lobe (cosine, GGX, …) around the local frame (x, y, n).
    Lobe(Lobe),
    /// The environment's own distribution.
    Env,
}

/// `∫ L_env(l) f(l, v) (n·l) dl` by multiple importance sampling (balance heuristic) over the
/// cosine lobe, the model's specular lobes and the environment's distribution, `samples`
/// directions in all (split evenly between the strategies). Each strategy's points are a
/// Hammersley set, Cranley-Patterson rotated per pixel (unbiased, stratified).
fn env_light(env: &RefEnv, s: &Surface, v: Vec3, key: [u64; 3], samples: u32) -> Vec3 {
    let n = s.n;
    // A right-handed frame with the surface's tangent (anisotropic lobes are along it).
    let x = s.x;
    let y = n.cross(x);
    let to_local = |d: Vec3| Vec3::new(d.dot(x), d.dot(y), d.dot(n));
    let to_world = |d: Vec3| x * d.x + y * d.y + n * d.z;
    let v_local = to_local(v);
    let classic = matches!(s.model, Model::Phong(_));
    // Every model but the classic one is 0 for n·v ≤ 0; the classic one only needs n·l > 0.
    if !classic && v_local.z <= 0.0 {
        return Vec3::ZERO;
    }
    let mut strategies = vec![Strategy::Lobe(Lobe::Cosine)];
    strategies.extend(
        sampling_lobes(&s.model)
            .into_iter()
            .filter(|l| *l != Lobe::Cosine)
            .map(Strategy::Lobe),
    );
    if env.dist.is_some() {
        strategies.push(Strategy::Env);
    }
    let per = samples.max(1).div_ceil(strategies.len() as u32).max(1);
    let pdf_sum = |l_world: Vec3, l_local: Vec3| -> f32 {
        strategies
            .iter()
            .map(|st| match st {
                Strategy::Lobe(lobe) => lobe.pdf(v_local, l_local),
                Strategy::Env => env.dist.as_ref().map_or(0.0, |d| d.pdf(l_world)),
            })
            .sum()
    };
    let mut sum = glam::DVec3::ZERO;
    for (k, st) in strategies.iter().enumerate() {
        let h = hash(&[key[0], key[1], key[2], k as u64 + 1]);
        let (r1, r2) = (unit_float(h), unit_float(mix64(h)));
        for j in 0..per {
            let u1 = ((j as f32 + 0.5) / per as f32 + r1).fract();
            let u2 = (radical_inverse_vdc(j) + r2).fract();
            let (l_world, l_local) = match st {
                Strategy::Lobe(lobe) => {
                    let l = lobe.sample(v_local, u1, u2);
                    let Some(l) = l.try_normalize() else {
                        continue;
                    };
                    (to_world(l), l)
                }
                Strategy::Env => {
                    let Some((l, _)) = env.dist.as_ref().and_then(|d| d.sample(u1, u2)) else {
                        continue;
                    };
                    (l, to_local(l))
                }
            };
            if l_local.z <= 0.0 {
                continue;
            }
            let radiance = env.radiance(l_world);
            let f = crate::brdf::radiance(&s.model, n, l_world, v, s.x, s.y, radiance);
            if f == Vec3::ZERO {
                continue;
            }
            let denom = pdf_sum(l_world, l_local) * per as f32;
            if denom > 0.0 && denom.is_finite() {
                sum += (f / denom).as_dvec3();
            }
        }
    }
    sum.as_vec3()
}

mod area;
mod transmission;

#[cfg(test)]
mod occluded_tests;

#[cfg(test)]
mod area_tests;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_incidence_matches_the_falloffs() {
        // A white point light 2 above the origin, no range, no size.
        let mut l = Light {
            position: Vec3::new(0.0, 2.0, 0.0),
            intensity: 8.0,
            falloff: crate::scene::Falloff::InverseSquare,
            ..crate::scene::edit::default_light(LightKind::Point, None)
        };
        let (dir, e) = light_incidence(&l, Vec3::ZERO);
        assert_eq!(dir, Vec3::Y);
        assert_eq!(e, Vec3::splat(2.0));
        l.kind = LightKind::Spot;
        l.umbra_deg = 30.0;
        // 45° off the axis: outside the cone.
        let (_, e) = light_incidence(&l, Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(e, Vec3::ZERO);
        l.inner_deg = Some(10.0);
        let (_, e) = light_incidence(&l, Vec3::new(0.0, 0.0, 0.0));
        assert_eq!(e, Vec3::splat(2.0));
        // A range: the window W(2) = (1 − (2/3)⁴)² at 2 m, nothing from 3 m on.
        l.range = Some(3.0);
        let (_, e) = light_incidence(&l, Vec3::ZERO);
        let w = (1.0f32 - (2.0f32 / 3.0).powi(4)).powi(2);
        assert!((e - Vec3::splat(2.0 * w)).abs().max_element() < 1e-6, "{e}");
        let (_, e) = light_incidence(&l, Vec3::new(0.0, -1.5, 0.0));
        assert_eq!(e, Vec3::ZERO);
    }
}
