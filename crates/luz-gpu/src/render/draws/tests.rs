//! The draw list on the CPU: sort keys (pipeline and material grouping, blended back to front,
//! depth views front to back), LOD selection, and shadow layers culling to the casters the
//! shadow pass drew before the list.

use super::*;
use crate::scene::lod::LodLevel;

fn level(first_index: u32, index_count: u32, error: f32) -> LodLevel {
    LodLevel {
        first_index,
        index_count,
        error,
    }
}

/// A unit sphere's shape with `levels` (one: not simplified).
fn shape(levels: Vec<LodLevel>) -> Shape {
    Shape {
        sphere: (Vec3::ZERO, 1.0),
        tight: (Vec3::ZERO, 1.0),
        bounds: (Vec3::splat(-0.5), Vec3::splat(0.5)),
        plane: None,
        levels: levels.into(),
    }
}

fn placed_at(position: Vec3) -> Placed {
    let model = Mat4::from_translation(position);
    Placed {
        model,
        scale: 1.0,
        sphere: Sphere {
            center: position,
            radius: 1.0,
        },
        tight: Sphere {
            center: position,
            radius: 1.0,
        },
    }
}

fn camera() -> Camera {
    let mut c = crate::scene::default_scene().camera;
    c.position = Vec3::new(0.0, 0.0, 10.0);
    c.target = Vec3::ZERO;
    c.up = Vec3::Y;
    c.near = 0.1;
    c.far = 1000.0;
    c.projection = crate::scene::Projection::Perspective;
    c
}

fn eye(camera: &Camera) -> Eye<'_> {
    Eye {
        camera,
        view_proj: camera.projection(1.0) * camera.view(),
        focal_px: crate::scene::lod::focal_px(camera, 720),
        budget: 1.0,
    }
}

fn item(shape: usize, material: usize, cull: bool, blend: bool) -> Item {
    Item {
        shape,
        object: 0,
        material,
        cull,
        blend,
        transmit: false,
    }
}

/// Opaque draws come grouped by pipeline, then material, culling and mesh (ties in list order);
/// blended ones after every opaque draw, farthest first; culled items are left out.
#[test]
fn colour_views_group_by_pipeline_and_material_then_blend_back_to_front() {
    let list = DrawList {
        shapes: vec![shape(vec![level(0, 3, 0.0)]), shape(vec![level(0, 6, 0.0)])],
        items: vec![
            item(0, 2, true, false),  // 0: pipeline 1
            item(1, 0, true, false),  // 1: pipeline 0
            item(0, 1, false, true),  // 2: blended, near
            item(0, 1, true, false),  // 3: pipeline 1, material 1
            item(1, 0, false, false), // 4: pipeline 0, not culled
            item(0, 1, false, true),  // 5: blended, far
            item(1, 0, true, false),  // 6: pipeline 0, behind the camera: culled
            item(0, 0, true, false),  // 7: pipeline 0, material 0, mesh 0
            item(0, 2, true, false),  // 8: same as 0
        ],
    };
    let at = |z: f32| placed_at(Vec3::new(0.0, 0.0, z));
    let placed = [
        at(0.0),
        at(0.0),
        at(2.0),
        at(0.0),
        at(0.0),
        at(-5.0),
        at(20.0),
        at(0.0),
        at(1.0),
    ];
    let pipelines = [1, 0, 0, 1, 0, 0, 0, 0, 1];
    let c = camera();
    let view = list.color_view(&placed, &eye(&c), &pipelines);
    // Pipeline 0: material 0, unculled (4) before culled, mesh 0 (7) before 1 (1); pipeline 1:
    // material 1 (3), then 2 (0, 8 in list order); blended 5 (farther) before 2.
    assert_eq!(view.order, vec![4, 7, 1, 3, 0, 8, 5, 2]);
    assert_eq!(key::second_phase(&view.keys), 6);
    assert!(view.keys.windows(2).all(|k| k[0] <= k[1]));
    assert!(view.keys[..6]
        .iter()
        .all(|&k| key::phase(k) == key::PHASE_OPAQUE));
    assert_eq!(view.levels, vec![0; 9]);
}

