//! glTF 2.0 files (issue 16): the real files in ../shared/gltf render (the three CesiumMan
//! containers identically), and hand-made files written here cover what they do not: node
//! hierarchies with TRS and matrix transforms, cameras, lights, sparse accessors, u8 indices,
//! strips and fans, quantized attributes, texture transforms, missing normals, scene-file
//! entries, the encoder round trip, the CPU reference, bad input and a large file.

mod common;

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{Vec2, Vec3};
use luz::scene::gltf;
use serde_json::{json, Value};

use common::*;

// ---------------------------------------------------------------------------------------------
// A small glTF writer for the tests.

const F32: u32 = 5126;
const U8: u32 = 5121;
const U16: u32 = 5123;
const U32: u32 = 5125;
const I16: u32 = 5122;

#[derive(Default)]
struct Gltf {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Gltf {
    /// A buffer view of `bytes` (4-byte aligned), with an optional byte stride.
    fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(s) = stride {
            v["byteStride"] = json!(s);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    fn accessor(&mut self, a: Value) -> usize {
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// Floats as an accessor of `ty` (VEC3 ones get min/max, as POSITION needs).
    fn floats(&mut self, data: &[f32], ty: &str) -> usize {
        let view = self.view(bytemuck::cast_slice(data), None);
        let n = match ty {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            _ => 4,
        };
        let mut a =
            json!({"bufferView": view, "componentType": F32, "count": data.len() / n, "type": ty});
        if n == 3 {
            let mut lo = [f32::INFINITY; 3];
            let mut hi = [f32::NEG_INFINITY; 3];
            for p in data.chunks_exact(3) {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            a["min"] = json!(lo);
            a["max"] = json!(hi);
        }
        self.accessor(a)
    }

    fn indices_u32(&mut self, data: &[u32]) -> usize {
        let view = self.view(bytemuck::cast_slice(data), None);
        self.accessor(json!({"bufferView": view, "componentType": U32, "count": data.len(), "type": "SCALAR"}))
    }

    /// The document: `rest` (meshes, nodes, …) plus the buffer, views and accessors.
    fn document(&self, rest: Value, uri: Option<&str>) -> Value {
        let mut doc = json!({"asset": {"version": "2.0"}});
        for (k, v) in rest.as_object().unwrap() {
            doc[k] = v.clone();
        }
        let mut buffer = json!({"byteLength": self.bin.len()});
        if let Some(u) = uri {
            buffer["uri"] = json!(u);
        }
        doc["buffers"] = json!([buffer]);
        doc["bufferViews"] = json!(self.views);
        doc["accessors"] = json!(self.accessors);
        doc
    }

    /// `<dir>/<name>.gltf` with its buffer in `<name>.bin`.
    fn write_gltf(&self, dir: &Path, name: &str, rest: Value) -> PathBuf {
        let bin = format!("{name}.bin");
        std::fs::write(dir.join(&bin), &self.bin).unwrap();
        let path = dir.join(format!("{name}.gltf"));
        let doc = self.document(rest, Some(&bin));
        std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
        path
    }

    /// `<dir>/<name>.glb`.
    fn write_glb(&self, dir: &Path, name: &str, rest: Value) -> PathBuf {
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, glb(&self.document(rest, None), &self.bin)).unwrap();
        path
    }
}

/// A binary glTF container: header, JSON chunk, BIN chunk.
fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(doc).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(b.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b);
    out
}

/// The plane luz builds for `{"type": "plane", "size": [2, 2]}`: the same vertices, UVs and
/// triangles, as a glTF mesh (POSITION, NORMAL, TEXCOORD_0, u32 indices).
fn quad(g: &mut Gltf) -> Value {
    let m = luz::scene::Mesh::plane([2.0, 2.0], 1);
    let p: Vec<f32> = m.positions.iter().flat_map(|v| v.to_array()).collect();
    let n: Vec<f32> = m.normals.iter().flat_map(|v| v.to_array()).collect();
    let t: Vec<f32> = m.uvs.iter().flat_map(|v| v.to_array()).collect();
    let pos = g.floats(&p, "VEC3");
    let nor = g.floats(&n, "VEC3");
    let uv = g.floats(&t, "VEC2");
    let idx = g.indices_u32(&m.indices);
    json!({"attributes": {"POSITION": pos, "NORMAL": nor, "TEXCOORD_0": uv}, "indices": idx, "material": 0})
}

fn load(path: &Path) -> gltf::GltfFile {
    gltf::load(path, None).unwrap_or_else(|e| panic!("{e}"))
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

// ---------------------------------------------------------------------------------------------
// Real files.

fn shared_files() -> Option<Vec<PathBuf>> {
    let dir = shared_dir("gltf")?;
    Some(
        [
            "CesiumMan/glTF/CesiumMan.gltf",
            "CesiumMan/glTF-Binary/CesiumMan.glb",
            "CesiumMan/glTF-Embedded/CesiumMan.gltf",
            "retroufo.glb",
            "venus.gltf",
            "deer.gltf",
            "color_teapot_spheres.gltf",
        ]
        .iter()
        .map(|f| dir.join(f))
        .collect(),
    )
}

fn render_small(
    ctx: &std::sync::Arc<luz::vk::Context>,
    scene: &luz::scene::Scene,
) -> luz::imageio::LinearImage {
    let mut r = luz::headless::Headless::with_options(
        ctx,
        scene,
        &luz::headless::RenderOptions {
            ibl: luz::render::ibl::IblSettings::fast(),
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{}: {e}", scene.display_name()));
    r.render().unwrap();
    r.image().unwrap()
}

/// The three containers of CesiumMan (external .bin + .jpg, .glb with the image in a buffer
/// view, base64 data URIs) give byte-identical images.
#[test]
fn cesium_man_containers_render_identically() {
    let Some(files) = shared_files() else { return };
    let ctx = gpu();
    let mut images = Vec::new();
    for f in &files[..3] {
        let t = Instant::now();
        let mut scene = luz::scene::load(f).unwrap_or_else(|e| panic!("{e}"));
        let load_s = t.elapsed().as_secs_f64();
        assert!(load_s < 1.0, "{}: loading took {load_s} s", f.display());
        assert_eq!(scene.materials.len(), 1, "{}", f.display());
        assert!(scene.materials[0].textures.base_color.is_some());
        assert!(
            scene.warnings.iter().any(|w| w.contains("skins")),
            "{:?}",
            scene.warnings
        );
        scene.override_size(Some(96), Some(128));
        let img = render_small(&ctx, &scene);
        assert_eq!(nan_count(&img), 0);
        images.push(img);
    }
    for (i, img) in images.iter().enumerate().skip(1) {
        let same = img
            .pixels
            .iter()
            .zip(&images[0].pixels)
            .all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits));
        assert!(
            same,
            "{} differs from {}",
            files[i].display(),
            files[0].display()
        );
    }
    // The textured model is not one flat colour (the JPEG decoded and mapped).
    let distinct: std::collections::HashSet<[u32; 4]> = images[0]
        .pixels
        .iter()
        .map(|p| p.map(|c| (c * 64.0) as u32))
        .collect();
    assert!(
        distinct.len() > 20,
        "only {} distinct colours",
        distinct.len()
    );
    assert_no_validation_messages(&ctx);
}

/// Every shared file opens as a scene and renders lit, finite, validation clean, and like its
/// golden (`tests/golden/gltf_*.png`; re-bless with `LUZ_BLESS=1`).
#[test]
fn every_shared_file_renders() {
    let Some(files) = shared_files() else { return };
    let ctx = gpu();
    for f in &files {
        let mut scene = luz::scene::load(f).unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.triangle_count() > 100, "{}", f.display());
        scene.override_size(Some(128), Some(96));
        let img = render_small(&ctx, &scene);
        assert_eq!(nan_count(&img), 0, "{}: NaN/Inf", f.display());
        let mut empty = scene.clone();
        empty.objects.clear();
        let bg = render_small(&ctx, &empty);
        let covered = img
            .pixels
            .iter()
            .zip(&bg.pixels)
            .filter(|(a, b)| (0..3).any(|c| (a[c] - b[c]).abs() > 1e-3))
            .count();
        assert!(
            covered > 128 * 96 / 20,
            "{}: the model covers only {covered} pixels",
            f.display()
        );
        // One golden per model (the three CesiumMan containers share theirs).
        let stem = f.file_stem().unwrap().to_string_lossy().to_lowercase();
        check_golden(&format!("gltf_{stem}"), &scene, &img, Tolerance::default());
    }
    assert_no_validation_messages(&ctx);
}

// ---------------------------------------------------------------------------------------------
// Hand-made files.

/// Node hierarchy: a parent with translation/rotation/scale and a child with a matrix; a mesh
/// instanced by both. The baked vertices are the analytic world positions; a mirroring scale
/// keeps the front faces (winding swapped).
#[test]
fn node_hierarchy_trs_and_matrix() {
    let dir = scratch("gltf-nodes");
    let mut g = Gltf::default();
    let pos = g.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
    let s = std::f32::consts::FRAC_1_SQRT_2;
    // Child: translate (0, 0, 3) as a column-major matrix.
    let child = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 3.0, 1.0,
    ];
    let path = g.write_gltf(
        &dir,
        "nodes",
        json!({
            "scene": 0,
            "scenes": [{"nodes": [0, 2]}],
            "nodes": [
                // 90° about +y (quaternion x, y, z, w), scale 2, then translate (1, 0, 0).
                {"name": "parent", "translation": [1, 0, 0], "rotation": [0, s, 0, s], "scale": [2, 2, 2], "mesh": 0, "children": [1]},
                {"name": "child", "matrix": child, "mesh": 0},
                {"name": "mirror", "scale": [-1, 1, 1], "mesh": 0}
            ],
            "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": pos}}]}]
        }),
    );
    let f = load(&path);
    assert_eq!(f.parts.len(), 3);
    assert_eq!(f.parts[0].name, "parent/tri");
    assert_eq!(f.parts[1].name, "child/tri");
    // R_y(90°) maps +x to −z. Parent: p ↦ (1, 0, 0) + R(2p).
    let parent = |p: Vec3| Vec3::new(1.0, 0.0, 0.0) + Vec3::new(2.0 * p.z, 2.0 * p.y, -2.0 * p.x);
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    // Without normals the mesh is flat: three split vertices in order.
    for (k, p) in tri.iter().enumerate() {
        assert!(
            close(f.parts[0].mesh.positions[k], parent(*p)),
            "{:?}",
            f.parts[0].mesh.positions
        );
        let c = parent(*p + Vec3::new(0.0, 0.0, 3.0));
        assert!(
            close(f.parts[1].mesh.positions[k], c),
            "{:?}",
            f.parts[1].mesh.positions
        );
    }
    // Flat normals of the transformed triangle: +z rotated to +x.
    for n in &f.parts[0].mesh.normals {
        assert!(close(*n, Vec3::X), "{n}");
    }
    // Mirrored: the triangle's normal still follows its winding (front faces stay front):
    // the mirrored +z triangle faces +z with swapped winding.
    let m = &f.parts[2].mesh;
    let t = &m.indices;
    let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
    let geometric = (b - a).cross(c - a).normalize();
    assert!(close(geometric, Vec3::Z), "{geometric}");
    assert!(close(m.normals[0], Vec3::Z), "{}", m.normals[0]);
}

