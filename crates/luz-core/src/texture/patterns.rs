//! Procedural images for tests: checkerboards and noise normal maps.

use glam::Vec3;
use image::RgbaImage;
use rayon::prelude::*;

/// A `size`×`size` checkerboard of `cells`×`cells` squares, colour `a` in the top-left square.
/// With `cells == size` every texel alternates.
pub fn checker(size: u32, cells: u32, a: [u8; 4], b: [u8; 4]) -> RgbaImage {
    let cells = cells.clamp(1, size.max(1));
    RgbaImage::from_fn(size, size, |x, y| {
        let cx = u64::from(x) * u64::from(cells) / u64::from(size);
        let cy = u64::from(y) * u64::from(cells) / u64::from(size);
        image::Rgba(if (cx + cy) % 2 == 0 { a } else { b })
    })
}

/// A tileable tangent-space normal map, `size`×`size`, from value noise of period 8 cells
/// (two octaves) seeded by `seed`. `strength` scales the slopes (0 gives a flat map, every
/// texel (128, 128, 255); 1 tilts up to about 50°). Normals follow the glTF convention (+Y up
/// in the image) and are encoded as round((n + 1) / 2 · 255): each decodes to a unit vector
/// within 8-bit quantisation, with z > 0.
pub fn noise_normal_map(size: u32, seed: u64, strength: f32) -> RgbaImage {
    const PERIOD: u32 = 8;
    let size = size.max(1);
    let hash = |x: u32, y: u32, octave: u32| -> f32 {
        let mut h = seed
            ^ (u64::from(x) << 1)
            ^ (u64::from(y) << 21)
            ^ (u64::from(octave) << 42)
            ^ 0x9e37_79b9_7f4a_7c15;
        h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h ^= h >> 31;
        (h >> 40) as f32 / (1u64 << 24) as f32
    };
    // Periodic value noise at (u, v) in [0, 1)²: `period` lattice cells per side, smoothstep
    // interpolation.
    let noise = |u: f32, v: f32, period: u32, octave: u32| -> f32 {
        let (x, y) = (u * period as f32, v * period as f32);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (sx, sy) = (fx * fx * (3.0 - 2.0 * fx), fy * fy * (3.0 - 2.0 * fy));
        let (ix, iy) = (
            (x0 as i64).rem_euclid(period as i64) as u32,
            (y0 as i64).rem_euclid(period as i64) as u32,
        );
        let (jx, jy) = ((ix + 1) % period, (iy + 1) % period);
        let a = hash(ix, iy, octave) + (hash(jx, iy, octave) - hash(ix, iy, octave)) * sx;
        let b = hash(ix, jy, octave) + (hash(jx, jy, octave) - hash(ix, jy, octave)) * sx;
        a + (b - a) * sy
    };
    let height = |x: u32, y: u32| -> f32 {
        let (u, v) = (x as f32 / size as f32, y as f32 / size as f32);
        noise(u, v, PERIOD, 0) + 0.5 * noise(u, v, 2 * PERIOD, 1)
    };
    let heights: Vec<f32> = (0..size * size)
        .into_par_iter()
        .map(|i| height(i % size, i / size))
        .collect();
    let at = |x: i64, y: i64| -> f32 {
        let s = i64::from(size);
        heights[(y.rem_euclid(s) * s + x.rem_euclid(s)) as usize]
    };
    // Slopes per lattice cell of the first octave.
    let cell = size as f32 / PERIOD as f32;
    RgbaImage::from_fn(size, size, |x, y| {
        let (x, y) = (i64::from(x), i64::from(y));
        let dx = (at(x + 1, y) - at(x - 1, y)) * 0.5 * cell;
        let dy_down = (at(x, y + 1) - at(x, y - 1)) * 0.5 * cell;
        // Image rows go down; +Y of the normal is up, so ∂h/∂up = −∂h/∂row.
        let n = Vec3::new(-strength * dx, strength * dy_down, 1.0).normalize();
        let e = (n + Vec3::ONE) * 0.5 * 255.0;
        image::Rgba([e.x.round() as u8, e.y.round() as u8, e.z.round() as u8, 255])
    })
}
