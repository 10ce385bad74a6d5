//! Area lights in the scene format (issue 36): decoding, the encoder's round trip and the errors.

use super::*;

fn parse_lights(lights: &str) -> Result<Scene, SceneError> {
    parse(
        &format!(r#"{{"lights": [{lights}]}}"#),
        Path::new("scenes/a.json"),
    )
}

fn area(light: &str) -> AreaLight {
    let s = parse_lights(light).unwrap_or_else(|e| panic!("{light}: {e}"));
    assert!(s.lights.is_empty(), "{light}: read as a punctual light");
    assert_eq!(s.area_lights.len(), 1, "{light}");
    s.area_lights[0]
}

/// Every shape with its defaults, and every field given.
#[test]
fn area_lights_decode() {
    let r = area(
        r#"{"type": "rect", "position": [0, 2, 0], "direction": [0, -2, 0], "up": [0, 0, 3], "size": [1, 0.5]}"#,
    );
    assert_eq!(
        r.shape,
        AreaShape::Rect {
            up: Vec3::Z,
            width: 1.0,
            height: 0.5
        }
    );
    assert_eq!(
        (r.position, r.direction, r.color, r.intensity),
        (Vec3::new(0.0, 2.0, 0.0), Vec3::NEG_Y, Vec3::ONE, 1.0)
    );
    assert_eq!(
        (r.two_sided, r.visible, r.method, r.range, r.shadow),
        (false, true, AreaMethod::Ltc, None, None)
    );
    let d = area(
        r#"{"type": "disk", "position": [1, 2, 3], "direction": [1, 0, 0], "radius": 0.25, "two_sided": true,
            "visible": false, "color": [1, 0.5, 0.25], "intensity": 4, "method": "sampled", "samples": 64,
            "range": 10, "shadow": true}"#,
    );
    assert_eq!(d.shape, AreaShape::Disk { radius: 0.25 });
    assert_eq!(d.radiance(), Vec3::new(4.0, 2.0, 1.0));
    assert_eq!(
        (d.two_sided, d.visible, d.method, d.range),
        (true, false, AreaMethod::Sampled { samples: 64 }, Some(10.0))
    );
    assert_eq!(d.shadow, Some(Shadow::default_for(LightKind::Point)));
    let s = area(
        r#"{"type": "sphere", "position": [0, 1, 0], "radius": 0.5, "method": "representative_point"}"#,
    );
    assert_eq!(
        (s.shape, s.method),
        (
            AreaShape::Sphere { radius: 0.5 },
            AreaMethod::RepresentativePoint
        )
    );
    let t = area(
        r#"{"type": "tube", "position": [0, 1, 0], "direction": [0, 0, -1], "length": 2, "radius": 0.1}"#,
    );
    assert_eq!(
        (t.shape, t.direction),
        (
            AreaShape::Tube {
                length: 2.0,
                radius: 0.1
            },
            Vec3::NEG_Z
        )
    );
    // Sampled without a count: the default.
    let d = area(
        r#"{"type": "disk", "position": [0, 1, 0], "direction": [0, -1, 0], "radius": 1, "method": "sampled"}"#,
    );
    assert_eq!(
        d.method,
        AreaMethod::Sampled {
            samples: area::DEFAULT_AREA_SAMPLES
        }
    );
    // Punctual and area lights side by side; the scene warns where the GPU shades a light
    // otherwise than asked (a disk by representative point), and not for a tube by LTC (its
    // facing ribbon).
    let both = parse_lights(
        r#"{"type": "point", "position": [0, 1, 0]}, {"type": "tube", "position": [0, 1, 0], "direction": [1, 0, 0], "length": 1, "radius": 0.1}, {"type": "disk", "position": [0, 1, 0], "direction": [0, -1, 0], "radius": 0.1, "method": "representative_point"}"#,
    )
    .unwrap();
    assert_eq!((both.lights.len(), both.area_lights.len()), (1, 2));
    assert_eq!(
        both.warnings
            .iter()
            .filter(|w| w.contains("area light"))
            .collect::<Vec<_>>(),
        [
            "lights: area light 1 (disk): representative point is for spheres and tubes; the GPU \
          shades this one by LTC"
        ],
    );
}

/// Every shape and every field goes through the encoder and back unchanged (directions that are
/// not unit vectors in the file too).
#[test]
fn area_lights_round_trip() {
    let text = r#"{"lights": [
        {"type": "point", "position": [0, 1, 0]},
        {"type": "rect", "position": [0.1, 2.3, -0.7], "direction": [0.3, -1, 0.2], "up": [0.7, 0.1, 1],
         "size": [1.7, 0.3], "two_sided": true, "color": [1, 0.9, 0.8], "intensity": 12.5, "range": 7.5,
         "shadow": {"method": "pcss", "resolution": 512}},
        {"type": "disk", "position": [1, 2, 3], "direction": [0, -1, 0.1], "radius": 0.35, "visible": false,
         "method": "sampled", "samples": 1024},
        {"type": "sphere", "position": [-1, 0.5, 2], "radius": 0.05, "method": "representative_point", "shadow": false},
        {"type": "tube", "position": [0, 3, 0], "direction": [1, 0.2, 0.1], "length": 1.25, "radius": 0.02}
    ]}"#;
    let a = parse(text, Path::new("scenes/a.json")).unwrap();
    assert_eq!(a.area_lights.len(), 4);
    let json = to_json(&a);
    let back = parse(
        &serde_json::to_string(&json).unwrap(),
        Path::new("scenes/a.json"),
    )
    .unwrap();
    assert_eq!(back.lights, a.lights);
    assert_eq!(back.area_lights, a.area_lights);
    // And the text is a fixed point.
    assert_eq!(to_json(&back), json);
}

