/* The viewer's window: GLFW glue, start-up and the frame loop
 * (sam_viewer_window.h). What input does is sam_viewer.c's; this file
 * carries out the effects it asks for. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>
/* epoxy provides the GL prototypes; GLFW must not include its own. */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "sam/sam_app_backlight.h"
#include "sam/sam_app_stage.h"
#include "sam/sam_app_thickness.h"
#include "sam/sam_light.h"
#include "sam/sam_runtime_scene.h"
#include "sam/sam_viewer_load.h"
#include "sam_viewer_draw.h"

void sam_viewer_window_init(sam_viewer_window *w, const char *shot_prefix)
{
    memset(w, 0, sizeof *w);
    sam_viewer_init(&w->state, shot_prefix);
}

/* ---- effects of input ---- */

static void push_lights(sam_viewer_window *w)
{
    sam_error err;
    if (sam_runtime_set_lights(w->rt, w->state.scene.lights, w->state.scene.light_count, &err) != SAM_OK)
        sam_viewer_say(&w->state, "lights: %s", err.message);
}

static void push_environment(sam_viewer_window *w)
{
    sam_viewer *v = &w->state;
    if (!v->environment_on || !w->environment.pixels) {
        sam_runtime_set_environment(w->rt, NULL);
        return;
    }
    float sh[9][3];
    sam_error err;
    if (sam_light_sh9_from_latlong(&w->environment, v->scene.environment.rotation_deg, v->scene.environment.intensity,
                                   sh, &err) != SAM_OK) {
        sam_viewer_say(v, "environment: %s", err.message);
        v->environment_on = 0;
        sam_runtime_set_environment(w->rt, NULL);
        return;
    }
    sam_runtime_set_environment(w->rt, (const float(*)[3])sh);
}

static void lose_context(sam_viewer_window *w, GLenum status)
{
    const char *why = status == GL_GUILTY_CONTEXT_RESET     ? "this program's commands caused a reset"
                      : status == GL_INNOCENT_CONTEXT_RESET ? "another program caused a reset"
                                                            : "the driver reset it";
    fprintf(stderr, "sam_view: the GL context was lost (%s, status 0x%04x); closing. Start sam_view again to go on.\n",
            why, (unsigned)status);
    w->lost = 1;
    glfwSetWindowShouldClose(w->window, 1);
}

/* Carries out the SAM_VIEWER_* `effects` of an input; `e` is the script's
 * event (NULL for live input). */
static void apply(sam_viewer_window *w, unsigned effects, const sam_view_event *e)
{
    if (effects & SAM_VIEWER_LIGHTS)
        push_lights(w);
    if (effects & SAM_VIEWER_ENVIRONMENT)
        push_environment(w);
    if (effects & SAM_VIEWER_SCREENSHOT)
        sam_viewer_draw_screenshot(w, NULL);
    if (e && (effects & SAM_VIEWER_SHOT_TO))
        sam_viewer_draw_screenshot(w, e->path);
    if (e && (effects & SAM_VIEWER_RESIZE))
        glfwSetWindowSize(w->window, (int)e->x0, (int)e->y0);
    if (effects & SAM_VIEWER_LOSE_CONTEXT)
        lose_context(w, GL_UNKNOWN_CONTEXT_RESET);
    if (effects & SAM_VIEWER_QUIT)
        glfwSetWindowShouldClose(w->window, 1);
}

/* The window's height for the pan's scale, as input arrives. */
static void note_height(sam_viewer_window *w)
{
    glfwGetWindowSize(w->window, NULL, &w->state.window_height);
}

static void on_key(GLFWwindow *window, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    sam_viewer_window *w = glfwGetWindowUserPointer(window);
    apply(w, sam_viewer_key(&w->state, key, action), NULL);
}

static void on_button(GLFWwindow *window, int button, int action, int mods)
{
    sam_viewer_window *w = glfwGetWindowUserPointer(window);
    sam_viewer_button(&w->state, button, action, mods);
}

static void on_cursor(GLFWwindow *window, double x, double y)
{
    sam_viewer_window *w = glfwGetWindowUserPointer(window);
    note_height(w);
    apply(w, sam_viewer_cursor(&w->state, x, y), NULL);
}

