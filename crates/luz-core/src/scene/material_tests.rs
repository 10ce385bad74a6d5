//! Unit tests of the physically based material models: `cook_torrance`, `metal_rough`,
//! `principled`, `oren_nayar` (defaults, every field, errors, the CPU reference's serde round trip).

use super::decode::{DIFFUSES, DISTRIBUTIONS, FRESNELS, GEOMETRIES};
use super::*;
use crate::brdf::{
    dielectric_ior, metal_preset, CookTorranceParams, Diffuse, Distribution, Fresnel, Geometry,
    MetalRoughParams, Model, OrenNayarParams, PrincipledParams, SpecularSource, DIELECTRIC_NAMES,
    METAL_NAMES,
};

/// The material `m` of a scene with one sphere and the material body `body` (without braces).
fn material(body: &str) -> Result<Material, SceneError> {
    let text = format!(
        r#"{{"materials": {{"m": {{{body}}}}}, "objects": [{{"mesh": {{"type": "sphere"}}, "material": "m"}}]}}"#
    );
    parse(&text, Path::new("scenes/a.json")).map(|s| s.materials[0].material)
}

fn ok(body: &str) -> Material {
    material(body).unwrap_or_else(|e| panic!("{body}: {e}"))
}

/// `body` must fail with a message containing every one of `expected`.
fn fails(body: &str, expected: &[&str]) {
    match material(body) {
        Ok(m) => panic!("{body}: expected an error, got {m:?}"),
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with("scenes/a.json: materials.m"), "{msg}");
            for s in expected {
                assert!(msg.contains(s), "{msg:?} does not contain {s:?}");
            }
        }
    }
}

