//! Image-based lighting on the CPU with a real HDR environment: `../shared/environments/
//! newport_loft.hdr` (not part of the project; the test says `SKIPPED` when it is absent).
//! Checks loading (size, finite, non-negative) and that 9-coefficient SH irradiance matches Monte
//! Carlo and quadrature irradiance at the six axis normals; prints timings.

mod common;

use std::time::Instant;

use glam::Vec3;
use luz::env::{
    irradiance_quadrature, irradiance_reference, load_equirect_with_report, sh9_irradiance,
    sh9_project, Equirect,
};
use luz::scene::{EnvSource, Environment};

use common::shared_dir;

fn load(max_dimension: u32) -> Option<Equirect> {
    let path = shared_dir("environments/newport_loft.hdr")?;
    let t = Instant::now();
    let env = Environment::new(EnvSource::Hdr(path));
    let (eq, report) = load_equirect_with_report(&env, max_dimension).expect("loads");
    println!(
        "loaded {}×{} (file {}×{}, downsampled ×{}, {} texels sanitised) in {:.1} ms",
        eq.width,
        eq.height,
        report.source_size.0,
        report.source_size.1,
        report.downsampled_by,
        report.sanitized_texels,
        t.elapsed().as_secs_f64() * 1e3
    );
    Some(eq)
}

#[test]
fn newport_loft_loads() {
    let Some(eq) = load(16384) else { return };
    assert_eq!((eq.width, eq.height), (1600, 800));
    assert_eq!(eq.texels.len(), 1600 * 800);
    assert!(eq.is_finite_non_negative());
    let max = eq.max_value();
    let mean = eq.integral() / (4.0 * std::f32::consts::PI);
    println!("max radiance {max:.1}, mean radiance {mean}");
    assert!(max > 1.0 && max < 65504.0, "{max}");
    assert!(mean.min_element() > 0.01, "{mean}");
    // The device limit is honoured by halving.
    let Some(small) = load(1000) else { return };
    assert_eq!((small.width, small.height), (800, 400));
    let rel = (small.integral() - eq.integral()).abs().max_element() / eq.integral().max_element();
    assert!(rel < 1e-3, "downsampling changed ∫L dω by {rel}");
}

#[test]
fn newport_loft_sh_irradiance_matches_monte_carlo() {
    let Some(eq) = load(16384) else { return };
    let t = Instant::now();
    let sh = sh9_project(&eq);
    println!(
        "SH projection of {}×{}: {:.1} ms",
        eq.width,
        eq.height,
        t.elapsed().as_secs_f64() * 1e3
    );
    let axes = [
        ("+x", Vec3::X),
        ("-x", Vec3::NEG_X),
        ("+y", Vec3::Y),
        ("-y", Vec3::NEG_Y),
        ("+z", Vec3::Z),
        ("-z", Vec3::NEG_Z),
    ];
    let mut failures = Vec::new();
    let t = Instant::now();
    for (name, n) in axes {
        let mc = irradiance_reference(&eq, n, 1 << 18);
        let quad = irradiance_quadrature(&eq, n);
        let s = sh9_irradiance(&sh, n);
        let lum = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        let err_mc = (lum(s) - lum(mc)).abs() / lum(mc);
        // Per channel, relative to the channel itself (dim channels suffer most from the
        // order-2 truncation) and relative to the brightest channel at that normal.
        let err_channels = ((s - mc).abs() / mc).max_element();
        let err_colour = (s - mc).abs().max_element() / mc.max_element();
        let mc_vs_quad = ((mc - quad).abs() / quad).max_element();
        println!(
            "n {name}: SH {s:.4} MC {mc:.4} quadrature {quad:.4}: SH−MC {:.2} % (luminance), {:.2} % (of the brightest channel), {:.2} % (worst channel, of itself); MC−quadrature {:.2} %",
            err_mc * 100.0,
            err_colour * 100.0,
            err_channels * 100.0,
            mc_vs_quad * 100.0
        );
        // 9 coefficients cannot follow the loft's bright windows exactly (MC agrees with the
        // quadrature to 0.03 %, so this is the SH truncation): luminance stays within 5 % (3.9 %
        // at +y), but a channel alone is off by up to 5.2 % of the brightest channel and 10 %
        // of itself (the dim blue channel facing the floor).
        if err_mc > 0.05 {
            failures.push(format!(
                "{name}: SH vs MC {:.2} % (luminance)",
                err_mc * 100.0
            ));
        }
        if err_channels > 0.12 {
            failures.push(format!(
                "{name}: SH vs MC {:.2} % (one channel)",
                err_channels * 100.0
            ));
        }
        if mc_vs_quad > 0.01 {
            failures.push(format!(
                "{name}: MC vs quadrature {:.2} %",
                mc_vs_quad * 100.0
            ));
        }
    }
    println!(
        "6 normals × (2^18 MC samples + quadrature): {:.1} ms",
        t.elapsed().as_secs_f64() * 1e3
    );
    assert!(failures.is_empty(), "{failures:#?}");
}
