//! The frame-time target's glue ([`crate::window::lod_target`]): whether the view changed, the
//! budget handed to the forward pass before its per-frame update, the measured frames fed back.

use super::*;
use crate::window::lod_target::Mode;

/// What the budget of a recorded frame was (kept with its frame slot until its timestamps are
/// read).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct FrameLod {
    /// The budget (px) its mesh levels were chosen with.
    pub budget: f32,
    /// Drawn at the adaptive budget (the view was changing).
    pub adaptive: bool,
    /// Triangles it drew (after frustum culling, at its levels).
    pub triangles: u64,
}

impl Viewer {
    /// Before the forward pass's update: whether the view changed since the last frame (camera,
    /// window size, an edit, a scripted action, a rebuild) or may change at once (a mouse button
    /// held on the scene: a drag that pauses should not pay for an exact frame when it goes on),
    /// and the budget the controller asks for. It acts only when some mesh has simplified levels
    /// and the lab compares nothing (no side B, no error view: comparisons are of the pictures the
    /// scenes' budgets make). A frame that takes a screenshot draws at the scene's budget whatever
    /// the view does: a screenshot is the exact picture.
    pub(super) fn choose_lod_budget(&mut self, slot: usize) {
        let view = (self.scene.camera, self.swapchain.extent);
        let dragging = self.drag.left || self.drag.middle;
        let changed =
            std::mem::take(&mut self.view_changed) || self.last_view != Some(view) || dragging;
        self.last_view = Some(view);
        self.lod_target
            .set_scene_budget(self.scene.output.tessellation_error_px);
        let enabled =
            self.forward.has_lod_levels() && self.lab.b.is_none() && !self.lab.settings.error_view;
        let budget = self.lod_target.frame(changed, enabled);
        let adaptive =
            self.lod_target.mode() == Mode::Adaptive && self.pending_screenshot.is_none();
        self.forward.set_lod_budget(adaptive.then_some(budget));
        self.frames[slot].lod.adaptive = adaptive;
    }

    /// Whether the viewer may stop drawing until the next window event: with the frame-time
    /// target on, the exact picture (the scene's budget, the view still) has been submitted, no
    /// input arrived in the last [`AWAKE_FRAMES`] frames, and nothing else counts on frames coming
    /// (a benchmark, `--frames`, a script, a screenshot, the shadow-map window's read-back).
    /// Redrawing the same picture every frame would take the CPU (half a second a frame on the
    /// 40 M scene) and leave frames in flight for the first moving frame to wait for.
    pub(super) fn may_wait(&self) -> bool {
        self.lod_target.exact_drawn()
            && self.awake == 0
            && !self.bench
            && self.frame_limit.is_none()
            && self.script.is_empty()
            && self.pending_screenshot.is_none()
            && !self.shadow_view.due
            && self.shadow_view.save.is_none()
    }

    /// After the forward pass's update: the profiler's geometry and budget lines, and what the
    /// slot's frame drew with.
    pub(super) fn note_lod(&mut self, slot: usize) {
        let choices = self.forward.lod_choices(slot, &self.scene);
        let triangles = self.forward.triangles_drawn(slot);
        self.profiler
            .set_geometry(triangles, crate::scene::lod::levels_in_use(&choices));
        let budget = self.forward.lod_budget();
        let has_lod = self.forward.has_lod_levels();
        self.profiler
            .set_lod_budget(has_lod.then(|| self.lod_target.describe(budget)));
        let lod = &mut self.frames[slot].lod;
        lod.budget = budget;
        lod.triangles = triangles;
    }
}

/// What the target compares: a frame's GPU time (all timed passes), or its wall frame time when
/// the device has no timestamps. The GPU time is what the budget changes (the triangles drawn);
/// the wall time also holds vsync waits and the host's own work, which no budget shortens.
pub(super) fn frame_cost(sample: &FrameSample) -> f64 {
    if sample.gpu_ms.is_empty() {
        sample.frame_ms
    } else {
        sample.gpu_ms.iter().map(|(_, t)| t).sum()
    }
}

/// Whether a scripted action can change the picture (anything but saving, screenshots, the
/// panels, help, vsync and which side the panels edit): the target's "the view changed".
pub(super) fn changes_view(action: &Action) -> bool {
    !matches!(
        action,
        Action::Screenshot(_)
            | Action::ShadowMapSave(_)
            | Action::Save(_)
            | Action::Panels(_)
            | Action::Help(_)
            | Action::Vsync(_)
            | Action::CompareEdit(_)
    )
}

/// [`changes_view`] for the panels' actions.
pub(super) fn ui_changes_view(action: &UiAction) -> bool {
    !matches!(
        action,
        UiAction::Save(_) | UiAction::Screenshot { .. } | UiAction::VsyncChanged
    )
}
