#version 430 core
// Diffuse radiance leaving the surface (Maisch and Ropinski eq. 5 with the
// front/back split of eq. 6-7): rho_dt(N.V) / pi * (R_front + T) * albedo
// (with a blur, sqrt(albedo) on the way in and sqrt(albedo) on the way out,
// d'Eon Sec. 5.3),
// where R_front = L_d times the profile's total diffuse reflectance stands
// for the front-side integral until a surface-diffusion pass blurs it, and
// T is the technique's translucency (technique.glsl; with texture-space
// diffusion it is in the atlas, and a TSM adds its own after the blur). Plus the Kelemen/Szirmay-Kalos specular lobe
// (d'Eon Sec. 6; the lobe rho_dt removed from the diffuse light) for every
// light, shadowed like L_d. Linear HDR out; tonemapping happens on output.
#include "sam_bindings.h"
#include "technique.glsl"
#include "surface.glsl"
#include "albedo.glsl"
#include "uv_atlas.glsl"

in vec3 v_position;
in vec3 v_normal;
in vec3 v_to_eye;
in vec3 v_translucency;

uniform uint u_light_count;       // 0 for translucency only
uniform float u_roughness;        // Beckmann m
uniform float u_f0;               // Schlick F0

uniform vec3 u_total_reflectance;
uniform int u_front;               // 0: translucency only

uniform int u_split;               // 1: write the parts surface diffusion needs

// u_split == 0: o_color is the final linear radiance.
// u_split == 1: o_color = (light entering the surface, linear view depth),
// o_factor = rho_dt(N.V) / pi * sqrt(albedo) (applied after the blur),
// o_specular = the specular radiance (not blurred).
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_factor;
layout(location = 2) out vec4 o_specular;

in float v_depth;
in float v_curvature;
in vec2 v_uv;
in vec3 v_color;         // the vertex colour, white without one

// Texture-space diffusion: the blurred entering light, read at the UV in
// the atlas's used corner (u_atlas_scale = used side / texture side).
uniform int u_texture_space;
uniform sampler2D u_atlas;
uniform float u_atlas_scale;
uniform float u_atlas_texel;  // 1 / texture side
uniform int u_read_atlas;     // 0: the atlas holds light this view does not show (a TSM's front light)
uniform int u_tsm;            // 1: add the translucent shadow maps' light
#include "tsm_read.glsl"

// 1: write the G-buffer instead (sam_runtime_gbuffer): o_color = position,
// o_factor = the normal as shading uses it, alpha 1.
uniform int u_gbuffer;

// Pre-integrated skin (Penner): tables of sam_preint, RGB, 64 x 64.
layout(std430, binding = SAM_B_PRE_DIFFUSE) readonly buffer PreDiffuse { float pre_diffuse[]; };
layout(std430, binding = SAM_B_PRE_PENUMBRA) readonly buffer PrePenumbra { float pre_penumbra[]; };
uniform int u_preintegrated;
uniform int u_pre_size;
uniform float u_pre_max_curvature;  // 1/mm
uniform float u_pre_max_penumbra;   // mm
uniform float u_min_penumbra;       // mm: the profile's 99% radius

// Bilinear lookup in a pre-integrated table (texel-centred), x and y in [0, 1].
vec3 table_rgb(int which, float x, float y)
{
    int x0, x1, y0, y1;
    float ax, ay;
    centred_taps(x, u_pre_size, x0, x1, ax);
    centred_taps(y, u_pre_size, y0, y1, ay);
    vec3 t[4];
    ivec2 at[4] = ivec2[4](ivec2(x0, y0), ivec2(x1, y0), ivec2(x0, y1), ivec2(x1, y1));
    for (int i = 0; i < 4; ++i) {
        int k = 3 * (at[i].y * u_pre_size + at[i].x);
        t[i] = which == 0 ? vec3(pre_diffuse[k], pre_diffuse[k + 1], pre_diffuse[k + 2])
                          : vec3(pre_penumbra[k], pre_penumbra[k + 1], pre_penumbra[k + 2]);
    }
    return mix(mix(t[0], t[1], ax), mix(t[2], t[3], ax), ay);
}

// The shadow filter's penumbra across the surface in mm: the 4-texel PCF
// footprint at the light's distance, stretched on slanted surfaces.
float penumbra_mm(Light l, vec3 p, float n_dot_l)
{
    return 4.0 * shadow_texel(l, p) * u_mm_per_unit / max(abs(n_dot_l), 0.2);
}

