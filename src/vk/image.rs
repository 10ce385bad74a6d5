//! 2D images (colour targets, depth, textures) with one view, freed on drop.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::{Context, VkError};

/// What to create.
#[derive(Debug, Clone, Copy)]
pub struct ImageDesc {
    pub width: u32,
    pub height: u32,
    pub format: vk::Format,
    pub usage: vk::ImageUsageFlags,
    pub samples: vk::SampleCountFlags,
    pub mip_levels: u32,
    pub aspect: vk::ImageAspectFlags,
}

impl ImageDesc {
    /// A single-sample colour target that can be copied out.
    pub fn color_target(width: u32, height: u32, format: vk::Format) -> Self {
        Self {
            width,
            height,
            format,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED,
            samples: vk::SampleCountFlags::TYPE_1,
            mip_levels: 1,
            aspect: vk::ImageAspectFlags::COLOR,
        }
    }
    /// A multisampled colour target resolved into a single-sample one.
    pub fn msaa_color(
        width: u32,
        height: u32,
        format: vk::Format,
        samples: vk::SampleCountFlags,
    ) -> Self {
        Self {
            width,
            height,
            format,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
            samples,
            mip_levels: 1,
            aspect: vk::ImageAspectFlags::COLOR,
        }
    }
    pub fn depth(
        width: u32,
        height: u32,
        format: vk::Format,
        samples: vk::SampleCountFlags,
    ) -> Self {
        Self {
            width,
            height,
            format,
            usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            samples,
            mip_levels: 1,
            aspect: vk::ImageAspectFlags::DEPTH,
        }
    }
}

pub struct Image {
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub desc: ImageDesc,
    allocation: Option<Allocation>,
    ctx: Arc<Context>,
}

impl Image {
    pub fn new(ctx: &Arc<Context>, name: &str, desc: ImageDesc) -> Result<Self, VkError> {
        let max = ctx.info.limits.max_image_dimension2_d;
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
                limit_name: "maxImageDimension2D",
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
            .array_layers(1)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let raw = unsafe { ctx.device.create_image(&info, None) }?;
        let requirements = unsafe { ctx.device.get_image_memory_requirements(raw) };
        let allocation = match ctx.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        }) {
            Ok(a) => a,
            Err(e) => {
                unsafe { ctx.device.destroy_image(raw, None) };
                return Err(e.into());
            }
        };
        let bound = unsafe {
            ctx.device
                .bind_image_memory(raw, allocation.memory(), allocation.offset())
        };
        let view = bound.and_then(|_| {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(raw)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(desc.format)
                .subresource_range(vk::ImageSubresourceRange {
                    aspect_mask: desc.aspect,
                    base_mip_level: 0,
                    level_count: desc.mip_levels,
                    base_array_layer: 0,
                    layer_count: 1,
                });
            unsafe { ctx.device.create_image_view(&view_info, None) }
        });
        let view = match view {
            Ok(v) => v,
            Err(e) => {
                let _ = ctx.allocator().free(allocation);
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
            allocation: Some(allocation),
            ctx: ctx.clone(),
        })
    }

    pub fn extent(&self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.desc.width,
            height: self.desc.height,
        }
    }

    pub fn subresource_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.desc.aspect,
            base_mip_level: 0,
            level_count: self.desc.mip_levels,
            base_array_layer: 0,
            layer_count: 1,
        }
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        unsafe {
            self.ctx.device.destroy_image_view(self.view, None);
            self.ctx.device.destroy_image(self.raw, None);
        }
        if let Some(a) = self.allocation.take() {
            let _ = self.ctx.allocator().free(a);
        }
    }
}
