//! Resource limits from the device, never assumed: every input-sized GPU resource is checked
//! against the limits the device reports (`luz::vk::limits`), and an input beyond them is a clear
//! error naming the scene, the object or field, and the limit. The limits are tightened on the
//! test's context (`Context::tighten_limits`) so small scenes exercise the checks; each test
//! asserts that the validation layer stayed silent.

mod common;

use std::path::Path;

use ash::vk;
use luz::headless::{Headless, DEPTH_FORMAT};
use luz::render::forward::{ForwardPass, PassOptions, TargetFormat};
use luz::render::gpu::{GpuLight, ObjectData};
use luz::vk::cmd::CommandPool;
use luz::vk::image::ImageDesc;
use luz::vk::{Buffer, Image, Limits, VkError};

use common::{assert_no_validation_messages, gpu, luz_command, parse, run, scratch};

/// A scene with `lights` point lights and one object of `mesh` (JSON) shaded `shading`.
fn scene_json(width: u32, height: u32, lights: usize, mesh: &str, shading: &str) -> String {
    let lights: Vec<String> = (0..lights)
        .map(|i| {
            format!(
                r#"{{"type": "point", "position": [{}, 2, 2], "intensity": 1}}"#,
                i as f32 - 1.0
            )
        })
        .collect();
    format!(
        r#"{{
  "output": {{"width": {width}, "height": {height}, "msaa": 1}},
  "camera": {{"position": [0, 0, 3], "target": [0, 0, 0], "fov_y_deg": 45}},
  "materials": {{"m": {{"model": "lambert"}}}},
  "lights": [{}],
  "objects": [{{"name": "thing", "mesh": {mesh}, "material": "m", "shading": "{shading}"}}]
}}"#,
        lights.join(", ")
    )
}

const CUBE: &str = r#"{"type": "cube", "size": 1}"#;
const PLANE: &str = r#"{"type": "plane", "size": [1, 1], "subdivisions": 1}"#;

fn limit_of(e: &VkError) -> &'static str {
    match e {
        VkError::Limit { limit_name, .. } => limit_name,
        other => panic!("expected a device-limit error, got {other}"),
    }
}

#[test]
fn update_with_more_or_fewer_lights_than_the_buffer_holds_is_an_error() {
    let ctx = gpu();
    let pool = CommandPool::new(&ctx, "test").unwrap();
    let scene = parse(&scene_json(16, 16, 2, CUBE, "phong"));
    let target = TargetFormat {
        color: luz::headless::COLOR_FORMAT,
        depth: DEPTH_FORMAT,
        samples: vk::SampleCountFlags::TYPE_1,
    };
    let mut pass = ForwardPass::in_flight(
        &ctx,
        &pool,
        &scene,
        target,
        1.0,
        None,
        PassOptions::default(),
    )
    .unwrap();
    pass.update(0, &scene, 1.0).unwrap();
    for n in [3, 1, 0] {
        let other = parse(&scene_json(16, 16, n, CUBE, "phong"));
        let e = pass.update(0, &other, 1.0).unwrap_err().to_string();
        // The pass's shape (render::world) names the change and what it needs.
        assert!(
            e.contains(&format!("2 lights → {n}")) && e.contains("Rebuild"),
            "{e}"
        );
    }
    // The pass still works with the scene it was built for.
    pass.update(0, &scene, 1.0).unwrap();
    drop(pass);
    assert_no_validation_messages(&ctx);
}

#[test]
fn lights_beyond_max_storage_buffer_range_fail_at_build_time() {
    let ctx = gpu();
    let light = std::mem::size_of::<GpuLight>() as u64;
    ctx.tighten_limits(&Limits {
        max_storage_buffer_range: 2 * light,
        ..Limits::unbounded()
    });
    // Two lights fit exactly.
    let two = parse(&scene_json(16, 16, 2, CUBE, "phong"));
    let mut r = Headless::new(&ctx, &two).expect("two lights fit");
    r.render().unwrap();
    drop(r);
    let three = parse(&scene_json(16, 16, 3, CUBE, "phong"));
    let e = Headless::new(&ctx, &three)
        .err()
        .expect("three lights do not fit");
    assert_eq!(limit_of(&e), "maxStorageBufferRange");
    assert_eq!(
        e.to_string(),
        format!(
            "<test scene>: lights (3 × {light} bytes) of {} exceeds the device limit of {} \
             (maxStorageBufferRange)",
            3 * light,
            2 * light
        )
    );
    assert_no_validation_messages(&ctx);
}

