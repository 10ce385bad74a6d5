//! The rows of the sweep: every model with each choice of its terms, and their parameter sets.

use glam::Vec3;

use crate::brdf::{
    metal_preset, ComplexIor, CookTorranceParams, Diffuse, Distribution, Fresnel, Geometry,
    LambertParams, MetalRoughParams, Model, OrenNayarParams, PhongParams, PrincipledParams,
    SpecularSource,
};

use super::{ROUGHNESS, SHININESS, SIGMA_DEG};

/// One parameter set of a row.
#[derive(Debug, Clone)]
pub struct ParamSet {
    /// e.g. `r=0.5 k_d=0 F0=1`.
    pub label: String,
    pub model: Model,
    /// Integrate its directional albedo.
    pub albedo: bool,
    /// Held to `R ≤ 1 + tolerance`.
    pub conserving: bool,
}

/// A row of the table: one model with one choice of its terms, swept over parameter sets.
#[derive(Debug, Clone)]
pub struct Row {
    /// The model name (serde tag).
    pub model: &'static str,
    /// The term choice, e.g. `ggx smith_ggx_correlated conductor`.
    pub variant: String,
    /// Which sets must conserve energy: "yes", "no", "metallic=1", …
    pub claim: &'static str,
    pub sets: Vec<ParamSet>,
}

/// Every model name, in table order.
pub const MODELS: [&str; 7] = [
    "lambert",
    "phong",
    "blinn_phong",
    "cook_torrance",
    "metal_rough",
    "principled",
    "oren_nayar",
];

/// Why each model is (not) held to energy conservation (printed above its table).
pub fn claim_note(model: &str) -> &'static str {
    match model {
        "lambert" => "conserves: R = ρ exactly (held for ρ ≤ 1)",
        "phong" | "blinn_phong" => {
            "empirical (MODELS.md §1: no 1/π, specular over n·l): not conserving, reported only"
        }
        "cook_torrance" => {
            "conserves: k_d·Lambert + (1 − k_d)·single-scattering microfacet, F ≤ 1 (held for every \
             set; albedo of the specular alone, k_d = 0 — R is affine in k_d, the k_d = 1 end is Lambert)"
        }
        "metal_rough" => {
            "conserves for metallic = 1 (held); dielectrics add Lambert to the specular without \
             energy exchange and gain (documented in docs/brdf.md): reported only"
        }
        "principled" => {
            "artistic (Burley 2012): retro-reflection, sheen, subsurface and clearcoat on top of the \
             specular, gains by design (documented): reported only"
        }
        "oren_nayar" => {
            "qualitative fit (MODELS.md §6): A + B/2 > 1 at small σ, gains ≤ 1.5 % at grazing \
             light (documented): reported only"
        }
        _ => "",
    }
}

/// The whole sweep, row by row, in [`MODELS`] order.
pub fn rows() -> Vec<Row> {
    let mut rows = Vec::new();
    let white = Vec3::ONE;
    lambert_rows(&mut rows);
    phong_rows(&mut rows, white);
    cook_torrance_rows(&mut rows, white);
    metal_rough_rows(&mut rows, white);
    metal_rough_layer_rows(&mut rows, white);
    principled_rows(&mut rows, white);
    oren_nayar_rows(&mut rows);
    rows
}

/// Lambert at ρ ∈ {0, 0.5, 1}.
fn lambert_rows(rows: &mut Vec<Row>) {
    rows.push(Row {
        model: "lambert",
        variant: "ρ ∈ {0, 0.5, 1}".into(),
        claim: "yes",
        sets: [0.0, 0.5, 1.0]
            .iter()
            .map(|&a| ParamSet {
                label: format!("ρ={a}"),
                model: Model::Lambert(LambertParams {
                    albedo: Vec3::splat(a),
                }),
                albedo: a == 1.0,
                conserving: true,
            })
            .collect(),
    });
}

/// Phong and Blinn-Phong, one row per exponent in [`SHININESS`].
fn phong_rows(rows: &mut Vec<Row>, white: Vec3) {
    for blinn in [false, true] {
        for &n in &SHININESS {
            let sets = [(1.0, 1.0), (1.0, 0.0), (0.0, 1.0)]
                .iter()
                .map(|&(kd, ks)| ParamSet {
                    label: format!("n={n} k_d={kd} k_s={ks}"),
                    model: Model::Phong(PhongParams {
                        diffuse_color: white,
                        specular_color: white,
                        ka: 0.0,
                        kd,
                        ks,
                        shininess: n,
                        blinn,
                    }),
                    albedo: kd == 1.0 && ks == 1.0,
                    conserving: false,
                })
                .collect();
            rows.push(Row {
                model: if blinn { "blinn_phong" } else { "phong" },
                variant: format!("shininess {n}"),
                claim: "no",
                sets,
            });
        }
    }
}

