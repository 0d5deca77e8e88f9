/* The viewer's state machine: input, frames, text and screenshots'
 * scenes (sam_viewer.h). No GL and no GLFW calls: GLFW's header is read
 * for its key and button codes only. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "sam/sam_light.h"
#include "sam/sam_viewer.h"

static const char *const mode_names[SAM_VIEWER_MODE_COUNT] = {"final", "translucency only", "irradiance", "samples",
                                                              "difference to truth"};

static const char help_text[] =
    "mouse: left drag orbit | right or shift+left drag pan | wheel zoom\n"
    "       middle or ctrl+left drag: move the selected light\n"
    "F frame all      L next light   = - intensity   C colour\n"
    "E environment on/off   , . rotate it\n"
    "T technique      D diffusion    [ ] samples per vertex\n"
    "S smoothing      SPACE play/pause animation\n"
    "V view: final, translucency, irradiance, samples, difference\n"
    "P or F12 screenshot   H or F1 this help   ESC or Q quit";

void sam_viewer_init(sam_viewer *v, const char *shot_prefix)
{
    memset(v, 0, sizeof *v);
    v->button = -1;
    v->smoothing = 1;
    v->reset_t = 1;
    v->shot_prefix = shot_prefix;
}

void sam_viewer_start(sam_viewer *v, uint32_t stride, const float centre[3], float radius, int uv_ok,
                      const float eye[3], const float target[3], float fov_deg)
{
    v->stride = stride;
    memcpy(v->centre, centre, sizeof v->centre);
    v->radius = radius;
    v->uv_ok = uv_ok;
    v->posed = v->scene.deformer_count || v->scene.keyframe_count;
    sam_viewer_camera_from(v, eye, target, fov_deg);
    if (v->scene.diffusion == SAM_DIFFUSION_TEXTURE && !uv_ok)
        v->scene.diffusion = SAM_DIFFUSION_SCREEN;
}

void sam_viewer_destroy(sam_viewer *v)
{
    if (v)
        sam_scene_destroy(&v->scene);
}

void sam_viewer_say(sam_viewer *v, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->message, sizeof v->message, fmt, ap);
    va_end(ap);
    fprintf(stderr, "sam_view: %s\n", v->message);
    v->message_until = (v->clock ? v->clock() : 0.0) + 4.0;
}

/* ---- switches ---- */

static void cycle_technique(sam_viewer *v)
{
    sam_scene *s = &v->scene;
    s->technique = (sam_technique)((s->technique + 1) % (SAM_TECHNIQUE_THICKNESS + 1));
    if (s->technique == SAM_TECHNIQUE_TSM) {
        if (!v->uv_ok) {
            sam_viewer_say(v, "tsm skipped: it needs texture-space diffusion, which this mesh's UVs cannot give");
            s->technique = SAM_TECHNIQUE_TRANSMITTANCE;
        } else if (s->diffusion != SAM_DIFFUSION_TEXTURE) {
            s->diffusion = SAM_DIFFUSION_TEXTURE;
            sam_viewer_say(v, "tsm needs texture-space diffusion: diffusion switched to texture");
        }
    }
    v->reset_t = 1;
}

static void cycle_diffusion(sam_viewer *v)
{
    static const sam_diffusion order[] = {SAM_DIFFUSION_SCREEN, SAM_DIFFUSION_TEXTURE, SAM_DIFFUSION_PREINTEGRATED,
                                          SAM_DIFFUSION_NONE};
    sam_scene *s = &v->scene;
    int i = 0;
    while (order[i] != s->diffusion)
        ++i;
    s->diffusion = order[(i + 1) % 4];
    if (s->diffusion == SAM_DIFFUSION_TEXTURE && !v->uv_ok) {
        sam_viewer_say(v, "texture-space diffusion skipped: the mesh's UVs are missing, overlap or leave [0,1]");
        s->diffusion = SAM_DIFFUSION_PREINTEGRATED;
    }
    if (s->technique == SAM_TECHNIQUE_TSM && s->diffusion != SAM_DIFFUSION_TEXTURE) {
        s->technique = SAM_TECHNIQUE_SAM;
        sam_viewer_say(v, "tsm needs texture-space diffusion: technique switched to sam");
    }
}

static void step_samples(sam_viewer *v, int more)
{
    uint32_t n = sam_viewer_samples_used(v);
    n = more ? (n < v->stride ? n + 1 : n) : (n > 1 ? n - 1 : 1);
    /* All of them is written 0, so a screenshot's scene keeps meaning "all". */
    v->scene.samples_per_vertex = n == v->stride ? 0 : n;
    v->reset_t = 1;
}

