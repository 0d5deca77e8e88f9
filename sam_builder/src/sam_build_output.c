/* A build result as a .sam container: render-vertex arrays plus INFO. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "sam_build_internal.h"

static cJSON *info_json(const sam_build_context *ctx, const sam_build_result *r, const sam_build_source *src)
{
    const sam_mesh *m = ctx->mesh;
    cJSON *info = cJSON_CreateObject();
    if (!info)
        return NULL;
    cJSON_AddNumberToObject(info, "vertex_count", m->vertex_count);
    cJSON_AddNumberToObject(info, "triangle_count", m->triangle_count);
    cJSON_AddNumberToObject(info, "samples_per_vertex", r->samples_per_vertex);
    cJSON_AddNumberToObject(info, "mm_per_unit", ctx->mm_per_unit);
    cJSON_AddBoolToObject(info, "has_uvs", m->uvs != NULL);
    char material[2048];
    sam_profile_to_json(ctx->profile, material, sizeof material);
    cJSON *mat = cJSON_Parse(material);
    if (mat)
        cJSON_AddItemToObject(info, "material", mat);
    cJSON *b = cJSON_AddObjectToObject(info, "builder");
    if (b) {
        cJSON_AddStringToObject(b, "name", "sam_build");
        cJSON_AddStringToObject(b, "version", SAM_BUILD_VERSION);
        cJSON_AddStringToObject(b, "map", sam_build_map_name(ctx->settings.map));
        if (ctx->settings.map == SAM_BUILD_MAP_CUT) {
            cJSON_AddNumberToObject(b, "cut_tolerance", ctx->settings.cut_tolerance);
            cJSON_AddNumberToObject(b, "cut_budget", ctx->settings.cut_budget);
            cJSON_AddNumberToObject(b, "tree_nodes", r->node_count);
        } else {
            cJSON_AddNumberToObject(b, "candidates", ctx->candidates);
        }
        cJSON_AddNumberToObject(b, "mc_samples", ctx->settings.mc_samples);
        cJSON_AddNumberToObject(b, "radius_tolerance", ctx->settings.radius_tolerance);
        cJSON_AddNumberToObject(b, "search_radius_mm", ctx->search_radius);
        /* A u64 seed may not fit a JSON number exactly: keep its digits. */
        char seed[32];
        snprintf(seed, sizeof seed, "%llu", (unsigned long long)ctx->settings.seed);
        cJSON_AddStringToObject(b, "seed", seed);
        cJSON_AddNumberToObject(b, "candidates_scored", (double)r->candidates_seen);
        cJSON_AddNumberToObject(b, "form_factors", (double)r->form_factors);
    }
    cJSON *s = cJSON_AddObjectToObject(info, "source");
    if (s) {
        if (src && src->file)
            cJSON_AddStringToObject(s, "file", sam_path_basename(src->file));
        if (src && src->sha256)
            cJSON_AddStringToObject(s, "sha256", src->sha256);
    }
    cJSON_AddNumberToObject(info, "build_seconds", r->seconds);
    return info;
}

/* A sample or child in topo numbering (samfile.h's layout with topo
 * vertices) in render numbering: a topo vertex becomes its representative
 * render vertex, node j becomes vertex_count + j. */
static uint32_t render_index(const sam_mesh *m, uint32_t s)
{
    if (s == SAM_BUILD_NO_SAMPLE)
        return SAMFILE_NO_SAMPLE;
    return s < m->topo_count ? m->topo_rep[s] : m->vertex_count + (s - m->topo_count);
}

/* Where each topo row goes when rows become render-vertex rows in place:
 * topo row t to its representative render vertex topo_rep[t], the other
 * render copies' (still empty) rows onto the rest, so that `dest` is a
 * permutation of [0, vertex_count). */
static void row_destinations(const sam_mesh *m, uint32_t *dest, unsigned char *is_rep)
{
    memset(is_rep, 0, m->vertex_count);
    for (uint32_t t = 0; t < m->topo_count; ++t) {
        dest[t] = m->topo_rep[t];
        is_rep[m->topo_rep[t]] = 1;
    }
    for (uint32_t v = 0, s = m->topo_count; v < m->vertex_count; ++v)
        if (!is_rep[v])
            dest[s++] = v;
}

/* Grows *rows from topo_count to vertex_count rows of `row` bytes and puts
 * them in render order in place (row v = topo row topo_of[v]): the rows
 * follow `dest` cycle by cycle, then each copy takes its representative's
 * row. One array of the whole map's samples is never held twice, which is
 * what keeps a large build's peak memory near the map's own size.
 * `moved` (vertex_count bytes) and tmp (2 * row bytes) are scratch.
 * Returns 0, with *rows unchanged, when out of memory. */
