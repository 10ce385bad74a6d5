//! Glass on the GPU (issue 35): the screen-space refraction of `include/transmission.glsl`
//! through the frame graph's copy of the opaque scene, against closed forms and the CPU
//! reference. Every GPU test asserts a clean validation log (synchronization checks included
//! under `scripts/test.sh`).
//!
//! - Energy: clear glass (volume and thin-walled, roughness 0 and 0.5) in a uniform environment
//!   of 1, shown, returns 1: what the surface reflects (the split sum's E) plus (1 − E) × the copy,
//!   which is 1 everywhere.
//! - Beer–Lambert: through the centre of a sphere of thickness 2, E + (1 − E) exp(−2σ), E read off
//!   the same sphere over a black background.
//! - Against the reference: a thin-walled pane in front of coloured bars (where the screen-space
//!   method is the reference's model: straight through, weighted by 1 − E) within 3 % relative
//!   RMSE; a solid sphere, where it is not (no second refraction, no inversion), published and
//!   held at its measured error.
//! - Shadows: transmissive objects cast opaque shadows on the GPU as in the reference (shadow
//!   rays stop at glass; no caustics): the floor under a glass sphere matches.

mod common;

use glam::Vec3;
use luz::reference::{render_reference, ReferenceOptions};
use luz::scene::{Refraction, Scene};

use common::{assert_no_validation_messages, gpu, parse, render_on};

fn luminance(p: [f32; 4]) -> f32 {
    0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
}

/// A unit sphere of `material` seen from z = 3 (`environment` JSON), 49×49, MSAA 1.
fn sphere_scene(material: &str, environment: &str) -> Scene {
    parse(&format!(
        r#"{{
        "camera": {{"position": [0, 0, 3], "target": [0, 0, 0], "fov_y_deg": 40}},
        "output": {{"width": 49, "height": 49, "msaa": 1}},
        "materials": {{"m": {material}}},
        "objects": [{{"mesh": {{"type": "sphere", "radius": 1}}, "material": "m"}}],
        "environment": {environment}
    }}"#
    ))
}

const UNIFORM: &str = r#"{"uniform": [1, 1, 1]}"#;

fn glass(roughness: f32, extra: &str) -> String {
    format!(
        r#"{{"model": "metal_rough", "base_color": [1, 1, 1], "metallic": 0, "roughness": {roughness},
        "transmission": {{"transmissionFactor": 1}}{extra}}}"#
    )
}

