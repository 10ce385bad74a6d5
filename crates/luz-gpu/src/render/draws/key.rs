//! The packed 64-bit sort key of a draw command (Filament's `RenderPass` command key is the
//! model): the fields a pass wants its draws grouped by, most significant first, so that one
//! integer sort puts every view's commands in recording order. Ties keep the list's order (the
//! sorts are stable), which is the scene's object order.
//!
//! Colour views (forward, G-buffer):
//!
//! | bits  | opaque and masked                   | blended                           |
//! |-------|-------------------------------------|-----------------------------------|
//! | 63–62 | phase 0                             | phase 2 (after the skybox)        |
//! | 61–52 | pipeline (rank of the variant)      | view depth, farthest first (32)   |
//! | 51–34 | material                            |                                   |
//! | 33    | back faces culled                   |                                   |
//! | 32–11 | mesh                                |                                   |
//! | 10–6  | LOD level                           |                                   |
//!
//! Transmissive draws (glass, issue 35) are phase 1: after the opaque ones and the skybox,
//! which they read a copy of, nearest first (bits 61–30, view depth), before the blended ones.
//!
//! Depth-only views (each shadow layer): phase 0 opaque casters (the vertex-only pipeline),
//! phase 1 alpha-tested ones grouped by material (bits 61–44), then the depth along the view's
//! axis, nearest first (bits 43–12), so that the depth test rejects what lies behind.
//!
//! A value too large for its field is clamped to the field's largest: the draws keep their
//! phase and near order, only the grouping of the very largest indices gets coarser.

/// A command's sort key.
pub type Key = u64;

/// Opaque (and alpha-masked) colour draws, and opaque shadow casters.
pub const PHASE_OPAQUE: u64 = 0;
/// Alpha-tested shadow casters (depth views).
pub const PHASE_SECOND: u64 = 1;
/// Transmissive colour draws (front to back, after the skybox and the copy of the scene).
pub const PHASE_TRANSMISSIVE: u64 = 1;
/// Blended colour draws (back to front, after the transmissive ones).
pub const PHASE_BLENDED: u64 = 2;

/// Packs `fields` (value, width in bits), most significant first, below the two phase bits.
fn pack(phase: u64, fields: &[(u64, u32)]) -> Key {
    let mut key = phase << 62;
    let mut shift = 62;
    for &(value, bits) in fields {
        shift -= bits;
        let max = (1u64 << bits) - 1;
        key |= value.min(max) << shift;
    }
    key
}

/// The bits of `v` as an unsigned integer in `f32::total_cmp` order.
pub fn ordered(v: f32) -> u32 {
    let b = v.to_bits();
    if b >> 31 == 1 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// An opaque or masked colour draw: grouped by pipeline, material, culling, mesh and LOD level,
/// so that draws one instanced draw can record are adjacent (the depth test makes their order
/// immaterial to the image).
pub fn opaque(pipeline: u32, material: usize, cull: bool, mesh: usize, level: u8) -> Key {
    pack(
        PHASE_OPAQUE,
        &[
            (pipeline.into(), 10),
            (material as u64, 18),
            (cull.into(), 1),
            (mesh as u64, 22),
            (level.into(), 5),
        ],
    )
}

/// A blended colour draw at view depth `depth` (of its bounding sphere's centre): back to
/// front, after every opaque draw.
pub fn blended(depth: f32) -> Key {
    pack(PHASE_BLENDED, &[(u64::from(!ordered(depth)), 32)])
}

/// A transmissive colour draw at view depth `depth`: front to back, after every opaque draw and
/// before the blended ones.
pub fn transmissive(depth: f32) -> Key {
    pack(PHASE_TRANSMISSIVE, &[(u64::from(ordered(depth)), 32)])
}

/// A shadow caster at `depth` along the layer's axis: opaque casters first, front to back; then
/// alpha-tested ones (`material`), grouped by material, each group front to back.
pub fn depth(alpha_material: Option<usize>, depth: f32) -> Key {
    match alpha_material {
        None => pack(PHASE_OPAQUE, &[(0, 18), (ordered(depth).into(), 32)]),
        Some(m) => pack(PHASE_SECOND, &[(m as u64, 18), (ordered(depth).into(), 32)]),
    }
}

/// The phase of `key`.
pub fn phase(key: Key) -> u64 {
    key >> 62
}

/// Where the second phase (a colour view's transmissive draws, then its blended ones) starts in
/// sorted `keys`.
pub fn second_phase(keys: &[Key]) -> usize {
    keys.partition_point(|&k| phase(k) == PHASE_OPAQUE)
}

/// Where a colour view's blended draws start in sorted `keys` (the transmissive ones are
/// `second_phase(keys)..blended_phase(keys)`).
pub fn blended_phase(keys: &[Key]) -> usize {
    keys.partition_point(|&k| phase(k) < PHASE_BLENDED)
}
