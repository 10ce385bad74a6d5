//! Automatic tessellation: where a scene leaves a sphere's, cone's or cylinder's `segments` unset,
//! luz picks the lowest segment count whose silhouette stays within a budget of pixels on screen.
//!
//! A circle of projected radius r px drawn as a regular N-gon is off by at most
//! r · (1 − cos(π/N)) px (the sagitta of one segment), so N = ⌈π / acos(1 − ε/r)⌉ for a budget of
//! ε px, rounded up to a multiple of 4 (symmetric under quarter turns) and clamped to
//! [[`AUTO_MIN_SEGMENTS`], [`AUTO_MAX_SEGMENTS`]]; a sphere's rings follow at N/2 unless the scene
//! gives them. The projected radius is that of the bounding circle seen straight on from the
//! scene's camera, f · r / √(d² − r²) with f = (height / 2) / tan(fov_y / 2); an object around the
//! camera gets the maximum. An orthographic camera sees r · height / (2 · half_height) px at any
//! distance.
//!
//! The budget is `output.tessellation_error_px` (default [`DEFAULT_TESSELLATION_ERROR_PX`]). It is
//! not a visual guess: `luz lab` renders the scene with automatic tessellation at several budgets
//! ("auto tessellation" variants) and measures each against the CPU reference (exact spheres), and
//! the default is the largest budget whose error on the benchmark grid (`assets/scenes/bench/
//! grid49.json`, Phong shading, GGX) matches the 64-segment mesh's — see the README's
//! "Model no more than a scene needs" figures and `scripts/auto_tessellation.sh`.
//!
//! The choice is made when the scene is loaded (and again when its output size changes,
//! [`resolve`]), from the scene's camera; the viewer keeps it while the camera orbits.

use std::sync::Arc;

use glam::Vec3;

use super::{Camera, MeshDesc, Object, Scene};

/// Default budget: the silhouette may be off by this many pixels (see the module docs for how it
/// was measured).
pub const DEFAULT_TESSELLATION_ERROR_PX: f32 = 0.05;
/// The fewest segments automatic tessellation chooses (a far or tiny object).
pub const AUTO_MIN_SEGMENTS: u32 = 8;
/// The most segments automatic tessellation chooses (a near or huge object).
pub const AUTO_MAX_SEGMENTS: u32 = 256;
/// Smallest accepted positive budget (px): below it N would hit the maximum for any visible object.
/// 0 is accepted too: full detail (the most segments; meshes drawn whole, [`super::lod`]).
pub const MIN_TESSELLATION_ERROR_PX: f32 = 1e-4;
/// Largest accepted budget (px).
pub const MAX_TESSELLATION_ERROR_PX: f32 = 100.0;

/// How an object's segment count was set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tessellation {
    /// Given in the scene file (or not applicable: OBJ meshes, cubes, planes, icospheres).
    Given,
    /// Chosen by [`resolve`]; `rings_given` keeps a sphere's explicit `rings`.
    Auto {
        /// The projected radius the choice was made for, in pixels.
        projected_radius_px: f32,
        rings_given: bool,
    },
}

/// Smallest segment count N (a multiple of 4 in [`AUTO_MIN_SEGMENTS`], [`AUTO_MAX_SEGMENTS`])
/// whose N-gon is within `budget_px` of a circle of radius `radius_px`.
pub fn segments_for(radius_px: f32, budget_px: f32) -> u32 {
    if radius_px.is_nan() || radius_px == f32::INFINITY {
        return AUTO_MAX_SEGMENTS;
    }
    let (r, e) = (f64::from(radius_px), f64::from(budget_px));
    if r <= e {
        return AUTO_MIN_SEGMENTS;
    }
    let n = (std::f64::consts::PI / (1.0 - e / r).acos()).ceil();
    let n = if n.is_finite() {
        n.min(f64::from(AUTO_MAX_SEGMENTS)) as u32
    } else {
        AUTO_MAX_SEGMENTS
    };
    n.next_multiple_of(4)
        .clamp(AUTO_MIN_SEGMENTS, AUTO_MAX_SEGMENTS)
}

