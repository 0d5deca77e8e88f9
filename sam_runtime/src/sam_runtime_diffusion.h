/* The local diffusions of the view: screen-space separable subsurface
 * scattering (its kernel, two 1D blurs and the composition) and the
 * pre-integrated skin tables (state in rt->diffusion). Not installed. */
#ifndef SAM_RUNTIME_DIFFUSION_H
#define SAM_RUNTIME_DIFFUSION_H

#include "sam_runtime_internal.h"

/* Step 9 of sam_runtime_create: the blur and composition programs.
 * Errors: SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_diffusion_create(sam_runtime *rt, sam_error *err);
void sam_runtime_diffusion_destroy(sam_runtime *rt);

/* Builds and uploads the pre-integrated tables on first use (about 0.3 s).
 * Errors: those of sam_preint_*_table, SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_ensure_preintegrated(sam_runtime *rt, sam_error *err);

/* The screen-space kernel of the given fit and taps, made when it changes.
 * Errors: those of sam_profile_separable_kernel*. */
sam_status sam_runtime_ensure_kernel(sam_runtime *rt, sam_sss_kernel kind, uint32_t taps, sam_error *err);

/* Two 1D passes of the kernel over the view's entering light (image 0 of
 * `tex`, the view targets), then the composition with the factor (1) and
 * specular (2); into `tex[3]`, with `tex[4]` between the passes. Before
 * each pass the pass's input, times coverage, goes into `mips` (view-sized
 * RGBA32F and R32F textures with full mipmap chains), from which each tap
 * reads the mean over its share of the kernel. */
void sam_runtime_screen_space_diffusion(sam_runtime *rt, const sam_render_view *view, const GLuint tex[5],
                                        const GLuint mips[2]);

#endif
