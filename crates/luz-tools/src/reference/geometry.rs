//! Exact ray intersection for the reference renderer: the built-in primitives as the ideal shapes
//! they stand for (an icosphere is a sphere), OBJ meshes as triangles in a BVH.
//!
//! Everything here works in an object's own space: the caller transforms the ray by the inverse
//! object matrix (the ray parameter `t` is unchanged by that, so it stays the view-space depth of
//! the hit when the world ray's direction has a view-space z of −1).
//!
//! Local-space conventions are those of `scene::mesh` (centred at the origin, y up, u around
//! from +x towards −z, v down an image), so that UVs and tangents of the ideal shapes match the
//! tessellated ones the GPU draws.

use glam::{Vec2, Vec3};

use crate::scene::Mesh;

/// A ray `o + t d` (d not normalised).
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    pub o: Vec3,
    pub d: Vec3,
}

impl Ray {
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + self.d * t
    }
}

/// An ideal shape in its local space.
#[derive(Debug, Clone)]
pub enum Shape {
    /// Sphere and icosphere.
    Sphere { radius: f32 },
    /// In y = 0, extents along x and z, normal +y, two-sided.
    Plane { half_x: f32, half_z: f32 },
    /// Axis-aligned cube of half edge `half`.
    Cube { half: f32 },
    /// Axis +y, from −half_height to +half_height.
    Cylinder { radius: f32, half_height: f32 },
    /// Axis +y, base disc at −half_height, apex at +half_height.
    Cone { radius: f32, half_height: f32 },
    /// Triangles (an OBJ file).
    Mesh(std::sync::Arc<MeshAccel>),
}

/// Which part of a shape a ray hit (for the surface attributes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Part {
    /// The sphere, the plane, the side of a cylinder or cone.
    Main,
    /// The cube face whose outward normal is ± the axis (0 = x, 1 = y, 2 = z).
    CubeFace {
        axis: usize,
        positive: bool,
    },
    TopCap,
    BottomCap,
    /// A triangle with barycentrics (b1, b2) of its second and third vertex.
    Triangle {
        index: u32,
        b1: f32,
        b2: f32,
    },
}

/// Surface attributes in local space.
#[derive(Debug, Clone, Copy)]
pub struct LocalSurface {
    pub p: Vec3,
    /// Unit shading normal (the exact surface's; interpolated vertex normals for meshes).
    pub n: Vec3,
    pub uv: Vec2,
    /// Tangent along +u (xyz, not necessarily unit) and handedness w: B = w (N × T).
    pub tangent: [f32; 4],
}

