//! Writes the shipped split-sum BRDF table (`luz_core::env::SHIPPED_LUT_FILE`, relative to the
//! luz-core crate): `cargo run --release -p luz-core --example brdf_lut`. The test
//! `shipped_lut_regenerates` checks that the file in the repository is this program's output.

fn main() -> std::io::Result<()> {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(luz_core::env::SHIPPED_LUT_FILE);
    let t = std::time::Instant::now();
    let bytes = luz_core::env::generate_shipped_lut();
    std::fs::write(&path, &bytes)?;
    println!(
        "wrote {} ({} bytes) in {:.1} s",
        path.display(),
        bytes.len(),
        t.elapsed().as_secs_f64()
    );
    Ok(())
}
