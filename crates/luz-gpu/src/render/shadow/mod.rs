//! Shadow maps: a depth-only pass per map layer before the frame, and the set the forward and
//! deferred shaders look them up in (`shaders_glsl/include/shadows.glsl`, set 3).
//!
//! Every map of a frame is a layer of one 2D-array depth image (D32, reversed depth): directional
//! lights get one layer per cascade, point lights and spots wider than 60° six cube-face layers,
//! other spots one. The image is as wide as the largest map; a light with a smaller resolution
//! draws into the top-left corner of its layers. A scene without a shadowed light gets a 1×1
//! image that is never drawn or read (its shaders are specialised without shadow code).
//!
//! Area lights with a `shadow` (issue 36) get maps too, after the punctual lights': each is a
//! point light at the emitter's centre ([`shadow_lights`]: a cube map, six layers) whose
//! `radius`, the soft-shadow size PCSS sizes its penumbrae by, is the emitter's
//! ([`area_shadow_size`]). Their records follow the punctual lights' in the `shadow_lights`
//! buffer (area light k at `lights.len() + k`); `area.glsl` looks them up by that index.
//! Visible emitters are drawn into the layers of every shadowed light but their own
//! ([`emitters`]), as the reference's emitters stop other lights' shadow rays.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};
use gpu_allocator::MemoryLocation;

use crate::render::gpu::{glsl, Vertex};
use crate::scene::{Scene, Shadow, ShadowMethod};
use luz_graph::{Access, FrameGraph, ImageHandle, ImageStateBefore};

use crate::vk::cmd::CommandPool;
use crate::vk::image::{Image, ImageDesc, Sampler};
use crate::vk::pipeline::{DescriptorPool, DescriptorSetLayout};
use crate::vk::{Buffer, Context, SetWrites, VkError};

pub mod cull;
mod emitters;
pub mod fit;
mod pipeline;
pub mod view;

pub use cull::{box_corners, world_plane, Reached, Receiver};
pub use fit::{LightFit, Sphere};
pub use view::{picture, MapLayer};

use glsl::include_shadows as g;
pub const SET_SHADOW: u32 = g::SET_SHADOW as u32;
pub const FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// `ShadowLight` of shadows.glsl (std430, 64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub struct GpuShadowLight {
    pub info: [i32; 4],
    pub params: Vec4,
    pub size: Vec4,
    pub splits: Vec4,
}

/// `ShadowLayer` of shadows.glsl (std430, 112 bytes).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub struct GpuShadowLayer {
    pub view_proj: Mat4,
    pub params: Vec4,
    pub origin: Vec4,
    pub axis: Vec4,
}

const _: () = assert!(std::mem::size_of::<GpuShadowLight>() == 64);

/// Set in a draw's fixed slot code when that light cannot darken the draw (shadows.glsl:
/// `SHADOW_FIXED_SKIP`): its pipeline leaves the lookup out.
pub const FIXED_SKIP: u32 = g::SHADOW_FIXED_SKIP;
const _: () = assert!(std::mem::size_of::<GpuShadowLayer>() == 112);

/// One shadowed light's maps in the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightMaps {
    /// Index into the scene's lights.
    pub light: usize,
    pub first_layer: u32,
    pub layers: u32,
    pub shadow: Shadow,
}

pub use crate::render::draws::Caster;
use crate::render::draws::{DepthDraw, DepthEye, DrawList};

impl ShadowMaps {
    /// Frames recorded so far with the maps drawn, and with them reused (nothing they see had
    /// changed since they were drawn).
    pub fn frames_drawn_reused(&self) -> (u64, u64) {
        let n = |k: usize| self.recorded[k].load(std::sync::atomic::Ordering::Relaxed);
        (n(0), n(1))
    }

    /// Layers drawn over every recorded frame (a frame reusing a layer does not draw it).
    pub fn layers_drawn(&self) -> u64 {
        self.layers_drawn.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Triangles drawn into the layers of slot `slot`: shadow casters at their LOD levels.
    pub fn triangles_drawn(&self, slot: usize) -> u64 {
        let s = &self.slots[slot.min(self.slots.len() - 1)];
        s.draws
            .iter()
            .flatten()
            .map(|d| u64::from(d.range.1 / 3))
            .sum()
    }
}

/// How the scene passes sample the shadow maps, and the state the image is kept in between
/// frames (it is made so when created).
pub const SHADOW_READ: Access = Access::Custom {
    name: "ShadowSampled",
    layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    stages: vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
            | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw(),
    ),
    access: vk::AccessFlags2::SHADER_SAMPLED_READ,
    writes: false,
};

