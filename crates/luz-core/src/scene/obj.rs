//! Wavefront OBJ (+ MTL) loading through `tobj`, guarded by a line-by-line check first.
//!
//! `tobj` reports no line numbers and panics or overflows on some malformed input (`Kd 0.5` in
//! an MTL, a `vt` index of 0, …). So every OBJ and MTL is first checked here line by line; what
//! passes cannot trip `tobj`, and every problem is reported with its file and line. As a last
//! line of defence the `tobj` call runs under `catch_unwind`.

use std::cell::RefCell;
use std::io::Cursor;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use super::mesh::Mesh;

/// A problem with an OBJ or MTL file; `line` is 1-based.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjError {
    pub file: PathBuf,
    pub line: Option<usize>,
    pub reason: String,
}

impl std::fmt::Display for ObjError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{l}: {}", self.file.display(), self.reason),
            None => write!(f, "{}: {}", self.file.display(), self.reason),
        }
    }
}

impl std::error::Error for ObjError {}

/// A material from an MTL file: the fields the classic model uses, the PBR extension's scalars
/// and the texture maps.
#[derive(Debug, Clone, PartialEq)]
pub struct MtlMaterial {
    pub name: String,
    pub ambient: Option<[f32; 3]>,
    pub diffuse: Option<[f32; 3]>,
    pub specular: Option<[f32; 3]>,
    pub shininess: Option<f32>,
    /// `Ke`.
    pub emissive: Option<[f32; 3]>,
    /// `Pr` (PBR extension), in [0, 1].
    pub roughness: Option<f32>,
    /// `Pm` (PBR extension), in [0, 1].
    pub metallic: Option<f32>,
    pub maps: MtlMaps,
}

/// The texture maps of an MTL material that luz uses (the last line of each kind wins).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MtlMaps {
    /// `map_Kd`.
    pub diffuse: Option<MtlMap>,
    /// `map_Ks`.
    pub specular: Option<MtlMap>,
    /// `map_Bump`, `map_bump`, `bump`, `norm`, `map_Kn`, `map_norm`: read as a tangent-space
    /// normal map (what Blender's exporter writes), not a height map.
    pub normal: Option<MtlMap>,
    /// `map_Pr`.
    pub roughness: Option<MtlMap>,
    /// `map_Pm`.
    pub metallic: Option<MtlMap>,
    /// `map_Ke`.
    pub emissive: Option<MtlMap>,
}

impl MtlMaps {
    /// Whether a map of the PBR extension (`map_Pr`, `map_Pm`) is present.
    pub fn has_pbr(&self) -> bool {
        self.roughness.is_some() || self.metallic.is_some()
    }
}

/// One texture-map line of an MTL file, with the options luz honours.
#[derive(Debug, Clone, PartialEq)]
pub struct MtlMap {
    /// The file, resolved against the MTL file's folder (backslashes read as `/`); checked to
    /// exist and to be a `.png`, `.exr` or `.hdr`.
    pub path: PathBuf,
    /// The MTL file and the 1-based line of the map.
    pub mtl: PathBuf,
    pub line: usize,
    /// `-clamp on`: clamp texture coordinates instead of repeating.
    pub clamp: bool,
    /// `-bm m`: the bump multiplier (the normal map's scale).
    pub bump_multiplier: Option<f32>,
    /// `-imfchan r|g|b|m`: the channel of a single-value map (0 = R … 3 = A).
    pub channel: Option<u8>,
}

/// One `tobj` model: a group/object of the file with one material.
#[derive(Debug, Clone)]
pub struct ObjPart {
    /// The `o`/`g` name (`unnamed_object` when the file has none).
    pub name: String,
    pub mesh: Mesh,
    /// Index into [`ObjFile::materials`].
    pub material: Option<usize>,
}

/// A loaded OBJ file.
#[derive(Debug, Clone)]
pub struct ObjFile {
    pub parts: Vec<ObjPart>,
    pub materials: Vec<MtlMaterial>,
    /// What the MTL files hold that luz ignores (`map_d`, UV transform options, …), each naming
    /// the MTL file and line.
    pub warnings: Vec<String>,
}

