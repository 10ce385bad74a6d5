//! Textures on the CPU: decoding real and generated files, mip chains, sRGB-correct averaging,
//! downscaling to a device limit, errors naming the file; the `textures` block of scene files and
//! the texture maps of OBJ/MTL files. No GPU.

mod common;

use std::path::{Path, PathBuf};
use std::time::Instant;

use common::{scratch, shared_dir};
use image::{DynamicImage, ImageBuffer, Luma, Rgba, RgbaImage};
use luz::scene::{self, Material, TextureRef, TextureSlot, Wrap};
use luz::texture::{
    checker, load_texture, mip_count, mip_extent, noise_normal_map, texture_from_image, ColorSpace,
    TexFormat, TextureData, TextureError,
};

fn write_png(dir: &Path, name: &str, img: &RgbaImage) -> PathBuf {
    let p = dir.join(name);
    img.save(&p).unwrap();
    p
}

fn load(
    path: &Path,
    space: ColorSpace,
    max: u32,
) -> (Result<TextureData, TextureError>, Vec<String>) {
    let mut warnings = Vec::new();
    let r = load_texture(&TextureRef::new(path), space, max, &mut |w| {
        warnings.push(w)
    });
    (r, warnings)
}

/// Every level has the Vulkan extent and the right byte count.
fn check_chain(t: &TextureData) {
    assert_eq!(t.mips.len() as u32, mip_count(t.width, t.height));
    for (k, level) in t.mips.iter().enumerate() {
        let (w, h) = mip_extent(t.width, t.height, k as u32);
        assert_eq!(
            level.len(),
            w as usize * h as usize * t.format.bytes_per_texel(),
            "level {k}"
        );
    }
    assert_eq!(t.level_extent(t.mips.len() - 1), (1, 1));
}

#[test]
fn real_pbr_set_decodes_with_full_mip_chains() {
    let Some(dir) = shared_dir("textures/gold") else {
        return;
    };
    for (file, space, format, size) in [
        ("albedo.png", ColorSpace::Srgb, TexFormat::Rgba8Srgb, 2048),
        (
            "normal.png",
            ColorSpace::NormalMap,
            TexFormat::Rgba8Unorm,
            2048,
        ),
        (
            "roughness.png",
            ColorSpace::Linear,
            TexFormat::Rgba8Unorm,
            2048,
        ),
        (
            "metallic.png",
            ColorSpace::Linear,
            TexFormat::Rgba8Unorm,
            2048,
        ),
        ("ao.png", ColorSpace::Linear, TexFormat::Rgba8Unorm, 512),
    ] {
        let start = Instant::now();
        let (t, warnings) = load(&dir.join(file), space, 16384);
        let t = t.unwrap_or_else(|e| panic!("{e}"));
        println!(
            "{file}: {}×{}, {} levels, {:.0} ms",
            t.width,
            t.height,
            t.mips.len(),
            start.elapsed().as_secs_f64() * 1e3
        );
        assert!(warnings.is_empty(), "{file}: {warnings:?}");
        assert_eq!(
            (t.width, t.height, t.format),
            (size, size, format),
            "{file}"
        );
        check_chain(&t);
        if space == ColorSpace::NormalMap {
            // Renormalised levels decode to unit vectors pointing out of the surface.
            for level in 1..t.mips.len() {
                for p in t.mips[level].chunks(4) {
                    let n = [p[0], p[1], p[2]].map(|c| c as f32 / 127.5 - 1.0);
                    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                    assert!(
                        (len - 1.0).abs() < 0.02 && n[2] > 0.0,
                        "{file} level {level}: {p:?}"
                    );
                }
            }
        }
    }
    // Downscaled to a small device limit, still with a full chain and a warning.
    let (t, warnings) = load(&dir.join("albedo.png"), ColorSpace::Srgb, 300);
    let t = t.unwrap();
    assert_eq!((t.width, t.height), (300, 300));
    check_chain(&t);
    assert_eq!(warnings.len(), 1);
    assert!(
        warnings[0].contains("albedo.png")
            && warnings[0].contains("2048×2048")
            && warnings[0].contains("300×300"),
        "{warnings:?}"
    );
}

