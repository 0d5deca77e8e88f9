#define _POSIX_C_SOURCE 200809L
#include "sam/sam_shape.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_shape_internal.h"

/* ---------------------------------------------------------------- tables */

static const char *const shape_names[SHAPE_COUNT] = {"sphere", "slab",  "torus",     "ear",
                                                     "knot",   "blobs", "perforated"};

static const sam_shape_info shape_infos[SHAPE_COUNT] = {
    {"sphere", "cube-sphere, size = diameter", "segments around the equator", 4, 0, 30.0},
    {"slab", "closed thin box, size = width (x), depth (z), thickness (y)",
     "segments along the width", 1, SAM_SHAPE_USES_DEPTH | SAM_SHAPE_USES_THICKNESS, 50.0},
    {"torus", "torus around z, size = outer diameter, thickness = tube diameter",
     "segments around the major circle", 8, SAM_SHAPE_USES_THICKNESS, 40.0},
    {"ear", "thin curled shell like the rim of an ear, size = height",
     "segments along the rim", 8, SAM_SHAPE_USES_THICKNESS, 60.0},
    {"knot", "tube along a (2,3) torus knot, thickness = tube diameter",
     "segments along the knot", 24, SAM_SHAPE_USES_THICKNESS, 40.0},
    {"blobs", "count disjoint deformed spheres in a cube of edge size",
     "segments around each blob's equator", 4, SAM_SHAPE_USES_COUNT | SAM_SHAPE_USES_SEED, 30.0},
    {"perforated", "thin square plate with count x count round holes, size = width",
     "segments along the width, at least 2 per hole", 8,
     SAM_SHAPE_USES_THICKNESS | SAM_SHAPE_USES_COUNT, 40.0},
};

static const sam_shape_params shape_defaults[SHAPE_COUNT] = {
    {64, 1.0, 1.0, 0.1, 1, 1},
    {64, 1.0, 1.0, 0.04, 1, 1},
    {96, 1.0, 1.0, 0.3, 1, 1},
    {128, 1.0, 1.0, 2.0 / 60.0, 1, 1},
    {256, 1.0, 1.0, 0.18, 1, 1},
    {32, 1.0, 1.0, 0.1, 6, 1},
    {30, 1.0, 1.0, 0.05, 5, 1},
};

static int shape_index(const char *name)
{
    if (!name)
        return -1;
    for (int i = 0; i < SHAPE_COUNT; ++i)
        if (strcmp(name, shape_names[i]) == 0)
            return i;
    return -1;
}

static sam_status fail_unknown(sam_error *err, const char *name)
{
    char known[128] = "";
    for (int i = 0; i < SHAPE_COUNT; ++i) {
        size_t used = strlen(known);
        snprintf(known + used, sizeof known - used, "%s%s", i ? ", " : "", shape_names[i]);
    }
    return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape \"%s\": unknown (known: %s)",
                    name ? name : "(null)", known);
}

const char *const *sam_shape_names(size_t *count)
{
    if (count)
        *count = SHAPE_COUNT;
    return shape_names;
}

const sam_shape_info *sam_shape_find(const char *name)
{
    int s = shape_index(name);
    return s < 0 ? NULL : &shape_infos[s];
}

sam_status sam_shape_default_params(const char *name, sam_shape_params *params, sam_error *err)
{
    int s = shape_index(name);
    if (s < 0)
        return fail_unknown(err, name);
    if (!params)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape %s: no params to fill", name);
    *params = shape_defaults[s];
    return SAM_OK;
}

static void builder_free(sam_shape_builder *b)
{
    free(b->surfaces);
    free(b->charts);
    free(b->knot_phi);
    memset(b, 0, sizeof *b);
}
double sam_shape_max_thickness(const char *name, const sam_shape_params *params)
{
    int s = shape_index(name);
    if (s < 0 || !params || !isfinite(params->size) || params->size <= 0)
        return 0.0;
    return sam_shape_thickness_limit(s, params->size);
}

