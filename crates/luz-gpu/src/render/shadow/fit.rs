//! Where each shadow map looks: orthographic cascades fitted to slices of the view frustum and to
//! the casters' bounds (directional lights), a perspective map over a spot's cone, or six
//! perspective cube faces (point lights, wide spots). Plain math on the CPU, tested here.
//!
//! Depth is reversed in every map (1 at the eye, 0 where nothing is drawn): perspective maps use
//! an infinite far plane (z = near / distance), orthographic ones z = 1 − distance / range.

use glam::{Mat4, Vec3, Vec4};

use crate::scene::shadow::WIDE_SPOT_DEG;
use crate::scene::{Camera, Light, LightKind, Shadow, ShadowMethod};

pub use crate::render::frustum::Sphere;

/// One map layer: its projection and what the shader needs to offset and compare.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layer {
    pub view_proj: Mat4,
    /// Texel size in metres: absolute (orthographic) or per metre of distance (perspective).
    pub texel: f32,
    pub perspective: bool,
    /// Perspective: the near plane's distance; orthographic: the depth range.
    pub depth: f32,
    pub origin: Vec3,
    pub axis: Vec3,
}

/// A light's layers and, for a directional light, each cascade's far view depth.
#[derive(Debug, Clone, PartialEq)]
pub struct LightFit {
    pub layers: Vec<Layer>,
    pub splits: [f32; 4],
}

/// What the fit sees of the frame.
pub struct View<'a> {
    pub camera: &'a Camera,
    pub aspect: f32,
    /// Objects drawn into the maps.
    pub casters: &'a [Sphere],
    /// Objects darkened by the maps (bound how far the cascades reach).
    pub receivers: &'a [Sphere],
}

/// Texels a filter reaches beyond the point looked up: maps are made this much wider so that
/// taps near an edge stay inside.
pub fn margin_texels(s: &Shadow) -> f32 {
    match s.method {
        ShadowMethod::Hard => 1.0,
        ShadowMethod::Pcf => s.pcf_kernel as f32 * 0.5 + 1.0,
        ShadowMethod::Pcss => pcss_max_radius(s) + 1.0,
    }
}

/// PCSS's largest filter radius in texels.
pub fn pcss_max_radius(s: &Shadow) -> f32 {
    4.0 * s.pcf_kernel as f32
}

pub fn fit(light: &Light, s: &Shadow, view: &View<'_>) -> LightFit {
    let res = s.resolution as f32;
    // Widening that keeps `margin` texels around the covered area.
    let widen = res / (res - 2.0 * margin_texels(s)).max(res * 0.5);
    match light.kind {
        LightKind::Directional => directional(light.direction, s, view, widen),
        LightKind::Spot if light.umbra_deg <= WIDE_SPOT_DEG => {
            let extent = scene_extent(light.position, view);
            let tan_half = light.umbra_deg.to_radians().tan() * widen;
            let axis = light.direction.normalize_or(Vec3::NEG_Z);
            LightFit {
                layers: vec![perspective(light.position, axis, tan_half, extent, res)],
                splits: [0.0; 4],
            }
        }
        _ => {
            let extent = scene_extent(light.position, view);
            LightFit {
                layers: CUBE_AXES
                    .iter()
                    .map(|&axis| perspective(light.position, axis, widen, extent, res))
                    .collect(),
                splits: [0.0; 4],
            }
        }
    }
}

/// The six faces' axes, in the order the shader picks them (+x, −x, +y, −y, +z, −z).
pub const CUBE_AXES: [Vec3; 6] = [
    Vec3::X,
    Vec3::NEG_X,
    Vec3::Y,
    Vec3::NEG_Y,
    Vec3::Z,
    Vec3::NEG_Z,
];

fn up_for(axis: Vec3) -> Vec3 {
    if axis.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::Z
    }
}

/// The farthest any caster or receiver reaches from `p` (at least a millimetre's millionth).
fn scene_extent(p: Vec3, view: &View<'_>) -> f32 {
    view.casters
        .iter()
        .chain(view.receivers)
        .map(|s| (s.center - p).length() + s.radius)
        .filter(|d| d.is_finite())
        .fold(1e-9f32, f32::max)
}

/// A perspective map from `eye` along `axis` with half-angle tangent `tan_half`, reversed depth
/// with an infinite far plane; the near plane a 10⁻⁵ of the scene's extent from the eye.
fn perspective(eye: Vec3, axis: Vec3, tan_half: f32, extent: f32, res: f32) -> Layer {
    let near = (extent * 1e-5).max(1e-12);
    let view = Mat4::look_to_rh(eye, axis, up_for(axis));
    let f = 1.0 / tan_half;
    let proj = Mat4::from_cols(
        Vec4::new(f, 0.0, 0.0, 0.0),
        Vec4::new(0.0, f, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 0.0, -1.0),
        Vec4::new(0.0, 0.0, near, 0.0),
    );
    Layer {
        view_proj: proj * view,
        texel: 2.0 * tan_half / res,
        perspective: true,
        depth: near,
        origin: eye,
        axis,
    }
}

