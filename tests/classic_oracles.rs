//! Analytic oracles for the classic model (MODELS.md §1–2): a plane seen from above under directional,
//! point and spot lights. Every pixel of the linear radiance is compared with the formula evaluated
//! on the CPU at the point where the pixel-centre ray meets the plane: 1e-4 relative (1e-6 absolute
//! where the expected value is near zero).

mod common;

use common::*;
use glam::Vec3;

const W: u32 = 64;
const H: u32 = 48;
const CAM: Vec3 = Vec3::new(0.3, 3.0, 0.4);
const FOV: f32 = 70.0;

fn scene_json(lights: &str, material: &str, extra: &str) -> String {
    format!(
        r#"{{
        "camera": {{"position": [{}, {}, {}], "target": [0.3, 0, 0.4], "up": [0, 0, -1], "fov_y_deg": {FOV}, "near": 0.1, "far": 20}},
        "output": {{"width": {W}, "height": {H}, "background": [0, 0, 0]}},
        "ambient": [0.2, 0.3, 0.4],
        "lights": [{lights}],
        "materials": {{"m": {material}}},
        "objects": [{{"mesh": {{"type": "plane", "size": [40, 40]}}, "material": "m"}}]
        {extra}
    }}"#,
        CAM.x, CAM.y, CAM.z
    )
}

/// World position on the plane y = 0 seen through the centre of pixel (i, j); (0,0) is top-left.
fn hit(i: u32, j: u32) -> Vec3 {
    let f = (Vec3::new(0.3, 0.0, 0.4) - CAM).normalize();
    let r = f.cross(Vec3::new(0.0, 0.0, -1.0)).normalize();
    let u = r.cross(f);
    let t = (FOV.to_radians() / 2.0).tan();
    let aspect = W as f32 / H as f32;
    let x = (2.0 * (i as f32 + 0.5) / W as f32 - 1.0) * t * aspect;
    let y = (1.0 - 2.0 * (j as f32 + 0.5) / H as f32) * t;
    let d = f + x * r + y * u;
    CAM + d * (-CAM.y / d.y)
}

fn view_depth(p: Vec3) -> f32 {
    (p - CAM).dot((Vec3::new(0.3, 0.0, 0.4) - CAM).normalize())
}

/// Compares every pixel with `expected(position)`; pixels for which `skip` is true are left out
/// (hard spot-cone edges, where a pixel centre may fall on either side).
fn check(name: &str, json: &str, expected: impl Fn(Vec3) -> Vec3, skip: impl Fn(Vec3) -> bool) {
    let scene = parse(json);
    let img = render(&scene);
    let mut worst = (0.0f32, 0u32, 0u32, Vec3::ZERO, Vec3::ZERO);
    let mut checked = 0;
    for j in 0..H {
        for i in 0..W {
            let p = hit(i, j);
            if skip(p) {
                continue;
            }
            checked += 1;
            let e = expected(p);
            let px = img.pixels[(j * W + i) as usize];
            let got = Vec3::new(px[0], px[1], px[2]);
            for c in 0..3 {
                let err = if e[c].abs() < 1e-3 {
                    (got[c] - e[c]).abs() / 1e-2
                } else {
                    (got[c] - e[c]).abs() / e[c].abs()
                };
                if err > worst.0 || err.is_nan() {
                    worst = (err, i, j, e, got);
                }
            }
        }
    }
    assert!(
        checked > (W * H / 2) as usize,
        "{name}: too few pixels checked"
    );
    assert!(
        worst.0 <= 1e-4,
        "{name}: worst relative error {} at pixel ({}, {}): expected {:?}, got {:?}",
        worst.0,
        worst.1,
        worst.2,
        worst.3,
        worst.4
    );
}

const AMBIENT: Vec3 = Vec3::new(0.2, 0.3, 0.4);
const N: Vec3 = Vec3::Y;

struct Classic {
    ka: f32,
    kd: f32,
    ks: f32,
    n: f32,
    od: Vec3,
    os: Vec3,
    blinn: bool,
}

