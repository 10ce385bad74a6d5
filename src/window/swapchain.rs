//! The window surface's swapchain: format and present-mode choice, one "render finished"
//! semaphore per swapchain image (a present may still wait on a semaphore of its image when the
//! next frame in flight starts, so per-frame semaphores would be reused too early), recreation on
//! resize, out-of-date or suboptimal results.

use std::sync::Arc;

use ash::vk;

use crate::vk::{Context, VkError};

pub struct Swapchain {
    pub loader: ash::khr::swapchain::Device,
    pub raw: vk::SwapchainKHR,
    pub images: Vec<vk::Image>,
    pub views: Vec<vk::ImageView>,
    /// Signalled by the frame that rendered into image i, waited on by its present.
    pub render_finished: Vec<vk::Semaphore>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub present_mode: vk::PresentModeKHR,
    /// The images allow TRANSFER_SRC (screenshots with the UI).
    pub can_read: bool,
    ctx: Arc<Context>,
}

/// Formats the tone-map output can be copied to unchanged: 8-bit UNORM holding sRGB codes.
const FORMATS: [vk::Format; 2] = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM];

impl Swapchain {
    /// A swapchain of `surface` at `size` (used when the surface does not dictate its extent);
    /// `vsync` selects FIFO, else MAILBOX or IMMEDIATE when available. `old` is retired.
    pub fn new(
        ctx: &Arc<Context>,
        surface_loader: &ash::khr::surface::Instance,
        surface: vk::SurfaceKHR,
        size: (u32, u32),
        vsync: bool,
        old: vk::SwapchainKHR,
    ) -> Result<Self, VkError> {
        let pd = ctx.physical;
        // SAFETY: `pd` is the context's physical device and `ctx.queue_family` one of its queue
        // families; `surface` is a live surface created from the same instance as
        // `surface_loader` (the caller's `Surface` outlives this swapchain).
        let supported = unsafe {
            surface_loader.get_physical_device_surface_support(pd, ctx.queue_family, surface)?
        };
        if !supported {
            return Err(VkError::Setup(format!(
                "{}: queue family {} cannot present to this window",
                ctx.info.name, ctx.queue_family
            )));
        }
        // SAFETY: as above: `pd` and `surface` are live and belong to `surface_loader`'s instance,
        // and presentation support was checked.
        let caps = unsafe { surface_loader.get_physical_device_surface_capabilities(pd, surface)? };
        // SAFETY: as above; ash sizes the output from the count query.
        let formats = unsafe { surface_loader.get_physical_device_surface_formats(pd, surface)? };
        let chosen = FORMATS
            .iter()
            .find_map(|f| {
                formats
                    .iter()
                    .find(|s| s.format == *f && s.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
            })
            .copied()
            .ok_or_else(|| {
                VkError::Setup(format!(
                    "the window offers no 8-bit UNORM sRGB-nonlinear format (offered: {:?})",
                    formats.iter().map(|f| f.format).collect::<Vec<_>>()
                ))
            })?;
        // SAFETY: as above; ash sizes the output from the count query.
        let modes =
            unsafe { surface_loader.get_physical_device_surface_present_modes(pd, surface)? };
        let present_mode = if vsync {
            vk::PresentModeKHR::FIFO
        } else {
            [vk::PresentModeKHR::IMMEDIATE, vk::PresentModeKHR::MAILBOX]
                .into_iter()
                .find(|m| modes.contains(m))
                .unwrap_or(vk::PresentModeKHR::FIFO)
        };
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size.0.clamp(
                    caps.min_image_extent.width,
                    caps.max_image_extent.width.max(1),
                ),
                height: size.1.clamp(
                    caps.min_image_extent.height,
                    caps.max_image_extent.height.max(1),
                ),
            }
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let can_read = caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let mut usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_DST;
        if can_read {
            usage |= vk::ImageUsageFlags::TRANSFER_SRC;
        }
        let loader = ash::khr::swapchain::Device::new(&ctx.instance.raw, &ctx.device);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(count)
            .image_format(chosen.format)
            .image_color_space(chosen.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(
                if caps
                    .supported_composite_alpha
                    .contains(vk::CompositeAlphaFlagsKHR::OPAQUE)
                {
                    vk::CompositeAlphaFlagsKHR::OPAQUE
                } else {
                    vk::CompositeAlphaFlagsKHR::INHERIT
                },
            )
            .present_mode(present_mode)
            .clipped(true)
            .old_swapchain(old);
        // SAFETY: `info` is a local that outlives the call. Its values come from what the surface
        // reported: a supported (format, colour space) pair, an extent clamped to the
        // capabilities, an image count within [min, max], usage and composite alpha the surface
        // supports, its current transform and an available present mode (FIFO always is). The
        // device was created with VK_KHR_swapchain by the viewer (`loader` needs it). `old` is null
        // or the caller's current, not yet retired swapchain of this `surface`.
        let raw = unsafe { loader.create_swapchain(&info, None)? };
        let mut this = Self {
            loader,
            raw,
            images: Vec::new(),
            views: Vec::new(),
            render_finished: Vec::new(),
            format: chosen.format,
            extent,
            present_mode,
            can_read,
            ctx: ctx.clone(),
        };
        // SAFETY: `raw` was just created by `this.loader`; ash sizes the output from the count
        // query.
        this.images = unsafe { this.loader.get_swapchain_images(raw)? };
        for (i, &image) in this.images.iter().enumerate() {
            ctx.set_name(image, &format!("swapchain image {i}"));
            // SAFETY: the create info is a temporary that outlives the call; `image` is a
            // swapchain image of `raw` (bound by the swapchain), 2D with one layer and one mip,
            // viewed with the swapchain's own format over its colour aspect.
            let view = unsafe {
                ctx.device.create_image_view(
                    &vk::ImageViewCreateInfo::default()
                        .image(image)
                        .view_type(vk::ImageViewType::TYPE_2D)
                        .format(chosen.format)
                        .subresource_range(color_range()),
                    None,
                )?
            };
            this.views.push(view);
            // SAFETY: the create info is a temporary that outlives the call; the device is alive
            // while `ctx` is.
            let sem = unsafe {
                ctx.device
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)?
            };
            ctx.set_name(sem, &format!("render finished (image {i})"));
            this.render_finished.push(sem);
        }
        Ok(this)
    }
}

pub fn color_range() -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // SAFETY: the views, semaphores and swapchain were created from `self.ctx.device` /
        // `self.loader` (the device is alive through `self.ctx`) and are destroyed exactly once,
        // views before the swapchain that owns their images. The viewer calls `device_wait_idle`
        // before it replaces or drops a swapchain, so no submitted batch still uses a view or a
        // semaphore and every use of an acquired image has completed
        // (VUID-vkDestroySemaphore-semaphore-01137, VUID-vkDestroySwapchainKHR-swapchain-01282).
        // The surface it was created for is dropped after it (the viewer's field order).
        unsafe {
            for &v in &self.views {
                self.ctx.device.destroy_image_view(v, None);
            }
            for &s in &self.render_finished {
                self.ctx.device.destroy_semaphore(s, None);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}
