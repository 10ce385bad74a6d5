//! Tube lights by LTC: the CPU mirror of the functions of the same names in
//! `shaders_glsl/include/area.glsl` (f32, as the shader computes them), after Heitz & Hill,
//! "Real-Time Line- and Disk-Light Shading with Linearly Transformed Cosines" (SIGGRAPH 2017
//! course).
//!
//! A tube of radius r is seen as its **facing ribbon**, the rectangle along its axis whose width
//! is perpendicular to the axis and to the direction from the shading point to it, its edges on
//! the cylinder's silhouette lines ([`ltc_ribbon`]: four corners through M⁻¹, integrated as a
//! polygon by the same edge form as rects, [`area_edge`]), plus **a flat disk of area πr² at each
//! end**, facing out along the axis and evaluated at its centre (the course's cap approximation,
//! `I_ltc_disks`). From a direction at θ to the axis a cylinder's silhouette is the ribbon
//! (2rL·sin θ projected) and half of each end's ellipse (πr²·|cos θ|/2 each, at its own distance),
//! so luz counts half of each end's disk (the course counts the whole of the end facing the point,
//! which overcounts the far half-ellipse at the near end's distance: 3.8 % over a 2 mm cylinder
//! seen 8.5° off its axis, `ltc_tube_matches_a_thin_cylinder`); seen end-on, where the far end
//! hides behind the near one, the near end's whole disk when that is larger. luz's tube is the
//! open side of a cylinder (`luz reference` samples that surface, inside and out); from outside
//! its silhouette is the closed cylinder's, so the disks stand for the ends of the silhouette, not
//! for extra emitting surfaces (spherical caps would add πr² at every angle: a capsule, not luz's
//! tube).
//!
//! Until 2026-11-29 the ribbon was the course's line form: a line with a first-order width in the
//! LTC's transformed space, which overcounts where M⁻¹ widens the ribbon to a large angle (a lobe
//! narrower than the tube: 53–87 % off at roughness 0.05 in the lab); the tests keep it to compare
//! (`ltc_tube_at_low_roughness`).
//!
//! Everything is in the shading frame (z the normal), the tube's axis given as its first end `p`
//! and its vector `dp` (given directly so that a tiny tube's ends do not cancel). The specular
//! term integrates the LTC of M⁻¹ (the table's matrix, any scale), the diffuse term the same with
//! M⁻¹ = I (the clamped cosine `max(z, 0)/π`).

use glam::{Mat3, Vec3};

/// The cosine-weighted integral of the great arc from `a` to `b` (unit vectors) as a vector,
/// (a × b) θ/(2π sin θ) with Heitz & Hill 2017's cubic rational fit of the factor, written as
/// a × (b − a) so that close vertices keep their precision (`area.glsl`'s `area_edge`).
pub fn area_edge(a: Vec3, b: Vec3) -> Vec3 {
    let x = a.dot(b);
    let y = x.abs();
    let u = 0.854_398_5 + (0.496_515_5 + 0.014_520_6 * y) * y;
    let w = 3.417_594 + (4.161_672_4 + y) * y;
    let v = u / w;
    let theta_sin = if x > 0.0 {
        v
    } else {
        0.5 / (1.0 - x * x).max(1e-7).sqrt() - v
    };
    a.cross(b - a) * theta_sin
}

