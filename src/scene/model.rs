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
pub const MODEL_EXTENSIONS: &[&str] = &["obj"];

/// Whether `path` names a model file ([`MODEL_EXTENSIONS`]) by its extension.
pub fn is_model(path: &Path) -> bool {
    extension(path).is_some_and(|e| MODEL_EXTENSIONS.contains(&e.as_str()))
}

/// An error for a model format luz does not read yet (glTF), `None` for anything else.
pub fn unsupported(path: &Path) -> Option<SceneError> {
    extension(path)
        .filter(|e| NOT_YET.contains(&e.as_str()))
        .map(|_| SceneError::Read {
            file: path.to_path_buf(),
            reason: "glTF files are not supported yet; luz opens .json scenes and .obj models"
                .to_string(),
        })
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// Model formats luz recognises but does not read yet: a clear error instead of a JSON one.
const NOT_YET: &[&str] = &["gltf", "glb"];

/// The scene of a model file: the model, the default rig and a camera that frames it.
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
        "objects": [{"name": name, "mesh": {"type": "obj", "path": abs}}]
    })
    .to_string();
    // Errors name the model file as the user gave it, not the generated scene's fields.
    let mut scene = super::parse(&text, path).map_err(|e| match e {
        SceneError::Mesh {
            mesh_file,
            line,
            reason,
            ..
        } => SceneError::Read {
            file: path.to_path_buf(),
            // The model's own line, or the file at fault (its MTL) with its line.
            reason: match (mesh_file == abs, line) {
                (true, Some(line)) => format!("line {line}: {reason}"),
                (true, None) => reason,
                (false, Some(line)) => format!("{}:{line}: {reason}", mesh_file.display()),
                (false, None) => format!("{}: {reason}", mesh_file.display()),
            },
        },
        SceneError::Invalid { reason, .. } => SceneError::Read {
            file: path.to_path_buf(),
            reason,
        },
        other => other,
    })?;
    let aspect = scene.output.width as f32 / scene.output.height as f32;
    if let Some(bounds) = scene.bounds() {
        scene.camera = framing(bounds, aspect, 40.0);
    }
    Ok(scene)
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
            for i in 0..8 {
                let c = Vec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                );
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
        assert!(!is_model(Path::new("scene.json")));
        assert!(!is_model(Path::new("obj")));
        let e = unsupported(Path::new("x/CesiumMan.glb"))
            .unwrap()
            .to_string();
        assert!(
            e.starts_with("x/CesiumMan.glb: ") && e.contains("not supported yet"),
            "{e}"
        );
        assert!(unsupported(Path::new("a.obj")).is_none());
    }
}
