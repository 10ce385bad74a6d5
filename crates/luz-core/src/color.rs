//! Colour pipeline on the CPU: exposure, tone mapping and exact sRGB transfer functions.
//!
//! Light is carried in linear RGB everywhere (MODELS.md §9). For display the order is always
//! **exposure → tone map → clamp → sRGB encode → round** ([`to_display_rgba8`]). The unclamped
//! linear float image is kept separately for measurement (EXR output, `luz diff`).

use std::sync::OnceLock;

use serde::{Deserialize, Serialize};

/// Tone-mapping operator applied after exposure and before sRGB encoding.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default, Serialize, Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum Tonemap {
    /// Clamp to [0, 1] only.
    #[default]
    None,
    /// x / (1 + x) per channel.
    Reinhard,
    /// Narkowicz's fitted ACES filmic curve.
    Aces,
    /// Khronos PBR Neutral.
    KhronosNeutral,
    /// Troy Sobotka's AgX, base look (the polynomial fit of its default contrast).
    Agx,
}

/// The largest input the non-identity tone mappers look at: the largest finite value of an
/// IEEE half float (what an RGBA16F render target can hold). Larger values and +Inf are clamped
/// to it so the rational curves never evaluate `inf / inf`.
pub const TONEMAP_INPUT_MAX: f32 = 65504.0;

impl Tonemap {
    /// Every operator, in a stable order (CLI help, UI combo boxes, tests).
    pub const ALL: [Tonemap; 5] = [
        Tonemap::None,
        Tonemap::Reinhard,
        Tonemap::Aces,
        Tonemap::KhronosNeutral,
        Tonemap::Agx,
    ];

    /// The name used on the command line and in scene files (same as the serde name).
    pub fn name(self) -> &'static str {
        match self {
            Tonemap::None => "none",
            Tonemap::Reinhard => "reinhard",
            Tonemap::Aces => "aces",
            Tonemap::KhronosNeutral => "khronos_neutral",
            Tonemap::Agx => "agx",
        }
    }

    /// Parses a name as printed by [`Tonemap::name`]; case-insensitive, `-` accepted for `_`.
    pub fn parse(s: &str) -> Option<Self> {
        let wanted = s.trim().to_ascii_lowercase().replace('-', "_");
        Self::ALL.into_iter().find(|t| t.name() == wanted)
    }

    /// Applies the operator to one linear RGB triple (already multiplied by the exposure scale).
    ///
    /// * `None` is the identity: no clamping here, clamping happens at encode time.
    /// * The other operators are defined on [0, ∞): each channel is first sanitised
    ///   (NaN → 0, negatives → 0, values above [`TONEMAP_INPUT_MAX`] and +Inf → that maximum).
    /// * `Reinhard`: x / (1 + x) per channel.
    /// * `Aces`: Krzysztof Narkowicz, "ACES Filmic Tone Mapping Curve" (2016):
    ///   `saturate(x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14))` applied to `0.6 · x`. The fitted
    ///   curve is fitted to input pre-scaled by 0.6 (Narkowicz's note: this matches the exposure
    ///   of the reference ACES RRT+ODT), so the 0.6 is part of the operator, not of the exposure.
    /// * `KhronosNeutral`: the Khronos PBR Neutral operator, transcribed from the reference GLSL
    ///   (KhronosGroup/ToneMapping, `PBR_Neutral`): start compression 0.8 − 0.04, desaturation 0.15.
    /// * `Agx`: see [`agx`].
    pub fn apply(self, rgb: [f32; 3]) -> [f32; 3] {
        match self {
            Tonemap::None => rgb,
            Tonemap::Reinhard => sanitize(rgb).map(|x| x / (1.0 + x)),
            Tonemap::Aces => sanitize(rgb).map(aces_narkowicz),
            Tonemap::KhronosNeutral => khronos_pbr_neutral(sanitize(rgb)),
            Tonemap::Agx => agx(sanitize(rgb)),
        }
    }
}

impl std::fmt::Display for Tonemap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

