//! Device context: physical-device choice, logical device, one graphics+compute queue, the allocator and
//! a command pool. No surface: the window layer adds one on top.

use std::ffi::CStr;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, RwLock};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::instance::{Instance, InstanceDesc};
use super::limits::Limits;
use super::VkError;

/// How to build a [`Context`].
#[derive(Debug, Clone, Default)]
pub struct ContextDesc {
    pub instance: InstanceDesc,
    /// Case-insensitive substring of the device name to use instead of the automatic choice.
    pub device_name: Option<String>,
    /// Device extensions beyond the core (e.g. the swapchain's).
    pub device_extensions: Vec<&'static CStr>,
    /// On a CPU device, raise glibc's malloc trim threshold ([`super::host`]). The library reads
    /// no environment for it: the binary sets it from `LUZ_MALLOC_TUNING`.
    pub malloc_tuning: bool,
}

/// What luz reports about the device it runs on.
#[derive(Debug, Clone)]
pub struct DeviceInfo {
    pub name: String,
    pub device_type: vk::PhysicalDeviceType,
    pub driver_name: String,
    pub driver_info: String,
    pub api_version: u32,
    pub timestamp_period_ns: f32,
    pub timestamp_valid_bits: u32,
    pub limits: vk::PhysicalDeviceLimits,
    /// The limits luz checks input-sized resources against, as the device reports them (the
    /// context's [`Context::limits`] may be tighter).
    pub resource_limits: Limits,
    /// Anisotropic filtering is supported and enabled.
    pub sampler_anisotropy: bool,
    /// The host allocator setting made for a CPU device ([`super::host`]); `None` on a GPU.
    pub malloc_tuning: Option<super::host::MallocTuning>,
}

impl DeviceInfo {
    /// One line: name, type, driver, API version.
    pub fn summary(&self) -> String {
        let v = self.api_version;
        let mut s = format!(
            "{} ({}), driver {} {}, Vulkan {}.{}.{}",
            self.name,
            type_name(self.device_type),
            self.driver_name,
            self.driver_info,
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        );
        if let Some(m) = self.malloc_tuning {
            s.push_str("; host: ");
            s.push_str(m.describe());
            if let Ok(n) = std::env::var(super::host::RASTERIZER_THREADS_ENV) {
                s.push_str(&format!(", {}={n}", super::host::RASTERIZER_THREADS_ENV));
            }
        }
        s
    }
}

pub fn type_name(t: vk::PhysicalDeviceType) -> &'static str {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
        vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
        vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
        vk::PhysicalDeviceType::CPU => "CPU",
        _ => "other",
    }
}

