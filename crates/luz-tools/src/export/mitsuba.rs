//! Mitsuba 3 XML (`<scene version="3.0.0">`). The XML is written with plain formatting and one
//! escaping function: the document is a fixed, shallow set of elements whose attribute values
//! are numbers and file names, so a writer crate would add a dependency without removing any
//! risk. The mapping of every field is in `docs/export.md`.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

use super::{ExportError, ExportOptions, ExportReport, Integrator};
use crate::brdf::{
    CookTorranceParams, Diffuse, Distribution, Fresnel, Geometry, MetalRoughParams, Model,
    PrincipledParams, SpecularSource, ALPHA_MIN,
};
use crate::color::Tonemap;
use crate::scene::{
    AlphaMode, EnvSource, Falloff, Filter, LightKind, MeshDesc, Projection, Saturation, Scene,
    Shading, Sides, TextureRef, TextureSlot, Wrap,
};

/// Writes `scene` as `out/scene.xml` with its meshes (`out/meshes/*.ply`), textures
/// (`out/textures/`) and environment (`out/env/`). `out` is created when missing.
pub fn export(
    scene: &Scene,
    opts: &ExportOptions,
    out: &Path,
) -> Result<ExportReport, ExportError> {
    std::fs::create_dir_all(out)
        .map_err(|e| ExportError::new(out, format!("cannot create the output folder: {e}")))?;
    let mut w = Writer {
        out: out.to_path_buf(),
        xml: String::new(),
        report: ExportReport {
            scene_file: out.join("scene.xml"),
            ..Default::default()
        },
        textures: HashMap::new(),
        meshes: HashMap::new(),
        notes: Vec::new(),
    };
    w.document(scene, opts)?;
    w.report.approximations = w
        .notes
        .iter()
        .map(|(what, whos)| {
            if whos.is_empty() {
                what.clone()
            } else {
                format!("{what}: {}", whos.join(", "))
            }
        })
        .collect();
    let path = w.report.scene_file.clone();
    std::fs::write(&path, &w.xml)
        .map_err(|e| ExportError::new(&path, format!("cannot write: {e}")))?;
    w.report.files.insert(0, path);
    Ok(w.report)
}

struct Writer {
    out: PathBuf,
    xml: String,
    report: ExportReport,
    /// Source texture (file or embedded name) → path relative to `out`.
    textures: HashMap<PathBuf, String>,
    /// Mesh (by address: objects share an `Arc<Mesh>`) → path relative to `out`.
    meshes: HashMap<usize, String>,
    /// Approximations: what, and whom it concerns (empty: the scene).
    notes: Vec<(String, Vec<String>)>,
}

/// XML attribute text: `&`, `<`, `>`, `"` and `'` escaped.
pub fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&apos;"),
            c => o.push(c),
        }
    }
    o
}

/// Text for an XML comment (no `--` inside).
fn comment(s: &str) -> String {
    escape(s).replace("--", "- -")
}

fn v3(v: Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}

/// A reflectance parameter: `<rgb>`, or above 1 (the doubled halves of a sum, see
/// `metal_rough`) an unbounded `srgb` texture (Mitsuba refuses `<rgb>` reflectances above 1).
fn reflectance(name: &str, v: Vec3) -> String {
    if v.max_element() > 1.0 {
        format!(
            "<texture type=\"srgb\" name=\"{name}\"><rgb name=\"color\" value=\"{}\"/><boolean name=\"unbounded\" value=\"true\"/></texture>",
            v3(v)
        )
    } else {
        format!("<rgb name=\"{name}\" value=\"{}\"/>", v3(v))
    }
}

fn xyz(v: Vec3) -> String {
    format!("x=\"{}\" y=\"{}\" z=\"{}\"", v.x, v.y, v.z)
}

/// Mitsuba's `<matrix value="…">`: 16 numbers, row by row.
fn matrix(m: Mat4) -> String {
    let mut s = String::new();
    for r in 0..4 {
        for c in 0..4 {
            if !s.is_empty() {
                s.push(' ');
            }
            let _ = write!(s, "{}", m.col(c)[r]);
        }
    }
    s
}

/// A unit vector not parallel to `d` (the `up` of a spot light's look-at).
fn any_perpendicular_up(d: Vec3) -> Vec3 {
    if d.y.abs() < 0.9 {
        Vec3::Y
    } else {
        Vec3::X
    }
}