/// Whether G belongs to another distribution than D: Beckmann's own Smith term on a GGX lobe
/// (selectable, measured, but not claimed to conserve: it gains up to 0.7 at grazing).
fn mismatched(d: Distribution, g: Geometry) -> bool {
    d == Distribution::Ggx && g == Geometry::SmithBeckmann
}

/// One row per (D, G, F) choice of a microfacet model, in row order, with the parameter sets
/// `sets_of` gives it; each row claims `claim` unless G belongs to another distribution
/// ([`mismatched`]), then "no".
fn microfacet_rows(
    rows: &mut Vec<Row>,
    model: &'static str,
    claim: &'static str,
    mut sets_of: impl FnMut(Distribution, Geometry, Fresnel) -> Vec<ParamSet>,
) {
    for d in Distribution::ALL {
        for g in Geometry::ALL {
            for f in Fresnel::ALL {
                rows.push(Row {
                    model,
                    variant: format!("{} {} {}", d.name(), g.name(), f.name()),
                    claim: if mismatched(d, g) { "no" } else { claim },
                    sets: sets_of(d, g, f),
                });
            }
        }
    }
}

/// Cook-Torrance, one row per (D, G, F), swept over roughness, k_d and the Fresnel source.
fn cook_torrance_rows(rows: &mut Vec<Row>, white: Vec3) {
    let gold = metal_preset("gold").expect("gold preset");
    microfacet_rows(
        rows,
        "cook_torrance",
        "yes",
        |distribution, geometry, fresnel| {
            let mut sets = Vec::new();
            for &roughness in &ROUGHNESS {
                for kd in [0.0, 0.5, 1.0] {
                    for (sl, specular) in [
                        ("F0=1", SpecularSource::F0(Vec3::ONE)),
                        ("η=1.5", SpecularSource::Ior(1.5)),
                        ("gold", SpecularSource::Complex(gold)),
                        // Extremes of the Fresnel inputs: F0 = 0, the η floor, index
                        // matching, and indices whose squares overflow f32.
                        ("F0=0", SpecularSource::F0(Vec3::ZERO)),
                        ("η=1e-4", SpecularSource::Ior(1e-4)),
                        ("η=1", SpecularSource::Ior(1.0)),
                        ("η=1e20", SpecularSource::Ior(1e20)),
                        (
                            "η+iκ=(1e20, 1+1e20i, 0)",
                            SpecularSource::Complex(ComplexIor {
                                eta: Vec3::new(1e20, 1.0, 0.0),
                                k: Vec3::new(0.0, 1e20, 0.0),
                            }),
                        ),
                    ] {
                        let model = |diffuse| {
                            Model::CookTorrance(CookTorranceParams {
                                color: white,
                                kd,
                                roughness,
                                specular,
                                distribution,
                                geometry,
                                fresnel,
                                diffuse,
                            })
                        };
                        sets.push(ParamSet {
                            label: format!("r={roughness} k_d={kd} {sl}"),
                            model: model(Diffuse::Lambert),
                            // F ≤ 1 scales the specular down: F0 = 1 (and gold, whose η < 1
                            // gives total reflection in the exact dielectric) bound η = 1.5.
                            albedo: kd == 0.0 && (sl == "F0=1" || sl == "gold"),
                            conserving: !mismatched(distribution, geometry),
                        });
                        // Burley's diffuse (its Fd exceeds 1 near grazing at high roughness:
                        // measured and reported, not held to R ≤ 1).
                        if kd > 0.0 && sl == "η=1.5" {
                            sets.push(ParamSet {
                                label: format!("r={roughness} k_d={kd} {sl} burley"),
                                model: model(Diffuse::Burley),
                                albedo: kd == 1.0,
                                conserving: false,
                            });
                        }
                    }
                }
            }
            sets
        },
    );
}