pub use crate::render::MeshRef;

struct Slot {
    set: vk::DescriptorSet,
    lights: Buffer,
    layers: Buffer,
    /// Per layer: the draw list's depth view of it (the casters that may reach it, each at its
    /// LOD level, with its clip-from-object matrix).
    draws: Vec<Vec<DepthDraw>>,
    /// The layer records of the slot's last update (what its maps are drawn with).
    records: Vec<GpuShadowLayer>,
    /// Per receiver of the slot's last update: where the maps may darken it.
    receives: Vec<Reached>,
    /// Per layer: the visible emitters drawn into it (every one but its light's own).
    emitters: Vec<Vec<emitters::EmitterDraw>>,
}

/// What one layer of the image holds: the layer record and draws it was last drawn with. A frame
/// whose record and draws for the layer are the same (nothing moved that the layer sees) reuses
/// it: a point light's faces stay while the camera orbits, a static scene draws its maps once.
type Drawn = (GpuShadowLayer, Vec<DepthDraw>, Vec<emitters::EmitterDraw>);

/// What `luz render --verbose` says about one light's maps.
#[derive(Debug, Clone, PartialEq)]
pub struct MapReport {
    pub light: usize,
    pub method: ShadowMethod,
    pub resolution: u32,
    pub layers: u32,
    /// Bytes of the image its layers take (at the image's size).
    pub bytes: u64,
    /// Per layer: casters drawn (of all casters) in slot 0.
    pub drawn: Vec<usize>,
    pub casters: usize,
    /// Casters (of all) drawn with the alpha-tested pipeline: MASK and BLEND materials.
    pub alpha_tested: usize,
}

pub struct ShadowMaps {
    maps: Vec<LightMaps>,
    size: u32,
    layer_views: Vec<vk::ImageView>,
    image: Image,
    _samplers: [Sampler; 3],
    set_layout: DescriptorSetLayout,
    slots: Vec<Slot>,
    _pool: DescriptorPool,
    pipeline: Option<pipeline::DepthPipeline>,
    /// Only for scenes with shadowed lights and alpha-tested casters.
    masks: Option<pipeline::MaskPipelines>,
    /// The emitters' unit shapes: only for scenes with shadowed lights and a visible area light.
    emitter_mesh: Option<emitters::EmitterMesh>,
    casters: usize,
    alpha_tested: usize,
    light_count: usize,
    /// The layer records of the last update (what the last recorded frame drew with).
    last_layers: Vec<GpuShadowLayer>,
    /// What each layer of the image holds (`None`: nothing yet); set when a frame's passes
    /// are recorded (recorded frames are submitted in order on one queue).
    drawn: std::sync::Mutex<Vec<Option<Drawn>>>,
    /// Maps are reused when unchanged (off: drawn every frame; `Switches::shadow_cache`).
    reuse: bool,
    /// Frames recorded with some layer drawn, and with every layer reused.
    recorded: [std::sync::atomic::AtomicU64; 2],
    /// Layers drawn over all recorded frames.
    layers_drawn: std::sync::atomic::AtomicU64,
    ctx: Arc<Context>,
}