/// Mip generation is linear in the pixels: a 2048² chain costs about 16× a 512² one (quadratic
/// work would cost 256×; caches make the larger one up to a few times dearer per pixel). The
/// best of three runs each, in the same run: no absolute time, which busy CI machines miss.
#[test]
fn mip_generation_of_2048_squared_is_linear() {
    let build = |size: u32, space: ColorSpace| {
        let img = DynamicImage::ImageRgba8(noise_normal_map(size, 5, 1.0));
        (0..3)
            .map(|_| {
                let start = Instant::now();
                let t = texture_from_image(
                    &img,
                    Path::new("noise.png"),
                    space,
                    None,
                    true,
                    16384,
                    &mut |w| panic!("{w}"),
                )
                .unwrap();
                check_chain(&t);
                start.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    for space in [ColorSpace::Srgb, ColorSpace::NormalMap] {
        let (small, large) = (build(512, space), build(2048, space));
        let ratio = large / small;
        println!(
            "{space:?}: 512² {:.1} ms, 2048² {:.0} ms, ratio {ratio:.2} (16 is linear)",
            small * 1e3,
            large * 1e3
        );
        if !cfg!(debug_assertions) {
            assert!(ratio < 64.0, "{space:?}: 2048² costs {ratio:.2}× 512²");
        }
    }
}

#[test]
fn srgb_mips_of_a_black_and_white_checker_are_188() {
    let dir = scratch("checker");
    let black = [0, 0, 0, 255];
    let white = [255, 255, 255, 255];
    // One-texel cells: level 1 is already the average.
    let p = write_png(&dir, "fine.png", &checker(64, 64, black, white));
    let t = load(&p, ColorSpace::Srgb, 4096).0.unwrap();
    assert_eq!(t.format, TexFormat::Rgba8Srgb);
    check_chain(&t);
    assert_eq!(
        t.mips[0],
        checker(64, 64, black, white).into_raw(),
        "level 0 is the file's bytes"
    );
    for level in 1..t.mips.len() {
        assert!(
            t.mips[level].chunks(4).all(|p| p == [188, 188, 188, 255]),
            "level {level}"
        );
        let v = t.texel(level, 0, 0).unwrap();
        assert!((v[0] - 0.5).abs() < 0.003, "{v:?}");
    }
    // Two-texel cells: level 1 is still black and white, level 2 the average.
    let p = write_png(&dir, "coarse.png", &checker(64, 32, black, white));
    let t = load(&p, ColorSpace::Srgb, 4096).0.unwrap();
    assert_eq!(&t.mips[1][..8], &[0, 0, 0, 255, 255, 255, 255, 255]);
    assert!(t.mips[2].chunks(4).all(|p| p == [188, 188, 188, 255]));
    // The same file as linear data averages codes: 128.
    let t = load(&p, ColorSpace::Linear, 4096).0.unwrap();
    assert!(t.mips[2].chunks(4).all(|p| p == [128, 128, 128, 255]));
}

#[test]
fn odd_sizes_and_no_mipmaps() {
    let dir = scratch("odd");
    let p = write_png(
        &dir,
        "odd.png",
        &RgbaImage::from_fn(37, 5, |x, y| Rgba([(x * 6) as u8, (y * 50) as u8, 7, 255])),
    );
    let t = load(&p, ColorSpace::Linear, 4096).0.unwrap();
    assert_eq!((t.width, t.height, t.mips.len()), (37, 5, 6));
    check_chain(&t);
    // A constant channel stays constant at every level (weights sum to 1).
    for level in &t.mips {
        assert!(level.chunks(4).all(|p| p[2] == 7 && p[3] == 255));
    }
    let mut r = TextureRef::new(&p);
    r.sampler.mipmaps = false;
    let t = load_texture(&r, ColorSpace::Linear, 4096, &mut |_| {}).unwrap();
    assert_eq!(t.mips.len(), 1);
}

#[test]
fn downscaling_to_the_device_limit_warns_with_both_sizes() {
    let dir = scratch("downscale");
    let p = write_png(
        &dir,
        "big.png",
        &checker(64, 16, [255, 0, 0, 255], [0, 0, 255, 255]),
    );
    let (t, warnings) = load(&p, ColorSpace::Srgb, 16);
    let t = t.unwrap();
    assert_eq!((t.width, t.height, t.mips.len()), (16, 16, 5));
    check_chain(&t);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = &warnings[0];
    assert!(
        w.contains("big.png") && w.contains("64×64") && w.contains("16×16"),
        "{w}"
    );
    // 4×4-texel cells become 1-texel cells of the pure colours (an exact 4:1 area filter).
    assert_eq!(&t.mips[0][..8], &[255, 0, 0, 255, 0, 0, 255, 255]);
    // Aspect ratio kept; a tiny limit still gives a valid texture.
    let p = write_png(&dir, "wide.png", &RgbaImage::new(100, 10));
    let t = load(&p, ColorSpace::Linear, 20).0.unwrap();
    assert_eq!((t.width, t.height), (20, 2));
    let t = load(&p, ColorSpace::Linear, 1).0.unwrap();
    assert_eq!((t.width, t.height, t.mips.len()), (1, 1, 1));
}

#[test]
fn sixteen_bit_grey_and_channels() {
    let dir = scratch("formats");
    // 16-bit grey → linear half floats.
    let grey: ImageBuffer<Luma<u16>, Vec<u16>> = ImageBuffer::from_pixel(4, 4, Luma([32768]));
    let p = dir.join("grey16.png");
    grey.save(&p).unwrap();
    let t = load(&p, ColorSpace::Linear, 4096).0.unwrap();
    assert_eq!(t.format, TexFormat::Rgba16F);
    check_chain(&t);
    let v = t.texel(2, 0, 0).unwrap();
    assert!((v[0] - 0.5).abs() < 1e-3 && v[3] == 1.0, "{v:?}");
    // As sRGB colour, decoded here: code 0.5 → 0.214 linear.
    let v = load(&p, ColorSpace::Srgb, 4096)
        .0
        .unwrap()
        .texel(0, 0, 0)
        .unwrap();
    assert!((v[0] - 0.214).abs() < 1e-3, "{v:?}");
    // A channel of a packed file becomes R = G = B.
    let p = write_png(
        &dir,
        "packed.png",
        &RgbaImage::from_pixel(2, 2, Rgba([10, 20, 30, 40])),
    );
    let mut r = TextureRef::new(&p);
    r.channel = Some(1);
    let t = load_texture(&r, ColorSpace::Linear, 4096, &mut |_| {}).unwrap();
    assert!(t
        .mips
        .iter()
        .all(|l| l.chunks(4).all(|p| p == [20, 20, 20, 255])));
    // A greyscale normal map is suspicious (a height map?): warned.
    let p = dir.join("bump.png");
    image::GrayImage::from_pixel(4, 4, Luma([128]))
        .save(&p)
        .unwrap();
    let (t, warnings) = load(&p, ColorSpace::NormalMap, 4096);
    assert!(t.is_ok());
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("bump.png") && w.contains("height")),
        "{warnings:?}"
    );
}

#[test]
fn exr_and_hdr_are_linear_half_floats() {
    let dir = scratch("float");
    let img = image::Rgb32FImage::from_fn(8, 4, |x, _| image::Rgb([x as f32, 0.5, 100.0]));
    for name in ["e.exr", "h.hdr"] {
        let p = dir.join(name);
        DynamicImage::ImageRgb32F(img.clone()).save(&p).unwrap();
        let t = load(&p, ColorSpace::Srgb, 4096)
            .0
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            (t.width, t.height, t.format),
            (8, 4, TexFormat::Rgba16F),
            "{name}"
        );
        check_chain(&t);
        let v = t.texel(0, 3, 1).unwrap();
        assert!(
            (v[0] - 3.0).abs() < 0.05 && (v[1] - 0.5).abs() < 0.01 && (v[2] - 100.0).abs() < 1.0,
            "{name}: {v:?}"
        );
        // Level 1 averages 2×2 texels: x ∈ {2, 3} → 2.5.
        let v = t.texel(1, 1, 0).unwrap();
        assert!((v[0] - 2.5).abs() < 0.05, "{name}: {v:?}");
    }
}

