//! `luz brdf`: runs the binary and checks its values against the CPU reference, the `--stdin`
//! protocol, error handling and the `--plot` files. No GPU needed. The plot test needs the chart
//! font (Debian package fonts-dejavu-core, or $LUZ_FONT).

mod common;

use glam::Vec3;
use luz::brdf;
use serde_json::Value;

use common::{luz_command, run, run_with_stdin, scratch, Ran};

/// `luz brdf <args>`, with `stdin` as its standard input when given.
fn brdf(args: &[&str], stdin: Option<&str>) -> Ran {
    let mut cmd = luz_command(["brdf"]);
    cmd.args(args);
    match stdin {
        Some(text) => run_with_stdin(&mut cmd, text),
        None => run(&mut cmd),
    }
}

fn assert_ok(o: &Ran) {
    assert!(
        o.status.success(),
        "exit {:?}\nstdout: {}\nstderr: {}",
        o.status,
        o.stdout,
        o.stderr
    );
}

fn no_panic(o: &Ran) {
    let e = &o.stderr;
    assert!(!e.contains("panicked"), "panic: {e}");
    assert!(o.status.code().is_some(), "killed by a signal: {e}");
}

/// The value of `key=` in the text line, as numbers.
fn text_field(line: &str, key: &str) -> Vec<f32> {
    let prefix = format!("{key}=");
    let v = line
        .split_whitespace()
        .find_map(|w| w.strip_prefix(prefix.as_str()))
        .unwrap_or_else(|| panic!("no {key}= in {line}"));
    v.split(',').map(|x| x.parse().unwrap()).collect()
}

fn json_vec3(v: &Value) -> Vec3 {
    let a = v.as_array().expect("array");
    Vec3::new(
        a[0].as_f64().unwrap() as f32,
        a[1].as_f64().unwrap() as f32,
        a[2].as_f64().unwrap() as f32,
    )
}

#[test]
fn lambert_is_albedo_over_pi() {
    let albedo = Vec3::new(0.5, 0.25, 1.0);
    let mat = r#"{"model":"lambert","albedo":[0.5,0.25,1.0]}"#;
    let expected = albedo / std::f32::consts::PI;

    let o = brdf(
        &[
            "--material",
            mat,
            "--theta-l",
            "20",
            "--theta-v",
            "50",
            "--phi-v",
            "30",
        ],
        None,
    );
    assert_ok(&o);
    let out = &o.stdout;
    assert_eq!(out.lines().count(), 1, "{out}");
    let f = text_field(out, "f");
    for k in 0..3 {
        assert!(
            (f[k] - expected[k]).abs() < 1e-6,
            "f = {f:?}, expected {expected}"
        );
    }
    assert_eq!(text_field(out, "specular"), vec![0.0, 0.0, 0.0]);
    assert!((text_field(out, "n_l")[0] - 20f32.to_radians().cos()).abs() < 1e-6);
    assert!((text_field(out, "n_v")[0] - 50f32.to_radians().cos()).abs() < 1e-6);

    // The same through --model/--set, vectors and --json.
    let o = brdf(
        &[
            "--model",
            "lambert",
            "--set",
            "albedo=0.5,0.25,1",
            "--l",
            "1,0,1",
            "--v",
            "0,-1,2",
            "--json",
        ],
        None,
    );
    assert_ok(&o);
    let j: Value = serde_json::from_str(o.stdout.trim()).unwrap();
    assert_eq!(j["model"], "lambert");
    let f = json_vec3(&j["f"]);
    assert!(
        (f - expected).abs().max_element() < 1e-6,
        "{f} vs {expected}"
    );
    assert!((j["n_l"].as_f64().unwrap() - 0.5f64.sqrt()).abs() < 1e-6);
}

