//! A/B comparison maps on the GPU, every frame (the viewer's `difference` and `flip` modes):
//! `compare.comp` computes the map of two HDR images and its summary figures, and
//! `compare_show.frag` draws it through FLIP's magma palette into the swapchain image.
//!
//! * difference: `max_c |A_c − B_c|` in linear radiance, as [`crate::compare::difference_map`];
//!   the colour bar's top is the map's 99th percentile (its maximum when that is 0) from a
//!   histogram of 1/6-octave bins, rounded up to the bin's top and clamped to the maximum, so a
//!   uniform map is exactly the top colour and identical inputs the bottom one.
//! * FLIP: LDR FLIP of B against A after A's exposure and tone map and the 8-bit sRGB encode, a
//!   port of nv-flip's separable C++ code ([`crate::compare::flip_map`] runs that code on the
//!   CPU): a conversion pass, a horizontal and a vertical filter pass. The colour bar is 0..1.
//!
//! The figures (histogram, maximum, count above 0.01, one sum per workgroup) go to a host-visible
//! buffer per frame slot, read after the slot's fence ([`ComparePass::read_stats`]).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::color::{exposure_scale, Tonemap};
use crate::compare::{ErrorMap, MapStats};
use crate::render::tonemap::tonemap_id;
use luz_graph::{Access, FrameGraph, ImageHandle, ImageStateBefore};

use crate::render::frame::{self, HDR_COMPARE_READ, TRANSFER_FILL};
use crate::vk::image::ImageDesc;
use crate::vk::interface::keys_with_prefix;
use crate::vk::pipeline::{GraphicsDesc, Pipeline};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Buffer, Context, Image, PushSet, VkError};

use crate::glsl::compare_comp as cc;
use crate::glsl::compare_show_frag as cs;

/// What the map measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CompareKind {
    Difference,
    Flip,
}

/// FLIP's constants (nv-flip `sharedflip.h`).
const PI: f32 = std::f32::consts::PI;
const GQC: f32 = 0.7;
const GPC: f32 = 0.4;
const GW: f32 = 0.082;

/// The largest filter radius `compare.comp`'s shared-memory tiles hold (`MAX_RADIUS`).
pub const MAX_FLIP_RADIUS: u32 = 10;

/// Radii of FLIP's spatial and feature filters at `ppd` pixels per degree (nv-flip's
/// `calculateSpatialFilterRadius` and `3σ` of the feature filter).
pub fn flip_radii(ppd: f32) -> (u32, u32) {
    let spatial = (3.0 * (0.04f32 / (2.0 * PI * PI)).sqrt() * ppd).ceil() as u32;
    let feature = (3.0 * 0.5 * GW * ppd).ceil() as u32;
    (spatial, feature)
}

fn lab(rgb: [f32; 3]) -> [f32; 3] {
    let xyz = [
        (10135552.0 / 24577794.0) * rgb[0]
            + (8788810.0 / 24577794.0) * rgb[1]
            + (4435075.0 / 24577794.0) * rgb[2],
        (2613072.0 / 12288897.0) * rgb[0]
            + (8788810.0 / 12288897.0) * rgb[1]
            + (887015.0 / 12288897.0) * rgb[2],
        (1425312.0 / 73733382.0) * rgb[0]
            + (8788810.0 / 73733382.0) * rgb[1]
            + (70074185.0 / 73733382.0) * rgb[2],
    ];
    let inv = [1.052_156_9_f32, 1.0, 0.918_357_7];
    let delta = 6.0f32 / 29.0;
    let f = |i: usize| {
        let v = xyz[i] * inv[i];
        if v > delta * delta * delta {
            v.powf(1.0 / 3.0)
        } else {
            v / (3.0 * delta * delta) + 4.0 / 29.0
        }
    };
    let (x, y, z) = (f(0), f(1), f(2));
    let l = 116.0 * y - 16.0;
    [l, 0.01 * l * 500.0 * (x - y), 0.01 * l * 200.0 * (y - z)]
}