/* The selected light's keys: next, brighter, dimmer, next colour. */
static unsigned light_key(sam_viewer *v, int key)
{
    static const float colours[6][3] = {{1, 1, 1}, {1, 0.8f, 0.6f}, {0.65f, 0.8f, 1}, {1, 0.2f, 0.15f},
                                        {0.2f, 1, 0.3f}, {0.25f, 0.4f, 1}};
    sam_scene *s = &v->scene;
    if (!s->light_count)
        return 0;
    sam_light *l = &s->lights[v->selected_light];
    if (key == GLFW_KEY_L) {
        v->selected_light = (v->selected_light + 1) % s->light_count;
        sam_viewer_say(v, "light %zu of %zu selected (%s)", v->selected_light + 1, s->light_count,
                       sam_light_type_name(s->lights[v->selected_light].type));
        return 0;
    }
    if (key == GLFW_KEY_C) {
        int next = 0;
        for (int i = 0; i < 6; ++i)
            if (!memcmp(l->color, colours[i], sizeof l->color))
                next = (i + 1) % 6;
        memcpy(l->color, colours[next], sizeof l->color);
    } else {
        l->intensity *= key == GLFW_KEY_EQUAL ? 1.25f : 0.8f;
    }
    return SAM_VIEWER_LIGHTS;
}

static unsigned environment_key(sam_viewer *v, int key)
{
    if (key == GLFW_KEY_E) {
        if (!v->has_environment) {
            sam_viewer_say(v, "no environment map (give --environment FILE.exr or a scene with one)");
            return 0;
        }
        v->environment_on = !v->environment_on;
    } else {
        float *rotation = &v->scene.environment.rotation_deg;
        *rotation = fmodf(*rotation + (key == GLFW_KEY_PERIOD ? 15.0f : 345.0f), 360.0f);
    }
    return SAM_VIEWER_ENVIRONMENT;
}

unsigned sam_viewer_key(sam_viewer *v, int key, int action)
{
    if (action != GLFW_PRESS && action != GLFW_REPEAT)
        return 0;
    switch (key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
        return SAM_VIEWER_QUIT;
    case GLFW_KEY_F:
        sam_viewer_frame_all(v);
        return 0;
    case GLFW_KEY_L:
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_MINUS:
    case GLFW_KEY_C:
        return light_key(v, key);
    case GLFW_KEY_E:
    case GLFW_KEY_COMMA:
    case GLFW_KEY_PERIOD:
        return environment_key(v, key);
    case GLFW_KEY_T:
        cycle_technique(v);
        return 0;
    case GLFW_KEY_D:
        cycle_diffusion(v);
        return 0;
    case GLFW_KEY_LEFT_BRACKET:
    case GLFW_KEY_RIGHT_BRACKET:
        step_samples(v, key == GLFW_KEY_RIGHT_BRACKET);
        return 0;
    case GLFW_KEY_S:
        v->smoothing = !v->smoothing;
        return 0;
    case GLFW_KEY_SPACE:
        if (!v->posed)
            sam_viewer_say(v, "nothing to play: the scene has no deformers or keyframes");
        v->playing = v->posed && !v->playing;
        return 0;
    case GLFW_KEY_V:
        v->mode = (sam_viewer_mode)((v->mode + 1) % SAM_VIEWER_MODE_COUNT);
        if (v->mode == SAM_VIEWER_DIFFERENCE && !v->has_truth)
            v->mode = SAM_VIEWER_FINAL;
        return 0;
    case GLFW_KEY_P:
    case GLFW_KEY_F12:
        /* Holding the key down must not write a screenshot per repeat. */
        return action == GLFW_PRESS ? SAM_VIEWER_SCREENSHOT : 0;
    case GLFW_KEY_H:
    case GLFW_KEY_F1:
        v->help = !v->help;
        return 0;
    default:
        return 0;
    }
}

/* ---- mouse ---- */

void sam_viewer_button(sam_viewer *v, int button, int action, int mods)
{
    if (action == GLFW_PRESS && v->button < 0) {
        v->button = button;
        v->button_mods = mods;
    } else if (action == GLFW_RELEASE && button == v->button) {
        v->button = -1;
    }
}

unsigned sam_viewer_cursor(sam_viewer *v, double x, double y)
{
    double dx = x - v->cursor_x, dy = y - v->cursor_y;
    v->cursor_x = x;
    v->cursor_y = y;
    int left = v->button == GLFW_MOUSE_BUTTON_LEFT;
    if ((left && (v->button_mods & GLFW_MOD_CONTROL)) || v->button == GLFW_MOUSE_BUTTON_MIDDLE)
        return sam_viewer_drag_light(v, dx, dy) ? SAM_VIEWER_LIGHTS : 0;
    if ((left && (v->button_mods & GLFW_MOD_SHIFT)) || v->button == GLFW_MOUSE_BUTTON_RIGHT)
        sam_viewer_pan(v, dx, dy, v->window_height);
    else if (left)
        sam_viewer_orbit(v, dx, dy);
    return 0;
}

void sam_viewer_scroll(sam_viewer *v, double dy)
{
    v->distance *= powf(0.9f, (float)dy);
    v->distance = fmaxf(v->distance, 1e-3f * v->radius);
}