impl Shape {
    /// Local-space bounding box.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match self {
            Shape::Sphere { radius } => (Vec3::splat(-radius), Vec3::splat(*radius)),
            Shape::Plane { half_x, half_z } => (
                Vec3::new(-half_x, 0.0, -half_z),
                Vec3::new(*half_x, 0.0, *half_z),
            ),
            Shape::Cube { half } => (Vec3::splat(-half), Vec3::splat(*half)),
            Shape::Cylinder {
                radius,
                half_height,
            }
            | Shape::Cone {
                radius,
                half_height,
            } => (
                Vec3::new(-radius, -half_height, -radius),
                Vec3::new(*radius, *half_height, *radius),
            ),
            Shape::Mesh(m) => m.bounds(),
        }
    }

    /// The nearest visible hit with `t` in `[t_min, t_max]`.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, Part)> {
        let hit = match self {
            Shape::Sphere { radius } => sphere(ray, *radius),
            Shape::Plane { half_x, half_z } => {
                return plane(ray, *half_x, *half_z).filter(|(t, _)| *t >= t_min && *t <= t_max)
            }
            Shape::Cube { half } => cube(ray, *half),
            Shape::Cylinder {
                radius,
                half_height,
            } => cylinder(ray, *radius, *half_height),
            Shape::Cone {
                radius,
                half_height,
            } => cone(ray, *radius, *half_height),
            Shape::Mesh(m) => return m.intersect(ray, t_min, t_max),
        };
        // Culled convex shapes: only the entry point is a front face.
        hit.filter(|(t, _)| *t >= t_min && *t <= t_max)
    }

    /// The surface attributes at the hit `(t, part)` of `ray`.
    pub fn surface(&self, ray: &Ray, t: f32, part: Part) -> LocalSurface {
        let p = ray.at(t);
        match (self, part) {
            (Shape::Mesh(m), Part::Triangle { index, b1, b2 }) => m.surface(index, b1, b2),
            (Shape::Sphere { .. }, _) => {
                let n = p.try_normalize().unwrap_or(Vec3::Y);
                LocalSurface {
                    p,
                    n,
                    uv: spherical_uv(n),
                    tangent: around_tangent(n),
                }
            }
            (Shape::Plane { half_x, half_z }, _) => LocalSurface {
                p,
                n: Vec3::Y,
                uv: Vec2::new(0.5 + p.x / (2.0 * half_x), 0.5 + p.z / (2.0 * half_z)),
                tangent: [1.0, 0.0, 0.0, 1.0],
            },
            (Shape::Cube { half }, Part::CubeFace { axis, positive }) => {
                let (n, u, v) = cube_face(axis, positive);
                let a = p.dot(u) / half;
                let b = p.dot(v) / half;
                LocalSurface {
                    p,
                    n,
                    uv: Vec2::new(0.5 * (a + 1.0), 0.5 * (1.0 - b)),
                    tangent: [u.x, u.y, u.z, 1.0],
                }
            }
            (
                Shape::Cylinder { radius, .. } | Shape::Cone { radius, .. },
                Part::TopCap | Part::BottomCap,
            ) => {
                let top = part == Part::TopCap;
                let x = 0.5 + p.x / (2.0 * radius);
                let z = p.z / (2.0 * radius);
                LocalSurface {
                    p,
                    n: if top { Vec3::Y } else { Vec3::NEG_Y },
                    uv: Vec2::new(x, if top { 0.5 + z } else { 0.5 - z }),
                    tangent: [1.0, 0.0, 0.0, 1.0],
                }
            }
            (Shape::Cylinder { half_height, .. }, _) => {
                let n = Vec3::new(p.x, 0.0, p.z).try_normalize().unwrap_or(Vec3::X);
                LocalSurface {
                    p,
                    n,
                    uv: Vec2::new(around_u(p), 0.5 - p.y / (2.0 * half_height)),
                    tangent: around_tangent(n),
                }
            }
            (
                Shape::Cone {
                    radius,
                    half_height,
                },
                _,
            ) => {
                let height = 2.0 * half_height;
                let radial = Vec3::new(p.x, 0.0, p.z).try_normalize();
                let n = match radial {
                    Some(r) => Vec3::new(height * r.x, *radius, height * r.z)
                        .try_normalize()
                        .unwrap_or(Vec3::Y),
                    None => Vec3::Y,
                };
                LocalSurface {
                    p,
                    n,
                    uv: Vec2::new(around_u(p), 0.5 - p.y / height),
                    tangent: around_tangent(radial.unwrap_or(Vec3::X)),
                }
            }
            // Unreachable combinations (a part another shape produces): a sane default.
            _ => LocalSurface {
                p,
                n: Vec3::Y,
                uv: Vec2::ZERO,
                tangent: [1.0, 0.0, 0.0, 1.0],
            },
        }
    }
}

/// u around the y axis, from +x towards −z, in [0, 1) (as `Mesh::sphere` and the rings).
fn around_u(p: Vec3) -> f32 {
    let u = (-p.z).atan2(p.x) / std::f32::consts::TAU;
    if u < 0.0 {
        u + 1.0
    } else {
        u
    }
}

/// Spherical UV of a unit direction, as `scene::mesh`'s: u around, v = 0 at +y.
fn spherical_uv(n: Vec3) -> Vec2 {
    Vec2::new(
        around_u(n),
        n.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI,
    )
}

/// dP/du around the y axis at a point of radial direction `n` (x, z): (z, 0, −x)/ρ, w = +1 (the
/// bitangent N × T then points up the image, towards +y).
fn around_tangent(n: Vec3) -> [f32; 4] {
    let rho = (n.x * n.x + n.z * n.z).sqrt();
    if rho < 1e-6 {
        return [1.0, 0.0, 0.0, 1.0];
    }
    [n.z / rho, 0.0, -n.x / rho, 1.0]
}

