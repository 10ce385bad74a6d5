//! Textured materials on lavapipe (validation on). Test data is generated here (checkers, a noise
//! normal map), nothing large is committed: a checker's texels land exactly on the plane, mips are
//! gamma-correct on the GPU, a textured and normal-mapped sphere under the procedural sky matches
//! its golden, and the real gold PBR set from ../shared renders.

mod common;

use common::*;
use glam::Vec3;

/// Renders with small IBL data (the environment is only lighting here), validation checked.
fn render_fast_ibl(scene: &luz::scene::Scene) -> luz::imageio::LinearImage {
    let ctx = gpu();
    let img = {
        let mut r = luz::headless::Headless::with_ibl_settings(
            &ctx,
            scene,
            &luz::render::ibl::IblSettings::fast(),
        )
        .unwrap();
        r.render().unwrap();
        r.image().unwrap()
    };
    assert_no_validation_messages(&ctx);
    img
}

/// A plane seen from straight above with a red/blue checker (nearest filtering, no mips) under a
/// directional light and a Lambert material: every pixel is exactly red·E cosθ/π or blue·E cosθ/π.
#[test]
fn checker_texels_reach_the_plane() {
    let dir = scratch("checker");
    let png = dir.join("checker.png");
    luz::texture::checker(64, 8, [255, 0, 0, 255], [0, 0, 255, 255])
        .save(&png)
        .unwrap();
    let scene = parse(&format!(
        r#"{{
        "camera": {{"position": [0, 2, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 60, "near": 0.1, "far": 10}},
        "output": {{"width": 64, "height": 64, "msaa": 1}},
        "lights": [{{"type": "directional", "direction": [0, -1, 0], "color": [1, 1, 1], "intensity": 3.14159265}}],
        "materials": {{"m": {{"model": "lambert", "albedo": [1, 1, 1],
            "textures": {{"base_color": {{"path": "{}", "mag_filter": "nearest", "min_filter": "nearest", "mipmaps": false}}}}}}}},
        "objects": [{{"mesh": {{"type": "plane", "size": [4, 4]}}, "material": "m"}}]
    }}"#,
        png.display()
    ));
    let img = render(&scene);
    let (mut red, mut blue, mut other) = (0, 0, 0);
    for p in &img.pixels {
        let c = Vec3::new(p[0], p[1], p[2]);
        if (c - Vec3::X).abs().max_element() < 1e-4 {
            red += 1;
        } else if (c - Vec3::Z).abs().max_element() < 1e-4 {
            blue += 1;
        } else {
            other += 1;
        }
    }
    assert!(
        red > 1000 && blue > 1000,
        "red {red}, blue {blue}, other {other}"
    );
    assert!(
        other < 200,
        "{other} pixels are neither checker colour (background or seams)"
    );
}

/// Seen from far away, a fine black/white checker averages to 0.5 in linear light through the
/// mip chain (sRGB-correct mips), not to 0.214 (the linear value of an sRGB average of 128).
#[test]
fn mips_are_gamma_correct_on_the_gpu() {
    let dir = scratch("mips");
    let png = dir.join("fine.png");
    luz::texture::checker(512, 256, [0, 0, 0, 255], [255, 255, 255, 255])
        .save(&png)
        .unwrap();
    let scene = parse(&format!(
        r#"{{
        "camera": {{"position": [0, 40, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 2, "near": 1, "far": 100}},
        "output": {{"width": 32, "height": 32, "msaa": 1}},
        "lights": [{{"type": "directional", "direction": [0, -1, 0], "color": [1, 1, 1], "intensity": 3.14159265}}],
        "materials": {{"m": {{"model": "lambert", "albedo": [1, 1, 1], "textures": {{"base_color": "{}"}}}}}},
        "objects": [{{"mesh": {{"type": "plane", "size": [100, 100]}}, "material": "m"}}]
    }}"#,
        png.display()
    ));
    let img = render(&scene);
    let mean: f32 = img.pixels.iter().map(|p| p[0]).sum::<f32>() / img.pixels.len() as f32;
    assert!(
        (mean - 0.5).abs() < 0.03,
        "mean linear value {mean}, expected 0.5"
    );
}

/// A sphere with a checker base colour, a noise normal map and an ORM map, under the procedural
/// sky (IBL, split sum), against its golden. The scene is the golden's case file
/// (`tests/golden/textured_sphere_sky/`, as `luz golden tests/golden` renders it); its textures
/// must be what `luz::texture` writes today (`LUZ_BLESS=1` rewrites them).
#[test]
fn textured_sphere_golden() {
    let dir = root().join("tests/golden/textured_sphere_sky");
    let maps = [
        (
            "base.png",
            luz::texture::checker(256, 8, [230, 180, 90, 255], [60, 90, 160, 255]),
        ),
        ("normal.png", luz::texture::noise_normal_map(256, 7, 1.0)),
        (
            "orm.png",
            luz::texture::checker(256, 4, [255, 60, 255, 255], [200, 220, 0, 255]),
        ),
    ];
    for (name, img) in &maps {
        let path = dir.join(name);
        if std::env::var_os("LUZ_BLESS").is_some() {
            img.save(&path).unwrap();
        }
        let committed = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .to_rgba8();
        assert!(
            committed.as_raw() == img.as_raw(),
            "{} differs from what luz::texture writes",
            path.display()
        );
    }
    let scene = golden_scene("textured_sphere_sky");
    let img = render_fast_ibl(&scene);
    check_golden("textured_sphere_sky", &scene, &img, Tolerance::default());
}

/// The gold PBR texture set from ../shared on a sphere in the studio environment: loads (2048²
/// maps with mips), renders finite and lit (a metal shows only reflections), validation clean.
#[test]
fn real_gold_texture_set() {
    let Some(gold) = shared_dir("textures/gold") else {
        return;
    };
    let scene = parse(&format!(
        r#"{{
        "camera": {{"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40, "near": 0.1, "far": 10}},
        "output": {{"width": 128, "height": 128, "msaa": 1}},
        "ambient": [0.1, 0.1, 0.1],
        "lights": [{{"type": "point", "position": [2, 2, 3], "color": [1, 1, 1], "intensity": 20}}],
        "materials": {{"gold": {{"model": "metal_rough", "roughness": 1, "metallic": 1,
            "textures": {{"base_color": "{0}/albedo.png", "normal": "{0}/normal.png", "roughness": "{0}/roughness.png",
                          "metallic": "{0}/metallic.png", "occlusion": "{0}/ao.png"}}}}}},
        "objects": [{{"mesh": {{"type": "sphere", "radius": 1, "segments": 64, "rings": 32}}, "material": "gold"}}],
        "environment": {{"procedural": "studio", "show_background": false}}
    }}"#,
        gold.display()
    ));
    let img = render_fast_ibl(&scene);
    assert_eq!(nan_count(&img), 0);
    let lit = img.pixels.iter().filter(|p| p[0] > 0.02).count();
    assert!(lit > 3000, "only {lit} lit pixels");
}
