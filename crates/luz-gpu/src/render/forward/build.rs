//! Building the forward pass's data: the frame set layout, the draws and the meshes they upload,
//! the per-slot buffers and descriptor sets, and the LUT layers the materials need.

use super::clusters::{ClusterHeader, Clusters};
use super::*;
use crate::scene::Sides;

/// `count` elements of `T` in one storage buffer bound whole (`field`: the scene's array):
/// `maxStorageBufferRange` and the buffer limits.
pub(super) fn storage_fits<T>(
    limits: &crate::vk::Limits,
    scene: &str,
    field: &str,
    count: usize,
) -> Result<(), VkError> {
    let size = std::mem::size_of::<T>();
    limits.check_storage(
        &format!("{scene}: {field} ({count} × {size} bytes)"),
        (count as u64).saturating_mul(size as u64),
    )
}

/// The per-frame set's layout: frame uniforms, lights, objects, the sRGB encode table, the
/// deferred path's materials, the light clusters and their index list, the instances' objects
/// (`bindings.glsl`, set 0), as the scene's shaders declare it.
pub(super) fn frame_set_layout(ctx: &Arc<Context>) -> Result<DescriptorSetLayout, VkError> {
    crate::render::sets::scene_interface()?.set_layout(ctx, gpu::SET_FRAME)
}

/// What [`build_draws`] makes: the meshes queued for upload, the objects' data and one draw per
/// drawn object.
pub(super) struct Draws {
    pub(super) meshes: Vec<GpuMesh>,
    /// One item per drawn object, one shape per mesh.
    pub(super) list: DrawList,
    pub(super) objects: Vec<gpu::ObjectData>,
    pub(super) draws: Vec<Draw>,
    /// Each scene object's index in `objects` (`None`: nothing to draw).
    pub(super) object_slots: Vec<Option<u32>>,
    /// What building the LOD chains of the meshes did.
    pub(super) lod_stats: crate::scene::lod::ChainStats,
}

