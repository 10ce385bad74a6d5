//! Issue 35's extensions on a metal-rough material, as the decoder reads them: each object only
//! when it differs from the extension's default (files without them are written as before).

use super::node::Node;
use crate::brdf::Transmission;

pub(super) fn put(n: &mut Node, t: &Transmission) {
    let d = Transmission::default();
    if t.factor != d.factor {
        n.put(
            "transmission",
            Node::obj().with("transmissionFactor", t.factor),
        );
    }
    if t.thickness != d.thickness
        || t.attenuation_color != d.attenuation_color
        || t.attenuation_distance != d.attenuation_distance
    {
        let mut v = Node::obj()
            .with("thicknessFactor", t.thickness)
            .with("attenuationColor", t.attenuation_color);
        if let Some(distance) = t.attenuation_distance {
            v.put("attenuationDistance", distance);
        }
        n.put("volume", v);
    }
    if t.dispersion != d.dispersion {
        n.put("dispersion", Node::obj().with("dispersion", t.dispersion));
    }
    if t.diffuse != d.diffuse || t.diffuse_color != d.diffuse_color {
        n.put(
            "diffuse_transmission",
            Node::obj()
                .with("diffuseTransmissionFactor", t.diffuse)
                .with("diffuseTransmissionColorFactor", t.diffuse_color),
        );
    }
}
