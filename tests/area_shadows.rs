//! Shadow maps of area lights on the GPU (issue 36, docs/area-lights.md#shadows): a Lambert plane
//! under a rect or a sphere emitter with a small sphere between them, on the forward and the
//! deferred path, against the CPU reference (which traces shadow rays to the emitter), on
//! lavapipe with the validation layer (zero messages). Each test prints its measured figures
//! (`-- --nocapture`); the tolerances are stated beside each assertion.

mod common;

use luz::imageio::LinearImage;
use luz::reference::{render_reference, ReferenceOptions};
use luz::scene::Scene;

use common::parse;

const W: u32 = 64;
const H: u32 = 48;

/// A Lambert plane (albedo 0.5) seen from above at a slant, `light` over it and, when `occluder`,
/// a Lambert sphere of radius 0.25 at (0, 0.4, 0) between them.
fn scene(light: &str, occluder: bool) -> Scene {
    let ball = if occluder {
        r#", {"mesh": {"type": "sphere", "radius": 0.25, "segments": 48}, "material": "m", "position": [0, 0.4, 0]}"#
    } else {
        ""
    };
    parse(&format!(
        r#"{{
        "camera": {{"position": [0.2, 4, 2.2], "target": [0, 0, 0], "fov_y_deg": 30}},
        "output": {{"width": {W}, "height": {H}, "msaa": 1}},
        "lights": [{light}],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.5, 0.5, 0.5]}}}},
        "objects": [{{"mesh": {{"type": "plane", "size": [40, 40]}}, "material": "m"}}{ball}]
    }}"#
    ))
}