/// Loads an OBJ file: triangulated (fans for quads and n-gons), one index per vertex, normals
/// computed where the file has none (angle-weighted, shared across equal positions), UVs kept
/// when every vertex has one (v flipped so that v = 0 is the top of an image). With
/// `with_materials` the MTL libraries named by `mtllib` are loaded (relative to the OBJ) and must
/// exist; without it they are not read at all.
pub fn load_obj(path: &Path, with_materials: bool) -> Result<ObjFile, ObjError> {
    let bytes = crate::files::read_input(path).map_err(|e| ObjError {
        file: path.to_path_buf(),
        line: None,
        reason: format!("cannot read: {e}"),
    })?;
    load_obj_bytes(&bytes, path, with_materials)
}

/// [`load_obj`] on the file's bytes already in memory; `path` names the file in errors and is
/// the base for `mtllib` paths.
pub fn load_obj_bytes(
    bytes: &[u8],
    path: &Path,
    with_materials: bool,
) -> Result<ObjFile, ObjError> {
    let err = |line: Option<usize>, reason: String| ObjError {
        file: path.to_path_buf(),
        line,
        reason,
    };
    let text = utf8(bytes).map_err(|(line, reason)| err(Some(line), reason))?;
    let mtllibs = check_obj(text).map_err(|(line, reason)| err(Some(line), reason))?;

    let dir = path.parent().unwrap_or(Path::new(""));
    // MTL problems found inside the loader callback (which can only return tobj's error codes).
    let mtl_error: RefCell<Option<ObjError>> = RefCell::new(None);
    // What luz reads from each MTL beyond tobj: maps with their lines, Pr/Pm, warnings. One entry
    // per `newmtl`, in the order tobj appends its materials.
    let extras: RefCell<Vec<MtlExtra>> = RefCell::new(Vec::new());
    let warnings: RefCell<Vec<String>> = RefCell::new(Vec::new());
    let loader = |mtl: &Path| -> tobj::MTLLoadResult {
        if !with_materials || mtl_error.borrow().is_some() {
            return Ok((Vec::new(), Default::default()));
        }
        let full = dir.join(mtl);
        let line = mtllibs
            .iter()
            .find(|(_, name)| Path::new(name) == mtl)
            .map(|(l, _)| *l);
        let result = crate::files::read_input(&full)
            .map_err(|e| ObjError {
                file: full.clone(),
                line: None,
                reason: format!(
                    "cannot read the material library named by {}{}: {e}",
                    path.display(),
                    line.map(|l| format!(":{l}")).unwrap_or_default()
                ),
            })
            .and_then(|bytes| {
                let text = utf8(&bytes).map_err(|(l, r)| ObjError {
                    file: full.clone(),
                    line: Some(l),
                    reason: r,
                })?;
                check_mtl(text).map_err(|(l, r)| ObjError {
                    file: full.clone(),
                    line: Some(l),
                    reason: r,
                })?;
                let (more, notes) = mtl_extras(text, &full).map_err(|(l, r)| ObjError {
                    file: full.clone(),
                    line: Some(l),
                    reason: r,
                })?;
                extras.borrow_mut().extend(more);
                warnings.borrow_mut().extend(notes);
                tobj::load_mtl_buf(&mut Cursor::new(text.as_bytes())).map_err(|e| ObjError {
                    file: full.clone(),
                    line: None,
                    reason: e.to_string(),
                })
            });
        result.map_err(|e| {
            *mtl_error.borrow_mut() = Some(e);
            tobj::LoadError::MaterialParseError
        })
    };
    #[allow(clippy::needless_update)] // more fields exist when tobj features are enabled
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let loaded = catch_unwind(AssertUnwindSafe(|| {
        tobj::load_obj_buf(&mut Cursor::new(text.as_bytes()), &options, loader)
    }))
    .map_err(|_| err(None, "the OBJ reader (tobj) panicked on this file".into()))?;
    if let Some(e) = mtl_error.into_inner() {
        return Err(e);
    }
    let (models, materials) = loaded.map_err(|e| err(None, e.to_string()))?;
    let materials = if with_materials {
        materials.map_err(|e| err(None, format!("material library: {e}")))?
    } else {
        Vec::new()
    };

    let mut parts = Vec::new();
    for model in models {
        let m = model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let positions: Vec<Vec3> = m
            .positions
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect();
        let n = positions.len();
        // tobj numbers vertices with `as u32`: beyond 2^32 of them its indices have wrapped.
        if n as u64 > 1 << 32 {
            return Err(err(
                None,
                format!("{n} vertices: more than 32-bit indices can address"),
            ));
        }
        let mut mesh = Mesh {
            positions,
            normals: Vec::new(),
            uvs: Vec::new(),
            indices: m.indices,
            ..Mesh::default()
        };
        if let Some(i) = mesh.indices.iter().find(|&&i| i as usize >= n) {
            return Err(err(None, format!("vertex index {i} out of range")));
        }
        if let Some(p) = mesh.positions.iter().find(|p| !p.is_finite()) {
            return Err(err(None, format!("vertex position {p} is not finite")));
        }
        if m.normals.len() == 3 * n {
            mesh.normals = m
                .normals
                .chunks_exact(3)
                .map(|v| Vec3::new(v[0], v[1], v[2]).normalize_or_zero())
                .collect();
        }
        if mesh.normals.len() != n || mesh.normals.contains(&Vec3::ZERO) {
            mesh.compute_smooth_normals();
        }
        if m.texcoords.len() == 2 * n {
            mesh.uvs = m
                .texcoords
                .chunks_exact(2)
                .map(|t| Vec2::new(t[0], 1.0 - t[1]))
                .collect();
        }
        mesh.validate().map_err(|e| err(None, e))?;
        parts.push(ObjPart {
            name: model.name,
            mesh,
            material: m.material_id.filter(|&i| i < materials.len()),
        });
    }
    if parts.is_empty() {
        return Err(err(None, "no faces (the file has no triangles)".into()));
    }
    let extras = extras.into_inner();
    if extras.len() != materials.len()
        || extras.iter().zip(&materials).any(|(e, m)| e.name != m.name)
    {
        return Err(err(
            None,
            "the material libraries' materials could not be matched with their texture maps".into(),
        ));
    }
    let materials = materials
        .into_iter()
        .zip(extras)
        .map(|(m, e)| MtlMaterial {
            name: m.name,
            ambient: m.ambient,
            diffuse: m.diffuse,
            specular: m.specular,
            shininess: m.shininess,
            emissive: m.emissive,
            roughness: e.roughness,
            metallic: e.metallic,
            maps: e.maps,
        })
        .collect();
    Ok(ObjFile {
        parts,
        materials,
        warnings: warnings.into_inner(),
    })
}

