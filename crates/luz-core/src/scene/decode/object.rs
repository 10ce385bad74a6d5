//! Objects: meshes (primitives shared between equal descriptions, OBJ files with their MTL
//! materials), transforms, shading and the scene's triangle budget.

use super::*;

// ---------------------------------------------------------------------------------------------
// Objects.

/// Most triangles of all distinct built-in meshes of one scene (2^25, about 1.9 GB of vertices
/// and indices): a small file must not make the loader build gigabytes.
pub const MAX_SCENE_PRIMITIVE_TRIANGLES: u64 = 1 << 25;

pub(super) struct Ctx<'a> {
    pub(super) base: &'a Path,
    /// Built primitives, shared between objects with equal descriptions.
    pub(super) primitives: MeshCache,
    /// Triangles of the distinct primitives built so far ([`MAX_SCENE_PRIMITIVE_TRIANGLES`]).
    pub(super) primitive_triangles: u64,
    /// Loaded OBJ files by (resolved path, with materials).
    pub(super) objs: HashMap<(PathBuf, bool), Arc<LoadedObj>>,
    /// Loaded glTF files by (resolved path, scene).
    pub(super) gltfs: HashMap<(PathBuf, Option<u32>), Arc<super::gltf_object::LoadedGltf>>,
    /// (resolved OBJ path, MTL material index or None for the default) → scene material index.
    pub(super) mtl_materials: HashMap<(PathBuf, Option<usize>), usize>,
    /// Index in `scene.materials` by name (the scene's materials, then the MTL ones as added).
    pub(super) material_index: HashMap<String, usize>,
}

pub(super) struct LoadedObj {
    pub(super) file: ObjFile,
    pub(super) meshes: Vec<Arc<Mesh>>,
}

pub(super) const MESH_TYPES: &[&str] = &[
    "sphere",
    "icosphere",
    "plane",
    "cube",
    "cone",
    "cylinder",
    "obj",
    "gltf",
];

