/* Rendering choices shared by scenes and the runtime (sam_technique.h). */
#include "sam/sam_technique.h"

void sam_diffusion_options_default(sam_diffusion_options *options)
{
    if (!options)
        return;
    options->sss_kernel = SAM_SSS_KERNEL_FIT2D;
    options->sss_samples = 17;
    options->atlas_size = 1024;
    options->culled = 0;
    options->depth_sized = 0;
    options->clipped = 1;
    options->texels_per_pixel = 1.0f;
}