/// What luz reads from one `newmtl` block beyond tobj.
#[derive(Debug, Default)]
struct MtlExtra {
    name: String,
    roughness: Option<f32>,
    metallic: Option<f32>,
    maps: MtlMaps,
}

/// The file extensions a texture may have.
pub const TEXTURE_EXTENSIONS: [&str; 3] = ["png", "exr", "hdr"];

/// Which [`MtlMaps`] field a map keyword fills (`None`: a map luz does not use).
fn map_target(keyword: &str) -> Option<fn(&mut MtlMaps) -> &mut Option<MtlMap>> {
    Some(match keyword.to_ascii_lowercase().as_str() {
        "map_kd" => |m| &mut m.diffuse,
        "map_ks" => |m| &mut m.specular,
        "map_bump" | "bump" | "norm" | "map_kn" | "map_norm" => |m| &mut m.normal,
        "map_pr" => |m| &mut m.roughness,
        "map_pm" => |m| &mut m.metallic,
        "map_ke" => |m| &mut m.emissive,
        _ => return None,
    })
}

/// Whether `keyword` names a texture map (used or not).
fn is_map_keyword(keyword: &str) -> bool {
    let k = keyword.to_ascii_lowercase();
    k.starts_with("map_") || ["bump", "norm", "disp", "decal", "refl"].contains(&k.as_str())
}