pub(super) fn object(
    v: &Value,
    path: &str,
    i: usize,
    ctx: &mut Ctx,
    scene: &mut Scene,
) -> Result<()> {
    let f = Fields::new(v, path)?;
    f.allow(
        &[
            "name",
            "mesh",
            "material",
            "position",
            "rotation_deg",
            "scale",
            "shading",
            "cast_shadow",
            "receive_shadow",
        ],
        "an object",
    )?;
    let name = f.string("name")?.map(str::to_string);
    let (desc, tessellation) = mesh_desc(f.req("mesh")?, &f.path("mesh"), ctx.base)?;
    let material = match f.get("material") {
        Some(m) => {
            let name = string(m, &f.path("material"))?;
            let found = ctx.material_index.get(name).copied();
            Some(found.ok_or_else(|| {
                let defined: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
                f.err(
                    "material",
                    format!(
                        "unknown material \"{name}\"; defined: {}{}",
                        if defined.is_empty() {
                            "none (add it under \"materials\")".to_string()
                        } else {
                            defined.join(", ")
                        },
                        suggestion(name, &defined)
                    ),
                )
            })?)
        }
        None if matches!(desc, MeshDesc::Obj { .. } | MeshDesc::Gltf { .. }) => None,
        None => return Err(f.err(
            "material",
            "missing required field (only OBJ and glTF meshes may take their materials from their files)",
        )),
    };
    let position = f.vec3("position", Vec3::ZERO)?;
    let rotation_deg = f.vec3("rotation_deg", Vec3::ZERO)?;
    let scale = match f.get("scale") {
        None => Vec3::ONE,
        Some(
            v @ Value {
                kind: Kind::Number { .. },
                ..
            },
        ) => Vec3::splat(number(v, &f.path("scale"), Check::Positive)?),
        Some(v) => vec3(v, &f.path("scale"), Check::Positive)?,
    };
    let shading = match f.choice("shading", &["flat", "gouraud", "phong"])? {
        Some("flat") => Shading::Flat,
        Some("gouraud") => Shading::Gouraud,
        _ => Shading::Phong,
    };
    let transform = Transform {
        position,
        rotation_deg,
        scale,
    };
    let shadow = ObjectShadow {
        cast: f.boolean("cast_shadow", true)?,
        receive: f.boolean("receive_shadow", true)?,
    };

    if let MeshDesc::Gltf { .. } = &desc {
        let name = name.unwrap_or_else(|| {
            desc.file()
                .and_then(|p| p.file_stem())
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| format!("gltf{i}"))
        });
        let part = super::gltf_object::Entry {
            desc: &desc,
            name,
            material,
            transform,
            shading,
            shadow,
            path: f.path("mesh"),
        };
        return super::gltf_object::expand(part, ctx, scene);
    }
    if let MeshDesc::Obj { path: obj_path } = &desc {
        let with_materials = material.is_none();
        let key = (obj_path.clone(), with_materials);
        let loaded = match ctx.objs.get(&key) {
            Some(l) => l.clone(),
            None => {
                let file = load_obj(obj_path, with_materials).map_err(|e| Invalid {
                    path: f.path("mesh") + ".path",
                    reason: e.reason,
                    mesh: Some((e.file, e.line)),
                })?;
                scene.warnings.extend(file.warnings.iter().cloned());
                let meshes = file
                    .parts
                    .iter()
                    .map(|p| Arc::new(p.mesh.clone()))
                    .collect();
                let l = Arc::new(LoadedObj { file, meshes });
                ctx.objs.insert(key, l.clone());
                l
            }
        };
        let file_name = obj_path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| obj_path.display().to_string());
        let stem = obj_path
            .file_stem()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| file_name.clone());
        let single = loaded.file.parts.len() == 1;
        for (part, mesh) in loaded.file.parts.iter().zip(&loaded.meshes) {
            let part_material = match material {
                Some(m) => m,
                None => mtl_material(
                    ctx,
                    scene,
                    obj_path,
                    &file_name,
                    &loaded.file,
                    part.material,
                ),
            };
            let base = name.clone().unwrap_or_else(|| stem.clone());
            scene.objects.push(Object {
                name: if single {
                    base
                } else {
                    format!("{base}/{}", part.name)
                },
                desc: desc.clone(),
                mesh: mesh.clone(),
                material: part_material,
                transform,
                shading,
                tessellation,
                shadow,
            });
        }
        return Ok(());
    }

    // Automatic tessellation builds its mesh once the whole scene is known (resolve).
    let mesh = match ctx.primitives.get(&desc) {
        _ if tessellation != Tessellation::Given => Arc::new(Mesh::default()),
        Some(m) => m.clone(),
        None => {
            let n = desc.triangle_count().unwrap_or(0);
            ctx.primitive_triangles += n;
            if ctx.primitive_triangles > MAX_SCENE_PRIMITIVE_TRIANGLES {
                return Err(f.err(
                    "mesh",
                    format!(
                        "the scene's built-in meshes would have {} triangles with this one ({n}); \
                         the limit per scene is {MAX_SCENE_PRIMITIVE_TRIANGLES} (objects with equal \
                         meshes share one)",
                        ctx.primitive_triangles
                    ),
                ));
            }
            let m = Arc::new(desc.build().unwrap_or_default());
            ctx.primitives.insert(desc.clone(), m.clone());
            m
        }
    };
    let kind = desc.type_name();
    scene.objects.push(Object {
        name: name.unwrap_or_else(|| format!("{kind}{i}")),
        desc,
        mesh,
        material: material.unwrap_or(0),
        transform,
        shading,
        tessellation,
        shadow,
    });
    Ok(())
}

/// Shininess of an MTL material without `Ns`.
pub(super) const MTL_DEFAULT_SHININESS: f32 = 32.0;

/// The scene material for an OBJ part's MTL material (appended on first use).
pub(super) fn mtl_material(
    ctx: &mut Ctx,
    scene: &mut Scene,
    obj_path: &Path,
    file_name: &str,
    file: &ObjFile,
    which: Option<usize>,
) -> usize {
    let key = (obj_path.to_path_buf(), which);
    if let Some(&i) = ctx.mtl_materials.get(&key) {
        return i;
    }
    let (mtl_name, material, textures) = match which.and_then(|i| file.materials.get(i)) {
        // The MTL's model (classic, or metal_rough with the PBR extension) and its maps.
        Some(m) => {
            let (material, textures) = maps::mtl_material(m, &mut scene.warnings);
            (m.name.clone(), material, textures)
        }
        None => (
            "default".to_string(),
            Material::default_phong(false),
            crate::scene::MaterialTextures::default(),
        ),
    };
    let mut name = format!("{file_name}/{mtl_name}");
    let mut n = 2;
    while ctx.material_index.contains_key(&name) {
        name = format!("{file_name}/{mtl_name}#{n}");
        n += 1;
    }
    let i = scene.materials.len();
    ctx.material_index.insert(name.clone(), i);
    scene.materials.push(NamedMaterial {
        name,
        material,
        textures,
    });
    ctx.mtl_materials.insert(key, i);
    i
}