/// The radius in pixels of a sphere of `radius` at `center` seen from `camera` on an image
/// `height_px` tall (straight on; infinite when the camera is inside it; orthographic:
/// r · height / (2 · half_height), whatever the distance).
pub fn projected_radius_px(camera: &Camera, height_px: u32, center: Vec3, radius: f32) -> f32 {
    if let Some(h) = camera.ortho_half_height() {
        return radius * 0.5 * height_px as f32 / h;
    }
    let d2 = f64::from((center - camera.position).length_squared());
    let r = f64::from(radius);
    if d2 <= r * r {
        return f32::INFINITY;
    }
    let f = 0.5 * f64::from(height_px) / (0.5 * f64::from(camera.fov_y_deg).to_radians()).tan();
    (f * r / (d2 - r * r).sqrt()) as f32
}

/// The radius of the circle an object's segments go around, in world units.
fn world_radius(object: &Object) -> Option<f32> {
    let s = object.transform.scale;
    match object.desc {
        MeshDesc::Sphere { radius, .. } => Some(radius * s.max_element()),
        MeshDesc::Cone { radius, height, .. } | MeshDesc::Cylinder { radius, height, .. } => {
            // The bounding sphere: the whole object must be within budget, not just its rim.
            let r = radius * s.x.max(s.z);
            let h = 0.5 * height * s.y;
            Some((r * r + h * h).sqrt())
        }
        _ => None,
    }
}

/// Chooses the segments (and a sphere's rings) of every object whose tessellation is automatic,
/// from the scene's camera, output height and `output.tessellation_error_px`, and rebuilds those
/// meshes (objects with the same choice share one). Call again after changing the camera or the
/// output size.
pub fn resolve(scene: &mut Scene) {
    let budget = scene.output.tessellation_error_px;
    let mut built = super::mesh_cache::MeshCache::default();
    for object in &mut scene.objects {
        let Tessellation::Auto { rings_given, .. } = object.tessellation else {
            continue;
        };
        let Some(radius) = world_radius(object) else {
            continue;
        };
        let r_px = projected_radius_px(
            &scene.camera,
            scene.output.height,
            object.transform.position,
            radius,
        );
        let n = segments_for(r_px, budget);
        let desc = match object.desc.clone() {
            MeshDesc::Sphere { radius, rings, .. } => MeshDesc::Sphere {
                radius,
                segments: n,
                rings: if rings_given { rings } else { (n / 2).max(4) },
            },
            MeshDesc::Cone { radius, height, .. } => MeshDesc::Cone {
                radius,
                height,
                segments: n,
            },
            MeshDesc::Cylinder { radius, height, .. } => MeshDesc::Cylinder {
                radius,
                height,
                segments: n,
            },
            other => other,
        };
        object.tessellation = Tessellation::Auto {
            projected_radius_px: r_px,
            rings_given,
        };
        if desc == object.desc && !object.mesh.indices.is_empty() {
            continue;
        }
        let mesh = match built.get(&desc) {
            Some(m) => m.clone(),
            None => {
                let m = Arc::new(desc.build().unwrap_or_default());
                built.insert(desc.clone(), m.clone());
                m
            }
        };
        object.desc = desc;
        object.mesh = mesh;
    }
}

/// What `luz render` and the viewer say of automatic tessellation: a summary line (how many
/// objects, the segment range) and, when `verbose`, one line per object (indented); nothing when
/// no object is tessellated automatically.
pub fn summary(scene: &Scene, verbose: bool) -> Vec<String> {
    let lines = report(scene);
    if lines.is_empty() {
        return lines;
    }
    let segments: Vec<u32> = scene
        .objects
        .iter()
        .filter(|o| matches!(o.tessellation, Tessellation::Auto { .. }))
        .filter_map(|o| o.desc.segments())
        .collect();
    let (lo, hi) = (
        segments.iter().min().copied().unwrap_or(0),
        segments.iter().max().copied().unwrap_or(0),
    );
    let mut out = vec![format!(
        "automatic tessellation (budget {} px): {} object(s), {lo}-{hi} segments{}",
        scene.output.tessellation_error_px,
        lines.len(),
        if verbose {
            ":"
        } else {
            " (--verbose lists them)"
        }
    )];
    if verbose {
        out.extend(lines.into_iter().map(|l| format!("  {l}")));
    }
    out
}

