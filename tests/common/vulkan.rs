//! A validated lavapipe context, rendering helpers and golden-image checks.

use std::path::Path;
use std::sync::Arc;

use luz::diff::{DiffOptions, DiffReport};
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

/// Compares the PNG encoding of `img` with `tests/golden/<name>.png`. With `LUZ_BLESS=1` the golden
/// is (re)written instead. On failure actual, expected and diff images go to
/// `target/golden-failures/`.
pub fn check_golden(name: &str, scene: &Scene, img: &LinearImage, tol: Tolerance) -> DiffReport {
    assert_eq!(
        nan_count(img),
        0,
        "{name}: NaN/Inf pixels in the linear buffer"
    );
    let golden = root().join("tests/golden").join(format!("{name}.png"));
    let fail_dir = root().join("target/golden-failures");
    std::fs::create_dir_all(&fail_dir).unwrap();
    let actual_path = fail_dir.join(format!("{name}.actual.png"));
    luz::imageio::save(
        &actual_path,
        img,
        scene.output.exposure,
        scene.output.tonemap,
    )
    .unwrap();
    if std::env::var_os("LUZ_BLESS").is_some() {
        std::fs::copy(&actual_path, &golden).unwrap();
        let ctx_driver = driver_string();
        std::fs::write(root().join("tests/golden/DRIVER.txt"), ctx_driver).unwrap();
        eprintln!("blessed {}", golden.display());
    }
    assert!(
        golden.exists(),
        "no golden {}; bless it with LUZ_BLESS=1 scripts/test.sh {name}",
        golden.display()
    );
    let opts = DiffOptions {
        max_flip_mean: Some(tol.max_flip_mean),
        max_abs: Some(tol.max_abs),
        max_bad_pixels: Some(tol.max_bad_pixels),
        bad_pixel_threshold: tol.bad_threshold,
        heatmap: Some(fail_dir.join(format!("{name}.diff.png"))),
        ..Default::default()
    };
    let expected = luz::imageio::load(&golden).unwrap();
    let actual: LoadedImage = luz::imageio::load(&actual_path).unwrap();
    assert_eq!(expected.format, FileFormat::Png);
    let report = luz::diff::compare(&expected, &actual, &opts).unwrap();
    let violations = report.violations(&opts);
    if violations.is_empty() {
        let _ = std::fs::remove_file(&actual_path);
        let _ = std::fs::remove_file(fail_dir.join(format!("{name}.diff.png")));
    } else {
        std::fs::copy(&golden, fail_dir.join(format!("{name}.expected.png"))).unwrap();
        panic!(
            "{name}: golden mismatch:\n{report}\n{}\nimages in {}",
            violations.join("\n"),
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