/// (normal, u axis, v axis) of a cube face, as `Mesh::cube`'s table.
fn cube_face(axis: usize, positive: bool) -> (Vec3, Vec3, Vec3) {
    match (axis, positive) {
        (0, true) => (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (0, false) => (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (1, true) => (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (1, false) => (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (2, true) => (Vec3::Z, Vec3::X, Vec3::Y),
        _ => (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    }
}

/// The interval of `t` where `lo ≤ o + t d ≤ hi` (one axis); `None` when empty.
fn slab(o: f32, d: f32, lo: f32, hi: f32) -> Option<(f32, f32)> {
    if d == 0.0 {
        return (o >= lo && o <= hi).then_some((f32::NEG_INFINITY, f32::INFINITY));
    }
    let inv = 1.0 / d;
    let (a, b) = ((lo - o) * inv, (hi - o) * inv);
    Some(if a <= b { (a, b) } else { (b, a) })
}

/// Roots of `a t² + 2 b t + c` (a ≠ 0), sorted, by the numerically stable formula.
fn roots(a: f32, b: f32, c: f32) -> Option<(f32, f32)> {
    let (a, b, c) = (f64::from(a), f64::from(b), f64::from(c));
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    let q = -(b + b.signum() * disc.sqrt());
    let (t0, t1) = if q == 0.0 {
        (-b / a, -b / a)
    } else {
        (q / a, c / q)
    };
    Some(if t0 <= t1 {
        (t0 as f32, t1 as f32)
    } else {
        (t1 as f32, t0 as f32)
    })
}

/// The entry point of a sphere of `radius` at the origin.
fn sphere(ray: &Ray, radius: f32) -> Option<(f32, Part)> {
    let a = ray.d.length_squared();
    if a == 0.0 {
        return None;
    }
    let (t0, _) = roots(
        a,
        ray.o.dot(ray.d),
        ray.o.length_squared() - radius * radius,
    )?;
    Some((t0, Part::Main))
}

/// A two-sided rectangle in y = 0.
fn plane(ray: &Ray, half_x: f32, half_z: f32) -> Option<(f32, Part)> {
    if ray.d.y == 0.0 {
        return None;
    }
    let t = -ray.o.y / ray.d.y;
    let p = ray.at(t);
    (p.x.abs() <= half_x && p.z.abs() <= half_z).then_some((t, Part::Main))
}

/// The entry point of an axis-aligned cube.
fn cube(ray: &Ray, half: f32) -> Option<(f32, Part)> {
    let mut enter = f32::NEG_INFINITY;
    let mut exit = f32::INFINITY;
    let mut axis = 0;
    for k in 0..3 {
        let (a, b) = slab(ray.o[k], ray.d[k], -half, half)?;
        if a > enter {
            enter = a;
            axis = k;
        }
        exit = exit.min(b);
    }
    if enter > exit || !enter.is_finite() {
        return None;
    }
    Some((
        enter,
        Part::CubeFace {
            axis,
            positive: ray.d[axis] < 0.0,
        },
    ))
}

/// The entry point of a capped cylinder.
fn cylinder(ray: &Ray, radius: f32, half_height: f32) -> Option<(f32, Part)> {
    let (y0, y1) = slab(ray.o.y, ray.d.y, -half_height, half_height)?;
    let (o, d) = (ray.o, ray.d);
    let a = d.x * d.x + d.z * d.z;
    let c = o.x * o.x + o.z * o.z - radius * radius;
    let (s0, s1) = if a <= 1e-20 * d.length_squared() {
        if c > 0.0 {
            return None;
        }
        (f32::NEG_INFINITY, f32::INFINITY)
    } else {
        roots(a, o.x * d.x + o.z * d.z, c)?
    };
    let enter = s0.max(y0);
    if enter > s1.min(y1) || !enter.is_finite() {
        return None;
    }
    let part = if s0 >= y0 {
        Part::Main
    } else if d.y < 0.0 {
        Part::TopCap
    } else {
        Part::BottomCap
    };
    Some((enter, part))
}

/// The entry point of a cone (base at −half_height, apex at +half_height).
fn cone(ray: &Ray, radius: f32, half_height: f32) -> Option<(f32, Part)> {
    let (y0, y1) = slab(ray.o.y, ray.d.y, -half_height, half_height)?;
    let (o, d) = (ray.o, ray.d);
    let k = radius / (2.0 * half_height);
    let k2 = k * k;
    // f(t) = x² + z² − k² (h − y)² ≤ 0 inside the double cone; the slab keeps the lower nappe.
    let w = half_height - o.y;
    let a = d.x * d.x + d.z * d.z - k2 * d.y * d.y;
    let b = o.x * d.x + o.z * d.z + k2 * w * d.y;
    let c = o.x * o.x + o.z * o.z - k2 * w * w;
    let inf = f32::INFINITY;
    let scale = d.x * d.x + d.z * d.z + k2 * d.y * d.y;
    let mut pieces: [Option<(f32, f32)>; 2] = [None, None];
    if a.abs() <= 1e-7 * scale {
        // Parallel to a generator: f is linear (2 b t + c).
        if b.abs() <= 1e-20 * scale.max(1e-30) {
            if c <= 0.0 {
                pieces[0] = Some((-inf, inf));
            }
        } else {
            let t = -c / (2.0 * b);
            pieces[0] = Some(if b > 0.0 { (-inf, t) } else { (t, inf) });
        }
    } else {
        match roots(a, b, c) {
            None => {
                if a < 0.0 {
                    pieces[0] = Some((-inf, inf));
                }
            }
            Some((t0, t1)) => {
                if a > 0.0 {
                    pieces[0] = Some((t0, t1));
                } else {
                    pieces = [Some((-inf, t0)), Some((t1, inf))];
                }
            }
        }
    }
    let mut best: Option<(f32, Part)> = None;
    for (s0, s1) in pieces.into_iter().flatten() {
        let enter = s0.max(y0);
        if enter > s1.min(y1) || !enter.is_finite() {
            continue;
        }
        // Entering through the slab's top plane only happens at the apex: a point of the side.
        let part = if s0 >= y0 || d.y < 0.0 {
            Part::Main
        } else {
            Part::BottomCap
        };
        if best.is_none_or(|(t, _)| enter < t) {
            best = Some((enter, part));
        }
    }
    best
}

// ---------------------------------------------------------------------------------------------
// Triangle meshes
// ---------------------------------------------------------------------------------------------

/// A node of the BVH: a box and either two children (`count == 0`, left child at `first`,
/// right child at `first + 1`) or `count` triangles from `order[first..]`.
#[derive(Debug, Clone, Copy)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    first: u32,
    count: u32,
}

/// A triangle mesh with a bounding volume hierarchy (median split on the longest axis of the
/// centroids' box, at most [`LEAF_SIZE`] triangles per leaf).
#[derive(Debug)]
pub struct MeshAccel {
    mesh: std::sync::Arc<Mesh>,
    /// Per-vertex tangents (xyz + w) when a material needs them (normal maps, anisotropy).
    tangents: Option<Vec<[f32; 4]>>,
    /// Per triangle: p0, e1 = p1 − p0, e2 = p2 − p0.
    tris: Vec<[Vec3; 3]>,
    order: Vec<u32>,
    nodes: Vec<Node>,
}

const LEAF_SIZE: usize = 4;

impl MeshAccel {
    /// Builds the BVH; `with_tangents` takes per-vertex tangents as the GPU path does
    /// (`render::mesh::mesh_tangents`: the mesh's own, else MikkTSpace on the UVs).
    pub fn new(mesh: std::sync::Arc<Mesh>, with_tangents: bool) -> Self {
        let count = mesh.positions.len();
        let mut tris = Vec::with_capacity(mesh.indices.len() / 3);
        let mut order = Vec::with_capacity(mesh.indices.len() / 3);
        for (k, t) in mesh.indices.chunks_exact(3).enumerate() {
            if t.iter().any(|&i| i as usize >= count) {
                continue;
            }
            let p = [0, 1, 2].map(|j| mesh.positions[t[j] as usize]);
            tris.push([p[0], p[1] - p[0], p[2] - p[0]]);
            order.push(k as u32);
        }
        // `tris` is indexed by triangle number; keep it dense even if an index was bad.
        let mut dense = vec![[Vec3::ZERO; 3]; mesh.indices.len() / 3];
        for (tri, &k) in tris.iter().zip(&order) {
            dense[k as usize] = *tri;
        }
        let tangents = with_tangents.then(|| crate::render::mesh::mesh_tangents(&mesh));
        let mut accel = MeshAccel {
            mesh,
            tangents,
            tris: dense,
            order,
            nodes: Vec::new(),
        };
        accel.build();
        accel
    }

    fn tri_bounds(&self, k: u32) -> (Vec3, Vec3) {
        let [p0, e1, e2] = self.tris[k as usize];
        let (p1, p2) = (p0 + e1, p0 + e2);
        (p0.min(p1).min(p2), p0.max(p1).max(p2))
    }

    fn build(&mut self) {
        let n = self.order.len();
        let centroids: Vec<Vec3> = (0..self.tris.len() as u32)
            .map(|k| {
                let (lo, hi) = self.tri_bounds(k);
                (lo + hi) * 0.5
            })
            .collect();
        self.nodes.push(Node {
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
            first: 0,
            count: n as u32,
        });
        // (node index, range start, range end)
        let mut stack = vec![(0usize, 0usize, n)];
        while let Some((node, start, end)) = stack.pop() {
            let mut lo = Vec3::splat(f32::INFINITY);
            let mut hi = Vec3::splat(f32::NEG_INFINITY);
            let mut clo = Vec3::splat(f32::INFINITY);
            let mut chi = Vec3::splat(f32::NEG_INFINITY);
            for &k in &self.order[start..end] {
                let (a, b) = self.tri_bounds(k);
                lo = lo.min(a);
                hi = hi.max(b);
                let c = centroids[k as usize];
                clo = clo.min(c);
                chi = chi.max(c);
            }
            self.nodes[node].lo = lo;
            self.nodes[node].hi = hi;
            let count = end - start;
            let extent = chi - clo;
            if count <= LEAF_SIZE || extent.max_element() <= 0.0 {
                self.nodes[node].first = start as u32;
                self.nodes[node].count = count as u32;
                continue;
            }
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = start + count / 2;
            self.order[start..end].select_nth_unstable_by(count / 2, |a, b| {
                centroids[*a as usize][axis].total_cmp(&centroids[*b as usize][axis])
            });
            let left = self.nodes.len();
            let empty = Node {
                lo: Vec3::ZERO,
                hi: Vec3::ZERO,
                first: 0,
                count: 0,
            };
            self.nodes.push(empty);
            self.nodes.push(empty);
            self.nodes[node].first = left as u32;
            self.nodes[node].count = 0;
            stack.push((left, start, mid));
            stack.push((left + 1, mid, end));
        }
    }

    pub fn bounds(&self) -> (Vec3, Vec3) {
        match self.nodes.first() {
            Some(n) if !self.order.is_empty() => (n.lo, n.hi),
            _ => (Vec3::ZERO, Vec3::ZERO),
        }
    }

    /// The nearest triangle hit (either side) with `t` in `[t_min, t_max]`.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, Part)> {
        if self.order.is_empty() {
            return None;
        }
        let inv = Vec3::ONE / ray.d;
        let mut best: Option<(f32, Part)> = None;
        let mut t_best = t_max;
        let mut stack = [0u32; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = self.nodes[stack[sp] as usize];
            if box_hit(ray.o, inv, node.lo, node.hi, t_min, t_best).is_none() {
                continue;
            }
            if node.count > 0 {
                let range = node.first as usize..(node.first + node.count) as usize;
                for &k in &self.order[range] {
                    if let Some((t, b1, b2)) = triangle(ray, &self.tris[k as usize]) {
                        if t >= t_min && t <= t_best {
                            t_best = t;
                            best = Some((t, Part::Triangle { index: k, b1, b2 }));
                        }
                    }
                }
                continue;
            }
            // Visit the nearer child first.
            let (l, r) = (node.first, node.first + 1);
            let dl = {
                let c = self.nodes[l as usize];
                box_hit(ray.o, inv, c.lo, c.hi, t_min, t_best)
            };
            let dr = {
                let c = self.nodes[r as usize];
                box_hit(ray.o, inv, c.lo, c.hi, t_min, t_best)
            };
            if sp + 2 > stack.len() {
                // Deeper than any median-split tree of 2^32 triangles: never happens.
                continue;
            }
            match (dl, dr) {
                (Some(a), Some(b)) => {
                    let (near, far) = if a <= b { (l, r) } else { (r, l) };
                    stack[sp] = far;
                    stack[sp + 1] = near;
                    sp += 2;
                }
                (Some(_), None) => {
                    stack[sp] = l;
                    sp += 1;
                }
                (None, Some(_)) => {
                    stack[sp] = r;
                    sp += 1;
                }
                (None, None) => {}
            }
        }
        best
    }

    /// Interpolated attributes of triangle `index` at barycentrics (b1, b2).
    fn surface(&self, index: u32, b1: f32, b2: f32) -> LocalSurface {
        let m = &self.mesh;
        let base = index as usize * 3;
        let ids = [0, 1, 2].map(|k| m.indices[base + k] as usize);
        let w = [1.0 - b1 - b2, b1, b2];
        let [p0, e1, e2] = self.tris[index as usize];
        let p = p0 + e1 * b1 + e2 * b2;
        let mut n = Vec3::ZERO;
        let mut uv = Vec2::ZERO;
        let mut t = [0.0f32; 4];
        for k in 0..3 {
            n += m.normals.get(ids[k]).copied().unwrap_or(Vec3::Y) * w[k];
            if let Some(v) = m.uvs.get(ids[k]) {
                uv += *v * w[k];
            }
            if let Some(tan) = self.tangents.as_ref().and_then(|ts| ts.get(ids[k])) {
                for c in 0..3 {
                    t[c] += tan[c] * w[k];
                }
                t[3] += tan[3] * w[k];
            }
        }
        let geometric = e1.cross(e2).try_normalize().unwrap_or(Vec3::Y);
        LocalSurface {
            p,
            n: n.try_normalize().unwrap_or(geometric),
            uv,
            tangent: if self.tangents.is_some() {
                [t[0], t[1], t[2], if t[3] < 0.0 { -1.0 } else { 1.0 }]
            } else {
                [0.0; 4]
            },
        }
    }

    /// The interpolated vertex colour of triangle `index` at barycentrics (b1, b2): white
    /// without vertex colours.
    pub fn vertex_color(&self, index: u32, b1: f32, b2: f32) -> glam::Vec4 {
        let m = &self.mesh;
        if m.colors.len() != m.positions.len() {
            return glam::Vec4::ONE;
        }
        let base = index as usize * 3;
        let w = [1.0 - b1 - b2, b1, b2];
        (0..3)
            .map(|k| m.colors[m.indices[base + k] as usize] * w[k])
            .sum()
    }

    /// The geometric normal of triangle `index` (e1 × e2, not normalised): its front side, as
    /// the winding says.
    pub fn face_normal(&self, index: u32) -> Vec3 {
        let [_, e1, e2] = self.tris[index as usize];
        e1.cross(e2)
    }

    /// The vertex normals of triangle `index` (for interpolation after the object
    /// transform, as the GPU does).
    pub fn vertex_normals(&self, index: u32) -> [Vec3; 3] {
        let m = &self.mesh;
        let base = index as usize * 3;
        [0, 1, 2].map(|k| {
            m.normals
                .get(m.indices[base + k] as usize)
                .copied()
                .unwrap_or(Vec3::Y)
        })
    }
}

/// Entry distance of a ray into a box within `[t_min, t_max]`, or `None`.
#[inline]
fn box_hit(o: Vec3, inv: Vec3, lo: Vec3, hi: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    // NaN (0 · ∞ on a flat box) must not reject: min/max of glam ignore NaN like fmin/fmax.
    let t0 = a.min(b);
    let t1 = a.max(b);
    let enter = t0.max_element().max(t_min);
    let exit = t1.min_element().min(t_max);
    (enter <= exit * (1.0 + 4.0 * f32::EPSILON)).then_some(enter)
}

/// Two-sided Möller–Trumbore: `(t, b1, b2)`.
#[inline]
fn triangle(ray: &Ray, tri: &[Vec3; 3]) -> Option<(f32, f32, f32)> {
    let [p0, e1, e2] = *tri;
    let pv = ray.d.cross(e2);
    let det = e1.dot(pv);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = ray.o - p0;
    let b1 = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let qv = tv.cross(e1);
    let b2 = ray.d.dot(qv) * inv;
    if b2 < 0.0 || b1 + b2 > 1.0 {
        return None;
    }
    Some((e2.dot(qv) * inv, b1, b2))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray {
        Ray {
            o: Vec3::from_array(o),
            d: Vec3::from_array(d),
        }
    }

    #[test]
    fn primitives_entry_points() {
        let r = ray([0.0, 0.0, 5.0], [0.0, 0.0, -1.0]);
        let s = Shape::Sphere { radius: 1.0 };
        assert_eq!(s.intersect(&r, 0.0, 100.0).unwrap().0, 4.0);
        // From inside a culled sphere nothing is seen.
        let inside = ray([0.0, 0.0, 0.0], [0.0, 0.0, -1.0]);
        assert!(s.intersect(&inside, 0.0, 100.0).is_none());
        let c = Shape::Cube { half: 0.5 };
        let (t, part) = c.intersect(&r, 0.0, 100.0).unwrap();
        assert_eq!(t, 4.5);
        assert_eq!(
            part,
            Part::CubeFace {
                axis: 2,
                positive: true
            }
        );
        let cyl = Shape::Cylinder {
            radius: 0.5,
            half_height: 1.0,
        };
        assert_eq!(cyl.intersect(&r, 0.0, 100.0).unwrap().0, 4.5);
        let down = ray([0.0, 5.0, 0.0], [0.0, -1.0, 0.0]);
        let (t, part) = cyl.intersect(&down, 0.0, 100.0).unwrap();
        assert_eq!((t, part), (4.0, Part::TopCap));
        let cone = Shape::Cone {
            radius: 0.5,
            half_height: 0.5,
        };
        // Halfway up the cone the radius is 0.25.
        let (t, part) = cone.intersect(&r, 0.0, 100.0).unwrap();
        assert!((t - 4.75).abs() < 1e-6 && part == Part::Main, "{t}");
        let up = ray([0.0, -5.0, 0.0], [0.0, 1.0, 0.0]);
        let (t, part) = cone.intersect(&up, 0.0, 100.0).unwrap();
        assert_eq!((t, part), (4.5, Part::BottomCap));
        // Cone surface normal tilts up by atan(r / h).
        let hit = cone.surface(&r, 4.75, Part::Main);
        assert!((hit.n - Vec3::new(0.0, 0.5, 1.0).normalize()).length() < 1e-5);
        let p = Shape::Plane {
            half_x: 1.0,
            half_z: 1.0,
        };
        assert_eq!(p.intersect(&down, 0.0, 100.0).unwrap().0, 5.0);
        assert_eq!(p.intersect(&up, 0.0, 100.0).unwrap().0, 5.0);
    }

    #[test]
    fn surfaces_match_the_tessellated_uvs() {
        let s = Shape::Sphere { radius: 2.0 };
        let mesh = Mesh::sphere(2.0, 16, 8);
        for (p, uv) in mesh.positions.iter().zip(&mesh.uvs) {
            if p.x.abs() + p.z.abs() < 1e-3 || uv.x > 0.999 {
                continue; // poles and the duplicated seam
            }
            let r = Ray {
                o: *p * 2.0,
                d: -*p,
            };
            let (t, part) = s.intersect(&r, 0.0, 10.0).unwrap();
            let hit = s.surface(&r, t, part);
            assert!((hit.uv - *uv).length() < 1e-5, "{} vs {}", hit.uv, uv);
        }
        let cube = Mesh::cube(1.0);
        let c = Shape::Cube { half: 0.5 };
        for t in cube.indices.chunks_exact(3) {
            let [a, b, cc] = [0, 1, 2].map(|k| t[k] as usize);
            let centre = (cube.positions[a] + cube.positions[b] + cube.positions[cc]) / 3.0;
            let uv = (cube.uvs[a] + cube.uvs[b] + cube.uvs[cc]) / 3.0;
            let n = cube.normals[a];
            let r = Ray {
                o: centre + n * 3.0,
                d: -n,
            };
            let (t, part) = c.intersect(&r, 0.0, 10.0).unwrap();
            let hit = c.surface(&r, t, part);
            assert!((hit.n - n).length() < 1e-6);
            assert!((hit.uv - uv).length() < 1e-5, "{} vs {}", hit.uv, uv);
        }
    }

    #[test]
    fn bvh_finds_the_nearest_triangle() {
        let mesh = std::sync::Arc::new(Mesh::sphere(1.0, 64, 32));
        let accel = MeshAccel::new(mesh, false);
        for k in 0..200 {
            let a = k as f32 * 0.1;
            let o = Vec3::new(a.cos() * 3.0, (a * 0.7).sin(), a.sin() * 3.0);
            let r = Ray { o, d: -o };
            let (t, _) = accel.intersect(&r, 0.0, 10.0).unwrap();
            // The inscribed polyhedron: between cos(π/32) and 1 of the radius.
            let d = o.length() * (1.0 - t);
            assert!((0.99..=1.0 + 1e-5).contains(&d), "{d}");
        }
    }
}
