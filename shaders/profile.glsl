#version 430 core
// The material's diffusion profile R_d(r), r in mm, RGB in mm^-2: the same
// formulas as sam_profile_eval (sam_core/src/sam_profile.c), fed from
// sam_profile by the runtime.

#include "constants.glsl"

uniform int u_profile_kind;       // 0: sum of Gaussians, 1: dipole
uniform int u_gaussian_count;
uniform vec4 u_gaussians[32];     // rgb: weights, w: variance in mm^2
uniform vec3 u_dipole_alpha;      // sigma_s' / sigma_t'
uniform vec3 u_dipole_sigma_tr;   // mm^-1
uniform vec3 u_dipole_zr;         // mm
uniform vec3 u_dipole_zv;         // mm

vec3 dipole_pole(vec3 z, vec3 sigma, float r)
{
    vec3 d = sqrt(r * r + z * z);
    return z * (1.0 + sigma * d) * exp(-sigma * d) / (d * d * d);
}

vec3 profile_rd(float r)
{
    if (u_profile_kind == 1)
        return u_dipole_alpha / (4.0 * PI) *
               (dipole_pole(u_dipole_zr, u_dipole_sigma_tr, r) + dipole_pole(u_dipole_zv, u_dipole_sigma_tr, r));
    vec3 sum = vec3(0.0);
    for (int i = 0; i < u_gaussian_count; ++i) {
        float v = u_gaussians[i].w;
        sum += u_gaussians[i].rgb * (exp(-r * r / (2.0 * v)) / (2.0 * PI * v));
    }
    return sum;
}
