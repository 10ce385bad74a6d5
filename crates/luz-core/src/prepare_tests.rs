//! `prepare` without a GPU: each OBJ mesh's LOD chain and each map once, in parallel;
//! reuse across edits; a map that cannot be decoded names its material and file.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::*;

/// A folder with a grid OBJ (`grid.obj`, 20×20 quads: a chain with levels), a 32×16 PNG
/// (`a.png`), another (`b.png`) and a file that is no PNG (`bad.png`).
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("luz-prepare-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut obj = String::new();
    let n = 21;
    for j in 0..n {
        for i in 0..n {
            let (x, z) = (i as f32 / 20.0, j as f32 / 20.0);
            let y = 0.1 * (x * 7.0).sin() * (z * 5.0).cos();
            obj += &format!("v {x} {y} {z}\n");
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = j * n + i + 1;
            obj += &format!(
                "f {a} {} {}\nf {a} {} {}\n",
                a + n + 1,
                a + 1,
                a + n,
                a + n + 1
            );
        }
    }
    std::fs::write(dir.join("grid.obj"), obj).unwrap();
    for (file, shade) in [("a.png", 200u8), ("b.png", 60)] {
        image::RgbaImage::from_fn(32, 16, |x, y| {
            image::Rgba([shade, x as u8 * 8, y as u8 * 16, 255])
        })
        .save(dir.join(file))
        .unwrap();
    }
    std::fs::write(dir.join("bad.png"), b"\x89PNG\r\n\x1a\n not really").unwrap();
    dir
}

fn scene(dir: &Path, a_map: &str) -> Scene {
    let text = format!(
        r#"{{
        "materials": {{
            "a": {{"model": "metal_rough", "textures": {{"base_color": "{a_map}", "roughness": "a.png"}}}},
            "b": {{"model": "lambert", "textures": {{"base_color": "a.png"}}}}
        }},
        "objects": [
            {{"mesh": {{"type": "obj", "path": "grid.obj"}}, "material": "a"}},
            {{"mesh": {{"type": "obj", "path": "grid.obj"}}, "material": "b", "position": [2, 0, 0]}},
            {{"mesh": {{"type": "sphere", "radius": 0.5}}, "material": "b"}}
        ]
    }}"#
    );
    crate::scene::parse(&text, &dir.join("scene.json")).expect("scene")
}

/// Two objects share the OBJ mesh (the loader's cache gives them one `Arc`): one chain, from a
/// build; the sphere (a primitive) has none. `a.png` is read as sRGB colour by both materials
/// and as linear roughness by `a`: two decodes, each with its mip chain.
#[test]
fn every_mesh_and_map_once() {
    let dir = folder("once");
    let s = scene(&dir, "a.png");
    assert!(Arc::ptr_eq(&s.objects[0].mesh, &s.objects[1].mesh));
    let p = prepare(&s, &PrepareOptions::default(), None).unwrap();
    assert_eq!(p.counts(), (1, 2));
    assert_eq!((p.lod_stats.built, p.lod_stats.loaded), (1, 0));
    let chain = p.chain(&s.objects[0].mesh).expect("the OBJ's chain");
    assert!(chain.levels.len() > 1, "a grid of 800 triangles simplifies");
    assert!(
        p.chain(&s.objects[2].mesh).is_none(),
        "a primitive has no chain"
    );
    let colour = s.materials[1].textures.get(TextureSlot::BaseColor).unwrap();
    let t = p.texture(colour, TextureSlot::BaseColor).expect("decoded");
    assert_eq!((t.width, t.height, t.mips.len()), (32, 16, 6));
    let rough = s.materials[0].textures.get(TextureSlot::Roughness).unwrap();
    let r = p.texture(rough, TextureSlot::Roughness).expect("decoded");
    assert!(!Arc::ptr_eq(t, r), "colour and data decodes differ");
    std::fs::remove_dir_all(dir).unwrap();
}

/// An edit that swaps one map keeps the chain and the other map (the same `Arc`s, nothing built
/// or decoded again) and decodes only the new one; what the scene no longer uses is dropped.
#[test]
fn prepare_again_keeps_what_the_edit_left() {
    let dir = folder("again");
    let s = scene(&dir, "a.png");
    let first = prepare(&s, &PrepareOptions::default(), None).unwrap();
    let chain = first.chain(&s.objects[0].mesh).unwrap().clone();
    let rough = s.materials[0].textures.get(TextureSlot::Roughness).unwrap();
    let kept = first
        .texture(rough, TextureSlot::Roughness)
        .unwrap()
        .clone();
    let mut edited = s.clone();
    edited.materials[0].textures = scene(&dir, "b.png").materials[0].textures.clone();
    edited.materials[1].textures = Default::default();
    let again = prepare_again(first, &edited, &PrepareOptions::default(), None).unwrap();
    assert_eq!((again.lod_stats.built, again.lod_stats.loaded), (0, 0));
    assert!(Arc::ptr_eq(
        again.chain(&edited.objects[0].mesh).unwrap(),
        &chain
    ));
    assert!(Arc::ptr_eq(
        again.texture(rough, TextureSlot::Roughness).unwrap(),
        &kept
    ));
    let b = edited.materials[0]
        .textures
        .get(TextureSlot::BaseColor)
        .unwrap();
    assert!(again.texture(b, TextureSlot::BaseColor).is_some());
    // a.png as colour is no longer used: two maps, not three.
    assert_eq!(again.counts(), (1, 2));
    std::fs::remove_dir_all(dir).unwrap();
}

/// A map that cannot be decoded: an error naming the material and the file, nothing prepared.
#[test]
fn a_bad_map_names_its_material_and_file() {
    let dir = folder("bad");
    let s = scene(&dir, "bad.png");
    let e = prepare(&s, &PrepareOptions::default(), None).unwrap_err();
    assert_eq!((e.material.as_str(), e.slot), ("a", TextureSlot::BaseColor));
    let text = e.to_string();
    assert!(text.starts_with("material \"a\": "), "{text}");
    assert!(text.contains("bad.png"), "{text}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// A smaller size limit decodes the maps downscaled, with one warning each.
#[test]
fn the_size_limit_downscales_with_a_warning() {
    let dir = folder("limit");
    let s = scene(&dir, "a.png");
    let options = PrepareOptions {
        max_texture_dimension: 8,
        ..PrepareOptions::default()
    };
    let p = prepare(&s, &options, None).unwrap();
    let colour = s.materials[1].textures.get(TextureSlot::BaseColor).unwrap();
    let t = p.texture(colour, TextureSlot::BaseColor).unwrap();
    assert_eq!((t.width, t.height), (8, 4));
    assert_eq!(p.max_texture_dimension(), 8);
    assert_eq!(p.warnings.len(), 2, "{:?}", p.warnings);
    std::fs::remove_dir_all(dir).unwrap();
}
