//! Round trips: scene → JSON → scene gives the same scene.

use std::path::{Component, Path, PathBuf};

use glam::Vec3;

use super::*;
use crate::scene::{
    default_scene, load, parse, DiffuseMethod, Falloff, Fog, Light, LightKind, MaterialTextures,
    MeshDesc, NamedMaterial, Scene, SpecularMethod, DEFAULT_SCENE_JSON,
};

// ---------------------------------------------------------------------------------------------
// Helpers.

/// A fresh, empty folder under the system's temporary folder, unique to this process and test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("luz-encode-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// A small PNG (2×2, varied texels) at `path`.
fn png(path: &Path) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let img = image::RgbImage::from_fn(2, 2, |x, y| image::Rgb([x as u8 * 200, y as u8 * 100, 50]));
    img.save(path).unwrap();
}

/// A file that passes the decoder's Radiance HDR check (its header).
fn hdr(path: &Path) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n").unwrap();
}

/// `../shared/<what>`, or `None` with a visible note (a clone without the shared folder).
fn shared_dir(what: &str) -> Option<PathBuf> {
    let p = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("..")
        .join("shared")
        .join(what);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "SKIPPED: {} not found (a fresh clone without ../shared)",
            p.display()
        );
        None
    }
}

fn canon(p: &Path) -> PathBuf {
    p.canonicalize().unwrap_or_else(|_| absolute(p))
}

fn canon_textures(t: &MaterialTextures) -> MaterialTextures {
    let mut t = t.clone();
    for slot in TextureSlot::ALL {
        if let Some(r) = t.get_mut(slot) {
            r.path = canon(&r.path);
        }
    }
    t
}

fn canon_desc(d: &MeshDesc) -> MeshDesc {
    match d {
        MeshDesc::Obj { path } => MeshDesc::Obj { path: canon(path) },
        MeshDesc::Gltf { path, .. } => {
            let mut d = d.clone();
            if let MeshDesc::Gltf { path: p, .. } = &mut d {
                *p = canon(path);
            }
            d
        }
        d => d.clone(),
    }
}

fn canon_env(e: &Option<Environment>) -> Option<Environment> {
    e.clone().map(|mut e| {
        if let EnvSource::Hdr(p) = &e.source {
            e.source = EnvSource::Hdr(canon(p));
        }
        e
    })
}

fn material_named<'a>(s: &'a Scene, name: &str) -> &'a NamedMaterial {
    s.materials
        .iter()
        .find(|m| m.name == name)
        .unwrap_or_else(|| panic!("no material \"{name}\""))
}

/// Everything that matters is equal (paths compared as the files they name). With
/// `material_order` the materials are also listed in the same order.
fn assert_same_with(a: &Scene, b: &Scene, what: &str, material_order: bool) {
    assert_eq!(a.description, b.description, "{what}: description");
    assert_eq!(a.camera, b.camera, "{what}: camera");
    assert_eq!(a.output, b.output, "{what}: output");
    assert_eq!(a.ambient, b.ambient, "{what}: ambient");
    assert_eq!(a.lights.len(), b.lights.len(), "{what}: light count");
    for (i, (x, y)) in a.lights.iter().zip(&b.lights).enumerate() {
        assert_eq!(x, y, "{what}: lights[{i}]");
    }
    assert_eq!(a.area_lights, b.area_lights, "{what}: area lights");
    let names = |s: &Scene| {
        let mut n: Vec<String> = s.materials.iter().map(|m| m.name.clone()).collect();
        if !material_order {
            n.sort();
        }
        n
    };
    assert_eq!(names(a), names(b), "{what}: material names");
    for m in &a.materials {
        let n = material_named(b, &m.name);
        assert_eq!(m.material, n.material, "{what}: material \"{}\"", m.name);
        assert_eq!(
            canon_textures(&m.textures),
            canon_textures(&n.textures),
            "{what}: textures of material \"{}\"",
            m.name
        );
    }
    assert_eq!(a.objects.len(), b.objects.len(), "{what}: object count");
    for (i, (x, y)) in a.objects.iter().zip(&b.objects).enumerate() {
        let w = format!("{what}: objects[{i}] \"{}\"", x.name);
        assert_eq!(x.name, y.name, "{w}: name");
        assert_eq!(canon_desc(&x.desc), canon_desc(&y.desc), "{w}: mesh");
        assert_eq!(
            a.materials[x.material].name, b.materials[y.material].name,
            "{w}: material"
        );
        assert_eq!(x.transform, y.transform, "{w}: transform");
        assert_eq!(x.shading, y.shading, "{w}: shading");
        assert_eq!(
            std::mem::discriminant(&x.tessellation),
            std::mem::discriminant(&y.tessellation),
            "{w}: tessellation"
        );
        assert_eq!(
            x.mesh.triangle_count(),
            y.mesh.triangle_count(),
            "{w}: triangles"
        );
        assert_eq!(
            x.mesh.positions.len(),
            y.mesh.positions.len(),
            "{w}: vertices"
        );
        assert_eq!(x.mesh.uvs.len(), y.mesh.uvs.len(), "{w}: uvs");
    }
    assert_eq!(a.fog, b.fog, "{what}: fog");
    assert_eq!(a.saturation, b.saturation, "{what}: saturation");
    assert_eq!(
        canon_env(&a.environment),
        canon_env(&b.environment),
        "{what}: environment"
    );
}

