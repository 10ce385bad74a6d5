//! The device's one Vulkan pipeline cache, kept on disk between runs (docs/reliability.md,
//! "Caches"): every pipeline luz creates goes through it, so that a second run hands the driver
//! the compiled pipelines of the first.
//!
//! The file (`pipelines.vkcache` in the cache folder) is [`encode`]d like luz's other caches: a
//! magic, the CRC-32 of the body, then the body. The body starts with the [`DeviceKey`] of the
//! device and driver that made it (Vulkan's own header check: vendorID, deviceID,
//! pipelineCacheUUID, plus the driver version), then the driver's blob. A damaged file or one
//! from another device or driver gives one warning naming the file and why; the pipelines are
//! compiled again and the file is replaced at the end of the run.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, RwLock, RwLockReadGuard};

use ash::vk;

use super::Context;

/// The file name of the pipeline cache in luz's cache folder.
pub const PIPELINE_CACHE_FILE: &str = "pipelines.vkcache";

/// Version 01 of the file format.
const MAGIC: &[u8; 8] = b"LUZPIP01";

/// Bytes of a [`DeviceKey`] in the file.
const KEY_BYTES: usize = 28;

/// Bytes of Vulkan's pipeline cache header, version one.
const VK_HEADER_BYTES: usize = 32;

/// The device and driver a pipeline cache blob belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeviceKey {
    pub vendor_id: u32,
    pub device_id: u32,
    pub driver_version: u32,
    pub pipeline_cache_uuid: [u8; 16],
}

impl DeviceKey {
    /// The key of a physical device, from its properties.
    pub fn of(props: &vk::PhysicalDeviceProperties) -> Self {
        Self {
            vendor_id: props.vendor_id,
            device_id: props.device_id,
            driver_version: props.driver_version,
            pipeline_cache_uuid: props.pipeline_cache_uuid,
        }
    }

    fn bytes(&self) -> [u8; KEY_BYTES] {
        let mut b = [0u8; KEY_BYTES];
        b[0..4].copy_from_slice(&self.vendor_id.to_le_bytes());
        b[4..8].copy_from_slice(&self.device_id.to_le_bytes());
        b[8..12].copy_from_slice(&self.driver_version.to_le_bytes());
        b[12..28].copy_from_slice(&self.pipeline_cache_uuid);
        b
    }

    fn from_bytes(b: &[u8]) -> Self {
        let u = |i: usize| u32::from_le_bytes(b[i..i + 4].try_into().expect("4 bytes"));
        Self {
            vendor_id: u(0),
            device_id: u(4),
            driver_version: u(8),
            pipeline_cache_uuid: b[12..28].try_into().expect("16 bytes"),
        }
    }

    /// "vendor 0x…, device 0x…, driver version 0x…, cache UUID …".
    pub fn describe(&self) -> String {
        let uuid: String = self
            .pipeline_cache_uuid
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        format!(
            "vendor {:#x}, device {:#x}, driver version {:#x}, cache UUID {uuid}",
            self.vendor_id, self.device_id, self.driver_version
        )
    }
}

/// What a pipeline cache file holds for this device.
#[derive(Debug, PartialEq)]
pub enum Decoded<'a> {
    /// The driver's blob, checksum and device verified.
    Blob(&'a [u8]),
    /// Another version of luz's format: replaced quietly.
    OtherVersion,
    /// Empty, truncated, zeroed or not matching its checksum.
    Damaged,
    /// Made by another device or driver (why).
    OtherDevice(String),
}

/// The file's bytes for `blob`, made by the device `key`.
pub fn encode(key: &DeviceKey, blob: &[u8]) -> Vec<u8> {
    let mut body = Vec::with_capacity(KEY_BYTES + blob.len());
    body.extend_from_slice(&key.bytes());
    body.extend_from_slice(blob);
    crate::files::cache_dir::frame(MAGIC, &body)
}