/// Clear glass in a uniform environment of 1 that the camera also sees: every pixel, on the
/// sphere and around it, is 1 within 1 % (volume and thin-walled; smooth and rough; through the
/// copy of the screen and through the environment).
#[test]
fn clear_glass_in_a_uniform_environment_returns_it() {
    let ctx = gpu();
    for (roughness, extra) in [
        (0.0, r#", "volume": {"thicknessFactor": 2}"#),
        (0.5, r#", "volume": {"thicknessFactor": 2}"#),
        (0.0, ""),
        (0.5, ""),
    ] {
        for refraction in [Refraction::Screen, Refraction::Environment] {
            let mut scene = sphere_scene(&glass(roughness, extra), UNIFORM);
            scene.output.refraction = refraction;
            let img = render_on(&ctx, &scene);
            let worst = img
                .pixels
                .iter()
                .flat_map(|p| p[..3].iter())
                .fold(0.0f32, |w, &c| w.max((c - 1.0).abs()));
            assert!(
                worst <= 0.01,
                "{refraction:?}, roughness {roughness}{extra}: worst |pixel − 1| = {worst}"
            );
            let centre = img.pixel(24, 24);
            assert!((centre[1] - 1.0).abs() <= 0.01, "{centre:?}");
        }
    }
    assert_no_validation_messages(&ctx);
}

/// Absorption through the centre of a sphere of radius 1 with thickness 2: E + (1 − E) e^(−2σ),
/// σ = −ln(attenuationColor) / attenuationDistance per channel, within 0.5 % of the pixel. E is
/// the same sphere's centre over a black background (nothing to transmit).
#[test]
fn absorption_through_the_centre_is_beer_lambert() {
    let ctx = gpu();
    let colour = Vec3::new(0.2, 0.6, 0.9);
    let distance = 1.5f32;
    let volume = format!(
        r#", "volume": {{"thicknessFactor": 2, "attenuationColor": [{}, {}, {}], "attenuationDistance": {distance}}}"#,
        colour.x, colour.y, colour.z
    );
    let seen = render_on(&ctx, &sphere_scene(&glass(0.0, &volume), UNIFORM)).pixel(24, 24);
    let hidden = r#"{"uniform": [1, 1, 1], "show_background": false}"#;
    let e = render_on(&ctx, &sphere_scene(&glass(0.0, &volume), hidden)).pixel(24, 24);
    for c in 0..3 {
        assert!(e[c] > 0.02 && e[c] < 0.06, "E = {e:?}");
        let sigma = -colour[c].ln() / distance;
        let want = e[c] + (1.0 - e[c]) * (-2.0 * sigma).exp();
        assert!(
            (seen[c] - want).abs() <= 0.005 * want,
            "channel {c}: {} against {want}",
            seen[c]
        );
    }
    assert_no_validation_messages(&ctx);
}

/// Relative RMSE √(Σ(a − b)² / Σ b²) over the RGB of every pixel, and the mean LDR FLIP.
fn errors(gpu: &luz::imageio::LinearImage, reference: &luz::imageio::LinearImage) -> (f64, f64) {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (a, b) in gpu.pixels.iter().zip(&reference.pixels) {
        for c in 0..3 {
            num += f64::from(a[c] - b[c]).powi(2);
            den += f64::from(b[c]).powi(2);
        }
    }
    let map = luz::compare::flip_map(
        &reference.pixels,
        &gpu.pixels,
        (gpu.width, gpu.height),
        (0.0, luz::color::Tonemap::KhronosNeutral),
    );
    let flip = map.values.iter().map(|&v| f64::from(v)).sum::<f64>() / map.values.len() as f64;
    ((num / den).sqrt(), flip)
}

/// Coloured bars behind `front` (an object JSON) under a uniform sky, 96×64, MSAA 1.
fn bars_scene(front: &str, material: &str) -> Scene {
    parse(&bars_json(front, material))
}

fn bars_json(front: &str, material: &str) -> String {
    format!(
        r#"{{
        "camera": {{"position": [0, 0, 4], "target": [0, 0, 0], "fov_y_deg": 40}},
        "output": {{"width": 96, "height": 64, "msaa": 1}},
        "materials": {{
            "glass": {material},
            "red": {{"model": "lambert", "albedo": [0.9, 0.1, 0.1]}},
            "blue": {{"model": "lambert", "albedo": [0.1, 0.2, 0.9]}}
        }},
        "objects": [
            {front},
            {{"mesh": {{"type": "cube", "size": 1}}, "scale": [0.4, 3, 0.2], "position": [-0.6, 0, -2], "material": "red"}},
            {{"mesh": {{"type": "cube", "size": 1}}, "scale": [0.4, 3, 0.2], "position": [0.6, 0, -2], "material": "blue"}}
        ],
        "lights": [{{"type": "directional", "direction": [0, 0, -1], "intensity": 2}}],
        "environment": {{"uniform": [0.5, 0.6, 0.7]}}
    }}"#
    )
}

