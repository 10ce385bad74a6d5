//! Materials: one decoder per model (the `model` names are `brdf::ModelKind`'s), the BRDF term
//! selectors and the Cook-Torrance specular sources.

use super::*;
use crate::brdf::{ModelKind, Transmission};

pub(super) type MaterialDecoder = fn(&Fields, &str) -> Result<Material>;

/// Every model, in the order the format (and its error messages) lists them; the names are
/// [`ModelKind::name`].
pub const MATERIAL_MODELS: [ModelKind; 7] = [
    ModelKind::Phong,
    ModelKind::BlinnPhong,
    ModelKind::Lambert,
    ModelKind::CookTorrance,
    ModelKind::MetalRough,
    ModelKind::Principled,
    ModelKind::OrenNayar,
];

/// The decoder of a model (a new `ModelKind` does not compile without one).
fn decoder(kind: ModelKind) -> MaterialDecoder {
    match kind {
        ModelKind::Phong | ModelKind::BlinnPhong => phong,
        ModelKind::Lambert => lambert,
        ModelKind::CookTorrance => cook_torrance,
        ModelKind::MetalRough => metal_rough,
        ModelKind::Principled => principled,
        ModelKind::OrenNayar => oren_nayar,
    }
}

/// The `distribution` selector (the names are `brdf::Distribution::name`).
pub(crate) const DISTRIBUTIONS: &[(&str, Distribution)] = &Distribution::NAMED;

/// The `geometry` selector.
pub(crate) const GEOMETRIES: &[(&str, Geometry)] = &Geometry::NAMED;

/// The `fresnel` selector.
pub(crate) const FRESNELS: &[(&str, Fresnel)] = &Fresnel::NAMED;

/// The `diffuse` selector (Cook-Torrance and metal_rough).
pub(crate) const DIFFUSES: &[(&str, Diffuse)] = &Diffuse::NAMED;

/// Where metal_rough's thin film takes its Fresnel: `iridescence_at_view` false or true.
pub(crate) const FILM_ANGLES: &[(&str, bool)] = &[("half_vector", false), ("view", true)];

/// Cook-Torrance's specular (Fresnel) sources; a material gives at most one.
pub(super) const SPECULAR_SOURCES: &[&str] = &["ior", "f0", "complex_ior", "preset"];

/// Every unit-range parameter in [0, 1].
pub(super) const UNIT: Check = Check::In(0.0, 1.0);

pub(super) fn material(v: &Value, path: &str) -> Result<Material> {
    let f = Fields::new(v, path)?;
    let names = MATERIAL_MODELS.map(|k| k.name());
    let model = choice(f.req("model")?, &f.path("model"), &names)?;
    let decode = ModelKind::from_name(model).map_or(phong as MaterialDecoder, decoder);
    decode(&f, model)
}

pub(super) fn phong(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &[
            "model",
            "textures",
            "ka",
            "kd",
            "ks",
            "shininess",
            "diffuse_color",
            "specular_color",
        ],
        &a_material(model),
    )?;
    // Start from the documented defaults and override what the file gives.
    let mut m = Material::default_phong(model == "blinn_phong");
    if let Material::Phong(p) = &mut m {
        p.ka = f.num("ka", p.ka, Check::NonNegative)?;
        p.kd = f.num("kd", p.kd, Check::NonNegative)?;
        p.ks = f.num("ks", p.ks, Check::NonNegative)?;
        p.shininess = f.num("shininess", p.shininess, Check::NonNegative)?;
        p.diffuse_color = f.color("diffuse_color", p.diffuse_color)?;
        p.specular_color = f.color("specular_color", p.specular_color)?;
    }
    Ok(m)
}

pub(super) fn lambert(f: &Fields, model: &str) -> Result<Material> {
    f.allow(&["model", "albedo", "textures"], &a_material(model))?;
    let albedo = f.color("albedo", Vec3::splat(0.8))?;
    if albedo.max_element() > 1.0 {
        return Err(f.err(
            "albedo",
            format!(
                "every channel must be in [0, 1] (energy conservation), got [{}, {}, {}]",
                show(albedo.x),
                show(albedo.y),
                show(albedo.z)
            ),
        ));
    }
    Ok(Material::Lambert(crate::brdf::LambertParams { albedo }))
}