/// One GPU copy of each mesh per (mesh, smooth/flat) pair, queued on `uploader`, with the levels
/// of its LOD chain for OBJ and glTF meshes (built once per mesh, or read from `lod_cache`), and a
/// draw with its pipeline variant and push constants for every object.
pub(super) fn build_draws(
    scene: &Scene,
    (ibl, ibl_key): (Option<&Ibl>, Option<IblKey>),
    debug: DebugView,
    (generic, clustered): (bool, bool),
    (limits, lod_cache, prepared): (
        &crate::vk::Limits,
        Option<&std::path::Path>,
        &crate::prepare::PreparedScene,
    ),
    uploader: &mut Uploader,
) -> Result<Draws, VkError> {
    use crate::scene::MeshDesc;
    let scene_name = scene.display_name();
    // Meshes: one GPU copy per (mesh, smooth/flat) pair, one LOD chain per mesh.
    let mut mesh_cache: HashMap<(usize, bool), usize> = HashMap::new();
    let mut chains: HashMap<usize, Arc<crate::scene::lod::LodChain>> = HashMap::new();
    // The prepared scene's chains; a mesh it lacks gets its chain here.
    let mut lod_stats = prepared.lod_stats.clone();
    let mut meshes = Vec::new();
    let mut list = DrawList::default();
    let mut objects = Vec::new();
    let mut draws = Vec::new();
    let mut object_slots = vec![None; scene.objects.len()];
    for (object, obj) in scene.objects.iter().enumerate() {
        let flat = matches!(obj.shading, Shading::Flat);
        let key = (Arc::as_ptr(&obj.mesh) as usize, flat);
        let mesh_index = match mesh_cache.get(&key) {
            Some(&m) => m,
            None => {
                // Beyond 32-bit indices or the device's index and buffer limits: an error
                // naming the object (no split into several draws).
                let size = mesh::draw_size(&obj.mesh, flat);
                limits.check_mesh(
                    &format!(
                        "{scene_name}: object \"{}\"{}",
                        obj.name,
                        if flat {
                            " (flat shading: 3 vertices per triangle)"
                        } else {
                            ""
                        }
                    ),
                    size.vertices,
                    std::mem::size_of::<Vertex>(),
                    size.indices,
                    size.max_index,
                )?;
                let simplified = matches!(obj.desc, MeshDesc::Obj { .. } | MeshDesc::Gltf { .. });
                let chain = simplified.then(|| {
                    if let Some(c) = prepared.chain(&obj.mesh) {
                        return c.clone();
                    }
                    chains
                        .entry(key.0)
                        .or_insert_with(|| {
                            crate::scene::lod::chain_for(
                                &obj.mesh,
                                &format!("{scene_name}: object \"{}\"", obj.name),
                                lod_cache,
                                &mut lod_stats,
                                &mut |w| log::warn!("{w}"),
                            )
                        })
                        .clone()
                });
                let (data, levels) = lod_data(&obj.mesh, chain.as_deref(), flat);
                // The levels' own vertices and indices within the device's limits too.
                limits.check_mesh(
                    &format!("{scene_name}: object \"{}\" with its LOD levels", obj.name),
                    data.vertices.len(),
                    std::mem::size_of::<Vertex>(),
                    data.indices.len(),
                    data.vertices.len().saturating_sub(1) as u64,
                )?;
                let levels_full = levels[0].index_count;
                if data.indices.is_empty() {
                    continue;
                }
                let name = &obj.name;
                let vertices = uploader.buffer(
                    &format!("{name} vertices"),
                    bytemuck::cast_slice(&data.vertices),
                    vk::BufferUsageFlags::VERTEX_BUFFER,
                )?;
                // The optional vertex streams: flat shading's centroids, vertex colours.
                let mut stream = |what: &str, bytes: Option<&[u8]>| {
                    bytes
                        .map(|b| {
                            let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
                            uploader.buffer(&format!("{name} {what}"), b, usage)
                        })
                        .transpose()
                };
                let centroids = stream(
                    "centroids",
                    data.centroids.as_deref().map(bytemuck::cast_slice),
                )?;
                let colors = stream(
                    "vertex colours",
                    data.colors.as_deref().map(bytemuck::cast_slice),
                )?;
                let indices = uploader.buffer(
                    &format!("{name} indices"),
                    bytemuck::cast_slice(&data.indices),
                    vk::BufferUsageFlags::INDEX_BUFFER,
                )?;
                // Over every level's vertices: a simplified level's placed vertices may sit
                // (by at most its error) outside the mesh, and culling must not cut them off.
                let positions: Vec<glam::Vec3> = data
                    .vertices
                    .iter()
                    .map(|v| glam::Vec3::from_array(v.position))
                    .collect();
                let bounds = crate::scene::mesh::bounds_of(&positions);
                let tight = tight_sphere(&positions, bounds);
                list.shapes.push(draws::Shape {
                    sphere: super::super::frustum::sphere(bounds),
                    tight,
                    bounds,
                    plane: obj.mesh.flat_plane(),
                    levels: levels.into(),
                });
                meshes.push(GpuMesh {
                    vertices,
                    centroids,
                    colors,
                    indices,
                    // Fits: checked by `check_mesh` above.
                    index_count: levels_full,
                });
                mesh_cache.insert(key, meshes.len() - 1);
                meshes.len() - 1
            }
        };
        let named = &scene.materials[obj.material];
        let material = &named.material;
        let mut push = gpu::material_push(material);
        let (model, terms) = super::material_key(material);
        push.object_index = objects.len() as u32;
        push.receive_shadow = obj.shadow.receive as u32;
        push.double_sided = (named.textures.sides == Sides::Double) as u32;
        object_slots[object] = Some(push.object_index);
        if let Some(i) = ibl {
            push.flags = i.lut_layer(lut_geometry(material));
        }
        objects.push(gpu::object_data(obj.transform.matrix()));
        let closed = matches!(
            obj.desc,
            MeshDesc::Sphere { .. }
                | MeshDesc::Icosphere { .. }
                | MeshDesc::Cube { .. }
                | MeshDesc::Cone { .. }
                | MeshDesc::Cylinder { .. }
        );
        let positive = obj.transform.scale.min_element() > 0.0;
        let alpha = AlphaKey::of(named.textures.alpha_mode);
        let vertex_color = meshes[mesh_index].colors.is_some() && obj.shading == Shading::Phong;
        // The generic pipeline: every map and light kind, no fixed shadow slots.
        let generic_key = VariantKey {
            shading: ShadingKey::from_shading(obj.shading),
            model,
            fog: scene.fog.is_some(),
            debug,
            ibl: ibl_key,
            terms: TermsKey::Generic,
            maps: GENERIC_MAPS,
            light_kinds: GENERIC_LIGHT_KINDS,
            // Flat and Gouraud shade in the vertex stage, over every light.
            clustered: clustered && obj.shading == Shading::Phong,
            shadow_slots: [0; 4],
            alpha,
            vertex_color,
            lobes: super::variant::GENERIC_LOBES,
            refraction: scene.output.refraction,
        };
        let transmits = super::variant::lobe_bits(material)
            & crate::glsl::brdf_models::BRDF_LOBE_TRANSMISSION
            != 0;
        list.items.push(draws::Item {
            shape: mesh_index,
            object,
            material: obj.material,
            cull: culls(named.textures.sides, closed) && positive,
            blend: alpha == AlphaKey::Blend,
            transmit: transmits
                && alpha != AlphaKey::Blend
                && scene.output.refraction != crate::scene::Refraction::None,
        });
        draws.push(Draw {
            variant: if generic {
                generic_key
            } else {
                VariantKey {
                    terms,
                    maps: crate::render::material::map_bits(&named.textures),
                    light_kinds: gpu::scene_light_kinds(scene),
                    shadow_slots: crate::render::shadow::fixed_slots(&scene.lights),
                    lobes: super::variant::lobe_bits(material),
                    ..generic_key
                }
            },
            push,
            shadow_area: None,
        });
    }
    // One line for every mesh drawn whole because its simplification failed (issue 38).
    if let Some(line) = lod_stats.failure_summary() {
        log::warn!("{line}");
    }
    Ok(Draws {
        meshes,
        list,
        objects,
        draws,
        object_slots,
        lod_stats,
    })
}

