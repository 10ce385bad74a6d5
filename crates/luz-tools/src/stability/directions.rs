//! The direction cases of the sweep: the cosine × azimuth grid and the degenerate vectors.

use glam::Vec3;

use super::{AZIMUTHS_DEG, COSINES};

/// A direction case of the sweep (local frame: the undisturbed normal is +z, tangent +x).
#[derive(Debug, Clone, PartialEq)]
pub struct Dir {
    /// What is special about it, e.g. `n·l=1e-4 n·v=0 φ=180°` or `n = 1e-7·z`.
    pub label: String,
    pub n: Vec3,
    pub l: Vec3,
    pub v: Vec3,
    pub x: Vec3,
    pub y: Vec3,
}

/// The unit direction at `n·d = cos_theta` and azimuth `phi_deg` (0, 90 or 180 exactly; other
/// angles through sin/cos).
pub fn direction(cos_theta: f32, phi_deg: f32) -> Vec3 {
    let c = cos_theta as f64;
    let s = (1.0 - c * c).max(0.0).sqrt();
    let (cp, sp) = match phi_deg {
        0.0 => (1.0, 0.0),
        90.0 => (0.0, 1.0),
        180.0 => (-1.0, 0.0),
        270.0 => (0.0, -1.0),
        p => {
            let r = (p as f64).to_radians();
            (r.cos(), r.sin())
        }
    };
    Vec3::new((s * cp) as f32, (s * sp) as f32, c as f32)
}

/// Every direction case: the grid `COSINES² × AZIMUTHS_DEG`, then l = −v, near-antipodal grazing
/// pairs, below-horizon directions, degenerate normals, light and view vectors, and degenerate
/// tangents.
pub fn directions() -> Vec<Dir> {
    let (z, x, y) = (Vec3::Z, Vec3::X, Vec3::Y);
    let mut out = Vec::new();
    let mut push = |label: String, n: Vec3, l: Vec3, v: Vec3, tx: Vec3, ty: Vec3| {
        out.push(Dir {
            label,
            n,
            l,
            v,
            x: tx,
            y: ty,
        })
    };
    for &cl in &COSINES {
        for &cv in &COSINES {
            for &phi in &AZIMUTHS_DEG {
                push(
                    format!("n·l={cl:e} n·v={cv:e} φ={phi}°"),
                    z,
                    direction(cl, 0.0),
                    direction(cv, phi),
                    x,
                    y,
                );
            }
        }
    }
    for c in [1.0, 0.5, 1e-4, 0.0] {
        let l = direction(c, 0.0);
        push(format!("l = −v, n·l={c:e}"), z, l, -l, x, y);
    }
    // l and v both just above the horizon and almost opposite: h almost ⊥ n.
    for (e, t) in [(1e-6, 1e-3), (1e-4, 1e-6), (1e-3, 1e-7)] {
        push(
            format!("near-antipodal grazing: l=(1,0,{e:e}) v=(−1,{t:e},{e:e})"),
            z,
            Vec3::new(1.0, 0.0, e),
            Vec3::new(-1.0, t, e),
            x,
            y,
        );
    }
    let below = Vec3::new(0.8, 0.0, -0.6);
    let above = direction(0.6, 180.0);
    push("l below the horizon".into(), z, below, above, x, y);
    push("v below the horizon".into(), z, above, below, x, y);
    push("l and v below the horizon".into(), z, below, -above, x, y);
    push(
        "l just below the horizon".into(),
        z,
        Vec3::new(1.0, 0.0, -1e-7),
        above,
        x,
        y,
    );

    // Degenerate normals, each with a generic, a mirror, a retro and a grazing pair.
    let pairs = [
        ("generic", direction(0.6, 0.0), direction(0.8, 120.0)),
        ("mirror", direction(0.5, 0.0), direction(0.5, 180.0)),
        ("l = v", direction(0.7, 0.0), direction(0.7, 0.0)),
        ("grazing", direction(1e-4, 0.0), direction(1e-3, 180.0)),
    ];
    let normals: [(&str, Vec3); 13] = [
        ("n = 0", Vec3::ZERO),
        ("n = 1e-40·z (denormal)", Vec3::new(0.0, 0.0, 1e-40)),
        ("n = 1e-7·z", z * 1e-7),
        ("n = 1e-6·z (|n|² at LEN2_EPS)", z * 1e-6),
        ("n = 1e-5·z", z * 1e-5),
        ("n = 1e-3·z", z * 1e-3),
        ("n = 0.5·z", z * 0.5),
        ("n = 3·z", z * 3.0),
        ("n = 1e19·z", z * 1e19),
        ("n = 1e20·z (|n|² overflows)", z * 1e20),
        ("n = (1e-7, 0, 1)", Vec3::new(1e-7, 0.0, 1.0)),
        (
            "n = (0.3, -0.2, 0.9)·7 (non-unit, tilted)",
            Vec3::new(2.1, -1.4, 6.3),
        ),
        ("n = (1e-30, 1e-30, 1e-30)", Vec3::splat(1e-30)),
    ];
    for (nl, n) in normals {
        for (pl, l, v) in pairs {
            push(format!("{nl}, {pl}"), n, l, v, x, y);
        }
    }
    // Degenerate light and view vectors (the normal is +z).
    let (l0, v0) = (direction(0.6, 0.0), direction(0.8, 120.0));
    for (s, label) in [
        (0.0, "0"),
        (1e-7, "1e-7·"),
        (1e-5, "1e-5·"),
        (1e3, "1e3·"),
        (1e20, "1e20·"),
    ] {
        push(format!("l = {label}unit"), z, l0 * s, v0, x, y);
        push(format!("v = {label}unit"), z, l0, v0 * s, x, y);
    }
    push("l = v = 0".into(), z, Vec3::ZERO, Vec3::ZERO, x, y);
    // Degenerate tangent frames (anisotropic Principled), with an off-plane pair.
    let (l1, v1) = (direction(0.5, 30.0), direction(0.7, 250.0));
    let tangents: [(&str, Vec3, Vec3); 8] = [
        ("x = y = 0", Vec3::ZERO, Vec3::ZERO),
        ("x = n, y = 0", z, Vec3::ZERO),
        ("x = n, y = n", z, z),
        ("x = −n, y = x", -z, x),
        ("x = 1e-7·x, y = 0", x * 1e-7, Vec3::ZERO),
        ("x = 3x + n (not ⊥, not unit)", x * 3.0 + z, y),
        (
            "x = y = (1,1,0)",
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ),
        ("x = y, y = x (swapped)", y, x),
    ];
    for (tl, tx, ty) in tangents {
        push(format!("tangent {tl}"), z, l1, v1, tx, ty);
        push(
            format!("tangent {tl}, grazing"),
            z,
            direction(1e-4, 45.0),
            direction(1e-3, 225.0),
            tx,
            ty,
        );
    }
    out
}