/// glTF metallic-roughness, one row per (D, G, F), swept over roughness, metallic, the (1 − F)
/// weight and the diffuse.
fn metal_rough_rows(rows: &mut Vec<Row>, white: Vec3) {
    microfacet_rows(
        rows,
        "metal_rough",
        "metallic=1",
        |distribution, geometry, fresnel| {
            let mut sets = Vec::new();
            for &roughness in &ROUGHNESS {
                for metallic in [0.0, 0.5, 1.0] {
                    for weight in [false, true] {
                        for diffuse in Diffuse::ALL {
                            let burley = diffuse == Diffuse::Burley;
                            sets.push(ParamSet {
                                label: format!(
                                    "r={roughness} metallic={metallic} (1−F)={weight}{}",
                                    if burley { " burley" } else { "" }
                                ),
                                model: Model::MetalRough(MetalRoughParams {
                                    base_color: white,
                                    metallic,
                                    roughness,
                                    distribution,
                                    geometry,
                                    fresnel,
                                    diffuse_fresnel_weight: weight,
                                    diffuse,
                                    ..MetalRoughParams::default()
                                }),
                                // Claimed: metallic 1 (the weight and the diffuse choice only
                                // change the diffuse, which metallic 1 removes); metallic 0
                                // without the weight for the report (Burley's too).
                                albedo: !weight
                                    && if burley {
                                        metallic == 0.0
                                    } else {
                                        metallic != 0.5
                                    },
                                conserving: metallic == 1.0 && !mismatched(distribution, geometry),
                            });
                        }
                    }
                }
            }
            sets
        },
    );
}

/// The glTF extensions' layers on metal_rough (issue 34), one row per layer at the edges of its
/// parameters — coat and sheen roughness 0 and 1, anisotropy strength 1 at roughness 0, a film
/// of thickness 0, 1e-3 nm and 1200 nm, film indices 1 (no film), 1.0001 and 2.5, F90 0 —
/// each over a white dielectric and a white metal at roughness 0, 1e-3, 0.1, 0.5 and 1; albedo
/// integrated at roughness 0.5. Reported, not claimed: the layers' energy is the white furnace
/// tests' (docs/brdf.md).
fn metal_rough_layer_rows(rows: &mut Vec<Row>, white: Vec3) {
    let base = MetalRoughParams {
        base_color: white,
        ..MetalRoughParams::default()
    };
    let layer = |label: &str, p: MetalRoughParams| (label.to_string(), p);
    let layers: Vec<(&str, Vec<(String, MetalRoughParams)>)> = vec![
        (
            "clearcoat (KHR_materials_clearcoat)",
            [0.0, 1.0]
                .iter()
                .map(|&r| {
                    layer(
                        &format!("coat 1 r_c={r}"),
                        MetalRoughParams {
                            clearcoat: 1.0,
                            clearcoat_roughness: r,
                            ..base
                        },
                    )
                })
                .collect(),
        ),
        (
            "sheen (KHR_materials_sheen)",
            [0.0, 1.0]
                .iter()
                .map(|&r| {
                    layer(
                        &format!("sheen white r_s={r}"),
                        MetalRoughParams {
                            sheen_color: Vec3::ONE,
                            sheen_roughness: r,
                            ..base
                        },
                    )
                })
                .collect(),
        ),
        (
            "anisotropy (KHR_materials_anisotropy)",
            [(1.0, 0.0), (1.0, 2.0), (0.5, 1.0)]
                .iter()
                .map(|&(s, rot)| {
                    layer(
                        &format!("strength={s} rotation={rot}"),
                        MetalRoughParams {
                            anisotropy_strength: s,
                            anisotropy_rotation: rot,
                            ..base
                        },
                    )
                })
                .collect(),
        ),
        (
            "iridescence (KHR_materials_iridescence)",
            [
                (0.0, 1.3),
                (1e-3, 1.3),
                (400.0, 1.0),
                (400.0, 1.0001),
                (1200.0, 2.5),
            ]
            .iter()
            .map(|&(d, ior)| {
                layer(
                    &format!("film {d} nm ior={ior}"),
                    MetalRoughParams {
                        iridescence: 1.0,
                        iridescence_ior: ior,
                        iridescence_thickness_max: d,
                        iridescence_thickness_min: 0.0,
                        ..base
                    },
                )
            })
            .collect(),
        ),
        (
            "specular F90 (KHR_materials_specular)",
            [0.0, 0.5]
                .iter()
                .map(|&f90| {
                    layer(
                        &format!("F90={f90}"),
                        MetalRoughParams {
                            dielectric_f0: Vec3::splat(0.04 * f90),
                            dielectric_f90: f90,
                            ..base
                        },
                    )
                })
                .collect(),
        ),
    ];
    for (variant, params) in layers {
        let mut sets = Vec::new();
        for (label, p) in &params {
            for metallic in [0.0, 1.0] {
                for roughness in [0.0, 1e-3, 0.1, 0.5, 1.0] {
                    sets.push(ParamSet {
                        label: format!("{label} metallic={metallic} r={roughness}"),
                        model: Model::MetalRough(MetalRoughParams {
                            metallic,
                            roughness,
                            ..*p
                        }),
                        albedo: roughness == 0.5,
                        conserving: false,
                    });
                }
            }
        }
        rows.push(Row {
            model: "metal_rough",
            variant: variant.into(),
            claim: "no",
            sets,
        });
    }
}