/// How far the cascades reach: `max_distance`, else the farthest receiver, within the camera's
/// planes.
fn shadow_distance(s: &Shadow, view: &View<'_>) -> f32 {
    let cam = view.camera;
    let fwd = cam.forward();
    let far = s.max_distance.unwrap_or_else(|| {
        view.receivers
            .iter()
            .map(|r| (r.center - cam.position).dot(fwd) + r.radius)
            .filter(|d| d.is_finite())
            .fold(cam.near, f32::max)
    });
    far.clamp(cam.near * 1.001, cam.far)
}

fn directional(direction: Vec3, s: &Shadow, view: &View<'_>, widen: f32) -> LightFit {
    let cam = view.camera;
    let axis = direction.normalize_or(Vec3::NEG_Y);
    let up = up_for(axis);
    let far = shadow_distance(s, view);
    let cuts = s.split.splits(cam.near, far, s.cascades);
    let mut splits = [0.0; 4];
    splits[..cuts.len()].copy_from_slice(&cuts);
    // The camera's frame (right, up, forward) in world space.
    let inv = cam.view().inverse();
    let (right, cam_up, fwd) = (
        inv.x_axis.truncate(),
        inv.y_axis.truncate(),
        -inv.z_axis.truncate(),
    );
    let light_view = Mat4::look_to_rh(Vec3::ZERO, axis, up);
    let res = s.resolution as f32;
    let mut z0 = cam.near;
    let layers = cuts
        .iter()
        .map(|&z1| {
            let mut corners = [Vec3::ZERO; 8];
            for (i, c) in corners.iter_mut().enumerate() {
                let z = if i < 4 { z0 } else { z1 };
                let sx = if i & 1 == 0 { -1.0 } else { 1.0 };
                let sy = if i & 2 == 0 { -1.0 } else { 1.0 };
                // The slice of the view volume: a frustum's, or an orthographic camera's box.
                let (hx, hy) = cam.half_extent(z, view.aspect);
                *c = cam.position + fwd * z + right * (sx * hx) + cam_up * (sy * hy);
            }
            z0 = z1;
            let center = corners.iter().copied().sum::<Vec3>() / 8.0;
            let radius = corners
                .iter()
                .map(|c| (*c - center).length())
                .fold(0.0, f32::max)
                * widen;
            // Snap the centre to whole texels in the light's frame, so the map does not swim
            // when the camera moves.
            let texel = 2.0 * radius / res;
            let lc = light_view.transform_point3(center);
            let snapped = Vec3::new(
                (lc.x / texel).round() * texel,
                (lc.y / texel).round() * texel,
                lc.z,
            );
            let center = light_view.inverse().transform_point3(snapped);
            // Depth: from the nearest caster in the cascade's column to the far side of the
            // slice's sphere.
            let c_d = center.dot(axis);
            let mut d_min = c_d - radius;
            for cs in view.casters {
                let lp = light_view.transform_point3(cs.center);
                let lateral = ((lp.x - snapped.x).powi(2) + (lp.y - snapped.y).powi(2)).sqrt();
                if lateral <= radius * std::f32::consts::SQRT_2 + cs.radius && lp.is_finite() {
                    d_min = d_min.min(cs.center.dot(axis) - cs.radius);
                }
            }
            let d_max = c_d + radius;
            let pad = (d_max - d_min) * 0.01 + texel;
            let (d_min, d_max) = (d_min - pad, d_max + pad);
            let range = d_max - d_min;
            let eye = center + axis * (d_min - c_d);
            let v = Mat4::look_to_rh(eye, axis, up);
            let proj = Mat4::from_cols(
                Vec4::new(1.0 / radius, 0.0, 0.0, 0.0),
                Vec4::new(0.0, 1.0 / radius, 0.0, 0.0),
                Vec4::new(0.0, 0.0, 1.0 / range, 0.0),
                Vec4::new(0.0, 0.0, 1.0, 1.0),
            );
            Layer {
                view_proj: proj * v,
                texel,
                perspective: false,
                depth: range,
                origin: eye,
                axis,
            }
        })
        .collect();
    LightFit { layers, splits }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::scene::Falloff;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(0.0, 3.0, 8.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 50.0,
            near: 0.1,
            far: 100.0,
            projection: crate::scene::Projection::Perspective,
        }
    }

    /// A light of `kind` with a default shadow (also the cull tests').
    pub(in crate::render::shadow) fn light(
        kind: LightKind,
        position: Vec3,
        direction: Vec3,
        umbra: f32,
    ) -> Light {
        Light {
            kind,
            direction,
            position,
            color: Vec3::ONE,
            intensity: 1.0,
            falloff: Falloff::InverseSquare,
            umbra_deg: umbra,
            inner_deg: None,
            exponent: 0.0,
            range: None,
            shadow: Some(Shadow::default_for(kind)),
            radius: 0.0,
            angular_radius_deg: 0.0,
        }
    }

    fn ndc(l: &Layer, p: Vec3) -> Vec3 {
        let c = l.view_proj * p.extend(1.0);
        c.truncate() / c.w
    }

    /// Every receiver point in view lands inside its cascade's map, with reversed depth that
    /// falls with distance from the light; casters above lie nearer the light.
    /// A view of `camera` whose only receiver is a ball of radius 10 at the origin.
    fn around_origin(camera: &Camera) -> View<'_> {
        const BALL: [Sphere; 1] = [Sphere {
            center: Vec3::ZERO,
            radius: 10.0,
        }];
        View {
            camera,
            aspect: 1.0,
            casters: &[],
            receivers: &BALL,
        }
    }

    #[test]
    fn cascades_cover_the_view_and_the_casters() {
        let cam = camera();
        let floor = Sphere {
            center: Vec3::ZERO,
            radius: 10.0,
        };
        let caster = Sphere {
            center: Vec3::new(0.0, 20.0, 0.0),
            radius: 1.0,
        };
        let l = light(
            LightKind::Directional,
            Vec3::ZERO,
            Vec3::new(0.3, -1.0, 0.2).normalize(),
            180.0,
        );
        let s = Shadow::default_for(LightKind::Directional);
        let v = View {
            camera: &cam,
            aspect: 16.0 / 9.0,
            casters: &[floor, caster],
            receivers: &[floor],
        };
        let f = fit(&l, &s, &v);
        assert_eq!(f.layers.len(), 3);
        assert!(f.splits[0] < f.splits[1] && f.splits[1] < f.splits[2]);
        // The far split reaches the floor's far side, within the camera's far plane.
        assert!(f.splits[2] > 8.0 && f.splits[2] <= 100.0, "{:?}", f.splits);
        for (i, layer) in f.layers.iter().enumerate() {
            assert!(!layer.perspective);
            // A point on the view axis in the middle of the cascade's slice.
            let z0 = if i == 0 { cam.near } else { f.splits[i - 1] };
            let z = 0.5 * (z0 + f.splits[i]);
            let p = cam.position + cam.forward() * z;
            let n = ndc(layer, p);
            assert!(n.x.abs() < 1.0 && n.y.abs() < 1.0, "cascade {i}: {n}");
            assert!((0.0..=1.0).contains(&n.z), "cascade {i}: {n}");
            // The caster over the floor's centre is nearer the light (larger reversed depth).
            let above = p - l.direction * 5.0;
            assert!(ndc(layer, above).z > n.z, "cascade {i}");
            // A caster over the cascade's area lies within its depth range (not clipped).
            let c = ndc(layer, caster.center);
            if c.x.abs() <= 1.0 && c.y.abs() <= 1.0 {
                assert!(c.z <= 1.0, "cascade {i}: caster clipped: {c}");
            }
        }
    }

    /// A point light's six faces: each covers its axis's direction, with depth near/distance.
    #[test]
    fn cube_faces_cover_their_axes() {
        let cam = camera();
        let l = light(
            LightKind::Point,
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::NEG_Y,
            180.0,
        );
        let s = Shadow::default_for(LightKind::Point);
        let v = around_origin(&cam);
        let f = fit(&l, &s, &v);
        assert_eq!(f.layers.len(), 6);
        for (layer, axis) in f.layers.iter().zip(CUBE_AXES) {
            // A point 2 m along the axis, a little off it.
            let p = l.position + axis * 2.0 + up_for(axis) * 1.9;
            let n = ndc(layer, p);
            assert!(n.x.abs() <= 1.0 && n.y.abs() <= 1.0, "{axis}: {n}");
            assert!((n.z - layer.depth / 2.0).abs() < 1e-6, "{axis}: {n}");
            assert!(layer.perspective);
        }
    }

    /// A spot's map spans its cone.
    #[test]
    fn spot_map_spans_the_cone() {
        let cam = camera();
        let dir = Vec3::new(0.0, -1.0, -0.5).normalize();
        let l = light(LightKind::Spot, Vec3::new(0.0, 5.0, 0.0), dir, 40.0);
        let s = Shadow::default_for(LightKind::Spot);
        let v = around_origin(&cam);
        let f = fit(&l, &s, &v);
        assert_eq!(f.layers.len(), 1);
        // A direction at 39° from the axis lands inside the map; its edge is past 40°.
        let side = dir.cross(Vec3::X).normalize();
        let at = |deg: f32| {
            let a = deg.to_radians();
            l.position + (dir * a.cos() + side * a.sin()) * 3.0
        };
        let inside = ndc(&f.layers[0], at(39.0));
        assert!(inside.x.abs().max(inside.y.abs()) < 1.0, "{inside}");
        let outside = ndc(&f.layers[0], at(50.0));
        assert!(outside.x.abs().max(outside.y.abs()) > 1.0, "{outside}");
    }
}
