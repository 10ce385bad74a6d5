//! Writes the shipped anisotropic split-sum table (`luz_core::brdf::ANISO_LUT_FILE`, relative
//! to the luz-core crate): `cargo run --release -p luz-core --example aniso_lut`. The test
//! `shipped_aniso_lut_regenerates` checks that the file in the repository is this program's
//! output.

fn main() -> std::io::Result<()> {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(luz_core::brdf::ANISO_LUT_FILE);
    let t = std::time::Instant::now();
    let bytes = luz_core::brdf::generate_aniso_lut();
    std::fs::write(&path, &bytes)?;
    println!(
        "wrote {} ({} bytes) in {:.1} s",
        path.display(),
        bytes.len(),
        t.elapsed().as_secs_f64()
    );
    Ok(())
}
