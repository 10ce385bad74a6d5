// Lights and the classic models of MODELS.md §1–2, shared by the vertex stage (flat, Gouraud) and the
// fragment stage (Phong shading).
#ifndef LUZ_LIGHTING_GLSL
#define LUZ_LIGHTING_GLSL

#include "bindings.glsl"
#include "shadows.glsl"
#include "tangent_frame.glsl"

// Distance attenuation: none, inverse square, or the slides' f_at = min(1/(c1 + c2 d + c3 d²), 1).
float light_falloff_only(Light L, float d) {
    uint kind = uint(L.direction_falloff.w);
    if ((LIGHT_KINDS & LK_FALLOFF_INVERSE_SQUARE) != 0u && kind == FALLOFF_INVERSE_SQUARE) {
        return 1.0 / max(d * d, 1e-8);
    }
    if ((LIGHT_KINDS & LK_FALLOFF_CLASSIC) != 0u && kind == FALLOFF_CLASSIC) {
        float q = L.atten.x + L.atten.y * d + L.atten.z * d * d;
        return q > 1.0 ? 1.0 / q : 1.0;
    }
    return 1.0;
}

// The falloff times KHR_lights_punctual's range window W(d) = clamp(1 − (d/range)⁴, 0, 1)²
// (src/scene/mod.rs: range_window); scenes without a ranged light leave the window out.
float light_falloff(Light L, float d) {
    float f = light_falloff_only(L, d);
    if ((LIGHT_KINDS & LK_RANGE) != 0u && L.cone.w > 0.0) {
        float x = d / L.cone.w;
        float w = clamp(1.0 - (x * x) * (x * x), 0.0, 1.0);
        f *= w * w;
    }
    return f;
}

// Direction towards the light and the irradiance it delivers on a surface facing it.
void light_incidence(Light L, vec3 P, out vec3 l, out vec3 E) {
    uint type = uint(L.position_type.w);
    if ((LIGHT_KINDS & (LK_POINT | LK_SPOT)) == 0u
        || ((LIGHT_KINDS & LK_DIRECTIONAL) != 0u && type == LIGHT_DIRECTIONAL)) {
        l = -L.direction_falloff.xyz;
        E = L.radiance.rgb;
        return;
    }
    vec3 to_light = L.position_type.xyz - P;
    float d = length(to_light);
    l = d > 0.0 ? to_light / d : vec3(0.0, 1.0, 0.0);
    E = L.radiance.rgb * light_falloff(L, d);
    if ((LIGHT_KINDS & LK_SPOT) != 0u && type == LIGHT_SPOT) {
        // θ_s: angle between the spot axis and −l.
        float cos_s = dot(L.direction_falloff.xyz, -l);
        float cone = L.cone.z > 0.5 ? smoothstep(L.cone.x, L.cone.y, cos_s) : (cos_s >= L.cone.x ? 1.0 : 0.0);
        float shape = L.atten.w > 0.0 ? pow(max(cos_s, 0.0), L.atten.w) : 1.0;
        E *= cone * shape;
    }
}

// The material's parameters with the model fixed by the pipeline's specialization constant.
BrdfParams material_params() {
    BrdfParams p = material.brdf;
    p.sel.x = MODEL;
    if (SEL_DISTRIBUTION >= 0) {
        p.sel.y = SEL_DISTRIBUTION;
    }
    if (SEL_GEOMETRY >= 0) {
        p.sel.z = SEL_GEOMETRY;
    }
    if (SEL_FRESNEL >= 0) {
        p.sel.w = SEL_FRESNEL;
    }
    if (SEL_DIFFUSE >= 0 && (MODEL == BRDF_MODEL_COOK_TORRANCE || MODEL == BRDF_MODEL_METAL_ROUGH)) {
        p.p0.y = float(SEL_DIFFUSE);
    }
    return p;
}

