//! Light through a dielectric interface, for the CPU reference's glass (issue 35): Snell's law,
//! the rough dielectric BSDF of Walter, Marschner, Li and Torrance 2007 ("Microfacet Models for
//! Refraction through Rough Surfaces": GGX microfacets, the exact Fresnel of
//! [`super::f_dielectric`], separable Smith G) with its importance sampling, and Beer–Lambert
//! attenuation with `KHR_materials_volume`'s parameters.
//!
//! Conventions (as pbrt's `MicrofacetTransmission`): directions in the surface's local frame,
//! `+z` the normal of the outside (index 1), the inside has index `ior`; `wo` towards the viewer,
//! `wi` towards the light, both pointing away from the surface, on either side. [`RoughDielectric::eval`]
//! is the radiance BSDF: `L_o(wo) = ∫ f(wo, wi) L_i(wi) |cos θ_i| dω_i`. Radiance crossing into
//! a medium of index η is η² times denser, so a uniform field of radiance 1 outside and `ior²`
//! inside is in equilibrium: the furnace the tests run.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::sampling::importance_sample_ggx;
use super::terms::{d_ggx, f_dielectric, g1_smith_ggx, ALPHA_MIN};

/// The direction `w` (pointing away from the surface, on `n`'s side) refracts into, pointing away
/// on the other side, with `eta = η_t / η_i` (the index beyond the surface over the index of
/// `w`'s side); `None` under total internal reflection. Snell: `sin θ_t = sin θ_i / eta`.
pub fn refract(w: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = w.dot(n);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-w / eta + (cos_i / eta - cos_t) * n)
}

/// Beer–Lambert: the fraction of light left after `distance` through a medium with attenuation
/// coefficient `sigma` (per unit length, per channel): `exp(−σ d)`.
pub fn beer_lambert(sigma: Vec3, distance: f32) -> Vec3 {
    (-sigma * distance).exp()
}

/// `KHR_materials_volume`'s attenuation coefficient: light that travels `attenuation_distance`
/// keeps `attenuation_color`, so `σ = −ln(color) / distance` (0 for an infinite distance; a
/// colour channel of 0 absorbs everything: σ = ∞).
pub fn attenuation_coefficient(attenuation_color: Vec3, attenuation_distance: f32) -> Vec3 {
    if !attenuation_distance.is_finite() {
        return Vec3::ZERO;
    }
    -attenuation_color.max(Vec3::ZERO).ln() / attenuation_distance
}

/// Light through a metal-rough material (issue 35): `KHR_materials_transmission`,
/// `KHR_materials_volume`, `KHR_materials_dispersion` and `KHR_materials_diffuse_transmission`,
/// with the extensions' defaults (everything off). The index of refraction is the material's own
/// (`KHR_materials_ior`, the dielectric F0's).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Transmission {
    /// `transmissionFactor`, [0, 1]: how much of the dielectric's diffuse is replaced by the
    /// specular BTDF. Default 0 (opaque).
    pub factor: f32,
    /// `thicknessFactor` ≥ 0, in the mesh's own units: 0 is a thin-walled surface (light
    /// crosses it without bending its path); more makes the object a volume whose inside
    /// refracts and attenuates. Default 0.
    pub thickness: f32,
    /// `attenuationColor`, [0, 1] per channel: what is left after `attenuation_distance`.
    /// Default white.
    pub attenuation_color: Vec3,
    /// `attenuationDistance` > 0; `None` is the extension's default, infinity (no attenuation).
    pub attenuation_distance: Option<f32>,
    /// `dispersion` ≥ 0: 20 / Abbe number; 0 (default) is one index for every channel.
    pub dispersion: f32,
    /// `diffuseTransmissionFactor`, [0, 1]: the part of the diffuse lobe that goes through as
    /// diffuse light. Default 0.
    pub diffuse: f32,
    /// `diffuseTransmissionColorFactor`, [0, 1] per channel. Default white.
    pub diffuse_color: Vec3,
}

impl Default for Transmission {
    fn default() -> Self {
        Self {
            factor: 0.0,
            thickness: 0.0,
            attenuation_color: Vec3::ONE,
            attenuation_distance: None,
            dispersion: 0.0,
            diffuse: 0.0,
            diffuse_color: Vec3::ONE,
        }
    }
}

impl Transmission {
    /// Whether light goes through at all (specular or diffuse transmission).
    pub fn any(&self) -> bool {
        self.factor > 0.0 || self.diffuse > 0.0
    }

