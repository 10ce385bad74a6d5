//! The objects and materials panel (every material model's parameters and maps).

use super::*;

// ---------------------------------------------------------------------------------------------
// Objects and materials.

pub(super) fn objects_ui(ui: &mut Ui, scene: &mut Scene, state: &mut UiState, out: &mut Out) {
    if scene.objects.is_empty() {
        ui.label("No objects.");
        return;
    }
    state.selected_object = state.selected_object.min(scene.objects.len() - 1);
    ComboBox::from_id_salt("luz_object")
        .selected_text(scene.objects[state.selected_object].name.as_str())
        .show_ui(ui, |ui| {
            for (i, o) in scene.objects.iter().enumerate() {
                ui.selectable_value(&mut state.selected_object, i, o.name.as_str());
            }
        });
    let material_names: Vec<String> = scene.materials.iter().map(|m| m.name.clone()).collect();
    let object = &mut scene.objects[state.selected_object];
    let changed = grid(ui, "luz_object_grid", |ui| {
        let mut c = false;
        let t = &mut object.transform;
        c |= row(ui, "Position", |ui| {
            vec3(ui, &mut t.position, f32::MIN..=f32::MAX, 0.02)
        });
        c |= row(ui, "Rotation (°)", |ui| {
            vec3(ui, &mut t.rotation_deg, -36000.0..=36000.0, 0.5)
        });
        c |= row(ui, "Scale", |ui| vec3(ui, &mut t.scale, 1e-3..=1e6, 0.01));
        c |= row(ui, "Shading", |ui| {
            combo(ui, "luz_shading", &mut object.shading, &SHADINGS)
        });
        c |= row(ui, "Material", |ui| {
            let mut m = object.material;
            let mut changed = false;
            ComboBox::from_id_salt("luz_object_material")
                .selected_text(material_names.get(m).map_or("?", String::as_str))
                .show_ui(ui, |ui| {
                    for (i, name) in material_names.iter().enumerate() {
                        changed |= ui.selectable_value(&mut m, i, name.as_str()).changed();
                    }
                });
            if changed && m != object.material && m < material_names.len() {
                object.material = m;
                true
            } else {
                false
            }
        });
        c
    });
    out.edit(changed);

    let mi = scene.objects[state.selected_object].material;
    let users = scene.objects.iter().filter(|o| o.material == mi).count();
    let Some(named) = scene.materials.get_mut(mi) else {
        return;
    };
    ui.separator();
    ui.label(format!(
        "Material \"{}\"{}",
        named.name,
        if users > 1 {
            format!(" (shared by {users} objects)")
        } else {
            String::new()
        }
    ));
    let mut model = named.material.name();
    let options: Vec<(&str, &str)> = crate::scene::MATERIAL_MODELS
        .iter()
        .map(|k| (k.name(), k.name()))
        .collect();
    if combo(ui, ("luz_model", mi), &mut model, &options) {
        set_material_model(&mut named.material, &mut named.textures, model);
        out.edit(true);
    }
    let changed = ui
        .push_id(("luz_material", mi), |ui| {
            material_ui(ui, &mut named.material)
        })
        .inner;
    out.edit(changed);
    let maps: Vec<&str> = named.textures.maps().map(|(s, _)| s.name()).collect();
    if !maps.is_empty() {
        ui.label(format!("Texture maps: {}", maps.join(", ")));
    }
}

const SHADINGS: [(Shading, &str); 3] = [
    (Shading::Flat, "flat"),
    (Shading::Gouraud, "Gouraud"),
    (Shading::Phong, "Phong"),
];

pub(super) const DISTRIBUTIONS: [(Distribution, &str); 2] = [
    (Distribution::Beckmann, "Beckmann"),
    (Distribution::Ggx, "GGX"),
];

pub(super) const DIFFUSES: [(Diffuse, &str); 2] = [
    (Diffuse::Lambert, "Lambert"),
    (Diffuse::Burley, "Burley (Disney)"),
];

