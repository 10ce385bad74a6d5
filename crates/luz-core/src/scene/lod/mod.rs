//! Automatic level of detail for meshes (OBJ and glTF): a chain of simplified index buffers per
//! mesh, built once when a scene is prepared for drawing, each level with the geometric error the
//! simplifier reports, and a per-frame choice of the coarsest level whose error, projected to
//! pixels at the object's distance, stays within `output.tessellation_error_px`: the budget that
//! also drives automatic tessellation of spheres, cones and cylinders
//! ([`super::tessellation`]). A budget of 0 draws every mesh whole.
//!
//! **Simplifier.** meshoptimizer (the `meshopt` crate, 0.7), `meshopt_simplifyWithUpdate`:
//! - it collapses edges like `meshopt_simplifyWithAttributes` and then *places* each kept vertex,
//!   its normal and its UV where the level's quadric error is least, instead of leaving them where
//!   the mesh had them. A coarse level's vertices sit slightly off the full surface so that its
//!   flat triangles follow it on average, and their normals average the relief they replace.
//!   Against the kept vertices, at the same triangles drawn at each budget, mean FLIP against
//!   full detail falls by 24–26 % on bunnies_40m (0.2–0.5 px) and by 8–24 % on bunnies_lab
//!   (0.1–2 px) (docs/performance.md, "Placed vertices"). Each simplified level has its own
//!   vertices ([`MovedVertices`], after the mesh's); placed normals are renormalised, colours and
//!   tangents come from the vertex each placed one replaces;
//! - attribute-aware: the vertex normals (weight [`NORMAL_WEIGHT`]) and UVs ([`UV_WEIGHT`]) are
//!   part of the quadric error, so shading and texture layout are kept where they vary; vertices
//!   split at a normal or UV seam (same position, other attributes) are collapsed only along the
//!   seam and placed together, so seams stay closed (meshoptimizer's default, we do not pass
//!   `Permissive`);
//! - `LockBorder`: vertices on an open border do not move. Parts of one model (an OBJ's groups, a
//!   glTF's primitives) are separate objects whose levels are chosen independently; a moving
//!   border would open cracks between them. Closed meshes have no border and lose nothing;
//! - `ErrorAbsolute`: the reported error is in the mesh's own units (object space), scaled to the
//!   world by the object's largest scale factor before projection;
//! - `ErrorClamped` keeps the attribute share of the error at the position error's scale, so the
//!   figure stays a distance that can be projected to pixels.
//!
//! Other normal weights, meshopt's `Regularize`, `RegularizeLight`, `Prune`, `PreserveFolds` and
//! `Permissive`, smoothed normals as the attribute and rescaled level errors were measured against
//! these on the triangles-against-FLIP curve (docs/performance.md, "Simplifier settings against
//! image quality per triangle", with the kept vertices): none made better triangles; the ones that
//! helped bunnies_40m only moved triangles from far objects to near ones, and hurt the bunnies_lab
//! scene as much.
//!
//! Every level is simplified from the full mesh (not from the previous level), so its error is
//! measured against what the scene file holds; errors are made non-decreasing along the chain.
//! A chain holds the levels' index buffers (about 1× the full index buffer in total at a ratio of
//! 1/2 per level) and their placed vertices (about 1× the mesh's vertices). On the GPU each level
//! draws its own vertices in the order it first uses them (`compact_levels` in
//! `src/render/forward/build.rs`: about 2× the mesh's vertices, for vertex fetches in sequence).
//!
//! Each level, the full mesh's too, is then reordered by `meshopt_optimizeVertexCache` (same
//! triangles and winding): lavapipe runs the vertex shader once per index that misses its small
//! vertex cache, and the simplifier's output order misses often (measured on bunnies_40m:
//! docs/performance.md).
//!
//! **Any mesh, in bounded time** ([`prepare`], issue 38). The simplifier is given the mesh's
//! vertices welded where they are exact copies (exported glTF often gives every triangle its own
//! vertices, which meshopt sees as seams everywhere), without degenerate triangles, with fans of
//! more than [`MAX_VALENCE`] triangles around one position kept whole in every level (meshopt's
//! edge lookups are quadratic in a vertex's valence), and at most [`SIMPLIFY_BUDGET`] triangles
//! per chain. When the first level still cannot be reduced, it may collapse across normal seams
//! (UV seams protected), then move open borders within the level's error. A mesh that still
//! cannot be simplified is drawn whole; [`ChainStats::failure_summary`] reports all such meshes
//! in one line.
//!
//! **Cache.** Chains are kept on disk ([`cache`]) under the IBL cache directory, keyed by a hash
//! of the mesh's contents and the simplifier settings (for a mesh placed by a glTF node, of its
//! local form: [`super::mesh::Placed`]; the chain is simplified there and its vertices and errors
//! are then carried through the node's transform, so that 1,000 nodes placing one mesh share one
//! file), with a CRC-32 over the file checked on
//! load: a damaged (also empty or zeroed) file gives one warning and is rebuilt. Failures are
//! cached too. The folder's size cap, temporary files and warnings: `files::cache_dir`.

