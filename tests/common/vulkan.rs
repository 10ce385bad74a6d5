//! A validated lavapipe context, rendering helpers and golden-image checks.

use std::path::Path;
use std::sync::Arc;

use luz::diff::DiffReport;
use luz::headless::Headless;
use luz::imageio::{FileFormat, LinearImage, LoadedImage};
use luz::scene::Scene;
use luz::vk::{Context, ContextDesc, InstanceDesc};

use super::root;

/// A device context with the validation layer on (always, in tests), and its synchronization
/// checks when `LUZ_SYNC_VALIDATION` is set (as `scripts/test.sh` does). The ICD is the caller's
/// `VK_ICD_FILENAMES`, else lavapipe (`.cargo/config.toml` sets it for `cargo test`).
pub fn gpu() -> Arc<Context> {
    gpu_with(std::env::var_os("LUZ_SYNC_VALIDATION").is_some())
}

/// [`gpu`] with synchronization validation on or off.
pub fn gpu_with(sync_validation: bool) -> Arc<Context> {
    Context::new(&ContextDesc {
        instance: InstanceDesc {
            validation: true,
            sync_validation,
            ..Default::default()
        },
        device_name: None,
        device_extensions: Vec::new(),
        malloc_tuning: true,
    })
    .expect("a Vulkan device with the validation layer (run scripts/setup.sh)")
}

/// Fails the test when the validation layer reported anything.
pub fn assert_no_validation_messages(ctx: &Context) {
    let log = ctx.validation_log();
    let msgs = log.messages();
    assert!(
        log.errors() == 0 && log.warnings() == 0,
        "validation reported {} errors and {} warnings:\n{}",
        log.errors(),
        log.warnings(),
        msgs.join("\n")
    );
}

pub fn parse(json: &str) -> Scene {
    luz::scene::parse(json, Path::new("<test scene>")).unwrap_or_else(|e| panic!("{e}"))
}

/// Renders `scene` once on `ctx` (call [`assert_no_validation_messages`] when done with it).
pub fn render_on(ctx: &Arc<Context>, scene: &Scene) -> LinearImage {
    let mut r = Headless::new(ctx, scene).expect("renderer");
    r.render().expect("frame");
    r.image().expect("readback")
}

/// Renders `scene` once and returns its linear radiance, asserting a clean validation log.
pub fn render(scene: &Scene) -> LinearImage {
    let ctx = gpu();
    let img = render_on(&ctx, scene);
    assert_no_validation_messages(&ctx);
    img
}

pub fn nan_count(img: &LinearImage) -> usize {
    img.pixels
        .iter()
        .filter(|p| p.iter().any(|c| !c.is_finite()))
        .count()
}

/// Tolerances of one golden comparison.
#[derive(Clone, Copy)]
pub struct Tolerance {
    pub max_flip_mean: f32,
    /// In 8-bit steps.
    pub max_abs: f32,
    /// Pixels allowed to differ by more than `bad_threshold` steps.
    pub max_bad_pixels: u64,
    pub bad_threshold: f32,
}

impl Default for Tolerance {
    /// The product's golden-image tolerances (`luz diff`'s and `luz golden`'s defaults), so the
    /// harness and the product cannot drift. Same machine: byte-exact. Other CPUs: lavapipe's
    /// approximate rcp/rsqrt move a few LSB.
    fn default() -> Self {
        Self {
            max_flip_mean: luz::diff::GOLDEN_MAX_FLIP_MEAN,
            max_abs: luz::diff::GOLDEN_MAX_ABS_STEPS,
            max_bad_pixels: luz::diff::GOLDEN_MAX_BAD_PIXELS,
            bad_threshold: luz::diff::GOLDEN_BAD_THRESHOLD_STEPS,
        }
    }
}

