// The surface's albedo: the view's colour times the vertex colour (white
// without one) times the albedo map at the UV.
uniform vec3 u_albedo;
uniform int u_has_albedo_map;
uniform sampler2D u_albedo_map;

vec3 surface_albedo(vec2 uv, vec3 vertex_color)
{
    vec3 albedo = u_albedo * vertex_color;
    return u_has_albedo_map != 0 ? albedo * texture(u_albedo_map, uv).rgb : albedo;
}
