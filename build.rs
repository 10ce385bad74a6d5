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

fn collect(dir: &Path, files: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            collect(&p, files);
        } else {
            files.push(p);
        }
    }
}

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap()).join("shaders_glsl");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo::rerun-if-changed={}", root.display());

    let mut files = Vec::new();
    collect(&root, &mut files);
    let includes: RefCell<BTreeSet<PathBuf>> = RefCell::new(BTreeSet::new());

    let compiler = shaderc::Compiler::new().expect("shaderc compiler");
    let mut table = String::new();
    let mut failures = Vec::new();
    for path in &files {
        println!("cargo::rerun-if-changed={}", path.display());
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        let kind = match ext {
            "vert" => shaderc::ShaderKind::Vertex,
            "frag" => shaderc::ShaderKind::Fragment,
            "comp" => shaderc::ShaderKind::Compute,
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
         pub static SPIRV: &[(&str, &[u8])] = &[\n{table}];\n"
    );
    std::fs::write(out_dir.join("shaders.rs"), code).expect("write shaders.rs");
    std::fs::write(
        out_dir.join("glsl_constants.rs"),
        glsl_constants(&root, &files),
    )
    .expect("write glsl_constants.rs");
}

/// A Rust literal and its type for a GLSL number: `12u`/`0xFFu` → u32, `-1`/`3` → i32,
/// `1e-3`/`3.14` → f64; `None` for anything else (expressions, names).
fn rust_number(text: &str) -> Option<(&'static str, String)> {
    let t = text.trim();
    if let Some(digits) = t.strip_suffix(['u', 'U']) {
        let v = match digits
            .strip_prefix("0x")
            .or_else(|| digits.strip_prefix("0X"))
        {
            Some(hex) => u32::from_str_radix(hex, 16).ok()?,
            None => digits.parse::<u32>().ok()?,
        };
        return Some(("u32", v.to_string()));
    }
    if let Some(hex) = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        return Some(("i32", i32::from_str_radix(hex, 16).ok()?.to_string()));
    }
    if let Ok(v) = t.parse::<i32>() {
        return Some(("i32", v.to_string()));
    }
    let f: f64 = t.trim_end_matches(['f', 'F']).parse().ok()?;
    f.is_finite().then(|| ("f64", format!("{f:?}")))
}

/// The Rust module of every constant the GLSL sources define (see the module docs).
fn glsl_constants(root: &Path, files: &[PathBuf]) -> String {
    let mut out = String::from(
        "// Generated by build.rs from shaders_glsl/: the constants Rust shares with GLSL.\n",
    );
    for path in files {
        let Ok(source) = std::fs::read_to_string(path) else {
            continue;
        };
        let rel = path
            .strip_prefix(root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        // By name; the first definition wins (a name defined twice under #if is left to GLSL).
        let mut items = std::collections::BTreeMap::new();
        for line in source.lines() {
            let line = line.trim();
            if let Some(rest) = line.strip_prefix("#define ") {
                let mut parts = rest.splitn(2, char::is_whitespace);
                let (Some(name), Some(value)) = (parts.next(), parts.next()) else {
                    continue;
                };
                let value = value.split("//").next().unwrap_or("");
                let identifier = name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
                if let (true, Some((ty, v))) = (identifier, rust_number(value)) {
                    items
                        .entry(name.to_string())
                        .or_insert(format!("    pub const {name}: {ty} = {v};\n"));
                }
            } else if let Some(rest) = line.strip_prefix("layout(constant_id") {
                // layout(constant_id = 7) const uint DEBUG_VIEW = 0u;
                let Some((id, decl)) = rest.split_once(')') else {
                    continue;
                };
                let id = id.trim_start_matches([' ', '=']).trim();
                let name = decl
                    .split('=')
                    .next()
                    .and_then(|d| d.split_whitespace().last());
                if let (Ok(id), Some(name)) = (id.parse::<u32>(), name) {
                    items
                        .entry(format!("SPEC_{name}"))
                        .or_insert(format!("    pub const SPEC_{name}: u32 = {id};\n"));
                }
            }
        }
        if items.is_empty() {
            continue;
        }
        let module: String = rel
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect::<String>()
            .trim_end_matches("_glsl")
            .to_string();
        writeln!(out, "/// Constants of `shaders_glsl/{rel}`.").unwrap();
        writeln!(
            out,
            "#[allow(dead_code, clippy::excessive_precision, clippy::approx_constant)]"
        )
        .unwrap();
        writeln!(out, "pub mod {module} {{").unwrap();
        for item in items.values() {
            out.push_str(item);
        }
        out.push_str("}\n");
    }
    out
}
