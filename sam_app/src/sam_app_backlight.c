/* The staged scene's back light (sam_app_backlight.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sam/sam_app_backlight.h"
#include "sam/sam_mesh.h"
#include "sam/sam_vec3.h"

#define PI_F 3.14159265f

/* The translucency the camera-facing side receives under `l` alone. */
static sam_status score(sam_runtime *rt, const samfile_data *sam, const float eye[3], const sam_light *l, float *t,
                        double *out, sam_error *err)
{
    sam_status st;
    if ((st = sam_runtime_set_lights(rt, l, 1, err)) != SAM_OK || (st = sam_runtime_irradiance(rt, err)) != SAM_OK ||
        (st = sam_runtime_translucency(rt, 0, 1.0f / 60.0f, 1, err)) != SAM_OK ||
        (st = sam_runtime_read_translucency(rt, t, err)) != SAM_OK)
        return st;
    double sum = 0;
    for (uint32_t v = 0; v < sam->vertex_count; ++v) {
        const float *p = sam->positions + 3 * (size_t)v, *nrm = sam->normals + 3 * (size_t)v;
        const float to_eye[3] = {eye[0] - p[0], eye[1] - p[1], eye[2] - p[2]};
        const float facing = sam_vec3_dot(nrm, to_eye);
        if (facing > 0)
            sum += (0.2126 * t[3 * v] + 0.7152 * t[3 * v + 1] + 0.0722 * t[3 * v + 2]) * sam->fan_area[v];
    }
    *out = sum;
    return SAM_OK;
}

/* The centre of the object's box and half its diagonal (the runtime's
 * bounds, sam_runtime_bounds), loose specks left out (sam_mesh_body): a
 * stray triangle far away put the light farther, and its places
 * elsewhere. */
static sam_status body_sphere(const samfile_data *sam, float centre[3], float *radius, sam_error *err)
{
    const sam_mesh view = {.vertex_count = sam->vertex_count,
                           .positions = sam->positions,
                           .triangle_count = sam->triangle_count,
                           .triangles = sam->triangles};
    sam_mesh_body_info body;
    const sam_status st = sam_mesh_body(&view, NULL, &body, err);
    if (st != SAM_OK)
        return st;
    for (int c = 0; c < 3; ++c)
        centre[c] = 0.5f * (body.min[c] + body.max[c]);
    *radius = (float)(0.5 * sam_mesh_box_diagonal(body.min, body.max));
    return SAM_OK;
}

sam_status sam_app_backlight_place(sam_runtime *rt, const samfile_data *sam, sam_scene *scene, size_t light,
                                   char *note, size_t n, sam_error *err)
{
    if (!scene->has_camera || light >= scene->light_count || scene->lights[light].type != SAM_LIGHT_POINT)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "back light: the scene needs a camera and point light %zu",
                        light);
    const sam_camera *cam = &scene->camera;
    float centre[3], radius = 0, back[3], side[3], up[3];
    sam_status st = body_sphere(sam, centre, &radius, err);
    if (st != SAM_OK)
        return st;
    float *t = malloc((size_t)sam->vertex_count * 3 * sizeof *t);
    if (!t)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "back light: out of memory for %u vertices", sam->vertex_count);
    for (int c = 0; c < 3; ++c)
        back[c] = cam->target[c] - cam->position[c];
    sam_vec3_normalize(back);
    sam_vec3_cross(back, cam->up, side);
    sam_vec3_normalize(side);
    sam_vec3_cross(side, back, up);
    /* Rings at 25, 50 and 75 degrees off the line of sight behind. */
    sam_light best = scene->lights[light], l = best;
    double best_score = -1;
    float best_angle = 0;
    const float dist = 2.0f * radius;
    l.intensity = 4.0f * dist * dist;
    for (int k = 0; k < SAM_APP_BACKLIGHT_CANDIDATES && st == SAM_OK; ++k) {
        const int ring = k == 0 ? 0 : 1 + (k - 1) / 8;
        const float theta = 25.0f * (float)ring * PI_F / 180.0f, phi = 2.0f * PI_F * (float)((k - 1) % 8) / 8.0f;
        for (int c = 0; c < 3; ++c)
            l.position[c] = centre[c] + dist * (cosf(theta) * back[c] +
                                                sinf(theta) * (cosf(phi) * side[c] + sinf(phi) * up[c]));
        double s;
        if ((st = score(rt, sam, cam->position, &l, t, &s, err)) == SAM_OK && s > best_score) {
            best_score = s;
            best = l;
            best_angle = 25.0f * (float)ring;
        }
    }
    free(t);
    if (st != SAM_OK)
        return st;
    scene->lights[light] = best;
    if (note && n && !(best_score > 0))
        snprintf(note, n,
                 "back light: a point light straight behind the object; none of the %d places tried sends any "
                 "translucency to the side the camera sees",
                 SAM_APP_BACKLIGHT_CANDIDATES);
    else if (note && n)
        snprintf(note, n,
                 "back light: a point light %.0f degrees off the line of sight behind the object, where the side "
                 "the camera sees gets the most translucency of %d places tried",
                 best_angle, SAM_APP_BACKLIGHT_CANDIDATES);
    return sam_runtime_set_lights(rt, scene->lights, scene->light_count, err);
}