#[test]
fn bad_files_give_errors_naming_the_file() {
    let dir = scratch("bad");
    let cases: Vec<(PathBuf, &str)> = {
        let corrupt = dir.join("corrupt.png");
        std::fs::write(&corrupt, b"\x89PNG\r\n\x1a\nthis is not a png").unwrap();
        let truncated = dir.join("truncated.png");
        let mut bytes = Vec::new();
        checker(64, 4, [0; 4], [255; 4])
            .write_to(
                &mut std::io::Cursor::new(&mut bytes),
                image::ImageFormat::Png,
            )
            .unwrap();
        std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
        let text = dir.join("text.exr");
        std::fs::write(&text, "hello").unwrap();
        let folder = dir.join("folder.png");
        std::fs::create_dir_all(&folder).unwrap();
        vec![
            (dir.join("missing.png"), "no such file"),
            (corrupt, "not a valid PNG file"),
            (truncated, "not a valid PNG file"),
            (text, "OpenEXR"),
            (folder, "is a directory"),
            (dir.join("anim.gif"), "unsupported texture file extension"),
        ]
    };
    for (path, what) in cases {
        let (r, _) = load(&path, ColorSpace::Srgb, 4096);
        let e = r.expect_err(&path.display().to_string());
        let msg = e.to_string();
        assert_eq!(e.path(), path.as_path());
        assert!(
            msg.contains(&path.display().to_string()) && msg.contains(what),
            "{msg}"
        );
    }
    // A declared size over the limits is refused before decoding (no huge allocation).
    let mut png = Vec::new();
    RgbaImage::new(1, 1)
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    png[16..20].copy_from_slice(&100_000u32.to_be_bytes());
    png[20..24].copy_from_slice(&100_000u32.to_be_bytes());
    let huge = dir.join("huge.png");
    std::fs::write(&huge, &png).unwrap();
    let msg = load(&huge, ColorSpace::Srgb, 4096)
        .0
        .unwrap_err()
        .to_string();
    assert!(msg.contains("huge.png"), "{msg}");
}