/// Cook-Torrance (seed 000). Defaults are `brdf::CookTorranceParams::default()`.
pub(super) fn cook_torrance(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &[
            "model",
            "textures",
            "color",
            "kd",
            "roughness",
            "ior",
            "f0",
            "complex_ior",
            "preset",
            "distribution",
            "geometry",
            "fresnel",
            "diffuse",
        ],
        &a_material(model),
    )?;
    let d = CookTorranceParams::default();
    let color = f.color_in("color", d.color, UNIT)?;
    let kd = f.num("kd", d.kd, UNIT)?;
    let roughness = f.num("roughness", d.roughness, UNIT)?;
    let distribution = f.select("distribution", DISTRIBUTIONS, d.distribution)?;
    let geometry = f.select("geometry", GEOMETRIES, d.geometry)?;
    let fresnel = f.select("fresnel", FRESNELS, d.fresnel)?;
    let diffuse = f.select("diffuse", DIFFUSES, d.diffuse)?;
    let source = specular_source(f)?;
    let name = |s: &Option<(&str, SpecularSource)>| match s {
        Some(("preset", _)) => format!(
            "preset \"{}\"",
            f.string("preset").ok().flatten().unwrap_or("")
        ),
        Some((key, _)) => format!("\"{key}\""),
        None => "the default ior 1.5".to_string(),
    };
    match (fresnel, &source) {
        (Fresnel::Conductor | Fresnel::ConductorExact, Some((_, SpecularSource::Complex(_)))) => {}
        (Fresnel::Conductor | Fresnel::ConductorExact, s) => {
            return Err(f.err(
                "fresnel",
                format!(
                    "the \"{}\" Fresnel needs a complex index of refraction (η and κ), got {}; give complex_ior {{\"eta\": [r, g, b], \"k\": [r, g, b]}} or a metal preset ({})",
                    fresnel.name(),
                    name(s),
                    METAL_NAMES.join(", ")
                ),
            ))
        }
        (Fresnel::Dielectric, s @ Some((_, SpecularSource::Complex(_)))) => {
            return Err(f.err(
                "fresnel",
                format!(
                    "the \"dielectric\" Fresnel takes a real index of refraction, but {} is a complex one (its κ would be dropped); give ior or f0, or use fresnel \"conductor\" or \"schlick\"",
                    name(s)
                ),
            ))
        }
        _ => {}
    }
    Ok(Material::CookTorrance(CookTorranceParams {
        color,
        kd,
        roughness,
        specular: source.map_or(d.specular, |(_, s)| s),
        distribution,
        geometry,
        fresnel,
        diffuse,
    }))
}

/// The one specular source of a Cook-Torrance material (`None`: not given), with its key.
pub(super) fn specular_source(f: &Fields) -> Result<Option<(&'static str, SpecularSource)>> {
    let Some(key) = f.exclusive(SPECULAR_SOURCES, "the Fresnel reflectance")? else {
        return Ok(None);
    };
    let v = f.get(key).unwrap_or(&NULL);
    let path = f.path(key);
    let source = match key {
        "ior" => SpecularSource::Ior(number(v, &path, Check::Positive)?),
        "f0" => SpecularSource::F0(color_in(v, &path, UNIT)?),
        "complex_ior" => SpecularSource::Complex(complex_ior(v, &path)?),
        _ => {
            let name = string(v, &path)?;
            if let Some(c) = metal_preset(name) {
                SpecularSource::Complex(c)
            } else if let Some(eta) = dielectric_ior(name) {
                SpecularSource::Ior(eta)
            } else {
                let all: Vec<&str> = METAL_NAMES
                    .iter()
                    .chain(&DIELECTRIC_NAMES)
                    .copied()
                    .collect();
                return Err(Invalid::new(
                    &path,
                    format!(
                        "unknown preset \"{name}\"; metals: {}; dielectrics: {}{}",
                        METAL_NAMES.join(", "),
                        DIELECTRIC_NAMES.join(", "),
                        suggestion(name, &all)
                    ),
                ));
            }
        }
    };
    Ok(Some((key, source)))
}

pub(super) const NULL: Value = Value {
    kind: Kind::Null,
    line: 0,
    column: 0,
};

