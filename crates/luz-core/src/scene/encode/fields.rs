//! The encoder's small blocks: selectors, sampler fields, camera, lights, primitives and fog.

use std::path::Path;

use glam::Vec3;

use super::node::{unit_preimage, Node};
use crate::scene::{
    CascadeSplit, Falloff, Filter, Fog, Light, LightKind, MeshDesc, Shadow, Tessellation, Wrap,
};

pub(super) fn block_has(block: &Node, key: &str) -> bool {
    matches!(block, Node::Obj(fields) if fields.iter().any(|(k, _)| k == key))
}

/// An OBJ's file name, as MTL-made material names start with it.
pub(super) fn obj_file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// An object name without its last `/<part>`.
pub(super) fn name_base(name: &str) -> &str {
    name.rfind('/').map_or(name, |i| &name[..i])
}

pub(super) fn select<T: PartialEq + Copy>(table: &[(&'static str, T)], value: T) -> &'static str {
    table
        .iter()
        .find(|(_, t)| *t == value)
        .map_or("", |(n, _)| *n)
}

pub(super) fn wrap(w: Wrap) -> &'static str {
    match w {
        Wrap::Repeat => "repeat",
        Wrap::Clamp => "clamp",
        Wrap::Mirror => "mirror",
    }
}

pub(super) fn filter(f: Filter) -> &'static str {
    match f {
        Filter::Nearest => "nearest",
        Filter::Linear => "linear",
    }
}

pub(super) fn camera(c: &crate::scene::Camera) -> Node {
    let n = Node::obj()
        .with("position", c.position)
        .with("target", c.target)
        .with("up", unit_preimage(c.up));
    // A perspective camera is written as before the field existed (no "projection").
    let n = match c.ortho_half_height() {
        None => n.with("fov_y_deg", c.fov_y_deg),
        Some(h) => n
            .with("projection", "orthographic")
            .with("ortho_half_height", h),
    };
    n.with("near", c.near).with("far", c.far)
}

pub(super) fn light(l: &Light) -> Node {
    let mut n = Node::obj();
    match l.kind {
        LightKind::Directional => {
            n.put("type", "directional")
                .put("direction", unit_preimage(l.direction));
            // Not used without a target, but the decoder keeps it: keep it too.
            if l.position != Vec3::ZERO {
                n.put("position", l.position);
            }
        }
        LightKind::Point => {
            n.put("type", "point").put("position", l.position);
        }
        LightKind::Spot => {
            n.put("type", "spot")
                .put("position", l.position)
                .put("direction", unit_preimage(l.direction));
        }
    }
    n.put("color", l.color).put("intensity", l.intensity);
    if l.kind != LightKind::Directional {
        n.put(
            "falloff",
            match l.falloff {
                Falloff::InverseSquare => Node::from("inverse_square"),
                Falloff::None => Node::from("none"),
                Falloff::Classic { c1, c2, c3 } => {
                    Node::obj().with("c1", c1).with("c2", c2).with("c3", c3)
                }
            },
        );
        if let Some(range) = l.range {
            n.put("range", range);
        }
    }
    if l.kind == LightKind::Spot {
        n.put("umbra_deg", l.umbra_deg);
        if let Some(inner) = l.inner_deg {
            n.put("inner_deg", inner);
        }
        n.put("exponent", l.exponent);
    }
    if l.radius > 0.0 {
        n.put("radius", l.radius);
    }
    if l.angular_radius_deg > 0.0 {
        n.put("angular_radius_deg", l.angular_radius_deg);
    }
    if let Some(s) = &l.shadow {
        n.put("shadow", shadow(s, l.kind));
    }
    n
}

/// A light's shadow: `true` when it has the defaults, else every setting.
pub(super) fn shadow(s: &Shadow, kind: LightKind) -> Node {
    if *s == Shadow::default_for(kind) {
        return Node::from(true);
    }
    let mut n = Node::obj();
    n.put("method", s.method.name())
        .put("resolution", s.resolution)
        .put("bias", s.bias)
        .put("normal_bias", s.normal_bias)
        .put("slope_bias", s.slope_bias)
        .put("pcf_kernel", s.pcf_kernel);
    if kind == LightKind::Directional {
        n.put("cascades", s.cascades);
        match s.split {
            CascadeSplit::Uniform => n.put("split", "uniform"),
            CascadeSplit::Logarithmic => n.put("split", "logarithmic"),
            CascadeSplit::Practical { lambda } => {
                n.put("split", "practical").put("split_lambda", lambda)
            }
        };
        if let Some(d) = s.max_distance {
            n.put("max_distance", d);
        }
    }
    n
}

/// A built-in mesh's description; automatically chosen segments (and rings) are left out, so the
/// file stays automatic.
pub(super) fn primitive(desc: &MeshDesc, tessellation: Tessellation) -> Node {
    let n = Node::obj().with("type", desc.type_name());
    let (auto, rings_given) = match tessellation {
        Tessellation::Given => (false, true),
        Tessellation::Auto { rings_given, .. } => (true, rings_given),
    };
    let segments = |n: Node, segments: u32| {
        if auto {
            n
        } else {
            n.with("segments", segments)
        }
    };
    match *desc {
        MeshDesc::Sphere {
            radius,
            segments: s,
            rings,
        } => {
            let n = segments(n.with("radius", radius), s);
            if rings_given {
                n.with("rings", rings)
            } else {
                n
            }
        }
        MeshDesc::Icosphere {
            radius,
            subdivisions,
        } => n.with("radius", radius).with("subdivisions", subdivisions),
        MeshDesc::Plane { size, subdivisions } => n
            .with(
                "size",
                Node::Arr(vec![Node::Num(size[0]), Node::Num(size[1])]),
            )
            .with("subdivisions", subdivisions),
        MeshDesc::Cube { size } => n.with("size", size),
        MeshDesc::Cone {
            radius,
            height,
            segments: s,
        }
        | MeshDesc::Cylinder {
            radius,
            height,
            segments: s,
        } => segments(n.with("radius", radius).with("height", height), s),
        MeshDesc::Obj { .. } | MeshDesc::Gltf { .. } => n,
    }
}

pub(super) fn fog(f: &Fog) -> Node {
    Node::obj()
        .with("z_a", f.z_a)
        .with("z_b", f.z_b)
        .with("s_a", f.s_a)
        .with("s_b", f.s_b)
        .with("color", f.color)
}