impl Classic {
    fn json(&self) -> String {
        format!(
            r#"{{"model": "{}", "ka": {}, "kd": {}, "ks": {}, "shininess": {}, "diffuse_color": [{}, {}, {}], "specular_color": [{}, {}, {}]}}"#,
            if self.blinn { "blinn_phong" } else { "phong" },
            self.ka,
            self.kd,
            self.ks,
            self.n,
            self.od.x,
            self.od.y,
            self.od.z,
            self.os.x,
            self.os.y,
            self.os.z
        )
    }
    fn ambient(&self) -> Vec3 {
        AMBIENT * self.ka * self.od
    }
    /// I_L (k_d O_d (n·l) + k_s O_s s^n), s = r·v (Phong) or n·h (Blinn-Phong); 0 where n·l <= 0.
    fn light(&self, p: Vec3, l: Vec3, e: Vec3) -> Vec3 {
        let nl = N.dot(l);
        if nl <= 0.0 {
            return Vec3::ZERO;
        }
        let v = (CAM - p).normalize();
        let s = if self.blinn {
            N.dot((l + v).normalize()).max(0.0)
        } else {
            (2.0 * nl * N - l).dot(v).max(0.0)
        };
        e * (self.kd * self.od * nl + self.ks * self.os * s.powf(self.n))
    }
}

const PHONG: Classic = Classic {
    ka: 0.4,
    kd: 0.7,
    ks: 0.6,
    n: 20.0,
    od: Vec3::new(0.9, 0.4, 0.2),
    os: Vec3::new(1.0, 0.9, 0.8),
    blinn: false,
};

#[test]
fn lambert_point_inverse_square() {
    let lp = Vec3::new(0.5, 1.5, 0.2);
    let json = scene_json(
        r#"{"type": "point", "position": [0.5, 1.5, 0.2], "color": [1, 0.8, 0.6], "intensity": 3, "falloff": "inverse_square"}"#,
        r#"{"model": "lambert", "albedo": [0.7, 0.6, 0.5]}"#,
        "",
    );
    let albedo = Vec3::new(0.7, 0.6, 0.5);
    check(
        "lambert/point/inverse_square",
        &json,
        |p| {
            let d = lp - p;
            let l = d.normalize();
            let e = Vec3::new(1.0, 0.8, 0.6) * 3.0 / d.length_squared();
            albedo * AMBIENT + albedo / std::f32::consts::PI * e * N.dot(l).max(0.0)
        },
        |_| false,
    );
}

#[test]
fn phong_directional() {
    let dir = Vec3::new(0.4, -1.0, 0.3).normalize();
    let json = scene_json(
        &format!(
            r#"{{"type": "directional", "direction": [{}, {}, {}], "color": [1, 1, 1], "intensity": 0.8}}"#,
            dir.x, dir.y, dir.z
        ),
        &PHONG.json(),
        "",
    );
    check(
        "phong/directional",
        &json,
        |p| PHONG.ambient() + PHONG.light(p, -dir, Vec3::splat(0.8)),
        |_| false,
    );
}

#[test]
fn blinn_phong_point_no_falloff() {
    let m = Classic {
        blinn: true,
        n: 40.0,
        ..PHONG
    };
    let lp = Vec3::new(-0.2, 1.0, 0.6);
    let json = scene_json(
        r#"{"type": "point", "position": [-0.2, 1.0, 0.6], "color": [0.9, 0.9, 1.0], "intensity": 0.8, "falloff": "none"}"#,
        &m.json(),
        "",
    );
    check(
        "blinn_phong/point/none",
        &json,
        |p| m.ambient() + m.light(p, (lp - p).normalize(), Vec3::new(0.9, 0.9, 1.0) * 0.8),
        |_| false,
    );
}

#[test]
fn phong_point_f_at() {
    let lp = Vec3::new(0.8, 1.2, -0.3);
    let (c1, c2, c3) = (0.5f32, 0.3f32, 0.2f32);
    let json = scene_json(
        r#"{"type": "point", "position": [0.8, 1.2, -0.3], "color": [1, 1, 1], "intensity": 1.5, "falloff": {"c1": 0.5, "c2": 0.3, "c3": 0.2}}"#,
        &PHONG.json(),
        "",
    );
    check(
        "phong/point/f_at",
        &json,
        |p| {
            let d = (lp - p).length();
            let fat = (1.0 / (c1 + c2 * d + c3 * d * d)).min(1.0);
            PHONG.ambient() + PHONG.light(p, (lp - p).normalize(), Vec3::splat(1.5 * fat))
        },
        |_| false,
    );
}