/// `{"eta": [r, g, b], "k": [r, g, b]}` (either may be one number for all channels).
pub(super) fn complex_ior(v: &Value, path: &str) -> Result<ComplexIor> {
    let f = Fields::new(v, path)?;
    f.allow(&["eta", "k"], "a complex index of refraction")?;
    let eta = color_in(f.req("eta")?, &f.path("eta"), Check::Positive)?;
    let k = color_in(f.req("k")?, &f.path("k"), Check::NonNegative)?;
    Ok(ComplexIor { eta, k })
}

/// glTF metallic-roughness (seed 001). Defaults are `brdf::MetalRoughParams::default()` (glTF's).
pub(super) fn metal_rough(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &[
            "model",
            "textures",
            "base_color",
            "metallic",
            "roughness",
            "preset",
            "distribution",
            "geometry",
            "fresnel",
            "diffuse_fresnel_weight",
            "diffuse",
            "clearcoat",
            "sheen",
            "anisotropy",
            "iridescence",
            "iridescence_angle",
            "transmission",
            "volume",
            "dispersion",
            "diffuse_transmission",
            "ior",
            "specular",
            "dielectric_f0",
            "dielectric_f90",
        ],
        &a_material(model),
    )?;
    let d = MetalRoughParams::default();
    let transmission = transmission(f)?;
    let (dielectric_f0, dielectric_f90) = dielectric_f0(f)?;
    let (clearcoat, clearcoat_roughness) = match f.get("clearcoat") {
        None => (d.clearcoat, d.clearcoat_roughness),
        Some(v) => clearcoat(v, &f.path("clearcoat"))?,
    };
    let (sheen_color, sheen_roughness) = match f.get("sheen") {
        None => (d.sheen_color, d.sheen_roughness),
        Some(v) => sheen(v, &f.path("sheen"))?,
    };
    let (base_color, metallic) = match f.string("preset")? {
        None => (
            f.color_in("base_color", d.base_color, UNIT)?,
            f.num("metallic", d.metallic, UNIT)?,
        ),
        Some(name) => {
            for key in ["base_color", "metallic"] {
                if f.has(key) {
                    return Err(f.err(
                        key,
                        format!("a preset sets base_color and metallic; give either the preset \"{name}\" or {key}, not both"),
                    ));
                }
            }
            let Some(c) = metal_preset(name) else {
                let reason = if dielectric_ior(name).is_some() {
                    format!("\"{name}\" is a dielectric; metal_rough presets are metals (a dielectric is metallic 0 with its F0 fixed at 0.04): {}", METAL_NAMES.join(", "))
                } else {
                    format!(
                        "unknown metal preset \"{name}\"; expected one of: {}{}",
                        METAL_NAMES.join(", "),
                        suggestion(name, &METAL_NAMES)
                    )
                };
                return Err(f.err("preset", reason));
            };
            (c.f0(), 1.0)
        }
    };
    let distribution = f.select("distribution", DISTRIBUTIONS, d.distribution)?;
    let (anisotropy_strength, anisotropy_rotation) = match f.get("anisotropy") {
        None => (d.anisotropy_strength, d.anisotropy_rotation),
        Some(v) => {
            let a = anisotropy(v, &f.path("anisotropy"))?;
            if a.0 > 0.0 && distribution != Distribution::Ggx {
                return Err(f.err(
                    "anisotropy",
                    "KHR_materials_anisotropy stretches the GGX lobe; it needs \"distribution\": \"ggx\"".to_string(),
                ));
            }
            a
        }
    };
    let film = match f.get("iridescence") {
        None => [
            d.iridescence,
            d.iridescence_ior,
            d.iridescence_thickness_min,
            d.iridescence_thickness_max,
        ],
        Some(v) => iridescence(v, &f.path("iridescence"))?,
    };
    // Beckmann's own Smith term is its default (issue 34: the GGX forms at the Beckmann width
    // were 1.4 % RMSE from Mitsuba, 5.9 % at grazing); "smith_ggx_correlated" keeps the old one.
    let default_geometry = match distribution {
        Distribution::Beckmann => Geometry::SmithBeckmann,
        Distribution::Ggx => d.geometry,
    };
    Ok(Material::MetalRough(MetalRoughParams {
        base_color,
        metallic,
        roughness: f.num("roughness", d.roughness, UNIT)?,
        distribution,
        geometry: f.select("geometry", GEOMETRIES, default_geometry)?,
        fresnel: f.select("fresnel", FRESNELS, d.fresnel)?,
        diffuse_fresnel_weight: f.boolean("diffuse_fresnel_weight", d.diffuse_fresnel_weight)?,
        diffuse: f.select("diffuse", DIFFUSES, d.diffuse)?,
        dielectric_f0,
        dielectric_f90,
        // The environment's switch, applied where the scene is rendered.
        energy_compensation: false,
        clearcoat,
        clearcoat_roughness,
        sheen_color,
        sheen_roughness,
        transmission,
        anisotropy_strength,
        anisotropy_rotation,
        iridescence: film[0],
        iridescence_ior: film[1],
        iridescence_thickness_min: film[2],
        iridescence_thickness_max: film[3],
        iridescence_at_view: f.select("iridescence_angle", FILM_ANGLES, d.iridescence_at_view)?,
        clearcoat_normal: None,
    }))
}

