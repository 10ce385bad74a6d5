//! Receiver splits: a flat draw whose shadow lookups are needed only in part of the screen is
//! recorded in parts, with the shadowed pipeline inside the screen rectangle shadows can reach
//! and the unshadowed one around it.

use ash::vk;

/// Flat draws of at most this many triangles are split where shadows can fall on them
/// (`ForwardPass::receive_slots`): each part runs the vertex stage again, which a floor of a
/// few hundred triangles repays many times over in fragments that skip the lookups, a mesh of
/// millions would not.
pub const SPLIT_TRIANGLES: u32 = 4096;

/// Whether a draw of `shape` is split where shadows can fall on it (its lookups per pixel:
/// `phong`): a flat mesh of at most [`SPLIT_TRIANGLES`] triangles. Flat and Gouraud light in the
/// vertex stage: a triangle across the rectangle's edge carries its vertices' shadows beyond it.
pub fn splits(shape: &super::Shape, phong: bool) -> bool {
    shape.plane.is_some() && shape.levels[0].index_count / 3 <= SPLIT_TRIANGLES && phong
}

/// The NDC rectangle (x0, y0, x1, y1) that world box `(lo, hi)` covers under `view_proj`
/// (empty when it is off screen); `None` when a corner is behind the eye (the whole screen).
pub fn ndc_rect((lo, hi): (glam::Vec3, glam::Vec3), view_proj: glam::Mat4) -> Option<[f32; 4]> {
    let mut r = [
        f32::INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NEG_INFINITY,
    ];
    for p in crate::render::frustum::box_corners(glam::Mat4::IDENTITY, (lo, hi)) {
        let c = view_proj * p.extend(1.0);
        if c.w.is_nan() || c.w <= 1e-6 {
            return None;
        }
        let (x, y) = (c.x / c.w, c.y / c.w);
        r = [r[0].min(x), r[1].min(y), r[2].max(x), r[3].max(y)];
    }
    Some([r[0].max(-1.0), r[1].max(-1.0), r[2].min(1.0), r[3].min(1.0)])
}

/// The scissors a draw whose shadow lookups are needed only inside `ndc` (x0, y0, x1, y1 in
/// normalised device coordinates; empty when x0 ≥ x1 or y0 ≥ y1) is recorded with inside the
/// caller's `area`: the area's pixels that `ndc` touches, grown by a pixel (`true`: the shadowed
/// pipeline), and the bands around them (`false`: the unshadowed one). The parts tile `area`
/// without overlap, so each pixel is shaded once.
pub fn split(ndc: [f32; 4], area: vk::Rect2D) -> Vec<(vk::Rect2D, bool)> {
    let (x, y) = (area.offset.x as i64, area.offset.y as i64);
    let (w, h) = (area.extent.width as i64, area.extent.height as i64);
    let px = |v: f32, size: i64, round: fn(f64) -> f64| {
        let p = round((f64::from(v) * 0.5 + 0.5) * size as f64) as i64;
        p.clamp(0, size)
    };
    let (x0, x1) = (px(ndc[0], w, f64::floor), px(ndc[2], w, f64::ceil));
    let (y0, y1) = (px(ndc[1], h, f64::floor), px(ndc[3], h, f64::ceil));
    // Nothing on screen (before growing by a pixel): one unshadowed part.
    let off = x0 >= x1 || y0 >= y1;
    let (x0, x1, y0, y1) = (
        (x0 - 1).max(0),
        (x1 + 1).min(w),
        (y0 - 1).max(0),
        (y1 + 1).min(h),
    );
    let rect = |(ax, ay, bx, by): (i64, i64, i64, i64), shadowed: bool| {
        (bx > ax && by > ay).then_some((
            vk::Rect2D {
                offset: vk::Offset2D {
                    x: (x + ax) as i32,
                    y: (y + ay) as i32,
                },
                extent: vk::Extent2D {
                    width: (bx - ax) as u32,
                    height: (by - ay) as u32,
                },
            },
            shadowed,
        ))
    };
    if off || ndc[0] >= ndc[2] || ndc[1] >= ndc[3] {
        return rect((0, 0, w, h), false).into_iter().collect();
    }
    [
        rect((x0, y0, x1, y1), true),
        rect((0, 0, w, y0), false),
        rect((0, y1, w, h), false),
        rect((0, y0, x0, y1), false),
        rect((x1, y0, w, y1), false),
    ]
    .into_iter()
    .flatten()
    .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(w: u32, h: u32) -> vk::Rect2D {
        vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: vk::Extent2D {
                width: w,
                height: h,
            },
        }
    }

    /// The parts of a split tile the area exactly: every pixel in one part, the shadowed part
    /// holding the NDC rectangle (grown by a pixel), an empty or off-screen rectangle leaving
    /// one unshadowed part, a rectangle over everything one shadowed part.
    #[test]
    fn split_parts_tile_the_area_once() {
        let (w, h) = (64u32, 36u32);
        let cases: [[f32; 4]; 5] = [
            [-0.5, -0.25, 0.5, 0.75],
            [-1.0, -1.0, 1.0, 1.0],
            [0.2, 0.2, 0.1, 0.9],
            [2.0, 2.0, 3.0, 3.0],
            [-3.0, 0.0, 0.0, 3.0],
        ];
        for ndc in cases {
            let parts = split(ndc, area(w, h));
            let mut hits = vec![0u8; (w * h) as usize];
            for (r, _) in &parts {
                for py in r.offset.y..r.offset.y + r.extent.height as i32 {
                    for px in r.offset.x..r.offset.x + r.extent.width as i32 {
                        hits[(py as u32 * w + px as u32) as usize] += 1;
                    }
                }
            }
            assert!(hits.iter().all(|&n| n == 1), "{ndc:?}: {parts:?}");
            let shadowed: Vec<_> = parts.iter().filter(|p| p.1).collect();
            let visible = ndc[0] < ndc[2] && ndc[1] < ndc[3] && ndc[0] < 1.0 && ndc[2] > -1.0;
            assert_eq!(shadowed.len(), usize::from(visible), "{ndc:?}");
        }
        let parts = split([-0.5, -0.25, 0.5, 0.75], area(w, h));
        let inside = parts.iter().find(|p| p.1).unwrap().0;
        // x: 16..48 grown to 15..49; y: 13.5..31.5 → 13..32 grown to 12..33.
        assert_eq!((inside.offset.x, inside.offset.y), (15, 12));
        assert_eq!((inside.extent.width, inside.extent.height), (34, 21));
        assert_eq!(
            split([-1.0, -1.0, 1.0, 1.0], area(w, h)),
            vec![(area(w, h), true)]
        );
    }
}