/// `, "shadow": …` for a shadow's JSON; nothing for "null" (no shadow).
fn shadow_field(shadow: &str) -> String {
    if shadow == "null" {
        String::new()
    } else {
        format!(r#", "shadow": {shadow}"#)
    }
}

/// A 0.8 m × 0.6 m rect facing down at height 1.6, `shadow` as given ("null": none).
fn rect(shadow: &str) -> String {
    format!(
        r#"{{"type": "rect", "position": [0, 1.6, 0], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [0.8, 0.6], "intensity": 4, "visible": false{}}}"#,
        shadow_field(shadow)
    )
}

/// A sphere of radius 0.3 at height 1.7, `shadow` as given.
fn sphere(shadow: &str) -> String {
    format!(
        r#"{{"type": "sphere", "position": [0, 1.7, 0], "radius": 0.3, "intensity": 4, "visible": false, "method": "ltc"{}}}"#,
        shadow_field(shadow)
    )
}

fn reference(scene: &Scene, samples: u32) -> LinearImage {
    let opts = ReferenceOptions {
        samples,
        ..ReferenceOptions::default()
    };
    render_reference(scene, &opts, None).unwrap_or_else(|e| panic!("{e:#}"))
}

fn lum(p: &[f32; 4]) -> f64 {
    f64::from(p[0] + p[1] + p[2])
}

/// Per pixel: the fraction of the light `with` keeps of `without` (1 where `without` is dark).
fn visibility(with: &LinearImage, without: &LinearImage) -> Vec<f64> {
    with.pixels
        .iter()
        .zip(&without.pixels)
        .map(|(a, b)| if lum(b) > 1e-6 { lum(a) / lum(b) } else { 1.0 })
        .collect()
}

/// The reference's visibility classes: umbra (< 0.02), penumbra (0.05–0.95), lit (> 0.98);
/// pixel indices of each.
struct Classes {
    umbra: Vec<usize>,
    penumbra: Vec<usize>,
    lit: Vec<usize>,
}

fn classes(v: &[f64]) -> Classes {
    let pick = |f: &dyn Fn(f64) -> bool| {
        v.iter()
            .enumerate()
            .filter(|(_, &x)| f(x))
            .map(|(i, _)| i)
            .collect()
    };
    Classes {
        umbra: pick(&|x| x < 0.02),
        penumbra: pick(&|x| (0.05..=0.95).contains(&x)),
        lit: pick(&|x| x > 0.98),
    }
}

fn mean(idx: &[usize], f: &dyn Fn(usize) -> f64) -> f64 {
    idx.iter().map(|&i| f(i)).sum::<f64>() / idx.len().max(1) as f64
}

/// What one GPU image of a shadowed scene measures against the reference.
#[derive(Debug)]
struct Measured {
    /// Mean |V_gpu − V_ref| over the reference's penumbra pixels (visibility: the shadowed image
    /// over the same renderer's unshadowed one, so shading errors cancel).
    penumbra: f64,
    /// Mean and largest V_gpu over the reference's umbra.
    umbra_mean: f64,
    umbra_max: f64,
    /// Mean V_gpu over the reference's lit pixels.
    lit: f64,
    /// Mean 1 − V_gpu over umbra and penumbra: how much the shadow takes away.
    darkened: f64,
}

fn measure(v_gpu: &[f64], v_ref: &[f64]) -> Measured {
    let c = classes(v_ref);
    let both: Vec<usize> = c.umbra.iter().chain(&c.penumbra).copied().collect();
    Measured {
        penumbra: mean(&c.penumbra, &|i| (v_gpu[i] - v_ref[i]).abs()),
        umbra_mean: mean(&c.umbra, &|i| v_gpu[i]),
        umbra_max: c.umbra.iter().map(|&i| v_gpu[i]).fold(0.0, f64::max),
        lit: mean(&c.lit, &|i| v_gpu[i]),
        darkened: mean(&both, &|i| 1.0 - v_gpu[i]),
    }
}

/// The reference's visibility of `shadowed` (the light with a shadow: with the occluder against
/// without), NaN at the pixels that see the occluder itself (where `plain`, the light without a
/// shadow, differs with the occluder and without: no shadow rays there, so only the occluder's own
/// pixels change); and its pixel classes' sizes.
fn reference_visibility(shadowed: &str, plain: &str) -> Vec<f64> {
    let with = reference(&scene(shadowed, true), 1024);
    let without = reference(&scene(shadowed, false), 1024);
    let ball = reference(&scene(plain, true), 16);
    let bare = reference(&scene(plain, false), 16);
    let mut v = visibility(&with, &without);
    for (i, x) in v.iter_mut().enumerate() {
        if (lum(&ball.pixels[i]) - lum(&bare.pixels[i])).abs() > 1e-6 * lum(&bare.pixels[i]) {
            *x = f64::NAN;
        }
    }
    let c = classes(&v);
    eprintln!(
        "reference: {} umbra, {} penumbra, {} lit pixels of {}",
        c.umbra.len(),
        c.penumbra.len(),
        c.lit.len(),
        v.len()
    );
    assert!(
        c.umbra.len() >= 10 && c.penumbra.len() >= 40,
        "the scene has both"
    );
    v
}

/// Done-when (issue 36, "PCSS shadows use the emitter's size"): a rect and a sphere emitter with
/// a PCSS shadow (1024² per cube face, `pcf_kernel` 6: filters up to 24 texels) over a plane,
/// a small sphere between them. On both paths: over the reference's penumbra (its visibility
/// 0.05–0.95, 1024 directions per strategy) the GPU's visibility is within the bound of the
/// reference's (mean absolute difference: 0.088 rect, 0.034 sphere measured 2026-11-29; bounds
/// 0.10 and 0.045; hard shadows are 0.25 off, `hard_and_pcf_area_shadows`; docs/area-lights.md
/// has the figures); over its umbra the GPU's is below 0.1 on average and 0.2 at every pixel
/// (0.063 measured); over its lit pixels above 0.97; and the shadow takes away more than 40 % of
/// the light over umbra and penumbra (the same scene without a shadow takes away none, so the
/// test fails without the maps).
#[test]
fn pcss_area_shadows_match_the_reference() {
    let ctx = common::gpu();
    let pcss = r#"{"method": "pcss", "resolution": 1024, "pcf_kernel": 6}"#;
    let mut failures = Vec::new();
    for (name, light, bound) in [
        // Measured 2026-11-29: 0.0877 (rect: PCSS takes it for the disk of its area, the
        // penumbra's shape is the rect's) and 0.0340 (sphere), both paths alike.
        ("rect", rect as fn(&str) -> String, 0.10),
        ("sphere", sphere as fn(&str) -> String, 0.045),
    ] {
        let v_ref = reference_visibility(&light(pcss), &light("null"));
        let unshadowed = common::both_paths(&ctx, &scene(&light("null"), true));
        let without = common::both_paths(&ctx, &scene(&light(pcss), false));
        let with = common::both_paths(&ctx, &scene(&light(pcss), true));
        for (((path, w), (_, wo)), (_, un)) in with.iter().zip(&without).zip(&unshadowed) {
            let v_gpu = visibility(w, wo);
            let m = measure(&v_gpu, &v_ref);
            let un_v = visibility(un, wo);
            let un_m = measure(&un_v, &v_ref);
            eprintln!(
                "{name} PCSS, {path}: {m:?}; without a shadow: darkened {:.3}",
                un_m.darkened
            );
            if m.penumbra > bound
                || m.umbra_mean > 0.1
                || m.umbra_max > 0.2
                || m.lit < 0.97
                || m.darkened < 0.4
                || un_m.darkened > 0.01
            {
                failures.push(format!("{name} {path}: {m:?} (unshadowed {un_m:?})"));
            }
        }
    }
    common::assert_no_validation_messages(&ctx);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Hard and PCF shadows of an area light: a cube map from the emitter's centre gives the shadow
/// of that point (no penumbra), so over the reference's umbra the GPU's visibility is below 0.05
/// (hard) or 0.1 (PCF) on average, over its lit pixels above 0.97, and it darkens umbra and
/// penumbra together by more than 40 % (measured 2026-11-29: umbra 0, lit 1, darkened 0.45;
/// over the reference's penumbra 0.254 (hard) and 0.235 (PCF 2×2) off its visibility).
#[test]
fn hard_and_pcf_area_shadows() {
    let ctx = common::gpu();
    let v_ref = reference_visibility(&rect("true"), &rect("null"));
    let mut failures = Vec::new();
    for (method, umbra) in [
        (r#"{"method": "hard", "resolution": 512}"#, 0.05),
        (r#"{"method": "pcf", "resolution": 512}"#, 0.1),
    ] {
        let without = common::both_paths(&ctx, &scene(&rect(method), false));
        let with = common::both_paths(&ctx, &scene(&rect(method), true));
        for ((path, w), (_, wo)) in with.iter().zip(&without) {
            let m = measure(&visibility(w, wo), &v_ref);
            eprintln!("rect {method}, {path}: {m:?}");
            if m.umbra_mean > umbra || m.lit < 0.97 || m.darkened < 0.4 {
                failures.push(format!("{method} {path}: {m:?}"));
            }
        }
    }
    common::assert_no_validation_messages(&ctx);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// An area light without a shadow beside one with: the unshadowed one's light is untouched (its
/// record says "no shadow"), and a scene whose only shadow is an area light's leaves punctual
/// lights unshadowed: each pixel equals the sum of the lights rendered alone within 1e-3
/// relative (the HDR target's half floats).
#[test]
fn shadows_are_per_area_light() {
    let ctx = common::gpu();
    let pcss = r#"{"method": "pcss", "resolution": 512}"#;
    let point = r#"{"type": "point", "position": [0.5, 2.5, 0.3], "intensity": 10}"#;
    let shadowed = sphere(pcss);
    let plain = rect("null").replace("[0, 1.6, 0]", "[0.6, 1.6, -0.4]");
    let render = |lights: &str| common::render_on(&ctx, &scene(lights, true));
    let all = render(&format!("{shadowed}, {plain}, {point}"));
    let parts = [render(&shadowed), render(&plain), render(point)];
    let mut worst = 0f64;
    for (i, p) in all.pixels.iter().enumerate() {
        let sum: f64 = parts.iter().map(|img| lum(&img.pixels[i])).sum();
        if sum > 1e-3 {
            worst = worst.max((lum(p) - sum).abs() / sum);
        }
    }
    eprintln!("worst relative difference from the sum of the parts: {worst:.2e}");
    common::assert_no_validation_messages(&ctx);
    assert!(worst < 1e-3, "{worst}");
}

/// A visible rect (0.8 × 1.2 m, facing down at 1.5 m, with a shadow) under a point light with a
/// shadow (1 m above it), over a Lambert plane seen from straight above (48 × 36 px): the GPU's
/// maps hold the emitter for the point light, so under the rect the plane gets the rect's light
/// only, as the reference's shadow rays stop there; with `visible: false` it gets both. Pixels
/// whose plane point lies more than 0.1 m inside or outside the rect's shadow outline (from the
/// point light) are compared (the outline's PCF edge left out). On both paths: the GPU is within
/// 1 % relative L1 of the reference (1024 directions per strategy) inside and outside, for the
/// visible and the invisible rect; inside, the visible rect takes away more than 60 % of the
/// light (the point light's share) and the GPU's loss matches the reference's within 2 %;
/// outside it takes away less than 0.5 %. Zero validation messages.
#[test]
fn visible_emitter_shadows_other_lights_on_the_gpu() {
    const SW: u32 = 48;
    const SH: u32 = 36;
    let ctx = common::gpu();
    let scene = |visible: bool| {
        parse(&format!(
            r#"{{
            "camera": {{"position": [0, 5, 0.01], "target": [0, 0, 0]}},
            "output": {{"width": {SW}, "height": {SH}, "msaa": 1}},
            "lights": [
                {{"type": "rect", "position": [0.2, 1.5, -0.3], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [0.8, 1.2], "intensity": 3, "shadow": true, "visible": {visible}}},
                {{"type": "point", "position": [0.2, 2.5, -0.3], "intensity": 20, "shadow": true}}
            ],
            "materials": {{"m": {{"model": "lambert", "albedo": [0.5, 0.5, 0.5]}}}},
            "objects": [{{"mesh": {{"type": "plane", "size": [40, 40]}}, "material": "m"}}]
        }}"#
        ))
    };
    let (blocked, through) = (scene(true), scene(false));
    // The rect's shadow from the point light: 2.5 times the rect (the plane 2.5 m below the
    // light, the rect 1 m), centred under both.
    let (half_x, half_z) = (0.4 * 2.5, 0.6 * 2.5);
    let margin = 0.1;
    let (mut inside, mut outside) = (Vec::new(), Vec::new());
    for py in 0..SH {
        for px in 0..SW {
            let (o, d) = luz::reference::primary_ray(&blocked, px as f32 + 0.5, py as f32 + 0.5);
            let q = o + d * (-o.y / d.y);
            let (dx, dz) = ((q.x - 0.2).abs(), (q.z + 0.3).abs());
            let i = (py * SW + px) as usize;
            if dx < half_x - margin && dz < half_z - margin {
                inside.push(i);
            } else if dx > half_x + margin || dz > half_z + margin {
                outside.push(i);
            }
        }
    }
    eprintln!(
        "{} pixels inside the rect's shadow, {} outside",
        inside.len(),
        outside.len()
    );
    assert!(
        inside.len() >= 200 && outside.len() >= 200,
        "the view has both"
    );
    let ref_blocked = reference(&blocked, 1024);
    let ref_through = reference(&through, 1024);
    let sum =
        |img: &LinearImage, px: &[usize]| -> f64 { px.iter().map(|&i| lum(&img.pixels[i])).sum() };
    let l1 = |gpu: &LinearImage, cpu: &LinearImage, px: &[usize]| {
        px.iter()
            .map(|&i| (lum(&gpu.pixels[i]) - lum(&cpu.pixels[i])).abs())
            .sum::<f64>()
            / sum(cpu, px)
    };
    let loss = |b: &LinearImage, t: &LinearImage, px: &[usize]| 1.0 - sum(b, px) / sum(t, px);
    let ref_loss = loss(&ref_blocked, &ref_through, &inside);
    eprintln!(
        "reference: the visible rect takes away {:.2} % inside, {:.3} % outside",
        100.0 * ref_loss,
        100.0 * loss(&ref_blocked, &ref_through, &outside)
    );
    let mut failures = Vec::new();
    let gpu_blocked = common::both_paths(&ctx, &blocked);
    let gpu_through = common::both_paths(&ctx, &through);
    for ((path, b), (_, t)) in gpu_blocked.iter().zip(&gpu_through) {
        let errors = [
            l1(b, &ref_blocked, &inside),
            l1(b, &ref_blocked, &outside),
            l1(t, &ref_through, &inside),
            l1(t, &ref_through, &outside),
        ];
        let (loss_in, loss_out) = (loss(b, t, &inside), loss(b, t, &outside));
        eprintln!(
            "{path}: against the reference (relative L1) visible inside {:.3} %, outside {:.3} %; \
             invisible inside {:.3} %, outside {:.3} %; the visible rect takes away {:.2} % \
             inside, {:.3} % outside",
            100.0 * errors[0],
            100.0 * errors[1],
            100.0 * errors[2],
            100.0 * errors[3],
            100.0 * loss_in,
            100.0 * loss_out
        );
        if errors.iter().any(|&e| e > 0.01)
            || loss_in < 0.6
            || (loss_in - ref_loss).abs() > 0.02
            || loss_out.abs() > 0.005
        {
            failures.push(format!("{path}: {errors:?}, loss {loss_in} / {loss_out}"));
        }
    }
    common::assert_no_validation_messages(&ctx);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// An area light's own emitter is not in its own maps (its cube map's eye is inside it): a
/// visible sphere emitter with a PCSS shadow, and a visible tube (its eye on the axis, inside the
/// side) with a PCF one, each alone over a bare plane, render on both paths as the same light
/// without a shadow within 0.5 % at every pixel (drawn into its own cube, the emitter would hide
/// the whole plane). Zero validation messages.
#[test]
fn an_emitter_does_not_shadow_its_own_light() {
    let ctx = common::gpu();
    let sphere = |shadow: &str| {
        format!(
            r#"{{"type": "sphere", "position": [0, 1.2, 0], "radius": 0.3, "intensity": 4, "method": "ltc"{}}}"#,
            shadow_field(shadow)
        )
    };
    let tube = |shadow: &str| {
        format!(
            r#"{{"type": "tube", "position": [0, 1.2, 0], "direction": [1, 0, 0.4], "length": 1, "radius": 0.05, "intensity": 30{}}}"#,
            shadow_field(shadow)
        )
    };
    let mut failures = Vec::new();
    for (name, light, shadow) in [
        (
            "sphere, PCSS",
            &sphere as &dyn Fn(&str) -> String,
            r#"{"method": "pcss", "resolution": 512}"#,
        ),
        (
            "tube, PCF",
            &tube,
            r#"{"method": "pcf", "resolution": 512}"#,
        ),
    ] {
        let with = common::both_paths(&ctx, &scene(&light(shadow), false));
        let without = common::both_paths(&ctx, &scene(&light("null"), false));
        for ((path, w), (_, wo)) in with.iter().zip(&without) {
            let v = visibility(w, wo);
            let worst = v.iter().map(|x| (1.0 - x).abs()).fold(0.0, f64::max);
            eprintln!(
                "{name}, {path}: worst |1 − V| {worst:.2e} over {} pixels",
                v.len()
            );
            if worst > 0.005 {
                failures.push(format!("{name} {path}: {worst}"));
            }
        }
    }
    common::assert_no_validation_messages(&ctx);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The map cache and emitters: a point light with a shadow (six cube faces) and a visible rect
/// over the plane. A second frame reuses every face; moving the rect redraws the faces (the
/// emitter's draws are part of what a face was drawn with), and the image is then exactly a
/// fresh renderer's of the moved scene (no stale emitter in the maps). Zero validation messages.
#[test]
fn a_moved_emitter_redraws_the_maps() {
    use luz::headless::Headless;
    let ctx = common::gpu();
    let point = r#"{"type": "point", "position": [0, 2.6, 0], "intensity": 20, "shadow": {"method": "pcf", "resolution": 256}}"#;
    let rect = |x: f32| {
        format!(
            r#"{{"type": "rect", "position": [{x}, 1.6, 0], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [0.8, 0.6], "intensity": 4}}"#
        )
    };
    let mut s = scene(&format!("{}, {point}", rect(0.0)), false);
    let mut r = Headless::new(&ctx, &s).expect("renderer");
    r.render().expect("frame");
    assert_eq!(r.shadow_frames_drawn_reused(), (1, 0, 6));
    r.render().expect("frame");
    assert_eq!(r.shadow_frames_drawn_reused(), (1, 1, 6));
    let first = r.image().expect("readback");
    s.area_lights[0].position.x = 0.4;
    r.update_scene(&s).expect("update");
    r.render().expect("frame");
    let (frames, reused, layers) = r.shadow_frames_drawn_reused();
    eprintln!("after the move: {frames} frames drawn, {reused} reused, {layers} layers drawn");
    assert_eq!((frames, reused), (2, 1));
    assert!(layers > 6, "{layers}");
    let moved = r.image().expect("readback");
    let fresh = common::render_on(&ctx, &s);
    assert_eq!(moved.pixels, fresh.pixels, "a stale emitter in the maps");
    assert_ne!(moved.pixels, first.pixels);
    common::assert_no_validation_messages(&ctx);
}

/// What a shadow lookup adds to the forward pass, for a point light and for a rect (LTC): a
/// plane filling a 640 × 360 view and a sphere (metal-rough), one light, 3 warm-up frames and
/// medians of 31 interleaved frames; the table is printed (docs/area-lights.md#shadows). Only
/// the device's timestamps are asserted: the ratios move with the machine's load.
/// `cargo test --release --test area_shadows area_shadow_cost -- --ignored --nocapture`.
#[test]
#[ignore]
fn area_shadow_cost() {
    let ctx = common::gpu();
    let scene = |light: &str| {
        parse(&format!(
            r#"{{
            "camera": {{"position": [0.3, 3, 4], "target": [0, 0.3, 0]}},
            "output": {{"width": 640, "height": 360, "msaa": 1}},
            "lights": [{light}],
            "materials": {{"m": {{"model": "metal_rough", "base_color": [0.8, 0.7, 0.6], "metallic": 0.3, "roughness": 0.4}}}},
            "objects": [
                {{"mesh": {{"type": "plane", "size": [40, 40]}}, "material": "m"}},
                {{"mesh": {{"type": "sphere", "radius": 0.5}}, "material": "m", "position": [0, 0.5, 0]}}
            ]
        }}"#
        ))
    };
    let point = |shadow: &str| {
        format!(
            r#"{{"type": "point", "position": [0.2, 1.5, -0.3], "intensity": 3, "radius": 0.3{}}}"#,
            shadow_field(shadow)
        )
    };
    let rect = |shadow: &str| {
        format!(
            r#"{{"type": "rect", "position": [0.2, 1.5, -0.3], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [0.8, 0.6], "intensity": 3, "visible": false{}}}"#,
            shadow_field(shadow)
        )
    };
    let pcss = r#"{"method": "pcss", "resolution": 1024}"#;
    let pcf = r#"{"method": "pcf", "resolution": 1024}"#;
    let cases = [
        ("point", point("null")),
        ("point, PCF 2×2", point(pcf)),
        ("point, PCSS", point(pcss)),
        ("rect, LTC", rect("null")),
        ("rect, LTC, PCF 2×2", rect(pcf)),
        ("rect, LTC, PCSS", rect(pcss)),
    ];
    let mut renderers: Vec<_> = cases
        .iter()
        .map(|(_, l)| luz::headless::Headless::new(&ctx, &scene(l)).expect("renderer"))
        .collect();
    let medians = common::interleaved_forward_medians(&mut renderers, 3, 31);
    drop(renderers);
    common::assert_no_validation_messages(&ctx);
    eprintln!(
        "| light | forward pass, median ms | × the same light without a shadow |\n|---|---:|---:|"
    );
    for (i, ((name, _), m)) in cases.iter().zip(&medians).enumerate() {
        let base = medians[if i < 3 { 0 } else { 3 }];
        eprintln!("| {name} | {m:.2} | {:.2} |", m / base);
    }
    assert!(
        medians.iter().all(|&m| m > 0.0),
        "the device has timestamps"
    );
}

/// What visible emitters add to the shadow maps of other lights: a point light with a PCF cube
/// (1024²) over the plane and the ball, and a rect between them, visible (drawn into the six
/// faces) or not. The point light moves by 1 mm every frame, so each frame redraws its six faces
/// (a static scene reuses them: the emitters then cost nothing). Medians of 31 interleaved frames
/// of the whole frame's GPU time and of its shadow rows; the table is printed
/// (docs/area-lights.md#shadows). Only the device's timestamps are asserted.
/// `cargo test --release --test area_shadows emitter_shadow_cost -- --ignored --nocapture`.
#[test]
#[ignore]
fn emitter_shadow_cost() {
    use luz::headless::Headless;
    let ctx = common::gpu();
    let light = |visible: bool, x: f32| {
        format!(
            r#"{{"type": "rect", "position": [0, 1.6, 0], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [0.8, 0.6], "intensity": 4, "visible": {visible}}}, {{"type": "point", "position": [{x}, 2.6, 0.3], "intensity": 20, "shadow": {{"method": "pcf", "resolution": 1024}}}}"#
        )
    };
    let mut cases: Vec<(bool, Scene, Headless)> = [false, true]
        .into_iter()
        .map(|visible| {
            let s = scene(&light(visible, 0.0), true);
            let r = Headless::new(&ctx, &s).expect("renderer");
            (visible, s, r)
        })
        .collect();
    let shadow_ms = |t: &luz::headless::FrameTimes| {
        t.gpu_ms
            .iter()
            .filter(|(n, _)| n.contains("shadow"))
            .map(|(_, ms)| ms)
            .sum::<f64>()
    };
    let mut times = vec![(Vec::new(), Vec::new()); cases.len()];
    for frame in 0..34 {
        for ((visible, s, r), (total, shadow)) in cases.iter_mut().zip(times.iter_mut()) {
            s.lights[0].position.x = if frame % 2 == 0 { 0.0 } else { 0.001 };
            r.update_scene(s).expect("update");
            let t = r.render().expect("frame");
            if frame == 0 {
                eprintln!("visible {visible}: passes {:?}", t.gpu_ms);
            }
            if frame >= 3 {
                total.push(t.gpu_ms.iter().map(|(_, ms)| ms).sum::<f64>());
                shadow.push(shadow_ms(&t));
            }
        }
    }
    for (visible, _, r) in &cases {
        // Every frame drew its maps (the light moved): none was reused.
        let (drawn, reused, _) = r.shadow_frames_drawn_reused();
        assert_eq!((drawn, reused), (34, 0), "visible {visible}");
    }
    drop(cases);
    common::assert_no_validation_messages(&ctx);
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let rows: Vec<(f64, f64)> = times
        .iter_mut()
        .map(|(t, s)| (median(t), median(s)))
        .collect();
    eprintln!("| rect | frame GPU ms | shadow rows ms | × not visible (frame / shadow) |\n|---|---:|---:|---:|");
    for (visible, (t, s)) in [false, true].iter().zip(&rows) {
        eprintln!(
            "| visible {visible} | {t:.2} | {s:.2} | {:.2} / {:.2} |",
            t / rows[0].0,
            s / rows[0].1
        );
    }
    assert!(
        rows.iter().all(|&(t, _)| t > 0.0),
        "the device has timestamps"
    );
}