// The interpolated vertex colour (glTF COLOR_0, linear RGBA) of the point being shaded: set by
// forward.frag before shade() in the VERTEX_COLOR variants, white otherwise.
vec4 g_vertex_color = vec4(1.0);

bool has_map(uint slot) {
    return (MAPS & (1u << slot)) != 0u && (opaque(mat_extra.present.x) & (1u << slot)) != 0u;
}

#ifndef LUZ_DEFERRED
vec4 sample_map(sampler2D s, vec2 uv) {
#ifdef LUZ_FRAGMENT
    return texture(s, uv);
#else
    return textureLod(s, uv, 0.0);
#endif
}
#endif

// What the maps make of the material at one point: parameters, shading frame, occlusion, emission.
struct Surface {
    BrdfParams p;
    vec3 n;
    vec3 x;
    vec3 y;
    float occlusion;
    vec3 emission;
    // Glass: x the volume's thickness (mesh units), yzw the diffuse transmission colour.
    vec4 glass;
    // KHR_materials_clearcoat: the coat's normal (the geometric one unless its map bends it).
    vec3 coat_n;
};

Surface surface_at(vec3 N, vec3 X, vec3 Y, vec2 uv) {
    Surface s;
    s.p = material_params();
    s.n = N;
    s.x = X;
    s.y = Y;
    s.occlusion = 1.0;
    s.coat_n = N;
    s.emission = mat_extra.emissive.rgb;
    s.glass = vec4(mat_extra.volume.x, mat_extra.diffuse_transmission.rgb);
#ifdef VERTEX_COLOR
    s.p.color.rgb *= g_vertex_color.rgb;
#endif
    if (MAPS == 0u || opaque(mat_extra.present.x) == 0u) {
        return s;
    }
#ifndef LUZ_DEFERRED
    if (has_map(MAP_BASE_COLOR)) {
        s.p.color.rgb *= sample_map(map_base_color, uv).rgb;
    }
    if (has_map(MAP_SPECULAR)) {
        s.p.spec.rgb *= sample_map(map_specular, uv).rgb;
    }
    if (has_map(MAP_METALLIC)) {
        s.p.spec.w *= sample_map(map_metallic, uv).r;
    }
    if (has_map(MAP_ROUGHNESS)) {
        s.p.color.w *= sample_map(map_roughness, uv).r;
    }
    float occ = 1.0;
    if (has_map(MAP_ORM)) {
        vec3 orm = sample_map(map_orm, uv).rgb;
        occ = orm.r;
        s.p.color.w *= orm.g;
        s.p.spec.w *= orm.b;
    }
    if (has_map(MAP_OCCLUSION)) {
        occ = sample_map(map_occlusion, uv).r;
    }
    s.occlusion = 1.0 + mat_extra.params.y * (occ - 1.0);
    if (has_map(MAP_EMISSIVE)) {
        s.emission *= sample_map(map_emissive, uv).rgb;
    }
    // Glass's maps (their channel moved to R by the loader where glTF packs them elsewhere).
    if (has_map(MAP_TRANSMISSION)) {
        s.p.p2.x *= sample_map(map_transmission, uv).r;
    }
    if (has_map(MAP_THICKNESS)) {
        s.glass.x *= sample_map(map_thickness, uv).r;
    }
    if (has_map(MAP_DIFFUSE_TRANSMISSION)) {
        s.p.p2.y *= sample_map(map_diffuse_transmission, uv).r;
    }
    if (has_map(MAP_DIFFUSE_TRANSMISSION_COLOR)) {
        s.glass.yzw *= sample_map(map_diffuse_transmission_color, uv).rgb;
    }
    if (has_map(MAP_NORMAL)) {
        // Tangent-space normal (glTF): n = normalize((2t − 1) · (scale, scale, 1)) in (X, Y, N).
        vec3 t = sample_map(map_normal, uv).xyz * 2.0 - 1.0;
        t.xy *= mat_extra.params.x;
        vec3 n = normalize(t.x * X + t.y * Y + t.z * N);
        vec3 x = X - n * dot(n, X);
        float len2 = dot(x, x);
        if (len2 > 1e-12) {
            s.x = x * inversesqrt(len2);
            s.y = cross(n, s.x) * (dot(cross(N, X), Y) < 0.0 ? -1.0 : 1.0);
            s.n = n;
        }
    }
    if (has_map(MAP_ANISOTROPY)) {
        // KHR_materials_anisotropy's map (surface_at in the reference): RG the direction in
        // the tangent frame, which becomes the frame's x (the rotation turns it further in the
        // BRDF); B scales the strength.
        vec3 a = sample_map(map_anisotropy, uv).rgb;
        vec2 d = a.rg * 2.0 - 1.0;
        vec3 t = d.x * s.x + d.y * s.y;
        float len2 = dot(t, t);
        if (len2 > 1e-12) {
            s.x = t * inversesqrt(len2);
            s.y = cross(s.n, s.x);
        }
        s.p.p1.z *= a.b;
    }
    // The layers' maps (surface_at in the reference), each multiplying its factor; the loader
    // moved glTF's channel (clearcoat roughness G, sheen roughness A, specular A, thickness G)
    // to R.
    if (has_map(MAP_CLEARCOAT)) {
        s.p.p1.x *= sample_map(map_clearcoat, uv).r;
    }
    if (has_map(MAP_CLEARCOAT_ROUGHNESS)) {
        s.p.p1.y *= sample_map(map_clearcoat_roughness, uv).r;
    }
    if (has_map(MAP_SHEEN_COLOR)) {
        s.p.kappa.rgb *= sample_map(map_sheen_color, uv).rgb;
    }
    if (has_map(MAP_SHEEN_ROUGHNESS)) {
        s.p.kappa.w *= sample_map(map_sheen_roughness, uv).r;
    }
    if (has_map(MAP_SPECULAR_COLOR)) {
        // KHR_materials_specular: F0 = min(F0(ior) · colour factor · map, 1) · specular; the
        // map multiplies the clamped F0 (the same unless the colour factor took F0 past 1).
        s.p.spec.rgb *= sample_map(map_specular_color, uv).rgb;
    }
    if (has_map(MAP_SPECULAR_FACTOR)) {
        // specularFactor scales the dielectric F0 and is its F90.
        float k = sample_map(map_specular_factor, uv).r;
        s.p.spec.rgb *= k;
        s.p.p0.z *= k;
    }
    if (has_map(MAP_IRIDESCENCE)) {
        s.p.p0.w *= sample_map(map_iridescence, uv).r;
    }
    if (has_map(MAP_CLEARCOAT_NORMAL)) {
        // The coat's tangent-space normal, as the base's, in the geometric frame.
        vec3 t = sample_map(map_clearcoat_normal, uv).xyz * 2.0 - 1.0;
        t.xy *= mat_extra.attenuation.w;
        s.coat_n = normalize(t.x * X + t.y * Y + t.z * N);
    }
    if (has_map(MAP_IRIDESCENCE_THICKNESS)) {
        s.p.p2.w = mix(mat_extra.volume.z, s.p.p2.w, sample_map(map_iridescence_thickness, uv).r);
    }
#endif
    return s;
}

