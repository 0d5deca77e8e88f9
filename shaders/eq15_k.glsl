// K of a stored sample by eq. 15, K = K' F'_b R_d(|v_b - v|), at the pose
// the bound buffers hold: the rest-K pass writes it once (rest_k.comp) and
// the evaluated rest pass sums it every frame (translucency.comp), from
// this one expression so that the two agree to the bit.
//
// The includer declares, before including this: profile.glsl, `positions`,
// `fan_area`, `nodes` (Node with centroid_area), u_vertex_count and
// u_mm_per_unit. `index` is a vertex, or vertex_count + node; p is the
// receiving vertex's position.
vec3 eq15_k(uint index, vec3 kprime, vec3 p)
{
    vec4 q = index >= u_vertex_count ? nodes[index - u_vertex_count].centroid_area
                                     : vec4(positions[index].xyz, fan_area[index]);
    return kprime * q.w * profile_rd(u_mm_per_unit * distance(q.xyz, p));
}