/// Reads the texture maps (with their options) and the PBR scalars `Pr`/`Pm` of an MTL text,
/// one entry per `newmtl`; texture paths are resolved against `mtl`'s folder and must exist.
/// Returns the entries and warnings about what is ignored.
fn mtl_extras(text: &str, mtl: &Path) -> Result<(Vec<MtlExtra>, Vec<String>), LineError> {
    let dir = mtl.parent().unwrap_or(Path::new(""));
    let mut out: Vec<MtlExtra> = Vec::new();
    let mut warnings = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let no = k + 1;
        let line = raw.trim();
        let Some(keyword) = line.split_whitespace().next() else {
            continue;
        };
        let rest = line[keyword.len()..].trim();
        if keyword == "newmtl" {
            out.push(MtlExtra {
                name: rest.to_string(),
                ..MtlExtra::default()
            });
            continue;
        }
        // Lines before the first newmtl belong to no material (tobj drops them too).
        let Some(cur) = out.last_mut() else {
            continue;
        };
        let warn = |what: String| format!("{}:{no}: {what}", mtl.display());
        match keyword {
            "Pr" | "Pm" => {
                let v = number(rest.split_whitespace().next(), keyword).map_err(|e| (no, e))?;
                if !(0.0..=1.0).contains(&v) {
                    return Err((no, format!("{keyword} must be in [0, 1], got {v}")));
                }
                if keyword == "Pr" {
                    cur.roughness = Some(v);
                } else {
                    cur.metallic = Some(v);
                }
            }
            kw if is_map_keyword(kw) => {
                let (opts, file) = map_options(kw, rest).map_err(|e| (no, e))?;
                let Some(target) = map_target(kw) else {
                    warnings.push(warn(format!(
                        "{kw} {}: this kind of map is not used, ignored",
                        crate::files::excerpt(file)
                    )));
                    continue;
                };
                let path = dir.join(file.replace('\\', "/"));
                let ext = crate::files::lowercase_extension(&path).unwrap_or_default();
                if !TEXTURE_EXTENSIONS.contains(&ext.as_str()) {
                    return Err((
                        no,
                        format!(
                            "{kw}: unsupported texture file \"{}\" (supported: .png, .exr, .hdr; convert it, or give the object a \"material\" so that the MTL file is not read)",
                            crate::files::excerpt(file)
                        ),
                    ));
                }
                if path.is_dir() {
                    return Err((
                        no,
                        format!(
                            "{kw}: texture file {} is a directory, not an image file",
                            path.display()
                        ),
                    ));
                }
                if !path.is_file() {
                    return Err((
                        no,
                        format!(
                            "{kw}: texture file {} not found (map paths are relative to the MTL file)",
                            path.display()
                        ),
                    ));
                }
                let normal = matches!(
                    kw.to_ascii_lowercase().as_str(),
                    "map_bump" | "bump" | "norm" | "map_kn" | "map_norm"
                );
                let single = matches!(kw.to_ascii_lowercase().as_str(), "map_pr" | "map_pm");
                for ignored in &opts.ignored {
                    warnings.push(warn(format!(
                        "{kw}: option {ignored} is not supported, ignored"
                    )));
                }
                if opts.bump_multiplier.is_some() && !normal {
                    warnings.push(warn(format!(
                        "{kw}: -bm applies to normal maps only, ignored"
                    )));
                }
                if opts.channel.is_some() && !single {
                    warnings.push(warn(format!(
                        "{kw}: -imfchan applies to single-value maps (map_Pr, map_Pm) only, ignored"
                    )));
                }
                *target(&mut cur.maps) = Some(MtlMap {
                    path,
                    mtl: mtl.to_path_buf(),
                    line: no,
                    clamp: opts.clamp,
                    bump_multiplier: opts.bump_multiplier.filter(|_| normal),
                    channel: opts.channel.filter(|_| single),
                });
            }
            _ => {}
        }
    }
    Ok((out, warnings))
}