/// A camera node and KHR_lights_punctual nodes: the model scene uses the file's first camera
/// (aspect ratio → output width) and its lights instead of the rig's key light; `--camera 1`
/// picks the second camera; a third that does not exist is a clear error.
#[test]
fn camera_and_light_nodes() {
    let dir = scratch("gltf-camera");
    let mut g = Gltf::default();
    let prim = quad(&mut g);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let path = g.write_glb(
        &dir,
        "lit",
        json!({
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": {"KHR_lights_punctual": {"lights": [
                {"type": "directional", "color": [1, 0.5, 0.25], "intensity": 3},
                {"type": "spot", "intensity": 40, "range": 9, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}
            ]}},
            "cameras": [
                {"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1, "aspectRatio": 2.0}},
                {"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.2, "zfar": 50}},
                {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}
            ],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.6, 0.7, 1], "metallicFactor": 0, "roughnessFactor": 0.5}}],
            "scenes": [{"nodes": [0, 1, 2, 3, 4, 5]}],
            "nodes": [
                {"mesh": 0},
                {"name": "cam", "camera": 0, "translation": [0, 0, 5]},
                // Looking down: −90° about x takes −z to −y.
                {"name": "top", "camera": 1, "translation": [0, 6, 0], "rotation": [-s, 0, 0, s]},
                {"name": "sun", "rotation": [-s, 0, 0, s], "extensions": {"KHR_lights_punctual": {"light": 0}}},
                {"name": "spot", "translation": [0, 4, 0], "rotation": [-s, 0, 0, s], "extensions": {"KHR_lights_punctual": {"light": 1}}},
                {"name": "ortho", "camera": 2}
            ],
            "meshes": [{"primitives": [prim]}]
        }),
    );
    let scene = luz::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.cameras.len(), 2, "the orthographic camera is skipped");
    assert!(
        scene.warnings.iter().any(|w| w.contains("orthographic")),
        "{:?}",
        scene.warnings
    );
    assert!(close(scene.camera.position, Vec3::new(0.0, 0.0, 5.0)));
    assert!(close(scene.camera.forward(), Vec3::NEG_Z));
    assert!((scene.camera.fov_y_deg - 0.7f32.to_degrees()).abs() < 1e-4);
    assert_eq!((scene.output.width, scene.output.height), (1440, 720));
    assert_eq!(
        scene.lights.len(),
        2,
        "the file's lights replace the key light"
    );
    let sun = &scene.lights[0];
    assert_eq!(sun.kind, luz::scene::LightKind::Directional);
    assert!(close(sun.direction, Vec3::NEG_Y), "{}", sun.direction);
    assert_eq!((sun.intensity, sun.color), (3.0, Vec3::new(1.0, 0.5, 0.25)));
    let spot = &scene.lights[1];
    assert_eq!(spot.kind, luz::scene::LightKind::Spot);
    assert!(close(spot.position, Vec3::new(0.0, 4.0, 0.0)));
    assert!((spot.umbra_deg - 0.6f32.to_degrees()).abs() < 1e-4);
    assert!((spot.inner_deg.unwrap() - 0.2f32.to_degrees()).abs() < 1e-4);
    assert_eq!((spot.intensity, spot.range), (40.0, Some(9.0)));

    let mut top = scene.clone();
    luz::scene::model::use_camera(&mut top, 1).unwrap();
    assert!(close(top.camera.forward(), Vec3::NEG_Y));
    assert_eq!((top.camera.near, top.camera.far), (0.2, 50.0));
    let e = luz::scene::model::use_camera(&mut top, 2)
        .unwrap_err()
        .to_string();
    assert!(e.contains("camera 2") && e.contains("2 cameras"), "{e}");

    // In a scene file: imported only when asked, through the object's transform.
    let text = r#"{"objects": [
        {"mesh": {"type": "gltf", "path": "lit.glb"}, "position": [10, 0, 0]},
        {"mesh": {"type": "gltf", "path": "lit.glb", "lights": true, "cameras": true}, "position": [0, 0, 10]}
    ]}"#;
    let s = luz::scene::parse(text, &dir.join("scene.json")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((s.lights.len(), s.cameras.len()), (2, 2));
    assert!(close(s.lights[1].position, Vec3::new(0.0, 4.0, 10.0)));
    assert!(close(
        s.cameras[0].camera.position,
        Vec3::new(0.0, 0.0, 15.0)
    ));
    assert_eq!(s.objects.len(), 2);
    assert!(close(
        s.objects[0].transform.position,
        Vec3::new(10.0, 0.0, 0.0)
    ));

    // Through the command line: renders with --camera 1, refuses --camera 7.
    let out = dir.join("top.png");
    let (code, stdout, stderr) = luz(&[
        "render",
        path.to_str().unwrap(),
        "--camera",
        "1",
        "--width",
        "64",
        "--height",
        "48",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let (code, _, stderr) = luz(&[
        "render",
        path.to_str().unwrap(),
        "--camera",
        "7",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("camera 7"), "{stderr}");
}

/// Sparse substitution, u8 indices, a triangle strip, interleaved (strided) attributes,
/// normalised quantized attributes (KHR_mesh_quantization) and a fan.
#[test]
fn accessors_sparse_strided_quantized_strips_and_fans() {
    let dir = scratch("gltf-accessors");
    let mut g = Gltf::default();
    // 4 vertices interleaved: position (3 f32) + uv (2 f32), stride 20.
    let verts: [[f32; 5]; 4] = [
        [0.0, 0.0, 0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 1.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0, 1.0, 1.0],
    ];
    let flat: Vec<f32> = verts.iter().flatten().copied().collect();
    let view = g.view(bytemuck::cast_slice(&flat), Some(20));
    let pos = g.accessor(json!({"bufferView": view, "componentType": F32, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}));
    let uv = g.accessor(json!({"bufferView": view, "byteOffset": 12, "componentType": F32, "count": 4, "type": "VEC2"}));
    // Sparse: vertex 3 moves to (2, 2, 0).
    let sparse_idx = g.view(&[3u8], None);
    let sparse_val = g.view(bytemuck::cast_slice(&[2.0f32, 2.0, 0.0]), None);
    let moved = g.accessor(json!({
        "bufferView": view, "componentType": F32, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [2, 2, 0],
        "sparse": {"count": 1, "indices": {"bufferView": sparse_idx, "componentType": U8}, "values": {"bufferView": sparse_val}}
    }));
    // u8 strip indices.
    let strip = g.view(&[0u8, 1, 2, 3], None);
    let strip_idx =
        g.accessor(json!({"bufferView": strip, "componentType": U8, "count": 4, "type": "SCALAR"}));
    // Quantized: i16 normalised positions (32767 = 1), u16 indices of a fan.
    let q: [i16; 12] = [0, 0, 0, 32767, 0, 0, 32767, 32767, 0, 0, 32767, 0];
    let qpos_view = g.view(bytemuck::cast_slice(&q), None);
    let qpos = g.accessor(json!({"bufferView": qpos_view, "componentType": I16, "normalized": true, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}));
    let fan = g.view(bytemuck::cast_slice(&[0u16, 1, 2, 3]), None);
    let fan_idx =
        g.accessor(json!({"bufferView": fan, "componentType": U16, "count": 4, "type": "SCALAR"}));
    let path = g.write_gltf(
        &dir,
        "accessors",
        json!({
            "extensionsUsed": ["KHR_mesh_quantization"],
            "extensionsRequired": ["KHR_mesh_quantization"],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [
                {"attributes": {"POSITION": moved, "TEXCOORD_0": uv}, "indices": strip_idx, "mode": 5},
                {"attributes": {"POSITION": qpos}, "indices": fan_idx, "mode": 6},
                {"attributes": {"POSITION": pos}, "mode": 1}
            ]}]
        }),
    );
    let f = load(&path);
    assert_eq!(f.parts.len(), 2, "lines are not drawn");
    // POSITION without min/max (required by the spec, unused by luz) is accepted.
    let mut doc: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let a = doc["accessors"][moved].as_object_mut().unwrap();
    a.remove("min");
    a.remove("max");
    std::fs::write(&path, doc.to_string()).unwrap();
    assert_eq!(load(&path).parts.len(), 2);
    assert!(
        f.warnings.iter().any(|w| w.contains("LINES")),
        "{:?}",
        f.warnings
    );
    let strip = &f.parts[0].mesh;
    assert_eq!(strip.triangle_count(), 2);
    // Flat (no normals): vertices split per triangle; strip triangle 1 is {1, 3, 2}, and
    // vertex 3 is the sparse one.
    assert!(
        close(strip.positions[4], Vec3::new(2.0, 2.0, 0.0)),
        "{:?}",
        strip.positions
    );
    assert!(close(strip.positions[3], Vec3::new(1.0, 0.0, 0.0)));
    assert_eq!(strip.uvs[3], Vec2::new(1.0, 0.0));
    assert_eq!(strip.uvs[4], Vec2::new(1.0, 1.0));
    assert!(
        strip.normals.iter().all(|n| close(*n, Vec3::Z)),
        "{:?}",
        strip.normals
    );
    let fan = &f.parts[1].mesh;
    assert_eq!(fan.triangle_count(), 2);
    assert!(
        fan.positions
            .iter()
            .any(|p| close(*p, Vec3::new(1.0, 1.0, 0.0))),
        "{:?}",
        fan.positions
    );
    assert!(fan.normals.iter().all(|n| close(*n, Vec3::Z)));
}

/// A material with a texture (a PNG in a buffer view) read through TEXCOORD_1 with a
/// KHR_texture_transform: the mesh's UVs are the transformed second set; the sampler maps.
#[test]
fn texture_transform_and_second_uv_set() {
    let dir = scratch("gltf-texture");
    let mut g = Gltf::default();
    let p = g.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
    let n = g.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC3");
    let uv0 = g.floats(&[0.0; 6], "VEC2");
    let uv1 = g.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2");
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 50, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let img_view = g.view(&png, None);
    let path = g.write_glb(
        &dir,
        "tex",
        json!({
            "extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength"],
            "images": [{"bufferView": img_view, "mimeType": "image/png"}],
            "samplers": [{"magFilter": 9728, "minFilter": 9729, "wrapS": 33071, "wrapT": 33648}],
            "textures": [{"source": 0, "sampler": 0}],
            "materials": [{"name": "t", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1,
                "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.25], "scale": [2, 3]}}}},
                "emissiveFactor": [1, 0.5, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
                "alphaMode": "BLEND", "doubleSided": true}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1}, "material": 0}]}]
        }),
    );
    let f = load(&path);
    let m = &f.parts[0].mesh;
    assert_eq!(
        m.uvs,
        vec![
            Vec2::new(0.5, 0.25),
            Vec2::new(2.5, 0.25),
            Vec2::new(0.5, 3.25)
        ]
    );
    assert_eq!(
        f.materials[0].textures.emissive_factor,
        Vec3::new(4.0, 2.0, 0.0)
    );
    let t = f.materials[0].textures.base_color.as_ref().unwrap();
    assert!(t.embedded.is_some());
    use luz::scene::{Filter, Wrap};
    assert_eq!(
        (t.sampler.wrap_u, t.sampler.wrap_v),
        (Wrap::Clamp, Wrap::Mirror)
    );
    assert_eq!(
        (t.sampler.mag, t.sampler.min, t.sampler.mipmaps),
        (Filter::Nearest, Filter::Linear, false)
    );
    // The embedded PNG decodes as a texture.
    let data =
        luz::texture::load_texture(t, luz::texture::ColorSpace::Srgb, 4096, &mut |_| {}).unwrap();
    assert_eq!((data.width, data.height), (2, 2));
}

