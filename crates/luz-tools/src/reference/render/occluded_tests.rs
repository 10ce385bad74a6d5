//! `Prepared::occluded` against alpha-tested casters: shadow rays through cut-out texels.

use super::*;

/// Two stacked 2 × 2 m quads of one OBJ mesh (y = 0 with u = (x + 1)/2, y = 1 with u shifted
/// by 0.25, clamped) under a 2 × 1 map whose left texel (u < 0.5) has alpha `cut` and right
/// one alpha `kept`, in a material of alpha mode `mode`.
fn stacked_quads(mode: AlphaMode, (cut, kept): (u8, u8)) -> Prepared {
    let dir = std::env::temp_dir().join(format!(
        "luz-unit-occluded-{}-{:?}-{cut}",
        std::process::id(),
        mode
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let obj = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n\
               v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\n\
               vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
               vt 0.25 0\nvt 1.25 0\nvt 1.25 1\nvt 0.25 1\n\
               f 1/1 2/2 3/3 4/4\nf 5/5 6/6 7/7 8/8\n";
    std::fs::write(dir.join("quads.obj"), obj).unwrap();
    let json = r#"{
        "camera": {"position": [0, 5, 5], "target": [0, 0, 0]},
        "output": {"width": 8, "height": 8},
        "lights": [{"type": "directional", "direction": [0, -1, 0], "shadow": true}],
        "materials": {"m": {"model": "lambert", "albedo": [0.5, 0.5, 0.5]}},
        "objects": [{"mesh": {"type": "obj", "path": "quads.obj"}, "material": "m"}]
    }"#;
    let mut scene = crate::scene::parse(json, &dir.join("scene.json")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let mut png = Vec::new();
    image::RgbaImage::from_raw(2, 1, vec![255, 255, 255, cut, 255, 255, 255, kept])
        .unwrap()
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let t = &mut scene.materials[0].textures;
    t.base_color = Some(crate::scene::TextureRef {
        path: "stripes.png".into(),
        sampler: crate::scene::SamplerDesc {
            wrap_u: crate::scene::Wrap::Clamp,
            wrap_v: crate::scene::Wrap::Clamp,
            mag: crate::scene::Filter::Nearest,
            min: crate::scene::Filter::Nearest,
            ..Default::default()
        },
        channel: None,
        embedded: Some(png.into()),
    });
    t.alpha_mode = mode;
    Prepared::new(&scene).unwrap()
}

/// Shadow rays pass through masked-out texels, also past a first cut-out hit to a kept texel
/// of the same mesh behind it; BLEND casts where alpha ≥ 0.5; opaque ignores alpha.
#[test]
fn occluded_passes_through_cut_out_texels() {
    let up = Vec3::Y;
    // Vertical rays from below at x: both quads cut out; the lower one cut out and the upper
    // one kept; the lower one kept.
    let ray = |x: f32| Vec3::new(x, -1.0, 0.3);
    let cases = [
        (AlphaMode::Mask { cutoff: 0.5 }, (0, 255)),
        (AlphaMode::Blend, (77, 204)),
    ];
    for (mode, texels) in cases {
        let p = stacked_quads(mode, texels);
        assert!(
            !p.occluded(ray(-0.9), up, f32::INFINITY),
            "{mode:?}: through both"
        );
        assert!(
            p.occluded(ray(-0.2), up, f32::INFINITY),
            "{mode:?}: upper quad"
        );
        assert!(
            p.occluded(ray(0.5), up, f32::INFINITY),
            "{mode:?}: lower quad"
        );
        // A segment ending between the quads does not reach the upper one.
        assert!(!p.occluded(ray(-0.2), up * 1.5, 1.0), "{mode:?}: segment");
    }
    // A mask whose cutoff no texel reaches casts nothing; an opaque material everywhere.
    let p = stacked_quads(AlphaMode::Mask { cutoff: 0.9 }, (77, 204));
    assert!(!p.occluded(ray(0.5), up, f32::INFINITY));
    let p = stacked_quads(AlphaMode::Opaque, (0, 255));
    assert!(p.occluded(ray(-0.9), up, f32::INFINITY));
}
