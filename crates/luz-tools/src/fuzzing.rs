//! Entry points shared by the fuzz targets (`fuzz/fuzz_targets/*.rs`, cargo-fuzz / libFuzzer)
//! and the regression test `tests/fuzz_regressions.rs`.
//!
//! Each function takes arbitrary bytes and must never panic, hang or allocate without bound:
//! errors are expected and ignored. Each runs the real code paths of the CLI (`luz render`,
//! `luz diff`) up to where Vulkan would start, with size limits small enough that no input can
//! legitimately need gigabytes (see [`FUZZ_LIMITS`]).
//!
//! * [`scene`]: scene text → [`crate::scene::parse`] (JSON parser, validator, primitive meshes,
//!   OBJ/MTL and texture references) → the CPU work `luz render` does before the GPU: triangle
//!   count, bounds, vertex streams with tangents ([`crate::render::mesh`]), BRDF parameters,
//!   LUT layers, texture decoding and the environment image.
//! * [`obj_mtl`]: an OBJ and an MTL file (split at [`SPLIT`]) loaded the way a scene's
//!   `{"type": "obj"}` mesh is: both are written to a scratch folder and a scene naming the OBJ
//!   is parsed, then the same CPU work as [`scene`].
//! * [`image`]: a PNG, EXR or Radiance HDR file (the first byte chooses the extension and the
//!   options) through the texture loader ([`crate::texture::decode_bytes`] +
//!   [`crate::texture::texture_from_image`]), the environment loader
//!   ([`crate::env::load_equirect_bytes`] + SH projection) and the image loader of `luz diff`
//!   ([`crate::imageio::load_bytes`]).
//! * [`gltf`]: a glTF file (JSON or binary) through [`crate::scene::gltf::load_bytes_with`] with
//!   [`GLTF_TRIANGLE_BUDGET`], its embedded images decoded at [`FUZZ_LIMITS`], then (within the
//!   budget) as a scene's `{"type": "gltf"}` object with its lights and cameras, and the CPU
//!   side of `luz render`.
//! * [`diff`]: two images (split at [`SPLIT`]; without it the image is compared with itself)
//!   through [`crate::imageio::load_bytes`] and [`crate::diff::compare_detailed`] with
//!   tolerances, then the report's violations and text.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use crate::imageio::SizeLimits;
use crate::scene::json::{Kind, Value};
use crate::scene::{Scene, Shading};
use crate::texture::ColorSpace;

/// Separates the two parts of a two-part input (OBJ and MTL; expected and actual image).
pub const SPLIT: &[u8] = b"\n#LUZ-SPLIT#\n";

/// Decoder limits of the fuzz entry points: 1 Mpixel, 32 MiB decoded. The file loaders use
/// [`SizeLimits::DEFAULT`] (1 Gpixel, 4 GiB): legitimate for real files, but a fuzz input that
/// declares such a size would be reported as out-of-memory by libFuzzer.
pub const FUZZ_LIMITS: SizeLimits = SizeLimits {
    max_dimension: crate::imageio::MAX_DIMENSION,
    max_pixels: 1 << 20,
    max_bytes: 32 << 20,
};

/// Limits of [`diff`]: FLIP costs about a microsecond per pixel, so 64 K pixels at most.
pub const DIFF_LIMITS: SizeLimits = SizeLimits {
    max_dimension: crate::imageio::MAX_DIMENSION,
    max_pixels: 1 << 16,
    max_bytes: 4 << 20,
};

/// Largest texture / environment side the fuzz entry points ask for (the renderer asks for the
/// device's `maxImageDimension2D`); small so that downscaling is exercised and cheap.
pub const FUZZ_MAX_DIMENSION: u32 = 256;

/// Total triangles of built-in primitives a fuzzed scene may ask for (estimated from the JSON
/// before parsing; larger scenes are skipped). The parser allows 2^24 per primitive and any
/// number of primitives, which is gigabytes for a scene of a few hundred bytes.
pub const SCENE_TRIANGLE_BUDGET: u64 = 1 << 20;

/// Scene text, parsed and validated as if it were `tests/bad_inputs/fuzz.json` of this checkout
/// (so the scenes of `tests/bad_inputs` find their OBJ, MTL, texture and environment files, and
/// `../../../shared/…` names the shared models, textures and environments), then the CPU side
/// of `luz render`.
pub fn scene(data: &[u8]) {
    let origin =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("tests/bad_inputs/fuzz.json");
    scene_at(data, &origin);
}

/// [`scene`] with the scene file's path given: `origin` names it in messages and its folder is
/// the base of relative paths (the regression test runs `tests/bad_scenes/*.json` from there).
pub fn scene_at(data: &[u8], origin: &Path) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(root) = crate::scene::json::parse(text) {
        if primitive_triangles(&root) > SCENE_TRIANGLE_BUDGET {
            return;
        }
    }
    if let Ok(scene) = crate::scene::parse(text, origin) {
        render_cpu_work(&scene, true);
    }
}

