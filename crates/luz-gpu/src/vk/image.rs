//! 2D images (colour targets, depth, textures) with one view, freed on drop.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::{Context, VkError};

/// What to create: the frame graph's description of an image (size, format, usage, samples,
/// mips, layers, aspect; its fields read through this one) and how the image is viewed.
#[derive(Debug, Clone, Copy)]
pub struct ImageDesc {
    pub image: luz_graph::ImageDesc,
    /// A cube map (6 layers, viewed as a cube).
    pub cube: bool,
    /// Viewed as a 2D array even with one layer.
    pub array: bool,
}

impl std::ops::Deref for ImageDesc {
    type Target = luz_graph::ImageDesc;

    fn deref(&self) -> &luz_graph::ImageDesc {
        &self.image
    }
}

impl std::ops::DerefMut for ImageDesc {
    fn deref_mut(&mut self) -> &mut luz_graph::ImageDesc {
        &mut self.image
    }
}

impl ImageDesc {
    /// An image of the graph's description `image`, viewed as 2D: what the constructors start
    /// from.
    fn viewed_2d(image: luz_graph::ImageDesc) -> Self {
        Self {
            image,
            cube: false,
            array: false,
        }
    }

    /// A sampled + storage cube map with `mips` levels (IBL data).
    pub fn cube(size: u32, format: vk::Format, mips: u32) -> Self {
        let usage = vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST;
        let image = luz_graph::ImageDesc::color(size, size, format).usage(usage);
        Self {
            cube: true,
            ..Self::viewed_2d(image.mips(mips).layers(6))
        }
    }
    /// A sampled texture (2D, or a 2D array when `layers` > 1) filled by copies or storage writes.
    pub fn texture(width: u32, height: u32, format: vk::Format, mips: u32, layers: u32) -> Self {
        let usage = vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_DST
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let image = luz_graph::ImageDesc::color(width, height, format).usage(usage);
        Self::of_graph(&image.mips(mips).layers(layers))
    }

    /// A graph description as a luz image description: 2D, or a 2D array when it has more than
    /// one layer.
    pub fn of_graph(image: &luz_graph::ImageDesc) -> Self {
        Self {
            array: image.layers > 1,
            ..Self::viewed_2d(*image)
        }
    }

    fn view_type(&self) -> vk::ImageViewType {
        if self.cube {
            vk::ImageViewType::CUBE
        } else if self.layers > 1 || self.array {
            vk::ImageViewType::TYPE_2D_ARRAY
        } else {
            vk::ImageViewType::TYPE_2D
        }
    }

    /// A single-sample colour target that can be copied out.
    pub fn color_target(width: u32, height: u32, format: vk::Format) -> Self {
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::SAMPLED;
        Self::viewed_2d(luz_graph::ImageDesc::color(width, height, format).usage(usage))
    }
    /// A multisampled colour target resolved into a single-sample one.
    pub fn msaa_color(
        width: u32,
        height: u32,
        format: vk::Format,
        samples: vk::SampleCountFlags,
    ) -> Self {
        let usage =
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT;
        let image = luz_graph::ImageDesc::color(width, height, format).usage(usage);
        Self::viewed_2d(image.samples(samples))
    }
    pub fn depth(
        width: u32,
        height: u32,
        format: vk::Format,
        samples: vk::SampleCountFlags,
    ) -> Self {
        let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let image = luz_graph::ImageDesc::depth(width, height, format).usage(usage);
        Self::viewed_2d(image.samples(samples))
    }

    /// Mips `base_mip_level ..+ level_count` of layers `base_array_layer ..+ layer_count`.
    fn range(
        &self,
        (base_mip_level, level_count): (u32, u32),
        (base_array_layer, layer_count): (u32, u32),
    ) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level,
            level_count,
            base_array_layer,
            layer_count,
        }
    }

    /// A view of `range` of `image` (an image of this description), in its format.
    fn view_info(
        &self,
        image: vk::Image,
        view_type: vk::ImageViewType,
        range: vk::ImageSubresourceRange,
    ) -> vk::ImageViewCreateInfo<'static> {
        vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(view_type)
            .format(self.format)
            .subresource_range(range)
    }
}

pub struct Image {
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub desc: ImageDesc,
    extra_views: Vec<vk::ImageView>,
    allocation: Option<Allocation>,
    ctx: Arc<Context>,
}

