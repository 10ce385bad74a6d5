// Glass on the GPU (issue 35): what a transmissive metal-rough surface lets through, added to
// its shaded reflection (whose diffuse the transmission took: brdf_diffuse_keep).
//
// Specular transmission (KHR_materials_transmission, _volume, _dispersion) is screen-space
// refraction, as Khronos' Sample Renderer and Filament draw it: the view ray refracts at the
// surface (index from the dielectric F0), runs `thickness` (the volume's thickness in mesh units
// × the object's largest scale) inside, and the copy of the opaque scene (transmission_copy,
// with mips) is read where that point projects, at a mip level that grows with the roughness
// (REFRACTION: the policy). Beer–Lambert over the same distance; one index per channel with
// dispersion; thin-walled (thickness 0 or REFRACTION_THIN) the ray goes straight through. What
// comes through is weighted by transmission · (1 − metallic) · base colour · (1 − E), E the
// surface's specular albedo at the view (the split-sum table's under an environment, Schlick's
// Fresnel without one). Glass behind glass is not seen (the copy holds the opaque scene only).
//
// Diffuse transmission (KHR_materials_diffuse_transmission): every light and the environment on
// the far side, through the Lambertian BTDF (1 − transmission)(1 − metallic) · diffuse
// transmission · colour · base colour / π; lights from behind are not shadowed.
#ifndef LUZ_TRANSMISSION_GLSL
#define LUZ_TRANSMISSION_GLSL

layout(set = SET_FRAME, binding = BINDING_TRANSMISSION) uniform sampler2D transmission_copy;

// The object's largest scale (the thickness is in its mesh's units): transmissive draws are
// never instanced, so the push constants name the object.
float transmission_object_scale() {
    mat4 m = objects[material.object_index].model;
    return max(length(m[0].xyz), max(length(m[1].xyz), length(m[2].xyz)));
}

// The dielectric's index from its F0 (the green channel of spec.rgb): (1 + √F0) / (1 − √F0).
float transmission_ior(BrdfParams p) {
    float s = sqrt(clamp(p.spec.g, 0.0, 0.9));
    return (1.0 + s) / (1.0 - s);
}

// The copy's mip level for a surface of this roughness and index (REFRACTION's policy).
float transmission_lod(float roughness, float ior) {
    float levels = float(textureQueryLevels(transmission_copy));
    float width = log2(float(textureSize(transmission_copy, 0).x));
    if (REFRACTION == REFRACTION_SCREEN_SHARP) {
        return 0.0;
    }
    if (REFRACTION == REFRACTION_SCREEN_FILAMENT) {
        return clamp(2.0 * log2(max(roughness, 1e-4)) + width, 0.0, levels - 1.0);
    }
    return clamp(width * roughness * clamp(2.0 * ior - 2.0, 0.0, 1.0), 0.0, levels - 1.0);
}

// The copy seen along the view ray refracted with index `ior` at P (normal n, towards the viewer
// V), `thickness` world units inside (0: straight through).
vec3 transmission_sample(vec3 P, vec3 n, vec3 V, float ior, float thickness, float lod) {
    vec3 r = thickness > 0.0 ? refract(-V, n, 1.0 / ior) : -V;
    vec4 clip = frame.view_proj * vec4(P + r * thickness, 1.0);
    vec2 uv = clip.xy / max(clip.w, 1e-6) * 0.5 + 0.5;
    return textureLod(transmission_copy, uv, lod).rgb;
}

// The surface's specular albedo at the view (what reflection keeps from transmission).
vec3 transmission_reflected(BrdfParams p, float n_v) {
#ifdef IBL
    vec2 ab = brdf_lut_ab(n_v, p.color.w);
    return p.spec.rgb * ab.x + ab.y;
#else
    return p.spec.rgb + (1.0 - p.spec.rgb) * pow(1.0 - n_v, 5.0);
#endif
}

#ifdef IBL
// REFRACTION_ENVIRONMENT (Filament's "solid" refraction): the view ray refracts in at P, crosses
// a sphere of diameter `thickness` (its length inside: `inside`) and refracts out; the
// prefiltered environment is read along the way it leaves, at the split sum's level for the
// roughness. Thin-walled: straight through.
vec3 transmission_environment(vec3 n, vec3 V, float ior, float thickness, float roughness,
                              out float inside) {
    vec3 d = -V;
    inside = 0.0;
    if (thickness > 0.0) {
        vec3 r = refract(-V, n, 1.0 / ior);
        float n_r = dot(n, r);
        inside = thickness * -n_r;
        vec3 out_n = normalize(n_r * r - n * 0.5);
        vec3 t = refract(r, out_n, ior);
        d = dot(t, t) > 0.0 ? t : r;
    }
    return textureLod(prefiltered_cube, d, prefiltered_lod(roughness, env.params.x)).rgb;
}
#endif

vec3 transmitted(Surface s, vec3 P, vec3 V) {
    BrdfParams p = s.p;
    vec3 n = s.n;
    float n_v = clamp(dot(n, V), 1e-4, 1.0);
    float ior = transmission_ior(p);
    bool thin = REFRACTION == REFRACTION_THIN;
    float thickness = thin ? 0.0 : s.glass.x * transmission_object_scale();
    float lod = transmission_lod(p.color.w, ior);
    vec3 through;
    float inside = thickness;
#ifdef IBL
    if (REFRACTION == REFRACTION_ENVIRONMENT) {
        if ((LOBES & BRDF_LOBE_DISPERSION) != 0u) {
            float spread = (ior - 1.0) * 0.025 * mat_extra.volume.y;
            float unused;
            through = vec3(
                transmission_environment(n, V, ior - spread, thickness, p.color.w, unused).r,
                transmission_environment(n, V, ior, thickness, p.color.w, inside).g,
                transmission_environment(n, V, ior + spread, thickness, p.color.w, unused).b);
        } else {
            through = transmission_environment(n, V, ior, thickness, p.color.w, inside);
        }
    } else
#endif
    if ((LOBES & BRDF_LOBE_DISPERSION) != 0u) {
        // KHR_materials_dispersion: ior ∓ (ior − 1) · 0.025 · dispersion for red and blue.
        float spread = (ior - 1.0) * 0.025 * mat_extra.volume.y;
        through = vec3(transmission_sample(P, n, V, ior - spread, thickness, lod).r,
                       transmission_sample(P, n, V, ior, thickness, lod).g,
                       transmission_sample(P, n, V, ior + spread, thickness, lod).b);
    } else {
        through = transmission_sample(P, n, V, ior, thickness, lod);
    }
    vec3 attenuation = exp(-mat_extra.attenuation.rgb * inside);
    vec3 tint = p.p2.x * (1.0 - p.spec.w) * p.color.rgb;
    return tint * (vec3(1.0) - transmission_reflected(p, n_v)) * attenuation * through;
}

// KHR_materials_diffuse_transmission's BTDF weight (× irradiance from the far side).
vec3 diffuse_transmission_weight(Surface s) {
    BrdfParams p = s.p;
    return (1.0 - p.p2.x) * (1.0 - p.spec.w) * p.p2.y * s.glass.yzw * p.color.rgb * M_1_PI;
}

#endif
