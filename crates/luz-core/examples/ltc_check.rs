//! Prints how far the shipped LTC table's lobes are from GGX: per roughness (rows) and view
//! angle (columns), the relative L1 distance ∫|f_LTC − f_GGX| / ∫f_GGX over the hemisphere
//! (both `f·cos` without Fresnel). `cargo run --release -p luz-core --example ltc_check`;
//! docs/area-lights.md quotes it.

fn main() {
    use std::f64::consts::PI;
    let n = luz_core::brdf::LTC_SIZE;
    let ts = [0usize, 20, 32, 45, 55, 60];
    print!("roughness \\ θ_v");
    for t in ts {
        let x = t as f64 / (n - 1) as f64;
        print!(" | {:5.1}°", (1.0 - x * x).acos().to_degrees());
    }
    println!();
    for a in [6usize, 16, 24, 32, 40, 48, 56, 63] {
        print!("{:15.3}", a as f64 / (n - 1) as f64);
        for t in ts {
            let k = 128;
            let (mut diff, mut total) = (0.0, 0.0);
            for j in 0..k {
                for i in 0..k {
                    let z = (i as f64 + 0.5) / k as f64;
                    let phi = 2.0 * PI * (j as f64 + 0.5) / k as f64;
                    let s = (1.0 - z * z).sqrt();
                    let (fl, fb) =
                        luz_core::brdf::shipped_lobe(t, a, [s * phi.cos(), s * phi.sin(), z]);
                    diff += (fl - fb).abs();
                    total += fb;
                }
            }
            print!(" | {:6.3}", diff / total);
        }
        println!();
    }
}
