#version 430 core
// Diffuse radiance leaving the surface (Maisch and Ropinski eq. 5 with the
// front/back split of eq. 6-7): rho_dt(N.V) / pi * (R_front + T) * albedo,
// where R_front = L_d times the profile's total diffuse reflectance stands
// for the front-side integral until a surface-diffusion pass blurs it, and
// T is the SAM translucency. Plus the Kelemen/Szirmay-Kalos specular lobe
// (d'Eon Sec. 6; the lobe rho_dt removed from the diffuse light) for every
// light, shadowed like L_d. Linear HDR out; tonemapping happens on output.
#include "lights.glsl"
#include "shadows.glsl"

in vec3 v_position;
in vec3 v_normal;
in vec3 v_to_eye;
in vec3 v_irradiance;
in vec3 v_translucency;

layout(std430, binding = 8) readonly buffer Lights { Light lights[]; };
layout(std430, binding = 9) readonly buffer RhoDt { float rho_dt_table[]; };

uniform uint u_light_count;       // 0 for translucency only
uniform float u_roughness;        // Beckmann m
uniform float u_f0;               // Schlick F0

uniform vec3 u_albedo;
uniform vec3 u_total_reflectance;
uniform int u_front;               // 0: translucency only
uniform int u_rho_size;
uniform float u_roughness_coord;
uniform float u_specular_k;

uniform int u_split;               // 1: write the parts surface diffusion needs

// u_split == 0: o_color is the final linear radiance.
// u_split == 1: o_color = (light entering the surface, linear view depth),
// o_factor = rho_dt(N.V) / pi * albedo (applied after the blur),
// o_specular = the specular radiance (not blurred).
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_factor;
layout(location = 2) out vec4 o_specular;

in float v_depth;

float rho_dt_view(float n_dot_v)
{
    float x = clamp(n_dot_v, 0.0, 1.0) * float(u_rho_size) - 0.5;
    float y = clamp(u_roughness_coord, 0.0, 1.0) * float(u_rho_size) - 0.5;
    int i0 = clamp(int(floor(x)), 0, u_rho_size - 1), i1 = clamp(int(floor(x)) + 1, 0, u_rho_size - 1);
    int j0 = clamp(int(floor(y)), 0, u_rho_size - 1), j1 = clamp(int(floor(y)) + 1, 0, u_rho_size - 1);
    float a = mix(rho_dt_table[j0 * u_rho_size + i0], rho_dt_table[j0 * u_rho_size + i1], x - floor(x));
    float b = mix(rho_dt_table[j1 * u_rho_size + i0], rho_dt_table[j1 * u_rho_size + i1], x - floor(x));
    return 1.0 - u_specular_k * (1.0 - mix(a, b, y - floor(y)));
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

vec3 light_direction(Light l, vec3 p)
{
    int type = int(l.color_type.w);
    if (type == 2)
        return -l.direction.xyz;
    if (type == 3) {
        vec3 c = vec3(0.0);
        int count = int(l.position.w);
        for (int i = 0; i < count; ++i)
            c += l.vertices[i].xyz;
        return normalize(c / float(count) - p);
    }
    return normalize(l.position.xyz - p);
}

void main()
{
    vec3 n = normalize(v_normal), v = normalize(v_to_eye);
    if (!gl_FrontFacing)
        n = -n;
    vec3 entering = v_translucency;
    if (u_front != 0)
        entering += v_irradiance * u_total_reflectance;
    vec3 factor = rho_dt_view(dot(n, v)) / PI * u_albedo;
    vec3 specular = vec3(0.0);
    for (uint i = 0u; i < u_light_count; ++i) {
        float n_dot_l;
        vec3 e = light_irradiance(lights[i], v_position, n, n_dot_l);
        if (e != vec3(0.0))
            specular += u_specular_k * ks_specular(n, light_direction(lights[i], v_position), v) * e *
                        shadow(lights[i], v_position, n);
    }
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
