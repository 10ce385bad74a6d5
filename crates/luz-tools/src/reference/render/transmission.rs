//! Glass in the reference (issue 35): what a transmissive metal-rough surface lets through,
//! added to its shaded reflection (whose diffuse the BTDF replaced: `brdf::metal_rough_terms`).
//! With a volume (`thickness` > 0) light really refracts through the object's closed surface
//! ([`glass::transmitted`]: Walter et al.'s rough dielectric, Beer–Lambert inside, up to
//! [`glass::MAX_BOUNCES`] crossings); thin-walled (`thickness` 0) it crosses each surface
//! without bending, blurred by the roughness and weighted by `1 − F`. The base colour tints
//! what enters, once. With dispersion each channel walks with its own index.

use glam::Vec3;

use super::{cmj, hash, light_incidence, unit_float, Hit, Prepared, RefObject};
use crate::brdf::{
    f_dielectric, g_smith_ggx_separable, importance_sample_ggx, ior_from_f0, ortho_basis,
    sample_cosine_hemisphere, Model, RoughDielectric, ALPHA_MIN, INV_PI,
};
use crate::reference::geometry::{Ray, Shape};
use crate::reference::glass::{self, Glass, GlassHit};

/// Walks per pixel sample at most; the surroundings each walk reaches are shaded with the
/// pixel's samples divided among the walks.
const MAX_WALKS: u32 = 256;

impl Prepared {
    /// The transmitted radiance seen along the unit ray `d` at the hit `hit` (0 for materials
    /// without transmission, and for rays that meet the surface from inside).
    pub(super) fn transmission(
        &self,
        hit: &Hit,
        d: Vec3,
        key: [u64; 3],
        samples: (u32, u32),
        layer: usize,
    ) -> Vec3 {
        let d = d.normalize_or(Vec3::NEG_Z);
        let (i, t, part, local) = hit;
        let obj = &self.objects[*i];
        let Some(mat) = self.materials.get(obj.material) else {
            return Vec3::ZERO;
        };
        let ls = obj.shape.surface(local, *t, *part);
        let (p, n, x, y, uv) = self.world_surface(obj, *part, &ls);
        let s = super::surface_at(mat, n, x, y, uv);
        let Model::MetalRough(m) = s.model else {
            return Vec3::ZERO;
        };
        let tr = m.transmission;
        if tr.factor <= 0.0 || d.dot(n) >= 0.0 {
            return Vec3::ZERO;
        }
        let tint = tr.factor * (1.0 - m.metallic) * m.base_color;
        let ior = ior_from_f0(m.dielectric_f0.x);
        let alpha = (m.roughness * m.roughness).max(ALPHA_MIN);
        let walks = samples.0.clamp(1, MAX_WALKS);
        let per = ((samples.0 / walks).max(1), samples.1);
        let iors = tr.channel_iors(ior);
        let dispersive = tr.dispersion > 0.0;
        let mut sum = Vec3::ZERO;
        for w in 0..walks {
            let mut state = hash(&[key[0], key[1], key[2], 0x91a5_5000 + u64::from(w)]);
            let mut rng = move || {
                state = super::mix64(state.wrapping_add(0x9e37_79b9_7f4a_7c15));
                unit_float(state)
            };
            let key = [key[0], key[1], hash(&[key[2], u64::from(w), layer as u64])];
            let surroundings =
                |o: Vec3, dir: Vec3| self.radiance_along(o, dir, 0.0, key, per, layer + 1);
            // With dispersion, walk w carries channel w mod 3 (×3: a third of the walks each).
            let channel = (w % 3) as usize;
            let eta = if dispersive { iors[channel] } else { ior };
            // Volumes walk spheres, cubes (slabs when scaled) and meshes; other shapes are
            // thin-walled.
            let volume = !tr.thin_walled()
                && matches!(
                    obj.shape,
                    Shape::Sphere { .. } | Shape::Cube { .. } | Shape::Mesh(_)
                );
            let l = if !volume {
                thin_walled(p, d, n, (alpha, eta), &surroundings, &mut rng)
            } else {
                let g = Glass {
                    interface: RoughDielectric { alpha, ior: eta },
                    sigma: tr.sigma(),
                };
                let hit = |o: Vec3, dir: Vec3| crossing(obj, o, dir);
                glass::transmitted((p, d, n), &g, hit, surroundings, &mut rng)
            };
            sum += if dispersive {
                Vec3::from_array(std::array::from_fn(|c| {
                    if c == channel {
                        3.0 * l[c]
                    } else {
                        0.0
                    }
                }))
            } else {
                l
            };
        }
        tint * sum / walks as f32
    }
}

