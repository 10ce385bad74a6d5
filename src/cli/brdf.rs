//! `luz brdf`: values and plots of a reflection model from the CPU reference ([`luz::brdf`]).
//!
//! Everything printed or plotted comes from [`brdf::eval_terms`] and [`brdf::directional_albedo`],
//! the functions the tests check. Local frame: n = +z, tangent x = +x, bitangent y = +y;
//! spherical angles in degrees, θ from n, φ from x towards y.

use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{anyhow, bail, Context as _, Result};
use clap::Args;
use glam::Vec3;
use serde::Serialize;
use serde_json::{Map, Value};

use luz::brdf::{self, Model};
use luz::plot;
pub use luz::plot::brdf_charts::spherical;
use luz::plot::brdf_charts::{
    albedo_chart_of, albedo_curve, albedo_line_chart, lobe_chart, slice_chart,
};

const EXAMPLES: &str = "\
Materials use the scene file's syntax: a JSON object tagged by \"model\" (lambert, phong, blinn_phong,
cook_torrance, metal_rough, principled, oren_nayar); missing fields take their defaults
(see --list-models). Directions: n = +z, tangent x = +x, bitangent y = +y; θ from n, φ from x
towards y, in degrees. φl defaults to 0 and φv to 180, so equal θl and θv are a mirror pair.

Output: one line of key=value pairs (model, f = the BRDF value RGB, D, G, F (Fresnel, RGB),
diffuse and specular parts of f (RGB), the cosines n_l n_v n_h v_h of the normalised directions);
--json prints the same as a JSON object (plus the normalised l and v and the material).

Examples:
  luz brdf --model lambert --theta-l 0 --theta-v 0
  luz brdf --material '{\"model\":\"metal_rough\",\"base_color\":[1,0.8,0.3],\"roughness\":0.3}' \\
           --theta-l 30 --theta-v 30 --json
  luz brdf --model cook_torrance --set roughness=0.2 --set specular=gold --set fresnel=conductor \\
           --l 0.5,0,0.866 --v -0.5,0,0.866
  echo '{\"material\":{\"model\":\"lambert\"},\"theta_l\":0,\"theta_v\":45}' | luz brdf --stdin
  luz brdf --model metal_rough --set metallic=0 --plot plots/ --sweep roughness=0,0.25,0.5,0.75,1

