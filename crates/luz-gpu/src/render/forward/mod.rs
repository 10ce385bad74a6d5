//! The forward pass: draws every object of a scene with the pipeline variant its material, shading
//! frequency and the scene's fog need. Variants are built once, only those the scene uses.

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use luz_graph::{Access, FrameGraph};

use super::draws::{self, ColorView, DrawList};
use super::frame::SceneTarget;
use super::gpu::{self, GpuLight, MaterialPush, Vertex};
use super::ibl::Ibl;
use super::material::{MaterialSets, SET_MATERIAL};
use super::mesh;
use super::shadow::{self, ShadowMaps};
use crate::color::Tonemap;
use crate::prepare::{PrepareOptions, PreparedScene};
use crate::scene::{Saturation, Scene, Shading};
use crate::vk::buffer::Uploader;
use crate::vk::cmd::{color_attachment, depth_attachment, rendering_info, CommandPool, Load};
use crate::vk::pipeline::{DescriptorPool, DescriptorSetLayout, Pipeline, PipelineLayout};
use crate::vk::{Buffer, Context, SetWrites, VkError};
use world::{Change, Shape};

mod build;
pub mod clusters;
mod deferred;
mod emitter;
mod instances;
mod lod;
mod per_frame;
mod record;
mod transmission;
mod variant;
pub mod world;

use build::{build_draws, frame_set_layout, storage_fits, Draws};
pub use build::{lut_geometries, lut_geometry, needs_aniso_lut};
pub use clusters::{ClusterStats, LightLoop};

pub use deferred::{eligible as deferred_eligible, RenderPath, GBUFFER_FORMAT};

pub use per_frame::ReceiverStats;
use variant::{create_pipeline, create_skybox, Modules};
pub use variant::{material_key, AlphaKey, DebugView, IblKey, ShadingKey, TermsKey, VariantKey};

/// A mesh's buffers (its bounds and LOD levels are the draw list's [`draws::Shape`]).
struct GpuMesh {
    vertices: Buffer,
    centroids: Option<Buffer>,
    /// Vertex colours (binding 2), for meshes that have them.
    colors: Option<Buffer>,
    indices: Buffer,
    /// Indices of the full-detail level (the first ones of `indices`).
    index_count: u32,
}

impl GpuMesh {
    /// The buffers' handles, as the passes record them.
    fn raw(&self) -> super::MeshRef {
        super::MeshRef {
            vertices: self.vertices.raw,
            centroids: self.centroids.as_ref().map(|c| c.raw),
            colors: self.colors.as_ref().map(|c| c.raw),
            indices: self.indices.raw,
            index_count: self.index_count,
        }
    }
}

/// What the forward pass adds to a draw-list item (same index): its pipeline variant and push
/// constants, and where its shadow lookups are needed.
struct Draw {
    variant: VariantKey,
    push: MaterialPush,
    /// Where (NDC x0, y0, x1, y1) the shadow lookups of `variant` are needed; elsewhere the
    /// draw is recorded with [`VariantKey::unshadowed`] ([`draws::split`]). `None`: everywhere.
    shadow_area: Option<[f32; 4]>,
}

/// Maps and light kinds of a generic ("all features") pipeline (its terms are
/// [`TermsKey::Generic`]): the shader keeps the code for every map and light kind.
pub const GENERIC_MAPS: u32 = 0xFF;
pub const GENERIC_LIGHT_KINDS: u32 = (gpu::LK_AREA_SHADOW_PCSS << 1) - 1;

/// How to build a [`ForwardPass`] beyond the scene and the target.
#[derive(Debug, Clone)]
pub struct PassOptions {
    pub debug: DebugView,
    /// Copies of the per-frame data, one per frame in flight (≥ 1).
    pub slots: usize,
    /// Build "all features" pipelines (runtime BRDF selectors, every map and light kind) instead
    /// of pipelines specialised to the scene: what the minimal pipelines save (`luz lab`).
    pub generic: bool,
    /// The output whose pipelines are built up front (others on [`ForwardPass::prepare`]).
    pub output: Output,
    /// Deferred lighting where the scene allows it, or always forward.
    pub path: RenderPath,
    /// Plain or clustered light loop in the fragment stage (or chosen from the scene's lights).
    pub light_loop: LightLoop,
    /// Keep meshes' LOD chains here between runs ([`crate::scene::lod::cache`]; `None`: build
    /// them every time).
    pub lod_cache: Option<std::path::PathBuf>,
    /// What measurements and comparisons turn off (all on by default).
    pub switches: Switches,
}

/// The savings a measurement or a comparison can turn off, each on by default (the image is the
/// same either way, to the bit: `tests/instancing.rs`, `tests/shadow_receivers.rs`). They are
/// options, not environment variables, so that an image's provenance records them
/// ([`crate::provenance::add_switches`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Switches {
    /// One instanced draw per run of draws sharing mesh, level, pipeline and material (off: one
    /// draw per object).
    pub instancing: bool,
    /// Shadow maps nothing they see changed in are reused (off: drawn every frame).
    pub shadow_cache: bool,
    /// Shadow lookups only where shadows can fall (off: everywhere).
    pub shadow_receivers: bool,
}

impl Default for Switches {
    fn default() -> Self {
        Self {
            instancing: true,
            shadow_cache: true,
            shadow_receivers: true,
        }
    }
}

