/*
 * sam_brdf: the Kelemen/Szirmay-Kalos specular BRDF that d'Eon & Luebke use
 * for skin, and the diffuse transmittance rho_dt derived from it.
 *
 * BRDF (Kelemen & Szirmay-Kalos 2001, as in d'Eon & Luebke 2007, Sec. 6, and
 * GPU Gems 3 ch. 14, "KS_Skin_Specular"). With unit vectors n (normal),
 * l (to the light), v (to the eye), the unnormalised half vector h = l + v
 * and H = h / |h|:
 *
 *   f_r(l, v) = D(n.H) * F(v.H) / (h.h)          (h.h = |l + v|^2 = 4 (v.H)^2)
 *   D(c)      = exp(-(1 - c^2) / (c^2 m^2)) / (pi m^2 c^4)      Beckmann, m = roughness
 *   F(c)      = F0 + (1 - F0) (1 - c)^5                          Schlick
 *
 * and f_r = 0 unless n.l > 0 and n.v > 0. D is normalised so that the
 * projected microfacet area integrates to one: int D(n.H) (n.H) dH = 1. This
 * is the microfacet BRDF D F G / (4 (n.l)(n.v)) with Kelemen's geometry
 * approximation G / ((n.l)(n.v)) = 1 / (v.H)^2. It is symmetric in l and v.
 *
 * d'Eon's shader uses P_H = pi * D (his PHBeckmann has no 1/pi) and scales by
 * a specular brightness rho_s (0.18 on average for skin, after Weyrich et
 * al.), so his specular term is (pi rho_s) f_r here. This module has no
 * brightness factor (it is 1): a renderer that draws the specular lobe as
 * k * f_r (k = pi * rho_s in d'Eon's units, k <= 1 to conserve energy) gets
 *
 *   rho_dt(k) = 1 - k * (1 - rho_dt)      (exact: the albedo is linear in k),
 *
 * which is the "1 - rho_s * tex2D(rhodTex, (N.L, m))" of GPU Gems 3 with
 * d'Eon's table equal to pi * (1 - rho_dt) of ours.
 *
 * rho_dt (SAM paper eq. 3, d'Eon's "Fresnel term rho_dt"): the fraction of
 * light arriving from a fixed direction l that is not reflected by the
 * specular lobe, 1 - A(l) with the directional albedo
 *
 *   A(l) = int_{n.v > 0} f_r(l, v) (n.v) dv.
 *
 * The paper integrates over the other argument (omega_i with omega_o fixed);
 * by reciprocity f_r(l, v) = f_r(v, l) the two are the same function of the
 * fixed direction's cosine. The albedo stays below 1 for every F0 in [0, 1]
 * (checked over n.l in [0, 1], m in [0.001, 2]; with F0 = 1 it reaches 1 in
 * the grazing limit), so rho_dt is in [0, 1]. F0 = 0 does not switch the
 * lobe off: Schlick's (1 - v.H)^5 remains, so rho_dt < 1 at grazing even
 * then (above 0.9995 for n.l >= 0.9). Skin (F0 = 0.028, m = 0.3):
 * rho_dt = 0.9745, 0.9529, 0.7572, 0.4941 at n.l = 1, 0.5, 0.1, 0.
 *
 * Integration (see sam_brdf.c): a change of variables to the half vector,
 * sampled by the Beckmann inverse CDF, leaves a bounded integrand whose
 * horizon cut is solved in closed form; a Gauss-Legendre product rule of
 * order n (n azimuths on each side of the plane perpendicular to incidence,
 * n radial nodes) then gives rho_dt to 4e-5 for any n.l in [0, 1] and m in
 * [1/64, 1] at the default order 64, and to 1e-5 for n.l >= 0.01.
 *
 * Every function here is pure and thread-safe; nothing allocates.
 */
#ifndef SAM_BRDF_H
#define SAM_BRDF_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Normal-incidence reflectance of skin (d'Eon & Luebke, GPU Gems 3 ch. 14:
 * fresnelReflectance(H, V, 0.028), i.e. a refractive index of about 1.4). */
#define SAM_BRDF_SKIN_F0 0.028f

/* Default rho_dt table: 32 N.L samples x 32 roughness samples over
 * (0, SAM_BRDF_ROUGHNESS_MAX] (d'Eon stores it in "a low resolution 2D
 * texture"; rho_dt is smooth, see sam_brdf_rho_dt_table_lookup). */
#define SAM_BRDF_RHO_DT_TABLE_SIZE 32u
#define SAM_BRDF_ROUGHNESS_MAX 1.0f
/* Largest table size per dimension: the cost is 8192 BRDF evaluations per
 * entry at the default order (the default table takes about 0.2 s). */
