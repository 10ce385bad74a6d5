//! The shadow stability sweep (issue 15): grazing light up to 89° from the receiver's normal,
//! casters resting on their receiver, the whole scene scaled from 1e-3 to 1e3, lights inside the
//! casters' bounds, a spot of 179° and a point light inside a closed sphere — for each method
//! (hard, PCF, PCSS): no NaN or Inf, no crash, the validation layer silent, and no acne beyond the
//! stated bound: outside a band of [`Method::band`] pixels around the reference's shadow edges,
//! ≥ 99.5 % of lit receiver pixels and ≥ 99.5 % of shadowed ones within 2 % of the reference
//! (lit, umbra and penumbra pixels from antialiased references, [`CLASS_SPP`] rays per pixel;
//! values from one ray through the pixel's centre, as the GPU samples).
//! Configurations that do not meet the bound are listed in [`KNOWN_FAILURES`] with their numbers
//! (docs/shadow-lab.md), and the test fails if that list is no longer exact.

mod common;

use common::shadow_judge::{judge, light_classes, luminance, Judged, LIT, UMBRA};
use common::*;
use luz::imageio::LinearImage;
use luz::reference::{render_reference, ReferenceOptions};

const W: u32 = 160;
const H: u32 = 120;

/// The reference with one ray through each pixel's centre, as the GPU images (MSAA 1) sample.
fn reference(json: &str) -> LinearImage {
    render_reference(&parse(json), &ReferenceOptions::default(), None).expect("reference")
}

/// Primary rays per pixel of the references that say which pixels are lit, umbra or penumbra:
/// a pixel is umbra only when no light reaches any part of it. One ray per pixel calls a pixel
/// umbra when its centre misses a thin gap of light crossing it (at 75°, between the sphere's and
/// the cube's shadows, docs/shadow-lab.md).
const CLASS_SPP: u32 = 16;

fn reference_antialiased(json: &str) -> LinearImage {
    let options = ReferenceOptions {
        spp: CLASS_SPP,
        ..ReferenceOptions::default()
    };
    render_reference(&parse(json), &options, None).expect("reference")
}

/// `[x, y, z]` times `s`.
fn v(p: [f32; 3], s: f32) -> String {
    format!("[{:e}, {:e}, {:e}]", p[0] * s, p[1] * s, p[2] * s)
}

/// A Lambert floor, a sphere and a cube resting on it (contact), everything scaled by `s`;
/// `extra` adds objects (JSON, leading comma). The sphere has 256 × 128 segments: its silhouette
/// is within 0.2 mm (at scale 1) of the reference's exact sphere in every map, where the
/// automatic tessellation for a 160×120 view (39 × 19) falls up to ~1 cm inside it and opens a
/// gap of light the exact scene does not have.
fn scene(lights: &str, s: f32, extra: &str) -> String {
    format!(
        r#"{{
        "camera": {{"position": {}, "target": {}, "up": [0, 1, 0], "fov_y_deg": 50, "near": {:e}, "far": {:e}}},
        "output": {{"width": {W}, "height": {H}, "background": [0, 0, 0], "msaa": 1}},
        "ambient": [0.05, 0.05, 0.05],
        "lights": [{lights}],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.8, 0.8, 0.8]}}}},
        "objects": [
            {{"mesh": {{"type": "plane", "size": [{:e}, {:e}]}}, "material": "m"}},
            {{"mesh": {{"type": "sphere", "radius": {:e}, "segments": 256, "rings": 128}}, "material": "m", "position": {}}},
            {{"mesh": {{"type": "cube", "size": {:e}}}, "material": "m", "position": {}, "rotation_deg": [0, 30, 0]}}{extra}
        ]
    }}"#,
        v([0.5, 4.0, 5.0], s),
        v([0.2, 0.2, 0.0], s),
        0.1 * s,
        40.0 * s,
        16.0 * s,
        16.0 * s,
        0.7 * s,
        v([0.0, 0.7, 0.0], s),
        0.8 * s,
        v([1.5, 0.4, -0.8], s),
    )
}