/// FLIP's filter taps and colour constants as `compare.comp` reads them: `(cmax, pccmax, 0, 0)`,
/// the spatial filter's taps (Y, Cx, Cz's two Gaussians), the feature filter's (Gaussian, first
/// and second derivative, 0); nv-flip's `setSpatialFilters`, `setFeatureFilter` and
/// `computeMaxDistance`.
pub fn flip_weights(ppd: f32) -> Vec<[f32; 4]> {
    let (rs, rf) = flip_radii(ppd);
    let (rs, rf) = (rs as i32, rf as i32);
    let green = lab([0.0, 1.0, 0.0]);
    let blue = lab([0.0, 0.0, 1.0]);
    let hyab = (green[0] - blue[0]).abs()
        + ((green[1] - blue[1]).powi(2) + (green[2] - blue[2]).powi(2)).sqrt();
    let cmax = hyab.powf(GQC);
    let mut out = vec![[cmax, GPC * cmax, 0.0, 0.0]];
    let gauss = |x2: f32, a: f32, b: f32| a * (PI / b).sqrt() * (-PI * PI * x2 / b).exp();
    let gauss_sqrt =
        |x2: f32, a: f32, b: f32| (a * (PI / b).sqrt()).sqrt() * (-PI * PI * x2 / b).exp();
    let spatial: Vec<[f32; 4]> = (-rs..=rs)
        .map(|i| {
            let x = i as f32 / ppd;
            let x2 = x * x;
            [
                gauss(x2, 1.0, 0.0047),
                gauss(x2, 1.0, 0.0053),
                gauss_sqrt(x2, 34.1, 0.04),
                gauss_sqrt(x2, 13.5, 0.025),
            ]
        })
        .collect();
    let sum = |c: usize| spatial.iter().map(|t| t[c]).sum::<f32>();
    let (sy, sx) = (sum(0), sum(1));
    let sz = (sum(2) * sum(2) + sum(3) * sum(3)).sqrt();
    out.extend(
        spatial
            .iter()
            .map(|t| [t[0] / sy, t[1] / sx, t[2] / sz, t[3] / sz]),
    );
    let sd = 0.5 * GW * ppd;
    let feature: Vec<[f32; 3]> = (-rf..=rf)
        .map(|i| {
            let x = i as f32;
            let g = (-(x * x) / (2.0 * sd * sd)).exp();
            [g, -x * g, (x * x / (sd * sd) - 1.0) * g]
        })
        .collect();
    let g_sum: f32 = feature.iter().map(|t| t[0]).sum();
    let pos = |c: usize| feature.iter().map(|t| t[c].max(0.0)).sum::<f32>();
    let neg = |c: usize| feature.iter().map(|t| (-t[c]).max(0.0)).sum::<f32>();
    let (dp, dn, ddp, ddn) = (pos(1), neg(1), pos(2), neg(2));
    out.extend(feature.iter().map(|t| {
        [
            t[0] / g_sum,
            t[1] / if t[1] > 0.0 { dp } else { dn },
            t[2] / if t[2] > 0.0 { ddp } else { ddn },
            0.0,
        ]
    }));
    out
}

/// Bytes before the per-workgroup sums in the stats buffer (`include/compare_stats.glsl`).
const STATS_HEADER: u64 = 256 * 4 + 16;

/// The largest value histogram bin `b` holds (`stats_bin_top` in `include/compare_stats.glsl`).
fn bin_top(kind: CompareKind, b: usize) -> f32 {
    match kind {
        CompareKind::Difference if b == 0 => 0.0,
        CompareKind::Difference => (b as f32 / 6.0 - 26.0).exp2(),
        CompareKind::Flip => (b + 1) as f32 / 256.0,
    }
}

/// The figures of one GPU map: [`MapStats`] with percentiles from the histogram (the top of the
/// bin that holds the rank, at most the maximum: within a sixth of an octave for a difference,
/// 1/256 for FLIP; mean, maximum and share above 0.01 exact) and the colour bar's top.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpuMapStats {
    pub stats: MapStats,
    pub scale: f32,
}