static void on_scroll(GLFWwindow *window, double dx, double dy)
{
    (void)dx;
    sam_viewer_window *w = glfwGetWindowUserPointer(window);
    sam_viewer_scroll(&w->state, dy);
}

static void on_glfw_error(int code, const char *message)
{
    fprintf(stderr, "sam_view: window system error 0x%x: %s\n", (unsigned)code, message);
}

/* ---- start-up ---- */

/* A window with an OpenGL 4.3 core context, robust if the driver can. */
static GLFWwindow *open_window(int width, int height, sam_error *err)
{
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_CONTEXT_ROBUSTNESS, GLFW_LOSE_CONTEXT_ON_RESET);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, sam_gl_debug_requested() ? GLFW_TRUE : GLFW_FALSE);
    GLFWwindow *window = glfwCreateWindow(width, height, "sam_view", NULL, NULL);
    if (!window) {
        glfwWindowHint(GLFW_CONTEXT_ROBUSTNESS, GLFW_NO_ROBUSTNESS);
        window = glfwCreateWindow(width, height, "sam_view", NULL, NULL);
    }
    if (!window) {
        const char *why = NULL;
        glfwGetError(&why);
        sam_fail(err, SAM_ERR_UNSUPPORTED, "cannot open a window with OpenGL 4.3 core: %s",
                 why ? why : "unknown reason");
    }
    return window;
}

/* GLFW, the window at the asked size (or the scene's, fitted to 1600 x
 * 1000) and its context made current. */
static sam_status start_window(sam_viewer_window *w, int width, int height, sam_error *err)
{
    if (!glfwInit()) {
        const char *why = NULL;
        glfwGetError(&why);
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "cannot reach a window system: %s (is DISPLAY set? sam_render renders without one)",
                        why ? why : "unknown reason");
    }
    w->glfw_up = 1;
    w->state.clock = glfwGetTime;
    const sam_scene *s = &w->state.scene;
    if (!width) {
        float fit = fminf(1.0f, fminf(1600.0f / (float)s->width, 1000.0f / (float)s->height));
        width = (int)fmaxf(16.0f, (float)s->width * fit);
        height = (int)fmaxf(16.0f, (float)s->height * fit);
    }
    if (!(w->window = open_window(width, height, err)))
        return err->status;
    /* Failures until here are reported once, by the caller; later ones as they come. */
    glfwSetErrorCallback(on_glfw_error);
    glfwSetWindowUserPointer(w->window, w);
    glfwMakeContextCurrent(w->window);
    glfwSwapInterval(0);
    return SAM_OK;
}

/* The truth image as a texture for the difference view. */
static void upload_truth(sam_viewer_window *w)
{
    const sam_image *t = &w->truth;
    /* Images run top-down; the shader flips. */
    glGenTextures(1, &w->truth_tex);
    glBindTexture(GL_TEXTURE_2D, w->truth_tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, (GLsizei)t->width, (GLsizei)t->height);
    GLenum format = t->channels == 4 ? GL_RGBA : t->channels == 3 ? GL_RGB : GL_RED;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)t->width, (GLsizei)t->height, format, GL_FLOAT, t->pixels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

/* The environment map and the truth image; either missing or unreadable is
 * said and left out, not fatal. */
static void load_images(sam_viewer_window *w, const char *truth)
{
    sam_viewer *v = &w->state;
    if (v->scene.environment.map) {
        v->environment_path = v->scene.environment.map;
        sam_error env_err;
        if (sam_image_read_exr(v->environment_path, &w->environment, &env_err) != SAM_OK)
            sam_viewer_say(v, "environment off: %s", env_err.message);
        else
            v->environment_on = v->has_environment = 1;
    }
    if (truth) {
        sam_error truth_err;
        if (sam_image_read_exr(truth, &w->truth, &truth_err) != SAM_OK) {
            sam_viewer_say(v, "no difference view: %s", truth_err.message);
        } else {
            upload_truth(w);
            v->has_truth = 1;
            fprintf(stderr, "sam_view: truth %s (%ux%u); it matches the view at the scene's camera and size\n",
                    truth, w->truth.width, w->truth.height);
        }
    }
}

