#version 430 core
// Shadow maps: area lights (from the area's centroid) and point lights
// close to the object get a cube map of distance / far; spot and
// directional lights and the other point lights a 2D map seen through
// u_flat_matrix (sam_runtime_set_lights chooses). Light.params.z is the map
// index, -1 for none; params.w is 1 for a cube map. Lookups happen at the
// vertex moved along its normal and towards the light by a few of the
// map's texels there, against self-shadowing (SHADOW_SLOPE_TEXELS).
uniform samplerCubeShadow u_cube_shadow[4];
uniform float u_cube_far[4];
uniform vec3 u_cube_origin[4];
uniform sampler2DShadow u_flat_shadow[4];
uniform mat4 u_flat_matrix[4];
uniform vec3 u_flat_origin[4];
uniform float u_flat_far[4];      // > 0: the map holds distance / far (spot, point)
uniform float u_flat_texel[4];    // far > 0: a texel's width per unit of distance; else in model units
uniform float u_flat_range[4];    // directional maps: model units per unit of stored depth
// The lookup's offsets, in texels of the map at the vertex (shadow_texel):
// along the normal SHADOW_SLOPE_TEXELS x sin(angle to the light) plus
// SHADOW_NORMAL_TEXELS, and towards the light SHADOW_DEPTH_TEXELS. The
// PCF's taps reach 2 texels across the map, where a plane tilted by theta
// from the light lies 2 w tan(theta) nearer the light; moving the lookup
// a along the normal puts it a / cos(theta) nearer than the plane below
// it, so a = 2 w sin(theta) keeps a plane out of its own shadow. The
// constant parts are for the facets around a vertex, which a smooth normal
// does not follow. Offsets tied to the object's size instead let light
// through any occluder nearer than they reach (docs/runtime.md).
#define SHADOW_SLOPE_TEXELS 2.0
#define SHADOW_NORMAL_TEXELS 0.5
#define SHADOW_DEPTH_TEXELS 0.5

// A face texel of cube map `index` spans 2 m / size across the direction
// d from its origin, m = d's major component.
float cube_texel(int index, vec3 d)
{
    return 2.0 * max(abs(d.x), max(abs(d.y), abs(d.z))) / float(textureSize(u_cube_shadow[index], 0).x);
}

// The width of a texel of light l's shadow map at p, in model units; 0
// without a map.
float shadow_texel(Light l, vec3 p)
{
    int index = int(l.params.z);
    if (index < 0)
        return 0.0;
    if (l.params.w != 0.0)
        return cube_texel(index, p - u_cube_origin[index]);
    return u_flat_far[index] > 0.0 ? u_flat_texel[index] * distance(p, u_flat_origin[index]) : u_flat_texel[index];
}

// Needs lights.glsl (Light).
float shadow(Light l, vec3 p, vec3 n)
{
    int index = int(l.params.z);
    if (index < 0)
        return 1.0;
    float w = shadow_texel(l, p);
    float c = clamp(dot(n, light_direction(l, p)), -1.0, 1.0);
    vec3 q = p + n * (w * (SHADOW_SLOPE_TEXELS * sqrt(1.0 - c * c) + SHADOW_NORMAL_TEXELS));
    if (l.params.w != 0.0) {
        // 3x3 taps of the hardware 2x2 compare filter, a texel apart in the
        // plane across the direction: the 2D maps' soft 4x4 texel PCF. One
        // tap drew a cast shadow's edge as a staircase of texels, 10 to 20
        // pixels a step on a head's ear at 1080p.
        vec3 d = q - u_cube_origin[index];
        float len = length(d), ref = (len - SHADOW_DEPTH_TEXELS * w) / u_cube_far[index];
        float texel = cube_texel(index, d);
        vec3 t = normalize(cross(d, abs(d.z) < 0.9 * len ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0)));
        vec3 b = cross(d / len, t);
        float sum = 0.0;
        for (int y = -1; y <= 1; ++y)
            for (int x = -1; x <= 1; ++x)
                sum += texture(u_cube_shadow[index], vec4(d + (float(x) * t + float(y) * b) * texel, ref));
        return sum / 9.0;
    }
    vec4 clip = u_flat_matrix[index] * vec4(q, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    if (clip.w <= 0.0 || any(greaterThan(abs(ndc), vec3(1.0))))
        return 1.0;
    vec3 uvz = ndc * 0.5 + 0.5;
    if (u_flat_far[index] > 0.0)
        uvz.z = (length(q - u_flat_origin[index]) - SHADOW_DEPTH_TEXELS * w) / u_flat_far[index];
    else
        uvz.z -= SHADOW_DEPTH_TEXELS * w / u_flat_range[index];
    // 3x3 taps of the hardware 2x2 compare filter: a soft 4x4 texel PCF.
    vec2 texel = 1.0 / vec2(textureSize(u_flat_shadow[index], 0));
    float sum = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            sum += texture(u_flat_shadow[index], vec3(uvz.xy + vec2(x, y) * texel, uvz.z));
    return sum / 9.0;
}