fn assert_same(a: &Scene, b: &Scene, what: &str) {
    assert_same_with(a, b, what, true);
}

/// Saves `scene` as `file`, checks that nothing was lost (no notes), reloads it, checks it is
/// the same scene, that encoding the reloaded scene gives the same text (a fixed point) and that
/// the `serde_json::Value` form loads as the same scene too (materials in name order). Returns
/// the reloaded scene and the saved text.
fn round_trip(scene: &Scene, file: &Path) -> (Scene, String) {
    let what = file.display().to_string();
    std::fs::create_dir_all(file.parent().unwrap()).unwrap();
    let encoded = encode(scene, file.parent());
    assert!(encoded.notes.is_empty(), "{what}: {:?}", encoded.notes);
    save(scene, file).unwrap_or_else(|e| panic!("{e}"));
    let text = std::fs::read_to_string(file).unwrap();
    assert_eq!(text, encoded.to_text(), "{what}: save writes to_text");
    let back =
        load(file).unwrap_or_else(|e| panic!("{what}: the saved scene does not load: {e}\n{text}"));
    assert!(
        back.warnings.len() <= scene.warnings.len(),
        "{what}: {:?}",
        back.warnings
    );
    assert_same(scene, &back, &what);
    let again = encode(&back, file.parent()).to_text();
    assert_eq!(text, again, "{what}: encoding is not a fixed point");
    // The Value (sorted keys) reads back as the same scene, up to the order of the materials.
    let value = serde_json::to_string(&to_json(&back)).unwrap();
    let from_value = parse(&value, file).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_same_with(scene, &from_value, &format!("{what} (Value)"), false);
    (back, text)
}

fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "json") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

// ---------------------------------------------------------------------------------------------
// Scenes.

#[test]
fn every_asset_scene_round_trips() {
    let assets = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("assets/scenes");
    let out = scratch("assets");
    let files = json_files(&assets);
    assert!(files.len() >= 30, "found only {} scenes", files.len());
    for file in &files {
        let scene = load(file).unwrap_or_else(|e| panic!("{e}"));
        let rel = file.strip_prefix(&assets).unwrap();
        round_trip(&scene, &out.join(rel));
    }
    eprintln!("{} asset scenes round-tripped", files.len());
    std::fs::remove_dir_all(out).unwrap();
}

#[test]
fn default_scene_round_trips() {
    let out = scratch("default");
    let scene = default_scene();
    assert!(scene.source.is_none());
    let (back, text) = round_trip(&scene, &out.join("default.json"));
    assert_eq!(back.objects.len(), scene.objects.len());
    // The embedded text and the encoder's agree on every value.
    let embedded = parse(DEFAULT_SCENE_JSON, &out.join("embedded.json")).unwrap();
    assert_same(&embedded, &back, "embedded");
    // A source-less scene has no folder: to_json writes the same as a save anywhere here.
    assert_eq!(
        to_json(&scene),
        serde_json::from_str::<Value>(&text).unwrap()
    );
    std::fs::remove_dir_all(out).unwrap();
}