/// GPU against the CPU reference: a thin-walled smooth pane (the same model on both sides) within
/// 3 % relative RMSE; a solid sphere (the screen-space approximation against true refraction)
/// held at its measured error. Prints both for docs/glass.md.
#[test]
fn gpu_glass_against_the_reference() {
    let ctx = gpu();
    let opts = ReferenceOptions {
        samples: 256,
        ..Default::default()
    };
    let pane = r#"{"mesh": {"type": "plane", "size": [2.4, 1.6]}, "rotation_deg": [90, 0, 0], "material": "glass"}"#;
    let sphere = r#"{"mesh": {"type": "sphere", "radius": 0.8}, "material": "glass"}"#;
    let volume = r#", "volume": {"thicknessFactor": 1.6}"#;
    for (name, front, material, bound) in [
        ("thin pane", pane, glass(0.0, ""), 0.03),
        ("solid sphere", sphere, glass(0.0, volume), 0.25),
    ] {
        let scene = bars_scene(front, &material);
        let img = render_on(&ctx, &scene);
        let reference = render_reference(&scene, &opts, None).unwrap();
        let (rmse, flip) = errors(&img, &reference);
        println!(
            "{name}: relative RMSE {:.2} %, mean FLIP {flip:.4}",
            rmse * 100.0
        );
        assert!(rmse <= bound, "{name}: relative RMSE {rmse} > {bound}");
        // Not trivially right: the glass changes the image (against the same scene without it).
        let bare = bars_scene(
            r#"{"mesh": {"type": "sphere", "radius": 0.01}, "position": [0, 0, 3], "material": "red"}"#,
            &material,
        );
        let (without, _) = errors(&render_on(&ctx, &bare), &reference);
        assert!(
            without > 2.0 * rmse,
            "{name}: {without} without the glass, {rmse} with"
        );
    }
    assert_no_validation_messages(&ctx);
}

/// The largest difference between `a` and `b` over the columns `columns`, every row, RGB.
fn max_diff(
    a: &luz::imageio::LinearImage,
    b: &luz::imageio::LinearImage,
    columns: std::ops::Range<u32>,
) -> f32 {
    let mut m = 0.0f32;
    for y in 0..a.height {
        for x in columns.clone() {
            let (p, q) = (a.pixel(x, y), b.pixel(x, y));
            for c in 0..3 {
                m = m.max((p[c] - q[c]).abs());
            }
        }
    }
    m
}