impl ShadowMaps {
    /// The maps `scene`'s shadowed lights need, with `slots` copies of the per-frame data.
    /// `materials`: the layout of the forward pass's material sets, which alpha-tested casters
    /// bind (the pipelines for them are made only when the scene has such a caster).
    pub fn new(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        scene: &Scene,
        (slots, reuse): (usize, bool),
        materials: &DescriptorSetLayout,
    ) -> Result<Self, VkError> {
        let limits = ctx.limits();
        let mut maps = Vec::new();
        let mut next = 0u32;
        let all = shadow_lights(scene);
        for (i, l) in all.iter().enumerate() {
            let Some(s) = l.shadow else { continue };
            if s.resolution > limits.max_image_dimension_2d {
                return Err(VkError::Limit {
                    what: format!(
                        "{}: {}.shadow.resolution",
                        scene.display_name(),
                        light_name(scene, i)
                    ),
                    requested: s.resolution as u64,
                    limit: limits.max_image_dimension_2d as u64,
                    limit_name: "maxImageDimension2D",
                });
            }
            let layers = s.layers(l.kind, l.umbra_deg);
            maps.push(LightMaps {
                light: i,
                first_layer: next,
                layers,
                shadow: s,
            });
            next += layers;
        }
        if next > limits.max_image_array_layers {
            return Err(VkError::Limit {
                what: format!(
                    "{}: shadow map layers (cascades and cube faces of every shadowed light)",
                    scene.display_name()
                ),
                requested: next as u64,
                limit: limits.max_image_array_layers as u64,
                limit_name: "maxImageArrayLayers",
            });
        }
        let size = maps.iter().map(|m| m.shadow.resolution).max().unwrap_or(1);
        let layer_count = next.max(1);
        // One image holds every map at the largest resolution: name the light that sets it.
        if let Some(big) = maps.iter().max_by_key(|m| m.shadow.resolution) {
            let bytes = u64::from(size) * u64::from(size) * 4 * u64::from(layer_count);
            limits.check_allocation(
                &format!(
                    "{}: {}.shadow.resolution {size} ({size}² texels × {layer_count} \
                     layers: every shadowed light's cascades and cube faces at the largest \
                     resolution): the shadow map image",
                    scene.display_name(),
                    light_name(scene, big.light)
                ),
                bytes,
            )?;
        }
        let mut image = Image::new(
            ctx,
            "shadow maps",
            ImageDesc {
                array: true,
                ..ImageDesc::of_graph(
                    &luz_graph::ImageDesc::depth(size, size, FORMAT)
                        // TRANSFER_SRC: read back for a look at the maps (view.rs).
                        .usage(
                            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                                | vk::ImageUsageFlags::SAMPLED
                                | vk::ImageUsageFlags::TRANSFER_SRC,
                        )
                        .layers(layer_count),
                )
            },
        )?;
        let mut layer_views = Vec::new();
        if !maps.is_empty() {
            for layer in 0..layer_count {
                layer_views.push(image.layer_view(layer)?);
            }
        }
        // Every frame starts the maps from UNDEFINED; until the first one (and for ever without
        // shadows) the image is in the layout its descriptors name.
        crate::render::frame::settle(ctx, pool, &image, SHADOW_READ)?;
        let sampler = |name: &str, filter: vk::Filter, compare: bool| {
            let info = vk::SamplerCreateInfo::default()
                .mag_filter(filter)
                .min_filter(filter)
                .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
                .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .compare_enable(compare)
                .compare_op(vk::CompareOp::GREATER_OR_EQUAL)
                .min_lod(0.0)
                .max_lod(0.0);
            Sampler::new(ctx, name, &info)
        };
        let samplers = [
            sampler("shadow compare linear", vk::Filter::LINEAR, true)?,
            sampler("shadow compare nearest", vk::Filter::NEAREST, true)?,
            sampler("shadow depth", vk::Filter::NEAREST, false)?,
        ];
        let set_layout = crate::render::sets::scene_interface()?.set_layout(ctx, SET_SHADOW)?;
        let n = slots.max(1) as u32;
        let desc_pool =
            DescriptorPool::for_sets(ctx, "shadow descriptor pool", &[(&set_layout, n)])?;
        let light_count = all.len().max(1);
        let mut slot_data = Vec::new();
        for i in 0..n {
            let buffer = |name: &str, bytes: usize| {
                Buffer::new(
                    ctx,
                    &format!("{name} (slot {i})"),
                    bytes as u64,
                    vk::BufferUsageFlags::STORAGE_BUFFER,
                    MemoryLocation::CpuToGpu,
                )
            };
            let mut lights = buffer(
                "shadow lights",
                light_count * std::mem::size_of::<GpuShadowLight>(),
            )?;
            // Until the first update: no light has a shadow.
            let none = vec![
                GpuShadowLight {
                    info: [-1, 0, 0, 0],
                    ..Zeroable::zeroed()
                };
                light_count
            ];
            lights.write(0, bytemuck::cast_slice(&none))?;
            let layers = buffer(
                "shadow layers",
                layer_count as usize * std::mem::size_of::<GpuShadowLayer>(),
            )?;
            let set = desc_pool.allocate(&set_layout)?;
            let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
            let image_bindings = [
                g::BINDING_SHADOW_LINEAR,
                g::BINDING_SHADOW_NEAREST,
                g::BINDING_SHADOW_DEPTH,
            ];
            let writes = image_bindings
                .iter()
                .zip(&samplers)
                .fold(SetWrites::new(&set_layout, set), |w, (b, s)| {
                    w.image(*b as u32, image.view, read, s.raw)
                })
                .buffer(g::BINDING_SHADOW_LIGHTS as u32, lights.raw)
                .buffer(g::BINDING_SHADOW_LAYERS as u32, layers.raw);
            // SAFETY: `set` was just allocated and no command buffer uses it; the samplers, view
            // and buffers written are live objects of this device with the usages the bindings
            // need (sampled depth image in the layout named, storage buffers).
            unsafe { writes.apply(ctx) }?;
            slot_data.push(Slot {
                set,
                lights,
                layers,
                draws: vec![Vec::new(); layer_count as usize],
                records: Vec::new(),
                receives: Vec::new(),
                emitters: vec![Vec::new(); layer_count as usize],
            });
        }
        let pipeline = if maps.is_empty() {
            None
        } else {
            Some(pipeline::DepthPipeline::new(ctx)?)
        };
        // Casters whose alpha decides where they cast; with vertex colours or not.
        let alpha_tested: Vec<bool> = scene
            .objects
            .iter()
            .filter(|o| {
                o.shadow.cast
                    && scene
                        .materials
                        .get(o.material)
                        .is_some_and(|m| m.textures.alpha_mode.shadow_cutoff().is_some())
            })
            .map(|o| !o.mesh.colors.is_empty())
            .collect();
        let masks = if maps.is_empty() || alpha_tested.is_empty() {
            None
        } else {
            let color = alpha_tested.iter().any(|&c| c);
            Some(pipeline::MaskPipelines::new(ctx, materials, color)?)
        };
        let emitter_mesh = if !maps.is_empty() && scene.area_lights.iter().any(|a| a.visible) {
            Some(emitters::EmitterMesh::new(ctx)?)
        } else {
            None
        };
        Ok(Self {
            maps,
            size,
            layer_views,
            image,
            _samplers: samplers,
            set_layout,
            slots: slot_data,
            _pool: desc_pool,
            pipeline,
            masks,
            emitter_mesh,
            casters: 0,
            alpha_tested: 0,
            light_count: all.len(),
            last_layers: Vec::new(),
            drawn: std::sync::Mutex::new(vec![None; layer_count as usize]),
            reuse,
            recorded: Default::default(),
            layers_drawn: Default::default(),
            ctx: ctx.clone(),
        })
    }