/// The options of a map line that luz reads.
#[derive(Debug, Default, PartialEq)]
struct MapOptions {
    clamp: bool,
    bump_multiplier: Option<f32>,
    channel: Option<u8>,
    /// Options given but not supported (UV transforms, value remapping), as written.
    ignored: Vec<String>,
}

/// Splits a map line's text after the keyword into its options and the file name (the rest of
/// the line, which may contain spaces). Options as in the MTL specification: `-blendu`,
/// `-blendv`, `-cc`, `-clamp` (on/off), `-bm`, `-boost`, `-texres` (a number), `-mm` (two
/// numbers), `-o`, `-s`, `-t` (one to three numbers), `-imfchan` (r, g, b, m, l or z), `-type`
/// (a word, for `refl`).
fn map_options<'a>(keyword: &str, rest: &'a str) -> Result<(MapOptions, &'a str), String> {
    fn take(s: &str) -> (&str, &str) {
        let end = s.find(char::is_whitespace).unwrap_or(s.len());
        (&s[..end], s[end..].trim_start())
    }
    let mut opts = MapOptions::default();
    let mut s = rest.trim();
    while s.starts_with('-') {
        let (opt, after) = take(s);
        s = after;
        let mut arg = |what: &str| -> Result<&'a str, String> {
            let (a, after) = take(s);
            if a.is_empty() {
                return Err(format!("{keyword}: option {opt} needs {what}"));
            }
            s = after;
            Ok(a)
        };
        match opt {
            "-blendu" | "-blendv" | "-cc" | "-clamp" => {
                let v = arg("on or off")?;
                let on = match v {
                    "on" => true,
                    "off" => false,
                    _ => return Err(format!("{keyword}: option {opt} takes on or off, got {}", Quoted(v))),
                };
                if opt == "-clamp" {
                    opts.clamp = on;
                }
            }
            "-bm" | "-boost" | "-texres" => {
                let v = number(Some(arg("a number")?), &format!("{keyword} {opt}"))?;
                if opt == "-bm" {
                    opts.bump_multiplier = Some(v);
                }
            }
            "-mm" => {
                for _ in 0..2 {
                    number(Some(arg("two numbers (base, gain)")?), &format!("{keyword} -mm"))?;
                }
                opts.ignored.push("-mm".into());
            }
            "-o" | "-s" | "-t" => {
                number(Some(arg("one to three numbers")?), &format!("{keyword} {opt}"))?;
                for _ in 0..2 {
                    let (a, after) = take(s);
                    if a.parse::<f32>().is_err() {
                        break;
                    }
                    s = after;
                }
                opts.ignored.push(opt.to_string());
            }
            "-imfchan" => {
                let v = arg("a channel (r, g, b, m, l or z)")?;
                opts.channel = match v {
                    "r" => Some(0),
                    "g" => Some(1),
                    "b" => Some(2),
                    "m" => Some(3),
                    "l" | "z" => {
                        opts.ignored.push(format!("-imfchan {v}"));
                        None
                    }
                    _ => {
                        return Err(format!(
                            "{keyword}: option -imfchan takes r, g, b, m, l or z, got {}",
                            Quoted(v)
                        ))
                    }
                };
            }
            "-type" => {
                arg("a type")?;
            }
            _ => {
                return Err(format!(
                    "{keyword}: unknown option {} (known: -blendu, -blendv, -bm, -boost, -cc, -clamp, -imfchan, -mm, -o, -s, -t, -texres, -type)",
                    crate::files::excerpt(opt)
                ))
            }
        }
    }
    if s.is_empty() {
        return Err(format!("{keyword}: no file name after the options"));
    }
    Ok((opts, s))
}

fn utf8(bytes: &[u8]) -> Result<&str, (usize, String)> {
    std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        (line, "not UTF-8 text (is this a binary file?)".to_string())
    })
}

