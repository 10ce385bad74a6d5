//! Writes the shipped bake of the default scene's environment
//! (`luz::render::ibl::shipped::DEFAULT_ENV_DATA`, relative to the luz-gpu crate) on lavapipe:
//! `VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json cargo run --release -p luz-gpu --example default_env`.
//! The test `tests/ibl.rs::shipped_default_environment_regenerates` checks that the shipped
//! bytes are this program's output.

use luz_gpu::render::ibl::shipped;
use luz_gpu::vk::{Context, ContextDesc};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let ctx = Context::new(&ContextDesc::default())?;
    println!("{}", ctx.info.summary());
    let (name, bytes) = luz_gpu::headless::bake_default_environment(&ctx)?;
    if name != shipped::DEFAULT_ENV_FILE {
        return Err(format!(
            "the default environment's cache file is now {name}: set DEFAULT_ENV_FILE to it"
        )
        .into());
    }
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(shipped::DEFAULT_ENV_DATA);
    let deflated = shipped::deflate(&bytes);
    std::fs::write(&path, &deflated)?;
    println!(
        "wrote {} ({} bytes, {} inflated)",
        path.display(),
        deflated.len(),
        bytes.len()
    );
    Ok(())
}