fn sanitize(rgb: [f32; 3]) -> [f32; 3] {
    rgb.map(|c| {
        if c.is_nan() {
            0.0
        } else {
            c.clamp(0.0, TONEMAP_INPUT_MAX)
        }
    })
}

fn aces_narkowicz(x: f32) -> f32 {
    const A: f32 = 2.51;
    const B: f32 = 0.03;
    const C: f32 = 2.43;
    const D: f32 = 0.59;
    const E: f32 = 0.14;
    let x = x * 0.6;
    ((x * (A * x + B)) / (x * (C * x + D) + E)).clamp(0.0, 1.0)
}

fn khronos_pbr_neutral(color: [f32; 3]) -> [f32; 3] {
    const START_COMPRESSION: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;

    let x = color[0].min(color[1].min(color[2]));
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let color = color.map(|c| c - offset);

    let peak = color[0].max(color[1].max(color[2]));
    if peak < START_COMPRESSION {
        return color;
    }

    const D: f32 = 1.0 - START_COMPRESSION;
    let new_peak = 1.0 - D * D / (peak + D - START_COMPRESSION);
    let color = color.map(|c| c * (new_peak / peak));

    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    // mix(color, vec3(newPeak), g)
    color.map(|c| c * (1.0 - g) + new_peak * g)
}

/// AgX's inset matrix (linear Rec.709 → the AgX working space), row-major: `out = M · rgb`.
/// The published matrix (Wrensch's `agx_mat`, given column-major in GLSL) has rows summing to
/// 1.000136, 0.999963 and 0.999952; here each row is divided by its sum so that grey stays
/// exactly grey: otherwise the three channels reach the top of the log range at slightly
/// different inputs (≈ 16.3) and the outset matrix makes grey dip by ~4e-6 there (not monotone).
/// The difference from the published look is below 2e-4 EV.
pub const AGX_INSET: [[f32; 3]; 3] = [
    [0.842_364_16, 0.078_422_9, 0.079_212_94],
    [0.042_329_81, 0.878_501_1, 0.079_169_06],
    [0.042_377_68, 0.078_437_35, 0.879_184_96],
];
/// AgX's outset matrix (the inverse of [`AGX_INSET`] as published), row-major.
pub const AGX_OUTSET: [[f32; 3]; 3] = [
    [1.196_879, -0.098_020_88, -0.099_029_74],
    [-0.052_896_85, 1.151_903_1, -0.098_961_18],
    [-0.052_971_635, -0.098_043_45, 1.151_073_7],
];
/// Lowest exposure AgX encodes, in stops relative to 0.18 grey's encoding (log2 units).
pub const AGX_MIN_EV: f32 = -12.473_93;
/// Highest exposure AgX encodes: inputs above 2^4.026069 ≈ 16.3 map to the top of the curve.
pub const AGX_MAX_EV: f32 = 4.026_069;

fn mat3_mul(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
}

/// The 6th-order polynomial fit of AgX's default-contrast sigmoid on the log-encoded [0, 1]
/// input (Benjamin Wrensch, "Minimal AgX implementation", 2023).
pub fn agx_default_contrast(x: f32) -> f32 {
    let x2 = x * x;
    let x4 = x2 * x2;
    15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
        - 0.00232
}

