#include "sam/sam_preint.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#define PI_D 3.14159265358979323846
/* Midpoint steps along the ring and across the penumbra: the integrands
 * are smooth except for the clamp, whose kink costs O(h^2). */
#define RING_STEPS 2048
#define STRIP_STEPS 2048

void sam_preint_diffuse(const sam_profile *profile, float n_dot_l, float curvature, float rgb[3])
{
    double c = n_dot_l < -1 ? -1 : n_dot_l > 1 ? 1 : n_dot_l;
    double theta = acos(c), r = 1.0 / curvature;
    double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
    for (int i = 0; i < RING_STEPS; ++i) {
        double x = -PI_D + (i + 0.5) * (2 * PI_D / RING_STEPS);
        float rd[3];
        sam_profile_eval(profile, (float)(2 * r * fabs(sin(0.5 * x))), rd);
        double light = cos(theta + x);
        for (int k = 0; k < 3; ++k) {
            den[k] += rd[k];
            if (light > 0)
                num[k] += light * rd[k];
        }
    }
    for (int k = 0; k < 3; ++k)
        rgb[k] = den[k] > 0 ? (float)(num[k] / den[k]) : (float)(c > 0 ? c : 0);
}

static sam_status check(const sam_profile *profile, uint32_t cols, uint32_t rows, float max, const char *what,
                        float *out, sam_error *err)
{
    if (!profile || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "pre-integrated %s table: NULL argument", what);
    if (cols < 2 || rows < 2 || cols > 1024 || rows > 1024)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "pre-integrated %s table: size %ux%u, expected 2..1024 each",
                        what, cols, rows);
    if (!(max > 0) || !isfinite(max))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "pre-integrated %s table: maximum %g must be finite and > 0",
                        what, max);
    return SAM_OK;
}

sam_status sam_preint_diffuse_table(const sam_profile *profile, uint32_t cols, uint32_t rows, float max_curvature,
                                    float *out, sam_error *err)
{
    sam_status st = check(profile, cols, rows, max_curvature, "diffuse", out, err);
    if (st != SAM_OK)
        return st;
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < cols; ++i)
            sam_preint_diffuse(profile, (float)(-1.0 + 2.0 * (i + 0.5) / cols),
                               (float)((j + 0.5) / rows * max_curvature), out + 3 * ((size_t)j * cols + i));
    return SAM_OK;
}

/* The narrower penumbra P' at position x (penumbra units). */
static double narrow(double x)
{
    double v = (x - 0.5) * 4.0 + 0.5;
    return v < 0 ? 0 : v > 1 ? 1 : v;
}

/* The marginal's one-sided mass on each of STRIP_STEPS / 2 cells of width
 * h out to the radius holding all but 1e-4 of the energy: computed once
 * per table, since only P' depends on s and w. */
typedef struct strip {
    double h;
    double mass[STRIP_STEPS / 2][3];
} strip;

static void make_strip(const sam_profile *profile, strip *st)
{
    st->h = 2.0 * sam_profile_radius(profile, 1e-4f) / STRIP_STEPS;
    float inner[3], outer[3];
    sam_profile_marginal_mass(profile, 0.0f, inner);
    for (int i = 0; i < STRIP_STEPS / 2; ++i) {
        sam_profile_marginal_mass(profile, (float)((i + 1) * st->h), outer);
        for (int k = 0; k < 3; ++k)
            st->mass[i][k] = 0.5 * ((double)outer[k] - inner[k]);
        memcpy(inner, outer, sizeof inner);
    }
}

static void penumbra_from_strip(const strip *st, float s, float width_mm, float rgb[3])
{
    double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
    for (int i = 0; i < STRIP_STEPS / 2; ++i) {
        double xm = (i + 0.5) * st->h;
        double p = narrow(s + xm / width_mm) + narrow(s - xm / width_mm);
        for (int k = 0; k < 3; ++k) {
            num[k] += st->mass[i][k] * p;
            den[k] += 2 * st->mass[i][k];
        }
    }
    for (int k = 0; k < 3; ++k)
        rgb[k] = den[k] > 0 ? (float)(num[k] / den[k]) : (float)narrow(s);
}

void sam_preint_penumbra(const sam_profile *profile, float s, float width_mm, float rgb[3])
{
    static_assert(sizeof(strip) < (1 << 20), "strip fits the stack");
    strip st;
    make_strip(profile, &st);
    penumbra_from_strip(&st, s, width_mm, rgb);
}

sam_status sam_preint_penumbra_table(const sam_profile *profile, uint32_t cols, uint32_t rows, float max_width_mm,
                                     float *out, sam_error *err)
{
    sam_status status = check(profile, cols, rows, max_width_mm, "penumbra", out, err);
    if (status != SAM_OK)
        return status;
    strip st;
    make_strip(profile, &st);
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < cols; ++i)
            penumbra_from_strip(&st, (float)((i + 0.5) / cols), (float)((j + 0.5) / rows * max_width_mm),
                                out + 3 * ((size_t)j * cols + i));
    return SAM_OK;
}
