#version 430 core
in vec3 v_world;

uniform int u_distance;     // 1: write distance to u_light / u_far (all but directional maps)
uniform vec3 u_light;
uniform float u_far;

void main()
{
    if (u_distance != 0)
        gl_FragDepth = clamp(distance(v_world, u_light) / u_far, 0.0, 1.0);
    else
        gl_FragDepth = gl_FragCoord.z;
}
