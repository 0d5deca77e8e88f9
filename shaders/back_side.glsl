// Eq. 13-14 at the pose for vertex i against receiver p with normal n:
// whether a stored vertex sample still counts (sample_on_back_side), and
// whether the walk may adopt vertex i (candidate_on_back_side).
//
// The builder stores only vertices that pass both tests at rest, in its own
// float normals and positions (a vertex that fails them but whose fan is
// partly behind hands its light to the row's other entries). Where a sample
// lies on the receiver's tangent plane or faces square to it, as on a side
// wall square to a slab's or an ear's face, the dot products are 0 but for
// rounding, and the runtime's normals and positions, equal to the
// builder's but for rounding, put them on the other side: an engine's pose
// equal to rest dropped such samples where the rest program kept them, and
// T moved by 1.7% of its largest on a skin ear (tests/test_gl_engine.c); a
// pose equal to rest but for rounding adopted different vertices in two
// runtimes (T at one receiver 0.0095 against 0.0020). So a stored sample
// counts until it is past either plane by more than float noise, and a
// candidate must be inside both by more than that: a vertex on the edge is
// neither adopted nor dropped by rounding.
//
// The includer declares, before including this: `positions`, `normals`.

// Float noise of a unit dot product, as an angle (radians).
#define BACK_SIDE_NOISE 1.0e-5

bool sample_on_back_side(uint i, vec3 p, vec3 n)
{
    vec3 d = positions[i].xyz - p;
    return dot(d, n) < BACK_SIDE_NOISE * length(d) && dot(normals[i].xyz, n) < BACK_SIDE_NOISE;
}

bool candidate_on_back_side(uint i, vec3 p, vec3 n)
{
    vec3 d = positions[i].xyz - p;
    return dot(d, n) < -BACK_SIDE_NOISE * length(d) && dot(normals[i].xyz, n) < -BACK_SIDE_NOISE;
}
