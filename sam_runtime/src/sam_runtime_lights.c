/* Lights and environment on the GPU: lights.glsl's Light array and the
 * environment's SH, which the irradiance, shading and technique passes read. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_vec3.h"
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
    free(rt->lights.cube);
    rt->lights.lights = NULL;
    rt->lights.cube = NULL;
}

float sam_runtime_to_centre(const sam_runtime *rt, const float p[3], float d[3])
{
    for (int c = 0; c < 3; ++c)
        d[c] = rt->centre[c] - p[c];
    return sqrtf(sam_vec3_dot(d, d));
}

float sam_runtime_object_half_angle(const sam_runtime *rt, const float position[3])
{
    /* 3% wider: lookups move up to 3 texels off the surface
     * (shadows.glsl), and the filter reads 2 texels beyond. */
    float d[3];
    const float dc = sam_runtime_to_centre(rt, position, d), r = 1.03f * rt->radius;
    return dc > r ? asinf(r / dc) : 1.5707963f;
}

/* A point light that sees the object within a cone of this half-angle gets
 * a 2D map fitted to that cone instead of a cube: 1024 texels across at
 * most 120 degrees resolve at least what a cube face's 512 do across 90
 * (5.5 times as fine at the centre from three radii away), in one draw
 * instead of six. */
#define FIT_HALF_ANGLE 1.0471976f /* 60 degrees */

/* Which shadowed lights get a cube map, into `cube` (count entries): area
 * lights and the point lights too close to fit a 2D map always do; spot
 * and directional lights never; the other point lights while a 2D map is
 * left after the spot and directional lights. */
static sam_status assign_maps(const sam_runtime *rt, const sam_light *lights, size_t count, unsigned char *cube,
                              sam_error *err)
{
    enum { FLAT, CUBE, FITS };
    uint32_t n[3] = {0, 0, 0};
    for (size_t i = 0; i < count; ++i) {
        const sam_light *l = &lights[i];
        cube[i] = l->type == SAM_LIGHT_POINT || l->type == SAM_LIGHT_AREA ? CUBE : FLAT;
        if (l->type == SAM_LIGHT_POINT && sam_runtime_object_half_angle(rt, l->position) <= FIT_HALF_ANGLE)
            cube[i] = FITS;
        n[cube[i]] += l->shadow != 0;
    }
    if (n[CUBE] > MAX_CUBE_SHADOWS || n[FLAT] > MAX_FLAT_SHADOWS ||
        n[CUBE] + n[FLAT] + n[FITS] > MAX_CUBE_SHADOWS + MAX_FLAT_SHADOWS)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "runtime: %u shadowed area or nearby point lights, %u spot or directional lights and %u "
                        "distant point lights; at most %d of the first, %d of the second and %d in all (turn "
                        "\"shadow\" off for the others)",
                        n[CUBE], n[FLAT], n[FITS], MAX_CUBE_SHADOWS, MAX_FLAT_SHADOWS,
                        MAX_CUBE_SHADOWS + MAX_FLAT_SHADOWS);
    for (size_t i = 0; i < count; ++i)
        if (cube[i] == FITS) {
            cube[i] = lights[i].shadow && n[FLAT] == MAX_FLAT_SHADOWS;
            if (lights[i].shadow)
                n[FLAT] += !cube[i];
        }
    return SAM_OK;
}

sam_status sam_runtime_set_lights(sam_runtime *rt, const sam_light *lights, size_t count, sam_error *err)
{
    if (count > SAM_LIGHT_MAX_COUNT || (count && !lights))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %zu lights (at most %d)", count,
                        SAM_LIGHT_MAX_COUNT);
    gpu_light *g = calloc(count ? count : 1, sizeof *g);
    sam_light *copy = malloc((count ? count : 1) * sizeof *copy);
    unsigned char *cube = malloc(count ? count : 1);
    if (!g || !copy || !cube) {
        free(g);
        free(copy);
        free(cube);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    }
    if (count)
        memcpy(copy, lights, count * sizeof *copy);
    for (size_t i = 0; i < count; ++i) {
        sam_runtime_to_frame(rt, copy[i].position, copy[i].position);
        for (uint32_t k = 0; k < copy[i].vertex_count && k < SAM_AREA_LIGHT_MAX_VERTICES; ++k)
            sam_runtime_to_frame(rt, copy[i].vertices[k], copy[i].vertices[k]);
    }
    /* From here on the lights are the copy, in the GPU's frame. */
    lights = copy;
    sam_status st = assign_maps(rt, lights, count, cube, err);
    if (st != SAM_OK) {
        free(g);
        free(copy);
        free(cube);
        return st;
    }
    free(rt->lights.lights);
    free(rt->lights.cube);
    rt->lights.lights = copy;
    rt->lights.cube = cube;
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
            g[i].params[2] = (float)(cube[i] ? rt->lights.cube_count++ : rt->lights.flat_count++);
            g[i].params[3] = (float)cube[i];
        }
        for (uint32_t k = 0; k < l->vertex_count && k < SAM_AREA_LIGHT_MAX_VERTICES; ++k)
            memcpy(g[i].vertices[k], l->vertices[k], 3 * sizeof(float));
    }
    st = sam_runtime_upload(rt, SAM_B_LIGHTS, g, (count ? count : 1) * sizeof *g, err);
    free(g);
    /* The arrays hold the new lights either way; without their buffer, no
     * light is read. */
    rt->lights.count = st == SAM_OK ? (uint32_t)count : 0;
    if (st != SAM_OK)
        rt->lights.cube_count = rt->lights.flat_count = 0;
    return st;
}

void sam_runtime_set_environment(sam_runtime *rt, const float sh[9][3])
{
    rt->lights.has_environment = sh != NULL;
    if (sh)
        memcpy(rt->lights.sh, sh, sizeof rt->lights.sh);
}