/// The integral of the LTC of `minv` (D(ω) = D_o(M⁻¹ω/|M⁻¹ω|) |∂ω_o/∂ω|, D_o = max(z, 0)/π, any
/// scale of M⁻¹) over the tube's **facing ribbon**: the rectangle of width 2`r` along the segment
/// from `p` to `p + dp`, its width along p × dp (perpendicular to the axis and to the direction
/// from the origin to the axis: it faces the origin, the tube's silhouette). Its four corners go
/// through M⁻¹ and the polygon's form factor is the sum of [`area_edge`] over its edges, as for
/// rects: exact in the ribbon's width however wide the transformed ribbon is (a narrow lobe, low
/// roughness). The part of the axis below the transformed horizon is cut off first (the ribbon
/// over the rest; its corners then reach at most its half-width below it), and the form factor is
/// the vector's z (not the polygons' `ltc_clipped`, whose equivalent sphere straddles the
/// horizon for a thin ribbon near it).
pub fn ltc_ribbon(p: Vec3, dp: Vec3, r: f32, minv: Mat3) -> f32 {
    let n = p.cross(dp);
    let n_len = n.length();
    if n_len <= 0.0 {
        // The origin is on the axis's line: the ribbon is edge-on.
        return 0.0;
    }
    let q = minv * p;
    let dq = minv * dp;
    let (z0, z1) = (q.z, q.z + dq.z);
    if z0 <= 0.0 && z1 <= 0.0 {
        return 0.0;
    }
    // The axis's part above the transformed horizon, as s in [s0, s1] along q + s dq.
    let s_h = z0 / (z0 - z1);
    let s0 = if z0 < 0.0 { s_h } else { 0.0 };
    let s1 = if z1 < 0.0 { s_h } else { 1.0 };
    let a = q + s0 * dq;
    let e = q + s1 * dq;
    // The half-width that puts the ribbon's edges on the cylinder's silhouette lines seen from
    // the origin (its tangent planes, asin(r/d) from the plane through the axis): r d/√(d² − r²),
    // d the axis's distance; past an end at most 2r/√3 (d ≤ 2r: near the axis's extension, where
    // the side is seen past an end and the caps dominate).
    // Beside the tube (the origin's foot on the axis within it) exact down to d = r; past an end
    // at most 2r/√3.
    let dp2 = dp.dot(dp);
    let d2 = n_len * n_len / dp2;
    let foot = -p.dot(dp);
    let lo = if foot >= 0.0 && foot <= dp2 {
        1e-4
    } else {
        0.75
    };
    let h = r / (1.0 - r * r / d2).max(lo).sqrt();
    let w = minv * (n * (h / n_len));
    let c = [
        (a + w).normalize(),
        (e + w).normalize(),
        (e - w).normalize(),
        (a - w).normalize(),
    ];
    let mut f = Vec3::ZERO;
    for k in 0..4 {
        f += area_edge(c[k], c[(k + 1) & 3]);
    }
    // Either winding: the vector points into the polygon's cone. Its z is the polygon's form
    // factor (Lambert's formula): exact above the horizon, and below it the corners reach at most
    // the half-width (their negative part is O(h²) of the cosine). Not `ltc_clipped`: the
    // equivalent sphere of a long thin ribbon near the horizon straddles it though the ribbon
    // does not (a tube lying on the plane was 15.7 % low on Lambert with it, 0.49 % with z).
    if f.dot(a + e) < 0.0 {
        f = -f;
    }
    f.z.max(0.0)
}

/// The tube's two end disks (area πr², facing out along the axis), each as its solid angle times
/// the LTC at its centre, πr² |cos_e|/|e|² · D(ê) = r² |det M⁻¹| max(q.z, 0) |cos_e| |e| / |q|⁴
/// with q = M⁻¹e (the course's `I_ltc_disks`): (half of each end's, the end facing the origin's
/// whole). The silhouette of a cylinder is the ribbon plus half of each end's ellipse (the near
/// and the far one, each at its own distance) until, seen end-on, the far end hides behind the
/// near one: [`ltc_tube`] takes the larger of the two.
pub fn ltc_tube_caps(p: Vec3, dp: Vec3, r: f32, minv: Mat3) -> (f32, f32) {
    let t = dp.normalize_or_zero();
    let det = minv.determinant().abs();
    let cap = |e: Vec3, facing: f32| {
        let q = minv * e;
        let q2 = q.dot(q);
        r * r * det * q.z.max(0.0) * facing / (q2 * q2)
    };
    let e2 = p + dp;
    // The first end faces −t (the origin sees its outside when t·p > 0), the second +t.
    let c1 = cap(p, t.dot(p).abs());
    let c2 = cap(e2, t.dot(e2).abs());
    let front = if t.dot(p) > 0.0 { c1 } else { c2 };
    (0.5 * (c1 + c2), front)
}

