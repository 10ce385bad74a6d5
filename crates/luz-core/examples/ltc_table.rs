//! Writes the shipped LTC table for GGX (`luz_core::brdf::LTC_FILE`, relative to the luz-core
//! crate): `cargo run --release -p luz-core --example ltc_table`. The test `ltc_table_refits`
//! checks that the file in the repository is this program's output.

fn main() -> std::io::Result<()> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(luz_core::brdf::LTC_FILE);
    let t = std::time::Instant::now();
    let bytes = luz_core::brdf::generate_ltc_table();
    std::fs::write(&path, &bytes)?;
    println!(
        "wrote {} ({} bytes) in {:.1} s",
        path.display(),
        bytes.len(),
        t.elapsed().as_secs_f64()
    );
    Ok(())
}