use std::sync::Arc;

use glam::Vec3;

use super::{Camera, Mesh};

pub mod cache;
mod prepare;

use prepare::Prepared;
pub use prepare::{AREA_EPSILON, MAX_VALENCE};

/// Bumped whenever [`build`] would make other levels for the same mesh (settings, algorithm,
/// the meshopt version), so old cache files stop matching.
pub const LOD_VERSION: u32 = 4;
/// Triangles of each level relative to the previous one (its target).
pub const LEVEL_RATIO: f32 = 0.5;
/// At most this many levels after the full mesh.
pub const MAX_LEVELS: usize = 10;
/// A chain stops once a level has fewer triangles than this.
pub const MIN_TRIANGLES: usize = 64;
/// Meshes with fewer triangles than this are not simplified (nothing to gain).
pub const MIN_SIMPLIFIED_TRIANGLES: usize = 2 * MIN_TRIANGLES;
/// Triangles a chain may give the simplifier in all (each level is simplified from the full
/// mesh, so about the mesh's triangles times its levels): a chain stops before a level that would
/// pass it, and a mesh larger than this is drawn whole. About 15 s of simplification on one core.
pub const SIMPLIFY_BUDGET: usize = 1 << 24;
/// Weight of each normal component in the simplifier's error (normals are unit vectors).
pub const NORMAL_WEIGHT: f32 = 0.5;
/// Weight of each UV component in the simplifier's error.
pub const UV_WEIGHT: f32 = 0.5;

/// One level of a chain: a range of [`LodChain::indices`] and its error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LodLevel {
    pub first_index: u32,
    pub index_count: u32,
    /// The simplifier's error against the full mesh, in the mesh's units (0 for level 0).
    pub error: f32,
}

impl LodLevel {
    pub fn triangles(&self) -> u64 {
        u64::from(self.index_count / 3)
    }
}

/// A mesh's levels: level 0 is the mesh itself, each next one coarser. `indices` holds every
/// level's index buffer one after the other (level 0's first: the mesh's own triangles, in vertex
/// cache order when simplified), into the mesh's vertices followed by `moved`
/// ([`LodChain::vertices_of`]): level 0 uses the mesh's, each simplified level its own.
#[derive(Debug, Clone, PartialEq)]
pub struct LodChain {
    pub indices: Vec<u32>,
    pub levels: Vec<LodLevel>,
    /// Vertices the simplifier moved, after the mesh's own: index `n + k` (n: the mesh's vertex
    /// count) is `moved`'s vertex k.
    pub moved: MovedVertices,
}

/// The simplified levels' own vertices: where `meshopt_simplifyWithUpdate` put them, each with
/// the mesh vertex it came from (`origin`: its colour and tangent).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MovedVertices {
    pub origin: Vec<u32>,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// Empty when the mesh has no UVs.
    pub uvs: Vec<glam::Vec2>,
}

