//! Clustered light culling (Olsson et al.'s clustered shading), assigned on the CPU.
//!
//! The view volume is cut into clusters: `tiles_x` × `tiles_y` screen tiles (in view-space
//! slopes x/d and y/d, d the view depth, so the grid does not depend on the pixel size; for an
//! orthographic camera in view-space x and y themselves, the rays being parallel) times
//! `slices` depth slices, exponential between the camera's near and far planes. Each light with a
//! range is listed in every cluster its bounding sphere (position, range) may reach; lights
//! without a range (directional lights, unranged point and spot lights) are listed once, ahead of
//! every cluster's list. A fragment at P finds its cluster from P's view-space position
//! (`light_cluster` in `shaders_glsl/include/lighting.glsl`) and loops over that list only.
//!
//! Area lights (issue 36) have lists of their own, beside the punctual ones: an area light with a
//! range is listed by the sphere (its shape's centre, range) — `area_window` in
//! `shaders_glsl/include/area.glsl` is the same window as a point light's, on the distance to the
//! centre, so beyond the range it delivers exactly 0 — and one without a range is in every
//! cluster. Each cluster has a second (base, count) pair for them, after every cluster's punctual
//! pair, so the punctual loop reads what it read before and a scene without area lights uploads
//! nothing more; the fragment runs a second loop over its area list (no per-light branch between
//! the two kinds, which lavapipe would run on both sides under a lane mask).
//!
//! Exactness: a light is dropped from a cluster only when its sphere, grown by a small margin for
//! rounding, misses the cluster's bounds: per depth slice, the sphere's part inside the slice lies
//! in a box (the largest cross-section's square × the slice's depths), and the tiles that box's
//! slopes cover are listed. So a light whose range reaches a fragment is always in its cluster;
//! beyond the range the light delivers nothing (the KHR window is 0), so the image is the plain
//! loop's up to the order of the sum.
//!
//! No Vulkan here: [`Grid`] and [`build`] are plain data, unit-tested against brute force.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};

use crate::scene::{AreaLight, Light, LightKind};

/// Screen tiles in y (x follows the aspect ratio: square-ish tiles). 32 × 64 slices on
/// plane1024 (docs/performance.md, "Many lights"): lighting 308 ms against 386 ms with 16 × 32
/// and 272 ms with 48 × 128, whose assignment costs 5.6× the CPU time and 3.7× the indices.
pub const TILES_Y: u32 = 32;
/// Most screen tiles in x (an aspect ratio beyond 4:1 gets wider tiles).
pub const MAX_TILES_X: u32 = 128;
/// Exponential depth slices between the depths the ranged lights span.
pub const SLICES: u32 = 64;

/// The light loop's crossover: with fewer ranged lights than this, [`LightLoop::Auto`] keeps the
/// plain loop over every light. Measured (docs/performance.md, "Many lights"): lights spread
/// over a plane, the clustered loop costs 1.09× the plain one with 1 light, 0.82× with 2, 0.71×
/// with 4, 0.27× with 8; lights that all reach every pixel cost 1.2–1.6× (nothing to cull,
/// [`MAX_LISTED_FRACTION`] keeps those plain).
pub const CROSSOVER: usize = 4;

/// [`LightLoop::Auto`] also keeps the plain loop when the clusters of the initial view that hold
/// ranged lights list more than this fraction of all lights on average: a listed light costs
/// about twice a plain-loop light on lavapipe (its index and data are gathered per lane instead
/// of loaded once for all lanes), so weak culling loses (lights256 with ranges for 1e-3: 243 of
/// 256 lights per cluster, 2.4× the plain loop's frame).
pub const MAX_LISTED_FRACTION: f64 = 0.3;

/// What one area light weighs in [`LightLoop::Auto`]'s decision, in punctual lights: a frame
/// with one area light costs 1.25× (representative point) to 3.71× (LTC sphere) the frame with
/// one point light (docs/area-lights.md, "Cost"), the base frame included, so an area light
/// costs several point lights: with 4, one ranged area light alone reaches [`CROSSOVER`], and
/// in the listed-fraction test an area light, listed or not, counts as 4 punctual ones.
pub const AREA_WEIGHT: usize = CROSSOVER;

