//! A self-contained SVG drawing of a plan (no Graphviz): passes as a column of boxes in execution
//! order, resources as ellipses in a column to the right placed at their first use, edges as
//! lines labelled with the access kind.

use std::fmt::Write;

use crate::dot::{image_label, time_of};
use crate::plan::Plan;
use crate::resource::Resource;
use crate::resource::UseMode;

/// Escapes text for XML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

const ROW: f64 = 70.0;
const PASS_X: f64 = 20.0;
const PASS_W: f64 = 220.0;
const PASS_H: f64 = 44.0;
const RES_CX: f64 = 640.0;
const RES_RX: f64 = 150.0;
const RES_RY: f64 = 26.0;
const TOP: f64 = 20.0;

impl Plan {
    /// The graph as a standalone SVG document (see the module docs); `times` adds GPU ms.
    pub fn to_svg(&self, times: &[(&str, f64)]) -> String {
        // Resources in order of first use, each at the row of that use or below the previous.
        let mut order: Vec<(Resource, usize)> = Vec::new();
        for (pi, p) in self.passes.iter().enumerate() {
            for u in &p.uses {
                if !order.iter().any(|(r, _)| *r == u.resource) {
                    order.push((u.resource, pi));
                }
            }
        }
        for i in 0..self.images.len() {
            let r = Resource::Image(crate::resource::ImageHandle(i as u32));
            if !order.iter().any(|(x, _)| *x == r) {
                order.push((r, self.passes.len()));
            }
        }
        for i in 0..self.buffers.len() {
            let r = Resource::Buffer(crate::resource::BufferHandle(i as u32));
            if !order.iter().any(|(x, _)| *x == r) {
                order.push((r, self.passes.len()));
            }
        }
        let pass_y = |pi: usize| TOP + pi as f64 * ROW;
        let mut res_y: Vec<(Resource, f64)> = Vec::new();
        let mut next = TOP;
        for (r, pi) in &order {
            let y = pass_y(*pi).max(next);
            res_y.push((*r, y));
            next = y + ROW;
        }
        let height = next.max(pass_y(self.passes.len())) + TOP;
        let width = RES_CX + RES_RX + 30.0;

        let mut s = String::new();
        let _ = writeln!(
            s,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\" font-family=\"Helvetica, Arial, sans-serif\">"
        );
        s.push_str("<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"10\" refY=\"5\" markerWidth=\"6\" markerHeight=\"6\" orient=\"auto-start-reverse\"><path d=\"M 0 0 L 10 5 L 0 10 z\" fill=\"#555\"/></marker></defs>\n");
        let _ = writeln!(
            s,
            "<rect x=\"0\" y=\"0\" width=\"{width}\" height=\"{height}\" fill=\"white\"/>"
        );

        // Edges first, under the nodes.
        for (pi, p) in self.passes.iter().enumerate() {
            let py = pass_y(pi) + PASS_H / 2.0;
            let px = PASS_X + PASS_W;
            for (k, u) in p.uses.iter().enumerate() {
                let Some(&(_, ry)) = res_y.iter().find(|(r, _)| *r == u.resource) else {
                    continue;
                };
                let ry = ry + RES_RY;
                let rx = RES_CX - RES_RX;
                let colour = match (p.live, u.mode) {
                    (false, _) => "#bbb",
                    (true, UseMode::Read) => "#2a6fdb",
                    (true, UseMode::Write) => "#d0402b",
                    (true, UseMode::ReadWrite) => "#8a3fc0",
                };
                let (x1, y1, x2, y2, markers) = match u.mode {
                    UseMode::Read => (rx, ry, px, py, "marker-end=\"url(#arrow)\""),
                    UseMode::Write => (px, py, rx, ry, "marker-end=\"url(#arrow)\""),
                    UseMode::ReadWrite => (
                        px,
                        py,
                        rx,
                        ry,
                        "marker-start=\"url(#arrow)\" marker-end=\"url(#arrow)\"",
                    ),
                };
                let dash = if p.live {
                    ""
                } else {
                    " stroke-dasharray=\"4 3\""
                };
                let _ = writeln!(
                    s,
                    "<line x1=\"{x1:.1}\" y1=\"{y1:.1}\" x2=\"{x2:.1}\" y2=\"{y2:.1}\" stroke=\"{colour}\" stroke-width=\"1.2\"{dash} {markers}/>"
                );
                // Labels spread along the edge so a pass's labels don't sit on each other.
                let t = 0.3 + 0.4 * ((k % 4) as f64 / 3.0);
                let (lx, ly) = (px + (rx - px) * t, py + (ry - py) * t - 3.0);
                let _ = writeln!(
                    s,
                    "<text x=\"{lx:.1}\" y=\"{ly:.1}\" font-size=\"9\" fill=\"{colour}\" text-anchor=\"middle\">{}</text>",
                    esc(u.access.name())
                );
            }
        }

        for (pi, p) in self.passes.iter().enumerate() {
            let y = pass_y(pi);
            let (stroke, fill, text, dash) = if p.live {
                ("#333", "#f4f4f4", "#000", "")
            } else {
                ("#aaa", "#fafafa", "#999", " stroke-dasharray=\"5 3\"")
            };
            let width = if p.side_effect { 2.5 } else { 1.2 };
            let _ = writeln!(
                s,
                "<rect x=\"{PASS_X}\" y=\"{y}\" width=\"{PASS_W}\" height=\"{PASS_H}\" rx=\"4\" fill=\"{fill}\" stroke=\"{stroke}\" stroke-width=\"{width}\"{dash}/>"
            );
            let mut sub = match time_of(times, p.name) {
                Some(t) => format!("{t:.3} ms"),
                None => String::new(),
            };
            if !p.live {
                sub = "culled".to_string();
            }
            let _ = writeln!(
                s,
                "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"13\" fill=\"{text}\" text-anchor=\"middle\">{}</text>",
                PASS_X + PASS_W / 2.0,
                y + 19.0,
                esc(p.name)
            );
            if !sub.is_empty() {
                let _ = writeln!(
                    s,
                    "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"10\" fill=\"{text}\" text-anchor=\"middle\">{}</text>",
                    PASS_X + PASS_W / 2.0,
                    y + 35.0,
                    esc(&sub)
                );
            }
        }

        for (r, y) in &res_y {
            let (name, detail, imported) = match *r {
                Resource::Image(h) => {
                    let im = &self.images[h.index()];
                    (im.name.clone(), image_label(im), im.imported)
                }
                Resource::Buffer(h) => {
                    let b = &self.buffers[h.index()];
                    (b.name.clone(), format!("{} bytes", b.size), true)
                }
            };
            let (fill, dash, kind) = if imported {
                ("#dcebfa", "", "imported")
            } else {
                ("#ffffff", " stroke-dasharray=\"5 3\"", "transient")
            };
            let cy = y + RES_RY;
            let _ = writeln!(
                s,
                "<ellipse cx=\"{RES_CX}\" cy=\"{cy}\" rx=\"{RES_RX}\" ry=\"{RES_RY}\" fill=\"{fill}\" stroke=\"#333\"{dash}/>"
            );
            let _ = writeln!(
                s,
                "<text x=\"{RES_CX}\" y=\"{:.1}\" font-size=\"12\" text-anchor=\"middle\">{}</text>",
                cy - 4.0,
                esc(&name)
            );
            let _ = writeln!(
                s,
                "<text x=\"{RES_CX}\" y=\"{:.1}\" font-size=\"9\" fill=\"#555\" text-anchor=\"middle\">{} ({kind})</text>",
                cy + 10.0,
                esc(&detail)
            );
        }
        s.push_str("</svg>\n");
        s
    }
}
