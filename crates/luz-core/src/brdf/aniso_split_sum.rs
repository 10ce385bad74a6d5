//! The split sum of KHR_materials_anisotropy's lobe (issue 34): the single-scattering albedo of
//! the anisotropic GGX lobe, `E_ss = F0·A + F90·B`, as [`super::split_sum`] holds it for the
//! isotropic lobe, but over the view's azimuth in the lobe's frame and the anisotropy strength
//! too: the isotropic table read at one "equivalent roughness" cannot follow the lobe's
//! dependence on the azimuth (a smooth dielectric of strength 0.5 seen at 85° across its lobe
//! returned 1.40 in a compensated white furnace).
//!
//! The lobe is luz's ([`super::anisotropic_lobe`]): `α = max(roughness², ALPHA_MIN)`,
//! `α_t = mix(α, 1, strength²)`, `α_b = α`, with `D` = [`super::d_gtr2_aniso`] and `G` the
//! height-correlated anisotropic Smith term [`super::g_smith_ggx_correlated_aniso`]. By symmetry
//! (the lobe is even in `t·v` and in `b·v`) the azimuth `φ = atan2(|b·v|, |t·v|)` spans
//! `[0, π/2]`.
//!
//! Layout ([`ANISO_LUT_NV`] × [`ANISO_LUT_ROUGHNESS`] × [`ANISO_LUT_PHI`] ×
//! [`ANISO_LUT_STRENGTH`] entries `[A, B]`, [`aniso_lut_coords`], [`aniso_lut_index`]): slice
//! `(k, m)` (azimuth and strength) is a 2D table over `(n·v, roughness)` like the isotropic one.
//! [`aniso_split_sum_ab`] reads it multilinearly; the GPU reads the same entries from an extra
//! layer of `brdf_lut`, slices as tiles (`luz-gpu`'s `ibl::aniso_lut_layer`).
//!
//! It is computed by VNDF sampling (each sample weighs `G2/G1(v) ≤ 1`, so smooth lobes and
//! grazing views converge) and shipped ([`ANISO_LUT_FILE`], checked by `shipped_aniso_lut_regenerates`);
//! its size, sample count and measured error are in docs/brdf.md.

use std::sync::OnceLock;

use glam::Vec3;
use rayon::prelude::*;

use super::{g_smith_ggx_correlated_aniso, hammersley, ALPHA_MIN, COS_EPS, PI};

use crate::glsl::include_ibl as glsl;

// The grid's sizes are `shaders_glsl/include/ibl.glsl`'s (the GPU reads the same tiles).
/// Columns of a slice: `sqrt(n·v)` uniform over `[0, 1]`.
pub const ANISO_LUT_NV: usize = glsl::ANISO_LUT_NV as usize;
/// Rows of a slice: perceptual roughness uniform over `[0, 1]`.
pub const ANISO_LUT_ROUGHNESS: usize = glsl::ANISO_LUT_ROUGHNESS as usize;
/// Azimuths of the view in the lobe's frame: `1 − cos φ` uniform over `[0, 1]`.
pub const ANISO_LUT_PHI: usize = glsl::ANISO_LUT_PHI as usize;
/// Strengths, uniform over `[0, 1]`.
pub const ANISO_LUT_STRENGTH: usize = glsl::ANISO_LUT_STRENGTH as usize;
/// VNDF samples per entry.
pub const ANISO_LUT_SAMPLES: u32 = 512;

/// A visible normal of the anisotropic GGX lobe `(α_x, α_y)` seen from `v` (+z normal),
/// Heitz 2018: its pdf is `G1(v) max(v·h, 0) D(h) / (n·v)`.
pub fn sample_ggx_vndf_aniso(v: Vec3, ax: f32, ay: f32, u1: f32, u2: f32) -> Vec3 {
    let vh = Vec3::new(ax * v.x, ay * v.y, v.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
    } else {
        Vec3::X
    };
    let t2 = vh.cross(t1);
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3::new(ax * nh.x, ay * nh.y, nh.z.max(0.0)).normalize()
}

/// The lobe's widths `(α_t, α_b)` at perceptual `roughness` and `strength`, as
/// [`super::anisotropic_lobe`] sets them.
pub fn aniso_widths(roughness: f32, strength: f32) -> (f32, f32) {
    let a = (roughness * roughness).max(ALPHA_MIN);
    (a + (1.0 - a) * strength * strength, a)
}