impl MovedVertices {
    pub fn len(&self) -> usize {
        self.origin.len()
    }

    pub fn is_empty(&self) -> bool {
        self.origin.is_empty()
    }

    fn append(&mut self, mut other: MovedVertices) {
        self.origin.append(&mut other.origin);
        self.positions.append(&mut other.positions);
        self.normals.append(&mut other.normals);
        self.uvs.append(&mut other.uvs);
    }
}

impl LodChain {
    /// The chain of the mesh alone (no simplified level).
    pub fn full(mesh: &Mesh) -> Self {
        LodChain {
            indices: mesh.indices.clone(),
            levels: vec![LodLevel {
                first_index: 0,
                index_count: mesh.indices.len() as u32,
                error: 0.0,
            }],
            moved: MovedVertices::default(),
        }
    }

    /// `mesh` with the moved vertices after its own (colours and tangents from their origin):
    /// the vertices every level's indices refer to.
    pub fn vertices_of<'a>(&self, mesh: &'a Mesh) -> std::borrow::Cow<'a, Mesh> {
        if self.moved.is_empty() {
            return std::borrow::Cow::Borrowed(mesh);
        }
        let m = &self.moved;
        let mut out = mesh.clone();
        out.positions.extend_from_slice(&m.positions);
        out.normals.extend_from_slice(&m.normals);
        if !mesh.uvs.is_empty() {
            out.uvs.extend_from_slice(&m.uvs);
        }
        if mesh.colors.len() == mesh.positions.len() {
            out.colors
                .extend(m.origin.iter().map(|&o| mesh.colors[o as usize]));
        }
        if mesh.tangents.len() == mesh.positions.len() {
            out.tangents
                .extend(m.origin.iter().map(|&o| mesh.tangents[o as usize]));
        }
        std::borrow::Cow::Owned(out)
    }

    /// Puts level `i`'s triangles (of a mesh of `vertex_count` vertices) in the order
    /// meshoptimizer's vertex cache optimiser picks (same triangles, same winding): lavapipe runs
    /// the vertex shader once per index that misses its small cache of recent vertices.
    ///
    /// The optimiser's time is quadratic in a vertex's valence (it rescores every triangle of a
    /// vertex each time one of them is emitted): triangles at a vertex of more than
    /// [`MAX_VALENCE`] triangles (a fan) keep their order, after the others.
    pub(crate) fn cache_order(&mut self, i: usize, vertex_count: usize) {
        let l = self.levels[i];
        let range = l.first_index as usize..(l.first_index + l.index_count) as usize;
        let level = &mut self.indices[range];
        let mut valence = vec![0u32; vertex_count];
        level.iter().for_each(|&v| valence[v as usize] += 1);
        if valence.iter().all(|&n| n as usize <= MAX_VALENCE) {
            meshopt::optimize_vertex_cache_in_place(level, vertex_count);
            return;
        }
        let (mut rest, fans): (Vec<[u32; 3]>, Vec<[u32; 3]>) = level
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .partition(|t| {
                t.iter()
                    .all(|&v| valence[v as usize] as usize <= MAX_VALENCE)
            });
        meshopt::optimize_vertex_cache_in_place(rest.as_flattened_mut(), vertex_count);
        level.copy_from_slice(&[rest, fans].concat().concat());
    }

    /// Level `i`'s indices.
    pub fn level_indices(&self, i: usize) -> &[u32] {
        let l = self.levels[i];
        &self.indices[l.first_index as usize..(l.first_index + l.index_count) as usize]
    }

    /// The levels' errors, from level 0.
    pub fn errors(&self) -> Vec<f32> {
        self.levels.iter().map(|l| l.error).collect()
    }
}

