/*
 * sam_vec3: the few float 3-vector operations the tools share (staging a
 * scene, placing its lights). Header only; arrays of 3 floats.
 */
#ifndef SAM_VEC3_H
#define SAM_VEC3_H

#include <math.h>

static inline float sam_vec3_dot(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* out = a x b; out may not alias a or b. */
static inline void sam_vec3_cross(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Scales v to unit length in place; a zero vector stays zero. */
static inline void sam_vec3_normalize(float v[3])
{
    const float len = sqrtf(sam_vec3_dot(v, v));
    if (len > 0)
        for (int c = 0; c < 3; ++c)
            v[c] /= len;
}

#endif