/// The blob in a file's bytes, if it is intact and was made by the device `key`.
pub fn decode<'a>(data: &'a [u8], key: &DeviceKey) -> Decoded<'a> {
    use crate::files::cache_dir::{unframe, Framed};
    let body = match unframe(data, MAGIC) {
        Framed::Body(body) => body,
        Framed::OtherVersion => return Decoded::OtherVersion,
        Framed::Damaged => return Decoded::Damaged,
    };
    if body.len() < KEY_BYTES + VK_HEADER_BYTES {
        return Decoded::Damaged;
    }
    let (stored, blob) = body.split_at(KEY_BYTES);
    let stored = DeviceKey::from_bytes(stored);
    if stored != *key {
        return Decoded::OtherDevice(format!(
            "made by {}; this device is {}",
            stored.describe(),
            key.describe()
        ));
    }
    // Vulkan's own header (VkPipelineCacheHeaderVersionOne): length, version, vendor, device, UUID.
    let u = |i: usize| u32::from_le_bytes(blob[i..i + 4].try_into().expect("4 bytes"));
    let header = DeviceKey {
        vendor_id: u(8),
        device_id: u(12),
        driver_version: key.driver_version,
        pipeline_cache_uuid: blob[16..32].try_into().expect("16 bytes"),
    };
    if (u(0) as usize) < VK_HEADER_BYTES
        || u(4) != vk::PipelineCacheHeaderVersion::ONE.as_raw() as u32
        || header != *key
    {
        return Decoded::OtherDevice(format!(
            "its Vulkan header names {}; this device is {}",
            header.describe(),
            key.describe()
        ));
    }
    Decoded::Blob(blob)
}

/// What [`Context::load_pipeline_cache`] found.
#[derive(Debug, PartialEq)]
pub enum Loaded {
    /// The driver's blob of this many bytes, merged into the device's cache.
    Blob(usize),
    /// No file (or luz's other format version): the pipelines are compiled and saved.
    Missing,
    /// This file was loaded before on this device.
    Again,
    /// The file cannot be used: the one warning given (it names the file and why).
    Rejected(String),
}

/// The device's pipeline cache and what was loaded into and saved from it.
pub(super) struct PipelineCache {
    raw: vk::PipelineCache,
    key: DeviceKey,
    /// Read: creating pipelines with the cache; write: merging a loaded blob into it
    /// (vkMergePipelineCaches needs the destination externally synchronised).
    lock: RwLock<()>,
    /// Pipelines created with the cache, and that number when the file was last written.
    created: AtomicU64,
    saved: AtomicU64,
    loaded: Mutex<Vec<PathBuf>>,
}

impl PipelineCache {
    /// An empty cache for `device` (a null handle, so no caching, if the driver cannot make one).
    pub(super) fn new(device: &ash::Device, props: &vk::PhysicalDeviceProperties) -> Self {
        let info = vk::PipelineCacheCreateInfo::default();
        // SAFETY: `info` is a local that outlives the call and carries no initial data.
        let raw = unsafe { device.create_pipeline_cache(&info, None) }.unwrap_or_else(|e| {
            log::warn!("cannot create a pipeline cache ({e}); pipelines are compiled every run");
            vk::PipelineCache::null()
        });
        Self {
            raw,
            key: DeviceKey::of(props),
            lock: RwLock::new(()),
            created: AtomicU64::new(0),
            saved: AtomicU64::new(0),
            loaded: Mutex::new(Vec::new()),
        }
    }

    /// Destroys the cache.
    ///
    /// # Safety
    /// Called once, from the context's drop, before the device is destroyed.
    pub(super) unsafe fn destroy(&self, device: &ash::Device) {
        // SAFETY: the caller's contract; a null handle is allowed.
        unsafe { device.destroy_pipeline_cache(self.raw, None) };
    }
}

