//! Texture maps on the CPU for the reference renderer: decoded by `crate::texture` exactly as the
//! GPU path decodes them (sRGB colour maps to linear, chosen channels copied to RGB), sampled at
//! mip level 0 with the map's wrap modes and its magnification filter (bilinear by default).
//! Mip level 0 with bilinear filtering is the map itself, unfiltered by the screen: with
//! `--spp` > 1 the pixel average does the filtering.

use std::sync::Arc;

use glam::{Vec2, Vec4};

use crate::scene::{Filter, TextureRef, TextureSlot, Wrap};
use crate::texture::{load_texture, ColorSpace, TextureError};

/// Level 0 of a decoded map as linear RGBA floats (shared by the materials that use the same
/// file the same way).
pub struct Texels {
    width: u32,
    height: u32,
    texels: Vec<Vec4>,
}

impl Texels {
    /// Decodes the map `r` for `slot`: the slot's colour space, `r.channel` copied to RGB.
    pub fn load(r: &TextureRef, slot: TextureSlot) -> Result<Self, TextureError> {
        let mut level0 = r.clone();
        level0.sampler.mipmaps = false;
        let data = load_texture(
            &level0,
            ColorSpace::for_slot(slot),
            crate::imageio::MAX_DIMENSION,
            &mut |_| {},
        )?;
        let (w, h) = (data.width, data.height);
        let mut texels = Vec::with_capacity(w as usize * h as usize);
        for y in 0..h {
            for x in 0..w {
                texels.push(Vec4::from_array(data.texel(0, x, y).unwrap_or([0.0; 4])));
            }
        }
        Ok(Texels {
            width: w,
            height: h,
            texels,
        })
    }
}

/// A map with its sampler.
pub struct CpuTexture {
    data: Arc<Texels>,
    wrap_u: Wrap,
    wrap_v: Wrap,
    filter: Filter,
}

impl CpuTexture {
    /// `data` sampled as `r` says.
    pub fn new(data: Arc<Texels>, r: &TextureRef) -> Self {
        CpuTexture {
            data,
            wrap_u: r.sampler.wrap_u,
            wrap_v: r.sampler.wrap_v,
            filter: r.sampler.mag,
        }
    }

    fn texel(&self, x: i64, y: i64) -> Vec4 {
        let d = &*self.data;
        let i = wrap(x, d.width, self.wrap_u);
        let j = wrap(y, d.height, self.wrap_v);
        d.texels[j * d.width as usize + i]
    }

    /// The filtered value at texture coordinates `uv` (Vulkan's rules: texel centres at
    /// half-integers, `REPEAT`, `CLAMP_TO_EDGE` or `MIRRORED_REPEAT`).
    pub fn sample(&self, uv: Vec2) -> Vec4 {
        if !uv.is_finite() {
            return self.data.texels[0];
        }
        let s = uv.x * self.data.width as f32;
        let t = uv.y * self.data.height as f32;
        if self.filter == Filter::Nearest {
            return self.texel(s.floor() as i64, t.floor() as i64);
        }
        let (s, t) = (s - 0.5, t - 0.5);
        let (s0, t0) = (s.floor(), t.floor());
        let (fs, ft) = (s - s0, t - t0);
        let (x0, y0) = (s0 as i64, t0 as i64);
        let top = self.texel(x0, y0) * (1.0 - fs) + self.texel(x0 + 1, y0) * fs;
        let bottom = self.texel(x0, y0 + 1) * (1.0 - fs) + self.texel(x0 + 1, y0 + 1) * fs;
        top * (1.0 - ft) + bottom * ft
    }
}

fn wrap(i: i64, size: u32, mode: Wrap) -> usize {
    let n = i64::from(size);
    let k = match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::Clamp => i.clamp(0, n - 1),
        Wrap::Mirror => {
            let t = i.rem_euclid(2 * n);
            if t < n {
                t
            } else {
                2 * n - 1 - t
            }
        }
    };
    k as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tex(wrap: Wrap) -> CpuTexture {
        CpuTexture {
            data: Arc::new(Texels {
                width: 2,
                height: 1,
                texels: vec![Vec4::ZERO, Vec4::ONE],
            }),
            wrap_u: wrap,
            wrap_v: wrap,
            filter: Filter::Linear,
        }
    }

    #[test]
    fn bilinear_with_wrap_modes() {
        let t = tex(Wrap::Repeat);
        assert_eq!(t.sample(Vec2::new(0.25, 0.5)).x, 0.0);
        assert_eq!(t.sample(Vec2::new(0.5, 0.5)).x, 0.5);
        assert_eq!(t.sample(Vec2::new(0.75, 0.5)).x, 1.0);
        // Between the last and (wrapped) first texel.
        assert_eq!(t.sample(Vec2::new(1.0, 0.5)).x, 0.5);
        assert_eq!(tex(Wrap::Clamp).sample(Vec2::new(1.0, 0.5)).x, 1.0);
        assert_eq!(tex(Wrap::Mirror).sample(Vec2::new(1.0, 0.5)).x, 1.0);
        assert_eq!(wrap(-1, 4, Wrap::Mirror), 0);
        assert_eq!(wrap(4, 4, Wrap::Mirror), 3);
    }
}