impl Switches {
    /// These switches for a run of `frames` frames: shadow receivers are culled only when more
    /// than one frame is drawn. Culling specialises the forward pass per (object, shadowed light),
    /// three forward variants instead of one on the default scene, and the driver compiling them
    /// costs more than one frame's lookups save (`luz render` time to first frame 2119 against
    /// 1466 ms with an empty shader cache, 1101 against 811 ms with a warm one: docs/performance.md,
    /// "Cold start"). The image is the same either way (`tests/shadow_receivers.rs`).
    pub fn for_frames(mut self, frames: u32) -> Self {
        self.shadow_receivers &= frames > 1;
        self
    }

    /// (name, on) of each switch, for provenance and reports.
    pub fn list(&self) -> [(&'static str, bool); 3] {
        [
            ("instancing", self.instancing),
            ("shadow_cache", self.shadow_cache),
            ("shadow_receivers", self.shadow_receivers),
        ]
    }
}

impl Default for PassOptions {
    fn default() -> Self {
        Self {
            debug: DebugView::None,
            slots: 1,
            generic: false,
            output: Output::Hdr,
            path: RenderPath::Auto,
            light_loop: LightLoop::Auto,
            lod_cache: None,
            switches: Switches::default(),
        }
    }
}

/// The names (and GPU timer rows) of the scene's passes: the main scene's, and the lab's B
/// side, timed on rows of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PassNames {
    pub shadows: &'static str,
    pub gbuffer: &'static str,
    pub lighting: &'static str,
    pub forward: &'static str,
    /// Glass: the copy of the opaque scene, and the transmissive (and blended) draws after it.
    pub transmission: &'static str,
    pub transmissive: &'static str,
    /// The visible area lights' emitters after the deferred path's lighting (the forward path
    /// draws them in its own pass).
    pub emitters: &'static str,
}

impl PassNames {
    /// The rows of `luz bench` and the viewer's profiler.
    pub const MAIN: Self = Self {
        shadows: "shadows",
        gbuffer: "gbuffer",
        lighting: "lighting",
        forward: "forward",
        transmission: "transmission copy",
        transmissive: "transmissive",
        emitters: "emitters",
    };
    /// The viewer's B side.
    pub const B: Self = Self {
        shadows: "B: shadows",
        gbuffer: "B: gbuffer",
        lighting: "B: lighting",
        forward: "B: forward",
        transmission: "B: transmission copy",
        transmissive: "B: transmissive",
        emitters: "B: emitters",
    };

    /// Every name, for the reports that group them.
    pub fn all(&self) -> [&'static str; 7] {
        [
            self.shadows,
            self.gbuffer,
            self.lighting,
            self.forward,
            self.transmission,
            self.transmissive,
            self.emitters,
        ]
    }
}

/// What the forward pass writes into its colour attachment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Output {
    /// Radiance into the float HDR target ([`TargetFormat::color`]): for EXR output, whole-image
    /// saturation, the lab and the readback of radiance.
    Hdr,
    /// Display codes straight into an 8-bit UNORM attachment of `format` (the swapchain image):
    /// the scene's clamp saturation when `clamp`, exposure, `tonemap` and the exact sRGB encode in
    /// the fragment shader (`include/output.glsl`), the codes the display pass would give after
    /// the float target, without writing and reading 16 bytes per pixel again.
    Display {
        format: vk::Format,
        tonemap: Tonemap,
        clamp: bool,
    },
}

impl Output {
    /// The display output for `scene` into attachments of `format`, or `None` when a frame of the
    /// scene needs the whole float image first (`normalize` saturation).
    /// Scenes with transmissive materials draw into the float target too: their glass reads a
    /// copy of the opaque scene's radiance.
    pub fn display_for(scene: &Scene, format: vk::Format) -> Option<Self> {
        if transmission::transmits(scene) {
            return None;
        }
        match scene.saturation {
            Saturation::Normalize => None,
            s => Some(Output::Display {
                format,
                tonemap: scene.output.tonemap,
                clamp: s == Saturation::Clamp,
            }),
        }
    }

    /// The colour format the pipelines write (`hdr`: the float target's).
    pub fn color_format(self, hdr: vk::Format) -> vk::Format {
        match self {
            Output::Hdr => hdr,
            Output::Display { format, .. } => format,
        }
    }

    /// The values of the `OUTPUT`, `OUTPUT_TONEMAP` and `OUTPUT_CLAMP` specialization constants.
    pub(crate) fn spec(self) -> [(u32, u32); 3] {
        use crate::glsl::include_output as o;
        match self {
            Output::Hdr => [
                (gpu::SPEC_OUTPUT, o::OUTPUT_HDR),
                (gpu::SPEC_OUTPUT_TONEMAP, 0),
                (gpu::SPEC_OUTPUT_CLAMP, 0),
            ],
            Output::Display { tonemap, clamp, .. } => [
                (gpu::SPEC_OUTPUT, o::OUTPUT_DISPLAY),
                (
                    gpu::SPEC_OUTPUT_TONEMAP,
                    crate::render::tonemap::tonemap_id(tonemap),
                ),
                (gpu::SPEC_OUTPUT_CLAMP, clamp as u32),
            ],
        }
    }

    /// The clear colour of the background `rgba` in this output (alpha 0: a transparent
    /// background, [`luz_core::scene::Output::transparent`]): the radiance, or the display
    /// codes (as UNORM floats) the shader would write for it at `exposure_ev`.
    pub fn clear_color(self, rgba: glam::Vec4, exposure_ev: f32) -> [f32; 4] {
        match self {
            Output::Hdr => rgba.to_array(),
            Output::Display { tonemap, clamp, .. } => {
                let rgb = rgba.truncate();
                let c = if clamp { rgb.min(glam::Vec3::ONE) } else { rgb };
                let codes = crate::color::to_display_rgba8(
                    &[c.extend(rgba.w).to_array()],
                    exposure_ev,
                    tonemap,
                );
                [0, 1, 2, 3].map(|i| codes[i] as f32 / 255.0)
            }
        }
    }
}