/// One configuration: a name, its single light (JSON with `SHADOW` where the shadow and size
/// keys go), the scene scale and extra objects.
struct Case {
    name: String,
    light: String,
    scale: f32,
    extra: String,
    /// The light is sealed inside a closed sphere: nothing outside it may receive its light.
    sealed: bool,
}

fn directional(theta_deg: f32, s: f32) -> Case {
    let t = theta_deg.to_radians();
    // Constant irradiance on the floor, whatever the angle.
    let intensity = 2.0 / t.cos();
    Case {
        name: format!("directional {theta_deg}° from the normal, scale {s:e}"),
        light: format!(
            r#"{{"type": "directional", "direction": [{}, {}, {}], "intensity": {intensity} SHADOW}}"#,
            t.sin() * 0.94,
            -t.cos(),
            t.sin() * 0.34
        ),
        scale: s,
        extra: String::new(),
        sealed: false,
    }
}

fn spot(name: &str, pos: [f32; 3], target: [f32; 3], umbra: f32, inner: f32, s: f32) -> Case {
    Case {
        name: format!("{name}, scale {s:e}"),
        light: format!(
            r#"{{"type": "spot", "position": {}, "target": {}, "umbra_deg": {umbra}, "inner_deg": {inner}, "intensity": {:e} SHADOW}}"#,
            v(pos, s),
            v(target, s),
            40.0 * s * s
        ),
        scale: s,
        extra: String::new(),
        sealed: false,
    }
}

fn point(name: &str, pos: [f32; 3], s: f32) -> Case {
    Case {
        name: format!("{name}, scale {s:e}"),
        light: format!(
            r#"{{"type": "point", "position": {}, "intensity": {:e} SHADOW}}"#,
            v(pos, s),
            15.0 * s * s
        ),
        scale: s,
        extra: String::new(),
        sealed: false,
    }
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for theta in [30.0, 60.0, 75.0, 80.0, 85.0, 87.0, 88.0, 89.0] {
        out.push(directional(theta, 1.0));
    }
    for s in [1e-3, 1e-2, 1e2, 1e3] {
        out.push(directional(45.0, s));
    }
    for s in [1e-3, 1.0, 1e3] {
        out.push(spot(
            "spot 35°",
            [1.5, 3.0, 1.5],
            [0.3, 0.0, -0.2],
            35.0,
            25.0,
            s,
        ));
    }
    // Between the sphere and the cube, below the cube's top: inside the casters' bounds.
    out.push(point(
        "point inside the casters' bounds",
        [0.75, 0.5, -0.1],
        1.0,
    ));
    out.push(spot(
        "spot inside the casters' bounds",
        [0.75, 0.5, -0.1],
        [0.75, 0.0, 0.6],
        50.0,
        40.0,
        1.0,
    ));
    out.push(spot(
        "spot 179° (umbra 89.5°)",
        [0.3, 2.5, 0.6],
        [0.3, 0.0, 0.6],
        89.5,
        80.0,
        1.0,
    ));
    let mut sealed = point("point inside a closed sphere", [-2.0, 1.0, 1.0], 1.0);
    sealed.extra = format!(
        r#", {{"mesh": {{"type": "sphere", "radius": 0.5, "segments": 32, "rings": 16}}, "material": "m", "position": {}}}"#,
        v([-2.0, 1.0, 1.0], 1.0)
    );
    sealed.sealed = true;
    out.push(sealed);
    out
}

/// A method: name, shadow settings, whether its light has a size, and the stated band
/// (pixels at 160×120) outside which the acne bound must hold.
struct Method {
    name: &'static str,
    shadow: &'static str,
    sized: bool,
    band: i32,
}

const METHODS: [Method; 3] = [
    Method {
        name: "hard",
        shadow: r#"{"method": "hard"}"#,
        sized: false,
        band: 2,
    },
    Method {
        name: "pcf",
        shadow: "true",
        sized: false,
        band: 3,
    },
    Method {
        name: "pcss",
        shadow: r#"{"method": "pcss"}"#,
        sized: true,
        band: 4,
    },
];

