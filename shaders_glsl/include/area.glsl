// Area lights (issue 36; docs/area-lights.md): rect, disk, sphere and tube emitters of uniform
// radiance, shaded by linearly transformed cosines (LTC: polygons, tubes as their facing ribbon),
// Karis's representative point or N stratified samples. Included by lighting.glsl; code for a
// method the scene does not use is left out by LIGHT_KINDS (LK_AREA_*), and a scene without area
// lights has none of it.
#ifndef LUZ_AREA_GLSL
#define LUZ_AREA_GLSL

// area_data (bindings.glsl): the LTC table (LTC_SIZE² entries of two vec4, row = view index t,
// column = roughness index a; src/brdf/ltc.rs) when the scene has an LTC light, then
// AREA_VEC4S vec4 per light from frame.counts.z (src/render/gpu.rs: GpuAreaLight).
struct AreaLight {
    vec3 position;
    uint shape;      // AREA_RECT, AREA_DISK, AREA_SPHERE, AREA_TUBE
    vec3 direction;  // emitting normal (rect, disk), axis (tube)
    uint method;     // AREA_LTC, AREA_RP, AREA_SAMPLED
    uint samples;
    vec3 radiance;
    float range;     // 0: none
    vec3 ex;         // rect: half width; disk: radius along x; tube: half axis
    bool two_sided;
    vec3 ey;         // rect: half height; disk: radius along y
    float radius;    // disk, sphere, tube
};

AreaLight area_light(uint k) {
    uint b = opaque(frame.counts.z) + k * AREA_VEC4S;
    vec4 v0 = area_data[b];
    vec4 v1 = area_data[b + 1u];
    vec4 v2 = area_data[b + 2u];
    vec4 v3 = area_data[b + 3u];
    vec4 v4 = area_data[b + 4u];
    AreaLight a;
    a.position = v0.xyz;
    a.shape = uint(v0.w);
    a.direction = v1.xyz;
    uint m = uint(v1.w);
    a.method = m & 3u;
    a.samples = m >> 2u;
    a.radiance = v2.rgb;
    a.range = v2.w;
    a.ex = v3.xyz;
    a.two_sided = v3.w > 0.5;
    a.ey = v4.xyz;
    a.radius = v4.w;
    return a;
}

// A disk is integrated as the regular AREA_DISK_EDGES-gon of the same area (docs/area-lights.md
// states the error this leaves).
#define AREA_DISK_EDGES 24u

// Lagarde & de Rousiers 2014's illuminance of a sphere (or facing disk) of sin²(half-angle)
// sin2_s whose centre is at cos θ = cos_t from the normal, per unit radiance; exact above the
// horizon (π sin² σ cos θ), and with the horizon cut otherwise.
float area_sphere_irradiance(float cos_t, float sin2_s) {
    cos_t = clamp(cos_t, -0.9999, 0.9999);
    float c2 = cos_t * cos_t;
    if (c2 > sin2_s) {
        return cos_t > 0.0 ? M_PI * sin2_s * cos_t : 0.0;
    }
    float sin_t = sqrt(1.0 - c2);
    float x = sqrt(1.0 / sin2_s - 1.0);
    float y = -x * (cos_t / sin_t);
    float s = sin_t * sqrt(max(1.0 - y * y, 0.0));
    return max((cos_t * acos(clamp(y, -1.0, 1.0)) - x * s) * sin2_s + atan(s / x), 0.0);
}

// The cosine-weighted integral of the great arc from a to b (unit vectors) as a vector (Heitz &
// Hill 2017's edge form: (a × b) θ/(2π sin θ), the factor by their cubic rational fit, no atan):
// the sum over a polygon's edges is its vector form factor, whose z is the polygon's form factor
// (Lambert's formula) when it lies above the horizon.
vec3 area_edge(vec3 a, vec3 b) {
    float x = dot(a, b);
    float y = abs(x);
    float u = 0.8543985 + (0.4965155 + 0.0145206 * y) * y;
    float w = 3.4175940 + (4.1616724 + y) * y;
    float v = u / w;
    float theta_sin = x > 0.0 ? v : 0.5 * inversesqrt(max(1.0 - x * x, 1e-7)) - v;
    // a × (b − a) = a × b, but without its cancellation for close a and b: b − a is exact (close
    // floats subtract exactly), while a × b of nearly parallel vectors keeps only an absolute
    // error of ~1e-7, as large as a tiny polygon's whole sum (a 1 mm rect at 1.5 m was 7.5× off).
    return cross(a, b - a) * theta_sin;
}