/// A hand-made glTF (a quad, its material, a camera and a light) inside a luz scene file renders
/// exactly like the equivalent scene made of luz's own plane; the encoder writes the glTF entry
/// back and the written scene loads as the same scene; a scene `material` overrides the file's;
/// the CPU reference renders it like the plane too.
#[test]
fn hand_made_file_equals_the_json_scene() {
    let dir = scratch("gltf-equal");
    let mut g = Gltf::default();
    let prim = quad(&mut g);
    g.write_gltf(
        &dir,
        "quad",
        json!({
            "materials": [{"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.3, 0.2, 1], "metallicFactor": 0.25, "roughnessFactor": 0.4}}],
            "nodes": [{"name": "q", "mesh": 0}],
            "meshes": [{"name": "quad", "primitives": [prim]}]
        }),
    );
    let common = r#""camera": {"position": [0.5, 2.5, 3], "target": [0, 0, 0], "fov_y_deg": 45},
        "output": {"width": 64, "height": 48, "msaa": 1},
        "ambient": [0.05, 0.05, 0.05],
        "lights": [{"type": "point", "position": [1, 2, 1], "intensity": 6}],"#;
    let material = r#""paint": {"model": "metal_rough", "base_color": [0.7, 0.3, 0.2], "metallic": 0.25, "roughness": 0.4}"#;
    let plane = format!(
        r#"{{ {common} "materials": {{ {material} }},
        "objects": [{{"mesh": {{"type": "plane", "size": [2, 2]}}, "material": "paint", "position": [0.1, 0, 0], "rotation_deg": [0, 20, 0]}}]}}"#
    );
    let with_gltf = format!(
        r#"{{ {common} "objects": [{{"name": "g", "mesh": {{"type": "gltf", "path": "quad.gltf"}}, "position": [0.1, 0, 0], "rotation_deg": [0, 20, 0]}}]}}"#
    );
    let a = luz::scene::parse(&plane, &dir.join("plane.json")).unwrap_or_else(|e| panic!("{e}"));
    let b = luz::scene::parse(&with_gltf, &dir.join("gltf.json")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(b.objects.len(), 1);
    assert_eq!(b.objects[0].name, "g/q/quad");
    assert_eq!(b.materials[0].name, "quad.gltf/paint");
    assert_eq!(b.materials[0].material, a.materials[0].material);
    let ctx = gpu();
    let ia = render_on(&ctx, &a);
    let ib = render_on(&ctx, &b);
    let max = ia
        .pixels
        .iter()
        .zip(&ib.pixels)
        .flat_map(|(x, y)| (0..3).map(move |c| (x[c] - y[c]).abs()))
        .fold(0.0f32, f32::max);
    assert!(max < 1e-5, "glTF and plane differ by {max}");
    let lit = ia.pixels.iter().filter(|p| p[0] > 0.01).count();
    assert!(lit > 200, "the quad is hardly visible ({lit} pixels)");
    assert_no_validation_messages(&ctx);

    // Encoder round trip.
    let saved = dir.join("saved.json");
    luz::scene::save(&b, &saved).unwrap();
    let text = std::fs::read_to_string(&saved).unwrap();
    assert!(
        text.contains("\"gltf\"") && text.contains("quad.gltf"),
        "{text}"
    );
    let c = luz::scene::load(&saved).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(c.objects.len(), 1);
    assert_eq!(c.objects[0].name, b.objects[0].name);
    assert_eq!(c.objects[0].transform, b.objects[0].transform);
    assert_eq!(*c.objects[0].mesh, *b.objects[0].mesh);
    assert_eq!(c.materials.len(), 1);
    assert_eq!(c.materials[0].material, b.materials[0].material);

    // A scene material overrides the file's.
    let over = format!(
        r#"{{ {common} "materials": {{"red": {{"model": "lambert", "albedo": [1, 0, 0]}}}},
        "objects": [{{"mesh": {{"type": "gltf", "path": "quad.gltf"}}, "material": "red"}}]}}"#
    );
    let o = luz::scene::parse(&over, &dir.join("over.json")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(o.materials.len(), 1);
    assert_eq!(o.objects[0].material, 0);

    // The CPU reference sees the glTF's triangles as it sees the plane.
    let opts = luz::reference::ReferenceOptions {
        spp: 1,
        ..Default::default()
    };
    let ra = luz::reference::render_reference(&a, &opts, None).unwrap();
    let rb = luz::reference::render_reference(&b, &opts, None).unwrap();
    let differing = ra
        .pixels
        .iter()
        .zip(&rb.pixels)
        .filter(|(x, y)| (0..3).any(|c| (x[c] - y[c]).abs() > 1e-3))
        .count();
    assert!(
        differing <= 3,
        "{differing} pixels differ between the reference's glTF and plane"
    );
}

