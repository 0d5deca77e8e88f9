#version 430 core
// L_d at every vertex (Maisch and Ropinski eq. 4): the light entering the
// surface, each light's irradiance times rho_dt(N.L) (d'Eon Sec. 6), plus
// the environment's SH-9 irradiance times its cosine-weighted mean rho_dt.
#include "lights.glsl"
#include "shadows.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 4) writeonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 8) readonly buffer Lights { Light lights[]; };
layout(std430, binding = 9) readonly buffer RhoDt { float rho_dt_table[]; };


uniform uint u_vertex_count;
uniform uint u_light_count;
uniform vec3 u_sh[9];            // environment radiance SH (rotation and intensity applied)
uniform int u_has_environment;
uniform float u_environment_rho_dt;
uniform int u_rho_size_ndotl;
uniform int u_rho_size_roughness;
uniform float u_roughness_coord;  // roughness / roughness_max
uniform float u_specular_k;       // pi * rho_s: rho_dt = 1 - k (1 - table)

// The table's bilinear filter, written out so it matches
// sam_brdf_rho_dt_table_lookup exactly (texture units round weights).
void taps(float coord, int size, out int k0, out int k1, out float t)
{
    float x = clamp(coord, 0.0, 1.0) * float(size) - 0.5;
    float f = floor(x);
    t = x - f;
    k0 = clamp(int(f), 0, size - 1);
    k1 = clamp(int(f) + 1, 0, size - 1);
}

float rho_dt(float n_dot_l)
{
    int i0, i1, j0, j1;
    float ti, tj;
    taps(n_dot_l, u_rho_size_ndotl, i0, i1, ti);
    taps(u_roughness_coord, u_rho_size_roughness, j0, j1, tj);
    float a = mix(rho_dt_table[j0 * u_rho_size_ndotl + i0], rho_dt_table[j0 * u_rho_size_ndotl + i1], ti);
    float b = mix(rho_dt_table[j1 * u_rho_size_ndotl + i0], rho_dt_table[j1 * u_rho_size_ndotl + i1], ti);
    return 1.0 - u_specular_k * (1.0 - mix(a, b, tj));
}

vec3 sh_irradiance(vec3 n)
{
    const float A0 = PI, A1 = 2.0 * A0 / 3.0, A2 = A0 / 4.0;
    float x = n.x, y = n.y, z = n.z;
    vec3 e = A0 * 0.282094792 * u_sh[0]
           + A1 * 0.488602512 * (y * u_sh[1] + z * u_sh[2] + x * u_sh[3])
           + A2 * (1.092548431 * (x * y * u_sh[4] + y * z * u_sh[5] + x * z * u_sh[7])
                   + 0.315391565 * (3.0 * z * z - 1.0) * u_sh[6]
                   + 0.546274215 * (x * x - y * y) * u_sh[8]);
    return max(e, vec3(0.0));
}

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 p = positions[v].xyz, n = normals[v].xyz;
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < u_light_count; ++i) {
        float n_dot_l;
        vec3 e = light_irradiance(lights[i], p, n, n_dot_l);
        if (e != vec3(0.0))
            sum += e * rho_dt(n_dot_l) * shadow(lights[i], p, n);
    }
    if (u_has_environment != 0)
        sum += sh_irradiance(n) * u_environment_rho_dt;
    irradiance[v] = vec4(sum, 1.0);
}
