//! The `environment` block (image-based lighting), decoded with the helpers of `decode.rs`.

use std::path::{Path, PathBuf};

use super::{choice, color, file_name, one_of, show, unit, Check, Fields, Invalid, Result, Value};
use crate::scene::{
    DiffuseMethod, EnvSource, Environment, SpecularMethod, DEFAULT_ENV_SAMPLES,
    DEFAULT_SUN_DIRECTION, DEFAULT_SUN_INTENSITY, MAX_ENV_SAMPLES, MAX_SUN_INTENSITY,
};

/// The keys that choose an environment's source; a block gives exactly one.
const ENV_SOURCES: &[&str] = &["hdr", "uniform", "procedural"];
/// The settings every environment accepts.
const ENV_SETTINGS: &[&str] = &[
    "intensity",
    "rotation_deg",
    "specular_method",
    "samples",
    "diffuse_method",
    "energy_compensation",
    "mip_filtered_samples",
    "show_background",
];
/// The settings only the procedural sky accepts.
const SKY_SETTINGS: &[&str] = &["sun_direction", "sun_intensity"];

pub(super) fn environment(v: &Value, path: &str, base: &Path) -> Result<Environment> {
    let f = Fields::new(v, path)?;
    let Some(key) = f.exclusive(ENV_SOURCES, "the environment's source")? else {
        // Unknown fields first: a misspelt source ("hrd") reads better as "did you mean".
        let mut all: Vec<&str> = ENV_SOURCES.to_vec();
        all.extend(ENV_SETTINGS);
        all.extend(SKY_SETTINGS);
        f.allow(&all, "an environment")?;
        return Err(Invalid::new(
            path,
            format!(
                "an environment needs exactly one source: \"hdr\": \"<file.hdr|file.exr>\", \"uniform\": [r, g, b] or \"procedural\": {}",
                one_of(PROCEDURALS)
            ),
        ));
    };
    let kind = match key {
        "procedural" => choice(f.req(key)?, &f.path(key), PROCEDURALS)?,
        k => k,
    };
    let mut allowed: Vec<&str> = vec![key];
    allowed.extend(ENV_SETTINGS);
    if kind == "sky" {
        allowed.extend(SKY_SETTINGS);
    } else if let Some(k) = SKY_SETTINGS.iter().find(|k| f.has(k)) {
        return Err(f.err(
            k,
            format!(
                "\"{k}\" only applies to the procedural sky (\"procedural\": \"sky\"), not to {}",
                match kind {
                    "hdr" => "an \"hdr\" environment",
                    "uniform" => "a \"uniform\" environment",
                    _ => "the procedural studio",
                }
            ),
        ));
    }
    let what = match kind {
        "hdr" => "an hdr environment",
        "uniform" => "a uniform environment",
        "sky" => "the procedural sky",
        _ => "the procedural studio",
    };
    f.allow(&allowed, what)?;
    let source = match kind {
        "hdr" => EnvSource::Hdr(env_image(f.req("hdr")?, &f.path("hdr"), base)?),
        "uniform" => EnvSource::Uniform(color(f.req("uniform")?, &f.path("uniform"))?),
        "sky" => {
            let d = f.vec3("sun_direction", DEFAULT_SUN_DIRECTION)?;
            let Some(d) = unit(d) else {
                return Err(f.err("sun_direction", "must not be a zero-length vector"));
            };
            if d.y > 0.0 {
                return Err(f.err(
                    "sun_direction",
                    format!(
                        "the sun would be below the horizon: sun_direction is the way sunlight travels, so its y must be ≤ 0 (got {})",
                        show(d.y)
                    ),
                ));
            }
            EnvSource::Sky {
                sun_direction: d,
                sun_intensity: f.num(
                    "sun_intensity",
                    DEFAULT_SUN_INTENSITY,
                    Check::In(0.0, MAX_SUN_INTENSITY),
                )?,
            }
        }
        _ => EnvSource::Studio,
    };
    let mut env = Environment::new(source);
    env.intensity = f.num("intensity", 1.0, Check::NonNegative)?;
    env.rotation_deg = f.num("rotation_deg", 0.0, Check::Any)?;
    env.specular_method = f.select(
        "specular_method",
        &SpecularMethod::NAMED,
        SpecularMethod::default(),
    )?;
    env.samples = f.int("samples", DEFAULT_ENV_SAMPLES, 1, MAX_ENV_SAMPLES)?;
    env.diffuse_method = f.select("diffuse_method", &DiffuseMethod::NAMED, DiffuseMethod::Sh9)?;
    env.energy_compensation = f.boolean("energy_compensation", false)?;
    env.mip_filtered_samples = f.boolean("mip_filtered_samples", true)?;
    env.show_background = f.boolean("show_background", true)?;
    Ok(env)
}

/// The procedural environments.
const PROCEDURALS: &[&str] = &["sky", "studio"];

/// An environment image path: `.hdr` or `.exr`, resolved against `base`, an existing file whose
/// first bytes are those of its format (the pixels are read later, by `env::load_equirect`).
fn env_image(v: &Value, path: &str, base: &Path) -> Result<PathBuf> {
    let (file, ext) = file_name(v, path, base)?;
    let (magic, format, article): (&[&[u8]], &str, &str) = match ext.as_deref() {
        Some("hdr") => (&[b"#?RADIANCE", b"#?RGBE"], "Radiance HDR", "a"),
        Some("exr") => (&[&[0x76, 0x2f, 0x31, 0x01]], "OpenEXR", "an"),
        _ => {
            return Err(Invalid::new(
                path,
                format!(
                    "{}: unsupported environment image; expected an equirectangular .hdr (Radiance RGBE) or .exr (OpenEXR) file",
                    file.display()
                ),
            ))
        }
    };
    let head = read_head(&file, 16)
        .map_err(|reason| Invalid::new(path, format!("{}: {reason}", file.display())))?;
    if !magic.iter().any(|m| head.starts_with(m)) {
        return Err(Invalid::new(
            path,
            format!(
                "{}: not {article} {format} file (its first bytes are not {article} {format} header)",
                file.display()
            ),
        ));
    }
    Ok(file)
}

/// The first `n` bytes of a file (fewer if it is shorter), or why it cannot be read.
fn read_head(file: &Path, n: usize) -> std::result::Result<Vec<u8>, String> {
    use std::io::Read;
    match std::fs::metadata(file) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err("no such file".to_string())
        }
        Err(e) => return Err(format!("cannot read: {e}")),
        Ok(m) if m.is_dir() => return Err("is a directory, not an image file".to_string()),
        Ok(_) => {}
    }
    let mut head = Vec::with_capacity(n);
    crate::files::open_input(file)
        .and_then(|f| f.take(n as u64).read_to_end(&mut head))
        .map_err(|e| format!("cannot read: {e}"))?;
    Ok(head)
}
