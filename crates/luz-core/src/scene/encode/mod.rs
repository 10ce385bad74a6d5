//! [`Scene`] → JSON: the inverse of `decode.rs`, so that an edited scene can be saved and loaded
//! back as the same scene.
//!
//! What is written:
//!
//! * every section explicitly (camera, output, ambient, saturation, lights, materials, objects,
//!   and fog and environment when present), every field of every light, material, texture map
//!   and environment, including the values that equal the defaults, so a saved file does not
//!   depend on the defaults of the luz that reads it;
//! * numbers as the shortest decimal text that reads back as the same `f32` through the
//!   decoder (which parses an `f64` and rounds it to `f32`); unit vectors (camera `up`, light and
//!   sun directions), which the decoder normalises, as a vector whose normalisation gives back
//!   exactly the stored one;
//! * file paths (OBJ meshes, texture maps, `hdr` environments) relative to the folder the scene is
//!   written into when the two share more than the file-system root, else absolute;
//! * an OBJ once per OBJ entry: the objects an OBJ file expanded into (one per part, consecutive,
//!   sharing their meshes) are written back as one `{"type": "obj"}` entry, without `material`
//!   when the parts take theirs from the MTL file (the MTL materials are then recreated by the
//!   decoder and not written), with it otherwise.
//!
//! Not written: `source`, `warnings`, `cameras` (a glTF's cameras; the one in use is the
//! scene's camera) and texture maps embedded in glTF files (a note says so). What the format cannot say (a part of an OBJ moved on its
//! own, a material given a map its model does not take, an MTL-made material used where the
//! decoder cannot recreate it, …) is either approximated or dropped, and described in
//! [`Encoded::notes`].
//!
//! `serde_json::Value` (without serde_json's `preserve_order` feature) keeps object keys sorted,
//! so [`to_json`] loses the order of the materials (a scene read back from its text lists them
//! by name); [`Encoded::to_text`] and [`save`] keep the scene's order.

use std::collections::{HashMap, HashSet};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;
use serde_json::Value;

use super::decode::{DIFFUSES, DISTRIBUTIONS, FILM_ANGLES, FRESNELS, GEOMETRIES};
use super::{
    EnvSource, Environment, Material, MaterialTextures, MeshDesc, Object, Saturation, Scene,
    Shading, TextureRef, TextureSlot,
};
use crate::brdf::{Distribution, Fresnel, Geometry, MetalRoughParams, SpecularSource};
use crate::scene::{slots_for_model, SamplerDesc};

/// The scene as JSON, with file paths relative to the folder of the file it was loaded from
/// (absolute for a scene without a `source`, such as the embedded default). Object keys are
/// sorted (see the module documentation); use [`encode`] and [`Encoded::to_text`] for the text a
/// file should hold.
pub fn to_json(scene: &Scene) -> Value {
    encode(scene, source_dir(scene)).to_json()
}

/// Writes `scene` to `path` as pretty-printed JSON (two-space indentation, arrays of numbers on
/// one line), with file paths relative to `path`'s folder. The text is written to a temporary
/// file next to `path` and renamed over it, so a failed save leaves an existing file intact.
/// Errors name `path`.
pub fn save(scene: &Scene, path: &Path) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let text = encode(scene, Some(dir)).to_text();
    let err = |e: std::io::Error, what: &str| {
        std::io::Error::new(
            e.kind(),
            format!("{}: cannot {what} the scene file: {e}", path.display()),
        )
    };
    let name = path
        .file_name()
        .ok_or_else(|| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("{}: not a file name", path.display()),
            )
        })?
        .to_string_lossy()
        .into_owned();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let written = std::fs::File::create(&tmp)
        .and_then(|mut f| {
            f.write_all(text.as_bytes())?;
            f.sync_all()
        })
        .map_err(|e| err(e, "write"))
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| err(e, "replace")));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