#ifndef LUZ_DEFERRED
// The base colour's alpha at uv: the material's factor × the base colour map's alpha × the vertex
// colour's alpha (glTF).
float base_alpha(vec2 uv) {
    float a = mat_extra.params.z * g_vertex_color.a;
    if (has_map(MAP_BASE_COLOR)) {
        a *= sample_map(map_base_color, uv).a;
    }
    return a;
}
#endif

// The ambient term: the slides' I_a k_a O_d for the classic models; for the others the uniform
// ambient radiance seen by the diffuse term (diffuse albedo × ambient).
vec3 ambient_term(BrdfParams p, vec3 ambient) {
    if (MODEL == BRDF_MODEL_PHONG || MODEL == BRDF_MODEL_BLINN_PHONG) {
        return ambient * p.p0.z * p.color.rgb;
    }
    if (MODEL == BRDF_MODEL_COOK_TORRANCE) {
        return ambient * p.kappa.w * p.color.rgb;
    }
    if (MODEL == BRDF_MODEL_METAL_ROUGH) {
        return ambient * (1.0 - p.spec.w) * brdf_diffuse_keep(p) * p.color.rgb;
    }
    if (MODEL == BRDF_MODEL_PRINCIPLED) {
        return ambient * (1.0 - p.spec.w) * p.color.rgb;
    }
    return ambient * p.color.rgb;
}

