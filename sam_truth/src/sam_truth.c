/* The ground truth's lifetime: argument checks, the copied scene, the
 * automatic sample count, and the accessors. */
#include "sam_truth_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "sam/sam_rng.h"

void sam_truth_default_settings(sam_truth_settings *settings)
{
    if (!settings)
        return;
    memset(settings, 0, sizeof *settings);
    settings->seed = 1;
    settings->area_light_samples = SAM_TRUTH_DEFAULT_AREA_SAMPLES;
}

static int finite3(const float *v)
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static sam_status check_mesh(const sam_truth_scene *s, sam_error *err)
{
    if (!s->positions || !s->normals || !s->triangles || !s->profile)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: scene.%s is NULL",
                        !s->positions   ? "positions"
                        : !s->normals   ? "normals"
                        : !s->triangles ? "triangles"
                                        : "profile");
    if (s->vertex_count == 0 || s->triangle_count == 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: scene.%s is 0",
                        s->vertex_count == 0 ? "vertex_count" : "triangle_count");
    if (!(s->mm_per_unit > 0) || !isfinite(s->mm_per_unit))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: scene.mm_per_unit must be finite and > 0, found %g",
                        s->mm_per_unit);
    for (uint32_t v = 0; v < s->vertex_count; ++v) {
        const float *p = s->positions + 3 * (size_t)v, *n = s->normals + 3 * (size_t)v;
        if (!finite3(p))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "truth: scene.positions of vertex %u not finite (%g, %g, %g)", v, p[0], p[1], p[2]);
        if (!finite3(n) || (n[0] == 0 && n[1] == 0 && n[2] == 0))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "truth: scene.normals of vertex %u must be finite and non-zero, found (%g, %g, %g)", v,
                            n[0], n[1], n[2]);
    }
    for (size_t i = 0; i < 3 * (size_t)s->triangle_count; ++i)
        if (s->triangles[i] >= s->vertex_count)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "truth: scene.triangles[%zu] (triangle %zu) = %u is out of range (vertex_count %u)", i,
                            i / 3, s->triangles[i], s->vertex_count);
    return SAM_OK;
}

static sam_status check_light(const sam_light *l, size_t i, sam_error *err)
{
    if ((int)l->type < SAM_LIGHT_POINT || l->type > SAM_LIGHT_AREA)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: lights[%zu].type %d is unknown", i, (int)l->type);
    if (!finite3(l->color) || l->color[0] < 0 || l->color[1] < 0 || l->color[2] < 0 || !isfinite(l->intensity) ||
        l->intensity < 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "truth: lights[%zu] color (%g, %g, %g) and intensity %g must be finite and >= 0", i,
                        l->color[0], l->color[1], l->color[2], l->intensity);
    if ((l->type == SAM_LIGHT_POINT || l->type == SAM_LIGHT_SPOT) && !finite3(l->position))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: lights[%zu].position is not finite", i);
    if ((l->type == SAM_LIGHT_SPOT || l->type == SAM_LIGHT_DIRECTIONAL) &&
        (!finite3(l->direction) || (l->direction[0] == 0 && l->direction[1] == 0 && l->direction[2] == 0)))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: lights[%zu].direction must be finite and non-zero",
                        i);
    if (l->type == SAM_LIGHT_AREA) {
        if (l->vertex_count < 3 || l->vertex_count > SAM_AREA_LIGHT_MAX_VERTICES)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: lights[%zu].vertex_count %u is outside 3..%d", i,
                            l->vertex_count, SAM_AREA_LIGHT_MAX_VERTICES);
        for (uint32_t k = 0; k < l->vertex_count; ++k)
            if (!finite3(l->vertices[k]))
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: lights[%zu].vertices[%u] is not finite", i, k);
        if (!finite3(l->normal))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: lights[%zu].normal is not finite", i);
    }
    return SAM_OK;
}

static sam_status check_arguments(const sam_truth_scene *s, const sam_truth_settings *set, sam_error *err)
{
    sam_status st = check_mesh(s, err);
    if (st != SAM_OK)
        return st;
    if (s->light_count > 0 && !s->lights)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: scene.lights is NULL with light_count %zu",
                        s->light_count);
    for (size_t i = 0; i < s->light_count; ++i)
        if ((st = check_light(&s->lights[i], i, err)) != SAM_OK)
            return st;
    if (s->sh) {
        for (int k = 0; k < 9; ++k)
            if (!finite3(s->sh[k]))
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: scene.sh[%d] is not finite", k);
        if (!isfinite(s->environment_rho_dt) || s->environment_rho_dt < 0)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "truth: scene.environment_rho_dt must be finite and >= 0, found %g",
                            s->environment_rho_dt);
    }
    if (set->sample_count > UINT32_MAX)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: settings.sample_count %llu is above %u",
                        (unsigned long long)set->sample_count, UINT32_MAX);
    if (set->threads < 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: settings.threads must be >= 0, found %d",
                        set->threads);
    if (!(set->far_field_tolerance >= 0 && set->far_field_tolerance < 0.5f))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "truth: settings.far_field_tolerance must be in [0, 0.5), found %g",
                        (double)set->far_field_tolerance);
    return SAM_OK;
}