/// KHR_materials_iridescence's factors, with the extension's names and defaults:
/// `{"iridescenceFactor": 1, "iridescenceIor": 1.3, "iridescenceThicknessMinimum": 100,
/// "iridescenceThicknessMaximum": 400}` (factor 0 by default; ior ≥ 1; thicknesses in nm, ≥ 0,
/// the minimum not above the maximum). Returns [factor, ior, minimum, maximum].
fn iridescence(v: &Value, path: &str) -> Result<[f32; 4]> {
    let f = Fields::new(v, path)?;
    f.allow(
        &[
            "iridescenceFactor",
            "iridescenceIor",
            "iridescenceThicknessMinimum",
            "iridescenceThicknessMaximum",
        ],
        "an iridescence (KHR_materials_iridescence; its textures are the `iridescence` and `iridescence_thickness` maps in \"textures\")",
    )?;
    let d = MetalRoughParams::default();
    let ior = f.num("iridescenceIor", d.iridescence_ior, Check::NonNegative)?;
    if let Some(why) = crate::brdf::film_ior_error(ior) {
        return Err(f.err("iridescenceIor", why));
    }
    let min = f.num(
        "iridescenceThicknessMinimum",
        d.iridescence_thickness_min,
        Check::NonNegative,
    )?;
    let max = f.num(
        "iridescenceThicknessMaximum",
        d.iridescence_thickness_max,
        Check::NonNegative,
    )?;
    if let Some(why) = crate::brdf::film_range_error(min, max) {
        return Err(f.err("iridescenceThicknessMinimum", why));
    }
    Ok([f.num("iridescenceFactor", 0.0, UNIT)?, ior, min, max])
}

/// KHR_materials_anisotropy's factors, with the extension's names:
/// `{"anisotropyStrength": 0.6, "anisotropyRotation": 1.57}` (defaults 0 and 0; the rotation in
/// radians, any finite number).
fn anisotropy(v: &Value, path: &str) -> Result<(f32, f32)> {
    let f = Fields::new(v, path)?;
    f.allow(
        &["anisotropyStrength", "anisotropyRotation"],
        "an anisotropy (KHR_materials_anisotropy; its texture is the `anisotropy` map in \"textures\")",
    )?;
    Ok((
        f.num("anisotropyStrength", 0.0, UNIT)?,
        f.num("anisotropyRotation", 0.0, Check::Any)?,
    ))
}

