//! A `{"type": "gltf"}` object: the file's parts become objects (node transforms baked into
//! their meshes, the entry's transform on top), its materials scene materials named
//! `<file name>/<material name>` (unless the entry names a `material`), and, when asked, its
//! lights and cameras join the scene (through the entry's transform).

use super::*;
use crate::scene::gltf::{self, GltfFile};

pub(crate) struct LoadedGltf {
    pub(crate) file: GltfFile,
    pub(crate) meshes: Vec<Arc<Mesh>>,
}

/// The fields of the scene's entry.
pub(super) struct Entry<'a> {
    pub(super) desc: &'a MeshDesc,
    pub(super) name: String,
    /// The scene material that overrides the file's.
    pub(super) material: Option<usize>,
    pub(super) transform: Transform,
    pub(super) shading: Shading,
    pub(super) shadow: crate::scene::ObjectShadow,
    /// JSON path of the entry's `mesh`.
    pub(super) path: String,
}

pub(super) fn expand(e: Entry, ctx: &mut Ctx, scene: &mut Scene) -> Result<()> {
    let MeshDesc::Gltf {
        path: file,
        scene: which,
        lights,
        cameras,
        light_shadow,
    } = e.desc
    else {
        return Ok(());
    };
    let key = (file.clone(), *which);
    let loaded = match ctx.gltfs.get(&key) {
        Some(l) => l.clone(),
        None => {
            let g = gltf::load(file, which.map(|s| s as usize)).map_err(|err| Invalid {
                path: format!("{}.path", e.path),
                reason: format!("{}: {}", err.path, err.reason),
                mesh: Some((err.file, None)),
            })?;
            scene.warnings.extend(g.warnings.iter().cloned());
            let meshes = g.parts.iter().map(|p| Arc::new(p.mesh.clone())).collect();
            let l = Arc::new(LoadedGltf { file: g, meshes });
            ctx.gltfs.insert(key, l.clone());
            l
        }
    };
    let file_name = file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| file.display().to_string());
    for (part, mesh) in loaded.file.parts.iter().zip(&loaded.meshes) {
        let material = match e.material {
            Some(m) => m,
            None => material(ctx, scene, file, &file_name, &loaded.file, part.material),
        };
        scene.objects.push(Object {
            name: format!("{}/{}", e.name, part.name),
            desc: e.desc.clone(),
            mesh: mesh.clone(),
            material,
            transform: e.transform,
            shading: e.shading,
            tessellation: Tessellation::Given,
            shadow: e.shadow,
        });
    }
    let m = e.transform.matrix();
    if *lights {
        for l in &loaded.file.lights {
            let mut l = *l;
            l.position = m.transform_point3(l.position);
            if l.kind != LightKind::Point {
                l.direction = m
                    .transform_vector3(l.direction)
                    .try_normalize()
                    .unwrap_or(l.direction);
            }
            if *light_shadow {
                l.shadow = Some(crate::scene::Shadow::default_for(l.kind));
            }
            scene.lights.push(l);
        }
        let k = super::super::gltf::max_scale(m);
        for a in &loaded.file.area_lights {
            let mut a = *a;
            a.position = m.transform_point3(a.position);
            a.direction = m
                .transform_vector3(a.direction)
                .try_normalize()
                .unwrap_or(a.direction);
            a.shape = match a.shape {
                crate::scene::AreaShape::Rect { up, width, height } => {
                    crate::scene::AreaShape::Rect {
                        up: m.transform_vector3(up).try_normalize().unwrap_or(up),
                        width: width * k,
                        height: height * k,
                    }
                }
                crate::scene::AreaShape::Disk { radius } => {
                    crate::scene::AreaShape::Disk { radius: radius * k }
                }
                other => other,
            };
            if *light_shadow {
                a.shadow = Some(crate::scene::Shadow::default_for(LightKind::Point));
            }
            scene.area_lights.push(a);
        }
    }
    if *cameras {
        for c in &loaded.file.cameras {
            let mut c = c.clone();
            let cam = &mut c.camera;
            let forward = m.transform_vector3(cam.target - cam.position);
            cam.position = m.transform_point3(cam.position);
            cam.target = cam.position + forward.try_normalize().unwrap_or(Vec3::NEG_Z);
            cam.up = m
                .transform_vector3(cam.up)
                .try_normalize()
                .unwrap_or(Vec3::Y);
            scene.cameras.push(c);
        }
    }
    Ok(())
}

/// The scene material for the file's material `which` (appended on first use).
fn material(
    ctx: &mut Ctx,
    scene: &mut Scene,
    file: &Path,
    file_name: &str,
    g: &GltfFile,
    which: usize,
) -> usize {
    let key = (file.to_path_buf(), Some(which));
    if let Some(&i) = ctx.mtl_materials.get(&key) {
        return i;
    }
    let gm = g
        .materials
        .get(which)
        .cloned()
        .unwrap_or_else(|| gltf::GltfMaterial {
            name: "default".into(),
            material: Material::MetalRough(MetalRoughParams::default()),
            textures: Default::default(),
            uv: Default::default(),
        });
    let mut name = format!("{file_name}/{}", gm.name);
    let mut n = 2;
    while ctx.material_index.contains_key(&name) {
        name = format!("{file_name}/{}#{n}", gm.name);
        n += 1;
    }
    let i = scene.materials.len();
    ctx.material_index.insert(name.clone(), i);
    scene.materials.push(NamedMaterial {
        name,
        material: gm.material,
        textures: gm.textures,
    });
    ctx.mtl_materials.insert(key, i);
    i
}
