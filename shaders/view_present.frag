#version 430 core
// sam_view: the runtime's linear HDR render as sam_image_tonemap and
// sam_image_write_png show it (the same curves, exposure, backdrop and sRGB
// encoding), so a screenshot matches sam_render's PNG. Mode 1 shows the
// difference to a ground-truth image instead, both tonemapped alike.
in vec2 v_uv;
out vec4 o_color;
uniform sampler2D u_image;
uniform sampler2D u_truth;
uniform int u_mode;          // 0 picture, 1 |picture - truth| x u_gain
uniform int u_curve;         // 0 ACES (Narkowicz), 1 Reinhard
uniform float u_scale;       // 2^exposure
uniform float u_backdrop;
uniform float u_gain;

float curve(float x)
{
    x = max(x, 0.0);
    if (u_curve == 1)
        return x / (1.0 + x);
    return min((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 1.0);
}

vec3 display(vec4 hdr)
{
    float a = clamp(hdr.a, 0.0, 1.0);
    vec3 c = vec3(curve(hdr.r * u_scale), curve(hdr.g * u_scale), curve(hdr.b * u_scale));
    return a * c + (1.0 - a) * vec3(u_backdrop);
}

vec3 srgb(vec3 l)
{
    l = clamp(l, 0.0, 1.0);
    return mix(12.92 * l, 1.055 * pow(l, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), l));
}

void main()
{
    vec3 c = srgb(display(texture(u_image, v_uv)));
    if (u_mode == 1) {
        // The truth image is stored top row first, as images are.
        vec3 t = srgb(display(texture(u_truth, vec2(v_uv.x, 1.0 - v_uv.y))));
        c = clamp(abs(c - t) * u_gain, 0.0, 1.0);
    }
    o_color = vec4(c, 1.0);
}
