//! glTF 2.0 files (`.gltf` with external or data-URI buffers, `.glb`) → meshes, materials,
//! cameras and lights in luz's terms. What is supported and how it maps is in `docs/gltf.md`.
//!
//! The `gltf` crate parses the JSON and the GLB container and checks every index; this module
//! reads buffers and accessors itself, with every byte range checked, so that no file makes it
//! panic. Node transforms are baked into the meshes (one mesh per node and primitive), so a part
//! needs no transform of its own: the scene object's transform goes on top. Each placed mesh
//! keeps its primitive's local form (built once per primitive, shared by the nodes that place
//! it: [`crate::scene::mesh::Placed`]) when several nodes name its mesh; automatic LOD keys its
//! cache and simplifies on that form.

mod accessor;
mod area;
mod ext;
mod material;
mod primitive;
mod transmission;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

pub use area::max_scale;
pub use material::GltfMaterial;
pub use primitive::UvChoice;

use super::{Camera, Falloff, Light, LightKind, Mesh, Projection};

/// Extensions luz reads; a file that requires any other one is refused.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "EXT_lights_area",
    "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_iridescence",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_dispersion",
    "KHR_materials_diffuse_transmission",
    "KHR_texture_transform",
    "KHR_mesh_quantization",
];

/// Narrowest camera `aspectRatio` accepted (1/16; the widest is 16): beyond, the image would be
/// one pixel or thousands of pixels wide.
const MIN_ASPECT: f32 = 1.0 / 16.0;

/// Why a glTF file could not be loaded: `<file>: <json path>: <reason>`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {path}: {reason}", file.display())]
pub struct GltfError {
    pub file: PathBuf,
    /// Where in the file: a JSON path such as `accessors[3].count`, or `(root)`.
    pub path: String,
    pub reason: String,
}

impl GltfError {
    fn at(file: &Path, path: impl Into<String>, reason: impl Into<String>) -> Self {
        GltfError {
            file: file.to_path_buf(),
            path: path.into(),
            reason: reason.into(),
        }
    }
}

/// A drawable piece: one primitive of one mesh instance, in the file's world coordinates.
#[derive(Debug, Clone)]
pub struct Part {
    /// `node name/mesh name` (or `#<index>` where a name is missing), with the primitive's index
    /// when the mesh has several.
    pub name: String,
    pub mesh: Mesh,
    /// Index into [`GltfFile::materials`].
    pub material: usize,
}

/// A camera of the file (perspective or orthographic), placed by its node.
#[derive(Debug, Clone)]
pub struct GltfCamera {
    pub name: String,
    /// `far` is the file's `zfar`, or 0 when the file has none (infinite): the caller picks one
    /// from the scene's bounds. `target` is one unit in front of the camera.
    pub camera: Camera,
    /// The file's `aspectRatio` (width / height), if any.
    pub aspect: Option<f32>,
}

/// Everything luz takes from one glTF file.
#[derive(Debug, Clone, Default)]
pub struct GltfFile {
    pub parts: Vec<Part>,
    /// The file's materials in order, then the glTF default material when a primitive has none.
    pub materials: Vec<GltfMaterial>,
    /// Perspective cameras in node order (depth first through the scene).
    pub cameras: Vec<GltfCamera>,
    /// KHR_lights_punctual lights in node order.
    pub lights: Vec<Light>,
    /// EXT_lights_area lights in node order.
    pub area_lights: Vec<super::AreaLight>,
    /// What the file has that luz does not use, one sentence each naming the file.
    pub warnings: Vec<String>,
}

impl GltfFile {
    /// Total triangles.
    pub fn triangle_count(&self) -> usize {
        self.parts.iter().map(|p| p.mesh.triangle_count()).sum()
    }
}

/// Whether `path` names a glTF file by its extension (`.gltf` or `.glb`).
pub fn is_gltf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// Loads scene `scene` of the glTF file at `path` (`None`: the file's default scene, else its
/// first).
pub fn load(path: &Path, scene: Option<usize>) -> Result<GltfFile, GltfError> {
    let bytes = crate::files::read_input(path)
        .map_err(|e| GltfError::at(path, "(root)", format!("cannot read the file: {e}")))?;
    load_bytes(&bytes, path, scene)
}

