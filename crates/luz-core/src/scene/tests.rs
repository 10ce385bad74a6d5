//! Unit tests of the scene format: defaults, assets, transforms and error messages.

use super::*;
use glam::Vec4;

fn parse_str(text: &str) -> Result<Scene, SceneError> {
    parse(text, Path::new("scenes/a.json"))
}

/// The error message for `text`, which must fail.
fn error(text: &str) -> String {
    match parse_str(text) {
        Ok(_) => panic!("expected an error for {text}"),
        Err(e) => e.to_string(),
    }
}

fn assert_error(text: &str, expected: &str) {
    let e = error(text);
    assert!(
        e.starts_with("scenes/a.json: "),
        "message does not start with the file: {e}"
    );
    assert!(e.contains(expected), "{e:?} does not contain {expected:?}");
}

const SPHERE: &str = r#""materials": {"m": {"model": "lambert"}},
    "objects": [{"mesh": {"type": "sphere"}, "material": "m"}]"#;

#[test]
fn default_scene_parses() {
    let s = default_scene();
    assert!(s.source.is_none());
    assert_eq!((s.output.width, s.output.height), (1280, 720));
    assert!((45.0..=50.0).contains(&s.camera.fov_y_deg));
    assert_eq!(s.lights.len(), 2);
    assert_eq!(s.lights[0].kind, LightKind::Directional);
    assert_eq!(s.lights[1].kind, LightKind::Point);
    let spheres = s
        .objects
        .iter()
        .filter(|o| matches!(o.desc, MeshDesc::Sphere { .. }))
        .count();
    assert!((3..=4).contains(&spheres));
    assert!(s
        .objects
        .iter()
        .any(|o| matches!(o.desc, MeshDesc::Plane { .. })));
    // Equal descriptions share one mesh.
    let sphere_meshes: Vec<_> = s
        .objects
        .iter()
        .filter(|o| matches!(o.desc, MeshDesc::Sphere { .. }))
        .map(|o| Arc::as_ptr(&o.mesh))
        .collect();
    assert!(sphere_meshes.windows(2).all(|w| w[0] == w[1]));
    // The camera looks slightly down at the spheres.
    assert!(s.camera.forward().y < 0.0 && s.camera.forward().y > -0.5);
}

/// Every light of the default scene gives a clearly lit, not blown-out sphere top under the
/// classic model (a CPU estimate, no tone mapping).
#[test]
fn default_scene_is_clearly_lit() {
    let s = default_scene();
    for o in s
        .objects
        .iter()
        .filter(|o| matches!(o.desc, MeshDesc::Sphere { .. }))
    {
        let Material::Phong(crate::brdf::PhongParams {
            ka,
            kd,
            diffuse_color,
            ..
        }) = s.materials[o.material].material
        else {
            panic!("the default scene uses the classic model")
        };
        // The point of the sphere facing the camera.
        let n = (s.camera.position - o.transform.position).normalize();
        let p = o.transform.position + n * 0.6;
        let mut c = s.ambient * ka * diffuse_color;
        for l in &s.lights {
            let (dir, e) = match l.kind {
                LightKind::Directional => (-l.direction, l.color * l.intensity),
                _ => {
                    let d = l.position - p;
                    let r = d.length();
                    (d / r, l.color * l.intensity * l.falloff.factor(r))
                }
            };
            c += e * kd * diffuse_color * n.dot(dir).max(0.0);
        }
        let lum = c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        assert!(lum > 0.1 && c.max_element() < 1.2, "{}: {c}", o.name);
    }
}

#[test]
fn every_asset_scene_parses() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("assets/scenes");
    let mut count = 0;
    let mut stack = vec![dir];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "json") {
                // Scenes built from the shared models (assets/scenes/lod) need ../shared.
                let shared =
                    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("../shared");
                let text = std::fs::read_to_string(&p).unwrap();
                if text.contains("/shared/") && !shared.exists() {
                    eprintln!("SKIPPED: {} needs ../shared", p.display());
                    continue;
                }
                let s = load(&p).unwrap_or_else(|e| panic!("{e}"));
                assert!(!s.objects.is_empty(), "{}", p.display());
                assert!(!s.description.is_empty(), "{}", p.display());
                count += 1;
            }
        }
    }
    assert!(count >= 10, "found only {count} scenes");
}