/// AgX (Troy Sobotka), base look, as the widely used GLSL of Benjamin Wrensch's "Minimal AgX":
/// inset matrix ([`AGX_INSET`], rows normalised) → `log2`, clamped to [[`AGX_MIN_EV`], [`AGX_MAX_EV`]] and
/// normalised to [0, 1] → the sigmoid polynomial ([`agx_default_contrast`]) → outset matrix
/// ([`AGX_OUTSET`]). That result is a display-*encoded* value (the curve bakes in the display
/// transfer function), while luz sRGB-encodes after tone mapping; so it is clamped to [0, 1]
/// and decoded with the exact sRGB curve ([`srgb_decode`]). The pipeline's encode then restores
/// it to float precision: the 8-bit codes are those the reference GLSL writes to a UNORM target.
/// (A `pow(x, 2.2)` decode would darken shadows once re-encoded with the piecewise sRGB curve.)
/// Input: linear Rec.709, sanitised (NaN and negatives → 0, capped at the half-float maximum).
pub fn agx(rgb: [f32; 3]) -> [f32; 3] {
    let range = AGX_MAX_EV - AGX_MIN_EV;
    let encoded = mat3_mul(&AGX_INSET, rgb).map(|c| {
        // log2(0) = −inf is clamped to the minimum, as GLSL's clamp(log2(0)) in practice.
        let ev = c.max(0.0).log2().clamp(AGX_MIN_EV, AGX_MAX_EV);
        agx_default_contrast((ev - AGX_MIN_EV) / range)
    });
    mat3_mul(&AGX_OUTSET, encoded).map(|c| srgb_decode(c.clamp(0.0, 1.0)))
}

/// The exposure multiplier for `ev` stops: 2^ev.
pub fn exposure_scale(ev: f32) -> f32 {
    ev.exp2()
}

/// IEC 61966-2-1 sRGB encoding (linear → non-linear), the exact piecewise curve.
///
/// Not clamped: values above 1 encode above 1, negatives follow the linear segment.
pub fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// IEC 61966-2-1 sRGB decoding (non-linear → linear), the exact piecewise curve.
pub fn srgb_decode(encoded: f32) -> f32 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Encodes a linear value to an 8-bit sRGB code: clamp to [0, 1], encode, scale, round.
/// NaN gives 0.
pub fn srgb_encode_u8(linear: f32) -> u8 {
    if linear.is_nan() {
        return 0;
    }
    let v = srgb_encode(linear.clamp(0.0, 1.0)) * 255.0;
    v.round().clamp(0.0, 255.0) as u8
}

/// Bins of [`srgb_encode_table`]: [0, 1] cut into this many equal bins, each narrow enough that
/// the 8-bit code changes at most once inside it (the curve's steepest slope, 12.92 × 255 codes per
/// unit at the linear segment, is below one code per bin).
pub const SRGB_ENCODE_BINS: usize = 4096;

/// The table behind [`srgb_encode_u8_lut`] and the viewer's display shader (`display.frag`), which
/// gives [`srgb_encode_u8`]'s exact codes with one lookup and one compare instead of a `pow`: for
/// bin i, covering [i/BINS, (i+1)/BINS), entry `[code, threshold]` holds the code at the bin's
/// start and the smallest value in the bin whose code is `code + 1` (2.0 when the code does not
/// change in the bin). Built by bisection over f32 bit patterns of [`srgb_encode_u8`] itself, so
/// it is that function by construction wherever that function is monotonic (tests check it).
pub fn srgb_encode_table() -> &'static [[f32; 2]; SRGB_ENCODE_BINS] {
    static TABLE: OnceLock<[[f32; 2]; SRGB_ENCODE_BINS]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let bins = SRGB_ENCODE_BINS as f32;
        std::array::from_fn(|i| {
            let lo = i as f32 / bins;
            // The last bin also holds 1.0 itself (the shader clamps the bin index).
            let last = if i + 1 == SRGB_ENCODE_BINS {
                1.0
            } else {
                f32::from_bits(((i + 1) as f32 / bins).to_bits() - 1)
            };
            let code = srgb_encode_u8(lo);
            if srgb_encode_u8(last) == code {
                return [code as f32, 2.0];
            }
            // Smallest x in (lo, last] with a higher code: bisect on the bit patterns, which are
            // ordered like the values for non-negative floats.
            let (mut a, mut b) = (lo.to_bits(), last.to_bits());
            while b - a > 1 {
                let m = a + (b - a) / 2;
                if srgb_encode_u8(f32::from_bits(m)) == code {
                    a = m;
                } else {
                    b = m;
                }
            }
            [code as f32, f32::from_bits(b)]
        })
    })
}