pub(super) const GEOMETRIES: [(Geometry, &str); 5] = [
    (Geometry::CookTorrance, "Cook-Torrance"),
    (Geometry::SmithGgx, "Smith GGX (separable)"),
    (
        Geometry::SmithGgxCorrelated,
        "Smith GGX (height-correlated)",
    ),
    (Geometry::SchlickGgx, "Schlick-GGX"),
    (Geometry::SmithBeckmann, "Smith Beckmann (Walter 2007)"),
];

pub(super) const FRESNELS: [(Fresnel, &str); 5] = [
    (Fresnel::Schlick, "Schlick"),
    (Fresnel::SchlickSg, "Schlick (spherical Gaussian)"),
    (Fresnel::Dielectric, "dielectric (exact)"),
    (Fresnel::Conductor, "conductor (complex index, approximate)"),
    (Fresnel::ConductorExact, "conductor (complex index, exact)"),
];

pub(super) fn material_ui(ui: &mut Ui, m: &mut Material) -> bool {
    grid(ui, "luz_material_grid", |ui| match m {
        Material::Phong(crate::brdf::PhongParams {
            blinn,
            ka,
            kd,
            ks,
            shininess,
            diffuse_color,
            specular_color,
        }) => {
            let mut c = false;
            c |= row(ui, "Blinn (n·h)", |ui| checkbox(ui, blinn, ""));
            c |= row(ui, "k_a", |ui| drag(ui, ka, 0.0..=f32::INFINITY));
            c |= row(ui, "k_d", |ui| drag(ui, kd, 0.0..=f32::INFINITY));
            c |= row(ui, "k_s", |ui| drag(ui, ks, 0.0..=f32::INFINITY));
            c |= row(ui, "Shininess n", |ui| {
                slider(ui, shininess, 0.0..=10_000.0, true)
            });
            c |= row(ui, "O_d (diffuse)", |ui| {
                color(ui, diffuse_color, f32::INFINITY)
            });
            c |= row(ui, "O_s (specular)", |ui| {
                color(ui, specular_color, f32::INFINITY)
            });
            c
        }
        Material::Lambert(crate::brdf::LambertParams { albedo }) => {
            row(ui, "Albedo", |ui| color(ui, albedo, 1.0))
        }
        Material::CookTorrance(p) => cook_torrance_ui(ui, p),
        Material::MetalRough(p) => metal_rough_ui(ui, p),
        Material::Principled(p) => {
            let mut c = false;
            c |= row(ui, "Base colour", |ui| color(ui, &mut p.base_color, 1.0));
            let fields: [(&str, &mut f32); 10] = [
                ("Subsurface", &mut p.subsurface),
                ("Metallic", &mut p.metallic),
                ("Specular", &mut p.specular),
                ("Specular tint", &mut p.specular_tint),
                ("Roughness", &mut p.roughness),
                ("Anisotropic", &mut p.anisotropic),
                ("Sheen", &mut p.sheen),
                ("Sheen tint", &mut p.sheen_tint),
                ("Clearcoat", &mut p.clearcoat),
                ("Clearcoat gloss", &mut p.clearcoat_gloss),
            ];
            for (name, v) in fields {
                c |= row(ui, name, |ui| unit(ui, v));
            }
            c
        }
        Material::OrenNayar(p) => {
            let mut c = false;
            c |= row(ui, "Albedo", |ui| color(ui, &mut p.albedo, 1.0));
            c |= row(ui, "σ (°)", |ui| {
                slider(ui, &mut p.sigma_deg, 0.0..=90.0, false)
            });
            c
        }
    })
}

/// How a Cook-Torrance material gives its Fresnel reflectance, for the combo box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum SourceKind {
    Ior,
    F0,
    Complex,
}

/// The D and G rows of the models with selectable terms (Cook-Torrance, metallic-roughness);
/// `ids` are their combo boxes' ids.
fn distribution_rows(
    ui: &mut Ui,
    [d_id, g_id]: [&str; 2],
    distribution: &mut Distribution,
    geometry: &mut Geometry,
) -> bool {
    let mut c = row(ui, "D", |ui| combo(ui, d_id, distribution, &DISTRIBUTIONS));
    c |= row(ui, "G", |ui| combo(ui, g_id, geometry, &GEOMETRIES));
    c
}