impl GpuMapStats {
    /// Decodes a stats buffer's bytes for a `width × height` map.
    pub fn decode(kind: CompareKind, bytes: &[u8], (width, height): (u32, u32)) -> Self {
        let words: &[u32] = bytemuck::cast_slice(&bytes[..STATS_HEADER as usize]);
        let hist = &words[..256];
        let max = f32::from_bits(words[256]);
        let above = words[257];
        let scale = f32::from_bits(words[258]);
        let groups = (width.div_ceil(16) * height.div_ceil(16)) as usize;
        let end = STATS_HEADER as usize + groups * 4;
        let sums: &[f32] = bytemuck::cast_slice(&bytes[STATS_HEADER as usize..end]);
        let n = u64::from(width) * u64::from(height);
        let total: u64 = hist.iter().map(|&c| u64::from(c)).sum();
        let rank = |p: f64| {
            let k = ((p * total as f64).ceil() as u64).max(1);
            let mut acc = 0u64;
            for (b, &c) in hist.iter().enumerate() {
                acc += u64::from(c);
                if acc >= k {
                    return bin_top(kind, b).min(max);
                }
            }
            max
        };
        Self {
            stats: MapStats {
                mean: (sums.iter().map(|&s| f64::from(s)).sum::<f64>() / n.max(1) as f64) as f32,
                p50: rank(0.50),
                p95: rank(0.95),
                p99: rank(0.99),
                max,
                above: above as f32 / n.max(1) as f32,
            },
            scale,
        }
    }
}

/// Format of the intermediate and map images.
const MAP_FORMAT: vk::Format = vk::Format::R32_SFLOAT;
const WORK_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ComparePush {
    exposure_scale: f32,
}

/// The map and its figures as a frame graph declared them ([`ComparePass::add_pass`]): a pass
/// that shows the map ([`ComparePass::record_show`]) reads both ([`MAP_SHOW_READ`],
/// `FragmentStorageBufferRead`).
#[derive(Debug, Clone, Copy)]
pub struct MapHandles {
    pub map: ImageHandle,
    pub figures: luz_graph::BufferHandle,
}

/// How [`ComparePass::record_show`] reads the map: a storage image in GENERAL, in the fragment
/// stage.
pub const MAP_SHOW_READ: Access = Access::FragmentStorageRead;

/// The maps of two HDR images (SAMPLED usage, read in GENERAL layout) of one size. The map and
/// the work images are transients of the frame graph; every image is pushed at record time.
pub struct ComparePass {
    extent: vk::Extent2D,
    stats: Vec<Buffer>,
    weights: Buffer,
    srgb_table: Buffer,
    palette: Buffer,
    /// The kernels' layout.
    kernels_layout: PushSet,
    /// The map display's layout.
    show: PushSet,
    radii: (u32, u32),
    kernels: Vec<((CompareKind, Tonemap), Vec<Pipeline>)>,
    shows: Vec<(vk::Format, Pipeline)>,
    ctx: Arc<Context>,
}

/// The work images' names: YCxCz of A and B, then the horizontal passes' results (colour,
/// features) of A and B, in the order of [`WORK_BINDINGS`].
const WORK_NAMES: [&str; 6] = [
    "compare YCxCz A",
    "compare YCxCz B",
    "compare colour A",
    "compare features A",
    "compare colour B",
    "compare features B",
];
const WORK_BINDINGS: [u32; 6] = [
    cc::BINDING_YCC_A as u32,
    cc::BINDING_YCC_B as u32,
    cc::BINDING_H0_A as u32,
    cc::BINDING_H1_A as u32,
    cc::BINDING_H0_B as u32,
    cc::BINDING_H1_B as u32,
];

/// The usage of the map and the work images (stated, so the pooled images' descriptions do not
/// depend on whether a frame copies the map).
const STORAGE_USAGE: vk::ImageUsageFlags = vk::ImageUsageFlags::from_raw(
    vk::ImageUsageFlags::STORAGE.as_raw() | vk::ImageUsageFlags::TRANSFER_SRC.as_raw(),
);

