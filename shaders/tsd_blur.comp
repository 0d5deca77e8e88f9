#version 430 core
// Texture-space diffusion, step 2: one separable pass of d'Eon's 7-tap
// Gaussian (unit variance at unit tap spacing) with the tap spacing set to
// sqrt(extra variance) in mm, turned into texels by the stretch map. Each
// level blurs the previous one by the variance it lacks.
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = 0) readonly uniform image2D u_source;
layout(rgba32f, binding = 1) writeonly uniform image2D u_target;
layout(rgba32f, binding = 2) readonly uniform image2D u_stretch;

uniform ivec2 u_direction;
uniform float u_sigma_mm;

const float WEIGHT[7] = float[7](0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006);

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(u_source);
    if (p.x >= size.x || p.y >= size.y)
        return;
    vec4 centre = imageLoad(u_source, p);
    if (centre.a <= 0.0) {
        imageStore(u_target, p, centre);
        return;
    }
    vec2 mm_per_texel = imageLoad(u_stretch, p).xy;
    float mm = u_direction.x != 0 ? mm_per_texel.x : mm_per_texel.y;
    float step_texels = mm > 0.0 ? u_sigma_mm / mm : 0.0;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 7; ++k) {
        ivec2 q = clamp(p + ivec2(round(vec2(u_direction) * float(k - 3) * step_texels)), ivec2(0), size - 1);
        vec4 tap = imageLoad(u_source, q);
        // Off the chart (background texels): the centre stands in, so light
        // neither leaks into nor vanishes through the atlas's empty space.
        sum += WEIGHT[k] * (tap.a > 0.0 ? tap.rgb : centre.rgb);
    }
    imageStore(u_target, p, vec4(sum, 1.0));
}
