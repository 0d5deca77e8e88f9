/* A .sam as GPU buffers, and the runtime's life: create hands each pass its
 * step in order, destroy takes them down. The passes live in files of their
 * own (sam_runtime_internal.h lists them). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_mesh.h"
#include "sam_runtime_deform.h"
#include "sam_runtime_diffusion.h"
#include "sam_runtime_engine.h"
#include "sam_runtime_gpu.h"
#include "sam_runtime_irradiance.h"
#include "sam_runtime_lights.h"
#include "sam_runtime_nodes.h"
#include "sam_runtime_rest_k.h"
#include "sam_runtime_shadows.h"
#include "sam_runtime_surface.h"
#include "sam_runtime_technique.h"
#include "sam_runtime_thickness.h"
#include "sam_runtime_translucency.h"
#include "sam_runtime_tsd.h"
#include "sam_runtime_view.h"

/* The mesh's own buffers: positions, normals, samples, fan areas, rings,
 * triangles, curvature, UVs, and L_d and T zeroed. */
static sam_status upload_mesh(sam_runtime *rt, const samfile_data *sam, sam_error *err)
{
    const size_t nv = sam->vertex_count, n = sam->samples_per_vertex;
    float *pos = sam_runtime_widen(sam->positions, sam->vertex_count, 1.0f);
    for (size_t v = 0; pos && v < nv; ++v)
        sam_runtime_to_frame(rt, pos + 4 * v, pos + 4 * v);
    float *nrm = sam_runtime_widen(sam->normals, sam->vertex_count, 0.0f);
    /* Samples pair the index with its packed K', slot-major
     * (shaders/sample.glsl): slot k of vertex v at k * nv + v. */
    uint32_t *samples = malloc(nv * n * 3 * sizeof *samples);
    float *zero = calloc(nv * 4, sizeof *zero);
    float *curvature = malloc(nv * sizeof *curvature);
    sam_status st = SAM_OK;
    if (!pos || !nrm || !samples || !zero || !curvature) {
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %zu vertices", nv);
        goto done;
    }
    for (size_t v = 0; v < nv; ++v)
        for (size_t k = 0; k < n; ++k) {
            const size_t from = v * n + k, to = k * nv + v;
            samples[3 * to] = sam->sample_index[from];
            sam_runtime_pack_k(sam->sample_kprime + 3 * from, samples + 3 * to + 1);
        }
    /* Mean curvature in 1/mm from the .sam's own rings. */
    sam_mesh_ring_curvature(sam->vertex_count, sam->positions, NULL, sam->normals, sam->adjacency_offsets,
                            sam->adjacency, curvature);
    for (size_t v = 0; v < nv; ++v)
        curvature[v] /= rt->mm_per_unit;
    if ((st = sam_runtime_upload(rt, SAM_B_POSITIONS, pos, nv * 4 * sizeof(float), err)) != SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_NORMALS, nrm, nv * 4 * sizeof(float), err)) != SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_SAMPLES, samples, nv * n * 3 * sizeof(uint32_t), err)) != SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_FAN_AREAS, sam->fan_area, nv * sizeof(float), err)) != SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_IRRADIANCE, zero, nv * 4 * sizeof(float), err)) != SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_TRANSLUCENCY, zero, nv * 4 * sizeof(float), err)) != SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_ADJ_OFFSETS, sam->adjacency_offsets, (nv + 1) * sizeof(uint32_t), err)) !=
            SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_ADJACENCY, sam->adjacency, (size_t)sam->adjacency_count * sizeof(uint32_t),
                                 err)) != SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_TRIANGLES, sam->triangles,
                                 (size_t)sam->triangle_count * 3 * sizeof(uint32_t), err)) != SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_CURVATURE, curvature, nv * sizeof *curvature, err)) != SAM_OK ||
        (sam->uvs && (st = sam_runtime_upload(rt, SAM_B_UVS, sam->uvs, nv * 2 * sizeof(float), err)) != SAM_OK))
        goto done;
done:
    free(pos);
    free(nrm);
    free(samples);
    free(zero);
    free(curvature);
    return st;
}

/* The rest pose's frame, bounds and surface area. */
static void measure(sam_runtime *rt, const samfile_data *sam)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < sam->vertex_count; ++v)
        for (int c = 0; c < 3; ++c) {
            lo[c] = fminf(lo[c], sam->positions[3 * v + c]);
            hi[c] = fmaxf(hi[c], sam->positions[3 * v + c]);
        }
    sam_runtime_choose_frame(rt, lo, hi);
    sam_runtime_to_frame(rt, lo, lo);
    sam_runtime_to_frame(rt, hi, hi);
    memcpy(rt->rest_box_lo, lo, sizeof lo);
    memcpy(rt->rest_box_hi, hi, sizeof hi);
    sam_runtime_set_box(rt, lo, hi);
    double area = 0;
    for (size_t t = 0; t < sam->triangle_count; ++t) {
        const float *a = sam->positions + 3 * (size_t)sam->triangles[3 * t],
                    *b = sam->positions + 3 * (size_t)sam->triangles[3 * t + 1],
                    *c = sam->positions + 3 * (size_t)sam->triangles[3 * t + 2];
        double e1[3], e2[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = (double)b[k] - a[k];
            e2[k] = (double)c[k] - a[k];
        }
        double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2], z = e1[0] * e2[1] - e1[1] * e2[0];
        area += 0.5 * sqrt(x * x + y * y + z * z);
    }
    rt->surface_area = (float)area;
}