/// Formats and sample count of the target the pass draws into.
#[derive(Debug, Clone, Copy)]
pub struct TargetFormat {
    pub color: vk::Format,
    pub depth: vk::Format,
    pub samples: vk::SampleCountFlags,
}

/// The data a frame may change without rebuilding anything: camera and frame uniforms, lights,
/// object transforms. One copy per frame in flight, so the host can write one while the GPU
/// reads another.
struct Slot {
    frame_ubo: Buffer,
    lights: Buffer,
    objects: Buffer,
    /// Per object slot: its material ([`gpu::DeferredMaterial`]), read by the deferred path.
    deferred_materials: Buffer,
    /// The light clusters of the slot's camera ([`clusters`]; a stub when the loop is plain).
    clusters: Buffer,
    cluster_lights: Buffer,
    /// The object of each entry of `order` (`BINDING_INSTANCES`): instanced draws read theirs
    /// from here ([`instances`]).
    instances: Buffer,
    /// The LTC table and the area lights (`BINDING_AREA`, [`gpu::area_data`]).
    area: Buffer,
    set: vk::DescriptorSet,
    /// The draws to record for the slot's camera and their LOD levels: the draw list's colour
    /// view ([`DrawList::color_view`]).
    view: ColorView,
}

pub struct ForwardPass {
    /// Built per (variant, output) on [`ForwardPass::prepare`].
    pipelines: BTreeMap<(VariantKey, Output), Pipeline>,
    modules: Modules,
    target: TargetFormat,
    /// The scene's drawn objects, every pass's (and the shadow layers').
    list: DrawList,
    /// Per item of `list`: its variant and push constants.
    draws: Vec<Draw>,
    /// Per shape of `list`: its buffers.
    meshes: Vec<GpuMesh>,
    slots: Vec<Slot>,
    /// Scene object index → index into the objects buffer (`None`: the object draws nothing).
    object_slots: Vec<Option<u32>>,
    lut_layers: Option<Vec<(i32, u32)>>,
    _pool: DescriptorPool,
    layout: PipelineLayout,
    set_layout: DescriptorSetLayout,
    /// Linear RGB and alpha where no object is (alpha 0 when the output is transparent).
    background: glam::Vec4,
    exposure: f32,
    light_count: u32,
    /// The fragment stage culls lights by clusters; the last assignment's figures.
    clustered: bool,
    cluster_stats: Option<ClusterStats>,
    variant_debug: DebugView,
    /// The scene shape the pass was built for ([`Shape`]).
    shape: Shape,
    /// The environment is drawn as the background: one pipeline per output.
    has_skybox: bool,
    skyboxes: BTreeMap<Output, Pipeline>,
    /// The visible area lights' emitters (issue 36); `None`: no visible area light.
    emitters: Option<emitter::Emitters>,
    /// Bound in every slot's set (`BINDING_SRGB_TABLE`); kept as long as they are.
    _srgb_table: Buffer,
    /// The deferred path, when the scene takes it ([`deferred::eligible`]).
    deferred: Option<deferred::Deferred>,
    env_set: Option<vk::DescriptorSet>,
    materials: MaterialSets,
    /// The shadow maps (set 3): a pass before the frame when a light has a shadow.
    shadows: ShadowMaps,
    /// What building the meshes' LOD chains did (chains built, read from the cache, failed).
    lod_stats: crate::scene::lod::ChainStats,
    /// Image height (px) the LOD choice projects errors onto: the target's (from
    /// [`ForwardPass::prepare_extent`]: the viewer's window), else the scene's output height.
    lod_height: u32,
    /// The height of the target the pass last prepared for, if any.
    target_height: Option<u32>,
    /// The budget of the last LOD choice: `lod_override`, else `output.tessellation_error_px`.
    lod_budget: f32,
    /// The budget asked for instead of the scene's ([`ForwardPass::set_lod_budget`]).
    lod_override: Option<f32>,
    /// Draws that share mesh, level, pipeline and material are one instanced draw; off
    /// ([`Switches::instancing`], for the test that compares both) records one draw per object.
    instancing: bool,
    /// Shadow lookups only where shadows can fall ([`Switches::shadow_receivers`]).
    receivers_culled: bool,
    /// Glass: the copy of the opaque scene per slot (a 1×1 stand-in without transmissive draws).
    transmission: transmission::TransmissionCopy,
    /// Some draw is transmissive (the copy follows the target's size).
    transmits: bool,
    /// Transmissive draws read the copy (not `refraction: environment` under an environment).
    copy_needed: bool,
    _empty_layout: DescriptorSetLayout,
    ctx: Arc<Context>,
}

/// Prepares `scene` for `ctx`'s device (textures within its 2D image limit), reusing what `old`
/// holds ([`crate::prepare::prepare_again`]); its warnings are logged.
pub fn prepare_for(
    ctx: &Context,
    scene: &Scene,
    (lod_cache, progress): (
        Option<std::path::PathBuf>,
        Option<&dyn crate::progress::Progress>,
    ),
    old: Option<PreparedScene>,
) -> Result<PreparedScene, VkError> {
    let options = PrepareOptions {
        lod_cache,
        max_texture_dimension: ctx.limits().max_image_dimension_2d,
    };
    let prepared =
        crate::prepare::prepare_again(old.unwrap_or_default(), scene, &options, progress)
            .map_err(|e| VkError::Setup(e.to_string()))?;
    for w in &prepared.warnings {
        log::warn!("{w}");
    }
    Ok(prepared)
}