/// Whether `mesh` can be simplified at all: finite positions and normals, indices in range, whole
/// triangles; the reason when not.
fn check(mesh: &Mesh) -> Result<(), String> {
    if !mesh.indices.len().is_multiple_of(3) {
        return Err(format!(
            "{} indices is not a whole number of triangles",
            mesh.indices.len()
        ));
    }
    let n = mesh.positions.len();
    if let Some(i) = mesh.indices.iter().find(|&&i| i as usize >= n) {
        return Err(format!("index {i} is beyond its {n} vertices"));
    }
    if mesh.positions.iter().any(|p| !p.is_finite()) {
        return Err("a vertex position is not finite (NaN or infinite)".into());
    }
    if mesh.normals.len() != n || mesh.normals.iter().any(|v| !v.is_finite()) {
        return Err("normals are missing or not finite".into());
    }
    if !mesh.uvs.is_empty() && (mesh.uvs.len() != n || mesh.uvs.iter().any(|v| !v.is_finite())) {
        return Err("UVs are not one finite pair per vertex".into());
    }
    Ok(())
}

/// Builds the chain of `mesh`. `Err(reason)` when it cannot be simplified (non-finite data,
/// indices out of range, nothing but degenerate triangles, a simplifier that cannot reduce it,
/// more triangles than [`SIMPLIFY_BUDGET`]): draw it whole.
///
/// The simplifier works on [`prepare`]'s input (exact copies welded, degenerate triangles
/// dropped, fans beyond [`prepare::MAX_VALENCE`] set aside and kept whole in every level), so its
/// time stays in proportion to the triangles whatever the mesh. When the first level cannot be
/// reduced on a mesh with seams (every vertex a copy on a hard edge, say), it tries once more
/// allowed across normal seams, with UV seams protected (meshopt's `Permissive` with `Protect`).
pub fn build(mesh: &Mesh) -> Result<LodChain, String> {
    check(mesh)?;
    let mut chain = LodChain::full(mesh);
    let triangles = mesh.indices.len() / 3;
    if triangles < MIN_SIMPLIFIED_TRIANGLES {
        chain.cache_order(0, mesh.positions.len());
        return Ok(chain);
    }
    if triangles > SIMPLIFY_BUDGET {
        return Err(format!(
            "{triangles} triangles is beyond the simplifier's budget of {SIMPLIFY_BUDGET} per mesh"
        ));
    }
    let prepared = prepare::prepare(mesh);
    if prepared.mesh.indices.is_empty() && prepared.set_aside.is_empty() {
        return Err(format!(
            "all {triangles} triangles are degenerate (no area)"
        ));
    }
    let mut simplifier = Simplifier::new(&prepared);
    let set_aside = prepared.set_aside.len() / 3;
    let mut previous = triangles;
    let mut error_so_far = 0.0f32;
    // Triangles given to meshopt so far: each level is simplified from the full mesh.
    let mut work = 0usize;
    while chain.levels.len() <= MAX_LEVELS && previous >= MIN_TRIANGLES {
        let target = ((previous as f32 * LEVEL_RATIO) as usize).max(1);
        let input = prepared.mesh.indices.len() / 3;
        if work + input > SIMPLIFY_BUDGET {
            break;
        }
        work += input;
        let (mut level, mut error) = simplifier.level(target.saturating_sub(set_aside) * 3);
        let mut count = level.indices.len() / 3 + set_aside;
        let stalled = |count: usize| count as f32 > previous as f32 * 0.9;
        // The first level could not be reduced: allowed across normal seams, then (a mesh that is
        // all border, an open band) its border allowed to move within the level's error.
        while stalled(count) && chain.levels.len() == 1 && simplifier.relax() {
            work += input;
            (level, error) = simplifier.level(target.saturating_sub(set_aside) * 3);
            count = level.indices.len() / 3 + set_aside;
        }
        if count == 0 {
            if chain.levels.len() == 1 {
                return Err("the simplifier removed every triangle (a degenerate mesh?)".into());
            }
            break;
        }
        if !error.is_finite() || error < 0.0 {
            return Err(format!("the simplifier reported the error {error}"));
        }
        // Stalled (borders, seams): another level would cost memory and gain nothing.
        if stalled(count) {
            if chain.levels.len() == 1 {
                let fans = if set_aside > 0 {
                    format!(", {set_aside} of them in fans kept whole")
                } else {
                    String::new()
                };
                return Err(format!(
                    "the simplifier could not reduce it: {count} of {triangles} triangles \
                     left{fans} (non-manifold?)"
                ));
            }
            break;
        }
        if level.moved.positions.iter().any(|p| !p.is_finite()) {
            return Err("the simplifier moved a vertex to a non-finite position".into());
        }
        // The level's vertices follow the mesh's and the levels' before it; the fans set aside
        // use the mesh's own.
        let base = (mesh.positions.len() + chain.moved.len()) as u32;
        level.indices.iter_mut().for_each(|i| *i += base);
        level.indices.extend_from_slice(&prepared.set_aside);
        chain.moved.append(level.moved);
        error_so_far = error_so_far.max(error);
        chain.levels.push(LodLevel {
            first_index: chain.indices.len() as u32,
            index_count: level.indices.len() as u32,
            error: error_so_far,
        });
        chain.indices.extend_from_slice(&level.indices);
        previous = count;
    }
    for i in 0..chain.levels.len() {
        chain.cache_order(i, mesh.positions.len() + chain.moved.len());
    }
    Ok(chain)
}