/// KHR_lights_punctual's range window, W(d) = clamp(1 − (d/range)⁴, 0, 1)², written out here
/// from the formula (not the library's function) for the oracle.
fn window(d: f32, range: f32) -> f32 {
    let x = d / range;
    (1.0 - x.powi(4)).clamp(0.0, 1.0).powi(2)
}

/// A point light with `range` (issue 18): inverse square times the window within the range,
/// nothing beyond it. The range, 1.9 m, cuts through the visible plane: pixels on both sides.
#[test]
fn phong_point_inverse_square_with_range() {
    let lp = Vec3::new(-0.2, 1.0, 0.6);
    let range = 1.9f32;
    let json = scene_json(
        r#"{"type": "point", "position": [-0.2, 1.0, 0.6], "color": [1, 0.9, 0.8], "intensity": 2.5, "range": 1.9}"#,
        &PHONG.json(),
        "",
    );
    let (mut inside, mut beyond) = (0, 0);
    for j in 0..H {
        for i in 0..W {
            match (lp - hit(i, j)).length() < range {
                true => inside += 1,
                false => beyond += 1,
            }
        }
    }
    assert!(
        inside > 500 && beyond > 500,
        "{inside} pixels within range, {beyond} beyond"
    );
    check(
        "phong/point/inverse_square/range",
        &json,
        |p| {
            let d = (lp - p).length();
            let e = Vec3::new(1.0, 0.9, 0.8) * 2.5 / (d * d) * window(d, range);
            PHONG.ambient() + PHONG.light(p, (lp - p).normalize(), e)
        },
        |_| false,
    );
}

/// A spot light with a range and the classic f_at: the window multiplies the falloff and the cone.
#[test]
fn spot_with_range_and_f_at() {
    let lp = Vec3::new(0.5, 1.4, 0.2);
    let axis = Vec3::new(-0.2, -1.0, 0.1).normalize();
    let range = 2.2f32;
    let json = scene_json(
        &format!(
            r#"{{"type": "spot", "position": [0.5, 1.4, 0.2], "direction": [{}, {}, {}], "intensity": 3, "falloff": {{"c1": 1, "c2": 0.2, "c3": 0.1}}, "umbra_deg": 60, "inner_deg": 40, "range": 2.2}}"#,
            axis.x, axis.y, axis.z
        ),
        &PHONG.json(),
        "",
    );
    check(
        "phong/spot/f_at/range",
        &json,
        |p| {
            let d = (lp - p).length();
            let fat = (1.0 / (1.0 + 0.2 * d + 0.1 * d * d)).min(1.0);
            let k = spot_factor(p, lp, axis, 60.0, Some(40.0), 0.0) * fat * window(d, range);
            PHONG.ambient() + PHONG.light(p, (lp - p).normalize(), Vec3::splat(3.0 * k))
        },
        |_| false,
    );
}

fn spot_factor(p: Vec3, lp: Vec3, axis: Vec3, umbra: f32, inner: Option<f32>, exp: f32) -> f32 {
    let l = (lp - p).normalize();
    let cos_s = axis.dot(-l);
    let cos_u = umbra.to_radians().cos();
    let cone = match inner {
        None => {
            if cos_s >= cos_u {
                1.0
            } else {
                0.0
            }
        }
        Some(inner) => {
            let cos_i = inner.to_radians().cos();
            let t = ((cos_s - cos_u) / (cos_i - cos_u)).clamp(0.0, 1.0);
            t * t * (3.0 - 2.0 * t)
        }
    };
    cone * if exp > 0.0 {
        cos_s.max(0.0).powf(exp)
    } else {
        1.0
    }
}