/// Encodes `scene` for a file in the folder `dir` (the base of relative paths; `None`: every
/// path absolute).
pub fn encode(scene: &Scene, dir: Option<&Path>) -> Encoded {
    let dir = dir.map(|d| {
        let d = if d.as_os_str().is_empty() {
            Path::new(".")
        } else {
            d
        };
        canonical_dir(d)
    });
    let mut enc = Encoder {
        scene,
        dir,
        notes: Vec::new(),
        exported: HashMap::new(),
        export_order: Vec::new(),
        created: HashSet::new(),
    };
    let root = enc.scene_node();
    Encoded {
        root,
        notes: enc.notes,
    }
}

/// An encoded scene: its JSON tree, in the scene's order, and what could not be encoded exactly.
#[derive(Debug, Clone)]
pub struct Encoded {
    root: Node,
    /// One sentence per thing the scene format cannot express, naming the object or material and
    /// saying what was written instead. Empty for any scene the decoder produced.
    pub notes: Vec<String>,
}

impl Encoded {
    /// The tree as a `serde_json::Value` (object keys sorted).
    pub fn to_json(&self) -> Value {
        self.root.to_value()
    }

    /// Pretty-printed JSON text in the scene's order, ending with a newline.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        self.root.write(0, &mut out);
        out.push('\n');
        out
    }
}

mod area;
mod fields;
mod node;
mod paths;
mod transmission;

use fields::*;
use node::*;
use paths::*;

// ---------------------------------------------------------------------------------------------
// The encoder.

struct Encoder<'a> {
    scene: &'a Scene,
    /// Canonical folder of the file being written (`None`: absolute paths).
    dir: Option<PathBuf>,
    notes: Vec<String>,
    /// Materials made from MTL files that must be written as scene materials (used where the
    /// decoder cannot recreate them): scene material index → the name written.
    exported: HashMap<usize, String>,
    export_order: Vec<usize>,
    /// MTL-made materials the OBJ entries written so far make the decoder recreate (by index):
    /// objects after them may refer to them by name.
    created: HashSet<usize>,
}

/// A name the `materials` block may hold (`/` is reserved for materials made from OBJ files).
fn is_scene_material_name(name: &str) -> bool {
    !name.trim().is_empty() && !name.contains('/')
}