/// The mesh description and whether its segments are left to [`tessellation::resolve`] (then
/// the description holds placeholder counts until the scene is resolved).
pub(super) fn mesh_desc(v: &Value, path: &str, base: &Path) -> Result<(MeshDesc, Tessellation)> {
    let f = Fields::new(v, path)?;
    let kind = choice(f.req("type")?, &f.path("type"), MESH_TYPES)?;
    let seg = |f: &Fields, default| f.int("segments", default, 3, MAX_SEGMENTS);
    let tessellation =
        if matches!(kind, "sphere" | "cone" | "cylinder") && f.get("segments").is_none() {
            Tessellation::Auto {
                projected_radius_px: 0.0,
                rings_given: f.get("rings").is_some(),
            }
        } else {
            Tessellation::Given
        };
    let desc = match kind {
        "sphere" => {
            f.allow(&["type", "radius", "segments", "rings"], "a sphere")?;
            MeshDesc::Sphere {
                radius: f.num("radius", 1.0, Check::Positive)?,
                segments: seg(&f, 64)?,
                rings: f.int("rings", 32, 2, MAX_RINGS)?,
            }
        }
        "icosphere" => {
            f.allow(&["type", "radius", "subdivisions"], "an icosphere")?;
            MeshDesc::Icosphere {
                radius: f.num("radius", 1.0, Check::Positive)?,
                subdivisions: f.int("subdivisions", 3, 0, MAX_ICOSPHERE_SUBDIVISIONS)?,
            }
        }
        "plane" => {
            f.allow(&["type", "size", "subdivisions"], "a plane")?;
            let size = match f.get("size") {
                None => [10.0, 10.0],
                Some(v) => {
                    let p = f.path("size");
                    let items = array(v, &p, "an array [x, z] of 2 numbers")?;
                    if items.len() != 2 {
                        return Err(Invalid::new(
                            &p,
                            format!(
                                "expected an array [x, z] of 2 numbers, got {} elements",
                                items.len()
                            ),
                        ));
                    }
                    [
                        number(&items[0], &index(&p, 0), Check::Positive)?,
                        number(&items[1], &index(&p, 1), Check::Positive)?,
                    ]
                }
            };
            MeshDesc::Plane {
                size,
                subdivisions: f.int("subdivisions", 1, 1, MAX_PLANE_SUBDIVISIONS)?,
            }
        }
        "cube" => {
            f.allow(&["type", "size"], "a cube")?;
            MeshDesc::Cube {
                size: f.num("size", 1.0, Check::Positive)?,
            }
        }
        "cone" | "cylinder" => {
            f.allow(
                &["type", "radius", "height", "segments"],
                &format!("a {kind}"),
            )?;
            let radius = f.num("radius", 0.5, Check::Positive)?;
            let height = f.num("height", 1.0, Check::Positive)?;
            let segments = seg(&f, 64)?;
            if kind == "cone" {
                MeshDesc::Cone {
                    radius,
                    height,
                    segments,
                }
            } else {
                MeshDesc::Cylinder {
                    radius,
                    height,
                    segments,
                }
            }
        }
        "gltf" => {
            f.allow(
                &["type", "path", "scene", "lights", "cameras", "light_shadow"],
                "a glTF mesh",
            )?;
            let p = string(f.req("path")?, &f.path("path"))?;
            if p.trim().is_empty() {
                return Err(f.err("path", "must not be empty"));
            }
            let scene = match f.get("scene") {
                None => None,
                Some(v) => Some(integer(v, &f.path("scene"), 0, u32::MAX)?),
            };
            let lights = f.boolean("lights", false)?;
            let light_shadow = f.boolean("light_shadow", false)?;
            if light_shadow && !lights {
                return Err(f.err(
                    "light_shadow",
                    "the file's lights cast shadows only when they are imported: add \"lights\": true",
                ));
            }
            return Ok((
                MeshDesc::Gltf {
                    path: base.join(p),
                    scene,
                    lights,
                    cameras: f.boolean("cameras", false)?,
                    light_shadow,
                },
                Tessellation::Given,
            ));
        }
        _ => {
            f.allow(&["type", "path"], "an OBJ mesh")?;
            let p = string(f.req("path")?, &f.path("path"))?;
            if p.trim().is_empty() {
                return Err(f.err("path", "must not be empty"));
            }
            return Ok((MeshDesc::Obj { path: base.join(p) }, Tessellation::Given));
        }
    };
    if let Some(n) = desc.triangle_count() {
        if n > MAX_PRIMITIVE_TRIANGLES {
            return Err(Invalid::new(
                path,
                format!(
                    "too finely tessellated: {n} triangles, the limit per primitive is {MAX_PRIMITIVE_TRIANGLES}"
                ),
            ));
        }
    }
    Ok((desc, tessellation))
}