    /// Thin-walled (no volume): `thickness` 0.
    pub fn thin_walled(&self) -> bool {
        self.thickness <= 0.0
    }

    /// The inside's attenuation coefficient σ per unit length ([`attenuation_coefficient`]).
    pub fn sigma(&self) -> Vec3 {
        attenuation_coefficient(
            self.attenuation_color,
            self.attenuation_distance.unwrap_or(f32::INFINITY),
        )
    }

    /// The index of refraction per channel (R, G, B) for the material's `ior`:
    /// `KHR_materials_dispersion`'s spread `(ior − 1) · 0.025 · dispersion` below and above
    /// green's `ior` (`ior − spread`, `ior`, `ior + spread`).
    pub fn channel_iors(&self, ior: f32) -> Vec3 {
        let spread = (ior - 1.0) * 0.025 * self.dispersion;
        Vec3::new(ior - spread, ior, ior + spread)
    }

    /// Factors in range, colours in [0, 1], a positive finite attenuation distance (else none),
    /// non-finite values to the defaults.
    pub fn sanitized(&self) -> Self {
        let d = Self::default();
        let unit = |x: f32, default: f32| {
            if x.is_finite() {
                x.clamp(0.0, 1.0)
            } else {
                default
            }
        };
        let colour = |c: Vec3| {
            if c.is_finite() {
                c.clamp(Vec3::ZERO, Vec3::ONE)
            } else {
                Vec3::ONE
            }
        };
        let non_negative = |x: f32| if x.is_finite() { x.max(0.0) } else { 0.0 };
        Self {
            factor: unit(self.factor, d.factor),
            thickness: non_negative(self.thickness),
            attenuation_color: colour(self.attenuation_color),
            attenuation_distance: self
                .attenuation_distance
                .filter(|x| x.is_finite() && *x > 0.0),
            dispersion: non_negative(self.dispersion),
            diffuse: unit(self.diffuse, d.diffuse),
            diffuse_color: colour(self.diffuse_color),
        }
    }
}

/// A sampled direction of a [`RoughDielectric`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DielectricSample {
    /// Towards the light, pointing away from the surface.
    pub wi: Vec3,
    /// `f(wo, wi) |cos θ_i| / pdf`.
    pub weight: f32,
    /// Solid-angle density of `wi`.
    pub pdf: f32,
    /// `wi` is on the other side of the surface from `wo`.
    pub transmitted: bool,
}

/// A rough dielectric interface (Walter et al. 2007): GGX width `alpha` (= roughness²), inside
/// index `ior` (outside 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughDielectric {
    pub alpha: f32,
    pub ior: f32,
}

/// What both directions of an evaluation share: the sides' indices and the microfacet normal.
struct Pair {
    /// Index of `wo`'s side and of `wi`'s side.
    eta_o: f32,
    eta_i: f32,
    /// The microfacet normal that takes `wo` to `wi` (reflected or refracted), facing +z.
    h: Vec3,
    transmitted: bool,
}

impl RoughDielectric {
    fn alpha(&self) -> f32 {
        self.alpha.max(ALPHA_MIN)
    }

    fn side_index(&self, w: Vec3) -> f32 {
        if w.z > 0.0 {
            1.0
        } else {
            self.ior
        }
    }

    /// The pair's indices and half vector; `None` when a direction lies in the surface or the
    /// microfacet would have to face away from one of them.
    fn pair(&self, wo: Vec3, wi: Vec3) -> Option<Pair> {
        if wo.z == 0.0 || wi.z == 0.0 {
            return None;
        }
        let transmitted = wo.z * wi.z < 0.0;
        let (eta_o, eta_i) = (self.side_index(wo), self.side_index(wi));
        // Reflection: h ∝ wo + wi; refraction: the generalised half vector ∝ −(η_o wo + η_i wi).
        let h = if transmitted {
            eta_o * wo + eta_i * wi
        } else {
            wo + wi
        };
        if h.length_squared() <= 1e-12 {
            return None;
        }
        let h = h.normalize();
        let h = if h.z < 0.0 { -h } else { h };
        // Each direction must see the microfacet from its own side of the surface, and a
        // refraction must cross it.
        let (o_h, i_h) = (wo.dot(h), wi.dot(h));
        if o_h * wo.z <= 0.0 || i_h * wi.z <= 0.0 || (transmitted && o_h * i_h >= 0.0) {
            return None;
        }
        Some(Pair {
            eta_o,
            eta_i,
            h,
            transmitted,
        })
    }

