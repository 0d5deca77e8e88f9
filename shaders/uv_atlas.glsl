// Where a UV lies in the texture-space atlas: the mesh's layout moved into
// [0,1]^2 when it reaches past it (sam_uv_fit_atlas), itself otherwise.
// The albedo map is read at the mesh's own UV.
uniform vec3 u_uv_atlas; // scale, offset u, offset v

vec2 atlas_uv(vec2 uv)
{
    return uv * u_uv_atlas.x + u_uv_atlas.yz;
}
