//! Instancing: draws next to each other in a slot's order that share mesh, LOD level, pipeline
//! variant, material, face culling and push constants (all but the object slot) are recorded as
//! one instanced draw. The slot's instance buffer (`BINDING_INSTANCES`) holds the object of each
//! entry of the order; an instanced draw starts at its first entry (`firstInstance`), and the
//! vertex stage reads `objects[instances[gl_InstanceIndex]]`. The fragment stages need nothing per
//! object beyond the material, which the instances share; the deferred path's G-buffer names the
//! first instance's material slot, whose data every instance's slot repeats.

use super::{draws::ColorView, gpu::MaterialPush, ForwardPass};
use crate::vk::VkError;

impl ForwardPass {
    /// Whether item `b` (at LOD level `lb`) can be another instance of the draw recording item
    /// `a` (at `la`): same mesh, level, variant, material, culling and push constants but for
    /// the object, neither split by where shadows fall nor transmissive (glass reads its own
    /// object's scale through the push constants).
    fn same_draw(&self, (a, la): (usize, u8), (b, lb): (usize, u8)) -> bool {
        let material = |i: usize| MaterialPush {
            object_index: 0,
            ..self.draws[i].push
        };
        let (da, db) = (&self.draws[a], &self.draws[b]);
        let (ia, ib) = (&self.list.items[a], &self.list.items[b]);
        ia.shape == ib.shape
            && !ia.transmit
            && !ib.transmit
            && la == lb
            && da.shadow_area.is_none()
            && db.shadow_area.is_none()
            && da.variant == db.variant
            && ia.material == ib.material
            && ia.cull == ib.cull
            && material(a) == material(b)
    }

    /// The draws to record for `order` (item indices, `levels` by item): runs `(start, count)`
    /// of `order`, each one instanced draw ([`crate::render::draws::runs`]); one run per entry
    /// when instancing is off.
    pub(super) fn runs(&self, order: &[usize], levels: &[u8]) -> Vec<(usize, usize)> {
        let level = |i: usize| levels.get(i).copied().unwrap_or(0);
        crate::render::draws::runs(order, self.instancing, |a, b| {
            self.same_draw((a, level(a)), (b, level(b)))
        })
    }

    /// Sets slot `slot`'s colour view and writes the object of each entry of its order into
    /// the slot's instance buffer.
    pub(super) fn set_view(&mut self, slot: usize, view: ColorView) -> Result<(), VkError> {
        let objects: Vec<u32> = view
            .order
            .iter()
            .map(|&i| self.draws[i].push.object_index)
            .collect();
        let s = &mut self.slots[slot];
        if !objects.is_empty() {
            s.instances.write(0, bytemuck::cast_slice(&objects))?;
        }
        s.view = view;
        Ok(())
    }

    /// Draw calls recorded for slot `slot`'s camera (instanced draws count once), and the
    /// objects they draw.
    pub fn draw_calls(&self, slot: usize) -> (usize, usize) {
        let s = &self.slots[slot.min(self.slots.len() - 1)];
        let runs = self.runs(&s.view.order, &s.view.levels);
        (runs.len(), s.view.order.len())
    }
}