#[test]
fn objects_beyond_max_storage_buffer_range_fail_at_build_time() {
    let ctx = gpu();
    // Room for the lights (GpuLight is smaller than ObjectData) but not for one object.
    let object = std::mem::size_of::<ObjectData>() as u64;
    ctx.tighten_limits(&Limits {
        max_storage_buffer_range: object - 1,
        ..Limits::unbounded()
    });
    let scene = parse(&scene_json(16, 16, 1, CUBE, "phong"));
    let e = Headless::new(&ctx, &scene)
        .err()
        .expect("no room for the object");
    assert_eq!(limit_of(&e), "maxStorageBufferRange");
    assert!(
        e.to_string()
            .starts_with(&format!("<test scene>: objects (1 × {object} bytes)")),
        "{e}"
    );
    assert_no_validation_messages(&ctx);
}

#[test]
fn meshes_beyond_max_draw_indexed_index_value_are_an_error_naming_the_object() {
    let ctx = gpu();
    ctx.tighten_limits(&Limits {
        max_draw_indexed_index_value: 5,
        ..Limits::unbounded()
    });
    // A one-quad plane: 4 vertices smooth, 6 flat (largest index 5): both fit and render.
    for shading in ["phong", "flat"] {
        let scene = parse(&scene_json(16, 16, 1, PLANE, shading));
        let mut r = Headless::new(&ctx, &scene).expect("the plane fits");
        r.render().unwrap();
    }
    // A cube: 24 vertices smooth, 36 flat.
    let scene = parse(&scene_json(16, 16, 1, CUBE, "phong"));
    let e = Headless::new(&ctx, &scene)
        .err()
        .expect("the cube does not fit");
    assert_eq!(
        e.to_string(),
        "<test scene>: object \"thing\": largest vertex index of 23 exceeds the device limit \
         of 5 (maxDrawIndexedIndexValue)"
    );
    let scene = parse(&scene_json(16, 16, 1, CUBE, "flat"));
    let e = Headless::new(&ctx, &scene)
        .err()
        .expect("the flat cube does not fit");
    assert_eq!(
        e.to_string(),
        "<test scene>: object \"thing\" (flat shading: 3 vertices per triangle): largest \
         vertex index of 35 exceeds the device limit of 5 (maxDrawIndexedIndexValue)"
    );
    assert_no_validation_messages(&ctx);
}

#[test]
fn vertex_buffers_beyond_the_allocation_limit_are_an_error_naming_the_object() {
    let ctx = gpu();
    let pool = CommandPool::new(&ctx, "test").unwrap();
    let vertex = std::mem::size_of::<luz::render::gpu::Vertex>() as u64;
    // One byte short of the cube's 24 vertices (the pass's other buffers are smaller).
    ctx.tighten_limits(&Limits {
        max_memory_allocation_size: 24 * vertex - 1,
        ..Limits::unbounded()
    });
    let scene = parse(&scene_json(16, 16, 1, CUBE, "phong"));
    let target = TargetFormat {
        color: luz::headless::COLOR_FORMAT,
        depth: DEPTH_FORMAT,
        samples: vk::SampleCountFlags::TYPE_1,
    };
    let e = ForwardPass::in_flight(
        &ctx,
        &pool,
        &scene,
        target,
        1.0,
        None,
        PassOptions::default(),
    )
    .err()
    .expect("the cube does not fit");
    assert_eq!(limit_of(&e), "maxMemoryAllocationSize");
    assert!(
        e.to_string()
            .starts_with("<test scene>: object \"thing\": vertex buffer (24 vertices) of"),
        "{e}"
    );
    assert_no_validation_messages(&ctx);
}

#[test]
fn render_size_beyond_the_framebuffer_limits_names_output_width_and_height() {
    let ctx = gpu();
    ctx.tighten_limits(&Limits {
        max_framebuffer_width: 32,
        max_framebuffer_height: 24,
        ..Limits::unbounded()
    });
    let ok = parse(&scene_json(32, 24, 1, CUBE, "phong"));
    let mut r = Headless::new(&ctx, &ok).expect("32x24 fits");
    r.render().unwrap();
    assert_eq!(r.image().unwrap().pixels.len(), 32 * 24);
    drop(r);
    let wide = parse(&scene_json(33, 24, 1, CUBE, "phong"));
    let e = Headless::new(&ctx, &wide).err().expect("too wide");
    assert_eq!(
        e.to_string(),
        "<test scene>: output.width of 33 exceeds the device limit of 32 (maxFramebufferWidth)"
    );
    let tall = parse(&scene_json(8, 25, 1, CUBE, "phong"));
    let e = Headless::new(&ctx, &tall).err().expect("too tall");
    assert_eq!(
        e.to_string(),
        "<test scene>: output.height of 25 exceeds the device limit of 24 (maxFramebufferHeight)"
    );
    // maxImageDimension2D is checked as well.
    ctx.tighten_limits(&Limits {
        max_image_dimension_2d: 16,
        ..Limits::unbounded()
    });
    let e = Headless::new(&ctx, &ok)
        .err()
        .expect("beyond maxImageDimension2D");
    assert_eq!(
        e.to_string(),
        "<test scene>: output.width of 32 exceeds the device limit of 16 (maxImageDimension2D)"
    );
    assert_no_validation_messages(&ctx);
}