#[test]
fn spot_cone_hard_edge_with_exponent() {
    let lp = Vec3::new(0.3, 2.0, 0.4);
    let axis = Vec3::new(0.2, -1.0, 0.1).normalize();
    let json = scene_json(
        &format!(
            r#"{{"type": "spot", "position": [0.3, 2.0, 0.4], "direction": [{}, {}, {}], "color": [1, 1, 1], "intensity": 4, "umbra_deg": 30, "exponent": 3}}"#,
            axis.x, axis.y, axis.z
        ),
        r#"{"model": "lambert", "albedo": [0.8, 0.8, 0.8]}"#,
        "",
    );
    let albedo = Vec3::splat(0.8);
    check(
        "lambert/spot/hard",
        &json,
        |p| {
            let d = lp - p;
            let l = d.normalize();
            let e = 4.0 / d.length_squared() * spot_factor(p, lp, axis, 30.0, None, 3.0);
            albedo * AMBIENT + albedo / std::f32::consts::PI * e * N.dot(l).max(0.0)
        },
        // Within 0.2° of the cone edge a pixel centre may fall on either side.
        |p| {
            let cos_s = axis.dot(-(lp - p).normalize());
            (cos_s.clamp(-1.0, 1.0).acos().to_degrees() - 30.0).abs() < 0.2
        },
    );
}

#[test]
fn spot_smooth_penumbra_classic() {
    let lp = Vec3::new(0.0, 2.5, 0.0);
    let axis = Vec3::new(0.1, -1.0, 0.2).normalize();
    let json = scene_json(
        &format!(
            r#"{{"type": "spot", "position": [0.0, 2.5, 0.0], "direction": [{}, {}, {}], "color": [1, 1, 1], "intensity": 1, "umbra_deg": 35, "inner_deg": 20, "falloff": "none"}}"#,
            axis.x, axis.y, axis.z
        ),
        &PHONG.json(),
        "",
    );
    check(
        "phong/spot/smooth",
        &json,
        |p| {
            let l = (lp - p).normalize();
            PHONG.ambient()
                + PHONG.light(
                    p,
                    l,
                    Vec3::splat(spot_factor(p, lp, axis, 35.0, Some(20.0), 0.0)),
                )
        },
        |_| false,
    );
}

#[test]
fn depth_cueing() {
    let dir = Vec3::new(0.0, -1.0, -0.5).normalize();
    let (za, zb, sa, sb) = (3.0f32, 5.0f32, 0.1f32, 0.8f32);
    let fog_color = Vec3::new(0.5, 0.6, 0.7);
    let json = scene_json(
        &format!(
            r#"{{"type": "directional", "direction": [{}, {}, {}], "color": [1, 1, 1], "intensity": 1}}"#,
            dir.x, dir.y, dir.z
        ),
        r#"{"model": "lambert", "albedo": [0.9, 0.2, 0.1]}"#,
        r#", "fog": {"z_a": 3.0, "z_b": 5.0, "s_a": 0.1, "s_b": 0.8, "color": [0.5, 0.6, 0.7]}"#,
    );
    let albedo = Vec3::new(0.9, 0.2, 0.1);
    check(
        "lambert/directional/fog",
        &json,
        |p| {
            let i = albedo * AMBIENT + albedo / std::f32::consts::PI * N.dot(-dir).max(0.0);
            let z = view_depth(p);
            let s = if z < za {
                sa
            } else if z > zb {
                sb
            } else {
                sa + (z - za) * (sb - sa) / (zb - za)
            };
            (1.0 - s) * i + s * fog_color
        },
        |_| false,
    );
}

#[test]
fn blinn_phong_directional() {
    let m = Classic {
        blinn: true,
        n: 60.0,
        ..PHONG
    };
    let dir = Vec3::new(-0.3, -1.0, 0.5).normalize();
    let json = scene_json(
        &format!(
            r#"{{"type": "directional", "direction": [{}, {}, {}], "color": [1, 0.9, 0.7], "intensity": 1.2}}"#,
            dir.x, dir.y, dir.z
        ),
        &m.json(),
        "",
    );
    check(
        "blinn_phong/directional",
        &json,
        |p| m.ambient() + m.light(p, -dir, Vec3::new(1.0, 0.9, 0.7) * 1.2),
        |_| false,
    );
}

#[test]
fn phong_point_inverse_square() {
    let lp = Vec3::new(-0.5, 1.1, 0.9);
    let json = scene_json(
        r#"{"type": "point", "position": [-0.5, 1.1, 0.9], "color": [1, 1, 1], "intensity": 2.5, "falloff": "inverse_square"}"#,
        &PHONG.json(),
        "",
    );
    check(
        "phong/point/inverse_square",
        &json,
        |p| {
            let d = lp - p;
            PHONG.ambient() + PHONG.light(p, d.normalize(), Vec3::splat(2.5 / d.length_squared()))
        },
        |_| false,
    );
}