fn cook_torrance(body: &str) -> CookTorranceParams {
    match ok(&format!(r#""model": "cook_torrance"{body}"#)) {
        Material::CookTorrance(p) => p,
        m => panic!("{m:?}"),
    }
}

fn metal_rough(body: &str) -> MetalRoughParams {
    match ok(&format!(r#""model": "metal_rough"{body}"#)) {
        Material::MetalRough(p) => p,
        m => panic!("{m:?}"),
    }
}

fn principled(body: &str) -> PrincipledParams {
    match ok(&format!(r#""model": "principled"{body}"#)) {
        Material::Principled(p) => p,
        m => panic!("{m:?}"),
    }
}

fn oren_nayar(body: &str) -> OrenNayarParams {
    match ok(&format!(r#""model": "oren_nayar"{body}"#)) {
        Material::OrenNayar(p) => p,
        m => panic!("{m:?}"),
    }
}

/// The selector tables use the same names as the CPU reference's serde names, and cover every
/// value.
#[test]
fn selector_names_match_the_brdf_module() {
    fn check<T: serde::Serialize + PartialEq + std::fmt::Debug + Copy>(
        table: &[(&str, T)],
        all: &[T],
    ) {
        assert_eq!(table.len(), all.len());
        for (name, value) in table {
            let serde_name = serde_json::to_value(value).unwrap();
            assert_eq!(serde_name.as_str(), Some(*name));
        }
        for v in all {
            assert!(table.iter().any(|(_, t)| t == v), "{v:?} missing");
        }
    }
    check(DISTRIBUTIONS, &Distribution::ALL);
    check(GEOMETRIES, &Geometry::ALL);
    check(FRESNELS, &Fresnel::ALL);
    check(DIFFUSES, &Diffuse::ALL);
    for (name, d) in DIFFUSES {
        assert_eq!(d.name(), *name);
    }
}

#[test]
fn model_names() {
    for (body, name) in [
        (r#""model": "cook_torrance""#, "cook_torrance"),
        (r#""model": "metal_rough""#, "metal_rough"),
        (r#""model": "principled""#, "principled"),
        (r#""model": "oren_nayar""#, "oren_nayar"),
    ] {
        assert_eq!(ok(body).name(), name);
    }
}

#[test]
fn cook_torrance_defaults_are_the_seeds() {
    let p = cook_torrance("");
    assert_eq!(p, CookTorranceParams::default());
    assert_eq!(p.distribution, Distribution::Beckmann);
    assert_eq!(p.geometry, Geometry::CookTorrance);
    assert_eq!(p.fresnel, Fresnel::Schlick);
    assert_eq!(p.specular, SpecularSource::Ior(1.5));
    assert_eq!((p.kd, p.roughness), (0.75, 0.3));
    assert_eq!(p.diffuse, Diffuse::Lambert);
}

#[test]
fn cook_torrance_every_field() {
    let p = cook_torrance(
        r#", "color": [0.1, 0.2, 0.3], "kd": 0.4, "roughness": 0.6, "ior": 1.33,
        "distribution": "ggx", "geometry": "smith_ggx_correlated", "fresnel": "dielectric",
        "diffuse": "burley""#,
    );
    assert_eq!(
        p,
        CookTorranceParams {
            color: Vec3::new(0.1, 0.2, 0.3),
            kd: 0.4,
            roughness: 0.6,
            specular: SpecularSource::Ior(1.33),
            distribution: Distribution::Ggx,
            geometry: Geometry::SmithGgxCorrelated,
            fresnel: Fresnel::Dielectric,
            diffuse: Diffuse::Burley,
        }
    );
    // Every selector value.
    for (name, d) in DISTRIBUTIONS {
        assert_eq!(
            cook_torrance(&format!(r#", "distribution": "{name}""#)).distribution,
            *d
        );
    }
    for (name, g) in GEOMETRIES {
        assert_eq!(
            cook_torrance(&format!(r#", "geometry": "{name}""#)).geometry,
            *g
        );
    }
    for (name, f) in FRESNELS {
        let source = if name.starts_with("conductor") {
            r#", "preset": "gold""#
        } else {
            ""
        };
        assert_eq!(
            cook_torrance(&format!(r#", "fresnel": "{name}"{source}"#)).fresnel,
            *f
        );
    }
    // A grey colour from one number; the range ends.
    let p = cook_torrance(r#", "color": 0.5, "kd": 0, "roughness": 1"#);
    assert_eq!((p.color, p.kd, p.roughness), (Vec3::splat(0.5), 0.0, 1.0));
}

#[test]
fn cook_torrance_specular_sources() {
    assert_eq!(
        cook_torrance(r#", "ior": 0.277"#).specular,
        SpecularSource::Ior(0.277)
    );
    assert_eq!(
        cook_torrance(r#", "f0": 0.04"#).specular,
        SpecularSource::F0(Vec3::splat(0.04))
    );
    assert_eq!(
        cook_torrance(r#", "f0": [0.9, 0.6, 0.3]"#).specular,
        SpecularSource::F0(Vec3::new(0.9, 0.6, 0.3))
    );
    let c = cook_torrance(
        r#", "complex_ior": {"eta": [0.2, 0.4, 1.4], "k": [3.6, 2.5, 1.9]}, "fresnel": "conductor""#,
    );
    let SpecularSource::Complex(ior) = c.specular else {
        panic!("{c:?}")
    };
    assert_eq!(ior.eta, Vec3::new(0.2, 0.4, 1.4));
    assert_eq!(ior.k, Vec3::new(3.6, 2.5, 1.9));
    let grey = cook_torrance(r#", "complex_ior": {"eta": 1.5, "k": 0}"#);
    assert!(
        matches!(grey.specular, SpecularSource::Complex(c) if c.eta == Vec3::splat(1.5) && c.k == Vec3::ZERO)
    );
    // Every preset the CPU reference knows, metals as complex indices, dielectrics as η.
    for name in METAL_NAMES.iter().chain(["aluminum", "Au", "GOLD"].iter()) {
        assert_eq!(
            cook_torrance(&format!(r#", "preset": "{name}", "fresnel": "conductor""#)).specular,
            SpecularSource::Complex(metal_preset(name).unwrap()),
            "{name}"
        );
    }
    for name in DIELECTRIC_NAMES.iter().chain(["bk7", "acrylic"].iter()) {
        assert_eq!(
            cook_torrance(&format!(r#", "preset": "{name}", "fresnel": "dielectric""#)).specular,
            SpecularSource::Ior(dielectric_ior(name).unwrap()),
            "{name}"
        );
    }
    // Dielectric Fresnel from an F0 is fine (η = ior_from_f0).
    assert_eq!(
        cook_torrance(r#", "f0": 0.04, "fresnel": "dielectric""#).specular,
        SpecularSource::F0(Vec3::splat(0.04))
    );
}

#[test]
fn cook_torrance_errors() {
    let ct = |rest: &str| format!(r#""model": "cook_torrance", {rest}"#);
    fails(
        &ct(r#""roughness": 1.5"#),
        &["materials.m.roughness: must be in [0, 1], got 1.5"],
    );
    fails(
        &ct(r#""roughness": -0.1"#),
        &["must be in [0, 1], got -0.1"],
    );
    fails(
        &ct(r#""kd": 2"#),
        &["materials.m.kd: must be in [0, 1], got 2"],
    );
    fails(
        &ct(r#""color": [0.5, 1.2, 0]"#),
        &["materials.m.color[1]: must be in [0, 1], got 1.2"],
    );
    fails(
        &ct(r#""color": [0.5, 0.5]"#),
        &["materials.m.color: expected a colour [r, g, b]"],
    );
    fails(&ct(r#""ior": 0"#), &["materials.m.ior: must be > 0, got 0"]);
    fails(
        &ct(r#""ior": -1.5"#),
        &["materials.m.ior: must be > 0, got -1.5"],
    );
    fails(
        &ct(r#""ior": 1e999"#),
        &["materials.m.ior: must be a finite number, got 1e999"],
    );
    fails(
        &ct(r#""ior": "glass""#),
        &["materials.m.ior: expected a number, got a string"],
    );
    fails(
        &ct(r#""f0": 1.1"#),
        &["materials.m.f0: must be in [0, 1], got 1.1"],
    );
    fails(
        &ct(r#""f0": [0.1, 0.2, -0.3]"#),
        &["materials.m.f0[2]: must be in [0, 1], got -0.3"],
    );
    fails(
        &ct(r#""complex_ior": {"eta": [0, 1, 1], "k": [1, 1, 1]}"#),
        &["materials.m.complex_ior.eta[0]: must be > 0, got 0"],
    );
    fails(
        &ct(r#""complex_ior": {"eta": 1, "k": -1}"#),
        &["materials.m.complex_ior.k: must be ≥ 0, got -1"],
    );
    fails(
        &ct(r#""complex_ior": {"eta": 1}"#),
        &["materials.m.complex_ior.k: missing required field"],
    );
    fails(
        &ct(r#""complex_ior": {"eta": 1, "k": 1, "kappa": 1}"#),
        &["materials.m.complex_ior.kappa: unknown field \"kappa\" for a complex index of refraction"],
    );
    fails(
        &ct(r#""complex_ior": [1, 2, 3]"#),
        &["materials.m.complex_ior: expected an object"],
    );
    // Two sources: the second one is reported, naming both.
    fails(
        &ct(r#""ior": 1.5, "f0": 0.04"#),
        &[
            "materials.m.f0: \"ior\" and \"f0\" both give the Fresnel reflectance",
            "ior, f0, complex_ior, preset",
        ],
    );
    fails(
        &ct(r#""preset": "gold", "complex_ior": {"eta": 1, "k": 1}"#),
        &["materials.m.complex_ior: \"preset\" and \"complex_ior\" both"],
    );
    // Presets.
    fails(
        &ct(r#""preset": "gould""#),
        &[
            "materials.m.preset: unknown preset \"gould\"",
            "metals: gold, silver",
            "dielectrics: water",
            "did you mean \"gold\"?",
        ],
    );
    fails(
        &ct(r#""preset": 3"#),
        &["materials.m.preset: expected a string, got a number"],
    );
    // Fresnel and source must agree.
    fails(
        &ct(r#""fresnel": "conductor""#),
        &[
            "materials.m.fresnel: the \"conductor\" Fresnel needs a complex index",
            "the default ior 1.5",
        ],
    );
    fails(
        &ct(r#""fresnel": "conductor", "ior": 0.277"#),
        &[
            "materials.m.fresnel: the \"conductor\" Fresnel needs a complex index",
            "got \"ior\"",
        ],
    );
    fails(
        &ct(r#""fresnel": "conductor", "preset": "glass""#),
        &["got preset \"glass\""],
    );
    fails(
        &ct(r#""fresnel": "dielectric", "preset": "gold""#),
        &[
            "materials.m.fresnel: the \"dielectric\" Fresnel takes a real index",
            "preset \"gold\"",
        ],
    );
    // Selectors.
    fails(
        &ct(r#""distribution": "phong""#),
        &["materials.m.distribution: unknown value \"phong\"; expected one of \"beckmann\", \"ggx\""],
    );
    fails(
        &ct(r#""geometry": "smith""#),
        &[
            "materials.m.geometry: unknown value \"smith\"",
            "\"smith_ggx_correlated\"",
        ],
    );
    fails(
        &ct(r#""fresnel": "schlik""#),
        &[
            "materials.m.fresnel: unknown value \"schlik\"",
            "did you mean \"schlick\"?",
        ],
    );
    fails(
        &ct(r#""fresnel": 1"#),
        &["materials.m.fresnel: expected one of \"schlick\""],
    );
    // Unknown fields, with the hint.
    fails(
        &ct(r#""roughnes": 0.5"#),
        &[
            "materials.m.roughnes: unknown field \"roughnes\" for a cook_torrance material",
            "did you mean \"roughness\"?",
        ],
    );
    fails(
        &ct(r#""base_color": 0.5"#),
        &["unknown field \"base_color\""],
    );
}

#[test]
fn metal_rough_defaults_are_gltfs() {
    let p = metal_rough("");
    assert_eq!(p, MetalRoughParams::default());
    assert_eq!(
        (p.base_color, p.metallic, p.roughness),
        (Vec3::ONE, 1.0, 1.0)
    );
    assert_eq!(p.distribution, Distribution::Ggx);
    assert_eq!(p.geometry, Geometry::SmithGgxCorrelated);
    assert_eq!(p.fresnel, Fresnel::Schlick);
    assert!(!p.diffuse_fresnel_weight);
    assert_eq!(p.diffuse, Diffuse::Lambert);
}

#[test]
fn metal_rough_every_field() {
    let p = metal_rough(
        r#", "base_color": [0.5, 0.1, 0.05], "metallic": 0.25, "roughness": 0.4,
        "distribution": "beckmann", "geometry": "smith_ggx", "fresnel": "schlick_sg",
        "diffuse_fresnel_weight": true, "diffuse": "burley",
        "sheen": {"sheenColorFactor": [0.5, 0.25, 1], "sheenRoughnessFactor": 0.3}"#,
    );
    assert_eq!(
        p,
        MetalRoughParams {
            base_color: Vec3::new(0.5, 0.1, 0.05),
            metallic: 0.25,
            roughness: 0.4,
            distribution: Distribution::Beckmann,
            geometry: Geometry::SmithGgx,
            fresnel: Fresnel::SchlickSg,
            diffuse_fresnel_weight: true,
            diffuse: Diffuse::Burley,
            dielectric_f0: Vec3::splat(0.04),
            energy_compensation: false,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            sheen_color: Vec3::new(0.5, 0.25, 1.0),
            sheen_roughness: 0.3,
            transmission: crate::brdf::Transmission::default(),
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            ..MetalRoughParams::default()
        }
    );
    // KHR_materials_anisotropy's block, with the extension's names.
    let a =
        metal_rough(r#", "anisotropy": {"anisotropyStrength": 0.6, "anisotropyRotation": -1.25}"#);
    assert_eq!((a.anisotropy_strength, a.anisotropy_rotation), (0.6, -1.25));
    // KHR_materials_iridescence's block, with the extension's names and defaults.
    let i = metal_rough(
        r#", "iridescence": {"iridescenceFactor": 0.8, "iridescenceThicknessMaximum": 520}"#,
    );
    assert_eq!(
        [
            i.iridescence,
            i.iridescence_ior,
            i.iridescence_thickness_min,
            i.iridescence_thickness_max
        ],
        [0.8, 1.3, 100.0, 520.0]
    );
    // Any Fresnel works (the exact forms take η from F0).
    for (name, f) in FRESNELS {
        assert_eq!(
            metal_rough(&format!(r#", "fresnel": "{name}""#)).fresnel,
            *f
        );
    }
    assert!(!metal_rough(r#", "diffuse_fresnel_weight": false"#).diffuse_fresnel_weight);
}

#[test]
fn metal_rough_and_cook_torrance_diffuse() {
    for (name, d) in DIFFUSES {
        let rest = format!(r#", "diffuse": "{name}""#);
        assert_eq!(metal_rough(&rest).diffuse, *d);
        assert_eq!(cook_torrance(&rest).diffuse, *d);
    }
    assert_eq!(metal_rough("").diffuse, Diffuse::Lambert);
    assert_eq!(cook_torrance("").diffuse, Diffuse::Lambert);
    // Independent of the (1 − F) weight.
    let p = metal_rough(r#", "diffuse": "burley", "diffuse_fresnel_weight": true"#);
    assert!(p.diffuse_fresnel_weight && p.diffuse == Diffuse::Burley);
    for model in ["metal_rough", "cook_torrance"] {
        fails(
            &format!(r#""model": "{model}", "diffuse": "burly""#),
            &[
                "materials.m.diffuse: unknown value \"burly\"",
                "expected one of \"lambert\", \"burley\"",
                "did you mean \"burley\"?",
            ],
        );
        fails(
            &format!(r#""model": "{model}", "diffuse": true"#),
            &["materials.m.diffuse: expected"],
        );
    }
    // Only the models with a diffuse selector take it.
    fails(
        r#""model": "principled", "diffuse": "burley""#,
        &["unknown field \"diffuse\""],
    );
}

#[test]
fn metal_rough_presets() {
    for name in METAL_NAMES {
        let p = metal_rough(&format!(r#", "preset": "{name}", "roughness": 0.3"#));
        let f0 = metal_preset(name).unwrap().f0();
        assert_eq!((p.base_color, p.metallic, p.roughness), (f0, 1.0, 0.3));
        assert!(f0.min_element() > 0.0 && f0.max_element() <= 1.0);
    }
    let gold = metal_rough(r#", "preset": "gold""#).base_color;
    assert!((gold - Vec3::new(0.957, 0.792, 0.408)).abs().max_element() < 1e-3);
    let mr = |rest: &str| format!(r#""model": "metal_rough", {rest}"#);
    fails(
        &mr(r#""preset": "gold", "base_color": [1, 1, 1]"#),
        &["materials.m.base_color: a preset sets base_color and metallic"],
    );
    fails(
        &mr(r#""metallic": 0.5, "preset": "gold""#),
        &["materials.m.metallic: a preset sets base_color and metallic"],
    );
    fails(
        &mr(r#""preset": "glass""#),
        &["materials.m.preset: \"glass\" is a dielectric; metal_rough presets are metals"],
    );
    fails(
        &mr(r#""preset": "coper""#),
        &[
            "materials.m.preset: unknown metal preset \"coper\"",
            "did you mean \"copper\"?",
        ],
    );
}

#[test]
fn metal_rough_errors() {
    let mr = |rest: &str| format!(r#""model": "metal_rough", {rest}"#);
    fails(
        &mr(r#""metallic": 1.01"#),
        &["materials.m.metallic: must be in [0, 1], got 1.01"],
    );
    fails(
        &mr(r#""roughness": 2"#),
        &["materials.m.roughness: must be in [0, 1], got 2"],
    );
    fails(
        &mr(r#""base_color": 1.5"#),
        &["materials.m.base_color: must be in [0, 1], got 1.5"],
    );
    fails(
        &mr(r#""base_color": "red""#),
        &["materials.m.base_color: expected a colour"],
    );
    fails(
        &mr(r#""diffuse_fresnel_weight": 1"#),
        &["materials.m.diffuse_fresnel_weight: expected true or false, got a number"],
    );
    fails(
        &mr(r#""geometry": "cook_torance""#),
        &[
            "materials.m.geometry: unknown value \"cook_torance\"",
            "did you mean \"cook_torrance\"?",
        ],
    );
    fails(
        &mr(r#""ior": "glass""#),
        &["materials.m.ior: expected an object"],
    );
    fails(&mr(r#""metalic": 1"#), &["did you mean \"metallic\"?"]);
}

#[test]
fn principled_defaults_are_disneys() {
    let p = principled("");
    assert_eq!(p, PrincipledParams::default());
    assert_eq!(p.base_color, Vec3::new(0.82, 0.67, 0.16));
    assert_eq!(
        (p.specular, p.roughness, p.sheen_tint, p.clearcoat_gloss),
        (0.5, 0.5, 0.5, 1.0)
    );
}

#[test]
fn principled_every_field() {
    let p = principled(
        r#", "base_color": [0.9, 0.1, 0.2], "subsurface": 0.1, "metallic": 0.2, "specular": 0.3,
        "specular_tint": 0.4, "roughness": 0.5, "anisotropic": 0.6, "sheen": 0.7,
        "sheen_tint": 0.8, "clearcoat": 0.9, "clearcoat_gloss": 0.05"#,
    );
    assert_eq!(
        p,
        PrincipledParams {
            base_color: Vec3::new(0.9, 0.1, 0.2),
            subsurface: 0.1,
            metallic: 0.2,
            specular: 0.3,
            specular_tint: 0.4,
            roughness: 0.5,
            anisotropic: 0.6,
            sheen: 0.7,
            sheen_tint: 0.8,
            clearcoat: 0.9,
            clearcoat_gloss: 0.05,
        }
    );
}

#[test]
fn principled_errors() {
    for field in [
        "subsurface",
        "metallic",
        "specular",
        "specular_tint",
        "roughness",
        "anisotropic",
        "sheen",
        "sheen_tint",
        "clearcoat",
        "clearcoat_gloss",
    ] {
        let p = |v: &str| format!(r#""model": "principled", "{field}": {v}"#);
        fails(
            &p("1.5"),
            &[&format!("materials.m.{field}: must be in [0, 1], got 1.5")],
        );
        fails(
            &p("-0.5"),
            &[&format!("materials.m.{field}: must be in [0, 1], got -0.5")],
        );
        fails(
            &p("1e999"),
            &[&format!(
                "materials.m.{field}: must be a finite number, got 1e999"
            )],
        );
        fails(
            &p("NaN"),
            &[&format!(
                "materials.m.{field}: NaN is not a number JSON allows"
            )],
        );
        fails(
            &p("\"0.5\""),
            &[&format!(
                "materials.m.{field}: expected a number, got a string"
            )],
        );
        fails(
            &p("[0.5]"),
            &[&format!(
                "materials.m.{field}: expected a number, got an array"
            )],
        );
        assert!(material(&p("0")).is_ok());
        assert!(material(&p("1")).is_ok());
    }
    fails(
        r#""model": "principled", "base_color": [1, 0.5, 2]"#,
        &["materials.m.base_color[2]: must be in [0, 1], got 2"],
    );
    fails(
        r#""model": "principled", "clearcoatGloss": 1"#,
        &[
            "unknown field \"clearcoatGloss\" for a principled material",
            "did you mean \"clearcoat_gloss\"?",
        ],
    );
    fails(
        r#""model": "principled", "diffuse_fresnel_weight": true"#,
        &["unknown field \"diffuse_fresnel_weight\""],
    );
}

#[test]
fn oren_nayar_fields_and_errors() {
    assert_eq!(oren_nayar(""), OrenNayarParams::default());
    assert_eq!(
        oren_nayar(r#", "albedo": [0.7, 0.6, 0.5], "sigma_deg": 30"#),
        OrenNayarParams {
            albedo: Vec3::new(0.7, 0.6, 0.5),
            sigma_deg: 30.0
        }
    );
    assert_eq!(oren_nayar(r#", "sigma_deg": 0"#).sigma_deg, 0.0);
    assert_eq!(oren_nayar(r#", "sigma_deg": 90"#).sigma_deg, 90.0);
    let on = |rest: &str| format!(r#""model": "oren_nayar", {rest}"#);
    fails(
        &on(r#""sigma_deg": 91"#),
        &["materials.m.sigma_deg: must be in [0, 90], got 91"],
    );
    fails(
        &on(r#""sigma_deg": -1"#),
        &["materials.m.sigma_deg: must be in [0, 90], got -1"],
    );
    fails(
        &on(r#""albedo": [0.5, 0.5, 1.01]"#),
        &["materials.m.albedo[2]: must be in [0, 1], got 1.01"],
    );
    fails(
        &on(r#""sigma": 20"#),
        &[
            "unknown field \"sigma\" for an oren_nayar material",
            "did you mean \"sigma_deg\"?",
        ],
    );
}

/// A decoded material is the CPU reference's model, and the model the CPU reference reads back
/// from its own serde form of them is the same.
#[test]
fn material_is_the_reference_model() {
    let bodies = [
        r#""model": "cook_torrance", "color": [0.1, 0.2, 0.3], "kd": 0.4, "roughness": 0.6, "preset": "copper", "distribution": "ggx", "geometry": "schlick_ggx", "fresnel": "conductor""#,
        r#""model": "cook_torrance", "f0": [0.9, 0.6, 0.3], "fresnel": "schlick_sg""#,
        r#""model": "metal_rough", "base_color": [0.5, 0.1, 0.05], "metallic": 0.25, "roughness": 0.4, "diffuse_fresnel_weight": true"#,
        r#""model": "principled", "base_color": [0.9, 0.1, 0.2], "subsurface": 0.1, "anisotropic": 0.6, "clearcoat": 0.9"#,
        r#""model": "oren_nayar", "albedo": 0.5, "sigma_deg": 45"#,
    ];
    for body in bodies {
        let m = ok(body);
        let brdf = m;
        match (&m, brdf) {
            (Material::CookTorrance(p), Model::CookTorrance(q)) => assert_eq!(*p, q),
            (Material::MetalRough(p), Model::MetalRough(q)) => assert_eq!(*p, q),
            (Material::Principled(p), Model::Principled(q)) => assert_eq!(*p, q),
            (Material::OrenNayar(p), Model::OrenNayar(q)) => assert_eq!(*p, q),
            other => panic!("{other:?}"),
        }
        // The CPU reference's own JSON form has the same model name and reads back equal.
        let json = serde_json::to_value(brdf).unwrap();
        assert_eq!(json["model"].as_str(), Some(m.name()), "{json}");
        let back: Model = serde_json::from_value(json).unwrap();
        assert_eq!(back, brdf);
        // Decoded parameters are already within the ranges the reference sanitises to.
        let same = match brdf {
            Model::CookTorrance(p) => p.sanitized() == p,
            Model::MetalRough(p) => p.sanitized() == p,
            Model::Principled(p) => p.sanitized() == p,
            Model::OrenNayar(p) => p.sanitized() == p,
            _ => false,
        };
        assert!(same, "{body}");
    }
}

/// Every file under assets/scenes/brdf/ loads and uses only physically based models.
#[test]
fn brdf_scenes() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("assets/scenes/brdf");
    let load_one = |name: &str| load(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
    let spheres = load_one("seed000_spheres.json");
    assert_eq!(spheres.objects.len(), 20);
    assert!(spheres
        .materials
        .iter()
        .all(|m| matches!(m.material, Material::Principled(_))));
    assert_eq!((spheres.output.width, spheres.output.height), (1280, 720));
    let kinds: Vec<_> = spheres.lights.iter().map(|l| l.kind).collect();
    assert_eq!(kinds, [LightKind::Directional, LightKind::Point]);

    for name in [
        "seed000_demo01_cook_torrance.json",
        "seed000_demo01_principled.json",
    ] {
        let s = load_one(name);
        assert_eq!(s.camera.fov_y_deg, 75.0, "{name}");
        // 0x50 decoded from sRGB.
        assert!((s.ambient - Vec3::splat(0.0802)).abs().max_element() < 1e-4);
        assert_eq!(s.lights.len(), 4);
        let white = s.lights[0];
        let from_to = Vec3::new(-1.0, -1.0, 0.0).normalize();
        assert!((white.direction - from_to).length() < 1e-6, "{name}");
        let spot = s.lights[3];
        assert_eq!(spot.kind, LightKind::Spot);
        assert_eq!(spot.position, Vec3::new(0.0, 1.5, 5.0));
        assert_eq!(spot.umbra_deg, 35.0);
        assert_eq!(s.objects.len(), 4);
        let model = if name.contains("cook") {
            "cook_torrance"
        } else {
            "principled"
        };
        assert!(s.materials.iter().all(|m| m.material.name() == model));
    }
    let ct = load_one("seed000_demo01_cook_torrance.json");
    let gold = &ct.materials[ct.material_index("gold").unwrap()].material;
    assert!(
        matches!(gold, Material::CookTorrance(p) if p.specular == SpecularSource::Complex(metal_preset("gold").unwrap()))
    );

    let grid = load_one("seed001_grid.json");
    assert_eq!(grid.objects.len(), 49);
    assert_eq!(grid.lights.len(), 4);
    assert!(grid
        .materials
        .iter()
        .all(|m| matches!(m.material, Material::MetalRough(_))));

    let bg = load_one("beckmann_vs_ggx.json");
    assert_eq!(bg.objects.len(), 10);
    let d: Vec<Distribution> = bg
        .objects
        .iter()
        .map(|o| match bg.materials[o.material].material {
            Material::CookTorrance(p) => p.distribution,
            ref m => panic!("{m:?}"),
        })
        .collect();
    assert_eq!(
        d.iter().filter(|d| **d == Distribution::Beckmann).count(),
        5
    );
    assert_eq!(d.iter().filter(|d| **d == Distribution::Ggx).count(), 5);

    let sc = load_one("smith_separable_vs_correlated.json");
    assert_eq!(sc.objects.len(), 10);
    let g: Vec<Geometry> = sc
        .objects
        .iter()
        .map(|o| match sc.materials[o.material].material {
            Material::MetalRough(p) => p.geometry,
            ref m => panic!("{m:?}"),
        })
        .collect();
    assert_eq!(g.iter().filter(|g| **g == Geometry::SmithGgx).count(), 5);
    assert_eq!(
        g.iter()
            .filter(|g| **g == Geometry::SmithGgxCorrelated)
            .count(),
        5
    );

    for s in [&spheres, &ct, &grid, &bg, &sc] {
        assert!(s.triangle_count() < 250_000, "{}", s.triangle_count());
    }
}

/// Issue 34: a metal-rough material with the Beckmann distribution gets Beckmann's own Smith term
/// unless it names another geometry (the GGX form at the Beckmann width stays selectable).
#[test]
fn beckmann_defaults_to_its_own_smith_term() {
    assert_eq!(
        metal_rough(r#", "distribution": "beckmann""#).geometry,
        Geometry::SmithBeckmann
    );
    assert_eq!(
        metal_rough(r#", "distribution": "beckmann", "geometry": "smith_ggx_correlated""#).geometry,
        Geometry::SmithGgxCorrelated
    );
    assert_eq!(
        metal_rough(r#", "distribution": "ggx""#).geometry,
        Geometry::SmithGgxCorrelated
    );
}

/// KHR_materials_clearcoat on metal_rough (issue 34): the extension's names, its defaults (no
/// coat), the values given, and errors naming the JSON path.
#[test]
fn metal_rough_clearcoat_fields_and_errors() {
    let d = metal_rough("");
    assert_eq!((d.clearcoat, d.clearcoat_roughness), (0.0, 0.0));
    let p = metal_rough(
        r#", "clearcoat": {"clearcoatFactor": 0.75, "clearcoatRoughnessFactor": 0.25}"#,
    );
    assert_eq!((p.clearcoat, p.clearcoat_roughness), (0.75, 0.25));
    let p = metal_rough(r#", "clearcoat": {"clearcoatFactor": 1}"#);
    assert_eq!((p.clearcoat, p.clearcoat_roughness), (1.0, 0.0));
    let mr = |rest: &str| format!(r#""model": "metal_rough", "clearcoat": {rest}"#);
    fails(
        &mr(r#"{"clearcoatFactor": 1.5}"#),
        &["materials.m.clearcoat.clearcoatFactor: must be in [0, 1], got 1.5"],
    );
    fails(
        &mr(r#"{"clearcoatRoughnessFactor": -0.1}"#),
        &["materials.m.clearcoat.clearcoatRoughnessFactor: must be in [0, 1], got -0.1"],
    );
    fails(
        &mr(r#"{"clearcoatFactor": "1"}"#),
        &["materials.m.clearcoat.clearcoatFactor"],
    );
    fails(&mr("0.5"), &["materials.m.clearcoat"]);
    fails(
        &mr(r#"{"clearcoatTexture": {"index": 0}}"#),
        &["materials.m.clearcoat", "clearcoatTexture"],
    );
}

/// Issue 34: metal_rough's dielectric F0 from KHR_materials_ior's and KHR_materials_specular's
/// fields (the extensions' names and formula, as glTF files give it), or `dielectric_f0` itself
/// (what the encoder writes); bad values name the field.
#[test]
fn metal_rough_ior_and_specular_set_the_dielectric_f0() {
    assert_eq!(metal_rough("").dielectric_f0, Vec3::splat(0.04));
    let water = ((1.33f32 - 1.0) / (1.33 + 1.0)).powi(2);
    assert_eq!(
        metal_rough(r#", "ior": {"ior": 1.33}"#).dielectric_f0,
        Vec3::splat(water)
    );
    assert_eq!(
        metal_rough(r#", "ior": 1.33"#).dielectric_f0,
        Vec3::splat(water)
    );
    // ior 0: the extension's special value, F0 = 1.
    assert_eq!(
        metal_rough(r#", "ior": {"ior": 0}"#).dielectric_f0,
        Vec3::ONE
    );
    // min(F0(ior) · colour, 1) · factor.
    let p = metal_rough(
        r#", "ior": {"ior": 2}, "specular": {"specularFactor": 0.5, "specularColorFactor": [1, 2, 100]}"#,
    );
    let f0 = 1.0f32 / 9.0;
    let want = Vec3::new(f0 * 0.5, 2.0 * f0 * 0.5, 0.5);
    assert!(
        (p.dielectric_f0 - want).abs().max_element() < 1e-6,
        "{} against {want}",
        p.dielectric_f0
    );
    // specularFactor is the dielectric's F90 too.
    assert_eq!(p.dielectric_f90, 0.5);
    assert_eq!(
        metal_rough(r#", "dielectric_f0": [0.1, 0.2, 0.3]"#).dielectric_f0,
        Vec3::new(0.1, 0.2, 0.3)
    );
    // What the encoder writes for them.
    let q = metal_rough(r#", "dielectric_f0": [0.1, 0.2, 0.3], "dielectric_f90": 0.25"#);
    assert_eq!(
        (q.dielectric_f0, q.dielectric_f90),
        (Vec3::new(0.1, 0.2, 0.3), 0.25)
    );
    let m = r#""model": "metal_rough", "#;
    fails(
        &format!(r#"{m}"ior": {{"ior": 0.5}}"#),
        &[
            "materials.m.ior.ior",
            "0 (the extension's special value) or at least 1, got 0.5",
        ],
    );
    fails(
        &format!(r#"{m}"ior": {{"ior": -1}}"#),
        &["materials.m.ior.ior"],
    );
    fails(
        &format!(r#"{m}"specular": {{"specularFactor": 2}}"#),
        &["materials.m.specular.specularFactor"],
    );
    fails(
        &format!(r#"{m}"specular": {{"specularColorFactor": [1, -1, 1]}}"#),
        &["materials.m.specular.specularColorFactor"],
    );
    fails(
        &format!(r#"{m}"specular": {{"specularTexture": {{}}}}"#),
        &["materials.m.specular", "specularTexture"],
    );
    fails(
        &format!(r#"{m}"dielectric_f0": [0.1, 0.1, 0.1], "ior": {{"ior": 1.5}}"#),
        &["materials.m.ior", "dielectric_f0"],
    );
    fails(
        &format!(r#"{m}"dielectric_f0": [0.1, 2, 0.1]"#),
        &["materials.m.dielectric_f0"],
    );
}
