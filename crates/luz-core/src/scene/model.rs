//! A model file opened as a scene: `luz render bunny.obj` and the other commands take a model
//! where they take a scene. The model's own materials (its MTL) are kept; a documented default
//! rig lights it, and the camera frames its bounds.
//!
//! The rig: the built-in `sky` environment (image-based lighting, intensity 0.3, also the
//! background) and one warm directional key light from the upper left front (irradiance 1.2),
//! ACES tone mapping,
//! 1280×720 with 4× MSAA. The camera looks at the centre of the model's bounding box from the
//! front, a little to the right and above (direction (0.35, 0.3, 1) normalised, +y up, +z front,
//! as OBJ files are usually authored), at the distance where the bounding sphere fills 90 % of
//! the narrower field of view.

use std::path::Path;

use glam::Vec3;

use super::{Camera, Scene, SceneError};

/// The file extensions (lower case) that are model files rather than JSON scenes.
pub const MODEL_EXTENSIONS: &[&str] = &["obj", "gltf", "glb"];

/// Whether `path` names a model file ([`MODEL_EXTENSIONS`]) by its extension.
pub fn is_model(path: &Path) -> bool {
    crate::files::lowercase_extension(path).is_some_and(|e| MODEL_EXTENSIONS.contains(&e.as_str()))
}

/// The scene of a model file: the model, the default rig and a camera that frames it. A glTF
/// file's own lights replace the rig's key light (the environment stays), and its first camera
/// replaces the framing one ([`use_camera`] picks another).
pub fn model_scene(path: &Path) -> Result<Scene, SceneError> {
    let abs = std::fs::canonicalize(path).map_err(|e| SceneError::Read {
        file: path.to_path_buf(),
        reason: format!("cannot open the model: {e}"),
    })?;
    let name = abs
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .unwrap_or("model");
    let gltf = super::gltf::is_gltf(&abs);
    let mesh = if gltf {
        serde_json::json!({"type": "gltf", "path": abs, "lights": true, "cameras": true})
    } else {
        serde_json::json!({"type": "obj", "path": abs})
    };
    let text = serde_json::json!({
        "description": format!("{}: the model with luz's default rig (src/scene/model.rs)", path.display()),
        "output": {"width": 1280, "height": 720, "msaa": 4, "tonemap": "aces"},
        "environment": {"procedural": "sky", "intensity": 0.3},
        "lights": [{
            "type": "directional",
            "direction": [0.5, -0.8, -0.6],
            "color": [1.0, 0.96, 0.9],
            "intensity": 1.2
        }],
        "objects": [{"name": name, "mesh": mesh}]
    })
    .to_string();
    // Errors name the model file as the user gave it, not the generated scene's fields.
    let mut scene = super::parse(&text, path).map_err(|e| match e {
        SceneError::Mesh {
            mesh_file,
            line,
            reason,
            ..
        } => match (mesh_file == abs, line) {
            // A glTF's own errors read "<json path>: <reason>".
            (true, None) if gltf => match reason.split_once(": ") {
                Some((json, why)) => SceneError::Invalid {
                    file: path.to_path_buf(),
                    path: json.to_string(),
                    reason: why.to_string(),
                },
                None => SceneError::Read {
                    file: path.to_path_buf(),
                    reason,
                },
            },
            (same, line) => SceneError::Read {
                file: path.to_path_buf(),
                // The model's own line, or the file at fault (its MTL) with its line.
                reason: match (same, line) {
                    (true, Some(line)) => format!("line {line}: {reason}"),
                    (true, None) => reason,
                    (false, Some(line)) => format!("{}:{line}: {reason}", mesh_file.display()),
                    (false, None) => format!("{}: {reason}", mesh_file.display()),
                },
            },
        },
        SceneError::Invalid { reason, .. } => SceneError::Read {
            file: path.to_path_buf(),
            reason,
        },
        other => other,
    })?;
    // The file's lights (after the rig's key light) replace the key light.
    if scene.lights.len() > 1 {
        scene.lights.remove(0);
    }
    let aspect = scene.output.width as f32 / scene.output.height as f32;
    if !scene.cameras.is_empty() {
        use_camera(&mut scene, 0)?;
    } else if let Some(bounds) = scene.bounds() {
        scene.camera = framing(bounds, aspect, 40.0);
    }
    Ok(scene)
}

