//! Compiles every `.vert`, `.frag` and `.comp` under `shaders_glsl/` to SPIR-V with shaderc and embeds
//! the results in the binary through `$OUT_DIR/shaders.rs`.
//!
//! * `#include "x.glsl"` resolves relative to the including file, then to `shaders_glsl/`.
//! * Every source and every include gets a `cargo::rerun-if-changed` line.
//! * Warnings are errors; a GLSL error fails the build with `file:line: message`.
//! * Variants: a line `//! variant NAME: DEF DEF=VALUE ...` near the top of a stage file builds one
//!   SPIR-V module per such line with those defines (`forward.frag` + `phong` → key
//!   `forward.frag:phong`). A stage file without such lines builds one module, key `forward.frag`.

use std::cell::RefCell;
use std::collections::BTreeSet;
use std::fmt::Write as _;

use std::path::{Path, PathBuf};

#[path = "../build-support/glsl.rs"]
mod glsl;

struct Variant {
    name: Option<String>,
    defines: Vec<(String, Option<String>)>,
}

fn parse_variants(source: &str, path: &Path) -> Vec<Variant> {
    let mut out = Vec::new();
    for (i, line) in source.lines().enumerate() {
        let Some(rest) = line.trim().strip_prefix("//! variant ") else {
            continue;
        };
        let Some((name, defs)) = rest.split_once(':') else {
            panic!(
                "{}:{}: a variant line reads `//! variant NAME: DEFINES`",
                path.display(),
                i + 1
            );
        };
        let defines = defs
            .split_whitespace()
            .map(|d| match d.split_once('=') {
                Some((k, v)) => (k.to_string(), Some(v.to_string())),
                None => (d.to_string(), None),
            })
            .collect();
        out.push(Variant {
            name: Some(name.trim().to_string()),
            defines,
        });
    }
    if out.is_empty() {
        out.push(Variant {
            name: None,
            defines: Vec::new(),
        });
    }
    out
}

