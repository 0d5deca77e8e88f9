/* Lights and environment on the GPU: lights.glsl's Light array and the
 * environment's SH, which the irradiance, shading and technique passes read. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_lights.h"

/* std430 image of lights.glsl's Light. */
typedef struct gpu_light {
    float color_type[4], position[4], direction[4], params[4], normal[4], vertices[8][4];
} gpu_light;

sam_status sam_runtime_lights_create(sam_runtime *rt, sam_error *err)
{
    return sam_runtime_upload(rt, SAM_B_LIGHTS, NULL, sizeof(gpu_light), err);
}

void sam_runtime_lights_destroy(sam_runtime *rt)
{
    free(rt->lights.lights);
    rt->lights.lights = NULL;
}

int sam_runtime_light_casts_cube(const sam_light *l)
{
    return l->type == SAM_LIGHT_POINT || l->type == SAM_LIGHT_AREA;
}

sam_status sam_runtime_set_lights(sam_runtime *rt, const sam_light *lights, size_t count, sam_error *err)
{
    if (count > SAM_LIGHT_MAX_COUNT || (count && !lights))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %zu lights (at most %d)", count,
                        SAM_LIGHT_MAX_COUNT);
    uint32_t cubes = 0, flats = 0;
    for (size_t i = 0; i < count; ++i) {
        if (!lights[i].shadow)
            continue;
        if (sam_runtime_light_casts_cube(&lights[i]))
            cubes++;
        else
            flats++;
    }
    if (cubes > MAX_CUBE_SHADOWS || flats > MAX_FLAT_SHADOWS)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "runtime: %u shadowed point/area and %u shadowed spot/directional lights; at most %d of each "
                        "(turn \"shadow\" off for the others)",
                        cubes, flats, MAX_CUBE_SHADOWS);
    gpu_light *g = calloc(count ? count : 1, sizeof *g);
    sam_light *copy = malloc((count ? count : 1) * sizeof *copy);
    if (!g || !copy) {
        free(g);
        free(copy);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    }
    if (count)
        memcpy(copy, lights, count * sizeof *copy);
    free(rt->lights.lights);
    rt->lights.lights = copy;
    rt->lights.cube_count = rt->lights.flat_count = 0;
    const double deg = 3.14159265358979323846 / 180.0;
    for (size_t i = 0; i < count; ++i) {
        const sam_light *l = &lights[i];
        for (int c = 0; c < 3; ++c) {
            g[i].color_type[c] = l->color[c] * l->intensity;
            g[i].position[c] = l->position[c];
            g[i].direction[c] = l->direction[c];
            g[i].normal[c] = l->normal[c];
        }
        g[i].color_type[3] = (float)l->type;
        g[i].position[3] = (float)l->vertex_count;
        g[i].direction[3] = (float)cos(l->inner_angle_deg * deg);
        g[i].params[0] = (float)cos(l->outer_angle_deg * deg);
        g[i].params[1] = (float)l->two_sided;
        g[i].params[2] = -1.0f;
        if (l->shadow) {
            int cube = sam_runtime_light_casts_cube(l);
            g[i].params[2] = (float)(cube ? rt->lights.cube_count++ : rt->lights.flat_count++);
            g[i].params[3] = (float)cube;
        }
        for (uint32_t k = 0; k < l->vertex_count && k < SAM_AREA_LIGHT_MAX_VERTICES; ++k)
            memcpy(g[i].vertices[k], l->vertices[k], 3 * sizeof(float));
    }
    sam_status st = sam_runtime_upload(rt, SAM_B_LIGHTS, g, (count ? count : 1) * sizeof *g, err);
    free(g);
    if (st == SAM_OK)
        rt->lights.count = (uint32_t)count;
    return st;
}

void sam_runtime_set_environment(sam_runtime *rt, const float sh[9][3])
{
    rt->lights.has_environment = sh != NULL;
    if (sh)
        memcpy(rt->lights.sh, sh, sizeof rt->lights.sh);
}