type LineError = (usize, String);

/// A word of the input in an error message: quoted, and shortened when long
/// ([`crate::files::quoted`]); formatted only when the message is.
struct Quoted<'a>(&'a str);

impl std::fmt::Display for Quoted<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&crate::files::quoted(self.0))
    }
}

fn number(word: Option<&str>, what: &str) -> Result<f32, String> {
    let Some(word) = word else {
        return Err(format!("{what}: missing number"));
    };
    let qw = Quoted(word);
    match word.parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!("{what}: {qw} is not a finite number")),
        Err(_) => Err(format!("{what}: {qw} is not a number")),
    }
}

/// Checks an OBJ text; returns its `mtllib` names with their lines.
fn check_obj(text: &str) -> Result<Vec<(usize, String)>, LineError> {
    // Pass 1: totals, because faces may refer to vertices defined later.
    let (mut nv, mut nvt, mut nvn) = (0usize, 0usize, 0usize);
    for line in text.lines() {
        match line.split_whitespace().next() {
            Some("v") => nv += 1,
            Some("vt") => nvt += 1,
            Some("vn") => nvn += 1,
            _ => {}
        }
    }
    // Pass 2: every line, with running counts for relative (negative) indices.
    let (mut cv, mut cvt, mut cvn) = (0usize, 0usize, 0usize);
    let mut coloured: Option<bool> = None;
    let mut mtllibs = Vec::new();
    let mut faces = 0usize;
    let mut triangles = 0usize;
    let max_triangles = crate::files::InputBudget::current().max_triangles;
    for (k, line) in text.lines().enumerate() {
        let no = k + 1;
        let fail = |reason: String| (no, reason);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let rest: Vec<&str> = words.collect();
                for (i, w) in rest.iter().take(3).enumerate() {
                    number(Some(w), ["x", "y", "z"][i]).map_err(|e| fail(format!("vertex {e}")))?;
                }
                let has_colour = match rest.len() {
                    0..=2 => return Err(fail("a vertex needs 3 coordinates".into())),
                    3 => false,
                    4 => {
                        let w =
                            number(Some(rest[3]), "w").map_err(|e| fail(format!("vertex {e}")))?;
                        if w == 0.0 {
                            return Err(fail("vertex w is 0".into()));
                        }
                        false
                    }
                    6 => {
                        for w in &rest[3..] {
                            number(Some(w), "colour").map_err(|e| fail(format!("vertex {e}")))?;
                        }
                        true
                    }
                    n => {
                        return Err(fail(format!(
                            "a vertex has 3, 4 (x y z w) or 6 (x y z r g b) numbers, not {n}"
                        )))
                    }
                };
                if *coloured.get_or_insert(has_colour) != has_colour {
                    return Err(fail(
                        "some vertices have colours (x y z r g b) and others do not".into(),
                    ));
                }
                cv += 1;
            }
            Some("vt") => {
                number(words.next(), "texture coordinate u").map_err(fail)?;
                number(words.next(), "texture coordinate v").map_err(fail)?;
                cvt += 1;
            }
            Some("vn") => {
                for c in ["x", "y", "z"] {
                    number(words.next(), &format!("normal {c}")).map_err(fail)?;
                }
                cvn += 1;
            }
            Some(kw @ ("f" | "l")) => {
                let mut corners = 0usize;
                for word in words {
                    corners += 1;
                    let qw = Quoted(word);
                    let parts: Vec<&str> = word.split('/').collect();
                    if parts.len() > 3 {
                        return Err(fail(format!(
                            "bad face vertex {qw} (v, v/vt, v//vn or v/vt/vn)"
                        )));
                    }
                    if parts[0].is_empty() {
                        return Err(fail(format!("face vertex {qw} has no position index")));
                    }
                    let what = ["vertex", "texture coordinate", "normal"];
                    let totals = [nv, nvt, nvn];
                    let running = [cv, cvt, cvn];
                    for (i, p) in parts.iter().enumerate() {
                        if p.is_empty() {
                            continue;
                        }
                        let Ok(x) = p.parse::<isize>() else {
                            return Err(fail(format!(
                                "face vertex {qw}: {} is not an index",
                                Quoted(p)
                            )));
                        };
                        let ok = if x > 0 {
                            x.unsigned_abs() <= totals[i]
                        } else if x < 0 {
                            x.unsigned_abs() <= running[i]
                        } else {
                            return Err(fail(format!(
                                "face vertex {qw}: index 0 (OBJ indices start at 1)"
                            )));
                        };
                        if !ok {
                            let plural = ["vertices", "texture coordinates", "normals"][i];
                            let have = if x > 0 {
                                format!("the file has {} {plural}", totals[i])
                            } else {
                                format!("only {} {plural} before this line", running[i])
                            };
                            return Err(fail(format!(
                                "face vertex {qw}: {} index {x} out of range ({have})",
                                what[i]
                            )));
                        }
                    }
                }
                if kw == "f" {
                    if corners < 3 {
                        return Err(fail(format!(
                            "a face needs at least 3 vertices, got {corners}"
                        )));
                    }
                    faces += 1;
                    // A face of n corners is n − 2 triangles (a fan): counted here, before tobj
                    // builds any of them, so that a file's triangles stay within the budget
                    // whatever its size (one `f` line of millions of corners too).
                    triangles = triangles.saturating_add(corners - 2);
                    if triangles > max_triangles {
                        return Err(fail(format!(
                            "the file expands into more than {max_triangles} triangles (faces \
                             up to this line, n − 2 for a face of n corners; raise the input \
                             budget with --max-triangles)"
                        )));
                    }
                }
            }
            Some("usemtl") => {
                let name = line.split_once(' ').map(|(_, n)| n.trim()).unwrap_or("");
                if name.is_empty() {
                    return Err(fail("usemtl without a material name".into()));
                }
            }
            Some("mtllib") => {
                let name = line.split_once(' ').map(|(_, n)| n.trim()).unwrap_or("");
                if name.is_empty() {
                    return Err(fail("mtllib without a file name".into()));
                }
                mtllibs.push((no, name.to_string()));
            }
            _ => {}
        }
    }
    if faces == 0 {
        let lines = text.lines().count().max(1);
        return Err((
            lines,
            format!(
                "no faces (read {nv} vertices and no 'f' lines; truncated or not an OBJ file?)"
            ),
        ));
    }
    Ok(mtllibs)
}