#[test]
fn edited_scene_round_trips() {
    let out = scratch("edited");
    let mut scene = default_scene();
    scene.lights[0].intensity = 1.375;
    scene.lights[1].color = Vec3::new(0.1, 0.2, 0.3);
    let Material::Phong(crate::brdf::PhongParams { kd, shininess, .. }) =
        &mut scene.materials[0].material
    else {
        panic!("the default scene's first material is Blinn-Phong")
    };
    *kd = 0.123_456_79;
    *shininess = 77.7;
    scene.lights.push(Light {
        kind: LightKind::Spot,
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
        position: Vec3::new(0.5, 4.0, 1.0),
        color: Vec3::new(1.0, 0.5, 0.25),
        intensity: 12.5,
        falloff: Falloff::Classic {
            c1: 1.0,
            c2: 0.05,
            c3: 0.0125,
        },
        umbra_deg: 33.0,
        inner_deg: Some(21.5),
        exponent: 1.5,
        range: Some(4.5),
        shadow: None,
        radius: 0.0,
        angular_radius_deg: 0.0,
    });
    scene.materials.push(NamedMaterial {
        name: "new clay".to_string(),
        material: Material::OrenNayar(crate::brdf::OrenNayarParams {
            albedo: Vec3::new(0.7, 0.45, 0.3),
            sigma_deg: 31.0,
        }),
        textures: MaterialTextures {
            emissive_factor: Vec3::new(0.0, 0.1, 0.0),
            ..MaterialTextures::default()
        },
    });
    let last = scene.materials.len() - 1;
    scene.objects[1].material = last;
    scene.objects[1].transform.position += Vec3::new(0.1, 0.2, 0.3);
    scene.objects[1].transform.scale = Vec3::new(1.0, 2.0, 0.5);
    scene.objects[2].shading = Shading::Flat;
    scene.objects[0].name = "renamed floor".to_string();
    scene.camera.position = Vec3::new(1.0, 3.0, 7.0);
    scene.camera.up = Vec3::new(0.1, 1.0, 0.05).normalize();
    scene.output.tonemap = crate::color::Tonemap::Agx;
    scene.output.exposure = 0.5;
    scene.fog = Some(Fog {
        z_a: 2.0,
        z_b: 30.0,
        s_a: 0.05,
        s_b: 0.7,
        color: Vec3::splat(0.1),
    });
    scene.saturation = Saturation::Clamp;
    scene.environment = Some(Environment {
        intensity: 0.8,
        rotation_deg: -45.0,
        ..Environment::new(EnvSource::Sky {
            sun_direction: Vec3::new(0.2, -0.5, -0.7).normalize(),
            sun_intensity: 4.5,
        })
    });
    scene.output.tessellation_error_px = 0.2;
    scene.output.golden = crate::diff::ToleranceOverrides {
        max_flip_mean: Some(Some(0.01)),
        max_bad_pixels: Some(None),
        ..Default::default()
    };
    // The spheres stay automatic: the file leaves their segments out, and loading it chooses them
    // for the edited camera and budget, as resolving the edited scene does.
    crate::scene::tessellation::resolve(&mut scene);
    let (back, _) = round_trip(&scene, &out.join("edited.json"));
    assert!(matches!(
        back.objects[1].tessellation,
        crate::scene::Tessellation::Auto { .. }
    ));
    assert_eq!(back.output.golden, scene.output.golden);
    assert_eq!(back.lights[0].intensity, 1.375);
    assert_eq!(back.lights.len(), 3);
    assert_eq!(back.objects[1].material, last);
    assert_eq!(back.materials[last].name, "new clay");
    assert!(matches!(
        back.materials[0].material,
        Material::Phong(crate::brdf::PhongParams { kd, shininess, .. }) if kd == 0.123_456_79 && shininess == 77.7
    ));
    std::fs::remove_dir_all(out).unwrap();
}