vec3 preintegrated_front(vec3 n, vec3 p)
{
    vec3 sum = vec3(0.0);
    float k = clamp(abs(v_curvature) / u_pre_max_curvature, 0.0, 1.0);
    for (uint i = 0u; i < u_light_count; ++i) {
        Light l = lights[i];
        if (int(l.color_type.w) == 3) {
            float n_dot_l;
            vec3 e = light_irradiance(l, p, n, n_dot_l);
            sum += e * rho_dt(n_dot_l) * shadow(l, p, n);
            continue;
        }
        vec3 dir = int(l.color_type.w) == 2 ? -l.direction.xyz : normalize(l.position.xyz - p);
        float n_dot_l = dot(n, dir);
        vec3 falloff = table_rgb(0, 0.5 * n_dot_l + 0.5, k);
        // Inside a penumbra, the shadow value re-mapped through the penumbra
        // table (Penner), its width clamped up to the profile's extent as the
        // table assumes; outside one (0 or 1) there is no edge to scatter across.
        float s = shadow(l, p, n);
        vec3 shade = vec3(s);
        if (l.params.z >= 0.0 && s > 0.001 && s < 0.999)
            shade = table_rgb(1, s, max(penumbra_mm(l, p, n_dot_l), u_min_penumbra) / u_pre_max_penumbra);
        sum += light_radiance(l, p) * falloff * shade * rho_dt(max(n_dot_l, 0.0));
    }
    return sum + environment_irradiance(n);
}

// f_r = D(N.H) F(V.H) / |L + V|^2 (sam_brdf_ks_eval), D normalised Beckmann.
float ks_specular(vec3 n, vec3 l, vec3 v)
{
    float nl = dot(n, l), nv = dot(n, v);
    if (nl <= 0.0 || nv <= 0.0)
        return 0.0;
    vec3 h = l + v;
    vec3 hn = normalize(h);
    float c = dot(n, hn), m2 = u_roughness * u_roughness, c2 = c * c;
    float d = exp(-(1.0 - c2) / (c2 * m2)) / (PI * m2 * c2 * c2);
    float f = u_f0 + (1.0 - u_f0) * pow(1.0 - dot(v, hn), 5.0);
    return d * f / dot(h, h);
}

void main()
{
    vec3 n = normalize(v_normal), v = normalize(v_to_eye);
    if (!gl_FrontFacing)
        n = -n;
    if (u_gbuffer != 0) {
        o_color = vec4(v_position, 1.0);
        o_factor = vec4(n, 1.0);
        o_specular = vec4(0.0);
        return;
    }
    vec3 albedo = surface_albedo(v_uv, v_color);
    bool blurred = u_split != 0 || u_texture_space != 0;
    // L_d at this pixel, as the irradiance pass computes it at the vertices
    // (lights times rho_dt(N.L), shadowed, and the environment), and the
    // specular lobe under the same shadows. Per pixel rather than the
    // vertices' L_d interpolated: on a coarse mesh an interpolated shadow
    // edge ran along the triangles, a staircase a vertex apart.
    vec3 front = vec3(0.0), specular = vec3(0.0);
    for (uint i = 0u; i < u_light_count; ++i) {
        float n_dot_l;
        vec3 e = light_irradiance(lights[i], v_position, n, n_dot_l);
        if (e == vec3(0.0))
            continue;
        float s = shadow(lights[i], v_position, n);
        front += e * rho_dt(n_dot_l) * s;
        specular += u_specular_k * ks_specular(n, light_direction(lights[i], v_position), v) * e * s;
    }
    front += environment_irradiance(n);
    vec3 entering = vec3(0.0);
    if (u_texture_space != 0) {
        // Clamped half a texel inside the used corner: bilinear taps past it
        // would read texels another (larger) atlas left behind. Divided by the
        // interpolated coverage, so taps on empty texels beside a chart's edge
        // (or culled, clipped ones) do not darken it: at a small depth-sized
        // atlas those seams would cover much of the surface.
        vec2 auv = atlas_uv(v_uv);
        if (u_read_atlas != 0) {
            vec4 s = texture(u_atlas, clamp(auv * u_atlas_scale, vec2(0.5 * u_atlas_texel),
                                            vec2(u_atlas_scale - 0.5 * u_atlas_texel)));
            entering = s.a > 0.0 ? s.rgb / s.a : s.rgb;
        }
        if (u_tsm != 0)
            entering += tsm_translucency(v_position, n, auv, u_total_reflectance);
    } else {
        entering = technique_translucency(v_translucency, v_position, n);
        if (u_front != 0)
            entering += (u_preintegrated != 0 ? preintegrated_front(n, v_position) : front) * u_total_reflectance;
        if (u_split != 0)
            entering *= sqrt(albedo);
    }
    vec3 factor = rho_dt(dot(n, v)) / PI * (blurred ? sqrt(albedo) : albedo);
    if (u_split != 0) {
        o_color = vec4(entering, v_depth);
        o_factor = vec4(factor, 1.0);
        o_specular = vec4(specular, 1.0);
    } else {
        o_color = vec4(factor * entering + specular, 1.0);
        o_factor = vec4(0.0);
        o_specular = vec4(0.0);
    }
}
