#include "sam/sam_bounds.h"

#include <math.h>

/* fminf and fmaxf are calls into libm unless NaNs and signed zeros may be
 * ignored, and this runs for every node test of the builder and the ground
 * truth; its inputs are finite. */
static inline float min2(float a, float b)
{
    return a < b ? a : b;
}

static inline float max2(float a, float b)
{
    return a > b ? a : b;
}

void sam_bounds_classify(const float lo[3], const float hi[3], const float nlo[3], const float nhi[3],
                         const float p[3], const float n[3], sam_bounds_range *out)
{
    float near2 = 0, far2 = 0, dn_lo = 0, dn_hi = 0, nn_lo = 0, nn_hi = 0;
    for (int k = 0; k < 3; ++k) {
        float a = lo[k] - p[k], b = hi[k] - p[k];
        float d = a > 0 ? a : b < 0 ? -b : 0.0f, e = max2(fabsf(a), fabsf(b));
        near2 += d * d;
        far2 += e * e;
        dn_lo += min2(a * n[k], b * n[k]);
        dn_hi += max2(a * n[k], b * n[k]);
        nn_lo += min2(nlo[k] * n[k], nhi[k] * n[k]);
        nn_hi += max2(nlo[k] * n[k], nhi[k] * n[k]);
    }
    *out = (sam_bounds_range){near2, far2, dn_lo, dn_hi, nn_lo, nn_hi};
}