/// Checks an MTL text line by line (what `tobj` would panic on or reject).
fn check_mtl(text: &str) -> Result<(), LineError> {
    for (k, line) in text.lines().enumerate() {
        let no = k + 1;
        let fail = |reason: String| (no, reason);
        let trimmed = line.trim();
        let mut words = trimmed.split_whitespace();
        match words.next() {
            Some("newmtl") if trimmed[6..].trim().is_empty() => {
                return Err(fail("newmtl without a material name".into()));
            }
            Some(kw @ ("Ka" | "Kd" | "Ks" | "Ke")) => {
                for c in ["r", "g", "b"] {
                    let v = number(words.next(), &format!("{kw} {c}")).map_err(fail)?;
                    if v < 0.0 {
                        return Err(fail(format!("{kw} {c} must be ≥ 0, got {v}")));
                    }
                }
            }
            Some(kw @ ("Ns" | "Ni" | "d")) => {
                let v = number(words.next(), kw).map_err(fail)?;
                if kw == "Ns" && v < 0.0 {
                    return Err(fail(format!("Ns must be ≥ 0, got {v}")));
                }
            }
            Some("illum") => {
                let w = words.next().unwrap_or("");
                if w.parse::<u8>().is_err() {
                    return Err(fail(format!(
                        "illum: {} is not a number from 0 to 255",
                        Quoted(w)
                    )));
                }
            }
            Some(kw) if (kw.starts_with("map_") || kw == "bump") && words.next().is_none() => {
                return Err(fail(format!("{kw} without a file name")));
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic fuzzer: random OBJ lines never make the loader panic (the `catch_unwind`
    /// backstop must never be what saves us).
    #[test]
    fn random_obj_text_never_panics() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        let keywords = [
            "v", "vt", "vn", "f", "l", "p", "o", "g", "usemtl", "s", "#", "f", "v", "",
        ];
        let words = [
            "0",
            "1",
            "2",
            "3",
            "-1",
            "-2",
            "-4",
            "0.5",
            "1e39",
            "nan",
            "inf",
            "x",
            "1/1",
            "1/1/1",
            "2//1",
            "//",
            "1/",
            "/1",
            "1/2/3/4",
            "99999999999999999999",
            "-99999999999999999999",
            "3/0",
            "0/0/0",
            "1//0",
            "a b",
            "\t",
            "1 1 1 1",
        ];
        let mut outcomes = [0usize; 2];
        for _ in 0..4000 {
            // A valid start half of the time, so that some files get through to tobj.
            let mut text = String::new();
            if next(2) == 0 {
                text.push_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\nf 1 2 3\n");
            }
            for _ in 0..next(8) {
                text.push_str(keywords[next(keywords.len())]);
                for _ in 0..next(6) {
                    text.push(' ');
                    text.push_str(words[next(words.len())]);
                }
                text.push('\n');
            }
            let r = load_obj_bytes(text.as_bytes(), Path::new("fuzz.obj"), false);
            if let Err(e) = &r {
                assert!(!e.reason.contains("panicked"), "{text:?}: {e}");
            }
            if let Ok(f) = &r {
                for p in &f.parts {
                    p.mesh.validate().unwrap();
                }
            }
            outcomes[usize::from(r.is_ok())] += 1;
        }
        assert!(outcomes[0] > 0 && outcomes[1] > 0, "{outcomes:?}");
    }

    fn line_err(text: &str) -> LineError {
        check_obj(text).expect_err(text)
    }

    #[test]
    fn obj_checks_report_lines() {
        let ok = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf -3 -2 -1\n";
        assert!(check_obj(ok).is_ok());
        assert_eq!(line_err("v 0 0 0\nv 1 0 0\nf 1 2 4\n").0, 3);
        assert!(line_err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/0 2/0 3/0\n")
            .1
            .contains("index 0"));
        assert!(line_err("v 0 0 0\nv 1 0 0\nf -4 1 2\n")
            .1
            .contains("out of range"));
        assert!(line_err("v 0 0 nan\n").1.contains("finite"));
        assert!(line_err("v 0 0\n").1.contains("3 coordinates"));
        assert!(line_err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n")
            .1
            .contains("at least 3"));
        assert!(line_err("v 0 0 0 1 1\n").1.contains("not 5"));
        assert!(line_err("v 0 0 0\n").1.contains("no faces"));
        assert!(line_err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n")
            .1
            .contains("bad face"));
        assert!(line_err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n")
            .1
            .contains("not an index"));
        assert!(line_err("v 0 0 0\nv 1 0 0 1 1 1\nv 0 1 0\nf 1 2 3\n")
            .1
            .contains("colours"));
        assert!(line_err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n")
            .1
            .contains("texture coordinate index 1"));
        assert!(
            line_err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n")
                .1
                .contains("not an index")
        );
    }

    #[test]
    fn mtl_checks_report_lines() {
        assert!(check_mtl("newmtl a\nKd 1 0.5 0.25\nNs 10\nillum 2\n").is_ok());
        assert_eq!(check_mtl("newmtl a\nKd 0.5\n").unwrap_err().0, 2);
        assert!(check_mtl("newmtl \n").is_err());
        assert!(check_mtl("newmtl a\nKs -1 0 0\n")
            .unwrap_err()
            .1
            .contains("≥ 0"));
        assert!(check_mtl("newmtl a\nillum x\n").is_err());
        assert!(check_mtl("newmtl a\nmap_Kd\n").is_err());
    }
}