static int rows_to_render_order(const sam_mesh *m, const uint32_t *dest, unsigned char *moved, unsigned char *tmp,
                                size_t row, void **rows)
{
    const size_t nv = m->vertex_count;
    unsigned char *a = realloc(*rows, (nv ? nv : 1) * row);
    if (!a)
        return 0;
    *rows = a;
    unsigned char *carry = tmp, *spare = tmp + row;
    memset(moved, 0, nv);
    for (size_t s = 0; s < nv; ++s) {
        if (moved[s])
            continue;
        memcpy(carry, a + s * row, row);
        for (size_t at = s;;) {
            const size_t to = dest[at];
            moved[at] = 1;
            if (to == s) {
                memcpy(a + s * row, carry, row);
                break;
            }
            memcpy(spare, a + to * row, row);
            memcpy(a + to * row, carry, row);
            unsigned char *swap = carry;
            carry = spare, spare = swap;
            at = to;
        }
    }
    for (size_t v = 0; v < nv; ++v) {
        const uint32_t rep = m->topo_rep[m->topo_of[v]];
        if (rep != v)
            memcpy(a + v * row, a + (size_t)rep * row, row);
    }
    return 1;
}

/* The mesh, adjacency, tree and INFO of the .sam: everything but the
 * per-sample arrays. */
static sam_status fill_mesh_part(const sam_build_context *ctx, const sam_build_result *r,
                                 const sam_build_source *source, samfile_data *out, sam_error *err)
{
    const sam_mesh *m = ctx->mesh;
    const size_t nv = m->vertex_count, nt = m->triangle_count;
    /* Every render copy carries its topo vertex's whole ring. */
    size_t adjacency = 0;
    for (size_t v = 0; v < nv; ++v) {
        uint32_t t = m->topo_of[v];
        adjacency += m->ring_offsets[t + 1] - m->ring_offsets[t];
    }
    if (adjacency > UINT32_MAX)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "build: %zu adjacency entries exceed the format's 32-bit range",
                        adjacency);
    out->vertex_count = (uint32_t)nv;
    out->triangle_count = (uint32_t)nt;
    out->samples_per_vertex = r->samples_per_vertex;
    out->positions = malloc(nv * 3 * sizeof(float));
    out->normals = malloc(nv * 3 * sizeof(float));
    out->uvs = m->uvs ? malloc(nv * 2 * sizeof(float)) : NULL;
    out->triangles = malloc(nt * 3 * sizeof(uint32_t));
    out->fan_area = malloc(nv * sizeof(float));
    out->adjacency_offsets = malloc((nv + 1) * sizeof(uint32_t));
    out->adjacency_count = (uint32_t)adjacency;
    out->adjacency = malloc((adjacency ? adjacency : 1) * sizeof(uint32_t));
    if (r->node_count) {
        out->node_count = r->node_count;
        out->level_count = r->level_count;
        out->node_children = malloc((size_t)r->node_count * 2 * sizeof(uint32_t));
        out->level_offsets = malloc(((size_t)r->level_count + 1) * sizeof(uint32_t));
    }
    if (m->source_of_render && m->source_count) {
        out->source_vertex_count = m->source_count;
        out->vertex_source = malloc((nv ? nv : 1) * sizeof *out->vertex_source);
        out->source_vertex = malloc((size_t)m->source_count * sizeof *out->source_vertex);
    }
    cJSON *info = info_json(ctx, r, source);
    out->info_json = info ? cJSON_PrintUnformatted(info) : NULL;
    cJSON_Delete(info);
    if (!out->positions || !out->normals || (m->uvs && !out->uvs) || !out->triangles || !out->fan_area ||
        !out->adjacency_offsets || !out->adjacency || !out->info_json ||
        (r->node_count && (!out->node_children || !out->level_offsets)) ||
        (out->source_vertex_count && (!out->vertex_source || !out->source_vertex)))
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory assembling the .sam of %zu vertices", nv);
    memcpy(out->positions, m->positions, nv * 3 * sizeof(float));
    memcpy(out->normals, m->normals, nv * 3 * sizeof(float));
    if (m->uvs)
        memcpy(out->uvs, m->uvs, nv * 2 * sizeof(float));
    memcpy(out->triangles, m->triangles, nt * 3 * sizeof(uint32_t));
    _Static_assert(SAM_MESH_DROPPED == SAMFILE_NO_SAMPLE, "a dropped source vertex is written as it is");
    if (out->source_vertex_count) {
        memcpy(out->vertex_source, m->source_of_render, nv * sizeof *out->vertex_source);
        memcpy(out->source_vertex, m->render_of_source, (size_t)m->source_count * sizeof *out->source_vertex);
    }
    size_t a = 0;
    for (size_t v = 0; v < nv; ++v) {
        uint32_t t = m->topo_of[v];
        out->fan_area[v] = r->fan_area[t];
        out->adjacency_offsets[v] = (uint32_t)a;
        for (uint32_t k = m->ring_offsets[t]; k < m->ring_offsets[t + 1]; ++k)
            out->adjacency[a++] = m->topo_rep[m->ring[k]];
    }
    out->adjacency_offsets[nv] = (uint32_t)a;
    for (size_t j = 0; j < 2 * (size_t)r->node_count; ++j)
        out->node_children[j] = render_index(m, r->node_children[j]);
    if (r->node_count)
        memcpy(out->level_offsets, r->level_offsets, ((size_t)r->level_count + 1) * sizeof(uint32_t));
    return SAM_OK;
}

