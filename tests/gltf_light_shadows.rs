//! A glTF file's own lights (KHR_lights_punctual) cast shadows when the scene asks
//! (`"light_shadow": true` beside `"lights": true`): issue 15's "every light type", for lights
//! that come from a model file.

mod common;

use common::*;
use glam::Vec3;
use luz::scene::{LightKind, Shadow};

/// A .gltf and its .bin in `dir`: a 6 m floor quad at y = 0 and a 1 m blocker quad at y = 1,
/// both facing up, and a directional light straight down (node rotated −90° about x).
fn write_file(dir: &std::path::Path) -> std::path::PathBuf {
    let quad = |half: f32, y: f32| -> Vec<f32> {
        vec![
            -half, y, -half, half, y, -half, half, y, half, -half, y, half,
        ]
    };
    let mut positions = quad(3.0, 0.0);
    positions.extend(quad(0.5, 1.0));
    let normals: Vec<f32> = (0..8).flat_map(|_| [0.0, 1.0, 0.0]).collect();
    // Counter-clockwise seen from above (+y).
    let indices: [u16; 12] = [0, 2, 1, 0, 3, 2, 4, 6, 5, 4, 7, 6];
    let mut bin: Vec<u8> = Vec::new();
    bin.extend(positions.iter().flat_map(|f| f.to_le_bytes()));
    bin.extend(normals.iter().flat_map(|f| f.to_le_bytes()));
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("lit.bin"), &bin).unwrap();
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let doc = format!(
        r#"{{
        "asset": {{"version": "2.0"}},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "directional", "intensity": 2}}]}}}},
        "buffers": [{{"uri": "lit.bin", "byteLength": {len}}}],
        "bufferViews": [
            {{"buffer": 0, "byteOffset": 0, "byteLength": 96}},
            {{"buffer": 0, "byteOffset": 96, "byteLength": 96}},
            {{"buffer": 0, "byteOffset": 192, "byteLength": 24}}
        ],
        "accessors": [
            {{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [-3, 0, -3], "max": [3, 1, 3]}},
            {{"bufferView": 1, "componentType": 5126, "count": 8, "type": "VEC3"}},
            {{"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"}}
        ],
        "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1}}}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2, "material": 0}}]}}],
        "nodes": [
            {{"mesh": 0}},
            {{"name": "sun", "rotation": [{ns}, 0, 0, {s}], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}
        ],
        "scenes": [{{"nodes": [0, 1]}}]
    }}"#,
        len = bin.len(),
        ns = -s,
    );
    let path = dir.join("lit.gltf");
    std::fs::write(&path, doc).unwrap();
    path
}

fn scene_json(light_shadow: &str) -> String {
    format!(
        r#"{{
        "camera": {{"position": [0, 5, 4], "target": [0, 0, 0], "fov_y_deg": 50}},
        "output": {{"width": 96, "height": 72, "msaa": 1}},
        "objects": [{{"mesh": {{"type": "gltf", "path": "lit.gltf", "lights": true{light_shadow}}}}}]
    }}"#
    )
}

/// Luminance of the floor's pixel at world point `p` (projected by the scene's camera).
fn floor_at(scene: &luz::scene::Scene, img: &luz::imageio::LinearImage, p: Vec3) -> f32 {
    let aspect = scene.output.width as f32 / scene.output.height as f32;
    let clip =
        luz::render::gpu::projection(&scene.camera, aspect) * scene.camera.view() * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    let x = ((ndc.x * 0.5 + 0.5) * scene.output.width as f32) as usize;
    let y = ((ndc.y * 0.5 + 0.5) * scene.output.height as f32) as usize;
    let px = img.pixels[y * scene.output.width as usize + x];
    0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2]
}

#[test]
fn imported_lights_cast_shadows_when_asked() {
    let dir = scratch("gltf_light_shadows");
    write_file(&dir);
    let scene_path = dir.join("scene.json");
    let parse_with = |extra: &str| {
        luz::scene::parse(&scene_json(extra), &scene_path).unwrap_or_else(|e| panic!("{e}"))
    };
    let plain = parse_with("");
    let shadowed = parse_with(r#", "light_shadow": true"#);
    assert_eq!(plain.lights.len(), 1);
    assert_eq!(plain.lights[0].shadow, None);
    assert_eq!(shadowed.lights[0].kind, LightKind::Directional);
    assert_eq!(
        shadowed.lights[0].shadow,
        Some(Shadow::default_for(LightKind::Directional))
    );

    let ctx = gpu_with(true);
    let lit = render_on(&ctx, &plain);
    let dark = render_on(&ctx, &shadowed);
    // Under the blocker (the light points straight down) and well outside it.
    let (under, open) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 2.0));
    let (u_lit, u_dark) = (
        floor_at(&plain, &lit, under),
        floor_at(&shadowed, &dark, under),
    );
    let (o_lit, o_dark) = (
        floor_at(&plain, &lit, open),
        floor_at(&shadowed, &dark, open),
    );
    // Lambert 0.8 under irradiance 2 straight down: 0.8 / π · 2 ≈ 0.509 where lit; the ambient
    // default lights the shadowed floor far less.
    assert!(
        (o_lit - 0.509).abs() < 0.02 && (o_dark - o_lit).abs() < 1e-4,
        "open floor: {o_lit} / {o_dark}"
    );
    assert!(u_lit > 0.45, "under the blocker without shadows: {u_lit}");
    assert!(
        u_dark < 0.1 * u_lit,
        "under the blocker with shadows: {u_dark} (lit {u_lit})"
    );
    assert_no_validation_messages(&ctx);
}

#[test]
fn light_shadow_without_lights_is_refused() {
    let dir = scratch("gltf_light_shadows_bad");
    write_file(&dir);
    let text = scene_json("").replace(r#""lights": true"#, r#""light_shadow": true"#);
    let e = luz::scene::parse(&text, &dir.join("scene.json"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("objects[0].mesh.light_shadow") && e.contains("\"lights\": true"),
        "{e}"
    );
    let e = luz::scene::parse(
        &scene_json(r#", "light_shadow": 3"#),
        &dir.join("scene.json"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("objects[0].mesh.light_shadow"), "{e}");
}