impl From<Tolerance> for luz::diff::Tolerance {
    fn from(t: Tolerance) -> Self {
        luz::diff::Tolerance {
            max_flip_mean: Some(t.max_flip_mean),
            max_abs: Some(t.max_abs),
            max_bad_pixels: Some(t.max_bad_pixels),
            bad_pixel_threshold: t.bad_threshold,
        }
    }
}

/// The case file `tests/golden/<name>.golden.json` (`luz golden`'s: the scene, its size and IBL
/// quality, tolerances), read by luz's own code.
pub fn golden_case(name: &str) -> luz::golden::CaseFile {
    let path = root()
        .join("tests/golden")
        .join(format!("{name}.golden.json"));
    luz::golden::CaseFile::read(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The scene of golden `name` as `luz golden tests/golden` renders it: through its case file.
pub fn golden_scene(name: &str) -> Scene {
    golden_case(name)
        .load_scene()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Asserts that `case` and `test` are the same scene (every field, the meshes' vertices
/// included; where they were loaded from aside).
pub fn assert_same_scene(case: &Scene, test: &Scene) {
    let show = |s: &Scene| {
        let mut s = s.clone();
        s.source = None;
        format!("{s:?}")
    };
    assert!(
        show(case) == show(test),
        "the golden's case file makes another scene than the test ({} against {})",
        case.display_name(),
        test.display_name()
    );
}

/// Compares the PNG encoding of `img` with `tests/golden/<name>.png` through the same library
/// code as `luz golden` ([`luz::golden::compare_with_golden`]). With `LUZ_BLESS=1` the golden is
/// (re)written instead. On failure actual, expected and diff images go to
/// `target/golden-failures/`.
pub fn check_golden(name: &str, scene: &Scene, img: &LinearImage, tol: Tolerance) -> DiffReport {
    assert_eq!(
        nan_count(img),
        0,
        "{name}: NaN/Inf pixels in the linear buffer"
    );
    // The case file's tolerances (over the test's), as `luz golden` reads them.
    let case = root()
        .join("tests/golden")
        .join(format!("{name}.golden.json"));
    let tol: luz::diff::Tolerance = match case.is_file() {
        true => golden_case(name).tolerance.apply(tol.into()),
        false => tol.into(),
    };
    let golden = root().join("tests/golden").join(format!("{name}.png"));
    let fail_dir = root().join("target/golden-failures");
    std::fs::create_dir_all(&fail_dir).unwrap();
    let actual_path = fail_dir.join(format!("{name}.actual.png"));
    let diff_path = fail_dir.join(format!("{name}.diff.png"));
    let unchanged = || {
        luz::imageio::load(&golden).is_ok_and(|g| {
            let now = LoadedImage::from_linear(
                img,
                FileFormat::Png,
                scene.output.exposure,
                scene.output.tonemap,
            );
            g.display == now.display && (g.width, g.height) == (now.width, now.height)
        })
    };
    // Blessing leaves a golden with the same pixels alone (`git diff tests/golden/` shows only
    // real changes).
    if std::env::var_os("LUZ_BLESS").is_some() && !unchanged() {
        luz::imageio::save(&golden, img, scene.output.exposure, scene.output.tonemap).unwrap();
        let ctx_driver = driver_string();
        std::fs::write(root().join("tests/golden/DRIVER.txt"), ctx_driver).unwrap();
        eprintln!("blessed {}", golden.display());
    }
    assert!(
        golden.exists(),
        "no golden {}; bless it with LUZ_BLESS=1 scripts/test.sh {name}",
        golden.display()
    );
    let actual = LoadedImage::from_linear(
        img,
        FileFormat::Png,
        scene.output.exposure,
        scene.output.tonemap,
    );
    let cmp = luz::golden::compare_with_golden(
        &golden,
        luz::imageio::count_non_finite(&img.pixels),
        actual,
        tol,
    );
    let expected = cmp.expected.as_ref().expect("the golden loads");
    assert_eq!(expected.format, FileFormat::Png);
    let report = cmp
        .report
        .clone()
        .unwrap_or_else(|| panic!("{name}: {}", cmp.failures.join("\n")));
    if cmp.failures.is_empty() {
        let _ = std::fs::remove_file(&actual_path);
        let _ = std::fs::remove_file(&diff_path);
    } else {
        luz::imageio::save(
            &actual_path,
            img,
            scene.output.exposure,
            scene.output.tonemap,
        )
        .unwrap();
        if let Some(map) = &cmp.flip {
            luz::diff::write_heatmap(&diff_path, map).unwrap();
        }
        std::fs::copy(&golden, fail_dir.join(format!("{name}.expected.png"))).unwrap();
        panic!(
            "{name}: golden mismatch:\n{report}\n{}\n{}\nimages in {}",
            cmp.failures.join("\n"),
            // Where the golden came from (goldens blessed before provenance have none).
            cmp.expected_provenance
                .map(|p| p
                    .entries
                    .iter()
                    .filter(
                        |(k, _)| ["luz.device", "luz.driver", "luz.vulkan"].contains(&k.as_str())
                    )
                    .map(|(k, v)| format!("golden {k}: {v}"))
                    .collect::<Vec<_>>()
                    .join("\n"))
                .unwrap_or_default(),
            fail_dir.display()
        );
    }
    report
}

fn driver_string() -> String {
    let ctx = gpu();
    format!(
        "Goldens in this folder were blessed on: {}\n",
        ctx.info.summary()
    )
}

/// Each renderer's forward-pass GPU ms (the forward, or the deferred path's gbuffer and
/// lighting passes), by [`interleaved_pass_medians`]: the area lights' and their shadows' cost
/// tests (tests/area_lights.rs, tests/area_shadows.rs).
pub fn interleaved_forward_medians(
    renderers: &mut [luz::headless::Headless],
    warmup: usize,
    rounds: usize,
) -> Vec<f64> {
    interleaved_pass_medians(renderers, warmup, rounds, |n| {
        n.contains("forward") || n.contains("lighting") || n.contains("gbuffer")
    })
}

/// Each renderer's GPU ms summed over the passes whose name `pass` accepts: `warmup` frames
/// each, then `rounds` rounds rendering every renderer in turn (a busy machine slows them
/// alike), and each one's median.
pub fn interleaved_pass_medians(
    renderers: &mut [luz::headless::Headless],
    warmup: usize,
    rounds: usize,
    pass: impl Fn(&str) -> bool,
) -> Vec<f64> {
    let ms = |t: &luz::headless::FrameTimes| {
        t.gpu_ms
            .iter()
            .filter(|(n, _)| pass(n))
            .map(|(_, ms)| ms)
            .sum::<f64>()
    };
    for r in renderers.iter_mut() {
        for _ in 0..warmup {
            r.render().expect("frame");
        }
    }
    let mut times = vec![Vec::new(); renderers.len()];
    for _ in 0..rounds {
        for (r, t) in renderers.iter_mut().zip(times.iter_mut()) {
            t.push(ms(&r.render().expect("frame")));
        }
    }
    times
        .iter_mut()
        .map(|v| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        })
        .collect()
}

/// Renders `scene` by the forward and the Auto paths (deferred for a Lambert scene), each image
/// named by the path that drew it (tests/area_lights.rs, tests/area_shadows.rs).
pub fn both_paths(ctx: &std::sync::Arc<Context>, scene: &Scene) -> Vec<(String, LinearImage)> {
    use luz::headless::{Headless, RenderOptions};
    use luz::render::forward::RenderPath;
    [RenderPath::Forward, RenderPath::Auto]
        .into_iter()
        .map(|path| {
            let options = RenderOptions {
                render_path: path,
                ..Default::default()
            };
            let mut r = Headless::with_options(ctx, scene, &options).expect("renderer");
            let name = r.render_path().to_string();
            r.render().expect("frame");
            (name, r.image().expect("readback"))
        })
        .collect()
}