sam_status sam_build_move_to_samfile(const sam_build_context *ctx, sam_build_result *r,
                                     const sam_build_source *source, samfile_data *out, sam_error *err)
{
    memset(out, 0, sizeof *out);
    const sam_mesh *m = ctx->mesh;
    const size_t nv = m->vertex_count, n = r->samples_per_vertex;
    sam_status st = fill_mesh_part(ctx, r, source, out, err);
    uint32_t *dest = malloc((nv ? nv : 1) * sizeof *dest);
    unsigned char *scratch = malloc(nv + 2 * 3 * n * sizeof(float) + 1);
    if (st == SAM_OK && (!dest || !scratch))
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory assembling the .sam of %zu vertices", nv);
    if (st == SAM_OK) {
        row_destinations(m, dest, scratch);
        unsigned char *tmp = scratch + nv;
        if (!rows_to_render_order(m, dest, scratch, tmp, n * sizeof *r->sample, (void **)&r->sample) ||
            !rows_to_render_order(m, dest, scratch, tmp, 3 * n * sizeof *r->kprime, (void **)&r->kprime) ||
            (r->tau && !rows_to_render_order(m, dest, scratch, tmp, n * sizeof *r->tau, (void **)&r->tau)))
            st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory assembling the .sam of %zu vertices",
                          nv);
    }
    free(dest);
    free(scratch);
    if (st == SAM_OK) {
        for (size_t i = 0; i < nv * n; ++i)
            r->sample[i] = render_index(m, r->sample[i]);
        out->sample_index = r->sample;
        out->sample_kprime = r->kprime;
        out->sample_tau = r->tau;
    } else {
        samfile_free(out);
        free(r->sample);
        free(r->kprime);
        free(r->tau);
    }
    r->sample = NULL;
    r->kprime = NULL;
    r->tau = NULL;
    return st;
}

sam_status sam_build_to_samfile(const sam_build_context *ctx, const sam_build_result *r,
                                const sam_build_source *source, samfile_data *out, sam_error *err)
{
    const size_t slots = (size_t)r->topo_count * r->samples_per_vertex;
    sam_build_result copy = *r;
    copy.sample = malloc((slots ? slots : 1) * sizeof *copy.sample);
    copy.kprime = malloc((slots ? slots : 1) * 3 * sizeof *copy.kprime);
    copy.tau = r->tau ? malloc((slots ? slots : 1) * sizeof *copy.tau) : NULL;
    if (!copy.sample || !copy.kprime || (r->tau && !copy.tau)) {
        free(copy.sample);
        free(copy.kprime);
        free(copy.tau);
        memset(out, 0, sizeof *out);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory assembling the .sam of %u vertices",
                        ctx->mesh->vertex_count);
    }
    memcpy(copy.sample, r->sample, slots * sizeof *copy.sample);
    memcpy(copy.kprime, r->kprime, slots * 3 * sizeof *copy.kprime);
    if (r->tau)
        memcpy(copy.tau, r->tau, slots * sizeof *copy.tau);
    return sam_build_move_to_samfile(ctx, &copy, source, out, err);
}

sam_status sam_build_samfile(const sam_mesh *mesh, const sam_profile *profile, float mm_per_unit,
                             const sam_build_settings *settings, const sam_build_source *source,
                             sam_build_progress_fn progress, void *user, samfile_data *out, double *seconds,
                             sam_error *err)
{
    memset(out, 0, sizeof *out);
    sam_build_settings defaults;
    if (!settings) {
        sam_build_default_settings(&defaults);
        settings = &defaults;
    }
    sam_build_context *ctx;
    sam_status st = sam_build_context_create(mesh, profile, mm_per_unit, settings, &ctx, err);
    if (st != SAM_OK)
        return st;
    sam_build_result result;
    st = sam_build_run(ctx, progress, user, &result, err);
    if (st == SAM_OK) {
        st = sam_build_move_to_samfile(ctx, &result, source, out, err);
        if (seconds)
            *seconds = result.seconds;
        sam_build_result_destroy(&result);
    }
    sam_build_context_destroy(ctx);
    return st;
}
