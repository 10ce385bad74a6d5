//! Instancing: draws next to each other in a slot's order that share mesh, LOD level, pipeline
//! variant, material, face culling and push constants (all but the object slot) are recorded as
//! one instanced draw. The slot's instance buffer (`BINDING_INSTANCES`) holds the object of each
//! entry of the order; an instanced draw starts at its first entry (`firstInstance`), and the
//! vertex stage reads `objects[instances[gl_InstanceIndex]]`. The fragment stages need nothing per
//! object beyond the material, which the instances share; the deferred path's G-buffer names the
//! first instance's material slot, whose data every instance's slot repeats.

use super::{gpu::MaterialPush, Draw, ForwardPass};
use crate::vk::VkError;

/// Whether `b` (at LOD level `lb`) can be another instance of the draw recording `a` (at `la`).
fn same_draw((a, la): (&Draw, u8), (b, lb): (&Draw, u8)) -> bool {
    let material = |d: &Draw| MaterialPush {
        object_index: 0,
        ..d.push
    };
    a.mesh == b.mesh
        && la == lb
        && a.shadow_area.is_none()
        && b.shadow_area.is_none()
        && a.variant == b.variant
        && a.material == b.material
        && a.cull == b.cull
        && material(a) == material(b)
}

/// The draws to record for `order` (draw indices, `levels` by draw): runs `(start, count)` of
/// `order`, each one instanced draw; one run per entry when `instancing` is off.
pub(super) fn runs(
    draws: &[Draw],
    (order, levels): (&[usize], &[u8]),
    instancing: bool,
) -> Vec<(usize, usize)> {
    let level = |i: usize| levels.get(i).copied().unwrap_or(0);
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        match runs.last_mut() {
            Some((start, count))
                if instancing
                    && same_draw(
                        (&draws[order[*start]], level(order[*start])),
                        (&draws[i], level(i)),
                    ) =>
            {
                *count += 1
            }
            _ => runs.push((k, 1)),
        }
    }
    runs
}

impl ForwardPass {
    /// Sets slot `slot`'s draw order and LOD levels and writes the object of each entry of the
    /// order into its instance buffer.
    pub(super) fn set_order(
        &mut self,
        slot: usize,
        order: Vec<usize>,
        levels: Vec<u8>,
    ) -> Result<(), VkError> {
        let objects: Vec<u32> = order
            .iter()
            .map(|&i| self.draws[i].push.object_index)
            .collect();
        let s = &mut self.slots[slot];
        if !objects.is_empty() {
            s.instances.write(0, bytemuck::cast_slice(&objects))?;
        }
        s.order = order;
        s.levels = levels;
        Ok(())
    }

    /// Draw calls recorded for slot `slot`'s camera (instanced draws count once), and the
    /// objects they draw.
    pub fn draw_calls(&self, slot: usize) -> (usize, usize) {
        let s = &self.slots[slot.min(self.slots.len() - 1)];
        let runs = runs(&self.draws, (&s.order, &s.levels), self.instancing);
        (runs.len(), s.order.len())
    }
}
