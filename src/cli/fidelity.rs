//! `luz fidelity '<JSON>'`: the offline-renderer contract of the Khronos glTF Render Fidelity
//! generator (`KhronosGroup/glTF-Render-Fidelity-Generator`,
//! `src/workflows/render-goldens/renderer-offline.ts`): one JSON argument
//! `{"scenario": {…}, "outputFile": "…png"}`, a PNG written, exit 0; anything else is an error on
//! stderr naming the JSON path and a non-zero exit.
//!
//! The scenario becomes a luz scene (printed with `--scene-out`), rendered as `luz render` would
//! render that scene. Each choice and its source is in docs/fidelity.md.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{anyhow, Result};
use clap::Args;
use serde_json::{json, Map, Value};

use luz::headless::Headless;
use luz::render::forward::DebugView;

use super::common::{context, render_options, validation_exit, GpuArgs, IblArgs};

#[derive(Args, Debug)]
pub struct FidelityArgs {
    /// The generator's argument: {"scenario": {"model": …, "lighting": …, "dimensions": {width,
    /// height}, "target": {x, y, z}, "orbit": {theta, phi, radius}, "verticalFoV": …,
    /// "renderSkybox": …}, "outputFile": "….png"}. Omitted scenario fields take the generator's
    /// defaults (config-reader.ts).
    #[arg(value_name = "JSON")]
    pub config: String,
    /// Resolve the scenario's relative paths (model, lighting, outputFile) against this folder
    /// [default: outputFile against the current folder, model and lighting against outputFile's
    /// folder, as the generator's Blender script does: its `../../../` paths are written for a
    /// folder two levels below `test/`, and the generator passes `test/goldens/<scenario>/…`].
    #[arg(long, value_name = "DIR")]
    pub root: Option<PathBuf>,
    /// Also write the equivalent luz scene file here (`luz render` of it gives the same pixels).
    #[arg(long, value_name = "FILE")]
    pub scene_out: Option<PathBuf>,
    #[command(flatten)]
    pub ibl: IblArgs,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// The generator's default scenario (config-reader.ts `defaultScenario`).
pub const DEFAULT_LIGHTING: &str = "../../../environments/lightroom_14b.hdr";
pub const DEFAULT_SIZE: u32 = 768;
pub const DEFAULT_FOV_DEG: f64 = 45.0;
/// model-viewer's and the generator's `DEVICE_PIXEL_RATIO`: the browser renderers capture at
/// twice the scenario's size, and Blender's script doubles it "to match other renderers".
pub const DEVICE_PIXEL_RATIO: u32 = 2;
/// luz's `aces` (Narkowicz's fit, which scales its input by 0.6) at this exposure matches
/// three.js's `ACESFilmicToneMapping` (Hill's fit of input / 0.6), the tone map of three.js, the
/// Sample Viewer and the generator's Blender script, within 0.011 over [0.05, 4] (docs/fidelity.md).
pub const EXPOSURE_EV: f64 = 0.4618;
/// The environment's turn about +y that puts the equirectangular image where three.js
/// (`equirectUv`: u = 0.5 + atan2(z, x)/2π), the Sample Viewer (`dirToUV`, the same) and the
/// generator's Blender script (Blender's `direction_to_equirectangular` after the glTF importer's
/// y-up to z-up turn: the same again) put it: the image's centre at +x, u = 0.75 at +z. luz's own
/// mapping puts the centre at −z and u = 0.75 at +x (docs/scene-format.md), so the image turns
/// by −90°: luz's u_env = u_world + rotation/360 = u_world − 0.25, which is three.js's u.
pub const ENV_ROTATION_DEG: f64 = -90.0;

/// A scenario read and checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    pub model: PathBuf,
    pub lighting: PathBuf,
    pub width: u32,
    pub height: u32,
    pub target: [f64; 3],
    pub theta_deg: f64,
    pub phi_deg: f64,
    pub radius: f64,
    pub fov_deg: f64,
    pub skybox: bool,
    pub output: PathBuf,
}

const TOP_FIELDS: &[&str] = &["scenario", "outputFile"];
/// `name`, `exclude` and `pt` are the generator's bookkeeping (common.ts ScenarioConfig): read and
/// not used.
const SCENARIO_FIELDS: &[&str] = &[
    "name",
    "model",
    "lighting",
    "dimensions",
    "target",
    "orbit",
    "verticalFoV",
    "renderSkybox",
    "exclude",
    "pt",
];

fn unknown(obj: &Map<String, Value>, at: &str, known: &[&str]) -> Result<(), String> {
    for k in obj.keys() {
        if !known.contains(&k.as_str()) {
            let path = if at.is_empty() {
                k.clone()
            } else {
                format!("{at}.{k}")
            };
            return Err(format!(
                "{path}: unknown field (known: {})",
                known.join(", ")
            ));
        }
    }
    Ok(())
}

fn object<'a>(v: &'a Value, at: &str) -> Result<&'a Map<String, Value>, String> {
    v.as_object()
        .ok_or_else(|| format!("{at}: must be a JSON object, not {v}"))
}

