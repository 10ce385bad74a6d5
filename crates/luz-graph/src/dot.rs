//! Graphviz DOT output of a plan.

use std::fmt::Write;

use crate::exec::CompiledGraph;
use crate::plan::{ImageInfo, Plan};
use crate::resource::Resource;
use crate::resource::UseMode;

/// Escapes a string for a DOT quoted label.
fn esc(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

/// "1920x1080 R16G16B16A16_SFLOAT, 6 layers, 5 mips".
pub(crate) fn image_label(im: &ImageInfo) -> String {
    let d = &im.desc;
    let mut s = format!("{}x{} {:?}", d.width, d.height, d.format);
    if d.layers > 1 {
        let _ = write!(s, ", {} layers", d.layers);
    }
    if d.mip_levels > 1 {
        let _ = write!(s, ", {} mips", d.mip_levels);
    }
    s
}

/// The GPU time of pass `name` in `times`, if any.
pub(crate) fn time_of(times: &[(&str, f64)], name: &str) -> Option<f64> {
    times.iter().find(|(n, _)| *n == name).map(|&(_, t)| t)
}

pub(crate) fn node_id(r: Resource) -> String {
    match r {
        Resource::Image(h) => format!("i{}", h.index()),
        Resource::Buffer(h) => format!("b{}", h.index()),
    }
}

impl Plan {
    /// The graph as Graphviz DOT: passes as boxes (with GPU ms from `times`, culled ones dashed
    /// and grey), resources as ellipses (imported filled, transients dashed), edges labelled with
    /// the access kind.
    pub fn to_dot(&self, times: &[(&str, f64)]) -> String {
        let mut s = String::new();
        s.push_str("digraph frame {\n  rankdir=LR;\n  node [fontname=\"Helvetica\", fontsize=10];\n  edge [fontname=\"Helvetica\", fontsize=8];\n");
        for (i, p) in self.passes.iter().enumerate() {
            let mut label = esc(p.name);
            if let Some(t) = time_of(times, p.name) {
                let _ = write!(label, "\\n{t:.3} ms");
            }
            let style = if p.live {
                if p.side_effect {
                    "shape=box, style=\"bold\""
                } else {
                    "shape=box"
                }
            } else {
                "shape=box, style=\"dashed\", color=grey60, fontcolor=grey60"
            };
            let culled = if p.live { "" } else { "\\n(culled)" };
            let _ = writeln!(s, "  p{i} [label=\"{label}{culled}\", {style}];");
        }
        for (i, im) in self.images.iter().enumerate() {
            let style = if im.imported {
                "shape=ellipse, style=filled, fillcolor=lightblue"
            } else {
                "shape=ellipse, style=dashed"
            };
            let kind = if im.imported { "imported" } else { "transient" };
            let _ = writeln!(
                s,
                "  i{i} [label=\"{}\\n{}\\n{kind}\", {style}];",
                esc(&im.name),
                esc(&image_label(im))
            );
        }
        for (i, b) in self.buffers.iter().enumerate() {
            let _ = writeln!(
                s,
                "  b{i} [label=\"{}\\n{} bytes\\nimported buffer\", shape=ellipse, style=filled, fillcolor=lightyellow];",
                esc(&b.name),
                b.size
            );
        }
        for (i, p) in self.passes.iter().enumerate() {
            let grey = if p.live { "" } else { ", color=grey60" };
            for u in &p.uses {
                let r = node_id(u.resource);
                let label = esc(u.access.name());
                match u.mode {
                    UseMode::Read => {
                        let _ = writeln!(s, "  {r} -> p{i} [label=\"{label}\"{grey}];");
                    }
                    UseMode::Write => {
                        let _ = writeln!(s, "  p{i} -> {r} [label=\"{label}\"{grey}];");
                    }
                    UseMode::ReadWrite => {
                        let _ = writeln!(s, "  p{i} -> {r} [label=\"{label}\", dir=both{grey}];");
                    }
                }
            }
        }
        s.push_str("}\n");
        s
    }
}

impl CompiledGraph<'_> {
    /// See [`Plan::to_dot`].
    pub fn to_dot(&self, times: &[(&str, f64)]) -> String {
        self.plan.to_dot(times)
    }

    /// See [`Plan::to_svg`].
    pub fn to_svg(&self, times: &[(&str, f64)]) -> String {
        self.plan.to_svg(times)
    }
}
