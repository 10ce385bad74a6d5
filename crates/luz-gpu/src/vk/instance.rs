//! Vulkan instance, optional validation layer and a debug-utils messenger that counts what it reports.

use std::ffi::{c_void, CStr, CString};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use ash::{ext, vk};

use super::VkError;

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// What the debug messenger has seen since the instance was created.
#[derive(Default, Debug)]
pub struct ValidationLog {
    errors: AtomicU32,
    warnings: AtomicU32,
    messages: Mutex<Vec<String>>,
}

impl ValidationLog {
    pub fn errors(&self) -> u32 {
        self.errors.load(Ordering::SeqCst)
    }
    pub fn warnings(&self) -> u32 {
        self.warnings.load(Ordering::SeqCst)
    }
    /// Every error and warning message, in order.
    pub fn messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }
    /// Records (and prints) an error found by luz itself, e.g. a leak at device destruction.
    pub fn report_error(&self, text: String) {
        log::error!("validation: {text}");
        self.record(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR, text);
    }

    fn record(&self, severity: vk::DebugUtilsMessageSeverityFlagsEXT, text: String) {
        if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            self.errors.fetch_add(1, Ordering::SeqCst);
        } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
            self.warnings.fetch_add(1, Ordering::SeqCst);
        } else {
            return;
        }
        if let Ok(mut m) = self.messages.lock() {
            m.push(text);
        }
    }
}

/// Options for creating the instance.
#[derive(Debug, Clone, Default)]
pub struct InstanceDesc {
    /// Enable `VK_LAYER_KHRONOS_validation` (an error if it is not installed).
    pub validation: bool,
    /// Also enable the layer's synchronization validation.
    pub sync_validation: bool,
    /// Extra instance extensions (a window surface's, for example).
    pub extensions: Vec<&'static CStr>,
}

/// The loader entry, the instance and, when present, the debug messenger.
pub struct Instance {
    pub entry: ash::Entry,
    pub raw: ash::Instance,
    pub debug_utils: Option<ext::debug_utils::Instance>,
    messenger: vk::DebugUtilsMessengerEXT,
    pub log: Arc<ValidationLog>,
    pub validation: bool,
}

/// The debug-utils messenger's callback: counts and records errors and warnings in the
/// [`ValidationLog`] passed as user data.
///
/// # Safety
///
/// Only the Vulkan loader calls this, as a `PFN_vkDebugUtilsMessengerCallbackEXT`: `data`, when not
/// null, points to callback data valid for the call (with `p_message` null or a NUL-terminated
/// string), and `user`, when not null, is the `Arc::as_ptr` of a [`ValidationLog`] that outlives
/// the messenger (as [`Instance::new`] registers it).
unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user.is_null() {
        return vk::FALSE;
    }
    // SAFETY: both are non-null (checked above). The loader passes callback data valid for the
    // duration of the call; `user` is the `Arc::as_ptr` of the `ValidationLog` that `Instance::new`
    // registered, and the `Instance` holds that Arc (never replaced) until after the messenger and
    // the instance are destroyed, so the pointee is alive and only shared references exist.
    let (data, log) = unsafe { (&*data, &*(user as *const ValidationLog)) };
    let msg = if data.p_message.is_null() {
        String::from("(no message)")
    } else {
        // SAFETY: `p_message` is non-null (checked above) and, per the callback data's valid usage,
        // a NUL-terminated UTF-8 string valid for the duration of the callback; the borrow ends
        // with `into_owned` below.
        unsafe { CStr::from_ptr(data.p_message) }
            .to_string_lossy()
            .into_owned()
    };
    let text = format!("[{severity:?} {types:?}] {msg}");
    if severity.intersects(
        vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
            | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
    ) {
        log::error!("validation: {text}");
    }
    log.record(severity, text);
    vk::FALSE
}