sam_status sam_viewer_window_open(sam_viewer_window *w, const sam_viewer_window_options *o,
                                  const sam_profile *profile, float mm_per_unit, sam_error *err)
{
    sam_viewer *v = &w->state;
    sam_status st = start_window(w, o->width, o->height, err);
    sam_gl_info info;
    if (st != SAM_OK || (st = sam_gl_check_current(sam_gl_debug_requested(), &info, err)) != SAM_OK ||
        (st = sam_runtime_create(&w->sam, profile, mm_per_unit, &w->rt, err)) != SAM_OK)
        return st;
    w->mm_per_unit = mm_per_unit;
    uint32_t stride = sam_runtime_samples_per_vertex(w->rt);
    fprintf(stderr, "sam_view: %s, OpenGL %s; %u vertices, N = %u\n", info.renderer, info.version,
            w->sam.vertex_count, stride);
    char note[512];
    if (sam_runtime_fitted_note(w->rt, note, sizeof note))
        fprintf(stderr, "sam_view: warning: %s\n", note);
    float centre[3], radius;
    sam_runtime_bounds(w->rt, centre, &radius);
    char warning[512];
    if ((o->default_lights && (st = sam_viewer_default_lights(&v->scene, centre, radius, err)) != SAM_OK) ||
        (st = sam_runtime_scene_setup(w->rt, &v->scene, NULL, NULL, warning, sizeof warning, err)) != SAM_OK ||
        (st = sam_runtime_scene_keyframes(w->rt, &v->scene, &w->sam, err)) != SAM_OK)
        return st;
    if (o->staged) {
        char note[256];
        if ((st = sam_app_backlight_place(w->rt, &w->sam, &v->scene, SAM_APP_STAGE_BACK_LIGHT, note, sizeof note,
                                          err)) != SAM_OK)
            return st;
        fprintf(stderr, "sam_view: %s\n", note);
    }
    if ((st = sam_viewer_draw_create(w, err)) != SAM_OK)
        return st;
    load_images(w, o->truth);
    if (warning[0])
        sam_viewer_say(v, "%s", warning);
    size_t n = w->sam.vertex_count;
    w->positions = malloc(n * 3 * sizeof *w->positions);
    w->sample_index = malloc(n * stride * sizeof *w->sample_index);
    w->sample_kprime = malloc(n * stride * 3 * sizeof *w->sample_kprime);
    if (!w->positions || !w->sample_index || !w->sample_kprime)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the samples view");
    sam_render_view start;
    sam_runtime_scene_view(w->rt, &v->scene, &start, NULL, 0);
    sam_viewer_start(v, stride, centre, radius, sam_runtime_uv_status(w->rt, NULL, 0, NULL), start.eye, start.target,
                     start.fov_deg);
    glfwSetKeyCallback(w->window, on_key);
    glfwSetMouseButtonCallback(w->window, on_button);
    glfwSetCursorPosCallback(w->window, on_cursor);
    glfwSetScrollCallback(w->window, on_scroll);
    glfwGetCursorPos(w->window, &v->cursor_x, &v->cursor_y);
    return SAM_OK;
}

/* ---- the frame loop ---- */

/* The local thickness, measured the first time the technique is shown
 * (most sessions never show it). 1 when it is on the GPU; else it is said
 * and the technique goes back to sam. */
static int ensure_thickness(sam_viewer_window *w)
{
    sam_error err;
    float *mm;
    sam_status st = sam_app_thickness(&w->sam, w->mm_per_unit, "sam_view", &mm, &err);
    if (st == SAM_OK) {
        st = sam_runtime_set_thickness(w->rt, mm, w->sam.vertex_count, &err);
        free(mm);
    }
    if (st == SAM_OK) {
        w->thickness_ready = 1;
        return 1;
    }
    sam_viewer_say(&w->state, "thickness unavailable: %s", err.message);
    w->state.scene.technique = SAM_TECHNIQUE_SAM;
    return 0;
}

/* The SAM passes of one frame. */
static void update(sam_viewer_window *w, double dt)
{
    sam_viewer *v = &w->state;
    sam_viewer_frame f;
    sam_error err;
    sam_viewer_frame_plan(v, dt, &f);
    if (f.thickness && !w->thickness_ready && !ensure_thickness(w)) {
        /* Back to sam, whose pass starts from a fresh history. */
        f.thickness = 0;
        f.translucency = f.reset = 1;
    }
    if (f.deform && (sam_runtime_deform(w->rt, f.time_s, &err) != SAM_OK || sam_runtime_walk(w->rt, &err) != SAM_OK)) {
        sam_viewer_say(v, "deformation stopped: %s", err.message);
        v->playing = 0;
    }
    if (sam_runtime_irradiance(w->rt, &err) != SAM_OK ||
        (f.translucency && sam_runtime_translucency(w->rt, f.samples, f.dt, f.reset, &err) != SAM_OK))
        sam_viewer_say(v, "frame: %s", err.message);
}