    pub fn set_layout(&self) -> &DescriptorSetLayout {
        &self.set_layout
    }

    /// Slot `slot`'s set (the last slot's for larger indices).
    pub fn set(&self, slot: usize) -> vk::DescriptorSet {
        self.slots[slot.min(self.slots.len() - 1)].set
    }

    /// Per receiver (in the order the last update of slot `slot` was given them): the maps
    /// that may darken it (bit k: map k of [`ShadowMaps::maps`], in the fixed slots' order:
    /// [`fixed_slots`]) and the part of its box where. A clear bit lets its pipeline leave the
    /// lookup out.
    pub fn receives(&self, slot: usize) -> &[Reached] {
        &self.slots[slot.min(self.slots.len() - 1)].receives
    }

    /// Whether any light has a shadow (otherwise nothing is drawn or updated).
    pub fn active(&self) -> bool {
        !self.maps.is_empty()
    }

    /// The shadowed lights' maps.
    pub fn maps(&self) -> &[LightMaps] {
        &self.maps
    }

    /// The image's side in texels and its layers.
    pub fn image_size(&self) -> (u32, u32) {
        (self.size, self.layer_views.len() as u32)
    }

    /// Refits every map to `scene`'s camera at `aspect` and writes slot `slot`'s data (the slot
    /// must not be in use by the GPU). `scene` has the lights the maps were made for.
    pub fn update(
        &mut self,
        slot: usize,
        scene: &Scene,
        aspect: f32,
        (list, casters): (&DrawList, &[Caster]),
        receivers: &[Receiver],
    ) -> Result<(), VkError> {
        if !self.active() {
            return Ok(());
        }
        let all = shadow_lights(scene);
        if all.len() != self.light_count
            || self
                .maps
                .iter()
                .any(|m| structure_of(&all[m.light]) != structure_of_map(m))
        {
            return Err(VkError::Setup(format!(
                "{}: lights or their shadows changed; rebuild the shadow maps",
                scene.display_name()
            )));
        }
        // Biases, kernel and splits may change from frame to frame (the viewer's sliders).
        for m in &mut self.maps {
            if let Some(sh) = all[m.light].shadow {
                m.shadow = sh;
            }
        }
        self.casters = casters.len();
        self.alpha_tested = casters.iter().filter(|c| c.alpha.is_some()).count();
        // Visible emitters cast shadows for every light but their own (emitters.rs): they count
        // in the fit as casters do.
        let placed = self
            .emitter_mesh
            .as_ref()
            .map(|m| emitters::visible(scene, &m.ranges))
            .unwrap_or_default();
        let emitter_casters: Vec<Caster> = placed
            .iter()
            .map(|e| Caster {
                item: usize::MAX,
                scale: 1.0,
                model: e.model,
                sphere: e.sphere,
                tight: e.sphere,
                plane: None,
                receiver: None,
                alpha: None,
            })
            .collect();
        let spheres: Vec<Sphere> = casters
            .iter()
            .chain(&emitter_casters)
            .map(|c| c.sphere)
            .collect();
        let receiver_spheres: Vec<Sphere> = receivers.iter().map(|r| r.sphere).collect();
        let view = fit::View {
            camera: &scene.camera,
            aspect,
            casters: &spheres,
            receivers: &receiver_spheres,
        };
        let mut lights = vec![
            GpuShadowLight {
                info: [-1, 0, 0, 0],
                ..Zeroable::zeroed()
            };
            self.light_count.max(1)
        ];
        let mut layers = vec![GpuShadowLayer::zeroed(); self.layer_views.len().max(1)];
        let last = self.slots.len() - 1;
        let s = &mut self.slots[slot.min(last)];
        for d in &mut s.draws {
            d.clear();
        }
        for d in &mut s.emitters {
            d.clear();
        }
        s.receives.clear();
        s.receives.resize(receivers.len(), Reached::default());
        for (k, m) in self.maps.iter().enumerate() {
            let light = &all[m.light];
            let fit = fit::fit(light, &m.shadow, &view);
            // Flat casters that can hide no receiver from this light (a floor under the objects).
            let drawn: Vec<&Caster> = casters
                .iter()
                .filter(|c| {
                    c.plane.is_none_or(|plane| {
                        !cull::hides_nothing(plane, light, receivers, c.receiver)
                    })
                })
                .collect();
            // The area light this map stands in for, whose own emitter it does not draw.
            let own = m.light.checked_sub(scene.lights.len());
            // The receiver test serves the forward pass's fixed slots, which are the punctual
            // lights' only: area lights' lookups are compiled in whatever a draw receives.
            if m.light < scene.lights.len() {
                cull::receiving(
                    &mut s.receives,
                    k,
                    (light, &m.shadow, &fit),
                    scene.camera.view(),
                    (
                        &drawn
                            .iter()
                            .copied()
                            .chain(&emitter_casters)
                            .collect::<Vec<_>>(),
                        receivers,
                    ),
                );
            }
            let sh = &m.shadow;
            let size_term = match light.kind {
                crate::scene::LightKind::Directional => light.angular_radius_deg.to_radians().tan(),
                _ => light.radius,
            };
            lights[m.light] = GpuShadowLight {
                info: [
                    m.first_layer as i32,
                    m.layers as i32,
                    method_code(sh.method),
                    sh.pcf_kernel as i32,
                ],
                params: Vec4::new(
                    sh.resolution as f32 / self.size as f32,
                    1.0 / self.size as f32,
                    sh.bias,
                    sh.normal_bias,
                ),
                size: Vec4::new(size_term, fit::pcss_max_radius(sh), 0.0, 0.0),
                splits: Vec4::from_array(fit.splits),
            };
            for (k, layer) in fit.layers.iter().enumerate() {
                let index = (m.first_layer as usize) + k;
                layers[index] = GpuShadowLayer {
                    view_proj: layer.view_proj,
                    params: Vec4::new(
                        layer.texel,
                        if layer.perspective { 1.0 } else { 0.0 },
                        layer.depth,
                        0.0,
                    ),
                    origin: layer.origin.extend(1.0),
                    axis: layer.axis.extend(0.0),
                };
                let eye = DepthEye {
                    view_proj: layer.view_proj,
                    texel: layer.texel,
                    perspective: layer.perspective,
                    origin: layer.origin,
                    axis: layer.axis,
                };
                let budget = scene.output.tessellation_error_px;
                s.draws[index] = list.layer_view(&drawn, &eye, budget);
                s.emitters[index].extend(placed.iter().filter(|e| Some(e.area) != own).map(|e| {
                    emitters::EmitterDraw {
                        clip: layer.view_proj * e.model,
                        range: e.range,
                    }
                }));
            }
        }
        s.lights.write(0, bytemuck::cast_slice(&lights))?;
        s.layers.write(0, bytemuck::cast_slice(&layers))?;
        s.records.clone_from(&layers);
        self.last_layers = layers;
        Ok(())
    }