impl ComparePass {
    /// A pass comparing images of `extent`, with a figures buffer for each of `slots` frames in
    /// flight.
    pub fn new(ctx: &Arc<Context>, extent: vk::Extent2D, slots: usize) -> Result<Self, VkError> {
        let kernels: Vec<&str> = keys_with_prefix("compare.comp:").collect();
        let kernels_layout = PushSet::new(ctx, "compare", &kernels)?;
        let show = PushSet::new(ctx, "compare show", &["display.vert", "compare_show.frag"])?;
        let groups = u64::from(extent.width.div_ceil(16) * extent.height.div_ceil(16));
        let stats = (0..slots)
            .map(|i| {
                Buffer::new(
                    ctx,
                    &format!("compare stats {i}"),
                    STATS_HEADER + 4 * groups,
                    vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryLocation::GpuToCpu,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        let weights = Buffer::with_data(
            ctx,
            "compare FLIP weights",
            flip_weights(crate::diff::DEFAULT_PIXELS_PER_DEGREE).as_slice(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let srgb_table = super::srgb_table(ctx, "compare sRGB encode table")?;
        let palette: Vec<u32> = crate::compare::palette()
            .iter()
            .map(|c| u32::from(c[0]) | u32::from(c[1]) << 8 | u32::from(c[2]) << 16)
            .collect();
        let palette = Buffer::with_data(
            ctx,
            "compare palette",
            palette.as_slice(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        Ok(Self {
            extent,
            stats,
            weights,
            srgb_table,
            palette,
            kernels_layout,
            show,
            radii: flip_radii(crate::diff::DEFAULT_PIXELS_PER_DEGREE),
            kernels: Vec::new(),
            shows: Vec::new(),
            ctx: ctx.clone(),
        })
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// Builds the kernels of `kind` with `tonemap` and the display pipeline for `format` unless
    /// they exist.
    pub fn prepare(
        &mut self,
        kind: CompareKind,
        tonemap: Tonemap,
        format: vk::Format,
    ) -> Result<(), VkError> {
        let tonemap = if kind == CompareKind::Flip {
            tonemap
        } else {
            Tonemap::None
        };
        if !self.kernels.iter().any(|(k, _)| *k == (kind, tonemap)) {
            let names: &[&str] = match kind {
                CompareKind::Difference => {
                    &["compare.comp:difference", "compare.comp:scale_difference"]
                }
                CompareKind::Flip => &[
                    "compare.comp:flip_convert",
                    "compare.comp:flip_h",
                    "compare.comp:flip_v",
                    "compare.comp:scale_flip",
                ],
            };
            let spec = [
                (cc::SPEC_TONEMAP, tonemap_id(tonemap)),
                (cc::SPEC_SPATIAL_RADIUS, self.radii.0),
                (cc::SPEC_FEATURE_RADIUS, self.radii.1),
            ];
            let pipelines = names
                .iter()
                .map(|k| {
                    let module = ShaderModule::new(&self.ctx, k)?;
                    Pipeline::compute(&self.ctx, &self.kernels_layout.layout, k, &module, &spec)
                })
                .collect::<Result<Vec<_>, _>>()?;
            self.kernels.push(((kind, tonemap), pipelines));
        }
        if !self.shows.iter().any(|(f, _)| *f == format) {
            let vertex = ShaderModule::new(&self.ctx, "display.vert")?;
            let fragment = ShaderModule::new(&self.ctx, "compare_show.frag")?;
            let pipeline = Pipeline::graphics(
                &self.ctx,
                &self.show.layout,
                &GraphicsDesc::fullscreen(
                    &format!("compare show [{format:?}]"),
                    (&vertex, &fragment),
                    &[],
                    &[format],
                ),
            )?;
            self.shows.push((format, pipeline));
        }
        Ok(())
    }

    /// The stage and access A and B must be readable at before [`ComparePass::record`] (in
    /// GENERAL layout).
    pub fn source_access() -> crate::vk::image::ImageState {
        (
            vk::ImageLayout::GENERAL,
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
        )
    }

    /// Declares the map of `kind` (node `name`) from the HDR images `a` and `b` (the two this
    /// pass was made for, read in GENERAL: [`HDR_COMPARE_READ`]) into slot `slot`'s figures (A's
    /// `exposure_ev` and `tonemap` for FLIP). The graph leaves the map readable by
    /// [`ComparePass::record_show`] and the figures by the host after the frame's fence. The
    /// kernels must be [`ComparePass::prepare`]d.
    pub fn add_pass<'a>(
        &'a self,
        g: &mut FrameGraph<'a>,
        (name, slot): (&'static str, usize),
        (a, b): (ImageHandle, ImageHandle),
        kind: CompareKind,
        (exposure_ev, tonemap): (f32, Tonemap),
    ) -> Result<MapHandles, VkError> {
        let tonemap = if kind == CompareKind::Flip {
            tonemap
        } else {
            Tonemap::None
        };
        let pipelines: Vec<vk::Pipeline> = self
            .kernels
            .iter()
            .find(|(k, _)| *k == (kind, tonemap))
            .map(|(_, p)| p.iter().map(|p| p.raw).collect())
            .ok_or_else(|| VkError::Setup("compare: the kernels were not prepared".into()))?;
        // The work images and the map hold nothing between frames: transients.
        let (w, h) = (self.extent.width, self.extent.height);
        let storage = |g: &mut FrameGraph<'a>, name: &str, format| {
            g.create_image(
                name,
                luz_graph::ImageDesc::color(w, h, format).usage(STORAGE_USAGE),
            )
        };
        let work: Vec<ImageHandle> = WORK_NAMES
            .iter()
            .map(|n| storage(g, n, WORK_FORMAT))
            .collect();
        let map = storage(g, "compare map", MAP_FORMAT);
        let stats = &self.stats[slot];
        let figures = g.import_buffer("compare figures", stats.raw, stats.size, None);
        g.buffer_after(figures, Access::HostRead);
        let mut pass = g
            .pass(name)
            .read(a, HDR_COMPARE_READ)
            .read(b, HDR_COMPARE_READ)
            .write(map, Access::ComputeStorageReadWrite)
            .write(figures, Access::ComputeStorageBufferReadWrite);
        for w in &work {
            pass = pass.write(*w, Access::ComputeStorageReadWrite);
        }
        let push = ComparePush {
            exposure_scale: exposure_scale(exposure_ev),
        };
        let groups = (
            self.extent.width.div_ceil(16),
            self.extent.height.div_ceil(16),
        );
        pass.record(move |rc| {
            let general = vk::ImageLayout::GENERAL;
            let mut writes = self
                .kernels_layout
                .writes()
                .buffer(cc::BINDING_SRGB_TABLE as u32, self.srgb_table.raw)
                .buffer(cc::BINDING_WEIGHTS as u32, self.weights.raw)
                .buffer(cc::BINDING_STATS as u32, stats.raw)
                .view(cc::BINDING_A as u32, rc.image(a)?.view, general)
                .view(cc::BINDING_B as u32, rc.image(b)?.view, general)
                .view(cc::BINDING_MAP as u32, rc.image(map)?.view, general);
            for (binding, h) in WORK_BINDINGS.iter().zip(&work) {
                writes = writes.view(*binding, rc.image(*h)?.view, general);
            }
            rc.buffer(figures)?;
            let (d, cmd) = (&self.ctx.device, rc.cmd());
            // SAFETY: `stats` has TRANSFER_DST usage and the fill covers its header; `cmd` is
            // recording outside a render pass (the graph records one pass at a time).
            unsafe { d.cmd_fill_buffer(cmd, stats.raw, 0, STATS_HEADER, 0) };
            rc.memory_barrier(TRANSFER_FILL, Access::ComputeStorageReadWrite);
            // SAFETY: every pipeline was built with `self.kernels_layout.layout`, whose set 0
            // `writes` fills, and the push bytes are a `ComparePush`, its push range. The views
            // are the graph's images for this frame (live until it completes); the graph put the
            // work images and the map in GENERAL and made A and B readable in GENERAL (the
            // accesses declared above); each kernel is ordered after the one before by the
            // barrier between them. The buffers are the pass's own.
            unsafe {
                self.kernels_layout
                    .push(cmd, vk::PipelineBindPoint::COMPUTE, writes)?;
                self.kernels_layout.layout.push(cmd, &push)?;
            }
            let last = pipelines.len() - 1;
            for (i, p) in pipelines.iter().enumerate() {
                if i > 0 {
                    rc.memory_barrier(
                        Access::ComputeStorageReadWrite,
                        Access::ComputeStorageReadWrite,
                    );
                }
                // SAFETY: as above.
                unsafe {
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, *p);
                    if i == last {
                        d.cmd_dispatch(cmd, 1, 1, 1);
                    } else {
                        d.cmd_dispatch(cmd, groups.0, groups.1, 1);
                    }
                }
            }
            Ok(())
        });
        Ok(MapHandles { map, figures })
    }

    /// Draws `map` (the view of [`MapHandles::map`] this frame) with slot `slot`'s figures
    /// through the palette over `extent`, only inside `clip` (inside a rendering instance on an
    /// attachment of `format`, prepared).
    pub fn record_show(
        &self,
        cmd: vk::CommandBuffer,
        (slot, map): (usize, vk::ImageView),
        format: vk::Format,
        extent: vk::Extent2D,
        clip: vk::Rect2D,
    ) -> Result<(), VkError> {
        let pipeline = super::prepared(&self.shows, &format, || {
            format!("compare: the display pipeline for {format:?}")
        })?;
        let writes = self
            .show
            .writes()
            .view(cs::BINDING_MAP as u32, map, vk::ImageLayout::GENERAL)
            .buffer(cs::BINDING_STATS as u32, self.stats[slot].raw)
            .buffer(cs::BINDING_PALETTE as u32, self.palette.raw);
        // SAFETY: `pipeline` was built with `self.show.layout` for attachments of `format`, with
        // viewport, scissor and cull mode dynamic (no push constants). The caller's part: `map`
        // is this frame's map, in GENERAL and readable by fragment shaders after `add_pass`'s
        // kernels ([`MAP_SHOW_READ`]), and `cmd` records inside a rendering instance on one
        // attachment of `format`.
        unsafe {
            crate::render::display::draw_fullscreen(
                cmd,
                (pipeline, &self.show, writes),
                (extent, clip),
                &[],
            )
        }
    }

    /// Slot `slot`'s figures of its last `kind` map (call after the slot's fence).
    pub fn read_stats(&self, slot: usize, kind: CompareKind) -> Result<GpuMapStats, VkError> {
        let bytes = self.stats[slot].mapped()?;
        Ok(GpuMapStats::decode(
            kind,
            bytes,
            (self.extent.width, self.extent.height),
        ))
    }
}

/// The map of `a` against `b` (same size) computed on the GPU, with its figures: what the viewer
/// shows, for tests and tools. Uploads both, records, waits.
pub fn compare_images(
    ctx: &Arc<Context>,
    pool: &crate::vk::cmd::CommandPool,
    (a, b): (&crate::imageio::LinearImage, &crate::imageio::LinearImage),
    kind: CompareKind,
    (exposure_ev, tonemap): (f32, Tonemap),
) -> Result<(ErrorMap, GpuMapStats), VkError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(VkError::Setup(format!(
            "compare: A is {}x{}, B {}x{}",
            a.width, a.height, b.width, b.height
        )));
    }
    let extent = vk::Extent2D {
        width: a.width,
        height: a.height,
    };
    let upload = |name: &str, img: &crate::imageio::LinearImage| -> Result<Image, VkError> {
        let mut desc = ImageDesc::texture(img.width, img.height, WORK_FORMAT, 1, 1);
        desc.usage |= vk::ImageUsageFlags::STORAGE;
        let image = Image::new(ctx, name, desc)?;
        let region = crate::vk::image::color_region(0, 0, (img.width, img.height));
        crate::vk::image::upload(
            ctx,
            pool,
            &image,
            bytemuck::cast_slice(&img.pixels),
            &[region],
            image.subresource_range(),
            (
                vk::ImageLayout::UNDEFINED,
                vk::PipelineStageFlags2::NONE,
                vk::AccessFlags2::NONE,
            ),
            ComparePass::source_access(),
        )?;
        Ok(image)
    };
    let (ia, ib) = (upload("compare input A", a)?, upload("compare input B", b)?);
    let mut pass = ComparePass::new(ctx, extent, 1)?;
    pass.prepare(kind, tonemap, vk::Format::R8G8B8A8_UNORM)?;
    let out = Buffer::new(
        ctx,
        "compare map read-back",
        u64::from(a.width) * u64::from(a.height) * 4,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    // The map and the work images are transients: their pool outlives the submission.
    let mut transients = frame::Transients::new(ctx);
    pool.one_shot(|cmd| {
        let mut g = FrameGraph::new();
        let uploaded = ImageStateBefore::Keep(HDR_COMPARE_READ);
        let ha = frame::import(&mut g, "compare input A", &ia, uploaded);
        let hb = frame::import(&mut g, "compare input B", &ib, uploaded);
        let map = pass.add_pass(
            &mut g,
            ("A/B map", 0),
            (ha, hb),
            kind,
            (exposure_ev, tonemap),
        )?;
        frame::add_readback(&mut g, "compare map read-back", map.map, &out, extent);
        let graph = g.compile()?;
        transients.execute(ctx, graph, cmd, None)?;
        Ok(())
    })?;
    let n = a.pixels.len();
    let values: Vec<f32> = bytemuck::cast_slice(&out.mapped()?[..n * 4]).to_vec();
    let stats = pass.read_stats(0, kind)?;
    Ok((
        ErrorMap {
            width: a.width,
            height: a.height,
            values,
        },
        stats,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flip_filters_are_nv_flips_at_67_ppd() {
        assert_eq!(flip_radii(67.0), (10, 9));
        let (s, f) = flip_radii(crate::diff::DEFAULT_PIXELS_PER_DEGREE);
        assert!(
            s.max(f) <= MAX_FLIP_RADIUS,
            "compare.comp's tiles hold the filters"
        );
        let w = flip_weights(67.0);
        assert_eq!(w.len(), 1 + 21 + 19);
        // Gaussians sum to 1; the derivatives' positive and negative parts to ±1.
        let s = |r: std::ops::Range<usize>, c: usize| w[r].iter().map(|t| t[c]).sum::<f32>();
        assert!((s(1..22, 0) - 1.0).abs() < 1e-5 && (s(1..22, 1) - 1.0).abs() < 1e-5);
        assert!((s(22..41, 0) - 1.0).abs() < 1e-5);
        assert!(s(22..41, 1).abs() < 1e-5 && s(22..41, 2).abs() < 1e-5);
        // cmax: HyAB of Hunt-adjusted green and blue, to the 0.7.
        assert!(
            w[0][0] > 10.0 && (w[0][1] - 0.4 * w[0][0]).abs() < 1e-6,
            "{:?}",
            w[0]
        );
    }

    #[test]
    fn stats_decode_reads_percentiles_from_the_bins() {
        let (w, h) = (32u32, 16u32);
        let mut words = vec![0u32; (STATS_HEADER / 4) as usize + 2];
        // 511 pixels at 0.25, one at 0.75 (FLIP bins of 1/256).
        words[64] = 511;
        words[192] = 1;
        words[256] = 0.75f32.to_bits();
        words[257] = 512;
        words[258] = 1.0f32.to_bits();
        let sums = [0.25 * 255.0 + 0.75, 0.25 * 256.0];
        for (i, s) in sums.iter().enumerate() {
            words[(STATS_HEADER / 4) as usize + i] = (*s as f32).to_bits();
        }
        let s = GpuMapStats::decode(CompareKind::Flip, bytemuck::cast_slice(&words), (w, h));
        assert_eq!(s.stats.p50, 65.0 / 256.0);
        assert_eq!(s.stats.p99, 65.0 / 256.0);
        assert_eq!(s.stats.max, 0.75);
        assert_eq!(s.stats.above, 1.0);
        assert!((s.stats.mean - (0.25 * 511.0 + 0.75) / 512.0).abs() < 1e-6);
        assert_eq!(bin_top(CompareKind::Difference, 0), 0.0);
        assert_eq!(bin_top(CompareKind::Difference, 156), 1.0);
    }
}