/// Bad input is an error that names the file and the field, never a panic.
#[test]
fn area_light_errors() {
    let cases = [
        // size ≤ 0, and its shape.
        (
            r#"{"type": "rect", "position": [0, 1, 0], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [1, 0]}"#,
            "lights[0].size[1]: must be > 0, got 0",
        ),
        (
            r#"{"type": "rect", "position": [0, 1, 0], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [-2, 1]}"#,
            "lights[0].size[0]: must be > 0, got -2",
        ),
        (
            r#"{"type": "rect", "position": [0, 1, 0], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [1]}"#,
            "lights[0].size: expected [width, height], got 1 numbers",
        ),
        (
            r#"{"type": "rect", "position": [0, 1, 0], "direction": [0, -1, 0], "up": [0, 0, 1]}"#,
            "lights[0].size: missing required field",
        ),
        // Zero direction.
        (
            r#"{"type": "disk", "position": [0, 1, 0], "direction": [0, 0, 0], "radius": 1}"#,
            "lights[0].direction: must not be a zero-length vector",
        ),
        (
            r#"{"type": "tube", "position": [0, 1, 0], "length": 1, "radius": 1}"#,
            "lights[0].direction: missing required field",
        ),
        // up parallel to direction (and opposite), and zero.
        (
            r#"{"type": "rect", "position": [0, 1, 0], "direction": [0, -1, 0], "up": [0, 2, 0], "size": [1, 1]}"#,
            "lights[0].up: must not be parallel to \"direction\"",
        ),
        (
            r#"{"type": "rect", "position": [0, 1, 0], "direction": [0, -1, 0], "up": [0, 0, 0], "size": [1, 1]}"#,
            "lights[0].up: must not be a zero-length vector",
        ),
        // A radius with rect; a size with a disk; two_sided with a sphere.
        (
            r#"{"type": "rect", "position": [0, 1, 0], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [1, 1], "radius": 1}"#,
            "lights[0].radius: unknown field \"radius\" for a rect light",
        ),
        (
            r#"{"type": "disk", "position": [0, 1, 0], "direction": [0, -1, 0], "radius": 1, "size": [1, 1]}"#,
            "lights[0].size: unknown field \"size\" for a disk light",
        ),
        (
            r#"{"type": "sphere", "position": [0, 1, 0], "radius": 1, "two_sided": true}"#,
            "lights[0].two_sided: unknown field \"two_sided\" for a sphere light",
        ),
        // Radii and lengths.
        (
            r#"{"type": "sphere", "position": [0, 1, 0], "radius": 0}"#,
            "lights[0].radius: must be > 0, got 0",
        ),
        (
            r#"{"type": "sphere", "position": [0, 1, 0]}"#,
            "lights[0].radius: missing required field",
        ),
        (
            r#"{"type": "tube", "position": [0, 1, 0], "direction": [1, 0, 0], "length": -1, "radius": 0.1}"#,
            "lights[0].length: must be > 0, got -1",
        ),
        // Not a finite number (JSON has no NaN; a number too large for an f32 is the way in).
        (
            r#"{"type": "disk", "position": [0, 1, 0], "direction": [0, -1, 0], "radius": 1e39}"#,
            "lights[0].radius: must be a finite number, got 1e39",
        ),
        (
            r#"{"type": "rect", "position": [0, 1, 0], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [1, 1e400]}"#,
            "lights[0].size[1]: must be a finite number, got 1e400",
        ),
        (
            r#"{"type": "sphere", "position": [0, 1e999, 0], "radius": 1}"#,
            "lights[0].position",
        ),
        (
            r#"{"type": "sphere", "position": [0, 1, 0], "radius": "1"}"#,
            "lights[0].radius: expected a number, got a string",
        ),
        // Methods and samples.
        (
            r#"{"type": "sphere", "position": [0, 1, 0], "radius": 1, "method": "ltcs"}"#,
            "lights[0].method",
        ),
        (
            r#"{"type": "sphere", "position": [0, 1, 0], "radius": 1, "method": "sampled", "samples": 0}"#,
            "lights[0].samples: must be in [1, 1024], got 0",
        ),
        (
            r#"{"type": "sphere", "position": [0, 1, 0], "radius": 1, "samples": 8}"#,
            "lights[0].samples: only the \"sampled\" method takes samples",
        ),
        (
            r#"{"type": "disk", "position": [0, 1, 0], "direction": [0, -1, 0], "radius": 1, "range": 0}"#,
            "lights[0].range: must be > 0, got 0",
        ),
        (
            r#"{"type": "disk", "position": [0, 1, 0], "direction": [0, -1, 0], "radius": 1, "intensity": -1}"#,
            "lights[0].intensity: must be ≥ 0, got -1",
        ),
        // An unknown type lists the area types too.
        (
            r#"{"type": "rectangle", "position": [0, 1, 0]}"#,
            "lights[0].type",
        ),
    ];
    for (light, expected) in cases {
        let e = match parse_lights(light) {
            Ok(_) => panic!("expected an error for {light}"),
            Err(e) => e.to_string(),
        };
        assert!(
            e.starts_with("scenes/a.json: "),
            "message does not start with the file: {e}"
        );
        assert!(e.contains(expected), "{e:?} does not contain {expected:?}");
    }
    let e = parse_lights(r#"{"type": "rectangle", "position": [0, 1, 0]}"#)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("\"rect\""), "{e}");
}
