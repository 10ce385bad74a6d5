//! Fits the GPU's Λ_sheen (a polynomial for the specification's `L`, issue 34's sheen cost) and
//! writes its GLSL (`shaders_glsl/brdf/sheen_lambda.glsl`, which the CPU reads too):
//! `cargo run --release -p luz-core --example sheen_lambda_fit`. It prints the new fit's largest
//! relative error in Λ and in the visibility against the specification's, on the grid of
//! `brdf::tests::sheen_lambda_fit_is_lambda`.

use luz_core::brdf::{fit_sheen_lambda, sheen_lambda_fit_error, sheen_lambda_glsl_source};

fn main() -> std::io::Result<()> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shaders_glsl/brdf/sheen_lambda.glsl");
    let f = fit_sheen_lambda();
    std::fs::write(&path, sheen_lambda_glsl_source(&f))?;
    println!("wrote {} ({} coefficients)", path.display(), f.c.len());
    let e = sheen_lambda_fit_error(&f);
    println!(
        "largest relative error: Λ {:.2e} (where Λ ≥ 1e-3), visibility {:.2e} (α {:.4}, n·l {:.4}, n·v {:.4})",
        e.lambda, e.visibility, e.at.0, e.at.1, e.at.2
    );
    Ok(())
}