/// One simplified level: its indices into its own vertices (`moved`, numbered from 0).
struct Level {
    indices: Vec<u32>,
    moved: MovedVertices,
}

/// meshoptimizer's `simplifyWithUpdate` on one prepared mesh, run once per level from the full
/// mesh.
struct Simplifier<'a> {
    prepared: &'a Prepared,
    /// Per vertex: the normal, then the UV when the mesh has UVs.
    attributes: Vec<f32>,
    stride: usize,
    locks: Vec<meshopt::SimplifyVertex>,
    /// How far the simplifier is allowed beyond its defaults ([`Relax`]).
    relax: Relax,
}

/// What the simplifier may do beyond its defaults when a mesh's first level cannot be reduced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Relax {
    /// Seams kept closed and collapsed only along themselves, open borders locked.
    None,
    /// Collapses across normal seams (meshopt's `Permissive`), UV seams protected.
    Seams,
    /// Also open borders may move (within the level's error, which measures them too).
    Border,
}

impl<'a> Simplifier<'a> {
    fn new(prepared: &'a Prepared) -> Self {
        let m = &prepared.mesh;
        let n = m.positions.len();
        let uv = m.uvs.len() == n;
        let stride = if uv { 5 } else { 3 };
        let mut attributes = Vec::with_capacity(n * stride);
        for i in 0..n {
            attributes.extend_from_slice(&m.normals[i].to_array());
            if uv {
                attributes.extend_from_slice(&m.uvs[i].to_array());
            }
        }
        let locks = prepared
            .uv_seam
            .iter()
            .map(|&s| {
                if s {
                    meshopt::SimplifyVertex::Protect
                } else {
                    meshopt::SimplifyVertex::None
                }
            })
            .collect();
        Simplifier {
            prepared,
            attributes,
            stride,
            locks,
            relax: Relax::None,
        }
    }

    /// Allows the next step of [`Relax`]; false when there is none left worth trying.
    fn relax(&mut self) -> bool {
        self.relax = match self.relax {
            Relax::None if self.prepared.has_seams => Relax::Seams,
            Relax::None | Relax::Seams => Relax::Border,
            Relax::Border => return false,
        };
        true
    }

