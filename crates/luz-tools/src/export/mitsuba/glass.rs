//! Glass (issue 35) as Mitsuba 3 dielectrics: a volume (`thickness` > 0) → `dielectric`
//! (roughness 0) or `roughdielectric` (GGX at α = roughness²), thin-walled → `thindielectric`,
//! interior index from the material's dielectric F0, exterior 1, the base colour as
//! `specular_transmittance`. A transmission factor below 1 (or a metallic part) blends the
//! dielectric with the material's opaque export. What has no counterpart is noted.

use glam::Vec3;

use super::{reflectance, Writer};
use crate::brdf::{ior_from_f0, Fresnel, MetalRoughParams, ALPHA_MIN};
use crate::export::ExportError;
use crate::scene::TextureRef;

impl Writer {
    /// `p` (sanitised) has a transmission factor > 0.
    pub(super) fn glass(
        &mut self,
        name: &str,
        p: &MetalRoughParams,
        base_map: Option<&TextureRef>,
    ) -> Result<String, ExportError> {
        let t = p.transmission;
        let ior = ior_from_f0(p.dielectric_f0.x);
        let alpha = (p.roughness * p.roughness).max(ALPHA_MIN);
        if p.fresnel != Fresnel::Dielectric {
            self.note(format!(
                "material '{name}': transmission with {:?} Fresnel on the reflection (Mitsuba's dielectrics use the exact Fresnel for both)",
                p.fresnel
            ));
        }
        if base_map.is_some() {
            self.note(format!(
                "material '{name}': a base colour map on glass (the constant factor tints the transmission)"
            ));
        }
        if p.base_color != Vec3::ONE && !t.thin_walled() {
            self.note(format!(
                "material '{name}': a tinted volume (luz tints what enters once, Mitsuba at every refraction)"
            ));
        }
        if t.sigma() != Vec3::ZERO {
            self.note(format!(
                "material '{name}': the volume's attenuation (no interior medium is exported)"
            ));
        }
        if t.dispersion > 0.0 {
            self.note(format!(
                "material '{name}': dispersion (Mitsuba's RGB modes have one index)"
            ));
        }
        if t.diffuse > 0.0 {
            self.note(format!("material '{name}': diffuse transmission"));
        }
        let iors = format!(
            "<float name=\"int_ior\" value=\"{ior}\"/><float name=\"ext_ior\" value=\"1\"/>{}",
            reflectance("specular_transmittance", p.base_color)
        );
        let dielectric = if t.thin_walled() {
            self.note(format!(
                "material '{name}': thin-walled glass (thindielectric is a slab with internal reflections, 2R/(1 + R), where luz's thin wall is one interface)"
            ));
            if alpha > ALPHA_MIN {
                self.note(format!(
                    "material '{name}': rough thin-walled glass (exported smooth: Mitsuba's thindielectric has no roughness)"
                ));
            }
            format!("<bsdf type=\"thindielectric\">{iors}</bsdf>")
        } else if alpha <= ALPHA_MIN {
            format!("<bsdf type=\"dielectric\">{iors}</bsdf>")
        } else {
            format!(
                "<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"{alpha}\"/>{iors}</bsdf>"
            )
        };
        let weight = t.factor * (1.0 - p.metallic);
        if weight >= 1.0 {
            return Ok(dielectric);
        }
        // The rest is the opaque material (its diffuse weighted by 1 − weight, as luz's).
        let mut opaque = *p;
        opaque.transmission.factor = 0.0;
        let opaque = self.metal_rough(name, &opaque, base_map)?;
        Ok(format!(
            "<bsdf type=\"blendbsdf\"><float name=\"weight\" value=\"{weight}\"/>{opaque}{dielectric}</bsdf>"
        ))
    }
}