--stdin reads one JSON object per line: {\"material\": {...}, \"l\": [x,y,z], \"v\": [x,y,z]}, with
\"theta_l\"/\"phi_l\" and \"theta_v\"/\"phi_v\" (degrees) instead of l or v if preferred, and \"material\"
optional when --material or --model is given. It writes one JSON line per non-blank input line;
a bad line gives {\"line\": N, \"error\": \"...\"} instead (also on stderr), processing continues,
and the exit status is 1 at the end.

--plot DIR writes, each as PNG and SVG (--plot-size pixels, default 800x600), and prints the paths:
  lobe_polar       f·cos θv in the plane of incidence (φ = 0/180) for each --incidence angle θl,
                   luminance Y of f, polar (0° = normal, light on the left, dashed)
  slice_thetah_thetad  f over θh (x) × θd (y) at --phi-d (Rusinkiewicz half/difference angles,
                   MERL/Burley style), luminance, log colour scale over --slice-decades, on
                   --slice-cells × --slice-cells cells evaluated at their centres; grey: l or v
                   below the horizon (f = 0)
  albedo           directional albedo R(θl) = ∫ f cos θv dω (brdf::directional_albedo, --samples):
                   R, G and B curves, or with --sweep KEY=V1,V2,… the largest channel per value
The chart font is read at run time from $LUZ_FONT or /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
(Debian package fonts-dejavu-core).";

/// `luz brdf`: evaluate a reflection model of the CPU reference, or plot it.
#[derive(Args, Debug, Clone, Default)]
#[command(after_long_help = EXAMPLES)]
pub struct BrdfArgs {
    /// The material as JSON (scene-file syntax), or @FILE to read it from a file.
    #[arg(long, value_name = "JSON", conflicts_with = "model")]
    pub material: Option<String>,
    /// The model by name with default parameters (see --list-models); change them with --set.
    #[arg(long, value_name = "NAME")]
    pub model: Option<String>,
    /// Set a parameter: KEY=VALUE, VALUE a number, true/false, r,g,b, a name (ggx, conductor, …;
    /// for cook_torrance's specular also a metal or dielectric preset: gold, water, …) or JSON.
    /// Repeatable; applies on top of --material or --model.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,

    /// Light direction θ in degrees from the normal.
    #[arg(
        long,
        value_name = "DEG",
        allow_negative_numbers = true,
        conflicts_with = "l"
    )]
    pub theta_l: Option<f64>,
    /// Light direction φ in degrees [default: 0].
    #[arg(
        long,
        value_name = "DEG",
        allow_negative_numbers = true,
        requires = "theta_l"
    )]
    pub phi_l: Option<f64>,
    /// View direction θ in degrees from the normal.
    #[arg(
        long,
        value_name = "DEG",
        allow_negative_numbers = true,
        conflicts_with = "v"
    )]
    pub theta_v: Option<f64>,
    /// View direction φ in degrees [default: 180, the mirror plane of φl = 0].
    #[arg(
        long,
        value_name = "DEG",
        allow_negative_numbers = true,
        requires = "theta_v"
    )]
    pub phi_v: Option<f64>,
    /// Light direction as a vector towards the light (normalised), n = +z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_vec3)]
    pub l: Option<Vec3>,
    /// View direction as a vector towards the viewer (normalised), n = +z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_vec3)]
    pub v: Option<Vec3>,

    /// Print a JSON object instead of key=value text.
    #[arg(long)]
    pub json: bool,
    /// Read queries as JSON lines from standard input, write one JSON line each.
    #[arg(long, conflicts_with_all = ["theta_l", "theta_v", "l", "v"])]
    pub stdin: bool,
    /// Print every model's default material (one JSON line each) and exit.
    #[arg(long)]
    pub list_models: bool,

    /// Write the lobe, θh × θd slice and albedo charts (PNG and SVG) into this directory.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Chart size in pixels.
    #[arg(long, value_name = "WxH", default_value = "800x600", value_parser = parse_size)]
    pub plot_size: (u32, u32),
    /// Light angles θl (degrees, 0 ≤ θl < 90) of the polar lobe plot.
    #[arg(
        long,
        value_name = "DEG,…",
        value_delimiter = ',',
        default_value = "0,30,60,80"
    )]
    pub incidence: Vec<f64>,
    /// φd of the θh × θd slice, degrees.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 90.0,
        allow_negative_numbers = true
    )]
    pub phi_d: f64,
    /// Cells per side of the θh × θd slice.
    #[arg(long, value_name = "N", default_value_t = 90, value_parser = clap::value_parser!(u32).range(4..=360))]
    pub slice_cells: u32,
    /// Decades of the slice's logarithmic colour scale (below its maximum).
    #[arg(long, value_name = "N", default_value_t = 6.0)]
    pub slice_decades: f64,
    /// Albedo chart: one curve per value of a scalar parameter, e.g. roughness=0,0.25,0.5,0.75,1.
    #[arg(long, value_name = "KEY=V1,V2,…")]
    pub sweep: Option<String>,
    /// Samples per directional-albedo value (multiple importance sampling).
    #[arg(long, value_name = "N", default_value_t = 4096, value_parser = clap::value_parser!(u32).range(16..=1_048_576))]
    pub samples: u32,
}

