#version 430 core
// L_d at every vertex (Maisch and Ropinski eq. 4): the light entering the
// surface, each light's irradiance times rho_dt(N.L) (d'Eon Sec. 6), plus
// the environment's SH-9 irradiance times its cosine-weighted mean rho_dt.
#include "sam_bindings.h"
#include "lights.glsl"
#include "shadows.glsl"
#include "surface.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_NORMALS) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = SAM_B_IRRADIANCE) writeonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = SAM_B_LIGHTS) readonly buffer Lights { Light lights[]; };

uniform uint u_vertex_count;
uniform uint u_light_count;

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
    sum += environment_irradiance(n);
    irradiance[v] = vec4(sum, 1.0);
}