fn number(obj: &Map<String, Value>, at: &str, key: &str, default: f64) -> Result<f64, String> {
    match obj.get(key) {
        None => Ok(default),
        Some(v) => v
            .as_f64()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("{at}.{key}: must be a finite number, not {v}")),
    }
}

fn file(
    v: Option<&Value>,
    at: &str,
    root: &Path,
    default: Option<&str>,
) -> Result<PathBuf, String> {
    let s = match (v, default) {
        (Some(Value::String(s)), _) if !s.is_empty() => s.clone(),
        (Some(v), _) => return Err(format!("{at}: must be a file name, not {v}")),
        (None, Some(d)) => d.to_string(),
        (None, None) => return Err(format!("{at}: missing")),
    };
    Ok(root.join(s))
}

/// Reads the generator's argument. Every message starts with the JSON path of the field at
/// fault (`scenario.orbit.radius: must be ≥ 0, not -1`). Relative paths are resolved against
/// `root`; without one, `outputFile` against the current folder and `model` and `lighting`
/// against `outputFile`'s folder (see `--root`).
pub fn parse(text: &str, root: Option<&Path>) -> Result<Scenario, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("not valid JSON: {e}"))?;
    let top = object(&v, "the argument")?;
    unknown(top, "", TOP_FIELDS)?;
    let s = object(top.get("scenario").ok_or("scenario: missing")?, "scenario")?;
    unknown(s, "scenario", SCENARIO_FIELDS)?;
    let output = file(
        top.get("outputFile"),
        "outputFile",
        root.unwrap_or(Path::new(".")),
        None,
    )?;
    let root = root.unwrap_or(output.parent().unwrap_or(Path::new(".")));
    if !output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(format!(
            "outputFile: must name a .png file, not {}",
            output.display()
        ));
    }
    let model = file(s.get("model"), "scenario.model", root, None)?;
    if !model.is_file() {
        return Err(format!("scenario.model: {}: no such file", model.display()));
    }
    let lighting = file(
        s.get("lighting"),
        "scenario.lighting",
        root,
        Some(DEFAULT_LIGHTING),
    )?;
    if !lighting.is_file() {
        return Err(format!(
            "scenario.lighting: {}: no such file{}",
            lighting.display(),
            if s.contains_key("lighting") {
                ""
            } else {
                " (the generator's default; give scenario.lighting)"
            }
        ));
    }
    let ext = lighting
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if !matches!(ext.as_str(), "hdr" | "exr") {
        return Err(format!(
            "scenario.lighting: {}: luz reads Radiance .hdr and OpenEXR .exr environments only",
            lighting.display()
        ));
    }
    let empty = Map::new();
    let sub = |key: &str| -> Result<&Map<String, Value>, String> {
        match s.get(key) {
            None => Ok(&empty),
            Some(v) => object(v, &format!("scenario.{key}")),
        }
    };
    let dims = sub("dimensions")?;
    unknown(dims, "scenario.dimensions", &["width", "height"])?;
    let max = luz::scene::MAX_IMAGE_SIZE / DEVICE_PIXEL_RATIO;
    let size = |key: &str| -> Result<u32, String> {
        match dims.get(key) {
            None => Ok(DEFAULT_SIZE),
            Some(v) => v
                .as_u64()
                .filter(|n| (1..=u64::from(max)).contains(n))
                .map(|n| n as u32)
                .ok_or_else(|| {
                    format!("scenario.dimensions.{key}: must be a whole number of pixels in 1..={max}, not {v}")
                }),
        }
    };
    let (width, height) = (size("width")?, size("height")?);
    let target = sub("target")?;
    unknown(target, "scenario.target", &["x", "y", "z"])?;
    let t = [
        number(target, "scenario.target", "x", 0.0)?,
        number(target, "scenario.target", "y", 0.0)?,
        number(target, "scenario.target", "z", 0.0)?,
    ];
    let orbit = sub("orbit")?;
    unknown(orbit, "scenario.orbit", &["theta", "phi", "radius"])?;
    let theta_deg = number(orbit, "scenario.orbit", "theta", 0.0)?;
    let phi_deg = number(orbit, "scenario.orbit", "phi", 90.0)?;
    let radius = number(orbit, "scenario.orbit", "radius", 1.0)?;
    if radius < 0.0 {
        return Err(format!("scenario.orbit.radius: must be ≥ 0, not {radius}"));
    }
    let fov_deg = number(s, "scenario", "verticalFoV", DEFAULT_FOV_DEG)?;
    if !(fov_deg > 0.0 && fov_deg < 180.0) {
        return Err(format!(
            "scenario.verticalFoV: must be in (0, 180) degrees, not {fov_deg}"
        ));
    }
    let skybox = match s.get("renderSkybox") {
        None => false,
        Some(Value::Bool(b)) => *b,
        Some(v) => {
            return Err(format!(
                "scenario.renderSkybox: must be true or false, not {v}"
            ))
        }
    };
    Ok(Scenario {
        model,
        lighting,
        width,
        height,
        target: t,
        theta_deg,
        phi_deg,
        radius,
        fov_deg,
        skybox,
        output,
    })
}

