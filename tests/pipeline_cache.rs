//! The pipeline cache on disk (lavapipe, validation on): a run saves the device's pipeline cache
//! in the cache folder, the next run on a new device context loads it and renders the same
//! pixels; a damaged file and a file from another device are each refused with one warning
//! naming the file and why, the pipelines are compiled again and the file is replaced.

mod common;

use common::*;
use luz::headless::{Headless, RenderOptions};
use luz::vk::pipeline_cache::{decode, encode, Decoded, DeviceKey, Loaded, PIPELINE_CACHE_FILE};

fn scene() -> luz::scene::Scene {
    parse(
        r#"{
        "camera": {"position": [0, 1.5, 5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 40},
        "output": {"width": 64, "height": 48, "msaa": 4},
        "lights": [{"type": "point", "position": [2, 4, 3], "intensity": 30}],
        "materials": {"m": {"model": "metal_rough", "base_color": [0.8, 0.5, 0.3], "metallic": 0.5, "roughness": 0.4}},
        "objects": [{"mesh": {"type": "sphere", "radius": 1}, "material": "m"},
                    {"mesh": {"type": "plane", "size": [10, 10]}, "material": "m"}]
    }"#,
    )
}

/// One run on a fresh device context with the cache folder `dir`: what loading the pipeline
/// cache file found before the run, and the image. The renderer saves the cache when dropped.
fn run(dir: &std::path::Path) -> (Loaded, luz::imageio::LinearImage, DeviceKey) {
    let ctx = gpu();
    let loaded = ctx.load_pipeline_cache(&dir.join(PIPELINE_CACHE_FILE));
    let options = RenderOptions {
        cache_dir: Some(dir.to_path_buf()),
        ..Default::default()
    };
    let mut r = Headless::with_options(&ctx, &scene(), &options).expect("renderer");
    r.render().expect("frame");
    let image = r.image().expect("readback");
    assert!(ctx.pipelines_created() > 0);
    drop(r);
    assert_no_validation_messages(&ctx);
    (loaded, image, ctx.device_key())
}

/// The file decodes as this device's blob.
fn assert_valid(file: &std::path::Path, key: &DeviceKey) -> Vec<u8> {
    let data = std::fs::read(file).expect("the pipeline cache file was written");
    match decode(&data, key) {
        Decoded::Blob(blob) => blob.to_vec(),
        d => panic!("{}: {d:?}", file.display()),
    }
}

#[test]
fn pipeline_cache_saved_loaded_and_rebuilt() {
    let tmp = scratch("pipelines");
    let dir = tmp.join("cache");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(PIPELINE_CACHE_FILE);

    let (first_load, first, key) = run(&dir);
    assert_eq!(
        first_load,
        Loaded::Missing,
        "an empty folder has no pipeline cache"
    );
    let blob = assert_valid(&file, &key);
    assert!(
        blob.len() >= 32,
        "a Vulkan pipeline cache has its 32-byte header"
    );

    let (second_load, second, _) = run(&dir);
    assert_eq!(
        second_load,
        Loaded::Blob(blob.len()),
        "the second run loads the first's"
    );
    assert!(
        first.pixels == second.pixels,
        "a loaded pipeline cache renders differently"
    );

    // Damaged on disk (bytes flipped inside an intact header): refused, rebuilt, replaced.
    let mut bytes = std::fs::read(&file).unwrap();
    let n = bytes.len();
    for at in [20, n / 2, n - 1] {
        bytes[at] ^= 0x5a;
    }
    std::fs::write(&file, &bytes).unwrap();
    let (damaged, third, _) = run(&dir);
    match &damaged {
        Loaded::Rejected(w) => assert!(
            w.contains(&file.display().to_string()) && w.contains("damaged"),
            "{w}"
        ),
        l => panic!("a damaged file must be refused: {l:?}"),
    }
    assert!(first.pixels == third.pixels);
    assert_valid(&file, &key);

    // From another device (an intact file, another vendor): refused with both devices named.
    let other = DeviceKey {
        vendor_id: key.vendor_id ^ 0x1000,
        ..key
    };
    std::fs::write(&file, encode(&other, &blob)).unwrap();
    let (foreign, fourth, _) = run(&dir);
    match &foreign {
        Loaded::Rejected(w) => assert!(
            w.contains(&file.display().to_string())
                && w.contains("another device")
                && w.contains(&other.describe())
                && w.contains(&key.describe()),
            "{w}"
        ),
        l => panic!("another device's file must be refused: {l:?}"),
    }
    assert!(first.pixels == fourth.pixels);
    assert_valid(&file, &key);

    // A folder in the file's place: refused with a warning, nothing panics.
    std::fs::remove_file(&file).unwrap();
    std::fs::create_dir(&file).unwrap();
    let (folder, fifth, _) = run(&dir);
    assert!(
        matches!(&folder, Loaded::Rejected(w) if w.contains("cannot be read")),
        "{folder:?}"
    );
    assert!(first.pixels == fifth.pixels);
}
