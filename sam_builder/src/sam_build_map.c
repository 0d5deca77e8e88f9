/* sam_build_run: the map the settings name, and the scaled flat baseline. */
#include <string.h>

#include "sam_build_internal.h"

/* Reports two builds in a row as one: the first half, then the second. */
typedef struct two_part_progress {
    sam_build_progress_fn fn;
    void *user;
    int part;
} two_part_progress;

static int two_part_report(void *user, uint64_t done, uint64_t total)
{
    two_part_progress *p = user;
    return p->fn(p->user, (uint64_t)p->part * total + done, 2 * total);
}

/* The flat map, each vertex's K and K' scaled per channel so that its
 * samples sum to the cut's total: the "more light through the same few
 * samples" baseline the cut map is measured against. */
static sam_status run_flat_scaled(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                                  sam_build_result *result, sam_error *err)
{
    double start = sam_seconds();
    two_part_progress two = {progress, user, 0};
    sam_build_progress_fn fn = progress ? two_part_report : NULL;
    sam_status st = sam_build_run_flat(ctx, fn, &two, result, err);
    if (st != SAM_OK)
        return st;
    two.part = 1;
    /* The total from the largest cut a row can hold, whatever N the flat
     * map has. Four times the default budget (128) overran the cut's
     * rows, which hold at most SAMFILE_MAX_SAMPLES_PER_VERTEX entries. */
    sam_build_context generous = *ctx;
    generous.settings.samples_per_vertex = generous.settings.cut_budget = SAMFILE_MAX_SAMPLES_PER_VERTEX;
    sam_build_result cut;
    if ((st = sam_build_run_cut(&generous, fn, &two, &cut, err)) != SAM_OK) {
        sam_build_result_destroy(result);
        return st;
    }
    const uint32_t n = result->samples_per_vertex;
    for (size_t t = 0; t < result->topo_count; ++t)
        for (int c = 0; c < 3; ++c) {
            double flat = 0;
            const double total = cut.k_total[3 * t + c];
            for (uint32_t k = 0; k < n; ++k)
                flat += result->k[3 * (t * n + k) + c];
            if (!(flat > 0))
                continue;
            const float scale = (float)(total / flat);
            for (uint32_t k = 0; k < n; ++k) {
                result->k[3 * (t * n + k) + c] *= scale;
                result->kprime[3 * (t * n + k) + c] *= scale;
            }
        }
    result->form_factors += cut.form_factors;
    result->candidates_seen += cut.candidates_seen;
    sam_build_result_destroy(&cut);
    result->seconds = sam_seconds() - start;
    return SAM_OK;
}

sam_status sam_build_run(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                         sam_build_result *result, sam_error *err)
{
    memset(result, 0, sizeof *result);
    switch (ctx->settings.map) {
    case SAM_BUILD_MAP_FLAT:
        return sam_build_run_flat(ctx, progress, user, result, err);
    case SAM_BUILD_MAP_FLAT_SCALED:
        return run_flat_scaled(ctx, progress, user, result, err);
    case SAM_BUILD_MAP_CUT:
    default:
        return sam_build_run_cut(ctx, progress, user, result, err);
    }
}