    /// Fresnel reflectance at the microfacet `h` seen from `wo`'s side.
    fn fresnel(&self, wo: Vec3, p: &Pair) -> f32 {
        f_dielectric(wo.dot(p.h).abs(), self.side_index(-wo) / p.eta_o)
    }

    /// `dω_h / dω_i` of a refraction: `η_i² |wi·h| / (η_o wo·h + η_i wi·h)²`.
    fn refraction_jacobian(wo: Vec3, wi: Vec3, p: &Pair) -> f32 {
        let den = p.eta_o * wo.dot(p.h) + p.eta_i * wi.dot(p.h);
        p.eta_i * p.eta_i * wi.dot(p.h).abs() / (den * den).max(1e-20)
    }

    /// The radiance BSDF `f(wo, wi)` (not multiplied by `|cos θ_i|`).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(p) = self.pair(wo, wi) else {
            return 0.0;
        };
        let a = self.alpha();
        let d = d_ggx(p.h.z, a);
        let g = g1_smith_ggx(wo.z.abs(), a) * g1_smith_ggx(wi.z.abs(), a);
        let f = self.fresnel(wo, &p);
        let (cos_o, cos_i) = (wo.z.abs(), wi.z.abs());
        if p.transmitted {
            // Walter et al. (21) in radiance form: η_o² |wi·h||wo·h| (1 − F) D G /
            // (|cos_o||cos_i| (η_o wo·h + η_i wi·h)²), i.e. (1 − F) D G |wo·h| / |cos_o cos_i| ×
            // the Jacobian × (η_o / η_i)².
            let ratio = p.eta_o / p.eta_i;
            (1.0 - f) * d * g * wo.dot(p.h).abs() * Self::refraction_jacobian(wo, wi, &p)
                / (cos_o * cos_i)
                * ratio
                * ratio
        } else {
            f * d * g / (4.0 * cos_o * cos_i)
        }
    }

    /// Solid-angle density of [`Self::sample`] choosing `wi` from `wo`: `h` drawn with density
    /// `D(h)(n·h)`, reflection with probability F, refraction with 1 − F.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(p) = self.pair(wo, wi) else {
            return 0.0;
        };
        let pdf_h = d_ggx(p.h.z, self.alpha()) * p.h.z;
        let f = self.fresnel(wo, &p);
        if p.transmitted {
            (1.0 - f) * pdf_h * Self::refraction_jacobian(wo, wi, &p)
        } else {
            f * pdf_h / (4.0 * wo.dot(p.h).abs())
        }
    }

    /// Samples `wi` for `wo` from uniform numbers `u` (the microfacet normal) and `u_lobe`
    /// (reflection or refraction, by the Fresnel reflectance). `None` when the drawn microfacet
    /// faces away from `wo` or the refraction is totally reflected away.
    pub fn sample(&self, wo: Vec3, u: (f32, f32), u_lobe: f32) -> Option<DielectricSample> {
        self.sample_lobe(wo, u, Some(u_lobe))
    }

    /// [`Self::sample`] restricted to refraction: the microfacet normal from `u`, always
    /// refracted, with the weight of the refracted part alone (`eval · |cos| / pdf` with the
    /// density of refraction given `h`, so the weights carry `1 − F`). Its expected weight is
    /// the BTDF's share of what [`Self::sample`] returns, with no noise from the lobe choice.
    pub fn sample_refraction(&self, wo: Vec3, u: (f32, f32)) -> Option<DielectricSample> {
        self.sample_lobe(wo, u, None)
    }

    /// `u_lobe` chooses the lobe by the Fresnel reflectance; `None` always refracts.
    fn sample_lobe(
        &self,
        wo: Vec3,
        u: (f32, f32),
        u_lobe: Option<f32>,
    ) -> Option<DielectricSample> {
        if wo.z == 0.0 {
            return None;
        }
        if (self.ior - 1.0).abs() < 1e-6 {
            // Index matching: no interface, light goes straight on (a delta: eval and pdf are
            // 0 for it, as for any specular lobe).
            return Some(DielectricSample {
                wi: -wo,
                weight: 1.0,
                pdf: f32::INFINITY,
                transmitted: true,
            });
        }
        let hs = importance_sample_ggx(u.0, u.1, self.alpha());
        // The microfacet normal on wo's side.
        let h = if wo.z > 0.0 { hs } else { -hs };
        let o_h = wo.dot(h);
        if o_h <= 0.0 {
            return None;
        }
        let eta_o = self.side_index(wo);
        let eta_t = self.side_index(-wo);
        let f = f_dielectric(o_h, eta_t / eta_o);
        let reflect = u_lobe.is_some_and(|u| u < f);
        let wi = if reflect {
            2.0 * o_h * h - wo
        } else {
            refract(wo, h, eta_t / eta_o)?
        };
        // A reflection must stay on wo's side and a refraction cross: a microfacet can send
        // light the other way, which the BSDF (defined per pair of sides) does not count.
        if (wo.z * wi.z > 0.0) != reflect {
            return None;
        }
        let mut pdf = self.pdf(wo, wi);
        let value = self.eval(wo, wi);
        if u_lobe.is_none() {
            // The density given refraction: without the lobe choice's 1 − F.
            pdf /= (1.0 - f).max(1e-12);
        }
        if pdf <= 0.0 || value <= 0.0 {
            return None;
        }
        Some(DielectricSample {
            wi,
            weight: value * wi.z.abs() / pdf,
            pdf,
            transmitted: wo.z * wi.z < 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
        let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
        Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
    }

    /// A small deterministic generator (xorshift), so the Monte Carlo figures are fixed.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    #[test]
    fn refraction_follows_snell_and_reflects_totally_past_the_critical_angle() {
        let n = Vec3::Z;
        for theta in [0.0f32, 10.0, 30.0, 60.0, 89.0] {
            let w = dir(theta, 40.0);
            let t = refract(w, n, 1.5).unwrap();
            assert!((t.length() - 1.0).abs() < 1e-5);
            let sin_t = (1.0 - t.z * t.z).sqrt();
            assert!(
                (sin_t - theta.to_radians().sin() / 1.5).abs() < 1e-5,
                "{theta}"
            );
            assert!(t.z < 0.0);
            // In the plane of incidence, on the other side of the normal.
            assert!(t.x * w.x <= 1e-7 && t.y * w.y <= 1e-7);
            // And back: the path reverses.
            let back = refract(t, -n, 1.0 / 1.5).unwrap();
            assert!((back - w).length() < 1e-4, "{theta}: {back} {w}");
        }
        // From glass (1.5) into air the critical angle is asin(1/1.5) = 41.81°.
        let inside = |theta: f32| -dir(theta, 0.0);
        assert!(refract(inside(41.0), -n, 1.0 / 1.5).is_some());
        assert!(refract(inside(42.0), -n, 1.0 / 1.5).is_none());
    }

    #[test]
    fn beer_lambert_keeps_the_attenuation_colour_over_the_attenuation_distance() {
        let sigma = attenuation_coefficient(Vec3::new(0.5, 0.25, 1.0), 2.0);
        assert!((sigma - Vec3::new(2f32.ln() / 2.0, 4f32.ln() / 2.0, 0.0)).length() < 1e-6);
        let left = beer_lambert(sigma, 2.0);
        assert!((left - Vec3::new(0.5, 0.25, 1.0)).length() < 1e-6);
        // exp(−σ d) is multiplicative over distance.
        let half = beer_lambert(sigma, 1.0);
        assert!((half * half - left).length() < 1e-6);
        assert_eq!(
            attenuation_coefficient(Vec3::ONE, f32::INFINITY),
            Vec3::ZERO
        );
        assert_eq!(beer_lambert(Vec3::ZERO, 1e6), Vec3::ONE);
    }

    /// The pdf integrates over the sphere to the probability that `sample` returns a direction,
    /// and each sample's weight is `eval · |cos| / pdf`: sampling and density agree.
    #[test]
    fn sampling_density_integrates_to_the_sampled_fraction() {
        for (alpha, ior, theta, outside) in [
            (0.3, 1.5, 30.0, true),
            (0.5, 1.5, 70.0, true),
            (0.3, 1.5, 20.0, false),
            (0.2, 1.33, 60.0, false),
        ] {
            let bsdf = RoughDielectric { alpha, ior };
            let wo = if outside {
                dir(theta, 0.0)
            } else {
                -dir(theta, 0.0)
            };
            // ∫ pdf dω over the sphere: midpoint rule in (cos θ, φ).
            let (nt, np) = (800, 400);
            let mut integral = 0.0f64;
            for i in 0..nt {
                let z = -1.0 + (i as f32 + 0.5) * 2.0 / nt as f32;
                let s = (1.0 - z * z).sqrt();
                for j in 0..np {
                    let p = (j as f32 + 0.5) * std::f32::consts::TAU / np as f32;
                    let wi = Vec3::new(s * p.cos(), s * p.sin(), z);
                    integral += bsdf.pdf(wo, wi) as f64;
                }
            }
            integral *= (2.0 / nt as f64) * (std::f64::consts::TAU / np as f64);
            let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
            let n = 200_000;
            let mut valid = 0usize;
            for _ in 0..n {
                if let Some(s) = bsdf.sample(wo, (rng.next(), rng.next()), rng.next()) {
                    valid += 1;
                    let expect = bsdf.eval(wo, s.wi) * s.wi.z.abs() / bsdf.pdf(wo, s.wi);
                    assert!((s.weight - expect).abs() <= 1e-4 * expect.max(1.0));
                }
            }
            let fraction = valid as f64 / n as f64;
            assert!(
                (integral - fraction).abs() < 0.01,
                "α {alpha}, η {ior}, θ {theta}, outside {outside}: ∫pdf {integral:.4}, sampled {fraction:.4}"
            );
        }
    }

    /// The radiance BSDF's reciprocity across an interface: `f(wo, wi) / η_o² = f(wi, wo) / η_i²`
    /// (Veach's generalised reciprocity, thesis §5.2), and plain symmetry for reflection.
    #[test]
    fn generalised_reciprocity() {
        let bsdf = RoughDielectric {
            alpha: 0.4,
            ior: 1.5,
        };
        for (a, b) in [
            (dir(20.0, 0.0), -dir(35.0, 10.0)),
            (dir(60.0, 30.0), -dir(30.0, 25.0)),
            (dir(45.0, 0.0), dir(30.0, 150.0)),
            (-dir(25.0, 0.0), -dir(50.0, 120.0)),
        ] {
            let (fab, fba) = (bsdf.eval(a, b), bsdf.eval(b, a));
            assert!(fab > 0.0, "{a} {b}");
            let eta2 = |w: Vec3| if w.z > 0.0 { 1.0 } else { 1.5f32 * 1.5 };
            let (l, r) = (fab / eta2(a), fba / eta2(b));
            assert!((l - r).abs() <= 1e-4 * l, "{a} {b}: {l} {r}");
        }
    }

    /// The furnace: radiance 1 outside and η² inside is in equilibrium, so a surface seen from
    /// either side returns its side's radiance, less what single scattering loses (the light
    /// that would bounce between microfacets). Smooth surfaces lose nothing.
    #[test]
    fn furnace_returns_the_equilibrium_radiance() {
        let ior = 1.5f32;
        let field = |w: Vec3| if w.z > 0.0 { 1.0 } else { ior * ior };
        let mut worst = (0.0f32, String::new());
        for alpha in [0.001f32, 0.01, 0.05, 0.1, 0.3] {
            for theta in [0.0f32, 30.0, 41.0, 60.0, 80.0] {
                for outside in [true, false] {
                    let bsdf = RoughDielectric { alpha, ior };
                    let wo = if outside {
                        dir(theta, 0.0)
                    } else {
                        -dir(theta, 0.0)
                    };
                    let mut rng = Rng(12345);
                    let n = 100_000;
                    let mut sum = 0.0f64;
                    for _ in 0..n {
                        if let Some(s) = bsdf.sample(wo, (rng.next(), rng.next()), rng.next()) {
                            sum += (s.weight * field(s.wi)) as f64;
                        }
                    }
                    let ratio = (sum / n as f64) as f32 / field(wo);
                    eprintln!("furnace: α {alpha}, θ {theta}, outside {outside}: {ratio:.4}");
                    // Never a gain. Single scattering loses what the separable Smith G masks
                    // and what microfacets send below the horizon, most at grazing angles and
                    // inside past the critical angle (41.8°), where all of it reflects: 12 % at
                    // α 0.1 and 80° inside.
                    assert!(
                        (0.6..=1.002).contains(&ratio),
                        "α {alpha}, θ {theta}, outside {outside}: {ratio}"
                    );
                    if alpha <= 0.05 && theta <= 60.0 {
                        assert!((ratio - 1.0).abs() < 0.01, "α {alpha}, θ {theta}: {ratio}");
                    }
                    let err = (1.0 - ratio).abs();
                    if err > worst.0 {
                        worst = (err, format!("α {alpha}, θ {theta}, outside {outside}"));
                    }
                }
            }
        }
        eprintln!("furnace: largest loss {:.4} at {}", worst.0, worst.1);
    }
}