#[test]
fn metal_rough_mirror_matches_d_g_f() {
    let base = Vec3::new(1.0, 0.8, 0.3);
    let roughness = 0.3f32;
    let mat = r#"{"model":"metal_rough","base_color":[1,0.8,0.3],"roughness":0.3}"#;
    let o = brdf(
        &[
            "--material",
            mat,
            "--theta-l",
            "30",
            "--theta-v",
            "30",
            "--json",
        ],
        None,
    );
    assert_ok(&o);
    let j: Value = serde_json::from_str(o.stdout.trim()).unwrap();

    // Mirror configuration: h = n, v·h = n·l = n·v = cos 30°; metallic 1 (default): no diffuse.
    let c = 30f32.to_radians().cos();
    let a = roughness * roughness;
    let d = brdf::d_ggx(1.0, a);
    let g = brdf::g_smith_ggx_correlated(c, c, a);
    let f = brdf::f_schlick(base, c);
    let expected = f * (d * g / (4.0 * c * c));

    let got = json_vec3(&j["f"]);
    let rel = ((got - expected).abs() / expected).max_element();
    assert!(
        rel < 1e-5,
        "f = {got}, expected D G F / (4 n·l n·v) = {expected} (rel {rel})"
    );
    let rel_d = (j["D"].as_f64().unwrap() as f32 - d).abs() / d;
    assert!(rel_d < 1e-5, "D = {}, expected {d}", j["D"]);
    assert!(
        (j["G"].as_f64().unwrap() as f32 - g).abs() < 1e-6,
        "G = {}, expected {g}",
        j["G"]
    );
    assert!((json_vec3(&j["F"]) - f).abs().max_element() < 1e-6);
    assert_eq!(json_vec3(&j["diffuse"]), Vec3::ZERO);
    assert!((j["n_h"].as_f64().unwrap() - 1.0).abs() < 1e-6);
    assert!((j["v_h"].as_f64().unwrap() as f32 - c).abs() < 1e-6);
    assert_eq!(j["material"]["roughness"], 0.3);
    assert_eq!(j["material"]["distribution"], "ggx");
}

/// Issue 34: `--material` takes the scene file's KHR_materials_clearcoat object. At normal
/// incidence (h = n, every cosine 1, G = 1) a coat of weight 1 and roughness 0.1 over a white
/// dielectric of roughness 0.5 gives `(1 − 0.04) · (1/π + 0.04 D(0.25)/4) + 0.04 D(0.01)/4`.
#[test]
fn clearcoat_material_from_the_scene_syntax() {
    let mat = r#"{"model":"metal_rough","metallic":0,"roughness":0.5,
        "clearcoat":{"clearcoatFactor":1,"clearcoatRoughnessFactor":0.1}}"#;
    let o = brdf(
        &["--material", mat, "--theta-l", "0", "--theta-v", "0"],
        None,
    );
    assert_ok(&o);
    let f = text_field(o.stdout.trim(), "f");
    let base = 1.0 / std::f32::consts::PI + 0.04 * brdf::d_ggx(1.0, 0.25) / 4.0;
    let want = 0.96 * base + 0.04 * brdf::d_ggx(1.0, 0.01) / 4.0;
    for c in f {
        assert!((c - want).abs() <= 1e-5 * want, "{c} against {want}");
    }
}

/// Issue 34: `--material` takes the scene file's KHR_materials_sheen object. At normal
/// incidence (h = n) the Charlie distribution is 0, so a white sheen of roughness 1 over a white
/// dielectric of roughness 0.5 only scales the base by `1 − E_sheen(1)`, the sheen lobe's albedo
/// at normal view (the fit, within 0.012 of the integral as brdf's sheen_albedo_fit_is_the_integral
/// asserts).
#[test]
fn sheen_material_from_the_scene_syntax() {
    let mat = r#"{"model":"metal_rough","metallic":0,"roughness":0.5,
        "sheen":{"sheenColorFactor":[1,1,1],"sheenRoughnessFactor":1}}"#;
    let o = brdf(
        &["--material", mat, "--theta-l", "0", "--theta-v", "0"],
        None,
    );
    assert_ok(&o);
    let f = text_field(o.stdout.trim(), "f");
    let e = brdf::sheen_albedo(1.0, 1.0);
    assert!(
        (e - brdf::sheen_albedo_integrated(1.0, 1.0)).abs() < 0.012,
        "{e}"
    );
    assert!(e > 0.1, "{e}");
    let base = 1.0 / std::f32::consts::PI + 0.04 * brdf::d_ggx(1.0, 0.25) / 4.0;
    let want = (1.0 - e) * base;
    for c in f {
        assert!((c - want).abs() <= 1e-5 * want, "{c} against {want}");
    }
}

