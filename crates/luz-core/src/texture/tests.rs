//! Unit tests of texture loading, colour spaces, channel picks, mips and half floats.

use super::*;
use image::RgbaImage;

fn data(img: RgbaImage, space: ColorSpace) -> TextureData {
    texture_from_image(
        &DynamicImage::ImageRgba8(img),
        Path::new("test.png"),
        space,
        None,
        true,
        16384,
        &mut |w| panic!("unexpected warning: {w}"),
    )
    .unwrap()
}

#[test]
fn mip_sizes() {
    assert_eq!(mip_count(1, 1), 1);
    assert_eq!(mip_count(2048, 2048), 12);
    assert_eq!(mip_count(5, 3), 3);
    assert_eq!(mip_count(0, 0), 1);
    assert_eq!(mip_extent(5, 3, 1), (2, 1));
    assert_eq!(mip_extent(5, 3, 2), (1, 1));
    assert_eq!(mip_extent(5, 3, 40), (1, 1));
}

#[test]
fn half_floats_round_trip() {
    for (f, h) in [
        (0.0f32, 0x0000u16),
        (-0.0, 0x8000),
        (1.0, 0x3c00),
        (-2.0, 0xc000),
        (0.5, 0x3800),
        (65504.0, 0x7bff),
        (65520.0, 0x7c00),
        (f32::INFINITY, 0x7c00),
        (6.103_515_6e-5, 0x0400),
        (5.960_464_5e-8, 0x0001),
        (1.0 / 3.0, 0x3555),
    ] {
        assert_eq!(f32_to_f16(f), h, "{f}");
    }
    assert!(f16_to_f32(f32_to_f16(f32::NAN)).is_nan());
    for h in (0u16..0x7c00).step_by(7) {
        assert_eq!(f32_to_f16(f16_to_f32(h)), h);
    }
}

#[test]
fn srgb_codes_match_the_exact_encoding() {
    for i in 0..=4096 {
        let v = i as f32 / 4096.0;
        assert_eq!(srgb_encode_code(v), crate::color::srgb_encode_u8(v), "{v}");
    }
    for c in 0..=255u8 {
        assert_eq!(srgb_encode_code(crate::color::srgb_decode_u8(c)), c);
    }
    assert_eq!(srgb_encode_code(-1.0), 0);
    assert_eq!(srgb_encode_code(2.0), 255);
}

#[test]
fn area_weights_cover_odd_sizes() {
    let w = area_weights(5, 2);
    assert_eq!(w[0].0, 0);
    assert_eq!(w[1].0, 2);
    for (i, expected) in [[0.4, 0.4, 0.2], [0.2, 0.4, 0.4]].iter().enumerate() {
        for (a, b) in w[i].1.iter().zip(expected) {
            assert!((a - b).abs() < 1e-6, "{w:?}");
        }
    }
    let same = area_weights(3, 3);
    assert!(same.iter().all(|(_, ws)| ws == &vec![1.0]));
}

#[test]
fn srgb_mips_average_in_linear_light() {
    let t = data(
        checker(8, 8, [0, 0, 0, 255], [255, 255, 255, 255]),
        ColorSpace::Srgb,
    );
    assert_eq!(t.format, TexFormat::Rgba8Srgb);
    assert_eq!(t.mips.len(), 4);
    assert!(t.mips[1].chunks(4).all(|p| p == [188, 188, 188, 255]));
    let lin = data(
        checker(8, 8, [0, 0, 0, 255], [255, 255, 255, 255]),
        ColorSpace::Linear,
    );
    assert!(lin.mips[1].chunks(4).all(|p| p == [128, 128, 128, 255]));
}

#[test]
fn channel_is_copied_to_rgb() {
    let img = RgbaImage::from_pixel(4, 4, image::Rgba([10, 20, 30, 40]));
    let t = texture_from_image(
        &DynamicImage::ImageRgba8(img),
        Path::new("m.png"),
        ColorSpace::Linear,
        Some(2),
        false,
        4096,
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(t.mips.len(), 1);
    assert!(t.mips[0].chunks(4).all(|p| p == [30, 30, 30, 255]));
}

#[test]
fn normal_mips_stay_unit() {
    let t = data(noise_normal_map(64, 7, 1.5), ColorSpace::NormalMap);
    assert_eq!(t.format, TexFormat::Rgba8Unorm);
    for level in 1..t.mips.len() {
        for p in t.mips[level].chunks(4) {
            let n = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) / 127.5 - Vec3::ONE;
            assert!((n.length() - 1.0).abs() < 0.02, "level {level}: {p:?}");
        }
    }
}

#[test]
fn float_images_become_half_floats() {
    let img = image::Rgba32FImage::from_pixel(3, 2, image::Rgba([0.25, 1e6, f32::NAN, 1.0]));
    let mut warnings = Vec::new();
    let t = texture_from_image(
        &DynamicImage::ImageRgba32F(img),
        Path::new("e.exr"),
        ColorSpace::Srgb,
        None,
        true,
        4096,
        &mut |w| warnings.push(w),
    )
    .unwrap();
    assert_eq!(t.format, TexFormat::Rgba16F);
    assert_eq!(t.mips.len(), 2);
    assert_eq!(t.texel(0, 2, 1), Some([0.25, 65504.0, 0.0, 1.0]));
    assert_eq!(t.texel(1, 0, 0), Some([0.25, 65504.0, 0.0, 1.0]));
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("e.exr"), "{warnings:?}");
}

#[test]
fn generators_are_deterministic_and_tile() {
    assert_eq!(noise_normal_map(32, 1, 1.0), noise_normal_map(32, 1, 1.0));
    assert_ne!(noise_normal_map(32, 1, 1.0), noise_normal_map(32, 2, 1.0));
    let flat = noise_normal_map(16, 3, 0.0);
    assert!(flat.pixels().all(|p| p.0 == [128, 128, 255, 255]));
    let c = checker(4, 2, [1, 1, 1, 1], [2, 2, 2, 2]);
    assert_eq!(c.get_pixel(0, 0).0, [1; 4]);
    assert_eq!(c.get_pixel(2, 0).0, [2; 4]);
    assert_eq!(c.get_pixel(2, 2).0, [1; 4]);
}
