// K of a stored sample carried from the rest pose to the current one. Eq. 15
// carries it with the point estimate F'_i R_d(|v_i - v_o|), which holds only
// while the fans keep their shape and their angle to each other (Sec. 3.5).
// Where fans are about as wide as the distance between them, a shear tilts
// them against the line between their centres: the centres' distance
// changes much more than the fans' distances do, and R_d at the centres
// overreacts. On a 2 mm slab under a wave (tests/test_gl_walk.c), T from
// the rest samples with that K was 0.118 (relative RMSE) off T from their
// Monte Carlo K at the pose, worse than with the rest K (0.072). K' keeps
// its rest meaning (rest K = K' times the rest point estimate) and K
// follows the ratio of a quadrature of eq. 11 at the pose to the same
// quadrature at rest; whatever the quadrature misses at rest, K' still
// corrects, as long as that changes slowly with the pose. The quadrature is
// the mean of two one-sided rules, i's fan against v_o and o's fan
// (averaged over its area) against v_i, each fan by one point per triangle
// at the centroid of the triangle's reduced part (the quadrilateral vertex /
// edge midpoint / centroid / edge midpoint), weighted by that part's area.
// Against Monte Carlo K of the same samples at the pose, T's relative RMSE
// was 0.062 on the wave and 0.085 on a twisted ear (eq. 15: 0.118, 0.122);
// every point of one fan against every point of the other did a little
// better (0.054, 0.077) at three times the cost, and either one-sided rule
// alone was biased on a bend.
//
// The includer declares, before including this: profile.glsl, `positions`
// (the pose), `rest_positions`, `adj_offsets` and `adjacency` (the .sam's
// rings, consecutive entries spanning one fan triangle), u_mm_per_unit.

vec3 fan_position(bool rest, uint t)
{
    return rest ? rest_positions[t].xyz : positions[t].xyz;
}

// The integral over t's reduced fan of R_d(|x - c|) (c in mm) by the rule
// above in rgb, and t's reduced fan area F'_t (eq. 16, mm^2) in w.
vec4 fan_integral(bool rest, uint t, vec3 c)
{
    vec3 v = fan_position(rest, t);
    vec4 sum = vec4(0.0);
    // Both offsets read into locals first: read where they were used,
    // adj_offsets[t + 1u] came back 0 on llvmpipe for some vertices (their
    // fans then had no triangle); why was not found.
    uint begin = adj_offsets[t], end = adj_offsets[t + 1u];
    for (uint k = begin + 1u; k < end; ++k) {
        vec3 a = fan_position(rest, adjacency[k - 1u]) - v, b = fan_position(rest, adjacency[k]) - v;
        // Centroid of the triangles (v, a/2, (a+b)/3) and (v, (a+b)/3, b/2),
        // which have equal areas.
        vec3 x = u_mm_per_unit * (v + (7.0 / 36.0) * (a + b));
        float w = length(cross(a, b)) * (u_mm_per_unit * u_mm_per_unit / 6.0);
        sum += w * vec4(profile_rd(distance(x, c)), 1.0);
    }
    return sum;
}

// The quadrature of eq. 11 between the fans of o and i in one pose in rgb,
// and F'_i in that pose in w.
vec4 fan_quadrature(bool rest, uint o, uint i)
{
    vec4 from_i = fan_integral(rest, i, u_mm_per_unit * fan_position(rest, o));
    vec4 from_o = fan_integral(rest, o, u_mm_per_unit * fan_position(rest, i));
    vec3 q = 0.5 * (from_i.rgb + (from_o.w > 0.0 ? from_o.rgb * (from_i.w / from_o.w) : vec3(0.0)));
    return vec4(q, from_i.w);
}

// K at the pose of sample i of vertex o whose K' (eq. 15) holds at rest. A
// channel whose rest quadrature underflowed to 0 carries no light at rest
// either, and gets none.
vec3 posed_form_factor(uint o, uint i, vec3 kprime)
{
    vec4 q_rest = fan_quadrature(true, o, i);
    vec3 q_pose = fan_quadrature(false, o, i).rgb;
    vec3 at_rest =
        kprime * q_rest.w * profile_rd(u_mm_per_unit * distance(rest_positions[i].xyz, rest_positions[o].xyz));
    return mix(vec3(0.0), at_rest * q_pose / q_rest.rgb, greaterThan(q_rest.rgb, vec3(0.0)));
}
