#version 430 core
// L_d at every vertex (Maisch and Ropinski eq. 4): the light entering the
// surface, each light's irradiance times rho_dt(N.L) (d'Eon Sec. 6), plus
// the environment's SH-9 irradiance times its cosine-weighted mean rho_dt.
#include "lights.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 4) writeonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 8) readonly buffer Lights { Light lights[]; };
layout(std430, binding = 9) readonly buffer RhoDt { float rho_dt_table[]; };

// Shadow maps: point and area lights (from the area's centroid) get a cube
// map of distance / far; spot and directional lights a 2D depth map seen
// through u_flat_matrix. Light.params.z is the map index, -1 for none;
// params.w is 1 for a cube map. Lookups happen at the vertex moved along
// its normal by u_normal_offset (model units), against self-shadowing.
uniform samplerCubeShadow u_cube_shadow[4];
uniform float u_cube_far[4];
uniform vec3 u_cube_origin[4];
uniform sampler2DShadow u_flat_shadow[4];
uniform mat4 u_flat_matrix[4];
uniform vec3 u_flat_origin[4];
uniform float u_flat_far[4];      // > 0: the map holds distance / far (spot)
uniform float u_normal_offset;
uniform float u_depth_bias;

float shadow(Light l, vec3 p, vec3 n)
{
    int index = int(l.params.z);
    if (index < 0)
        return 1.0;
    vec3 q = p + n * u_normal_offset;
    if (l.params.w != 0.0) {
        vec3 d = q - u_cube_origin[index];
        return texture(u_cube_shadow[index], vec4(d, length(d) / u_cube_far[index] - u_depth_bias));
    }
    vec4 clip = u_flat_matrix[index] * vec4(q, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    if (clip.w <= 0.0 || any(greaterThan(abs(ndc), vec3(1.0))))
        return 1.0;
    vec3 uvz = ndc * 0.5 + 0.5;
    if (u_flat_far[index] > 0.0)
        uvz.z = length(q - u_flat_origin[index]) / u_flat_far[index];
    // 3x3 taps of the hardware 2x2 compare filter: a soft 4x4 texel PCF.
    vec2 texel = 1.0 / vec2(textureSize(u_flat_shadow[index], 0));
    float sum = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            sum += texture(u_flat_shadow[index], vec3(uvz.xy + vec2(x, y) * texel, uvz.z - u_depth_bias));
    return sum / 9.0;
}

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
    const float A0 = 3.14159265358979323846, A1 = 2.0 * A0 / 3.0, A2 = A0 / 4.0;
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