/// Other settings on the two configurations that once failed (configuration, method); each must
/// meet the stated bound (docs/shadow-lab.md).
const DIAGNOSTICS: [(&str, Method); 4] = [
    (
        "directional 75° from the normal, scale 1e0",
        Method {
            name: "pcf at 2048²",
            shadow: r#"{"method": "pcf", "resolution": 2048}"#,
            sized: false,
            band: 3,
        },
    ),
    (
        "directional 75° from the normal, scale 1e0",
        Method {
            name: "pcf with 4 cascades",
            shadow: r#"{"method": "pcf", "cascades": 4}"#,
            sized: false,
            band: 3,
        },
    ),
    (
        "directional 89° from the normal, scale 1e0",
        Method {
            name: "pcss with pcf_kernel 1 (largest filter 4 texels)",
            shadow: r#"{"method": "pcss", "pcf_kernel": 1}"#,
            sized: true,
            band: 4,
        },
    ),
    (
        "directional 89° from the normal, scale 1e0",
        Method {
            name: "pcss with normal_bias 4",
            shadow: r#"{"method": "pcss", "normal_bias": 4}"#,
            sized: true,
            band: 4,
        },
    ),
];

/// Configurations measured not to meet the bound (case name, method), documented with their
/// numbers in docs/shadow-lab.md.
/// None since 2026-11-25: PCF at 75° (98.03 % of 1374 umbra pixels at 3 px) failed on light
/// the exact scene has too, a gap narrower than a pixel between the sphere's and the cube's
/// shadows that one ray per pixel missed, widened by the sphere's automatic tessellation
/// (docs/shadow-lab.md).
const KNOWN_FAILURES: &[(&str, &str)] = &[];

