//! Looking at the maps themselves: read every layer back after a frame and turn a light's layers
//! into a picture (`luz render --shadow-maps DIR`, the viewer's shadow-map window).
//!
//! Each texel becomes the distance from the layer's eye along its axis (metres), so a picture
//! means the same whatever the projection: near is bright, far is dark, scaled to the nearest and
//! farthest drawn texel of the light's layers; texels nothing was drawn into are dark blue.

use ash::vk;
use glam::{Mat4, Vec3};

use super::{GpuShadowLayer, ShadowMaps};
use crate::vk::cmd::{read_to_host, CommandPool};
use crate::vk::VkError;

/// One layer (a cascade, a cube face or a spot's map) as it was last drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct MapLayer {
    /// The light's index in the scene.
    pub light: usize,
    /// The layer's index among the light's layers (cascade or cube face).
    pub index: u32,
    /// Side in texels (the light's `shadow.resolution`).
    pub resolution: u32,
    /// Clip from world, as the depth pass drew it (texel (x, y) of the light's `resolution`² is
    /// at NDC (2(x + ½)/resolution − 1, 2(y + ½)/resolution − 1)).
    pub view_proj: Mat4,
    /// The layer's eye and unit axis: distances are measured from it along the axis.
    pub origin: Vec3,
    pub axis: Vec3,
    /// Row by row: distance (m) from the layer's eye along its axis; `None` where nothing was
    /// drawn.
    pub distance: Vec<Option<f32>>,
}

/// The colour of texels nothing was drawn into.
pub const EMPTY_TEXEL: [u8; 4] = [16, 24, 64, 255];

impl ShadowMaps {
    /// Every layer of every shadowed light as the last recorded frame drew it. The caller makes
    /// sure that frame has completed and no other submission uses the image (a headless render
    /// waits; the viewer waits for the device). Empty without shadowed lights or before the first
    /// frame's update.
    pub fn read_layers(&self, pool: &CommandPool) -> Result<Vec<MapLayer>, VkError> {
        if !self.active() || self.last_layers.is_empty() {
            return Ok(Vec::new());
        }
        let size = self.size;
        let layers = self.layer_views.len() as u32;
        let bytes = u64::from(size) * u64::from(size) * 4 * u64::from(layers);
        let sampled = (
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::PipelineStageFlags2::VERTEX_SHADER | vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
        );
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::DEPTH,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: layers,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: size,
                height: size,
                depth: 1,
            },
        };
        let mapped = read_to_host(
            &self.ctx,
            pool,
            &self.image,
            sampled,
            (&[region], bytes),
            "shadow map readback",
        )?;
        // The copy is a byte vector (alignment 1): decode, do not cast.
        let depths: Vec<f32> = mapped
            .chunks_exact(4)
            .map(|c| f32::from_ne_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let side = size as usize;
        let mut out = Vec::new();
        for m in &self.maps {
            let res = m.shadow.resolution as usize;
            for k in 0..m.layers {
                let layer = (m.first_layer + k) as usize;
                let record = &self.last_layers[layer];
                let base = layer * side * side;
                let mut distance = Vec::with_capacity(res * res);
                for y in 0..res {
                    let row = &depths[base + y * side..base + y * side + res];
                    distance.extend(row.iter().map(|&z| layer_distance(record, z)));
                }
                out.push(MapLayer {
                    light: m.light,
                    index: k,
                    resolution: m.shadow.resolution,
                    view_proj: record.view_proj,
                    origin: record.origin.truncate(),
                    axis: record.axis.truncate(),
                    distance,
                });
            }
        }
        Ok(out)
    }
}

/// Distance from the layer's eye along its axis for a stored (reversed) depth `z`, as
/// `shadow_distance` in shadows.glsl computes it; `None` for the cleared value (nothing drawn).
pub fn layer_distance(layer: &GpuShadowLayer, z: f32) -> Option<f32> {
    if z <= 0.0 {
        return None;
    }
    Some(if layer.params.y > 0.5 {
        layer.params.z / z
    } else {
        (1.0 - z) * layer.params.z
    })
}

/// A light's layers side by side (layer 0 on the left), as RGBA8 rows: grey from white (the
/// nearest drawn texel of all its layers) to black (the farthest), [`EMPTY_TEXEL`] where nothing
/// was drawn. Returns (width, height, pixels); `None` when `layers` is empty.
pub fn picture(layers: &[&MapLayer]) -> Option<(u32, u32, Vec<u8>)> {
    let res = layers.first()?.resolution as usize;
    let (mut near, mut far) = (f32::INFINITY, f32::NEG_INFINITY);
    for d in layers.iter().flat_map(|l| l.distance.iter().flatten()) {
        near = near.min(*d);
        far = far.max(*d);
    }
    let span = (far - near).max(f32::MIN_POSITIVE);
    let width = res * layers.len();
    let mut pixels = vec![0u8; width * res * 4];
    for (i, l) in layers.iter().enumerate() {
        for y in 0..res {
            for x in 0..res {
                let o = ((y * width) + i * res + x) * 4;
                let texel = match l.distance[y * res + x] {
                    None => EMPTY_TEXEL,
                    Some(d) => {
                        let g = (255.0 * (1.0 - (d - near) / span))
                            .round()
                            .clamp(0.0, 255.0) as u8;
                        [g, g, g, 255]
                    }
                };
                pixels[o..o + 4].copy_from_slice(&texel);
            }
        }
    }
    Some((width as u32, res as u32, pixels))
}

#[cfg(test)]
mod tests {
    use super::*;
    use bytemuck::Zeroable;
    use glam::Vec4;

    fn record(perspective: bool, z: f32) -> GpuShadowLayer {
        GpuShadowLayer {
            params: Vec4::new(0.01, if perspective { 1.0 } else { 0.0 }, z, 0.0),
            ..Zeroable::zeroed()
        }
    }

    #[test]
    fn distances_invert_both_projections() {
        // Orthographic: z = 1 − d / range; perspective (infinite far, reversed): z = near / d.
        let ortho = record(false, 40.0);
        assert_eq!(layer_distance(&ortho, 0.75), Some(10.0));
        let persp = record(true, 0.05);
        assert!((layer_distance(&persp, 0.01).unwrap() - 5.0).abs() < 1e-5);
        assert_eq!(layer_distance(&persp, 0.0), None);
    }

    #[test]
    fn picture_scales_near_to_white_and_marks_empty_texels() {
        let a = MapLayer {
            light: 0,
            index: 0,
            resolution: 2,
            view_proj: Mat4::IDENTITY,
            origin: Vec3::ZERO,
            axis: Vec3::Z,
            distance: vec![Some(1.0), Some(3.0), None, Some(2.0)],
        };
        let b = MapLayer {
            index: 1,
            distance: vec![None, None, None, Some(5.0)],
            ..a.clone()
        };
        let (w, h, px) = picture(&[&a, &b]).unwrap();
        assert_eq!((w, h), (4, 2));
        let at = |x: usize, y: usize| &px[(y * 4 + x) * 4..(y * 4 + x) * 4 + 4];
        assert_eq!(at(0, 0), [255, 255, 255, 255]); // nearest of both layers
        assert_eq!(at(1, 0), [128, 128, 128, 255]); // 3 m of 1..5 m
        assert_eq!(at(0, 1), EMPTY_TEXEL);
        assert_eq!(at(3, 1), [0, 0, 0, 255]); // the farthest, in layer 1
        assert_eq!(at(2, 0), EMPTY_TEXEL);
        assert!(picture(&[]).is_none());
    }
}