#[test]
fn generated_normal_maps_hold_unit_normals() {
    let img = noise_normal_map(128, 42, 1.0);
    let mut tilted = 0;
    for p in img.pixels() {
        let n = [p[0], p[1], p[2]].map(|c| c as f32 / 127.5 - 1.0);
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((len - 1.0).abs() < 0.015 && n[2] > 0.0, "{p:?}");
        if n[2] < 0.95 {
            tilted += 1;
        }
    }
    assert!(
        tilted > 128 * 128 / 10,
        "the map has relief ({tilted} tilted texels)"
    );
}

// ---------------------------------------------------------------------------------------------
// Scene files.

#[test]
fn textures_block_in_a_scene() {
    let dir = scratch("scene");
    write_png(
        &dir,
        "albedo.png",
        &checker(8, 2, [200, 10, 10, 255], [10, 10, 200, 255]),
    );
    write_png(&dir, "n.png", &noise_normal_map(8, 1, 1.0));
    write_png(&dir, "orm.png", &RgbaImage::new(4, 4));
    write_png(&dir, "m.png", &RgbaImage::new(4, 4));
    let json = r#"{
      "materials": {
        "gold": { "model": "metal_rough", "roughness": 0.5,
          "textures": {
            "base_color": "albedo.png",
            "normal": { "path": "n.png", "wrap": "clamp", "anisotropy": 8, "mipmaps": false },
            "normal_scale": 0.5,
            "orm": { "path": "orm.png", "min_filter": "nearest", "wrap_v": "mirror" },
            "occlusion_strength": 0.75,
            "emissive": "albedo.png"
          } },
        "chalk": { "model": "lambert", "textures": { "base_color": "albedo.png", "emissive_factor": [1, 2, 3] } },
        "metal": { "model": "principled", "textures": { "metallic": { "path": "m.png", "channel": "b" } } },
        "plain": { "model": "phong" }
      },
      "objects": [ { "mesh": { "type": "plane" }, "material": "gold" } ]
    }"#;
    let scene_path = dir.join("s.json");
    std::fs::write(&scene_path, json).unwrap();
    let s = scene::load(&scene_path).unwrap_or_else(|e| panic!("{e}"));
    let t = &s.materials[0].textures;
    assert_eq!(t.base_color.as_ref().unwrap().path, dir.join("albedo.png"));
    let n = t.normal.as_ref().unwrap();
    assert_eq!(
        (n.sampler.wrap_u, n.sampler.wrap_v),
        (Wrap::Clamp, Wrap::Clamp)
    );
    assert_eq!((n.sampler.anisotropy, n.sampler.mipmaps), (8.0, false));
    assert_eq!(t.normal_scale, 0.5);
    let orm = t.orm.as_ref().unwrap();
    assert_eq!(
        (orm.sampler.wrap_u, orm.sampler.wrap_v),
        (Wrap::Repeat, Wrap::Mirror)
    );
    assert_eq!(orm.sampler.min, scene::Filter::Nearest);
    assert_eq!(orm.sampler.mag, scene::Filter::Linear);
    assert_eq!(
        orm.sampler.anisotropy_for(true, 16.0),
        None,
        "nearest minification"
    );
    assert_eq!(n.sampler.anisotropy_for(true, 4.0), Some(4.0));
    assert_eq!(n.sampler.anisotropy_for(false, 16.0), None);
    assert_eq!(t.occlusion_strength, 0.75);
    assert_eq!(
        t.emissive_factor,
        glam::Vec3::ONE,
        "an emissive map defaults to factor 1"
    );
    let slots: Vec<TextureSlot> = t.maps().map(|(s, _)| s).collect();
    assert_eq!(
        slots,
        [
            TextureSlot::BaseColor,
            TextureSlot::Orm,
            TextureSlot::Normal,
            TextureSlot::Emissive
        ]
    );
    assert_eq!(
        ColorSpace::for_slot(TextureSlot::BaseColor),
        ColorSpace::Srgb
    );
    assert_eq!(ColorSpace::for_slot(TextureSlot::Orm), ColorSpace::Linear);
    assert_eq!(
        ColorSpace::for_slot(TextureSlot::Normal),
        ColorSpace::NormalMap
    );
    let chalk = &s.materials[1].textures;
    assert_eq!(chalk.emissive_factor, glam::Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(
        s.materials[2].textures.metallic.as_ref().unwrap().channel,
        Some(2)
    );
    assert!(s.materials[3].textures.is_empty());
    // Every map of the scene loads.
    for m in &s.materials {
        for (slot, r) in m.textures.maps() {
            load_texture(r, ColorSpace::for_slot(slot), 4096, &mut |_| {}).unwrap();
        }
    }
}

