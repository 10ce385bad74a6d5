// BRDF terms (MODELS.md §3, §4, §6): the GLSL mirror of src/brdf/terms.rs.
// Same function names, operation order, clamps and epsilons as the Rust reference, which the GPU
// output is compared against per pixel. Every function returns a finite, non-negative value for
// any finite input. GLSL 4.60, no extension needed; include it, do not compile it on its own.
#ifndef LUZ_BRDF_TERMS_GLSL
#define LUZ_BRDF_TERMS_GLSL

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#ifndef M_1_PI
#define M_1_PI 0.31830988618379067154
#endif

// Smallest width a normal distribution is evaluated with (α, α_x, α_y, Beckmann m).
#define BRDF_ALPHA_MIN 1e-3
// Floor for cosines that are divided by, applied after the "≤ 0 gives 0" test.
#define BRDF_COS_EPS 1e-4
// A vector whose squared length is at most this is the zero vector.
#define BRDF_LEN2_EPS 1e-12
// Largest refractive index η and extinction κ the Fresnel terms use (squares stay finite).
#define BRDF_IOR_MAX 1e9

// ------------------------------------------------------------------------------------------------
// Helpers
// ------------------------------------------------------------------------------------------------

float brdf_saturate(float x) {
    return clamp(x, 0.0, 1.0);
}

// v / |v|, or the zero vector when |v|² ≤ BRDF_LEN2_EPS.
vec3 brdf_safe_normalize(vec3 v) {
    float len2 = dot(v, v);
    if (len2 > BRDF_LEN2_EPS) {
        return v * (1.0 / sqrt(len2));
    }
    return vec3(0.0);
}

// A cosine already known to be positive, clamped into [BRDF_COS_EPS, 1].
float brdf_clamp_cos(float c) {
    return clamp(c, BRDF_COS_EPS, 1.0);
}

// (1 − clamp(u, 0, 1))^5 as m²·m²·m (Disney's SchlickFresnel).
float brdf_schlick_weight(float u) {
    float m = brdf_saturate(1.0 - u);
    float m2 = m * m;
    return m2 * m2 * m;
}

// A unit vector orthogonal to the unit vector n (Duff et al. 2017); (1, 0, 0) for n = 0.
vec3 brdf_any_tangent(vec3 n) {
    if (n.x == 0.0 && n.y == 0.0 && n.z == 0.0) {
        return vec3(1.0, 0.0, 0.0);
    }
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    return vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
}

// The tangent of tangent_frame() in src/brdf/terms.rs: x made orthogonal to n; if degenerate,
// y' × n; if that is degenerate too, brdf_any_tangent(n). The bitangent is cross(n, tangent).
vec3 brdf_tangent_x(vec3 n, vec3 x, vec3 y) {
    vec3 t = brdf_safe_normalize(x - n * dot(n, x));
    if (t.x == 0.0 && t.y == 0.0 && t.z == 0.0) {
        vec3 b = brdf_safe_normalize(y - n * dot(n, y));
        if (b.x == 0.0 && b.y == 0.0 && b.z == 0.0) {
            t = brdf_any_tangent(n);
        } else {
            t = brdf_safe_normalize(cross(b, n));
        }
    }
    return t;
}

// ------------------------------------------------------------------------------------------------
// D: normal distribution functions
// ------------------------------------------------------------------------------------------------

// sin²θ_h = 1 − (n·h)² from n·h alone, as (1 − c)(1 + c). Near the peak of a narrow lobe n·h has
// too few bits; the models pass |n × h|² to the *_sin2 forms instead (exact at any angle).
float brdf_sin2_from_cos(float c) {
    float cc = clamp(c, 0.0, 1.0);
    return (1.0 - cc) * (1.0 + cc);
}

// Beckmann with sin²θ_h given: exp(−s²/(m² c²)) / (π m² c⁴); 0 for c ≤ 0.
float d_beckmann_sin2(float n_h, float sin2_h, float m) {
    if (n_h <= 0.0) {
        return 0.0;
    }
    float mm = max(m, BRDF_ALPHA_MIN);
    float c = brdf_clamp_cos(n_h);
    float s2 = brdf_saturate(sin2_h);
    float c2 = c * c;
    float m2 = mm * mm;
    return exp(-s2 / (m2 * c2)) / (M_PI * m2 * c2 * c2);
}