/// Runs `luz brdf`. Exit status 0, or 1 when a `--stdin` line failed (other errors are `Err`).
pub fn run(args: BrdfArgs) -> Result<ExitCode> {
    if args.list_models {
        let mut out = std::io::stdout().lock();
        for m in default_models() {
            writeln!(out, "{}", serde_json::to_string(&m)?)?;
        }
        return Ok(ExitCode::SUCCESS);
    }
    let material = command_line_material(&args)?;
    let l = resolve_direction(
        args.l,
        args.theta_l,
        args.phi_l,
        0.0,
        ["--l", "--theta-l", "--phi-l"],
    )?;
    let v = resolve_direction(
        args.v,
        args.theta_v,
        args.phi_v,
        180.0,
        ["--v", "--theta-v", "--phi-v"],
    )?;
    if args.sweep.is_some() && args.plot.is_none() {
        bail!("--sweep only affects the albedo chart: add --plot DIR");
    }
    let mut code = ExitCode::SUCCESS;
    let mut did = false;
    if args.stdin {
        code = run_stdin(material.as_ref())?;
        did = true;
    }
    match (l, v) {
        (Some(l), Some(v)) => {
            let (model, value) = material
                .as_ref()
                .ok_or_else(|| anyhow!("no material: give --material JSON or --model NAME"))?;
            let rec = evaluate(model, value, l, v);
            let mut out = std::io::stdout().lock();
            if args.json {
                writeln!(out, "{}", serde_json::to_string(&rec)?)?;
            } else {
                writeln!(out, "{}", rec.text())?;
            }
            did = true;
        }
        (Some(_), None) => {
            bail!("the view direction is missing: give --theta-v (and --phi-v) or --v")
        }
        (None, Some(_)) => {
            bail!("the light direction is missing: give --theta-l (and --phi-l) or --l")
        }
        (None, None) => {}
    }
    if let Some(dir) = &args.plot {
        let (model, value) = material
            .as_ref()
            .ok_or_else(|| anyhow!("no material to plot: give --material JSON or --model NAME"))?;
        let paths = write_plots(model, value, &args, dir)?;
        let mut out = std::io::stdout().lock();
        if args.json {
            let p: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
            writeln!(out, "{}", serde_json::json!({ "plots": p }))?;
        } else {
            for p in &paths {
                writeln!(out, "{}", p.display())?;
            }
        }
        did = true;
    }
    if !did {
        bail!(
            "nothing to do: give directions (--theta-l/--theta-v or --l/--v), --stdin or --plot DIR \
             (see luz brdf --help)"
        );
    }
    Ok(code)
}

// ---------------------------------------------------------------------------------------------
// Materials
// ---------------------------------------------------------------------------------------------

/// One model of each kind with its default parameters, in `--list-models` order.
pub fn default_models() -> Vec<Model> {
    brdf::ModelKind::ALL.map(Model::default_of).to_vec()
}

fn model_names() -> Vec<&'static str> {
    brdf::ModelKind::ALL.map(|k| k.name()).to_vec()
}

