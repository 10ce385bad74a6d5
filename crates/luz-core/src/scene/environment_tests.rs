//! Unit tests of the `environment` block.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::*;

fn parse_env(env: &str) -> Result<Option<Environment>, SceneError> {
    parse(
        &format!(r#"{{"environment": {env}}}"#),
        Path::new("scenes/a.json"),
    )
    .map(|s| s.environment)
}

fn env_ok(env: &str) -> Environment {
    match parse_env(env) {
        Ok(Some(e)) => e,
        Ok(None) => panic!("no environment for {env}"),
        Err(e) => panic!("{env}: {e}"),
    }
}

fn env_err(env: &str, expected: &str) {
    match parse_env(env) {
        Ok(_) => panic!("expected an error for {env}"),
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with("scenes/a.json: "), "{msg}");
            assert!(
                msg.contains(expected),
                "{msg:?} does not contain {expected:?}"
            );
        }
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("luz-scene-env-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn no_environment_by_default() {
    let s = parse("{}", Path::new("a.json")).unwrap();
    assert!(s.environment.is_none());
    assert!(parse_env("null").unwrap().is_none());
}

#[test]
fn sources_and_defaults() {
    let e = env_ok(r#"{"procedural": "studio"}"#);
    assert_eq!(e, Environment::new(EnvSource::Studio));
    assert_eq!(e.intensity, 1.0);
    assert_eq!(e.rotation_deg, 0.0);
    assert_eq!(e.specular_method, SpecularMethod::FittedLobes);
    assert_eq!(e.samples, 64);
    assert_eq!(e.diffuse_method, DiffuseMethod::Sh9);
    assert!(!e.energy_compensation && e.mip_filtered_samples && e.show_background);

    assert_eq!(
        env_ok(r#"{"uniform": 0.5}"#).source,
        EnvSource::Uniform(Vec3::splat(0.5))
    );
    assert_eq!(
        env_ok(r#"{"uniform": [1, 2, 3]}"#).source,
        EnvSource::Uniform(Vec3::new(1.0, 2.0, 3.0))
    );
    match env_ok(r#"{"procedural": "sky"}"#).source {
        EnvSource::Sky {
            sun_direction,
            sun_intensity,
        } => {
            assert!((sun_direction - DEFAULT_SUN_DIRECTION.normalize()).length() < 1e-6);
            assert_eq!(sun_intensity, DEFAULT_SUN_INTENSITY);
        }
        s => panic!("{s:?}"),
    }
    let e = env_ok(
        r#"{"procedural": "sky", "sun_direction": [0, -2, 0], "sun_intensity": 10,
            "intensity": 0.5, "rotation_deg": -45, "specular_method": "importance",
            "samples": 256, "diffuse_method": "cubemap", "energy_compensation": true,
            "mip_filtered_samples": false, "show_background": false}"#,
    );
    assert_eq!(
        e.source,
        EnvSource::Sky {
            sun_direction: Vec3::NEG_Y,
            sun_intensity: 10.0
        }
    );
    assert_eq!((e.intensity, e.rotation_deg, e.samples), (0.5, -45.0, 256));
    assert_eq!(e.specular_method, SpecularMethod::Importance);
    assert_eq!(e.diffuse_method, DiffuseMethod::Cubemap);
    assert!(e.energy_compensation && !e.mip_filtered_samples && !e.show_background);
    assert_eq!(e.source.kind_name(), "sky");
    assert_eq!(SpecularMethod::SplitSum.name(), "split_sum");
    assert_eq!(DiffuseMethod::Sh9.name(), "sh9");
}

#[test]
fn hdr_paths_resolve_against_the_scene_file() {
    let dir = scratch("hdr");
    std::fs::create_dir_all(dir.join("envs")).unwrap();
    std::fs::create_dir_all(dir.join("scenes")).unwrap();
    std::fs::write(
        dir.join("envs/a.hdr"),
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n",
    )
    .unwrap();
    std::fs::write(dir.join("envs/b.EXR"), [0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0]).unwrap();
    std::fs::write(dir.join("envs/fake.hdr"), b"P3\n1 1\n255\n").unwrap();
    std::fs::create_dir_all(dir.join("envs/folder.hdr")).unwrap();
    let scene = dir.join("scenes/s.json");
    let load =
        |env: &str| parse(&format!(r#"{{"environment": {env}}}"#), &scene).map(|s| s.environment);
    match load(r#"{"hdr": "../envs/a.hdr", "intensity": 2}"#) {
        Ok(Some(Environment {
            source: EnvSource::Hdr(p),
            intensity,
            ..
        })) => {
            assert_eq!(p, dir.join("scenes/../envs/a.hdr"));
            assert_eq!(intensity, 2.0);
        }
        other => panic!("{other:?}"),
    }
    assert!(load(r#"{"hdr": "../envs/b.EXR"}"#).is_ok());
    let err = |env: &str| load(env).unwrap_err().to_string();
    let e = err(r#"{"hdr": "../envs/missing.hdr"}"#);
    assert!(
        e.contains("environment.hdr: ") && e.contains("missing.hdr: no such file"),
        "{e}"
    );
    let e = err(r#"{"hdr": "../envs/fake.hdr"}"#);
    assert!(e.contains("fake.hdr: not a Radiance HDR file"), "{e}");
    let e = err(r#"{"hdr": "../envs/folder.hdr"}"#);
    assert!(e.contains("folder.hdr: is a directory"), "{e}");
    let e = err(r#"{"hdr": "../envs/a.png"}"#);
    assert!(e.contains("a.png: unsupported environment image"), "{e}");
    let e = err(r#"{"hdr": " "}"#);
    assert!(e.contains("environment.hdr: must not be empty"), "{e}");
    let e = err(r#"{"hdr": 3}"#);
    assert!(e.contains("environment.hdr: expected a string"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn errors_name_the_path() {
    env_err("{}", "environment: an environment needs exactly one source");
    env_err(
        r#"{"intensity": 2}"#,
        "environment: an environment needs exactly one source",
    );
    env_err(
        r#"{"hrd": "x.hdr"}"#,
        r#"environment.hrd: unknown field "hrd" for an environment"#,
    );
    env_err(r#"{"hrd": "x.hdr"}"#, r#"(did you mean "hdr"?)"#);
    env_err(
        r#"{"uniform": 1, "procedural": "sky"}"#,
        r#"environment.procedural: "uniform" and "procedural" both give the environment's source"#,
    );
    env_err(
        r#"{"procedural": "skye"}"#,
        r#"environment.procedural: unknown value "skye"; expected one of "sky", "studio" (did you mean "sky"?)"#,
    );
    env_err(
        r#"{"procedural": "studio", "sun_intensity": 2}"#,
        r#"environment.sun_intensity: "sun_intensity" only applies to the procedural sky"#,
    );
    env_err(
        r#"{"uniform": 1, "sun_direction": [0, -1, 0]}"#,
        r#"environment.sun_direction: "sun_direction" only applies to the procedural sky"#,
    );
    env_err(
        r#"{"procedural": "sky", "sun_direction": [0, 1, 0]}"#,
        "environment.sun_direction: the sun would be below the horizon",
    );
    env_err(
        r#"{"procedural": "sky", "sun_direction": [0, 0, 0]}"#,
        "environment.sun_direction: must not be a zero-length vector",
    );
    env_err(
        r#"{"procedural": "sky", "sun_intensity": 51}"#,
        "environment.sun_intensity: must be in [0, 50], got 51",
    );
    env_err(
        r#"{"uniform": [1, -1, 1]}"#,
        "environment.uniform[1]: must be ≥ 0, got -1",
    );
    env_err(
        r#"{"uniform": 1, "intensity": -1}"#,
        "environment.intensity: must be ≥ 0, got -1",
    );
    env_err(
        r#"{"uniform": 1, "samples": 0}"#,
        "environment.samples: must be in [1, 1024], got 0",
    );
    env_err(
        r#"{"uniform": 1, "samples": 1025}"#,
        "environment.samples: must be in [1, 1024], got 1025",
    );
    env_err(
        r#"{"uniform": 1, "specular_method": "splitsum"}"#,
        r#"environment.specular_method: unknown value "splitsum"; expected one of "importance", "split_sum", "fitted_lobes" (did you mean "split_sum"?)"#,
    );
    env_err(
        r#"{"uniform": 1, "diffuse_method": "sh"}"#,
        r#"environment.diffuse_method: unknown value "sh""#,
    );
    env_err(
        r#"{"uniform": 1, "show_background": 1}"#,
        "environment.show_background: expected true or false, got a number",
    );
    env_err(
        r#"{"uniform": 1, "rotation_deg": 1e999}"#,
        "environment.rotation_deg: must be a finite number",
    );
    env_err("[1, 2]", "environment: expected an object");
}
