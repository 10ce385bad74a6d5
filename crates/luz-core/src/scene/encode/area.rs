//! Area lights (issue 36) as the decoder reads them: every field explicitly.

use super::fields::shadow;
use super::node::{unit_preimage, Node};
use crate::scene::{AreaLight, AreaMethod, AreaShape, LightKind};

pub(super) fn area_light(l: &AreaLight) -> Node {
    let mut n = Node::obj();
    n.put("type", l.shape.name()).put("position", l.position);
    match l.shape {
        AreaShape::Rect { up, width, height } => {
            n.put("direction", unit_preimage(l.direction))
                .put("up", unit_preimage(up))
                .put("size", Node::Arr(vec![width.into(), height.into()]));
        }
        AreaShape::Disk { radius } => {
            n.put("direction", unit_preimage(l.direction))
                .put("radius", radius);
        }
        AreaShape::Sphere { radius } => {
            n.put("radius", radius);
        }
        AreaShape::Tube { length, radius } => {
            n.put("direction", unit_preimage(l.direction))
                .put("length", length)
                .put("radius", radius);
        }
    }
    n.put("color", l.color)
        .put("intensity", l.intensity)
        .put("visible", l.visible)
        .put("method", l.method.name());
    if l.shape.is_flat() {
        n.put("two_sided", l.two_sided);
    }
    if let AreaMethod::Sampled { samples } = l.method {
        n.put("samples", samples);
    }
    if let Some(range) = l.range {
        n.put("range", range);
    }
    if let Some(s) = &l.shadow {
        n.put("shadow", shadow(s, LightKind::Point));
    }
    n
}