#[test]
fn classic_scenes_match_the_slides() {
    let dir =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("assets/scenes/classic");
    let s = load(&dir.join("06_colour.json")).unwrap();
    assert_eq!(s.ambient, Vec3::splat(0.5));
    assert_eq!(s.lights[0].position, Vec3::splat(2.0));
    assert_eq!(s.lights[0].falloff, Falloff::None);
    let xs: Vec<f32> = s.objects.iter().map(|o| o.transform.position.x).collect();
    assert!(xs[0] < xs[1] && xs[1] < xs[2]);
    let Material::Phong(crate::brdf::PhongParams {
        blinn,
        ka,
        kd,
        ks,
        shininess,
        diffuse_color,
        ..
    }) = s.materials[s.objects[0].material].material
    else {
        panic!()
    };
    assert!(!blinn);
    assert_eq!((ka, kd, ks, shininess), (0.4, 0.8, 0.7, 20.0));
    assert_eq!(diffuse_color, Vec3::Y);
    let on = load(&dir.join("09_depth_cue_on.json")).unwrap();
    let off = load(&dir.join("08_depth_cue_off.json")).unwrap();
    assert!(on.fog.is_some() && off.fog.is_none());
    let ml = load(&dir.join("07_multiple_lights.json")).unwrap();
    let kinds: Vec<_> = ml.lights.iter().map(|l| l.kind).collect();
    assert_eq!(kinds, [LightKind::Point, LightKind::Spot]);
}

#[test]
fn defaults() {
    let s = parse_str("{}").unwrap();
    assert_eq!(s.camera.position, Vec3::new(0.0, 0.0, 5.0));
    assert_eq!(s.camera.up, Vec3::Y);
    assert_eq!(
        (s.camera.fov_y_deg, s.camera.near, s.camera.far),
        (45.0, 0.1, 100.0)
    );
    assert_eq!(s.output.msaa, 4);
    assert_eq!(s.output.tonemap, crate::color::Tonemap::None);
    assert_eq!(s.ambient, Vec3::ZERO);
    assert!(s.lights.is_empty() && s.objects.is_empty() && s.fog.is_none());
    assert_eq!(s.saturation, Saturation::None);
    assert_eq!(s.source.as_deref(), Some(Path::new("scenes/a.json")));

    let s = parse_str(&format!("{{{SPHERE}}}")).unwrap();
    let o = &s.objects[0];
    assert_eq!(o.name, "sphere0");
    // Segments left out: chosen from the projected size (a unit sphere 5 units from the default
    // camera, fov 45°, 720 px tall: 175.6 px) within the default 0.05 px budget.
    let r_px = crate::scene::tessellation::projected_radius_px(&s.camera, 720, Vec3::ZERO, 1.0);
    let n = crate::scene::tessellation::segments_for(r_px, 0.05);
    assert!(
        matches!(o.tessellation, crate::scene::Tessellation::Auto { projected_radius_px, .. } if projected_radius_px == r_px)
    );
    assert_eq!(
        o.desc,
        MeshDesc::Sphere {
            radius: 1.0,
            segments: n,
            rings: n / 2
        }
    );
    assert_eq!(
        o.mesh.indices.len() as u64,
        3 * o.desc.triangle_count().unwrap()
    );
    assert_eq!(s.output.tessellation_error_px, 0.05);
    assert_eq!(o.shading, Shading::Phong);
    assert_eq!(o.transform, Transform::default());
    assert_eq!(
        s.materials[0].material,
        Material::Lambert(crate::brdf::LambertParams {
            albedo: Vec3::splat(0.8)
        })
    );
}

#[test]
fn lights_are_decoded() {
    let s = parse_str(
        r#"{"lights": [
        {"type": "directional", "direction": [0, -2, 0], "intensity": 3},
        {"type": "directional", "position": [3, 4, 0], "target": [2, 3, 0]},
        {"type": "point", "position": [1, 2, 3], "color": 0.5},
        {"type": "point", "position": [1, 2, 3], "falloff": {"c2": 0.5}},
        {"type": "spot", "position": [0, 1.5, 5], "target": [0, 0, 2], "umbra_deg": 35, "inner_deg": 20, "exponent": 2, "falloff": "none"}
    ]}"#,
    )
    .unwrap();
    let l = &s.lights;
    assert_eq!(l[0].direction, Vec3::NEG_Y);
    assert_eq!(l[0].intensity, 3.0);
    assert_eq!(l[0].falloff, Falloff::None);
    assert!((l[1].direction - Vec3::new(-1.0, -1.0, 0.0).normalize()).length() < 1e-6);
    assert_eq!(l[2].color, Vec3::splat(0.5));
    assert_eq!(l[2].falloff, Falloff::InverseSquare);
    assert_eq!(
        (l[2].umbra_deg, l[2].exponent, l[2].inner_deg),
        (180.0, 0.0, None)
    );
    assert_eq!(
        l[3].falloff,
        Falloff::Classic {
            c1: 1.0,
            c2: 0.5,
            c3: 0.0
        }
    );
    assert_eq!(l[4].kind, LightKind::Spot);
    assert!((l[4].direction - Vec3::new(0.0, -1.5, -3.0).normalize()).length() < 1e-6);
    assert_eq!(
        (l[4].umbra_deg, l[4].inner_deg, l[4].exponent),
        (35.0, Some(20.0), 2.0)
    );
    assert_eq!(l[4].falloff, Falloff::None);
}