    /// The level of (at most) `target_indices` indices and its error. The simplifier collapses
    /// edges on copies of the mesh's data and places each kept vertex (and its normal and UV) where
    /// its quadric error is least; the vertices the level uses are copied out in first-use order,
    /// normals renormalised.
    fn level(&self, target_indices: usize) -> (Level, f32) {
        let weights = [
            NORMAL_WEIGHT,
            NORMAL_WEIGHT,
            NORMAL_WEIGHT,
            UV_WEIGHT,
            UV_WEIGHT,
        ];
        let mut options =
            meshopt::SimplifyOptions::ErrorAbsolute | meshopt::SimplifyOptions::ErrorClamped;
        if self.relax < Relax::Border {
            options |= meshopt::SimplifyOptions::LockBorder;
        }
        if self.relax >= Relax::Seams {
            options |= meshopt::SimplifyOptions::Permissive;
        }
        let p = self.prepared;
        let mut indices = p.mesh.indices.clone();
        let mut positions: Vec<[f32; 3]> = p.mesh.positions.iter().map(|v| v.to_array()).collect();
        let mut attributes = self.attributes.clone();
        let mut error = 0.0f32;
        let count = if indices.is_empty() {
            0
        } else {
            meshopt::simplify_with_update(
                &mut indices,
                &mut positions,
                &mut attributes,
                &weights[..self.stride],
                self.stride * 4,
                Some(&self.locks),
                // meshopt asserts (aborts) on a target above its input.
                target_indices.min(p.mesh.indices.len()),
                f32::MAX,
                options,
                Some(&mut error),
            )
        };
        indices.truncate(count);
        let mut moved = MovedVertices::default();
        let mut slot = vec![u32::MAX; positions.len()];
        for i in indices.iter_mut() {
            let v = *i as usize;
            if slot[v] == u32::MAX {
                slot[v] = moved.len() as u32;
                let a = &attributes[v * self.stride..(v + 1) * self.stride];
                let normal = Vec3::new(a[0], a[1], a[2]);
                moved.origin.push(p.origin[v]);
                moved.positions.push(Vec3::from_array(positions[v]));
                moved
                    .normals
                    .push(normal.try_normalize().unwrap_or(p.mesh.normals[v]));
                if self.stride == 5 {
                    moved.uvs.push(glam::Vec2::new(a[3], a[4]));
                }
            }
            *i = slot[v];
        }
        (Level { indices, moved }, error)
    }
}

/// What building the chains of a scene's meshes did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ChainStats {
    /// Chains simplified now.
    pub built: usize,
    /// Chains read from the disk cache.
    pub loaded: usize,
    /// Meshes drawn whole because their simplification failed (now or in a cached run).
    pub failed: usize,
    /// Each failure: the mesh's name and the reason, for [`ChainStats::failure_summary`].
    pub failures: Vec<(String, String)>,
}

impl ChainStats {
    /// The one line that reports the meshes drawn whole because their simplification failed
    /// (none: `None`): how many, the first with its reason, and how many more.
    pub fn failure_summary(&self) -> Option<String> {
        let (name, reason) = self.failures.first()?;
        let more = match self.failures.len() - 1 {
            0 => String::new(),
            n => format!(", and {n} more"),
        };
        Some(format!(
            "automatic LOD: {} mesh(es) drawn at full detail because their simplification \
             failed: {name} ({reason}){more}",
            self.failures.len()
        ))
    }

    fn fail(&mut self, name: &str, reason: String) {
        self.failed += 1;
        self.failures.push((name.to_string(), reason));
    }
}