/// The clear value where no object is: the scene's background, alpha 0 when the output is
/// transparent (the coverage then accumulates in alpha: MSAA resolves it, blending adds it).
fn background(output: &crate::scene::Output) -> glam::Vec4 {
    output
        .background
        .extend(if output.transparent { 0.0 } else { 1.0 })
}

/// The interface of the modules drawn in the forward layout: the forward variants, the skybox
/// and the deferred path's geometry pass (its push block is [`MaterialPush`]).
fn forward_interface() -> Result<crate::vk::Interface, VkError> {
    use crate::vk::interface::keys_with_prefix;
    let keys: Vec<&str> = ["forward.", "skybox.", "emitter.", "deferred_gbuffer."]
        .into_iter()
        .flat_map(keys_with_prefix)
        .collect();
    let interface = crate::vk::Interface::of("forward", &keys)?;
    interface.check_push::<MaterialPush>()?;
    Ok(interface)
}

impl ForwardPass {
    /// A pass with `slots` copies of its per-frame data (camera, lights, transforms), one per
    /// frame in flight: [`ForwardPass::update`] writes a slot, [`ForwardPass::record_slot`] draws
    /// with it. Prepares the scene first ([`crate::prepare`]; its warnings are logged).
    pub fn in_flight(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        scene: &Scene,
        target: TargetFormat,
        aspect: f32,
        ibl: Option<&Ibl>,
        options: PassOptions,
    ) -> Result<Self, VkError> {
        let prepared = prepare_for(ctx, scene, (options.lod_cache.clone(), None), None)?;
        Self::prepared(ctx, pool, (scene, &prepared), target, aspect, ibl, options)
    }

    /// [`ForwardPass::in_flight`] of a scene already prepared: only uploads and GPU objects.
    pub fn prepared(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        (scene, prepared): (&Scene, &PreparedScene),
        target: TargetFormat,
        aspect: f32,
        ibl: Option<&Ibl>,
        options: PassOptions,
    ) -> Result<Self, VkError> {
        let PassOptions {
            debug,
            slots,
            generic,
            output,
            path,
            light_loop,
            lod_cache,
            switches,
        } = options;
        let clustered = light_loop.clustered(scene, aspect);
        let slot_count = slots.max(1);
        let ibl_key = match (ibl, &scene.environment) {
            (Some(_), Some(e)) => Some(IblKey::from_env(e)),
            _ => None,
        };
        let set_layout = frame_set_layout(ctx)?;
        let materials =
            MaterialSets::new(ctx, pool, (scene, prepared), &mut |w| log::warn!("{w}"))?;
        let shadows = ShadowMaps::new(
            ctx,
            pool,
            scene,
            (slot_count, switches.shadow_cache),
            &materials.set_layout,
        )?;
        // Sets in index order (asserted in gpu.rs): frame, environment (an empty layout without
        // one, so the materials keep their index), materials, shadows.
        let empty_layout = DescriptorSetLayout::empty(ctx, "empty set layout")?;
        let env_layout = ibl.map(|i| &i.set_layout).unwrap_or(&empty_layout);
        const _: () = assert!(shadow::SET_SHADOW == 3 && SET_MATERIAL == 2);
        let layout = forward_interface()?.pipeline_layout(
            ctx,
            &[
                &set_layout,
                env_layout,
                &materials.set_layout,
                shadows.set_layout(),
            ],
        )?;
        let desc_pool = DescriptorPool::for_sets(
            ctx,
            "forward descriptor pool",
            &[(&set_layout, slot_count as u32)],
        )?;

        // Lights: any number up to what one storage buffer can bind (never empty: Vulkan wants a
        // non-zero range); per-object data likewise. Checked against the device's limits.
        let limits = ctx.limits();
        let scene_name = scene.display_name();
        storage_fits::<GpuLight>(&limits, &scene_name, "lights", scene.lights.len())?;
        storage_fits::<gpu::ObjectData>(&limits, &scene_name, "objects", scene.objects.len())?;
        let lights: Vec<GpuLight> = scene.lights.iter().map(GpuLight::from_light).collect();
        let mut uploader = Uploader::new(ctx);

        let built: Draws = build_draws(
            scene,
            (ibl, ibl_key),
            debug,
            (generic, clustered),
            (&limits, lod_cache.as_deref(), prepared),
            &mut uploader,
        )?;
        uploader.flush(pool)?;
        let Draws {
            meshes,
            list,
            draws,
            object_slots,
            lod_stats,
            ..
        } = built;
        let objects = built.objects;
        // Only Phong-shaded draws loop per fragment: without one, no clusters to build.
        let clustered = draws.iter().any(|d| d.variant.clustered);
        let light_count = lights.len().max(1);
        let object_count = objects.len().max(1);
        let srgb_table = super::srgb_table(ctx, "forward sRGB encode table")?;
        let area_data = gpu::area_data(scene);
        let mut slots = Vec::with_capacity(slot_count);
        for i in 0..slot_count {
            slots.push(Slot::new(
                ctx,
                &desc_pool,
                &set_layout,
                i,
                (
                    light_count,
                    object_count,
                    if clustered {
                        // With area lights, every cluster has an area pair too.
                        clusters::Grid::of(scene, aspect).cells()
                            * if scene.area_lights.is_empty() { 1 } else { 2 }
                    } else {
                        1
                    },
                    draws.len(),
                ),
                (&srgb_table, &area_data),
            )?);
        }
        let transmits = list.items.iter().any(|it| it.transmit);
        let copy_extent = if transmits {
            vk::Extent2D {
                width: scene.output.width,
                height: scene.output.height,
            }
        } else {
            vk::Extent2D {
                width: 1,
                height: 1,
            }
        };
        let transmission =
            transmission::TransmissionCopy::new(ctx, (slot_count, copy_extent, target.color))?;
        let sets: Vec<vk::DescriptorSet> = slots.iter().map(|s| s.set).collect();
        transmission.bind(ctx, &set_layout, &sets)?;
        let has_skybox =
            matches!((ibl, &scene.environment), (Some(_), Some(e)) if e.show_background);
        let variants: Vec<VariantKey> = draws.iter().map(|d| d.variant).collect();
        let deferred = match (path, deferred::eligible(&variants, target.samples)) {
            (RenderPath::Auto, Some(v)) if !has_skybox => Some(deferred::Deferred::new(
                ctx,
                &layout,
                &set_layout,
                (&empty_layout, shadows.set_layout()),
                target,
                v,
            )?),
            _ => None,
        };
        let lut_layers = ibl.map(|i| {
            lut_geometries(scene)
                .into_iter()
                .map(|g| (g, i.lut_layer(g)))
                .collect()
        });
        let mut pass = Self {
            pipelines: BTreeMap::new(),
            modules: Modules::default(),
            target,
            list,
            draws,
            meshes,
            slots,
            object_slots,
            lut_layers,
            _pool: desc_pool,
            layout,
            set_layout,
            background: background(&scene.output),
            exposure: scene.output.exposure,
            light_count: lights.len() as u32,
            clustered,
            cluster_stats: None,
            variant_debug: debug,
            shape: Shape::of(scene, debug),
            has_skybox,
            skyboxes: BTreeMap::new(),
            emitters: emitter::Emitters::new(scene),
            _srgb_table: srgb_table,
            deferred,
            env_set: ibl.map(|i| i.set),
            materials,
            shadows,
            lod_stats,
            lod_height: scene.output.height,
            target_height: None,
            lod_budget: scene.output.tessellation_error_px,
            lod_override: None,
            instancing: switches.instancing,
            receivers_culled: switches.shadow_receivers,
            transmission,
            transmits,
            copy_needed: !(scene.output.refraction == crate::scene::Refraction::Environment
                && ibl_key.is_some()),
            _empty_layout: empty_layout,
            ctx: ctx.clone(),
        };
        for slot in 0..slot_count {
            pass.update(slot, scene, aspect)?;
        }
        pass.prepare(output)?;
        Ok(pass)
    }