/// Transmissive draws come after every opaque draw, nearest first, and before every blended
/// one, whatever their pipelines.
#[test]
fn transmissive_draws_sit_between_opaque_and_blended_nearest_first() {
    let glass = |material| Item {
        transmit: true,
        ..item(0, material, true, false)
    };
    let list = DrawList {
        shapes: vec![shape(vec![level(0, 3, 0.0)])],
        items: vec![
            glass(3),                // 0: glass, far
            item(0, 1, false, true), // 1: blended
            item(0, 0, true, false), // 2: opaque
            glass(3),                // 3: glass, near
            item(0, 2, true, false), // 4: opaque
        ],
    };
    let at = |z: f32| placed_at(Vec3::new(0.0, 0.0, z));
    let placed = [at(-6.0), at(-1.0), at(0.0), at(1.0), at(-2.0)];
    let c = camera();
    let view = list.color_view(&placed, &eye(&c), &[9, 0, 5, 9, 5]);
    assert_eq!(view.order, vec![2, 4, 3, 0, 1]);
    assert_eq!(key::second_phase(&view.keys), 2);
    assert_eq!(key::blended_phase(&view.keys), 4);
    assert_eq!(key::phase(view.keys[2]), key::PHASE_TRANSMISSIVE);
    assert_eq!(key::phase(view.keys[4]), key::PHASE_BLENDED);
}

/// The pipeline outranks every other field; material outranks culling, mesh and level; a value
/// too large for its field keeps its phase.
#[test]
fn opaque_keys_order_fields_by_significance() {
    let k = key::opaque;
    assert!(k(0, 9_999, true, 9_999, 9) < k(1, 0, false, 0, 0));
    assert!(k(3, 0, true, 9_999, 9) < k(3, 1, false, 0, 0));
    assert!(k(3, 1, false, 9_999, 9) < k(3, 1, true, 0, 0));
    assert!(k(3, 1, true, 4, 9) < k(3, 1, true, 5, 0));
    assert!(k(3, 1, true, 4, 1) < k(3, 1, true, 4, 2));
    let huge = k(u32::MAX, usize::MAX, true, usize::MAX, u8::MAX);
    assert_eq!(key::phase(huge), key::PHASE_OPAQUE);
    assert!(huge < key::blended(f32::MAX));
    // Back to front, whatever the depth's sign; `ordered` follows `total_cmp`.
    let depths = [-3.0f32, -0.0, 0.0, 1e-30, 2.5, 1e30, f32::INFINITY];
    for w in depths.windows(2) {
        assert!(key::ordered(w[0]) < key::ordered(w[1]), "{w:?}");
        assert!(key::blended(w[0]) > key::blended(w[1]), "{w:?}");
        assert!(key::depth(None, w[0]) < key::depth(None, w[1]), "{w:?}");
    }
}

/// A depth view draws its opaque casters first, nearest first, then the alpha-tested ones
/// grouped by material, each group nearest first.
#[test]
fn depth_views_draw_opaque_casters_front_to_back_first() {
    let list = DrawList {
        shapes: vec![shape(vec![level(0, 3, 0.0)])],
        items: vec![item(0, 0, true, false); 6],
    };
    let eye = DepthEye {
        view_proj: Mat4::orthographic_rh(-20.0, 20.0, -20.0, 20.0, 0.0, 100.0)
            * Mat4::look_to_rh(Vec3::new(0.0, 0.0, 50.0), Vec3::NEG_Z, Vec3::Y),
        texel: 0.01,
        perspective: false,
        origin: Vec3::new(0.0, 0.0, 50.0),
        axis: Vec3::NEG_Z,
    };
    // (z, alpha material): depth along the axis is 50 − z.
    let spec = [
        (0.0, None),
        (10.0, Some(3)),
        (20.0, None),
        (-10.0, Some(1)),
        (30.0, Some(3)),
        (-20.0, None),
    ];
    let casters: Vec<Caster> = spec
        .iter()
        .enumerate()
        .map(|(i, &(z, alpha))| {
            let p = placed_at(Vec3::new(0.0, 0.0, z));
            caster(i, &p, alpha.map(|m| (m, 0.5)))
        })
        .collect();
    let refs: Vec<&Caster> = casters.iter().collect();
    let draws = list.layer_view(&refs, &eye, 1.0);
    let clips: Vec<Mat4> = draws.iter().map(|d| d.clip).collect();
    let expected: Vec<Mat4> = [2, 0, 5, 3, 4, 1]
        .iter()
        .map(|&i| eye.view_proj * casters[i].model)
        .collect();
    assert_eq!(clips, expected);
    assert_eq!(
        draws
            .iter()
            .map(|d| d.alpha.map(|a| a.0))
            .collect::<Vec<_>>(),
        vec![None, None, None, Some(1), Some(3), Some(3)]
    );
}