impl Instance {
    pub fn new(desc: &InstanceDesc) -> Result<Self, VkError> {
        // SAFETY: `Entry::load` dlopens the system Vulkan loader (libvulkan.so.1) and runs its
        // initialisers; that library is trusted to be a conforming loader. Failure is an error.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| VkError::Loader(e.to_string()))?;
        // SAFETY: global commands need only a loaded entry; ash sizes the output from the count
        // query.
        let layers_avail = unsafe { entry.enumerate_instance_layer_properties() }?;
        // SAFETY: as above; `None` asks for the loader's and implicit layers' extensions.
        let exts_avail = unsafe { entry.enumerate_instance_extension_properties(None) }?;
        let has_layer = |name: &CStr| {
            layers_avail
                .iter()
                .any(|l| l.layer_name_as_c_str().ok() == Some(name))
        };
        let has_ext = |name: &CStr| {
            exts_avail
                .iter()
                .any(|e| e.extension_name_as_c_str().ok() == Some(name))
        };

        let mut layers: Vec<*const i8> = Vec::new();
        if desc.validation {
            if !has_layer(VALIDATION_LAYER) {
                return Err(VkError::Setup(
                    "validation was requested but VK_LAYER_KHRONOS_validation is not installed \
                     (Debian: apt-get install vulkan-validationlayers)"
                        .into(),
                ));
            }
            layers.push(VALIDATION_LAYER.as_ptr());
        }
        let debug_ext = has_ext(ext::debug_utils::NAME);
        let mut extensions: Vec<*const i8> = desc.extensions.iter().map(|e| e.as_ptr()).collect();
        for e in &desc.extensions {
            if !has_ext(e) {
                return Err(VkError::Setup(format!(
                    "the Vulkan loader lacks the instance extension {}",
                    e.to_string_lossy()
                )));
            }
        }
        if debug_ext {
            extensions.push(ext::debug_utils::NAME.as_ptr());
        }
        // VK_EXT_validation_features comes with the validation layer, not the loader: ask the layer.
        let validation_features_ext = c"VK_EXT_validation_features";
        // SAFETY: a global command on the loaded entry; the layer name is a `'static` C string.
        let layer_has_features = desc.validation
            && unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
                .map(|exts| {
                    exts.iter()
                        .any(|e| e.extension_name_as_c_str().ok() == Some(validation_features_ext))
                })
                .unwrap_or(false);
        let sync = desc.validation && desc.sync_validation;
        if sync && !layer_has_features {
            return Err(VkError::Setup(
                "synchronization validation was requested but the validation layer lacks \
                 VK_EXT_validation_features"
                    .into(),
            ));
        }
        if sync {
            extensions.push(validation_features_ext.as_ptr());
        }

        let app_name = CString::new("luz").unwrap();
        let app = vk::ApplicationInfo::default()
            .application_name(&app_name)
            .application_version(vk::make_api_version(0, 0, 1, 0))
            .engine_name(&app_name)
            .api_version(vk::API_VERSION_1_3);
        let log = Arc::new(ValidationLog::default());
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                    | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(debug_callback))
            .user_data(Arc::as_ptr(&log) as *mut c_void);
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if debug_ext && desc.validation {
            // Also catches messages from vkCreateInstance / vkDestroyInstance themselves.
            info = info.push_next(&mut messenger_info);
        }
        if sync {
            info = info.push_next(&mut features);
        }
        // SAFETY: `info` and everything it points to (`app` and `app_name`, the layer and extension
        // name arrays, whose pointers are into `'static` CStrs, `messenger_info`, `features` and
        // `enables`) are locals that outlive the call. Every layer and extension named was checked
        // available above, and the chained structs are allowed by them: the messenger info by
        // VK_EXT_debug_utils (chained only when `debug_ext`), the validation features by
        // VK_EXT_validation_features (chained only when `sync`, which enables it). The messenger's
        // user data is `log`, which the returned `Instance` keeps alive.
        let raw = unsafe { entry.create_instance(&info, None) }?;

        let (debug_utils, messenger) = if debug_ext {
            let du = ext::debug_utils::Instance::new(&entry, &raw);
            let messenger = if desc.validation {
                // SAFETY: `du` was loaded for `raw`, which enabled VK_EXT_debug_utils
                // (`debug_ext`). `messenger_info` is a live local whose pNext is null (push_next put
                // it last in `info`'s chain); its user data is `log`, kept alive by the `Instance`
                // for longer than the messenger.
                unsafe { du.create_debug_utils_messenger(&messenger_info, None) }?
            } else {
                vk::DebugUtilsMessengerEXT::null()
            };
            (Some(du), messenger)
        } else {
            (None, vk::DebugUtilsMessengerEXT::null())
        };
        Ok(Self {
            entry,
            raw,
            debug_utils,
            messenger,
            log,
            validation: desc.validation,
        })
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: the messenger was created from this instance and is destroyed first, exactly
        // once. Every other child object (the device, surfaces) is owned by something that holds
        // this instance and drops it last: `Context` keeps it as its last field, after the device,
        // and the viewer's surface is destroyed before its context
        // (VUID-vkDestroyInstance-instance-00629). `self.log`, the messenger's user data, is dropped
        // only after this function, so callbacks during destruction still find it.
        unsafe {
            if let Some(du) = &self.debug_utils {
                if self.messenger != vk::DebugUtilsMessengerEXT::null() {
                    du.destroy_debug_utils_messenger(self.messenger, None);
                }
            }
            self.raw.destroy_instance(None);
        }
    }
}
