//! Compiling a declared graph into a [`Plan`]: validation, culling and barrier derivation, all as
//! plain data (no Vulkan calls).
//!
//! State is tracked per subresource cell (one mip of one layer; a buffer is one cell). Each cell
//! remembers its layout, the last write (stages and write accesses, or a layout transition), the
//! stages that read it since, and the (stages, accesses) the last write was already made visible
//! to. A use then needs:
//! - a read in the same layout: nothing if no write is pending or the write is already visible
//!   to that (stages, accesses) (read after read); otherwise a barrier from the write (RAW);
//! - a write or a layout change: a barrier whose source is the last write plus every reading
//!   stage since (WAW, WAR, transitions).

use std::collections::{BTreeMap, HashSet};

use ash::vk;

use crate::access::{Access, AppliesTo, MemoryBarrier, WRITE_ACCESS};
use crate::error::GraphError;
use crate::exec::CompiledGraph;
use crate::graph::{resource_name, BufferEntry, FrameGraph, ImageEntry};
use crate::plan::{BarrierInfo, BufferInfo, ImageInfo, PassPlan, Plan};
use crate::resource::{
    ImageHandle, ImageSource, ImageStateBefore, ImportedImage, Resource, SubresourceRange, Use,
    UseMode,
};

/// A barrier's content, before merging cells into ranges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Key {
    old: vk::ImageLayout,
    new: vk::ImageLayout,
    scopes: MemoryBarrier,
    pool: bool,
}

/// The tracked state of one subresource cell.
#[derive(Clone, Debug)]
struct Cell {
    layout: vk::ImageLayout,
    /// The last write (or layout transition): its stages and write accesses.
    write: Option<(vk::PipelineStageFlags2, vk::AccessFlags2)>,
    /// Stages that read since the last write.
    readers: vk::PipelineStageFlags2,
    /// (stages, accesses) the last write has been made visible to.
    visible: Vec<(vk::PipelineStageFlags2, vk::AccessFlags2)>,
    /// A transient cell not touched yet this frame (its pooled image's last use is the source).
    fresh: bool,
}

impl Cell {
    fn empty(layout: vk::ImageLayout) -> Self {
        Cell {
            layout,
            write: None,
            readers: vk::PipelineStageFlags2::NONE,
            visible: Vec::new(),
            fresh: false,
        }
    }

    /// The state after `last`: pending write if it wrote, reading stages otherwise.
    fn after(layout: vk::ImageLayout, last: Access) -> Self {
        let mut c = Cell::empty(layout);
        if last.writes() {
            c.write = Some((last.stages(), last.access() & WRITE_ACCESS));
        } else {
            c.readers = last.stages();
        }
        c
    }

    /// The source scope a later write must wait for.
    fn scope(&self) -> (vk::PipelineStageFlags2, vk::AccessFlags2) {
        let (ws, wa) = self.write.unwrap_or_default();
        (ws | self.readers, wa)
    }
}

/// The merged use of one cell by one pass.
#[derive(Clone, Copy, Debug)]
struct Merged {
    layout: vk::ImageLayout,
    stages: vk::PipelineStageFlags2,
    access: vk::AccessFlags2,
    writes: bool,
    name: &'static str,
}