fn caster(item: usize, p: &Placed, alpha: Option<(usize, f32)>) -> Caster {
    Caster {
        item,
        scale: p.scale,
        model: p.model,
        sphere: p.sphere,
        tight: p.tight,
        plane: None,
        receiver: None,
        alpha,
    }
}

/// The camera's LOD choice: full detail near, coarser levels farther away (never finer), the
/// full mesh with a zero budget or a single level, and the scene's `choose` of each.
#[test]
fn lod_levels_coarsen_with_distance() {
    let levels = vec![
        level(0, 3000, 0.0),
        level(3000, 1500, 0.001),
        level(4500, 600, 0.01),
        level(5100, 90, 0.1),
    ];
    let list = DrawList {
        shapes: vec![shape(levels.clone()), shape(vec![level(0, 30, 0.0)])],
        items: vec![item(0, 0, true, false), item(1, 0, true, false)],
    };
    let c = camera();
    let mut e = eye(&c);
    let mut last = 0;
    for z in [9.0f32, 5.0, 0.0, -20.0, -100.0, -500.0] {
        let p = placed_at(Vec3::new(0.0, 0.0, z));
        let l = list.camera_level(0, &p, &e);
        let distance = crate::scene::lod::camera_distance(&c, p.sphere.center, 1.0);
        let want = crate::scene::lod::choose(&levels, 1.0, e.focal_px, distance, 1.0);
        assert_eq!(usize::from(l), want, "z {z}");
        assert!(l >= last, "z {z}: level {l} finer than {last}");
        last = l;
        assert_eq!(list.camera_level(1, &p, &e), 0);
    }
    assert_eq!(last, 3, "the farthest draws the coarsest level");
    let touching = list.camera_level(0, &placed_at(Vec3::new(0.0, 0.0, 9.5)), &e);
    assert_eq!(touching, 0, "at the eye: full detail");
    e.budget = 0.0;
    let far = placed_at(Vec3::new(0.0, 0.0, -500.0));
    assert_eq!(
        list.camera_level(0, &far, &e),
        0,
        "zero budget: full detail"
    );
    // The levels the colour view records, and the triangles they hold.
    let placed = [far, placed_at(Vec3::ZERO)];
    let view = list.color_view(&placed, &eye(&c), &[0, 0]);
    assert_eq!(view.levels, vec![3, 0]);
    assert_eq!(list.triangles(&view.order, &view.levels), 30 + 10);
}

/// A caster as a layer draws it: its item, index range and alpha test.
type Drawn = (usize, (u32, u32), Option<(usize, f32)>);

