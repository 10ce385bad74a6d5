//! Tests of the CPU reference BRDFs: analytic checkpoints, positivity, reciprocity, robustness
//! at degenerate inputs, and directional albedo (energy) over parameter grids.
//!
//! `cargo test brdf::tests::albedo_report -- --ignored --nocapture` prints the full albedo
//! tables quoted in docs/brdf.md.

use glam::Vec3;

use super::*;

/// xorshift64* — a seeded generator, so the "random" directions are the same on every run.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / 16_777_216.0)
    }
    /// Uniform direction on the +z hemisphere.
    fn hemi(&mut self) -> Vec3 {
        sample_uniform_hemisphere(self.f32(), self.f32())
    }
}

const N: Vec3 = Vec3::Z;
const X: Vec3 = Vec3::X;
const Y: Vec3 = Vec3::Y;

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn finite(v: Vec3) -> bool {
    v.is_finite()
}

const ROUGHNESSES: [f32; 5] = [0.0, 1e-4, 1e-2, 0.5, 1.0];

/// One instance of every model and selector combination, at the given roughness, with
/// white-ish colours (the worst case for energy).
fn all_models(roughness: f32) -> Vec<Model> {
    let mut out = vec![
        Model::Lambert(LambertParams { albedo: Vec3::ONE }),
        Model::OrenNayar(OrenNayarParams {
            albedo: Vec3::ONE,
            sigma_deg: roughness * 90.0,
        }),
    ];
    for blinn in [false, true] {
        out.push(Model::Phong(PhongParams {
            shininess: 1.0 + roughness * 100.0,
            blinn,
            ..Default::default()
        }));
    }
    let sources = [
        SpecularSource::Ior(1.5),
        SpecularSource::Ior(0.277),
        SpecularSource::F0(Vec3::ONE),
        SpecularSource::Complex(metal_preset("gold").unwrap()),
    ];
    for d in Distribution::ALL {
        for g in Geometry::ALL {
            for f in Fresnel::ALL {
                for (i, s) in sources.iter().enumerate() {
                    for diffuse in Diffuse::ALL {
                        out.push(Model::CookTorrance(CookTorranceParams {
                            color: Vec3::ONE,
                            kd: [0.0, 0.5, 0.75, 1.0][i],
                            roughness,
                            specular: *s,
                            distribution: d,
                            geometry: g,
                            fresnel: f,
                            diffuse,
                        }));
                    }
                }
                for metallic in [0.0, 1.0] {
                    for w in [false, true] {
                        for diffuse in Diffuse::ALL {
                            out.push(Model::MetalRough(MetalRoughParams {
                                base_color: Vec3::ONE,
                                metallic,
                                roughness,
                                distribution: d,
                                geometry: g,
                                fresnel: f,
                                diffuse_fresnel_weight: w,
                                diffuse,
                                ..MetalRoughParams::default()
                            }));
                        }
                    }
                }
            }
        }
    }
    for bits in 0..64u32 {
        let b = |k: u32| if bits & (1 << k) != 0 { 1.0 } else { 0.0 };
        out.push(Model::Principled(PrincipledParams {
            base_color: Vec3::new(0.9, 0.6, 0.2),
            subsurface: b(0),
            metallic: b(1),
            specular: 0.5 + 0.5 * b(2),
            specular_tint: b(2),
            roughness,
            anisotropic: b(3),
            sheen: b(4),
            sheen_tint: b(4),
            clearcoat: b(5),
            clearcoat_gloss: 1.0 - 0.5 * b(3),
        }));
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Analytic checkpoints
// ---------------------------------------------------------------------------------------------

/// GGX specular alone, F = 1, α = 1, viewed along the normal: albedo 1 − ln 2.
///
/// With α = 1, D = 1/π everywhere. With v = n, G1(v) = 1 for every Smith form, and
/// G1(l) = 2μ/(1 + μ), μ = n·l, for the separable Smith GGX (2μ/(μ + sqrt(1))), the
/// height-correlated one (Λ(v) = 0 so G2 = 1/(1 + Λ(l)) = G1(l)) and Schlick-GGX with
/// k = 0.5 (which is both k_punctual(1) and k_ibl(1): μ/(0.5μ + 0.5)). So
/// R = ∫ D G/(4 n·v) dω = (1/4π) · 2π ∫₀¹ 2μ/(1+μ) dμ = ∫₀¹ (1 − 1/(1+μ)) dμ = 1 − ln 2.
/// The Cook-Torrance G instead gives G = min(1, 2μ) and R = ½ (¼ + ½) = 3/8.
#[test]
fn ggx_albedo_checkpoint_is_one_minus_ln2() {
    let want = 1.0 - std::f32::consts::LN_2;
    let l = N;
    let lobes = [Lobe::Ggx { ax: 1.0, ay: 1.0 }];
    // G as a function of (n·h, n·l, n·v, v·h).
    type GFn = fn(f32, f32, f32, f32) -> f32;
    let spec = |g: GFn| {
        move |v: Vec3| {
            let h = (l + v).normalize();
            let (nl, nv) = (N.dot(l), N.dot(v));
            Vec3::splat(d_ggx(h.z, 1.0) * g(h.z, nl, nv, l.dot(h)) / (4.0 * nl * nv))
        }
    };
    let cases: [(&str, GFn, f32); 5] = [
        (
            "smith separable",
            |_, l, v, _| g_smith_ggx_separable(l, v, 1.0),
            want,
        ),
        (
            "smith correlated",
            |_, l, v, _| g_smith_ggx_correlated(l, v, 1.0),
            want,
        ),
        (
            "schlick k_punctual(1)",
            |_, l, v, _| g_schlick_ggx(l, v, k_punctual(1.0)),
            want,
        ),
        (
            "schlick k_ibl(1)",
            |_, l, v, _| g_schlick_ggx(l, v, k_ibl(1.0)),
            want,
        ),
        (
            "cook-torrance",
            |h, l, v, vh| g_cook_torrance(h, v, l, vh),
            0.375,
        ),
    ];
    for (name, g, expected) in cases {
        let r = integrate_hemisphere(spec(g), l, &lobes, 16_384).x;
        assert!((r - expected).abs() < 1e-3, "{name}: {r} vs {expected}");
    }
    // The same through the model: Cook-Torrance, k_d = 0, GGX at roughness 1 (α = 1), F0 = 1.
    let m = Model::CookTorrance(CookTorranceParams {
        kd: 0.0,
        roughness: 1.0,
        specular: SpecularSource::F0(Vec3::ONE),
        distribution: Distribution::Ggx,
        geometry: Geometry::SmithGgx,
        fresnel: Fresnel::Schlick,
        ..Default::default()
    });
    let r = directional_albedo(&m, 1.0, 16_384);
    assert!((r - Vec3::splat(want)).abs().max_element() < 1e-3, "{r}");
}

#[test]
fn lambert_albedo_is_exactly_the_albedo() {
    let m = Model::Lambert(LambertParams {
        albedo: Vec3::new(1.0, 0.5, 0.25),
    });
    for c in [1.0, 0.7, 0.2, 0.01] {
        let r = directional_albedo(&m, c, 4096);
        assert!(
            (r - Vec3::new(1.0, 0.5, 0.25)).abs().max_element() < 1e-3,
            "{c}: {r}"
        );
    }
}

/// Every D is normalised: ∫ D(h) (n·h) dω_h = 1 over the hemisphere of h (GGX, GTR2
/// anisotropic, GTR1, Beckmann), down to the floor α = 1e-3. Quadrature in x = ln tanθ_h
/// (dθ = sinθ cosθ dx), which spreads any width evenly, and φ.
#[test]
fn distributions_are_normalised() {
    let integrate = |d: &dyn Fn(f32, f32, f32, f32) -> f32| {
        let (x0, x1, nx, nphi) = (-25.0f64, 12.0f64, 4000, 48);
        let dx = (x1 - x0) / nx as f64;
        let dphi = 2.0 * std::f64::consts::PI / nphi as f64;
        let mut sum = 0.0f64;
        for i in 0..nx {
            let theta = (x0 + (i as f64 + 0.5) * dx).exp().atan();
            let (s, c) = theta.sin_cos();
            for j in 0..nphi {
                let (sp, cp) = ((j as f64 + 0.5) * dphi).sin_cos();
                let val = d(c as f32, (s * s) as f32, (s * cp) as f32, (s * sp) as f32) as f64;
                sum += val * c * s * s * c * dx * dphi;
            }
        }
        sum
    };
    for a in [0.001f32, 0.01, 0.1, 0.5, 1.0] {
        let ggx = integrate(&|c, s2, _, _| d_ggx_sin2(c, s2, a));
        assert!((ggx - 1.0).abs() < 1e-3, "ggx {a}: {ggx}");
        let (ax, ay) = (a, (a * 0.3).max(ALPHA_MIN));
        let aniso = integrate(&|c, _, hx, hy| d_gtr2_aniso(c, hx, hy, ax, ay));
        assert!((aniso - 1.0).abs() < 1e-3, "gtr2 aniso {a}: {aniso}");
        let gtr1 = integrate(&|c, s2, _, _| d_gtr1_sin2(c, s2, a));
        assert!((gtr1 - 1.0).abs() < 1e-3, "gtr1 {a}: {gtr1}");
        let beck = integrate(&|c, s2, _, _| d_beckmann_sin2(c, s2, a));
        assert!((beck - 1.0).abs() < 1e-3, "beckmann {a}: {beck}");
    }
    // The n·h-only forms equal the sin² forms (away from the peak, where n·h has enough bits).
    for c in [0.2f32, 0.5, 0.9] {
        let s2 = 1.0 - c * c;
        assert!((d_ggx(c, 0.3) - d_ggx_sin2(c, s2, 0.3)).abs() < 1e-5 * d_ggx(c, 0.3));
        assert!(
            (d_beckmann(c, 0.3) - d_beckmann_sin2(c, s2, 0.3)).abs()
                < 1e-5 * d_beckmann(c, 0.3).max(1e-6)
        );
        assert!((d_gtr1(c, 0.3) - d_gtr1_sin2(c, s2, 0.3)).abs() < 1e-5 * d_gtr1(c, 0.3));
        let t = c * c * (0.09 - 1.0) + 1.0;
        assert!((d_ggx(c, 0.3) - 0.09 / (PI * t * t)).abs() < 1e-5 * d_ggx(c, 0.3));
    }
    // The analytic peaks at the floor α = 1e-3 (roughness 0 stays finite).
    assert!((d_ggx(1.0, 0.0) - 1.0 / (PI * 1e-6)).abs() / d_ggx(1.0, 0.0) < 1e-4);
    assert!((d_beckmann(1.0, 0.0) - 1.0 / (PI * 1e-6)).abs() / d_beckmann(1.0, 0.0) < 1e-4);
}

#[test]
fn smith_forms_agree_with_lambda() {
    for a in [0.05f32, 0.3, 0.7, 1.0] {
        for c in [0.05f32, 0.3, 0.8, 1.0] {
            let tan2 = (1.0 - c * c) / (c * c);
            let lambda = (-1.0 + (1.0 + a * a * tan2).sqrt()) / 2.0;
            assert!((g1_smith_ggx(c, a) - 1.0 / (1.0 + lambda)).abs() < 1e-5);
            // Disney's visibility form: G1 = 2 (n·v) Vis.
            let vis = vis_smith_ggx_aniso(c, (1.0 - c * c).sqrt(), 0.0, a, a);
            assert!((2.0 * c * vis - g1_smith_ggx(c, a)).abs() < 1e-5);
            assert!((2.0 * c * vis_smith_ggx_iso(c, a) - g1_smith_ggx(c, a)).abs() < 1e-5);
            for c2 in [0.1f32, 0.6, 1.0] {
                let tan2b = (1.0 - c2 * c2) / (c2 * c2);
                let lambda_b = (-1.0 + (1.0 + a * a * tan2b).sqrt()) / 2.0;
                let want = 1.0 / (1.0 + lambda + lambda_b);
                assert!((g_smith_ggx_correlated(c, c2, a) - want).abs() < 1e-5);
            }
        }
    }
    assert_eq!(k_punctual(1.0), 0.5);
    assert_eq!(k_punctual(0.0), 0.125);
    assert_eq!(k_ibl(1.0), 0.5);
}

/// The exact Fresnel equations with a complex index, in f64 — to measure the MODELS.md §3
/// conductor formula (PBRT 2nd ed.'s approximation) against.
fn conductor_exact(cos_i: f64, eta: f64, k: f64) -> f64 {
    // n₂ = η + iκ, n₁ = 1; cosθ_t = sqrt(1 − sin²θ_i / n₂²) (complex).
    let (c, s2) = (cos_i, 1.0 - cos_i * cos_i);
    let (nr, ni) = (eta, k);
    let n2r = nr * nr - ni * ni;
    let n2i = 2.0 * nr * ni;
    let den = n2r * n2r + n2i * n2i;
    // z = 1 − s2 / n²
    let zr = 1.0 - s2 * n2r / den;
    let zi = s2 * n2i / den;
    let m = (zr * zr + zi * zi).sqrt();
    let (tr, ti) = (
        ((m + zr) / 2.0).sqrt(),
        zi.signum() * ((m - zr) / 2.0).sqrt(),
    );
    let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let abs2 = |a: (f64, f64)| a.0 * a.0 + a.1 * a.1;
    let nt = mul((nr, ni), (tr, ti));
    let nc = (nr * c, ni * c);
    let rs = abs2((c - nt.0, -nt.1)) / abs2((c + nt.0, nt.1));
    let rp = abs2((nc.0 - tr, nc.1 - ti)) / abs2((nc.0 + tr, nc.1 + ti));
    0.5 * (rs + rp)
}

#[test]
fn fresnel_terms() {
    // Dielectric: F0 of glass, grazing 1, total internal reflection, equals the r⊥/r∥ form.
    assert!((f_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
    assert!((f_dielectric(0.0, 1.5) - 1.0).abs() < 1e-6);
    assert_eq!(f_dielectric(0.5, 1.0 / 1.5), 1.0);
    assert_eq!(f_dielectric(1.0, 1.0), 0.0);
    let mut schlick_worst = 0.0f32;
    for i in 0..=100 {
        let ci = i as f32 / 100.0;
        let eta = 1.33f32;
        let st = (1.0 - ci * ci).sqrt() / eta;
        let ct = (1.0 - st * st).sqrt();
        let rs = (ci - eta * ct) / (ci + eta * ct);
        let rp = (eta * ci - ct) / (eta * ci + ct);
        let want = 0.5 * (rs * rs + rp * rp);
        assert!((f_dielectric(ci, eta) - want).abs() < 1e-5, "{ci}");
        // Schlick against the exact curve for water.
        let schlick = f_schlick(Vec3::splat(f0_from_ior(eta)), ci).x;
        schlick_worst = schlick_worst.max((schlick - want).abs());
        // The spherical-Gaussian fit stays within 0.01 of Schlick.
        let sg = f_schlick_sg(Vec3::splat(0.04), ci).x;
        let s = f_schlick(Vec3::splat(0.04), ci).x;
        assert!((sg - s).abs() < 0.01, "sg {ci}: {sg} vs {s}");
    }
    println!("Schlick vs exact dielectric, water: max |error| {schlick_worst:.4}");
    assert!(schlick_worst < 0.07, "{schlick_worst}");
    assert!((f0_from_ior(1.5) - 0.04).abs() < 1e-7);
    assert!((ior_from_f0(0.04) - 1.5).abs() < 1e-5);
    // The seed's gold preset, a real η = 0.277 alone, gives F0 = 0.32 (MODELS.md §3).
    assert!((f0_from_ior(0.277) - 0.3202).abs() < 1e-3);
    // The f64 reference reduces to the dielectric equations for κ = 0.
    for i in 0..=20 {
        let c = i as f32 / 20.0;
        assert!((conductor_exact(c as f64, 1.5, 0.0) as f32 - f_dielectric(c, 1.5)).abs() < 1e-5);
    }
    // Conductor: exact at normal incidence, 1 at grazing; near the exact complex Fresnel.
    for name in METAL_NAMES {
        let m = metal_preset(name).unwrap();
        let f0 = f_conductor(1.0, m.eta, m.k);
        assert!((f0 - m.f0()).abs().max_element() < 1e-5, "{name}");
        assert!(
            (f_conductor(0.0, m.eta, m.k) - Vec3::ONE)
                .abs()
                .max_element()
                < 1e-6
        );
        let mut worst = 0.0f64;
        for i in 0..=200 {
            let c = i as f32 / 200.0;
            let got = f_conductor(c, m.eta, m.k);
            for ch in 0..3 {
                let want = conductor_exact(c as f64, m.eta[ch] as f64, m.k[ch] as f64);
                worst = worst.max((got[ch] as f64 - want).abs());
            }
        }
        println!(
            "{name}: MODELS.md conductor formula vs exact complex Fresnel, max |error| {worst:.4}"
        );
        assert!(
            worst < 0.05,
            "{name}: conductor approximation off by {worst}"
        );
    }
}

#[test]
fn presets() {
    let gold = metal_preset("Gold").unwrap().f0();
    assert!(gold.x > 0.9 && gold.y > 0.75 && gold.z < 0.45, "{gold}");
    let silver = metal_preset("ag").unwrap().f0();
    assert!(silver.min_element() > 0.95, "{silver}");
    let copper = metal_preset("copper").unwrap().f0();
    assert!(copper.x > copper.y && copper.y > copper.z, "{copper}");
    assert!(metal_preset("aluminum").is_some());
    assert!(metal_preset("unobtainium").is_none());
    for name in METAL_NAMES {
        let f0 = metal_preset(name).unwrap().f0();
        assert!(
            f0.min_element() > 0.35 && f0.max_element() < 1.0,
            "{name}: {f0}"
        );
    }
    for name in DIELECTRIC_NAMES {
        let eta = dielectric_ior(name).unwrap();
        assert!((1.3..2.5).contains(&eta), "{name}");
    }
}

/// Principled at l = v = n: FL = FV = FH = 0, Fd = ss·… so the value is known in closed form.
#[test]
fn principled_at_normal_incidence() {
    let p = PrincipledParams {
        base_color: Vec3::new(0.5, 0.25, 0.1),
        roughness: 0.5,
        clearcoat: 1.0,
        clearcoat_gloss: 0.0,
        ..Default::default()
    };
    let got = principled(&p, N, N, N, X, Y);
    let cdlin = p.base_color;
    let a = 0.25f32; // roughness² with aspect 1
    let ds = 1.0 / (PI * a * a); // GTR2 at n·h = 1
    let gs = 0.25; // (1/(1 + 1))²
    let cspec0 = Vec3::splat(0.5 * 0.08);
    let dr = {
        let a2 = 0.01f32; // α = 0.1
        (a2 - 1.0) / (PI * a2.ln() * a2)
    };
    let gr = 0.25;
    let want = cdlin / PI + cspec0 * gs * ds + Vec3::splat(0.25 * gr * 0.04 * dr);
    assert!(
        (got - want).abs().max_element() < 1e-5 * want.max_element(),
        "{got} vs {want}"
    );
}

// ---------------------------------------------------------------------------------------------
// Plausibility: positivity, reciprocity, robustness
// ---------------------------------------------------------------------------------------------

#[test]
fn positive_and_finite_over_grids() {
    let mut rng = Rng::new(1);
    let mut count = 0usize;
    for r in [0.0, 1e-4, 1e-2, 0.1, 0.25, 0.5, 0.75, 1.0] {
        for m in all_models(r) {
            for _ in 0..24 {
                let (l, v) = (rng.hemi(), rng.hemi());
                let x = Vec3::new(rng.f32() - 0.5, rng.f32() - 0.5, rng.f32() - 0.5);
                let y = N.cross(x);
                let f = eval(&m, N, l, v, x, y);
                assert!(finite(f) && f.min_element() >= 0.0, "{m:?} {l} {v}: {f}");
                let t = eval_terms(&m, N, l, v, x, y);
                assert!(t.d >= 0.0 && t.g >= 0.0 && t.f.min_element() >= 0.0);
                assert!((t.total() - f).abs().max_element() <= 1e-6 * f.max_element());
                let e = radiance(&m, N, l, v, x, y, Vec3::new(1.0, 2.0, 3.0));
                assert!(finite(e) && e.min_element() >= 0.0);
                count += 1;
            }
        }
    }
    assert!(count > 10_000);
}

/// Directions that break naive code: grazing, below the horizon, l = −v, l = v = n, zero and
/// unnormalised vectors, degenerate tangents.
#[test]
fn no_nan_or_inf_at_degenerate_inputs() {
    let g = |t: f32| Vec3::new(t.sin(), 0.0, t.cos());
    let half_pi = std::f32::consts::FRAC_PI_2;
    let dirs = [
        N,
        -N,
        Vec3::X,
        Vec3::Y,
        g(half_pi - 1e-7),
        g(half_pi - 1e-4),
        g(-(half_pi - 1e-6)),
        g(half_pi + 1e-6),
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, 1e-30),
        Vec3::new(3.0, 0.0, 4.0),
        Vec3::new(1e-20, 1e-20, 1e-20),
    ];
    let tangents = [
        Vec3::X,
        Vec3::ZERO,
        N,
        -N,
        Vec3::new(1e-30, 0.0, 0.0),
        Vec3::Y * 5.0,
    ];
    let normals = [N, Vec3::ZERO, Vec3::new(0.0, 0.0, 7.0)];
    for r in ROUGHNESSES {
        for m in all_models(r) {
            for n in normals {
                for l in dirs {
                    for v in dirs.iter().copied().chain([-l, l]) {
                        for x in tangents {
                            let f = eval(&m, n, l, v, x, N.cross(x));
                            assert!(
                                finite(f) && f.min_element() >= 0.0,
                                "{m:?} n{n} l{l} v{v} x{x}: {f}"
                            );
                            let e = radiance(&m, n, l, v, x, Vec3::ZERO, Vec3::ONE);
                            assert!(finite(e) && e.min_element() >= 0.0, "{m:?}: {e}");
                        }
                    }
                }
            }
            // Zero below the horizon, for both l and v.
            assert_eq!(eval(&m, N, -N, N, X, Y), Vec3::ZERO);
            assert_eq!(eval(&m, N, N, g(half_pi + 0.1), X, Y), Vec3::ZERO);
            assert_eq!(eval(&m, N, Vec3::ZERO, N, X, Y), Vec3::ZERO);
        }
    }
    // The terms on their own, at their edges.
    for a in [0.0, 1e-8, 1e-3, 1.0, 10.0] {
        for c in [-1.0, 0.0, 1e-30, 1e-7, 1e-4, 0.5, 1.0, 1.5] {
            for val in [
                d_beckmann(c, a),
                d_ggx(c, a),
                d_gtr1(c, a),
                d_gtr2_aniso(c, 0.0, 0.0, a, a),
                d_gtr2_aniso(c, 1.0, 1.0, a, a * 0.1),
                g1_smith_ggx(c, a),
                g_smith_ggx_correlated(c, c, a),
                g_schlick_ggx(c, c, a),
                g_cook_torrance(c, c, c, c),
                vis_smith_ggx_aniso(c, 1.0, 1.0, a, a),
                vis_smith_ggx_iso(c, a),
                f_dielectric(c, a),
                f_conductor_1(c, a, a),
                ss_hanrahan_krueger(c, c, c, a),
            ] {
                assert!(val.is_finite() && val >= 0.0, "a {a} c {c}: {val}");
            }
        }
    }
    // The seed's Beckmann at roughness 0 was 0/0.
    assert!(d_beckmann(1.0, 0.0).is_finite() && d_beckmann(0.999, 0.0).is_finite());
    assert!((d_gtr1(0.5, 0.999_999_9) - INV_PI).abs() < 1e-4);
    assert_eq!(d_gtr1(0.5, 1.0), INV_PI);
}

/// Non-finite and out-of-range parameters are sanitised, never propagated.
#[test]
fn parameters_are_sanitised() {
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -5.0, 5.0];
    let l = dir(30.0, 10.0);
    let v = dir(50.0, 200.0);
    for b in bad {
        let models = [
            Model::Lambert(LambertParams {
                albedo: Vec3::splat(b),
            }),
            Model::Phong(PhongParams {
                kd: b,
                ks: b,
                shininess: b,
                diffuse_color: Vec3::splat(b),
                ..Default::default()
            }),
            Model::CookTorrance(CookTorranceParams {
                kd: b,
                roughness: b,
                specular: SpecularSource::Ior(b),
                ..Default::default()
            }),
            Model::CookTorrance(CookTorranceParams {
                specular: SpecularSource::Complex(ComplexIor {
                    eta: Vec3::splat(b),
                    k: Vec3::splat(b),
                }),
                fresnel: Fresnel::Conductor,
                ..Default::default()
            }),
            Model::MetalRough(MetalRoughParams {
                metallic: b,
                roughness: b,
                base_color: Vec3::splat(b),
                ..Default::default()
            }),
            Model::Principled(PrincipledParams {
                base_color: Vec3::splat(b),
                subsurface: b,
                metallic: b,
                specular: b,
                specular_tint: b,
                roughness: b,
                anisotropic: b,
                sheen: b,
                sheen_tint: b,
                clearcoat: b,
                clearcoat_gloss: b,
            }),
            Model::OrenNayar(OrenNayarParams {
                albedo: Vec3::splat(b),
                sigma_deg: b,
            }),
        ];
        for m in models {
            let f = eval(&m, N, l, v, X, Y);
            assert!(finite(f) && f.min_element() >= 0.0, "{m:?}: {f}");
        }
    }
}

#[test]
fn reciprocity() {
    let mut rng = Rng::new(7);
    let mut phong_max_asym = 0.0f32;
    for r in [0.05, 0.3, 0.7, 1.0] {
        for m in all_models(r) {
            for _ in 0..16 {
                let (l, v) = (rng.hemi(), rng.hemi());
                if l.z < 0.02 || v.z < 0.02 {
                    continue;
                }
                let x = Vec3::new(rng.f32() - 0.5, rng.f32() - 0.5, 0.0);
                let y = N.cross(x);
                let a = eval(&m, N, l, v, x, y);
                let b = eval(&m, N, v, l, x, y);
                let rel =
                    (a - b).abs().max_element() / a.max_element().max(b.max_element()).max(1e-6);
                if m.is_reciprocal() {
                    assert!(rel < 2e-4, "{m:?} l{l} v{v}: {a} vs {b}");
                } else {
                    phong_max_asym = phong_max_asym.max(rel);
                }
            }
        }
    }
    // Phong's BRDF equivalent k_s (r·v)^n / (n·l) is not reciprocal.
    assert!(phong_max_asym > 0.1, "{phong_max_asym}");
}

#[test]
fn radiance_is_f_times_e_times_cos() {
    let l = dir(40.0, 30.0);
    let v = dir(20.0, 250.0);
    let e = Vec3::new(2.0, 1.0, 0.5);
    for m in all_models(0.4) {
        let got = radiance(&m, N, l, v, X, Y, e);
        let want = eval(&m, N, l, v, X, Y) * e * l.z;
        assert!(
            (got - want).abs().max_element() <= 1e-5 * want.max_element(),
            "{m:?}"
        );
    }
    // The slides' formula for Phong: I_L (k_d O_d n·l + k_s O_s (r·v)^n).
    let p = PhongParams {
        diffuse_color: Vec3::new(0.0, 1.0, 0.0),
        specular_color: Vec3::ONE,
        kd: 0.8,
        ks: 0.7,
        shininess: 5.0,
        ..Default::default()
    };
    let r = N * 2.0 * N.dot(l) - l;
    let want = Vec3::splat(0.8)
        * (p.diffuse_color * 0.8 * l.z + Vec3::ONE * 0.7 * r.dot(v).max(0.0).powf(5.0));
    let got = phong_radiance(&p, N, l, v, Vec3::splat(0.8));
    assert!((got - want).abs().max_element() < 1e-6, "{got} vs {want}");
    assert_eq!(p.ambient(Vec3::splat(0.5)), Vec3::new(0.0, 0.1, 0.0));
}

/// With anisotropic = 0 the tangent frame does not matter.
#[test]
fn principled_isotropic_ignores_tangents() {
    let p = Model::Principled(PrincipledParams {
        roughness: 0.3,
        clearcoat: 1.0,
        sheen: 1.0,
        ..Default::default()
    });
    let (l, v) = (dir(35.0, 20.0), dir(60.0, 170.0));
    let f0 = eval(&p, N, l, v, X, Y);
    for x in [Vec3::Y, Vec3::new(1.0, 1.0, 0.3), Vec3::ZERO, N] {
        let f = eval(&p, N, l, v, x, N.cross(x));
        assert!(
            (f - f0).abs().max_element() < 1e-5 * f0.max_element(),
            "{x}"
        );
    }
    // Anisotropic: stretching along x widens the highlight along x.
    let a = Model::Principled(PrincipledParams {
        roughness: 0.3,
        anisotropic: 1.0,
        ..Default::default()
    });
    // Off-specular along x (l in the x-z plane, v 20° short of the mirror direction) versus the
    // same configuration rotated by 90° about n.
    let hx = eval(&a, N, dir(30.0, 0.0), dir(10.0, 180.0), X, Y);
    let hy = eval(&a, N, dir(30.0, 90.0), dir(10.0, 270.0), X, Y);
    assert!(hx.x > hy.x, "{hx} vs {hy}");
}

#[test]
fn serde_names_and_defaults() {
    let names = |v: &[String]| v.join(",");
    let d: Vec<String> = Distribution::ALL
        .iter()
        .map(|x| serde_json::to_string(x).unwrap())
        .collect();
    assert_eq!(names(&d), r#""beckmann","ggx""#);
    let g: Vec<String> = Geometry::ALL
        .iter()
        .map(|x| serde_json::to_string(x).unwrap())
        .collect();
    assert_eq!(
        names(&g),
        r#""cook_torrance","smith_ggx","smith_ggx_correlated","schlick_ggx","smith_beckmann""#
    );
    let f: Vec<String> = Fresnel::ALL
        .iter()
        .map(|x| serde_json::to_string(x).unwrap())
        .collect();
    assert_eq!(
        names(&f),
        r#""schlick","schlick_sg","dielectric","conductor","conductor_exact""#
    );

    let m: Model = serde_json::from_str(r#"{"model": "principled", "roughness": 0.25}"#).unwrap();
    assert_eq!(
        m,
        Model::Principled(PrincipledParams {
            roughness: 0.25,
            ..Default::default()
        })
    );
    let m: Model = serde_json::from_str(
        r#"{"model": "cook_torrance", "specular": {"complex": {"eta": [0.2, 0.4, 1.4], "k": [3.6, 2.5, 1.9]}},
            "distribution": "ggx", "geometry": "smith_ggx_correlated", "fresnel": "conductor"}"#,
    )
    .unwrap();
    let Model::CookTorrance(ct) = m else {
        panic!("{m:?}")
    };
    assert_eq!(ct.fresnel, Fresnel::Conductor);
    assert_eq!(ct.kd, 0.75);
    let m: Model =
        serde_json::from_str(r#"{"model": "cook_torrance", "specular": {"ior": 1.461}}"#).unwrap();
    assert_eq!(m.name(), "cook_torrance");
    assert!(
        serde_json::from_str::<Model>(r#"{"model": "lambert", "albedoo": [1, 1, 1]}"#).is_err()
    );
    for m in all_models(0.5) {
        let json = serde_json::to_string(&m).unwrap();
        assert_eq!(serde_json::from_str::<Model>(&json).unwrap(), m, "{json}");
    }
}

#[test]
fn gpu_packing() {
    assert_eq!(std::mem::size_of::<GpuBrdfParams>(), 112);
    let p = Model::Principled(PrincipledParams {
        roughness: 0.3,
        sheen: 0.7,
        ..Default::default()
    });
    let g = GpuBrdfParams::from_model(&p);
    assert_eq!(g.sel[0], model_code::PRINCIPLED);
    assert_eq!(g.color[3], 0.3);
    assert_eq!(g.p1[0], 0.7);
    let bytes = g.to_bytes();
    assert_eq!(&bytes[12..16], &0.3f32.to_ne_bytes());
    assert_eq!(&bytes[80..84], &model_code::PRINCIPLED.to_ne_bytes());
    let ct = Model::CookTorrance(CookTorranceParams {
        specular: SpecularSource::Ior(1.5),
        distribution: Distribution::Ggx,
        geometry: Geometry::SchlickGgx,
        fresnel: Fresnel::SchlickSg,
        ..Default::default()
    });
    let g = GpuBrdfParams::from_model(&ct);
    assert_eq!(g.sel, [model_code::COOK_TORRANCE, 1, 3, 1]);
    assert_eq!(g.p0[1], 0.0);
    assert_eq!(GpuBrdfParams::diffuse_selector(&ct), Some(0));
    // The diffuse selector travels in p0.y (sel is full).
    for (m, code) in [
        (
            Model::CookTorrance(CookTorranceParams {
                diffuse: Diffuse::Burley,
                ..Default::default()
            }),
            1,
        ),
        (
            Model::MetalRough(MetalRoughParams {
                diffuse: Diffuse::Burley,
                diffuse_fresnel_weight: true,
                ..Default::default()
            }),
            1,
        ),
        (Model::MetalRough(MetalRoughParams::default()), 0),
    ] {
        let g = GpuBrdfParams::from_model(&m);
        assert_eq!(g.p0[1], code as f32, "{m:?}");
        assert_eq!(GpuBrdfParams::diffuse_selector(&m), Some(code));
    }
    assert_eq!(GpuBrdfParams::diffuse_selector(&p), None);
    assert!((g.spec[0] - 0.04).abs() < 1e-7);
    assert_eq!(g.kappa[3], 0.75);
    // Selector codes as in models.glsl (the source text and the constants build.rs generates).
    let glsl = include_str!("../../../../shaders_glsl/brdf/models.glsl");
    use crate::glsl::brdf_models as g;
    let generated = [
        g::BRDF_MODEL_LAMBERT,
        g::BRDF_MODEL_PHONG,
        g::BRDF_MODEL_BLINN_PHONG,
        g::BRDF_MODEL_COOK_TORRANCE,
        g::BRDF_MODEL_METAL_ROUGH,
        g::BRDF_MODEL_PRINCIPLED,
        g::BRDF_MODEL_OREN_NAYAR,
        g::BRDF_D_BECKMANN,
        g::BRDF_D_GGX,
        g::BRDF_G_COOK_TORRANCE,
        g::BRDF_G_SMITH_GGX,
        g::BRDF_G_SMITH_GGX_CORRELATED,
        g::BRDF_G_SCHLICK_GGX,
        g::BRDF_G_SMITH_BECKMANN,
        g::BRDF_F_SCHLICK,
        g::BRDF_F_SCHLICK_SG,
        g::BRDF_F_DIELECTRIC,
        g::BRDF_F_CONDUCTOR,
        g::BRDF_F_CONDUCTOR_EXACT,
        g::BRDF_DIFFUSE_LAMBERT,
        g::BRDF_DIFFUSE_BURLEY,
    ];
    for ((name, code), generated) in [
        ("BRDF_MODEL_LAMBERT", model_code::LAMBERT),
        ("BRDF_MODEL_PHONG", model_code::PHONG),
        ("BRDF_MODEL_BLINN_PHONG", model_code::BLINN_PHONG),
        ("BRDF_MODEL_COOK_TORRANCE", model_code::COOK_TORRANCE),
        ("BRDF_MODEL_METAL_ROUGH", model_code::METAL_ROUGH),
        ("BRDF_MODEL_PRINCIPLED", model_code::PRINCIPLED),
        ("BRDF_MODEL_OREN_NAYAR", model_code::OREN_NAYAR),
        ("BRDF_D_BECKMANN", Distribution::Beckmann as i32),
        ("BRDF_D_GGX", Distribution::Ggx as i32),
        ("BRDF_G_COOK_TORRANCE", Geometry::CookTorrance as i32),
        ("BRDF_G_SMITH_GGX", Geometry::SmithGgx as i32),
        (
            "BRDF_G_SMITH_GGX_CORRELATED",
            Geometry::SmithGgxCorrelated as i32,
        ),
        ("BRDF_G_SCHLICK_GGX", Geometry::SchlickGgx as i32),
        ("BRDF_G_SMITH_BECKMANN", Geometry::SmithBeckmann as i32),
        ("BRDF_F_SCHLICK", Fresnel::Schlick as i32),
        ("BRDF_F_SCHLICK_SG", Fresnel::SchlickSg as i32),
        ("BRDF_F_DIELECTRIC", Fresnel::Dielectric as i32),
        ("BRDF_F_CONDUCTOR", Fresnel::Conductor as i32),
        ("BRDF_F_CONDUCTOR_EXACT", Fresnel::ConductorExact as i32),
        ("BRDF_DIFFUSE_LAMBERT", Diffuse::Lambert as i32),
        ("BRDF_DIFFUSE_BURLEY", Diffuse::Burley as i32),
    ]
    .into_iter()
    .zip(generated)
    {
        assert!(glsl.contains(&format!("#define {name} {code}\n")), "{name}");
        assert_eq!(code, generated, "{name}");
    }
    let terms = include_str!("../../../../shaders_glsl/brdf/terms.glsl");
    assert!(terms.contains("#define BRDF_ALPHA_MIN 1e-3\n") && ALPHA_MIN == 1e-3);
    assert!(terms.contains("#define BRDF_COS_EPS 1e-4\n") && COS_EPS == 1e-4);
    assert!(terms.contains("#define BRDF_LEN2_EPS 1e-12\n") && LEN2_EPS == 1e-12);
    assert!(terms.contains("#define BRDF_IOR_MAX 1e9\n") && IOR_MAX == 1e9);
    use crate::glsl::brdf_terms as t;
    assert_eq!(
        [ALPHA_MIN, COS_EPS, LEN2_EPS, IOR_MAX],
        [
            t::BRDF_ALPHA_MIN,
            t::BRDF_COS_EPS,
            t::BRDF_LEN2_EPS,
            t::BRDF_IOR_MAX
        ]
        .map(|v| v as f32)
    );
}

/// Found by `luz stability`: indices whose squares overflow f32 gave NaN (conductor, complex F0),
/// and index matching (η = 1) gave F ≈ 1e-4 at grazing incidence from cancellation.
#[test]
fn fresnel_extreme_indices_stay_finite() {
    for x in [1e20, 3e38, f32::MAX] {
        for c in [0.0, 1e-6, 1e-4, 1e-3, 0.5, 1.0] {
            // The η → ∞ limit is a perfect mirror; within 1e-4 of it from cos θ = 1e-4 on.
            let low = if c >= 1e-4 { 0.9999 } else { 0.0 };
            for (what, f) in [
                ("conductor η", f_conductor_1(c, x, 0.0)),
                ("conductor κ", f_conductor_1(c, 1.0, x)),
                ("dielectric η", f_dielectric(c, x)),
            ] {
                assert!(
                    f.is_finite() && f >= low && f <= 1.0,
                    "{what}={x} c={c}: {f}"
                );
            }
        }
        let f0 = ComplexIor {
            eta: Vec3::new(x, 1.0, 0.0),
            k: Vec3::new(0.0, x, 0.0),
        }
        .f0();
        assert!(
            f0.is_finite() && f0.cmple(Vec3::ONE).all(),
            "f0 of {x}: {f0}"
        );
        assert!(
            f0.x > 0.9999 && f0.y > 0.9999 && f0.z == 1.0,
            "f0 of {x}: {f0}"
        );
    }
    for c in [1e-6, 1e-3, 0.5, 1.0] {
        assert_eq!(f_dielectric(c, 1.0), 0.0, "index matching at cos θ = {c}");
    }
}

#[test]
fn sampling_helpers() {
    assert_eq!(radical_inverse_vdc(0), 0.0);
    assert_eq!(radical_inverse_vdc(1), 0.5);
    assert_eq!(radical_inverse_vdc(2), 0.25);
    assert_eq!(radical_inverse_vdc(3), 0.75);
    assert!(radical_inverse_vdc(u32::MAX) < 1.0);
    assert_eq!(hammersley(4, 8), (0.5, 0.125));
    // The MODELS.md GGX sampling and the slope-space sampler draw the same distribution:
    // compare the mean of cosθ_h over a Hammersley set.
    for a in [0.1f32, 0.5, 1.0] {
        let n = 4096;
        let (mut m1, mut m2) = (0.0f64, 0.0f64);
        for i in 0..n {
            let (u1, u2) = hammersley(i, n);
            m1 += importance_sample_ggx(u2, u1, a).z as f64;
            m2 += sample_ggx_aniso_h(u1, u2, a, a).z as f64;
        }
        assert!((m1 - m2).abs() / (n as f64) < 2e-3, "{a}: {m1} {m2}");
    }
    let (t, b) = ortho_basis(Vec3::new(0.0, 0.0, -1.0));
    assert!(t.dot(b).abs() < 1e-6 && t.length() > 0.999);
}

// ---------------------------------------------------------------------------------------------
// Energy: directional albedo over parameter grids
// ---------------------------------------------------------------------------------------------

const COS_L: [f32; 5] = [1.0, 0.866, 0.5, 0.174, 0.017];

fn max_albedo(m: &Model, samples: u32) -> (f32, f32) {
    let mut best = (0.0f32, 1.0f32);
    for c in COS_L {
        let r = directional_albedo(m, c, samples).max_element();
        if r > best.0 {
            best = (r, c);
        }
    }
    best
}

/// Fast energy checks (the full tables are in `albedo_report`).
#[test]
fn energy_conservation_where_expected() {
    // Metal-rough, white metal, height-correlated Smith: single scattering only loses energy.
    for r in [0.0, 0.2, 0.5, 1.0] {
        let m = Model::MetalRough(MetalRoughParams {
            roughness: r,
            ..Default::default()
        });
        let (a, c) = max_albedo(&m, 2048);
        assert!(a <= 1.0 + 2e-3, "metal-rough r {r}: {a} at cos {c}");
        if r == 0.0 {
            // A mirror reflects everything it sees (F → 1 at grazing is Schlick with F0 = 1).
            assert!(a > 0.98, "{a}");
        }
    }
    // Metal-rough with Burley's diffuse: metallic 1 has no diffuse, so the choice changes
    // nothing; metallic 0 (white) darkens at roughness 0 (Fd90 = 0.5) and, at roughness 1,
    // brightens near grazing (Fd90 up to 2.5) beyond Lambert's.
    for r in [0.0, 0.5, 1.0] {
        let lambert = MetalRoughParams {
            roughness: r,
            ..Default::default()
        };
        let burley = MetalRoughParams {
            diffuse: Diffuse::Burley,
            ..lambert
        };
        for (dl, dv) in [(dir(30.0, 0.0), dir(60.0, 120.0)), (dir(80.0, 10.0), N)] {
            assert_eq!(
                eval(&Model::MetalRough(lambert), N, dl, dv, X, Y),
                eval(&Model::MetalRough(burley), N, dl, dv, X, Y)
            );
        }
    }
    let white_dielectric = |r: f32, diffuse: Diffuse| {
        Model::MetalRough(MetalRoughParams {
            metallic: 0.0,
            roughness: r,
            diffuse,
            ..Default::default()
        })
    };
    let grazing = 0.174;
    let al0 = directional_albedo(&white_dielectric(0.0, Diffuse::Lambert), grazing, 2048).x;
    let ab0 = directional_albedo(&white_dielectric(0.0, Diffuse::Burley), grazing, 2048).x;
    assert!(ab0 < al0, "r 0: burley {ab0} lambert {al0}");
    let al1 = directional_albedo(&white_dielectric(1.0, Diffuse::Lambert), grazing, 2048).x;
    let ab1 = directional_albedo(&white_dielectric(1.0, Diffuse::Burley), grazing, 2048).x;
    assert!(ab1 > al1, "r 1: burley {ab1} lambert {al1}");
    // Oren-Nayar and Burley-based diffuse stay near 1 for white albedo.
    let on = Model::OrenNayar(OrenNayarParams {
        albedo: Vec3::ONE,
        sigma_deg: 30.0,
    });
    assert!(max_albedo(&on, 1024).0 < 1.0);
    // Phong with the slides' intensities gains energy: its diffuse alone reflects π k_d O_d.
    let ph = Model::Phong(PhongParams {
        diffuse_color: Vec3::ONE,
        kd: 0.8,
        ks: 0.0,
        ..Default::default()
    });
    let r = directional_albedo(&ph, 1.0, 1024).x;
    assert!((r - PI * 0.8).abs() < 1e-3, "{r}");
    // Principled with white base colour and full sheen exceeds 1 (an artistic term).
    let pr = Model::Principled(PrincipledParams {
        base_color: Vec3::ONE,
        roughness: 1.0,
        sheen: 1.0,
        ..Default::default()
    });
    assert!(max_albedo(&pr, 2048).0 > 1.0);
    // The integrator agrees with itself at twice the samples (convergence).
    for m in [pr, Model::CookTorrance(CookTorranceParams::default())] {
        for c in [1.0, 0.3] {
            let a = directional_albedo(&m, c, 4096);
            let b = directional_albedo(&m, c, 8192);
            assert!((a - b).abs().max_element() < 2e-3, "{m:?} {c}: {a} {b}");
        }
    }
}

fn report_grid(name: &str, models: Vec<(String, Model)>, samples: u32) {
    let mut rows: Vec<(f32, f32, String)> = models
        .into_iter()
        .map(|(label, m)| {
            let (a, c) = max_albedo(&m, samples);
            (a, c, label)
        })
        .collect();
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    let over: Vec<_> = rows.iter().filter(|r| r.0 > 1.0 + 1e-3).collect();
    println!(
        "\n## {name}: {} parameter sets, max albedo {:.4} ({}, cos θl = {}); {} gain energy",
        rows.len(),
        rows[0].0,
        rows[0].2,
        rows[0].1,
        over.len()
    );
    for r in rows.iter().take(12) {
        println!("  {:8.4}  cosθl={:<6} {}", r.0, r.1, r.2);
    }
    if let Some(min) = rows.last() {
        println!("  ... lowest max {:.4} ({})", min.0, min.2);
    }
}

/// Prints the albedo tables of docs/brdf.md. Slow-ish; run with `--ignored --nocapture`.
#[test]
#[ignore]
fn albedo_report() {
    let samples = 8192;
    let rough = [0.0, 0.1, 0.25, 0.5, 0.75, 1.0];

    // Lambert and Oren-Nayar.
    let mut v = vec![(
        "lambert albedo 1".to_string(),
        Model::Lambert(LambertParams { albedo: Vec3::ONE }),
    )];
    for s in [0.0, 10.0, 20.0, 30.0, 45.0, 60.0, 90.0] {
        v.push((
            format!("oren_nayar sigma {s}°"),
            Model::OrenNayar(OrenNayarParams {
                albedo: Vec3::ONE,
                sigma_deg: s,
            }),
        ));
    }
    report_grid("lambert / oren_nayar (albedo 1)", v, samples);

    // Phong / Blinn-Phong.
    let mut v = vec![];
    for blinn in [false, true] {
        for kd in [0.0, 0.4, 0.8] {
            for ks in [0.0, 0.4, 0.8] {
                for n in [1.0, 5.0, 20.0, 40.0, 100.0] {
                    v.push((
                        format!(
                            "{} kd {kd} ks {ks} n {n}",
                            if blinn { "blinn" } else { "phong" }
                        ),
                        Model::Phong(PhongParams {
                            kd,
                            ks,
                            shininess: n,
                            blinn,
                            ..Default::default()
                        }),
                    ));
                }
            }
        }
    }
    report_grid("phong / blinn_phong (O_d = O_s = 1)", v, samples);

    // Cook-Torrance: every D × G × F, k_d sweep, F0 = 1 (worst case) and glass.
    for (sname, source) in [
        ("F0=1", SpecularSource::F0(Vec3::ONE)),
        ("ior 1.5", SpecularSource::Ior(1.5)),
        (
            "gold",
            SpecularSource::Complex(metal_preset("gold").unwrap()),
        ),
    ] {
        let mut v = vec![];
        for d in Distribution::ALL {
            for g in Geometry::ALL {
                for f in Fresnel::ALL {
                    for kd in [0.0, 0.5, 1.0] {
                        for r in rough {
                            v.push((
                                format!("{d:?} {g:?} {f:?} kd {kd} r {r}"),
                                Model::CookTorrance(CookTorranceParams {
                                    color: Vec3::ONE,
                                    kd,
                                    roughness: r,
                                    specular: source,
                                    distribution: d,
                                    geometry: g,
                                    fresnel: f,
                                    diffuse: Diffuse::Lambert,
                                }),
                            ));
                        }
                    }
                }
            }
        }
        report_grid(&format!("cook_torrance ({sname}, white)"), v, samples);
    }
    // Cook-Torrance defaults only (Beckmann, CT G, Schlick), specular alone with F0 = 1.
    let mut v = vec![];
    for r in rough {
        v.push((
            format!("defaults kd 0 F0=1 r {r}"),
            Model::CookTorrance(CookTorranceParams {
                kd: 0.0,
                roughness: r,
                specular: SpecularSource::F0(Vec3::ONE),
                ..Default::default()
            }),
        ));
    }
    report_grid("cook_torrance defaults, specular only, F = 1", v, samples);

    // Metal-rough.
    let mut v = vec![];
    for d in Distribution::ALL {
        for g in Geometry::ALL {
            for w in [false, true] {
                for diffuse in Diffuse::ALL {
                    for metallic in [0.0, 0.5, 1.0] {
                        for r in rough {
                            v.push((
                                format!(
                                    "{d:?} {g:?} (1-F) {w} {diffuse:?} metallic {metallic} r {r}"
                                ),
                                Model::MetalRough(MetalRoughParams {
                                    base_color: Vec3::ONE,
                                    metallic,
                                    roughness: r,
                                    distribution: d,
                                    geometry: g,
                                    fresnel: Fresnel::Schlick,
                                    diffuse_fresnel_weight: w,
                                    diffuse,
                                    ..MetalRoughParams::default()
                                }),
                            ));
                        }
                    }
                }
            }
        }
    }
    report_grid("metal_rough (white, Schlick)", v, samples);
    let mut v = vec![];
    for w in [false, true] {
        for diffuse in Diffuse::ALL {
            for metallic in [0.0, 1.0] {
                for r in rough {
                    v.push((
                        format!("defaults (1-F) {w} {diffuse:?} metallic {metallic} r {r}"),
                        Model::MetalRough(MetalRoughParams {
                            base_color: Vec3::ONE,
                            metallic,
                            roughness: r,
                            diffuse_fresnel_weight: w,
                            diffuse,
                            ..Default::default()
                        }),
                    ));
                }
            }
        }
    }
    report_grid(
        "metal_rough defaults (GGX, correlated Smith, Schlick), white",
        v,
        samples,
    );

    // Principled: every parameter at 0 / 1 (specular 0, 0.5, 1), white base colour.
    let mut v = vec![];
    for bits in 0..256u32 {
        let b = |k: u32| if bits & (1 << k) != 0 { 1.0 } else { 0.0 };
        for r in [0.0, 0.5, 1.0] {
            for spec in [0.0, 0.5, 1.0] {
                let p = PrincipledParams {
                    base_color: Vec3::ONE,
                    subsurface: b(0),
                    metallic: b(1),
                    specular: spec,
                    specular_tint: b(2),
                    roughness: r,
                    anisotropic: b(3),
                    sheen: b(4),
                    sheen_tint: b(5),
                    clearcoat: b(6),
                    clearcoat_gloss: b(7),
                };
                v.push((
                    format!(
                        "ss {} metal {} spec {} tint {} r {} aniso {} sheen {} stint {} cc {} ccg {}",
                        p.subsurface,
                        p.metallic,
                        p.specular,
                        p.specular_tint,
                        p.roughness,
                        p.anisotropic,
                        p.sheen,
                        p.sheen_tint,
                        p.clearcoat,
                        p.clearcoat_gloss
                    ),
                    Model::Principled(p),
                ));
            }
        }
    }
    report_grid("principled (white base colour)", v, 4096);
    // Principled, one parameter at a time from the defaults with white base colour.
    let base = PrincipledParams {
        base_color: Vec3::ONE,
        ..Default::default()
    };
    let mut v = vec![("defaults, white".to_string(), Model::Principled(base))];
    for r in [0.0, 0.5, 1.0] {
        v.push((
            format!("roughness {r}"),
            Model::Principled(PrincipledParams {
                roughness: r,
                ..base
            }),
        ));
        v.push((
            format!("subsurface 1 roughness {r}"),
            Model::Principled(PrincipledParams {
                roughness: r,
                subsurface: 1.0,
                ..base
            }),
        ));
        v.push((
            format!("sheen 1 roughness {r}"),
            Model::Principled(PrincipledParams {
                roughness: r,
                sheen: 1.0,
                ..base
            }),
        ));
        v.push((
            format!("clearcoat 1 roughness {r}"),
            Model::Principled(PrincipledParams {
                roughness: r,
                clearcoat: 1.0,
                ..base
            }),
        ));
        v.push((
            format!("specular 1 roughness {r}"),
            Model::Principled(PrincipledParams {
                roughness: r,
                specular: 1.0,
                ..base
            }),
        ));
        v.push((
            format!("metallic 1 roughness {r}"),
            Model::Principled(PrincipledParams {
                roughness: r,
                metallic: 1.0,
                ..base
            }),
        ));
    }
    report_grid("principled one at a time (white)", v, samples);

    // Albedo vs angle for a few reference materials.
    println!("\n## albedo vs cos θl = 1, 0.866, 0.5, 0.174, 0.017 (R channel)");
    let refs = [
        (
            "lambert",
            Model::Lambert(LambertParams { albedo: Vec3::ONE }),
        ),
        (
            "metal_rough white metal r 0.5",
            Model::MetalRough(MetalRoughParams {
                roughness: 0.5,
                ..Default::default()
            }),
        ),
        (
            "metal_rough white dielectric r 0.5",
            Model::MetalRough(MetalRoughParams {
                roughness: 0.5,
                metallic: 0.0,
                ..Default::default()
            }),
        ),
        (
            "principled white defaults",
            Model::Principled(PrincipledParams {
                base_color: Vec3::ONE,
                ..Default::default()
            }),
        ),
        (
            "principled white roughness 1",
            Model::Principled(PrincipledParams {
                base_color: Vec3::ONE,
                roughness: 1.0,
                ..Default::default()
            }),
        ),
        (
            "principled white subsurface 1 roughness 0",
            Model::Principled(PrincipledParams {
                base_color: Vec3::ONE,
                roughness: 0.0,
                subsurface: 1.0,
                ..Default::default()
            }),
        ),
        (
            "principled white sheen 1 roughness 1",
            Model::Principled(PrincipledParams {
                base_color: Vec3::ONE,
                roughness: 1.0,
                sheen: 1.0,
                ..Default::default()
            }),
        ),
        (
            "principled white clearcoat 1 (gloss 1)",
            Model::Principled(PrincipledParams {
                base_color: Vec3::ONE,
                clearcoat: 1.0,
                ..Default::default()
            }),
        ),
        (
            "principled white metallic 1 roughness 0.5",
            Model::Principled(PrincipledParams {
                base_color: Vec3::ONE,
                metallic: 1.0,
                ..Default::default()
            }),
        ),
        (
            "oren_nayar albedo 1 sigma 10°",
            Model::OrenNayar(OrenNayarParams {
                albedo: Vec3::ONE,
                sigma_deg: 10.0,
            }),
        ),
        (
            "oren_nayar albedo 1 sigma 30°",
            Model::OrenNayar(OrenNayarParams {
                albedo: Vec3::ONE,
                sigma_deg: 30.0,
            }),
        ),
        (
            "cook_torrance defaults",
            Model::CookTorrance(CookTorranceParams::default()),
        ),
        ("phong defaults", Model::Phong(PhongParams::default())),
        (
            "phong O_d=O_s=1 kd 0.8 ks 0.7 n 20",
            Model::Phong(PhongParams {
                diffuse_color: Vec3::ONE,
                kd: 0.8,
                ks: 0.7,
                shininess: 20.0,
                ..Default::default()
            }),
        ),
    ];
    for (name, m) in refs {
        let row: Vec<String> = [1.0, 0.866, 0.5, 0.174, 0.017]
            .iter()
            .map(|&c| format!("{:.4}", directional_albedo(&m, c, samples).x))
            .collect();
        println!("  {name:40} {}", row.join("  "));
    }
}

/// Each model kind: its name is the serde tag of its default model, `kind()` gives it back, its
/// code is the GLSL `BRDF_MODEL_*`, and the names parse back; the same for every selector.
#[test]
fn model_kinds_and_selector_names_have_one_source() {
    use crate::glsl::brdf_models as g;
    let codes = [
        g::BRDF_MODEL_LAMBERT,
        g::BRDF_MODEL_PHONG,
        g::BRDF_MODEL_BLINN_PHONG,
        g::BRDF_MODEL_COOK_TORRANCE,
        g::BRDF_MODEL_METAL_ROUGH,
        g::BRDF_MODEL_PRINCIPLED,
        g::BRDF_MODEL_OREN_NAYAR,
    ];
    for (kind, code) in ModelKind::ALL.into_iter().zip(codes) {
        let m = Model::default_of(kind);
        assert_eq!(m.kind(), kind);
        assert_eq!(m.name(), kind.name());
        let json = serde_json::to_value(m).unwrap();
        assert_eq!(json["model"].as_str(), Some(kind.name()), "{json}");
        assert_eq!(kind.code(), code, "{kind:?}");
        assert_eq!(GpuBrdfParams::from_model(&m).sel[0], code);
        assert_eq!(ModelKind::from_name(kind.name()), Some(kind));
    }
    fn serde_names<T: serde::Serialize + Copy + PartialEq + std::fmt::Debug>(
        named: &[(&str, T)],
        from_name: fn(&str) -> Option<T>,
    ) {
        for (name, v) in named {
            assert_eq!(serde_json::to_value(v).unwrap().as_str(), Some(*name));
            assert_eq!(from_name(name), Some(*v));
        }
        assert_eq!(from_name("bogus"), None);
    }
    serde_names(&Distribution::NAMED, Distribution::from_name);
    serde_names(&Geometry::NAMED, Geometry::from_name);
    serde_names(&Fresnel::NAMED, Fresnel::from_name);
    serde_names(&Diffuse::NAMED, Diffuse::from_name);
}

/// Issue 34's furnace, on the CPU model: with energy compensation a white metal-rough surface
/// (metallic 0 and 1) reflects 1 ± 1 % of a uniform environment for roughness 0.05–1 and views
/// to 85° (`∫ f(l, v) cos θ_l dω_l`, MIS over the cosine and GGX lobes, 2^14 points); without it
/// the white dielectric reflects more than 1 (its diffuse is not weighted by what the specular
/// already reflects: 1.03–1.04 at normal view) and the rough white metal less.
#[test]
fn energy_compensation_makes_a_white_furnace() {
    let furnace = |metallic: f32, roughness: f32, view_deg: f32, on: bool| {
        white_furnace(
            MetalRoughParams {
                base_color: Vec3::ONE,
                metallic,
                roughness,
                energy_compensation: on,
                ..MetalRoughParams::default()
            },
            view_deg,
        )
    };
    let mut worst = (0.0f32, 0.0, 0.0, 0.0, 0.0);
    for metallic in [0.0, 1.0] {
        for roughness in [0.05, 0.1, 0.25, 0.5, 0.75, 1.0] {
            for view in [0.0, 30.0, 60.0, 75.0, 85.0] {
                let e = furnace(metallic, roughness, view, true);
                if (e - 1.0).abs() > worst.0 {
                    worst = ((e - 1.0).abs(), metallic, roughness, view, e);
                }
            }
        }
    }
    eprintln!(
        "compensated furnace: worst |E − 1| = {:.4} (metallic {}, roughness {}, view {}°: {:.4})",
        worst.0, worst.1, worst.2, worst.3, worst.4
    );
    assert!(worst.0 <= 0.01, "{worst:?}");
    let dielectric = furnace(0.0, 0.5, 0.0, false);
    assert!(
        dielectric > 1.02,
        "uncompensated white dielectric: {dielectric}"
    );
    let rough_metal = furnace(1.0, 1.0, 0.0, false);
    assert!(
        rough_metal < 0.9,
        "uncompensated rough white metal: {rough_metal}"
    );
}

/// The white furnace of a metal-rough material seen at `view_deg` from the normal: the
/// hemispherical integral of `f · n·l` (importance sampled), red channel.
fn white_furnace(p: MetalRoughParams, view_deg: f32) -> f32 {
    white_furnace_rgb(p, view_deg).x
}

/// [`white_furnace`] in every channel (a film or a coloured layer makes them differ).
fn white_furnace_rgb(p: MetalRoughParams, view_deg: f32) -> Vec3 {
    let model = Model::MetalRough(p);
    let (s, c) = view_deg.to_radians().sin_cos();
    let v = Vec3::new(s, 0.0, c);
    let lobes = sampling_lobes(&model);
    integrate_hemisphere(
        |l| eval(&model, Vec3::Z, l, v, Vec3::X, Vec3::Y),
        v,
        &lobes,
        1 << 14,
    )
}

/// Issue 34, KHR_materials_clearcoat: with energy compensation a white furnace stays 1 ± 1 %
/// under any coat (weight 0.5 and 1, coat roughness 0.05–1) over a white dielectric and a white
/// metal of roughness 0.05–1, at views to 85° (measured worst 0.07 %, 0.93 % before the split-sum
/// table's fix of 2026-11-29); without it a rough coat
/// over a smooth white metal returns 0.97.
#[test]
fn clearcoat_keeps_a_compensated_white_furnace() {
    let mut worst = (0.0f32, [0.0f32; 5]);
    for metallic in [0.0, 1.0] {
        for roughness in [0.05, 0.5, 1.0] {
            for clearcoat in [0.5, 1.0] {
                for coat_roughness in [0.05, 0.3, 1.0] {
                    for view in [0.0, 45.0, 75.0, 85.0] {
                        let e = white_furnace(
                            MetalRoughParams {
                                base_color: Vec3::ONE,
                                metallic,
                                roughness,
                                clearcoat,
                                clearcoat_roughness: coat_roughness,
                                energy_compensation: true,
                                ..MetalRoughParams::default()
                            },
                            view,
                        );
                        if (e - 1.0).abs() > worst.0 {
                            worst = (
                                (e - 1.0).abs(),
                                [metallic, roughness, clearcoat, coat_roughness, view],
                            );
                        }
                    }
                }
            }
        }
    }
    eprintln!("clearcoat furnace: worst |E − 1| = {:.4} at (metallic, roughness, clearcoat, coat roughness, view°) {:?}", worst.0, worst.1);
    assert!(worst.0 <= 0.01, "{worst:?}");
    let uncompensated = white_furnace(
        MetalRoughParams {
            base_color: Vec3::ONE,
            metallic: 1.0,
            roughness: 0.05,
            clearcoat: 1.0,
            clearcoat_roughness: 1.0,
            ..MetalRoughParams::default()
        },
        0.0,
    );
    eprintln!("clearcoat furnace without compensation (white metal 0.05, coat 1 of roughness 1): {uncompensated:.4}");
    // Measured 0.972: the rough coat loses its multiple scattering.
    assert!(uncompensated < 0.98, "{uncompensated}");
}

/// KHR_materials_clearcoat against its formula: no coat is the base exactly; a coat of the
/// base's roughness over a black dielectric (whose specular is the coat's lobe itself) gives
/// `f_coat (1 − Fc) + f_coat`, with Fc Schlick's F of F0 0.04 at n·v.
#[test]
fn clearcoat_layers_as_the_extension_says() {
    let n = Vec3::Z;
    let l = Vec3::new(0.3, -0.2, 0.8).normalize();
    let v = Vec3::new(-0.5, 0.1, 0.6).normalize();
    let base = MetalRoughParams {
        base_color: Vec3::new(0.7, 0.3, 0.2),
        metallic: 0.3,
        roughness: 0.4,
        ..MetalRoughParams::default()
    };
    let uncoated = metal_rough(&base, n, l, v);
    let zero = MetalRoughParams {
        clearcoat_roughness: 0.7,
        ..base
    };
    assert_eq!(metal_rough(&zero, n, l, v), uncoated);
    let black = MetalRoughParams {
        base_color: Vec3::ZERO,
        metallic: 0.0,
        roughness: 0.3,
        clearcoat: 1.0,
        clearcoat_roughness: 0.3,
        ..MetalRoughParams::default()
    };
    let h = (l + v).normalize();
    let a = 0.09f32;
    let f_coat = d_ggx(n.dot(h), a) * g_smith_ggx_correlated(n.dot(l), n.dot(v), a)
        / (4.0 * n.dot(l) * n.dot(v))
        * (0.04 + 0.96 * (1.0 - v.dot(h)).powi(5));
    let fc = 0.04 + 0.96 * (1.0 - n.dot(v)).powi(5);
    let expected = f_coat * (2.0 - fc);
    let got = metal_rough(&black, n, l, v);
    for c in 0..3 {
        assert!(
            (got[c] - expected).abs() <= 1e-5 * expected,
            "{got} against {expected}"
        );
    }
    // Half a coat: the base's lobe weighted by 1 − Fc/2, plus half the coat's.
    let half = MetalRoughParams {
        clearcoat: 0.5,
        clearcoat_roughness: 0.6,
        ..base
    };
    let coat = clearcoat_specular(&half, n, l, v);
    let expected = uncoated * (1.0 - 0.5 * fc) + Vec3::splat(0.5 * coat);
    let got = metal_rough(&half, n, l, v);
    assert!(
        (got - expected).abs().max_element() <= 1e-6,
        "{got} against {expected}"
    );
    assert!(coat > 0.0, "{coat}");
}

/// Issue 34: Beckmann's own Smith G1 (Walter et al. 2007's rational approximation) is within
/// 0.35 % of the exact `2/(1 + erf(a) + e^{−a²}/(a√π))` at every angle and width, and differs
/// from the Smith GGX form at the Beckmann width (what luz used before) by several percent at
/// grazing.
#[test]
fn smith_beckmann_matches_the_exact_g1() {
    // erf by Simpson's rule on e^{−t²} (2,000 intervals: far below 1e-6 for |x| ≤ 10).
    let erf = |x: f64| {
        let n = 2000;
        let h = x / n as f64;
        let f = |t: f64| (-t * t).exp();
        let mut s = f(0.0) + f(x);
        for i in 1..n {
            s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0 * 2.0 / std::f64::consts::PI.sqrt()
    };
    let exact = |c: f64, m: f64| {
        let a = c / (m * (1.0 - c * c).sqrt());
        2.0 / (1.0 + erf(a) + (-a * a).exp() / (a * std::f64::consts::PI.sqrt()))
    };
    let (mut worst, mut most_apart) = (0.0f64, 0.0f64);
    for m in [0.05, 0.1, 0.3, 0.5, 0.7, 1.0] {
        for c in [0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.99] {
            let g = g1_smith_beckmann(c as f32, m as f32) as f64;
            let e = exact(c, m);
            worst = worst.max((g - e).abs() / e);
            let ggx = g1_smith_ggx(c as f32, m as f32) as f64;
            most_apart = most_apart.max((ggx - e).abs() / e);
        }
    }
    eprintln!("Smith Beckmann G1: worst relative error {worst:.2e}; GGX form at the Beckmann width up to {most_apart:.3} off");
    assert!(worst < 3.5e-3, "{worst}");
    assert!(most_apart > 0.02, "{most_apart}");
    assert_eq!(g1_smith_beckmann(1.0, 0.5), 1.0);
    assert_eq!(g1_smith_beckmann(0.0, 0.5), 0.0);
    assert_eq!(g1_smith_beckmann(-0.5, 0.5), 0.0);
    assert!(g1_smith_beckmann(0.3, f32::NAN).is_finite());
}

/// Issue 34: the exact conductor Fresnel equals the Fresnel equations evaluated with complex
/// arithmetic (r_s, r_p from the complex refraction cosine, in f64) to 1e-5 at every angle for
/// gold, aluminium and a dielectric-like index; the usual approximation (`f_conductor`) is up to
/// about 1 % away from it for gold.
#[test]
fn exact_conductor_fresnel_is_the_fresnel_equations() {
    #[derive(Clone, Copy)]
    struct C(f64, f64);
    let mul = |a: C, b: C| C(a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let div = |a: C, b: C| {
        let d = b.0 * b.0 + b.1 * b.1;
        C((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
    };
    let sqrt = |a: C| {
        let r = (a.0 * a.0 + a.1 * a.1).sqrt();
        let re = ((r + a.0) / 2.0).max(0.0).sqrt();
        let im = ((r - a.0) / 2.0).max(0.0).sqrt().copysign(a.1);
        C(re, im)
    };
    let norm2 = |a: C| a.0 * a.0 + a.1 * a.1;
    let fresnel = |cos_i: f64, eta: f64, k: f64| {
        let n = C(eta, k);
        let sin2 = 1.0 - cos_i * cos_i;
        // cos_t = sqrt(1 − sin²θ / n²)
        let n2 = mul(n, n);
        let cos_t = sqrt(C(1.0, 0.0).sub_from(div(C(sin2, 0.0), n2)));
        let ci = C(cos_i, 0.0);
        let nct = mul(n, cos_t);
        let rs = div(C(ci.0 - nct.0, -nct.1), C(ci.0 + nct.0, nct.1));
        let nci = mul(n, ci);
        let rp = div(
            C(nci.0 - cos_t.0, nci.1 - cos_t.1),
            C(nci.0 + cos_t.0, nci.1 + cos_t.1),
        );
        0.5 * (norm2(rs) + norm2(rp))
    };
    trait SubFrom {
        fn sub_from(self, b: C) -> C;
    }
    impl SubFrom for C {
        fn sub_from(self, b: C) -> C {
            C(self.0 - b.0, self.1 - b.1)
        }
    }
    let gold = metal_preset("gold").unwrap();
    let aluminium = metal_preset("aluminium").unwrap();
    let (mut worst, mut approx_off) = (0.0f64, 0.0f64);
    for (eta, k) in [
        (gold.eta.x, gold.k.x),
        (gold.eta.z, gold.k.z),
        (aluminium.eta.y, aluminium.k.y),
        (1.5, 0.0),
    ] {
        for i in 0..=100 {
            let c = i as f64 / 100.0;
            let want = fresnel(c.max(1e-9), eta as f64, k as f64);
            let got = f_conductor_exact_1(c as f32, eta, k) as f64;
            worst = worst.max((got - want).abs());
            if k > 0.0 && eta < 1.0 {
                let approx = f_conductor_1(c as f32, eta, k) as f64;
                approx_off = approx_off.max((approx - want).abs() / want.max(1e-6));
            }
        }
    }
    eprintln!("exact conductor Fresnel: worst |F − F_complex| {worst:.2e}; the approximation up to {:.2} % off for gold", approx_off * 100.0);
    assert!(worst < 1e-5, "{worst}");
    assert!(approx_off > 1e-3, "{approx_off}");
}

/// KHR_materials_sheen's albedo fit (`shaders_glsl/brdf/sheen_albedo.glsl`): the file is what
/// the generator writes for its coefficients (so the GLSL evaluates what the CPU does), and on a
/// 64 × 34 grid off the fit's nodes (roughness 0–1, √(n·v) 0–1 at (i + 0.5)/64, views to 89°)
/// it stays within 0.0075 of the lobe's integral (measured 0.0068, RMS 0.0039, with 10 × 8
/// terms; the 8 × 7 fit before 2026-11-29: 0.0116, RMS 0.0056) (the 32 × 32 bilinear table it replaces was
/// within 0.01 between its nodes at views to 85°): that difference is all a white furnace can
/// gain or lose from the sheen's albedo scaling.
#[test]
fn sheen_albedo_fit_is_the_integral() {
    let c = sheen_albedo_fit();
    assert_eq!(
        crate::brdf::models::layers::SHEEN_ALBEDO_GLSL,
        sheen_albedo_glsl_source(c),
        "sheen_albedo.glsl is not the generator's output (cargo run --release -p luz-core --example sheen_fit)"
    );
    let (mut worst, mut at) = (0.0f32, (0.0f32, 0.0f32));
    let (mut sum, mut count) = (0.0f64, 0);
    for j in 0..34 {
        let r = j as f32 / 33.0;
        for i in 0..64 {
            let x = (i as f32 + 0.5) / 64.0;
            let n_v = x * x;
            if n_v < 89f32.to_radians().cos() {
                continue;
            }
            let d = (sheen_albedo(n_v, r) - sheen_albedo_integrated(n_v, r)).abs();
            sum += (d * d) as f64;
            count += 1;
            if d > worst {
                (worst, at) = (d, (n_v, r));
            }
        }
    }
    let rms = (sum / count as f64).sqrt();
    eprintln!(
        "sheen albedo fit: within {worst:.4} of the integral (n·v {:.3}, roughness {:.3}), RMS {rms:.5} over {count} points",
        at.0, at.1
    );
    assert!(worst <= 0.0075, "{worst} at {at:?}");
    assert!(rms <= 0.0045, "{rms}");
    // Not a fit of zeros: a rough sheen reflects a fair part at normal view, a smooth one none.
    assert!(sheen_albedo(1.0, 1.0) > 0.1, "{}", sheen_albedo(1.0, 1.0));
    assert!(sheen_albedo(1.0, 0.0) < 1e-3, "{}", sheen_albedo(1.0, 0.0));
}

/// Issue 34, KHR_materials_sheen: a white sheen of any roughness over a white dielectric or
/// metal keeps the compensated white furnace at 1 ± 1 % (roughness 0.05–1, views to 85°), with
/// the clear coat on top too; the sheen is not negligible (it changes the BRDF at grazing by
/// more than 10 %).
#[test]
fn sheen_keeps_a_compensated_white_furnace() {
    let mut worst = (0.0f32, [0.0f32; 5]);
    for metallic in [0.0, 1.0] {
        for roughness in [0.05, 0.5, 1.0] {
            for sheen_roughness in [0.0, 0.3, 0.7, 1.0] {
                for clearcoat in [0.0, 1.0] {
                    for view in [0.0, 45.0, 75.0, 85.0] {
                        let e = white_furnace(
                            MetalRoughParams {
                                base_color: Vec3::ONE,
                                metallic,
                                roughness,
                                sheen_color: Vec3::ONE,
                                sheen_roughness,
                                clearcoat,
                                clearcoat_roughness: 0.3,
                                energy_compensation: true,
                                ..MetalRoughParams::default()
                            },
                            view,
                        );
                        if (e - 1.0).abs() > worst.0 {
                            worst = (
                                (e - 1.0).abs(),
                                [metallic, roughness, sheen_roughness, clearcoat, view],
                            );
                        }
                    }
                }
            }
        }
    }
    eprintln!("sheen furnace: worst |E − 1| = {:.5} at (metallic, roughness, sheen roughness, clearcoat, view°) {:?}", worst.0, worst.1);
    assert!(worst.0 <= 0.01, "{worst:?}");
    let p = MetalRoughParams {
        base_color: Vec3::new(0.2, 0.3, 0.8),
        metallic: 0.0,
        roughness: 0.6,
        sheen_color: Vec3::new(1.0, 0.8, 0.6),
        sheen_roughness: 0.5,
        ..MetalRoughParams::default()
    };
    let (n, l, v) = (
        Vec3::Z,
        Vec3::new(0.2, 0.1, 0.95).normalize(),
        Vec3::new(-0.95, 0.0, 0.2).normalize(),
    );
    let with = metal_rough(&p, n, l, v);
    let without = metal_rough(
        &MetalRoughParams {
            sheen_color: Vec3::ZERO,
            ..p
        },
        n,
        l,
        v,
    );
    assert!(
        (with - without).abs().max_element() > 0.1 * without.max_element(),
        "{with} against {without}"
    );
}

/// KHR_materials_anisotropy, the lobe's shape: strength 0 is the isotropic material exactly; the
/// anisotropic GGX of equal widths is GGX and its height-correlated Smith term the isotropic one;
/// the stretched D is normalised (∫ D (n·h) dω_h = 1, quadrature); the BRDF stays reciprocal; a
/// rotation of π/2 is the frame turned by π/2; the lobe is wider along t than along b.
#[test]
fn anisotropy_lobe_shape() {
    let base = MetalRoughParams {
        base_color: Vec3::new(0.9, 0.6, 0.3),
        metallic: 1.0,
        roughness: 0.4,
        ..MetalRoughParams::default()
    };
    let mut rng = Rng::new(34);
    for _ in 0..64 {
        let (l, v) = (rng.hemi(), rng.hemi());
        let iso = metal_rough_terms_frame(&base, Vec3::Z, l, v, Vec3::X, Vec3::Y);
        let zero = MetalRoughParams {
            anisotropy_rotation: 1.0,
            ..base
        };
        let z = metal_rough_terms_frame(&zero, Vec3::Z, l, v, Vec3::X, Vec3::Y);
        assert_eq!(iso.total(), z.total());
        let (a, c) = (0.16, l.z);
        let g_iso = g_smith_ggx_correlated(l.z, v.z, a);
        let g_an = g_smith_ggx_correlated_aniso(c, v.z, l.x, l.y, v.x, v.y, a, a);
        assert!(
            (g_iso - g_an).abs() <= 1e-5 * g_iso.max(1e-3),
            "{g_iso} {g_an}"
        );
    }
    // ∫ D(h) (n·h) dω_h over the hemisphere, midpoint rule in (cos θ, φ).
    for (at, ab) in [(0.5, 0.05), (0.9, 0.3), (0.2, 0.2)] {
        let (nt, np) = (2000, 400);
        let mut sum = 0.0f64;
        for i in 0..nt {
            let c = (i as f64 + 0.5) / nt as f64;
            let s = (1.0 - c * c).sqrt();
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                let d = d_gtr2_aniso(
                    c as f32,
                    (s * phi.cos()) as f32,
                    (s * phi.sin()) as f32,
                    at,
                    ab,
                );
                sum += d as f64 * c;
            }
        }
        let integral = sum * std::f64::consts::TAU / (nt * np) as f64;
        assert!((integral - 1.0).abs() < 0.01, "α ({at}, {ab}): {integral}");
    }
    let p = MetalRoughParams {
        anisotropy_strength: 0.8,
        anisotropy_rotation: 0.7,
        ..base
    };
    let turned = MetalRoughParams {
        anisotropy_rotation: 0.7 + std::f32::consts::FRAC_PI_2,
        ..p
    };
    for _ in 0..64 {
        let (l, v) = (rng.hemi(), rng.hemi());
        let f = metal_rough_terms_frame(&p, Vec3::Z, l, v, Vec3::X, Vec3::Y).total();
        let r = metal_rough_terms_frame(&p, Vec3::Z, v, l, Vec3::X, Vec3::Y).total();
        assert!(
            (f - r).abs().max_element() <= 1e-4 * f.max_element().max(1e-3),
            "{f} {r}"
        );
        // x → y, y → −x turns the frame by π/2.
        let g = metal_rough_terms_frame(&turned, Vec3::Z, l, v, Vec3::X, Vec3::Y).total();
        let h = metal_rough_terms_frame(&p, Vec3::Z, l, v, Vec3::Y, -Vec3::X).total();
        assert!(
            (g - h).abs().max_element() <= 1e-4 * g.max_element().max(1e-3),
            "{g} {h}"
        );
    }
    // Off the mirror direction along t the stretched lobe is brighter than along b and than the
    // isotropic lobe; the isotropic lobe is the same both ways.
    let aligned = MetalRoughParams {
        anisotropy_strength: 0.8,
        ..base
    };
    let v = Vec3::new(0.0, 0.0, 1.0);
    let spec = |p: &MetalRoughParams, l: Vec3| {
        metal_rough_terms_frame(p, Vec3::Z, l.normalize(), v, Vec3::X, Vec3::Y)
            .specular
            .x
    };
    let along_t = Vec3::new(0.6f32.sin(), 0.0, 0.6f32.cos());
    let along_b = Vec3::new(0.0, 0.6f32.sin(), 0.6f32.cos());
    assert!(spec(&aligned, along_t) > 3.0 * spec(&aligned, along_b));
    assert!(spec(&aligned, along_t) > 3.0 * spec(&base, along_t));
    let (t_iso, b_iso) = (spec(&base, along_t), spec(&base, along_b));
    assert!((t_iso - b_iso).abs() <= 1e-4 * t_iso, "{t_iso} {b_iso}");
}

/// Issue 34, KHR_materials_anisotropy, the white furnace with energy compensation (the
/// anisotropic lobe's own split sum at the view's azimuth, `aniso_split_sum_ab`) over a white
/// dielectric and metal of roughness 0.05–1, strengths 0.5 and 1, the lobe along and across the
/// view, with and without a coat and a sheen, views to 85°. Measured (2026-11-29, 10 × 8 sheen
/// fit): worst 0.78 % over the whole grid (a metal of roughness 0.3, strength 1, with coat and
/// sheen, 45°; its isotropic twin returns 0.51 %; 1.01 % with the 8 × 7 fit), 0.42 % without
/// coat and sheen; bounds 1 % and 0.5 %. (With the isotropic table at an equivalent
/// roughness it was 0.64–1.40.)
#[test]
fn anisotropy_white_furnace_with_compensation() {
    let mut worst = (0.0f32, [0.0f32; 6]);
    let mut bare = (0.0f32, [0.0f32; 6]);
    for metallic in [0.0, 1.0] {
        for roughness in [0.05, 0.3, 0.6, 1.0] {
            for strength in [0.5, 1.0] {
                for rotation in [0.0, std::f32::consts::FRAC_PI_2] {
                    for layers in [0.0, 1.0] {
                        for view in [0.0, 45.0, 75.0, 85.0] {
                            let e = white_furnace(
                                MetalRoughParams {
                                    base_color: Vec3::ONE,
                                    metallic,
                                    roughness,
                                    anisotropy_strength: strength,
                                    anisotropy_rotation: rotation,
                                    clearcoat: layers,
                                    clearcoat_roughness: 0.3,
                                    sheen_color: Vec3::splat(layers),
                                    sheen_roughness: 0.5,
                                    energy_compensation: true,
                                    ..MetalRoughParams::default()
                                },
                                view,
                            );
                            let at = [metallic, roughness, strength, rotation, layers, view];
                            if (e - 1.0).abs() > worst.0 {
                                worst = ((e - 1.0).abs(), at);
                            }
                            if layers == 0.0 && (e - 1.0).abs() > bare.0 {
                                bare = ((e - 1.0).abs(), at);
                            }
                        }
                    }
                }
            }
        }
    }
    eprintln!("anisotropy furnace: worst |E − 1| = {:.4} at (metallic, roughness, strength, rotation, coat+sheen, view°) {:?}; without coat and sheen: {:.4} at {:?}", worst.0, worst.1, bare.0, bare.1);
    // The worst point's isotropic twin (strength 0): how much of it the coat and sheen's own
    // compensation leaves.
    let [metallic, roughness, _, _, layers, view] = worst.1;
    let twin = white_furnace(
        MetalRoughParams {
            base_color: Vec3::ONE,
            metallic,
            roughness,
            clearcoat: layers,
            clearcoat_roughness: 0.3,
            sheen_color: Vec3::splat(layers),
            sheen_roughness: 0.5,
            energy_compensation: true,
            ..MetalRoughParams::default()
        },
        view,
    );
    eprintln!("its isotropic twin: |E − 1| = {:.4}", (twin - 1.0).abs());
    assert!(bare.0 <= 0.005, "{bare:?}");
    assert!(worst.0 <= 0.01, "{worst:?}");
}

/// Issue 34, KHR_materials_iridescence on metal_rough: factor 0 or thickness 0 is the material
/// without a film exactly; a factor of 1 replaces F by the film's (the specular's ratio to the
/// film-less one is the ratio of the Fresnels at v·h); the film colours a grey dielectric.
#[test]
fn iridescence_replaces_the_fresnel() {
    let base = MetalRoughParams {
        base_color: Vec3::new(0.5, 0.5, 0.5),
        metallic: 0.0,
        roughness: 0.4,
        ..MetalRoughParams::default()
    };
    let mut rng = Rng::new(0x1d);
    for _ in 0..32 {
        let (l, v) = (rng.hemi(), rng.hemi());
        let plain = metal_rough(&base, Vec3::Z, l, v);
        for off in [
            MetalRoughParams {
                iridescence: 0.0,
                iridescence_thickness_max: 300.0,
                ..base
            },
            MetalRoughParams {
                iridescence: 1.0,
                iridescence_thickness_max: 0.0,
                iridescence_thickness_min: 0.0,
                ..base
            },
        ] {
            assert_eq!(metal_rough(&off, Vec3::Z, l, v), plain);
        }
        let film = MetalRoughParams {
            iridescence: 1.0,
            iridescence_thickness_max: 300.0,
            ..base
        };
        let t = metal_rough_terms(&film, Vec3::Z, l, v);
        let t0 = metal_rough_terms(&base, Vec3::Z, l, v);
        let v_h = v.dot((l + v).normalize());
        let want = super::iridescence::iridescence_fresnel(1.0, 1.3, v_h, 300.0, Vec3::splat(0.04));
        assert!((t.f - want).abs().max_element() < 1e-5, "{} {want}", t.f);
        assert_eq!(t.diffuse, t0.diffuse);
        let ratio = t.specular / t0.specular.max(Vec3::splat(1e-12));
        let f_ratio = want / t0.f;
        assert!(
            (ratio - f_ratio).abs().max_element() < 1e-3 * f_ratio.max_element(),
            "{ratio} {f_ratio}"
        );
    }
    let f = super::iridescence::iridescence_fresnel(1.0, 1.3, 1.0, 300.0, Vec3::splat(0.04));
    assert!(f.max_element() > 1.5 * f.min_element(), "{f}");
}

/// Issue 34's furnace: with energy compensation, a white furnace over every combination of the
/// opaque layers — clear coat, sheen and iridescence, each on and off — over a white dielectric
/// and a white metal of roughness 0.05–1 at views to 85°. Measured (2026-11-29, after the
/// split-sum table's fix and with the 10 × 8 sheen albedo fit): without the film within 0.66 %
/// (a sheen over a dielectric of roughness 0.3 at 75°); with the film within 0.92 % (a
/// dielectric of roughness 0.3 at 85° with a 300 nm film: the film's mean Fresnel over the lobe
/// from three points, `iridescence_f0_lobe`). Held at the issue's 1 %.
/// Anisotropy has its own test (`anisotropy_white_furnace_with_compensation`).
#[test]
fn furnace_over_lobe_combinations() {
    let mut worst = [(0.0f32, [0.0f32; 6]); 2];
    for metallic in [0.0, 1.0] {
        for roughness in [0.05, 0.3, 0.6, 1.0] {
            for mask in 0..8u32 {
                for view in [0.0, 45.0, 75.0, 85.0] {
                    let on = |bit: u32| if mask & bit != 0 { 1.0 } else { 0.0 };
                    let e = white_furnace_rgb(
                        MetalRoughParams {
                            base_color: Vec3::ONE,
                            metallic,
                            roughness,
                            clearcoat: on(1),
                            clearcoat_roughness: 0.3,
                            sheen_color: Vec3::splat(on(2)),
                            sheen_roughness: 0.5,
                            iridescence: on(4),
                            iridescence_thickness_max: 300.0,
                            energy_compensation: true,
                            ..MetalRoughParams::default()
                        },
                        view,
                    );
                    // The channel farthest from 1 (the film colours them).
                    let e = 1.0 + (e - Vec3::ONE).abs().max_element();
                    let k = (mask & 4 != 0) as usize;
                    if (e - 1.0).abs() > worst[k].0 {
                        worst[k] = (
                            (e - 1.0).abs(),
                            [metallic, roughness, on(1), on(2), on(4), view],
                        );
                    }
                }
            }
        }
    }
    eprintln!(
        "furnace over coat × sheen × film: without the film worst |E − 1| = {:.4} at {:?}; with it {:.4} at {:?} (metallic, roughness, coat, sheen, film, view°)",
        worst[0].0, worst[0].1, worst[1].0, worst[1].1
    );
    // Without the film: 0.66 % (the sheen albedo fit's error at 75°; 1.11 % before the split-sum
    // table's fix and the 10 × 8 fit: the 8 × 7 fit's 0.8 % on top of the base's own 0.7 %).
    // With it: 0.92 % in the worst channel (2.05 % with the film's Fresnel at the lobe's mean
    // Schlick angle alone, 2.77 % in red at n·v; 1.20 % with the 8 × 7 sheen fit).
    assert!(worst[0].0 <= 0.0075, "{:?}", worst[0]);
    assert!(worst[1].0 <= 0.01, "{:?}", worst[1]);
}

/// Issue 34, KHR_materials_specular's F90: a dielectric of `specularFactor` s reaches F = s at
/// grazing instead of 1 (`F0 + (F90 − F0)(1 − v·h)⁵` exactly, with F0 = 0.04 s), a metal keeps
/// F90 = 1, the Spherical-Gaussian Schlick form likewise, the exact forms ignore it; with
/// energy compensation (`F0·A + F90·B` the lobe's albedo) the white furnace stays 1 ± 1 %.
#[test]
fn specular_f90_scales_the_grazing_fresnel() {
    let s = 0.5;
    let p = MetalRoughParams {
        metallic: 0.0,
        roughness: 0.3,
        dielectric_f0: MetalRoughParams::dielectric_f0_from(None, s, Vec3::ONE),
        dielectric_f90: s,
        ..MetalRoughParams::default()
    };
    let mut rng = Rng::new(90);
    for _ in 0..32 {
        let (l, v) = (rng.hemi(), rng.hemi());
        let v_h = v.dot((l + v).normalize());
        let t = metal_rough_terms(&p, Vec3::Z, l, v);
        let want = 0.04 * s + (s - 0.04 * s) * schlick_weight(v_h);
        assert!((t.f.x - want).abs() < 1e-6, "{} {want}", t.f.x);
        let metal = MetalRoughParams { metallic: 1.0, ..p };
        let plain = MetalRoughParams {
            dielectric_f90: 1.0,
            ..metal
        };
        assert_eq!(
            metal_rough_terms(&metal, Vec3::Z, l, v).f,
            metal_rough_terms(&plain, Vec3::Z, l, v).f
        );
        let exact = MetalRoughParams {
            fresnel: Fresnel::Dielectric,
            ..p
        };
        let exact1 = MetalRoughParams {
            dielectric_f90: 1.0,
            ..exact
        };
        assert_eq!(
            metal_rough_terms(&exact, Vec3::Z, l, v).f,
            metal_rough_terms(&exact1, Vec3::Z, l, v).f
        );
    }
    let sg = MetalRoughParams {
        fresnel: Fresnel::SchlickSg,
        ..p
    };
    let grazing = metal_rough_terms(
        &sg,
        Vec3::Z,
        Vec3::new(1.0, 0.0, 0.01).normalize(),
        Vec3::new(-1.0, 0.0, 0.01).normalize(),
    );
    assert!((grazing.f.x - s).abs() < 0.05, "{}", grazing.f.x);
    let mut worst = 0.0f32;
    for roughness in [0.05, 0.5, 1.0] {
        for view in [0.0, 45.0, 75.0, 85.0] {
            let e = white_furnace(
                MetalRoughParams {
                    base_color: Vec3::ONE,
                    roughness,
                    energy_compensation: true,
                    ..p
                },
                view,
            );
            worst = worst.max((e - 1.0).abs());
        }
    }
    eprintln!("specular F90 0.5 furnace: worst |E − 1| = {worst:.4}");
    assert!(worst <= 0.01, "{worst}");
}

/// Issue 34, the anisotropic split sum: the table read between its entries against the
/// Monte Carlo reference at 4096 samples, at random `(n·v ≥ cos 85°, φ, roughness ≥ 0.05,
/// strength)`; the albedos `E = A + B` (white metal) and `0.04 A + B` (dielectric).
#[test]
fn aniso_split_sum_table_error() {
    let t0 = std::time::Instant::now();
    let _ = aniso_lut();
    eprintln!(
        "aniso split sum table: {} entries, built in {:.2} s",
        aniso_lut().len(),
        t0.elapsed().as_secs_f64()
    );
    let mut rng = Rng::new(0xa5);
    let (mut worst_e, mut worst_d) = ((0.0f32, [0.0f32; 4]), (0.0f32, [0.0f32; 4]));
    let mut sum = 0.0f64;
    let n = 2000;
    for _ in 0..n {
        let n_v = 0.087 + (1.0 - 0.087) * rng.f32();
        let phi = rng.f32() * std::f32::consts::FRAC_PI_2;
        let r = 0.05 + 0.95 * rng.f32();
        let s = rng.f32();
        let (a, b) = aniso_split_sum_ab(n_v, phi, r, s);
        let (ra, rb) = aniso_split_sum_reference(n_v, phi, r, s, 4096);
        let de = ((a + b) - (ra + rb)).abs();
        let dd = ((0.04 * a + b) - (0.04 * ra + rb)).abs();
        sum += f64::from(de);
        if de > worst_e.0 {
            worst_e = (de, [n_v, phi, r, s]);
        }
        if dd > worst_d.0 {
            worst_d = (dd, [n_v, phi, r, s]);
        }
    }
    eprintln!(
        "aniso split sum: |ΔE| mean {:.5}, worst {:.5} at (n·v, φ, roughness, strength) {:?}; |Δ(0.04 A + B)| worst {:.5} at {:?}",
        sum / f64::from(n),
        worst_e.0,
        worst_e.1,
        worst_d.0,
        worst_d.1
    );
    // The isotropic end (strength 0) equals the isotropic lobe's albedo.
    for (n_v, r) in [(0.5, 0.5), (0.1, 0.9), (0.9, 0.2)] {
        let (a, b) = aniso_split_sum_reference(n_v, 0.3, r, 0.0, 4096);
        let (ia, ib) = split_sum_lut_reference(n_v, r, Geometry::SmithGgxCorrelated, 4096);
        assert!(
            ((a + b) - (ia + ib)).abs() < 5e-3,
            "{n_v} {r}: {} {}",
            a + b,
            ia + ib
        );
    }
    assert!(worst_e.0 <= 0.012, "{worst_e:?}");
    assert!(worst_d.0 <= 0.02, "{worst_d:?}");
}

/// Issue 34's sheen cost: the GPU's Λ_sheen (a polynomial fit of the specification's `L`,
/// `sheen_lambda.glsl`, mirrored by `lambda_sheen_of`) is the generator's output and within
/// 1e-3 of the specification's: relative in Λ where Λ ≥ 1e-3, and relative in the visibility, so
/// in the lobe `D · V · n·l`, at every α from 0.0049 to 1 and every pair of cosines from
/// `COS_EPS` to 1 on the grid of `sheen_lambda_fit_error`.
#[test]
fn sheen_lambda_fit_is_lambda() {
    let k = sheen_lambda_constants();
    assert_eq!(
        SHEEN_LAMBDA_GLSL,
        sheen_lambda_glsl_source(k),
        "sheen_lambda.glsl is not the generator's output's format"
    );
    // The generator's output to the last bits but one (its f64 cos and powf may round apart on
    // another platform's libm).
    let new = fit_sheen_lambda();
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * a.abs().max(1e-3);
    assert!(
        close(new.q_scale, k.q_scale)
            && close(new.q_offset, k.q_offset)
            && new.c.len() == k.c.len()
            && new.c.iter().zip(&k.c).all(|(&a, &b)| close(a, b)),
        "sheen_lambda.glsl is not the generator's output (cargo run --release -p luz-core --example sheen_lambda_fit)"
    );
    let e = sheen_lambda_fit_error(k);
    eprintln!(
        "sheen Λ fit: Λ within {:.2e}, the visibility within {:.2e} (α {:.4}, n·l {:.4}, n·v {:.4})",
        e.lambda, e.visibility, e.at.0, e.at.1, e.at.2
    );
    assert!(e.lambda <= 1e-3, "{e:?}");
    assert!(e.visibility <= 1e-3, "{e:?}");
    // The mirror is the fit: at normal incidence and grazing, and at both sides of cos θ = 0.5.
    let sheen_alpha = crate::brdf::models::layers::sheen_alpha;
    for alpha in [sheen_alpha(0.0), sheen_alpha(0.5), 1.0] {
        let f = sheen_lambda_fit(alpha);
        for c in [COS_EPS, 0.1, 0.4999, 0.5, 0.9, 1.0] {
            let (x, y) = (lambda_sheen(c, alpha), lambda_sheen_of(c, &f));
            assert!(
                (y - x).abs() <= 1e-3 * x.max(1.0),
                "α {alpha} cos {c}: {y} vs {x}"
            );
        }
    }
}