/// A tube's LTC form factor: the facing ribbon ([`ltc_ribbon`]) plus half of each end disk, or the
/// end disk facing the origin alone if that is larger (seen end-on); at most 1 (the course's
/// clamp: the caps, taken at their centres, grow without bound as the shading point nears an end).
pub fn ltc_tube(p: Vec3, dp: Vec3, r: f32, minv: Mat3) -> f32 {
    let (halves, front) = ltc_tube_caps(p, dp, r, minv);
    (ltc_ribbon(p, dp, r, minv) + halves).max(front).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use std::f32::consts::PI;
    use std::f64::consts::PI as PI64;

    // The line form the ribbon replaced (luz until 2026-11-29): the ribbon as a line with a
    // first-order width in the LTC's transformed space. Kept to show what the polygon fixes.

    /// The form factor of a ribbon of half-width 1 along the segment from `p` to `p + dp`, its width
    /// perpendicular to the plane through the origin and the segment, with the part of the segment
    /// below the horizon (z < 0) cut off: (1/π) ∫ 2d z(l) / |p(l)|⁴ dl over the segment (d: the
    /// line's distance from the origin, l: the position along it from its foot). A ribbon of
    /// half-width r: r times this (for r ≪ d). The course's `I_diffuse_line`, with the differences of
    /// its antiderivatives written so that a short segment keeps its precision in f32.
    fn ltc_line_diffuse(p: Vec3, dp: Vec3) -> f32 {
        let z0 = p.z;
        let z1 = p.z + dp.z;
        if z0 <= 0.0 && z1 <= 0.0 {
            return 0.0;
        }
        let len = dp.length();
        if len <= 0.0 {
            return 0.0;
        }
        // The segment's part above the horizon, as s in [s0, s1] along p + s dp.
        let s_h = z0 / (z0 - z1);
        let s0 = if z0 < 0.0 { s_h } else { 0.0 };
        let s1 = if z1 < 0.0 { s_h } else { 1.0 };
        let t = dp / len;
        let l0 = p.dot(t);
        let l1 = l0 + s0 * len;
        let l2 = l0 + s1 * len;
        // The foot of the origin's perpendicular on the line, and the line's distance.
        let po = p - l0 * t;
        let d = po.length();
        if d <= 1e-6 * (l1.abs() + l2.abs()) {
            // The line passes through the origin: the ribbon is seen edge-on.
            return 0.0;
        }
        let dl = (s1 - s0) * len;
        let a1 = d * d + l1 * l1;
        let a2 = d * d + l2 * l2;
        // ∫ 2d/(d² + l²)² dl and ∫ 2d l/(d² + l²)² dl from l1 to l2.
        let f_po =
            dl * (d * d - l1 * l2) / (d * a1 * a2) + (d * dl).atan2(d * d + l1 * l2) / (d * d);
        let f_wt = d * dl * (l1 + l2) / (a1 * a2);
        ((po.z * f_po + t.z * f_wt) / PI).max(0.0)
    }

    /// The integral of the LTC of `minv` (D(ω) = D_o(M⁻¹ω/|M⁻¹ω|) |∂ω_o/∂ω|, D_o = max(z, 0)/π) over
    /// the ribbon of half-width 1 along the segment (`p`, `dp`): the transformed ribbon's form factor.
    /// M⁻¹ maps the ribbon to one along the transformed segment whose half-width perpendicular to the
    /// transformed plane is the course's width factor w = 1/|(M⁻¹)⁻ᵀ o| (o: the unit normal of the
    /// plane through the origin and the segment; the ribbon's shear within that plane changes its
    /// solid angle only at second order), computed here as |det M⁻¹| |p × dp| / |M⁻¹p × M⁻¹dp| (the
    /// same number, since (Au) × (Av) = det(A) A⁻ᵀ (u × v), without the inverse).
    fn ltc_line(p: Vec3, dp: Vec3, minv: Mat3) -> f32 {
        let q = minv * p;
        let dq = minv * dp;
        let c = q.cross(dq).length();
        if c <= 0.0 {
            return 0.0;
        }
        let w = minv.determinant().abs() * p.cross(dp).length() / c;
        w * ltc_line_diffuse(q, dq)
    }

    /// The old line form of the tube: the line's ribbon plus the same caps.
    fn ltc_tube_line_form(p: Vec3, dp: Vec3, r: f32, minv: Mat3) -> f32 {
        let (halves, front) = ltc_tube_caps(p, dp, r, minv);
        (r * ltc_line(p, dp, minv) + halves).max(front).min(1.0)
    }

    /// The LTC of `minv` at direction `l` (unit, f64): D_o(M⁻¹l/|M⁻¹l|) · |det M⁻¹| / |M⁻¹l|³.
    fn ltc_d(minv: &glam::DMat3, l: DVec3) -> f64 {
        let q = *minv * l;
        let len = q.length();
        (q.z / len).max(0.0) / PI64 * minv.determinant().abs() / (len * len * len)
    }

    /// The integral of the LTC over a closed cylinder (axis from `p` to `p + dp`, radius `r`):
    /// the midpoint rule over its side (n_l × n_phi cells) and its two end disks, counting the
    /// elements that face the origin (the cylinder is convex: those are the visible ones, and its
    /// silhouette is the open cylinder's).
    fn cylinder_integral(p: DVec3, dp: DVec3, r: f64, minv: &glam::DMat3) -> f64 {
        cylinder_integral_n(p, dp, r, minv, (4000, 256, 64))
    }

    /// [`cylinder_integral`] with `(n_l, n_phi, n_r)` cells.
    fn cylinder_integral_n(
        p: DVec3,
        dp: DVec3,
        r: f64,
        minv: &glam::DMat3,
        (n_l, n_phi, n_r): (usize, usize, usize),
    ) -> f64 {
        let len = dp.length();
        let t = dp / len;
        let u = t.any_orthonormal_vector();
        let v = t.cross(u);
        let element = |x: DVec3, n: DVec3, area: f64| {
            let dist2 = x.length_squared();
            let l = x / dist2.sqrt();
            let cos_e = -n.dot(l);
            if cos_e <= 0.0 {
                return 0.0;
            }
            ltc_d(minv, l) * cos_e * area / dist2
        };
        let mut sum = 0.0;
        let d_phi = 2.0 * PI64 / n_phi as f64;
        for i in 0..n_l {
            let s = (i as f64 + 0.5) / n_l as f64;
            for j in 0..n_phi {
                let phi = (j as f64 + 0.5) * d_phi;
                let n = phi.cos() * u + phi.sin() * v;
                sum += element(p + s * dp + r * n, n, r * d_phi * len / n_l as f64);
            }
        }
        for (c, n) in [(p, -t), (p + dp, t)] {
            for i in 0..n_r {
                let rho = r * (i as f64 + 0.5) / n_r as f64;
                for j in 0..n_phi {
                    let phi = (j as f64 + 0.5) * d_phi;
                    let x = c + rho * (phi.cos() * u + phi.sin() * v);
                    sum += element(x, n, rho * (r / n_r as f64) * d_phi);
                }
            }
        }
        sum
    }

    /// The worst relative error of the course's caps (the whole disk of the end facing the point,
    /// none of the other) on `tubes`, the same ribbon: what the halves improve on.
    fn ltc_tube_course_caps_error(tubes: &[(Vec3, Vec3)], minvs: &[(String, Mat3)], r: f32) -> f64 {
        let mut worst: f64 = 0.0;
        for (_, minv) in minvs {
            for &(p, dp) in tubes {
                let want =
                    cylinder_integral(p.as_dvec3(), dp.as_dvec3(), f64::from(r), &minv.as_dmat3());
                let got = f64::from(ltc_ribbon(p, dp, r, *minv) + ltc_tube_caps(p, dp, r, *minv).1);
                worst = worst.max((got - want).abs() / want.max(1e-6));
            }
        }
        worst
    }

    /// The shipped table's M⁻¹ at entry (t, a), as the shader builds it.
    fn table_minv(t: usize, a: usize) -> Mat3 {
        let table = super::super::ltc_table();
        let e = &table[(t * super::super::LTC_SIZE + a) * super::super::LTC_ENTRY..];
        Mat3::from_cols(
            Vec3::new(e[0], 0.0, e[1]),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(e[2], 0.0, e[3]),
        )
    }

    /// The tube form against numerical integration of the same LTC over a thin closed cylinder
    /// (radius 2 mm at 0.25–2 m): the cosine (M⁻¹ = I) and the shipped table's matrices at several
    /// views and roughnesses, tubes above the horizon, crossing it, seen sideways, obliquely,
    /// end-on and just off end-on. Each within 2.5 % of the numerical value (relative to it, or to
    /// 1e-6 where the whole integral is smaller). Measured (2026-11-29, the ribbon as a polygon):
    /// most rows < 0.1 %, all but five < 0.5 %; 3 mm off the axis seen end-on 1.2–2.2 % low (the
    /// far end's disk partly beside the near one: neither form is the silhouette; the line form
    /// was 5.4 % there); the grazing view at roughness 0.13, table (56, 8), 2.2 % on a 4.7e-6 row
    /// (the edge's fitted θ/sin θ, as for rects: < 0.5 % with the exact factor) and 1.3 % on a
    /// 3e-7 one (the line form's closed form: 0.06 % at worst on these rows).
    #[test]
    fn ltc_tube_matches_a_thin_cylinder() {
        let tubes = [
            // (first end, axis): in the shading frame, z up.
            (Vec3::new(-0.4, 0.3, 1.0), Vec3::new(0.8, 0.0, 0.0)),
            (Vec3::new(0.2, -0.5, 0.6), Vec3::new(0.1, 1.0, 0.3)),
            (Vec3::new(0.3, 0.2, -0.4), Vec3::new(0.0, 0.1, 1.2)),
            (Vec3::new(-1.0, 0.4, 0.2), Vec3::new(1.5, 0.0, -0.5)),
            (Vec3::new(0.1, 0.05, 0.5), Vec3::new(0.05, 0.0, 0.6)),
            (Vec3::new(1.0, 0.0, 0.3), Vec3::new(0.5, 0.0, 0.0)),
            (Vec3::new(-0.9, 0.2, 0.25), Vec3::new(0.6, 0.1, 0.0)),
            // End-on and just off it (the far end behind the near one, then beside it).
            (Vec3::new(0.0, 0.0, 0.8), Vec3::new(0.0, 0.0, 0.5)),
            (Vec3::new(0.001, 0.0, 0.8), Vec3::new(0.0, 0.0, 0.5)),
            (Vec3::new(0.003, 0.0, 0.8), Vec3::new(0.0, 0.0, 0.5)),
            (Vec3::new(0.01, 0.0, 0.8), Vec3::new(0.0, 0.0, 0.5)),
        ];
        let mut minvs = vec![("cosine".to_string(), Mat3::IDENTITY)];
        for (t, a) in [(10, 16), (32, 16), (32, 32), (50, 32), (20, 63), (56, 8)] {
            minvs.push((format!("table ({t}, {a})"), table_minv(t, a)));
        }
        let r = 0.002f32;
        let mut worst: f64 = 0.0;
        let mut failures = Vec::new();
        for (name, minv) in &minvs {
            let m64 = minv.as_dmat3();
            for (p, dp) in tubes {
                let want = cylinder_integral(p.as_dvec3(), dp.as_dvec3(), f64::from(r), &m64);
                let got = f64::from(ltc_tube(p, dp, r, *minv));
                let e = (got - want).abs() / want.max(1e-6);
                worst = worst.max(e);
                if e > 0.025 {
                    failures.push(format!("{name}, tube {p} + {dp}: {got:e} against {want:e}"));
                }
            }
        }
        eprintln!("ltc_tube against a 2 mm cylinder: worst relative error {worst:.5}");
        let course = ltc_tube_course_caps_error(&tubes[4..5], &minvs, r);
        eprintln!("the same 8.5° off the axis with the course's caps: {course:.4}");
        assert!(course > 0.02, "the halves are the better caps: {course}");
        assert!(failures.is_empty(), "{failures:#?}");
    }

    /// Roughness 0.05 (the table's column 3, α = 0.0023), where the lobe is narrower than the
    /// tube: tubes of radius 2, 20 and 50 mm, 0.6 m long, 1 m away across the lobe's peak (the
    /// direction M e_z), their axis across the plane of incidence and in it, the peak on the axis
    /// and on the silhouette's edge (offset r), views 13°, 42° and 68°, against numerical
    /// integration of the same LTC over the closed cylinder (midpoint rule, 4000 × 1024 cells of
    /// the side). The ribbon as a polygon: within 0.1 % (measured 2026-11-29: 0.017 % worst; with
    /// `ltc_clipped`'s equivalent sphere instead of the polygon's z it was 0.89 % on the
    /// silhouette's edge). The line form it replaced (the
    /// ribbon's width to first order in the transformed space) is 0.06–31 % off with the peak on the
    /// axis and 90–99.8 % on the edge (must be > 20 %).
    #[test]
    fn ltc_tube_at_low_roughness() {
        let mut worst: f64 = 0.0;
        let mut worst_line: f64 = 0.0;
        let mut failures = Vec::new();
        for t in [10, 32, 50] {
            let minv = table_minv(t, 3);
            let peak = (minv.inverse() * Vec3::Z).normalize();
            let across = peak.cross(Vec3::Z).normalize();
            let along = peak.cross(across);
            for r in [0.002f32, 0.02, 0.05] {
                for (axis, side) in [(across, along), (along, across)] {
                    for offset in [0.0, r] {
                        let c = peak + offset * side;
                        let (p, dp) = (c - 0.3 * axis, 0.6 * axis);
                        let want = cylinder_integral_n(
                            p.as_dvec3(),
                            dp.as_dvec3(),
                            f64::from(r),
                            &minv.as_dmat3(),
                            (4000, 1024, 64),
                        );
                        let got = f64::from(ltc_tube(p, dp, r, minv));
                        let line = f64::from(ltc_tube_line_form(p, dp, r, minv));
                        let e = (got - want).abs() / want.max(1e-6);
                        let e_line = (line - want).abs() / want.max(1e-6);
                        eprintln!(
                            "t {t}, r {r}, axis {axis}, offset {offset}: {want:.5e}, ribbon {e:.5}, line {e_line:.4}"
                        );
                        worst = worst.max(e);
                        worst_line = worst_line.max(e_line);
                        if e > 0.001 {
                            failures.push(format!("t {t}, r {r}, axis {axis}, offset {offset}: {got:e} against {want:e}"));
                        }
                    }
                }
            }
        }
        eprintln!(
            "roughness 0.05: worst relative error {worst:.5}, the line form's {worst_line:.3}"
        );
        assert!(worst_line > 0.2, "the line form fails here: {worst_line}");
        assert!(failures.is_empty(), "{failures:#?}");
    }

    /// The caps matter only end-on: a tube pointing at the shading point is its near end disk
    /// (and the ribbon, edge-on, gives almost nothing); a 1 mm tube far away keeps its precision
    /// (its ends' directions nearly equal in f32).
    #[test]
    fn ltc_tube_end_on_and_tiny() {
        let r = 0.01f32;
        // Axis along z, its near end 1 m above: the near disk's form factor is r²/1² (cos = 1).
        let p = Vec3::new(0.0, 0.0, 1.0);
        let dp = Vec3::new(0.0, 0.0, 0.5);
        let got = ltc_tube(p, dp, r, Mat3::IDENTITY);
        assert!((got - r * r).abs() < 1e-3 * r * r, "{got}");
        // A 1 mm tube 1.5 m away against the same tube 20× longer and thicker about the same
        // centre (a thin tube's form factor scales with r·L, its caps' with r²): 400× within 2 %.
        let c = Vec3::new(0.3, -0.2, 1.5);
        let tube = |k: f32| {
            let dp = Vec3::new(1e-3, 0.0, 2e-4) * k;
            ltc_tube(c - 0.5 * dp, dp, 5e-4 * k, table_minv(32, 32))
        };
        let (small, big) = (tube(1.0), tube(20.0));
        assert!(small > 0.0 && big > 0.0);
        let ratio = big / small;
        assert!(
            (ratio / 400.0 - 1.0).abs() < 0.02,
            "{big} / {small} = {ratio}"
        );
    }
}