/// An OBJ file and, after [`SPLIT`], its MTL file: written as `m.obj` and `m.mtl` to a scratch
/// folder of this thread, then loaded through a scene `{"objects": [{"mesh": {"type": "obj",
/// "path": "m.obj"}}]}` (no `material`, so the MTL libraries named by `mtllib` are read), and
/// the CPU side of `luz render`.
pub fn obj_mtl(data: &[u8]) {
    let (obj, mtl) = split(data);
    let Some(dir) = scratch_dir() else {
        return;
    };
    let (obj_path, mtl_path) = (dir.join("m.obj"), dir.join("m.mtl"));
    if std::fs::write(&obj_path, obj).is_err() {
        return;
    }
    let written = match mtl {
        Some(m) => std::fs::write(&mtl_path, m),
        None => match std::fs::remove_file(&mtl_path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
            _ => Ok(()),
        },
    };
    if written.is_err() {
        return;
    }
    let text = r#"{"objects": [{"mesh": {"type": "obj", "path": "m.obj"}}]}"#;
    if let Ok(scene) = crate::scene::parse(text, &dir.join("scene.json")) {
        render_cpu_work(&scene, false);
    }
}

/// Most triangles a fuzzed glTF file may expand into (the loader's own limit is 2^25).
pub const GLTF_TRIANGLE_BUDGET: usize = 1 << 18;

/// A glTF file, as `fuzz.glb` in a scratch folder of this thread (relative URIs find nothing
/// there but what earlier inputs left: `fuzz.glb` itself).
pub fn gltf(data: &[u8]) {
    let Some(dir) = scratch_dir() else {
        return;
    };
    let path = dir.join("fuzz.glb");
    let Ok(file) = crate::scene::gltf::load_bytes_with(data, &path, None, GLTF_TRIANGLE_BUDGET)
    else {
        return;
    };
    for m in &file.materials {
        for (slot, r) in m.textures.maps() {
            if let Some(bytes) = &r.embedded {
                if let Ok(img) = crate::texture::decode_embedded(bytes, &r.path, &FUZZ_LIMITS) {
                    let _ = crate::texture::texture_from_image(
                        &img,
                        &r.path,
                        ColorSpace::for_slot(slot),
                        r.channel,
                        r.sampler.mipmaps,
                        FUZZ_MAX_DIMENSION,
                        &mut |_| {},
                    );
                }
            }
        }
    }
    if std::fs::write(&path, data).is_err() {
        return;
    }
    let text = r#"{"objects": [{"mesh": {"type": "gltf", "path": "fuzz.glb", "lights": true, "cameras": true}}]}"#;
    if let Ok(mut scene) = crate::scene::parse(text, &dir.join("scene.json")) {
        if !scene.cameras.is_empty() {
            let _ = crate::scene::model::use_camera(&mut scene, 0);
        }
        render_cpu_work(&scene, false);
    }
}

/// An image file. The first byte chooses: bits 0–1 the extension (`.png`, `.exr`, `.hdr`,
/// `.png`), bits 2–3 the colour space of the texture (sRGB, linear, normal map, sRGB), bits 4–6
/// the channel (none, R, G, B, A, none…), bit 7 no mipmaps. The rest is the file.
pub fn image(data: &[u8]) {
    let Some((&opts, file)) = data.split_first() else {
        return;
    };
    let name = Path::new(["fuzz.png", "fuzz.exr", "fuzz.hdr", "fuzz.png"][usize::from(opts & 3)]);
    let space = [
        ColorSpace::Srgb,
        ColorSpace::Linear,
        ColorSpace::NormalMap,
        ColorSpace::Srgb,
    ][usize::from((opts >> 2) & 3)];
    let channel = match (opts >> 4) & 7 {
        c @ 1..=4 => Some(c - 1),
        _ => None,
    };
    let mipmaps = opts & 0x80 == 0;

    // A material's texture map, as `render::material` loads it.
    if let Ok(img) = crate::texture::decode_bytes(file, name, &FUZZ_LIMITS) {
        let _ = crate::texture::texture_from_image(
            &img,
            name,
            space,
            channel,
            mipmaps,
            FUZZ_MAX_DIMENSION,
            &mut |_| {},
        );
    }
    // An `{"hdr": …}` environment, as `headless::build_ibl` loads it.
    if let Ok((eq, _)) =
        crate::env::load_equirect_bytes(file, name, 1.5, FUZZ_MAX_DIMENSION, &FUZZ_LIMITS)
    {
        let _ = crate::env::sh9_irradiance_coeffs(&crate::env::sh9_project(&eq));
    }
    // One side of `luz diff`.
    let _ = crate::imageio::load_bytes(file, name, &FUZZ_LIMITS);
}