/// [`LightLoop::Auto`] also takes the clustered loop when some area light has a range and the
/// clusters list, on average over all clusters, at most this fraction of the area lights (and
/// the punctual lights are at most [`AREA_WEIGHT`] per ranged area light, so that their gathers
/// do not outweigh what the area lights save). Area lights cost so much more than the cluster
/// lookup that any real culling pays: measured (docs/area-lights.md, "Clustered culling"), the
/// clustered loop costs 0.54–0.55× the plain one with 1 ranged rect, 0.29× with 4, 0.09× with 24
/// of mixed shapes, and 0.97–1.04× when every area light reaches every pixel (nothing to cull: the
/// fraction is then 1, and the loop stays plain).
pub const MAX_AREA_LISTED_FRACTION: f64 = 0.5;

/// How the fragment stage loops over lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LightLoop {
    /// Clustered when the scene has at least [`CROSSOVER`] lights with a range (an area light
    /// counting [`AREA_WEIGHT`]) that the clusters cull, or ranged area lights that the clusters
    /// cull ([`MAX_AREA_LISTED_FRACTION`]); plain otherwise.
    #[default]
    Auto,
    /// Every light at every fragment (the loop before clusters).
    Plain,
    /// Only the lights of the fragment's cluster (lights without a range are in every one).
    Clustered,
}

impl LightLoop {
    /// Whether the pass for `scene` (drawn at `aspect`) culls by clusters.
    pub fn clustered(self, scene: &crate::scene::Scene, aspect: f32) -> bool {
        match self {
            LightLoop::Plain => false,
            LightLoop::Clustered => true,
            LightLoop::Auto => {
                let (lights, areas) = (&scene.lights, &scene.area_lights);
                let ranged_areas = ranged_areas(areas);
                ranged(lights) + AREA_WEIGHT * ranged_areas >= CROSSOVER && {
                    let c = build(&Grid::of(scene, aspect), scene.camera.view(), lights, areas);
                    let w = AREA_WEIGHT as f64;
                    let s = c.stats;
                    s.mean_occupied + w * s.area_mean_occupied
                        <= MAX_LISTED_FRACTION * (lights.len() as f64 + w * areas.len() as f64)
                        || (ranged_areas > 0
                            && lights.len() <= AREA_WEIGHT * ranged_areas
                            && s.area_mean <= MAX_AREA_LISTED_FRACTION * areas.len() as f64)
                }
            }
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            LightLoop::Auto => "auto",
            LightLoop::Plain => "plain",
            LightLoop::Clustered => "clustered",
        }
    }
}

/// Whether `l` is culled by its range (a point or spot light with a range).
fn has_range(l: &Light) -> bool {
    l.kind != LightKind::Directional && l.range.is_some_and(|r| r.is_finite() && r > 0.0)
}

/// Lights with a range.
pub fn ranged(lights: &[Light]) -> usize {
    lights.iter().filter(|l| has_range(l)).count()
}

/// Whether the area light `a` is culled by its range.
fn area_has_range(a: &AreaLight) -> bool {
    a.range.is_some_and(|r| r.is_finite() && r > 0.0)
}

/// Area lights with a range.
pub fn ranged_areas(areas: &[AreaLight]) -> usize {
    areas.iter().filter(|a| area_has_range(a)).count()
}

/// The cluster grid of a camera: tile counts, slices, and the mapping from view-space position to
/// cluster (the same formulas as `light_cluster` in `lighting.glsl`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub slices: u32,
    /// column = floor(x/d · sx + ox), row = floor(y/d · sy + oy) (orthographic: x and y for x/d
    /// and y/d).
    sx: f32,
    ox: f32,
    sy: f32,
    oy: f32,
    /// slice = floor(ln d · ls + lo): exponential slices between the depths the ranged lights
    /// span (within near and far; [`Grid::fitted`]); the first and last slices reach on to the
    /// camera's near and far planes.
    ls: f32,
    lo: f32,
    /// The camera's near and far planes.
    near: f32,
    far: f32,
    /// An orthographic camera's grid: tiles in x and y, not in slopes.
    ortho: bool,
}

/// `ClusterHeader` (std430, 64 bytes) at the start of the clusters buffer, before the
/// (base, count) pairs of every cluster (then, with area lights, every cluster's area pair).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub struct ClusterHeader {
    /// tiles x, tiles y, slices, lights in every cluster (at the start of the index list).
    pub dims: [u32; 4],
    /// sx, ox, sy, oy.
    pub xy: Vec4,
    /// ls, lo, 1 for an orthographic grid (tiles in x and y, not slopes) else 0, unused.
    pub depth: Vec4,
    /// Area lights in every cluster, where they start in the index list, unused, unused.
    pub area: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<ClusterHeader>() == 64);

