/*
 * sam_technique: the rendering choices a scene makes and the GL runtime
 * carries out: where the translucency through the object comes from (the
 * technique), how light diffuses along the surface (the diffusion) and the
 * settings of the screen- and texture-space diffusions.
 *
 * These are plain values shared by the scene files (sam_scene.h, which
 * reads and writes them by the names given there) and the runtime
 * (sam_runtime.h, which renders with them), so the runtime needs no scene
 * parser to be told what to do. Nothing here keeps global state.
 */
#ifndef SAM_TECHNIQUE_H
#define SAM_TECHNIQUE_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sam_technique {
    SAM_TECHNIQUE_SAM = 0,          /* spatial adjacency maps */
    SAM_TECHNIQUE_NONE = 1,         /* no translucency through the object */
    SAM_TECHNIQUE_TSM = 2,          /* d'Eon's translucent shadow maps */
    SAM_TECHNIQUE_TRANSMITTANCE = 3, /* Jimenez's shadow-map transmittance */
    SAM_TECHNIQUE_THICKNESS = 4      /* Barre-Brisebois and Bouchard's local thickness (GDC 2011) */
} sam_technique;

typedef enum sam_diffusion {
    SAM_DIFFUSION_SCREEN = 0,       /* separable screen-space blur */
    SAM_DIFFUSION_TEXTURE = 1,      /* texture-space sum of Gaussians */
    SAM_DIFFUSION_PREINTEGRATED = 2, /* Penner's pre-integrated lookup */
    SAM_DIFFUSION_NONE = 3           /* no surface diffusion: per-pixel shading only */
} sam_diffusion;

/* The screen-space kernel's fit to the profile (sam_profile.h): the
 * energy-conserving separable fit of the 2D kernel (Jimenez eq. 2), each
 * channel's own 1D marginal (exact on straight edges), or eq. 1's width,
 * strength and falloff. */
typedef enum sam_sss_kernel {
    SAM_SSS_KERNEL_FIT2D = 0,
    SAM_SSS_KERNEL_MARGINAL = 1,
    SAM_SSS_KERNEL_EQ1 = 2
} sam_sss_kernel;

/* Settings of the surface-diffusion techniques. */
typedef struct sam_diffusion_options {
    sam_sss_kernel sss_kernel; /* screen space */
    uint32_t sss_samples;      /* screen space: taps per pass, odd, 9..33 */
    uint32_t atlas_size;       /* texture space: the atlas's (largest) side, 64..4096 */
    int culled;                /* texture space: skip texels facing away past the silhouette by more than
                                * max(15 degrees, 4 widest-Gaussian sigmas of surface at the vertex's curvature) */
    int depth_sized;           /* texture space: atlas side from the object's distance */
    int clipped;               /* texture space: skip texels outside the view frustum */
    float texels_per_pixel;    /* depth-sized: atlas texels per screen pixel at the nearest point, > 0 */
} sam_diffusion_options;

/* Fills `options` with the defaults: fit2d, 17 samples, a 1024 atlas,
 * clipped on, culled and depth-sized off (they change the picture: culling
 * loses light diffusing around a back-lit silhouette, a depth-sized atlas
 * resamples it), 1 texel per pixel. `options` may be NULL (nothing is
 * done); it owns nothing, so nothing is freed. Cannot fail. */
void sam_diffusion_options_default(sam_diffusion_options *options);

#ifdef __cplusplus
}
#endif

#endif