impl Image {
    pub fn new(ctx: &Arc<Context>, name: &str, desc: ImageDesc) -> Result<Self, VkError> {
        let limits = ctx.limits();
        let (max, max_name) = if desc.cube {
            (limits.max_image_dimension_cube, "maxImageDimensionCube")
        } else {
            (limits.max_image_dimension_2d, "maxImageDimension2D")
        };
        if desc.width == 0 || desc.height == 0 {
            return Err(VkError::Setup(format!(
                "{name}: image size {}x{} must be at least 1x1",
                desc.width, desc.height
            )));
        }
        if desc.width > max || desc.height > max {
            return Err(VkError::Limit {
                what: format!("{name} size {}x{}", desc.width, desc.height),
                requested: desc.width.max(desc.height) as u64,
                limit: max as u64,
                limit_name: max_name,
            });
        }
        if desc.layers > limits.max_image_array_layers {
            return Err(VkError::Limit {
                what: format!("{name} array layers"),
                requested: desc.layers as u64,
                limit: limits.max_image_array_layers as u64,
                limit_name: "maxImageArrayLayers",
            });
        }
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(desc.mip_levels)
            .array_layers(desc.layers)
            .flags(if desc.cube {
                vk::ImageCreateFlags::CUBE_COMPATIBLE
            } else {
                vk::ImageCreateFlags::empty()
            })
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: `info` is a local that outlives the call. Extent and layer count are non-zero and
        // within the device limits (checked above); format, usage, samples and mip count come from
        // the `ImageDesc` constructors, whose callers choose combinations the device supports
        // (this is not re-checked here).
        let raw = unsafe { ctx.device.create_image(&info, None) }?;
        // SAFETY: `raw` was just created from `ctx.device` (non-disjoint, so no plane info needed).
        let requirements = unsafe { ctx.device.get_image_memory_requirements(raw) };
        if let Err(e) = limits.check_allocation(
            &format!("{name} ({}x{} image)", desc.width, desc.height),
            requirements.size,
        ) {
            // SAFETY: `raw` was created above, has no memory, view or command using it, and is not
            // used after this.
            unsafe { ctx.device.destroy_image(raw, None) };
            return Err(e);
        }
        let allocation = match ctx.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        }) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: as above: `raw` is unbound, unused, and dropped here.
                unsafe { ctx.device.destroy_image(raw, None) };
                return Err(e.into());
            }
        };
        // SAFETY: `raw` is a new image with no memory bound yet (VUID-vkBindImageMemory-image-07460);
        // `allocation` came from this device's allocator for `requirements` (non-linear, so
        // bufferImageGranularity is respected), so its memory type, alignment and size fit.
        let bound = unsafe {
            ctx.device
                .bind_image_memory(raw, allocation.memory(), allocation.offset())
        };
        let view = bound.and_then(|_| {
            let range = desc.range((0, desc.mip_levels), (0, desc.layers));
            let view_info = desc.view_info(raw, desc.view_type(), range);
            // SAFETY: `view_info` is a local that outlives the call; `raw` is bound to memory
            // (this closure runs only when the bind succeeded); the view covers exactly the
            // image's mips and layers with its own format, aspect and a view type matching its
            // layer count and cube flag (`view_type`).
            unsafe { ctx.device.create_image_view(&view_info, None) }
        });
        let view = match view {
            Ok(v) => v,
            Err(e) => {
                let _ = ctx.allocator().free(allocation);
                // SAFETY: `raw` has no view (creating it failed) and no command ever used it; it is
                // not used after this, so the memory freed just before is never accessed through it.
                unsafe { ctx.device.destroy_image(raw, None) };
                return Err(e.into());
            }
        };
        ctx.set_name(raw, name);
        ctx.set_name(view, &format!("{name} view"));
        Ok(Self {
            raw,
            view,
            desc,
            extra_views: Vec::new(),
            allocation: Some(allocation),
            ctx: ctx.clone(),
        })
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.desc.extent()
    }

    pub fn subresource_range(&self) -> vk::ImageSubresourceRange {
        self.desc.full_range()
    }

    /// An extra view of one mip level (all layers; a cube stays a cube), owned by the image.
    pub fn mip_view(&mut self, level: u32) -> Result<vk::ImageView, VkError> {
        let range = self.desc.range((level, 1), (0, self.desc.layers));
        let info = self.desc.view_info(self.raw, self.desc.view_type(), range);
        // SAFETY: `info` is a local that outlives the call; `self.raw` is a live, bound image of
        // this device. The range is one mip at `level` over all layers; the caller passes
        // `level < mip_levels` (as the IBL passes do: one view per mip).
        let view = unsafe { self.ctx.device.create_image_view(&info, None) }?;
        Ok(self.keep_view(view, &format!("mip {level} view")))
    }
}

impl Image {
    /// Names `view`, an extra view of this image, and destroys it with the image.
    fn keep_view(&mut self, view: vk::ImageView, name: &str) -> vk::ImageView {
        self.ctx.set_name(view, name);
        self.extra_views.push(view);
        view
    }

    /// An extra 2D view of one array layer (mip 0), owned by the image: a render target for
    /// one layer (the shadow maps).
    pub fn layer_view(&mut self, layer: u32) -> Result<vk::ImageView, VkError> {
        if layer >= self.desc.layers {
            return Err(VkError::Setup(format!(
                "layer {layer} of an image with {} layers",
                self.desc.layers
            )));
        }
        let range = self.desc.range((0, 1), (layer, 1));
        let info = self
            .desc
            .view_info(self.raw, vk::ImageViewType::TYPE_2D, range);
        // SAFETY: `info` is a local that outlives the call; `self.raw` is a live, bound image of
        // this device; the range is mip 0 of one layer below the layer count (checked above), a
        // 2D view of a 2D image with the image's own format and aspect.
        let view = unsafe { self.ctx.device.create_image_view(&info, None) }?;
        Ok(self.keep_view(view, &format!("layer {layer} view")))
    }
}