// ---------------------------------------------------------------------------------------------
// Bad input: one clear message naming the file and the JSON path, exit code 1, no panic.

#[test]
fn bad_files_fail_clearly() {
    let dir = scratch("gltf-bad");
    let mut g = Gltf::default();
    let prim = quad(&mut g);
    let good =
        json!({"nodes": [{"mesh": 0}], "meshes": [{"primitives": [prim]}], "materials": [{}]});
    let glb_path = g.write_glb(&dir, "good", good.clone());
    let bytes = std::fs::read(&glb_path).unwrap();
    let mut cases: Vec<(PathBuf, &str)> = Vec::new();
    // Truncated .glb.
    let p = dir.join("truncated.glb");
    std::fs::write(&p, &bytes[..bytes.len() - 40]).unwrap();
    cases.push((p, "truncated"));
    // Missing buffer file.
    let p = g.write_gltf(&dir, "missing_bin", good.clone());
    std::fs::remove_file(dir.join("missing_bin.bin")).unwrap();
    cases.push((p, "buffers[0].uri"));
    // Bad accessor index.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    std::fs::write(dir.join("good.bin"), &g.bin).unwrap();
    doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(99);
    let p = dir.join("bad_accessor.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "meshes[0].primitives[0].attributes.NORMAL"));
    // Unsupported required extension.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    let p = dir.join("draco.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "extensionsRequired[0]"));
    // Version 1.0.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    doc["asset"]["version"] = json!("1.0");
    let p = dir.join("v1.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "asset.version"));
    // A node cycle.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    doc["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
    doc["scenes"] = json!([{"nodes": [0]}]);
    let p = dir.join("cycle.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "nodes[0]"));
    // Indices out of range.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    doc["accessors"][3]["componentType"] = json!(U8);
    doc["accessors"][3]["count"] = json!(6);
    let mut bad_idx = g.bin.clone();
    let off = doc["bufferViews"][3]["byteOffset"].as_u64().unwrap() as usize;
    bad_idx[off + 2] = 77;
    std::fs::write(dir.join("bad_idx.bin"), &bad_idx).unwrap();
    doc["buffers"][0]["uri"] = json!("bad_idx.bin");
    let p = dir.join("bad_indices.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "meshes[0].primitives[0].indices"));
    // An accessor past its buffer view.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    doc["accessors"][0]["count"] = json!(4_000_000_000u64);
    let p = dir.join("huge_count.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "accessors[0]"));
    // Negative field of view.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    doc["cameras"] = json!([{"type": "perspective", "perspective": {"yfov": -1, "znear": 0.1}}]);
    doc["nodes"][0]["camera"] = json!(0);
    let p = dir.join("negative_fov.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "cameras[0].perspective.yfov"));
    // Float indices.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    doc["accessors"][3]["componentType"] = json!(F32);
    let p = dir.join("float_indices.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "indices"));
    // Not JSON at all.
    let p = dir.join("text.gltf");
    std::fs::write(&p, "hello").unwrap();
    cases.push((p, "(root)"));
    // A missing image.
    let mut doc = g.document(good.clone(), Some("good.bin"));
    doc["images"] = json!([{"uri": "nope.png"}]);
    let p = dir.join("missing_image.gltf");
    std::fs::write(&p, doc.to_string()).unwrap();
    cases.push((p, "images[0].uri"));

    let out = dir.join("out.png");
    for (path, field) in &cases {
        let (code, stdout, stderr) = luz(&[
            "render",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        let name = path.file_name().unwrap().to_str().unwrap();
        assert_eq!(code, 1, "{name}: exit code {code}\n{stdout}\n{stderr}");
        assert!(
            stderr.contains(name) && stderr.contains(field),
            "{name}: the message should name the file and {field}:\n{stderr}"
        );
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
    }
}

/// A megabytes-large file (a grid of 2 million triangles, about 48 MB) loads in linear time: a
/// sixteenth of it takes about a sixteenth of the time, and the whole loads within seconds.
#[test]
fn large_file_loads_in_linear_time() {
    let dir = scratch("gltf-large");
    let write = |n: u32, name: &str| {
        let mut g = Gltf::default();
        let mut p = Vec::with_capacity(((n + 1) * (n + 1) * 3) as usize);
        for i in 0..=n {
            for j in 0..=n {
                p.extend_from_slice(&[j as f32 / n as f32, 0.0, i as f32 / n as f32]);
            }
        }
        let mut idx = Vec::with_capacity((n * n * 6) as usize);
        for i in 0..n {
            for j in 0..n {
                let a = i * (n + 1) + j;
                let b = a + n + 1;
                idx.extend_from_slice(&[a, b, b + 1, a, b + 1, a + 1]);
            }
        }
        let normals: Vec<f32> = (0..p.len() / 3).flat_map(|_| [0.0, 1.0, 0.0]).collect();
        let pos = g.floats(&p, "VEC3");
        let nor = g.floats(&normals, "VEC3");
        let ind = g.indices_u32(&idx);
        g.write_glb(
            &dir,
            name,
            json!({"nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nor}, "indices": ind}]}]}),
        )
    };
    let small = write(250, "small");
    let large = write(1000, "large");
    // The fastest of three runs of each (the machine is shared).
    let time = |p: &Path| {
        let mut best = f64::INFINITY;
        let mut triangles = 0;
        for _ in 0..3 {
            let t = Instant::now();
            let f = load(p);
            best = best.min(t.elapsed().as_secs_f64());
            triangles = f.triangle_count();
        }
        (best, triangles)
    };
    let (ts, ns) = time(&small);
    let (tl, nl) = time(&large);
    assert_eq!((ns, nl), (125_000, 2_000_000));
    eprintln!("125k triangles: {ts:.3} s, 2M triangles: {tl:.3} s");
    assert!(tl < 10.0, "2M triangles took {tl} s");
    // 16 times the data: linear is 16 times the time, quadratic 256 times (cache effects make
    // larger inputs a little slower per byte).
    assert!(
        tl < 100.0 * ts.max(0.002),
        "not linear: {ts} s for 1/16 of {tl} s"
    );
}

/// The viewer opens a glTF file given on the command line and one dropped on it (a scripted
/// `open=`), validation clean.
#[test]
fn viewer_opens_gltf_files() {
    let Some(files) = shared_files() else { return };
    let glb = files[1].to_str().unwrap().to_string();
    let script = format!("2:open={}", files[0].display());
    let Some((code, out, err)) = luz_in_window(&[
        "view",
        &glb,
        "--frames",
        "5",
        "--width",
        "160",
        "--height",
        "120",
        "--ibl-quality",
        "fast",
        "--script",
        &script,
    ]) else {
        return;
    };
    assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
    assert!(out.contains("opened model"), "{out}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("validation: 0 errors, 0 warnings"), "{err}");
}