fn main() {
    let root = glsl::shader_root();
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo::rerun-if-changed={}", root.display());

    let mut files = Vec::new();
    glsl::collect(&root, &mut files);
    let includes: RefCell<BTreeSet<PathBuf>> = RefCell::new(BTreeSet::new());

    let compiler = shaderc::Compiler::new().expect("shaderc compiler");
    let mut table = String::new();
    let mut interfaces = String::new();
    let mut failures = Vec::new();
    for path in &files {
        println!("cargo::rerun-if-changed={}", path.display());
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        // The stage as a VkShaderStageFlags bit (build scripts do not link ash).
        let (kind, stage_bit) = match ext {
            "vert" => (shaderc::ShaderKind::Vertex, 0x1),
            "frag" => (shaderc::ShaderKind::Fragment, 0x10),
            "comp" => (shaderc::ShaderKind::Compute, 0x20),
            _ => continue,
        };
        let source = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        let rel = path
            .strip_prefix(&root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        for variant in parse_variants(&source, path) {
            let mut options = shaderc::CompileOptions::new().expect("shaderc options");
            options.set_target_env(
                shaderc::TargetEnv::Vulkan,
                shaderc::EnvVersion::Vulkan1_3 as u32,
            );
            options.set_source_language(shaderc::SourceLanguage::GLSL);
            options.set_warnings_as_errors();
            options.set_generate_debug_info();
            options.set_optimization_level(shaderc::OptimizationLevel::Performance);
            for (k, v) in &variant.defines {
                options.add_macro_definition(k, v.as_deref());
            }
            let root_c = root.clone();
            let includes_c = &includes;
            options.set_include_callback(move |requested, ty, requester, _depth| {
                let requester = Path::new(requester);
                let mut candidates = Vec::new();
                if ty == shaderc::IncludeType::Relative {
                    if let Some(parent) = requester.parent() {
                        candidates.push(parent.join(requested));
                    }
                }
                candidates.push(root_c.join(requested));
                for c in candidates {
                    if let Ok(content) = std::fs::read_to_string(&c) {
                        includes_c.borrow_mut().insert(c.clone());
                        return Ok(shaderc::ResolvedInclude {
                            resolved_name: c.to_string_lossy().into_owned(),
                            content,
                        });
                    }
                }
                Err(format!(
                    "cannot find include \"{requested}\" (from {})",
                    requester.display()
                ))
            });
            let input_name = path.to_string_lossy().into_owned();
            match compiler.compile_into_spirv(&source, kind, &input_name, "main", Some(&options)) {
                Ok(artifact) => {
                    let key = match &variant.name {
                        Some(n) => format!("{rel}:{n}"),
                        None => rel.clone(),
                    };
                    let file_name = format!("{}.spv", key.replace(['/', ':'], "_"));
                    std::fs::write(out_dir.join(&file_name), artifact.as_binary_u8())
                        .expect("write SPIR-V");
                    match interface(&key, stage_bit, artifact.as_binary_u8()) {
                        Ok(entry) => interfaces.push_str(&entry),
                        Err(e) => failures.push(format!("{}: reflection: {e}", path.display())),
                    }
                    writeln!(
                        table,
                        "    ({key:?}, include_bytes!(concat!(env!(\"OUT_DIR\"), \"/{file_name}\"))),"
                    )
                    .unwrap();
                }
                Err(e) => {
                    let which = match &variant.name {
                        Some(n) => format!(" (variant {n})"),
                        None => String::new(),
                    };
                    failures.push(format!("{}{which}:\n{e}", path.display()));
                }
            }
        }
    }
    for inc in includes.borrow().iter() {
        println!("cargo::rerun-if-changed={}", inc.display());
    }
    if !failures.is_empty() {
        for f in &failures {
            eprintln!("GLSL error in {f}");
        }
        panic!(
            "{} shader(s) failed to compile:\n{}",
            failures.len(),
            failures.join("\n")
        );
    }
    let code = format!(
        "/// Every SPIR-V module compiled by build.rs: (key, bytes). Keys are `path.stage` or `path.stage:variant`.\n\
         pub static SPIRV: &[(&str, &[u8])] = &[\n{table}];\n\
         /// Every module's resource interface, read from its SPIR-V: (key, interface).\n\
         pub static INTERFACES: &[(&str, ModuleInterface)] = &[\n{interfaces}];\n"
    );
    std::fs::write(out_dir.join("shaders.rs"), code).expect("write shaders.rs");
    std::fs::write(
        out_dir.join("glsl_constants.rs"),
        glsl::glsl_constants(&root, &files),
    )
    .expect("write glsl_constants.rs");
}

/// One module's entry of `INTERFACES`: its descriptor bindings (set, binding, VkDescriptorType,
/// count, name) and its push-constant block's size, read from the SPIR-V by [`reflect`].
fn interface(key: &str, stage_bit: u32, spirv: &[u8]) -> Result<String, String> {
    let r = reflect(spirv)?;
    let mut bindings = String::new();
    for b in &r.bindings {
        write!(
            bindings,
            "ReflectedBinding {{ set: {}, binding: {}, ty: {}, count: {}, name: {:?} }}, ",
            b.set, b.binding, b.ty, b.count, b.name
        )
        .unwrap();
    }
    Ok(format!(
        "    ({key:?}, ModuleInterface {{ stage: {stage_bit:#x}, push_size: {}, bindings: &[{bindings}] }}),\n",
        r.push_size
    ))
}

struct Binding {
    set: u32,
    binding: u32,
    ty: u32,
    count: u32,
    name: String,
}

struct Reflected {
    bindings: Vec<Binding>,
    push_size: u32,
}

/// The descriptor bindings and the push-constant block size of a SPIR-V module.
///
/// Hand-written on purpose: rspirv-reflect 0.9 (rspirv 0.12) refuses shaderc's output here — it
/// cannot place `OpExecutionModeId` (every compute shader) and rejects debug-info strings that
/// `OpSourceContinued` splits inside a UTF-8 character. luz needs only a few opcodes, each found
/// by its word count, so everything else (new opcodes, debug info) is skipped unread.
fn reflect(spirv: &[u8]) -> Result<Reflected, String> {
    use std::collections::HashMap;
    if !spirv.len().is_multiple_of(4) || spirv.len() < 20 {
        return Err("not a SPIR-V module (length)".into());
    }
    let words: Vec<u32> = spirv
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    if words[0] != 0x0723_0203 {
        return Err("not a SPIR-V module (magic)".into());
    }
    let string = |w: &[u32]| -> String {
        let bytes: Vec<u8> = w.iter().flat_map(|x| x.to_le_bytes()).collect();
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        String::from_utf8_lossy(&bytes[..end]).into_owned()
    };
    enum Type {
        Scalar(u32),
        Vector(u32, u32),
        Matrix(u32, u32),
        Image { sampled: u32, dim: u32 },
        Sampler,
        SampledImage,
        Array(u32, u32),
        RuntimeArray,
        Struct(Vec<u32>),
        Pointer(u32),
        Other,
    }
    let mut names: HashMap<u32, String> = HashMap::new();
    let mut decorations: HashMap<(u32, u32), u32> = HashMap::new();
    let mut member_decorations: HashMap<(u32, u32, u32), u32> = HashMap::new();
    let mut types: HashMap<u32, Type> = HashMap::new();
    let mut constants: HashMap<u32, u32> = HashMap::new();
    let mut variables: Vec<(u32, u32, u32)> = Vec::new(); // (pointer type, id, storage class)
    let mut at = 5;
    while at < words.len() {
        let (count, op) = ((words[at] >> 16) as usize, words[at] & 0xffff);
        if count == 0 || at + count > words.len() {
            return Err(format!("truncated instruction at word {at}"));
        }
        let o = &words[at + 1..at + count];
        match op {
            5 if !o.is_empty() => {
                names.insert(o[0], string(&o[1..]));
            }
            71 if o.len() >= 2 => {
                decorations.insert((o[0], o[1]), o.get(2).copied().unwrap_or(0));
            }
            72 if o.len() >= 3 => {
                member_decorations.insert((o[0], o[1], o[2]), o.get(3).copied().unwrap_or(0));
            }
            19 | 20 => {
                types.insert(o[0], Type::Other);
            }
            21 | 22 => {
                types.insert(o[0], Type::Scalar(o[1] / 8));
            }
            23 => {
                types.insert(o[0], Type::Vector(o[1], o[2]));
            }
            24 => {
                types.insert(o[0], Type::Matrix(o[1], o[2]));
            }
            25 => {
                types.insert(
                    o[0],
                    Type::Image {
                        dim: o[2],
                        sampled: o[6],
                    },
                );
            }
            26 => {
                types.insert(o[0], Type::Sampler);
            }
            27 => {
                types.insert(o[0], Type::SampledImage);
            }
            28 => {
                types.insert(o[0], Type::Array(o[1], o[2]));
            }
            29 => {
                types.insert(o[0], Type::RuntimeArray);
            }
            30 => {
                types.insert(o[0], Type::Struct(o[1..].to_vec()));
            }
            32 => {
                types.insert(o[0], Type::Pointer(o[2]));
            }
            43 if o.len() >= 3 => {
                constants.insert(o[1], o[2]);
            }
            59 => variables.push((o[0], o[1], o[2])),
            _ => {}
        }
        at += count;
    }
    const DESCRIPTOR_SET: u32 = 34;
    const BINDING: u32 = 33;
    const BLOCK: u32 = 2;
    const BUFFER_BLOCK: u32 = 3;
    const ARRAY_STRIDE: u32 = 6;
    const MATRIX_STRIDE: u32 = 7;
    const OFFSET: u32 = 35;
    // The byte size of a type inside a block (explicit layout: offsets and strides).
    fn size_of(
        id: u32,
        types: &HashMap<u32, Type>,
        constants: &HashMap<u32, u32>,
        decorations: &HashMap<(u32, u32), u32>,
        member_decorations: &HashMap<(u32, u32, u32), u32>,
        matrix_stride: Option<u32>,
    ) -> Result<u32, String> {
        let size = |t| size_of(t, types, constants, decorations, member_decorations, None);
        Ok(match types.get(&id) {
            Some(Type::Scalar(b)) => *b,
            Some(Type::Vector(c, n)) => size(*c)? * n,
            Some(Type::Matrix(col, n)) => match matrix_stride {
                Some(stride) => stride * n,
                None => size(*col)? * n,
            },
            Some(Type::Array(e, len)) => {
                let n = constants.get(len).copied().ok_or("array length")?;
                match decorations.get(&(id, ARRAY_STRIDE)) {
                    Some(stride) => stride * n,
                    None => size(*e)? * n,
                }
            }
            Some(Type::Struct(members)) => {
                let mut end = 0;
                for (i, m) in members.iter().enumerate() {
                    let i = i as u32;
                    let offset = member_decorations.get(&(id, i, OFFSET)).copied();
                    let stride = member_decorations.get(&(id, i, MATRIX_STRIDE)).copied();
                    let s = size_of(
                        *m,
                        types,
                        constants,
                        decorations,
                        member_decorations,
                        stride,
                    )?;
                    end = end.max(offset.unwrap_or(end) + s);
                }
                end
            }
            _ => return Err(format!("cannot size type %{id}")),
        })
    }
    let mut bindings = Vec::new();
    let mut push_size = 0;
    for (pointer, id, class) in variables {
        let Some(Type::Pointer(pointee)) = types.get(&pointer) else {
            continue;
        };
        if class == 9 {
            push_size = push_size.max(size_of(
                *pointee,
                &types,
                &constants,
                &decorations,
                &member_decorations,
                None,
            )?);
            continue;
        }
        let (Some(&set), Some(&binding)) = (
            decorations.get(&(id, DESCRIPTOR_SET)),
            decorations.get(&(id, BINDING)),
        ) else {
            continue;
        };
        let (mut ty_id, mut count) = (*pointee, 1);
        if let Some(Type::Array(e, len)) = types.get(&ty_id) {
            count = constants.get(len).copied().ok_or("array length")?;
            ty_id = *e;
        } else if let Some(Type::RuntimeArray) = types.get(&ty_id) {
            return Err(format!(
                "set {set} binding {binding} is an unsized array; luz's layouts need a fixed count"
            ));
        }
        // VkDescriptorType values.
        let ty = match (class, types.get(&ty_id)) {
            (0, Some(Type::Sampler)) => 0,
            (0, Some(Type::SampledImage)) => 1,
            (0, Some(Type::Image { sampled: 2, dim: 5 })) => 5,
            (0, Some(Type::Image { dim: 5, .. })) => 4,
            (0, Some(Type::Image { sampled: 2, .. })) => 3,
            (0, Some(Type::Image { .. })) => 2,
            (2, _) if decorations.contains_key(&(ty_id, BUFFER_BLOCK)) => 7,
            (2, _) if decorations.contains_key(&(ty_id, BLOCK)) => 6,
            (12, _) => 7,
            _ => {
                return Err(format!(
                    "set {set} binding {binding}: unknown resource kind"
                ))
            }
        };
        let name = match names.get(&id) {
            Some(n) if !n.is_empty() => n.clone(),
            _ => names.get(&ty_id).cloned().unwrap_or_default(),
        };
        bindings.push(Binding {
            set,
            binding,
            ty,
            count,
            name,
        });
    }
    bindings.sort_by_key(|b| (b.set, b.binding));
    Ok(Reflected {
        bindings,
        push_size,
    })
}
