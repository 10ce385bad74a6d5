//! The CPU half of building a renderer for a scene, done before any Vulkan object exists:
//! every OBJ and glTF mesh's LOD chain (built, or read from the LOD cache) and every material
//! map decoded with its mip chain. Independent items run in parallel (rayon) and report
//! progress; the GPU passes then only upload what [`PreparedScene`] holds.
//!
//! A prepared scene is also a cache across edits: [`prepare_again`] keeps the chains of meshes
//! and the maps of texture files the edited scene still uses and prepares only what is new, so
//! an edit that needs new pipelines does no CPU work again.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use rayon::prelude::*;

use crate::progress::{Progress, Reporting};
use crate::scene::lod::{self, ChainStats, LodChain};
use crate::scene::mesh::Mesh;
use crate::scene::{MeshDesc, Scene, TextureRef, TextureSlot};
use crate::texture::{ColorSpace, TextureData};

/// What preparation needs to know besides the scene.
#[derive(Debug, Clone, Default)]
pub struct PrepareOptions {
    /// Keep meshes' LOD chains here between runs (`None`: build them every time).
    pub lod_cache: Option<PathBuf>,
    /// Textures larger than this per side are downscaled (the device's
    /// `maxImageDimension2D`; 0: [`crate::imageio::MAX_DIMENSION`]).
    pub max_texture_dimension: u32,
}

/// A texture as decoded: its file (or embedded image), the channel, encoding and mips asked
/// for, and the size limit it was decoded under.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct TextureKey {
    path: PathBuf,
    /// The embedded image's address (kept alive by [`PreparedTexture::source`]).
    embedded: Option<usize>,
    channel: Option<u8>,
    space: ColorSpace,
    mipmaps: bool,
    max_dimension: u32,
}

impl TextureKey {
    fn of(r: &TextureRef, space: ColorSpace, max_dimension: u32) -> Self {
        Self {
            path: r.path.clone(),
            embedded: r.embedded.as_ref().map(|b| b.as_ptr() as usize),
            channel: r.channel,
            space,
            mipmaps: r.sampler.mipmaps,
            max_dimension,
        }
    }
}

#[derive(Debug)]
struct PreparedTexture {
    data: Arc<TextureData>,
    /// Holds the embedded bytes whose address is part of the key.
    _source: Option<Arc<[u8]>>,
}

/// The CPU work of a scene, ready to upload (see the module documentation).
#[derive(Debug, Default)]
pub struct PreparedScene {
    /// By mesh address; the meshes are held so no address is reused while the chain is kept.
    chains: HashMap<usize, (Arc<Mesh>, Arc<LodChain>)>,
    textures: HashMap<TextureKey, PreparedTexture>,
    max_texture_dimension: u32,
    /// What the LOD chains took: built now, read from the cache, failed.
    pub lod_stats: ChainStats,
    /// Warnings to show once (a texture downscaled, a damaged cache entry).
    pub warnings: Vec<String>,
}

/// A map that cannot be decoded: the material, the map and the reason (which names the file).
#[derive(Debug, Clone, thiserror::Error)]
#[error("material \"{material}\": {reason}")]
pub struct PrepareError {
    pub material: String,
    pub slot: TextureSlot,
    pub reason: String,
}

/// Does the CPU work of `scene` (see the module documentation).
pub fn prepare(
    scene: &Scene,
    options: &PrepareOptions,
    progress: Option<&dyn Progress>,
) -> Result<PreparedScene, PrepareError> {
    prepare_again(PreparedScene::default(), scene, options, progress)
}