const TRIANGLE_OBJ: &str = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/3/1\nusemtl b\nf 1/1/1 3/3/1 2/2/1\n";

fn obj_scene(dir: &Path, mtl: &str) -> Result<scene::Scene, scene::SceneError> {
    std::fs::write(dir.join("t.obj"), TRIANGLE_OBJ).unwrap();
    std::fs::write(dir.join("m.mtl"), mtl).unwrap();
    let p = dir.join("s.json");
    std::fs::write(
        &p,
        r#"{ "objects": [ { "mesh": { "type": "obj", "path": "t.obj" } } ] }"#,
    )
    .unwrap();
    scene::load(&p)
}

#[test]
fn mtl_maps_become_material_textures() {
    let dir = scratch("mtl");
    std::fs::create_dir_all(dir.join("tex")).unwrap();
    for f in [
        "kd.png", "ks.png", "n.png", "pr.png", "pm.png", "ke.png", "d.png",
    ] {
        write_png(&dir.join("tex"), f, &RgbaImage::new(2, 2));
    }
    let mtl = "newmtl a\nKd 0.5 0.5 0.5\nmap_Kd -s 2 2 tex/kd.png\nmap_Ks tex\\ks.png\nmap_Bump -bm 0.3 -clamp on tex/n.png\nmap_d tex/d.png\n\
               newmtl b\nPm 0.25\nmap_Kd tex/kd.png\nmap_Pr -imfchan g tex/pr.png\nmap_Pm tex/pm.png\nnorm tex/n.png\nmap_Ke tex/ke.png\nKe 2 2 2\nmap_Ks tex/ks.png\n";
    let s = obj_scene(&dir, mtl).unwrap_or_else(|e| panic!("{e}"));
    let a = s.materials.iter().find(|m| m.name == "t.obj/a").unwrap();
    let b = s.materials.iter().find(|m| m.name == "t.obj/b").unwrap();
    // a: classic Phong with diffuse, specular and normal maps.
    assert!(
        matches!(a.material, Material::Phong(luz::brdf::PhongParams { .. })),
        "{:?}",
        a.material
    );
    if let Material::Phong(luz::brdf::PhongParams {
        diffuse_color,
        specular_color,
        ..
    }) = a.material
    {
        assert_eq!(diffuse_color, glam::Vec3::splat(0.5));
        assert_eq!(
            specular_color,
            glam::Vec3::ONE,
            "Ks defaults to 1 under a map_Ks"
        );
    }
    let ta = &a.textures;
    assert_eq!(ta.base_color.as_ref().unwrap().path, dir.join("tex/kd.png"));
    assert_eq!(
        ta.specular.as_ref().unwrap().path,
        dir.join("tex/ks.png"),
        "backslashes read as /"
    );
    let n = ta.normal.as_ref().unwrap();
    assert_eq!((ta.normal_scale, n.sampler.wrap_u), (0.3, Wrap::Clamp));
    // b: the PBR extension → metal_rough.
    let Material::MetalRough(p) = &b.material else {
        panic!("{:?}", b.material)
    };
    assert_eq!((p.metallic, p.roughness), (0.25, 1.0));
    assert_eq!(
        p.base_color,
        glam::Vec3::ONE,
        "Kd defaults to 1 under a map_Kd"
    );
    let tb = &b.textures;
    assert_eq!(tb.roughness.as_ref().unwrap().channel, Some(1));
    assert!(tb.metallic.is_some() && tb.normal.is_some() && tb.specular.is_none());
    assert_eq!(tb.emissive_factor, glam::Vec3::splat(2.0));
    // Warnings name the MTL and line of what is ignored.
    let w = s.warnings.join("\n");
    assert!(w.contains("m.mtl:3") && w.contains("-s"), "{w}");
    assert!(w.contains("m.mtl:6") && w.contains("map_d"), "{w}");
    assert!(w.contains("m.mtl:15") && w.contains("map_Ks"), "{w}");
}