impl Grid {
    /// The grid of a perspective camera (vertical field of view, aspect, near and far planes).
    pub fn new(fov_y_deg: f32, aspect: f32, near: f32, far: f32) -> Self {
        let tan_y = (fov_y_deg.to_radians() * 0.5).tan().max(1e-6);
        Self::with_extent(tan_y, aspect, near, far, false)
    }

    /// The grid of an orthographic camera (half view height, aspect, near and far planes).
    pub fn orthographic(half_height: f32, aspect: f32, near: f32, far: f32) -> Self {
        Self::with_extent(half_height.max(1e-6), aspect, near, far, true)
    }

    /// `tan_y`: the half view height at depth 1 (perspective) or everywhere (orthographic).
    fn with_extent(tan_y: f32, aspect: f32, near: f32, far: f32, ortho: bool) -> Self {
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let tan_x = tan_y * aspect;
        let tiles_y = TILES_Y;
        let tiles_x = ((tiles_y as f32 * aspect).round() as u32).clamp(1, MAX_TILES_X);
        let near = near.max(1e-6);
        let far = far.max(near * 1.001);
        let mut g = Self {
            tiles_x,
            tiles_y,
            slices: SLICES,
            sx: 0.5 * tiles_x as f32 / tan_x,
            ox: 0.5 * tiles_x as f32,
            sy: 0.5 * tiles_y as f32 / tan_y,
            oy: 0.5 * tiles_y as f32,
            ls: 0.0,
            lo: 0.0,
            near,
            far,
            ortho,
        };
        g.slice_between(near, far);
        g
    }

    /// Slices between depths `z0` and `z1` (clamped to near and far).
    fn slice_between(&mut self, z0: f32, z1: f32) {
        let z0 = z0.max(self.near);
        let z1 = z1.min(self.far).max(z0 * 1.001);
        self.ls = self.slices as f32 / (z1 / z0).ln();
        self.lo = -z0.ln() * self.ls;
    }

    /// This grid with its slices between the nearest and farthest depth the spheres
    /// (view-space centre, radius) reach: where the lights are, the slices are thinner.
    pub fn fitted(&self, spheres: impl Iterator<Item = (glam::Vec3, f32)>) -> Self {
        let (mut z0, mut z1) = (f32::INFINITY, 0.0f32);
        for (c, r) in spheres {
            z0 = z0.min(-c.z - r);
            z1 = z1.max(-c.z + r);
        }
        let mut g = *self;
        if z0 < z1 {
            g.slice_between(z0, z1);
        }
        g
    }

    /// The grid of `scene`'s camera at `aspect`.
    pub fn of(scene: &crate::scene::Scene, aspect: f32) -> Self {
        let c = &scene.camera;
        match c.ortho_half_height() {
            None => Self::new(c.fov_y_deg, aspect, c.near, c.far),
            Some(h) => Self::orthographic(h, aspect, c.near, c.far),
        }
    }

    pub fn cells(&self) -> usize {
        (self.tiles_x * self.tiles_y * self.slices) as usize
    }

    /// The header of lists with `always` punctual lights in every cluster (and `area_always`
    /// area lights, from `area_start` in the index list).
    pub fn header(&self, always: u32, [area_always, area_start]: [u32; 2]) -> ClusterHeader {
        ClusterHeader {
            dims: [self.tiles_x, self.tiles_y, self.slices, always],
            xy: Vec4::new(self.sx, self.ox, self.sy, self.oy),
            depth: Vec4::new(self.ls, self.lo, if self.ortho { 1.0 } else { 0.0 }, 0.0),
            area: [area_always, area_start, 0, 0],
        }
    }

    /// What the tiles cut at view depth `d`: the slope x/d, or x itself (orthographic).
    fn slope(&self, x: f32, d: f32) -> f32 {
        if self.ortho {
            x
        } else {
            x / d
        }
    }

    fn column(&self, t: f32) -> u32 {
        ((t * self.sx + self.ox).floor().max(0.0) as u32).min(self.tiles_x - 1)
    }

    fn row(&self, t: f32) -> u32 {
        ((t * self.sy + self.oy).floor().max(0.0) as u32).min(self.tiles_y - 1)
    }

    fn slice(&self, d: f32) -> u32 {
        ((d.max(1e-30).ln() * self.ls + self.lo).floor().max(0.0) as u32).min(self.slices - 1)
    }