/// Updates `cell` for the use `m`, returning the barrier it needs.
fn apply(cell: &mut Cell, m: &Merged) -> Option<Key> {
    let layout_change = cell.layout != m.layout;
    if !m.writes && !layout_change {
        let covered = cell.write.is_none()
            || cell
                .visible
                .iter()
                .any(|&(s, a)| s.contains(m.stages) && a.contains(m.access));
        cell.readers |= m.stages;
        if covered {
            return None;
        }
        let (ws, wa) = cell.write.unwrap_or_default();
        cell.visible.push((m.stages, m.access));
        return Some(Key {
            old: cell.layout,
            new: m.layout,
            scopes: MemoryBarrier {
                src_stages: ws,
                src_access: wa,
                dst_stages: m.stages,
                dst_access: m.access,
            },
            pool: false,
        });
    }
    let (src_stages, src_access) = cell.scope();
    let key = if src_stages.is_empty() && !layout_change && !cell.fresh {
        None
    } else {
        Some(Key {
            old: cell.layout,
            new: m.layout,
            scopes: MemoryBarrier {
                src_stages,
                src_access,
                dst_stages: m.stages,
                dst_access: m.access,
            },
            pool: cell.fresh,
        })
    };
    cell.fresh = false;
    cell.layout = m.layout;
    if m.writes {
        cell.write = Some((m.stages, m.access & WRITE_ACCESS));
        cell.readers = vk::PipelineStageFlags2::NONE;
        cell.visible.clear();
    } else {
        // A read with a layout transition: the transition is the last "write", visible to this
        // use's scope.
        cell.write = Some((m.stages, vk::AccessFlags2::NONE));
        cell.readers = m.stages;
        cell.visible = vec![(m.stages, m.access)];
    }
    key
}

/// The cells (mip * layers + layer) of a range.
fn cells_of(range: Option<SubresourceRange>, dims: (u32, u32)) -> Vec<u32> {
    let r = range.unwrap_or(SubresourceRange::whole(dims.0, dims.1));
    let mut out = Vec::new();
    for m in r.base_mip..r.base_mip + r.mip_count {
        for l in r.base_layer..r.base_layer + r.layer_count {
            out.push(m * dims.1 + l);
        }
    }
    out
}

/// Merges per-cell barriers of one image into rectangles of mips x layers.
fn coalesce(cells: &[(u32, Key)], dims: (u32, u32)) -> Vec<(SubresourceRange, Key)> {
    let layers = dims.1;
    // Runs of consecutive layers within a mip.
    let mut runs: Vec<(u32, u32, u32, Key)> = Vec::new(); // mip, base layer, count, key
    for &(c, k) in cells {
        let (m, l) = (c / layers, c % layers);
        if let Some(last) = runs.last_mut() {
            if last.0 == m && last.1 + last.2 == l && last.3 == k {
                last.2 += 1;
                continue;
            }
        }
        runs.push((m, l, 1, k));
    }
    let mut rects: Vec<(SubresourceRange, Key)> = Vec::new();
    for (m, l, n, k) in runs {
        if let Some(r) = rects.iter_mut().find(|(r, rk)| {
            *rk == k && r.base_layer == l && r.layer_count == n && r.base_mip + r.mip_count == m
        }) {
            r.0.mip_count += 1;
        } else {
            rects.push((SubresourceRange::new(m, 1, l, n), k));
        }
    }
    rects
}

fn info(name: &str, handle: Resource, range: Option<SubresourceRange>, k: Key) -> BarrierInfo {
    BarrierInfo {
        resource: name.to_string(),
        handle,
        old_layout: k.old,
        new_layout: k.new,
        scopes: k.scopes,
        range,
        after_pool_use: k.pool,
    }
}

/// Validates one declaration.
fn validate(
    pass: &'static str,
    u: &Use,
    images: &[ImageEntry],
    buffers: &[BufferEntry],
) -> Result<(), GraphError> {
    let Some(name) = resource_name(images, buffers, u.resource) else {
        return Err(GraphError::InvalidHandle {
            pass,
            handle: format!("{:?}", u.resource),
        });
    };
    let invalid = |reason: String| GraphError::InvalidUse {
        pass,
        resource: name.clone(),
        reason,
    };
    let a = u.access.info();
    match (u.mode, a.writes) {
        (UseMode::Read, true) => {
            return Err(invalid(format!(
                "{} writes; declare it with write or read_write",
                a.name
            )))
        }
        (UseMode::Write | UseMode::ReadWrite, false) => {
            return Err(invalid(format!(
                "{} does not write; declare it with read",
                a.name
            )))
        }
        _ => {}
    }
    match (u.resource, a.applies_to) {
        (Resource::Image(_), AppliesTo::Buffer) => {
            return Err(invalid(format!("{} is a buffer access", a.name)))
        }
        (Resource::Buffer(_), AppliesTo::Image) => {
            return Err(invalid(format!("{} is an image access", a.name)))
        }
        _ => {}
    }
    if let (Resource::Image(h), Some(r)) = (u.resource, u.range) {
        let (mips, layers) = images[h.index()].dims();
        if r.mip_count == 0
            || r.layer_count == 0
            || r.base_mip + r.mip_count > mips
            || r.base_layer + r.layer_count > layers
        {
            return Err(invalid(format!(
                "range {r:?} is outside its {mips} mips x {layers} layers"
            )));
        }
    }
    Ok(())
}