/// Two images for `luz diff`, split at [`SPLIT`] (without it, the image is compared with
/// itself). Each part's first byte chooses its extension (even: `.png`, odd: `.exr`); the
/// expected part's first byte also picks the tolerances.
pub fn diff(data: &[u8]) {
    let (a, b) = split(data);
    let b = b.unwrap_or(a);
    let load = |part: &[u8]| {
        let (&opts, file) = part.split_first()?;
        let name = Path::new(if opts & 1 == 0 { "a.png" } else { "a.exr" });
        crate::imageio::load_bytes(file, name, &DIFF_LIMITS).ok()
    };
    let (Some(expected), Some(actual)) = (load(a), load(b)) else {
        return;
    };
    let k = a.first().copied().unwrap_or(0);
    let opts = crate::diff::DiffOptions {
        max_flip_mean: (k & 2 != 0).then_some(0.01),
        max_abs: (k & 4 != 0).then_some(if k & 8 != 0 { 0.0 } else { 2.0 }),
        max_bad_pixels: (k & 16 != 0).then_some(3),
        bad_pixel_threshold: if k & 32 != 0 { 1.0 } else { 0.0 },
        heatmap: None,
        pixels_per_degree: if k & 64 != 0 {
            crate::diff::DEFAULT_PIXELS_PER_DEGREE
        } else {
            1.0 + f32::from(k)
        },
    };
    if let Ok((report, _map)) = crate::diff::compare_detailed(&expected, &actual, &opts) {
        let _ = report.violations(&opts);
        let _ = report.to_string();
    }
}

/// The parts of a two-part input: before and after the first [`SPLIT`].
pub fn split(data: &[u8]) -> (&[u8], Option<&[u8]>) {
    match data.windows(SPLIT.len()).position(|w| w == SPLIT) {
        Some(i) => (&data[..i], Some(&data[i + SPLIT.len()..])),
        None => (data, None),
    }
}

/// A folder of this thread for [`obj_mtl`]'s files (created once; `None` if it cannot be), so
/// that tests calling it from several threads do not overwrite each other's files.
fn scratch_dir() -> Option<PathBuf> {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    thread_local! {
        static DIR: Option<PathBuf> = {
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let dir = std::env::temp_dir().join(format!("luz-fuzz-{}-{n}", std::process::id()));
            std::fs::create_dir_all(&dir).ok().map(|_| dir)
        };
    }
    DIR.with(|d| d.clone())
}

/// What `luz render` computes on the CPU from a parsed scene before (and while) building its
/// GPU data: totals and bounds, each distinct (mesh, flat) pair's vertex stream with tangents,
/// the BRDF parameters and LUT layers, camera matrices, and — with `files` — the texture maps
/// and the environment image (at [`FUZZ_MAX_DIMENSION`]).
fn render_cpu_work(scene: &Scene, files: bool) {
    let _ = scene.triangle_count();
    let _ = scene.bounds();
    let _ = scene.camera.view() * scene.camera.projection(scene.output.aspect());
    let mut seen = HashSet::new();
    for obj in &scene.objects {
        let flat = obj.shading == Shading::Flat;
        if !seen.insert((Arc::as_ptr(&obj.mesh) as usize, flat)) {
            continue;
        }
        let _ = obj.mesh.bounds();
        let _ = obj.transform.normal_matrix();
        let _ = obj.desc.triangle_count();
        let _ = if flat {
            crate::render::mesh::flat(&obj.mesh)
        } else {
            crate::render::mesh::smooth(&obj.mesh)
        };
    }
    let _ = crate::render::forward::lut_geometries(scene);
    for m in &scene.materials {
        let _ = m.material.sanitized();
        if !files {
            continue;
        }
        for (slot, r) in m.textures.maps() {
            let _ = crate::texture::load_texture(
                r,
                ColorSpace::for_slot(slot),
                FUZZ_MAX_DIMENSION,
                &mut |_| {},
            );
        }
    }
    if let (true, Some(env)) = (files, &scene.environment) {
        if let Ok(eq) = crate::env::load_equirect(env, FUZZ_MAX_DIMENSION) {
            let _ = crate::env::sh9_irradiance_coeffs(&crate::env::sh9_project(&eq));
        }
    }
}

/// A generous estimate of the triangles of the built-in primitives in scene JSON: every object
/// with a `type` counts as the largest primitive its `segments`, `rings` and `subdivisions`
/// (defaults when absent) could make.
fn primitive_triangles(v: &Value) -> u64 {
    match &v.kind {
        Kind::Array(items) => items
            .iter()
            .map(primitive_triangles)
            .fold(0, u64::saturating_add),
        Kind::Object(fields) => {
            let int = |key: &str, default: u64| {
                fields
                    .iter()
                    .find(|(k, _)| k == key)
                    .and_then(|(_, v)| match v.kind {
                        Kind::Number { value, .. } if value.is_finite() && value >= 0.0 => {
                            Some(value.min(1e9) as u64)
                        }
                        _ => None,
                    })
                    .unwrap_or(default)
            };
            let own = if fields.iter().any(|(k, _)| k == "type") {
                let (seg, rings, sub) = (
                    int("segments", 64),
                    int("rings", 64),
                    int("subdivisions", 8),
                );
                let sphere = 2 * seg * rings;
                let ico = 20u64 << (2 * sub.min(20));
                let plane = 2 * sub * sub;
                sphere.max(ico).max(plane).max(4 * seg)
            } else {
                0
            };
            fields
                .iter()
                .map(|(_, v)| primitive_triangles(v))
                .fold(own, u64::saturating_add)
        }
        _ => 0,
    }
}