/* Copies the mesh and lights and builds the area CDF (mm^2). */
static sam_status copy_scene(sam_truth *t, const sam_truth_scene *s, sam_error *err)
{
    t->vertex_count = s->vertex_count;
    t->triangle_count = s->triangle_count;
    size_t vsize = 3 * sizeof(float) * s->vertex_count, tsize = 3 * sizeof(uint32_t) * s->triangle_count;
    t->positions = malloc(vsize);
    t->normals = malloc(vsize);
    t->triangles = malloc(tsize);
    t->area_cdf = malloc(sizeof *t->area_cdf * s->triangle_count);
    t->lights = malloc(sizeof *t->lights * (s->light_count ? s->light_count : 1));
    if (!t->positions || !t->normals || !t->triangles || !t->area_cdf || !t->lights)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY,
                        "truth: out of memory for a copy of the mesh (%u vertices, %u triangles)", s->vertex_count,
                        s->triangle_count);
    memcpy(t->positions, s->positions, vsize);
    memcpy(t->triangles, s->triangles, tsize);
    for (uint32_t v = 0; v < s->vertex_count; ++v) {
        const float *n = s->normals + 3 * (size_t)v;
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k)
            t->normals[3 * (size_t)v + k] = n[k] / len;
    }
    if (s->light_count)
        memcpy(t->lights, s->lights, sizeof *t->lights * s->light_count);
    t->light_count = s->light_count;
    t->has_environment = s->sh != NULL;
    if (s->sh)
        memcpy(t->sh, s->sh, sizeof t->sh);
    t->environment_rho_dt = s->environment_rho_dt;
    t->rho_dt = s->rho_dt;
    t->rho_dt_user = s->rho_dt_user;
    t->mm_per_unit = s->mm_per_unit;

    double sum = 0, mm2 = (double)s->mm_per_unit * s->mm_per_unit;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < s->triangle_count; ++i) {
        const uint32_t *tri = s->triangles + 3 * (size_t)i;
        double e1[3], e2[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = (double)s->positions[3 * (size_t)tri[1] + k] - s->positions[3 * (size_t)tri[0] + k];
            e2[k] = (double)s->positions[3 * (size_t)tri[2] + k] - s->positions[3 * (size_t)tri[0] + k];
            for (int c = 0; c < 3; ++c) {
                lo[k] = fminf(lo[k], s->positions[3 * (size_t)tri[c] + k]);
                hi[k] = fmaxf(hi[k], s->positions[3 * (size_t)tri[c] + k]);
            }
        }
        double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        sum += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) * mm2;
        t->area_cdf[i] = sum;
    }
    if (!(sum > 0) || !isfinite(sum))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "truth: the mesh's area is %g mm^2 (every triangle degenerate?)", sum);
    t->total_area = sum;
    float diag2 = 0;
    for (int k = 0; k < 3; ++k)
        diag2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    t->ray_offset = SAM_TRUTH_RAY_OFFSET * sqrtf(diag2);
    return SAM_OK;
}

/* The overview's rule: spacing a quarter of the sigma of the narrowest fit
 * Gaussian that carries a relevant share of some channel. */
static sam_status automatic_count(const sam_truth *t, const sam_profile *profile, uint64_t *count, sam_error *err)
{
    sam_gaussian_fit fit;
    sam_error fit_err;
    if (sam_profile_fit_gaussians(profile, &fit, &fit_err) != SAM_OK)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: scene.profile: %s", fit_err.message);
    float total[3] = {0, 0, 0};
    for (uint32_t g = 0; g < fit.count; ++g)
        for (int c = 0; c < 3; ++c)
            total[c] += fit.weight[g][c];
    double variance = INFINITY;
    for (uint32_t g = 0; g < fit.count; ++g)
        for (int c = 0; c < 3; ++c)
            if (total[c] > 0 && fit.weight[g][c] >= SAM_TRUTH_RELEVANT_WEIGHT * total[c] &&
                fit.variance[g] < variance)
                variance = fit.variance[g];
    double n = isfinite(variance) ? t->total_area / (variance / 16.0) : 0.0;
    *count = n >= (double)SAM_TRUTH_MAX_SAMPLES ? SAM_TRUTH_MAX_SAMPLES
             : n <= (double)SAM_TRUTH_MIN_SAMPLES ? SAM_TRUTH_MIN_SAMPLES
                                                  : (uint64_t)ceil(n);
    return SAM_OK;
}

