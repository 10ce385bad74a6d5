//! Glass on the GPU (issue 35): the copy of the opaque scene that transmissive draws read.
//!
//! When a slot's view has transmissive draws, the forward pass is recorded in two rendering
//! instances with a copy between them: "forward" draws the opaque objects and the skybox (and
//! keeps its multisampled colour), "transmission copy" copies the resolved HDR colour into this
//! slot's copy image and fills its mips by halving blits, and "transmissive" loads the colour
//! and depth again and draws the transmissive objects (nearest first, each reading the copy
//! where its refracted ray leaves it: `shaders_glsl/include/transmission.glsl`), then the blended
//! ones. The copy is an image per slot (frames in flight), of the target's size with every mip,
//! in the HDR format, bound to the frame set (`BINDING_TRANSMISSION`); a scene without
//! transmissive draws binds a 1×1 stand-in and records no copy.

use std::sync::Arc;

use ash::vk;
use luz_graph::{Access, FrameGraph, ImageHandle, ImageStateBefore};

use crate::render::frame::{import, settle};
use crate::vk::cmd::CommandPool;
use crate::vk::image::Sampler;
use crate::vk::pipeline::DescriptorSetLayout;
use crate::vk::{Context, Image, SetWrites, VkError};

/// Whether `scene` has a transmissive material the GPU draws as glass (not `refraction: none`).
pub(super) fn transmits(scene: &crate::scene::Scene) -> bool {
    scene.output.refraction != crate::scene::Refraction::None
        && scene.materials.iter().any(|m| {
            super::variant::lobe_bits(&m.material)
                & crate::glsl::brdf_models::BRDF_LOBE_TRANSMISSION
                != 0
        })
}

/// Per slot, the copy image transmissive draws sample, and its sampler.
pub(super) struct TransmissionCopy {
    images: Vec<Image>,
    sampler: Sampler,
    /// The copies' size (1×1 for the stand-in).
    extent: vk::Extent2D,
    format: vk::Format,
}

/// Mip levels of a full chain over `extent`.
fn levels(extent: vk::Extent2D) -> u32 {
    32 - extent.width.max(extent.height).max(1).leading_zeros()
}

impl TransmissionCopy {
    /// Copies of `extent` (a full mip chain) in `format` for `slots` slots, left in the state
    /// transmissive draws read them in, and their sampler (linear, clamped, every mip).
    pub(super) fn new(
        ctx: &Arc<Context>,
        (slots, extent, format): (usize, vk::Extent2D, vk::Format),
    ) -> Result<Self, VkError> {
        let pool = CommandPool::new(ctx, "transmission copy")?;
        let mut images = Vec::with_capacity(slots);
        for slot in 0..slots {
            let desc = crate::vk::image::ImageDesc::texture(
                extent.width,
                extent.height,
                format,
                levels(extent),
                1,
            );
            let image = Image::new(ctx, &format!("transmission copy (slot {slot})"), desc)?;
            settle(ctx, &pool, &image, Access::FragmentSampled)?;
            images.push(image);
        }
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(vk::LOD_CLAMP_NONE);
        let sampler = Sampler::new(ctx, "transmission copy sampler", &info)?;
        Ok(Self {
            images,
            sampler,
            extent,
            format,
        })
    }

    /// The copies' size.
    pub(super) fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// Points `BINDING_TRANSMISSION` of each slot's frame set (`sets`, by slot) at its copy.
    /// The sets must not be in use by the GPU.
    pub(super) fn bind(
        &self,
        ctx: &Arc<Context>,
        layout: &DescriptorSetLayout,
        sets: &[vk::DescriptorSet],
    ) -> Result<(), VkError> {
        for (set, image) in sets.iter().zip(&self.images) {
            let writes = SetWrites::new(layout, *set).image(
                crate::render::gpu::BINDING_TRANSMISSION,
                image.view,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                self.sampler.raw,
            );
            // SAFETY: the caller guarantees `set` is not in use by a pending command buffer; the
            // view and sampler are alive (owned by `self`, which the forward pass keeps as long
            // as its sets), and the image is in SHADER_READ_ONLY_OPTIMAL whenever a draw reads it
            // (settled on creation, left so by every frame's graph).
            unsafe { writes.apply(ctx) }?;
        }
        Ok(())
    }

    /// Declares "transmission copy" for slot `slot`: `source` (the resolved HDR colour of the
    /// opaque scene, `extent`) copied into mip 0 of the slot's copy, the mips blitted from it.
    /// Returns the copy's handle, which the transmissive draws read.
    pub(super) fn add_copy<'a>(
        &'a self,
        g: &mut FrameGraph<'a>,
        (slot, name): (usize, &'static str),
        source: ImageHandle,
        extent: vk::Extent2D,
    ) -> Result<ImageHandle, VkError> {
        let image = &self.images[slot.min(self.images.len() - 1)];
        if extent != self.extent {
            return Err(VkError::Setup(format!(
                "transmission copy: made for {}x{}, the frame is {}x{} (call prepare_extent)",
                self.extent.width, self.extent.height, extent.width, extent.height
            )));
        }
        let copy = import(
            g,
            "transmission copy",
            image,
            ImageStateBefore::Discard(Access::FragmentSampled),
        );
        g.image_after(copy, Access::FragmentSampled);
        let levels = levels(extent);
        g.pass(name)
            .read(source, Access::TransferSrc)
            .write(copy, Access::TransferDst)
            .record(move |rc| {
                let src = rc.image(source)?.image;
                let dst = rc.image(copy)?.image;
                let (d, cmd) = (rc.device(), rc.cmd());
                let layers = vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                };
                let region = vk::ImageCopy {
                    src_subresource: layers,
                    src_offset: vk::Offset3D::default(),
                    dst_subresource: layers,
                    dst_offset: vk::Offset3D::default(),
                    extent: vk::Extent3D {
                        width: extent.width,
                        height: extent.height,
                        depth: 1,
                    },
                };
                // SAFETY: the graph records this pass outside any rendering instance with
                // `source` in TRANSFER_SRC_OPTIMAL and the copy in TRANSFER_DST_OPTIMAL (the
                // accesses declared above); both are single-sample images of at least `extent`
                // in the same format, alive until the frame's submission completes.
                unsafe {
                    d.cmd_copy_image(
                        cmd,
                        src,
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        dst,
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        &[region],
                    )
                };
                crate::vk::cmd::blit_mip_chain(d, cmd, dst, extent, levels);
                Ok(())
            });
        Ok(copy)
    }

    /// The HDR format the copies hold.
    pub(super) fn format(&self) -> vk::Format {
        self.format
    }
}
