#version 430 core
// d'Eon et al.'s modified translucent shadow maps (Sec. 5.2), read in the
// final pass of texture-space diffusion. Each point, spot or directional
// light with a shadow map has a TSM holding, for the surface nearest the
// light (A), its UV, its distance from the light (light_distance) and its
// normal. A shadowed point C looks up A, takes the distance m through the
// object, d = lerp(m, m cos(theta), max(0, -N_A.N_C)) with theta between N_A
// and the light, and adds sum_i w_i exp(-d^2 / 2v_i) fadeOut_i level_i(uv_A),
// level_i the irradiance map convolved by G(v_i) (the texture-space blur's
// levels, kept for it). d is computed per pixel rather than blurred in the
// levels' alpha: the blur uses alpha as its coverage mask.
#include "technique.glsl"

uniform sampler2DArray u_tsm_flat;     // layer 2k: (u, v, distance, 1); 2k + 1: (normal, 1)
// Cube-mapped point lights' faces as 2D layers 12k + face and 12k + 6 +
// face (a cube map array would do, but sampling one crashes llvmpipe's
// LLVM 15), and the faces' view-projections from the origin: their x and y
// do not depend on the origin's position or the far plane.
uniform sampler2DArray u_tsm_cube;
uniform mat4 u_cube_face[6];
uniform sampler2DArray u_levels;       // layer i: the irradiance convolved by G(v_i)
uniform sampler2D u_stretch;           // mm per texel along u and v
uniform float u_atlas_used;            // texels along the used corner's side
// u_atlas_scale and u_atlas_texel: shade.frag's.

// The level's light where a chart covers it: bilinear taps beside a chart's
// edge read empty texels (alpha 0), so divide by the covered fraction.
vec3 level_at(vec2 uv, int i)
{
    vec4 s = texture(u_levels, vec3(clamp(uv * u_atlas_scale, vec2(0.5 * u_atlas_texel),
                                          vec2(u_atlas_scale - 0.5 * u_atlas_texel)), float(i)));
    return s.a > 0.0 ? s.rgb / s.a : vec3(0.0);
}

vec3 tsm_translucency(vec3 p, vec3 n, vec2 uv, vec3 total_reflectance)
{
    vec3 per_weight = vec3(total_reflectance.r > 0.0 ? 1.0 / total_reflectance.r : 0.0,
                           total_reflectance.g > 0.0 ? 1.0 / total_reflectance.g : 0.0,
                           total_reflectance.b > 0.0 ? 1.0 / total_reflectance.b : 0.0);
    vec2 stretch = texture(u_stretch, uv * u_atlas_scale).xy;
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < u_all_light_count; ++i) {
        Light l = lights[i];
        int index = int(l.params.z);
        if (index < 0 || int(l.color_type.w) == 3)
            continue;
        // Lit points see their own surface in the map: only shadow sends
        // light through (the fade alone leaves the narrowest Gaussians
        // leaking across one TSM texel of UV).
        float dark = 1.0 - shadow(l, p, n);
        if (dark <= 0.0)
            continue;
        vec4 a, na;
        if (l.params.w != 0.0) {
            // The face a cube map would pick: the major axis.
            vec3 dir = p - u_cube_origin[index], m = abs(dir);
            int face = m.x >= m.y && m.x >= m.z ? (dir.x > 0.0 ? 0 : 1)
                       : m.y >= m.z             ? (dir.y > 0.0 ? 2 : 3)
                                                : (dir.z > 0.0 ? 4 : 5);
            vec4 clip = u_cube_face[face] * vec4(dir, 1.0);
            vec2 at = clip.xy / clip.w * 0.5 + 0.5;
            a = texture(u_tsm_cube, vec3(at, float(12 * index + face)));
            na = texture(u_tsm_cube, vec3(at, float(12 * index + 6 + face)));
        } else {
            vec4 clip = u_flat_matrix[index] * vec4(p, 1.0);
            vec3 ndc = clip.xyz / clip.w;
            if (clip.w <= 0.0 || any(greaterThan(abs(ndc.xy), vec2(1.0))))
                continue;
            a = texture(u_tsm_flat, vec3(ndc.xy * 0.5 + 0.5, float(2 * index)));
            na = texture(u_tsm_flat, vec3(ndc.xy * 0.5 + 0.5, float(2 * index + 1)));
        }
        if (a.w <= 0.0)
            continue;
        float m = max(light_distance(l, p) - a.z, 0.0) * u_mm_per_unit;
        vec3 n_a = normalize(na.xyz);
        float cos_theta = abs(dot(n_a, light_direction(l, p)));
        float d = mix(m, m * cos_theta, max(0.0, -dot(n_a, n)));
        float apart = length((a.xy - uv) * u_atlas_used * stretch);
        for (int g = 0; g < u_fit_count; ++g) {
            float fade = clamp(apart / (6.0 * sqrt(u_fit[g].w)), 0.0, 1.0);
            sum += dark * fade * exp(-d * d / (2.0 * u_fit[g].w)) * u_fit[g].rgb * per_weight * level_at(a.xy, g);
        }
    }
    return sum;
}