/* The readout with each pass's GPU time, and the title from it. */
static void refresh_readout(sam_viewer_window *w, double now)
{
    if (!sam_viewer_count_frame(&w->state, now))
        return;
    static const sam_pass passes[] = {SAM_PASS_IRRADIANCE, SAM_PASS_TRANSLUCENCY, SAM_PASS_SHADE,
                                      SAM_PASS_DIFFUSION, SAM_PASS_DEFORM, SAM_PASS_WALK, SAM_PASS_NODES};
    static const char *const names[] = {"irr", "transl", "shade", "diff", "deform", "walk", "nodes"};
    char ms[160] = "";
    size_t len = 0;
    for (size_t i = 0; i < sizeof passes / sizeof passes[0]; ++i) {
        double t = sam_runtime_pass_ms(w->rt, passes[i]);
        if (t >= 0 && len < sizeof ms)
            len += (size_t)snprintf(ms + len, sizeof ms - len, " %s %.2f", names[i], t);
    }
    sam_viewer_set_status(&w->state, ms);
    char title[400];
    sam_viewer_title(&w->state, title, sizeof title);
    glfwSetWindowTitle(w->window, title);
}

static int check_reset(sam_viewer_window *w)
{
    if (epoxy_gl_version() < 45 && !epoxy_has_gl_extension("GL_KHR_robustness"))
        return 0;
    GLenum status = glGetGraphicsResetStatus();
    if (status != GL_NO_ERROR)
        lose_context(w, status);
    return status != GL_NO_ERROR;
}

/* Runs the script's events due by `now` seconds since the start from
 * `*next` on, in order; a screenshot ends the batch so the next one sees a
 * new frame. */
static void run_events(sam_viewer_window *w, const sam_view_event *events, size_t event_count, size_t *next,
                       double now)
{
    while (*next < event_count && events[*next].time_s <= now && !glfwWindowShouldClose(w->window)) {
        const sam_view_event *e = &events[(*next)++];
        /* The screenshot shows this frame's state with the passes run. */
        if (e->action == SAM_VIEW_SCREENSHOT)
            update(w, 0);
        note_height(w);
        apply(w, sam_viewer_event(&w->state, e), e);
        if (e->action == SAM_VIEW_SCREENSHOT)
            break;
    }
}

int sam_viewer_window_run(sam_viewer_window *w, const sam_view_event *events, size_t event_count, float fps)
{
    size_t next = 0;
    double start = fps > 0 ? 0 : glfwGetTime(), last = start;
    for (long frame = 0; !glfwWindowShouldClose(w->window); ++frame) {
        glfwPollEvents();
        double now = fps > 0 ? (double)frame / fps : glfwGetTime();
        run_events(w, events, event_count, &next, now - start);
        if (glfwWindowShouldClose(w->window) || check_reset(w))
            break;
        double dt = now - last;
        last = now;
        update(w, dt);
        int width, height;
        glfwGetFramebufferSize(w->window, &width, &height);
        if (width > 0 && height > 0) {
            refresh_readout(w, glfwGetTime());
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            sam_viewer_draw_frame(w, width, height, 1, glfwGetTime());
        }
        glfwSwapBuffers(w->window);
    }
    return w->lost ? 1 : 0;
}

void sam_viewer_window_destroy(sam_viewer_window *w)
{
    if (w->window) {
        sam_viewer_draw_destroy(w);
        glDeleteTextures(1, &w->truth_tex);
        sam_runtime_destroy(w->rt);
        glfwDestroyWindow(w->window);
    }
    free(w->sample_index);
    free(w->sample_kprime);
    free(w->positions);
    sam_image_destroy(&w->environment);
    sam_image_destroy(&w->truth);
    samfile_free(&w->sam);
    sam_viewer_destroy(&w->state);
    if (w->glfw_up)
        glfwTerminate();
    w->window = NULL;
    w->glfw_up = 0;
}
