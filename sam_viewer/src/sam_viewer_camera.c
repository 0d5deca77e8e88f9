/* The viewer's orbit camera and light dragging (sam_viewer.h). */
#include <math.h>
#include <string.h>

#include "sam/sam_viewer.h"

#define PI_F 3.14159265f

void sam_viewer_eye(const sam_viewer *v, float eye[3])
{
    eye[0] = v->target[0] + v->distance * cosf(v->pitch) * sinf(v->yaw);
    eye[1] = v->target[1] + v->distance * sinf(v->pitch);
    eye[2] = v->target[2] + v->distance * cosf(v->pitch) * cosf(v->yaw);
}

void sam_viewer_frame_all(sam_viewer *v)
{
    memcpy(v->target, v->centre, sizeof v->target);
    v->distance = v->radius / sinf(0.5f * v->fov_deg * PI_F / 180.0f) * 1.05f;
}

void sam_viewer_camera_from(sam_viewer *v, const float eye[3], const float target[3], float fov_deg)
{
    float d[3] = {eye[0] - target[0], eye[1] - target[1], eye[2] - target[2]};
    v->distance = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    memcpy(v->target, target, sizeof v->target);
    v->pitch = asinf(fmaxf(-1.0f, fminf(1.0f, d[1] / v->distance)));
    v->yaw = atan2f(d[0], d[2]);
    v->fov_deg = fov_deg;
}

void sam_viewer_camera_axes(const sam_viewer *v, float right[3], float up[3])
{
    float eye[3];
    sam_viewer_eye(v, eye);
    float f[3] = {v->target[0] - eye[0], v->target[1] - eye[1], v->target[2] - eye[2]};
    float r[3] = {-f[2], 0, f[0]}; /* f x (0, 1, 0) */
    float rl = sqrtf(r[0] * r[0] + r[2] * r[2]);
    /* Looking straight up or down: any horizontal right will do. */
    if (rl < 1e-12f)
        rl = 1, r[0] = 1;
    for (int c = 0; c < 3; ++c)
        right[c] = r[c] / rl;
    float fl = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int c = 0; c < 3; ++c)
        f[c] /= fl;
    up[0] = right[1] * f[2] - right[2] * f[1];
    up[1] = right[2] * f[0] - right[0] * f[2];
    up[2] = right[0] * f[1] - right[1] * f[0];
}

void sam_viewer_orbit(sam_viewer *v, double dx, double dy)
{
    v->yaw -= (float)dx * 0.01f;
    /* Short of the poles, where the up vector would flip. */
    v->pitch = fmaxf(-1.55f, fminf(1.55f, v->pitch + (float)dy * 0.01f));
}

void sam_viewer_pan(sam_viewer *v, double dx, double dy, int height)
{
    float right[3], up[3];
    sam_viewer_camera_axes(v, right, up);
    float per_px = 2.0f * v->distance * tanf(0.5f * v->fov_deg * PI_F / 180.0f) / (float)(height > 0 ? height : 1);
    for (int c = 0; c < 3; ++c)
        v->target[c] += (float)(-dx * right[c] + dy * up[c]) * per_px;
}

/* Turns p about the axis through `centre` along unit `axis` by `angle`;
 * a direction (is_point 0) turns about the origin. */
static void rotate_about(float p[3], const float centre[3], const float axis[3], float angle, int is_point)
{
    float q[3];
    for (int c = 0; c < 3; ++c)
        q[c] = p[c] - (is_point ? centre[c] : 0.0f);
    float cs = cosf(angle), sn = sinf(angle);
    float d = axis[0] * q[0] + axis[1] * q[1] + axis[2] * q[2];
    float x[3] = {axis[1] * q[2] - axis[2] * q[1], axis[2] * q[0] - axis[0] * q[2], axis[0] * q[1] - axis[1] * q[0]};
    for (int c = 0; c < 3; ++c)
        p[c] = q[c] * cs + x[c] * sn + axis[c] * d * (1 - cs) + (is_point ? centre[c] : 0.0f);
}

/* A horizontal drag turns the light about the camera's up axis, a vertical
 * one about its right axis, so it moves the way the cursor does. */
int sam_viewer_drag_light(sam_viewer *v, double dx, double dy)
{
    if (!v->scene.light_count)
        return 0;
    sam_light *l = &v->scene.lights[v->selected_light];
    float right[3], up[3];
    sam_viewer_camera_axes(v, right, up);
    for (int turn = 0; turn < 2; ++turn) {
        const float *axis = turn == 0 ? up : right;
        float angle = (float)(turn == 0 ? dx : dy) * 0.01f;
        rotate_about(l->position, v->centre, axis, angle, 1);
        rotate_about(l->direction, v->centre, axis, angle, 0);
        rotate_about(l->normal, v->centre, axis, angle, 0);
        for (uint32_t k = 0; k < l->vertex_count; ++k)
            rotate_about(l->vertices[k], v->centre, axis, angle, 1);
    }
    return 1;
}

void sam_viewer_apply_view(const sam_viewer *v, sam_render_view *view)
{
    sam_viewer_eye(v, view->eye);
    memcpy(view->target, v->target, sizeof view->target);
    view->up[0] = view->up[2] = 0;
    view->up[1] = 1;
    view->fov_deg = v->fov_deg;
    view->near_plane = view->far_plane = 0;
    view->technique = v->scene.technique;
    if (v->mode == SAM_VIEWER_TRANSLUCENCY) {
        view->front = 0;
    } else if (v->mode == SAM_VIEWER_IRRADIANCE) {
        view->technique = SAM_TECHNIQUE_NONE;
        view->diffusion = 0;
        view->albedo[0] = view->albedo[1] = view->albedo[2] = 1.0f;
    }
}
