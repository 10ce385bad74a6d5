//! Push-descriptor layouts (`vk::PushSet`, `SetWrites::push`): the passes that read the frame
//! graph's transient images push their views at record time. A push layout has no set to write,
//! a pooled set's layout cannot be pushed, and a push is checked against the shader's bindings
//! like a write — all on lavapipe under the validation layer.

mod common;

use ash::vk;
use common::*;
use luz::vk::{PushSet, SingleSet};

#[test]
fn push_layouts_and_set_layouts_are_not_interchangeable() {
    let ctx = gpu();
    let display = PushSet::new(&ctx, "display", &["display.vert", "display.frag"]).unwrap();
    let binding_hdr = luz::glsl::display_frag::BINDING_HDR as u32;
    let binding_table = luz::glsl::display_frag::BINDING_SRGB_TABLE as u32;
    // SAFETY: `apply` refuses before any Vulkan call (a push layout has no set).
    let err = unsafe {
        display
            .writes()
            .view(binding_hdr, vk::ImageView::null(), vk::ImageLayout::GENERAL)
            .apply(&ctx)
    }
    .unwrap_err()
    .to_string();
    assert!(err.contains("push-descriptor layout has no set"), "{err}");

    let pooled = SingleSet::new(&ctx, "display", &["display.vert", "display.frag"]).unwrap();
    let pool = luz::vk::cmd::CommandPool::new(&ctx, "push test").unwrap();
    let result = pool.one_shot(|cmd| {
        // SAFETY: refused before recording: the layout was made for sets, not pushes.
        let not_pushed = unsafe {
            pooled
                .writes()
                .buffer(binding_table, vk::Buffer::null())
                .push(cmd, vk::PipelineBindPoint::GRAPHICS, &pooled.layout, 0)
        }
        .unwrap_err()
        .to_string();
        assert!(
            not_pushed.contains("not a push-descriptor layout"),
            "{not_pushed}"
        );
        // SAFETY: refused before recording: a buffer for an image binding.
        let wrong_kind = unsafe {
            display.push(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                display.writes().buffer(binding_hdr, vk::Buffer::null()),
            )
        }
        .unwrap_err()
        .to_string();
        assert!(
            wrong_kind.contains(&format!("binding {binding_hdr}")),
            "{wrong_kind}"
        );
        // SAFETY: refused before recording: the layout has no binding 99.
        let missing = unsafe {
            display.push(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                display.writes().buffer(99, vk::Buffer::null()),
            )
        }
        .unwrap_err()
        .to_string();
        assert!(missing.contains("no binding 99"), "{missing}");
        Ok(())
    });
    result.unwrap();
    assert_no_validation_messages(&ctx);
}
