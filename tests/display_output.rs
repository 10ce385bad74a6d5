//! The display output (the viewer's direct path: exposure, tone map and sRGB encode in the forward
//! pass's fragment shader, into 8 bits) against the float path (RGBA32F radiance, then the CPU's
//! `color::to_display_rgba8`, the code every PNG of `luz render` goes through): the same codes,
//! byte for byte (AgX: at most 1 LSB on at most 0.1% of the bytes, the GPU's log2 and pow against
//! Rust's, the bound tests/tonemap_gpu.rs sets for the display pass), on scenes that cover every tone map, exposure, clamp saturation, depth cueing,
//! the environment as background, texture maps and the lean and full Phong variants.

mod common;

use common::*;
use luz::color::Tonemap;
use luz::headless::{Headless, RenderOptions};
use luz::render::forward::Output;
use luz::render::ibl::IblSettings;
use luz::scene::Scene;

/// Both paths on one renderer; panics with the first differing pixel.
fn assert_same_codes(ctx: &std::sync::Arc<luz::vk::Context>, name: &str, scene: &Scene) {
    let mut r = Headless::with_options(
        ctx,
        scene,
        &RenderOptions {
            ibl: IblSettings::fast(),
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    r.render().unwrap();
    let hdr = r.image().unwrap();
    let expected =
        luz::color::to_display_rgba8(&hdr.pixels, scene.output.exposure, scene.output.tonemap);
    let output = r.display_output(scene).unwrap();
    r.render_display(output).unwrap();
    let actual = r.display_codes().unwrap();
    assert_eq!(actual.len(), expected.len(), "{name}");
    let w = scene.output.width as usize;
    let agx = scene.output.tonemap == Tonemap::Agx;
    let off_by_one = expected
        .iter()
        .zip(&actual)
        .filter(|(e, a)| e.abs_diff(**a) == 1)
        .count();
    let allowed =
        |e: &[u8], a: &[u8]| e == a || (agx && e.iter().zip(a).all(|(x, y)| x.abs_diff(*y) <= 1));
    let bad = expected
        .chunks_exact(4)
        .zip(actual.chunks_exact(4))
        .filter(|(e, a)| !allowed(e, a))
        .count();
    if agx {
        assert!(
            off_by_one * 1000 <= expected.len(),
            "{name}: {off_by_one} of {} bytes off by one (more than 0.1%)",
            expected.len()
        );
    }
    if let Some((i, (e, a))) = expected
        .chunks_exact(4)
        .zip(actual.chunks_exact(4))
        .enumerate()
        .find(|(_, (e, a))| !allowed(e, a))
    {
        panic!(
            "{name}: {bad} of {} pixels differ; first at ({}, {}): float path {e:?}, display \
             output {a:?} (radiance {:?})",
            expected.len() / 4,
            i % w,
            i / w,
            hdr.pixels[i]
        );
    }
    // Not a blank image: the comparison means something.
    let distinct: std::collections::BTreeSet<&[u8]> = actual.chunks_exact(4).collect();
    assert!(
        distinct.len() > 20,
        "{name}: only {} distinct colours",
        distinct.len()
    );
}

fn asset(path: &str) -> Scene {
    let mut s = luz::scene::load(&root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
    s.output.msaa = 1;
    s.override_size(Some(192), Some(108));
    s
}

#[test]
fn every_tonemap_and_exposure_gives_the_float_paths_codes() {
    let ctx = gpu();
    let base = asset("assets/scenes/bench/grid49.json");
    for (tonemap, exposure) in [
        (Tonemap::Aces, 0.0),
        (Tonemap::None, 1.5),
        (Tonemap::Reinhard, -1.0),
        (Tonemap::KhronosNeutral, 2.0),
        (Tonemap::Agx, 0.5),
    ] {
        let mut s = base.clone();
        s.output.tonemap = tonemap;
        s.output.exposure = exposure;
        assert_same_codes(&ctx, &format!("grid49 {tonemap:?} {exposure} EV"), &s);
    }
    assert_no_validation_messages(&ctx);
}

#[test]
fn classic_scenes_with_clamp_and_depth_cueing() {
    let ctx = gpu();
    for path in [
        "assets/scenes/classic/07_multiple_lights.json",
        "assets/scenes/classic/09_depth_cue_on.json",
        "assets/scenes/models/principled.json",
        "assets/scenes/default.json",
    ] {
        let s = asset(path);
        assert_same_codes(&ctx, path, &s);
    }
    let s = asset("assets/scenes/classic/07_multiple_lights.json");
    assert_eq!(
        s.saturation,
        luz::scene::Saturation::Clamp,
        "the clamp case is covered"
    );
    assert_no_validation_messages(&ctx);
}

#[test]
fn environment_background_and_texture_maps() {
    let ctx = gpu();
    let sky = asset("assets/scenes/ibl/seed001_grid_sky.json");
    assert!(sky.environment.as_ref().is_some_and(|e| e.show_background));
    assert_same_codes(&ctx, "seed001_grid_sky", &sky);

    let dir = scratch("display_output");
    let base = dir.join("base.png");
    let normal = dir.join("normal.png");
    luz::texture::checker(64, 8, [230, 180, 90, 255], [60, 90, 160, 255])
        .save(&base)
        .unwrap();
    luz::texture::noise_normal_map(64, 7, 1.0)
        .save(&normal)
        .unwrap();
    let textured = parse(&format!(
        r#"{{
        "camera": {{"position": [0, 0.3, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40, "near": 0.1, "far": 10}},
        "output": {{"width": 128, "height": 96, "msaa": 1, "tonemap": "khronos_neutral", "background": [0.3, 0.2, 0.1]}},
        "saturation": "clamp",
        "lights": [{{"type": "point", "position": [2, 2, 3], "color": [1, 1, 1], "intensity": 30}}],
        "materials": {{"m": {{"model": "metal_rough", "base_color": [1, 1, 1], "metallic": 0.5, "roughness": 0.4,
            "textures": {{"base_color": "{}", "normal": "{}"}}}}}},
        "objects": [{{"mesh": {{"type": "sphere", "radius": 1, "segments": 48, "rings": 24}}, "material": "m"}}]
    }}"#,
        base.display(),
        normal.display()
    ));
    assert_same_codes(&ctx, "textured sphere", &textured);
    assert_no_validation_messages(&ctx);
}

/// Scenes that need the whole float image say so instead of rendering something else.
#[test]
fn normalize_and_msaa_have_no_display_output() {
    let ctx = gpu();
    let mut s = asset("assets/scenes/classic/07_multiple_lights.json");
    s.saturation = luz::scene::Saturation::Normalize;
    let r = Headless::new(&ctx, &s).unwrap();
    let e = r.display_output(&s).unwrap_err().to_string();
    assert!(e.contains("normalize"), "{e}");

    let mut s = asset("assets/scenes/bench/grid49.json");
    s.output.msaa = 4;
    let mut r = Headless::new(&ctx, &s).unwrap();
    let e = r.display_output(&s).unwrap_err().to_string();
    assert!(e.contains("msaa"), "{e}");
    assert!(r.render_display(Output::Hdr).is_err());
    r.render().unwrap();
    assert!(r.display_codes().is_err(), "no display frame was rendered");
    assert_no_validation_messages(&ctx);
}