#[test]
fn mtl_texture_problems_name_the_mtl_file_and_line() {
    let dir = scratch("mtl-bad");
    write_png(&dir, "ok.png", &RgbaImage::new(2, 2));
    for (mtl, line, what) in [
        ("newmtl a\nKd 1 1 1\nmap_Kd nope.png\n", 3, "not found"),
        ("newmtl a\nmap_Kd ok.tga\n", 2, "unsupported texture file"),
        ("newmtl a\n\nmap_Bump -bm ok.png\n", 3, "not a number"),
        ("newmtl a\nmap_Pr -imfchan q ok.png\n", 2, "-imfchan"),
        ("newmtl a\nmap_Kd -clamp on\n", 2, "no file name"),
        (
            "newmtl a\nmap_Kd -zoom 2 ok.png\n",
            2,
            "unknown option -zoom",
        ),
        ("newmtl a\nPr 2\n", 2, "Pr must be in [0, 1]"),
    ] {
        let e = obj_scene(&dir, mtl).expect_err(mtl);
        let msg = e.to_string();
        assert!(
            msg.contains(&format!("m.mtl:{line}")) && msg.contains(what),
            "{mtl:?}: {msg}"
        );
        assert!(
            msg.contains("s.json") && msg.contains("objects[0].mesh.path"),
            "{msg}"
        );
    }
}