/// The anisotropic split sum `(A, B)` by Monte Carlo: `t = +x`, `b = +y`, `n = +z`,
/// `v = (sinθ cosφ, sinθ sinφ, n·v)`, `samples` visible normals on Hammersley points,
/// `l = reflect(−v, h)`, weight `G2(v, l)/G1(v)` for `n·l > 0`, `Fc = (1 − v·h)^5`,
/// `A = mean((1 − Fc) w)`, `B = mean(Fc w)`. `n·v` clamped to at least `COS_EPS`.
pub fn aniso_split_sum_reference(
    n_v: f32,
    phi: f32,
    roughness: f32,
    strength: f32,
    samples: u32,
) -> (f32, f32) {
    let n_v = n_v.clamp(COS_EPS, 1.0);
    let sin = (1.0 - n_v * n_v).max(0.0).sqrt();
    let v = Vec3::new(sin * phi.cos(), sin * phi.sin(), n_v);
    let (at, ab) = aniso_widths(roughness.clamp(0.0, 1.0), strength.clamp(0.0, 1.0));
    let g1 = 2.0 * n_v / (n_v + Vec3::new(at * v.x, ab * v.y, n_v).length());
    let samples = samples.max(1);
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for i in 0..samples {
        let (u1, u2) = hammersley(i, samples);
        let h = sample_ggx_vndf_aniso(v, at, ab, u1, u2);
        let v_h = v.dot(h);
        if v_h <= 0.0 {
            continue;
        }
        let l = h * (2.0 * v_h) - v;
        if l.z <= 0.0 {
            continue;
        }
        let g2 = g_smith_ggx_correlated_aniso(l.z, n_v, l.x, l.y, v.x, v.y, at, ab);
        let w = f64::from(g2 / g1);
        let fc = f64::from((1.0 - v_h).clamp(0.0, 1.0).powi(5));
        a += (1.0 - fc) * w;
        b += fc * w;
    }
    let n = f64::from(samples);
    ((a / n) as f32, (b / n) as f32)
}

/// The grid's coordinates of entry `(i, j, k, m)`: `(n·v, roughness, φ, strength)`. Every grid
/// holds both its ends; `n·v = (i/(N − 1))²` (denser towards grazing, where a smooth lobe's
/// albedo changes fastest), the roughness uniform, `cos φ = 1 − k/(N_φ − 1)` (the Smith term of
/// a stretched smooth lobe is about linear in `cos φ`), the strength uniform (denser in `α_t`
/// near 0 than a grid in `strength²`). Each choice measured against the alternatives
/// (docs/brdf.md).
pub fn aniso_lut_coords(i: usize, j: usize, k: usize, m: usize) -> (f32, f32, f32, f32) {
    let u = i as f32 / (ANISO_LUT_NV - 1) as f32;
    let r = j as f32 / (ANISO_LUT_ROUGHNESS - 1) as f32;
    let phi = (1.0 - k as f32 / (ANISO_LUT_PHI - 1) as f32).acos();
    let s = m as f32 / (ANISO_LUT_STRENGTH - 1) as f32;
    (u * u, r, phi, s)
}

/// Index of entry `(i, j, k, m)` in [`aniso_lut`]: slices `(k, m)` of `N_nv × N_r`, row-major,
/// azimuth fastest.
pub fn aniso_lut_index(i: usize, j: usize, k: usize, m: usize) -> usize {
    ((m * ANISO_LUT_PHI + k) * ANISO_LUT_ROUGHNESS + j) * ANISO_LUT_NV + i
}

/// The whole table at `samples` per entry, in [`aniso_lut_index`] order.
pub fn aniso_lut_table(samples: u32) -> Vec<[f32; 2]> {
    let n = ANISO_LUT_NV * ANISO_LUT_ROUGHNESS * ANISO_LUT_PHI * ANISO_LUT_STRENGTH;
    (0..n)
        .into_par_iter()
        .map(|idx| {
            let i = idx % ANISO_LUT_NV;
            let j = (idx / ANISO_LUT_NV) % ANISO_LUT_ROUGHNESS;
            let k = (idx / (ANISO_LUT_NV * ANISO_LUT_ROUGHNESS)) % ANISO_LUT_PHI;
            let m = idx / (ANISO_LUT_NV * ANISO_LUT_ROUGHNESS * ANISO_LUT_PHI);
            let (n_v, r, phi, s) = aniso_lut_coords(i, j, k, m);
            let (a, b) = aniso_split_sum_reference(n_v, phi, r, s, samples);
            [a, b]
        })
        .collect()
}