/// The scene file's glTF extension objects on metal_rough as the CPU model's fields:
/// KHR_materials_clearcoat's `"clearcoat": {"clearcoatFactor": c, "clearcoatRoughnessFactor": r}`
/// as `"clearcoat": c, "clearcoat_roughness": r` (a number `clearcoat` is kept as it is), and
/// KHR_materials_sheen's `"sheen": {"sheenColorFactor": [r, g, b], "sheenRoughnessFactor": s}`
/// as `"sheen_color": [r, g, b], "sheen_roughness": s`, KHR_materials_anisotropy's
/// `"anisotropy": {"anisotropyStrength": s, "anisotropyRotation": r}` as
/// `"anisotropy_strength": s, "anisotropy_rotation": r`, KHR_materials_iridescence's four
/// fields likewise (`iridescence`, `iridescence_ior`, `iridescence_thickness_min`,
/// `iridescence_thickness_max`); `ior` and `specular` as
/// `dielectric_f0`.
fn scene_layers(value: &Value) -> Value {
    let mut v = value.clone();
    let is_mr = v.get("model").and_then(Value::as_str) == Some("metal_rough");
    let Some(obj) = v.as_object_mut().filter(|_| is_mr) else {
        return v;
    };
    // (scene object, its field, the model's field, default)
    let fields = [
        (
            "clearcoat",
            "clearcoatFactor",
            "clearcoat",
            Value::from(0.0),
        ),
        (
            "clearcoat",
            "clearcoatRoughnessFactor",
            "clearcoat_roughness",
            Value::from(0.0),
        ),
        (
            "sheen",
            "sheenColorFactor",
            "sheen_color",
            Value::from(vec![0.0; 3]),
        ),
        (
            "sheen",
            "sheenRoughnessFactor",
            "sheen_roughness",
            Value::from(0.0),
        ),
        (
            "anisotropy",
            "anisotropyStrength",
            "anisotropy_strength",
            Value::from(0.0),
        ),
        (
            "anisotropy",
            "anisotropyRotation",
            "anisotropy_rotation",
            Value::from(0.0),
        ),
        (
            "iridescence",
            "iridescenceFactor",
            "iridescence",
            Value::from(0.0),
        ),
        (
            "iridescence",
            "iridescenceIor",
            "iridescence_ior",
            Value::from(1.3),
        ),
        (
            "iridescence",
            "iridescenceThicknessMinimum",
            "iridescence_thickness_min",
            Value::from(100.0),
        ),
        (
            "iridescence",
            "iridescenceThicknessMaximum",
            "iridescence_thickness_max",
            Value::from(400.0),
        ),
    ];
    let objects: Vec<(&str, serde_json::Map<String, Value>)> =
        ["clearcoat", "sheen", "anisotropy", "iridescence"]
            .into_iter()
            .filter_map(|k| match obj.get(k) {
                Some(Value::Object(o)) => Some((k, o.clone())),
                _ => None,
            })
            .collect();
    // KHR_materials_ior's `"ior": 1.33` (or `{"ior": 1.33}`) and KHR_materials_specular's
    // `"specular": {"specularFactor": f, "specularColorFactor": [r, g, b]}` as the model's
    // `dielectric_f0`, computed as scene files compute it.
    if obj.contains_key("ior") || obj.contains_key("specular") {
        let ior = match obj.remove("ior") {
            Some(Value::Object(o)) => o.get("ior").and_then(Value::as_f64),
            Some(v) => v.as_f64(),
            None => None,
        };
        let spec = obj.remove("specular");
        let spec = spec.as_ref().and_then(Value::as_object);
        let factor = spec
            .and_then(|o| o.get("specularFactor"))
            .and_then(Value::as_f64)
            .unwrap_or(1.0);
        let color = spec
            .and_then(|o| o.get("specularColorFactor"))
            .and_then(Value::as_array)
            .map(|a| {
                glam::Vec3::from_array(std::array::from_fn(|i| {
                    a.get(i).and_then(Value::as_f64).unwrap_or(1.0) as f32
                }))
            })
            .unwrap_or(glam::Vec3::ONE);
        let f0 =
            brdf::MetalRoughParams::dielectric_f0_from(ior.map(|x| x as f32), factor as f32, color);
        obj.insert("dielectric_f0".into(), Value::from(f0.to_array().to_vec()));
        // KHR_materials_specular's specularFactor is also the dielectric's F90.
        obj.insert("dielectric_f90".into(), Value::from(factor));
    }
    for (key, o) in &objects {
        obj.remove(*key);
        for (scene, field, model, default) in &fields {
            if scene == key {
                obj.insert(
                    model.to_string(),
                    o.get(*field).cloned().unwrap_or(default.clone()),
                );
            }
        }
    }
    v
}

/// A [`Model`] from its JSON value (scene-file syntax), with errors that name the field.
pub fn model_from_value(value: &Value) -> Result<Model> {
    let names = model_names().join(", ");
    let Some(obj) = value.as_object() else {
        bail!("a material must be a JSON object such as {{\"model\": \"lambert\", \"albedo\": [0.8, 0.8, 0.8]}}, not {value}");
    };
    let tag = match obj.get("model") {
        None => bail!("missing field `model` (one of {names})"),
        Some(Value::String(s)) => s.as_str(),
        Some(other) => bail!("field `model`: expected a string (one of {names}), not {other}"),
    };
    if !model_names().contains(&tag) {
        bail!("field `model`: unknown model `{tag}` (expected one of {names})");
    }
    let value = &scene_layers(value);
    match serde_json::from_value::<Model>(value.clone()) {
        Ok(m) => Ok(m),
        Err(whole) => {
            // serde's error for a tagged enum names no field: find the first field that fails alone.
            for (key, v) in obj.iter().filter(|(k, _)| k.as_str() != "model") {
                let mut single = Map::new();
                single.insert("model".into(), Value::String(tag.into()));
                single.insert(key.clone(), v.clone());
                if let Err(e) = serde_json::from_value::<Model>(Value::Object(single)) {
                    let msg = e.to_string();
                    if msg.starts_with("unknown field") {
                        bail!("{tag}: {msg}");
                    }
                    bail!("{tag}: field `{key}` = {v}: {msg}");
                }
            }
            bail!("{tag}: {whole}")
        }
    }
}