/// The cells a use touches.
fn use_cells(u: &Use, dims: &[(u32, u32)]) -> Vec<u32> {
    match u.resource {
        Resource::Image(h) => cells_of(u.range, dims[h.index()]),
        Resource::Buffer(_) => vec![0],
    }
}

/// Every cell of the imported images `keep` selects.
fn imported_cells(
    images: &[ImageEntry],
    dims: &[(u32, u32)],
    keep: impl Fn(&ImportedImage) -> bool,
) -> HashSet<(Resource, u32)> {
    let mut cells = HashSet::new();
    for (i, im) in images.iter().enumerate() {
        if let ImageSource::Imported(imp) = &im.source {
            if keep(imp) {
                for c in cells_of(None, dims[i]) {
                    cells.insert((Resource::Image(ImageHandle(i as u32)), c));
                }
            }
        }
    }
    cells
}

impl<'a> FrameGraph<'a> {
    /// Checks the declarations, culls passes nobody needs and derives every barrier.
    pub fn compile(self) -> Result<CompiledGraph<'a>, GraphError> {
        compile(self)
    }
}

pub(crate) fn compile(graph: FrameGraph<'_>) -> Result<CompiledGraph<'_>, GraphError> {
    let FrameGraph {
        images,
        buffers,
        passes,
    } = graph;
    for p in &passes {
        for u in &p.uses {
            validate(p.name, u, &images, &buffers)?;
        }
    }
    let dims: Vec<(u32, u32)> = images.iter().map(ImageEntry::dims).collect();

    // Per pass: the merged use of every cell, resources in order of first declaration.
    let mut merged: Vec<Vec<(Resource, BTreeMap<u32, Merged>)>> = Vec::new();
    for p in &passes {
        let mut per: Vec<(Resource, BTreeMap<u32, Merged>)> = Vec::new();
        for u in &p.uses {
            let a = u.access.info();
            let layout = match u.resource {
                Resource::Image(_) => a.layout,
                Resource::Buffer(_) => vk::ImageLayout::UNDEFINED,
            };
            let idx = match per.iter().position(|(r, _)| *r == u.resource) {
                Some(i) => i,
                None => {
                    per.push((u.resource, BTreeMap::new()));
                    per.len() - 1
                }
            };
            for c in use_cells(u, &dims) {
                let m = per[idx].1.entry(c).or_insert(Merged {
                    layout,
                    stages: vk::PipelineStageFlags2::NONE,
                    access: vk::AccessFlags2::NONE,
                    writes: false,
                    name: a.name,
                });
                if m.layout != layout {
                    return Err(GraphError::ConflictingAccess {
                        pass: p.name,
                        resource: resource_name(&images, &buffers, u.resource).unwrap_or_default(),
                        first: m.name,
                        second: a.name,
                    });
                }
                m.stages |= a.stages;
                m.access |= a.access;
                m.writes |= a.writes;
            }
        }
        merged.push(per);
    }

    // Reads must follow a write (or imported contents), in declaration order.
    let mut defined = imported_cells(&images, &dims, |imp| imp.before.defined());
    for (i, _) in buffers.iter().enumerate() {
        // Buffers are always imported; their contents are the caller's.
        defined.insert((Resource::Buffer(crate::resource::BufferHandle(i as u32)), 0));
    }
    for p in &passes {
        for u in p.uses.iter().filter(|u| u.mode.reads()) {
            if use_cells(u, &dims)
                .iter()
                .any(|&c| !defined.contains(&(u.resource, c)))
            {
                return Err(GraphError::ReadBeforeWrite {
                    pass: p.name,
                    resource: resource_name(&images, &buffers, u.resource).unwrap_or_default(),
                });
            }
        }
        for u in p.uses.iter().filter(|u| u.mode.writes()) {
            for c in use_cells(u, &dims) {
                defined.insert((u.resource, c));
            }
        }
    }

    // Culling: walk backwards keeping the set of cells whose current contents are needed.
    let mut needed = imported_cells(&images, &dims, |imp| imp.after.is_some());
    for (i, b) in buffers.iter().enumerate() {
        if b.after.is_some() {
            needed.insert((Resource::Buffer(crate::resource::BufferHandle(i as u32)), 0));
        }
    }
    let mut live = vec![false; passes.len()];
    for (pi, p) in passes.iter().enumerate().rev() {
        let writes_needed = p.uses.iter().filter(|u| u.mode.writes()).any(|u| {
            use_cells(u, &dims)
                .iter()
                .any(|&c| needed.contains(&(u.resource, c)))
        });
        if !(p.side_effect || writes_needed) {
            continue;
        }
        live[pi] = true;
        for u in p.uses.iter().filter(|u| u.mode.writes()) {
            for c in use_cells(u, &dims) {
                needed.remove(&(u.resource, c));
            }
        }
        for u in p.uses.iter().filter(|u| u.mode.reads()) {
            for c in use_cells(u, &dims) {
                needed.insert((u.resource, c));
            }
        }
    }

    // Barriers over the live passes.
    let mut image_cells: Vec<Vec<Cell>> = images
        .iter()
        .enumerate()
        .map(|(i, im)| {
            let n = (dims[i].0 * dims[i].1) as usize;
            let cell = match &im.source {
                ImageSource::Transient => Cell {
                    fresh: true,
                    ..Cell::empty(vk::ImageLayout::UNDEFINED)
                },
                ImageSource::Imported(imp) => match imp.before {
                    ImageStateBefore::Undefined => Cell::empty(vk::ImageLayout::UNDEFINED),
                    ImageStateBefore::Discard(a) => Cell::after(vk::ImageLayout::UNDEFINED, a),
                    ImageStateBefore::Keep(a) => Cell::after(a.layout(), a),
                },
            };
            vec![cell; n]
        })
        .collect();
    let mut buffer_cells: Vec<Cell> = buffers
        .iter()
        .map(|b| match b.before {
            Some(a) => Cell::after(vk::ImageLayout::UNDEFINED, a),
            None => Cell::empty(vk::ImageLayout::UNDEFINED),
        })
        .collect();
    let mut image_life: Vec<Option<(usize, usize)>> = vec![None; images.len()];
    let mut buffer_life: Vec<Option<(usize, usize)>> = vec![None; buffers.len()];
    let extend = |life: &mut Option<(usize, usize)>, pi: usize| {
        *life = Some(match *life {
            Some((a, _)) => (a, pi),
            None => (pi, pi),
        });
    };

    let name_of = |r: Resource| resource_name(&images, &buffers, r).unwrap_or_default();
    let mut plans = Vec::with_capacity(passes.len());
    for (pi, p) in passes.iter().enumerate() {
        let mut barriers = Vec::new();
        if live[pi] {
            for (r, cells) in &merged[pi] {
                match *r {
                    Resource::Image(h) => {
                        extend(&mut image_life[h.index()], pi);
                        let state = &mut image_cells[h.index()];
                        let keyed: Vec<(u32, Key)> = cells
                            .iter()
                            .filter_map(|(&c, m)| apply(&mut state[c as usize], m).map(|k| (c, k)))
                            .collect();
                        for (range, k) in coalesce(&keyed, dims[h.index()]) {
                            barriers.push(info(&name_of(*r), *r, Some(range), k));
                        }
                    }
                    Resource::Buffer(h) => {
                        extend(&mut buffer_life[h.index()], pi);
                        if let Some(k) = apply(&mut buffer_cells[h.index()], &cells[&0]) {
                            barriers.push(info(&name_of(*r), *r, None, k));
                        }
                    }
                }
            }
        }
        plans.push(PassPlan {
            name: p.name,
            live: live[pi],
            side_effect: p.side_effect,
            uses: p.uses.clone(),
            barriers,
        });
    }

    // Final states of imported resources.
    let mut final_barriers = Vec::new();
    for (i, im) in images.iter().enumerate() {
        let ImageSource::Imported(imp) = &im.source else {
            continue;
        };
        let Some(after) = imp.after else { continue };
        let a = after.info();
        let m = Merged {
            layout: a.layout,
            stages: a.stages,
            access: a.access,
            writes: a.writes,
            name: a.name,
        };
        let keyed: Vec<(u32, Key)> = image_cells[i]
            .iter_mut()
            .enumerate()
            .filter_map(|(c, cell)| apply(cell, &m).map(|k| (c as u32, k)))
            .collect();
        let r = Resource::Image(ImageHandle(i as u32));
        for (range, k) in coalesce(&keyed, dims[i]) {
            final_barriers.push(info(&im.name, r, Some(range), k));
        }
    }
    for (i, b) in buffers.iter().enumerate() {
        let Some(after) = b.after else { continue };
        let a = after.info();
        let m = Merged {
            layout: vk::ImageLayout::UNDEFINED,
            stages: a.stages,
            access: a.access,
            writes: a.writes,
            name: a.name,
        };
        if let Some(k) = apply(&mut buffer_cells[i], &m) {
            let r = Resource::Buffer(crate::resource::BufferHandle(i as u32));
            final_barriers.push(info(&b.name, r, None, k));
        }
    }

    // Image infos: transients get the usage their accesses need.
    let mut usage = vec![vk::ImageUsageFlags::empty(); images.len()];
    for p in &passes {
        for u in &p.uses {
            if let Resource::Image(h) = u.resource {
                usage[h.index()] |= u.access.image_usage();
            }
        }
    }
    let image_infos = images
        .iter()
        .enumerate()
        .map(|(i, im)| {
            let imported = matches!(im.source, ImageSource::Imported(_));
            let mut desc = im.desc;
            if !imported {
                desc.usage |= usage[i];
            }
            let mut scope = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
            let mut includes_previous = false;
            for c in &image_cells[i] {
                if c.fresh {
                    includes_previous = true;
                } else {
                    let (s, a) = c.scope();
                    scope.0 |= s;
                    scope.1 |= a;
                }
            }
            let first = image_cells[i][0].layout;
            let end_layout = image_cells[i]
                .iter()
                .all(|c| c.layout == first)
                .then_some(first);
            ImageInfo {
                end_layout,
                name: im.name.clone(),
                desc,
                imported,
                after: match &im.source {
                    ImageSource::Imported(imp) => imp.after,
                    ImageSource::Transient => None,
                },
                lifetime: image_life[i],
                final_scope: scope,
                final_includes_previous: includes_previous,
                source: im.source,
                dims: dims[i],
            }
        })
        .collect();
    let buffer_infos = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| BufferInfo {
            name: b.name.clone(),
            buffer: b.buffer,
            size: b.size,
            after: b.after,
            lifetime: buffer_life[i],
        })
        .collect();
    let records = passes
        .into_iter()
        .enumerate()
        .map(|(i, p)| if live[i] { p.record } else { None })
        .collect();
    Ok(CompiledGraph {
        plan: Plan {
            images: image_infos,
            buffers: buffer_infos,
            passes: plans,
            final_barriers,
        },
        records,
    })
}