static sam_status validate(int s, const sam_shape_params *p, sam_error *err)
{
    const char *name = shape_names[s];
    const sam_shape_info *info = &shape_infos[s];
    if (p->resolution < info->min_resolution || p->resolution > SAM_SHAPE_MAX_RESOLUTION)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "shape %s: resolution %d out of range [%d, %d]", name, p->resolution,
                        info->min_resolution, SAM_SHAPE_MAX_RESOLUTION);
    if (!isfinite(p->size) || p->size <= 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "shape %s: size %g must be a positive finite number", name, p->size);
    if ((info->uses & SAM_SHAPE_USES_DEPTH) && (!isfinite(p->depth) || p->depth <= 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "shape %s: depth %g must be a positive finite number", name, p->depth);
    if (info->uses & SAM_SHAPE_USES_THICKNESS) {
        double lo = SAM_SHAPE_MIN_RELATIVE_THICKNESS * p->size;
        double hi = sam_shape_max_thickness(name, p);
        if (!isfinite(p->thickness) || p->thickness < lo || p->thickness > hi) {
            if (isfinite(hi))
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                                "shape %s: thickness %g out of range [%g, %g] for size %g", name,
                                p->thickness, lo, hi, p->size);
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "shape %s: thickness %g must be finite and at least %g for size %g",
                            name, p->thickness, lo, p->size);
        }
    }
    if ((info->uses & SAM_SHAPE_USES_COUNT) && (p->count < 1 || p->count > SAM_SHAPE_MAX_COUNT))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape %s: count %d out of range [1, %d]",
                        name, p->count, SAM_SHAPE_MAX_COUNT);
    return SAM_OK;
}

/* Assigns each chart its first vertex and triangle and totals them; returns
 * 0 when the mesh would exceed SAM_SHAPE_MAX_VERTICES. */
static int count_elements(sam_shape_builder *b, uint64_t *vertices, uint64_t *triangles)
{
    *vertices = 0;
    *triangles = 0;
    for (size_t k = 0; k < b->chart_count; ++k) {
        sam_shape_chart *c = &b->charts[k];
        c->first_vertex = (uint32_t)*vertices;
        c->first_triangle = (uint32_t)*triangles;
        *vertices += (uint64_t)(c->nu + 1) * (uint64_t)(c->nv + 1);
        *triangles += 2 * (uint64_t)c->nu * (uint64_t)c->nv;
        if (*vertices > SAM_SHAPE_MAX_VERTICES || *triangles > SAM_SHAPE_MAX_VERTICES)
            return 0;
    }
    return 1;
}

sam_status sam_shape_generate(const char *name, const sam_shape_params *params,
                              sam_shape_mesh *mesh, sam_error *err)
{
    if (mesh)
        memset(mesh, 0, sizeof *mesh);
    int s = shape_index(name);
    if (s < 0)
        return fail_unknown(err, name);
    if (!params || !mesh)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape %s: params and mesh are required",
                        name);
    sam_status st = validate(s, params, err);
    if (st != SAM_OK)
        return st;

    sam_shape_builder b;
    memset(&b, 0, sizeof b);
    st = sam_shape_setup_surfaces(s, name, params, &b, err);
    if (st != SAM_OK) {
        builder_free(&b);
        return st;
    }
    for (size_t k = 0; k < b.surface_count; ++k)
        if (!sam_shape_add_surface_charts(&b, k)) {
            builder_free(&b);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape %s: out of memory", name);
        }
    /* Count before splitting too, so an oversized request fails before the
     * charts are measured. */
    uint64_t vertices, triangles;
    int fits = count_elements(&b, &vertices, &triangles);
    if (fits) {
        if (!sam_shape_split_long_charts(&b)) {
            builder_free(&b);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape %s: out of memory", name);
        }
        fits = count_elements(&b, &vertices, &triangles);
    }
    if (!fits) {
        builder_free(&b);
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "shape %s: resolution %d gives more than %u vertices or triangles", name,
                        params->resolution, SAM_SHAPE_MAX_VERTICES);
    }
    mesh->vertex_count = (uint32_t)vertices;
    mesh->triangle_count = (uint32_t)triangles;
    mesh->positions = malloc((size_t)vertices * 3 * sizeof(float));
    mesh->uvs = malloc((size_t)vertices * 2 * sizeof(float));
    mesh->triangles = malloc((size_t)triangles * 3 * sizeof(uint32_t));
    double side = 0.0;
    if (!mesh->positions || !mesh->uvs || !mesh->triangles || !sam_shape_pack_atlas(&b, &side)) {
        builder_free(&b);
        sam_shape_mesh_destroy(mesh);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY,
                        "shape %s: out of memory for %llu vertices, %llu triangles", name,
                        (unsigned long long)vertices, (unsigned long long)triangles);
    }
    sam_shape_emit(&b, side, mesh);
    builder_free(&b);
    return SAM_OK;
}

void sam_shape_mesh_destroy(sam_shape_mesh *mesh)
{
    if (!mesh)
        return;
    free(mesh->positions);
    free(mesh->uvs);
    free(mesh->triangles);
    memset(mesh, 0, sizeof *mesh);
}
