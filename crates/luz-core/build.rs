//! Turns every number the GLSL sources define into a Rust constant (`luz_core::glsl`): the one
//! source of the set, binding, specialization and code numbers Rust shares with the shaders. No
//! shader is compiled here (that is luz-gpu's build script): the core builds without shaderc.

#[path = "../build-support/glsl.rs"]
mod glsl;

fn main() {
    let root = glsl::shader_root();
    println!("cargo::rerun-if-changed={}", root.display());
    let mut files = Vec::new();
    glsl::collect(&root, &mut files);
    for f in &files {
        println!("cargo::rerun-if-changed={}", f.display());
    }
    let out_dir = std::path::PathBuf::from(std::env::var("OUT_DIR").unwrap());
    std::fs::write(
        out_dir.join("glsl_constants.rs"),
        glsl::glsl_constants(&root, &files),
    )
    .expect("write glsl_constants.rs");
}