    /// Builds the pipelines drawing with `output` that are not built yet (each variant the draws
    /// use, and the skybox).
    pub fn prepare(&mut self, output: Output) -> Result<(), VkError> {
        if let Some(e) = &mut self.emitters {
            e.prepare(&self.ctx, &self.layout, self.target, output)?;
        }
        if let Some(d) = &mut self.deferred {
            return d.prepare(output);
        }
        let needed: std::collections::BTreeSet<VariantKey> = self
            .draws
            .iter()
            .flat_map(|d| {
                [
                    Some(d.variant),
                    d.shadow_area.map(|_| d.variant.unshadowed()),
                ]
            })
            .flatten()
            .collect();
        for v in needed {
            if self.pipelines.contains_key(&(v, output)) {
                continue;
            }
            let (vs, fs) = self.modules.forward(&self.ctx, v)?;
            let pipeline =
                create_pipeline(&self.ctx, &self.layout, self.target, v, output, vs, fs)?;
            self.pipelines.insert((v, output), pipeline);
        }
        if self.has_skybox && !self.skyboxes.contains_key(&output) {
            let (vs, fs) = self.modules.skybox(&self.ctx)?;
            let sky = create_skybox(&self.ctx, &self.layout, self.target, output, vs, fs)?;
            self.skyboxes.insert(output, sky);
        }
        Ok(())
    }

    /// Sets the size of the target the next frames draw into (the LOD choice projects errors
    /// onto its height).
    /// A scene with transmissive draws remakes its copies of the opaque scene at that size
    /// (after waiting for the device: frames in flight may read the old ones).
    pub fn prepare_extent(&mut self, extent: vk::Extent2D) -> Result<(), VkError> {
        self.target_height = Some(extent.height);
        if self.transmits && self.transmission.extent() != extent {
            // SAFETY: waiting needs the queue externally synchronised: every submission comes
            // from the thread that owns this pass.
            unsafe { self.ctx.device.device_wait_idle() }?;
            let format = self.transmission.format();
            self.transmission =
                transmission::TransmissionCopy::new(&self.ctx, (self.slots.len(), extent, format))?;
            let sets: Vec<vk::DescriptorSet> = self.slots.iter().map(|s| s.set).collect();
            self.transmission.bind(&self.ctx, &self.set_layout, &sets)?;
        }
        Ok(())
    }