// Beckmann: exp((c² − 1)/(m² c²)) / (π m² c⁴), c = n·h.
float d_beckmann(float n_h, float m) {
    return d_beckmann_sin2(n_h, brdf_sin2_from_cos(n_h), m);
}

// GGX with sin²θ_h given: α² / (π (α² c² + s²)²)  (c²(α² − 1) + 1 = α² c² + s²).
float d_ggx_sin2(float n_h, float sin2_h, float alpha) {
    if (n_h <= 0.0) {
        return 0.0;
    }
    float a = max(alpha, BRDF_ALPHA_MIN);
    float a2 = a * a;
    float c = brdf_clamp_cos(n_h);
    float t = a2 * c * c + brdf_saturate(sin2_h);
    return a2 / (M_PI * t * t);
}

// GGX / Trowbridge-Reitz (GTR2): α² / (π ((n·h)²(α² − 1) + 1)²); 0 for n·h ≤ 0.
float d_ggx(float n_h, float alpha) {
    return d_ggx_sin2(n_h, brdf_sin2_from_cos(n_h), alpha);
}

// GTR1 with sin²θ_h given: (α² − 1) / (π ln(α²) (α² c² + s²)); 1/π when α² ≥ 1.
float d_gtr1_sin2(float n_h, float sin2_h, float alpha) {
    if (n_h <= 0.0) {
        return 0.0;
    }
    float a = max(alpha, BRDF_ALPHA_MIN);
    float a2 = a * a;
    if (a2 >= 1.0) {
        return M_1_PI;
    }
    float c = brdf_clamp_cos(n_h);
    float t = a2 * c * c + brdf_saturate(sin2_h);
    return (a2 - 1.0) / (M_PI * log(a2) * t);
}

// GTR1 (clearcoat): (α² − 1) / (π ln(α²) (1 + (α² − 1)(n·h)²)).
float d_gtr1(float n_h, float alpha) {
    return d_gtr1_sin2(n_h, brdf_sin2_from_cos(n_h), alpha);
}

// Anisotropic GTR2: 1 / (π α_x α_y ((h·x/α_x)² + (h·y/α_y)² + (n·h)²)²).
float d_gtr2_aniso(float n_h, float h_x, float h_y, float ax, float ay) {
    if (n_h <= 0.0) {
        return 0.0;
    }
    float axx = max(ax, BRDF_ALPHA_MIN);
    float ayy = max(ay, BRDF_ALPHA_MIN);
    float c = brdf_clamp_cos(n_h);
    float sx = h_x / axx;
    float sy = h_y / ayy;
    float t = sx * sx + sy * sy + c * c;
    return 1.0 / (M_PI * axx * ayy * t * t);
}

// ------------------------------------------------------------------------------------------------
// G: masking-shadowing
// ------------------------------------------------------------------------------------------------

// Cook-Torrance: min(1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h)).
float g_cook_torrance(float n_h, float n_v, float n_l, float v_h) {
    if (n_h <= 0.0 || n_v <= 0.0 || n_l <= 0.0) {
        return 0.0;
    }
    float vh = max(v_h, BRDF_COS_EPS);
    float g_v = 2.0 * n_h * n_v / vh;
    float g_l = 2.0 * n_h * n_l / vh;
    return min(min(g_v, g_l), 1.0);
}