// The form factor of a polygon from its vector form factor F, the part below the horizon (z < 0)
// cut as for the sphere of the same F (Heitz & Hill 2017's approximation, with Lagarde & de
// Rousiers' closed form instead of a table): exact when the polygon lies wholly above.
float ltc_clipped(vec3 F) {
    float len2 = dot(F, F);
    if (len2 < 1e-18) {
        return 0.0;
    }
    float len = sqrt(len2);
    return area_sphere_irradiance(F.z / len, min(len, 0.9999)) / M_PI;
}

// The vector form factors of the emitter's polygon (centre c, axes ex, ey, n vertices) seen from
// P, in the shading frame (`to_frame`, diffuse) and through the LTC's M⁻¹ (`minv`, specular;
// `spec` false: skipped), each oriented towards the polygon.
void ltc_polygon(mat3 to_frame, mat3 minv, bool spec, vec3 P, vec3 c, vec3 ex, vec3 ey, uint n,
                 out vec3 fd, out vec3 fs) {
    fd = vec3(0.0);
    fs = vec3(0.0);
    vec3 d0 = to_frame * (c - P);
    vec3 dx = to_frame * ex;
    vec3 dy = to_frame * ey;
    if ((LIGHT_KINDS & (LK_AREA_DISK | LK_AREA_SPHERE)) == 0u) {
        // Rects only: the four corners, unrolled.
        vec3 q[4] = vec3[](d0 + dx + dy, d0 - dx + dy, d0 - dx - dy, d0 + dx - dy);
        vec3 u[4];
        vec3 w[4];
        for (uint k = 0u; k < 4u; ++k) {
            u[k] = normalize(q[k]);
            w[k] = spec ? normalize(minv * q[k]) : u[k];
        }
        for (uint k = 0u; k < 4u; ++k) {
            fd += area_edge(u[k], u[(k + 1u) & 3u]);
            if (spec) {
                fs += area_edge(w[k], w[(k + 1u) & 3u]);
            }
        }
        fd *= dot(fd, d0) < 0.0 ? -1.0 : 1.0;
        fs *= dot(fs, minv * d0) < 0.0 ? -1.0 : 1.0;
        return;
    }
    // Vertex k at angle φ_k = 2πk/n (a rect: its corners at 45°, 135°, … scaled by √2).
    float step = 2.0 * M_PI / float(n);
    float scale = n == 4u ? sqrt(2.0) : 1.0;
    float phi0 = n == 4u ? 0.25 * M_PI : 0.0;
    vec2 cs = vec2(cos(phi0), sin(phi0)) * scale;
    vec2 rot = vec2(cos(step), sin(step));
    vec3 first_d = normalize(d0 + cs.x * dx + cs.y * dy);
    vec3 first_s = normalize(minv * (d0 + cs.x * dx + cs.y * dy));
    vec3 prev_d = first_d;
    vec3 prev_s = first_s;
    for (uint k = 1u; k <= n; ++k) {
        vec3 vd_k;
        vec3 vs_k;
        if (k == n) {
            vd_k = first_d;
            vs_k = first_s;
        } else {
            cs = vec2(cs.x * rot.x - cs.y * rot.y, cs.x * rot.y + cs.y * rot.x);
            vec3 q = d0 + cs.x * dx + cs.y * dy;
            vd_k = normalize(q);
            vs_k = spec ? normalize(minv * q) : vd_k;
        }
        fd += area_edge(prev_d, vd_k);
        if (spec) {
            fs += area_edge(prev_s, vs_k);
        }
        prev_d = vd_k;
        prev_s = vs_k;
    }
    // Either winding: the form factor vector points into the polygon's cone.
    fd *= dot(fd, d0) < 0.0 ? -1.0 : 1.0;
    fs *= dot(fs, minv * d0) < 0.0 ? -1.0 : 1.0;
}