/// The dielectric F0 of a metal_rough material: KHR_materials_ior's `{"ior": 1.5}` (0 or ≥ 1;
/// 0 is the extension's F0 = 1) and KHR_materials_specular's `{"specularFactor": 1,
/// "specularColorFactor": [1, 1, 1]}` (factor in [0, 1], colour ≥ 0), combined as the
/// specification does ([`MetalRoughParams::dielectric_f0_from`]), with F90 = `specularFactor`;
/// or `dielectric_f0` itself (RGB in [0, 1], what the encoder writes) and `dielectric_f90`
/// (in [0, 1], default 1), not with either.
fn dielectric_f0(f: &Fields) -> Result<(Vec3, f32)> {
    if f.has("dielectric_f0") || f.has("dielectric_f90") {
        let key = if f.has("dielectric_f0") {
            "dielectric_f0"
        } else {
            "dielectric_f90"
        };
        if let Some(other) = ["ior", "specular"].into_iter().find(|k| f.has(k)) {
            return Err(f.err(
                other,
                format!("\"{key}\" already gives the dielectric's Fresnel; give either it or ior/specular, not both"),
            ));
        }
        let f0 = match f.get("dielectric_f0") {
            Some(v) => color_in(v, &f.path("dielectric_f0"), UNIT)?,
            None => Vec3::splat(0.04),
        };
        return Ok((f0, f.num("dielectric_f90", 1.0, UNIT)?));
    }
    let ior = match f.get("ior") {
        None => None,
        // `"ior": 1.33` or the extension's `"ior": {"ior": 1.33}`.
        Some(v) => {
            let (ior, at) = if matches!(v.kind, Kind::Number { .. }) {
                (
                    number(v, &f.path("ior"), Check::NonNegative)?,
                    f.path("ior"),
                )
            } else {
                let g = Fields::new(v, &f.path("ior"))?;
                g.allow(&["ior"], "an index of refraction (KHR_materials_ior)")?;
                (g.num("ior", 1.5, Check::NonNegative)?, g.path("ior"))
            };
            if ior != 0.0 && ior < 1.0 {
                return Err(Invalid::new(
                    &at,
                    format!("must be 0 (the extension's special value) or at least 1, got {ior}"),
                ));
            }
            Some(ior)
        }
    };
    let (factor, color) = match f.get("specular") {
        None => (1.0, Vec3::ONE),
        Some(v) => {
            let g = Fields::new(v, &f.path("specular"))?;
            g.allow(
                &["specularFactor", "specularColorFactor"],
                "a specular block (KHR_materials_specular; its textures are the `specular_factor` and `specular_color` maps in \"textures\")",
            )?;
            (
                g.num("specularFactor", 1.0, UNIT)?,
                g.color_in("specularColorFactor", Vec3::ONE, Check::NonNegative)?,
            )
        }
    };
    Ok((
        MetalRoughParams::dielectric_f0_from(ior, factor, color),
        factor,
    ))
}

/// KHR_materials_sheen's factors, with the extension's names:
/// `{"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5}` (defaults black and 0).
fn sheen(v: &Value, path: &str) -> Result<(Vec3, f32)> {
    let f = Fields::new(v, path)?;
    f.allow(
        &["sheenColorFactor", "sheenRoughnessFactor"],
        "a sheen (KHR_materials_sheen; its textures are the `sheen_color` and `sheen_roughness` maps in \"textures\")",
    )?;
    Ok((
        f.color_in("sheenColorFactor", Vec3::ZERO, UNIT)?,
        f.num("sheenRoughnessFactor", 0.0, UNIT)?,
    ))
}

/// Issue 35's four extensions on a metal-rough material, each an object with the extension's
/// own names: `"transmission": {"transmissionFactor"}`, `"volume": {"thicknessFactor",
/// "attenuationDistance", "attenuationColor"}`, `"dispersion": {"dispersion"}`,
/// `"diffuse_transmission": {"diffuseTransmissionFactor", "diffuseTransmissionColorFactor"}`.
/// Defaults are the extensions' (nothing goes through).
fn transmission(f: &Fields) -> Result<Transmission> {
    let mut t = Transmission::default();
    if let Some(v) = f.get("transmission") {
        let g = Fields::new(v, &f.path("transmission"))?;
        g.allow(
            &["transmissionFactor"],
            "transmission (KHR_materials_transmission; its texture is the `transmission` map in \"textures\")",
        )?;
        t.factor = g.num("transmissionFactor", t.factor, UNIT)?;
    }
    if let Some(v) = f.get("volume") {
        let g = Fields::new(v, &f.path("volume"))?;
        g.allow(
            &["thicknessFactor", "attenuationDistance", "attenuationColor"],
            "a volume (KHR_materials_volume; its thickness texture is the `thickness` map in \"textures\")",
        )?;
        t.thickness = g.num("thicknessFactor", t.thickness, Check::NonNegative)?;
        t.attenuation_color = g.color_in("attenuationColor", t.attenuation_color, UNIT)?;
        if g.has("attenuationDistance") {
            t.attenuation_distance =
                Some(g.num("attenuationDistance", f32::INFINITY, Check::Positive)?);
        }
    }
    if let Some(v) = f.get("dispersion") {
        let g = Fields::new(v, &f.path("dispersion"))?;
        g.allow(&["dispersion"], "dispersion (KHR_materials_dispersion)")?;
        t.dispersion = g.num("dispersion", t.dispersion, Check::NonNegative)?;
    }
    if let Some(v) = f.get("diffuse_transmission") {
        let g = Fields::new(v, &f.path("diffuse_transmission"))?;
        g.allow(
            &["diffuseTransmissionFactor", "diffuseTransmissionColorFactor"],
            "diffuse transmission (KHR_materials_diffuse_transmission; its textures are the `diffuse_transmission` and `diffuse_transmission_color` maps in \"textures\")",
        )?;
        t.diffuse = g.num("diffuseTransmissionFactor", t.diffuse, UNIT)?;
        t.diffuse_color = g.color_in("diffuseTransmissionColorFactor", t.diffuse_color, UNIT)?;
    }
    Ok(t)
}