/// Where the generator writes the shipped table, relative to the luz-core crate:
/// [`aniso_lut_table`]`(`[`ANISO_LUT_SAMPLES`]`)` as little-endian `f32` pairs `(A, B)` in
/// [`aniso_lut_index`] order (`cargo run --release -p luz-core --example aniso_lut`).
pub const ANISO_LUT_FILE: &str = "data/aniso_split_sum_32x32x6x16_512.bin";

static SHIPPED: &[u8] = include_bytes!("../../data/aniso_split_sum_32x32x6x16_512.bin");

/// Entries of the table.
const ANISO_LUT_ENTRIES: usize =
    ANISO_LUT_NV * ANISO_LUT_ROUGHNESS * ANISO_LUT_PHI * ANISO_LUT_STRENGTH;

/// The shipped table's entries, or None when the file does not hold this grid (a grid changed
/// without regenerating it: then [`aniso_lut`] computes the table).
pub fn shipped_aniso_lut() -> Option<Vec<[f32; 2]>> {
    if SHIPPED.len() != ANISO_LUT_ENTRIES * 8 {
        return None;
    }
    let f = |b: &[u8]| f32::from_le_bytes(b.try_into().expect("4 bytes"));
    Some(
        SHIPPED
            .chunks_exact(8)
            .map(|c| [f(&c[..4]), f(&c[4..])])
            .collect(),
    )
}

/// The bytes of the table, computed now (what the generator writes).
pub fn generate_aniso_lut() -> Vec<u8> {
    aniso_lut_table(ANISO_LUT_SAMPLES)
        .iter()
        .flat_map(|[a, b]| a.to_le_bytes().into_iter().chain(b.to_le_bytes()))
        .collect()
}

/// The table at [`ANISO_LUT_SAMPLES`]: the shipped one (computing it took 2–3 s on 2 cores),
/// else computed once per process.
pub fn aniso_lut() -> &'static [[f32; 2]] {
    static TABLE: OnceLock<Vec<[f32; 2]>> = OnceLock::new();
    TABLE.get_or_init(|| shipped_aniso_lut().unwrap_or_else(|| aniso_lut_table(ANISO_LUT_SAMPLES)))
}

/// The view's azimuth in the lobe's frame folded into `[0, π/2]`: `atan2(|b·v|, |t·v|)`
/// (0 along the normal).
pub fn aniso_azimuth(t_v: f32, b_v: f32) -> f32 {
    let (x, y) = (t_v.abs(), b_v.abs());
    if x + y <= 0.0 {
        0.0
    } else {
        y.atan2(x)
    }
}

/// `(i0, i1, f)` of `x ∈ [0, 1]` over a grid of `n` points holding both ends.
fn ends(x: f32, n: usize) -> (usize, usize, f32) {
    let x = if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let p = x * (n - 1) as f32;
    let i = (p.floor() as usize).min(n - 2);
    (i, i + 1, p - i as f32)
}

/// The anisotropic split sum `(A, B)` at `(n·v, φ, roughness, strength)` from [`aniso_lut`]:
/// multilinear in `(sqrt(n·v), roughness, 1 − cos φ, strength)` ([`aniso_lut_coords`]; `φ` folded
/// into `[0, π/2]` by the caller, [`aniso_azimuth`]), clamped at the ends.
pub fn aniso_split_sum_ab(n_v: f32, phi: f32, roughness: f32, strength: f32) -> (f32, f32) {
    let t = aniso_lut();
    let (i0, i1, fx) = ends(n_v.max(0.0).sqrt(), ANISO_LUT_NV);
    let (j0, j1, fy) = ends(roughness, ANISO_LUT_ROUGHNESS);
    let (k0, k1, fk) = ends(1.0 - phi.cos(), ANISO_LUT_PHI);
    let (m0, m1, fm) = ends(strength, ANISO_LUT_STRENGTH);
    let lerp =
        |a: [f32; 2], b: [f32; 2], f: f32| [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f];
    let slice = |k: usize, m: usize| {
        let at = |i: usize, j: usize| t[aniso_lut_index(i, j, k, m)];
        lerp(
            lerp(at(i0, j0), at(i1, j0), fx),
            lerp(at(i0, j1), at(i1, j1), fx),
            fy,
        )
    };
    let ab = lerp(
        lerp(slice(k0, m0), slice(k1, m0), fk),
        lerp(slice(k0, m1), slice(k1, m1), fk),
        fm,
    );
    (ab[0], ab[1])
}

