//! What a rendered image records about where it came from ([`crate::imageio::Provenance`]): the
//! device, driver and Vulkan version, the scene file and a hash of its contents, the render size,
//! tone map and exposure, and frame-time medians.

use ash::vk;

use crate::headless::TimingReport;
use crate::imageio::provenance::content_hash;
use crate::imageio::Provenance;
use crate::scene::Scene;
use crate::vk::DeviceInfo;

/// [`Provenance::base`] plus the device and the scene (and, when given, the frame times).
pub fn of_render(device: &DeviceInfo, scene: &Scene, timing: Option<&TimingReport>) -> Provenance {
    let mut p = Provenance::base();
    add_device(&mut p, device);
    add_scene(&mut p, scene);
    if let Some(t) = timing {
        add_timing(&mut p, t);
    }
    p
}

/// `luz.device`, `luz.driver`, `luz.vulkan`.
pub fn add_device(p: &mut Provenance, device: &DeviceInfo) {
    p.set("luz.device", device.name.clone());
    p.set(
        "luz.driver",
        format!("{} {}", device.driver_name, device.driver_info),
    );
    let v = device.api_version;
    p.set(
        "luz.vulkan",
        format!(
            "{}.{}.{}",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        ),
    );
}

/// `luz.scene` (the file, or `embedded default`), `luz.scene_hash` (of the file's bytes),
/// `luz.size`, `luz.tonemap`, `luz.exposure_ev`, `luz.msaa`.
pub fn add_scene(p: &mut Provenance, scene: &Scene) {
    p.set("luz.scene", scene.display_name());
    if let Some(path) = &scene.source {
        if let Ok(bytes) = std::fs::read(path) {
            p.set("luz.scene_hash", content_hash(&bytes));
        }
    }
    let o = &scene.output;
    p.set("luz.size", format!("{}x{}", o.width, o.height));
    p.set("luz.tonemap", o.tonemap.name());
    p.set("luz.exposure_ev", o.exposure.to_string());
    p.set("luz.msaa", o.msaa.to_string());
}

/// `luz.instancing`, `luz.shadow_cache`, `luz.shadow_receivers`: `on` or `off` (the
/// [`crate::render::forward::Switches`] the image was rendered with).
pub fn add_switches(p: &mut Provenance, switches: &crate::render::forward::Switches) {
    for (name, on) in switches.list() {
        p.set(&format!("luz.{name}"), if on { "on" } else { "off" });
    }
}

/// `luz.frame.frames`, `luz.frame.cpu_median_ms` and `luz.frame.gpu_<pass>_median_ms`.
pub fn add_timing(p: &mut Provenance, t: &TimingReport) {
    p.set("luz.frame.frames", t.frames.to_string());
    p.set("luz.frame.cpu_median_ms", format!("{:.3}", t.cpu.median));
    for (name, s) in &t.passes {
        p.set(
            &format!("luz.frame.gpu_{}_median_ms", name.replace(' ', "_")),
            format!("{:.3}", s.median),
        );
    }
    if !t.passes.is_empty() {
        p.set(
            "luz.frame.gpu_total_median_ms",
            format!("{:.3}", t.gpu_total.median),
        );
    }
}