/// Parses a `--set` value: JSON (`{`, `[`, `"`), true/false, a number, numbers separated by
/// commas (an array), else a plain string.
fn parse_set_value(raw: &str) -> Result<Value> {
    let t = raw.trim();
    if t.starts_with(['{', '[', '"']) {
        return serde_json::from_str(t).map_err(|e| anyhow!("not valid JSON: {e}"));
    }
    if t == "true" || t == "false" {
        return Ok(Value::Bool(t == "true"));
    }
    let number = |s: &str| -> Option<Value> {
        let x: f64 = s.trim().parse().ok()?;
        serde_json::Number::from_f64(x).map(Value::Number)
    };
    if t.contains(',') {
        return t
            .split(',')
            .map(|s| number(s).ok_or_else(|| anyhow!("`{}` is not a finite number", s.trim())))
            .collect::<Result<Vec<_>>>()
            .map(Value::Array);
    }
    if let Some(n) = number(t) {
        return Ok(n);
    }
    if t.parse::<f64>().is_ok() {
        bail!("`{t}` is not a finite number");
    }
    Ok(Value::String(t.to_string()))
}

/// Sets `key` in a material object; the Cook-Torrance `specular` also takes preset names.
fn set_field(material: &mut Value, key: &str, mut value: Value) -> Result<()> {
    if key == "model" {
        bail!(
            "use --model NAME (or the material's \"model\") to choose the model, not --set model=…"
        );
    }
    let Some(obj) = material.as_object_mut() else {
        bail!("the material is not a JSON object");
    };
    let is_ct = obj.get("model").and_then(Value::as_str) == Some("cook_torrance");
    if let (true, "specular", Value::String(name)) = (is_ct, key, &value) {
        value = if let Some(c) = brdf::metal_preset(name) {
            serde_json::json!({ "complex": c })
        } else if let Some(eta) = brdf::dielectric_ior(name) {
            serde_json::json!({ "ior": eta })
        } else {
            bail!(
                "unknown preset `{name}` (metals: {}; dielectrics: {})",
                brdf::METAL_NAMES.join(", "),
                brdf::DIELECTRIC_NAMES.join(", ")
            );
        };
    }
    obj.insert(key.to_string(), value);
    Ok(())
}

fn split_key_value<'a>(s: &'a str, what: &str) -> Result<(&'a str, &'a str)> {
    match s.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim(), v)),
        _ => bail!("{what} `{s}`: expected KEY=VALUE"),
    }
}

/// The material of `--material` / `--model` and `--set`, as a model and its JSON.
fn command_line_material(args: &BrdfArgs) -> Result<Option<(Model, Value)>> {
    let mut value = match (&args.material, &args.model) {
        (Some(m), _) => {
            let text = match m.strip_prefix('@') {
                Some(path) => luz::files::read_input_text(std::path::Path::new(path))
                    .with_context(|| format!("--material: reading {path}"))?,
                None => m.clone(),
            };
            let source = match m.strip_prefix('@') {
                Some(path) => format!("--material {path}"),
                None => "--material".to_string(),
            };
            let v: Value = serde_json::from_str(&text)
                .map_err(|e| anyhow!("{source}: not valid JSON: {e}"))?;
            if !v.is_object() {
                bail!("--material: expected a JSON object such as {{\"model\": \"lambert\"}}, not {v}");
            }
            v
        }
        (None, Some(name)) => {
            if !model_names().contains(&name.as_str()) {
                bail!(
                    "--model: unknown model `{name}` (expected one of {})",
                    model_names().join(", ")
                );
            }
            serde_json::json!({ "model": name })
        }
        (None, None) => {
            if !args.set.is_empty() {
                bail!("--set needs a material: give --material JSON or --model NAME");
            }
            return Ok(None);
        }
    };
    for s in &args.set {
        let (key, raw) = split_key_value(s, "--set")?;
        let v = parse_set_value(raw).with_context(|| format!("--set {key}"))?;
        set_field(&mut value, key, v).with_context(|| format!("--set {key}"))?;
    }
    let what = if args.material.is_some() {
        "--material"
    } else {
        "--model/--set"
    };
    let model = model_from_value(&value).with_context(|| what.to_string())?;
    warn_sanitized(&model, "");
    // Echo the full parameter set (defaults filled in).
    let value = material_json(&model)?;
    Ok(Some((model, value)))
}

