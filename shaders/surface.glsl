#version 430 core
// The light the surface lets in (d'Eon Sec. 6, Maisch and Ropinski eq. 4),
// shared by the irradiance pass and the shading pass: rho_dt from the
// table of sam_brdf_rho_dt_table, and the environment's SH-9 irradiance
// (sam_light_sh9_irradiance).
#include "sam_bindings.h"
#include "constants.glsl"

layout(std430, binding = SAM_B_RHO_DT) readonly buffer RhoDt { float rho_dt_table[]; };

uniform int u_rho_size;           // the square table's side
uniform float u_roughness_coord;  // roughness / roughness_max
uniform float u_specular_k;       // pi * rho_s: rho_dt = 1 - k (1 - table)
uniform vec3 u_sh[9];             // environment radiance SH (rotation and intensity applied)
uniform int u_has_environment;
uniform float u_environment_rho_dt;

// Linear filtering of a table sampled at texel centres, written out so it
// matches the CPU lookups exactly (texture units round their weights): the
// two texels around coord in [0, 1] and the weight of the second.
void centred_taps(float coord, int size, out int k0, out int k1, out float t)
{
    float x = clamp(coord, 0.0, 1.0) * float(size) - 0.5;
    float f = floor(x);
    t = x - f;
    k0 = clamp(int(f), 0, size - 1);
    k1 = clamp(int(f) + 1, 0, size - 1);
}

float rho_dt(float cosine)
{
    int i0, i1, j0, j1;
    float ti, tj;
    centred_taps(cosine, u_rho_size, i0, i1, ti);
    centred_taps(u_roughness_coord, u_rho_size, j0, j1, tj);
    float a = mix(rho_dt_table[j0 * u_rho_size + i0], rho_dt_table[j0 * u_rho_size + i1], ti);
    float b = mix(rho_dt_table[j1 * u_rho_size + i0], rho_dt_table[j1 * u_rho_size + i1], ti);
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

// The environment's contribution to L_d at normal n.
vec3 environment_irradiance(vec3 n)
{
    return u_has_environment != 0 ? sh_irradiance(n) * u_environment_rho_dt : vec3(0.0);
}