sam_status sam_truth_create(const sam_truth_scene *scene, const sam_truth_settings *settings, sam_truth **out,
                            sam_error *err)
{
    if (out)
        *out = NULL;
    if (!scene || !settings || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: %s is NULL",
                        !scene ? "scene" : !settings ? "settings" : "out");
    sam_status st = check_arguments(scene, settings, err);
    if (st != SAM_OK)
        return st;
    float radius = sam_profile_radius(scene->profile, SAM_TRUTH_RADIUS_TOLERANCE);
    if (!(radius > 0) || !isfinite(radius))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth: scene.profile's radius of influence is %g mm",
                        radius);

    double start = sam_seconds();
    sam_truth *t = calloc(1, sizeof *t);
    if (!t)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "truth: out of memory");
    t->radius_mm = radius;
    t->seed = settings->seed;
    t->area_samples = settings->area_light_samples ? settings->area_light_samples : SAM_TRUTH_DEFAULT_AREA_SAMPLES;
    t->threads = settings->threads > 0 ? settings->threads : omp_get_max_threads();
    t->progress = settings->progress;
    t->progress_user = settings->progress_user;
    t->tolerance = settings->far_field_tolerance;
    t->far_ratio = expf(sqrtf(8.0f * t->tolerance));
    /* 53 random bits each: the shifts of the two lattice axes. */
    t->shift[0] = (double)(sam_rng_mix(settings->seed) >> 11) * 0x1.0p-53;
    t->shift[1] = (double)(sam_rng_mix(settings->seed ^ 0xA5A5A5A5A5A5A5A5ull) >> 11) * 0x1.0p-53;

    if ((st = copy_scene(t, scene, err)) != SAM_OK)
        goto fail;
    t->sample_count = settings->sample_count;
    if (t->sample_count == 0 && (st = automatic_count(t, scene->profile, &t->sample_count, err)) != SAM_OK)
        goto fail;

    t->device = rtcNewDevice(NULL);
    if (!t->device) {
        st = sam_fail(err, SAM_ERR_UNSUPPORTED, "truth: Embree could not create a device (rtcGetDeviceError %d)",
                      (int)rtcGetDeviceError(NULL));
        goto fail;
    }
    if ((st = truth_embree_scene(t, err)) != SAM_OK || (st = truth_compute_samples(t, err)) != SAM_OK ||
        (st = truth_build_tree(t, scene->profile, err)) != SAM_OK)
        goto fail;
    t->seconds = sam_seconds() - start;
    *out = t;
    return SAM_OK;
fail:
    sam_truth_destroy(t);
    return st;
}

void sam_truth_destroy(sam_truth *truth)
{
    if (!truth)
        return;
    if (truth->scene)
        rtcReleaseScene(truth->scene);
    if (truth->device)
        rtcReleaseDevice(truth->device);
    free(truth->positions);
    free(truth->normals);
    free(truth->triangles);
    free(truth->area_cdf);
    free(truth->lights);
    free(truth->rd_table);
    free(truth->lit);
    free(truth->nodes);
    free(truth);
}

uint64_t sam_truth_sample_count(const sam_truth *truth)
{
    return truth ? truth->sample_count : 0;
}

uint64_t sam_truth_lit_sample_count(const sam_truth *truth)
{
    return truth ? truth->lit_count : 0;
}

double sam_truth_sample_area(const sam_truth *truth)
{
    return truth ? truth->total_area / (double)truth->sample_count : 0.0;
}

double sam_truth_seconds(const sam_truth *truth)
{
    return truth ? truth->seconds : 0.0;
}

sam_status sam_truth_sample(sam_truth *truth, uint64_t index, float position[3], float normal[3], float l_d[3],
                            sam_error *err)
{
    if (!truth)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth sample: truth is NULL");
    if (index >= truth->sample_count)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth sample: index %llu is out of range (%llu samples)",
                        (unsigned long long)index, (unsigned long long)truth->sample_count);
    double start = sam_seconds();
    float p[3], n[3], l[3];
    truth_sample_at(truth, index, p, n, l);
    if (position)
        memcpy(position, p, sizeof p);
    if (normal)
        memcpy(normal, n, sizeof n);
    if (l_d)
        memcpy(l_d, l, sizeof l);
    truth->seconds += sam_seconds() - start;
    return SAM_OK;
}