    /// Declares slot `slot`'s maps in `g`: the image imported with its kept layers, and — when a
    /// layer must be drawn this frame — the pass `name` ("shadows") that clears and draws those layers'
    /// casters (alpha-tested ones with their material's set of `materials`, by material index).
    /// Returns the image for the passes that sample it ([`SHADOW_READ`]); `None` without
    /// shadows.
    pub fn add_pass<'a>(
        &'a self,
        g: &mut FrameGraph<'a>,
        (slot, name): (usize, &'static str),
        (meshes, materials): (Vec<MeshRef>, &'a [vk::DescriptorSet]),
    ) -> Option<ImageHandle> {
        let pipeline = self.pipeline.as_ref()?;
        // The image is left readable between frames: created so, and every frame's last use is
        // a read by the scene passes.
        let image = crate::render::frame::import(
            g,
            "shadow maps",
            &self.image,
            ImageStateBefore::Keep(SHADOW_READ),
        );
        let s = &self.slots[slot.min(self.slots.len() - 1)];
        // Layers the image already holds (drawn by a frame recorded earlier in this queue's
        // order) are not drawn again.
        let redraw: Vec<bool> = {
            let mut drawn = self.drawn.lock().unwrap_or_else(|e| e.into_inner());
            (0..s.draws.len())
                .map(|i| {
                    let same = drawn[i].as_ref().is_some_and(|(r, d, e)| {
                        Some(r) == s.records.get(i) && *d == s.draws[i] && *e == s.emitters[i]
                    });
                    if !(self.reuse && same) {
                        drawn[i] = s
                            .records
                            .get(i)
                            .map(|r| (*r, s.draws[i].clone(), s.emitters[i].clone()));
                    }
                    !(self.reuse && same)
                })
                .collect()
        };
        let count = redraw.iter().filter(|&&r| r).count() as u64;
        use std::sync::atomic::Ordering::Relaxed;
        self.layers_drawn.fetch_add(count, Relaxed);
        self.recorded[usize::from(count == 0)].fetch_add(1, Relaxed);
        if count == 0 {
            return Some(image);
        }
        let emitter_mesh = self.emitter_mesh.as_ref().map(emitters::EmitterMesh::raw);
        // The layers not drawn keep their contents: the whole image is read and written.
        g.pass(name)
            .read_write(image, Access::DepthAttachmentWrite)
            .record(move |rc| {
                rc.image(image)?;
                let cmd = rc.cmd();
                for m in &self.maps {
                    let res = m.shadow.resolution;
                    for k in 0..m.layers {
                        let index = (m.first_layer + k) as usize;
                        if !redraw[index] {
                            continue;
                        }
                        pipeline.record_layer(
                            cmd,
                            self.layer_views[index],
                            (res, m.shadow.slope_bias),
                            (&s.draws[index], &meshes),
                            self.masks.as_ref().map(|p| (p, materials)),
                            emitter_mesh
                                .as_ref()
                                .map(|mesh| (mesh, s.emitters[index].as_slice())),
                        );
                    }
                }
                Ok(())
            });
        Some(image)
    }

    /// Per shadowed light: its maps, their memory and the casters slot 0 draws into each.
    pub fn report(&self) -> Vec<MapReport> {
        let texel_bytes = 4u64;
        self.maps
            .iter()
            .map(|m| MapReport {
                light: m.light,
                method: m.shadow.method,
                resolution: m.shadow.resolution,
                layers: m.layers,
                bytes: self.size as u64 * self.size as u64 * texel_bytes * m.layers as u64,
                drawn: (0..m.layers)
                    .map(|k| self.slots[0].draws[(m.first_layer + k) as usize].len())
                    .collect(),
                casters: self.casters,
                alpha_tested: self.alpha_tested,
            })
            .collect()
    }
}

impl MapReport {
    /// One line for `luz render --verbose`: "light 0: pcf 3x3, 3 layers of 2048², 48.0 MiB,
    /// casters drawn per layer 5 4 2 of 5", and ", 2 alpha-tested" when some casters are.
    pub fn describe(&self, kernel: u32) -> String {
        let method = match self.method {
            ShadowMethod::Pcf => format!("pcf {kernel}x{kernel}"),
            m => m.name().to_string(),
        };
        let drawn: Vec<String> = self.drawn.iter().map(|d| d.to_string()).collect();
        let alpha = if self.alpha_tested > 0 {
            format!(", {} alpha-tested", self.alpha_tested)
        } else {
            String::new()
        };
        format!(
            "light {}: {method}, {} layer{} of {}², {:.1} MiB, casters drawn per layer {} of \
             {}{alpha}",
            self.light,
            self.layers,
            if self.layers == 1 { "" } else { "s" },
            self.resolution,
            self.bytes as f64 / (1024.0 * 1024.0),
            drawn.join(" "),
            self.casters
        )
    }
}

/// The lights the maps are made for: the scene's punctual lights, then (when the scene has area
/// lights) one stand-in per area light, in order: a point light at the emitter's centre with the
/// area light's shadow (`None`: no maps) and the emitter's soft-shadow size as its `radius`
/// ([`area_shadow_size`]). Shadow record `i` of the GPU is entry `i` of this list. Borrowed
/// unchanged for a scene without area lights.
pub fn shadow_lights(scene: &Scene) -> std::borrow::Cow<'_, [crate::scene::Light]> {
    if scene.area_lights.is_empty() {
        return std::borrow::Cow::Borrowed(&scene.lights);
    }
    let mut all = scene.lights.clone();
    all.extend(scene.area_lights.iter().map(|a| crate::scene::Light {
        kind: crate::scene::LightKind::Point,
        direction: glam::Vec3::NEG_Y,
        position: a.position,
        color: a.color,
        intensity: a.intensity,
        falloff: crate::scene::Falloff::InverseSquare,
        umbra_deg: 180.0,
        inner_deg: None,
        exponent: 0.0,
        range: a.range,
        shadow: a.shadow,
        radius: area_shadow_size(a),
        angular_radius_deg: 0.0,
    }));
    std::borrow::Cow::Owned(all)
}