#[test]
fn buffers_and_images_beyond_the_allocation_limits_fail_cleanly() {
    let ctx = gpu();
    ctx.tighten_limits(&Limits {
        max_buffer_size: 1000,
        max_memory_allocation_size: 64 * 64 * 4 - 1,
        ..Limits::unbounded()
    });
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let cpu = gpu_allocator::MemoryLocation::CpuToGpu;
    assert!(Buffer::new(&ctx, "small", 1000, usage, cpu).is_ok());
    let e = Buffer::new(&ctx, "big", 1001, usage, cpu).err().unwrap();
    assert_eq!(
        e.to_string(),
        "big of 1001 exceeds the device limit of 1000 (maxBufferSize)"
    );
    // A 64×64 RGBA8 image needs at least 16384 bytes: over the allocation limit. The image
    // created to ask for its memory requirements is destroyed again.
    let desc = ImageDesc::texture(64, 64, vk::Format::R8G8B8A8_UNORM, 1, 1);
    let e = Image::new(&ctx, "texture", desc).err().unwrap();
    assert_eq!(limit_of(&e), "maxMemoryAllocationSize");
    assert!(
        e.to_string().starts_with("texture (64x64 image) of "),
        "{e}"
    );
    // Cube maps are checked against maxImageDimensionCube, layers against maxImageArrayLayers.
    ctx.tighten_limits(&Limits {
        max_image_dimension_cube: 8,
        max_image_array_layers: 4,
        ..Limits::unbounded()
    });
    let e = Image::new(
        &ctx,
        "cube",
        ImageDesc::cube(16, vk::Format::R16G16B16A16_SFLOAT, 1),
    )
    .err()
    .unwrap();
    assert_eq!(
        e.to_string(),
        "cube size 16x16 of 16 exceeds the device limit of 8 (maxImageDimensionCube)"
    );
    let e = Image::new(
        &ctx,
        "cube",
        ImageDesc::cube(8, vk::Format::R16G16B16A16_SFLOAT, 1),
    )
    .err()
    .unwrap();
    assert_eq!(limit_of(&e), "maxImageArrayLayers");
    assert_no_validation_messages(&ctx);
}

#[test]
fn device_limits_are_queried_from_the_device() {
    let ctx = gpu();
    let l = ctx.limits();
    assert_eq!(l, ctx.info.resource_limits);
    let vk_limits = &ctx.info.limits;
    assert_eq!(l.max_image_dimension_2d, vk_limits.max_image_dimension2_d);
    assert_eq!(l.max_framebuffer_width, vk_limits.max_framebuffer_width);
    assert_eq!(
        l.max_draw_indexed_index_value,
        vk_limits.max_draw_indexed_index_value
    );
    // Vulkan's minimum guarantees (the maintenance3/4 values are filled in).
    assert!(l.max_memory_allocation_size >= 1 << 30);
    assert!(l.max_buffer_size >= 1 << 30);
    assert!(l.max_draw_indexed_index_value >= (1 << 24) - 1);
    assert_no_validation_messages(&ctx);
}

/// `luz render` of a scene whose output is within the decoder's bounds (16384 per side) but
/// whose 16-byte-per-pixel colour target and readback exceed lavapipe's 2 GiB
/// maxMemoryAllocationSize: a clear error naming the scene and `output.width × output.height`,
/// before anything is allocated.
#[test]
fn luz_render_names_output_size_beyond_the_allocation_limit() {
    let ctx = gpu();
    let pixels_bytes = 16384u64 * 16384 * 16;
    let l = ctx.limits();
    if pixels_bytes <= l.max_memory_allocation_size.min(l.max_buffer_size) {
        eprintln!("SKIPPED: this device can allocate a 16384x16384 RGBA32F target");
        return;
    }
    drop(ctx);
    let dir = scratch("huge-output");
    let scene = dir.join("huge_output.json");
    std::fs::write(&scene, scene_json(16384, 16384, 1, CUBE, "phong")).unwrap();
    let out = run(luz_command(["render", scene.to_str().unwrap(), "-o"]).arg(dir.join("out.exr")));
    let stderr = &out.stderr;
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("huge_output.json: output.width × output.height (16384x16384)")
            && stderr.contains("exceeds the device limit of"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("panicked") && !stderr.contains("VUID"),
        "{stderr}"
    );
    assert!(!Path::new(&dir.join("out.exr")).exists());
}
