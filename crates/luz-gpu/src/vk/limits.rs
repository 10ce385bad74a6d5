//! The device limits luz sizes its GPU resources against, queried from the device at run time
//! (never assumed), and the checks that turn an input too large for them into a clear error.
//!
//! Every allocation whose size depends on the input is checked:
//!
//! - images ([`super::Image::new`]): width and height against `maxImageDimension2D`
//!   (`maxImageDimensionCube` for cube maps), layers against `maxImageArrayLayers`, and the
//!   memory the driver asks for against `maxMemoryAllocationSize`. Textures and environments
//!   larger than `maxImageDimension2D` never get here: they are box-downscaled to fit first (see
//!   [`crate::texture`] and [`crate::env::load_equirect`]).
//! - buffers ([`super::Buffer::new`]): size against `maxBufferSize` and the memory against
//!   `maxMemoryAllocationSize`.
//! - the render target ([`Limits::check_render_size`], named after the scene's
//!   `output.width` / `output.height`): `maxImageDimension2D`, `maxFramebufferWidth` /
//!   `maxFramebufferHeight`, and the colour target's and readback buffer's bytes.
//! - meshes ([`Limits::check_mesh`]): the vertex and index counts must fit 32-bit indices and the
//!   largest index `maxDrawIndexedIndexValue`; vertex and index bytes the buffer limits. A mesh
//!   beyond them is an error naming the object (luz does not split meshes into several draws).
//! - lights and per-object data ([`Limits::check_storage`]): `maxStorageBufferRange`.

use ash::vk;

use super::VkError;

/// The limits of one device that luz checks input-sized resources against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// `maxImageDimension2D`.
    pub max_image_dimension_2d: u32,
    /// `maxImageDimensionCube`.
    pub max_image_dimension_cube: u32,
    /// `maxImageArrayLayers`.
    pub max_image_array_layers: u32,
    /// `maxFramebufferWidth`.
    pub max_framebuffer_width: u32,
    /// `maxFramebufferHeight`.
    pub max_framebuffer_height: u32,
    /// `maxStorageBufferRange`, in bytes.
    pub max_storage_buffer_range: u64,
    /// `maxDrawIndexedIndexValue`: the largest index a 32-bit index buffer may hold.
    pub max_draw_indexed_index_value: u32,
    /// `maxMemoryAllocationSize` (`VkPhysicalDeviceMaintenance3Properties`), in bytes.
    pub max_memory_allocation_size: u64,
    /// `maxBufferSize` (`VkPhysicalDeviceMaintenance4Properties`), in bytes.
    pub max_buffer_size: u64,
}

impl Limits {
    /// The limits a device reports.
    pub fn from_properties(
        limits: &vk::PhysicalDeviceLimits,
        maintenance3: &vk::PhysicalDeviceMaintenance3Properties,
        maintenance4: &vk::PhysicalDeviceMaintenance4Properties,
    ) -> Self {
        Self {
            max_image_dimension_2d: limits.max_image_dimension2_d,
            max_image_dimension_cube: limits.max_image_dimension_cube,
            max_image_array_layers: limits.max_image_array_layers,
            max_framebuffer_width: limits.max_framebuffer_width,
            max_framebuffer_height: limits.max_framebuffer_height,
            max_storage_buffer_range: u64::from(limits.max_storage_buffer_range),
            max_draw_indexed_index_value: limits.max_draw_indexed_index_value,
            max_memory_allocation_size: maintenance3.max_memory_allocation_size,
            max_buffer_size: maintenance4.max_buffer_size,
        }
    }

    /// Limits with no bound at all (a starting point for tests that tighten one field).
    pub fn unbounded() -> Self {
        Self {
            max_image_dimension_2d: u32::MAX,
            max_image_dimension_cube: u32::MAX,
            max_image_array_layers: u32::MAX,
            max_framebuffer_width: u32::MAX,
            max_framebuffer_height: u32::MAX,
            max_storage_buffer_range: u64::MAX,
            max_draw_indexed_index_value: u32::MAX,
            max_memory_allocation_size: u64::MAX,
            max_buffer_size: u64::MAX,
        }
    }