/// The radius (m) of the spherical light PCSS takes an area light for: a sphere's or a disk's
/// own radius; for a rect, the radius of the disk of equal area, √(w·h/π); for a tube, that of
/// the disk of the area of its side-on silhouette (2·r·length), √(2·r·length/π), and at least
/// its radius (seen along its axis the tube is a disk of its radius: its penumbrae there come
/// out wider than the reference's). docs/area-lights.md#shadows.
pub fn area_shadow_size(a: &crate::scene::AreaLight) -> f32 {
    use crate::scene::AreaShape;
    use std::f32::consts::PI;
    match a.shape {
        AreaShape::Sphere { radius } | AreaShape::Disk { radius } => radius,
        AreaShape::Rect { width, height, .. } => (width * height / PI).sqrt(),
        AreaShape::Tube { length, radius } => (2.0 * radius * length / PI).sqrt().max(radius),
    }
}

/// How messages name entry `i` of [`shadow_lights`]: `lights[i]` for a punctual light, "area
/// light k" for the others.
fn light_name(scene: &Scene, i: usize) -> String {
    match i.checked_sub(scene.lights.len()) {
        None => format!("lights[{i}]"),
        Some(k) => format!("area light {k}"),
    }
}

/// What of a light's shadow needs new maps or pipelines when it changes: the method (shader
/// code), the resolution and the layers. `None` without a shadow.
pub fn structure_of(l: &crate::scene::Light) -> Option<(ShadowMethod, u32, u32)> {
    l.shadow
        .map(|s| (s.method, s.resolution, s.layers(l.kind, l.umbra_deg)))
}