/// The case's light with `shadow` (or none) and a size (0.1 m radius scaled, 1° angular radius).
fn light(case: &Case, shadow: Option<&str>, sized: bool) -> String {
    let mut s = match shadow {
        Some(sh) => format!(r#", "shadow": {sh}"#),
        None => String::new(),
    };
    if sized {
        s += &if case.light.contains("directional") {
            r#", "angular_radius_deg": 1.0"#.to_string()
        } else {
            format!(r#", "radius": {:e}"#, 0.1 * case.scale)
        };
    }
    case.light.replace(" SHADOW", &s)
}

fn json(case: &Case, lights: &str) -> String {
    scene(lights, case.scale, &case.extra)
}

/// The judge's classes: lit or umbra; penumbra and pixels the light does not reach are not
/// judged.
fn kind(c: u8) -> Option<bool> {
    match c {
        LIT => Some(true),
        UMBRA => Some(false),
        _ => None,
    }
}

fn pct(a: usize, b: usize) -> String {
    if b == 0 {
        "–".into()
    } else {
        format!("{:.2} % of {b}", 100.0 * a as f64 / b as f64)
    }
}

#[test]
fn shadows_stay_finite_and_free_of_acne_across_the_sweep() {
    let ctx = gpu();
    let mut table = Vec::new();
    let mut failures = Vec::new();
    let mut out_of_bound = Vec::new();
    for case in cases() {
        let none = reference(&json(&case, ""));
        let plain_json = json(&case, &light(&case, None, false));
        let ref_plain = reference(&plain_json);
        let gpu_plain = render_on(&ctx, &parse(&plain_json));
        let gpu_none = render_on(&ctx, &parse(&json(&case, "")));
        // The classes' references (not needed for the sealed light, which is judged whole).
        let (none_aa, plain_aa) = if case.sealed {
            (none.clone(), ref_plain.clone())
        } else {
            (
                reference_antialiased(&json(&case, "")),
                reference_antialiased(&plain_json),
            )
        };
        let mut refs: [Option<LinearImage>; 2] = [None, None];
        let mut refs_aa: [Option<LinearImage>; 2] = [None, None];
        let methods = METHODS.iter().chain(
            DIAGNOSTICS
                .iter()
                .filter(|(c, _)| *c == case.name)
                .map(|(_, m)| m),
        );
        for m in methods {
            let shadowed = json(&case, &light(&case, Some(m.shadow), m.sized));
            let img = render_on(&ctx, &parse(&shadowed));
            let nan = nan_count(&img);
            if nan > 0 {
                failures.push(format!("{}: {}: {nan} NaN/Inf pixels", case.name, m.name));
            }
            let reference = refs[m.sized as usize].get_or_insert_with(|| reference(&shadowed));
            if nan_count(reference) > 0 {
                failures.push(format!("{}: {}: NaN in the reference", case.name, m.name));
            }
            if case.sealed {
                // Nothing outside the sphere receives the light: the image is the one without
                // it (ambient only), on the GPU as in the reference.
                let worst = |a: &LinearImage, b: &LinearImage| {
                    a.pixels
                        .iter()
                        .zip(&b.pixels)
                        .map(|(p, q)| {
                            let (l, r) = (luminance(*p), luminance(*q));
                            (l - r).abs() / r.max(1e-3)
                        })
                        .fold(0.0f32, f32::max)
                };
                let (g, r) = (worst(&img, &gpu_none), worst(reference, &none));
                // Without the shadow the light does reach the floor: the check can see a leak.
                let open = worst(&gpu_plain, &gpu_none);
                if open < 0.5 {
                    failures.push(format!(
                        "{}: unshadowed, the light changes nothing ({open:.2e}): no test",
                        case.name
                    ));
                }
                table.push(format!(
                    "| {} | {} | dark: largest relative difference from the unlit image {g:.2e} (reference {r:.2e}) | | |",
                    case.name, m.name
                ));
                if g > 0.02 || r > 0.02 {
                    failures.push(format!(
                        "{}: {}: light escapes the sphere: GPU {g:.3e}, reference {r:.3e}",
                        case.name, m.name
                    ));
                }
                continue;
            }
            let with_aa =
                refs_aa[m.sized as usize].get_or_insert_with(|| reference_antialiased(&shadowed));
            let class = light_classes(&none_aa, with_aa, &plain_aa);
            let judge = |band| -> Judged {
                let images = (&img, &*reference);
                judge(&class, (W, H), kind, images, (&gpu_plain, &ref_plain), band)
            };
            let found = (0..=16).find_map(|band| {
                let j = judge(band);
                j.passes().then_some((band, j))
            });
            let at_bound = judge(m.band);
            let band_text = match found {
                Some((b, _)) => format!("{b} px"),
                None => "> 16 px".into(),
            };
            table.push(format!(
                "| {} | {} | {band_text} | {} | {} |",
                case.name,
                m.name,
                pct(at_bound.lit_ok, at_bound.lit),
                pct(at_bound.dark_ok, at_bound.dark),
            ));
            // Enough receiver pixels outside the band and the penumbrae to judge (a sized light
            // close to the casters leaves mostly penumbra).
            if at_bound.lit + at_bound.dark < 100 || at_bound.lit == 0 {
                failures.push(format!(
                    "{}: {}: only {} lit and {} shadowed pixels judged",
                    case.name, m.name, at_bound.lit, at_bound.dark
                ));
            }
            if !at_bound.passes() {
                out_of_bound.push((case.name.clone(), m.name));
                // The images, to look at: target/shadow-stability/.
                let dir = root().join("target/shadow-stability");
                let stem: String = format!("{} {}", case.name, m.name)
                    .chars()
                    .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                    .collect();
                let _ = std::fs::create_dir_all(&dir);
                for (what, im) in [("gpu", &img), ("reference", &*reference)] {
                    let _ = luz::imageio::save(
                        &dir.join(format!("{stem}_{what}.png")),
                        im,
                        0.0,
                        luz::color::Tonemap::None,
                    );
                }
            }
        }
    }
    assert_no_validation_messages(&ctx);
    eprintln!("| configuration | method | narrowest band that passes | lit within 2 % (at the stated band) | shadowed within 2 % (at the stated band) |");
    eprintln!("|---|---|---|---|---|");
    for row in &table {
        eprintln!("{row}");
    }
    for (c, m) in &out_of_bound {
        if !KNOWN_FAILURES.iter().any(|(kc, km)| kc == c && km == m) {
            failures.push(format!("{c}: {m}: acne or leaks beyond the stated band"));
        }
    }
    for (kc, km) in KNOWN_FAILURES {
        if !out_of_bound.iter().any(|(c, m)| c == kc && m == km) {
            failures.push(format!(
                "{kc}: {km}: listed as a known failure but now within the bound: update docs/shadow-lab.md"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