    /// The tighter of two sets of limits, field by field.
    pub fn min(&self, other: &Self) -> Self {
        Self {
            max_image_dimension_2d: self
                .max_image_dimension_2d
                .min(other.max_image_dimension_2d),
            max_image_dimension_cube: self
                .max_image_dimension_cube
                .min(other.max_image_dimension_cube),
            max_image_array_layers: self
                .max_image_array_layers
                .min(other.max_image_array_layers),
            max_framebuffer_width: self.max_framebuffer_width.min(other.max_framebuffer_width),
            max_framebuffer_height: self
                .max_framebuffer_height
                .min(other.max_framebuffer_height),
            max_storage_buffer_range: self
                .max_storage_buffer_range
                .min(other.max_storage_buffer_range),
            max_draw_indexed_index_value: self
                .max_draw_indexed_index_value
                .min(other.max_draw_indexed_index_value),
            max_memory_allocation_size: self
                .max_memory_allocation_size
                .min(other.max_memory_allocation_size),
            max_buffer_size: self.max_buffer_size.min(other.max_buffer_size),
        }
    }

    /// A buffer of `bytes` (`what` names it): `maxBufferSize` and `maxMemoryAllocationSize`.
    pub fn check_buffer(&self, what: &str, bytes: u64) -> Result<(), VkError> {
        check(what, bytes, self.max_buffer_size, "maxBufferSize")?;
        self.check_allocation(what, bytes)
    }

    /// One memory allocation of `bytes`: `maxMemoryAllocationSize`.
    pub fn check_allocation(&self, what: &str, bytes: u64) -> Result<(), VkError> {
        check(
            what,
            bytes,
            self.max_memory_allocation_size,
            "maxMemoryAllocationSize",
        )
    }

    /// A storage buffer bound whole (lights, per-object data): `maxStorageBufferRange`, then the
    /// buffer limits.
    pub fn check_storage(&self, what: &str, bytes: u64) -> Result<(), VkError> {
        check(
            what,
            bytes,
            self.max_storage_buffer_range,
            "maxStorageBufferRange",
        )?;
        self.check_buffer(what, bytes)
    }

    /// The render target of a `width`×`height` output (`scene` names the scene file): each side
    /// against `maxImageDimension2D` and `maxFramebufferWidth` / `maxFramebufferHeight`, the
    /// largest colour target (`target_bytes_per_pixel`, all samples) against
    /// `maxMemoryAllocationSize`, and the readback buffer (`readback_bytes_per_pixel`) against the
    /// buffer limits. Errors name `output.width` / `output.height`.
    pub fn check_render_size(
        &self,
        scene: &str,
        width: u32,
        height: u32,
        target_bytes_per_pixel: u64,
        readback_bytes_per_pixel: u64,
    ) -> Result<(), VkError> {
        for (field, value, fb, fb_name) in [
            (
                "output.width",
                width,
                self.max_framebuffer_width,
                "maxFramebufferWidth",
            ),
            (
                "output.height",
                height,
                self.max_framebuffer_height,
                "maxFramebufferHeight",
            ),
        ] {
            let what = format!("{scene}: {field}");
            check(
                &what,
                u64::from(value),
                u64::from(self.max_image_dimension_2d),
                "maxImageDimension2D",
            )?;
            check(&what, u64::from(value), u64::from(fb), fb_name)?;
        }
        let pixels = u64::from(width) * u64::from(height);
        let what = |part: &str, bpp: u64| {
            format!(
                "{scene}: output.width × output.height ({width}x{height}): {part} at {bpp} bytes \
                 per pixel"
            )
        };
        self.check_allocation(
            &what("colour target", target_bytes_per_pixel),
            pixels.saturating_mul(target_bytes_per_pixel),
        )?;
        self.check_buffer(
            &what("readback buffer", readback_bytes_per_pixel),
            pixels.saturating_mul(readback_bytes_per_pixel),
        )
    }

    /// One mesh as drawn: `vertices` vertices of `vertex_bytes` each, `indices` 32-bit indices
    /// whose largest value is `max_index`; `what` names the scene and object. Errors (no split
    /// into several draws) when the counts do not fit 32-bit indices or the largest index exceeds
    /// `maxDrawIndexedIndexValue`, or when a vertex or index buffer exceeds the buffer limits.
    pub fn check_mesh(
        &self,
        what: &str,
        vertices: usize,
        vertex_bytes: usize,
        indices: usize,
        max_index: u64,
    ) -> Result<(), VkError> {
        let u32_max = u64::from(u32::MAX);
        check(
            &format!("{what}: vertex count"),
            vertices as u64,
            u32_max,
            "32-bit indices",
        )?;
        check(
            &format!("{what}: index count"),
            indices as u64,
            u32_max,
            "32-bit index count of vkCmdDrawIndexed",
        )?;
        check(
            &format!("{what}: largest vertex index"),
            max_index,
            u64::from(self.max_draw_indexed_index_value),
            "maxDrawIndexedIndexValue",
        )?;
        self.check_buffer(
            &format!("{what}: vertex buffer ({vertices} vertices)"),
            (vertices as u64).saturating_mul(vertex_bytes as u64),
        )?;
        self.check_buffer(
            &format!("{what}: index buffer ({indices} indices)"),
            (indices as u64).saturating_mul(4),
        )
    }
}