#ifdef IBL
#include "ibl.glsl"
#endif
#include "area.glsl"
#if defined(LUZ_FRAGMENT) && !defined(LUZ_DEFERRED)
#define LUZ_GLASS
#include "transmission.glsl"
#endif

// The number of lights, for loops over them (through opaque(): see bindings.glsl).
uint light_count() {
    return opaque(frame.counts.x);
}

// The index of P's cluster in clusters[] (fragment stage, CLUSTERED only).
uint light_cluster(vec3 P) {
#ifdef LUZ_FRAGMENT
    vec3 v = (frame.view * vec4(P, 1.0)).xyz;
    float d = max(-v.z, 1e-6);
    // Tiles cut slopes x/d, y/d; an orthographic grid's (cluster_depth.z = 1) cut x, y.
    float dxy = max(d * (1.0 - cluster_depth.z), cluster_depth.z);
    ivec3 c = ivec3(floor(vec3(v.x / dxy * cluster_xy.x + cluster_xy.y,
                               v.y / dxy * cluster_xy.z + cluster_xy.w,
                               log(d) * cluster_depth.x + cluster_depth.y)));
    c = clamp(c, ivec3(0), ivec3(cluster_dims.xyz) - 1);
    return (uint(c.z) * cluster_dims.y + uint(c.y)) * cluster_dims.x + uint(c.x);
#else
    return 0u;
#endif
}

// The lights of cluster `cell` (light_cluster) when CLUSTERED (fragment stage): (base, count);
// else (0, every light). The loop's k-th light is light_list_index(list, k).
uvec2 light_list_of(uint cell) {
#ifdef LUZ_FRAGMENT
    if (CLUSTERED) {
        return clusters[cell];
    }
#endif
    return uvec2(0u, light_count());
}

uint light_list_index(uvec2 list, uint k) {
#ifdef LUZ_FRAGMENT
    if (CLUSTERED) {
        return cluster_lights[k < cluster_dims.w ? k : list.x + k];
    }
#endif
    return k;
}

// The area lights of cluster `cell` when CLUSTERED (fragment stage): their own (base, count),
// after every cluster's punctual pair; else (0, every area light). The loop's k-th area light is
// area_list_index(list, k).
uvec2 area_list_of(uint cell) {
#ifdef LUZ_FRAGMENT
    if (CLUSTERED) {
        return clusters[cluster_dims.x * cluster_dims.y * cluster_dims.z + cell];
    }
#endif
    return uvec2(0u, opaque(frame.counts.y));
}

uint area_list_index(uvec2 list, uint k) {
#ifdef LUZ_FRAGMENT
    if (CLUSTERED) {
        return cluster_lights[k < cluster_area.x ? cluster_area.y + k : list.x + k];
    }
#endif
    return k;
}