/// Principled, one row per parameter choice, swept over roughness.
fn principled_rows(rows: &mut Vec<Row>, white: Vec3) {
    let base = PrincipledParams {
        base_color: white,
        ..Default::default()
    };
    let all_one = PrincipledParams {
        base_color: white,
        subsurface: 1.0,
        metallic: 1.0,
        specular: 1.0,
        specular_tint: 1.0,
        roughness: 0.5,
        anisotropic: 1.0,
        sheen: 1.0,
        sheen_tint: 1.0,
        clearcoat: 1.0,
        clearcoat_gloss: 1.0,
    };
    let principled: Vec<(&str, PrincipledParams)> = vec![
        ("defaults, white base", base),
        (
            "metallic=1",
            PrincipledParams {
                metallic: 1.0,
                ..base
            },
        ),
        (
            "anisotropic=1",
            PrincipledParams {
                anisotropic: 1.0,
                ..base
            },
        ),
        (
            "anisotropic=1 metallic=1",
            PrincipledParams {
                anisotropic: 1.0,
                metallic: 1.0,
                ..base
            },
        ),
        (
            "clearcoat=1 gloss=1",
            PrincipledParams {
                clearcoat: 1.0,
                clearcoat_gloss: 1.0,
                ..base
            },
        ),
        (
            "clearcoat=1 gloss=0",
            PrincipledParams {
                clearcoat: 1.0,
                clearcoat_gloss: 0.0,
                ..base
            },
        ),
        (
            "sheen=1 sheen_tint=1",
            PrincipledParams {
                sheen: 1.0,
                sheen_tint: 1.0,
                ..base
            },
        ),
        (
            "subsurface=1",
            PrincipledParams {
                subsurface: 1.0,
                ..base
            },
        ),
        (
            "specular=1 specular_tint=1",
            PrincipledParams {
                specular: 1.0,
                specular_tint: 1.0,
                ..base
            },
        ),
        (
            "specular=0",
            PrincipledParams {
                specular: 0.0,
                ..base
            },
        ),
        ("all=1", all_one),
        (
            "all=1 but metallic=0, gloss=0",
            PrincipledParams {
                metallic: 0.0,
                clearcoat_gloss: 0.0,
                ..all_one
            },
        ),
        (
            "all=0, black base",
            PrincipledParams {
                base_color: Vec3::ZERO,
                subsurface: 0.0,
                metallic: 0.0,
                specular: 0.0,
                specular_tint: 0.0,
                roughness: 0.0,
                anisotropic: 0.0,
                sheen: 0.0,
                sheen_tint: 0.0,
                clearcoat: 0.0,
                clearcoat_gloss: 0.0,
            },
        ),
    ];
    for (variant, p) in principled {
        rows.push(Row {
            model: "principled",
            variant: variant.into(),
            claim: "no",
            sets: ROUGHNESS
                .iter()
                .map(|&roughness| ParamSet {
                    label: format!("{variant}, r={roughness}"),
                    model: Model::Principled(PrincipledParams { roughness, ..p }),
                    albedo: true,
                    conserving: false,
                })
                .collect(),
        });
    }
}

/// Oren-Nayar, one row per σ in [`SIGMA_DEG`].
fn oren_nayar_rows(rows: &mut Vec<Row>) {
    for &sigma_deg in &SIGMA_DEG {
        rows.push(Row {
            model: "oren_nayar",
            variant: format!("σ={sigma_deg}°"),
            claim: "no",
            sets: [0.0, 1.0]
                .iter()
                .map(|&a| ParamSet {
                    label: format!("σ={sigma_deg}° ρ={a}"),
                    model: Model::OrenNayar(OrenNayarParams {
                        albedo: Vec3::splat(a),
                        sigma_deg,
                    }),
                    albedo: a == 1.0,
                    conserving: false,
                })
                .collect(),
        });
    }
}