/// The vertex and index data of `mesh` drawn smooth or `flat`, with every level of `chain` in
/// one index buffer and one vertex buffer (smooth: [`compact_levels`]; flat: each level gets its
/// own three vertices per triangle), and the levels' ranges (level 0 first, the full mesh).
fn lod_data(
    mesh: &crate::scene::Mesh,
    chain: Option<&crate::scene::lod::LodChain>,
    flat: bool,
) -> (mesh::MeshData, Vec<crate::scene::lod::LodLevel>) {
    use crate::scene::lod::LodLevel;
    let whole = |data: mesh::MeshData| {
        let level = LodLevel {
            first_index: 0,
            index_count: data.indices.len() as u32,
            error: 0.0,
        };
        (data, vec![level])
    };
    // OBJ and glTF meshes (they have a chain, one level when not simplified) drawn smooth: in
    // vertex fetch order, whole or not.
    if let (Some(chain), false) = (chain, flat) {
        return compact_levels(&smooth_with_moved(mesh, chain), chain);
    }
    let Some(chain) = chain.filter(|c| c.levels.len() > 1) else {
        return whole(if flat {
            mesh::flat(mesh)
        } else {
            mesh::smooth(mesh)
        });
    };
    let mut data = mesh::flat(mesh);
    let all = chain.vertices_of(mesh);
    let mut levels = vec![LodLevel {
        first_index: 0,
        index_count: data.indices.len() as u32,
        error: 0.0,
    }];
    for (i, l) in chain.levels.iter().enumerate().skip(1) {
        let level = crate::scene::Mesh {
            indices: chain.level_indices(i).to_vec(),
            ..all.as_ref().clone()
        };
        let part = mesh::flat(&level);
        let base = data.vertices.len() as u32;
        levels.push(LodLevel {
            first_index: data.indices.len() as u32,
            index_count: part.indices.len() as u32,
            error: l.error,
        });
        data.vertices.extend_from_slice(&part.vertices);
        if let (Some(c), Some(p)) = (&mut data.centroids, &part.centroids) {
            c.extend_from_slice(p);
        }
        data.indices.extend(part.indices.iter().map(|i| i + base));
    }
    (data, levels)
}