/// As [`prepare`], reusing what `old` holds that `scene` still uses; what it no longer uses is
/// dropped.
pub fn prepare_again(
    mut old: PreparedScene,
    scene: &Scene,
    options: &PrepareOptions,
    progress: Option<&dyn Progress>,
) -> Result<PreparedScene, PrepareError> {
    let max_dim = match options.max_texture_dimension {
        0 => crate::imageio::MAX_DIMENSION,
        d => d,
    };
    // The meshes with LOD chains (OBJ and glTF; primitives keep their tessellation), once each.
    let mut meshes: Vec<(usize, &Arc<Mesh>, String)> = Vec::new();
    for o in &scene.objects {
        if !matches!(o.desc, MeshDesc::Obj { .. } | MeshDesc::Gltf { .. }) {
            continue;
        }
        let key = Arc::as_ptr(&o.mesh) as usize;
        if !meshes.iter().any(|(k, _, _)| *k == key) {
            let name = format!("{}: object \"{}\"", scene.display_name(), o.name);
            meshes.push((key, &o.mesh, name));
        }
    }
    // The maps, once per (file, channel, encoding, mips).
    let mut maps: Vec<(TextureKey, &TextureRef, ColorSpace, &str, TextureSlot)> = Vec::new();
    for m in &scene.materials {
        for slot in TextureSlot::ALL {
            let Some(r) = m.textures.get(slot) else {
                continue;
            };
            let space = ColorSpace::for_slot(slot);
            let key = TextureKey::of(r, space, max_dim);
            if !maps.iter().any(|(k, ..)| *k == key) {
                maps.push((key, r, space, m.name.as_str(), slot));
            }
        }
    }
    let mut prepared = PreparedScene {
        max_texture_dimension: max_dim,
        ..PreparedScene::default()
    };
    let new_meshes: Vec<_> = meshes
        .into_iter()
        .filter(|(key, mesh, _)| match old.chains.remove(key) {
            Some(kept) if Arc::ptr_eq(&kept.0, mesh) => {
                prepared.chains.insert(*key, kept);
                false
            }
            _ => true,
        })
        .collect();
    let new_maps: Vec<_> = maps
        .into_iter()
        .filter(|(key, ..)| match old.textures.remove(key) {
            Some(kept) => {
                prepared.textures.insert(key.clone(), kept);
                false
            }
            None => true,
        })
        .collect();
    let total = (new_meshes.len() + new_maps.len()) as u64;
    let report = Reporting(progress);
    let done = std::sync::atomic::AtomicU64::new(0);
    let step = |stage: &str| {
        let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        report.update(stage, n, total);
    };
    if total > 0 {
        report.update("scene: LOD chains and textures", 0, total);
    }
    let lod_cache = options.lod_cache.as_deref();
    let chain_of = |(key, mesh, name): &(usize, &Arc<Mesh>, String)| {
        let mut stats = ChainStats::default();
        let mut warnings = Vec::new();
        let chain = lod::chain_for(mesh, name, lod_cache, &mut stats, &mut |w| warnings.push(w));
        step("scene: LOD chains");
        (*key, Arc::clone(*mesh), chain, stats, warnings)
    };
    // Meshes placed by nodes share one local form and so one cache entry: the first of each local
    // form is simplified first (in parallel with the other local forms), then the rest read it
    // from the cache, as one after the other would (the stats say "1 built, 999 read").
    let local_of = |mesh: &Arc<Mesh>| match &mesh.placed {
        Some(placed) => Arc::as_ptr(&placed.local) as usize,
        None => Arc::as_ptr(mesh) as usize,
    };
    let mut seen = std::collections::HashSet::new();
    let (first, rest): (Vec<_>, Vec<_>) = new_meshes
        .into_iter()
        .enumerate()
        .partition(|(_, (_, mesh, _))| seen.insert(local_of(mesh)));
    let mut chains: Vec<_> = first.par_iter().map(|(i, m)| (*i, chain_of(m))).collect();
    chains.extend(
        rest.par_iter()
            .map(|(i, m)| (*i, chain_of(m)))
            .collect::<Vec<_>>(),
    );
    chains.sort_by_key(|(i, _)| *i);
    let chains = chains.into_iter().map(|(_, c)| c);
    let textures: Vec<_> = new_maps
        .par_iter()
        .map(|(key, r, space, material, slot)| {
            let mut warnings = Vec::new();
            let data = crate::texture::load_texture(r, *space, max_dim, &mut |w| warnings.push(w))
                .map_err(|e| PrepareError {
                    material: material.to_string(),
                    slot: *slot,
                    reason: e.to_string(),
                });
            step("scene: textures");
            (key.clone(), r.embedded.clone(), data, warnings)
        })
        .collect();
    // In the scene's order, so stats and warnings read the same on every run.
    for (key, mesh, chain, stats, warnings) in chains {
        prepared.lod_stats.built += stats.built;
        prepared.lod_stats.loaded += stats.loaded;
        prepared.lod_stats.failed += stats.failed;
        prepared.lod_stats.failures.extend(stats.failures);
        prepared.warnings.extend(warnings);
        prepared.chains.insert(key, (mesh, chain));
    }
    for (key, source, data, warnings) in textures {
        prepared.warnings.extend(warnings);
        prepared.textures.insert(
            key,
            PreparedTexture {
                data: Arc::new(data?),
                _source: source,
            },
        );
    }
    Ok(prepared)
}

impl PreparedScene {
    /// The LOD chain of `mesh` (`None`: not an OBJ or glTF mesh of the prepared scene).
    pub fn chain(&self, mesh: &Arc<Mesh>) -> Option<&Arc<LodChain>> {
        self.chains
            .get(&(Arc::as_ptr(mesh) as usize))
            .filter(|(m, _)| Arc::ptr_eq(m, mesh))
            .map(|(_, c)| c)
    }

    /// The decoded map `r` of a map in `slot` (`None`: not a map of the prepared scene).
    pub fn texture(&self, r: &TextureRef, slot: TextureSlot) -> Option<&Arc<TextureData>> {
        let key = TextureKey::of(r, ColorSpace::for_slot(slot), self.max_texture_dimension);
        self.textures.get(&key).map(|t| &t.data)
    }

    /// Drops the decoded maps (after their upload: a renderer that keeps its prepared scene for
    /// the next edit keeps the LOD chains, not a second copy of every texture).
    pub fn forget_textures(&mut self) {
        self.textures.clear();
    }

    /// How many LOD chains and decoded maps it holds.
    pub fn counts(&self) -> (usize, usize) {
        (self.chains.len(), self.textures.len())
    }

    /// The texture size limit the maps were decoded under.
    pub fn max_texture_dimension(&self) -> u32 {
        self.max_texture_dimension
    }
}

#[cfg(test)]
#[path = "prepare_tests.rs"]
mod tests;