/// One line per automatically tessellated object: its name, the choice and why.
pub fn report(scene: &Scene) -> Vec<String> {
    scene
        .objects
        .iter()
        .filter_map(|o| {
            let Tessellation::Auto {
                projected_radius_px,
                ..
            } = o.tessellation
            else {
                return None;
            };
            let choice = match o.desc {
                MeshDesc::Sphere {
                    segments, rings, ..
                } => format!("{segments} segments x {rings} rings"),
                MeshDesc::Cone { segments, .. } | MeshDesc::Cylinder { segments, .. } => {
                    format!("{segments} segments")
                }
                _ => return None,
            };
            Some(format!(
                "{}: {choice}, {} triangles (projected radius {:.1} px, budget {} px)",
                o.name,
                o.desc.triangle_count().unwrap_or(0),
                projected_radius_px,
                scene.output.tessellation_error_px
            ))
        })
        .collect()
}

/// Marks every sphere, cone and cylinder of `scene` as automatically tessellated (keeping no
/// explicit rings) and resolves them with `budget_px`: the lab's "auto tessellation" variants.
pub fn make_automatic(scene: &mut Scene, budget_px: f32) {
    scene.output.tessellation_error_px = budget_px;
    for o in &mut scene.objects {
        if o.desc.segments().is_some() {
            o.tessellation = Tessellation::Auto {
                projected_radius_px: 0.0,
                rings_given: false,
            };
        }
    }
    resolve(scene);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_meet_the_budget_and_are_the_fewest() {
        for r in [1.0f32, 3.0, 10.0, 35.0, 100.0, 400.0, 2000.0] {
            for e in [0.01f32, 0.05, 0.25, 1.0] {
                let n = segments_for(r, e);
                assert!(
                    n.is_multiple_of(4) && (AUTO_MIN_SEGMENTS..=AUTO_MAX_SEGMENTS).contains(&n)
                );
                let sagitta = |n: u32| r * (1.0 - (std::f32::consts::PI / n as f32).cos());
                if n < AUTO_MAX_SEGMENTS {
                    assert!(sagitta(n) <= e * 1.0001, "r {r} e {e}: {n} is over budget");
                }
                if n > AUTO_MIN_SEGMENTS {
                    assert!(sagitta(n - 4) > e, "r {r} e {e}: {} would do", n - 4);
                }
            }
        }
        assert_eq!(segments_for(0.0, 0.05), AUTO_MIN_SEGMENTS);
        assert_eq!(segments_for(f32::INFINITY, 0.05), AUTO_MAX_SEGMENTS);
        assert_eq!(segments_for(f32::NAN, 0.05), AUTO_MAX_SEGMENTS);
        assert_eq!(segments_for(1e30, 0.05), AUTO_MAX_SEGMENTS);
        // Fewer pixels, fewer segments.
        assert!(segments_for(10.0, 0.05) < segments_for(40.0, 0.05));
    }

    #[test]
    fn projected_radius_matches_the_pinhole_camera() {
        let camera = Camera {
            position: Vec3::new(0.0, 0.0, 10.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 90.0,
            near: 0.1,
            far: 100.0,
            projection: crate::scene::Projection::Perspective,
        };
        // f = 360 px; a unit sphere 10 away subtends r / √(d² − r²) = 1/√99.
        let r = projected_radius_px(&camera, 720, Vec3::ZERO, 1.0);
        assert!((r - 360.0 / 99f32.sqrt()).abs() < 1e-3, "{r}");
        // Orthographic, half height 4: 1 · 720 / 8 = 90 px near or far.
        let ortho = Camera {
            projection: crate::scene::Projection::Orthographic { half_height: 4.0 },
            ..camera
        };
        for z in [-50.0, 0.0, 8.0] {
            let r = projected_radius_px(&ortho, 720, Vec3::new(0.0, 0.0, z), 1.0);
            assert_eq!(r, 90.0);
        }
        assert_eq!(
            projected_radius_px(&camera, 720, Vec3::new(0.0, 0.0, 9.5), 1.0),
            f32::INFINITY
        );
    }
}
