/*
 * sam_preint: the lookup tables of pre-integrated skin shading (Penner and
 * Borshukov, GPU Pro 2), built from any sam_profile.
 *
 * Diffuse falloff (Penner eq. 1.1): a ring of radius r (mm) lit from one
 * direction, blurred by the profile along the ring:
 *   D(theta, r) = int_{-pi}^{pi} max(cos(theta + x), 0) R(2 r |sin(x/2)|) dx
 *               / int_{-pi}^{pi} R(2 r |sin(x/2)|) dx
 * per RGB channel (the paper's denominator drops the r; with it, D is a
 * normalised blur and integrates to the clamped cosine's 2 over theta).
 * Table: rows curvature k = 1/r in (0, max_curvature] at texel centres
 * k_j = (j + 0.5) / rows * max_curvature; columns N.L at texel centres
 * -1 + 2 (i + 0.5) / cols; out[(j * cols + i) * 3 + c]. Indexing by N.L
 * keeps the acos out of the shader.
 *
 * Shadow penumbra: a shadow value s in [0, 1] from a box-filtered shadow map
 * lies at position s across a linear penumbra; it is re-mapped to a
 * penumbra a quarter as wide, P'(x) = clamp((x - 0.5) * 4 + 0.5, 0, 1),
 * blurred by the profile's 1D marginal over a penumbra w mm wide:
 *   P_S(s, w) = int P'(s + x / w) M(x) dx / int M(x) dx
 * (x in mm; M the marginal of R). Table: rows w in (0, max_width] mm at
 * texel centres, columns s at texel centres (i + 0.5) / cols, RGB.
 *
 * Pure functions of their arguments; no global state.
 */
#ifndef SAM_PREINT_H
#define SAM_PREINT_H

#include "sam/sam_profile.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SAM_PREINT_DEFAULT_SIZE 64

/* The diffuse falloff D for one angle (cos theta = n_dot_l in [-1, 1]) and
 * curvature (1/mm, > 0) into rgb. */
void sam_preint_diffuse(const sam_profile *profile, float n_dot_l, float curvature, float rgb[3]);

/* The diffuse table, cols x rows RGB floats (layout above). Sizes 2..1024,
 * max_curvature > 0 and finite. Errors: SAM_ERR_INVALID_ARGUMENT naming the
 * value; `out` untouched then. */
sam_status sam_preint_diffuse_table(const sam_profile *profile, uint32_t cols, uint32_t rows, float max_curvature,
                                    float *out, sam_error *err);

/* The penumbra lookup P_S for one shadow value s in [0, 1] and penumbra
 * width (mm, > 0) into rgb. */
void sam_preint_penumbra(const sam_profile *profile, float s, float width_mm, float rgb[3]);

/* The penumbra table, cols x rows RGB floats (layout above). */
sam_status sam_preint_penumbra_table(const sam_profile *profile, uint32_t cols, uint32_t rows, float max_width_mm,
                                     float *out, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