impl Context {
    /// The device's pipeline cache for one `vkCreate*Pipelines` call (hold the guard across it).
    pub(super) fn pipeline_cache(&self) -> (RwLockReadGuard<'_, ()>, vk::PipelineCache) {
        let p = &self.pipelines;
        (p.lock.read().unwrap_or_else(|e| e.into_inner()), p.raw)
    }

    /// Counts a pipeline created with [`Context::pipeline_cache`].
    pub(super) fn pipeline_created(&self) {
        self.pipelines.created.fetch_add(1, Ordering::Relaxed);
    }

    /// Pipelines created on this device so far.
    pub fn pipelines_created(&self) -> u64 {
        self.pipelines.created.load(Ordering::Relaxed)
    }

    /// This device's [`DeviceKey`].
    pub fn device_key(&self) -> DeviceKey {
        self.pipelines.key
    }

    /// Merges the pipeline cache file `path` into the device's cache, once per file. A damaged
    /// file or one from another device gives one warning naming it and why (the pipelines are
    /// compiled again, and [`Context::save_pipeline_cache`] replaces the file).
    pub fn load_pipeline_cache(&self, path: &Path) -> Loaded {
        let p = &self.pipelines;
        if p.raw == vk::PipelineCache::null() {
            return Loaded::Missing;
        }
        {
            let mut loaded = p.loaded.lock().unwrap_or_else(|e| e.into_inner());
            if loaded.iter().any(|l| l == path) {
                return Loaded::Again;
            }
            loaded.push(path.to_path_buf());
        }
        let reject = |why: String| {
            let w = format!(
                "{}: pipeline cache {why}; compiling the pipelines again and replacing the file",
                path.display()
            );
            log::warn!("{w}");
            Loaded::Rejected(w)
        };
        let data = match std::fs::read(path) {
            Ok(data) => data,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Loaded::Missing,
            Err(e) => return reject(format!("cannot be read ({e})")),
        };
        let blob = match decode(&data, &p.key) {
            Decoded::Blob(blob) => blob,
            Decoded::OtherVersion => return Loaded::Missing,
            Decoded::Damaged => {
                return reject(
                    "is damaged (empty, truncated, zeroed or not matching its checksum)".into(),
                )
            }
            Decoded::OtherDevice(why) => {
                return reject(format!("is from another device or driver ({why})"))
            }
        };
        let info = vk::PipelineCacheCreateInfo::default().initial_data(blob);
        // SAFETY: `info` and `blob` outlive the call; the blob's header was checked against this
        // device (the driver still validates the rest and may ignore it).
        let src = match unsafe { self.device.create_pipeline_cache(&info, None) } {
            Ok(src) => src,
            Err(e) => return reject(format!("was refused by the driver ({e})")),
        };
        let merged = {
            let _write = p.lock.write().unwrap_or_else(|e| e.into_inner());
            // SAFETY: `p.raw` is externally synchronised by the write lock (every other use holds
            // the read lock); `src` is a live cache of this device, not the destination.
            unsafe { self.device.merge_pipeline_caches(p.raw, &[src]) }
        };
        // SAFETY: `src` was created above, is no longer used and is destroyed once.
        unsafe { self.device.destroy_pipeline_cache(src, None) };
        if let Err(e) = merged {
            return reject(format!("could not be merged ({e})"));
        }
        crate::files::cache_dir::touch(path);
        Loaded::Blob(blob.len())
    }