impl Prepared {
    /// KHR_materials_diffuse_transmission: light arriving on the side away from the viewer
    /// through the Lambertian BTDF `(1 − transmission)(1 − metallic) · diffuseTransmission ·
    /// diffuseTransmissionColor / π` (the extension's mix; the reflected diffuse lost that share:
    /// `brdf::metal_rough_terms`). Every light on that side (with its shadow rays) and the
    /// environment over that hemisphere (cosine-sampled, unoccluded as the reflected
    /// environment is).
    pub(super) fn diffuse_transmission(
        &self,
        hit: &Hit,
        d: Vec3,
        key: [u64; 3],
        (samples, shadow_samples): (u32, u32),
    ) -> Vec3 {
        let (i, t, part, local) = hit;
        let obj = &self.objects[*i];
        let Some(mat) = self.materials.get(obj.material) else {
            return Vec3::ZERO;
        };
        let ls = obj.shape.surface(local, *t, *part);
        let (p, n, x, y, uv) = self.world_surface(obj, *part, &ls);
        let Model::MetalRough(m) = super::surface_at(mat, n, x, y, uv).model else {
            return Vec3::ZERO;
        };
        let tr = m.transmission;
        if tr.diffuse <= 0.0 {
            return Vec3::ZERO;
        }
        let w = (1.0 - tr.factor) * (1.0 - m.metallic) * tr.diffuse * tr.diffuse_color * INV_PI;
        // The side away from the viewer.
        let back = if d.dot(n) < 0.0 { -n } else { n };
        let mut sum = Vec3::ZERO;
        for (k, light) in self.lights.iter().enumerate() {
            let (l, e) = light_incidence(light, p);
            let c = l.dot(back);
            if c <= 0.0 || e == Vec3::ZERO {
                continue;
            }
            let vis = if obj.receive_shadow && light.shadow.is_some() {
                let key = [key[0], key[1], key[2] ^ ((k as u64 + 1) << 40) ^ 0xd1ff];
                self.light_visibility(light, (p, n, l), obj, key, shadow_samples)
            } else {
                1.0
            };
            sum += w * e * c * vis;
        }
        if let Some(env) = &self.env {
            let (t, b) = ortho_basis(back);
            let count = samples.max(1);
            let pattern = hash(&[key[0], key[1], key[2], 0xd1ff_e000]) as u32;
            let mut l_sum = Vec3::ZERO;
            for k in 0..count {
                let u = cmj(k, count, pattern);
                let c = sample_cosine_hemisphere(u.x, u.y);
                l_sum += env.radiance((t * c.x + b * c.y + back * c.z).normalize());
            }
            // Cosine sampling: f L cos / (cos/π) = w π L.
            sum += w * std::f32::consts::PI * l_sum / count as f32;
        }
        sum
    }
}

/// A thin-walled surface: the microfacet reflection of `d` about a GGX-sampled normal, mirrored
/// through the surface (the extension's thin-walled BTDF), weighted by `1 − F` and the sample's
/// `G (v·h)/((n·h)(n·v))`; the ray goes on from the other side.
fn thin_walled(
    p: Vec3,
    d: Vec3,
    n: Vec3,
    (alpha, ior): (f32, f32),
    surroundings: &impl Fn(Vec3, Vec3) -> Vec3,
    rng: &mut impl FnMut() -> f32,
) -> Vec3 {
    let v = -d;
    let n_v = n.dot(v);
    let (t, b) = ortho_basis(n);
    let hl = importance_sample_ggx(rng(), rng(), alpha);
    let h = t * hl.x + b * hl.y + n * hl.z;
    let v_h = v.dot(h);
    let r = h * (2.0 * v_h) - v;
    let n_r = n.dot(r);
    if v_h <= 0.0 || n_r <= 0.0 || n_v <= 0.0 {
        return Vec3::ZERO;
    }
    let through = r - n * (2.0 * n_r);
    let weight = (1.0 - f_dielectric(v_h, ior)) * g_smith_ggx_separable(n_r, n_v, alpha) * v_h
        / (hl.z * n_v);
    let scale = p.abs().max_element().max(1.0);
    weight * surroundings(p - n * (scale * 2e-5), through)
}

/// The nearest crossing of `obj`'s closed surface along the unit world ray `(o, d)`, from
/// outside or inside, with the outside normal: both roots of a sphere, every triangle of a mesh
/// (its winding makes the normal the outside one); `None` for the other shapes.
fn crossing(obj: &RefObject, o: Vec3, d: Vec3) -> Option<GlassHit> {
    let lo = obj.to_local.transform_point3(o);
    let ld = obj.to_local.transform_vector3(d);
    let scale = ld.length();
    match &obj.shape {
        Shape::Sphere { radius } => {
            let h = glass::sphere_hit(Vec3::ZERO, *radius, lo, ld / scale)?;
            Some(GlassHit {
                t: h.t / scale,
                n_out: (obj.normal_matrix * h.n_out).normalize(),
            })
        }
        Shape::Cube { half } => {
            // The slabs' entry and exit (from outside or inside): the nearest crossing beyond
            // a small epsilon, its outside normal the face's.
            let (mut near, mut far) = ((f32::NEG_INFINITY, 0), (f32::INFINITY, 0));
            for k in 0..3 {
                if ld[k].abs() < 1e-12 {
                    if lo[k].abs() > *half {
                        return None;
                    }
                    continue;
                }
                let (t1, t2) = ((-half - lo[k]) / ld[k], (half - lo[k]) / ld[k]);
                let (a, b) = (t1.min(t2), t1.max(t2));
                if a > near.0 {
                    near = (a, k);
                }
                if b < far.0 {
                    far = (b, k);
                }
            }
            let eps = 1e-5 * ld.length().recip();
            let (t, k) = if near.0 > eps { near } else { far };
            if near.0 > far.0 || t <= eps {
                return None;
            }
            let mut n = Vec3::ZERO;
            n[k] = 1f32.copysign(lo[k] + ld[k] * t);
            Some(GlassHit {
                t,
                n_out: (obj.normal_matrix * n).normalize(),
            })
        }
        Shape::Mesh(m) => {
            let ray = Ray { o: lo, d: ld };
            let (t, part) = m.intersect(&ray, 1e-5, f32::INFINITY)?;
            let ls = obj.shape.surface(&ray, t, part);
            Some(GlassHit {
                t,
                n_out: (obj.normal_matrix * ls.n).normalize(),
            })
        }
        _ => None,
    }
}