#define SAM_BRDF_MAX_TABLE_SIZE 256u

/* Quadrature order of sam_brdf_rho_dt and the table (2 * 64^2 nodes), and
 * the largest order sam_brdf_ks_albedo accepts. */
#define SAM_BRDF_QUADRATURE_ORDER 64u
#define SAM_BRDF_MAX_QUADRATURE_ORDER 256u

/* Normalised Beckmann distribution D(n.H) for roughness m (the RMS slope).
 * Returns 0 for n_dot_h <= 0; NaN for a non-finite argument or m <= 0. */
float sam_brdf_beckmann(float n_dot_h, float roughness);

/* Schlick's Fresnel reflectance F0 + (1 - F0)(1 - c)^5 for c = v.H, clamped
 * to [0, 1] first. NaN for a non-finite argument or F0 outside [0, 1]. */
float sam_brdf_fresnel_schlick(float v_dot_h, float f0);

/* f_r in sr^-1 from the cosines of one configuration: n.l, n.v, n.H and
 * v.H (= l.H), H the normalised half vector. Returns 0 when n.l, n.v, n.H or
 * v.H is <= 0 (below the horizon, or no half vector). The caller keeps the
 * four cosines consistent; the function does not check that they come from
 * real directions. NaN for a non-finite argument, m <= 0 or F0 outside
 * [0, 1]. */
float sam_brdf_ks_eval(float n_dot_l, float n_dot_v, float n_dot_h, float v_dot_h,
                       float roughness, float f0);

/* f_r in sr^-1 from unit vectors n, l (to the light) and v (to the eye),
 * three floats each, none NULL; the half vector is formed here. Returns 0
 * when n.l <= 0, n.v <= 0 or l = -v. NaN as sam_brdf_ks_eval. */
float sam_brdf_ks_eval_dir(const float n[3], const float l[3], const float v[3], float roughness,
                           float f0);

/* Directional albedo A = int f_r(l, v) (n.v) dv of the lobe for light at
 * incidence cosine n.l (clamped to [0, 1]), by the product Gauss-Legendre
 * rule of order `order` (1..SAM_BRDF_MAX_QUADRATURE_ORDER; 2 * order^2 BRDF
 * evaluations). NaN for a non-finite argument, m <= 0, F0 outside [0, 1] or
 * an order out of range. */
double sam_brdf_ks_albedo(float n_dot_l, float roughness, float f0, uint32_t order);

/* rho_dt = 1 - A at the default order, in [0, 1]; n.l is clamped to [0, 1]
 * (n.l = 0 gives the grazing limit). NaN as sam_brdf_ks_albedo. */
float sam_brdf_rho_dt(float n_dot_l, float roughness, float f0);

/* Fills `out` (size_ndotl * size_roughness floats, caller-owned) with
 *
 *   out[j * size_ndotl + i] = sam_brdf_rho_dt((i + 0.5) / size_ndotl,
 *                                             (j + 0.5) / size_roughness * roughness_max, f0)
 *
 * i.e. rows by roughness, N.L varying fastest, every sample at a texel
 * centre. Upload it as a size_ndotl x size_roughness (width x height)
 * single-channel float texture (GL_R32F, GL_RED, GL_FLOAT, unpack alignment
 * 4) with GL_LINEAR filtering and GL_CLAMP_TO_EDGE wrapping, and sample it at
 * (N.L, m / roughness_max): the texel centres then sit exactly on the
 * samples, and N.L below 0.5 / size_ndotl reads the first column.
 * sam_brdf_rho_dt_table_lookup does the same filtering on the CPU.
 * Errors: SAM_ERR_INVALID_ARGUMENT (out NULL; a size outside
 * 2..SAM_BRDF_MAX_TABLE_SIZE; roughness_max not finite or <= 0; F0 not in
 * [0, 1]), naming the value; `out` is untouched then. */
sam_status sam_brdf_rho_dt_table(uint32_t size_ndotl, uint32_t size_roughness, float f0,
                                 float roughness_max, float *out, sam_error *err);

/* Bilinear lookup in a table laid out as by sam_brdf_rho_dt_table, as GL
 * samples it (GL_LINEAR, GL_CLAMP_TO_EDGE) at (n_dot_l, roughness /
 * roughness_max), in exact arithmetic where GPUs round the weights (often
 * to 8 bits). `table` is not NULL and holds size_ndotl * size_roughness
 * floats; sizes >= 1; roughness_max > 0. Coordinates outside [0, 1] clamp. */
float sam_brdf_rho_dt_table_lookup(const float *table, uint32_t size_ndotl,
                                   uint32_t size_roughness, float roughness_max, float n_dot_l,
                                   float roughness);

#ifdef __cplusplus
}
#endif

#endif