fn structure_of_map(m: &LightMaps) -> Option<(ShadowMethod, u32, u32)> {
    Some((m.shadow.method, m.shadow.resolution, m.layers))
}

/// The forward pass's fixed shadow slots (`SHADOW_FIXED_*` of shadows.glsl): each shadowed light
/// of `lights` packed whole (light index, first layer, geometry, layers, method, PCF taps), the
/// layers assigned in light order as [`ShadowMaps::new`] assigns them. All zero (the lookups
/// read their records per pixel) with more shadowed lights than slots, or a field out of range.
pub fn fixed_slots(lights: &[crate::scene::Light]) -> [u32; 4] {
    const SLOTS: usize = g::SHADOW_FIXED_SLOTS as usize;
    let mut slots = [0u32; SLOTS];
    let mut next = 0u32;
    let mut used = 0;
    for (i, l) in lights.iter().enumerate() {
        let Some(s) = l.shadow else { continue };
        let layers = s.layers(l.kind, l.umbra_deg);
        let geometry = match (l.kind, layers) {
            (crate::scene::LightKind::Directional, _) => g::SHADOW_GEOMETRY_CASCADES,
            (_, 1) => g::SHADOW_GEOMETRY_SINGLE,
            _ => g::SHADOW_GEOMETRY_CUBE,
        };
        if used == SLOTS || i > 255 || next > 255 || layers > 7 || s.pcf_kernel > 31 {
            return [0; SLOTS];
        }
        slots[used] = g::SHADOW_FIXED_USED
            | i as u32
            | next << 8
            | geometry << 16
            | layers << 18
            | (method_code(s.method) as u32) << 21
            | s.pcf_kernel << 23;
        used += 1;
        next += layers;
    }
    slots
}

