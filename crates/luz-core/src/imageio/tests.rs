//! Unit tests of image I/O: formats, limits, EXR headers, radiance images, saving.

use super::*;

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("luz-imageio-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn gradient(width: u32, height: u32) -> LinearImage {
    let mut img = LinearImage::filled(width, height, [0.0, 0.0, 0.0, 1.0]);
    for y in 0..height {
        for x in 0..width {
            let u = x as f32 / (width - 1) as f32;
            let v = y as f32 / (height - 1) as f32;
            *img.pixel_mut(x, y) = [u, v, 0.5 * u * v, 0.25 + 0.5 * u];
        }
    }
    img
}

/// A flat (not run-length encoded) Radiance RGBE file.
fn write_flat_hdr(path: &Path, width: u32, height: u32, rgbe: &[[u8; 4]]) {
    let mut out = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n".to_vec();
    out.extend(format!("-Y {height} +X {width}\n").bytes());
    for p in rgbe {
        out.extend(p);
    }
    fs::write(path, out).unwrap();
}

#[test]
fn radiance_hdr_loads_and_fails_clearly() {
    let dir = scratch_dir("hdr");
    let path = dir.join("tiny.hdr");
    // RGBE (128, 64, 32, 129): mantissa/256 · 2^(129 − 128) = (1, 0.5, 0.25) (+ half-ULP
    // rounding in some decoders: allow 1/256 relative).
    write_flat_hdr(&path, 2, 1, &[[128, 64, 32, 129], [0, 0, 0, 0]]);
    let img = load_radiance(&path).unwrap();
    assert_eq!((img.width, img.height), (2, 1));
    for (got, want) in img.pixels[0].iter().zip([1.0, 0.5, 0.25, 1.0]) {
        assert!((got - want).abs() <= want / 128.0, "{got} vs {want}");
    }
    assert_eq!(img.pixels[1], [0.0, 0.0, 0.0, 1.0]);

    let err = load_radiance(&dir.join("missing.hdr")).unwrap_err();
    assert!(
        matches!(err, ImageError::File(FileError::NotFound { .. })),
        "{err}"
    );
    assert!(err.to_string().contains("missing.hdr"));
    let garbage = dir.join("garbage.hdr");
    fs::write(
        &garbage,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n\x01",
    )
    .unwrap();
    let err = load_radiance(&garbage).unwrap_err();
    assert!(err.to_string().contains("garbage.hdr"), "{err}");
    let not_hdr = dir.join("png.hdr");
    fs::write(&not_hdr, b"\x89PNG\r\n\x1a\n").unwrap();
    let err = load_radiance(&not_hdr).unwrap_err();
    assert!(
        err.to_string().contains("png.hdr") && err.to_string().contains("Radiance"),
        "{err}"
    );
    let err = load_radiance(&dir.join("x.png")).unwrap_err();
    assert!(err.to_string().contains(".hdr") && err.to_string().contains("x.png"));
    // EXR goes through the same loader.
    let exr = dir.join("env.exr");
    save(&exr, &gradient(8, 4), 0.0, Tonemap::None).unwrap();
    let img = load_radiance(&exr).unwrap();
    assert_eq!(img, gradient(8, 4));
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn format_from_extension() {
    assert_eq!(
        FileFormat::from_path(Path::new("a/b.PNG")).unwrap(),
        FileFormat::Png
    );
    assert_eq!(
        FileFormat::from_path(Path::new("x.Exr")).unwrap(),
        FileFormat::Exr
    );
    for bad in ["x.jpg", "x", "dir.png/x.hdr", ".png"] {
        let err = FileFormat::from_path(Path::new(bad)).unwrap_err();
        let msg = err.to_string();
        assert!(
            matches!(err, ImageError::UnsupportedExtension { .. }),
            "{bad}"
        );
        assert!(msg.contains(bad) && msg.contains(".png") && msg.contains(".exr"));
    }
}

#[test]
fn exr_round_trip_is_exact() {
    let dir = scratch_dir("exr");
    let mut img = gradient(17, 9);
    *img.pixel_mut(3, 4) = [f32::NAN, f32::INFINITY, -2.5, 0.0];
    *img.pixel_mut(0, 0) = [1e5, 1e-9, 123.456, 7.0];
    let path = dir.join("round.exr");
    // Exposure and tone map must not affect EXR.
    save(&path, &img, 3.0, Tonemap::Aces).unwrap();
    let loaded = load(&path).unwrap();
    assert_eq!((loaded.width, loaded.height), (17, 9));
    assert_eq!(loaded.format, FileFormat::Exr);
    assert_eq!(loaded.encoded_max, 1.0);
    for (a, b) in loaded.linear.iter().zip(&img.pixels) {
        for (x, y) in a.iter().zip(b) {
            assert!(x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()));
        }
    }
    assert_eq!(loaded.non_finite_pixels(), 1);
    assert_eq!(loaded.display[17 * 4 + 3], [0, 255, 0]);
    let in_memory = LoadedImage::from_linear(&img, FileFormat::Exr, 3.0, Tonemap::Aces);
    assert_eq!(in_memory.display, loaded.display);
    assert_eq!(in_memory.non_finite_pixels(), 1);
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn png_round_trip_within_half_lsb() {
    let dir = scratch_dir("png");
    let img = gradient(33, 20);
    let path = dir.join("round.png");
    save(&path, &img, 0.0, Tonemap::None).unwrap();
    let loaded = load(&path).unwrap();
    assert_eq!(
        (loaded.width, loaded.height, loaded.encoded_max),
        (33, 20, 255.0)
    );
    for (got, want) in loaded.linear.iter().zip(&img.pixels) {
        for c in 0..3 {
            // Compare in encoded units: re-encoding the decoded value lands within 0.5 LSB.
            let e_got = crate::color::srgb_encode(got[c]) * 255.0;
            let e_want = crate::color::srgb_encode(want[c]) * 255.0;
            assert!((e_got - e_want).abs() <= 0.5 + 1e-3, "{e_got} vs {e_want}");
        }
        assert_eq!(got[3], 1.0, "PNG is written opaque RGB");
    }
    let in_memory = LoadedImage::from_linear(&img, FileFormat::Png, 0.0, Tonemap::None);
    assert_eq!(in_memory, loaded);
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn png_16_bit_and_grey_alpha_load() {
    let dir = scratch_dir("png16");
    let path = dir.join("sixteen.png");
    let raw: Vec<u16> = vec![0, 32768, 65535, 65535, 65535, 257, 0, 0];
    let buf = image::ImageBuffer::<image::Rgba<u16>, _>::from_raw(2, 1, raw).unwrap();
    buf.save(&path).unwrap();
    let img = load(&path).unwrap();
    assert_eq!(img.encoded_max, 65535.0);
    assert_eq!(img.encoded[0], [0.0, 32768.0, 65535.0, 65535.0]);
    assert_eq!(img.display[0], [0, 128, 255]);
    assert_eq!(img.display[1], [255, 1, 0]);
    assert!((img.linear[0][1] - srgb_decode(32768.0 / 65535.0)).abs() < 1e-7);
    assert_eq!(img.linear[1][3], 0.0);

    let path = dir.join("grey.png");
    image::GrayAlphaImage::from_raw(1, 1, vec![188, 51])
        .unwrap()
        .save(&path)
        .unwrap();
    let img = load(&path).unwrap();
    assert_eq!(img.encoded_max, 255.0);
    assert_eq!(img.encoded[0], [188.0, 188.0, 188.0, 51.0]);
    assert_eq!(img.display[0], [188; 3]);
    assert!((img.linear[0][3] - 0.2).abs() < 1e-7);
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn load_errors_name_the_file() {
    let dir = scratch_dir("errors");
    let missing = dir.join("missing.png");
    let err = load(&missing).unwrap_err();
    assert!(matches!(err, ImageError::File(FileError::NotFound { .. })));
    assert!(err.to_string().contains("missing.png"));

    let as_dir = dir.join("folder.exr");
    fs::create_dir(&as_dir).unwrap();
    let err = load(&as_dir).unwrap_err();
    assert!(
        matches!(err, ImageError::File(FileError::IsDirectory { .. })),
        "{err}"
    );
    assert!(err.to_string().contains("folder.exr"));

    let garbage = dir.join("garbage.png");
    fs::write(&garbage, b"this is not a png at all, just text").unwrap();
    let err = load(&garbage).unwrap_err();
    assert!(matches!(err, ImageError::Corrupt { .. }), "{err}");
    assert!(err.to_string().contains("garbage.png"), "{err}");

    let garbage = dir.join("garbage.exr");
    fs::write(&garbage, b"not an exr").unwrap();
    let err = load(&garbage).unwrap_err();
    assert!(matches!(err, ImageError::Corrupt { .. }), "{err}");
    assert!(err.to_string().contains("garbage.exr"), "{err}");

    // A valid PNG cut short after its header.
    let full = dir.join("full.png");
    save(&full, &gradient(64, 64), 0.0, Tonemap::None).unwrap();
    let bytes = fs::read(&full).unwrap();
    let cut = dir.join("cut.png");
    fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let err = load(&cut).unwrap_err();
    assert!(matches!(err, ImageError::Corrupt { .. }), "{err}");
    assert!(err.to_string().contains("cut.png"), "{err}");

    // PNG content behind an .exr name.
    let wrong = dir.join("wrong.exr");
    fs::copy(&full, &wrong).unwrap();
    let err = load(&wrong).unwrap_err();
    assert!(err.to_string().contains("wrong.exr"), "{err}");

    let err = load(&dir.join("x.tiff")).unwrap_err();
    assert!(matches!(err, ImageError::UnsupportedExtension { .. }));
    fs::remove_dir_all(dir).unwrap();
}

/// A PNG whose header declares `width × height` followed by a tiny IDAT and IEND.
fn png_with_declared_size(width: u32, height: u32) -> Vec<u8> {
    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = 0xffff_ffffu32;
        for &b in bytes {
            crc ^= b as u32;
            for _ in 0..8 {
                crc = if crc & 1 != 0 {
                    (crc >> 1) ^ 0xedb8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }
    fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
        out.extend((data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend(data);
        out.extend(&body);
        out.extend(crc32(&body).to_be_bytes());
    }
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend(width.to_be_bytes());
    ihdr.extend(height.to_be_bytes());
    ihdr.extend([8, 2, 0, 0, 0]); // 8-bit RGB
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(
        &mut out,
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    );
    chunk(&mut out, b"IEND", &[]);
    out
}

#[test]
fn absurd_declared_sizes_are_refused() {
    let dir = scratch_dir("huge");
    for (w, h) in [(100_000, 10), (10, 40_000), (2_000_000_000, 2_000_000_000)] {
        let path = dir.join(format!("huge-{w}x{h}.png"));
        fs::write(&path, png_with_declared_size(w, h)).unwrap();
        let err = load(&path).unwrap_err();
        assert!(matches!(err, ImageError::TooLarge { .. }), "{err}");
        let msg = err.to_string();
        assert!(msg.contains(&format!("{w}×{h}")), "{msg}");
        assert!(msg.contains(&format!("huge-{w}x{h}.png")), "{msg}");
    }
    // A size within the limits whose pixel data is missing fails as corrupt.
    let path = dir.join("ok-size-bad-data.png");
    fs::write(&path, png_with_declared_size(300, 200)).unwrap();
    let err = load(&path).unwrap_err();
    assert!(matches!(err, ImageError::Corrupt { .. }), "{err}");
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn save_errors() {
    let dir = scratch_dir("save");
    let img = gradient(4, 4);
    let path = dir.join("no/such/dir/out.png");
    let err = save(&path, &img, 0.0, Tonemap::None).unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, ImageError::Write { .. }));
    assert!(
        msg.starts_with("cannot write ") && msg.contains("out.png"),
        "{msg}"
    );
    assert!(msg.contains("No such file"), "{msg}");

    let as_dir = dir.join("taken.exr");
    fs::create_dir(&as_dir).unwrap();
    let err = save(&as_dir, &img, 0.0, Tonemap::None).unwrap_err();
    assert!(matches!(err, ImageError::Write { .. }), "{err}");

    let err = save(&dir.join("x.jpg"), &img, 0.0, Tonemap::None).unwrap_err();
    assert!(matches!(err, ImageError::UnsupportedExtension { .. }));

    let bad = LinearImage {
        width: 3,
        height: 3,
        pixels: vec![[0.0; 4]; 8],
    };
    let err = save(&dir.join("bad.png"), &bad, 0.0, Tonemap::None).unwrap_err();
    assert!(matches!(err, ImageError::Encode { .. }), "{err}");
    assert!(!dir.join("bad.png").exists());
    let empty = LinearImage::filled(0, 5, [0.0; 4]);
    assert!(save(&dir.join("empty.exr"), &empty, 0.0, Tonemap::None).is_err());
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn png_applies_exposure_and_tonemap() {
    let img = LinearImage::filled(2, 2, [0.25, 1.0, 4.0, 1.0]);
    let plain = LoadedImage::from_linear(&img, FileFormat::Png, 0.0, Tonemap::None);
    assert_eq!(plain.display[0], [137, 255, 255]);
    let exposed = LoadedImage::from_linear(&img, FileFormat::Png, 1.0, Tonemap::None);
    assert_eq!(exposed.display[0], [188, 255, 255]);
    let mapped = LoadedImage::from_linear(&img, FileFormat::Png, 0.0, Tonemap::Reinhard);
    assert_eq!(
        mapped.display[0],
        [0.2, 0.5, 0.8].map(crate::color::srgb_encode_u8)
    );
}

/// A transparent render is written RGBA with straight alpha: a pixel of coverage a and
/// premultiplied colour a·c reads back as colour c (within half an LSB in encoded units) and
/// alpha round(255·a); coverage 0 is (0, 0, 0, 0). The file says so in its provenance.
#[test]
fn transparent_png_has_straight_coverage_alpha() {
    let dir = scratch_dir("png-alpha");
    let straight = [0.2f32, 0.5, 0.8];
    let coverages = [0.0f32, 0.25, 0.5, 1.0];
    let img = LinearImage {
        width: 4,
        height: 1,
        pixels: coverages
            .iter()
            .map(|&a| [straight[0] * a, straight[1] * a, straight[2] * a, a])
            .collect(),
    };
    let mut output = Encoding {
        exposure_ev: 0.0,
        tonemap: Tonemap::None,
        transparent: true,
    };
    let path = dir.join("alpha.png");
    save_render(&path, &img, output, &Provenance::base()).unwrap();
    let bytes = fs::read(&path).unwrap();
    let decoded = image::load_from_memory(&bytes).unwrap();
    assert!(decoded.color().has_alpha(), "RGBA");
    let rgba = decoded.to_rgba8();
    assert_eq!(rgba.get_pixel(0, 0).0, [0, 0, 0, 0]);
    for (x, &a) in coverages.iter().enumerate().skip(1) {
        let p = rgba.get_pixel(x as u32, 0).0;
        assert_eq!(p[3], (a * 255.0).round() as u8, "alpha at coverage {a}");
        for c in 0..3 {
            let want = crate::color::srgb_encode(straight[c]) * 255.0;
            assert!(
                (p[c] as f32 - want).abs() <= 0.5 + 1e-3,
                "coverage {a}: channel {c} is {} (straight {want})",
                p[c]
            );
        }
    }
    assert!(String::from_utf8_lossy(&bytes).contains("luz.alpha"));
    // The same image with an opaque output is RGB, as before.
    output.transparent = false;
    save_render(&path, &img, output, &Provenance::base()).unwrap();
    assert!(!image::open(&path).unwrap().color().has_alpha());
    fs::remove_dir_all(dir).unwrap();
}