/// The chain of `mesh` (named `name` in warnings): from the cache in `cache_dir` when a file for
/// its contents is there and intact, else built (and written there). A failed simplification
/// gives the full mesh's chain and is recorded in `stats` (one line for all of them:
/// [`ChainStats::failure_summary`]); it is cached too, so the next run does not pay for it again.
/// Cache problems (a damaged file, an entry that cannot be written) give one warning each
/// through `warn`.
pub fn chain_for(
    mesh: &Mesh,
    name: &str,
    cache_dir: Option<&std::path::Path>,
    stats: &mut ChainStats,
    warn: &mut dyn FnMut(String),
) -> Arc<LodChain> {
    if let Some(placed) = &mesh.placed {
        let local = chain_for(&placed.local, name, cache_dir, stats, warn);
        if let Some(chain) = place(&local, placed.transform) {
            return Arc::new(chain);
        }
    }
    let key = cache::key(mesh);
    // Still in vertex cache order where its indices are valid: drawn whole every frame.
    let whole = || {
        let mut chain = LodChain::full(mesh);
        if check(mesh).is_ok() {
            chain.cache_order(0, mesh.positions.len());
        }
        Arc::new(chain)
    };
    // Where to write what is built: not over an entry that cannot be read (a folder).
    let mut write_to = cache_dir;
    if let Some(dir) = cache_dir {
        match cache::read(dir, key, mesh) {
            cache::Read::Hit(chain) => {
                stats.loaded += 1;
                return Arc::new(chain);
            }
            cache::Read::Failed(reason) => {
                stats.loaded += 1;
                stats.fail(name, reason);
                return whole();
            }
            cache::Read::Miss => {}
            cache::Read::Corrupt(path) => warn(format!(
                "{}: cached LOD chain of {name} is damaged (empty, zeroed or not matching its \
                 checksum); simplifying it again and replacing the file",
                path.display()
            )),
            cache::Read::Unreadable(path, why) => {
                write_to = None;
                crate::files::cache_dir::warn_once(
                    &format!("folder:{}", path.display()),
                    format!(
                        "{}: cached LOD chain of {name} cannot be read ({why}); it is simplified \
                         again on every run until this is removed",
                        path.display()
                    ),
                    warn,
                );
            }
        }
    }
    let built = build(mesh);
    if let Some(dir) = write_to {
        if let Err(e) = cache::write(dir, key, mesh, built.as_ref()) {
            warn(e);
        }
    }
    match built {
        Ok(chain) => {
            stats.built += 1;
            Arc::new(chain)
        }
        Err(reason) => {
            stats.fail(name, reason);
            whole()
        }
    }
}

/// The chain of a mesh's local form (`local`, [`super::mesh::Placed`]) for the mesh `transform`
/// placed: the same indices (the placed mesh has the local form's vertices in the same order),
/// the moved vertices through `transform` (normals through its normal matrix, renormalised) and
/// the errors scaled by its largest axis scale. None when a moved vertex leaves the finite
/// range (the caller then builds the placed mesh's own chain).
fn place(local: &LodChain, transform: glam::Mat4) -> Option<LodChain> {
    let mut chain = local.clone();
    if chain.levels.len() == 1 && chain.moved.is_empty() {
        return Some(chain);
    }
    let linear = glam::Mat3::from_mat4(transform);
    let scale = linear
        .x_axis
        .length()
        .max(linear.y_axis.length())
        .max(linear.z_axis.length());
    let normal = linear.inverse().transpose();
    if !scale.is_finite() || !normal.is_finite() {
        return None;
    }
    let m = &mut chain.moved;
    for p in &mut m.positions {
        *p = transform.transform_point3(*p);
    }
    for n in &mut m.normals {
        *n = (normal * *n).try_normalize().unwrap_or(*n);
    }
    if m.positions.iter().any(|p| !p.is_finite()) {
        return None;
    }
    for l in &mut chain.levels[1..] {
        l.error *= scale;
    }
    Some(chain)
}

/// Pixels per world unit at distance 1 on an image `height_px` tall: (height / 2) / tan(fov_y / 2);
/// for an orthographic camera at every distance, height / (2 · half_height) (its distance is 1:
/// [`camera_distance`]).
pub fn focal_px(camera: &Camera, height_px: u32) -> f32 {
    match camera.ortho_half_height() {
        None => 0.5 * height_px as f32 / (0.5 * camera.fov_y_deg.to_radians()).tan(),
        Some(h) => 0.5 * height_px as f32 / h,
    }
}

/// The distance [`projected_error_px`] divides by for the sphere (`centre`, `radius`) seen by
/// `camera`: [`sphere_distance`] from the eye, or 1 for an orthographic camera (its projection
/// does not shrink with distance; [`focal_px`] holds the whole scale).
pub fn camera_distance(camera: &Camera, centre: Vec3, radius: f32) -> f32 {
    match camera.ortho_half_height() {
        None => sphere_distance(camera.position, centre, radius),
        Some(_) => 1.0,
    }
}

