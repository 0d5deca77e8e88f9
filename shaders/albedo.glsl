// The surface's albedo: the view's colour times the vertex colour (white
// without one) times the albedo map at the UV: one map (u_has_albedo_map
// 1), or (2) the layer of the array its triangle reads, none for
// 0xFFFFFFFF. Draws take the whole mesh in one call, so gl_PrimitiveID is
// the triangle's index.
uniform vec3 u_albedo;
uniform int u_has_albedo_map;
uniform sampler2D u_albedo_map;
uniform sampler2DArray u_albedo_array;
uniform usamplerBuffer u_triangle_map;

vec3 surface_albedo(vec2 uv, vec3 vertex_color)
{
    vec3 albedo = u_albedo * vertex_color;
    if (u_has_albedo_map == 2) {
        uint layer = texelFetch(u_triangle_map, gl_PrimitiveID).r;
        // Sampled on every triangle: implicit derivatives want the whole
        // quad of pixels to sample, across a boundary between maps too.
        vec3 texel = texture(u_albedo_array, vec3(uv, float(layer == 0xFFFFFFFFu ? 0u : layer))).rgb;
        return layer == 0xFFFFFFFFu ? albedo : albedo * texel;
    }
    return u_has_albedo_map != 0 ? albedo * texture(u_albedo_map, uv).rgb : albedo;
}