#[test]
fn falloff_factors() {
    assert_eq!(Falloff::InverseSquare.factor(2.0), 0.25);
    assert_eq!(Falloff::None.factor(100.0), 1.0);
    let c = Falloff::Classic {
        c1: 0.0,
        c2: 0.0,
        c3: 0.0,
    };
    assert_eq!(c.factor(3.0), 1.0);
    let c = Falloff::Classic {
        c1: 1.0,
        c2: 1.0,
        c3: 1.0,
    };
    assert_eq!(c.factor(1.0), 1.0 / 3.0);
}

/// `range`: decoded for point and spot lights, the window of KHR_lights_punctual, and a clear
/// error for a bad value or on a directional light.
#[test]
fn light_range() {
    let s = parse_str(
        r#"{"lights": [
            {"type": "point", "position": [0, 1, 0], "intensity": 4, "range": 2.5},
            {"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "range": 1e3},
            {"type": "point", "position": [0, 1, 0]}
        ]}"#,
    )
    .unwrap();
    assert_eq!(s.lights[0].range, Some(2.5));
    assert_eq!(s.lights[1].range, Some(1000.0));
    assert_eq!(s.lights[2].range, None);
    let l = &s.lights[0];
    assert_eq!(l.distance_factor(1.0), range_window(1.0, Some(2.5)));
    assert_eq!(l.distance_factor(2.0), 0.25 * range_window(2.0, Some(2.5)));
    assert_eq!(l.distance_factor(2.5), 0.0);
    assert_eq!(l.distance_factor(7.0), 0.0);
    assert_eq!(s.lights[2].distance_factor(7.0), 1.0 / 49.0);
    // W(d) = clamp(1 − (d/r)⁴, 0, 1)²
    assert_eq!(range_window(0.0, Some(2.0)), 1.0);
    assert!((range_window(1.0, Some(2.0)) - (1.0f32 - 1.0 / 16.0).powi(2)).abs() < 1e-7);
    assert_eq!(range_window(2.0, Some(2.0)), 0.0);
    assert_eq!(range_window(1e9, None), 1.0);
    for (value, expected) in [
        ("-1", "lights[0].range: must be > 0, got -1"),
        ("0", "lights[0].range: must be > 0, got 0"),
        (
            "\"NaN\"",
            "lights[0].range: expected a number, got a string",
        ),
        ("1e39", "lights[0].range: must be a finite number"),
    ] {
        assert_error(
            &format!(
                r#"{{"lights": [{{"type": "point", "position": [0, 1, 0], "range": {value}}}]}}"#
            ),
            expected,
        );
    }
    assert_error(
        r#"{"lights": [{"type": "directional", "direction": [0, -1, 0], "range": 3}]}"#,
        "lights[0].range: unknown field \"range\" for a directional light",
    );
}

/// The range for a radiance threshold bounds the error of the cut everywhere, and the bound is
/// tight: the largest error, found by sampling, is the threshold.
#[test]
fn range_for_threshold_bounds_the_cut() {
    for (intensity, threshold) in [(1.0f32, 1e-2f32), (40.0, 1e-3), (500.0, 1e-5)] {
        let r = range_for_threshold(intensity, threshold).unwrap();
        let light = Light {
            intensity,
            falloff: Falloff::InverseSquare,
            range: Some(r),
            ..crate::scene::edit::default_light(LightKind::Point, None)
        };
        let mut worst = 0.0f32;
        for k in 1..=20_000 {
            let d = r * 1.5 * k as f32 / 20_000.0;
            let exact = intensity / (d * d);
            let cut = intensity * light.distance_factor(d);
            worst = worst.max(exact - cut);
        }
        assert!(
            (worst - threshold).abs() <= threshold * 2e-3,
            "I = {intensity}, t = {threshold}: range {r}, worst error {worst}"
        );
    }
    assert_eq!(range_for_threshold(0.0, 1e-3), None);
    assert_eq!(range_for_threshold(1.0, f32::NAN), None);
}