/// `requested` against `limit`, as a [`VkError::Limit`].
fn check(what: &str, requested: u64, limit: u64, limit_name: &'static str) -> Result<(), VkError> {
    if requested > limit {
        return Err(VkError::Limit {
            what: what.to_string(),
            requested,
            limit,
            limit_name,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny() -> Limits {
        Limits {
            max_image_dimension_2d: 64,
            max_image_dimension_cube: 32,
            max_image_array_layers: 6,
            max_framebuffer_width: 48,
            max_framebuffer_height: 40,
            max_storage_buffer_range: 256,
            max_draw_indexed_index_value: 5,
            max_memory_allocation_size: 4096,
            max_buffer_size: 8192,
        }
    }

    fn limit_name(r: Result<(), VkError>) -> &'static str {
        match r {
            Err(VkError::Limit { limit_name, .. }) => limit_name,
            other => panic!("expected a limit error, got {other:?}"),
        }
    }

    #[test]
    fn render_size_names_the_field_and_the_limit() {
        let l = tiny();
        assert!(l.check_render_size("s.json", 16, 16, 16, 16).is_ok());
        let e = l
            .check_render_size("s.json", 65, 8, 16, 16)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "s.json: output.width of 65 exceeds the device limit of 64 (maxImageDimension2D)"
        );
        assert_eq!(
            limit_name(l.check_render_size("s.json", 49, 8, 16, 16)),
            "maxFramebufferWidth"
        );
        let e = l
            .check_render_size("s.json", 8, 41, 16, 16)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.json: output.height of 41") && e.contains("(maxFramebufferHeight)"),
            "{e}"
        );
        // 17×16 pixels of 16 bytes: 4352 bytes, over the 4096-byte allocation limit.
        let e = l
            .check_render_size("s.json", 17, 16, 16, 4)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "s.json: output.width × output.height (17x16): colour target at 16 bytes per pixel \
             of 4352 exceeds the device limit of 4096 (maxMemoryAllocationSize)"
        );
        // The readback buffer against maxBufferSize (8192): 16×16 × 33 bytes.
        let l = Limits {
            max_memory_allocation_size: u64::MAX,
            ..tiny()
        };
        let e = l
            .check_render_size("s.json", 16, 16, 4, 33)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("readback buffer at 33 bytes per pixel of 8448")
                && e.contains("(maxBufferSize)"),
            "{e}"
        );
    }

    #[test]
    fn meshes_beyond_the_index_limit_are_errors() {
        let l = tiny();
        // Six vertices: indices 0..=5 fit maxDrawIndexedIndexValue = 5.
        assert!(l.check_mesh("s.json: object \"a\"", 6, 48, 6, 5).is_ok());
        let e = l
            .check_mesh("s.json: object \"a\"", 7, 48, 6, 6)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "s.json: object \"a\": largest vertex index of 6 exceeds the device limit of 5 \
             (maxDrawIndexedIndexValue)"
        );
        // Counts beyond 32 bits never reach a truncating cast.
        let big = u32::MAX as usize + 1;
        assert_eq!(
            limit_name(Limits::unbounded().check_mesh("m", big, 48, 3, 2)),
            "32-bit indices"
        );
        assert_eq!(
            limit_name(Limits::unbounded().check_mesh("m", 3, 48, big, 2)),
            "32-bit index count of vkCmdDrawIndexed"
        );
        // Vertex bytes: 100 × 48 = 4800 > 4096.
        let l = Limits {
            max_draw_indexed_index_value: u32::MAX,
            ..tiny()
        };
        assert_eq!(
            limit_name(l.check_mesh("m", 100, 48, 3, 2)),
            "maxMemoryAllocationSize"
        );
    }

    #[test]
    fn storage_and_buffers() {
        let l = tiny();
        assert!(l.check_storage("lights", 256).is_ok());
        let e = l
            .check_storage("s.json: 5 lights", 320)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "s.json: 5 lights of 320 exceeds the device limit of 256 (maxStorageBufferRange)"
        );
        assert_eq!(limit_name(l.check_buffer("b", 8193)), "maxBufferSize");
        assert_eq!(
            limit_name(l.check_buffer("b", 5000)),
            "maxMemoryAllocationSize"
        );
    }

    #[test]
    fn min_takes_the_tighter_field() {
        let l = Limits::unbounded().min(&tiny());
        assert_eq!(l, tiny());
        assert_eq!(tiny().min(&Limits::unbounded()), tiny());
    }
}