/// Glass's maps (issue 35: `transmission`, `thickness`, `diffuse_transmission_color`; the
/// glTF textures load into them, tests/gltf.rs). A thin pane whose map is black on its left half
/// and white on its right (2×1, nearest) renders, half by half away from the seam, as the pane
/// with the factor at 0 and at 1, within 1e-3; the transmission-mapped pane matches the CPU
/// reference (which samples the same map) within the untextured pane's 3 %. A solid sphere with
/// a black thickness map renders as the thin-walled sphere, with a white one as the factor's
/// thickness.
#[test]
fn glass_maps_scale_their_factors() {
    let dir = common::scratch("glass-maps");
    let px = |v: u8| image::Rgba([v, v, v, 255]);
    image::RgbaImage::from_fn(2, 1, |x, _| px(if x == 0 { 0 } else { 255 }))
        .save(dir.join("split.png"))
        .unwrap();
    for (name, v) in [("black.png", 0), ("white.png", 255)] {
        image::RgbaImage::from_pixel(1, 1, px(v))
            .save(dir.join(name))
            .unwrap();
    }
    let at = |json: String| {
        luz::scene::parse(&json, &dir.join("scene.json")).unwrap_or_else(|e| panic!("{e}"))
    };
    let split = |slot: &str| {
        format!(
            r#", "textures": {{"{slot}": {{"path": "split.png", "filter": "nearest", "mipmaps": false, "wrap": "clamp"}}}}"#
        )
    };
    let ctx = gpu();
    let pane = r#"{"mesh": {"type": "plane", "size": [2.4, 1.6]}, "rotation_deg": [90, 0, 0], "material": "glass"}"#;
    let diffuse = |color: &str, extra: &str| {
        format!(
            r#"{{"model": "metal_rough", "base_color": [1, 1, 1], "metallic": 0, "roughness": 0.5,
            "diffuse_transmission": {{"diffuseTransmissionFactor": 1, "diffuseTransmissionColorFactor": {color}}}{extra}}}"#
        )
    };
    let transmission = |factor: f32, extra: &str| {
        format!(
            r#"{{"model": "metal_rough", "base_color": [1, 1, 1], "metallic": 0, "roughness": 0,
            "transmission": {{"transmissionFactor": {factor}}}{extra}}}"#
        )
    };
    let cases = [
        (
            "transmission",
            transmission(1.0, &split("transmission")),
            transmission(0.0, ""),
            transmission(1.0, ""),
        ),
        (
            "diffuse transmission colour",
            diffuse("[1, 1, 1]", &split("diffuse_transmission_color")),
            diffuse("[0, 0, 0]", ""),
            diffuse("[1, 1, 1]", ""),
        ),
    ];
    for (name, mapped, left, right) in cases {
        let img = render_on(&ctx, &at(bars_json(pane, &mapped)));
        let (l, r) = (
            render_on(&ctx, &at(bars_json(pane, &left))),
            render_on(&ctx, &at(bars_json(pane, &right))),
        );
        let (dl, dr) = (max_diff(&img, &l, 0..44), max_diff(&img, &r, 52..96));
        println!("{name}: left half {dl:.2e} from factor 0, right half {dr:.2e} from factor 1");
        assert!(dl < 1e-3 && dr < 1e-3, "{name}: {dl} / {dr}");
        // Not trivially equal: the two factors differ on the pane.
        let apart = max_diff(&l, &r, 30..66);
        assert!(
            apart > 0.05,
            "{name}: factor 0 and 1 differ by {apart} only"
        );
        if name == "transmission" {
            let opts = ReferenceOptions {
                samples: 256,
                ..Default::default()
            };
            let scene = at(bars_json(pane, &mapped));
            let reference = render_reference(&scene, &opts, None).unwrap();
            let (rmse, flip) = errors(&img, &reference);
            println!(
                "mapped pane against the reference: relative RMSE {:.2} %, FLIP {flip:.4}",
                rmse * 100.0
            );
            assert!(rmse <= 0.03, "mapped pane: relative RMSE {rmse}");
        }
    }
    // Thickness: a black map makes the sphere thin-walled; a white one keeps the factor's.
    let sphere = r#"{"mesh": {"type": "sphere", "radius": 0.8}, "material": "glass"}"#;
    let volume = |map: &str| {
        let textures = match map {
            "" => String::new(),
            m => format!(r#", "textures": {{"thickness": "{m}"}}"#),
        };
        glass(
            0.0,
            &format!(r#", "volume": {{"thicknessFactor": 1.6}}{textures}"#),
        )
    };
    let solid = render_on(&ctx, &at(bars_json(sphere, &volume(""))));
    let thin = render_on(&ctx, &at(bars_json(sphere, &glass(0.0, ""))));
    let black = render_on(&ctx, &at(bars_json(sphere, &volume("black.png"))));
    let white = render_on(&ctx, &at(bars_json(sphere, &volume("white.png"))));
    let (db, dw) = (
        max_diff(&black, &thin, 0..96),
        max_diff(&white, &solid, 0..96),
    );
    println!("thickness: black map {db:.2e} from thin-walled, white map {dw:.2e} from the factor");
    assert!(db < 1e-3 && dw < 1e-3, "thickness maps: {db} / {dw}");
    assert!(max_diff(&thin, &solid, 0..96) > 0.05);
    assert_no_validation_messages(&ctx);
}

/// Shadows under glass: a transmissive sphere casts an opaque shadow on the floor on the GPU, as
/// in the reference (its shadow rays stop at glass). The floor under the sphere is as dark in
/// both (within 2 % of the lit floor), and darker than the lit floor.
#[test]
fn glass_casts_an_opaque_shadow_like_the_reference() {
    let ctx = gpu();
    let scene = parse(&format!(
        r#"{{
        "camera": {{"position": [0, 4, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 50}},
        "output": {{"width": 64, "height": 64, "msaa": 1}},
        "materials": {{"glass": {}, "floor": {{"model": "lambert", "albedo": [0.8, 0.8, 0.8]}}}},
        "objects": [
            {{"mesh": {{"type": "plane", "size": [6, 6]}}, "material": "floor"}},
            {{"mesh": {{"type": "sphere", "radius": 0.5}}, "position": [1, 1, 0], "material": "glass"}}
        ],
        "lights": [{{"type": "directional", "direction": [-1, -1, 0], "intensity": 3, "shadow": true}}],
        "ambient": [0.2, 0.2, 0.2]
    }}"#,
        glass(0.0, r#", "volume": {"thicknessFactor": 1}"#)
    ));
    let img = render_on(&ctx, &scene);
    let reference = render_reference(&scene, &ReferenceOptions::default(), None).unwrap();
    // The light travels down and towards −x: the sphere at (1, 1, 0) shadows an ellipse around
    // the origin (x within ±0.7, z within ±0.5), beside the sphere as the camera (looking down
    // the y axis, x to the right, z down the image) sees it. Sample it at x = −0.3 and the lit
    // floor at x = −2.
    let at = |x: f32, z: f32| {
        let (w, h) = (img.width as f32, img.height as f32);
        let half = (25.0f32.to_radians()).tan() * 4.0;
        let px = ((x / half) * 0.5 + 0.5) * w;
        let py = ((z / half) * 0.5 + 0.5) * h;
        (px as u32, py as u32)
    };
    let (sx, sy) = at(-0.3, 0.0);
    let (lx, ly) = at(-2.0, 0.0);
    let lit = luminance(reference.pixel(lx, ly));
    let (gs, rs) = (
        luminance(img.pixel(sx, sy)),
        luminance(reference.pixel(sx, sy)),
    );
    assert!(
        rs < 0.5 * lit,
        "the reference's shadow: {rs} against {lit} lit"
    );
    assert!(
        (gs - rs).abs() <= 0.02 * lit,
        "GPU {gs} against the reference's {rs} in the shadow ({lit} lit)"
    );
    assert_no_validation_messages(&ctx);
}

/// Cost (issue 35: the transmission node and its draws ≤ 1.5× the same scene drawn opaque),
/// measured in one run: `assets/scenes/glass/spheres.json` under every `output.refraction`,
/// frames alternating between them, the median of the GPU passes that draw the scene (forward,
/// transmission copy, transmissive) over 31 frames each. A timing, so ignored in the suite:
/// `cargo test --release --test glass_gpu -- --ignored --nocapture`. Asserts the ratio only.
#[test]
#[ignore]
fn glass_cost() {
    let ctx = gpu();
    let path = common::root().join("assets/scenes/glass/spheres.json");
    let base = luz::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let methods = luz::scene::Refraction::ALL;
    let mut renderers: Vec<_> = methods
        .iter()
        .map(|&r| {
            let mut s = base.clone();
            s.output.refraction = r;
            luz::headless::Headless::new(&ctx, &s).expect("renderer")
        })
        .collect();
    let medians = common::interleaved_pass_medians(&mut renderers, 3, 31, |n| {
        n.contains("forward") || n.contains("transmission") || n.contains("transmissive")
    });
    drop(renderers);
    assert_no_validation_messages(&ctx);
    let opaque = medians[methods.len() - 1];
    eprintln!("| refraction | scene passes, median GPU ms | × drawn opaque |\n|---|---:|---:|");
    for (r, m) in methods.iter().zip(&medians) {
        eprintln!("| `{}` | {m:.2} | {:.2} |", r.name(), m / opaque);
    }
    assert!(
        medians[0] <= 1.5 * opaque,
        "screen-space refraction {:.2} ms against {opaque:.2} ms drawn opaque",
        medians[0]
    );
}