    /// The near depth of slice `k` (`k` = slices: far).
    fn slice_start(&self, k: u32) -> f32 {
        ((k as f32 - self.lo) / self.ls).exp()
    }

    /// The cluster of the view-space point `v` (x, y, z with depth d = −z), as the shader finds it.
    pub fn cluster_of(&self, v: glam::Vec3) -> usize {
        let d = (-v.z).max(1e-6);
        let (c, r, k) = (
            self.column(self.slope(v.x, d)),
            self.row(self.slope(v.y, d)),
            self.slice(d),
        );
        ((k * self.tiles_y + r) * self.tiles_x + c) as usize
    }
}

/// Lights per cluster, for reports.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ClusterStats {
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub slices: u32,
    /// Lights in every cluster (no range).
    pub always: u32,
    /// Most lights in one cluster (with `always`).
    pub max: u32,
    /// Mean lights per cluster (with `always`).
    pub mean: f64,
    /// Mean lights per cluster over the clusters that list a ranged light, punctual or area
    /// (with `always`).
    pub mean_occupied: f64,
    /// The same four for area lights (`area_mean_occupied` over the same clusters).
    pub area_always: u32,
    pub area_max: u32,
    pub area_mean: f64,
    pub area_mean_occupied: f64,
    /// Light indices listed in all (the buffer's length).
    pub indices: usize,
    /// CPU time of the assignment, ms.
    pub build_ms: f64,
}

/// The clusters of one frame: the grid, its header, (base, count) per cluster — the cluster's
/// k-th light is `indices[k]` for k < always, `indices[base + k]` after — the same for area
/// lights (`area_cells`, empty without area lights: the k-th is `indices[area_start + k]` for
/// k < area_always, `indices[base + k]` after), and the index list.
#[derive(Debug, Clone)]
pub struct Clusters {
    pub grid: Grid,
    pub header: ClusterHeader,
    pub cells: Vec<[u32; 2]>,
    pub area_cells: Vec<[u32; 2]>,
    pub indices: Vec<u32>,
    pub stats: ClusterStats,
}

impl Clusters {
    /// The lights of cluster `cell`, in the order the shader visits them.
    pub fn lights_of(&self, cell: usize) -> impl Iterator<Item = u32> + '_ {
        let [base, count] = self.cells[cell];
        let always = self.header.dims[3];
        (0..count).map(move |k| {
            if k < always {
                self.indices[k as usize]
            } else {
                self.indices[(base + k) as usize]
            }
        })
    }

    /// The area lights of cluster `cell`, in the order the shader visits them (none without area
    /// lights).
    pub fn area_lights_of(&self, cell: usize) -> impl Iterator<Item = u32> + '_ {
        let [base, count] = self.area_cells.get(cell).copied().unwrap_or([0, 0]);
        let [always, start, ..] = self.header.area;
        (0..count).map(move |k| {
            if k < always {
                self.indices[(start + k) as usize]
            } else {
                self.indices[(base + k) as usize]
            }
        })
    }

    /// The (base, count) pairs as the clusters buffer holds them after its header: every
    /// cluster's punctual pair, then (with area lights) every cluster's area pair.
    pub fn pairs(&self) -> impl Iterator<Item = &[u32; 2]> {
        self.cells.iter().chain(&self.area_cells)
    }
}

/// Relative growth of a light's range and of the slice bounds: rounding in the shader's cluster
/// lookup (a matrix product, a division, a logarithm) never moves a fragment by this much.
const MARGIN: f32 = 1e-3;

/// One rectangle of tiles per (light, slice): kind (0 punctual, 1 area), slice, columns, rows,
/// light.
type TileRect = (usize, u32, [u32; 2], [u32; 2], u32);