/// A sampler, destroyed on drop.
pub struct Sampler {
    pub raw: vk::Sampler,
    ctx: Arc<Context>,
}

impl Sampler {
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        info: &vk::SamplerCreateInfo<'_>,
    ) -> Result<Self, VkError> {
        // SAFETY: `info` is borrowed for the call. Callers enable anisotropy only when the device
        // feature is on, with `max_anisotropy` clamped to `maxSamplerAnisotropy`
        // (`SamplerDesc::anisotropy_for`).
        let raw = unsafe { ctx.device.create_sampler(info, None) }?;
        ctx.set_name(raw, name);
        Ok(Self {
            raw,
            ctx: ctx.clone(),
        })
    }

    /// Trilinear filtering with the given address mode on u (v and w clamp to edge).
    pub fn linear(
        ctx: &Arc<Context>,
        name: &str,
        address_u: vk::SamplerAddressMode,
    ) -> Result<Self, VkError> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(address_u)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(vk::LOD_CLAMP_NONE);
        Self::new(ctx, name, &info)
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: `self.raw` was created from `self.ctx.device` (alive through `self.ctx`) and is
        // destroyed only here, after the work that used it finished (VUID-vkDestroySampler-sampler-01082):
        // owners wait for their submissions (fences, `device_wait_idle`) before dropping samplers.
        unsafe { self.ctx.device.destroy_sampler(self.raw, None) };
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the views and the image were created from `self.ctx.device` (alive through
        // `self.ctx`) and are destroyed exactly once: `drain` empties `extra_views`, and `view` and
        // `raw` are not used again. Views go before their image. No submitted command still uses
        // them (VUID-vkDestroyImage-image-01000, VUID-vkDestroyImageView-imageView-01026): owners
        // drop images only after waiting for the work that used them (one-shot submissions wait;
        // `Headless` and the viewer wait on fences or `device_wait_idle`). The memory is freed
        // after the image is gone.
        unsafe {
            for v in self.extra_views.drain(..) {
                self.ctx.device.destroy_image_view(v, None);
            }
            self.ctx.device.destroy_image_view(self.view, None);
            self.ctx.device.destroy_image(self.raw, None);
        }
        if let Some(a) = self.allocation.take() {
            let _ = self.ctx.allocator().free(a);
        }
    }
}

pub use super::cmd::ImageState;

/// A copy of `width`×`height` texels of mip `mip` (layer 0, colour) from `buffer_offset`.
pub fn color_region(
    mip: u32,
    buffer_offset: vk::DeviceSize,
    (width, height): (u32, u32),
) -> vk::BufferImageCopy {
    vk::BufferImageCopy {
        buffer_offset,
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: mip,
            base_array_layer: 0,
            layer_count: 1,
        },
        image_extent: vk::Extent3D {
            width,
            height,
            depth: 1,
        },
        ..Default::default()
    }
}

/// Copies `bytes` into `image` through a staging buffer: `range` goes from `from` to
/// TRANSFER_DST_OPTIMAL, receives `regions` (offsets into `bytes`), then goes to `to`. Submits and
/// waits.
#[allow(clippy::too_many_arguments)]
pub fn upload(
    ctx: &Arc<Context>,
    pool: &super::cmd::CommandPool,
    image: &Image,
    bytes: &[u8],
    regions: &[vk::BufferImageCopy],
    range: vk::ImageSubresourceRange,
    from: ImageState,
    to: ImageState,
) -> Result<(), VkError> {
    let staging = super::Buffer::with_data(
        ctx,
        "image upload staging",
        bytes,
        vk::BufferUsageFlags::TRANSFER_SRC,
    )?;
    let d = &ctx.device;
    let dst = (
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_WRITE,
    );
    let raw = image.raw;
    pool.one_shot(|cmd| {
        super::cmd::between_transitions(d, cmd, (raw, range), [from, dst, to], || {
            // SAFETY: `one_shot` hands over `cmd` recording, outside a render pass. `staging`
            // (TRANSFER_SRC, holding `bytes`) lives until `one_shot` has waited for the copy;
            // `raw` is in TRANSFER_DST_OPTIMAL over `range` after the transition just recorded.
            // The caller passes `regions` inside `bytes` and inside `range` of `image`, and
            // `image` with TRANSFER_DST usage (the contract of this function).
            unsafe {
                d.cmd_copy_buffer_to_image(
                    cmd,
                    staging.raw,
                    raw,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    regions,
                )
            };
        });
        Ok(())
    })
}