/// A shadow layer's view holds the casters, levels and matrices the shadow pass drew before the
/// draw list (each caster whose sphere meets the layer's volume, at `layer_level`), for random
/// casters under orthographic and perspective layers.
#[test]
fn layer_views_cull_to_the_casters_drawn_before() {
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    let levels = vec![
        level(0, 300, 0.0),
        level(300, 120, 0.02),
        level(420, 30, 0.2),
    ];
    let list = DrawList {
        shapes: vec![shape(levels), shape(vec![level(0, 36, 0.0)])],
        items: (0..200).map(|i| item(i % 2, i % 3, true, false)).collect(),
    };
    let casters: Vec<Caster> = (0..200)
        .map(|i| {
            let pos = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * 60.0;
            let s = 0.2 + 3.0 * next();
            let model = Mat4::from_scale_rotation_translation(
                Vec3::splat(s),
                glam::Quat::from_rotation_y(next() * 6.0),
                pos,
            );
            let p = Placed {
                model,
                scale: frustum::max_scale(model),
                sphere: Sphere {
                    center: pos,
                    radius: s,
                },
                tight: Sphere {
                    center: pos,
                    radius: s,
                },
            };
            caster(i, &p, (i % 5 == 0).then_some((i % 3, 0.5)))
        })
        .collect();
    let refs: Vec<&Caster> = casters.iter().collect();
    let light = Vec3::new(3.0, 20.0, 4.0);
    let eyes = [
        DepthEye {
            view_proj: Mat4::orthographic_rh(-15.0, 15.0, -10.0, 12.0, 0.0, 80.0)
                * Mat4::look_to_rh(light, Vec3::new(0.2, -1.0, 0.1).normalize(), Vec3::Z),
            texel: 0.03,
            perspective: false,
            origin: light,
            axis: Vec3::new(0.2, -1.0, 0.1).normalize(),
        },
        DepthEye {
            view_proj: Mat4::perspective_infinite_reverse_rh(1.2, 1.0, 0.05)
                * Mat4::look_to_rh(light, Vec3::NEG_Y, Vec3::Z),
            texel: 0.002,
            perspective: true,
            origin: light,
            axis: Vec3::NEG_Y,
        },
    ];
    for (k, eye) in eyes.iter().enumerate() {
        // The shadow pass's culling before the draw list (render/shadow/mod.rs).
        let planes = frustum::planes(eye.view_proj);
        let before: Vec<Drawn> = casters
            .iter()
            .filter(|c| frustum::sphere_visible(&planes, c.sphere.center, c.sphere.radius))
            .map(|c| {
                let shape = list.items[c.item].shape;
                let ls = &list.shapes[shape].levels;
                let l = ls[layer_level(ls, c.scale, c.sphere, eye, 1.0)];
                (c.item, (l.first_index, l.index_count), c.alpha)
            })
            .collect();
        let draws = list.layer_view(&refs, eye, 1.0);
        let mut now: Vec<Drawn> = draws
            .iter()
            .map(|d| {
                let c = casters
                    .iter()
                    .find(|c| eye.view_proj * c.model == d.clip)
                    .expect("a caster's matrix");
                assert_eq!(d.mesh, list.items[c.item].shape);
                (c.item, d.range, d.alpha)
            })
            .collect();
        now.sort_by_key(|d| d.0);
        assert_eq!(now, before, "layer {k}");
        assert!(
            before.len() > 10 && before.len() < casters.len(),
            "layer {k}: {}",
            before.len()
        );
        let coarse = before.iter().filter(|d| d.1 .0 > 0).count();
        assert!(k == 1 || coarse > 0, "layer {k}: no coarser level chosen");
    }
}

/// Runs join neighbours the predicate calls one draw, never across a different one, and
/// every entry is a run of its own when instancing is off.
#[test]
fn runs_join_adjacent_instances_only() {
    let order = [4, 5, 6, 1, 7, 8];
    let group = |i: usize| if i >= 4 { i / 2 } else { 100 + i };
    let same = |a: usize, b: usize| group(a) == group(b);
    assert_eq!(
        runs(&order, true, same),
        vec![(0, 2), (2, 1), (3, 1), (4, 1), (5, 1)]
    );
    let order = [4, 5, 8, 9];
    let same = |a: usize, b: usize| group(a) == group(b);
    assert_eq!(runs(&order, true, same), vec![(0, 2), (2, 2)]);
    assert_eq!(
        runs(&order, false, same),
        vec![(0, 1), (1, 1), (2, 1), (3, 1)]
    );
}