unsigned sam_viewer_event(sam_viewer *v, const sam_view_event *e)
{
    unsigned effects = 0;
    switch (e->action) {
    case SAM_VIEW_KEY:
        effects = sam_viewer_key(v, e->key, GLFW_PRESS);
        return effects | sam_viewer_key(v, e->key, GLFW_RELEASE);
    case SAM_VIEW_MOUSE:
        return sam_viewer_cursor(v, e->x0, e->y0);
    case SAM_VIEW_DRAG:
        effects = sam_viewer_cursor(v, e->x0, e->y0);
        sam_viewer_button(v, e->button, GLFW_PRESS, 0);
        for (int i = 1; i <= 8; ++i)
            effects |= sam_viewer_cursor(v, e->x0 + (e->x1 - e->x0) * (float)i / 8,
                                         e->y0 + (e->y1 - e->y0) * (float)i / 8);
        sam_viewer_button(v, e->button, GLFW_RELEASE, 0);
        return effects;
    case SAM_VIEW_SCROLL:
        sam_viewer_scroll(v, e->y0);
        return 0;
    case SAM_VIEW_RESIZE:
        return SAM_VIEWER_RESIZE;
    case SAM_VIEW_SCREENSHOT:
        return SAM_VIEWER_SHOT_TO;
    case SAM_VIEW_LOSE_CONTEXT:
        return SAM_VIEWER_LOSE_CONTEXT;
    case SAM_VIEW_QUIT:
        return SAM_VIEWER_QUIT;
    }
    return 0;
}

/* ---- frames and text ---- */

uint32_t sam_viewer_samples_used(const sam_viewer *v)
{
    uint32_t n = v->scene.samples_per_vertex;
    return n && n < v->stride ? n : v->stride;
}

void sam_viewer_frame_plan(sam_viewer *v, double dt, sam_viewer_frame *f)
{
    if (v->playing)
        v->anim_time += dt;
    f->deform = v->posed && (v->playing || v->reset_t);
    f->time_s = (float)v->anim_time;
    f->translucency = v->scene.technique == SAM_TECHNIQUE_SAM;
    f->thickness = v->scene.technique == SAM_TECHNIQUE_THICKNESS;
    f->samples = v->scene.samples_per_vertex;
    f->dt = (float)dt;
    f->reset = v->reset_t || !v->smoothing;
    v->reset_t = 0;
}

int sam_viewer_count_frame(sam_viewer *v, double now)
{
    ++v->fps_frames;
    if (now - v->fps_time < 0.5 && v->status_line[0])
        return 0;
    v->fps = v->fps_frames / fmax(now - v->fps_time, 1e-9);
    v->fps_time = now;
    v->fps_frames = 0;
    return 1;
}

void sam_viewer_set_status(sam_viewer *v, const char *gpu_ms)
{
    snprintf(v->status_line, sizeof v->status_line, "%s | %s | N %u/%u | %s | %s%s\n%.1f fps | GPU ms:%s",
             sam_technique_name(v->scene.technique), sam_diffusion_name(v->scene.diffusion),
             sam_viewer_samples_used(v), v->stride, v->smoothing ? "smoothing" : "no smoothing", mode_names[v->mode],
             v->posed ? (v->playing ? " | playing" : " | paused") : "", v->fps, gpu_ms ? gpu_ms : "");
}

void sam_viewer_title(const sam_viewer *v, char *out, size_t n)
{
    snprintf(out, n, "sam_view - %s", v->status_line);
    char *newline = strchr(out, '\n');
    if (newline)
        *newline = ' ';
}

void sam_viewer_overlay(const sam_viewer *v, double now, char *out, size_t n)
{
    int show_message = now < v->message_until;
    snprintf(out, n, "%s%s%s", v->status_line, show_message ? "\n" : "", show_message ? v->message : "");
}

const char *sam_viewer_help_text(void)
{
    return help_text;
}

/* ---- screenshots ---- */

void sam_viewer_shot_name(sam_viewer *v, const char *prefix, char *out, size_t n)
{
    if (prefix)
        snprintf(out, n, "%s", prefix);
    else
        snprintf(out, n, "%s_%04d", v->shot_prefix ? v->shot_prefix : "sam_view", ++v->shot_number);
}

sam_status sam_viewer_write_scene(sam_viewer *v, const char *path, int width, int height, sam_error *err)
{
    sam_scene *s = &v->scene;
    s->has_camera = 1;
    sam_viewer_eye(v, s->camera.position);
    memcpy(s->camera.target, v->target, sizeof s->camera.target);
    s->camera.up[0] = s->camera.up[2] = 0;
    s->camera.up[1] = 1;
    s->camera.fov_deg = v->fov_deg;
    s->camera.near_plane = s->camera.far_plane = 0;
    s->width = (uint32_t)width;
    s->height = (uint32_t)height;
    s->environment.map = v->environment_on ? v->environment_path : NULL;
    sam_status st = sam_scene_write(path, s, err);
    s->environment.map = v->environment_path;
    return st;
}