/// KHR_materials_clearcoat's factors, with the extension's names:
/// `{"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.1}` (defaults 0 and 0).
fn clearcoat(v: &Value, path: &str) -> Result<(f32, f32)> {
    let f = Fields::new(v, path)?;
    f.allow(
        &["clearcoatFactor", "clearcoatRoughnessFactor"],
        "a clear coat (KHR_materials_clearcoat; its textures are the `clearcoat` and `clearcoat_roughness` maps in \"textures\")",
    )?;
    Ok((
        f.num("clearcoatFactor", 0.0, UNIT)?,
        f.num("clearcoatRoughnessFactor", 0.0, UNIT)?,
    ))
}

/// Disney "Principled". Defaults are `brdf::PrincipledParams::default()` (`disney.brdf`'s).
pub(super) fn principled(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &[
            "model",
            "textures",
            "base_color",
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
        ],
        &a_material(model),
    )?;
    let d = PrincipledParams::default();
    Ok(Material::Principled(PrincipledParams {
        base_color: f.color_in("base_color", d.base_color, UNIT)?,
        subsurface: f.num("subsurface", d.subsurface, UNIT)?,
        metallic: f.num("metallic", d.metallic, UNIT)?,
        specular: f.num("specular", d.specular, UNIT)?,
        specular_tint: f.num("specular_tint", d.specular_tint, UNIT)?,
        roughness: f.num("roughness", d.roughness, UNIT)?,
        anisotropic: f.num("anisotropic", d.anisotropic, UNIT)?,
        sheen: f.num("sheen", d.sheen, UNIT)?,
        sheen_tint: f.num("sheen_tint", d.sheen_tint, UNIT)?,
        clearcoat: f.num("clearcoat", d.clearcoat, UNIT)?,
        clearcoat_gloss: f.num("clearcoat_gloss", d.clearcoat_gloss, UNIT)?,
    }))
}

/// Qualitative Oren-Nayar. Defaults are `brdf::OrenNayarParams::default()`.
pub(super) fn oren_nayar(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &["model", "albedo", "sigma_deg", "textures"],
        &a_material(model),
    )?;
    let d = OrenNayarParams::default();
    Ok(Material::OrenNayar(OrenNayarParams {
        albedo: f.color_in("albedo", d.albedo, UNIT)?,
        sigma_deg: f.num("sigma_deg", d.sigma_deg, Check::In(0.0, 90.0))?,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_kind_is_listed_and_decodes_from_its_name() {
        let mut listed = MATERIAL_MODELS.to_vec();
        listed.sort();
        assert_eq!(listed, ModelKind::ALL.to_vec());
        for kind in ModelKind::ALL {
            let text = format!(r#"{{"model": "{}"}}"#, kind.name());
            let v = crate::scene::json::parse(&text).unwrap();
            let m = material(&v, "materials.m").unwrap();
            assert_eq!(m.kind(), kind);
            assert_eq!(m, Material::default_of(kind), "{kind:?}");
        }
    }
}
