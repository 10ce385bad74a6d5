//! `luz reference`: the CPU reference renderer, the answer every GPU method is measured against.
//!
//! It renders the same scene as `luz render`, with the same camera, lights, materials, maps,
//! fog, background and saturation, but without the GPU path's approximations:
//!
//! * **Exact geometry.** Built-in primitives are the ideal shapes they stand for, intersected
//!   analytically in object space (the ray is transformed by the inverse object matrix): sphere,
//!   plane, cube, cylinder, cone. **An icosphere is a sphere**: the reference shows the ideal
//!   shape, not the polyhedron the GPU draws. Normals, UVs and tangents are the exact surface's,
//!   with the local-space conventions of `scene::mesh` (so maps land where they do on the
//!   tessellated mesh). OBJ meshes are triangles (a BVH, median split) with interpolated vertex
//!   normals.
//! * **Per-pixel shading always.** Flat and Gouraud objects are shaded per pixel as well: the
//!   reference is the Phong-frequency answer the cheaper frequencies approximate.
//! * **The same formulas.** `surface_at`, `ambient_term`, `light_incidence` and `apply_fog` of
//!   `shaders_glsl/include/lighting.glsl` are mirrored here; each light goes through the CPU BRDF
//!   reference's [`crate::brdf::radiance`] (the classic Phong's literal formula included).
//! * **The environment converged.** `∫ L_env(l) f(l, v) (n·l) dl` is estimated by Monte Carlo
//!   with `samples` directions per pixel, multiple importance sampling (balance heuristic) over
//!   the cosine lobe, the model's specular lobes (GGX, Beckmann, GTR1, Phong) and the
//!   environment image (luminance × sin θ). Radiance is read from the equirectangular image
//!   itself (bilinear), not from a cube map, SH or prefiltered mips. The classic models take the
//!   environment through their literal formula too (diffuse *and* specular).
//! * **Textures** are sampled at mip level 0 (bilinear, or nearest with a `nearest`
//!   magnification filter) with the map's wrap modes; `--spp` > 1 does the filtering.
//! * **Pixel sampling.** One primary ray through each pixel centre `(x + 0.5, y + 0.5)` by default
//!   (compare with `msaa` 1 renders); `--spp N` averages N correlated multi-jittered rays.
//!
//! Like the GPU path it is local illumination: shadow rays for the lights with `shadow` (soft ones
//! for lights with a size), no inter-reflections.

mod geometry;
pub mod glass;
mod render;
mod sampling;
mod texture;

use anyhow::{bail, Result};
use rayon::prelude::*;

use crate::imageio::LinearImage;
use crate::scene::{Saturation, Scene};

/// Settings of [`render_reference`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReferenceOptions {
    /// Primary rays per pixel, ≥ 1: the pixel centre for 1, correlated multi-jittered points
    /// for more. Default 1.
    pub spp: u32,
    /// Directions per pixel for the environment integral, ≥ 1 (split between the primary rays
    /// when `spp` > 1). Default 1024.
    pub samples: u32,
    /// Seed of every random choice; the same seed gives the same image whatever the thread
    /// count. Default 1.
    pub seed: u64,
    /// Shadow rays per light per primary ray towards a light with a size (`radius`,
    /// `angular_radius_deg`), ≥ 1: the fraction that reaches the light scales it (soft shadows).
    /// Point-like lights take one ray (hard shadows). Default 64.
    pub shadow_samples: u32,
}

impl Default for ReferenceOptions {
    fn default() -> Self {
        ReferenceOptions {
            spp: 1,
            samples: 1024,
            seed: 1,
            shadow_samples: DEFAULT_SHADOW_SAMPLES,
        }
    }
}

/// `shadow_samples` unless asked otherwise.
pub const DEFAULT_SHADOW_SAMPLES: u32 = 64;

/// Largest `spp` and `samples`.
pub const MAX_SPP: u32 = 65_536;
/// Largest `samples`.
pub const MAX_SAMPLES: u32 = 1 << 20;

/// Renders `scene` on the CPU: linear radiance (RGBA, alpha 1) after the scene's saturation,
/// before exposure and tone mapping, as [`crate::headless::Headless::image`] returns it.
/// `progress(done, total)` is called on the calling thread as rows complete (total = height).
pub fn render_reference(
    scene: &Scene,
    opts: &ReferenceOptions,
    progress: Option<&dyn Fn(u64, u64)>,
) -> Result<LinearImage> {
    check_options(opts)?;
    let prepared = render::Prepared::new(scene)?;
    let (w, h) = (prepared.width, prepared.height);
    let row = |y: u32| -> Vec<[f32; 4]> {
        (0..w)
            .map(|x| {
                let c = prepared.pixel(x, y, opts);
                [c.x, c.y, c.z, 1.0]
            })
            .collect()
    };
    let rows: Vec<Vec<[f32; 4]>> = match progress {
        None => (0..h).into_par_iter().map(row).collect(),
        Some(report) => {
            // The callback need not be Sync: workers send a message per row, this thread reports.
            let (tx, rx) = std::sync::mpsc::channel::<()>();
            std::thread::scope(|s| {
                let worker = s.spawn(move || {
                    (0..h)
                        .into_par_iter()
                        .map_with(tx, |tx, y| {
                            let r = row(y);
                            let _ = tx.send(());
                            r
                        })
                        .collect::<Vec<_>>()
                });
                report(0, u64::from(h));
                let mut done = 0u64;
                for () in rx.iter() {
                    done += 1;
                    report(done, u64::from(h));
                }
                worker
                    .join()
                    .map_err(|_| anyhow::anyhow!("reference: a render thread failed"))
            })?
        }
    };
    let mut image = LinearImage {
        width: w,
        height: h,
        pixels: rows.into_iter().flatten().collect(),
    };
    saturate(&mut image, scene.saturation);
    Ok(image)
}

