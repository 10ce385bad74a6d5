//! Writes the shipped table of the `fitted_lobes` specular method (`luz_core::env::LOBES_FILE`,
//! relative to the luz-core crate): `cargo run --release -p luz-core --example ibl_lobe_table`.
//! The test `lobe_table_refits` checks that the file in the repository is this program's output;
//! with `--check` it prints the fit's L1 distance from the real lobe against the split sum's
//! single lookup instead (docs/accuracy.md quotes it).

fn main() -> std::io::Result<()> {
    use luz_core::env::{lobe_entry_coords, lobe_fit_error, LOBES_FILE, LOBES_SIZE};
    if std::env::args().any(|a| a == "--check") {
        let ts = [0usize, 8, 14, 20, 25, 29];
        print!("| roughness \\ θ_v |");
        for t in ts {
            print!(" {:.1}° |", lobe_entry_coords(t, 0).0.acos().to_degrees());
        }
        println!();
        println!("|---|{}", "---:|".repeat(ts.len()));
        for a in [3usize, 6, 9, 13, 17, 22, 27, 31] {
            print!("| {:.3} |", lobe_entry_coords(0, a).1);
            for t in ts {
                let (fitted, single) = lobe_fit_error(t, a, 4096);
                print!(" {fitted:.3} ({single:.3}) |");
            }
            println!();
        }
        return Ok(());
    }
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(LOBES_FILE);
    let t = std::time::Instant::now();
    let bytes = luz_core::env::generate_lobe_table();
    std::fs::write(&path, &bytes)?;
    println!(
        "wrote {} ({} bytes, {}² entries) in {:.1} s",
        path.display(),
        bytes.len(),
        LOBES_SIZE,
        t.elapsed().as_secs_f64()
    );
    Ok(())
}