/* The vertex array every draw uses: positions, normals and UVs (or 0, 0). */
static void make_vertex_array(sam_runtime *rt, int has_uvs)
{
    glGenVertexArrays(1, &rt->vao);
    glBindVertexArray(rt->vao);
    glBindBuffer(GL_ARRAY_BUFFER, rt->buffer[SAM_B_POSITIONS]);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), NULL);
    glBindBuffer(GL_ARRAY_BUFFER, rt->buffer[SAM_B_NORMALS]);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), NULL);
    if (has_uvs) {
        glBindBuffer(GL_ARRAY_BUFFER, rt->buffer[SAM_B_UVS]);
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), NULL);
    } else {
        glVertexAttrib2f(2, 0.0f, 0.0f);
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, rt->buffer[SAM_B_TRIANGLES]);
    glBindVertexArray(0);
}

/* `sam` as the GL can hold it: the per-sample buffers (12 bytes a slot:
 * the samples and their rest K) must each fit one storage block, which
 * llvmpipe and the GL minimum allow 128 MiB, about 700k vertices at the
 * default N = 16, and `max_bytes` where it is not 0. A larger map is
 * fitted to the samples that fit, its rows carrying their whole K
 * (samfile_fit_samples), rather than not rendering: *fitted is `sam` with
 * its own sample arrays then (free them with free_fitted), else `sam`
 * itself. */
static sam_status fit_to_blocks(const samfile_data *sam, const sam_profile *profile, float mm_per_unit,
                                size_t max_bytes, samfile_data *fitted, sam_error *err)
{
    *fitted = *sam;
    const size_t gl_limit = sam_runtime_block_limit();
    const size_t limit = max_bytes && max_bytes < gl_limit ? max_bytes : gl_limit;
    const size_t slot_bytes = (size_t)sam->vertex_count * 3 * sizeof(uint32_t), fit = limit / slot_bytes;
    if (fit >= sam->samples_per_vertex)
        return SAM_OK;
    if (fit == 0)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "runtime: one sample per vertex of %u vertices needs %zu bytes per buffer, the limit is %zu",
                        sam->vertex_count, slot_bytes, limit);
    const size_t slots = (size_t)sam->vertex_count * fit;
    fitted->samples_per_vertex = (uint32_t)fit;
    fitted->sample_index = malloc(slots * sizeof *fitted->sample_index);
    fitted->sample_kprime = malloc(slots * 3 * sizeof *fitted->sample_kprime);
    fitted->sample_tau = sam->node_count ? malloc(slots * sizeof *fitted->sample_tau) : NULL;
    if (!fitted->sample_index || !fitted->sample_kprime || (sam->node_count && !fitted->sample_tau))
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %zu samples", slots);
    return samfile_fit_samples(sam, (uint32_t)fit, profile, mm_per_unit, fitted->sample_index, fitted->sample_kprime,
                               fitted->sample_tau, err);
}

static void free_fitted(const samfile_data *sam, samfile_data *fitted)
{
    if (fitted->sample_index != sam->sample_index)
        free(fitted->sample_index);
    if (fitted->sample_kprime != sam->sample_kprime)
        free(fitted->sample_kprime);
    if (fitted->sample_tau != sam->sample_tau)
        free(fitted->sample_tau);
}

/* sam_runtime_create once `sam` is validated and fits the GL. */
static sam_status create(const samfile_data *sam, const sam_profile *profile, float mm_per_unit,
                         sam_runtime **out, sam_error *err)
{
    sam_status st;
    sam_runtime *rt = calloc(1, sizeof *rt);
    if (!rt)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    rt->vertex_count = sam->vertex_count;
    rt->stride = sam->samples_per_vertex;
    rt->triangle_count = sam->triangle_count;
    rt->mm_per_unit = mm_per_unit;
    rt->profile = *profile;
    sam_profile_total_reflectance(profile, rt->total_reflectance);
    glGenBuffers(SAM_B_COUNT, rt->buffer);
    glGenQueries(SAM_PASS_COUNT, rt->query);
    measure(rt, sam);
    if ((st = upload_mesh(rt, sam, err)) == SAM_OK && (st = sam_profile_fit_gaussians(profile, &rt->fit, err)) == SAM_OK) {
        make_vertex_array(rt, sam->uvs != NULL);
        /* Each pass's own programs and state, in the header's step order. */
        if ((st = sam_runtime_lights_create(rt, err)) == SAM_OK && (st = sam_runtime_surface_create(rt, sam, err)) == SAM_OK &&
            (st = sam_runtime_shadows_create(rt, err)) == SAM_OK && (st = sam_runtime_deform_create(rt, err)) == SAM_OK &&
            (st = sam_runtime_engine_create(rt, sam, err)) == SAM_OK &&
            (st = sam_runtime_irradiance_create(rt, err)) == SAM_OK &&
            (st = sam_runtime_nodes_create(rt, sam, err)) == SAM_OK &&
            (st = sam_runtime_rest_k_create(rt, err)) == SAM_OK &&
            (st = sam_runtime_translucency_create(rt, err)) == SAM_OK &&
            (st = sam_runtime_technique_create(rt, err)) == SAM_OK &&
            (st = sam_runtime_tsd_create(rt, sam, err)) == SAM_OK &&
            (st = sam_runtime_diffusion_create(rt, err)) == SAM_OK &&
            (st = sam_runtime_view_create(rt, err)) == SAM_OK)
            st = sam_runtime_thickness_create(rt, err);
    }
    if (st != SAM_OK) {
        sam_runtime_destroy(rt);
        return st;
    }
    *out = rt;
    return SAM_OK;
}