fn method_code(m: ShadowMethod) -> i32 {
    match m {
        ShadowMethod::Hard => g::SHADOW_HARD,
        ShadowMethod::Pcf => g::SHADOW_PCF,
        ShadowMethod::Pcss => g::SHADOW_PCSS,
    }
}

/// The vertex layout the depth pass reads (positions at the start of each [`Vertex`]).
pub(crate) const VERTEX_STRIDE: u32 = std::mem::size_of::<Vertex>() as u32;

#[cfg(test)]
mod tests {
    use super::*;

    /// The built-in scene's two shadowed lights fill two fixed slots with their own fields and
    /// layers in light order; five shadowed lights (more than the slots) leave every slot 0.
    #[test]
    fn fixed_slots_pack_each_shadowed_light_whole() {
        let scene = crate::scene::default_scene();
        let slots = fixed_slots(&scene.lights);
        let field = |code: u32, shift: u32, bits: u32| (code >> shift) & ((1 << bits) - 1);
        let sun = slots[0];
        assert_ne!(sun & g::SHADOW_FIXED_USED, 0);
        assert_eq!(field(sun, 0, 8), 0, "light index");
        assert_eq!(field(sun, 8, 8), 0, "first layer");
        assert_eq!(field(sun, 16, 2), g::SHADOW_GEOMETRY_CASCADES);
        let cascades = scene.lights[0].shadow.unwrap().cascades;
        assert_eq!(field(sun, 18, 3), cascades);
        assert_eq!(field(sun, 21, 2), g::SHADOW_PCF as u32);
        assert_eq!(field(sun, 23, 5), 2, "PCF taps per side");
        let lamp = slots[1];
        assert_eq!(field(lamp, 0, 8), 1);
        assert_eq!(field(lamp, 8, 8), cascades);
        assert_eq!(field(lamp, 16, 2), g::SHADOW_GEOMETRY_CUBE);
        assert_eq!(field(lamp, 18, 3), 6);
        assert_eq!(&slots[2..], &[0, 0]);
        let mut many = scene.lights.clone();
        many.extend(std::iter::repeat_n(scene.lights[1], 3));
        assert_eq!(fixed_slots(&many), [0; 4]);
        assert_eq!(
            fixed_slots(&many[..4]).iter().filter(|&&c| c != 0).count(),
            4
        );
    }

    /// Area lights' records follow the punctual lights': one point light per area light at its
    /// centre with its shadow and the emitter's soft-shadow size; without area lights the list is
    /// the scene's own, borrowed.
    #[test]
    fn area_lights_follow_the_punctual_lights() {
        use crate::scene::{AreaLight, AreaMethod, AreaShape, LightKind};
        use glam::Vec3;
        let mut scene = crate::scene::default_scene();
        scene.area_lights.clear();
        let n = scene.lights.len();
        assert!(matches!(
            shadow_lights(&scene),
            std::borrow::Cow::Borrowed(_)
        ));
        let shadow = Shadow::default_for(LightKind::Point);
        let area = |shape, shadow| AreaLight {
            shape,
            position: Vec3::new(1.0, 2.0, 3.0),
            direction: Vec3::NEG_Y,
            color: Vec3::ONE,
            intensity: 1.0,
            shadow,
            two_sided: false,
            visible: true,
            method: AreaMethod::Ltc,
            range: None,
        };
        let rect = AreaShape::Rect {
            up: Vec3::Z,
            width: 0.8,
            height: 0.6,
        };
        let tube = AreaShape::Tube {
            length: 1.0,
            radius: 0.05,
        };
        scene.area_lights = vec![
            area(rect, Some(shadow)),
            area(AreaShape::Sphere { radius: 0.3 }, None),
            area(tube, Some(shadow)),
        ];
        let all = shadow_lights(&scene);
        assert_eq!(all.len(), n + 3);
        assert_eq!(&all[..n], &scene.lights[..]);
        let r = all[n];
        assert_eq!(
            (r.kind, r.position, r.shadow),
            (LightKind::Point, Vec3::new(1.0, 2.0, 3.0), Some(shadow))
        );
        assert!((r.radius - (0.48 / std::f32::consts::PI).sqrt()).abs() < 1e-6);
        assert_eq!((all[n + 1].radius, all[n + 1].shadow), (0.3, None));
        assert!((all[n + 2].radius - (0.1 / std::f32::consts::PI).sqrt()).abs() < 1e-6);
        // The punctual lights' fixed slots do not see the area lights.
        assert_eq!(fixed_slots(&scene.lights), fixed_slots(&all[..n]));
        assert_eq!(light_name(&scene, n + 2), "area light 2");
    }
}