/// The environment's `to_world`: luz's lookup is Mitsuba's turned by 180° about +y (luz puts
/// the image's centre at −z, Mitsuba its left edge), plus the scene's own rotation.
pub fn environment_rotation_deg(rotation_deg: f32) -> f32 {
    180.0 + rotation_deg
}

impl Writer {
    /// Records an approximation. "material 'x': what", "lights[i]: what" and
    /// "objects[i] 'x': what" are grouped by what, so that the warning reads "what: material
    /// 'a', material 'b'" once.
    fn note(&mut self, s: impl Into<String>) {
        let s = s.into();
        let subject = ["material '", "lights[", "objects["]
            .iter()
            .any(|p| s.starts_with(p));
        let (what, who) = match s.split_once(": ") {
            Some((who, what)) if subject => (what.to_string(), Some(who.to_string())),
            _ => (s, None),
        };
        match self.notes.iter_mut().find(|(w, _)| *w == what) {
            Some((_, whos)) => whos.extend(who),
            None => self.notes.push((what, who.into_iter().collect())),
        }
    }

    fn line(&mut self, depth: usize, s: &str) {
        for _ in 0..depth {
            self.xml.push_str("    ");
        }
        self.xml.push_str(s);
        self.xml.push('\n');
    }

    /// A `<kind name="name" value="value"/>` line.
    fn param(&mut self, depth: usize, kind: &str, name: &str, value: impl std::fmt::Display) {
        self.line(
            depth,
            &format!("<{kind} name=\"{name}\" value=\"{value}\"/>"),
        );
    }