pub(super) fn cook_torrance_ui(ui: &mut Ui, p: &mut CookTorranceParams) -> bool {
    let mut c = false;
    c |= row(ui, "Colour", |ui| color(ui, &mut p.color, 1.0));
    c |= row(ui, "k_d", |ui| unit(ui, &mut p.kd));
    c |= row(ui, "Roughness", |ui| unit(ui, &mut p.roughness));
    c |= row(ui, "Diffuse", |ui| {
        combo(ui, "ct_diffuse", &mut p.diffuse, &DIFFUSES)
    });
    c |= distribution_rows(ui, ["ct_d", "ct_g"], &mut p.distribution, &mut p.geometry);
    c |= row(ui, "F", |ui| {
        let changed = combo(ui, "ct_f", &mut p.fresnel, &FRESNELS);
        if changed {
            fix_cook_torrance(p);
        }
        changed
    });
    c |= row(ui, "Fresnel source", |ui| {
        let mut k = match p.specular {
            SpecularSource::Ior(_) => SourceKind::Ior,
            SpecularSource::F0(_) => SourceKind::F0,
            SpecularSource::Complex(_) => SourceKind::Complex,
        };
        // Only the sources the selected Fresnel accepts.
        let options: Vec<(SourceKind, &str)> = [
            (SourceKind::Ior, "index of refraction η"),
            (SourceKind::F0, "F0"),
            (SourceKind::Complex, "complex index η + iκ"),
        ]
        .into_iter()
        .filter(|(k, _)| match p.fresnel {
            Fresnel::Conductor | Fresnel::ConductorExact => *k == SourceKind::Complex,
            Fresnel::Dielectric => *k != SourceKind::Complex,
            _ => true,
        })
        .collect();
        let mut changed = combo(ui, "ct_source", &mut k, &options);
        if changed {
            let f0 = p.specular.fresnel_inputs(Fresnel::Schlick).0;
            p.specular = match k {
                SourceKind::Ior => SpecularSource::Ior(1.5),
                SourceKind::F0 => SpecularSource::F0(f0.clamp(Vec3::ZERO, Vec3::ONE)),
                SourceKind::Complex => {
                    SpecularSource::Complex(metal_preset("gold").unwrap_or(ComplexIor {
                        eta: Vec3::ONE,
                        k: Vec3::ZERO,
                    }))
                }
            };
        }
        // Presets: metals give a complex index, dielectrics a real one.
        let mut preset: Option<&str> = None;
        ComboBox::from_id_salt("ct_preset")
            .selected_text("preset…")
            .show_ui(ui, |ui| {
                if p.fresnel != Fresnel::Dielectric {
                    for name in METAL_NAMES {
                        if ui.selectable_label(false, name).clicked() {
                            preset = Some(name);
                        }
                    }
                }
                if !matches!(p.fresnel, Fresnel::Conductor | Fresnel::ConductorExact) {
                    ui.separator();
                    for name in DIELECTRIC_NAMES {
                        if ui.selectable_label(false, name).clicked() {
                            preset = Some(name);
                        }
                    }
                }
            });
        if let Some(name) = preset {
            if let Some(c) = metal_preset(name) {
                p.specular = SpecularSource::Complex(c);
                changed = true;
            } else if let Some(eta) = dielectric_ior(name) {
                p.specular = SpecularSource::Ior(eta);
                changed = true;
            }
            fix_cook_torrance(p);
        }
        changed
    });
    c |= match &mut p.specular {
        SpecularSource::Ior(eta) => row(ui, "η", |ui| drag_speed(ui, eta, 1e-3..=100.0, 0.005)),
        SpecularSource::F0(f0) => row(ui, "F0", |ui| color(ui, f0, 1.0)),
        SpecularSource::Complex(ci) => {
            let mut c = row(ui, "η (r, g, b)", |ui| {
                vec3(ui, &mut ci.eta, 1e-3..=100.0, 0.005)
            });
            c |= row(ui, "κ (r, g, b)", |ui| {
                vec3(ui, &mut ci.k, 0.0..=100.0, 0.005)
            });
            c
        }
    };
    c
}