    /// "deferred" or "forward": how this pass draws.
    pub fn render_path(&self) -> &'static str {
        if self.deferred.is_some() {
            "deferred"
        } else {
            "forward"
        }
    }

    /// Number of per-frame data copies.
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }

    /// The scene shape the pass was built for: [`Shape::change_to`] says what drawing another
    /// scene costs it.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// Rewrites slot `slot`'s per-frame data from `scene`: camera, ambient, fog, background,
    /// lights, object transforms and material parameters. `scene` must have the structure the
    /// pass was built for ([`Structure::of`] equal); the slot must not be in use by the GPU.
    pub fn update(&mut self, slot: usize, scene: &Scene, aspect: f32) -> Result<(), VkError> {
        // Buffers, pipelines and sets are built for the pass's shape: only per-frame data moves.
        let shape = Shape::of(scene, self.variant_debug);
        let change = self.shape.change(&shape);
        if change != Change::InPlace {
            return Err(VkError::Setup(format!(
                "{}: the forward pass was built for another scene ({}): that needs {change:?} \
                 (Headless::apply rebuilds what it needs)",
                scene.display_name(),
                self.shape.describe_change(&shape),
            )));
        }
        let s = self
            .slots
            .get_mut(slot)
            .ok_or_else(|| VkError::Setup(format!("no frame slot {slot}")))?;
        let data = gpu::frame_data(scene, aspect, self.light_count);
        s.frame_ubo.write(0, bytemuck::bytes_of(&data))?;
        let lights: Vec<GpuLight> = scene.lights.iter().map(GpuLight::from_light).collect();
        s.lights.write(0, bytemuck::cast_slice(&lights))?;
        let area = gpu::area_lights_data(scene);
        if !area.is_empty() {
            s.area.write(
                (gpu::area_offset(scene) * 16) as u64,
                bytemuck::cast_slice(&area),
            )?;
        }
        for (obj, index) in scene.objects.iter().zip(&self.object_slots) {
            if let Some(i) = index {
                let data = gpu::object_data(obj.transform.matrix());
                s.objects.write(
                    *i as u64 * std::mem::size_of::<gpu::ObjectData>() as u64,
                    bytemuck::bytes_of(&data),
                )?;
            }
        }
        self.background = background(&scene.output);
        self.exposure = scene.output.exposure;
        let placed = self.list.place(scene);
        let view = self.color_view(scene, aspect, &placed);
        self.set_view(slot, view)?;
        self.update_shadows(slot, scene, aspect, &placed)?;
        self.write_clusters(slot, scene, aspect)?;
        let (light_kinds, shadow_slots) = (
            gpu::scene_light_kinds(scene),
            crate::render::shadow::fixed_slots(&scene.lights),
        );
        for (draw, item) in self.draws.iter_mut().zip(&self.list.items) {
            let obj = &scene.objects[item.object];
            let material = &scene.materials[obj.material].material;
            let mut push = gpu::material_push(material);
            let (model, terms) = material_key(material);
            let generic = draw.variant.terms == TermsKey::Generic;
            if model != draw.variant.model
                || (!generic
                    && (terms != draw.variant.terms
                        || variant::lobe_bits(material) != draw.variant.lobes
                        || light_kinds != draw.variant.light_kinds
                        || shadow_slots
                            != draw.variant.shadow_slots.map(|c| c & !shadow::FIXED_SKIP)))
            {
                return Err(VkError::Setup(format!(
                    "object {}: material model, BRDF terms or lobes, light kinds or shadowed lights changed; rebuild the forward pass",
                    obj.name
                )));
            }
            push.object_index = draw.push.object_index;
            push.receive_shadow = obj.shadow.receive as u32;
            push.double_sided = draw.push.double_sided;
            if let Some(layers) = &self.lut_layers {
                let g = lut_geometry(material);
                push.flags = layers
                    .iter()
                    .find(|(geometry, _)| *geometry == g)
                    .map(|(_, l)| *l)
                    .unwrap_or(draw.push.flags);
            }
            draw.push = push;
        }
        if self.deferred.is_some() {
            let s = &mut self.slots[slot];
            for (draw, item) in self.draws.iter().zip(&self.list.items) {
                let named = &scene.materials[scene.objects[item.object].material];
                let data = gpu::DeferredMaterial {
                    push: draw.push,
                    extra: super::material::MaterialExtra::without_maps(named),
                };
                s.deferred_materials.write(
                    draw.push.object_index as u64
                        * std::mem::size_of::<gpu::DeferredMaterial>() as u64,
                    bytemuck::bytes_of(&data),
                )?;
            }
        }
        Ok(())
    }

    /// Rewrites the per-frame uniforms (camera, ambient, fog) of every slot.
    pub fn update_camera(&mut self, scene: &Scene, aspect: f32) -> Result<(), VkError> {
        let data = gpu::frame_data(scene, aspect, self.light_count);
        let placed = self.list.place(scene);
        let view = self.color_view(scene, aspect, &placed);
        for slot in 0..self.slots.len() {
            self.set_view(slot, view.clone())?;
            self.slots[slot]
                .frame_ubo
                .write(0, bytemuck::bytes_of(&data))?;
        }
        for slot in 0..self.slots.len() {
            self.update_shadows(slot, scene, aspect, &placed)?;
            self.write_clusters(slot, scene, aspect)?;
        }
        Ok(())
    }

    /// The shadow maps (`luz render --verbose`, the viewer's debug view).
    pub fn shadow_maps(&self) -> &ShadowMaps {
        &self.shadows
    }

    /// The light clusters' figures of the last assignment (`None`: the plain loop).
    pub fn cluster_stats(&self) -> Option<ClusterStats> {
        self.cluster_stats
    }

    /// The debug view the pipelines were built with.
    pub fn debug_view(&self) -> DebugView {
        self.variant_debug
    }

    /// Texture maps uploaded for the scene's materials.
    pub fn texture_count(&self) -> usize {
        self.materials.texture_count
    }

    /// The pipeline variants this pass built, in a stable order.
    pub fn variants(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .draws
            .iter()
            .map(|d| d.variant)
            .collect::<std::collections::BTreeSet<_>>()
            .iter()
            .map(|k| k.to_string())
            .collect();
        if self.has_skybox {
            v.push("skybox".to_string());
        }
        v
    }

    /// Objects (draws) recorded for slot `slot`'s camera after frustum culling, and all of them.
    pub fn drawn_objects(&self, slot: usize) -> (usize, usize) {
        let s = &self.slots[slot.min(self.slots.len() - 1)];
        (s.view.order.len(), self.draws.len())
    }

    pub fn triangle_count(&self) -> u64 {
        self.list
            .items
            .iter()
            .map(|it| self.meshes[it.shape].index_count as u64 / 3)
            .sum()
    }

    /// Declares the scene's passes for slot `slot` in `g`, writing `output` into `target` (its
    /// pipelines [`ForwardPass::prepare`]d, the colour image of `output`'s format): the shadow
    /// maps when a layer must be drawn ("shadows"), then either "gbuffer" and "lighting" (the
    /// deferred path) or "forward" (opaque draws, the skybox behind them, blended draws over
    /// both).
    pub fn add_passes<'a>(
        &'a self,
        g: &mut FrameGraph<'a>,
        (slot, names): (usize, PassNames),
        output: Output,
        target: SceneTarget,
    ) -> Result<(), VkError> {
        let meshes: Vec<super::MeshRef> = self.meshes.iter().map(GpuMesh::raw).collect();
        let shadow_image = self.shadows.add_pass(
            g,
            (slot, names.shadows),
            (meshes, self.materials.sets.as_slice()),
        );
        let shadow_set = self.shadows.set(slot);
        let slot_index = slot;
        let slot = &self.slots[slot.min(self.slots.len() - 1)];
        let set = slot.set;
        let view = &slot.view;
        let (order, levels) = (view.order.as_slice(), view.levels.as_slice());
        let clear = vk::ClearValue {
            color: vk::ClearColorValue {
                float32: output.clear_color(self.background, self.exposure),
            },
        };
        if let Some(def) = &self.deferred {
            if !def.ready(output) || target.resolve.is_some() {
                return Err(VkError::Setup(format!(
                    "forward (deferred): not prepared for {output:?} (call prepare first)"
                )));
            }
            let full = vk::Rect2D {
                extent: target.extent,
                ..Default::default()
            };
            let emitters = match &self.emitters {
                None => None,
                Some(e) => Some(e.pipeline(output).ok_or_else(|| {
                    VkError::Setup(format!(
                        "forward: the emitters for {output:?} were not prepared"
                    ))
                })?),
            };
            def.add_passes(
                g,
                (target, names),
                (output, clear, emitters.is_some()),
                (set, shadow_set, shadow_image),
                move |cmd, pipeline| {
                    self.record_draws(
                        cmd,
                        (set, shadow_set, (order, levels, 0)),
                        |_| (pipeline, pipeline),
                        full,
                    )
                },
            );
            if let Some(pipeline) = emitters {
                // After the lighting (which kept depth for it): the emitters over the lit scene.
                // Both kept: the lit scene under the emitters, its depth to test them against.
                g.pass(names.emitters)
                    .read_write(target.color, Access::ColorAttachmentReadWrite)
                    .read_write(target.depth, Access::DepthAttachmentWrite)
                    .record(move |rc| {
                        let views = attachment_views(rc, target)?;
                        let (d, cmd) = (rc.device(), rc.cmd());
                        let _area =
                            begin_scene_rendering((d, cmd), target, views, (Load::Keep, false));
                        self.record_emitters(cmd, (set, shadow_set), pipeline);
                        // SAFETY: closes the rendering instance begun above, in the same command
                        // buffer.
                        unsafe { d.cmd_end_rendering(cmd) };
                        Ok(())
                    });
            }
            return Ok(());
        }
        let mut pipelines = Vec::new();
        for draw in &self.draws {
            let get = |v: VariantKey| {
                self.pipelines
                    .get(&(v, output))
                    .map(|p| p.raw)
                    .ok_or_else(|| {
                        VkError::Setup(format!(
                            "forward: the pipeline {v} for {output:?} was not prepared"
                        ))
                    })
            };
            let own = get(draw.variant)?;
            let outside = match draw.shadow_area {
                Some(_) => get(draw.variant.unshadowed())?,
                None => own,
            };
            pipelines.push((own, outside));
        }
        let skybox = match (self.has_skybox, self.skyboxes.get(&output)) {
            (false, _) => None,
            (true, Some(p)) => Some(p.raw),
            (true, None) => {
                return Err(VkError::Setup(format!(
                    "forward: the skybox for {output:?} was not prepared"
                )))
            }
        };
        let emitters = match &self.emitters {
            None => None,
            Some(e) => Some(e.pipeline(output).ok_or_else(|| {
                VkError::Setup(format!(
                    "forward: the emitters for {output:?} were not prepared"
                ))
            })?),
        };
        // Glass (issue 35): transmissive draws in view split the pass around a copy of the
        // opaque scene ([`transmission`]).
        let second = draws::key::second_phase(&view.keys);
        let blended = draws::key::blended_phase(&view.keys);
        // The environment method reads no copy: one pass (transmissive draws after the sky).
        let glass = second < blended && output == Output::Hdr && self.copy_needed;
        let opaque_end = if glass { second } else { order.len() };
        let mut pass = g
            .pass(names.forward)
            .write(target.color, Access::ColorAttachmentWrite)
            .write(target.depth, Access::DepthAttachmentWrite);
        if let Some(resolve) = target.resolve {
            pass = pass.write(resolve, Access::ColorAttachmentWrite);
        }
        if let Some(s) = shadow_image {
            pass = pass.read(s, shadow::SHADOW_READ);
        }
        let pipelines = std::sync::Arc::new(pipelines);
        let first_pipelines = pipelines.clone();
        pass.record(move |rc| {
            let views = attachment_views(rc, target)?;
            let (d, cmd) = (rc.device(), rc.cmd());
            let area = begin_scene_rendering((d, cmd), target, views, (Load::Clear(clear), glass));
            // Opaque draws, the skybox behind them, then (without glass) blended draws over both.
            let pipelines = &first_pipelines;
            self.record_draws(
                cmd,
                (set, shadow_set, (&order[..second], levels, 0)),
                |i| pipelines[i],
                area,
            );
            // SAFETY: as in `begin_scene_rendering`; the draws left the rendering instance open.
            unsafe {
                if let Some(sky) = skybox {
                    d.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, sky);
                    d.cmd_draw(cmd, 3, 1, 0, 0);
                }
            }
            // The visible area lights' emitters over the opaque scene and the sky, before glass
            // and blended draws (issue 36).
            if let Some(pipeline) = emitters {
                self.record_emitters(cmd, (set, shadow_set), pipeline);
            }
            let rest = (&order[second..opaque_end], levels, second);
            self.record_draws(cmd, (set, shadow_set, rest), |i| pipelines[i], area);
            // SAFETY: as above; the draws left the rendering instance open.
            unsafe { d.cmd_end_rendering(cmd) };
            Ok(())
        });
        if !glass {
            return Ok(());
        }
        let copy = self.transmission.add_copy(
            g,
            (slot_index, names.transmission),
            target.output(),
            target.extent,
        )?;
        let mut pass = g
            .pass(names.transmissive)
            .read(copy, Access::FragmentSampled)
            .write(target.color, Access::ColorAttachmentReadWrite)
            .write(target.depth, Access::DepthAttachmentWrite);
        if let Some(resolve) = target.resolve {
            pass = pass.write(resolve, Access::ColorAttachmentWrite);
        }
        if let Some(s) = shadow_image {
            pass = pass.read(s, shadow::SHADOW_READ);
        }
        pass.record(move |rc| {
            let views = attachment_views(rc, target)?;
            let (d, cmd) = (rc.device(), rc.cmd());
            let area = begin_scene_rendering((d, cmd), target, views, (Load::Keep, false));
            // Transmissive draws, nearest first, then the blended ones over them.
            let rest = (&order[second..], levels, second);
            self.record_draws(cmd, (set, shadow_set, rest), |i| pipelines[i], area);
            // SAFETY: as in `begin_scene_rendering`; the draws left the rendering instance open.
            unsafe { d.cmd_end_rendering(cmd) };
            Ok(())
        });
        Ok(())
    }
}

