//! Tests of [`super`]: unions, conflicts, and the reflected tables against the GLSL constants.
use super::*;
use crate::vk::shaders::ReflectedBinding;

fn leak(b: Vec<ReflectedBinding>) -> &'static [ReflectedBinding] {
    Box::leak(b.into_boxed_slice())
}

const fn binding(
    set: u32,
    binding: u32,
    ty: vk::DescriptorType,
    name: &'static str,
) -> ReflectedBinding {
    ReflectedBinding {
        set,
        binding,
        ty: ty.as_raw() as u32,
        count: 1,
        name,
    }
}

#[test]
fn the_union_of_two_stages_sees_each_binding_in_the_stages_that_declare_it() {
    let vert = ModuleInterface {
        stage: vk::ShaderStageFlags::VERTEX.as_raw(),
        push_size: 64,
        bindings: leak(vec![binding(
            0,
            0,
            vk::DescriptorType::UNIFORM_BUFFER,
            "frame",
        )]),
    };
    let frag = ModuleInterface {
        stage: vk::ShaderStageFlags::FRAGMENT.as_raw(),
        push_size: 80,
        bindings: leak(vec![
            binding(0, 0, vk::DescriptorType::UNIFORM_BUFFER, "frame"),
            binding(2, 1, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, "map"),
        ]),
    };
    let i = Interface::from_modules("t", &[("a.vert", &vert), ("a.frag", &frag)]).unwrap();
    let both = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    assert_eq!(i.bindings(0).len(), 1);
    assert_eq!(i.bindings(0)[0].stages, both);
    assert_eq!(i.bindings(1), &[]);
    assert_eq!(i.bindings(2)[0].stages, vk::ShaderStageFlags::FRAGMENT);
    // The push range: the larger block, for both stages.
    let push = i.push_range().unwrap();
    assert_eq!((push.size, push.stage_flags), (80, both));
    assert!(i.check_push::<[u8; 80]>().is_ok());
    let e = i.check_push::<[u8; 64]>().unwrap_err().to_string();
    assert!(e.contains("80 bytes") && e.contains("64"), "{e}");
}

#[test]
fn one_binding_declared_with_two_types_is_refused() {
    let a = ModuleInterface {
        stage: vk::ShaderStageFlags::COMPUTE.as_raw(),
        push_size: 0,
        bindings: leak(vec![binding(
            0,
            3,
            vk::DescriptorType::STORAGE_IMAGE,
            "dst",
        )]),
    };
    let b = ModuleInterface {
        stage: vk::ShaderStageFlags::COMPUTE.as_raw(),
        push_size: 0,
        bindings: leak(vec![binding(
            0,
            3,
            vk::DescriptorType::SAMPLED_IMAGE,
            "src",
        )]),
    };
    let e = Interface::from_modules("pass", &[("a.comp", &a), ("b.comp", &b)])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("pass: set 0 binding 3") && e.contains("`dst`") && e.contains("b.comp"),
        "{e}"
    );
}

#[test]
fn variants_add_the_bindings_the_optimiser_removed_from_one_of_them() {
    // saturate.comp's clamp kernel does not touch the reduction buffer; its normalize kernels
    // do. One layout serves all three.
    let clamp = Interface::of("s", &["saturate.comp:clamp"]).unwrap();
    let all = Interface::of("s", &["saturate.comp:clamp", "saturate.comp:reduce"]).unwrap();
    let names = |i: &Interface| i.bindings(0).iter().map(|b| b.name).collect::<Vec<_>>();
    assert_eq!(names(&clamp), ["hdr"]);
    assert_eq!(names(&all).len(), 2, "{:?}", names(&all));
}

#[test]
fn the_reflected_tables_agree_with_the_glsl_constants() {
    // display.frag: a sampled HDR image and the sRGB table (storage buffer), a 4-byte push.
    let d = module_interface("display.frag").unwrap();
    let find = |b: i32| d.bindings.iter().find(|x| x.binding == b as u32).unwrap();
    let g = crate::glsl::display_frag::BINDING_HDR;
    assert_eq!(
        find(g).ty,
        vk::DescriptorType::SAMPLED_IMAGE.as_raw() as u32
    );
    let t = crate::glsl::display_frag::BINDING_SRGB_TABLE;
    assert_eq!(
        find(t).ty,
        vk::DescriptorType::STORAGE_BUFFER.as_raw() as u32
    );
    assert_eq!(d.push_size, 4);
    assert_eq!(d.stage, vk::ShaderStageFlags::FRAGMENT.as_raw());
    // Every module the build embedded has an interface, and no key is unknown.
    assert_eq!(INTERFACES.len(), super::super::shaders::keys().count());
    assert!(module_interface("no_such.frag").is_err());
}

#[test]
fn the_scene_sets_have_every_binding_of_bindings_glsl() {
    let scene = crate::render::sets::scene_interface().unwrap();
    // Frame set: 9 buffers (the area lights' included) and glass's copy of the opaque scene;
    // materials: 22 maps (glass's four and the layers' ten included) and the extras; shadows:
    // 3 maps, 2 buffers.
    assert_eq!(scene.bindings(crate::render::gpu::SET_FRAME).len(), 10);
    assert_eq!(scene.bindings(crate::render::gpu::SET_MATERIAL).len(), 23);
    assert_eq!(scene.bindings(crate::render::gpu::SET_SHADOW).len(), 5);
    assert_eq!(scene.bindings(crate::render::gpu::SET_ENV).len(), 5);
}