// Outgoing value at P (world space) with unit normal N, tangent frame (X, Y) and texture
// coordinates uv: ambient plus every light, each through the CPU reference's mirror brdf_radiance,
// plus the environment (IBL) and emission.
// The quantity a debug view shows (DebugView in src/render/forward.rs).
vec3 debug_value(Surface s, vec3 P, vec3 V) {
    BrdfParams p = s.p;
    if (DEBUG_VIEW == DEBUG_VIEW_BASE_COLOR) return p.color.rgb;
    if (DEBUG_VIEW == DEBUG_VIEW_NORMAL) return s.n * 0.5 + 0.5;
    if (DEBUG_VIEW == DEBUG_VIEW_METALLIC) return vec3(p.spec.w);
    if (DEBUG_VIEW == DEBUG_VIEW_ROUGHNESS) return vec3(p.color.w);
    if (DEBUG_VIEW == DEBUG_VIEW_AO) return vec3(s.occlusion);
    if (DEBUG_VIEW >= DEBUG_VIEW_D && DEBUG_VIEW <= DEBUG_VIEW_SPECULAR) {
        if (light_count() == 0u) return vec3(0.0);
        vec3 l;
        vec3 E;
        light_incidence(lights[0], P, l, E);
        BrdfTerms t = brdf_eval_terms(p, s.n, l, V, s.x, s.y);
        if (DEBUG_VIEW == DEBUG_VIEW_D) return vec3(t.d);
        if (DEBUG_VIEW == DEBUG_VIEW_G) return vec3(t.g);
        if (DEBUG_VIEW == DEBUG_VIEW_F) return t.f;
        if (DEBUG_VIEW == DEBUG_VIEW_DIFFUSE) return t.diffuse;
        return t.specular;
    }
    if (DEBUG_VIEW == DEBUG_VIEW_CLUSTERS) {
        // Blue (no light) through green (32) to red (64 or more); area lights count too.
        uint cell = CLUSTERED ? light_cluster(P) : 0u;
        uint n = light_list_of(cell).y;
        if ((LIGHT_KINDS & LK_AREA) != 0u) {
            n += area_list_of(cell).y;
        }
        float t = clamp(float(n) / 64.0, 0.0, 1.0);
        return vec3(clamp(2.0 * t - 1.0, 0.0, 1.0), 1.0 - abs(2.0 * t - 1.0), clamp(1.0 - 2.0 * t, 0.0, 1.0));
    }
    if (DEBUG_VIEW == DEBUG_VIEW_SHADOW || DEBUG_VIEW == DEBUG_VIEW_SHADOW_LAYERS) {
        // The first light with a shadow: its visibility, or the layer (cascade, cube face) the
        // point reads, one colour each.
        for (uint i = 0u; i < light_count(); ++i) {
            ShadowLight sh = shadow_lights[i];
            if ((LIGHT_KINDS & SHADOW_KINDS) == 0u || sh.info.x < 0) {
                continue;
            }
            if (DEBUG_VIEW == DEBUG_VIEW_SHADOW_LAYERS) {
                bool beyond;
                int k = shadow_layer(i, sh, P, beyond) - sh.info.x;
                const vec3 tint[6] = vec3[](vec3(1.0, 0.3, 0.3), vec3(0.3, 1.0, 0.3),
                    vec3(0.3, 0.4, 1.0), vec3(1.0, 1.0, 0.3), vec3(1.0, 0.3, 1.0),
                    vec3(0.3, 1.0, 1.0));
                return beyond ? vec3(0.1) : tint[k] * (0.35 + 0.65 * max(dot(s.n, V), 0.0));
            }
            vec3 l;
            vec3 E;
            light_incidence(lights[i], P, l, E);
            return vec3(shadow_visibility(i, P, s.n, l));
        }
        return vec3(0.0);
    }
#ifdef IBL
    if (DEBUG_VIEW == DEBUG_VIEW_IRRADIANCE) return env_irradiance(s.n) / M_PI;
    if (DEBUG_VIEW == DEBUG_VIEW_PREFILTERED) {
        vec3 r = 2.0 * dot(s.n, V) * s.n - V;
        return textureLod(prefiltered_cube, r, prefiltered_lod(p.color.w, env.params.x)).rgb;
    }
#endif
    return vec3(0.0);
}