sam_status sam_runtime_create(const samfile_data *sam, const sam_profile *profile, float mm_per_unit,
                              sam_runtime **out, sam_error *err)
{
    return sam_runtime_create_fitted(sam, profile, mm_per_unit, 0, out, err);
}

sam_status sam_runtime_create_fitted(const samfile_data *sam, const sam_profile *profile, float mm_per_unit,
                                     size_t max_sample_bytes, sam_runtime **out, sam_error *err)
{
    *out = NULL;
    if (!sam || !profile || !(mm_per_unit > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: no .sam, no profile or a scale <= 0");
    /* An engine may build its samfile_data by hand: an index out of range
     * would be read on the GPU, and a tree node shared by two parents
     * would leave the node pass's arrival counter wrong for good. */
    sam_status st = samfile_validate(sam, err);
    if (st != SAM_OK)
        return st;
    samfile_data fitted;
    if ((st = fit_to_blocks(sam, profile, mm_per_unit, max_sample_bytes, &fitted, err)) == SAM_OK &&
        (st = create(&fitted, profile, mm_per_unit, out, err)) == SAM_OK)
        (*out)->file_samples = sam->samples_per_vertex;
    free_fitted(sam, &fitted);
    return st;
}

void sam_runtime_destroy(sam_runtime *rt)
{
    if (!rt)
        return;
    sam_runtime_thickness_destroy(rt);
    sam_runtime_view_destroy(rt);
    sam_runtime_diffusion_destroy(rt);
    sam_runtime_tsd_destroy(rt);
    sam_runtime_technique_destroy(rt);
    sam_runtime_translucency_destroy(rt);
    sam_runtime_rest_k_destroy(rt);
    sam_runtime_nodes_destroy(rt);
    sam_runtime_irradiance_destroy(rt);
    sam_runtime_engine_destroy(rt);
    sam_runtime_deform_destroy(rt);
    sam_runtime_shadows_destroy(rt);
    sam_runtime_surface_destroy(rt);
    sam_runtime_lights_destroy(rt);
    glDeleteVertexArrays(1, &rt->vao);
    glDeleteBuffers(SAM_B_COUNT, rt->buffer);
    glDeleteQueries(SAM_PASS_COUNT, rt->query);
    free(rt);
}

uint32_t sam_runtime_vertex_count(const sam_runtime *rt)
{
    return rt->vertex_count;
}

uint32_t sam_runtime_samples_per_vertex(const sam_runtime *rt)
{
    return rt->stride;
}

uint32_t sam_runtime_file_samples_per_vertex(const sam_runtime *rt)
{
    return rt->file_samples;
}

int sam_runtime_fitted_note(const sam_runtime *rt, char *note, size_t size)
{
    if (rt->stride >= rt->file_samples)
        return 0;
    if (note && size)
        snprintf(note, size,
                 "the GPU holds %u of the map's %u samples per vertex (no more of %u vertices' samples fit its "
                 "storage blocks or the limit given): each row's best %u, scaled to carry the row's whole "
                 "transport; rebuild with --samples %u for a map that fits whole",
                 rt->stride, rt->file_samples, rt->vertex_count, rt->stride, rt->stride);
    return 1;
}

void sam_runtime_bounds(const sam_runtime *rt, float centre[3], float *radius)
{
    sam_runtime_from_frame(rt, rt->centre, centre);
    *radius = rt->radius;
}

double sam_runtime_pass_ms(sam_runtime *rt, sam_pass pass)
{
    if (pass >= SAM_PASS_COUNT || !rt->query_used[pass])
        return -1.0;
    GLuint64 ns = 0;
    glGetQueryObjectui64v(rt->query[pass], GL_QUERY_RESULT, &ns);
    /* No pass takes longer than the wall time since its query began: llvmpipe
     * answers the texture-space diffusion's query with the time since boot. */
    if ((double)ns * 1e-9 > sam_seconds() - rt->query_begun[pass])
        return -1.0;
    return (double)ns * 1e-6;
}