#[test]
fn fog_defaults_and_factor() {
    let s =
        parse_str(r#"{"output": {"background": [0.1, 0.2, 0.3]}, "fog": {"z_a": 2, "z_b": 4}}"#)
            .unwrap();
    let f = s.fog.unwrap();
    assert_eq!((f.s_a, f.s_b), (0.0, 1.0));
    assert_eq!(f.color, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(f.factor(1.0), 0.0);
    assert_eq!(f.factor(3.0), 0.5);
    assert_eq!(f.factor(9.0), 1.0);
    assert!(parse_str(r#"{"fog": null}"#).unwrap().fog.is_none());
}

#[test]
fn transform_matrix_is_t_rz_ry_rx_s() {
    let t = Transform {
        position: Vec3::new(1.0, 2.0, 3.0),
        rotation_deg: Vec3::new(90.0, 0.0, 0.0),
        scale: Vec3::new(2.0, 3.0, 4.0),
    };
    let m = t.matrix();
    // Scale first: +y becomes (0, 3, 0); then 90° about X maps +y to +z.
    let p = m.transform_point3(Vec3::Y);
    assert!((p - Vec3::new(1.0, 2.0, 6.0)).length() < 1e-5, "{p}");
    // X first, then Y, then Z: rotate +y by 90° about X (→ +z), then 90° about Y (+z → +x).
    let t = Transform {
        rotation_deg: Vec3::new(90.0, 90.0, 0.0),
        ..Transform::default()
    };
    let p = t.matrix().transform_vector3(Vec3::Y);
    assert!((p - Vec3::X).length() < 1e-5, "{p}");
    // … and Z last: +x by 90° about Z → +y.
    let t = Transform {
        rotation_deg: Vec3::new(90.0, 90.0, 90.0),
        ..Transform::default()
    };
    let p = t.matrix().transform_vector3(Vec3::Y);
    assert!((p - Vec3::Y).length() < 1e-5, "{p}");
    assert_eq!(Transform::default().matrix(), Mat4::IDENTITY);
    // Normals of a non-uniformly scaled sphere stay perpendicular to the surface.
    let t = Transform {
        scale: Vec3::new(1.0, 4.0, 1.0),
        ..Transform::default()
    };
    let n = (t.normal_matrix() * Vec3::new(1.0, 1.0, 0.0)).normalize();
    let tangent = t.matrix() * Vec4::new(1.0, -1.0, 0.0, 0.0);
    assert!(n.dot(tangent.truncate()).abs() < 1e-5);
}

#[test]
fn camera_view_is_look_at() {
    let s =
        parse_str(r#"{"camera": {"position": [0, 0, 5], "target": [0, 0, 0], "up": [0, 2, 0]}}"#)
            .unwrap();
    assert_eq!(s.camera.up, Vec3::Y);
    let v = s.camera.view();
    let p = v.transform_point3(Vec3::ZERO);
    assert!((p - Vec3::new(0.0, 0.0, -5.0)).length() < 1e-6);
    let clip = s.camera.projection(s.output.aspect()) * Vec4::new(0.0, 0.0, -5.0, 1.0);
    let depth = clip.z / clip.w;
    assert!((0.0..1.0).contains(&depth));
}

#[test]
fn error_messages() {
    // The example from the issue, verbatim.
    assert_error(
        r#"{"lights": [
            {"type": "point", "position": [0, 1, 0]},
            {"type": "point", "position": [0, 1, 0]},
            {"type": "point", "position": [0, 1, 0], "intensity": -1}]}"#,
        "scenes/a.json: lights[2].intensity: must be ≥ 0, got -1",
    );
    assert_error(
        r#"{"camera": {"fov_y_deg": "45"}}"#,
        "camera.fov_y_deg: expected a number, got a string",
    );
    assert_error(r#"{"camra": {}}"#, "camra: unknown field \"camra\"");
    assert_error(r#"{"camra": {}}"#, "did you mean \"camera\"?");
    assert_error(
        r#"{"camera": {"far": 1e999}}"#,
        "camera.far: must be a finite number, got 1e999",
    );
    assert_error(
        r#"{"camera": {"far": 1e39}}"#,
        "camera.far: must be a finite number, got 1e39",
    );
    assert_error(
        r#"{"camera": {"near": NaN}}"#,
        "camera.near: NaN is not a number JSON allows",
    );
    assert_error(
        r#"{"camera": {"near": 10, "far": 5}}"#,
        "camera.far: must be > near (10), got 5",
    );
    assert_error(
        r#"{"camera": {"fov_y_deg": 180}}"#,
        "camera.fov_y_deg: must be in (0, 180), got 180",
    );
    assert_error(
        r#"{"camera": {"up": [0, 0, -1]}}"#,
        "camera.up: is parallel to the view direction",
    );
    assert_error(
        r#"{"camera": {"target": [0, 0, 5]}}"#,
        "camera.target: equals the camera position",
    );
    assert_error(
        r#"{"output": {"msaa": 3}}"#,
        "output.msaa: must be 1, 2, 4 or 8, got 3",
    );
    assert_error(
        r#"{"output": {"width": 0}}"#,
        "output.width: must be in [1, 16384], got 0",
    );
    assert_error(
        r#"{"output": {"height": 16385}}"#,
        "output.height: must be in [1, 16384], got 16385",
    );
    assert_error(
        r#"{"output": {"width": 12.5}}"#,
        "output.width: expected an integer, got 12.5",
    );
    assert_error(
        r#"{"output": {"tonemap": "filmic"}}"#,
        "output.tonemap: unknown variant `filmic`",
    );
    assert_error(
        r#"{"lights": [{"type": "directional", "direction": [0, 0, 0]}]}"#,
        "lights[0].direction: must not be a zero-length vector",
    );
    assert_error(
        r#"{"lights": [{"type": "directional", "direction": [0, -1, 0], "falloff": "none"}]}"#,
        "lights[0].falloff: unknown field \"falloff\" for a directional light",
    );
    assert_error(
        r#"{"lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "umbra_deg": 20, "inner_deg": 25}]}"#,
        "lights[0].inner_deg: must be < umbra_deg (20), got 25",
    );
    assert_error(
        r#"{"lights": [{"type": "area"}]}"#,
        "lights[0].type: unknown value \"area\"",
    );
    assert_error(
        r#"{"lights": [{"type": "point"}]}"#,
        "lights[0].position: missing required field",
    );
    assert_error(
        r#"{"materials": {"m": {"model": "phong", "kd": -0.5}}}"#,
        "materials.m.kd: must be ≥ 0, got -0.5",
    );
    assert_error(
        r#"{"materials": {"my m": {"model": "cook"}}}"#,
        "materials[\"my m\"].model: unknown value \"cook\"",
    );
    assert_error(
        r#"{"materials": {"m": {"model": "lambert", "albedo": [1.5, 0, 0]}}}"#,
        "materials.m.albedo: every channel must be in [0, 1]",
    );
    assert_error(
        r#"{"materials": {"a/b": {"model": "lambert"}}}"#,
        "materials[\"a/b\"]: a material name must not contain '/'",
    );
    assert_error(
        r#"{"objects": [{"mesh": {"type": "sphere"}, "material": "gold"}]}"#,
        "objects[0].material: unknown material \"gold\"",
    );
    assert_error(
        r#"{"objects": [{"mesh": {"type": "sphere"}}]}"#,
        "objects[0].material: missing required field",
    );
    assert_error(
        &format!(r#"{{{SPHERE}, "fog": {{"z_a": 5, "z_b": 5}}}}"#),
        "fog.z_b: must be > z_a (5), got 5",
    );
    let obj = |mesh: &str| {
        format!(
            r#"{{"materials": {{"m": {{"model": "lambert"}}}}, "objects": [{{"mesh": {mesh}, "material": "m"}}]}}"#
        )
    };
    assert_error(
        &obj(r#"{"type": "sphere", "segments": 100000}"#),
        "objects[0].mesh.segments: must be in [3, 4096], got 100000",
    );
    assert_error(
        &obj(r#"{"type": "sphere", "segments": 4096, "rings": 4096}"#),
        "objects[0].mesh: too finely tessellated: 33546240 triangles",
    );
    assert_error(
        &obj(r#"{"type": "icosphere", "subdivisions": 9}"#),
        "objects[0].mesh.subdivisions: must be in [0, 8], got 9",
    );
    assert_error(
        &obj(r#"{"type": "cube", "size": 0}"#),
        "objects[0].mesh.size: must be > 0, got 0",
    );
    assert_error(
        &obj(r#"{"type": "plane", "size": [1, -2]}"#),
        "objects[0].mesh.size[1]: must be > 0, got -2",
    );
    assert_error(
        &obj(r#"{"type": "cone", "radius": 1, "heigth": 2}"#),
        "did you mean \"height\"?",
    );
    assert_error(
        &obj(r#"{"type": "obj", "path": "nope.obj"}"#),
        "objects[0].mesh.path: scenes/nope.obj: cannot read",
    );
    assert_error(
        r#"{"objects": [{"mesh": {"type": "cube"}, "material": "m", "scale": [1, 0, 1]}], "materials": {"m": {"model": "lambert"}}}"#,
        "objects[0].scale[1]: must be > 0, got 0",
    );
    assert_error(
        r#"{"objects": [{"mesh": {"type": "cube"}, "material": "m", "shading": "smooth"}], "materials": {"m": {"model": "lambert"}}}"#,
        "objects[0].shading: unknown value \"smooth\"",
    );
    // Syntax errors name the path being read and the position.
    assert_error(
        "{\"camera\": {\"position\": [0, 1",
        "camera.position: unexpected end of file",
    );
    assert_error("{\"camera\": {\"position\": [0, 1", "at line 1, column 30");
    assert_error("[1, 2]", "(root): expected a JSON object");
    assert_error("", "(root): the file is empty");
}

#[test]
fn transparent_output_is_a_boolean() {
    assert!(!parse_str("{}").unwrap().output.transparent);
    assert!(
        parse_str(r#"{"output": {"transparent": true}}"#)
            .unwrap()
            .output
            .transparent
    );
    let e = parse_str(r#"{"output": {"transparent": "yes"}}"#).unwrap_err();
    assert_eq!(e.json_path(), "output.transparent");
}

#[test]
fn error_accessors() {
    let e = parse_str(r#"{"output": {"msaa": 3}}"#).unwrap_err();
    assert_eq!(e.file(), Path::new("scenes/a.json"));
    assert_eq!(e.json_path(), "output.msaa");
    assert_eq!(e.reason(), "must be 1, 2, 4 or 8, got 3");
    let e = load(Path::new("/definitely/not/here.json")).unwrap_err();
    assert!(e
        .to_string()
        .starts_with("/definitely/not/here.json: (root): cannot read"));
}

#[test]
fn obj_meshes_and_mtl_materials() {
    let dir = std::env::temp_dir().join(format!("luz-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("quad.obj"),
        "mtllib quad.mtl\no first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         usemtl red\nf 1/1 2/2 3/3 4/4\no second\nusemtl shiny\nf 1 3 2\nusemtl nowhere\nf 1 4 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("quad.mtl"),
        "newmtl red\nKa 0.1 0.2 0.3\nKd 1 0 0\nnewmtl shiny\nKs 0.5 0.5 0.5\nNs 100\n",
    )
    .unwrap();
    let scene_path = dir.join("s.json");
    std::fs::write(
        &scene_path,
        r#"{"materials": {"m": {"model": "lambert"}}, "objects": [
            {"name": "q", "mesh": {"type": "obj", "path": "quad.obj"}},
            {"mesh": {"type": "obj", "path": "quad.obj"}, "material": "m"},
            {"mesh": {"type": "obj", "path": "quad.obj"}, "position": [1, 0, 0]}]}"#,
    )
    .unwrap();
    let s = load(&scene_path).unwrap();
    let names: Vec<&str> = s.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names[..3],
        ["q/first", "q/second", "q/second"],
        "one object per tobj model"
    );
    // Without MTL materials tobj only splits by group: the second OBJ object gives 2 parts.
    assert_eq!(s.objects.len(), 8);
    let mats: Vec<&str> = s.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        mats,
        ["m", "quad.obj/red", "quad.obj/shiny", "quad.obj/default"]
    );
    let Material::Phong(crate::brdf::PhongParams {
        ka,
        kd,
        ks,
        shininess,
        diffuse_color,
        specular_color,
        ..
    }) = s.materials[1].material
    else {
        panic!()
    };
    assert_eq!((ka, kd, ks), (0.3, 1.0, 1.0));
    assert_eq!((diffuse_color, specular_color), (Vec3::X, Vec3::ZERO));
    assert_eq!(shininess, 32.0);
    let Material::Phong(crate::brdf::PhongParams { shininess, .. }) = s.materials[2].material
    else {
        panic!()
    };
    assert_eq!(shininess, 100.0);
    // Objects 3..5 use the scene material; objects 5..8 reuse the MTL materials.
    assert!(s.objects[3..5].iter().all(|o| o.material == 0));
    assert_eq!(s.objects[5].material, 1);
    assert_eq!(s.objects[7].material, 3);
    // The quad was triangulated, has UVs (v flipped) and computed normals (+z).
    let first = &s.objects[0].mesh;
    assert_eq!(first.triangle_count(), 2);
    assert_eq!(first.uvs.len(), first.positions.len());
    assert!(first.uvs.contains(&glam::Vec2::new(0.0, 1.0)));
    assert!(first.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
    // The same OBJ is loaded once per material mode and shared.
    assert!(Arc::ptr_eq(&s.objects[0].mesh, &s.objects[5].mesh));

    // A missing MTL is an error when the scene gives no material…
    std::fs::remove_file(dir.join("quad.mtl")).unwrap();
    let e = load(&scene_path).unwrap_err().to_string();
    assert!(
        e.contains("objects[0].mesh.path: ")
            && e.contains("quad.mtl: cannot read the material library named by"),
        "{e}"
    );
    assert!(e.contains("quad.obj:1"), "{e}");
    // … and not read at all when it does.
    std::fs::write(
        &scene_path,
        r#"{"materials": {"m": {"model": "lambert"}}, "objects": [{"mesh": {"type": "obj", "path": "quad.obj"}, "material": "m"}]}"#,
    )
    .unwrap();
    assert_eq!(load(&scene_path).unwrap().objects.len(), 2);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A deterministic fuzzer: truncations and random edits of real scenes never panic, and every
/// error names the file.
#[test]
fn no_input_panics() {
    let classic = include_str!("../../../../assets/scenes/classic/09_depth_cue_on.json");
    let spot = r#"{"lights": [{"type": "spot", "position": [0, 1, 0], "target": [0, 0, 0], "umbra_deg": 30, "inner_deg": 10, "falloff": {"c1": 1, "c2": 0, "c3": 0}}],
        "materials": {"m": {"model": "lambert", "albedo": [0.5, 0.5, 0.5]}},
        "objects": [{"mesh": {"type": "plane", "size": [2, 2], "subdivisions": 3}, "material": "m", "scale": [1, 2, 3]},
                    {"mesh": {"type": "icosphere", "subdivisions": 2}, "material": "m"},
                    {"mesh": {"type": "cone", "segments": 7}, "material": "m", "shading": "flat"}]}"#;
    let check = |text: &str| {
        if let Err(e) = parse_str(text) {
            assert!(e.to_string().starts_with("scenes/a.json: "), "{e}");
        }
    };
    let pbr = r#"{"materials": {
        "a": {"model": "cook_torrance", "color": [0.5, 0.5, 0.5], "kd": 0.5, "roughness": 0.3, "preset": "gold", "fresnel": "conductor", "distribution": "ggx"},
        "b": {"model": "cook_torrance", "complex_ior": {"eta": [0.2, 0.4, 1.4], "k": [3.6, 2.5, 1.9]}, "geometry": "smith_ggx"},
        "c": {"model": "metal_rough", "base_color": [0.5, 0, 0], "metallic": 0.5, "roughness": 0.5, "diffuse_fresnel_weight": true},
        "d": {"model": "principled", "base_color": [0.8, 0.1, 0.1], "subsurface": 0.5, "sheen": 1, "clearcoat": 1, "clearcoat_gloss": 0.5},
        "e": {"model": "oren_nayar", "albedo": 0.5, "sigma_deg": 30}},
        "objects": [{"mesh": {"type": "sphere", "segments": 8, "rings": 4}, "material": "a"},
                    {"mesh": {"type": "cube"}, "material": "e"}]}"#;
    assert!(parse_str(pbr).is_ok());
    for text in [DEFAULT_SCENE_JSON, classic, spot, pbr] {
        for cut in (0..text.len()).filter(|&c| text.is_char_boundary(c)) {
            check(&text[..cut]);
        }
    }
    let tokens = [
        "",
        "-",
        "1e999",
        "-1e999",
        "1e39",
        "NaN",
        "[",
        "]",
        "{",
        "}",
        ",",
        ":",
        "\"",
        "0",
        "-1",
        "null",
        "true",
        "4096",
        "8",
        "9",
        "0.0",
        "\"x\"",
        "[0, 0, 0]",
        "[1]",
        "\\u12",
        "\"obj\"",
        "\"spot\"",
        "\"point\"",
        "\"directional\"",
        "99999999999999999999",
        "-0",
        "\u{1F600}",
        "\"conductor\"",
        "\"dielectric\"",
        "\"gold\"",
        "\"glass\"",
        "true",
        "1.5",
    ];
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let mut ok = 0;
    for _ in 0..6000 {
        let base = [DEFAULT_SCENE_JSON, classic, spot, pbr][next(4)];
        let mut text = base.to_string();
        for _ in 0..1 + next(3) {
            let mut at = next(text.len() + 1);
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            let mut end = (at + next(4)).min(text.len());
            while !text.is_char_boundary(end) {
                end += 1;
            }
            text.replace_range(at..end, tokens[next(tokens.len())]);
        }
        check(&text);
        ok += usize::from(parse_str(&text).is_ok());
    }
    assert!(
        ok > 0,
        "no mutation survived: the fuzzer only tests the JSON reader"
    );
}

#[test]
fn automatic_tessellation() {
    let scene = |objects: &str, output: &str| {
        parse_str(&format!(
            r#"{{"camera": {{"position": [0, 0, 10], "target": [0, 0, 0], "fov_y_deg": 90}},
                "output": {{"height": 720 {output}}},
                "materials": {{"m": {{"model": "lambert"}}}}, "objects": [{objects}]}}"#
        ))
    };
    let s = scene(
        r#"{"mesh": {"type": "sphere"}, "material": "m"},
           {"mesh": {"type": "sphere", "rings": 7}, "material": "m", "position": [0, 0, -90]},
           {"mesh": {"type": "cylinder", "radius": 0.5, "height": 1}, "material": "m", "scale": 2},
           {"mesh": {"type": "sphere", "segments": 12}, "material": "m"},
           {"mesh": {"type": "sphere"}, "material": "m", "position": [0, 0, 9.5]}"#,
        "",
    )
    .unwrap();
    let seg = |i: usize| match s.objects[i].desc {
        MeshDesc::Sphere {
            segments, rings, ..
        } => (segments, rings),
        MeshDesc::Cylinder { segments, .. } => (segments, 0),
        _ => unreachable!(),
    };
    // f = 360 px: the unit sphere 10 away is 36.2 px, 100 away 3.6 px.
    let near = crate::scene::tessellation::segments_for(360.0 / 99f32.sqrt(), 0.05);
    assert_eq!(seg(0), (near, near / 2));
    let far = seg(1);
    assert!(
        far.0 < near && far.1 == 7,
        "{far:?}: explicit rings are kept"
    );
    // The cylinder's bounding sphere (radius √2 after scaling by 2), not just its rim.
    let cyl = crate::scene::tessellation::segments_for(
        crate::scene::tessellation::projected_radius_px(&s.camera, 720, Vec3::ZERO, 2f32.sqrt()),
        0.05,
    );
    assert_eq!(seg(2).0, cyl);
    assert_eq!(seg(3), (12, 32), "given segments stay");
    assert_eq!(s.objects[3].tessellation, crate::scene::Tessellation::Given);
    assert_eq!(
        seg(4).0,
        crate::scene::tessellation::AUTO_MAX_SEGMENTS,
        "the camera is inside it"
    );
    let report = crate::scene::tessellation::report(&s);
    assert_eq!(report.len(), 4, "{report:?}");
    assert!(
        report[0].contains(&format!("{near} segments x {} rings", near / 2))
            && report[0].contains("36.2 px"),
        "{report:?}"
    );

    // A looser budget, fewer segments; the budget is checked.
    let loose = scene(
        r#"{"mesh": {"type": "sphere"}, "material": "m"}"#,
        r#", "tessellation_error_px": 1"#,
    )
    .unwrap();
    assert!(matches!(loose.objects[0].desc, MeshDesc::Sphere { segments, .. } if segments < near));
    for bad in ["-1", "-0.5", "0.00001", "1000", "1e999", "\"a\""] {
        let e = scene("", &format!(r#", "tessellation_error_px": {bad}"#)).unwrap_err();
        assert!(
            e.to_string().contains("output.tessellation_error_px"),
            "{bad}: {e}"
        );
    }
}

#[test]
fn scene_triangle_limit() {
    // Three distinct 4096 x 2049 spheres: 50 million triangles from 300 bytes.
    let sphere = |r: f32| {
        format!(
            r#"{{"mesh": {{"type": "sphere", "radius": {r}, "segments": 4096, "rings": 2049}}, "material": "m"}}"#
        )
    };
    let text = format!(
        r#"{{"materials": {{"m": {{"model": "lambert"}}}}, "objects": [{}, {}, {}]}}"#,
        sphere(1.0),
        sphere(2.0),
        sphere(3.0)
    );
    let e = parse_str(&text).unwrap_err().to_string();
    assert!(
        e.contains("objects[2].mesh: the scene's built-in meshes would have 50331648 triangles"),
        "{e}"
    );
    // Equal meshes are shared, so they count once.
    let text = format!(
        r#"{{"materials": {{"m": {{"model": "lambert"}}}}, "objects": [{}, {}, {}]}}"#,
        sphere(1.0),
        sphere(1.0),
        sphere(1.0)
    );
    assert_eq!(parse_str(&text).unwrap().objects.len(), 3);
}