/// The JSON of a model with its `f32` values written shortest (0.8, not 0.800000011920929).
pub fn material_json(model: &Model) -> Result<Value> {
    Ok(serde_json::from_str(&serde_json::to_string(model)?)?)
}

/// Notes on stderr for parameters that `eval` clamps or replaces.
fn warn_sanitized(model: &Model, prefix: &str) {
    let (Ok(Value::Object(a)), Ok(Value::Object(b))) = (
        serde_json::to_value(model),
        serde_json::to_value(model.sanitized()),
    ) else {
        return;
    };
    for (k, va) in &a {
        if let Some(vb) = b.get(k).filter(|vb| *vb != va) {
            eprintln!(
                "{prefix}note: {} {k} = {va} is out of range; evaluated as {vb}",
                model.name()
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Directions and evaluation
// ---------------------------------------------------------------------------------------------

fn parse_vec3(s: &str) -> std::result::Result<Vec3, String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected three comma-separated numbers X,Y,Z, got `{s}`"
        ));
    }
    let mut c = [0.0f32; 3];
    for (i, p) in parts.iter().enumerate() {
        c[i] = p
            .trim()
            .parse::<f32>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("`{}` is not a finite number", p.trim()))?;
    }
    Ok(Vec3::from(c))
}

fn parse_size(s: &str) -> std::result::Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, e.g. 800x600, got `{s}`"))?;
    let p = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|x| (64..=8192).contains(x))
            .ok_or_else(|| format!("`{t}`: each side must be 64 to 8192 pixels"))
    };
    Ok((p(w)?, p(h)?))
}

/// One direction from either a vector or spherical angles; `names` are (vector, θ, φ) for errors.
fn resolve_direction(
    vec: Option<Vec3>,
    theta: Option<f64>,
    phi: Option<f64>,
    default_phi: f64,
    names: [&str; 3],
) -> Result<Option<Vec3>> {
    let [nv, nt, np] = names;
    match (vec, theta) {
        (Some(_), Some(_)) => bail!("give either {nv} or {nt}, not both"),
        (Some(v), None) => {
            if phi.is_some() {
                bail!("{np} goes with {nt}, not with {nv}");
            }
            if !v.is_finite() || v.length_squared() < 1e-12 {
                bail!("{nv} must be a finite, non-zero vector");
            }
            Ok(Some(v.normalize()))
        }
        (None, Some(t)) => {
            let p = phi.unwrap_or(default_phi);
            if !t.is_finite() || !p.is_finite() {
                bail!("{nt} and {np} must be finite numbers");
            }
            Ok(Some(spherical(t, p)))
        }
        (None, None) => {
            if phi.is_some() {
                bail!("{np} needs {nt}");
            }
            Ok(None)
        }
    }
}

/// One evaluation, as printed.
#[derive(Debug, Clone, Serialize)]
pub struct Record {
    pub model: &'static str,
    /// The BRDF value f (RGB, 1/sr), not multiplied by n·l.
    pub f: [f32; 3],
    #[serde(rename = "D")]
    pub d: f32,
    #[serde(rename = "G")]
    pub g: f32,
    /// Fresnel (RGB).
    #[serde(rename = "F")]
    pub fresnel: [f32; 3],
    pub diffuse: [f32; 3],
    pub specular: [f32; 3],
    pub n_l: f32,
    pub n_v: f32,
    pub n_h: f32,
    pub v_h: f32,
    pub l: [f32; 3],
    pub v: [f32; 3],
    pub material: Value,
}

impl Record {
    /// The one-line key=value form.
    pub fn text(&self) -> String {
        let c = |a: [f32; 3]| format!("{},{},{}", a[0], a[1], a[2]);
        format!(
            "model={} f={} D={} G={} F={} diffuse={} specular={} n_l={} n_v={} n_h={} v_h={}",
            self.model,
            c(self.f),
            self.d,
            self.g,
            c(self.fresnel),
            c(self.diffuse),
            c(self.specular),
            self.n_l,
            self.n_v,
            self.n_h,
            self.v_h
        )
    }
}