fn check_options(opts: &ReferenceOptions) -> Result<()> {
    if opts.spp == 0 || opts.spp > MAX_SPP {
        bail!("reference: spp must be in 1..={MAX_SPP}, got {}", opts.spp);
    }
    if opts.samples == 0 || opts.samples > MAX_SAMPLES {
        bail!(
            "reference: samples must be in 1..={MAX_SAMPLES}, got {}",
            opts.samples
        );
    }
    if opts.shadow_samples == 0 || opts.shadow_samples > MAX_SAMPLES {
        bail!(
            "reference: shadow samples must be in 1..={MAX_SAMPLES}, got {}",
            opts.shadow_samples
        );
    }
    Ok(())
}

/// [`render_reference`] for a viewer: rows are counted in `rows_done` as they complete, and
/// once `cancel` is set the remaining rows are skipped and `Ok(None)` is returned (a camera that
/// moved makes the image useless). Validation errors as [`render_reference`].
pub fn render_reference_cancellable(
    scene: &Scene,
    opts: &ReferenceOptions,
    rows_done: &std::sync::atomic::AtomicU64,
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<Option<LinearImage>> {
    use std::sync::atomic::Ordering;
    check_options(opts)?;
    let prepared = render::Prepared::new(scene)?;
    let (w, h) = (prepared.width, prepared.height);
    let rows: Vec<Vec<[f32; 4]>> = (0..h)
        .into_par_iter()
        .map(|y| {
            if cancel.load(Ordering::Relaxed) {
                return Vec::new();
            }
            let r = (0..w)
                .map(|x| {
                    let c = prepared.pixel(x, y, opts);
                    [c.x, c.y, c.z, 1.0]
                })
                .collect();
            rows_done.fetch_add(1, Ordering::Relaxed);
            r
        })
        .collect();
    if cancel.load(Ordering::Relaxed) {
        return Ok(None);
    }
    let mut image = LinearImage {
        width: w,
        height: h,
        pixels: rows.into_iter().flatten().collect(),
    };
    saturate(&mut image, scene.saturation);
    Ok(Some(image))
}

/// The primary ray through continuous pixel coordinates `(px, py)` of `scene` (pixel `(x, y)`
/// covers `[x, x + 1] × [y, y + 1]`, y = 0 at the top; its centre is `(x + 0.5, y + 0.5)`):
/// `(origin, direction)` in world space, the direction scaled so that its view-space z is −1
/// (the ray parameter is the view-space depth); an orthographic camera's rays are parallel
/// ([`crate::scene::Camera::ray`]). The same mapping as the GPU path's Vulkan projection
/// (`render::gpu::projection`).
pub fn primary_ray(scene: &Scene, px: f32, py: f32) -> (glam::Vec3, glam::Vec3) {
    let (w, h) = (scene.output.width as f32, scene.output.height as f32);
    let ndc_x = 2.0 * px / w - 1.0;
    let ndc_y = 2.0 * py / h - 1.0;
    scene.camera.ray(ndc_x, ndc_y, w / h)
}

/// The scene's saturation, as the GPU's saturate pass: clamp each channel to 1, or divide the
/// image by its largest finite channel value when that exceeds 1.
fn saturate(img: &mut LinearImage, mode: Saturation) {
    match mode {
        Saturation::None => {}
        Saturation::Clamp => {
            for p in &mut img.pixels {
                for c in &mut p[..3] {
                    *c = c.min(1.0);
                }
            }
        }
        Saturation::Normalize => {
            let m = img
                .pixels
                .iter()
                .map(|p| p[0].max(p[1]).max(p[2]).max(0.0))
                .filter(|m| m.is_finite())
                .fold(0.0f32, f32::max);
            if m > 1.0 {
                for p in &mut img.pixels {
                    for c in &mut p[..3] {
                        *c /= m;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod cancellable_tests {
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

    use super::*;

    #[test]
    fn cancellable_reference_matches_the_plain_one_and_stops_when_cancelled() {
        let mut scene = crate::scene::default_scene();
        scene.environment = None;
        scene.override_size(Some(48), Some(32));
        let opts = ReferenceOptions::default();
        let plain = render_reference(&scene, &opts, None).unwrap();
        let rows = AtomicU64::new(0);
        let cancel = AtomicBool::new(false);
        let image = render_reference_cancellable(&scene, &opts, &rows, &cancel)
            .unwrap()
            .expect("not cancelled");
        assert_eq!(image.pixels, plain.pixels);
        assert_eq!(rows.load(Ordering::Relaxed), 32);
        cancel.store(true, Ordering::Relaxed);
        let rows = AtomicU64::new(0);
        assert!(render_reference_cancellable(&scene, &opts, &rows, &cancel)
            .unwrap()
            .is_none());
        assert_eq!(
            rows.load(Ordering::Relaxed),
            0,
            "no row rendered once cancelled"
        );
        let bad = ReferenceOptions { spp: 0, ..opts };
        let e = render_reference_cancellable(&scene, &bad, &rows, &AtomicBool::new(false))
            .unwrap_err()
            .to_string();
        assert!(e.contains("spp must be in"), "{e}");
    }
}