/// Slices a texel of the GPU's layers holds: two, `(A, B)` in RG and in BA.
const SLICES_PER_TEXEL: usize = 2;

/// The tiles of the anisotropic table: each a `N_nv × N_r` block of texels holding two slices
/// (`q = m·N_φ + k` even in RG, the next in BA), tile `q/2` at column `tile % per_row`, row
/// `(tile % per_layer)/per_row` of layer `tile/per_layer` (`per_row = size/N_nv`,
/// `per_layer = per_row²`). Returns `(per_row, layers)` for a `size × size` array image.
pub fn aniso_lut_tiles(size: u32) -> (usize, usize) {
    let per_row = (size as usize / ANISO_LUT_NV).max(1);
    let tiles = (ANISO_LUT_PHI * ANISO_LUT_STRENGTH).div_ceil(SLICES_PER_TEXEL);
    (per_row, tiles.div_ceil(per_row * per_row))
}

/// The anisotropic table as layers of a `size × size` RGBA array image ([`aniso_lut_tiles`]):
/// the GPU reads entry `(i, j)` of a slice at texel `(tile_x·N_nv + i, tile_y·N_r + j)`, so
/// that its bilinear filter between texel centres is [`aniso_split_sum_ab`]'s. Texels outside
/// the tiles are 0.
pub fn aniso_lut_layers(size: u32) -> Vec<Vec<[f32; 4]>> {
    let (per_row, layers) = aniso_lut_tiles(size);
    let size = size as usize;
    let per_layer = per_row * per_row;
    let t = aniso_lut();
    let mut out = vec![vec![[0.0f32; 4]; size * size]; layers];
    for m in 0..ANISO_LUT_STRENGTH {
        for k in 0..ANISO_LUT_PHI {
            let q = m * ANISO_LUT_PHI + k;
            let (tile, c) = (q / SLICES_PER_TEXEL, 2 * (q % SLICES_PER_TEXEL));
            let layer = &mut out[tile / per_layer];
            let (tx, ty) = ((tile % per_layer) % per_row, (tile % per_layer) / per_row);
            for j in 0..ANISO_LUT_ROUGHNESS {
                for i in 0..ANISO_LUT_NV {
                    let (x, y) = (tx * ANISO_LUT_NV + i, ty * ANISO_LUT_ROUGHNESS + j);
                    let ab = t[aniso_lut_index(i, j, k, m)];
                    layer[y * size + x][c] = ab[0];
                    layer[y * size + x][c + 1] = ab[1];
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped table is the generator's output, not a hand-copied blob: every 7th entry
    /// (14,044 of 98,304, every slice's kinds: grazing and normal views, smooth and rough lobes,
    /// each azimuth and strength) computed again as the generator computes it equals the shipped
    /// value within 1e-6 (a last-bit difference of another libm's sin/cos; on the machine that
    /// made it, exact). And the table is shipped: its size is this grid's.
    #[test]
    fn shipped_aniso_lut_regenerates() {
        let table = shipped_aniso_lut().unwrap_or_else(|| {
            panic!("{ANISO_LUT_FILE} does not hold this grid: regenerate it with `cargo run --release -p luz-core --example aniso_lut`")
        });
        let worst = (0..ANISO_LUT_ENTRIES)
            .into_par_iter()
            .step_by(7)
            .map(|idx| {
                let i = idx % ANISO_LUT_NV;
                let j = (idx / ANISO_LUT_NV) % ANISO_LUT_ROUGHNESS;
                let k = (idx / (ANISO_LUT_NV * ANISO_LUT_ROUGHNESS)) % ANISO_LUT_PHI;
                let m = idx / (ANISO_LUT_NV * ANISO_LUT_ROUGHNESS * ANISO_LUT_PHI);
                assert_eq!(aniso_lut_index(i, j, k, m), idx);
                let (n_v, r, phi, s) = aniso_lut_coords(i, j, k, m);
                let (a, b) = aniso_split_sum_reference(n_v, phi, r, s, ANISO_LUT_SAMPLES);
                let [ta, tb] = table[idx];
                (ta - a).abs().max((tb - b).abs())
            })
            .reduce(|| 0.0f32, f32::max);
        assert!(
            worst <= 1e-6,
            "{ANISO_LUT_FILE} differs from a fresh generation by {worst}; regenerate it with \
             `cargo run --release -p luz-core --example aniso_lut`"
        );
        assert!(std::ptr::eq(aniso_lut(), aniso_lut()));
        assert_eq!(aniso_lut(), &table[..]);
    }
}