/// Every light kind and falloff, every material model with every parameter, every specular
/// source, texture maps with every sampler setting, every mesh type, fog, and every environment
/// source and setting; saved into another folder, so every path is rewritten.
#[test]
fn every_field_round_trips() {
    let dir = scratch("fields");
    let tex = dir.join("tex ü");
    for name in [
        "albedo.png",
        "spec.png",
        "normal.png",
        "ao.png",
        "emit.png",
        "rough.png",
        "orm.png",
        "mr.png",
    ] {
        png(&tex.join(name));
    }
    hdr(&dir.join("env/sky.hdr"));
    let src = dir.join("src/scene.json");
    write(
        &src,
        r#"{
 "description": "every field \"quoted\", ünïcödé\nand a new line",
 "camera": {"position": [1.5, 2.25, 7], "target": [0.1, 0.2, -0.3], "up": [0.1, 1, 0.2],
            "fov_y_deg": 37.5, "near": 0.05, "far": 250},
 "output": {"width": 333, "height": 222, "background": [0.01, 0.02, 0.03], "exposure": -1.25,
            "tonemap": "agx", "msaa": 8},
 "ambient": [0.1, 0.2, 0.3],
 "saturation": "normalize",
 "lights": [
   {"type": "directional", "direction": [0.3, -1, -0.7], "color": [1, 0.9, 0.8], "intensity": 0.7},
   {"type": "directional", "position": [1, 2, 3], "target": [0, 0.1, 0], "intensity": 2},
   {"type": "point", "position": [1, 2, 3], "color": 0.5, "intensity": 5, "falloff": "none"},
   {"type": "point", "position": [-1, 2, 3], "intensity": 5},
   {"type": "point", "position": [-1, 2, -3], "intensity": 0,
    "falloff": {"c1": 0.5, "c2": 0.25, "c3": 0.125}},
   {"type": "spot", "position": [0, 4, 3], "target": [0, 0, 0], "intensity": 10, "umbra_deg": 25,
    "inner_deg": 15, "exponent": 2, "falloff": {"c1": 1, "c2": 0.1, "c3": 0.01}},
   {"type": "spot", "position": [0, 4, -3], "direction": [0.1, -1, 0.2], "intensity": 1e-7,
    "umbra_deg": 90, "inner_deg": 0}
 ],
 "materials": {
   "phong": {"model": "phong", "ka": 0.3, "kd": 0.7, "ks": 0.4, "shininess": 17,
     "diffuse_color": [0.9, 0.1, 0.2], "specular_color": [0.5, 0.6, 0.7],
     "textures": {
       "base_color": "../tex ü/albedo.png",
       "specular": {"path": "../tex ü/spec.png", "wrap_u": "clamp", "wrap_v": "mirror",
                    "mag_filter": "nearest", "min_filter": "linear", "mipmaps": false, "anisotropy": 4},
       "normal": {"path": "../tex ü/normal.png", "wrap": "mirror", "filter": "nearest"},
       "normal_scale": -0.5,
       "occlusion": {"path": "../tex ü/ao.png", "channel": "g"},
       "occlusion_strength": 0.75,
       "emissive": "../tex ü/emit.png", "emissive_factor": [2, 3, 4]}},
   "blinn": {"model": "blinn_phong", "ka": 0, "kd": 1.5, "ks": 0, "shininess": 0,
     "diffuse_color": 0.25, "specular_color": [0, 0, 0]},
   "lambert": {"model": "lambert", "albedo": [0.2, 0.3, 0.4],
     "textures": {"emissive_factor": [0.5, 0.5, 0.5]}},
   "lambert_default": {"model": "lambert"},
   "ct_ior": {"model": "cook_torrance", "color": [0.1, 0.2, 0.3], "kd": 0.5, "roughness": 0.25,
     "distribution": "ggx", "geometry": "smith_ggx", "fresnel": "dielectric", "ior": 1.33,
     "textures": {"roughness": {"path": "../tex ü/rough.png", "channel": "b"},
                  "base_color": {"path": "../tex ü/albedo.png", "filter": "nearest"}}},
   "ct_f0": {"model": "cook_torrance", "fresnel": "schlick_sg", "f0": [0.04, 0.05, 0.06],
     "geometry": "schlick_ggx", "diffuse": "burley"},
   "ct_complex": {"model": "cook_torrance", "fresnel": "conductor", "distribution": "beckmann",
     "geometry": "smith_ggx_correlated",
     "complex_ior": {"eta": [0.2378, 1.0066, 1.2404], "k": [3.6264, 2.5823, 2.3929]}},
   "ct_gold": {"model": "cook_torrance", "color": [1, 0.86, 0.48], "kd": 0.75,
     "roughness": 0.05, "preset": "gold"},
   "ct_water": {"model": "cook_torrance", "preset": "water"},
   "ct_default": {"model": "cook_torrance"},
   "mr": {"model": "metal_rough", "base_color": [0.5, 0.25, 0.125], "metallic": 0.3,
     "roughness": 0.6, "distribution": "beckmann", "geometry": "cook_torrance",
     "fresnel": "dielectric", "diffuse_fresnel_weight": true, "diffuse": "burley",
     "textures": {"orm": {"path": "../tex ü/orm.png", "anisotropy": 1}, "occlusion_strength": 0.5,
                  "normal": "../tex ü/normal.png"}},
   "mr_copper": {"model": "metal_rough", "preset": "copper", "roughness": 0.4, "fresnel": "conductor",
     "textures": {"metallic": {"path": "../tex ü/mr.png", "channel": "b"},
                  "roughness": {"path": "../tex ü/mr.png", "channel": "a"},
                  "occlusion": "../tex ü/ao.png"}},
   "mr_default": {"model": "metal_rough"},
   "mr_coat": {"model": "metal_rough", "metallic": 0, "roughness": 0.5,
     "clearcoat": {"clearcoatFactor": 0.75, "clearcoatRoughnessFactor": 0.125}},
   "mr_glass": {"model": "metal_rough", "metallic": 0, "roughness": 0.1,
     "ior": {"ior": 1.33}, "specular": {"specularFactor": 0.8, "specularColorFactor": [1, 0.9, 1.25]},
     "transmission": {"transmissionFactor": 1}, "volume": {"thicknessFactor": 0.5},
     "diffuse_transmission": {"diffuseTransmissionFactor": 0.25},
     "textures": {"transmission": "../tex ü/rough.png", "thickness": {"path": "../tex ü/mr.png", "channel": "g"},
                  "diffuse_transmission": {"path": "../tex ü/mr.png", "channel": "a"},
                  "diffuse_transmission_color": "../tex ü/albedo.png"}},
   "principled": {"model": "principled", "base_color": [0.05, 0.1, 0.7], "subsurface": 0.1,
     "metallic": 0.2, "specular": 0.3, "specular_tint": 0.4, "roughness": 0.55, "anisotropic": 0.6,
     "sheen": 0.7, "sheen_tint": 0.8, "clearcoat": 0.9, "clearcoat_gloss": 0.15,
     "textures": {"metallic": "../tex ü/mr.png", "emissive": "../tex ü/emit.png"}},
   "principled_default": {"model": "principled"},
   "oren": {"model": "oren_nayar", "albedo": [0.7, 0.45, 0.3], "sigma_deg": 33,
     "textures": {"base_color": "../tex ü/albedo.png", "normal": "../tex ü/normal.png"}},
   "oren_default": {"model": "oren_nayar"}
 },
 "objects": [
   {"name": "floor", "mesh": {"type": "plane", "size": [12, 7.5], "subdivisions": 8}, "material": "phong"},
   {"mesh": {"type": "plane"}, "material": "blinn", "position": [0, -1, 0]},
   {"mesh": {"type": "sphere", "radius": 0.5, "segments": 17, "rings": 9}, "material": "ct_ior",
    "position": [-1, 0.5, 0], "rotation_deg": [10, 20, 30], "scale": [1, 0.5, 2], "shading": "gouraud"},
   {"mesh": {"type": "sphere"}, "material": "ct_f0"},
   {"mesh": {"type": "icosphere", "radius": 0.25, "subdivisions": 0}, "material": "ct_complex",
    "shading": "flat", "scale": 3},
   {"mesh": {"type": "icosphere"}, "material": "ct_gold"},
   {"name": "box", "mesh": {"type": "cube", "size": 0.6}, "material": "mr", "rotation_deg": [0, 30, 0]},
   {"mesh": {"type": "cube"}, "material": "mr_copper"},
   {"mesh": {"type": "cone", "radius": 0.3, "height": 0.9, "segments": 5}, "material": "principled"},
   {"mesh": {"type": "cone"}, "material": "oren"},
   {"mesh": {"type": "cylinder", "radius": 0.2, "height": 2, "segments": 3}, "material": "lambert"},
   {"name": "same name", "mesh": {"type": "cylinder"}, "material": "ct_water"},
   {"name": "same name", "mesh": {"type": "cylinder"}, "material": "ct_water", "position": [1e-30, -3e38, 1e20]}
 ],
 "fog": {"z_a": 1, "z_b": 30, "s_a": 0.1, "s_b": 0.9, "color": [0.2, 0.3, 0.4]},
 "environment": {"hdr": "../env/sky.hdr", "intensity": 1.5, "rotation_deg": 33,
   "specular_method": "importance", "samples": 128, "diffuse_method": "cubemap",
   "energy_compensation": true, "mip_filtered_samples": false, "show_background": false}
}"#,
    );
    let scene = load(&src).unwrap_or_else(|e| panic!("{e}"));
    let (_, text) = round_trip(&scene, &dir.join("out/deep/scene.json"));
    // Paths are relative to the new folder; a map with the default sampler is a plain name.
    assert!(
        text.contains(r#""base_color": "../../tex ü/albedo.png""#),
        "{text}"
    );
    assert!(text.contains(r#""hdr": "../../env/sky.hdr""#), "{text}");
    // The diffuse selector is written (and read back by the round trip).
    assert!(text.contains(r#""diffuse": "burley""#), "{text}");
    assert!(text.contains(r#""diffuse": "lambert""#), "{text}");
    assert!(
        text.contains(r#""position": [1e-30, -3e38, 1e20]"#),
        "{text}"
    );
    // In the scene's own folder the paths are those of the original file.
    let (_, text) = round_trip(&scene, &dir.join("src/copy.json"));
    assert!(
        text.contains(r#""normal": "../tex ü/normal.png""#),
        "{text}"
    );

    // Every other environment source, no environment and no fog; every tone map and
    // saturation.
    let sources = [
        Some(EnvSource::Uniform(Vec3::new(1.0, 0.5, 0.25))),
        Some(EnvSource::Sky {
            sun_direction: Vec3::new(-0.4, -0.75, -0.5).normalize(),
            sun_intensity: 50.0,
        }),
        Some(EnvSource::Studio),
        None,
    ];
    for (i, source) in sources.into_iter().enumerate() {
        let mut s = scene.clone();
        s.environment = source.map(|src| Environment {
            samples: 1024,
            specular_method: SpecularMethod::SplitSum,
            diffuse_method: DiffuseMethod::Sh9,
            ..Environment::new(src)
        });
        s.fog = None;
        s.output.tonemap = crate::color::Tonemap::ALL[i];
        s.saturation = [Saturation::Clamp, Saturation::None][i % 2];
        round_trip(&s, &dir.join(format!("out/env{i}.json")));
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// A multi-part OBJ with MTL materials and texture maps, used several ways: MTL materials, one
/// given material, twice in a row at the same place (the entries share meshes), a second OBJ
/// with the same file name (MTL names get "#2"), a single-part OBJ, and a sphere using an MTL
/// material by name.
#[test]
fn obj_parts_and_mtl_materials_round_trip() {
    let dir = scratch("obj");
    let obj = "mtllib quad.mtl\no first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\n\
               vt 1 1\nvt 0 1\nusemtl red\nf 1/1 2/2 3/3 4/4\no second\nusemtl shiny\nf 1 3 2\n\
               usemtl nowhere\nf 1 4 3\n";
    let mtl =
        "newmtl red\nKa 0.1 0.2 0.3\nKd 1 0 0\nmap_Kd maps/red.png\nmap_Bump -bm 0.5 maps/n.png\n\
               newmtl shiny\nKs 0.5 0.5 0.5\nNs 100\nmap_Ke -clamp on maps/e.png\nKe 2 2 2\n\
               newmtl pbr\nPr 0.3\nmap_Pm -imfchan b maps/m.png\n";
    for d in ["models", "models/other"] {
        write(&dir.join(d).join("quad.obj"), obj);
        write(&dir.join(d).join("quad.mtl"), mtl);
        for m in ["red.png", "n.png", "e.png", "m.png"] {
            png(&dir.join(d).join("maps").join(m));
        }
    }
    // The PBR material, on a single-part OBJ.
    write(
        &dir.join("models/tri.obj"),
        "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl pbr\nf 1 2 3\n",
    );
    let src = dir.join("scenes/s.json");
    write(
        &src,
        r#"{"materials": {"m": {"model": "lambert"}}, "objects": [
            {"name": "q", "mesh": {"type": "obj", "path": "../models/quad.obj"}},
            {"mesh": {"type": "obj", "path": "../models/quad.obj"}, "material": "m"},
            {"mesh": {"type": "obj", "path": "../models/quad.obj"}, "position": [1, 0, 0]},
            {"mesh": {"type": "obj", "path": "../models/quad.obj"}, "position": [1, 0, 0]},
            {"mesh": {"type": "sphere"}, "material": "quad.obj/red"},
            {"mesh": {"type": "obj", "path": "../models/other/quad.obj"}, "shading": "flat"},
            {"mesh": {"type": "obj", "path": "../models/tri.obj"}},
            {"name": "tri with m", "mesh": {"type": "obj", "path": "../models/tri.obj"}, "material": "m",
             "scale": [1, 2, 3]}
        ]}"#,
    );
    let scene = load(&src).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.objects.len(), 3 + 2 + 3 + 3 + 1 + 3 + 1 + 1);
    let mats: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        mats,
        [
            "m",
            "quad.obj/red",
            "quad.obj/shiny",
            "quad.obj/default",
            "quad.obj/red#2",
            "quad.obj/shiny#2",
            "quad.obj/default#2",
            "tri.obj/pbr"
        ]
    );
    assert!(!material_named(&scene, "quad.obj/red").textures.is_empty());

    // Saved elsewhere: every path is rewritten relative to the new folder.
    let (_, text) = round_trip(&scene, &dir.join("out/a/b/scene.json"));
    assert_eq!(text.matches(r#""type": "obj""#).count(), 7, "{text}");
    assert!(
        text.contains(r#""path": "../../../models/quad.obj""#),
        "{text}"
    );
    assert!(text.contains(r#""material": "quad.obj/red""#), "{text}");
    // MTL materials are not written: loading the OBJ makes them.
    assert!(!text.contains(r#""quad.obj/red": {"#), "{text}");
    // Saved next to the original: the paths are the original's.
    let (_, text) = round_trip(&scene, &dir.join("scenes/copy.json"));
    assert!(text.contains(r#""path": "../models/quad.obj""#), "{text}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// Edits the format cannot express are approximated without duplicating geometry, and named.
#[test]
fn edits_the_format_cannot_express_are_noted() {
    let dir = scratch("lossy");
    write(
        &dir.join("quad.obj"),
        "mtllib quad.mtl\no a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl red\nf 1 2 3\no b\nusemtl blue\nf 1 3 2\n",
    );
    write(
        &dir.join("quad.mtl"),
        "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n",
    );
    let src = dir.join("s.json");
    write(
        &src,
        r#"{"materials": {"m": {"model": "lambert"}, "quad.obj_red": {"model": "lambert"}},
            "objects": [
            {"name": "ball", "mesh": {"type": "sphere"}, "material": "m"},
            {"mesh": {"type": "obj", "path": "quad.obj"}},
            {"mesh": {"type": "obj", "path": "quad.obj"}, "material": "m"}]}"#,
    );
    let scene = load(&src).unwrap();
    assert_eq!(scene.objects.len(), 5);
    let red = scene.material_index("quad.obj/red").unwrap();
    let out = dir.join("out/s.json");
    std::fs::create_dir_all(out.parent().unwrap()).unwrap();

    // A sphere (before the OBJ that makes the material) takes an MTL material: written as a
    // copy under a free name.
    let mut s = scene.clone();
    s.objects[0].material = red;
    let notes = encode(&s, out.parent()).notes;
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(notes[0].contains("\"quad.obj_red_2\""), "{notes:?}");
    save(&s, &out).unwrap();
    let back = load(&out).unwrap();
    assert_eq!(back.objects.len(), 5);
    let copy = &back.materials[back.objects[0].material];
    assert_eq!(copy.name, "quad.obj_red_2");
    assert_eq!(copy.material, s.materials[red].material);

    // One part of an OBJ moved or given another material: the entry keeps the first part's
    // transform and the MTL materials (or its one material), and no part is duplicated. (The
    // second OBJ entry, at the same place with one material, repeats the part names: it stays
    // an entry of its own.)
    type Edit = fn(&mut Scene);
    let edits: [(Edit, &str); 4] = [
        (
            |s| s.objects[2].transform.position = Vec3::X,
            "object \"quad/b\": the parts of one OBJ entry share one transform",
        ),
        (
            |s| s.objects[4].material = 1,
            "object \"quad/b\": the parts of one OBJ entry share one material",
        ),
        (
            |s| s.objects[2].material = 0,
            "object \"quad/b\": one part of an OBJ whose parts take their materials from its MTL file",
        ),
        (
            |s| s.objects[1].material = 0,
            "object \"quad/a\": one part of an OBJ whose parts take their materials from its MTL file",
        ),
    ];
    for (edit, note) in edits {
        let mut s = scene.clone();
        edit(&mut s);
        let notes = encode(&s, out.parent()).notes;
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].starts_with(note), "{notes:?}");
        save(&s, &out).unwrap();
        let back = load(&out).unwrap();
        assert_same(&scene, &back, note);
    }

    // A normal scale without a normal map, a map the model does not take, a channel on a
    // colour map: noted, and the file still loads.
    let mut s = scene.clone();
    s.materials[0].textures.normal_scale = 2.0;
    png(&dir.join("t.png"));
    let mut t = TextureRef::new(dir.join("t.png"));
    s.materials[0].textures.metallic = Some(t.clone());
    t.channel = Some(1);
    s.materials[0].textures.base_color = Some(t);
    let notes = encode(&s, out.parent()).notes;
    assert_eq!(notes.len(), 3, "{notes:?}");
    save(&s, &out).unwrap();
    let back = load(&out).unwrap();
    assert!(back.materials[0].textures.base_color.is_some());
    assert!(back.materials[0].textures.metallic.is_none());
    std::fs::remove_dir_all(dir).unwrap();
}

/// Real OBJ files, texture set and environment from `../shared`, saved under the temporary
/// folder: the paths are absolute when the two share only the root, relative when they share a
/// folder (a clone under the temporary folder, or a temporary folder under the clone's parent).
#[test]
fn shared_models_round_trip() {
    let (Some(models), Some(textures), Some(envs)) = (
        shared_dir("models"),
        shared_dir("textures/gold"),
        shared_dir("environments"),
    ) else {
        return;
    };
    let dir = scratch("shared");
    let q = |p: PathBuf| serde_json::to_string(&p.to_string_lossy()).unwrap();
    let mut objects = Vec::new();
    for (i, name) in [
        "teapot",
        "suzanne",
        "spot",
        "cow",
        "homer",
        "stanford-bunny",
    ]
    .iter()
    .enumerate()
    {
        let material = if i % 2 == 0 {
            r#", "material": "gold""#
        } else {
            ""
        };
        objects.push(format!(
            r#"{{"mesh": {{"type": "obj", "path": {}}}{material}, "position": [{i}, 0, 0], "scale": 0.2}}"#,
            q(models.join(format!("{name}.obj")))
        ));
    }
    let t = |n: &str| q(textures.join(n));
    let text = format!(
        r#"{{"materials": {{"gold": {{"model": "metal_rough", "roughness": 1,
              "textures": {{"base_color": {}, "normal": {}, "roughness": {}, "metallic": {},
                           "occlusion": {}}}}}}},
            "objects": [{}],
            "environment": {{"hdr": {}, "intensity": 0.5}}}}"#,
        t("albedo.png"),
        t("normal.png"),
        t("roughness.png"),
        t("metallic.png"),
        t("ao.png"),
        objects.join(",\n"),
        q(envs.join("newport_loft.hdr"))
    );
    let src = dir.join("src/shared.json");
    write(&src, &text);
    let scene = load(&src).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.triangle_count() > 69_000);
    let (_, saved) = round_trip(&scene, &dir.join("out/shared.json"));
    // The teapot as the encoder names it (its folder resolved, its name kept), seen from the
    // folder the scene was saved in.
    let teapot = canon(&models).join("teapot.obj");
    let saved_dir = canon(&dir.join("out"));
    let t: Vec<Component> = teapot.components().collect();
    let d: Vec<Component> = saved_dir.components().collect();
    let common = t.iter().zip(&d).take_while(|(a, b)| a == b).count();
    let expected = if t[..common]
        .iter()
        .any(|c| matches!(c, Component::Normal(_)))
    {
        let mut parts = vec!["..".to_string(); d.len() - common];
        parts.extend(
            t[common..]
                .iter()
                .map(|c| c.as_os_str().to_string_lossy().into_owned()),
        );
        parts.join("/")
    } else {
        teapot.to_string_lossy().into_owned()
    };
    assert!(
        saved.contains(&serde_json::to_string(&expected).unwrap()),
        "expected the teapot as {expected:?} in {}:\n{saved}",
        saved_dir.display()
    );
    std::fs::remove_dir_all(dir).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Pieces.

#[test]
fn numbers_read_back_exactly() {
    let check = |x: f32| {
        let text = num_text(x).unwrap();
        let back = text.parse::<f64>().unwrap() as f32;
        assert_eq!(back.to_bits(), x.to_bits(), "{x:?} written as {text}");
        let v = Node::Num(x).to_value();
        assert_eq!(
            (v.as_f64().unwrap() as f32).to_bits(),
            x.to_bits(),
            "{x:?} in a Value: {v}"
        );
        // The scene's own JSON reader agrees.
        let doc = crate::scene::json::parse(&text).unwrap();
        let crate::scene::json::Kind::Number { value, .. } = doc.kind else {
            panic!("{text}")
        };
        assert_eq!((value as f32).to_bits(), x.to_bits(), "{text}");
    };
    for x in [
        0.0,
        -0.0,
        0.1,
        0.8,
        1.0 / 3.0,
        1e-7,
        f32::MIN_POSITIVE,
        1e-45,
        f32::MAX,
        f32::MIN,
        16_777_216.0,
        1.2,
        1.0 + f32::EPSILON,
        f32::from_bits(1),
    ] {
        check(x);
    }
    // A stride through every finite bit pattern, both signs.
    let mut bits: u32 = 0;
    let mut n = 0;
    while bits < 0x7f80_0000 {
        check(f32::from_bits(bits));
        check(-f32::from_bits(bits));
        bits += 4093;
        n += 1;
    }
    assert!(n > 500_000);
    assert!(num_text(f32::NAN).is_none() && num_text(f32::INFINITY).is_none());
    assert_eq!(num_text(0.8).unwrap(), "0.8");
    assert_eq!(num_text(64.0).unwrap(), "64.0");
}

#[test]
fn unit_vectors_normalise_to_themselves() {
    // A small deterministic generator (xorshift).
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    };
    let mut moved = 0;
    let mut missed = Vec::new();
    for _ in 0..200_000 {
        let v = Vec3::new(next(), next(), next());
        let Some(u) = unit(v) else { continue };
        if unit(u) != Some(u) {
            moved += 1;
        }
        let w = unit_preimage(u);
        if unit(w) != Some(u) {
            missed.push((v, u, w));
        }
    }
    eprintln!(
        "{moved} of 200000 unit vectors move when normalised again; missed {}",
        missed.len()
    );
    assert!(missed.is_empty(), "{:?}", &missed[..missed.len().min(5)]);
    assert_eq!(
        unit_preimage(Vec3::new(0.0, 3.0, 0.0)),
        Vec3::new(0.0, 3.0, 0.0)
    );
}

#[test]
fn paths_are_relative_when_they_share_a_folder() {
    let dir = scratch("paths");
    for f in ["a/b/scene/x.png", "a/c/y.obj", "a/b/scene/sub/z.hdr"] {
        write(&dir.join(f), "");
    }
    let scene_dir = canonical_dir(&dir.join("a/b/scene"));
    let rel = |f: &str| file_path(&dir.join(f), Some(&scene_dir));
    assert_eq!(rel("a/b/scene/x.png"), "x.png");
    assert_eq!(rel("a/c/y.obj"), "../../c/y.obj");
    assert_eq!(rel("a/b/scene/sub/z.hdr"), "sub/z.hdr");
    // `..` and `.` in the stored path are resolved.
    assert_eq!(rel("a/b/scene/../../c/./y.obj"), "../../c/y.obj");
    // A missing file is still written (lexically normalised).
    assert_eq!(rel("a/missing/w.png"), "../../missing/w.png");
    // Only the root in common: absolute.
    assert_eq!(
        file_path(Path::new("/x/y.png"), Some(&scene_dir)),
        "/x/y.png"
    );
    // No folder: absolute.
    let abs = file_path(&dir.join("a/c/y.obj"), None);
    assert!(
        Path::new(&abs).is_absolute() && abs.ends_with("a/c/y.obj"),
        "{abs}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn save_errors_name_the_file() {
    let dir = scratch("errors");
    let target = dir.join("no/such/folder/s.json");
    let e = save(&default_scene(), &target).unwrap_err();
    assert!(
        e.to_string().starts_with(&format!(
            "{}: cannot write the scene file",
            target.display()
        )),
        "{e}"
    );
    // Nothing is left behind; an existing file is replaced.
    let file = dir.join("s.json");
    std::fs::write(&file, "old").unwrap();
    save(&default_scene(), &file).unwrap();
    assert!(load(&file).is_ok());
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(left.len(), 1, "{left:?}");
    std::fs::remove_dir_all(dir).unwrap();
}