/// Evaluates `model` for unit `l`, `v` in the local frame (n = +z, x = +x, y = +y).
pub fn evaluate(model: &Model, material: &Value, l: Vec3, v: Vec3) -> Record {
    let n = Vec3::Z;
    let t = brdf::eval_terms(model, n, l, v, Vec3::X, Vec3::Y);
    let f = t.total();
    let h = brdf::safe_normalize(l + v);
    Record {
        model: model.name(),
        f: f.to_array(),
        d: t.d,
        g: t.g,
        fresnel: t.f.to_array(),
        diffuse: t.diffuse.to_array(),
        specular: t.specular.to_array(),
        n_l: n.dot(l),
        n_v: n.dot(v),
        n_h: n.dot(h),
        v_h: v.dot(h),
        l: l.to_array(),
        v: v.to_array(),
        material: material.clone(),
    }
}

// ---------------------------------------------------------------------------------------------
// --stdin
// ---------------------------------------------------------------------------------------------

const QUERY_FIELDS: [&str; 7] = ["material", "l", "v", "theta_l", "phi_l", "theta_v", "phi_v"];

fn vec3_field(obj: &Map<String, Value>, key: &str) -> Result<Option<Vec3>> {
    let Some(v) = obj.get(key) else {
        return Ok(None);
    };
    let arr = v.as_array().filter(|a| a.len() == 3);
    let nums: Option<Vec<f32>> = arr.and_then(|a| {
        a.iter()
            .map(|x| x.as_f64().map(|x| x as f32).filter(|x| x.is_finite()))
            .collect()
    });
    match nums {
        Some(c) => Ok(Some(Vec3::new(c[0], c[1], c[2]))),
        None => bail!("field `{key}`: expected [x, y, z] (three finite numbers), not {v}"),
    }
}

fn num_field(obj: &Map<String, Value>, key: &str) -> Result<Option<f64>> {
    match obj.get(key) {
        None => Ok(None),
        Some(v) => match v.as_f64() {
            Some(x) => Ok(Some(x)),
            None => bail!("field `{key}`: expected a number of degrees, not {v}"),
        },
    }
}

fn query(line: &str, default: Option<&(Model, Value)>) -> Result<Record> {
    let value: Value = serde_json::from_str(line).map_err(|e| anyhow!("not valid JSON: {e}"))?;
    let Some(obj) = value.as_object() else {
        bail!("expected a JSON object {{\"material\": {{…}}, \"l\": [x, y, z], \"v\": [x, y, z]}}");
    };
    if let Some(k) = obj.keys().find(|k| !QUERY_FIELDS.contains(&k.as_str())) {
        bail!("unknown field `{k}` (expected {})", QUERY_FIELDS.join(", "));
    }
    let (model, material) = match obj.get("material") {
        Some(m) => {
            let model = model_from_value(m).context("field `material`")?;
            (model, material_json(&model)?)
        }
        None => default
            .cloned()
            .ok_or_else(|| anyhow!("no `material` field, and no --material or --model given"))?,
    };
    let l = resolve_direction(
        vec3_field(obj, "l")?,
        num_field(obj, "theta_l")?,
        num_field(obj, "phi_l")?,
        0.0,
        ["`l`", "`theta_l`", "`phi_l`"],
    )?
    .ok_or_else(|| anyhow!("the light direction is missing: give `l` or `theta_l`"))?;
    let v = resolve_direction(
        vec3_field(obj, "v")?,
        num_field(obj, "theta_v")?,
        num_field(obj, "phi_v")?,
        180.0,
        ["`v`", "`theta_v`", "`phi_v`"],
    )?
    .ok_or_else(|| anyhow!("the view direction is missing: give `v` or `theta_v`"))?;
    Ok(evaluate(&model, &material, l, v))
}

