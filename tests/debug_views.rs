//! Debug views: each shows its quantity (checked against known values on simple scenes).

mod common;

use common::*;
use luz::headless::{Headless, RenderOptions};
use luz::render::forward::DebugView;
use luz::render::ibl::IblSettings;

fn plane_scene(material: &str, env: &str) -> luz::scene::Scene {
    parse(&format!(
        r#"{{
        "camera": {{"position": [0, 2, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 60, "near": 0.1, "far": 10}},
        "output": {{"width": 32, "height": 32, "msaa": 1}},
        "lights": [{{"type": "directional", "direction": [0, -1, 0], "intensity": 1}}],
        "materials": {{"m": {material}}},
        "objects": [{{"mesh": {{"type": "plane", "size": [10, 10]}}, "material": "m"}}]
        {env}
    }}"#
    ))
}

fn view(
    ctx: &std::sync::Arc<luz::vk::Context>,
    scene: &luz::scene::Scene,
    v: DebugView,
) -> Vec<[f32; 4]> {
    let mut r = Headless::with_options(
        ctx,
        scene,
        &RenderOptions {
            ibl: IblSettings::fast(),
            debug_view: v,
            ..Default::default()
        },
    )
    .unwrap();
    r.render().unwrap();
    r.image().unwrap().pixels
}

fn assert_all(pixels: &[[f32; 4]], want: [f32; 3], tol: f32, what: &str) {
    for p in pixels {
        for c in 0..3 {
            assert!(
                (p[c] - want[c]).abs() <= tol,
                "{what}: pixel {p:?}, expected {want:?}"
            );
        }
    }
}

#[test]
fn debug_views_show_their_quantity() {
    let ctx = gpu();
    let scene = plane_scene(
        r#"{"model": "metal_rough", "base_color": [0.8, 0.4, 0.2], "metallic": 0.25, "roughness": 0.6}"#,
        r#", "environment": {"uniform": [1, 1, 1], "show_background": false}"#,
    );
    assert_all(
        &view(&ctx, &scene, DebugView::Normal),
        [0.5, 1.0, 0.5],
        1e-5,
        "normal",
    );
    assert_all(
        &view(&ctx, &scene, DebugView::BaseColor),
        [0.8, 0.4, 0.2],
        1e-6,
        "base colour",
    );
    assert_all(
        &view(&ctx, &scene, DebugView::Metallic),
        [0.25; 3],
        1e-6,
        "metallic",
    );
    assert_all(
        &view(&ctx, &scene, DebugView::Roughness),
        [0.6; 3],
        1e-6,
        "roughness",
    );
    assert_all(
        &view(&ctx, &scene, DebugView::Ao),
        [1.0; 3],
        1e-6,
        "occlusion",
    );
    // A uniform environment of radiance 1: E/π = 1 everywhere, prefiltered radiance 1.
    assert_all(
        &view(&ctx, &scene, DebugView::Irradiance),
        [1.0; 3],
        1e-3,
        "irradiance",
    );
    assert_all(
        &view(&ctx, &scene, DebugView::Prefiltered),
        [1.0; 3],
        1e-3,
        "prefiltered",
    );
    // The light comes straight down: D at the pixel under the camera is D_GGX(n·h) for the
    // viewing direction there; every value finite and positive, F between F0 and 1.
    for v in [
        DebugView::D,
        DebugView::G,
        DebugView::F,
        DebugView::Diffuse,
        DebugView::Specular,
    ] {
        let px = view(&ctx, &scene, v);
        assert!(
            px.iter()
                .all(|p| p[..3].iter().all(|c| c.is_finite() && *c >= 0.0)),
            "{v:?}: a non-finite or negative value"
        );
        assert!(px.iter().any(|p| p[0] > 0.0), "{v:?}: all zero");
    }
    let f = view(&ctx, &scene, DebugView::F);
    let f0 = 0.04 * 0.75 + 0.8 * 0.25;
    assert!(
        f.iter().all(|p| p[0] >= f0 - 1e-4 && p[0] <= 1.0),
        "F outside [F0, 1]"
    );
    // The NaN highlighter leaves a clean image untouched.
    let shaded = view(&ctx, &scene, DebugView::None);
    let nan_view = view(&ctx, &scene, DebugView::Nan);
    assert!(shaded == nan_view, "the NaN view changed finite pixels");
    assert_no_validation_messages(&ctx);
}
