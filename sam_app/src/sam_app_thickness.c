/* A map's local thickness for the programs (sam_app_thickness.h). */
#include <stdio.h>
#include <stdlib.h>

#include "sam/sam_app.h"
#include "sam/sam_app_thickness.h"
#include "sam/sam_thickness.h"

/* The progress bar, silent for its first second: most meshes are done by
 * then and need no bar. */
static int delayed_progress(void *user, uint64_t done, uint64_t total)
{
    sam_app_progress *bar = user;
    if (sam_seconds() - bar->start < 1.0)
        return 0;
    return sam_app_progress_update(bar, done, total);
}

sam_status sam_app_thickness(const samfile_data *sam, float mm_per_unit, const char *tool, float **mm,
                             sam_error *err)
{
    *mm = malloc((size_t)sam->vertex_count * sizeof **mm);
    if (!*mm)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the thickness of %u vertices",
                        sam->vertex_count);
    sam_app_progress bar;
    sam_app_progress_init(&bar, tool, tool == NULL, NULL);
    const sam_thickness_surface surface = {sam->vertex_count, sam->positions, sam->normals, sam->triangle_count,
                                           sam->triangles};
    float *raw = malloc((size_t)sam->vertex_count * sizeof *raw);
    sam_status st = raw ? sam_thickness_compute(&surface, mm_per_unit, NULL, delayed_progress, &bar, raw, err)
                        : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the thickness of %u vertices",
                                   sam->vertex_count);
    /* Lone vertices over a crack of the scan read next to no thickness:
     * fireflies (sam_thickness.h). */
    if (st == SAM_OK)
        st = sam_thickness_ring_median(sam->vertex_count, sam->adjacency_offsets, sam->adjacency, raw, *mm, err);
    free(raw);
    if (st != SAM_OK) {
        free(*mm);
        *mm = NULL;
    } else if (tool && sam_seconds() - bar.start >= 1.0) {
        fprintf(stderr, "%s: measured the local thickness of %u vertices in %.2f s\n", tool, sam->vertex_count,
                sam_seconds() - bar.start);
    }
    return st;
}