fn run_stdin(default: Option<&(Model, Value)>) -> Result<ExitCode> {
    let stdin = std::io::stdin().lock();
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    let mut errors = 0usize;
    for (i, line) in stdin.lines().enumerate() {
        let n = i + 1;
        let line = line.with_context(|| format!("reading standard input, line {n}"))?;
        if line.trim().is_empty() {
            continue;
        }
        match query(&line, default) {
            Ok(rec) => writeln!(out, "{}", serde_json::to_string(&rec)?)?,
            Err(e) => {
                errors += 1;
                let msg = format!("{e:#}");
                #[derive(Serialize)]
                struct LineError<'a> {
                    line: usize,
                    error: &'a str,
                }
                writeln!(
                    out,
                    "{}",
                    serde_json::to_string(&LineError {
                        line: n,
                        error: &msg
                    })?
                )?;
                out.flush()?;
                eprintln!("luz brdf: stdin line {n}: {msg}");
            }
        }
    }
    out.flush()?;
    if errors > 0 {
        eprintln!("luz brdf: {errors} bad input line(s)");
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

// ---------------------------------------------------------------------------------------------
// --plot
// ---------------------------------------------------------------------------------------------

/// The directional-albedo chart of `material`; with `sweep = (key, values)` one curve (largest
/// channel) per value of that parameter, else one curve per channel.
pub fn albedo_chart(
    material: &Value,
    sweep: Option<(&str, &[f64])>,
    samples: u32,
) -> Result<plot::LineChart> {
    let model = model_from_value(material)?;
    let Some((key, values)) = sweep else {
        return Ok(albedo_chart_of(&model, samples));
    };
    let title = format!("{}: directional albedo, {key} sweep", model.name());
    let mut series = Vec::new();
    for (i, &x) in values.iter().enumerate() {
        let mut m = material.clone();
        let num = serde_json::Number::from_f64(x)
            .ok_or_else(|| anyhow!("--sweep {key}: {x} is not finite"))?;
        set_field(&mut m, key, Value::Number(num))?;
        let mm = model_from_value(&m).with_context(|| format!("--sweep {key}={x}"))?;
        let pts = albedo_curve(&mm, samples)
            .into_iter()
            .map(|(t, r)| (t, r.max_element() as f64))
            .collect();
        series.push(
            plot::Series::new(format!("{key} = {}", plot::format_number(x)), pts).color(
                plot::viridis(if values.len() > 1 {
                    0.9 * i as f64 / (values.len() - 1) as f64
                } else {
                    0.0
                }),
            ),
        );
    }
    Ok(albedo_line_chart(title, series, true))
}

fn parse_sweep(s: &str) -> Result<(String, Vec<f64>)> {
    let (key, list) = split_key_value(s, "--sweep")?;
    let values = list
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| anyhow!("--sweep {key}: `{}` is not a finite number", x.trim()))
        })
        .collect::<Result<Vec<f64>>>()?;
    if values.is_empty() || values.len() > 16 {
        bail!("--sweep {key}: give 1 to 16 values");
    }
    Ok((key.to_string(), values))
}

/// Writes the three charts (PNG and SVG) into `dir`; returns the paths written.
fn write_plots(
    model: &Model,
    material: &Value,
    args: &BrdfArgs,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    plot::init_font()?;
    let sweep = args.sweep.as_deref().map(parse_sweep).transpose()?;
    if let Some((key, values)) = &sweep {
        // Fail before drawing anything if the key is not a scalar parameter of this model.
        for &x in values {
            let mut m = material.clone();
            set_field(&mut m, key, serde_json::json!(x))?;
            model_from_value(&m).with_context(|| format!("--sweep {key}={x}"))?;
        }
    }
    let lobe = lobe_chart(model, &args.incidence)?;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let (w, h) = args.plot_size;
    let mut paths = Vec::new();
    paths.extend(plot::save_png_svg(
        &lobe.into(),
        &dir.join("lobe_polar"),
        w,
        h,
    )?);
    if !(args.slice_decades > 0.0 && args.slice_decades <= 30.0) {
        bail!("--slice-decades {}: must be in (0, 30]", args.slice_decades);
    }
    let slice = slice_chart(
        model,
        args.phi_d,
        args.slice_cells as usize,
        args.slice_decades,
    );
    paths.extend(plot::save_png_svg(
        &slice.into(),
        &dir.join("slice_thetah_thetad"),
        w,
        h,
    )?);
    let sweep_ref = sweep.as_ref().map(|(k, v)| (k.as_str(), v.as_slice()));
    let albedo = albedo_chart(material, sweep_ref, args.samples)?;
    paths.extend(plot::save_png_svg(
        &albedo.into(),
        &dir.join("albedo"),
        w,
        h,
    )?);
    Ok(paths)
}