/// Makes camera `n` of [`Scene::cameras`] (a glTF file's cameras) the scene's camera. A camera
/// with an aspect ratio sets the output width (height × aspect); the look-at target goes to the
/// depth of the scene's centre, and a camera without `zfar` gets a far plane behind the scene.
pub fn use_camera(scene: &mut Scene, n: usize) -> Result<(), SceneError> {
    let Some(c) = scene.cameras.get(n).cloned() else {
        return Err(SceneError::Invalid {
            file: scene.source.clone().unwrap_or_default(),
            path: "(cameras)".into(),
            reason: format!(
                "camera {n} asked for, but the scene's glTF files offer {} camera{}",
                scene.cameras.len(),
                if scene.cameras.len() == 1 { "" } else { "s" }
            ),
        });
    };
    let mut cam = c.camera;
    if let Some(a) = c.aspect {
        let w = (scene.output.height as f32 * a).round();
        scene.output.width = (w.max(1.0) as u32).min(super::MAX_IMAGE_SIZE);
    }
    let forward = cam.forward();
    if let Some((lo, hi)) = scene.bounds() {
        let centre = (lo + hi) * 0.5;
        let radius = (hi - lo).length() * 0.5;
        let depth = (centre - cam.position).dot(forward);
        if depth > cam.near {
            cam.target = cam.position + forward * depth;
        }
        if cam.far == 0.0 {
            cam.far = ((centre - cam.position).length() + radius) * 2.0;
        }
    }
    if !(cam.far > cam.near && cam.far.is_finite()) {
        cam.far = cam.near * 1e4;
    }
    scene.camera = cam;
    super::tessellation::resolve(scene);
    Ok(())
}

/// A camera looking at the centre of `bounds` from direction (0.35, 0.3, 1), far enough that the
/// bounding sphere fills 90 % of the narrower of the vertical and horizontal fields of view.
pub fn framing((lo, hi): (Vec3, Vec3), aspect: f32, fov_y_deg: f32) -> Camera {
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo).length() * 0.5).max(1e-4);
    let half_y = (fov_y_deg.to_radians() * 0.5).max(1e-3);
    let half_x = (half_y.tan() * aspect.max(1e-3)).atan();
    let half = half_y.min(half_x);
    let distance = radius / (0.9 * half.sin()).min(0.999);
    let dir = Vec3::new(0.35, 0.3, 1.0).normalize();
    Camera {
        position: centre + dir * distance,
        target: centre,
        up: Vec3::Y,
        fov_y_deg,
        near: ((distance - radius) * 0.5).max(distance * 1e-4),
        far: distance + radius * 2.0,
        projection: super::Projection::Perspective,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every corner of the box projects inside the image, and the sphere fills most of it.
    #[test]
    fn framing_sees_the_whole_box() {
        for (lo, hi, aspect) in [
            (Vec3::splat(-1.0), Vec3::splat(1.0), 16.0 / 9.0),
            (
                Vec3::new(-0.1, 0.0, -0.05),
                Vec3::new(0.1, 0.15, 0.05),
                16.0 / 9.0,
            ),
            (Vec3::new(-20.0, 5.0, 3.0), Vec3::new(20.0, 6.0, 4.0), 0.5),
        ] {
            let cam = framing((lo, hi), aspect, 40.0);
            let vp = cam.projection(aspect) * cam.view();
            let mut extent = 0.0f32;
            for c in crate::scene::box_corners(glam::Mat4::IDENTITY, (lo, hi)) {
                let p = vp.project_point3(c);
                assert!(
                    p.x.abs() <= 1.0 && p.y.abs() <= 1.0,
                    "{c} at {p} ({lo}, {hi})"
                );
                assert!((0.0..=1.0).contains(&p.z), "{c} clipped: depth {}", p.z);
                extent = extent.max(p.x.abs()).max(p.y.abs());
            }
            assert!(extent > 0.35, "the model fills too little: {extent}");
        }
    }

    #[test]
    fn model_extensions() {
        assert!(is_model(Path::new("a/bunny.OBJ")));
        assert!(is_model(Path::new("x/CesiumMan.glb")));
        assert!(is_model(Path::new("x/CesiumMan.gltf")));
        assert!(!is_model(Path::new("scene.json")));
        assert!(!is_model(Path::new("obj")));
    }
}