/// [`load`] on the file's bytes; `path` names it and is the base of relative URIs. The file may
/// expand into at most the input budget's triangles and instances
/// ([`crate::files::InputBudget`]): a small file whose thousands of nodes share one big mesh
/// must not make the loader build gigabytes.
pub fn load_bytes(bytes: &[u8], path: &Path, scene: Option<usize>) -> Result<GltfFile, GltfError> {
    let budget = crate::files::InputBudget::current();
    load_bytes_with(bytes, path, scene, budget.max_triangles)
}

/// [`load_bytes`] with another budget of triangles than the input budget's (the fuzz target's
/// is smaller).
pub fn load_bytes_with(
    bytes: &[u8],
    path: &Path,
    scene: Option<usize>,
    max_triangles: usize,
) -> Result<GltfFile, GltfError> {
    let root_err = |reason: String| GltfError::at(path, "(root)", reason);
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| match e {
        gltf::Error::Binary(b) => {
            root_err(format!("not a valid binary glTF (.glb): {}", glb_error(&b)))
        }
        gltf::Error::Deserialize(e) => root_err(format!("not valid glTF JSON: {e}")),
        other => root_err(other.to_string()),
    })?;
    let gltf::Gltf { document, blob } = raw;
    let json = document.into_json();
    check_version(&json.asset, path)?;
    for (i, ext) in json.extensions_required.iter().enumerate() {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            return Err(GltfError::at(
                path,
                format!("extensionsRequired[{i}]"),
                format!(
                    "the file requires the extension {ext}, which luz does not support (supported: {})",
                    SUPPORTED_EXTENSIONS.join(", ")
                ),
            ));
        }
    }
    // The crate's validation indexes `accessors` with POSITION's index unchecked: check first.
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, a) in &prim.attributes {
                if a.value() >= json.accessors.len() {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => s.to_string(),
                        gltf::json::validation::Checked::Invalid => "?".into(),
                    };
                    return Err(GltfError::at(
                        path,
                        format!("meshes[{m}].primitives[{p}].attributes.{name}"),
                        format!(
                            "accessor {} does not exist (the file has {})",
                            a.value(),
                            json.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    // Fields the crate's document API unwraps without its validation having checked them.
    for (i, img) in json.images.iter().enumerate() {
        let problem = match (&img.buffer_view, &img.uri, &img.mime_type) {
            (None, None, _) => Some("an image needs a uri or a bufferView"),
            (Some(_), _, None) => Some("an image in a bufferView needs a mimeType"),
            _ => None,
        };
        if let Some(p) = problem {
            return Err(GltfError::at(path, format!("images[{i}]"), p));
        }
    }
    for (i, cam) in json.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        use gltf::json::validation::Checked;
        let missing = match cam.type_ {
            Checked::Valid(Type::Perspective) if cam.perspective.is_none() => Some("perspective"),
            Checked::Valid(Type::Orthographic) if cam.orthographic.is_none() => {
                Some("orthographic")
            }
            _ => None,
        };
        if let Some(field) = missing {
            return Err(GltfError::at(
                path,
                format!("cameras[{i}].{field}"),
                format!("missing, but the camera's type is \"{field}\""),
            ));
        }
    }
    let mut errors = Vec::new();
    {
        use gltf::json::validation::Validate;
        json.validate(&json, gltf::json::Path::new, &mut |p, e| {
            let p = p().to_string();
            // Required extensions were checked above, against luz's list; POSITION's min and
            // max are required by the spec but unused here (some exporters leave them out).
            let unused_bounds = matches!(e, gltf::json::validation::Error::Missing)
                && (p.ends_with("[\"POSITION\"].min") || p.ends_with("[\"POSITION\"].max"));
            if !matches!(e, gltf::json::validation::Error::Unsupported) && !unused_bounds {
                errors.push((p, e.to_string()));
            }
        });
    }
    if let Some((p, e)) = errors.into_iter().next() {
        return Err(GltfError::at(path, p, e.to_lowercase()));
    }
    let doc = gltf::Document::from_json_without_validation(json);
    let buffers = load_buffers(&doc, path, blob)?;
    let mut b = Builder::new(&doc, path, &buffers)?;
    b.max_triangles = max_triangles;
    b.run(scene)
}

fn glb_error(e: &gltf::binary::Error) -> String {
    use gltf::binary::Error as B;
    match e {
        B::Io(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => "the file is truncated".into(),
        B::Length {
            length,
            length_read,
        } => format!("the header declares {length} bytes, the file has {length_read} (truncated?)"),
        B::ChunkLength {
            ty,
            length,
            length_read,
        } => format!(
            "the {ty:?} chunk declares {length} bytes, only {length_read} are there (truncated?)"
        ),
        other => other.to_string(),
    }
}

fn check_version(asset: &gltf::json::Asset, path: &Path) -> Result<(), GltfError> {
    let major = |v: &str| {
        v.split('.')
            .next()
            .and_then(|m| m.trim().parse::<u32>().ok())
    };
    let want = asset.min_version.as_deref().unwrap_or(&asset.version);
    if major(&asset.version) != Some(2) || major(want).is_none_or(|m| m > 2) {
        return Err(GltfError::at(
            path,
            "asset.version",
            format!(
                "glTF version \"{}\" is not supported; luz reads glTF 2.0",
                asset.version
            ),
        ));
    }
    Ok(())
}

/// Decodes a `data:` URI (base64 only).
fn data_uri(uri: &str) -> Result<Vec<u8>, String> {
    use base64::Engine;
    let (head, data) = uri
        .split_once(',')
        .ok_or("a data URI without a comma before its data")?;
    if !head.ends_with(";base64") {
        return Err("a data URI that is not base64-encoded".into());
    }
    base64::engine::general_purpose::STANDARD
        .decode(data.trim())
        .map_err(|e| format!("invalid base64 data: {e}"))
}

/// A relative URI's `%xx` escapes decoded (glTF URIs are RFC 3986).
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    let hex = |c: u8| (c as char).to_digit(16);
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            if let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn load_buffers(
    doc: &gltf::Document,
    path: &Path,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, GltfError> {
    let base = path.parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for b in doc.buffers() {
        let i = b.index();
        let data = match b.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                GltfError::at(
                    path,
                    format!("buffers[{i}]"),
                    "refers to the binary chunk of a .glb, which this file does not have",
                )
            })?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                data_uri(uri).map_err(|e| GltfError::at(path, format!("buffers[{i}].uri"), e))?
            }
            gltf::buffer::Source::Uri(uri) => {
                let budget = crate::files::InputBudget::current();
                if b.length() as u64 > budget.max_file_bytes {
                    return Err(GltfError::at(
                        path,
                        format!("buffers[{i}].byteLength"),
                        format!(
                            "declares {}, more than the input budget's largest file ({}; raise \
                             it with --max-file-mb)",
                            crate::files::human_bytes(b.length() as u64),
                            crate::files::human_bytes(budget.max_file_bytes)
                        ),
                    ));
                }
                let file = crate::files::resolve_inside(
                    base,
                    &percent_decode(uri),
                    budget.allow_outside_uris,
                )
                .map_err(|e| GltfError::at(path, format!("buffers[{i}].uri"), e))?;
                crate::files::read_input(&file).map_err(|e| {
                    GltfError::at(
                        path,
                        format!("buffers[{i}].uri"),
                        format!("cannot read the buffer file {}: {e}", file.display()),
                    )
                })?
            }
        };
        if data.len() < b.length() {
            return Err(GltfError::at(
                path,
                format!("buffers[{i}].byteLength"),
                format!(
                    "declares {} bytes, but the data has only {}",
                    b.length(),
                    data.len()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// Walks the node hierarchy of one scene.
struct Builder<'a> {
    doc: &'a gltf::Document,
    path: &'a Path,
    file_name: String,
    buffers: &'a [Vec<u8>],
    images: material::Images,
    out: GltfFile,
    /// glTF material index → index in `out.materials` (the default material at the end).
    default_material: Option<usize>,
    warned: HashMap<&'static str, ()>,
    /// Triangles of the parts so far, and the budget.
    triangles: usize,
    max_triangles: usize,
    /// Most parts (mesh instances, one per node and primitive).
    max_instances: usize,
    /// A node with a skin, a primitive with morph targets (one warning at the end).
    skinned: bool,
    morphed: bool,
    /// Each primitive before any node transform, by (mesh, primitive, mirrored): built once and
    /// shared by every node that places it ([`crate::scene::mesh::Placed`]).
    local: HashMap<(usize, usize, bool), Option<std::sync::Arc<Mesh>>>,
    /// Per mesh, how many nodes name it: a mesh named by one node keeps no local form (nothing
    /// to share, and no second copy of it in memory).
    uses: Vec<u32>,
}

impl<'a> Builder<'a> {
    fn new(
        doc: &'a gltf::Document,
        path: &'a Path,
        buffers: &'a [Vec<u8>],
    ) -> Result<Self, GltfError> {
        let images = material::Images::resolve(doc, path, buffers)?;
        let file_name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| path.display().to_string());
        Ok(Builder {
            doc,
            path,
            file_name,
            buffers,
            images,
            out: GltfFile::default(),
            default_material: None,
            warned: HashMap::new(),
            triangles: 0,
            max_triangles: crate::files::InputBudget::current().max_triangles,
            max_instances: crate::files::InputBudget::current().max_instances,
            skinned: false,
            morphed: false,
            local: HashMap::new(),
            uses: {
                let mut uses = vec![0u32; doc.meshes().len()];
                for m in doc.nodes().filter_map(|n| n.mesh()) {
                    uses[m.index()] = uses[m.index()].saturating_add(1);
                }
                uses
            },
        })
    }

    fn warn_once(&mut self, key: &'static str, text: String) {
        if self.warned.insert(key, ()).is_none() {
            self.out.warnings.push(text);
        }
    }

    fn run(mut self, scene: Option<usize>) -> Result<GltfFile, GltfError> {
        let f = self.file_name.clone();
        for m in self.doc.materials() {
            let mut gm = material::material(&m, &self.images, &f, &mut self.out.warnings);
            let textures = material::TextureSource {
                doc: self.doc,
                images: &self.images,
            };
            // The material extensions luz reads onto metal_rough.
            for read in [
                material::ior,
                material::clearcoat,
                material::sheen,
                material::anisotropy,
                material::iridescence,
                material::specular,
                transmission::transmission,
            ] {
                read(
                    &m,
                    &mut gm,
                    &textures,
                    (self.path, &f),
                    &mut self.out.warnings,
                )?;
            }
            self.out.materials.push(gm);
        }
        let roots: Vec<usize> = match scene {
            Some(s) => {
                let sc = self.doc.scenes().nth(s).ok_or_else(|| {
                    GltfError::at(
                        self.path,
                        "scenes",
                        format!(
                            "scene {s} asked for, but the file has {}",
                            self.doc.scenes().len()
                        ),
                    )
                })?;
                sc.nodes().map(|n| n.index()).collect()
            }
            None => match self
                .doc
                .default_scene()
                .or_else(|| self.doc.scenes().next())
            {
                Some(sc) => sc.nodes().map(|n| n.index()).collect(),
                // No scene: every node that is nobody's child.
                None => {
                    let mut child = vec![false; self.doc.nodes().len()];
                    for n in self.doc.nodes() {
                        for c in n.children() {
                            child[c.index()] = true;
                        }
                    }
                    let roots: Vec<usize> = (0..child.len()).filter(|&i| !child[i]).collect();
                    if roots.is_empty() && !child.is_empty() {
                        return Err(GltfError::at(
                            self.path,
                            "nodes",
                            "the file has no scene and every node is the child of another (a \
                             cycle): there is no root node to draw",
                        ));
                    }
                    roots
                }
            },
        };
        let nodes: Vec<gltf::Node> = self.doc.nodes().collect();
        let mut visited = vec![false; nodes.len()];
        let mut stack: Vec<(usize, Mat4)> =
            roots.iter().rev().map(|&r| (r, Mat4::IDENTITY)).collect();
        while let Some((i, parent)) = stack.pop() {
            if visited[i] {
                return Err(GltfError::at(
                    self.path,
                    format!("nodes[{i}]"),
                    "the node is reached twice (a cycle in children, or a node with two parents)",
                ));
            }
            visited[i] = true;
            let node = &nodes[i];
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            if !local.is_finite() {
                return Err(GltfError::at(
                    self.path,
                    format!("nodes[{i}]"),
                    "its transform (matrix or translation/rotation/scale) is not finite",
                ));
            }
            let world = parent * local;
            self.node(node, world)?;
            for c in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((c.index(), world));
            }
        }
        // Skins, morph targets and animations: one warning for the file, naming what it has.
        let mut unused = Vec::new();
        if self.skinned {
            unused.push("skins (meshes drawn in their bind pose, placed by their node)");
        }
        if self.morphed {
            unused.push("morph targets (meshes keep their base shape)");
        }
        if self.doc.animations().len() > 0 {
            unused.push("animations (the node transforms' static pose)");
        }
        if !unused.is_empty() {
            self.out.warnings.push(format!(
                "{f}: luz draws the static pose; not applied: {}",
                unused.join(", ")
            ));
        }
        Ok(self.out)
    }

    fn node(&mut self, node: &gltf::Node, world: Mat4) -> Result<(), GltfError> {
        let f = self.file_name.clone();
        let i = node.index();
        let node_name = node
            .name()
            .map(str::to_string)
            .unwrap_or_else(|| format!("#{i}"));
        self.skinned |= node.skin().is_some();
        if let Some(cam) = node.camera() {
            self.camera(&cam, world, &node_name)?;
        }
        if let Some(light) = node.light() {
            self.light(&light, world)?;
        }
        self.area_light(node, world)?;
        let Some(mesh) = node.mesh() else {
            return Ok(());
        };
        let mesh_name = mesh
            .name()
            .map(str::to_string)
            .unwrap_or_else(|| format!("#{}", mesh.index()));
        let count = mesh.primitives().len();
        for p in mesh.primitives() {
            self.morphed |= p.morph_targets().len() > 0;
            let material = match p.material().index() {
                Some(m) => m,
                None => self.default_material(),
            };
            let uv = self
                .out
                .materials
                .get(material)
                .map(|m| m.uv)
                .unwrap_or_default();
            let where_ = format!("meshes[{}].primitives[{}]", mesh.index(), p.index());
            // At most this many triangles (a strip or fan of n indices has n − 2 < n).
            let estimate = p
                .indices()
                .or_else(|| p.get(&gltf::Semantic::Positions))
                .map_or(0, |a| a.count());
            self.triangles = self.triangles.saturating_add(estimate / 3 + estimate % 3);
            if self.triangles > self.max_triangles {
                return Err(GltfError::at(
                    self.path,
                    format!("nodes[{i}]"),
                    format!(
                        "the file expands into more than {} triangles (its meshes are baked once \
                         per node that uses them; raise the input budget with --max-triangles)",
                        self.max_triangles
                    ),
                ));
            }
            if self.out.parts.len() >= self.max_instances {
                return Err(GltfError::at(
                    self.path,
                    format!("nodes[{i}]"),
                    format!(
                        "the file places more than {} mesh instances (one per node and \
                         primitive; raise the input budget with --max-instances)",
                        self.max_instances
                    ),
                ));
            }
            let built = primitive::build(&p, self.buffers, world, uv, &where_).map_err(|e| {
                // `e` starts with its own JSON path.
                match e.split_once(": ") {
                    Some((p, r)) => GltfError::at(self.path, p, r),
                    None => GltfError::at(self.path, where_.clone(), e),
                }
            })?;
            match built {
                primitive::Built::Mesh(mut m) => {
                    if m.indices.is_empty() {
                        continue;
                    }
                    m.placed = self.placed(&p, mesh.index(), world, uv, &where_, &m);
                    let name = if count == 1 {
                        format!("{node_name}/{mesh_name}")
                    } else {
                        format!("{node_name}/{mesh_name}/{}", p.index())
                    };
                    self.out.parts.push(Part {
                        name,
                        mesh: m,
                        material,
                    });
                }
                primitive::Built::NotTriangles(mode) => self.warn_once(
                    "lines",
                    format!(
                        "{f}: {where_}: {mode} primitives are not drawn (luz draws triangles only)"
                    ),
                ),
                primitive::Built::NoPositions => self.warn_once(
                    "nopos",
                    format!("{f}: {where_}: a primitive without POSITION is not drawn"),
                ),
            }
        }
        Ok(())
    }

    /// The local form of primitive `p` (of mesh `mesh`) placed by `world` as `placed`, for
    /// automatic LOD's cache key: None when `world` is the identity (`placed` is its own local
    /// form), when only one node names the mesh (its placed form is keyed as it is, as many
    /// files either way) or when the local form does not match `placed` vertex for vertex.
    fn placed(
        &mut self,
        p: &gltf::Primitive,
        mesh: usize,
        world: Mat4,
        uv: primitive::UvChoice,
        where_: &str,
        placed: &Mesh,
    ) -> Option<std::sync::Arc<crate::scene::mesh::Placed>> {
        if world == Mat4::IDENTITY || self.uses.get(mesh).is_none_or(|&n| n < 2) {
            return None;
        }
        let mirrored = glam::Mat3::from_mat4(world).determinant() < 0.0;
        let buffers = self.buffers;
        let local = self
            .local
            .entry((mesh, p.index(), mirrored))
            .or_insert_with(|| {
                let Ok(primitive::Built::Mesh(mut m)) =
                    primitive::build(p, buffers, Mat4::IDENTITY, uv, where_)
                else {
                    return None;
                };
                if mirrored {
                    m.indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
                }
                Some(std::sync::Arc::new(m))
            })
            .clone()?;
        let same = local.positions.len() == placed.positions.len()
            && local.normals.len() == placed.normals.len()
            && local.uvs.len() == placed.uvs.len()
            && local.indices == placed.indices;
        same.then(|| {
            std::sync::Arc::new(crate::scene::mesh::Placed {
                local,
                transform: world,
            })
        })
    }

    fn default_material(&mut self) -> usize {
        *self.default_material.get_or_insert_with(|| {
            self.out.materials.push(material::default_material());
            self.out.materials.len() - 1
        })
    }

    fn camera(
        &mut self,
        cam: &gltf::Camera,
        world: Mat4,
        node_name: &str,
    ) -> Result<(), GltfError> {
        let c = cam.index();
        let (projection, fov_y_deg, near, far, aspect) = match cam.projection() {
            gltf::camera::Projection::Perspective(p) => self.perspective(c, &p)?,
            gltf::camera::Projection::Orthographic(o) => self.orthographic(c, &o)?,
        };
        let position = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::NEG_Z).try_normalize();
        let up = world.transform_vector3(Vec3::Y).try_normalize();
        let (Some(forward), Some(up)) = (forward, up) else {
            return Err(GltfError::at(
                self.path,
                "nodes",
                format!("the node of cameras[{c}] (\"{node_name}\") has a degenerate transform"),
            ));
        };
        // Orthogonalise up against the view direction (a sheared node transform).
        let up = (up - forward * up.dot(forward))
            .try_normalize()
            .unwrap_or(Vec3::Y);
        self.out.cameras.push(GltfCamera {
            name: cam
                .name()
                .map(str::to_string)
                .unwrap_or_else(|| node_name.to_string()),
            camera: Camera {
                position,
                target: position + forward,
                up,
                fov_y_deg,
                near,
                far,
                projection,
            },
            aspect,
        });
        Ok(())
    }

    /// An error at `cameras[c].<kind>.<field>`.
    fn camera_error(&self, c: usize, kind: &str) -> impl Fn(&str, String) -> GltfError + '_ {
        let at = format!("cameras[{c}].{kind}");
        move |field, reason| GltfError::at(self.path, format!("{at}.{field}"), reason)
    }

    /// A perspective camera's projection, vertical field of view (degrees), near, far (0: none)
    /// and aspect ratio, checked.
    fn perspective(
        &self,
        c: usize,
        p: &gltf::camera::Perspective,
    ) -> Result<(Projection, f32, f32, f32, Option<f32>), GltfError> {
        let err = self.camera_error(c, "perspective");
        let yfov = p.yfov();
        if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
            return Err(err(
                "yfov",
                format!("must be in (0, π) radians, got {yfov}"),
            ));
        }
        let near = p.znear();
        if !(near > 0.0 && near.is_finite()) {
            return Err(err("znear", format!("must be positive, got {near}")));
        }
        let far = match p.zfar() {
            None => 0.0,
            Some(f) if f > near && f.is_finite() => f,
            Some(f) => {
                return Err(err(
                    "zfar",
                    format!("must be greater than znear ({near}), got {f}"),
                ))
            }
        };
        let aspect = match p.aspect_ratio() {
            None => None,
            Some(a) if (MIN_ASPECT..=1.0 / MIN_ASPECT).contains(&a) => Some(a),
            Some(a) => {
                return Err(err(
                    "aspectRatio",
                    format!(
                        "must be between 1/16 and 16 (the image is its height × aspectRatio \
                         wide), got {a}"
                    ),
                ))
            }
        };
        Ok((
            Projection::Perspective,
            yfov.to_degrees(),
            near,
            far,
            aspect,
        ))
    }

    /// An orthographic camera: half height `ymag`, aspect `xmag / ymag`, near `znear` (0 becomes
    /// zfar · 1e-6: luz's near plane is positive), far `zfar`.
    fn orthographic(
        &self,
        c: usize,
        o: &gltf::camera::Orthographic,
    ) -> Result<(Projection, f32, f32, f32, Option<f32>), GltfError> {
        let err = self.camera_error(c, "orthographic");
        let (xmag, ymag) = (o.xmag(), o.ymag());
        for (field, v) in [("xmag", xmag), ("ymag", ymag)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(err(field, format!("must be positive, got {v}")));
            }
        }
        let near = o.znear();
        if !(near >= 0.0 && near.is_finite()) {
            return Err(err("znear", format!("must be ≥ 0, got {near}")));
        }
        let far = o.zfar();
        if !(far > near && far.is_finite()) {
            return Err(err(
                "zfar",
                format!("must be greater than znear ({near}), got {far}"),
            ));
        }
        let near = if near > 0.0 { near } else { far * 1e-6 };
        let projection = Projection::Orthographic { half_height: ymag };
        Ok((projection, 45.0, near, far, Some(xmag / ymag)))
    }

    fn light(
        &mut self,
        l: &gltf::khr_lights_punctual::Light,
        world: Mat4,
    ) -> Result<(), GltfError> {
        use gltf::khr_lights_punctual::Kind;
        let li = l.index();
        let at = |field: &str, reason: String| {
            GltfError::at(
                self.path,
                format!("extensions.KHR_lights_punctual.lights[{li}].{field}"),
                reason,
            )
        };
        let color = Vec3::from_array(l.color());
        if !color.is_finite() || color.min_element() < 0.0 {
            return Err(at(
                "color",
                format!("must be finite and non-negative, got {color}"),
            ));
        }
        let intensity = l.intensity();
        if !(intensity.is_finite() && intensity >= 0.0) {
            return Err(at(
                "intensity",
                format!("must be finite and non-negative, got {intensity}"),
            ));
        }
        let range = match l.range() {
            None => None,
            Some(r) if r > 0.0 && r.is_finite() => Some(r),
            Some(r) => return Err(at("range", format!("must be positive, got {r}"))),
        };
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world
            .transform_vector3(Vec3::NEG_Z)
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z);
        let mut hard_edge = None;
        let (kind, umbra_deg, inner_deg) = match l.kind() {
            Kind::Directional => (LightKind::Directional, 180.0, None),
            Kind::Point => (LightKind::Point, 180.0, None),
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let outer = outer_cone_angle.to_degrees();
                if !(outer > 0.0 && outer <= 90.0) {
                    return Err(at(
                        "spot.outerConeAngle",
                        format!("must be in (0, π/2], got {outer_cone_angle}"),
                    ));
                }
                let inner = inner_cone_angle.to_degrees();
                if !(inner >= 0.0 && inner.is_finite()) {
                    return Err(at(
                        "spot.innerConeAngle",
                        format!("must be in [0, outerConeAngle), got {inner_cone_angle}"),
                    ));
                }
                if inner >= outer {
                    hard_edge = Some(format!(
                        "{}: extensions.KHR_lights_punctual.lights[{li}].spot.innerConeAngle \
                         ({inner_cone_angle}) is not below outerConeAngle ({outer_cone_angle}); \
                         the spot is drawn with a hard edge at outerConeAngle",
                        self.file_name
                    ));
                }
                (LightKind::Spot, outer, (inner < outer).then_some(inner))
            }
        };
        if let Some(w) = hard_edge {
            self.out.warnings.push(w);
        }
        self.out.lights.push(Light {
            kind,
            direction: if kind == LightKind::Point {
                Vec3::NEG_Y
            } else {
                direction
            },
            position,
            color,
            intensity,
            falloff: if kind == LightKind::Directional {
                Falloff::None
            } else {
                Falloff::InverseSquare
            },
            umbra_deg,
            inner_deg,
            exponent: 0.0,
            range: if kind == LightKind::Directional {
                None
            } else {
                range
            },
            shadow: None,
            radius: 0.0,
            angular_radius_deg: 0.0,
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris() {
        assert_eq!(percent_decode("a%20b.bin"), "a b.bin");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz"), "%zz");
        assert_eq!(
            data_uri("data:application/octet-stream;base64,AAEC").unwrap(),
            vec![0, 1, 2]
        );
        assert!(data_uri("data:text/plain,abc").is_err());
    }
}