pub(super) fn metal_rough_ui(ui: &mut Ui, p: &mut MetalRoughParams) -> bool {
    let mut c = false;
    c |= row(ui, "Base colour", |ui| color(ui, &mut p.base_color, 1.0));
    c |= row(ui, "Metallic", |ui| unit(ui, &mut p.metallic));
    c |= row(ui, "Roughness", |ui| unit(ui, &mut p.roughness));
    c |= row(ui, "Metal preset", |ui| {
        let mut preset = None;
        ComboBox::from_id_salt("mr_preset")
            .selected_text("preset…")
            .show_ui(ui, |ui| {
                for name in METAL_NAMES {
                    if ui.selectable_label(false, name).clicked() {
                        preset = metal_preset(name);
                    }
                }
            });
        match preset {
            // As the decoder: base colour = the metal's F0, metallic 1.
            Some(m) => {
                p.base_color = m.f0().clamp(Vec3::ZERO, Vec3::ONE);
                p.metallic = 1.0;
                true
            }
            None => false,
        }
    });
    c |= distribution_rows(ui, ["mr_d", "mr_g"], &mut p.distribution, &mut p.geometry);
    c |= row(ui, "F", |ui| combo(ui, "mr_f", &mut p.fresnel, &FRESNELS));
    c |= row(ui, "Diffuse", |ui| {
        combo(ui, "mr_diffuse", &mut p.diffuse, &DIFFUSES)
    });
    c |= row(ui, "Diffuse × (1 − F)", |ui| {
        checkbox(ui, &mut p.diffuse_fresnel_weight, "")
    });
    // KHR_materials_specular's F90 of the dielectric (its F0 follows the specularFactor it
    // came from; here only the grazing value).
    c |= row(ui, "Dielectric F90", |ui| unit(ui, &mut p.dielectric_f90));
    // KHR_materials_clearcoat (turning the coat on or off rebuilds the pipelines: LOBES).
    c |= row(ui, "Clearcoat", |ui| unit(ui, &mut p.clearcoat));
    c |= row(ui, "Clearcoat roughness", |ui| {
        unit(ui, &mut p.clearcoat_roughness)
    });
    // KHR_materials_sheen (a black sheen colour is no sheen: LOBES likewise).
    c |= row(ui, "Sheen colour", |ui| color(ui, &mut p.sheen_color, 1.0));
    c |= row(ui, "Sheen roughness", |ui| unit(ui, &mut p.sheen_roughness));
    // KHR_materials_anisotropy (strength 0 is isotropic: LOBES likewise); the rotation in degrees.
    c |= row(ui, "Anisotropy", |ui| unit(ui, &mut p.anisotropy_strength));
    c |= row(ui, "Anisotropy rotation °", |ui| {
        let mut deg = p.anisotropy_rotation.to_degrees();
        let changed = ui
            .add(
                egui::DragValue::new(&mut deg)
                    .range(-180.0..=180.0)
                    .speed(1.0),
            )
            .changed();
        if changed {
            p.anisotropy_rotation = deg.to_radians();
        }
        changed
    });
    // KHR_materials_iridescence (factor 0 or thickness 0 is no film: LOBES likewise).
    c |= row(ui, "Iridescence", |ui| unit(ui, &mut p.iridescence));
    c |= row(ui, "Film ior", |ui| {
        ui.add(
            egui::DragValue::new(&mut p.iridescence_ior)
                .range(1.0..=3.0)
                .speed(0.01),
        )
        .changed()
    });
    c |= row(ui, "Film thickness nm", |ui| {
        ui.add(
            egui::DragValue::new(&mut p.iridescence_thickness_max)
                .range(0.0..=1200.0)
                .speed(5.0),
        )
        .changed()
    });
    c
}