fn absolute(p: &Path) -> String {
    std::path::absolute(p)
        .unwrap_or_else(|_| p.to_path_buf())
        .display()
        .to_string()
}

impl Scenario {
    /// The camera: model-viewer's orbit (theta the azimuth about +y from +z, phi the polar angle
    /// from +y, both in degrees; radius in the model's units) around `target`, the view up
    /// following the orbit as the Blender script's camera rig turns it.
    pub fn camera(&self) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let (th, ph) = (self.theta_deg.to_radians(), self.phi_deg.to_radians());
        // cos(90°) is 6e-17 in floating point: such crumbs become 0, so phi = 90 looks exactly
        // level with up exactly +y.
        let snap = |v: [f64; 3]| v.map(|x| if x.abs() < 1e-12 { 0.0 } else { x });
        let dir = snap([ph.sin() * th.sin(), ph.cos(), ph.sin() * th.cos()]);
        let up = snap([-ph.cos() * th.sin(), ph.sin(), -ph.cos() * th.cos()]);
        let pos: Vec<f64> = (0..3)
            .map(|i| self.target[i] + self.radius * dir[i])
            .collect();
        // Looking along −dir (the target itself when radius is 0, as in Sponza's scenario).
        let look: Vec<f64> = (0..3).map(|i| pos[i] - dir[i]).collect();
        ([pos[0], pos[1], pos[2]], [look[0], look[1], look[2]], up)
    }

    /// The equivalent luz scene file.
    pub fn luz_scene(&self) -> Value {
        let (position, target, up) = self.camera();
        // Blender's script: clip 2r/1000 to 2r with r the larger of radius and the model's
        // bounding sphere; luz does not know the sphere before loading, so far reaches 1e5 × near.
        let near = 2.0 * self.radius.max(1e-4) / 1000.0;
        json!({
            "camera": {
                "position": position, "target": target, "up": up,
                "fov_y_deg": self.fov_deg, "near": near, "far": near * 1e5
            },
            "output": {
                "width": self.width * DEVICE_PIXEL_RATIO,
                "height": self.height * DEVICE_PIXEL_RATIO,
                "exposure": EXPOSURE_EV, "tonemap": "aces", "msaa": 4,
                "background": [0, 0, 0], "transparent": !self.skybox
            },
            "ambient": [0, 0, 0],
            "environment": {
                "hdr": absolute(&self.lighting), "intensity": 1, "rotation_deg": ENV_ROTATION_DEG,
                "show_background": self.skybox
            },
            "objects": [
                {"mesh": {"type": "gltf", "path": absolute(&self.model), "lights": true}}
            ]
        })
    }
}

pub fn run(a: FidelityArgs) -> Result<ExitCode> {
    let t0 = Instant::now();
    let scenario = parse(&a.config, a.root.as_deref()).map_err(|e| anyhow!("luz fidelity: {e}"))?;
    let scene_json = serde_json::to_string_pretty(&scenario.luz_scene())?;
    // Parsed as if it were a file beside the output (the paths in it are absolute).
    let origin = scenario
        .output
        .parent()
        .unwrap_or(Path::new("."))
        .join("luz-fidelity-scene.json");
    let scene = luz::scene::parse(&scene_json, &origin)
        .map_err(|e| anyhow!("luz fidelity: the scenario's luz scene: {e}"))?;
    if let Some(p) = &a.scene_out {
        std::fs::write(p, &scene_json).map_err(|e| anyhow!("--scene-out {}: {e}", p.display()))?;
        println!("wrote {} (the equivalent luz scene)", p.display());
    }
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let ctx = context(&a.gpu)?;
    println!("device: {}", ctx.info.summary());
    let options = luz::headless::RenderOptions {
        switches: luz::render::forward::Switches::default().for_frames(1),
        ..render_options(&a.ibl, DebugView::None)
    };
    let mut renderer = Headless::with_options(&ctx, &scene, &options)?;
    let frame = renderer.render()?;
    let image = renderer.image()?;
    let timing = luz::headless::TimingReport::of(&[frame]);
    if let Some(dir) = scenario
        .output
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
    {
        std::fs::create_dir_all(dir)
            .map_err(|e| anyhow!("outputFile: cannot create {}: {e}", dir.display()))?;
    }
    luz::imageio::save_render(
        &scenario.output,
        &image,
        scene.output.encoding(),
        &luz::provenance::of_render(&ctx.info, &scene, Some(&timing)),
    )
    .map_err(|e| anyhow!("outputFile: {e}"))?;
    println!(
        "wrote {} ({}×{}) in {:.0} ms",
        scenario.output.display(),
        scene.output.width,
        scene.output.height,
        t0.elapsed().as_secs_f64() * 1e3
    );
    Ok(validation_exit(&ctx))
}
