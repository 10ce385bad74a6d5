//! Fits KHR_materials_sheen's albedo E_sheen(n·v, sheenRoughness) and writes the fit's GLSL
//! (`shaders_glsl/brdf/sheen_albedo.glsl`, which the CPU reads too):
//! `cargo run --release -p luz-core --example sheen_fit`. It prints the new fit's largest error
//! against the integral on the grid of `brdf::tests::sheen_albedo_fit_is_the_integral`.

use luz_core::brdf::{fit_sheen_albedo, sheen_albedo_glsl_source, sheen_albedo_integrated};

fn main() -> std::io::Result<()> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shaders_glsl/brdf/sheen_albedo.glsl");
    let t = std::time::Instant::now();
    let c = fit_sheen_albedo();
    std::fs::write(&path, sheen_albedo_glsl_source(&c))?;
    println!(
        "wrote {} ({} coefficients) in {:.1} s",
        path.display(),
        c.len(),
        t.elapsed().as_secs_f64()
    );
    // The written fit, evaluated as luz_core::brdf::sheen_albedo does (that one reads the
    // file compiled in).
    let eval = |n_v: f32, r: f32| {
        let (u, t) = luz_core::brdf::sheen_fit_variables(n_v, r);
        let (nx, ns) = (luz_core::brdf::SHEEN_FIT_X, luz_core::brdf::SHEEN_FIT_S);
        let mut p = 0.0f32;
        for a in (0..nx).rev() {
            let mut q = 0.0f32;
            for b in (0..ns).rev() {
                q = q * t + c[a * ns + b];
            }
            p = p * u + q;
        }
        p.exp()
    };
    let (mut worst, mut at) = (0.0f32, (0.0, 0.0));
    for j in 0..34 {
        let r = j as f32 / 33.0;
        for i in 0..64 {
            let x = (i as f32 + 0.5) / 64.0;
            if x * x < 89f32.to_radians().cos() {
                continue;
            }
            let d = (eval(x * x, r) - sheen_albedo_integrated(x * x, r)).abs();
            if d > worst {
                (worst, at) = (d, (x * x, r));
            }
        }
    }
    println!(
        "largest error {worst:.4} at n·v {:.3}, roughness {:.3}",
        at.0, at.1
    );
    Ok(())
}