    /// Writes the device's pipeline cache to `path` (atomically) if pipelines were created since
    /// it was last written; returns whether it wrote. A write that fails gives one warning per
    /// folder and problem.
    pub fn save_pipeline_cache(&self, path: &Path) -> bool {
        let p = &self.pipelines;
        let created = p.created.load(Ordering::Relaxed);
        if p.raw == vk::PipelineCache::null() || created == p.saved.load(Ordering::Relaxed) {
            return false;
        }
        let blob = {
            let _read = p.lock.read().unwrap_or_else(|e| e.into_inner());
            // SAFETY: `p.raw` is a live cache of this device; ash sizes the buffer from the
            // count query.
            unsafe { self.device.get_pipeline_cache_data(p.raw) }
        };
        let blob = match blob {
            Ok(blob) => blob,
            Err(e) => {
                log::warn!("cannot read the pipeline cache back ({e}); it is not saved");
                return false;
            }
        };
        let data = encode(&p.key, &blob);
        match crate::files::try_write_file_atomically(path, &data) {
            Ok(()) => {
                p.saved.store(created, Ordering::Relaxed);
                crate::files::cache_dir::written(path, data.len() as u64);
                true
            }
            Err(e) => {
                let folder = path.parent().unwrap_or(path);
                crate::files::cache_dir::warn_once(
                    &format!("pipelines:{}:{:?}", folder.display(), e.kind()),
                    format!(
                        "{}: cannot write the pipeline cache ({e}); pipelines are compiled \
                         again on every run",
                        path.display()
                    ),
                    &mut |w| log::warn!("{w}"),
                );
                false
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> DeviceKey {
        DeviceKey {
            vendor_id: 0x10005,
            device_id: 0,
            driver_version: 0x5803006,
            pipeline_cache_uuid: *b"0123456789abcdef",
        }
    }

    /// A blob as a driver writes it: Vulkan's header for `key`, then `extra` bytes.
    fn blob(key: &DeviceKey, extra: usize) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(&32u32.to_le_bytes());
        b.extend_from_slice(&1u32.to_le_bytes());
        b.extend_from_slice(&key.vendor_id.to_le_bytes());
        b.extend_from_slice(&key.device_id.to_le_bytes());
        b.extend_from_slice(&key.pipeline_cache_uuid);
        b.extend((0..extra).map(|i| (i * 13 % 251) as u8));
        b
    }

    /// A file round-trips; any flipped byte outside the reserved ones is damage; another
    /// device, driver version or Vulkan header is named in the reason; empty, zeroed and
    /// truncated files are damage; another version of the format is a quiet miss.
    #[test]
    fn pipeline_cache_files() {
        let k = key();
        let b = blob(&k, 300);
        let file = encode(&k, &b);
        assert_eq!(decode(&file, &k), Decoded::Blob(&b));
        // Bytes 6–7 are the format version (another version is a miss), 12–15 are reserved.
        for at in (0..file.len()).filter(|at| !(6..8).contains(at) && !(12..16).contains(at)) {
            let mut bad = file.clone();
            bad[at] ^= 0x10;
            assert_eq!(decode(&bad, &k), Decoded::Damaged, "byte {at}");
        }
        for other in [
            DeviceKey {
                vendor_id: 0x10de,
                ..k
            },
            DeviceKey { device_id: 7, ..k },
            DeviceKey {
                driver_version: 1,
                ..k
            },
            DeviceKey {
                pipeline_cache_uuid: [9; 16],
                ..k
            },
        ] {
            let file = encode(&other, &blob(&other, 10));
            match decode(&file, &k) {
                Decoded::OtherDevice(why) => assert!(
                    why.contains(&other.describe()) && why.contains(&k.describe()),
                    "{why}"
                ),
                d => panic!("{other:?}: {d:?}"),
            }
        }
        // luz's key matches but the driver's own header names another device.
        let file = encode(&k, &blob(&DeviceKey { device_id: 3, ..k }, 10));
        assert!(
            matches!(decode(&file, &k), Decoded::OtherDevice(w) if w.contains("Vulkan header"))
        );
        assert_eq!(decode(&[], &k), Decoded::Damaged);
        assert_eq!(decode(&[0; 4096], &k), Decoded::Damaged);
        assert_eq!(decode(&file[..20], &k), Decoded::Damaged);
        assert_eq!(decode(&encode(&k, &b[..8]), &k), Decoded::Damaged);
        let mut old = encode(&k, &b);
        old[..8].copy_from_slice(b"LUZPIP00");
        assert_eq!(decode(&old, &k), Decoded::OtherVersion);
    }
}