    fn write_file(&mut self, rel: &str, bytes: &[u8]) -> Result<(), ExportError> {
        let path = self.out.join(rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| ExportError::new(parent, format!("cannot create: {e}")))?;
        }
        std::fs::write(&path, bytes)
            .map_err(|e| ExportError::new(&path, format!("cannot write: {e}")))?;
        self.report.files.push(path);
        Ok(())
    }

    fn document(&mut self, scene: &Scene, opts: &ExportOptions) -> Result<(), ExportError> {
        self.line(0, "<?xml version=\"1.0\" encoding=\"utf-8\"?>");
        self.line(
            0,
            &format!(
                "<!-- luz export of {} (luz {}); mappings: docs/export.md -->",
                comment(&scene.display_name()),
                env!("CARGO_PKG_VERSION")
            ),
        );
        self.line(0, "<scene version=\"3.0.0\">");
        self.integrator(scene, opts);
        self.sensor(scene, opts);
        self.scene_level_notes(scene);
        self.environment(scene)?;
        self.lights(scene);
        self.area_lights(scene);
        let used = self.materials(scene)?;
        self.shapes(scene, &used)?;
        self.line(0, "</scene>");
        Ok(())
    }

    fn integrator(&mut self, scene: &Scene, opts: &ExportOptions) {
        let hide = scene
            .environment
            .as_ref()
            .is_some_and(|e| !e.show_background);
        let hide = if hide {
            "\n        <boolean name=\"hide_emitters\" value=\"true\"/>"
        } else {
            ""
        };
        match opts.integrator {
            Integrator::Direct => {
                self.line(1, &format!("<integrator type=\"direct\">{hide}"));
            }
            Integrator::Path { max_depth } => {
                self.line(
                    1,
                    &format!(
                        "<integrator type=\"path\">\n        <integer name=\"max_depth\" value=\"{max_depth}\"/>{hide}"
                    ),
                );
            }
        }
        self.line(1, "</integrator>");
    }

    fn sensor(&mut self, scene: &Scene, opts: &ExportOptions) {
        let c = &scene.camera;
        let o = &scene.output;
        let lookat = format!(
            "<lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>",
            v3(c.position),
            v3(c.target),
            v3(c.up)
        );
        match c.projection {
            Projection::Perspective => {
                self.line(1, "<sensor type=\"perspective\">");
                self.line(2, "<string name=\"fov_axis\" value=\"y\"/>");
                self.param(2, "float", "fov", c.fov_y_deg);
                self.line(2, "<transform name=\"to_world\">");
                self.line(3, &lookat);
            }
            Projection::Orthographic { half_height } => {
                // Mitsuba's orthographic camera sees x in [−1, 1] and y in [−1/aspect, 1/aspect]
                // before to_world: scaling both by half the width gives luz's view rectangle.
                let s = half_height * o.aspect();
                self.line(1, "<sensor type=\"orthographic\">");
                self.line(2, "<transform name=\"to_world\">");
                self.line(3, &format!("<scale x=\"{s}\" y=\"{s}\"/>"));
                self.line(3, &lookat);
            }
        }
        self.line(2, "</transform>");
        self.param(2, "float", "near_clip", c.near);
        self.param(2, "float", "far_clip", c.far);
        self.line(2, "<sampler type=\"multijitter\">");
        self.param(3, "integer", "sample_count", opts.spp.max(1));
        self.line(2, "</sampler>");
        self.line(2, "<film type=\"hdrfilm\">");
        self.param(3, "integer", "width", o.width);
        self.param(3, "integer", "height", o.height);
        self.line(3, "<string name=\"pixel_format\" value=\"rgb\"/>");
        self.line(3, "<rfilter type=\"box\"/>");
        self.line(2, "</film>");
        self.line(1, "</sensor>");
    }

    fn scene_level_notes(&mut self, scene: &Scene) {
        let o = &scene.output;
        if o.tonemap != Tonemap::None || o.exposure != 0.0 {
            self.note(format!(
                "tone mapping ({}) and exposure ({} EV): Mitsuba writes linear radiance",
                o.tonemap.name(),
                o.exposure
            ));
        }
        match scene.saturation {
            Saturation::None => {}
            s => self.note(format!(
                "saturation {s:?} (a clamp or normalisation of the image, not of the light)"
            )),
        }
        if scene.fog.is_some() {
            self.note("depth cueing (fog): no participating medium is exported");
        }
        if scene.ambient != Vec3::ZERO {
            self.note(
                "ambient light (luz: a uniform radiance seen by the diffuse term only): left out",
            );
        }
        if scene.environment.is_none() && o.background != Vec3::ZERO {
            self.note("output.background (Mitsuba's background is black without an environment)");
        }
    }

    fn environment(&mut self, scene: &Scene) -> Result<(), ExportError> {
        let Some(env) = &scene.environment else {
            return Ok(());
        };
        let rotate = format!(
            "<transform name=\"to_world\"><rotate y=\"1\" angle=\"{}\"/></transform>",
            environment_rotation_deg(env.rotation_deg)
        );
        match &env.source {
            EnvSource::Uniform(c) => {
                self.line(1, "<emitter type=\"constant\">");
                self.line(
                    2,
                    &format!(
                        "<rgb name=\"radiance\" value=\"{}\"/>",
                        v3(*c * env.intensity)
                    ),
                );
                self.line(1, "</emitter>");
            }
            EnvSource::Hdr(path) => {
                let name = path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "environment.hdr".into());
                let rel = format!("env/{name}");
                let bytes = std::fs::read(path).map_err(|e| {
                    ExportError::new(path, format!("cannot read the environment: {e}"))
                })?;
                self.write_file(&rel, &bytes)?;
                self.line(1, "<emitter type=\"envmap\">");
                self.param(2, "string", "filename", escape(&rel));
                self.param(2, "float", "scale", env.intensity);
                self.line(2, &rotate);
                self.line(1, "</emitter>");
            }
            EnvSource::Sky { .. } | EnvSource::Studio => {
                // luz's own image of the procedural source (intensity applied), as an EXR.
                let eq = crate::env::load_equirect(env, 1 << 14)
                    .map_err(|e| ExportError::new(&self.out.join("env"), e))?;
                let img = crate::imageio::LinearImage {
                    width: eq.width,
                    height: eq.height,
                    pixels: eq.texels,
                };
                let rel = format!("env/{}.exr", env.source.kind_name());
                let path = self.out.join(&rel);
                std::fs::create_dir_all(self.out.join("env")).map_err(|e| {
                    ExportError::new(&self.out.join("env"), format!("cannot create: {e}"))
                })?;
                crate::imageio::save(&path, &img, 0.0, Tonemap::None)
                    .map_err(|e| ExportError::new(&path, e))?;
                self.report.files.push(path);
                self.line(1, "<emitter type=\"envmap\">");
                self.param(2, "string", "filename", escape(&rel));
                self.line(2, &rotate);
                self.line(1, "</emitter>");
            }
        }
        Ok(())
    }

    fn lights(&mut self, scene: &Scene) {
        let mut unshadowed = Vec::new();
        for (i, l) in scene.lights.iter().enumerate() {
            let e = l.color * l.intensity;
            if l.shadow.is_none() {
                unshadowed.push(format!("lights[{i}]"));
            } else if l.radius > 0.0 || l.angular_radius_deg > 0.0 {
                self.note(format!(
                    "lights[{i}]: its size (soft shadows in luz; Mitsuba's punctual lights cast hard ones)"
                ));
            }
            if l.kind != LightKind::Directional {
                match l.falloff {
                    Falloff::InverseSquare => {}
                    Falloff::None => self.note(format!(
                        "lights[{i}]: falloff \"none\" (Mitsuba's lights fall off as 1/d²)"
                    )),
                    Falloff::Classic { .. } => self.note(format!(
                        "lights[{i}]: the classic falloff f_at (Mitsuba's lights fall off as 1/d²)"
                    )),
                }
                if l.range.is_some() {
                    self.note(format!(
                        "lights[{i}]: the range window (Mitsuba's lights reach everywhere)"
                    ));
                }
            }
            match l.kind {
                LightKind::Directional => {
                    self.line(1, "<emitter type=\"directional\">");
                    self.line(
                        2,
                        &format!("<vector name=\"direction\" {}/>", xyz(l.direction)),
                    );
                    self.line(
                        2,
                        &format!("<rgb name=\"irradiance\" value=\"{}\"/>", v3(e)),
                    );
                }
                LightKind::Point => {
                    self.line(1, "<emitter type=\"point\">");
                    self.line(
                        2,
                        &format!("<point name=\"position\" {}/>", xyz(l.position)),
                    );
                    self.line(2, &format!("<rgb name=\"intensity\" value=\"{}\"/>", v3(e)));
                }
                LightKind::Spot => {
                    if l.exponent != 0.0 {
                        self.note(format!(
                            "lights[{i}]: the spot exponent (cos θ)^{} (Mitsuba's spot has none)",
                            l.exponent
                        ));
                    }
                    // A hard edge: the beam a hair inside the cut-off (Mitsuba ramps linearly in
                    // angle between them). With an inner cone: luz's smoothstep in cos θ against
                    // Mitsuba's linear ramp in θ.
                    let beam = match l.inner_deg {
                        None => (l.umbra_deg - 1e-3).max(0.0),
                        Some(inner) => {
                            self.note(format!(
                                "lights[{i}]: the spot's inner cone (luz: smoothstep in cos θ; Mitsuba: linear in θ)"
                            ));
                            inner
                        }
                    };
                    self.line(1, "<emitter type=\"spot\">");
                    self.line(2, "<transform name=\"to_world\">");
                    self.line(
                        3,
                        &format!(
                            "<lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>",
                            v3(l.position),
                            v3(l.position + l.direction),
                            v3(any_perpendicular_up(l.direction))
                        ),
                    );
                    self.line(2, "</transform>");
                    self.line(2, &format!("<rgb name=\"intensity\" value=\"{}\"/>", v3(e)));
                    self.param(2, "float", "cutoff_angle", l.umbra_deg);
                    self.line(2, &format!("<float name=\"beam_width\" value=\"{beam}\"/>"));
                }
            }
            self.line(1, "</emitter>");
        }
        if !unshadowed.is_empty() {
            self.note(format!(
                "lights without shadow (Mitsuba always shadows): {}",
                unshadowed.join(", ")
            ));
        }
    }

    /// Copies a texture beside the scene (once) and returns its path relative to the output.
    fn texture_file(&mut self, t: &TextureRef) -> Result<String, ExportError> {
        if let Some(rel) = self.textures.get(&t.path) {
            return Ok(rel.clone());
        }
        let bytes: Vec<u8> = match &t.embedded {
            Some(b) => b.to_vec(),
            None => std::fs::read(&t.path)
                .map_err(|e| ExportError::new(&t.path, format!("cannot read the texture: {e}")))?,
        };
        let ext = if bytes.starts_with(b"\x89PNG") {
            "png".to_string()
        } else if bytes.starts_with(&[0xFF, 0xD8]) {
            "jpg".to_string()
        } else {
            t.path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_else(|| "png".into())
        };
        let stem: String = t
            .path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let rel = format!("textures/t{}_{stem}.{ext}", self.textures.len());
        self.write_file(&rel, &bytes)?;
        self.textures.insert(t.path.clone(), rel.clone());
        Ok(rel)
    }

    /// A colour parameter: the map (when given) or the constant.
    fn colour_param(
        &mut self,
        name: &str,
        value: Vec3,
        map: Option<&TextureRef>,
        material: &str,
    ) -> Result<String, ExportError> {
        let Some(t) = map else {
            return Ok(reflectance(name, value));
        };
        if value != Vec3::ONE {
            self.note(format!(
                "material '{material}': base colour factor × map (Mitsuba multiplies no textures; the map alone is exported)"
            ));
        }
        let rel = self.texture_file(t)?;
        let wrap = |w: Wrap| match w {
            Wrap::Repeat => "repeat",
            Wrap::Clamp => "clamp",
            Wrap::Mirror => "mirror",
        };
        if t.sampler.wrap_u != t.sampler.wrap_v {
            self.note(format!(
                "material '{material}': different wrap modes in u and v"
            ));
        }
        let filter = match t.sampler.mag {
            Filter::Linear => "bilinear",
            Filter::Nearest => "nearest",
        };
        Ok(format!(
            "<texture type=\"bitmap\" name=\"{name}\"><string name=\"filename\" value=\"{}\"/><string name=\"wrap_mode\" value=\"{}\"/><string name=\"filter_type\" value=\"{filter}\"/></texture>",
            escape(&rel),
            wrap(t.sampler.wrap_u)
        ))
    }

    /// Each used material as `<bsdf id="mN">` (and `mN_2s`, twosided, when an open mesh uses it).
    /// Returns, per material, whether it was written.
    fn materials(&mut self, scene: &Scene) -> Result<Vec<bool>, ExportError> {
        let mut used = vec![false; scene.materials.len()];
        let mut two_sided = vec![false; scene.materials.len()];
        for o in &scene.objects {
            if let Some(u) = used.get_mut(o.material) {
                *u = true;
                two_sided[o.material] |= needs_two_sided(scene, o);
            }
        }
        for (i, m) in scene.materials.iter().enumerate() {
            if !used[i] {
                continue;
            }
            let inner = self.bsdf(&m.name, &m.material, &m.textures)?;
            self.line(1, &format!("<!-- material {} -->", comment(&m.name)));
            self.line(
                1,
                &inner.replacen("<bsdf ", &format!("<bsdf id=\"m{i}\" "), 1),
            );
            if two_sided[i] {
                self.line(
                    1,
                    &format!("<bsdf type=\"twosided\" id=\"m{i}_2s\">{inner}</bsdf>"),
                );
            }
            let t = &m.textures;
            // Every map but the base colour (exported as a bitmap) and the emission.
            let mut dropped: Vec<String> = t
                .maps()
                .filter(|(slot, _)| !matches!(slot, TextureSlot::BaseColor | TextureSlot::Emissive))
                .map(|(slot, _)| format!("{} map", slot.name()))
                .collect();
            if t.emissive.is_some() || t.emissive_factor != Vec3::ZERO {
                dropped.push("emission".into());
            }
            if !dropped.is_empty() {
                self.note(format!(
                    "material '{}': {} left out",
                    m.name,
                    dropped.join(", ")
                ));
            }
            if t.alpha_mode != AlphaMode::Opaque {
                self.note(format!(
                    "material '{}': alpha {:?} (exported opaque)",
                    m.name, t.alpha_mode
                ));
            }
        }
        Ok(used)
    }

    /// One material's BSDF element (without an id).
    fn bsdf(
        &mut self,
        name: &str,
        model: &Model,
        tex: &crate::scene::MaterialTextures,
    ) -> Result<String, ExportError> {
        let base_map = tex.base_color.as_ref();
        Ok(match model {
            Model::Lambert(p) => {
                let r = self.colour_param("reflectance", p.albedo, base_map, name)?;
                format!("<bsdf type=\"diffuse\">{r}</bsdf>")
            }
            Model::OrenNayar(p) => {
                if p.sigma_deg > 0.0 {
                    self.note(format!(
                        "material '{name}': qualitative Oren-Nayar (exported as Lambert with its albedo)"
                    ));
                }
                let r = self.colour_param("reflectance", p.albedo, base_map, name)?;
                format!("<bsdf type=\"diffuse\">{r}</bsdf>")
            }
            Model::Phong(p) => {
                self.note(format!(
                    "material '{name}': classic {} (exported as Lambert with albedo k_d·O_d; the classic model has no 1/π and its lobe is not a BRDF)",
                    if p.blinn { "Blinn-Phong" } else { "Phong" }
                ));
                let r = self.colour_param(
                    "reflectance",
                    (p.diffuse_color * p.kd).min(Vec3::ONE),
                    base_map,
                    name,
                )?;
                format!("<bsdf type=\"diffuse\">{r}</bsdf>")
            }
            Model::CookTorrance(p) => self.cook_torrance(name, p, base_map)?,
            Model::MetalRough(p) => self.metal_rough(name, p, base_map)?,
            Model::Principled(p) => self.principled(name, p, base_map)?,
        })
    }

    /// Notes where luz's specular terms differ from Mitsuba's microfacet model (separable
    /// Smith G of the same distribution, exact Fresnel).
    fn specular_notes(&mut self, name: &str, d: Distribution, g: Geometry, diffuse: Diffuse) {
        match (d, g) {
            (Distribution::Ggx, Geometry::SmithGgx) => {}
            (Distribution::Ggx, g) => self.note(format!(
                "material '{name}': geometry {g:?} (Mitsuba's GGX uses the separable Smith G: \"smith_ggx\")"
            )),
            // Walter et al.'s rational G1, within 0.31 % of Mitsuba's exact one.
            (Distribution::Beckmann, Geometry::SmithBeckmann) => {}
            (Distribution::Beckmann, g) => self.note(format!(
                "material '{name}': Beckmann with geometry {g:?} (Mitsuba's Beckmann uses its own Smith G)"
            )),
        }
        if diffuse == Diffuse::Burley {
            self.note(format!(
                "material '{name}': Burley diffuse (exported as Lambert)"
            ));
        }
    }

    fn conductor(&mut self, d: Distribution, alpha: f32, eta: Vec3, k: Vec3, scale: f32) -> String {
        let dist = match d {
            Distribution::Ggx => "ggx",
            Distribution::Beckmann => "beckmann",
        };
        let mut s = format!(
            "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"{dist}\"/><float name=\"alpha\" value=\"{alpha}\"/><rgb name=\"eta\" value=\"{}\"/><rgb name=\"k\" value=\"{}\"/>",
            v3(eta),
            v3(k)
        );
        if scale != 1.0 {
            s.push_str(&reflectance("specular_reflectance", Vec3::splat(scale)));
        }
        s.push_str("</bsdf>");
        s
    }

    /// A constant-F0 mirror-coated conductor: Mitsuba's `material="none"` (F = 1) scaled by F0.
    fn constant_f0(&mut self, d: Distribution, alpha: f32, f0: Vec3) -> String {
        let dist = match d {
            Distribution::Ggx => "ggx",
            Distribution::Beckmann => "beckmann",
        };
        format!(
            "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"{dist}\"/><float name=\"alpha\" value=\"{alpha}\"/><string name=\"material\" value=\"none\"/>{}</bsdf>",
            reflectance("specular_reflectance", f0)
        )
    }

    fn cook_torrance(
        &mut self,
        name: &str,
        p: &CookTorranceParams,
        base_map: Option<&TextureRef>,
    ) -> Result<String, ExportError> {
        let p = p.sanitized();
        self.specular_notes(name, p.distribution, p.geometry, p.diffuse);
        let alpha = p.width();
        let (spec, kappa) = p.specular.fresnel_inputs(p.fresnel);
        let specular = match p.fresnel {
            Fresnel::ConductorExact => self.conductor(p.distribution, alpha, spec, kappa, 1.0),
            Fresnel::Conductor => {
                self.note(format!(
                    "material '{name}': the approximate conductor Fresnel (Mitsuba's is exact: \"conductor_exact\"; 0.2-0.9 % apart for gold)"
                ));
                self.conductor(p.distribution, alpha, spec, kappa, 1.0)
            }
            Fresnel::Dielectric => {
                if spec.min_element() < 1.0 {
                    self.note(format!(
                        "material '{name}': dielectric Fresnel with η < 1 (exported as a conductor with κ = 0)"
                    ));
                }
                if matches!(p.specular, SpecularSource::Complex(_)) {
                    self.note(format!(
                        "material '{name}': κ dropped by the dielectric Fresnel"
                    ));
                }
                self.conductor(p.distribution, alpha, spec, Vec3::ZERO, 1.0)
            }
            f => {
                self.note(format!(
                    "material '{name}': {f:?} Fresnel (exported as a constant F0; Mitsuba's conductors use the exact Fresnel)"
                ));
                self.constant_f0(p.distribution, alpha, spec)
            }
        };
        let diffuse_r = self.colour_param("reflectance", p.color, base_map, name)?;
        let diffuse = format!("<bsdf type=\"diffuse\">{diffuse_r}</bsdf>");
        // f = (1 − k_d) · specular + k_d · diffuse: blendbsdf's weight is that of its second BSDF.
        Ok(if p.kd <= 0.0 {
            specular
        } else if p.kd >= 1.0 {
            diffuse
        } else {
            format!(
                "<bsdf type=\"blendbsdf\"><float name=\"weight\" value=\"{}\"/>{specular}{diffuse}</bsdf>",
                p.kd
            )
        })
    }

    fn metal_rough(
        &mut self,
        name: &str,
        p: &MetalRoughParams,
        base_map: Option<&TextureRef>,
    ) -> Result<String, ExportError> {
        let p = p.sanitized();
        if p.transmission.factor > 0.0 {
            return self.glass(name, &p, base_map);
        }
        self.specular_notes(name, p.distribution, p.geometry, p.diffuse);
        if p.diffuse_fresnel_weight {
            self.note(format!("material '{name}': the diffuse's 1 − F weight"));
        }
        // The glTF extension layers: Mitsuba's principled has a clearcoat and a sheen of its own
        // (Disney 2015's), not KHR_materials_clearcoat's or KHR_materials_sheen's; left out.
        if p.clearcoat > 0.0 {
            self.note(format!(
                "material '{name}': KHR_materials_clearcoat's coat (left out)"
            ));
        }
        if p.sheen_color != Vec3::ZERO {
            self.note(format!(
                "material '{name}': KHR_materials_sheen's sheen (left out)"
            ));
        }
        // Mitsuba's alpha_u / alpha_v follow the mesh's own parameterisation, not the glTF
        // tangents luz turns the lobe from; left out rather than exported along another axis.
        if p.anisotropy_strength > 0.0 {
            self.note(format!(
                "material '{name}': KHR_materials_anisotropy's stretched lobe (left out: isotropic)"
            ));
        }
        if crate::brdf::has_iridescence(&p.sanitized()) {
            self.note(format!(
                "material '{name}': KHR_materials_iridescence's thin film (left out)"
            ));
        }
        let alpha = (p.roughness * p.roughness).max(ALPHA_MIN);
        let f0 = p.dielectric_f0.lerp(p.base_color, p.metallic);
        let c_diff = p.base_color * (1.0 - p.metallic);
        if base_map.is_some() && p.metallic > 0.0 {
            self.note(format!(
                "material '{name}': a base colour map on a metal (its F0 is the constant factor)"
            ));
        }
        // f = diffuse + specular, a sum: blendbsdf at ½ of both, each doubled.
        let scale = if p.metallic < 1.0 { 2.0 } else { 1.0 };
        let specular = match p.fresnel {
            Fresnel::Conductor | Fresnel::ConductorExact | Fresnel::Dielectric => {
                let (eta, _) = p.fresnel.inputs_from_f0(f0);
                self.conductor(p.distribution, alpha, eta, Vec3::ZERO, scale)
            }
            f => {
                self.note(format!(
                    "material '{name}': {f:?} Fresnel (exported as a constant F0; Mitsuba's conductors use the exact Fresnel)"
                ));
                self.constant_f0(p.distribution, alpha, f0 * scale)
            }
        };
        if p.metallic >= 1.0 {
            return Ok(specular);
        }
        let map = if p.metallic == 0.0 { base_map } else { None };
        let r = self.colour_param("reflectance", c_diff * scale, map, name)?;
        let diffuse = format!("<bsdf type=\"diffuse\">{r}</bsdf>");
        Ok(format!(
            "<bsdf type=\"blendbsdf\"><float name=\"weight\" value=\"0.5\"/>{specular}{diffuse}</bsdf>"
        ))
    }

    fn principled(
        &mut self,
        name: &str,
        p: &PrincipledParams,
        base_map: Option<&TextureRef>,
    ) -> Result<String, ExportError> {
        let p = p.sanitized();
        if p.metallic < 1.0 {
            self.note(format!(
                "material '{name}': Principled with metallic < 1 (Mitsuba's principled is Disney 2015, luz's disney.brdf 2012: the dielectric and diffuse parts differ)"
            ));
        }
        if p.clearcoat > 0.0 {
            self.note(format!(
                "material '{name}': Principled clearcoat (not cross-checked)"
            ));
        }
        if p.anisotropic > 0.0 {
            self.note(format!(
                "material '{name}': Principled anisotropy (tangent frames are not matched)"
            ));
        }
        let base = self.colour_param("base_color", p.base_color, base_map, name)?;
        let f = |n: &str, v: f32| format!("<float name=\"{n}\" value=\"{v}\"/>");
        Ok(format!(
            "<bsdf type=\"principled\">{base}{}{}{}{}{}{}{}{}{}</bsdf>",
            f("metallic", p.metallic),
            f("specular", p.specular),
            f("spec_tint", p.specular_tint),
            f("roughness", p.roughness),
            f("anisotropic", p.anisotropic),
            f("sheen", p.sheen),
            f("sheen_tint", p.sheen_tint),
            f("clearcoat", p.clearcoat),
            f("clearcoat_gloss", p.clearcoat_gloss),
        ))
    }

    fn shapes(&mut self, scene: &Scene, used: &[bool]) -> Result<(), ExportError> {
        for (i, o) in scene.objects.iter().enumerate() {
            if !used.get(o.material).copied().unwrap_or(false) {
                continue;
            }
            let m = &scene.materials[o.material];
            let bsdf = if needs_two_sided(scene, o) {
                format!("<ref id=\"m{}_2s\"/>", o.material)
            } else {
                format!("<ref id=\"m{}\"/>", o.material)
            };
            if o.shading == Shading::Gouraud {
                self.note(format!(
                    "objects[{i}] '{}': Gouraud shading (exported smooth, lit per pixel)",
                    o.name
                ));
            }
            if !o.shadow.cast || !o.shadow.receive {
                self.note(format!(
                    "objects[{i}] '{}': shadow casting/receiving switched off (Mitsuba always shadows)",
                    o.name
                ));
            }
            if !o.mesh.colors.is_empty() {
                self.note(format!(
                    "objects[{i}] '{}': vertex colours left out",
                    o.name
                ));
            }
            self.line(1, &format!("<!-- objects[{i}]: {} -->", comment(&o.name)));
            // Exact spheres (luz's reference intersects them exactly too) when the scale is
            // uniform and no map needs luz's UVs.
            let t = &o.transform;
            let uniform = (t.scale.x - t.scale.y).abs() <= 1e-6 * t.scale.x
                && (t.scale.x - t.scale.z).abs() <= 1e-6 * t.scale.x;
            let radius = match o.desc {
                MeshDesc::Sphere { radius, .. } | MeshDesc::Icosphere { radius, .. } => {
                    Some(radius)
                }
                _ => None,
            };
            if let (Some(r), true, false) = (radius, uniform, has_maps(&m.textures)) {
                self.line(1, "<shape type=\"sphere\">");
                self.line(2, &format!("<point name=\"center\" {}/>", xyz(t.position)));
                self.param(2, "float", "radius", r * t.scale.x);
                self.line(2, &bsdf);
                self.line(1, "</shape>");
                continue;
            }
            let key = std::sync::Arc::as_ptr(&o.mesh) as usize;
            let rel = match self.meshes.get(&key) {
                Some(r) => r.clone(),
                None => {
                    let rel = format!("meshes/mesh{}.ply", self.meshes.len());
                    self.write_file(&rel, &super::ply_bytes(&o.mesh))?;
                    self.meshes.insert(key, rel.clone());
                    rel
                }
            };
            self.line(1, "<shape type=\"ply\">");
            self.param(2, "string", "filename", escape(&rel));
            self.line(
                2,
                &format!(
                    "<transform name=\"to_world\"><matrix value=\"{}\"/></transform>",
                    matrix(t.matrix())
                ),
            );
            if o.shading == Shading::Flat {
                self.line(2, "<boolean name=\"face_normals\" value=\"true\"/>");
            }
            self.line(2, &bsdf);
            self.line(1, "</shape>");
        }
        Ok(())
    }
}

fn has_maps(t: &crate::scene::MaterialTextures) -> bool {
    t.base_color.is_some() || t.normal.is_some() || t.specular.is_some()
}

/// Whether an object's back faces are lit in luz (an open mesh or glTF `doubleSided`), which in
/// Mitsuba needs a `twosided` BSDF.
fn needs_two_sided(scene: &Scene, o: &crate::scene::Object) -> bool {
    let Some(m) = scene.materials.get(o.material) else {
        return false;
    };
    match m.textures.sides {
        Sides::Single => false,
        Sides::Double => true,
        Sides::Auto => matches!(
            o.desc,
            MeshDesc::Plane { .. } | MeshDesc::Obj { .. } | MeshDesc::Gltf { .. }
        ),
    }
}

mod area;
mod glass;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping_and_matrices() {
        assert_eq!(escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&apos;");
        assert_eq!(comment("x--y"), "x- -y");
        let m = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(matrix(m), "1 0 0 1 0 1 0 2 0 0 1 3 0 0 0 1");
    }
}