vec3 shade(vec3 P, vec3 N, vec3 X, vec3 Y, vec2 uv) {
    Surface s = surface_at(N, X, Y, uv);
    // KHR_materials_clearcoat's normal, for every coat term of this pixel (brdf_coat_normal),
    // the environment's energy scale included: set before anything reads it.
    g_coat_n = s.coat_n;
    BrdfParams p = s.p;
    // camera_pos is (eye, 1), or (−forward, 0) for an orthographic camera: V is constant then.
    vec3 V = normalize(frame.camera_pos.xyz - P * frame.camera_pos.w);
    // KHR_materials_sheen's Λ fit and its value at the view, once for every light (v_sheen reads
    // them in the fragment stage: set before anything, the debug views included, evaluates the
    // sheen; has_sheen compiles out without the lobe).
    if (has_sheen(p)) {
        sheen_view(p.kappa.w, brdf_clamp_cos(dot(s.n, V)));
    }
    // KHR_materials_iridescence's film and bases, once for every light and the environment
    // (brdf_iridescence_fresnel_of reads them in the fragment stage).
    if (MODEL == BRDF_MODEL_METAL_ROUGH && (LOBES & BRDF_LOBE_IRIDESCENCE) != 0u
        && brdf_has_iridescence(p)) {
        g_material_film = brdf_material_film(p);
    }
    if (DEBUG_VIEW != DEBUG_VIEW_NONE && DEBUG_VIEW != DEBUG_VIEW_NAN) {
        return debug_value(s, P, V);
    }
    vec3 result = s.occlusion * ambient_term(p, frame.ambient.rgb);
    // KHR_materials_anisotropy's lobe frame, once for every light and the energy scale (off
    // unless LOBES has it).
    AnisotropicLobe an = brdf_anisotropic_lobe(p, s.n, s.x, s.y);
#ifdef IBL
    EnergyScale es = energy_scale(p, s.n, V, an);
    float e_sheen = es.sheen;
#else
    // The sheen's albedo at the view, once for every light (MODEL is a constant: the branch
    // and the fit compile out without a sheen lobe).
    float e_sheen = MODEL == BRDF_MODEL_METAL_ROUGH ? brdf_sheen_albedo_at(p, s.n, V) : 0.0;
#endif
    // KHR_materials_iridescence at the view: the film once for every light.
    if (MODEL == BRDF_MODEL_METAL_ROUGH && brdf_has_iridescence(p) && brdf_film_at_view(p)) {
        g_film_view = brdf_iridescence_fresnel_of(p, brdf_clamp_cos(dot(s.n, V)));
    }
    uint cell = CLUSTERED ? light_cluster(P) : 0u;
    uvec2 cluster = light_list_of(cell);
    // Fixed shadow slots (shadows.glsl): each shadowed light's visibility once, before the loop.
    bool fixed_shadows = (LIGHT_KINDS & SHADOW_KINDS) != 0u && SHADOW_FIXED_0 != 0u;
    vec4 fixed_vis = vec4(1.0);
    if (fixed_shadows) {
        fixed_vis = opaque(material.receive_shadow) != 0u ? shadow_fixed_all(P, N) : vec4(1.0);
    }
    for (uint k = 0u; k < cluster.y; ++k) {
        uint i = light_list_index(cluster, k);
        vec3 l;
        vec3 E;
        light_incidence(lights[i], P, l, E);
        // Shadows darken direct light only (the environment stays unshadowed); the normal
        // offset uses the interpolated normal N, not a normal map's.
        // Every model's radiance is zero where n·l ≤ 0: no lookup there. (A loop of zero or one
        // trip instead of this `if` made lavapipe 22.3 skip the code for lights without a
        // shadow, 2.1× → 1.6× on the default scene, but grow its memory ~5 MB per frame even
        // in scenes without shadows: docs/shadows.md.)
        if (fixed_shadows) {
            E *= shadow_fixed_pick(i, fixed_vis);
        }
        bool shadowed = (LIGHT_KINDS & SHADOW_KINDS) != 0u && !fixed_shadows
            && opaque(material.receive_shadow) != 0u
            && shadow_lights[i].info.x >= 0 && (E.r > 0.0 || E.g > 0.0 || E.b > 0.0)
            && dot(s.n, l) > 0.0;
        if (shadowed) {
            E *= shadow_visibility(i, P, N, l);
        }
#ifdef LUZ_GLASS
        if ((LOBES & BRDF_LOBE_DIFFUSE_TRANSMISSION) != 0u && MODEL == BRDF_MODEL_METAL_ROUGH) {
            result += diffuse_transmission_weight(s) * E * clamp(-dot(s.n, l), 0.0, 1.0);
        }
#endif
#ifdef IBL
        if (energy_compensated(p)) {
            BrdfTerms t = brdf_metal_rough_base_terms_lobe(p, s.n, l, V, an);
            t.diffuse *= es.diffuse;
            t.specular *= es.specular;
            if (has_sheen(p) && dot(s.n, l) > 0.0) {
                t = sheen_layer(t, p, s.n, l, V, es.sheen);
            }
            if ((LOBES & BRDF_LOBE_CLEARCOAT) != 0u && dot(s.n, l) > 0.0) {
                t = clearcoat_layer(t, p, s.n, l, V, es.coat);
            }
            result += (t.diffuse + t.specular) * E * clamp(dot(s.n, l), 0.0, 1.0);
            continue;
        }
#endif
        if (p.sel.x == BRDF_MODEL_METAL_ROUGH) {
            BrdfTerms t = brdf_metal_rough_terms_lobe_es(p, s.n, l, V, an, e_sheen);
            result += (t.diffuse + t.specular) * E * clamp(dot(s.n, l), 0.0, 1.0);
            continue;
        }
        result += brdf_radiance_unit(p, s.n, l, V, s.x, s.y, E);
    }
    if ((LIGHT_KINDS & LK_AREA) != 0u) {
        // Clustered: the cluster's area lights only (a loop of its own, not a branch per light).
        uvec2 areas = area_list_of(cell);
        for (uint k = 0u; k < areas.y; ++k) {
            uint j = area_list_index(areas, k);
            vec3 lo = area_shade(j, s, P, V);
            // Shadowed area lights (AREA_SHADOW_KINDS: compiled only when some has a shadow):
            // the emitter's light times the fraction of it the maps let through.
            if (AREA_SHADOW_KINDS != 0u && opaque(material.receive_shadow) != 0u
                && (lo.r > 0.0 || lo.g > 0.0 || lo.b > 0.0)) {
                lo *= area_shadow(j, area_data[opaque(frame.counts.z) + j * AREA_VEC4S].xyz, P, N);
            }
            result += lo;
        }
    }
#ifdef IBL
    result += s.occlusion * ibl_shade(p, s.n, V, s.x, s.y, es);
#endif
#ifdef LUZ_GLASS
    if (MODEL == BRDF_MODEL_METAL_ROUGH && REFRACTION != REFRACTION_NONE) {
        if ((LOBES & BRDF_LOBE_TRANSMISSION) != 0u) {
            result += transmitted(s, P, V);
        }
#ifdef IBL
        if ((LOBES & BRDF_LOBE_DIFFUSE_TRANSMISSION) != 0u) {
            result += s.occlusion * diffuse_transmission_weight(s) * env_irradiance(-s.n);
        }
#endif
    }
#endif
    return result + s.emission;
}

// Depth cueing: S from the view-space depth z, then I' = (1 − S) I + S I_F.
vec3 apply_fog(vec3 c, float z) {
    if (!FOG) {
        return c;
    }
    float za = frame.fog.x;
    float zb = frame.fog.y;
    float sa = frame.fog.z;
    float sb = frame.fog.w;
    float S;
    if (z < za) {
        S = sa;
    } else if (z > zb) {
        S = sb;
    } else {
        S = zb > za ? sa + (z - za) * (sb - sa) / (zb - za) : sa;
    }
    return (1.0 - S) * c + S * frame.fog_color.rgb;
}

#endif