impl Encoder<'_> {
    fn path(&self, file: &Path) -> String {
        file_path(file, self.dir.as_deref())
    }

    fn scene_node(&mut self) -> Node {
        let s = self.scene;
        let mut root = Node::obj();
        root.put("description", s.description.as_str());
        root.put("camera", camera(&s.camera));
        let mut output = Node::obj()
            .with("width", s.output.width)
            .with("height", s.output.height)
            .with("background", s.output.background)
            .with("exposure", s.output.exposure)
            .with("tonemap", s.output.tonemap.name())
            .with("msaa", s.output.msaa)
            .with("tessellation_error_px", s.output.tessellation_error_px);
        if s.output.transparent {
            output.put("transparent", true);
        }
        if s.output.refraction != super::Refraction::default() {
            output.put("refraction", s.output.refraction.name());
        }
        if !s.output.golden.is_empty() {
            output.put("golden", golden_tolerances(&s.output.golden));
        }
        root.put("output", output);
        root.put("ambient", s.ambient);
        root.put(
            "saturation",
            match s.saturation {
                Saturation::Clamp => "clamp",
                Saturation::Normalize => "normalize",
                Saturation::None => "none",
            },
        );
        // Area lights after the punctual ones (the decoder keeps them in their own list).
        let lights = s.lights.iter().map(light);
        let area = s.area_lights.iter().map(area::area_light);
        root.put("lights", Node::Arr(lights.chain(area).collect()));
        // Objects first: they decide which MTL-made materials must be written as scene materials.
        let objects = self.objects();
        root.put("materials", self.materials());
        root.put("objects", Node::Arr(objects));
        if let Some(f) = &s.fog {
            root.put("fog", fog(f));
        }
        if let Some(e) = &s.environment {
            root.put("environment", self.environment(e));
        }
        root
    }

    // --- Materials --------------------------------------------------------------------------

    fn materials(&mut self) -> Node {
        let mut block = Node::obj();
        let scene = self.scene;
        for m in &scene.materials {
            if is_scene_material_name(&m.name) {
                let node = self.material(&m.name, &m.material, &m.textures);
                block.put(&m.name, node);
            }
        }
        for &i in &self.export_order.clone() {
            let m = &scene.materials[i];
            let name = self.exported[&i].clone();
            let node = self.material(&name, &m.material, &m.textures);
            block.put(&name, node);
        }
        block
    }

    fn material(&mut self, name: &str, material: &Material, textures: &MaterialTextures) -> Node {
        let mut n = Node::obj().with("model", material.name());
        match material {
            Material::Phong(p) => {
                n.put("ka", p.ka)
                    .put("kd", p.kd)
                    .put("ks", p.ks)
                    .put("shininess", p.shininess)
                    .put("diffuse_color", p.diffuse_color)
                    .put("specular_color", p.specular_color);
            }
            Material::Lambert(crate::brdf::LambertParams { albedo }) => {
                n.put("albedo", *albedo);
            }
            Material::CookTorrance(p) => {
                let n = n.put("color", p.color).put("kd", p.kd);
                put_terms(n, p.roughness, (p.distribution, p.geometry, p.fresnel))
                    .put("diffuse", select(DIFFUSES, p.diffuse));
                match p.specular {
                    SpecularSource::Ior(eta) => n.put("ior", eta),
                    SpecularSource::F0(f0) => n.put("f0", f0),
                    SpecularSource::Complex(c) => {
                        n.put("complex_ior", Node::obj().with("eta", c.eta).with("k", c.k))
                    }
                };
            }
            Material::MetalRough(p) => {
                let n = n
                    .put("base_color", p.base_color)
                    .put("metallic", p.metallic);
                let n = put_terms(n, p.roughness, (p.distribution, p.geometry, p.fresnel))
                    .put("diffuse_fresnel_weight", p.diffuse_fresnel_weight)
                    .put("diffuse", select(DIFFUSES, p.diffuse));
                // The dielectric F0 (from KHR_materials_ior / _specular), only when not 0.04.
                if p.dielectric_f0 != MetalRoughParams::default().dielectric_f0 {
                    n.put("dielectric_f0", p.dielectric_f0);
                }
                // Its F90 (KHR_materials_specular's specularFactor), only when not 1.
                if p.dielectric_f90 != 1.0 {
                    n.put("dielectric_f90", p.dielectric_f90);
                }
                // The film's Fresnel at the view, only when chosen.
                if p.iridescence_at_view {
                    n.put("iridescence_angle", select(FILM_ANGLES, true));
                }
                // KHR_materials_clearcoat, only when there is a coat (files without one are
                // written as before).
                if p.clearcoat != 0.0 || p.clearcoat_roughness != 0.0 {
                    n.put(
                        "clearcoat",
                        Node::obj()
                            .with("clearcoatFactor", p.clearcoat)
                            .with("clearcoatRoughnessFactor", p.clearcoat_roughness),
                    );
                }
                // KHR_materials_sheen, likewise only when there is a sheen.
                if p.sheen_color != Vec3::ZERO || p.sheen_roughness != 0.0 {
                    n.put(
                        "sheen",
                        Node::obj()
                            .with("sheenColorFactor", p.sheen_color)
                            .with("sheenRoughnessFactor", p.sheen_roughness),
                    );
                }
                // KHR_materials_anisotropy, likewise.
                if p.anisotropy_strength != 0.0 || p.anisotropy_rotation != 0.0 {
                    n.put(
                        "anisotropy",
                        Node::obj()
                            .with("anisotropyStrength", p.anisotropy_strength)
                            .with("anisotropyRotation", p.anisotropy_rotation),
                    );
                }
                // KHR_materials_iridescence, likewise (every field once the film is on).
                let d = crate::brdf::MetalRoughParams::default();
                if p.iridescence != 0.0
                    || (
                        p.iridescence_ior,
                        p.iridescence_thickness_min,
                        p.iridescence_thickness_max,
                    ) != (
                        d.iridescence_ior,
                        d.iridescence_thickness_min,
                        d.iridescence_thickness_max,
                    )
                {
                    n.put(
                        "iridescence",
                        Node::obj()
                            .with("iridescenceFactor", p.iridescence)
                            .with("iridescenceIor", p.iridescence_ior)
                            .with("iridescenceThicknessMinimum", p.iridescence_thickness_min)
                            .with("iridescenceThicknessMaximum", p.iridescence_thickness_max),
                    );
                }
                transmission::put(n, &p.transmission);
            }
            Material::Principled(p) => {
                n.put("base_color", p.base_color)
                    .put("subsurface", p.subsurface)
                    .put("metallic", p.metallic)
                    .put("specular", p.specular)
                    .put("specular_tint", p.specular_tint)
                    .put("roughness", p.roughness)
                    .put("anisotropic", p.anisotropic)
                    .put("sheen", p.sheen)
                    .put("sheen_tint", p.sheen_tint)
                    .put("clearcoat", p.clearcoat)
                    .put("clearcoat_gloss", p.clearcoat_gloss);
            }
            Material::OrenNayar(p) => {
                n.put("albedo", p.albedo).put("sigma_deg", p.sigma_deg);
            }
        }
        if let Some(t) = self.textures(name, material.kind(), textures) {
            n.put("textures", t);
        }
        n
    }

    /// The `textures` block (`None` when there is nothing to say).
    fn textures(
        &mut self,
        name: &str,
        model: crate::brdf::ModelKind,
        t: &MaterialTextures,
    ) -> Option<Node> {
        let takes = slots_for_model(model);
        let mut block = Node::obj();
        let mut maps = 0;
        for slot in TextureSlot::ALL {
            let Some(tex) = t.get(slot) else { continue };
            if tex.embedded.is_some() {
                self.notes.push(format!(
                    "material \"{name}\": its {} map is an image embedded in a glTF file ({}), which a scene file cannot name; not written",
                    slot.name(),
                    tex.path.display()
                ));
                continue;
            }
            if !takes.contains(&slot) {
                self.notes.push(format!(
                    "material \"{name}\": a {} material takes no \"{}\" map; {} not written",
                    model.name(),
                    slot.name(),
                    tex.path.display()
                ));
                continue;
            }
            let packed = matches!(
                slot,
                TextureSlot::Metallic | TextureSlot::Roughness | TextureSlot::Occlusion
            ) && t.orm.is_some()
                && takes.contains(&TextureSlot::Orm);
            if packed {
                self.notes.push(format!(
                    "material \"{name}\": the \"orm\" map already gives {}; the separate map {} is not written",
                    slot.name(),
                    tex.path.display()
                ));
                continue;
            }
            block.put(slot.name(), self.texture(name, slot, tex));
            maps += 1;
        }
        let has_normal = block_has(&block, "normal");
        let has_occlusion = block_has(&block, "occlusion") || block_has(&block, "orm");
        if has_normal {
            block.put("normal_scale", t.normal_scale);
        } else if t.normal_scale != 1.0 {
            self.notes.push(format!(
                "material \"{name}\": normal_scale {} without a normal map is not written",
                t.normal_scale
            ));
        }
        if block_has(&block, "clearcoat_normal") {
            block.put("clearcoat_normal_scale", t.clearcoat_normal_scale);
        }
        if has_occlusion {
            block.put("occlusion_strength", t.occlusion_strength);
        } else if t.occlusion_strength != 1.0 {
            self.notes.push(format!(
                "material \"{name}\": occlusion_strength {} without an occlusion or orm map is not written",
                t.occlusion_strength
            ));
        }
        if maps > 0 || t.emissive_factor != Vec3::ZERO {
            block.put("emissive_factor", t.emissive_factor);
        }
        match &block {
            Node::Obj(fields) if fields.is_empty() => None,
            _ => Some(block),
        }
    }

    /// One map: its file name alone with the default sampler, else an object.
    fn texture(&mut self, name: &str, slot: TextureSlot, tex: &TextureRef) -> Node {
        let path = self.path(&tex.path);
        let channel = match tex.channel {
            Some(c) if !slot.is_single_channel() => {
                self.notes.push(format!(
                    "material \"{name}\": the {} map uses all its channels; its channel {c} is not written",
                    slot.name()
                ));
                None
            }
            c => c,
        };
        let s = &tex.sampler;
        if *s == SamplerDesc::default() && channel.is_none() {
            return Node::Str(path);
        }
        let mut n = Node::obj().with("path", path);
        if s.wrap_u == s.wrap_v {
            n.put("wrap", wrap(s.wrap_u));
        } else {
            n.put("wrap_u", wrap(s.wrap_u))
                .put("wrap_v", wrap(s.wrap_v));
        }
        if s.mag == s.min {
            n.put("filter", filter(s.min));
        } else {
            n.put("mag_filter", filter(s.mag))
                .put("min_filter", filter(s.min));
        }
        n.put("mipmaps", s.mipmaps).put("anisotropy", s.anisotropy);
        if let Some(c) = channel {
            n.put(
                "channel",
                ["r", "g", "b", "a"]
                    .get(usize::from(c))
                    .copied()
                    .unwrap_or("r"),
            );
        }
        n
    }

    /// The name an object refers to material `i` by: a scene material's own name; an MTL-made
    /// material's name when an OBJ entry written before recreates it; otherwise the name of a
    /// copy written as a scene material. `None` for an index out of range.
    fn material_ref(&mut self, i: usize) -> Option<String> {
        let m = self.scene.materials.get(i)?;
        if is_scene_material_name(&m.name) || self.created.contains(&i) {
            return Some(m.name.clone());
        }
        if let Some(name) = self.exported.get(&i) {
            return Some(name.clone());
        }
        let base = if m.name.trim().is_empty() {
            "material".to_string()
        } else {
            m.name.replace('/', "_")
        };
        let taken = |n: &str| {
            self.scene.materials.iter().any(|m| m.name == n)
                || self.exported.values().any(|e| e == n)
        };
        let mut name = base.clone();
        let mut k = 2;
        while taken(&name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        self.notes.push(format!(
            "material \"{}\" (made from an OBJ's MTL file) is used where loading the file cannot recreate it; written as the scene material \"{name}\"",
            m.name
        ));
        self.exported.insert(i, name.clone());
        self.export_order.push(i);
        Some(name)
    }

    // --- Objects ----------------------------------------------------------------------------

    fn objects(&mut self) -> Vec<Node> {
        let objects = &self.scene.objects;
        let mut out = Vec::new();
        let mut i = 0;
        while i < objects.len() {
            let end = match &objects[i].desc {
                MeshDesc::Obj { path } | MeshDesc::Gltf { path, .. } => self.obj_run_end(i, path),
                _ => i + 1,
            };
            if let Some(node) = self.object_entry(&objects[i..end]) {
                out.push(node);
            }
            i = end;
        }
        out
    }

    fn material_name(&self, o: &Object) -> &str {
        self.scene
            .materials
            .get(o.material)
            .map_or("", |m| m.name.as_str())
    }

    /// Whether `o`'s material was made from the MTL of the OBJ named `file_name`.
    fn uses_mtl(&self, o: &Object, file_name: &str) -> bool {
        self.material_name(o).starts_with(&format!("{file_name}/"))
    }

    /// The end of the run of objects starting at `start` that one OBJ entry made: consecutive
    /// objects of the same OBJ file, each with its own mesh (a second entry of the same file in
    /// the same material mode shares the first one's meshes) and the same material mode (MTL
    /// materials, or one given material). A part whose mode differs but whose name base,
    /// transform and shading match, and whose name is not yet in the run, is taken as an edited
    /// part of the same entry (a second entry of the file at the same place repeats the names).
    fn obj_run_end(&self, start: usize, path: &Path) -> usize {
        let objects = &self.scene.objects;
        let first = &objects[start];
        let file_name = obj_file_name(path);
        let mut mtl = self.uses_mtl(first, &file_name);
        let mut meshes = vec![Arc::as_ptr(&first.mesh)];
        let mut end = start + 1;
        while let Some(o) = objects.get(end) {
            let same_file = o.desc == first.desc;
            if !same_file || meshes.contains(&Arc::as_ptr(&o.mesh)) {
                break;
            }
            let o_mtl = self.uses_mtl(o, &file_name);
            if o_mtl != mtl {
                let looks_edited = name_base(&o.name) == name_base(&first.name)
                    && o.transform == first.transform
                    && o.shading == first.shading
                    && o.shadow == first.shadow
                    && !objects[start..end].iter().any(|p| p.name == o.name);
                if !looks_edited {
                    break;
                }
                mtl |= o_mtl;
            }
            meshes.push(Arc::as_ptr(&o.mesh));
            end += 1;
        }
        end
    }

    /// One entry of `objects`: a primitive (`run` has one object) or an OBJ file (`run` holds its
    /// parts). The name is always written (the decoder's default names depend on the entry's
    /// index, which edits may change).
    fn object_entry(&mut self, run: &[Object]) -> Option<Node> {
        let first = &run[0];
        let (name, mesh, material) = match &first.desc {
            MeshDesc::Obj { path } | MeshDesc::Gltf { path, .. } => {
                let file_name = obj_file_name(path);
                // A run with any MTL material takes its materials from the MTL file.
                let mtl = run.iter().any(|o| self.uses_mtl(o, &file_name));
                let name = self.obj_entry_name(run, path);
                let mut material = None;
                if mtl {
                    for o in run {
                        if self.uses_mtl(o, &file_name) {
                            self.created.insert(o.material);
                        } else {
                            self.notes.push(format!(
                                "object \"{}\": one part of an OBJ whose parts take their materials from its MTL file cannot have its own material (\"{}\"); it gets its MTL material back",
                                o.name,
                                self.material_name(o)
                            ));
                        }
                    }
                } else {
                    material = Some(self.material_ref(first.material)?);
                    for o in &run[1..] {
                        if o.material != first.material {
                            self.notes.push(format!(
                                "object \"{}\": the parts of one OBJ entry share one material; written with \"{}\" instead of \"{}\"",
                                o.name,
                                self.material_name(first),
                                self.material_name(o)
                            ));
                        }
                    }
                }
                for o in &run[1..] {
                    if o.transform != first.transform
                        || o.shading != first.shading
                        || o.shadow != first.shadow
                    {
                        self.notes.push(format!(
                            "object \"{}\": the parts of one OBJ entry share one transform, shading and shadow flags; written with those of \"{}\"",
                            o.name, first.name
                        ));
                    }
                }
                let mesh = match &first.desc {
                    MeshDesc::Gltf { scene, .. } => {
                        let mut m = Node::obj()
                            .with("type", "gltf")
                            .with("path", self.path(path));
                        if let Some(s) = scene {
                            m.put("scene", *s);
                        }
                        // Imported lights and cameras are in the scene's own lists, which are
                        // written; importing them again would double them.
                        m.with("lights", false).with("cameras", false)
                    }
                    _ => Node::obj()
                        .with("type", "obj")
                        .with("path", self.path(path)),
                };
                let name = match &first.desc {
                    // Parts are "<entry>/<node>/<mesh>": the entry is the name's first segment.
                    MeshDesc::Gltf { .. } => first
                        .name
                        .split_once('/')
                        .map_or(first.name.clone(), |(e, _)| e.to_string()),
                    _ => name,
                };
                (name, mesh, material)
            }
            desc => {
                let Some(material) = self.material_ref(first.material) else {
                    self.notes.push(format!(
                        "object \"{}\": material index {} does not exist; the object is not written",
                        first.name, first.material
                    ));
                    return None;
                };
                (
                    first.name.clone(),
                    primitive(desc, first.tessellation),
                    Some(material),
                )
            }
        };
        let mut n = Node::obj().with("name", name).with("mesh", mesh);
        if let Some(m) = material {
            n.put("material", m);
        }
        let t = &first.transform;
        n.put("position", t.position)
            .put("rotation_deg", t.rotation_deg);
        if t.scale.x == t.scale.y && t.scale.y == t.scale.z {
            n.put("scale", t.scale.x);
        } else {
            n.put("scale", t.scale);
        }
        n.put(
            "shading",
            match first.shading {
                Shading::Flat => "flat",
                Shading::Gouraud => "gouraud",
                Shading::Phong => "phong",
            },
        );
        // Only what differs from the defaults (true), so scenes without shadows read as before.
        if !first.shadow.cast {
            n.put("cast_shadow", false);
        }
        if !first.shadow.receive {
            n.put("receive_shadow", false);
        }
        Some(n)
    }

    /// The `name` of an OBJ entry from its parts' names: a single part carries the entry's name;
    /// several are called `<name>/<part>`.
    fn obj_entry_name(&mut self, run: &[Object], path: &Path) -> String {
        if run.len() == 1 {
            return run[0].name.clone();
        }
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| obj_file_name(path));
        if run.iter().all(|o| o.name.starts_with(&format!("{stem}/"))) {
            return stem;
        }
        // The longest common prefix that ends before a '/'.
        let mut prefix = run[0].name.as_str();
        for o in &run[1..] {
            let n = prefix
                .char_indices()
                .zip(o.name.chars())
                .take_while(|((_, a), b)| a == b)
                .last()
                .map_or(0, |((i, a), _)| i + a.len_utf8());
            prefix = &prefix[..n];
        }
        match prefix.rfind('/') {
            Some(i) if i > 0 => prefix[..i].to_string(),
            _ => {
                let base = name_base(&run[0].name).to_string();
                self.notes.push(format!(
                    "objects \"{}\" …: the parts of one OBJ entry are named \"<name>/<part>\"; their names do not share a \"<name>/\", written as \"{base}\"",
                    run[0].name
                ));
                base
            }
        }
    }

    // --- Environment ------------------------------------------------------------------------

    fn environment(&self, e: &Environment) -> Node {
        let mut n = Node::obj();
        match &e.source {
            EnvSource::Hdr(p) => {
                n.put("hdr", self.path(p));
            }
            EnvSource::Uniform(c) => {
                n.put("uniform", *c);
            }
            EnvSource::Sky {
                sun_direction,
                sun_intensity,
            } => {
                n.put("procedural", "sky")
                    .put("sun_direction", unit_preimage(*sun_direction))
                    .put("sun_intensity", *sun_intensity);
            }
            EnvSource::Studio => {
                n.put("procedural", "studio");
            }
        }
        n.put("intensity", e.intensity)
            .put("rotation_deg", e.rotation_deg)
            .put("specular_method", e.specular_method.name())
            .put("samples", e.samples)
            .put("diffuse_method", e.diffuse_method.name())
            .put("energy_compensation", e.energy_compensation)
            .put("mip_filtered_samples", e.mip_filtered_samples)
            .put("show_background", e.show_background);
        n
    }
}
#[cfg(test)]
mod tests;

/// The roughness and the D, G and F selectors of the models that have them (Cook-Torrance,
/// metallic-roughness), in the scene format's order.
fn put_terms(
    n: &mut Node,
    roughness: f32,
    (distribution, geometry, fresnel): (Distribution, Geometry, Fresnel),
) -> &mut Node {
    n.put("roughness", roughness)
        .put("distribution", select(DISTRIBUTIONS, distribution))
        .put("geometry", select(GEOMETRIES, geometry))
        .put("fresnel", select(FRESNELS, fresnel))
}

/// `output.golden`: the overridden checks, null for one turned off.
fn golden_tolerances(o: &crate::diff::ToleranceOverrides) -> Node {
    let opt = |v: Option<f32>| v.map_or(Node::Null, Node::from);
    let mut n = Node::obj();
    if let Some(v) = o.max_flip_mean {
        n.put("max_flip_mean", opt(v));
    }
    if let Some(v) = o.max_abs {
        n.put("max_abs", opt(v));
    }
    if let Some(v) = o.max_bad_pixels {
        n.put("max_bad_pixels", v.map_or(Node::Null, Node::Int));
    }
    if let Some(v) = o.bad_pixel_threshold {
        n.put("bad_pixel_threshold", v);
    }
    n
}