/// [`mesh::smooth`] of `mesh` with the vertices the simplifier moved for `chain`'s levels after
/// its own, each with the tangent and colour of the vertex it came from.
fn smooth_with_moved(
    mesh: &crate::scene::Mesh,
    chain: &crate::scene::lod::LodChain,
) -> mesh::MeshData {
    let mut data = mesh::smooth(mesh);
    let m = &chain.moved;
    for k in 0..m.len() {
        let origin = m.origin[k] as usize;
        let mut v = data.vertices[origin];
        v.position = m.positions[k].to_array();
        v.normal = m.normals[k].to_array();
        if let Some(uv) = m.uvs.get(k) {
            v.uv = uv.to_array();
        }
        data.vertices.push(v);
        if let Some(c) = &mut data.colors {
            c.push(c[origin]);
        }
    }
    data
}

/// Smooth levels, each with its own copy of the vertices it uses, in the order its (vertex cache
/// ordered) triangles first use them: meshoptimizer's vertex fetch order, one pass per level
/// (written here rather than `meshopt::optimize_vertex_fetch` per level, which would need a remap
/// per stream and per level: the vertex colours follow the same copy). lavapipe's vertex fetch
/// then reads each level's vertices nearly in sequence instead of scattered over the whole mesh,
/// the full mesh's too (an OBJ's vertex order is not its triangles'): on bunnies_40m, full detail
/// 4,757 → 4,069 ms and 0.2 px 507 → 473 ms (docs/performance.md). The vertex buffer holds about
/// twice the mesh's vertices (level 0 all of them, each coarser level about half the one before).
fn compact_levels(
    all: &mesh::MeshData,
    chain: &crate::scene::lod::LodChain,
) -> (mesh::MeshData, Vec<crate::scene::lod::LodLevel>) {
    let n = all.vertices.len();
    let mut data = mesh::MeshData {
        vertices: Vec::with_capacity(2 * n),
        centroids: None,
        colors: all.colors.as_ref().map(|_| Vec::with_capacity(2 * n)),
        indices: Vec::with_capacity(chain.indices.len()),
    };
    let mut levels = Vec::with_capacity(chain.levels.len());
    let mut slot = vec![u32::MAX; n];
    for (i, level) in chain.levels.iter().enumerate() {
        slot.fill(u32::MAX);
        let first_index = data.indices.len() as u32;
        for &v in chain.level_indices(i) {
            let s = &mut slot[v as usize];
            if *s == u32::MAX {
                *s = data.vertices.len() as u32;
                data.vertices.push(all.vertices[v as usize]);
                if let (Some(out), Some(c)) = (&mut data.colors, &all.colors) {
                    out.push(c[v as usize]);
                }
            }
            data.indices.push(*s);
        }
        levels.push(crate::scene::lod::LodLevel {
            first_index,
            index_count: data.indices.len() as u32 - first_index,
            error: level.error,
        });
    }
    (data, levels)
}

/// Whether a draw culls back faces: by the material's sides, else ([`Sides::Auto`], scene files)
/// when its primitive is closed.
fn culls(sides: Sides, closed: bool) -> bool {
    match sides {
        Sides::Auto => closed,
        Sides::Single => true,
        Sides::Double => false,
    }
}

/// The geometry term whose split-sum LUT layer a material reads (BRDF_G_*).
pub fn lut_geometry(m: &crate::brdf::Model) -> i32 {
    use crate::brdf::{Geometry, Model};
    match m {
        Model::CookTorrance(p) => p.geometry.for_split_sum() as i32,
        Model::MetalRough(p) => p.geometry.for_split_sum() as i32,
        // Principled's Gs is the separable Smith GGX (in visibility form).
        Model::Principled(_) => Geometry::SmithGgx as i32,
        _ => Geometry::SmithGgxCorrelated as i32,
    }
}