fn type_rank(t: vk::PhysicalDeviceType) -> u32 {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

/// The device and everything whose lifetime equals it. Shared as `Arc<Context>`; objects that hold
/// one are destroyed before the device.
pub struct Context {
    pub info: DeviceInfo,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub allocator: ManuallyDrop<Mutex<Allocator>>,
    pub debug_utils: Option<ash::ext::debug_utils::Device>,
    /// `vkCmdPushDescriptorSetKHR`: the passes that read the frame graph's transient images
    /// write their descriptors into the command buffer at record time ([`super::PushSet`]).
    pub push_descriptor: ash::khr::push_descriptor::Device,
    /// Serialises queue submissions (the queue is externally synchronised).
    pub queue_lock: Mutex<()>,
    /// The limits resources are checked against: the device's, or tighter ones set by
    /// [`Context::tighten_limits`].
    limits: RwLock<Limits>,
    /// The one pipeline cache every pipeline is created with ([`super::pipeline_cache`]).
    pub(super) pipelines: super::pipeline_cache::PipelineCache,
    // Last: destroyed after the device.
    pub instance: Instance,
}

/// Device extensions luz needs on every device: push descriptors, so that a pass binds the
/// frame graph's transient images (which may change from frame to frame) without rewriting a
/// descriptor set a pending frame uses. Every desktop driver and lavapipe has it; it is core in
/// Vulkan 1.4.
pub const REQUIRED_EXTENSIONS: [&CStr; 1] = [ash::khr::push_descriptor::NAME];

struct Candidate {
    physical: vk::PhysicalDevice,
    name: String,
    device_type: vk::PhysicalDeviceType,
    queue_family: u32,
}

impl Context {
    pub fn new(desc: &ContextDesc) -> Result<Arc<Self>, VkError> {
        let instance = Instance::new(&desc.instance)?;
        let inst = &instance.raw;
        // SAFETY: `inst` is the instance `Instance::new` just created and `instance` keeps alive; the
        // call only fills a Vec that ash sizes from the count query.
        let physicals = unsafe { inst.enumerate_physical_devices() }?;
        let mut candidates = Vec::new();
        let mut rejected = Vec::new();
        for &p in &physicals {
            // SAFETY: `p` was enumerated from `inst` above; physical devices live as long as their
            // instance.
            let props = unsafe { inst.get_physical_device_properties(p) };
            let name = props
                .device_name_as_c_str()
                .map(|c| c.to_string_lossy().into_owned())
                .unwrap_or_default();
            if props.api_version < vk::API_VERSION_1_3 {
                rejected.push(format!("{name} (Vulkan < 1.3)"));
                continue;
            }
            // SAFETY: `p` was enumerated from `inst` above; ash sizes the output from the count query.
            let families = unsafe { inst.get_physical_device_queue_family_properties(p) };
            let family = families.iter().position(|f| {
                f.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            });
            let Some(family) = family else {
                rejected.push(format!("{name} (no graphics+compute queue)"));
                continue;
            };
            // SAFETY: `p` was enumerated from `inst` above; ash sizes the output from the count query.
            let extensions = unsafe { inst.enumerate_device_extension_properties(p) }?;
            let has = |want: &CStr| {
                extensions
                    .iter()
                    .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == want))
            };
            if let Some(missing) = REQUIRED_EXTENSIONS.iter().find(|e| !has(e)) {
                rejected.push(format!("{name} (no {})", missing.to_string_lossy()));
                continue;
            }
            candidates.push(Candidate {
                physical: p,
                name,
                device_type: props.device_type,
                queue_family: family as u32,
            });
        }
        let all_names = || {
            let mut v: Vec<String> = candidates
                .iter()
                .map(|c| format!("{} ({})", c.name, type_name(c.device_type)))
                .collect();
            v.extend(rejected.iter().cloned());
            if v.is_empty() {
                "none".to_string()
            } else {
                v.join(", ")
            }
        };
        let chosen = if let Some(want) = &desc.device_name {
            let w = want.to_lowercase();
            candidates
                .iter()
                .find(|c| c.name.to_lowercase().contains(&w))
                .ok_or_else(|| {
                    VkError::Setup(format!(
                        "no Vulkan device matches --device \"{want}\"; available: {}",
                        all_names()
                    ))
                })?
        } else {
            candidates
                .iter()
                .min_by_key(|c| type_rank(c.device_type))
                .ok_or_else(|| {
                    VkError::Setup(format!(
                        "no usable Vulkan 1.3 device found; seen: {} (install mesa-vulkan-drivers for lavapipe)",
                        all_names()
                    ))
                })?
        };
        let physical = chosen.physical;
        let queue_family = chosen.queue_family;

        let mut driver_props = vk::PhysicalDeviceDriverProperties::default();
        let mut maintenance3 = vk::PhysicalDeviceMaintenance3Properties::default();
        let mut maintenance4 = vk::PhysicalDeviceMaintenance4Properties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default()
            .push_next(&mut driver_props)
            .push_next(&mut maintenance3)
            .push_next(&mut maintenance4);
        // SAFETY: `physical` was enumerated from `inst`. The structs chained into `props2`
        // (driver, maintenance3, maintenance4 properties) are live locals that outlive the call, and
        // each is a valid extension of VkPhysicalDeviceProperties2 here: all three are core in
        // Vulkan 1.3, and devices below 1.3 were rejected above.
        unsafe { inst.get_physical_device_properties2(physical, &mut props2) };
        let props = props2.properties;
        // SAFETY: `physical` was enumerated from `inst`, which is alive.
        let families = unsafe { inst.get_physical_device_queue_family_properties(physical) };
        let mut info = DeviceInfo {
            name: chosen.name.clone(),
            device_type: props.device_type,
            driver_name: driver_props
                .driver_name_as_c_str()
                .map(|c| c.to_string_lossy().into_owned())
                .unwrap_or_default(),
            driver_info: driver_props
                .driver_info_as_c_str()
                .map(|c| c.to_string_lossy().into_owned())
                .unwrap_or_default(),
            api_version: props.api_version,
            timestamp_period_ns: props.limits.timestamp_period,
            timestamp_valid_bits: families[queue_family as usize].timestamp_valid_bits,
            limits: props.limits,
            resource_limits: Limits::from_properties(&props.limits, &maintenance3, &maintenance4),
            sampler_anisotropy: false,
            malloc_tuning: (props.device_type == vk::PhysicalDeviceType::CPU)
                .then(|| super::host::tune_for_cpu_device(desc.malloc_tuning)),
        };

        // Features: Vulkan 1.3 dynamic rendering + synchronization2; optional extras when present.
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut f12)
            .push_next(&mut f13);
        // SAFETY: `physical` was enumerated from `inst`; `f12` and `f13`, chained into `f2`, are live
        // locals that outlive the call, and the Vulkan 1.2/1.3 feature structs are valid in the chain
        // of a Vulkan 1.3 device (older devices were rejected above).
        unsafe { inst.get_physical_device_features2(physical, &mut f2) };
        let supported = f2.features;
        let (dyn_rendering, sync2) = (f13.dynamic_rendering, f13.synchronization2);
        let host_query_reset = f12.host_query_reset;
        if dyn_rendering == vk::FALSE || sync2 == vk::FALSE {
            return Err(VkError::Setup(format!(
                "{} lacks dynamic rendering or synchronization2",
                info.name
            )));
        }
        info.sampler_anisotropy = supported.sampler_anisotropy == vk::TRUE;
        let features = vk::PhysicalDeviceFeatures::default()
            .sampler_anisotropy(supported.sampler_anisotropy == vk::TRUE)
            .fill_mode_non_solid(supported.fill_mode_non_solid == vk::TRUE)
            // maxDrawIndexedIndexValue is 2^32 − 1 only with this feature enabled.
            .full_draw_index_uint32(supported.full_draw_index_uint32 == vk::TRUE)
            .shader_float64(false);
        // maintenance4 is required by Vulkan 1.3 (shaderc emits LocalSizeId, which needs it).
        let mut e13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true)
            .maintenance4(f13.maintenance4 == vk::TRUE);
        let mut e12 = vk::PhysicalDeviceVulkan12Features::default()
            .host_query_reset(host_query_reset == vk::TRUE);
        let priorities = [1.0f32];
        let queue_infos = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let ext_names: Vec<*const i8> = REQUIRED_EXTENSIONS
            .iter()
            .chain(&desc.device_extensions)
            .map(|e| e.as_ptr())
            .collect();
        let device_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_infos)
            .enabled_extension_names(&ext_names)
            .enabled_features(&features)
            .push_next(&mut e12)
            .push_next(&mut e13);
        // SAFETY: `device_info` and everything it points to (queue infos and priorities, the
        // extension-name pointers into `'static` CStrs, `features`, the `e12`/`e13` chain) are locals
        // that outlive the call. `queue_family` is an index into this physical device's families,
        // and only features the device reported (`supported`, `f12`, `f13`, checked above) are
        // enabled. An extension the device lacks makes the call fail, which is returned as an error.
        let device = unsafe { inst.create_device(physical, &device_info, None) }?;
        // SAFETY: the device was created with one queue of family `queue_family` (`queue_infos`), so
        // index 0 exists (VUID-vkGetDeviceQueue-queueIndex-00385).
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: inst.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: `device` was created just above and nothing has been created from it
                // (the allocator failed to build), so it has no child objects and no pending work
                // (VUID-vkDestroyDevice-device-00378); it is not used after this.
                unsafe { device.destroy_device(None) };
                return Err(e.into());
            }
        };
        let debug_utils = instance
            .debug_utils
            .as_ref()
            .map(|_| ash::ext::debug_utils::Device::new(inst, &device));
        let limits = RwLock::new(info.resource_limits);
        let push_descriptor = ash::khr::push_descriptor::Device::new(inst, &device);
        // SAFETY: `physical` was enumerated from `inst`, which is alive.
        let props = unsafe { inst.get_physical_device_properties(physical) };
        let pipelines = super::pipeline_cache::PipelineCache::new(&device, &props);
        let ctx = Arc::new(Self {
            pipelines,
            push_descriptor,
            info,
            physical,
            device,
            queue,
            queue_family,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            debug_utils,
            queue_lock: Mutex::new(()),
            limits,
            instance,
        });
        ctx.set_name(ctx.queue, "luz queue");
        Ok(ctx)
    }

    /// Gives a Vulkan object a debug name (shown by validation messages and capture tools).
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(du) = &self.debug_utils else { return };
        let Ok(cname) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&cname);
        // Naming is best effort; a failure here must never stop rendering.
        // SAFETY: `info` and the `cname` it points to outlive the call; `du` was loaded for
        // `self.device`. Callers pass handles they created from `self.device` and name them right
        // after creation, before any other thread can see them (objectHandle is externally
        // synchronised).
        let _ = unsafe { du.set_debug_utils_object_name(&info) };
    }

    /// The limits input-sized resources are checked against (see [`super::limits`]).
    pub fn limits(&self) -> Limits {
        *self.limits.read().unwrap_or_else(|p| p.into_inner())
    }

    /// Makes later checks use `limits` where they are tighter than the current ones (never
    /// looser than the device's): tests exercise the limit checks with small inputs this way.
    pub fn tighten_limits(&self, limits: &Limits) {
        let mut l = self.limits.write().unwrap_or_else(|p| p.into_inner());
        *l = l.min(limits);
    }

    /// Validation errors and warnings seen so far.
    pub fn validation_log(&self) -> &super::instance::ValidationLog {
        &self.instance.log
    }

    pub fn allocator(&self) -> std::sync::MutexGuard<'_, Allocator> {
        // A poisoned allocator lock means a panic happened mid-allocation; the allocator itself is
        // still consistent, so keep going.
        self.allocator.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Submits one command buffer and waits for it (fence), with the queue lock held.
    pub fn submit_and_wait(&self, cmd: vk::CommandBuffer) -> Result<(), VkError> {
        // SAFETY: `self.device` is alive for `&self`; the create info is a temporary that outlives
        // the call.
        let fence = unsafe {
            self.device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }?;
        let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = vk::SubmitInfo2::default().command_buffer_infos(&cmd_infos);
        let result = {
            let _q = self.queue_lock.lock().unwrap_or_else(|p| p.into_inner());
            // SAFETY: `_q` holds `queue_lock`, which serialises every use of `self.queue` (queue
            // access is externally synchronised). `submit` points to `cmd_infos`, a live local.
            // `fence` was just created, unsignalled and unused (VUID-vkQueueSubmit2-fence-04894).
            // `cmd` is a command buffer of this device that the caller has finished recording and
            // that is not pending (the contract of this function; `CommandPool::one_shot` passes a
            // fresh, ended one).
            unsafe { self.device.queue_submit2(self.queue, &[submit], fence) }
        };
        // SAFETY: `fence` was created above from `self.device` and is destroyed only below, after
        // this wait returns.
        let result =
            result.and_then(|_| unsafe { self.device.wait_for_fences(&[fence], true, u64::MAX) });
        // SAFETY: no queue operation still refers to `fence` (VUID-vkDestroyFence-fence-01120):
        // either the submit failed, so it was never used, or the unbounded wait above returned
        // (success, or device loss, after which every submission counts as complete). It is not
        // used after this.
        unsafe { self.device.destroy_fence(fence, None) };
        result.map_err(VkError::from)
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: `self.device` is still alive (destroyed at the end of this function). Waiting
        // idle needs every queue of the device externally synchronised: `&mut self` in `drop`
        // means no other reference to this context, and so to `self.queue`, exists.
        unsafe {
            let _ = self.device.device_wait_idle();
        }
        // gpu-allocator's own leak report goes to `log`, which luz does not route anywhere: report
        // live allocations here, as a validation error, so tests see leaks.
        let report = self.allocator().generate_report();
        if !report.allocations.is_empty() {
            let names: Vec<String> = report
                .allocations
                .iter()
                .take(8)
                .map(|a| format!("{} ({} bytes)", a.name, a.size))
                .collect();
            self.instance.log.report_error(format!(
                "[ERROR LEAK] gpu-allocator: {} allocation(s), {} bytes, still live when the device \
                 is destroyed: {}",
                report.allocations.len(),
                report.total_allocated_bytes,
                names.join(", ")
            ));
        }
        // SAFETY: `self.allocator` is dropped exactly once, here, and not touched afterwards (the
        // context is being dropped); it returns its memory blocks while the device is still alive.
        // Then the device has no children left (VUID-vkDestroyDevice-device-00378): every object
        // created from it is owned by a wrapper holding an `Arc<Context>`, so all of them were
        // dropped before this `drop` could run, and the idle wait above finished all their work.
        // The pipeline cache is a child of the device like the rest, owned by the context itself.
        unsafe {
            self.pipelines.destroy(&self.device);
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
        }
    }
}