// Smith GGX, one direction: 2(n·v) / ((n·v) + sqrt(α² + (1 − α²)(n·v)²)).
float g1_smith_ggx(float n_v, float alpha) {
    if (n_v <= 0.0) {
        return 0.0;
    }
    float c = brdf_clamp_cos(n_v);
    float a2 = alpha * alpha;
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

float g_smith_ggx_separable(float n_l, float n_v, float alpha) {
    return g1_smith_ggx(n_l, alpha) * g1_smith_ggx(n_v, alpha);
}

// Smith GGX height-correlated (Heitz 2014), division-free form.
float g_smith_ggx_correlated(float n_l, float n_v, float alpha) {
    if (n_l <= 0.0 || n_v <= 0.0) {
        return 0.0;
    }
    float cl = brdf_clamp_cos(n_l);
    float cv = brdf_clamp_cos(n_v);
    float a2 = alpha * alpha;
    float lambda_v = cl * sqrt(cv * cv * (1.0 - a2) + a2);
    float lambda_l = cv * sqrt(cl * cl * (1.0 - a2) + a2);
    return 2.0 * cl * cv / (lambda_v + lambda_l);
}

// Smith Beckmann, Walter et al. 2007's rational approximation (g1_smith_beckmann in terms.rs).
float g1_smith_beckmann(float n_v, float m) {
    if (n_v <= 0.0) {
        return 0.0;
    }
    float c = brdf_clamp_cos(n_v);
    float s = sqrt(max(1.0 - c * c, 0.0));
    if (s <= 0.0) {
        return 1.0;
    }
    float a = c / (max(m, BRDF_ALPHA_MIN) * s);
    if (a >= 1.6) {
        return 1.0;
    }
    return (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
}

float g_smith_beckmann(float n_l, float n_v, float m) {
    return g1_smith_beckmann(n_l, m) * g1_smith_beckmann(n_v, m);
}

// Schlick-GGX (UE4): G1 = (n·v) / ((n·v)(1 − k) + k).
float g_schlick_ggx(float n_l, float n_v, float k) {
    if (n_l <= 0.0 || n_v <= 0.0) {
        return 0.0;
    }
    float kk = max(k, 0.0);
    float cl = brdf_clamp_cos(n_l);
    float cv = brdf_clamp_cos(n_v);
    float gl = cl / (cl * (1.0 - kk) + kk);
    float gv = cv / (cv * (1.0 - kk) + kk);
    return gl * gv;
}

float k_punctual(float roughness) {
    float r1 = roughness + 1.0;
    return r1 * r1 / 8.0;
}

float k_ibl(float roughness) {
    return roughness * roughness / 2.0;
}

// Smith GGX, height-correlated and anisotropic (g_smith_ggx_correlated_aniso in terms.rs;
// KHR_materials_anisotropy's V × 4 (n·l)(n·v)): t_l = t·l, b_l = b·l, t_v, b_v likewise.
float g_smith_ggx_correlated_aniso(float n_l, float n_v, float t_l, float b_l, float t_v,
                                   float b_v, float at, float ab) {
    if (n_l <= 0.0 || n_v <= 0.0) {
        return 0.0;
    }
    float att = max(at, BRDF_ALPHA_MIN);
    float abb = max(ab, BRDF_ALPHA_MIN);
    float cl = brdf_clamp_cos(n_l);
    float cv = brdf_clamp_cos(n_v);
    float lambda_v = cl * length(vec3(att * t_v, abb * b_v, cv));
    float lambda_l = cv * length(vec3(att * t_l, abb * b_l, cl));
    return 2.0 * cl * cv / (lambda_v + lambda_l);
}

// Disney anisotropic Smith GGX, visibility form: 1 / (c + sqrt((a α_x)² + (b α_y)² + c²)).
float vis_smith_ggx_aniso(float n_v, float v_x, float v_y, float ax, float ay) {
    if (n_v <= 0.0) {
        return 0.0;
    }
    float c = brdf_clamp_cos(n_v);
    float sx = v_x * ax;
    float sy = v_y * ay;
    return 1.0 / (c + sqrt(sx * sx + sy * sy + c * c));
}

// Disney isotropic Smith GGX, visibility form: 1 / (c + sqrt(g² + c² − g²c²)).
float vis_smith_ggx_iso(float n_v, float alpha_g) {
    if (n_v <= 0.0) {
        return 0.0;
    }
    float c = brdf_clamp_cos(n_v);
    float a = alpha_g * alpha_g;
    float b = c * c;
    return 1.0 / (c + sqrt(a + b - a * b));
}

// ------------------------------------------------------------------------------------------------
// F: Fresnel
// ------------------------------------------------------------------------------------------------

vec3 f_schlick(vec3 f0, float v_h) {
    float w = brdf_schlick_weight(v_h);
    return f0 + (vec3(1.0) - f0) * w;
}

// UE4 spherical-Gaussian Schlick: F0 + (1 − F0) 2^((−5.55473 c − 6.98316) c).
vec3 f_schlick_sg(vec3 f0, float v_h) {
    float c = brdf_saturate(v_h);
    float w = exp2((-5.55473 * c - 6.98316) * c);
    return f0 + (vec3(1.0) - f0) * w;
}

// Exact unpolarised dielectric Fresnel, eta = η_t/η_i; total internal reflection gives 1.
float f_dielectric(float cos_i, float eta) {
    float c = brdf_saturate(cos_i);
    float e = clamp(eta, 1e-4, BRDF_IOR_MAX);
    float g2 = (e - 1.0) * (e + 1.0) + c * c;
    if (g2 < 0.0) {
        return 1.0;
    }
    float g = sqrt(g2);
    float a = g - c;
    float b = g + c;
    if (b <= 1e-6) {
        return 1.0;
    }
    float p = c * b - 1.0;
    float q = c * a + 1.0;
    return min(0.5 * (a * a) / (b * b) * (1.0 + (p * p) / (q * q)), 1.0);
}

// Conductor Fresnel, one channel, complex index η + iκ (MODELS.md §3).
float f_conductor_1(float cos_i, float eta, float k) {
    float c = brdf_saturate(cos_i);
    float e = clamp(eta, 0.0, BRDF_IOR_MAX);
    float kk = min(abs(k), BRDF_IOR_MAX);
    float c2 = c * c;
    float t0 = e * e + kk * kk;
    float t1 = 2.0 * e * c;
    float r_perp = (t0 - t1 + c2) / max(t0 + t1 + c2, 1e-12);
    float r_par = (t0 * c2 - t1 + 1.0) / (t0 * c2 + t1 + 1.0);
    return clamp(0.5 * (r_perp + r_par), 0.0, 1.0);
}

vec3 f_conductor(float cos_i, vec3 eta, vec3 k) {
    return vec3(f_conductor_1(cos_i, eta.x, k.x),
                f_conductor_1(cos_i, eta.y, k.y),
                f_conductor_1(cos_i, eta.z, k.z));
}

// Exact complex-index Fresnel (f_conductor_exact_1 in terms.rs).
float f_conductor_exact_1(float cos_i, float eta, float k) {
    float c = brdf_saturate(cos_i);
    float e = clamp(eta, 0.0, BRDF_IOR_MAX);
    float kk = min(abs(k), BRDF_IOR_MAX);
    float c2 = c * c;
    float s2 = max(1.0 - c2, 0.0);
    float t0 = e * e - kk * kk - s2;
    float a2pb2 = sqrt(max(t0 * t0 + 4.0 * e * e * kk * kk, 0.0));
    float a = sqrt(max(0.5 * (a2pb2 + t0), 0.0));
    float t1 = a2pb2 + c2;
    float t2 = 2.0 * c * a;
    float rs = (t1 - t2) / max(t1 + t2, 1e-12);
    float t3 = c2 * a2pb2 + s2 * s2;
    float t4 = t2 * s2;
    float rp = rs * (t3 - t4) / max(t3 + t4, 1e-12);
    return clamp(0.5 * (rs + rp), 0.0, 1.0);
}

vec3 f_conductor_exact(float cos_i, vec3 eta, vec3 k) {
    return vec3(f_conductor_exact_1(cos_i, eta.x, k.x),
                f_conductor_exact_1(cos_i, eta.y, k.y),
                f_conductor_exact_1(cos_i, eta.z, k.z));
}

// ------------------------------------------------------------------------------------------------
// Diffuse
// ------------------------------------------------------------------------------------------------

vec3 diffuse_lambert(vec3 albedo) {
    return albedo * M_1_PI;
}

// Disney Fd = mix(1, Fd90, FL) mix(1, Fd90, FV), Fd90 = 0.5 + 2 roughness (l·h)².
float fd_burley(float n_l, float n_v, float l_h, float roughness) {
    float fl = brdf_schlick_weight(n_l);
    float fv = brdf_schlick_weight(n_v);
    float fd90 = 0.5 + 2.0 * l_h * l_h * roughness;
    return mix(1.0, fd90, fl) * mix(1.0, fd90, fv);
}

vec3 diffuse_burley(vec3 albedo, float n_l, float n_v, float l_h, float roughness) {
    return albedo * (M_1_PI * fd_burley(n_l, n_v, l_h, roughness));
}

// Disney Hanrahan-Krueger subsurface factor ss = 1.25 (Fss (1/(n·l + n·v) − 0.5) + 0.5).
float ss_hanrahan_krueger(float n_l, float n_v, float l_h, float roughness) {
    if (n_l <= 0.0 || n_v <= 0.0) {
        return 0.0;
    }
    float cl = brdf_clamp_cos(n_l);
    float cv = brdf_clamp_cos(n_v);
    float fl = brdf_schlick_weight(cl);
    float fv = brdf_schlick_weight(cv);
    float fss90 = l_h * l_h * roughness;
    float fss = mix(1.0, fss90, fl) * mix(1.0, fss90, fv);
    return 1.25 * (fss * (1.0 / (cl + cv) - 0.5) + 0.5);
}

vec3 diffuse_hanrahan_krueger_ss(vec3 albedo, float n_l, float n_v, float l_h, float roughness) {
    return albedo * (M_1_PI * ss_hanrahan_krueger(n_l, n_v, l_h, roughness));
}

// Qualitative Oren-Nayar, sigma in radians, cos_phi_diff = cos(φ_i − φ_o).
vec3 diffuse_oren_nayar(vec3 albedo, float sigma, float n_l, float n_v, float cos_phi_diff) {
    if (n_l <= 0.0 || n_v <= 0.0) {
        return vec3(0.0);
    }
    float cl = brdf_clamp_cos(n_l);
    float cv = brdf_clamp_cos(n_v);
    float s2 = sigma * sigma;
    float a = 1.0 - 0.5 * s2 / (s2 + 0.33);
    float b = 0.45 * s2 / (s2 + 0.09);
    float cos_alpha = min(cl, cv);
    float cos_beta = max(cl, cv);
    float sin_alpha = sqrt(max(1.0 - cos_alpha * cos_alpha, 0.0));
    float tan_beta = sqrt(max(1.0 - cos_beta * cos_beta, 0.0)) / cos_beta;
    return albedo * (M_1_PI * (a + b * max(cos_phi_diff, 0.0) * sin_alpha * tan_beta));
}

// cos(φ_l − φ_v) around the unit normal n; 0 when l or v lies along n.
float cos_phi_diff(vec3 n, vec3 l, vec3 v) {
    vec3 lp = l - n * dot(n, l);
    vec3 vp = v - n * dot(n, v);
    float d = dot(lp, lp) * dot(vp, vp);
    if (d > BRDF_LEN2_EPS) {
        return clamp(dot(lp, vp) / sqrt(d), -1.0, 1.0);
    }
    return 0.0;
}

// KHR_materials_iridescence's thin-film Fresnel (src/brdf/iridescence.rs, same names and order):
// Belcour & Barla 2017, the film's first two Airy orders against the CIE sensitivities' Gaussian
// fit, to linear Rec. 709.
const mat3 IRID_XYZ_TO_REC709 = mat3(3.2404542, -0.9692660, 0.0556434, -1.5371385, 1.8760108,
                                     -0.2040259, -0.4985314, 0.0415560, 1.0572252);

float irid_schlick1(float f0, float c) {
    return f0 + (1.0 - f0) * brdf_schlick_weight(c);
}

float irid_ior_to_f0(float eta_t, float eta_i) {
    float r = (eta_t - eta_i) / (eta_t + eta_i);
    return r * r;
}

float irid_f0_to_ior(float f0) {
    float s = sqrt(clamp(f0, 0.0, 0.9999));
    return (1.0 + s) / (1.0 - s);
}

// The film whatever the angle and the base (Film in iridescence.rs): a material's film, made
// once per pixel; film_at adds the angle.
struct Film {
    float outside_ior;
    float eta2;
    float r12_f0;
    float phi21;
    float phase_per_cos2;
};

Film film_of(float outside_ior, float film_ior, float thickness_nm) {
    Film m;
    float t = clamp(thickness_nm / 0.03, 0.0, 1.0);
    m.outside_ior = outside_ior;
    m.eta2 = outside_ior + (film_ior - outside_ior) * (t * t * (3.0 - 2.0 * t));
    m.r12_f0 = irid_ior_to_f0(m.eta2, outside_ior);
    m.phi21 = m.eta2 < outside_ior ? 0.0 : M_PI;
    m.phase_per_cos2 = 2.0 * M_PI * (2.0 * m.eta2 * thickness_nm) * 1.0e-9;
    return m;
}

// What a base gives under the film whatever the angle (FilmBase): the second interface's F0
// per channel and the first order's sign. Made once per pixel per base.
struct FilmBase {
    vec3 r23_f0;
    vec3 sgn;
};

FilmBase film_base(Film m, vec3 base_f0) {
    FilmBase b;
    for (int i = 0; i < 3; ++i) {
        float base_ior = irid_f0_to_ior(base_f0[i]);
        b.r23_f0[i] = irid_ior_to_f0(base_ior, m.eta2);
        b.sgn[i] = base_ior < m.eta2 ? -1.0 : 1.0;
    }
    return b;
}

// What the film gives at one angle whatever the base (FilmAt in iridescence.rs): the first
// interface, the refracted cosine, and the sensitivity fit's cosines and Gaussians at its path
// difference and phase φ21; a base only flips first-order cosines' signs, so two bases share
// the transcendentals. tir: total internal reflection (F = 1).
struct FilmAt {
    float r12;
    float t121;
    float cos2;
    vec3 c;
    float cx;
    vec3 e;
    float ex;
    bool tir;
};

FilmAt film_at(Film m, float cos_theta1) {
    FilmAt f;
    float c1 = clamp(cos_theta1, 0.0, 1.0);
    float r_io = m.outside_ior / m.eta2;
    float cos2_theta2 = 1.0 - r_io * r_io * (1.0 - c1 * c1);
    f.tir = cos2_theta2 < 0.0;
    f.cos2 = sqrt(max(cos2_theta2, 0.0));
    f.r12 = irid_schlick1(m.r12_f0, c1);
    f.t121 = 1.0 - f.r12;
    float phase = m.phase_per_cos2 * f.cos2;
    vec3 pos = vec3(1.6810e+06, 1.7953e+06, 2.2084e+06);
    vec3 var = vec3(4.3278e+09, 9.3046e+09, 6.6121e+09);
    f.c = cos(pos * phase + m.phi21);
    f.e = exp(-(phase * phase) * var);
    f.cx = cos(2.2399e+06 * phase + m.phi21);
    f.ex = exp(-4.5282e+09 * (phase * phase));
    return f;
}

// The film's Fresnel over base b (film_over).
vec3 film_over(FilmAt f, FilmBase b) {
    vec3 val = vec3(5.4856e-13, 4.4201e-13, 5.2481e-13);
    vec3 var = vec3(4.3278e+09, 9.3046e+09, 6.6121e+09);
    float w = brdf_schlick_weight(f.cos2);
    vec3 r23 = b.r23_f0 + (vec3(1.0) - b.r23_f0) * w;
    vec3 k = val * sqrt(2.0 * M_PI * var);
    vec3 e2 = (f.e * f.e) * (f.e * f.e);
    vec3 xyz1 = k * b.sgn * f.c * f.e;
    vec3 xyz2 = k * (2.0 * f.c * f.c - 1.0) * e2;
    float kx = 9.7470e-14 * sqrt(2.0 * M_PI * 4.5282e+09);
    xyz1.x += kx * b.sgn.x * f.cx * f.ex;
    xyz2.x += kx * (2.0 * f.cx * f.cx - 1.0) * ((f.ex * f.ex) * (f.ex * f.ex));
    vec3 s1 = IRID_XYZ_TO_REC709 * (xyz1 / 1.0685e-7);
    vec3 s2 = IRID_XYZ_TO_REC709 * (xyz2 / 1.0685e-7);
    vec3 r123 = clamp(f.r12 * r23, vec3(1e-5), vec3(0.9999));
    vec3 sqrt_r123 = sqrt(r123);
    vec3 rs = (f.t121 * f.t121) * r23 / (vec3(1.0) - r123);
    vec3 k1 = (rs - vec3(f.t121)) * sqrt_r123;
    vec3 k2 = k1 * sqrt_r123;
    // Total internal reflection: 1 (a select, not a branch).
    return f.tir ? vec3(1.0) : max(vec3(f.r12) + rs + 2.0 * (k1 * s1 + k2 * s2), vec3(0.0));
}

vec3 iridescence_fresnel(float outside_ior, float film_ior, float cos_theta1, float thickness_nm,
                         vec3 base_f0) {
    Film m = film_of(outside_ior, film_ior, thickness_nm);
    return film_over(film_at(m, cos_theta1), film_base(m, base_f0));
}

#endif // LUZ_BRDF_TERMS_GLSL