/// [`srgb_encode_u8`] through [`srgb_encode_table`]: the CPU mirror of the display shader's
/// encode (include/color.glsl: `srgb_encode_u8_lut`).
pub fn srgb_encode_u8_lut(linear: f32) -> u8 {
    if linear.is_nan() {
        return 0;
    }
    let x = linear.clamp(0.0, 1.0);
    let bin = ((x * SRGB_ENCODE_BINS as f32) as usize).min(SRGB_ENCODE_BINS - 1);
    let [code, threshold] = srgb_encode_table()[bin];
    code as u8 + u8::from(x >= threshold)
}

/// The 256-entry table of linear values for every 8-bit sRGB code (computed in f64).
pub fn srgb_decode_table() -> &'static [f32; 256] {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|i| {
            let v = i as f64 / 255.0;
            let l = if v <= 0.040_45 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            };
            l as f32
        })
    })
}

/// Decodes an 8-bit sRGB code to linear (table lookup).
pub fn srgb_decode_u8(code: u8) -> f32 {
    srgb_decode_table()[code as usize]
}

/// Converts linear RGBA pixels to display RGBA8: exposure → tone map → clamp → sRGB encode → round.
///
/// Alpha is always 255 (the renderer's alpha carries no coverage worth showing). NaN channels
/// become 0 (black) so one bad pixel cannot poison its neighbours in a viewer; NaN and Inf pixels
/// are *counted* elsewhere (`luz diff`, the render statistics), never hidden by this function's
/// output being well formed. +Inf becomes white.
pub fn to_display_rgba8(pixels: &[[f32; 4]], exposure_ev: f32, tonemap: Tonemap) -> Vec<u8> {
    let scale = exposure_scale(exposure_ev);
    let mut out = Vec::with_capacity(pixels.len() * 4);
    for p in pixels {
        let rgb = [p[0], p[1], p[2]].map(|c| if c.is_nan() { 0.0 } else { c * scale });
        let mapped = tonemap.apply(rgb);
        out.extend(mapped.map(srgb_encode_u8));
        out.push(255);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table gives srgb_encode_u8's codes for every one of the 1 065 353 217 floats in [0, 1]
    /// (about 6 s on 2 cores), and for specials and out-of-range values.
    #[test]
    fn encode_table_matches_reference_exhaustively() {
        use rayon::prelude::*;
        let changes = srgb_encode_table().iter().filter(|e| e[1] <= 1.0).count();
        assert_eq!(changes, 255, "one code change per code above 0");
        let bad: Vec<u32> = (0..=1.0f32.to_bits())
            .into_par_iter()
            .filter(|&b| {
                let x = f32::from_bits(b);
                srgb_encode_u8_lut(x) != srgb_encode_u8(x)
            })
            .collect();
        assert!(
            bad.is_empty(),
            "{} floats differ, first {:?}",
            bad.len(),
            bad.first().map(|&b| f32::from_bits(b))
        );
        for x in [
            -0.0,
            -1.0,
            2.0,
            1e30,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ] {
            assert_eq!(srgb_encode_u8_lut(x), srgb_encode_u8(x), "{x:e}");
        }
    }

    #[test]
    fn known_values() {
        assert!((srgb_encode(0.5) - 0.735_356_7).abs() < 1e-5);
        assert!((srgb_decode(0.5) - 0.214_041_14).abs() < 1e-6);
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_decode(1.0) - 1.0).abs() < 1e-6);
        // Linear segment.
        assert!((srgb_encode(0.002) - 0.025_84).abs() < 1e-7);
        assert_eq!(srgb_encode_u8(0.5), 188);
        assert_eq!(srgb_encode_u8(-1.0), 0);
        assert_eq!(srgb_encode_u8(7.0), 255);
        assert_eq!(srgb_encode_u8(f32::NAN), 0);
        assert_eq!(srgb_encode_u8(f32::INFINITY), 255);
        assert_eq!(exposure_scale(0.0), 1.0);
        assert_eq!(exposure_scale(3.0), 8.0);
        assert_eq!(exposure_scale(-1.0), 0.5);
    }

    #[test]
    fn round_trips() {
        for i in 0..=10_000 {
            let v = i as f32 / 10_000.0;
            assert!((srgb_decode(srgb_encode(v)) - v).abs() < 2e-6, "{v}");
            assert!((srgb_encode(srgb_decode(v)) - v).abs() < 2e-6, "{v}");
        }
        for code in 0..=255u8 {
            assert_eq!(srgb_encode_u8(srgb_decode_u8(code)), code);
            let exact = srgb_decode(code as f32 / 255.0);
            assert!((srgb_decode_u8(code) - exact).abs() < 1e-6);
        }
    }

    #[test]
    fn curves_are_continuous_and_monotonic() {
        // The two pieces meet at the threshold (to within the standard's rounding of constants).
        let t = 0.003_130_8_f32;
        assert!((12.92 * t - (1.055 * t.powf(1.0 / 2.4) - 0.055)).abs() < 1e-6);
        let mut prev_e = f32::NEG_INFINITY;
        let mut prev_d = f32::NEG_INFINITY;
        for i in 0..=20_000 {
            let v = i as f32 / 10_000.0;
            let (e, d) = (srgb_encode(v), srgb_decode(v));
            assert!(e >= prev_e && d >= prev_d, "not monotonic at {v}");
            prev_e = e;
            prev_d = d;
        }
        for op in Tonemap::ALL {
            let mut prev = -1.0;
            for i in 0..=4000 {
                let x = i as f32 * 0.01;
                let y = op.apply([x; 3])[0];
                assert!(y >= prev - 1e-6, "{op} not monotonic at {x}");
                prev = y;
            }
        }
    }

    #[test]
    fn tonemap_limits() {
        for op in Tonemap::ALL {
            assert_eq!(op.apply([0.0; 3]), [0.0; 3], "{op} at 0");
        }
        let big = [1e6, 1e6, 1e6];
        for op in [Tonemap::Reinhard, Tonemap::Aces, Tonemap::KhronosNeutral] {
            for c in op.apply(big) {
                assert!((c - 1.0).abs() < 1e-3, "{op} at large input gave {c}");
            }
            for c in op.apply([f32::INFINITY, f32::NAN, -3.0]) {
                assert!(c.is_finite() && (0.0..=1.0).contains(&c), "{op}: {c}");
            }
        }
        assert_eq!(Tonemap::None.apply([2.0, -1.0, 0.5]), [2.0, -1.0, 0.5]);
        assert!((Tonemap::Reinhard.apply([1.0; 3])[0] - 0.5).abs() < 1e-7);
        // Narkowicz at x = 1 (after the 0.6 pre-scale): 0.6(2.51·0.6+0.03)/(0.6(2.43·0.6+0.59)+0.14).
        let x = 0.6f32;
        let want = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
        assert!((Tonemap::Aces.apply([1.0; 3])[0] - want).abs() < 1e-6);
        // Khronos Neutral: below the compression start it only subtracts the toe offset.
        let n = Tonemap::KhronosNeutral.apply([0.5, 0.3, 0.2]);
        for (got, want) in n.iter().zip([0.46, 0.26, 0.16]) {
            assert!((got - want).abs() < 1e-6);
        }
        // Above it, grey stays grey and the peak is compressed below 1.
        let g = Tonemap::KhronosNeutral.apply([4.0; 3]);
        assert!(g[0] == g[1] && g[1] == g[2] && g[0] < 1.0 && g[0] > 0.9);
        // A saturated colour is desaturated towards its new peak.
        let s = Tonemap::KhronosNeutral.apply([8.0, 0.0, 0.0]);
        assert!(s[0] < 1.0 && s[1] > 0.0 && s[1] == s[2]);
    }

    #[test]
    fn agx_behaves() {
        // Grey in, grey out; monotone in luminance; 0 → 0; saturates just below 1.
        let mut prev = -1.0f32;
        for i in 0..=20_000 {
            let x = 1e-5 * 1.001f32.powi(i);
            let y = Tonemap::Agx.apply([x; 3]);
            assert!(
                (y[0] - y[1]).abs() < 1e-3 && (y[1] - y[2]).abs() < 1e-3,
                "{x}: {y:?}"
            );
            assert!(y[0] >= prev - 1e-6, "not monotone at {x}");
            prev = y[0];
        }
        assert_eq!(Tonemap::Agx.apply([0.0; 3]), [0.0; 3]);
        assert!(Tonemap::Agx.apply([1e-4; 3])[0] < 1e-3);
        for c in Tonemap::Agx.apply([1e6; 3]) {
            assert!(c <= 1.0 && c > 0.98, "{c}");
        }
        for c in Tonemap::Agx.apply([f32::INFINITY, f32::NAN, -3.0]) {
            assert!(c.is_finite() && (0.0..=1.0).contains(&c), "{c}");
        }
        // Middle grey 0.18 lands near the middle of the display range (encoded ≈ 0.50; an
        // identity curve would give srgb_encode(0.18) = 0.46).
        let grey = srgb_encode(Tonemap::Agx.apply([0.18; 3])[0]);
        assert!((0.40..0.52).contains(&grey), "{grey}");
        // The published formula by hand: the encoded output at 0.18 is the polynomial at
        // (log2 0.18 − min EV)/(max EV − min EV), times the outset matrix's row sum.
        let t = (0.18f32.log2() - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV);
        let p = agx_default_contrast(t);
        let want = 0.999_83 * p;
        assert!((grey - want).abs() < 1e-4, "{grey} vs {want}");
        // The matrices are inverses (to the published precision); the inset keeps grey.
        for (i, row) in AGX_INSET.iter().enumerate() {
            assert!(
                (row.iter().sum::<f32>() - 1.0).abs() < 1e-6,
                "inset row {i}"
            );
        }
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        for (k, e) in id.iter().enumerate() {
            let back = mat3_mul(&AGX_OUTSET, mat3_mul(&AGX_INSET, *e));
            for (c, want) in back.iter().zip(e) {
                assert!((c - want).abs() < 1e-3, "column {k}: {back:?}");
            }
        }
        // A saturated colour keeps its hue order and stays in range.
        let r = Tonemap::Agx.apply([4.0, 0.5, 0.1]);
        assert!(r[0] > r[1] && r[1] > r[2] && r[0] <= 1.0);
    }

    #[test]
    fn names_round_trip() {
        for op in Tonemap::ALL {
            assert_eq!(Tonemap::parse(op.name()), Some(op));
            let json = serde_json::to_string(&op).unwrap();
            assert_eq!(json, format!("\"{}\"", op.name()));
        }
        assert_eq!(
            Tonemap::parse("Khronos-Neutral"),
            Some(Tonemap::KhronosNeutral)
        );
        assert_eq!(Tonemap::parse("filmic"), None);
        assert_eq!(Tonemap::parse("AgX"), Some(Tonemap::Agx));
    }

    #[test]
    fn display_pipeline() {
        let px = [
            [0.5, 0.0, 1.0, 0.3],
            [f32::NAN, f32::INFINITY, -1.0, 1.0],
            [0.25, 0.25, 0.25, 1.0],
        ];
        let out = to_display_rgba8(&px, 0.0, Tonemap::None);
        assert_eq!(&out[0..4], &[188, 0, 255, 255]);
        assert_eq!(&out[4..8], &[0, 255, 0, 255]);
        // +1 EV doubles 0.25 to 0.5.
        let out = to_display_rgba8(&px, 1.0, Tonemap::None);
        assert_eq!(&out[8..12], &[188, 188, 188, 255]);
        let out = to_display_rgba8(&px, 0.0, Tonemap::Reinhard);
        assert_eq!(out[0], srgb_encode_u8(0.5 / 1.5));
        assert_eq!(&out[4..8], &[0, 255, 0, 255]);
    }
}