/// Issue 34: `--material` takes KHR_materials_ior's and KHR_materials_specular's fields as the
/// scene file does: at normal incidence F = F0 = ((ior − 1)/(ior + 1))² · specularFactor.
#[test]
fn ior_and_specular_from_the_scene_syntax() {
    for (extra, f0) in [
        (r#""ior":1.33"#, (0.33f32 / 2.33).powi(2)),
        (
            r#""ior":{"ior":2},"specular":{"specularFactor":0.5}"#,
            0.5 / 9.0,
        ),
    ] {
        let mat = format!(r#"{{"model":"metal_rough","metallic":0,"roughness":0.5,{extra}}}"#);
        let o = brdf(
            &["--material", &mat, "--theta-l", "0", "--theta-v", "0"],
            None,
        );
        assert_ok(&o);
        for c in text_field(o.stdout.trim(), "F") {
            assert!((c - f0).abs() <= 1e-6, "{extra}: F {c} against {f0}");
        }
    }
}

#[test]
fn stdin_three_lines_give_three_json_lines() {
    let input = concat!(
        r#"{"material":{"model":"lambert"},"theta_l":0,"theta_v":45}"#,
        "\n",
        r#"{"material":{"model":"metal_rough","roughness":0.5},"l":[0.5,0,0.866],"v":[-0.5,0,0.866]}"#,
        "\n\n",
        r#"{"material":{"model":"principled","anisotropic":0.5},"theta_l":40,"phi_l":20,"theta_v":60,"phi_v":250}"#,
        "\n",
    );
    let o = brdf(&["--stdin"], Some(input));
    assert_ok(&o);
    let out = &o.stdout;
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    let models = ["lambert", "metal_rough", "principled"];
    for (line, model) in lines.iter().zip(models) {
        let j: Value = serde_json::from_str(line).unwrap();
        assert_eq!(j["model"], model);
        let f = json_vec3(&j["f"]);
        assert!(
            f.is_finite() && f.min_element() >= 0.0 && f.max_element() > 0.0,
            "{line}"
        );
    }
    let j: Value = serde_json::from_str(lines[0]).unwrap();
    assert!((json_vec3(&j["f"]).x - 0.8 / std::f32::consts::PI).abs() < 1e-6);

    // The command-line material is the default for lines without one.
    let o = brdf(
        &["--stdin", "--model", "lambert"],
        Some("{\"l\":[0,0,1],\"v\":[0,0,1]}\n"),
    );
    assert_ok(&o);
    assert_eq!(o.stdout.lines().count(), 1);
}

#[test]
fn stdin_bad_line_reports_line_number_and_continues() {
    let input = concat!(
        r#"{"material":{"model":"lambert"},"theta_l":0,"theta_v":0}"#,
        "\n",
        r#"{"material":{"model":"metal_rough","roughness":"rough"},"theta_l":0,"theta_v":0}"#,
        "\n",
        "not json\n",
        r#"{"material":{"model":"lambert"},"l":[0,0,1],"v":[0,0,1]}"#,
        "\n",
    );
    let o = brdf(&["--stdin"], Some(input));
    no_panic(&o);
    assert_eq!(o.status.code(), Some(1), "{}", o.stderr);
    let out = &o.stdout;
    let lines: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 4, "{out}");
    assert_eq!(lines[0]["model"], "lambert");
    assert_eq!(lines[1]["line"], 2);
    assert!(
        lines[1]["error"].as_str().unwrap().contains("roughness"),
        "{}",
        lines[1]
    );
    assert_eq!(lines[2]["line"], 3);
    assert_eq!(lines[3]["model"], "lambert");
    assert!(o.stderr.contains("line 2"), "{}", o.stderr);
}

#[test]
fn bad_material_is_a_clear_error() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["--material", r#"{"model":"metal_rough","roughness":"a"}"#],
            "roughness",
        ),
        (
            &["--material", r#"{"model":"metal_rough","roughnes":0.3}"#],
            "roughnes",
        ),
        (&["--material", r#"{"model":"metal_rough""#], "JSON"),
        (&["--material", r#"{"model":"gold"}"#], "unknown model"),
        (&["--material", r#"{"roughness":0.3}"#], "model"),
        (
            &["--model", "metal_rough", "--set", "distribution=ggz"],
            "distribution",
        ),
    ];
    for (args, needle) in cases {
        let mut all = args.to_vec();
        all.extend(["--theta-l", "0", "--theta-v", "0"]);
        let o = brdf(&all, None);
        no_panic(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", o.stderr);
        assert!(o.stdout.is_empty(), "{args:?}: {}", o.stdout);
        let e = &o.stderr;
        assert!(e.contains("error") && e.contains(needle), "{args:?}: {e}");
    }
    // Missing directions and nothing to do are errors too.
    for args in [
        &["--model", "lambert", "--theta-l", "10"][..],
        &["--model", "lambert"][..],
    ] {
        let o = brdf(args, None);
        no_panic(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", o.stderr);
    }
}

#[test]
fn plot_writes_decodable_non_blank_pngs() {
    let tmp = scratch("plot");
    let dir = tmp.join("plot");
    let dir_s = dir.to_str().unwrap();
    let o = brdf(
        &[
            "--model",
            "metal_rough",
            "--set",
            "metallic=0",
            "--set",
            "base_color=0.8,0.5,0.2",
            "--plot",
            dir_s,
            "--sweep",
            "roughness=0.1,0.5,1",
            "--samples",
            "512",
        ],
        None,
    );
    assert_ok(&o);
    let out = &o.stdout;
    let printed: Vec<&str> = out.lines().map(str::trim).collect();
    for stem in ["lobe_polar", "slice_thetah_thetad", "albedo"] {
        let png = dir.join(format!("{stem}.png"));
        let svg = dir.join(format!("{stem}.svg"));
        assert!(
            printed.contains(&png.to_str().unwrap()),
            "{png:?} not printed: {printed:?}"
        );
        assert!(
            printed.contains(&svg.to_str().unwrap()),
            "{svg:?} not printed: {printed:?}"
        );
        let img = image::open(&png)
            .unwrap_or_else(|e| panic!("{png:?}: {e}"))
            .to_rgb8();
        assert_eq!(
            img.dimensions(),
            (800, 600),
            "{png:?}: the documented default size"
        );
        let total = img.pixels().count();
        let non_white = img.pixels().filter(|p| p.0 != [255, 255, 255]).count();
        assert!(
            non_white * 50 > total,
            "{png:?} is nearly blank: {non_white} of {total} pixels"
        );
        let mut colours: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
        colours.sort_unstable();
        colours.dedup();
        assert!(
            colours.len() > 20,
            "{png:?}: only {} colours",
            colours.len()
        );
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("<svg") && text.contains("</svg>"), "{svg:?}");
    }

    // --plot-size is honoured; a bad sweep key fails before anything is written.
    let dir2 = tmp.join("plot_small");
    let o = brdf(
        &[
            "--model",
            "lambert",
            "--plot",
            dir2.to_str().unwrap(),
            "--plot-size",
            "320x240",
        ],
        None,
    );
    assert_ok(&o);
    let img = image::open(dir2.join("albedo.png")).unwrap();
    assert_eq!((img.width(), img.height()), (320, 240));
    let dir3 = tmp.join("plot_bad");
    let o = brdf(
        &[
            "--model",
            "lambert",
            "--plot",
            dir3.to_str().unwrap(),
            "--sweep",
            "roughness=0,1",
        ],
        None,
    );
    no_panic(&o);
    assert_eq!(o.status.code(), Some(1));
    assert!(o.stderr.contains("roughness"), "{}", o.stderr);
    assert!(!dir3.exists());
}

/// Issue 34: `--material` takes the scene file's KHR_materials_anisotropy object. At normal
/// incidence (h = n, G = 1) a white metal's value is `1/(4π α_t α_b)` with `α_t = mix(α, 1, s²)`;
/// turning the lobe by π/2 is the same as turning the light and view by π/2 the other way.
#[test]
fn anisotropy_material_from_the_scene_syntax() {
    let mat = |rotation: f32| {
        format!(
            r#"{{"model":"metal_rough","metallic":1,"base_color":[1,1,1],"roughness":0.5,
            "anisotropy":{{"anisotropyStrength":0.8,"anisotropyRotation":{rotation}}}}}"#
        )
    };
    let o = brdf(
        &["--material", &mat(0.0), "--theta-l", "0", "--theta-v", "0"],
        None,
    );
    assert_ok(&o);
    let (a, at) = (0.25f32, 0.25 + 0.75 * 0.64);
    let want = 1.0 / (4.0 * std::f32::consts::PI * at * a);
    for c in text_field(o.stdout.trim(), "f") {
        assert!((c - want).abs() <= 1e-4 * want, "{c} against {want}");
    }
    let at_angles = |m: &str, phi_l: &str, phi_v: &str| {
        let o = brdf(
            &[
                "--material",
                m,
                "--theta-l",
                "35",
                "--phi-l",
                phi_l,
                "--theta-v",
                "50",
                "--phi-v",
                phi_v,
            ],
            None,
        );
        assert_ok(&o);
        text_field(o.stdout.trim(), "f")[0]
    };
    let turned = at_angles(&mat(std::f32::consts::FRAC_PI_2), "90", "250");
    let straight = at_angles(&mat(0.0), "0", "160");
    assert!(
        (turned - straight).abs() <= 1e-4 * straight,
        "{turned} {straight}"
    );
    // And it is anisotropic: the unturned lobe at the turned angles differs.
    let other = at_angles(&mat(0.0), "90", "250");
    assert!(
        (other - straight).abs() > 0.1 * straight,
        "{other} {straight}"
    );
}
