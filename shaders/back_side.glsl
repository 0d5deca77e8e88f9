// Whether a stored vertex sample i is still on receiver p's back side at
// the pose (eq. 13-14, n the receiver's normal), asked as the builder asked
// it when it chose the sample: of the vertex for a flat map, whose search
// tests vertices, and of the sample's reduced fan for a cut map
// (sam_build_fan_side). The fan tests are linear in a fan point and its
// interpolated normal, so a fan passes when some corner (the vertex, an
// edge midpoint, a triangle's centroid) is behind the receiver's tangent
// plane and some corner faces away from it. Asked of the vertex alone, the
// test failed at rest for cut samples the builder keeps because their
// fans' rims pass it: an engine's pose a float's width from rest dropped
// them, and T moved by 1.7% of its largest on a skin ear
// (tests/test_gl_engine.c). Asked of the fan in a flat map, it kept
// samples the pose had taken off the back side: a twisted ear's walked T
// erred by 0.141 against a fresh build, 0.086 with the vertex test
// (tests/test_gl_walk.c). The ring is walked only where the vertex itself
// does not pass.
//
// The includer declares, before including this: `positions`, `normals`,
// `adj_offsets` and `adjacency` (the .sam's rings, consecutive entries
// spanning one fan triangle).
bool vertex_on_back_side(uint i, vec3 p, vec3 n)
{
    return dot(positions[i].xyz - p, n) < 0.0 && dot(normals[i].xyz, n) < 0.0;
}

bool fan_on_back_side(uint i, vec3 p, vec3 n)
{
    float d0 = dot(positions[i].xyz - p, n), c0 = dot(normals[i].xyz, n);
    bool d_some = d0 < 0.0, c_some = c0 < 0.0;
    if (d_some && c_some)
        return true;
    uint begin = adj_offsets[i], end = adj_offsets[i + 1u];
    float d_prev = 0.0, c_prev = 0.0;
    for (uint k = begin; k < end; ++k) {
        uint a = adjacency[k];
        float d = dot(positions[a].xyz - p, n), c = dot(normals[a].xyz, n);
        // The edge midpoint's values are (x0 + x) / 2, the centroid's
        // (x0 + x_prev + x) / 3: only their signs are asked.
        d_some = d_some || d0 + d < 0.0;
        c_some = c_some || c0 + c < 0.0;
        if (k > begin) {
            d_some = d_some || d0 + d_prev + d < 0.0;
            c_some = c_some || c0 + c_prev + c < 0.0;
        }
        if (d_some && c_some)
            return true;
        d_prev = d, c_prev = c;
    }
    return false;
}

// `cut`: the map is a cut map (it holds tree nodes).
bool sample_on_back_side(uint i, vec3 p, vec3 n, bool cut)
{
    return cut ? fan_on_back_side(i, p, n) : vertex_on_back_side(i, p, n);
}
