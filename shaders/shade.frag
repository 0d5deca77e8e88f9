#version 430 core
// Diffuse radiance leaving the surface (Maisch and Ropinski eq. 5 with the
// front/back split of eq. 6-7): rho_dt(N.V) / pi * (R_front + T) * albedo,
// where R_front = L_d times the profile's total diffuse reflectance stands
// for the front-side integral until a surface-diffusion pass blurs it, and
// T is the SAM translucency. Linear HDR out; tonemapping happens on output.
in vec3 v_normal;
in vec3 v_to_eye;
in vec3 v_irradiance;
in vec3 v_translucency;

layout(std430, binding = 9) readonly buffer RhoDt { float rho_dt_table[]; };

uniform vec3 u_albedo;
uniform vec3 u_total_reflectance;
uniform int u_front;               // 0: translucency only
uniform int u_rho_size;
uniform float u_roughness_coord;
uniform float u_specular_k;

out vec4 o_color;

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

void main()
{
    vec3 n = normalize(v_normal), v = normalize(v_to_eye);
    if (!gl_FrontFacing)
        n = -n;
    vec3 entering = v_translucency;
    if (u_front != 0)
        entering += v_irradiance * u_total_reflectance;
    o_color = vec4(rho_dt_view(dot(n, v)) / 3.14159265358979 * entering * u_albedo, 1.0);
}