/// The views of a scene target's colour, depth and resolve images in a pass's recording.
fn attachment_views(
    rc: &mut luz_graph::RecordContext<'_>,
    target: SceneTarget,
) -> Result<(vk::ImageView, vk::ImageView, Option<vk::ImageView>), luz_graph::PassError> {
    let color = rc.image(target.color)?.view;
    let depth = rc.image(target.depth)?.view;
    let resolve = match target.resolve {
        Some(r) => Some(rc.image(r)?.view),
        None => None,
    };
    Ok((color, depth, resolve))
}

/// Begins rendering the scene into `target` (views `color`, `depth`, `resolve`) with the
/// colour starting as `load` (depth cleared to 1 with it, kept otherwise) and sets the viewport;
/// `more`: a later pass loads colour and depth again, so the multisampled colour and the depth
/// are stored. A multisampled colour resolves into `resolve` at the end. Returns the render area.
fn begin_scene_rendering(
    (d, cmd): (&ash::Device, vk::CommandBuffer),
    target: SceneTarget,
    (color_view, depth_view, resolve_view): (vk::ImageView, vk::ImageView, Option<vk::ImageView>),
    (load, more): (Load, bool),
) -> vk::Rect2D {
    let depth_load = match load {
        Load::Clear(_) => Load::depth(1.0),
        other => other,
    };
    let mut color = color_attachment(color_view, load, true);
    if let Some(resolve) = resolve_view {
        color = color
            .resolve_mode(vk::ResolveModeFlags::AVERAGE)
            .resolve_image_view(resolve)
            .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
        if !more {
            color = color.store_op(vk::AttachmentStoreOp::DONT_CARE);
        }
    }
    let colors = [color];
    let depth = depth_attachment(depth_view, depth_load, more);
    let area = vk::Rect2D {
        offset: vk::Offset2D { x: 0, y: 0 },
        extent: target.extent,
    };
    let info = rendering_info(area, &colors, Some(&depth));
    // SAFETY: the graph records the caller's pass outside any rendering instance, with the
    // attachments in the layouts its accesses declare (colour, resolve: COLOR_ATTACHMENT_OPTIMAL;
    // depth: DEPTH_ATTACHMENT_OPTIMAL); `info` and the slices it points to outlive the calls;
    // every pipeline, set and buffer the caller binds belongs to the forward pass and outlives
    // the command buffer's execution (the owner waits before dropping it).
    unsafe {
        d.cmd_begin_rendering(cmd, &info);
        crate::vk::cmd::set_viewport(d, cmd, target.extent, area);
    }
    area
}
