//! Shadow settings of a light (`"shadow"` in a scene's light) and of an object (`"cast_shadow"`,
//! `"receive_shadow"`). The GPU side is `render::shadow`; the CPU reference traces shadow rays
//! (`reference::render`). docs/shadows.md describes every field.

use super::LightKind;

/// How a shadow map is filtered when a surface looks it up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ShadowMethod {
    /// One depth comparison at the nearest texel: aliased edges, the cheapest.
    Hard,
    /// Percentage-closer filtering: `pcf_kernel`² bilinear comparisons around the point.
    Pcf,
    /// Percentage-closer soft shadows: a blocker search sizes the filter from the light's radius
    /// (or angular radius) and the blocker-receiver distance: contact-hardening penumbrae.
    Pcss,
}

impl ShadowMethod {
    pub const ALL: [ShadowMethod; 3] = [ShadowMethod::Hard, ShadowMethod::Pcf, ShadowMethod::Pcss];

    pub fn name(self) -> &'static str {
        match self {
            ShadowMethod::Hard => "hard",
            ShadowMethod::Pcf => "pcf",
            ShadowMethod::Pcss => "pcss",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// Where a directional light's cascades end, between the camera's near plane and the shadow
/// distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CascadeSplit {
    /// Equal depth ranges.
    Uniform,
    /// Each cascade `(far/near)^(1/n)` times as deep as the one before.
    Logarithmic,
    /// The blend λ·logarithmic + (1 − λ)·uniform of Zhang et al.'s parallel-split shadow maps.
    Practical { lambda: f32 },
}

impl CascadeSplit {
    /// The far view depth of each of `n` cascades over [near, far].
    pub fn splits(self, near: f32, far: f32, n: u32) -> Vec<f32> {
        let near = near.max(1e-6);
        let far = far.max(near * 1.0001);
        (1..=n)
            .map(|i| {
                let t = i as f32 / n as f32;
                let uniform = near + (far - near) * t;
                let log = near * (far / near).powf(t);
                match self {
                    CascadeSplit::Uniform => uniform,
                    CascadeSplit::Logarithmic => log,
                    CascadeSplit::Practical { lambda } => lambda * log + (1.0 - lambda) * uniform,
                }
            })
            .collect()
    }
}

/// A light's shadow: how its map is made and filtered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shadow {
    pub method: ShadowMethod,
    /// Texels per side of each map (each cascade, each cube face).
    pub resolution: u32,
    /// Receiver offset towards the light, in texels of the map at the receiver.
    pub bias: f32,
    /// Receiver offset along its normal, in texels of the map at the receiver, scaled by the
    /// sine of the angle between the normal and the light.
    pub normal_bias: f32,
    /// The rasteriser's slope-scaled depth bias of the shadow pass (depth units per unit slope).
    pub slope_bias: f32,
    /// Taps per side of the PCF kernel (1–9, one texel apart, centred); PCSS's largest filter is this many texels
    /// times four.
    pub pcf_kernel: u32,
    /// Directional lights: cascades over the view (1–4); 1 for other lights.
    pub cascades: u32,
    /// Directional lights: where the cascades split.
    pub split: CascadeSplit,
    /// Directional lights: the view depth the last cascade ends at (`None`: the farthest
    /// shadow-receiving object, within the camera's far plane).
    pub max_distance: Option<f32>,
}

pub const MIN_RESOLUTION: u32 = 16;
/// The largest resolution a scene may ask for; the device's own limit is checked when the maps
/// are made.
pub const MAX_RESOLUTION: u32 = 16384;
pub const MAX_CASCADES: u32 = 4;
pub const MAX_PCF_KERNEL: u32 = 9;

impl Shadow {
    /// The defaults for a light of `kind` (`"shadow": true`): PCF 2×2 (a 3×3-texel tent) with
    /// biases that need no tuning on the shipped scenes; three cascades at 1024² for directional
    /// lights, 1024² for spots and 512² per cube face for point lights.
    pub fn default_for(kind: LightKind) -> Self {
        Shadow {
            method: ShadowMethod::Pcf,
            resolution: match kind {
                LightKind::Directional => 1024,
                LightKind::Spot => 1024,
                LightKind::Point => 512,
            },
            bias: 1.0,
            normal_bias: 1.5,
            slope_bias: 1.5,
            pcf_kernel: 2,
            cascades: if kind == LightKind::Directional { 3 } else { 1 },
            split: CascadeSplit::Practical { lambda: 0.75 },
            max_distance: None,
        }
    }

    /// The number of map layers the light needs: its cascades, six cube faces for a point light
    /// or a spot wider than [`WIDE_SPOT_DEG`], one for other spots.
    pub fn layers(&self, kind: LightKind, umbra_deg: f32) -> u32 {
        match kind {
            LightKind::Directional => self.cascades,
            LightKind::Point => 6,
            LightKind::Spot if umbra_deg > WIDE_SPOT_DEG => 6,
            LightKind::Spot => 1,
        }
    }
}

/// Spots whose umbra half-angle is wider than this get a cube map like a point light (one
/// perspective map over the cone would waste most texels, and cannot exceed 180°).
pub const WIDE_SPOT_DEG: f32 = 60.0;

/// An object's part in shadows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObjectShadow {
    /// Drawn into the shadow maps.
    pub cast: bool,
    /// Darkened where a map says it is occluded.
    pub receive: bool,
}

impl Default for ObjectShadow {
    fn default() -> Self {
        ObjectShadow {
            cast: true,
            receive: true,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_end_at_far_and_grow() {
        for split in [
            CascadeSplit::Uniform,
            CascadeSplit::Logarithmic,
            CascadeSplit::Practical { lambda: 0.75 },
        ] {
            let s = split.splits(0.1, 100.0, 4);
            assert_eq!(s.len(), 4);
            assert!((s[3] - 100.0).abs() < 1e-3, "{split:?}: {s:?}");
            assert!(s.windows(2).all(|w| w[0] < w[1]), "{split:?}: {s:?}");
        }
        let u = CascadeSplit::Uniform.splits(0.0, 100.0, 4);
        assert!((u[0] - 25.0).abs() < 1e-3, "{u:?}");
        let l = CascadeSplit::Logarithmic.splits(0.1, 100.0, 3);
        assert!(
            (l[0] - 1.0).abs() < 1e-3 && (l[1] - 10.0).abs() < 1e-2,
            "{l:?}"
        );
    }
}