/// An object-space error `error` of an object whose bounding sphere (world centre `centre`,
/// radius `radius`) is seen from `eye`, scaled to the world by `scale`, in pixels: the error
/// seen at the sphere's nearest point, f · error · scale / distance. Infinite when the camera is
/// inside the sphere.
pub fn projected_error_px(error: f32, scale: f32, focal_px: f32, distance: f32) -> f32 {
    if error <= 0.0 {
        return 0.0;
    }
    if distance <= 0.0 || distance.is_nan() {
        return f32::INFINITY;
    }
    focal_px * error * scale / distance
}

/// The distance from `eye` to the nearest point of the sphere (`centre`, `radius`) (≤ 0 inside).
pub fn sphere_distance(eye: Vec3, centre: Vec3, radius: f32) -> f32 {
    (centre - eye).length() - radius
}

/// The coarsest level of `levels` whose error (object space, × `scale`) projects within
/// `budget_px` at `distance` ([`projected_error_px`]); 0 when the budget is 0 (or not a
/// positive finite number) or no coarser level fits.
pub fn choose(
    levels: &[LodLevel],
    scale: f32,
    focal_px: f32,
    distance: f32,
    budget_px: f32,
) -> usize {
    if !(budget_px > 0.0 && budget_px.is_finite()) {
        return 0;
    }
    (1..levels.len())
        .rev()
        .find(|&i| projected_error_px(levels[i].error, scale, focal_px, distance) <= budget_px)
        .unwrap_or(0)
}

/// The level an object drew and why (`luz render --verbose`, the viewer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LodChoice {
    /// Index into the scene's objects.
    pub object: usize,
    pub level: usize,
    pub levels: usize,
    pub triangles: u64,
    pub full_triangles: u64,
    /// The chosen level's error in pixels.
    pub error_px: f32,
    /// Inside the view volume (drawn).
    pub visible: bool,
}

/// The LOD levels the objects in view draw at, as the viewer shows them: "0-4 (600 objects)",
/// or "none" without a simplified mesh in view.
pub fn levels_in_use(choices: &[LodChoice]) -> String {
    let drawn = choices.iter().filter(|c| c.visible);
    let (lo, hi, n) = drawn.fold((usize::MAX, 0, 0), |(lo, hi, n), c| {
        (lo.min(c.level), hi.max(c.level), n + 1)
    });
    if n == 0 {
        "none".into()
    } else {
        format!("{lo}-{hi} ({n} objects)")
    }
}

/// What `luz render` says of automatic LOD, as [`super::tessellation::summary`] does for
/// primitives: a summary line and, when `verbose`, one line per object (indented). Nothing
/// without a simplified mesh.
pub fn summary(scene: &super::Scene, choices: &[LodChoice], verbose: bool) -> Vec<String> {
    if choices.is_empty() {
        return Vec::new();
    }
    let drawn: Vec<&LodChoice> = choices.iter().filter(|c| c.visible).collect();
    let (lo, hi) = (
        drawn.iter().map(|c| c.level).min().unwrap_or(0),
        drawn.iter().map(|c| c.level).max().unwrap_or(0),
    );
    let tri: u64 = drawn.iter().map(|c| c.triangles).sum();
    let full: u64 = choices.iter().map(|c| c.full_triangles).sum();
    let mut out = vec![format!(
        "automatic LOD (budget {} px): {} mesh object(s), {} in view at levels {lo}-{hi}, \
         {tri} of {full} triangles drawn{}",
        scene.output.tessellation_error_px,
        choices.len(),
        drawn.len(),
        if verbose {
            ":"
        } else {
            " (--verbose lists them)"
        }
    )];
    if verbose {
        for c in choices {
            let name = scene.objects.get(c.object).map_or("?", |o| o.name.as_str());
            out.push(if c.visible {
                format!(
                    "  {name}: level {} of {}, {} of {} triangles (error {:.3} px)",
                    c.level,
                    c.levels - 1,
                    c.triangles,
                    c.full_triangles,
                    c.error_px
                )
            } else {
                format!("  {name}: out of view")
            });
        }
    }
    out
}

#[cfg(test)]
mod tests;