/// Whether a scene's materials need the anisotropic lobe's split sum in the LUT
/// (`brdf::aniso_lut_layers`): one of them has KHR_materials_anisotropy's lobe.
pub fn needs_aniso_lut(scene: &Scene) -> bool {
    scene.materials.iter().any(|m| {
        super::variant::lobe_bits(&m.material) & crate::glsl::brdf_models::BRDF_LOBE_ANISOTROPY != 0
    })
}

/// The LUT layers a scene's materials need.
pub fn lut_geometries(scene: &Scene) -> Vec<i32> {
    let mut g: Vec<i32> = scene
        .materials
        .iter()
        .map(|m| lut_geometry(&m.material))
        .collect();
    g.sort_unstable();
    g.dedup();
    g
}

impl Slot {
    pub(super) fn new(
        ctx: &Arc<Context>,
        pool: &DescriptorPool,
        layout: &DescriptorSetLayout,
        index: usize,
        (light_count, object_count, cells, draw_count): (usize, usize, usize, usize),
        (srgb_table, area_data): (&Buffer, &[glam::Vec4]),
    ) -> Result<Self, VkError> {
        let buffer = |name: &str, size: usize, usage| {
            Buffer::new(
                ctx,
                &format!("{name} (slot {index})"),
                size as u64,
                usage,
                MemoryLocation::CpuToGpu,
            )
        };
        let frame_ubo = buffer(
            "frame uniforms",
            std::mem::size_of::<gpu::FrameData>(),
            vk::BufferUsageFlags::UNIFORM_BUFFER,
        )?;
        let lights = buffer(
            "lights",
            light_count * std::mem::size_of::<GpuLight>(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let mut area = buffer(
            "area lights and LTC table",
            std::mem::size_of_val(area_data),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        area.write(0, bytemuck::cast_slice(area_data))?;
        let objects = buffer(
            "objects",
            object_count * std::mem::size_of::<gpu::ObjectData>(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let set = pool.allocate(layout)?;
        let deferred_materials = buffer(
            "deferred materials",
            object_count * std::mem::size_of::<gpu::DeferredMaterial>(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let clusters = buffer(
            "light clusters",
            std::mem::size_of::<ClusterHeader>() + cells.max(1) * 8,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let cluster_lights = buffer(
            "cluster light indices",
            4,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let instances = buffer(
            "instance objects",
            draw_count.max(1) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let writes = [
            (gpu::BINDING_FRAME, &frame_ubo),
            (gpu::BINDING_LIGHTS, &lights),
            (gpu::BINDING_OBJECTS, &objects),
            (gpu::BINDING_SRGB_TABLE, srgb_table),
            (gpu::BINDING_DEFERRED_MATERIALS, &deferred_materials),
            (gpu::BINDING_CLUSTERS, &clusters),
            (gpu::BINDING_CLUSTER_LIGHTS, &cluster_lights),
            (gpu::BINDING_INSTANCES, &instances),
            (gpu::BINDING_AREA, &area),
        ]
        .into_iter()
        .fold(SetWrites::new(layout, set), |w, (binding, b)| {
            w.buffer(binding, b.raw)
        });
        // SAFETY: `set` was just allocated and is not in use by any command buffer; the writes'
        // buffers are live and of the usages the bindings need.
        unsafe { writes.apply(ctx) }?;
        Ok(Self {
            frame_ubo,
            lights,
            objects,
            deferred_materials,
            clusters,
            cluster_lights,
            instances,
            area,
            set,
            view: ColorView::default(),
        })
    }

    /// Writes `c` into the slot's cluster buffers, growing the index list (a new buffer, the set
    /// rewritten) when it does not fit. The slot must not be in use by the GPU.
    pub(super) fn write_clusters(
        &mut self,
        (ctx, layout): (&Arc<Context>, &DescriptorSetLayout),
        index: usize,
        c: &Clusters,
    ) -> Result<(), VkError> {
        let header = std::mem::size_of::<ClusterHeader>();
        let sizes = [
            (header + (c.cells.len() + c.area_cells.len()) * 8) as u64,
            (c.indices.len().max(1) * 4) as u64,
        ];
        for (which, bytes) in sizes.into_iter().enumerate() {
            let (buffer, name, binding) = if which == 0 {
                (&mut self.clusters, "light clusters", gpu::BINDING_CLUSTERS)
            } else {
                (
                    &mut self.cluster_lights,
                    "cluster light indices",
                    gpu::BINDING_CLUSTER_LIGHTS,
                )
            };
            if bytes <= buffer.size {
                continue;
            }
            *buffer = Buffer::new(
                ctx,
                &format!("{name} (slot {index})"),
                bytes.next_power_of_two(),
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::CpuToGpu,
            )?;
            let writes = SetWrites::new(layout, self.set).buffer(binding, buffer.raw);
            // SAFETY: the slot (and so its set) is not in use by any pending command buffer (the
            // caller's contract); the new buffer is live, a storage buffer, kept in the slot as
            // long as the set refers to it.
            unsafe { writes.apply(ctx) }?;
        }
        self.clusters.write(0, bytemuck::bytes_of(&c.header))?;
        self.clusters
            .write(header as u64, bytemuck::cast_slice(&c.cells))?;
        if !c.area_cells.is_empty() {
            self.clusters.write(
                (header + c.cells.len() * 8) as u64,
                bytemuck::cast_slice(&c.area_cells),
            )?;
        }
        if !c.indices.is_empty() {
            self.cluster_lights
                .write(0, bytemuck::cast_slice(&c.indices))?;
        }
        Ok(())
    }
}

/// The centre of the bounds `(lo, hi)` of `positions` and the distance from it to the farthest
/// one: a bounding sphere as tight as the box's allows (a sphere mesh's own radius, where the
/// box's corner sphere is √3 times larger).
fn tight_sphere(positions: &[glam::Vec3], (lo, hi): (glam::Vec3, glam::Vec3)) -> (glam::Vec3, f32) {
    let c = (lo + hi) * 0.5;
    let r = positions
        .iter()
        .map(|p| (*p - c).length())
        .fold(0.0f32, f32::max);
    (c, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Culling bounds hold every level: the simplifier places some of a coarse sphere's vertices
    /// outside the unit sphere (so its flat triangles follow the surface on average), beyond
    /// the mesh's own tight sphere; the bounds over the levels' vertices contain them all.
    #[test]
    fn bounds_hold_the_placed_vertices() {
        let m = crate::scene::Mesh::sphere(1.0, 96, 48);
        let chain = crate::scene::lod::build(&m).unwrap();
        let (data, _) = lod_data(&m, Some(&chain), false);
        let own = tight_sphere(&m.positions, m.bounds());
        assert!((own.1 - 1.0).abs() < 1e-5, "{own:?}");
        let positions: Vec<glam::Vec3> = data
            .vertices
            .iter()
            .map(|v| glam::Vec3::from_array(v.position))
            .collect();
        let (centre, radius) = tight_sphere(&positions, crate::scene::mesh::bounds_of(&positions));
        let outside = chain
            .moved
            .positions
            .iter()
            .filter(|p| (**p - own.0).length() > own.1 + 1e-4)
            .count();
        assert!(outside > 0, "no placed vertex outside the mesh's sphere");
        for p in &positions {
            assert!((*p - centre).length() <= radius * (1.0 + 1e-6), "{p}");
        }
        assert_eq!(
            crate::scene::mesh::bounds_of(&[]),
            (glam::Vec3::ZERO, glam::Vec3::ZERO)
        );
    }

    /// Flat shading draws each simplified level's triangles on the simplifier's placed vertices
    /// (three corners per triangle, the face normal), level 0 on the mesh's own.
    #[test]
    fn flat_levels_draw_the_placed_vertices() {
        let m = crate::scene::Mesh::sphere(1.0, 96, 48);
        let chain = crate::scene::lod::build(&m).unwrap();
        assert!(!chain.moved.is_empty());
        let all = chain.vertices_of(&m);
        let (data, levels) = lod_data(&m, Some(&chain), true);
        assert_eq!(levels.len(), chain.levels.len());
        // Level 0 in the mesh's own triangle order, the others in the chain's.
        assert_eq!(levels[0].index_count as usize, m.indices.len());
        for (i, l) in levels.iter().enumerate().skip(1) {
            let ours = &data.indices[l.first_index as usize..][..l.index_count as usize];
            let theirs = chain.level_indices(i);
            assert_eq!(ours.len(), theirs.len(), "level {i}");
            for (t, (a, b)) in ours.chunks(3).zip(theirs.chunks(3)).enumerate() {
                let p = [0, 1, 2].map(|k| all.positions[b[k] as usize]);
                let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                for k in 0..3 {
                    let v = data.vertices[a[k] as usize];
                    assert_eq!(v.position, p[k].to_array(), "level {i} triangle {t}");
                    let n = glam::Vec3::from_array(v.normal);
                    assert!(
                        face == glam::Vec3::ZERO || n.dot(face) > 0.9999,
                        "level {i}"
                    );
                }
            }
        }
    }

    /// Every level draws the same corners as the chain's indices into the mesh (same vertex data,
    /// same order), from its own vertices, numbered in the order its triangles first use them.
    #[test]
    fn compacted_levels_draw_the_chain_from_their_own_vertices_in_fetch_order() {
        let mut m = crate::scene::Mesh::sphere(1.0, 96, 48);
        // Vertex colours follow their vertices.
        m.colors = m
            .positions
            .iter()
            .map(|p| glam::Vec4::new(p.x, p.y, p.z, 1.0))
            .collect();
        let chain = crate::scene::lod::build(&m).unwrap();
        assert!(chain.levels.len() > 3);
        let all = smooth_with_moved(&m, &chain);
        let n = m.positions.len();
        assert_eq!(all.vertices.len(), n + chain.moved.len());
        // The placed vertices: the simplifier's positions and normals, their origin's colour and
        // tangent.
        let own = mesh::smooth(&m);
        for (k, &o) in chain.moved.origin.iter().enumerate() {
            let (v, from) = (all.vertices[n + k], own.vertices[o as usize]);
            assert_eq!(v.position, chain.moved.positions[k].to_array());
            assert_eq!(v.normal, chain.moved.normals[k].to_array());
            assert_eq!(v.tangent, from.tangent);
            assert_eq!(
                all.colors.as_ref().unwrap()[n + k],
                m.colors[o as usize].to_array()
            );
        }
        let (data, levels) = compact_levels(&all, &chain);
        assert_eq!(levels.len(), chain.levels.len());
        let colors = data.colors.as_ref().unwrap();
        assert_eq!(colors.len(), data.vertices.len());
        let mut next = 0u32;
        for (i, l) in levels.iter().enumerate() {
            assert_eq!(l.error, chain.levels[i].error);
            let range = l.first_index as usize..(l.first_index + l.index_count) as usize;
            let ours = &data.indices[range];
            let theirs = chain.level_indices(i);
            assert_eq!(ours.len(), theirs.len(), "level {i}");
            for (&a, &b) in ours.iter().zip(theirs) {
                assert_eq!(
                    data.vertices[a as usize], all.vertices[b as usize],
                    "level {i}"
                );
                assert_eq!(colors[a as usize], all.colors.as_ref().unwrap()[b as usize]);
                // First use order: a new vertex is the next one; a seen one is earlier.
                assert!(a <= next, "level {i}: index {a} before {next}");
                if a == next {
                    next += 1;
                }
            }
            // Each level's vertices follow the previous level's, none unused.
            let used: std::collections::HashSet<u32> = ours.iter().copied().collect();
            assert_eq!(
                used.len() as u32,
                next - ours.iter().min().copied().unwrap()
            );
        }
        assert_eq!(next as usize, data.vertices.len());
        // About twice the mesh's vertices (the coarse levels keep a little more than half).
        assert!(
            data.vertices.len() * 2 <= n * 5,
            "{} vertices for {n}: {:?}",
            data.vertices.len(),
            levels.iter().map(|l| l.index_count).collect::<Vec<_>>()
        );
    }
}