/// Assigns `lights` and `areas` to the clusters of the camera grid `camera` (slices fitted to
/// the lights, [`Grid::fitted`]) for the camera `view` (world to view space).
pub fn build(camera: &Grid, view: Mat4, lights: &[Light], areas: &[AreaLight]) -> Clusters {
    let start = std::time::Instant::now();
    let always: Vec<u32> = (0..lights.len() as u32)
        .filter(|&i| !has_range(&lights[i as usize]))
        .collect();
    let area_always: Vec<u32> = (0..areas.len() as u32)
        .filter(|&i| !area_has_range(&areas[i as usize]))
        .collect();
    // World-space bounding spheres (kind: 0 punctual, 1 area; index; centre; range). An area
    // light's window is on the distance to its shape's centre (area.glsl: area_window), so the
    // sphere there of radius range bounds every point it reaches, whatever the shape's size.
    let punctual = lights.iter().enumerate().filter_map(|(i, l)| {
        let range = l.range.filter(|_| has_range(l))?;
        Some((0usize, i as u32, l.position, range))
    });
    let area = areas.iter().enumerate().filter_map(|(i, a)| {
        let range = a.range.filter(|_| area_has_range(a))?;
        Some((1usize, i as u32, a.position, range))
    });
    // View-space bounding spheres, grown by the margin.
    let spheres: Vec<(usize, u32, glam::Vec3, f32)> = punctual
        .chain(area)
        .filter_map(|(kind, i, p, range)| {
            let c = view.transform_point3(p);
            let r = range * (1.0 + MARGIN) + 1e-5 * (1.0 + c.length());
            (c.is_finite() && r.is_finite()).then_some((kind, i, c, r))
        })
        .collect();
    let grid = camera.fitted(spheres.iter().map(|&(_, _, c, r)| (c, r)));
    let mut rects: Vec<TileRect> = Vec::new();
    let min_depth = grid.near * 0.5;
    for &(kind, i, c, r) in &spheres {
        let dc = -c.z;
        let (zlo, zhi) = (dc - r, dc + r);
        // Fragments lie between the near and far planes.
        if zhi < min_depth || zlo > grid.far * (1.0 + MARGIN) {
            continue;
        }
        let k0 = grid.slice(zlo.max(min_depth));
        let k1 = grid.slice(zhi);
        for k in k0..=k1 {
            let lo = if k == 0 {
                min_depth
            } else {
                grid.slice_start(k) * (1.0 - MARGIN)
            };
            let hi = if k + 1 == grid.slices {
                f32::INFINITY
            } else {
                grid.slice_start(k + 1) * (1.0 + MARGIN)
            };
            let za = zlo.max(lo).max(min_depth);
            let zb = zhi.min(hi);
            if za > zb {
                continue;
            }
            // The largest cross-section of the sphere within [za, zb].
            let rho = if (za..=zb).contains(&dc) {
                r
            } else {
                let dz = if dc < za { za - dc } else { dc - zb };
                (r * r - dz * dz).max(0.0).sqrt()
            };
            // Slopes x/d of the box [c.x ± rho] × [za, zb]: extremes at the box's corners.
            let span = |x: f32| {
                let (x0, x1) = (x - rho, x + rho);
                let t0 = grid.slope(x0, za).min(grid.slope(x0, zb));
                let t1 = grid.slope(x1, za).max(grid.slope(x1, zb));
                (
                    t0 - MARGIN * (1.0 + t0.abs()),
                    t1 + MARGIN * (1.0 + t1.abs()),
                )
            };
            let (tx0, tx1) = span(c.x);
            let (ty0, ty1) = span(c.y);
            rects.push((
                kind,
                k,
                [grid.column(tx0), grid.column(tx1)],
                [grid.row(ty0), grid.row(ty1)],
                i,
            ));
        }
    }
    let cells = grid.cells();
    let (tx, ty) = (grid.tiles_x as usize, grid.tiles_y as usize);
    let cell = |k: u32, row: u32, col: u32| (k as usize * ty + row as usize) * tx + col as usize;
    // Per kind (punctual, then area when the scene has area lights): ranged lights per cluster.
    let kinds = if areas.is_empty() { 1 } else { 2 };
    let mut counts = vec![vec![0u32; cells]; kinds];
    for &(kind, k, cols, rows, _) in &rects {
        for row in rows[0]..=rows[1] {
            for col in cols[0]..=cols[1] {
                counts[kind][cell(k, row, col)] += 1;
            }
        }
    }
    // The always-lit punctual lights first, then the always-lit area lights, then each cluster's
    // punctual list, then each cluster's area list.
    let n_always = [always.len() as u32, area_always.len() as u32];
    let mut offsets = vec![Vec::with_capacity(cells); kinds];
    let mut next = n_always[0] + n_always[1];
    for (offsets, counts) in offsets.iter_mut().zip(&counts) {
        for &n in counts {
            offsets.push(next);
            next += n;
        }
    }
    let mut indices = always;
    indices.extend(&area_always);
    indices.resize(next as usize, 0);
    let mut fill = offsets.clone();
    for &(kind, k, cols, rows, light) in &rects {
        for row in rows[0]..=rows[1] {
            for col in cols[0]..=cols[1] {
                let c = cell(k, row, col);
                indices[fill[kind][c] as usize] = light;
                fill[kind][c] += 1;
            }
        }
    }
    let pairs = |kind: usize| -> Vec<[u32; 2]> {
        offsets[kind]
            .iter()
            .zip(&counts[kind])
            .map(|(&o, &n)| [o - n_always[kind], n + n_always[kind]])
            .collect()
    };
    let cells_data = pairs(0);
    let area_cells = if kinds == 2 { pairs(1) } else { Vec::new() };
    let max = |c: &[[u32; 2]]| c.iter().map(|c| c[1]).max().unwrap_or(0);
    let mean = |c: &[[u32; 2]]| c.iter().map(|c| c[1] as f64).sum::<f64>() / cells.max(1) as f64;
    // The clusters that list a ranged light of either kind.
    let occupied: Vec<usize> = (0..cells)
        .filter(|&c| counts.iter().any(|n| n[c] > 0))
        .collect();
    let mean_occupied = |kind: usize| {
        let listed = |c: usize| counts.get(kind).map_or(0, |n| n[c]) + n_always[kind];
        occupied.iter().map(|&c| listed(c) as f64).sum::<f64>() / occupied.len().max(1) as f64
    };
    Clusters {
        grid,
        header: grid.header(n_always[0], [n_always[1], n_always[0]]),
        stats: ClusterStats {
            tiles_x: grid.tiles_x,
            tiles_y: grid.tiles_y,
            slices: grid.slices,
            always: n_always[0],
            max: max(&cells_data),
            mean: mean(&cells_data),
            mean_occupied: mean_occupied(0),
            area_always: n_always[1],
            area_max: max(&area_cells),
            area_mean: if areas.is_empty() {
                0.0
            } else {
                mean(&area_cells)
            },
            area_mean_occupied: if areas.is_empty() {
                0.0
            } else {
                mean_occupied(1)
            },
            indices: indices.len(),
            build_ms: start.elapsed().as_secs_f64() * 1e3,
        },
        cells: cells_data,
        area_cells,
        indices,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Falloff;
    use glam::Vec3;

    fn point(p: Vec3, range: Option<f32>) -> Light {
        Light {
            position: p,
            falloff: Falloff::InverseSquare,
            range,
            ..crate::scene::edit::default_light(LightKind::Point, None)
        }
    }

    /// An area light of shape `k` mod 4 (rect, disk, sphere, tube) at `p`, of size up to 1 m.
    fn area(p: Vec3, range: Option<f32>, k: usize) -> AreaLight {
        use crate::scene::{AreaMethod, AreaShape};
        let shape = match k % 4 {
            0 => AreaShape::Rect {
                up: Vec3::Z,
                width: 1.0,
                height: 0.5,
            },
            1 => AreaShape::Disk { radius: 0.4 },
            2 => AreaShape::Sphere { radius: 0.3 },
            _ => AreaShape::Tube {
                length: 1.0,
                radius: 0.05,
            },
        };
        AreaLight {
            shape,
            position: p,
            direction: Vec3::NEG_Y,
            color: Vec3::ONE,
            intensity: 1.0,
            shadow: None,
            two_sided: false,
            visible: true,
            method: AreaMethod::Ltc,
            range,
        }
    }

    /// A cheap deterministic sequence in [0, 1).
    fn rand(seed: &mut u64) -> f32 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Every point in the view volume finds, in its cluster, every light whose range reaches it
    /// (random punctual and area lights and points, a camera looking down at a plane), and lights
    /// without a range are in every cluster; the culling also drops most lights.
    #[test]
    fn no_light_that_reaches_a_point_is_missing_from_its_cluster() {
        let (fov, aspect, near, far) = (50.0f32, 16.0 / 9.0, 0.1, 100.0);
        let tan_y = (fov.to_radians() * 0.5).tan();
        // A point in the view volume: a slope pair and a depth (log-uniform, some at the
        // extremes of the frustum).
        check_clusters(Grid::new(fov, aspect, near, far), &|seed| {
            let tx = (rand(seed) * 2.0 - 1.0) * tan_y * aspect;
            let ty = (rand(seed) * 2.0 - 1.0) * tan_y;
            let d = near * (far / near).powf(rand(seed));
            Vec3::new(tx * d, ty * d, -d)
        });
    }

    /// The same for an orthographic camera's grid (tiles in x and y): points anywhere in its box.
    #[test]
    fn orthographic_clusters_miss_no_light_either() {
        let (h, aspect, near, far) = (6.0f32, 16.0 / 9.0, 0.1, 100.0);
        let grid = Grid::orthographic(h, aspect, near, far);
        assert_eq!(grid.header(0, [0, 0]).depth.z, 1.0);
        check_clusters(grid, &|seed| {
            let x = (rand(seed) * 2.0 - 1.0) * h * aspect;
            let y = (rand(seed) * 2.0 - 1.0) * h;
            let d = near * (far / near).powf(rand(seed));
            Vec3::new(x, y, -d)
        });
    }

    /// Random lights around a camera looking down at a plane; `point` draws a view-space point
    /// inside `grid`'s view volume.
    fn check_clusters(grid: Grid, point_in_view: &dyn Fn(&mut u64) -> Vec3) {
        let mut seed = 7u64;
        let eye = Vec3::new(0.0, 7.0, 11.0);
        let view = Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Y);
        let mut lights: Vec<Light> = (0..600)
            .map(|_| {
                let p = Vec3::new(
                    rand(&mut seed) * 40.0 - 20.0,
                    rand(&mut seed) * 2.0 - 0.5,
                    rand(&mut seed) * 40.0 - 25.0,
                );
                point(p, Some(0.2 + rand(&mut seed) * 3.0))
            })
            .collect();
        // Lights near and behind the camera, and without a range.
        lights.push(point(eye + Vec3::new(0.0, 0.0, 0.05), Some(1.0)));
        lights.push(point(eye + Vec3::new(0.0, 0.0, 2.0), Some(2.5)));
        lights.push(point(Vec3::new(1.0, 1.0, 1.0), None));
        lights.push(crate::scene::edit::default_light(
            LightKind::Directional,
            None,
        ));
        // Area lights of every shape (an area light's range is on the distance to its centre),
        // near and behind the camera, and without a range.
        let mut areas: Vec<AreaLight> = (0..300)
            .map(|k| {
                let p = Vec3::new(
                    rand(&mut seed) * 40.0 - 20.0,
                    rand(&mut seed) * 2.0 - 0.5,
                    rand(&mut seed) * 40.0 - 25.0,
                );
                area(p, Some(0.2 + rand(&mut seed) * 3.0), k)
            })
            .collect();
        areas.push(area(eye + Vec3::new(0.0, 0.0, 0.05), Some(1.0), 0));
        areas.push(area(eye + Vec3::new(0.0, 0.0, 2.0), Some(2.5), 1));
        areas.push(area(Vec3::new(-1.0, 1.0, 1.0), None, 2));
        areas.push(area(Vec3::new(2.0, 1.0, 1.0), None, 3));
        areas.push(area(Vec3::new(3.0, 1.0, 1.0), None, 0));
        let c = build(&grid, view, &lights, &areas);
        assert_eq!(c.header.dims[3], 2, "two lights without a range");
        assert_eq!(
            c.header.area[..2],
            [3, 2],
            "three area lights without a range, after 2"
        );
        assert_eq!(c.cells.len(), grid.cells());
        assert_eq!(c.area_cells.len(), grid.cells());
        let (mut checked, mut area_checked) = (0, 0);
        let (mut listed, mut area_listed) = (0usize, 0usize);
        for _ in 0..40_000 {
            let v = point_in_view(&mut seed);
            let p = view.inverse().transform_point3(v);
            let cell = c.grid.cluster_of(view.transform_point3(p));
            let list: Vec<u32> = c.lights_of(cell).collect();
            listed += list.len();
            let area_list: Vec<u32> = c.area_lights_of(cell).collect();
            area_listed += area_list.len();
            for (i, a) in areas.iter().enumerate() {
                if a.range.is_none_or(|r| (a.position - p).length() < r) {
                    area_checked += 1;
                    assert!(
                        area_list.contains(&(i as u32)),
                        "area light {i} reaches {p} (cluster {cell}) but is not listed"
                    );
                }
            }
            for (i, l) in lights.iter().enumerate() {
                let reaches = match l.range {
                    _ if l.kind == LightKind::Directional => true,
                    Some(r) => (l.position - p).length() < r,
                    None => true,
                };
                if reaches {
                    checked += 1;
                    assert!(
                        list.contains(&(i as u32)),
                        "light {i} reaches {p} (cluster {cell}) but is not listed"
                    );
                }
            }
        }
        assert!(checked > 10_000, "{checked}");
        // The 3 unranged area lights at each of the 40,000 points, and ranged ones.
        assert!(area_checked > 3 * 40_000 + 3_000, "{area_checked}");
        let mean = listed as f64 / 40_000.0;
        assert!(
            mean < 60.0,
            "{mean} lights per sampled cluster of {}",
            lights.len()
        );
        let area_mean = area_listed as f64 / 40_000.0;
        assert!(
            area_mean < 40.0,
            "{area_mean} area lights per sampled cluster of {}",
            areas.len()
        );
        // Lists are in light order (the plain loop's order of the sum).
        for cell in 0..c.cells.len() {
            let l: Vec<u32> = c.lights_of(cell).skip(2).collect();
            assert!(l.windows(2).all(|w| w[0] < w[1]), "cell {cell}: {l:?}");
            let l: Vec<u32> = c.area_lights_of(cell).skip(3).collect();
            assert!(l.windows(2).all(|w| w[0] < w[1]), "cell {cell}: {l:?}");
        }
        // Without area lights, no area pairs: nothing more to upload.
        let plain = build(&grid, view, &lights, &[]);
        assert!(plain.area_cells.is_empty());
        assert_eq!(plain.header.area[0], 0);
        assert_eq!(plain.stats.area_max, 0);
    }

    /// Auto: clustered with at least CROSSOVER ranged lights that the clusters cull; plain with
    /// fewer, without ranges, or when every light reaches everything.
    #[test]
    fn auto_needs_enough_ranged_lights_that_cull() {
        let mut scene = crate::scene::parse(
            r#"{"camera": {"position": [0, 7, 11], "target": [0, 0, 0], "fov_y_deg": 50, "near": 0.1, "far": 100}}"#,
            std::path::Path::new("<test>"),
        )
        .unwrap();
        let at = |k: usize| {
            Vec3::new(
                (k % 8) as f32 * 3.0 - 12.0,
                0.5,
                (k / 8) as f32 * 3.0 - 12.0,
            )
        };
        let aspect = 16.0 / 9.0;
        scene.lights = (0..CROSSOVER - 1)
            .map(|k| point(at(k), Some(1.0)))
            .collect();
        assert!(!LightLoop::Auto.clustered(&scene, aspect));
        assert!(LightLoop::Clustered.clustered(&scene, aspect));
        scene.lights.push(point(at(CROSSOVER), Some(1.0)));
        assert!(LightLoop::Auto.clustered(&scene, aspect));
        assert!(!LightLoop::Plain.clustered(&scene, aspect));
        // Ranges that reach the whole view: nothing to cull.
        for l in &mut scene.lights {
            l.range = Some(100.0);
        }
        assert!(!LightLoop::Auto.clustered(&scene, aspect));
        for l in &mut scene.lights {
            l.range = None;
        }
        assert!(!LightLoop::Auto.clustered(&scene, aspect));
        // A ranged area light weighs AREA_WEIGHT punctual lights: CROSSOVER − 1 ranged point
        // lights stay plain, one ranged area light more tips them over; the same area light
        // reaching the whole view, or without a range, does not.
        scene.lights = (0..CROSSOVER - 1)
            .map(|k| point(at(k), Some(1.0)))
            .collect();
        assert!(!LightLoop::Auto.clustered(&scene, aspect));
        scene.area_lights = vec![area(at(9), Some(1.0), 0)];
        assert!(LightLoop::Auto.clustered(&scene, aspect));
        scene.area_lights[0].range = Some(100.0);
        assert!(!LightLoop::Auto.clustered(&scene, aspect));
        scene.area_lights[0].range = None;
        assert!(!LightLoop::Auto.clustered(&scene, aspect));
        // One ranged area light alone is culled enough (MAX_AREA_LISTED_FRACTION), unless its
        // range reaches the whole view, or unranged punctual lights outnumber AREA_WEIGHT per
        // ranged area light; 24 spread over the plane take the clustered loop.
        scene.lights.clear();
        scene.area_lights = vec![area(at(9), Some(1.0), 0)];
        assert!(LightLoop::Auto.clustered(&scene, aspect));
        scene.area_lights[0].range = Some(100.0);
        assert!(!LightLoop::Auto.clustered(&scene, aspect));
        scene.area_lights[0].range = Some(1.0);
        scene.lights = (0..AREA_WEIGHT + 1).map(|k| point(at(k), None)).collect();
        assert!(!LightLoop::Auto.clustered(&scene, aspect));
        scene.lights.clear();
        scene.area_lights = (0..24).map(|k| area(at(k), Some(1.5), k)).collect();
        assert!(LightLoop::Auto.clustered(&scene, aspect));
    }
}