// The polygon (centre, axes, vertex count) the LTC integrates for a rect, a disk, or the disk
// facing P that covers a sphere's cone exactly. False: P sees the emitter's back (one-sided) or
// is inside the sphere.
bool area_polygon(AreaLight a, vec3 P, out vec3 c, out vec3 ex, out vec3 ey, out uint n) {
    c = a.position;
    ex = a.ex;
    ey = a.ey;
    n = 4u;
    if ((LIGHT_KINDS & LK_AREA_SPHERE) != 0u && a.shape == AREA_SPHERE) {
        vec3 w = P - c;
        float d2 = dot(w, w);
        float r2 = a.radius * a.radius;
        if (d2 <= r2) {
            return false;
        }
        w *= inversesqrt(d2);
        vec3 t = abs(w.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
        vec3 u = normalize(cross(w, t));
        vec3 v = cross(w, u);
        // A disk through the centre, perpendicular to w, seen under the sphere's half-angle.
        float rd = a.radius * sqrt(d2 / (d2 - r2));
        ex = u * rd;
        ey = v * rd;
    } else if (!a.two_sided && dot(P - c, a.direction) <= 0.0) {
        return false;
    }
    if ((LIGHT_KINDS & (LK_AREA_DISK | LK_AREA_SPHERE)) != 0u && a.shape != AREA_RECT) {
        // The regular polygon of the disk's area: circumradius · sqrt(2π / (n sin(2π/n))).
        n = AREA_DISK_EDGES;
        float s = sqrt(2.0 * M_PI / (float(n) * sin(2.0 * M_PI / float(n))));
        ex *= s;
        ey *= s;
    }
    return true;
}

// Bilinear lookup of the LTC table at view index coordinate x_t and roughness coordinate x_a
// (both in [0, 1]): (M⁻¹ elements, (norm, Schlick weight)).
void ltc_lookup(float x_t, float x_a, out vec4 m, out vec4 f) {
    float n1 = float(LTC_SIZE - 1);
    vec2 g = clamp(vec2(x_a, x_t), 0.0, 1.0) * n1;
    vec2 g0 = min(floor(g), vec2(n1 - 1.0));
    vec2 w = g - g0;
    uint a0 = uint(g0.x);
    uint t0 = uint(g0.y);
    m = vec4(0.0);
    f = vec4(0.0);
    for (uint j = 0u; j < 2u; ++j) {
        for (uint i = 0u; i < 2u; ++i) {
            float wt = (i == 0u ? 1.0 - w.x : w.x) * (j == 0u ? 1.0 - w.y : w.y);
            uint e = ((t0 + j) * uint(LTC_SIZE) + a0 + i) * 2u;
            m += wt * area_data[e];
            f += wt * area_data[e + 1u];
        }
    }
}

// The range window of point lights (lighting.glsl), on the distance to the emitter's centre.
float area_window(AreaLight a, vec3 P) {
    if ((LIGHT_KINDS & LK_RANGE) == 0u || a.range <= 0.0) {
        return 1.0;
    }
    float x = length(P - a.position) / a.range;
    float w = clamp(1.0 - (x * x) * (x * x), 0.0, 1.0);
    return w * w;
}

// Karis 2013's representative point for spheres and tubes: the specular lobe is evaluated towards
// the point of the emitter nearest the reflected ray, with its D widened from α to
// α' = sat(α + r/(2d)) and the energy renormalised by (α/α')²; the diffuse term sees the sphere's
// (or, for a tube, the nearest point's sphere's) irradiance from its centre, exact above the
// horizon (no horizon cut: the cheap method).
vec3 area_representative_point(AreaLight a, Surface s, vec3 P, vec3 V) {
    vec3 n = s.n;
    vec3 r = reflect(-V, n);
    vec3 c = a.position;
    if ((LIGHT_KINDS & LK_AREA_TUBE) != 0u && a.shape == AREA_TUBE) {
        // The segment's point nearest the reflected ray, then a sphere of the tube's radius there.
        vec3 l0 = a.position - a.ex - P;
        vec3 l1 = a.position + a.ex - P;
        vec3 ld = l1 - l0;
        float rd = dot(r, ld);
        float t = clamp((dot(r, l0) * rd - dot(l0, ld)) / max(dot(ld, ld) - rd * rd, 1e-12), 0.0, 1.0);
        c = P + l0 + ld * t;
    }
    vec3 L = c - P;
    float d2 = dot(L, L);
    float d = sqrt(d2);
    float sin2 = min(a.radius * a.radius / max(d2, 1e-12), 0.9999);
    vec3 lc = L / max(d, 1e-12);
    vec3 to_ray = dot(L, r) * r - L;
    vec3 q = L + to_ray * clamp(a.radius / max(length(to_ray), 1e-12), 0.0, 1.0);
    vec3 ls = normalize(q);
    float roughness = s.p.color.w;
    float alpha = max(roughness * roughness, BRDF_ALPHA_MIN);
    float alpha2 = clamp(alpha + a.radius / (2.0 * max(d, 1e-6)), 0.0, 1.0);
    float norm = (alpha / alpha2) * (alpha / alpha2);
    // One evaluation, towards the representative point: its diffuse term with the irradiance of
    // the sphere above the horizon (π sin²σ cos θ from the centre), its specular term with the
    // sphere's solid angle at that point.
    BrdfTerms t;
    if (MODEL == BRDF_MODEL_METAL_ROUGH) {
        t = brdf_metal_rough_base_terms_lobe(s.p, n, ls, V, brdf_anisotropic_lobe(s.p, n, s.x, s.y));
    } else {
        t = brdf_eval_terms(s.p, n, ls, V, s.x, s.y);
    }
    float e_d = M_PI * sin2 * max(dot(n, lc), 0.0);
    float e_s = M_PI * sin2 * max(dot(n, ls), 0.0) * norm;
    return t.diffuse * e_d + t.specular * e_s;
}

// The radical inverse of i in base 2 (Hammersley's second coordinate).
float area_radical_inverse(uint i) {
    return float(bitfieldReverse(i)) * 2.3283064365386963e-10;
}

// N stratified samples (a Hammersley set) of the emitter: rect and disk by area, spheres by the
// cone they subtend, tubes by the area of their side; each sample through the material's BRDF.
vec3 area_sampled(AreaLight a, Surface s, vec3 P, vec3 V) {
    uint count = max(a.samples, 1u);
    vec3 sum = vec3(0.0);
    vec3 w = vec3(0.0);
    vec3 u = vec3(0.0);
    vec3 v = vec3(0.0);
    float cos_max = 1.0;
    float inv_n = 1.0 / float(count);
    if ((LIGHT_KINDS & LK_AREA_SPHERE) != 0u && a.shape == AREA_SPHERE) {
        vec3 to_c = a.position - P;
        float d2 = dot(to_c, to_c);
        if (d2 <= a.radius * a.radius) {
            return vec3(0.0);
        }
        w = to_c * inversesqrt(d2);
        vec3 t = abs(w.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
        u = normalize(cross(w, t));
        v = cross(w, u);
        cos_max = sqrt(max(1.0 - a.radius * a.radius / d2, 0.0));
    } else if ((LIGHT_KINDS & LK_AREA_TUBE) != 0u && a.shape == AREA_TUBE) {
        w = normalize(a.ex);
        vec3 t = abs(w.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
        u = normalize(cross(w, t));
        v = cross(w, u);
    }
    for (uint i = 0u; i < count; ++i) {
        float u1 = (float(i) + 0.5) * inv_n;
        float u2 = area_radical_inverse(i);
        vec3 l;
        float weight;  // the sample's solid angle
        if ((LIGHT_KINDS & LK_AREA_SPHERE) != 0u && a.shape == AREA_SPHERE) {
            float ct = 1.0 - u1 * (1.0 - cos_max);
            float st = sqrt(max(1.0 - ct * ct, 0.0));
            float phi = 2.0 * M_PI * u2;
            l = ct * w + st * (cos(phi) * u + sin(phi) * v);
            weight = 2.0 * M_PI * (1.0 - cos_max) * inv_n;
        } else {
            vec3 q;
            vec3 nq;
            float area;
            if (a.shape == AREA_RECT) {
                q = a.position + (2.0 * u1 - 1.0) * a.ex + (2.0 * u2 - 1.0) * a.ey;
                nq = a.direction;
                area = 4.0 * length(a.ex) * length(a.ey);
            } else if ((LIGHT_KINDS & LK_AREA_DISK) != 0u && a.shape == AREA_DISK) {
                float rr = sqrt(u1);
                float phi = 2.0 * M_PI * u2;
                q = a.position + rr * (cos(phi) * a.ex + sin(phi) * a.ey);
                nq = a.direction;
                area = M_PI * a.radius * a.radius;
            } else {
                float phi = 2.0 * M_PI * u2;
                nq = cos(phi) * u + sin(phi) * v;
                q = a.position + (2.0 * u1 - 1.0) * a.ex + a.radius * nq;
                area = 2.0 * M_PI * a.radius * 2.0 * length(a.ex);
            }
            vec3 lq = q - P;
            float dq2 = max(dot(lq, lq), 1e-12);
            l = lq * inversesqrt(dq2);
            float cos_q = -dot(nq, l);
            if (a.two_sided) {
                cos_q = abs(cos_q);
            }
            weight = max(cos_q, 0.0) * area / dq2 * inv_n;
        }
        if (weight > 0.0) {
            sum += brdf_radiance_unit(s.p, s.n, l, V, s.x, s.y, vec3(weight));
        }
    }
    return sum;
}

// Tubes by LTC (LK_AREA_LTC_TUBE): the tube's facing ribbon (the rectangle of its width 2r along
// its axis, facing the shading point: its silhouette) as a 4-vertex polygon through the LTC, as
// rects are, plus flat disks of area πr² at its ends facing out along the axis, taken at their
// centres (Heitz & Hill 2017's course's caps; luz counts half of each, see ltc_tube_caps). The CPU
// mirror, with the same names and tests against a thin cylinder and at roughness 0.05:
// crates/luz-core/src/brdf/ltc_line.rs. Points in the shading frame; the axis is its first end p
// and its vector dp.

// The LTC of minv over the facing ribbon: its width along p × dp, its half-width r d/√(d² − r²)
// (d: the axis's distance; the edges on the cylinder's silhouette lines, asin(r/d) from the
// plane through the axis; past the tube's ends at most 2r/√3). The axis's part below the transformed horizon is cut
// off first; the corners then reach at most that half-width below it.
float ltc_ribbon(vec3 p, vec3 dp, float r, mat3 minv) {
    vec3 n = cross(p, dp);
    float n2 = dot(n, n);
    if (n2 <= 0.0) {
        return 0.0;
    }
    vec3 q = minv * p;
    vec3 dq = minv * dp;
    float z0 = q.z;
    float z1 = q.z + dq.z;
    if (z0 <= 0.0 && z1 <= 0.0) {
        return 0.0;
    }
    float s_h = z0 / (z0 - z1);
    vec3 a = q + (z0 < 0.0 ? s_h : 0.0) * dq;
    vec3 e = q + (z1 < 0.0 ? s_h : 1.0) * dq;
    float n_len = sqrt(n2);
    float dp2 = dot(dp, dp);
    float d2 = n2 / dp2;
    float foot = -dot(p, dp);
    float h = r * inversesqrt(max(1.0 - r * r / d2, foot >= 0.0 && foot <= dp2 ? 1e-4 : 0.75));
    vec3 w = minv * (n * (h / n_len));
    vec3 c0 = normalize(a + w);
    vec3 c1 = normalize(e + w);
    vec3 c2 = normalize(e - w);
    vec3 c3 = normalize(a - w);
    vec3 f = area_edge(c0, c1) + area_edge(c1, c2) + area_edge(c2, c3) + area_edge(c3, c0);
    // The form factor is f.z (Lambert's formula), not ltc_clipped: the equivalent sphere of a
    // long thin ribbon near the horizon straddles it though the ribbon does not.
    f *= dot(f, a + e) < 0.0 ? -1.0 : 1.0;
    return max(f.z, 0.0);
}

// The two end disks (πr², facing out along the axis), each its solid angle times the LTC at its
// centre: r² |det M⁻¹| max(q.z, 0) |cos_e| |e| / |q|⁴, q = M⁻¹e (the course's I_ltc_disks): (half
// of each end's, the end facing the point's whole). A cylinder's silhouette is the ribbon and half
// of each end's ellipse, each at its own distance, until seen end-on the far end hides behind the
// near one: ltc_tube takes the larger.
vec2 ltc_tube_caps(vec3 p, vec3 dp, float r, mat3 minv) {
    vec3 t = normalize(dp);
    float det = abs(determinant(minv));
    vec3 e2 = p + dp;
    vec3 q1 = minv * p;
    vec3 q2 = minv * e2;
    float n1 = dot(q1, q1);
    float n2 = dot(q2, q2);
    float tp = dot(t, p);
    float c1 = r * r * det * max(q1.z, 0.0) * abs(tp) / (n1 * n1);
    float c2 = r * r * det * max(q2.z, 0.0) * abs(dot(t, e2)) / (n2 * n2);
    return vec2(0.5 * (c1 + c2), tp > 0.0 ? c1 : c2);
}

// A tube's LTC form factor: the facing ribbon plus half of each end disk, or the end disk facing
// the point alone if larger (end-on); at most 1 (the caps, taken at their centres, grow without
// bound as the point nears an end).
float ltc_tube(vec3 p, vec3 dp, float r, mat3 minv) {
    vec2 caps = ltc_tube_caps(p, dp, r, minv);
    return min(max(ltc_ribbon(p, dp, r, minv) + caps.x, caps.y), 1.0);
}

// LTC: the diffuse term's form factor (the cosine itself) and GGX's fitted lobe, for Lambert and
// metallic-roughness materials (area_shade gives other models 16 samples instead). Rects, disks and
// spheres by their polygon (LK_AREA_LTC), tubes by their facing ribbon's (LK_AREA_LTC_TUBE): a scene with
// one kind compiles only its path.
vec3 area_ltc(AreaLight a, Surface s, vec3 P, vec3 V) {
    bool tube = (LIGHT_KINDS & LK_AREA_LTC_TUBE) != 0u
        && ((LIGHT_KINDS & LK_AREA_LTC) == 0u || a.shape == AREA_TUBE);
    vec3 c;
    vec3 ex;
    vec3 ey;
    uint n;
    if (!tube && !area_polygon(a, P, c, ex, ey, n)) {
        return vec3(0.0);
    }
    vec3 N = s.n;
    float n_v = dot(N, V);
    vec3 t1 = V - N * n_v;
    float len2 = dot(t1, t1);
    if (len2 < 1e-12) {
        t1 = abs(N.x) < 0.9 ? cross(N, vec3(1.0, 0.0, 0.0)) : cross(N, vec3(0.0, 1.0, 0.0));
        len2 = dot(t1, t1);
    }
    t1 *= inversesqrt(len2);
    mat3 to_frame = transpose(mat3(t1, cross(N, t1), N));
    // The tube's axis in the frame: its first end and the axis vector (given directly, so that a
    // tiny tube's ends do not cancel).
    vec3 tp = vec3(0.0);
    vec3 tdp = vec3(0.0);
    if (tube) {
        tp = to_frame * (a.position - a.ex - P);
        tdp = to_frame * (2.0 * a.ex);
    }
    vec3 fd;
    vec3 fs;
    if (MODEL == BRDF_MODEL_LAMBERT) {
        float ffd;
        if (tube) {
            ffd = ltc_tube(tp, tdp, a.radius, mat3(1.0));
        } else {
            ltc_polygon(to_frame, mat3(1.0), false, P, c, ex, ey, n, fd, fs);
            ffd = ltc_clipped(fd);
        }
        return s.p.color.rgb * ffd;
    }
    BrdfParams p = s.p;
    float roughness = p.color.w;
    float metallic = p.spec.w;
    vec3 f0 = mix(p.spec.rgb, p.color.rgb, metallic);
    vec4 m;
    vec4 f;
    ltc_lookup(sqrt(max(1.0 - clamp(n_v, 0.0, 1.0), 0.0)), roughness, m, f);
    mat3 minv = mat3(vec3(m.x, 0.0, m.y), vec3(0.0, 1.0, 0.0), vec3(m.z, 0.0, m.w));
    float ffd;
    float ffs;
    if (tube) {
        ffd = ltc_tube(tp, tdp, a.radius, mat3(1.0));
        ffs = ltc_tube(tp, tdp, a.radius, minv);
    } else {
        ltc_polygon(to_frame, minv, true, P, c, ex, ey, n, fd, fs);
        ffd = ltc_clipped(fd);
        ffs = ltc_clipped(fs);
    }
    vec3 spec = f0 * (f.x - f.y) + f.y;
    // The diffuse weight 1 − F (metal-rough's p0.x) at the view's Schlick Fresnel.
    vec3 weight = p.p0.x != 0.0 ? vec3(1.0) - f_schlick(f0, clamp(n_v, 0.0, 1.0)) : vec3(1.0);
    return p.color.rgb * ((1.0 - metallic) * brdf_diffuse_keep(p)) * weight * ffd + spec * ffs;
}

// The light one area light reflects towards V at P. Rects and disks are shaded by LTC unless
// sampled (representative point is for spheres and tubes), spheres and tubes by the method they
// ask for; src/render/gpu.rs: area_kinds sets the LK_AREA_* bits the same way. Models without an
// LTC form (not Lambert nor metallic-roughness) take 16 samples instead of LTC.
vec3 area_shade(uint k, Surface s, vec3 P, vec3 V) {
    AreaLight a = area_light(k);
    vec3 lo = vec3(0.0);
    bool ltc_model = MODEL == BRDF_MODEL_LAMBERT || MODEL == BRDF_MODEL_METAL_ROUGH;
    if ((LIGHT_KINDS & LK_AREA_SAMPLED) != 0u && a.method == AREA_SAMPLED) {
        lo = area_sampled(a, s, P, V);
    } else if ((LIGHT_KINDS & LK_AREA_RP) != 0u && a.method == AREA_RP
               && (a.shape == AREA_TUBE || a.shape == AREA_SPHERE)) {
        lo = area_representative_point(a, s, P, V);
    } else if ((LIGHT_KINDS & (LK_AREA_LTC | LK_AREA_LTC_TUBE)) != 0u) {
        if (ltc_model) {
            lo = area_ltc(a, s, P, V);
        } else {
            a.samples = 16u;
            lo = area_sampled(a, s, P, V);
        }
    }
    return lo * a.radiance * area_window(a, P);
}

// The shadow filters area lights use (LK_AREA_SHADOW_* as LK_SHADOW_* bits; 0: no area light has
// a shadow and none of area_shadow is compiled).
const uint AREA_SHADOW_KINDS = (LIGHT_KINDS >> LK_AREA_SHADOW_SHIFT) & SHADOW_KINDS;

// The fraction of area light k's emitter that P sees past the shadow maps (1 without a shadow):
// its record follows the punctual lights' (src/render/shadow: shadow_lights), a cube map from the
// emitter's centre c, whose PCSS light size is the emitter's (docs/area-lights.md#shadows). N: the
// interpolated normal (the normal offset), as for punctual lights.
float area_shadow(uint k, vec3 c, vec3 P, vec3 N) {
    ShadowLight s = shadow_lights[opaque(frame.counts.x) + k];
    if (s.info.x < 0) {
        return 1.0;
    }
    vec3 d = P - c;
    vec3 a = abs(d);
    int face = a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1)
             : (a.y >= a.z ? (d.y >= 0.0 ? 2 : 3) : (d.z >= 0.0 ? 4 : 5));
    float len = length(d);
    vec3 l = len > 0.0 ? -d / len : vec3(0.0, 1.0, 0.0);
    int layer = s.info.x + face;
    ShadowLayer L = shadow_layers[layer];
    // When every shadowed area light uses one filter, the method is a constant: the filter
    // compiles alone (lavapipe would otherwise run PCSS and the PCF fallback after it both).
    int method = AREA_SHADOW_KINDS == LK_SHADOW_PCSS ? SHADOW_PCSS
               : AREA_SHADOW_KINDS == LK_SHADOW_HARD ? SHADOW_HARD
               : AREA_SHADOW_KINDS == LK_SHADOW_PCF ? SHADOW_PCF : s.info.z;
    return shadow_lookup_of(AREA_SHADOW_KINDS, s, L, layer, false, true, method, s.info.w, P, N,
                            l);
}

#endif
