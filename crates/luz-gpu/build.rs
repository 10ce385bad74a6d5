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
        glsl::glsl_constants(&root, &files),
    )
    .expect("write glsl_constants.rs");
}
