/*
 * sam_view: the real-time viewer. A GLFW window (OpenGL 4.3 core) on the
 * runtime sam_render uses: orbit the camera, drag the lights, switch the
 * translucency technique, the diffusion, the samples per vertex and the
 * view mode, play deformations, and take screenshots that sam_render
 * reproduces. `--script FILE` drives it with timed input (sam_view_script.h).
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <epoxy/gl.h>
/* epoxy provides the GL prototypes; GLFW must not include its own. */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <cjson/cJSON.h>
#include <stb/stb_easy_font.h>

#include "sam/sam_app.h"
#include "sam/sam_app_scene.h"
#include "sam/sam_light.h"
#include "sam/sam_runtime_scene.h"
#include "sam/sam_sha256.h"
#include "sam/sam_view_script.h"

#define PI_F 3.14159265f
#define TEXT_SCALE 2.0f
#define PICK_RADIUS_PX 12.0

/* Set by SIGINT/SIGTERM during a build: the progress callback cancels it.
 * The one global a signal handler needs. */
static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_view SCENE.json | FILE.sam | MESH [options]\n"
            "\n"
            "Shows the object in a window with real-time SAM translucency. A bare mesh (.obj, .ply,\n"
            ".off, .stl) or a scene naming only a mesh has its map built first, with a progress bar,\n"
            "and cached (a cached map is used again while the mesh's SHA-256, the material, the scale\n"
            "and N match). A .sam or a bare mesh is lit from behind and dimly from the front.\n"
            "options:\n"
            "  --material M         material of a bare mesh (a preset or a profile file; default skin)\n"
            "  --size-mm D          a bare mesh's bounding-box diagonal in mm (default 60)\n"
            "  --environment E.exr  a lat-long environment for a bare mesh or .sam\n"
            "  --truth T.exr        a ground-truth image for the difference view (same camera and size)\n"
            "  --size WxH           window size in pixels (default: the scene's resolution, at most\n"
            "                       1600x1000)\n"
            "  --shot PREFIX        screenshot names: PREFIX_0001.exr/.png/.json ... (default sam_view)\n"
            "  --cache DIR          where built maps are kept (default $XDG_CACHE_HOME/sam_view or\n"
            "                       ~/.cache/sam_view)\n"
            "  --no-cache           build without reading or writing the cache\n"
            "  --script FILE        timed key and mouse events (see README: sam_view)\n"
            "  --fps F              a fixed clock: every frame advances time by 1/F, however long it\n"
            "                       took (frame-exact scripts and animation); default: the wall clock\n"
            "  -h, --help           this help\n"
            "\n"
            "mouse:\n"
            "  left drag            orbit the camera about its target\n"
            "  right drag           pan (shift + left drag too)\n"
            "  wheel                zoom\n"
            "  middle drag          move the selected light around the object (ctrl + left drag too)\n"
            "keys:\n"
            "  F                    frame the whole object\n"
            "  L                    select the next light\n"
            "  = / -                selected light's intensity x1.25 / /1.25\n"
            "  C                    selected light's colour: white, warm, cool, red, green, blue\n"
            "  E                    environment on / off;  , and .  rotate it by 15 degrees\n"
            "  T                    technique: sam, none, tsm, transmittance\n"
            "  D                    diffusion: screen, texture, pre-integrated, none\n"
            "  [ and ]              fewer / more samples per vertex (of those the .sam holds)\n"
            "  S                    temporal smoothing on / off\n"
            "  SPACE                play / pause the animation (scenes with deformers or keyframes)\n"
            "  V                    view: final, translucency only, irradiance, samples under the\n"
            "                       cursor as lines, difference to --truth\n"
            "  P or F12             screenshot (EXR, PNG and a scene file sam_render reproduces)\n"
            "  H or F1              this help in the window\n"
            "  ESCAPE or Q          quit\n"
            "The title bar shows frames per second and each pass's GPU milliseconds.\n");
}

typedef enum view_mode {
    MODE_FINAL = 0,
    MODE_TRANSLUCENCY,
    MODE_IRRADIANCE,
    MODE_SAMPLES,
    MODE_DIFFERENCE,
    MODE_COUNT
} view_mode;

static const char *const mode_names[MODE_COUNT] = {"final", "translucency only", "irradiance", "samples",
                                                   "difference to truth"};

typedef struct viewer {
    GLFWwindow *window;
    sam_scene scene; /* the state a screenshot writes: lights, camera, switches */
    samfile_data sam;
    sam_runtime *rt;
    uint32_t stride; /* samples the .sam holds per vertex */
    int posed;
    float centre[3], radius;

    float target[3], yaw, pitch, distance, fov_deg;

    char *environment_path; /* kept while the environment is switched off */
    sam_image environment;
    int environment_on;
    sam_image truth;
    GLuint truth_tex;

    view_mode mode;
    int help, smoothing, playing, reset_t;
    double anim_time;
    size_t selected_light;

    GLuint present_program, lines_program, text_program;
    GLuint empty_vao, lines_vao, lines_vbo, text_vao, text_vbo;
    GLuint shot_fbo, shot_tex;
    int shot_width, shot_height;

    double cursor_x, cursor_y;
    int button; /* the button held, -1 for none */
    int button_mods;

    double fps, fps_time;
    int fps_frames;
    char status_line[256];
    char message[256];
    double message_until;

    const char *shot_prefix;
    int shot_number;
    int lost;
    uint32_t *sample_index; /* read back for the samples view */
    float *sample_kprime, *positions;
} viewer;

static void say(viewer *v, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* A message on the terminal and for a few seconds in the window. */
static void say(viewer *v, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->message, sizeof v->message, fmt, ap);
    va_end(ap);
    fprintf(stderr, "sam_view: %s\n", v->message);
    v->message_until = glfwGetTime() + 4.0;
}

/* ---- the object: scene, map (built and cached), runtime ---- */

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && !strcmp(s + n - m, suffix);
}

/* mkdir -p */
static sam_status make_dirs(const char *path, sam_error *err)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "cache: path %s is too long", path);
    for (char *p = buf + 1;; ++p) {
        if (*p == '/' || !*p) {
            char c = *p;
            *p = 0;
            if (mkdir(buf, 0755) != 0 && errno != EEXIST)
                return sam_fail(err, SAM_ERR_IO, "cache: cannot create %s: %s", buf, strerror(errno));
            *p = c;
            if (!c)
                break;
        }
    }
    return SAM_OK;
}

/* Where the map of the scene's mesh is cached: a name from the mesh's
 * SHA-256 and everything else the build depends on, so a changed mesh,
 * material or scale never reads a stale map. */
static sam_status cache_path(const char *dir, const sam_scene *scene, char *out, size_t n, sam_error *err)
{
    char mesh_hash[65];
    sam_status st = sam_sha256_file(scene->mesh_path, mesh_hash, err);
    if (st != SAM_OK)
        return st;
    sam_build_settings settings;
    sam_build_default_settings(&settings);
    char key[512];
    snprintf(key, sizeof key, "%s\n%s\n%d %.9g\n%u %u %llu", mesh_hash, scene->material ? scene->material : "",
             (int)scene->scale_kind, scene->scale_value, settings.samples_per_vertex, settings.mc_samples,
             (unsigned long long)settings.seed);
    sam_sha256 h;
    uint8_t digest[32];
    sam_sha256_init(&h);
    sam_sha256_update(&h, key, strlen(key));
    sam_sha256_final(&h, digest);
    const char *base = strrchr(scene->mesh_path, '/');
    base = base ? base + 1 : scene->mesh_path;
    int len = snprintf(out, n, "%s/%.*s-", dir, (int)strcspn(base, "."), base);
    for (int i = 0; i < 8 && len > 0 && (size_t)len + 2 < n; ++i)
        len += snprintf(out + len, n - (size_t)len, "%02x", digest[i]);
    if (len < 0 || (size_t)len + 5 > n)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "cache: path in %s is too long", dir);
    strcat(out, ".sam");
    return SAM_OK;
}

static void default_cache_dir(char *out, size_t n)
{
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (xdg && xdg[0])
        snprintf(out, n, "%s/sam_view", xdg);
    else
        snprintf(out, n, "%s/.cache/sam_view", home && home[0] ? home : "/tmp");
}

/* The scene's map: read, or built (progress bar) and cached. */
static sam_status load_map(viewer *v, const char *cache_dir, int use_cache, sam_profile *profile, float *mm_per_unit,
                           sam_error *err)
{
    sam_scene *s = &v->scene;
    char cached[4096] = "";
    if (s->mesh_path && !s->sam_path && use_cache) {
        sam_status st = cache_path(cache_dir, s, cached, sizeof cached, err);
        if (st != SAM_OK)
            return st;
        struct stat info;
        if (stat(cached, &info) == 0) {
            s->sam_path = sam_strdup(cached);
            if (!s->sam_path)
                return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
            sam_error cache_err;
            if (sam_app_scene_object(s, NULL, NULL, NULL, &v->sam, profile, mm_per_unit, NULL, &cache_err) ==
                SAM_OK) {
                fprintf(stderr, "sam_view: using the cached map %s\n", cached);
                return SAM_OK;
            }
            /* A damaged or mismatched cache entry is rebuilt, not fatal. */
            fprintf(stderr, "sam_view: rebuilding the cached map: %s\n", cache_err.message);
            free(s->sam_path);
            s->sam_path = NULL;
        }
    }
    sam_app_progress bar;
    sam_app_progress_init(&bar, "sam_view", 0, &interrupted);
    double seconds;
    if (s->mesh_path && !s->sam_path)
        fprintf(stderr, "sam_view: building the map of %s\n", s->mesh_path);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    sam_status st =
        sam_app_scene_object(s, NULL, sam_app_progress_update, &bar, &v->sam, profile, mm_per_unit, &seconds, err);
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    if (bar.open_line)
        fputc('\n', stderr);
    if (st != SAM_OK || !cached[0])
        return st;
    fprintf(stderr, "sam_view: built in %.1f s (%u vertices)\n", seconds, v->sam.vertex_count);
    sam_error cache_err;
    if (make_dirs(cache_dir, &cache_err) != SAM_OK || samfile_write(cached, &v->sam, &cache_err) != SAM_OK) {
        fprintf(stderr, "sam_view: warning: the map is not cached: %s\n", cache_err.message);
        return SAM_OK;
    }
    /* Screenshots name the cached map, so sam_render need not build it. */
    s->sam_path = sam_strdup(cached);
    return s->sam_path ? SAM_OK : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
}

/* A scene for a bare mesh or .sam, written as JSON and parsed, so it goes
 * through the scene loader's checks like any scene file. */
static sam_status bare_scene(const char *input, int is_sam, const char *material, float size_mm,
                             const char *environment, sam_scene *scene, sam_error *err)
{
    cJSON *root = cJSON_CreateObject();
    if (!root)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
    cJSON_AddStringToObject(root, is_sam ? "sam" : "mesh", input);
    if (!is_sam || material)
        cJSON_AddStringToObject(root, "material", material ? material : "skin");
    if (!is_sam) {
        cJSON *scale = cJSON_AddObjectToObject(root, "scale");
        if (scale)
            cJSON_AddNumberToObject(scale, "size_mm", size_mm);
    }
    if (environment) {
        cJSON *env = cJSON_AddObjectToObject(root, "environment");
        if (env)
            cJSON_AddStringToObject(env, "map", environment);
    }
    char *text = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    if (!text)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
    sam_status st = sam_scene_parse(text, strlen(text), NULL, input, scene, err);
    free(text);
    return st;
}

/* Lights for a bare mesh or .sam: a point light behind the object (as
 * seen from the camera) that shines through its thin parts, and a dim one
 * in front so its shape reads. */
static sam_status default_lights(viewer *v, sam_error *err)
{
    sam_scene *s = &v->scene;
    s->lights = calloc(2, sizeof *s->lights);
    if (!s->lights)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
    s->light_count = 2;
    for (int i = 0; i < 2; ++i) {
        sam_light *l = &s->lights[i];
        l->type = SAM_LIGHT_POINT;
        l->shadow = 1;
        for (int c = 0; c < 3; ++c)
            l->color[c] = 1.0f;
        float side = i == 0 ? -2.5f : 3.0f;
        l->position[0] = v->centre[0] + (i == 0 ? 0.3f : -0.8f) * v->radius;
        l->position[1] = v->centre[1] + 0.5f * v->radius;
        l->position[2] = v->centre[2] + side * v->radius;
        /* Intensity in the scene's units: about 1 of irradiance at the object. */
        float d = (i == 0 ? 2.5f : 3.0f) * v->radius;
        l->intensity = (i == 0 ? 2.0f : 0.25f) * d * d;
    }
    return SAM_OK;
}

/* ---- camera ---- */

static void camera_eye(const viewer *v, float eye[3])
{
    eye[0] = v->target[0] + v->distance * cosf(v->pitch) * sinf(v->yaw);
    eye[1] = v->target[1] + v->distance * sinf(v->pitch);
    eye[2] = v->target[2] + v->distance * cosf(v->pitch) * cosf(v->yaw);
}

static void frame_all(viewer *v)
{
    memcpy(v->target, v->centre, sizeof v->target);
    v->distance = v->radius / sinf(0.5f * v->fov_deg * PI_F / 180.0f) * 1.05f;
}

/* The orbit from a look-at camera (+Y up). */
static void camera_from(viewer *v, const float eye[3], const float target[3], float fov_deg)
{
    float d[3] = {eye[0] - target[0], eye[1] - target[1], eye[2] - target[2]};
    v->distance = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    memcpy(v->target, target, sizeof v->target);
    v->pitch = asinf(fmaxf(-1.0f, fminf(1.0f, d[1] / v->distance)));
    v->yaw = atan2f(d[0], d[2]);
    v->fov_deg = fov_deg;
}

/* The camera's right and up unit vectors. */
static void camera_axes(const viewer *v, float right[3], float up[3])
{
    float eye[3];
    camera_eye(v, eye);
    float f[3] = {v->target[0] - eye[0], v->target[1] - eye[1], v->target[2] - eye[2]};
    float r[3] = {-f[2], 0, f[0]}; /* f x (0, 1, 0) */
    float rl = sqrtf(r[0] * r[0] + r[2] * r[2]);
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

static void make_view(const viewer *v, int width, int height, sam_render_view *view)
{
    char warning[256];
    sam_runtime_scene_view(v->rt, &v->scene, view, warning, sizeof warning);
    view->width = (uint32_t)width;
    view->height = (uint32_t)height;
    camera_eye(v, view->eye);
    memcpy(view->target, v->target, sizeof view->target);
    view->up[0] = view->up[2] = 0;
    view->up[1] = 1;
    view->fov_deg = v->fov_deg;
    view->near_plane = view->far_plane = 0;
    view->technique = v->scene.technique;
    if (v->mode == MODE_TRANSLUCENCY) {
        view->front = 0;
    } else if (v->mode == MODE_IRRADIANCE) {
        view->technique = SAM_TECHNIQUE_NONE;
        view->diffusion = 0;
        view->albedo[0] = view->albedo[1] = view->albedo[2] = 1.0f;
    }
}

/* ---- lights and environment ---- */

/* Turns p about the axis through `centre` along unit `axis` by `angle`. */
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

static void push_lights(viewer *v)
{
    sam_error err;
    if (sam_runtime_set_lights(v->rt, v->scene.lights, v->scene.light_count, &err) != SAM_OK)
        say(v, "lights: %s", err.message);
}

/* Moves the selected light around the object: a horizontal drag turns it
 * about the camera's up axis, a vertical one about its right axis. */
static void drag_light(viewer *v, double dx, double dy)
{
    if (!v->scene.light_count)
        return;
    sam_light *l = &v->scene.lights[v->selected_light];
    float right[3], up[3];
    camera_axes(v, right, up);
    for (int turn = 0; turn < 2; ++turn) {
        const float *axis = turn == 0 ? up : right;
        float angle = (float)(turn == 0 ? dx : dy) * 0.01f;
        rotate_about(l->position, v->centre, axis, angle, 1);
        rotate_about(l->direction, v->centre, axis, angle, 0);
        rotate_about(l->normal, v->centre, axis, angle, 0);
        for (uint32_t k = 0; k < l->vertex_count; ++k)
            rotate_about(l->vertices[k], v->centre, axis, angle, 1);
    }
    push_lights(v);
}

static void push_environment(viewer *v)
{
    if (!v->environment_on || !v->environment.pixels) {
        sam_runtime_set_environment(v->rt, NULL);
        return;
    }
    float sh[9][3];
    sam_error err;
    if (sam_light_sh9_from_latlong(&v->environment, v->scene.environment.rotation_deg,
                                   v->scene.environment.intensity, sh, &err) != SAM_OK) {
        say(v, "environment: %s", err.message);
        v->environment_on = 0;
        sam_runtime_set_environment(v->rt, NULL);
        return;
    }
    sam_runtime_set_environment(v->rt, (const float(*)[3])sh);
}

/* ---- switches ---- */

static void cycle_technique(viewer *v)
{
    sam_scene *s = &v->scene;
    s->technique = (sam_technique)((s->technique + 1) % 4);
    if (s->technique == SAM_TECHNIQUE_TSM) {
        if (!sam_runtime_uv_status(v->rt, NULL, 0)) {
            say(v, "tsm skipped: it needs texture-space diffusion, which this mesh's UVs cannot give");
            s->technique = SAM_TECHNIQUE_TRANSMITTANCE;
        } else if (s->diffusion != SAM_DIFFUSION_TEXTURE) {
            s->diffusion = SAM_DIFFUSION_TEXTURE;
            say(v, "tsm needs texture-space diffusion: diffusion switched to texture");
        }
    }
    v->reset_t = 1;
}

static void cycle_diffusion(viewer *v)
{
    static const sam_diffusion order[] = {SAM_DIFFUSION_SCREEN, SAM_DIFFUSION_TEXTURE, SAM_DIFFUSION_PREINTEGRATED,
                                          SAM_DIFFUSION_NONE};
    sam_scene *s = &v->scene;
    int i = 0;
    while (order[i] != s->diffusion)
        ++i;
    s->diffusion = order[(i + 1) % 4];
    if (s->diffusion == SAM_DIFFUSION_TEXTURE && !sam_runtime_uv_status(v->rt, NULL, 0)) {
        say(v, "texture-space diffusion skipped: the mesh's UVs are missing, overlap or leave [0,1]");
        s->diffusion = SAM_DIFFUSION_PREINTEGRATED;
    }
    if (s->technique == SAM_TECHNIQUE_TSM && s->diffusion != SAM_DIFFUSION_TEXTURE) {
        s->technique = SAM_TECHNIQUE_SAM;
        say(v, "tsm needs texture-space diffusion: technique switched to sam");
    }
}

static uint32_t samples_used(const viewer *v)
{
    uint32_t n = v->scene.samples_per_vertex;
    return n && n < v->stride ? n : v->stride;
}

static void screenshot(viewer *v, const char *prefix);
static void lose_context(viewer *v, GLenum status);

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    viewer *v = glfwGetWindowUserPointer(w);
    if (action != GLFW_PRESS && action != GLFW_REPEAT)
        return;
    sam_scene *s = &v->scene;
    sam_light *l = s->light_count ? &s->lights[v->selected_light] : NULL;
    static const float colours[6][3] = {{1, 1, 1}, {1, 0.8f, 0.6f}, {0.65f, 0.8f, 1}, {1, 0.2f, 0.15f},
                                        {0.2f, 1, 0.3f}, {0.25f, 0.4f, 1}};
    (void)mods;
    switch (key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
        glfwSetWindowShouldClose(w, 1);
        break;
    case GLFW_KEY_F:
        frame_all(v);
        break;
    case GLFW_KEY_L:
        if (s->light_count) {
            v->selected_light = (v->selected_light + 1) % s->light_count;
            say(v, "light %zu of %zu selected (%s)", v->selected_light + 1, s->light_count,
                sam_light_type_name(s->lights[v->selected_light].type));
        }
        break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_MINUS:
        if (l) {
            l->intensity *= key == GLFW_KEY_EQUAL ? 1.25f : 0.8f;
            push_lights(v);
        }
        break;
    case GLFW_KEY_C:
        if (l) {
            int next = 0;
            for (int i = 0; i < 6; ++i)
                if (!memcmp(l->color, colours[i], sizeof l->color))
                    next = (i + 1) % 6;
            memcpy(l->color, colours[next], sizeof l->color);
            push_lights(v);
        }
        break;
    case GLFW_KEY_E:
        if (!v->environment.pixels) {
            say(v, "no environment map (give --environment FILE.exr or a scene with one)");
            break;
        }
        v->environment_on = !v->environment_on;
        push_environment(v);
        break;
    case GLFW_KEY_COMMA:
    case GLFW_KEY_PERIOD:
        s->environment.rotation_deg = fmodf(s->environment.rotation_deg + (key == GLFW_KEY_PERIOD ? 15.0f : 345.0f),
                                            360.0f);
        push_environment(v);
        break;
    case GLFW_KEY_T:
        cycle_technique(v);
        break;
    case GLFW_KEY_D:
        cycle_diffusion(v);
        break;
    case GLFW_KEY_LEFT_BRACKET:
    case GLFW_KEY_RIGHT_BRACKET: {
        uint32_t n = samples_used(v);
        n = key == GLFW_KEY_RIGHT_BRACKET ? (n < v->stride ? n + 1 : n) : (n > 1 ? n - 1 : 1);
        s->samples_per_vertex = n == v->stride ? 0 : n;
        v->reset_t = 1;
        break;
    }
    case GLFW_KEY_S:
        v->smoothing = !v->smoothing;
        break;
    case GLFW_KEY_SPACE:
        if (!v->posed)
            say(v, "nothing to play: the scene has no deformers or keyframes");
        v->playing = v->posed && !v->playing;
        break;
    case GLFW_KEY_V:
        v->mode = (view_mode)((v->mode + 1) % MODE_COUNT);
        if (v->mode == MODE_DIFFERENCE && !v->truth_tex)
            v->mode = MODE_FINAL;
        break;
    case GLFW_KEY_P:
    case GLFW_KEY_F12:
        if (action == GLFW_PRESS)
            screenshot(v, NULL);
        break;
    case GLFW_KEY_H:
    case GLFW_KEY_F1:
        v->help = !v->help;
        break;
    default:
        break;
    }
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    viewer *v = glfwGetWindowUserPointer(w);
    if (action == GLFW_PRESS && v->button < 0) {
        v->button = button;
        v->button_mods = mods;
    } else if (action == GLFW_RELEASE && button == v->button) {
        v->button = -1;
    }
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    viewer *v = glfwGetWindowUserPointer(w);
    double dx = x - v->cursor_x, dy = y - v->cursor_y;
    v->cursor_x = x;
    v->cursor_y = y;
    int left = v->button == GLFW_MOUSE_BUTTON_LEFT;
    if ((left && (v->button_mods & GLFW_MOD_CONTROL)) || v->button == GLFW_MOUSE_BUTTON_MIDDLE) {
        drag_light(v, dx, dy);
    } else if ((left && (v->button_mods & GLFW_MOD_SHIFT)) || v->button == GLFW_MOUSE_BUTTON_RIGHT) {
        float right[3], up[3];
        camera_axes(v, right, up);
        int height;
        glfwGetWindowSize(w, NULL, &height);
        float per_px = 2.0f * v->distance * tanf(0.5f * v->fov_deg * PI_F / 180.0f) / (float)(height > 0 ? height : 1);
        for (int c = 0; c < 3; ++c)
            v->target[c] += (float)(-dx * right[c] + dy * up[c]) * per_px;
    } else if (left) {
        v->yaw -= (float)dx * 0.01f;
        v->pitch = fmaxf(-1.55f, fminf(1.55f, v->pitch + (float)dy * 0.01f));
    }
}

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)dx;
    viewer *v = glfwGetWindowUserPointer(w);
    v->distance *= powf(0.9f, (float)dy);
    v->distance = fmaxf(v->distance, 1e-3f * v->radius);
}

/* ---- drawing ---- */

static sam_status make_programs(viewer *v, sam_error *err)
{
    sam_status st = sam_gl_render_program("view_present.vert", "view_present.frag", NULL, &v->present_program, err);
    if (st == SAM_OK)
        st = sam_gl_render_program("view_lines.vert", "view_lines.frag", NULL, &v->lines_program, err);
    if (st == SAM_OK)
        st = sam_gl_render_program("view_text.vert", "view_text.frag", NULL, &v->text_program, err);
    if (st != SAM_OK)
        return st;
    glGenVertexArrays(1, &v->empty_vao);
    glGenVertexArrays(1, &v->lines_vao);
    glGenBuffers(1, &v->lines_vbo);
    glBindVertexArray(v->lines_vao);
    glBindBuffer(GL_ARRAY_BUFFER, v->lines_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, NULL);
    glGenVertexArrays(1, &v->text_vao);
    glGenBuffers(1, &v->text_vbo);
    glBindVertexArray(v->text_vao);
    glBindBuffer(GL_ARRAY_BUFFER, v->text_vbo);
    /* stb_easy_font's vertices: x, y, z floats and 4 colour bytes. */
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 16, NULL);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 16, (const void *)12);
    glBindVertexArray(0);
    return SAM_OK;
}

/* The vertex under the cursor: the front-most of those within
 * PICK_RADIUS_PX, else the one nearest to it on screen; -1 for none in
 * front of the camera. */
static long pick_vertex(viewer *v, const float vp[16], int width, int height)
{
    uint32_t n = v->sam.vertex_count;
    sam_error err;
    if (sam_runtime_read_positions(v->rt, v->positions, &err) != SAM_OK) {
        say(v, "samples view: %s", err.message);
        return -1;
    }
    long best = -1, nearest = -1;
    float best_depth = INFINITY;
    double nearest_d2 = INFINITY;
    for (uint32_t i = 0; i < n; ++i) {
        const float *p = v->positions + 3 * i;
        float clip[4];
        for (int r = 0; r < 4; ++r)
            clip[r] = vp[r] * p[0] + vp[4 + r] * p[1] + vp[8 + r] * p[2] + vp[12 + r];
        if (clip[3] <= 0)
            continue;
        double sx = (clip[0] / clip[3] * 0.5 + 0.5) * width, sy = (0.5 - clip[1] / clip[3] * 0.5) * height;
        double dx = sx - v->cursor_x, dy = sy - v->cursor_y;
        float depth = clip[2] / clip[3];
        double d2 = dx * dx + dy * dy;
        if (d2 <= PICK_RADIUS_PX * PICK_RADIUS_PX && depth < best_depth) {
            best_depth = depth;
            best = (long)i;
        }
        if (d2 < nearest_d2) {
            nearest_d2 = d2;
            nearest = (long)i;
        }
    }
    return best >= 0 ? best : nearest;
}

/* Lines from the vertex under the cursor to each of its samples in use. */
static void draw_samples(viewer *v, const float vp[16], int width, int height)
{
    long picked = pick_vertex(v, vp, width, height);
    if (picked < 0)
        return;
    sam_error err;
    if (sam_runtime_read_samples(v->rt, v->sample_index, v->sample_kprime, &err) != SAM_OK) {
        say(v, "samples view: %s", err.message);
        return;
    }
    float lines[2 * 64 * 3 + 3];
    uint32_t count = 0, used = samples_used(v);
    const float *from = v->positions + 3 * picked;
    for (uint32_t k = 0; k < used; ++k) {
        uint32_t b = v->sample_index[(size_t)picked * v->stride + k];
        if (b >= v->sam.vertex_count)
            continue;
        memcpy(lines + 6 * count, from, 3 * sizeof(float));
        memcpy(lines + 6 * count + 3, v->positions + 3 * (size_t)b, 3 * sizeof(float));
        ++count;
    }
    memcpy(lines + 6 * count, from, 3 * sizeof(float));
    glBindBuffer(GL_ARRAY_BUFFER, v->lines_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((6 * count + 3) * sizeof(float)), lines, GL_STREAM_DRAW);
    glUseProgram(v->lines_program);
    glUniformMatrix4fv(glGetUniformLocation(v->lines_program, "u_view_proj"), 1, GL_FALSE, vp);
    glBindVertexArray(v->lines_vao);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUniform4f(glGetUniformLocation(v->lines_program, "u_color"), 1.0f, 0.85f, 0.1f, 1.0f);
    /* Core profiles need not draw lines wider than a pixel: three pixels
     * wide from nine one-pixel copies, shifted in clip space. */
    GLint shift = glGetUniformLocation(v->lines_program, "u_shift");
    for (int i = 0; i < 9; ++i) {
        glUniform2f(shift, (float)(i % 3 - 1) * 2.0f / (float)width, (float)(i / 3 - 1) * 2.0f / (float)height);
        glDrawArrays(GL_LINES, 0, (GLsizei)(2 * count));
    }
    glUniform2f(shift, 0, 0);
    glUniform4f(glGetUniformLocation(v->lines_program, "u_color"), 0.1f, 0.9f, 1.0f, 1.0f);
    glDrawArrays(GL_POINTS, (GLsizei)(2 * count), 1);
    glBindVertexArray(0);
}

/* Text (and a dark panel behind it) at pixel (x, y) of a window `width` x `height`. */
static void draw_text(viewer *v, float x, float y, const char *text, int width, int height)
{
    enum { QUAD_BYTES = 160000 }; /* about 2000 glyph segments */
    static const unsigned char white[4] = {235, 235, 235, 255};
    char *copy = sam_strdup(text), *quads = malloc(QUAD_BYTES);
    if (!copy || !quads) {
        free(copy);
        free(quads);
        return;
    }
    int n = stb_easy_font_print(0, 0, copy, (unsigned char *)white, quads, QUAD_BYTES);
    float tw = (float)stb_easy_font_width(copy) * TEXT_SCALE, th = (float)stb_easy_font_height(copy) * TEXT_SCALE;
    free(copy);
    /* A panel first, then the glyphs' quads as triangles, all in pixels. */
    size_t floats = (size_t)(n + 1) * 6 * 4;
    float *tri = malloc(floats * sizeof *tri);
    if (!tri) {
        free(quads);
        return;
    }
    float *o = tri;
    const float panel[4][2] = {{x - 6, y - 6}, {x + tw + 6, y - 6}, {x + tw + 6, y + th + 4}, {x - 6, y + th + 4}};
    static const int order[6] = {0, 1, 2, 0, 2, 3};
    const unsigned char dark[4] = {0, 0, 0, 170};
    for (int q = 0; q <= n; ++q) {
        for (int i = 0; i < 6; ++i, o += 4) {
            const float *src = q == 0 ? panel[order[i]] : (const float *)(quads + ((size_t)(q - 1) * 4 + order[i]) * 16);
            o[0] = q == 0 ? src[0] : x + src[0] * TEXT_SCALE;
            o[1] = q == 0 ? src[1] : y + src[1] * TEXT_SCALE;
            o[2] = 0;
            memcpy(&o[3], q == 0 ? dark : (const unsigned char *)src + 12, 4);
        }
    }
    free(quads);
    glBindBuffer(GL_ARRAY_BUFFER, v->text_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(floats * sizeof *tri), tri, GL_STREAM_DRAW);
    free(tri);
    glUseProgram(v->text_program);
    glUniform2f(glGetUniformLocation(v->text_program, "u_window"), (float)width, (float)height);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(v->text_vao);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)((n + 1) * 6));
    glBindVertexArray(0);
    glDisable(GL_BLEND);
}

static const char help_text[] =
    "mouse: left drag orbit | right or shift+left drag pan | wheel zoom\n"
    "       middle or ctrl+left drag: move the selected light\n"
    "F frame all      L next light   = - intensity   C colour\n"
    "E environment on/off   , . rotate it\n"
    "T technique      D diffusion    [ ] samples per vertex\n"
    "S smoothing      SPACE play/pause animation\n"
    "V view: final, translucency, irradiance, samples, difference\n"
    "P or F12 screenshot   H or F1 this help   ESC or Q quit";

/* The picture of the current state into the bound framebuffer: the
 * tonemapped render and the samples view's lines; `text` adds the readout
 * and help. Returns 0 when the render failed (the message is shown). */
static int draw_frame(viewer *v, int width, int height, int text)
{
    sam_render_view view;
    make_view(v, width, height, &view);
    GLuint image;
    sam_error err;
    GLint target;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    if (sam_runtime_render_texture(v->rt, &view, &image, &err) != SAM_OK) {
        say(v, "render: %s", err.message);
        glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
        glViewport(0, 0, width, height);
        glClearColor(0.3f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        return 0;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    GLuint p = v->present_program;
    glUseProgram(p);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, image);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, v->truth_tex);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_image"), 0);
    glUniform1i(glGetUniformLocation(p, "u_truth"), 1);
    glUniform1i(glGetUniformLocation(p, "u_mode"), v->mode == MODE_DIFFERENCE);
    glUniform1i(glGetUniformLocation(p, "u_curve"), v->scene.tonemap == SAM_TONEMAP_REINHARD);
    glUniform1f(glGetUniformLocation(p, "u_scale"), exp2f(v->scene.exposure));
    glUniform1f(glGetUniformLocation(p, "u_backdrop"), SAM_IMAGE_PICTURE_BACKDROP);
    glUniform1f(glGetUniformLocation(p, "u_gain"), 4.0f);
    glBindVertexArray(v->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    if (v->mode == MODE_SAMPLES) {
        float vp[16];
        sam_runtime_view_projection(v->rt, &view, vp);
        draw_samples(v, vp, width, height);
    }
    if (text) {
        char line[512];
        int show_message = glfwGetTime() < v->message_until;
        snprintf(line, sizeof line, "%s%s%s", v->status_line, show_message ? "\n" : "",
                 show_message ? v->message : "");
        draw_text(v, 10, 10, line, width, height);
        if (v->help)
            draw_text(v, 10, 40 + (float)stb_easy_font_height(line) * TEXT_SCALE, help_text, width, height);
    }
    return 1;
}

/* ---- screenshots ---- */

static sam_status ensure_shot_target(viewer *v, int width, int height, sam_error *err)
{
    if (v->shot_fbo && v->shot_width == width && v->shot_height == height)
        return SAM_OK;
    if (v->shot_fbo) {
        glDeleteFramebuffers(1, &v->shot_fbo);
        glDeleteTextures(1, &v->shot_tex);
    }
    glGenFramebuffers(1, &v->shot_fbo);
    glGenTextures(1, &v->shot_tex);
    glBindTexture(GL_TEXTURE_2D, v->shot_tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, v->shot_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, v->shot_tex, 0);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        glDeleteFramebuffers(1, &v->shot_fbo);
        glDeleteTextures(1, &v->shot_tex);
        v->shot_fbo = v->shot_tex = 0;
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "screenshot: framebuffer incomplete (0x%04x) at %dx%d", status,
                        width, height);
    }
    v->shot_width = width;
    v->shot_height = height;
    return SAM_OK;
}

/* The displayed picture (without text) as an 8-bit image, top row first. */
static sam_status read_display(viewer *v, int width, int height, sam_image *out, sam_error *err)
{
    sam_status st = ensure_shot_target(v, width, height, err);
    if (st != SAM_OK)
        return st;
    glBindFramebuffer(GL_FRAMEBUFFER, v->shot_fbo);
    int ok = draw_frame(v, width, height, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, v->shot_fbo);
    unsigned char *rgba = malloc((size_t)width * height * 4);
    if (rgba) {
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!ok) {
        free(rgba);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "screenshot: the render failed: %s", v->message);
    }
    if (!rgba || (st = sam_image_create(out, (uint32_t)width, (uint32_t)height, 3, err)) != SAM_OK) {
        free(rgba);
        return rgba ? st : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "screenshot: out of memory");
    }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                out->pixels[((size_t)y * width + x) * 3 + c] =
                    rgba[((size_t)(height - 1 - y) * width + x) * 4 + c] / 255.0f;
    free(rgba);
    return SAM_OK;
}

/* The scene of the current state: what sam_render needs to render the
 * final view (or, with --translucency-only, the translucency view). */
static sam_status write_shot_scene(viewer *v, const char *path, int width, int height, sam_error *err)
{
    sam_scene *s = &v->scene;
    s->has_camera = 1;
    camera_eye(v, s->camera.position);
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

static void screenshot(viewer *v, const char *prefix)
{
    char base[4096], exr[4120], png[4120], json[4120];
    if (prefix)
        snprintf(base, sizeof base, "%s", prefix);
    else
        snprintf(base, sizeof base, "%s_%04d", v->shot_prefix, ++v->shot_number);
    snprintf(exr, sizeof exr, "%s.exr", base);
    snprintf(png, sizeof png, "%s.png", base);
    snprintf(json, sizeof json, "%s.json", base);
    int width, height;
    glfwGetFramebufferSize(v->window, &width, &height);
    sam_render_view view;
    make_view(v, width, height, &view);
    sam_image hdr = {0}, shown = {0};
    sam_error err;
    if (sam_runtime_render(v->rt, &view, &hdr, &err) != SAM_OK ||
        sam_image_write_exr(exr, &hdr, SAM_EXR_FLOAT, &err) != SAM_OK ||
        read_display(v, width, height, &shown, &err) != SAM_OK ||
        sam_image_write_png(png, &shown, SAM_PNG_LINEAR, &err) != SAM_OK ||
        write_shot_scene(v, json, width, height, &err) != SAM_OK)
        say(v, "screenshot failed: %s", err.message);
    else
        say(v, "wrote %s, %s and %s; sam_render %s -o OUT.exr --png OUT.png%s reproduces the %s view", exr, png,
            json, json, v->mode == MODE_TRANSLUCENCY ? " --translucency-only" : "",
            v->mode == MODE_TRANSLUCENCY ? "translucency" : "final");
    sam_image_destroy(&hdr);
    sam_image_destroy(&shown);
}

/* ---- the frame loop ---- */

static void lose_context(viewer *v, GLenum status)
{
    const char *why = status == GL_GUILTY_CONTEXT_RESET     ? "this program's commands caused a reset"
                      : status == GL_INNOCENT_CONTEXT_RESET ? "another program caused a reset"
                                                            : "the driver reset it";
    fprintf(stderr, "sam_view: the GL context was lost (%s, status 0x%04x); closing. Start sam_view again to go on.\n",
            why, (unsigned)status);
    v->lost = 1;
    glfwSetWindowShouldClose(v->window, 1);
}

static void run_event(viewer *v, const sam_view_event *e)
{
    GLFWwindow *w = v->window;
    switch (e->action) {
    case SAM_VIEW_KEY:
        on_key(w, e->key, 0, GLFW_PRESS, e->mods);
        on_key(w, e->key, 0, GLFW_RELEASE, e->mods);
        break;
    case SAM_VIEW_MOUSE:
        on_cursor(w, e->x0, e->y0);
        break;
    case SAM_VIEW_DRAG: {
        int mods = 0;
        on_cursor(w, e->x0, e->y0);
        on_button(w, e->button, GLFW_PRESS, mods);
        for (int i = 1; i <= 8; ++i)
            on_cursor(w, e->x0 + (e->x1 - e->x0) * (float)i / 8, e->y0 + (e->y1 - e->y0) * (float)i / 8);
        on_button(w, e->button, GLFW_RELEASE, mods);
        break;
    }
    case SAM_VIEW_SCROLL:
        on_scroll(w, 0, e->y0);
        break;
    case SAM_VIEW_RESIZE:
        glfwSetWindowSize(w, (int)e->x0, (int)e->y0);
        break;
    case SAM_VIEW_SCREENSHOT:
        screenshot(v, e->path);
        break;
    case SAM_VIEW_LOSE_CONTEXT:
        lose_context(v, GL_UNKNOWN_CONTEXT_RESET);
        break;
    case SAM_VIEW_QUIT:
        glfwSetWindowShouldClose(w, 1);
        break;
    }
}

/* The SAM passes of one frame. */
static void update(viewer *v, double dt)
{
    sam_error err;
    if (v->playing)
        v->anim_time += dt;
    if (v->posed && (v->playing || v->reset_t)) {
        if (sam_runtime_deform(v->rt, (float)v->anim_time, &err) != SAM_OK ||
            sam_runtime_walk(v->rt, &err) != SAM_OK) {
            say(v, "deformation stopped: %s", err.message);
            v->playing = 0;
        }
    }
    if (sam_runtime_irradiance(v->rt, &err) != SAM_OK ||
        (v->scene.technique == SAM_TECHNIQUE_SAM &&
         sam_runtime_translucency(v->rt, v->scene.samples_per_vertex, (float)dt, v->reset_t || !v->smoothing, &err) !=
             SAM_OK))
        say(v, "frame: %s", err.message);
    v->reset_t = 0;
}

static void refresh_readout(viewer *v, double now)
{
    ++v->fps_frames;
    if (now - v->fps_time < 0.5 && v->status_line[0])
        return;
    v->fps = v->fps_frames / fmax(now - v->fps_time, 1e-9);
    v->fps_time = now;
    v->fps_frames = 0;
    static const sam_pass passes[] = {SAM_PASS_IRRADIANCE, SAM_PASS_TRANSLUCENCY, SAM_PASS_SHADE,
                                      SAM_PASS_DIFFUSION, SAM_PASS_DEFORM, SAM_PASS_WALK};
    static const char *const names[] = {"irr", "transl", "shade", "diff", "deform", "walk"};
    char ms[160] = "";
    size_t len = 0;
    for (size_t i = 0; i < sizeof passes / sizeof passes[0]; ++i) {
        double t = sam_runtime_pass_ms(v->rt, passes[i]);
        if (t >= 0 && len < sizeof ms)
            len += (size_t)snprintf(ms + len, sizeof ms - len, " %s %.2f", names[i], t);
    }
    snprintf(v->status_line, sizeof v->status_line, "%s | %s | N %u/%u | %s | %s%s\n%.1f fps | GPU ms:%s",
             sam_technique_name(v->scene.technique), sam_diffusion_name(v->scene.diffusion), samples_used(v),
             v->stride, v->smoothing ? "smoothing" : "no smoothing", mode_names[v->mode],
             v->posed ? (v->playing ? " | playing" : " | paused") : "", v->fps, ms);
    char title[400];
    snprintf(title, sizeof title, "sam_view - %s", v->status_line);
    *strchr(title, '\n') = ' ';
    glfwSetWindowTitle(v->window, title);
}

static int check_reset(viewer *v)
{
    if (epoxy_gl_version() < 45 && !epoxy_has_gl_extension("GL_KHR_robustness"))
        return 0;
    GLenum status = glGetGraphicsResetStatus();
    if (status != GL_NO_ERROR)
        lose_context(v, status);
    return status != GL_NO_ERROR;
}

/* With `fps` > 0 the clock advances 1/fps per frame whatever the frame
 * took, so a script's events and the animation land on exact frames. */
static void run(viewer *v, const sam_view_event *events, size_t event_count, float fps)
{
    size_t next = 0;
    double start = fps > 0 ? 0 : glfwGetTime(), last = start;
    for (long frame = 0; !glfwWindowShouldClose(v->window); ++frame) {
        glfwPollEvents();
        double now = fps > 0 ? (double)frame / fps : glfwGetTime();
        /* Events at or before now run in order; a screenshot ends the batch
         * so the next one sees a new frame. */
        while (next < event_count && events[next].time_s <= now - start && !glfwWindowShouldClose(v->window)) {
            const sam_view_event *e = &events[next++];
            if (e->action == SAM_VIEW_SCREENSHOT)
                update(v, 0);
            run_event(v, e);
            if (e->action == SAM_VIEW_SCREENSHOT)
                break;
        }
        if (glfwWindowShouldClose(v->window) || check_reset(v))
            break;
        double dt = now - last;
        last = now;
        update(v, dt);
        int width, height;
        glfwGetFramebufferSize(v->window, &width, &height);
        if (width > 0 && height > 0) {
            refresh_readout(v, glfwGetTime());
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            draw_frame(v, width, height, 1);
        }
        glfwSwapBuffers(v->window);
    }
}

/* ---- start-up ---- */

typedef struct options {
    const char *input, *material, *environment, *truth, *shot, *cache, *script;
    float size_mm, fps;
    int width, height, no_cache;
} options;

static int parse_options(int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->size_mm = 60.0f;
    o->shot = "sam_view";
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            exit(0);
        } else if (!strcmp(a, "--no-cache")) {
            o->no_cache = 1;
        } else if (a[0] == '-' && a[1] && !val) {
            fprintf(stderr, "sam_view: %s needs a value (see --help)\n", a);
            return 0;
        } else if (!strcmp(a, "--material")) {
            o->material = argv[++i];
        } else if (!strcmp(a, "--environment")) {
            o->environment = argv[++i];
        } else if (!strcmp(a, "--truth")) {
            o->truth = argv[++i];
        } else if (!strcmp(a, "--shot")) {
            o->shot = argv[++i];
        } else if (!strcmp(a, "--cache")) {
            o->cache = argv[++i];
        } else if (!strcmp(a, "--script")) {
            o->script = argv[++i];
        } else if (!strcmp(a, "--size-mm")) {
            double v;
            if (!sam_parse_double(argv[++i], &v) || !((float)v > 0 && isfinite((float)v))) {
                fprintf(stderr, "sam_view: --size-mm must be a positive number, got \"%s\"\n", argv[i]);
                return 0;
            }
            o->size_mm = (float)v;
        } else if (!strcmp(a, "--fps")) {
            double v;
            if (!sam_parse_double(argv[++i], &v) || !(v > 0 && v <= 1000)) {
                fprintf(stderr, "sam_view: --fps must be a number in (0, 1000], got \"%s\"\n", argv[i]);
                return 0;
            }
            o->fps = (float)v;
        } else if (!strcmp(a, "--size")) {
            char tail;
            if (sscanf(argv[++i], "%dx%d%c", &o->width, &o->height, &tail) != 2 || o->width < 16 ||
                o->height < 16 || o->width > 16384 || o->height > 16384) {
                fprintf(stderr, "sam_view: --size must be WxH with each in 16..16384, got \"%s\"\n", argv[i]);
                return 0;
            }
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "sam_view: unknown option \"%s\" (see --help)\n", a);
            return 0;
        } else if (!o->input) {
            o->input = a;
        } else {
            fprintf(stderr, "sam_view: unexpected argument \"%s\"\n", a);
            return 0;
        }
    }
    if (!o->input) {
        usage(stderr);
        return 0;
    }
    return 1;
}

static void on_glfw_error(int code, const char *message)
{
    fprintf(stderr, "sam_view: window system error 0x%x: %s\n", (unsigned)code, message);
}

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
    GLFWwindow *w = glfwCreateWindow(width, height, "sam_view", NULL, NULL);
    if (!w) {
        glfwWindowHint(GLFW_CONTEXT_ROBUSTNESS, GLFW_NO_ROBUSTNESS);
        w = glfwCreateWindow(width, height, "sam_view", NULL, NULL);
    }
    if (!w) {
        const char *why = NULL;
        glfwGetError(&why);
        sam_fail(err, SAM_ERR_UNSUPPORTED, "cannot open a window with OpenGL 4.3 core: %s",
                 why ? why : "unknown reason");
    }
    return w;
}

/* The environment map and the truth image; either missing or unreadable is
 * said and left out, not fatal. */
static void load_images(viewer *v, const char *truth)
{
    if (v->scene.environment.map) {
        v->environment_path = v->scene.environment.map;
        sam_error env_err;
        if (sam_image_read_exr(v->environment_path, &v->environment, &env_err) != SAM_OK)
            say(v, "environment off: %s", env_err.message);
        else
            v->environment_on = 1;
    }
    if (truth) {
        sam_error truth_err;
        if (sam_image_read_exr(truth, &v->truth, &truth_err) != SAM_OK) {
            say(v, "no difference view: %s", truth_err.message);
        } else {
            /* Images run top-down; the shader flips. */
            glGenTextures(1, &v->truth_tex);
            glBindTexture(GL_TEXTURE_2D, v->truth_tex);
            glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, (GLsizei)v->truth.width, (GLsizei)v->truth.height);
            GLenum format = v->truth.channels == 4 ? GL_RGBA : v->truth.channels == 3 ? GL_RGB : GL_RED;
            glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)v->truth.width, (GLsizei)v->truth.height, format,
                            GL_FLOAT, v->truth.pixels);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            fprintf(stderr, "sam_view: truth %s (%ux%u); it matches the view at the scene's camera and size\n",
                    truth, v->truth.width, v->truth.height);
        }
    }
}

static void destroy(viewer *v)
{
    if (v->window) {
        glDeleteProgram(v->present_program);
        glDeleteProgram(v->lines_program);
        glDeleteProgram(v->text_program);
        glDeleteVertexArrays(1, &v->empty_vao);
        glDeleteVertexArrays(1, &v->lines_vao);
        glDeleteVertexArrays(1, &v->text_vao);
        glDeleteBuffers(1, &v->lines_vbo);
        glDeleteBuffers(1, &v->text_vbo);
        glDeleteTextures(1, &v->truth_tex);
        if (v->shot_fbo) {
            glDeleteFramebuffers(1, &v->shot_fbo);
            glDeleteTextures(1, &v->shot_tex);
        }
        sam_runtime_destroy(v->rt);
        glfwDestroyWindow(v->window);
    }
    free(v->sample_index);
    free(v->sample_kprime);
    free(v->positions);
    sam_image_destroy(&v->environment);
    sam_image_destroy(&v->truth);
    samfile_free(&v->sam);
    sam_scene_destroy(&v->scene);
}

int main(int argc, char **argv)
{
    options o;
    if (!parse_options(argc, argv, &o))
        return 2;
    viewer v;
    memset(&v, 0, sizeof v);
    v.button = -1;
    v.smoothing = 1;
    v.reset_t = 1;
    v.shot_prefix = o.shot;
    sam_error err;
    sam_view_event *events = NULL;
    size_t event_count = 0;
    int code = 1, glfw_up = 0;
    sam_status st = SAM_OK;
    if (o.script)
        st = sam_view_script_load(o.script, &events, &event_count, &err);
    int is_scene = has_suffix(o.input, ".json"), is_sam = has_suffix(o.input, ".sam");
    if (st == SAM_OK && is_scene && (o.material || o.environment))
        st = sam_fail(&err, SAM_ERR_INVALID_ARGUMENT, "--material and --environment are for a bare mesh or .sam; "
                                                      "%s sets its own",
                      o.input);
    if (st == SAM_OK)
        st = is_scene ? sam_scene_load(o.input, &v.scene, &err)
                      : bare_scene(o.input, is_sam, o.material, o.size_mm, o.environment, &v.scene, &err);
    char cache_dir[4096];
    if (o.cache)
        snprintf(cache_dir, sizeof cache_dir, "%s", o.cache);
    else
        default_cache_dir(cache_dir, sizeof cache_dir);
    sam_profile profile;
    float mm_per_unit;
    if (st == SAM_OK)
        st = load_map(&v, cache_dir, !o.no_cache, &profile, &mm_per_unit, &err);
    if (st != SAM_OK)
        goto done;
    if (!glfwInit()) {
        const char *why = NULL;
        glfwGetError(&why);
        sam_fail(&err, SAM_ERR_UNSUPPORTED, "cannot reach a window system: %s (is DISPLAY set? sam_render renders "
                                            "without one)",
                 why ? why : "unknown reason");
        goto done;
    }
    glfw_up = 1;
    int width = o.width, height = o.height;
    if (!width) {
        float fit = fminf(1.0f, fminf(1600.0f / (float)v.scene.width, 1000.0f / (float)v.scene.height));
        width = (int)fmaxf(16.0f, (float)v.scene.width * fit);
        height = (int)fmaxf(16.0f, (float)v.scene.height * fit);
    }
    if (!(v.window = open_window(width, height, &err)))
        goto done;
    /* Failures until here are reported once, by the caller; later ones as they come. */
    glfwSetErrorCallback(on_glfw_error);
    glfwSetWindowUserPointer(v.window, &v);
    glfwMakeContextCurrent(v.window);
    glfwSwapInterval(0);
    sam_gl_info info;
    if (sam_gl_check_current(sam_gl_debug_requested(), &info, &err) != SAM_OK ||
        sam_runtime_create(&v.sam, &profile, mm_per_unit, &v.rt, &err) != SAM_OK)
        goto done;
    fprintf(stderr, "sam_view: %s, OpenGL %s; %u vertices, N = %u\n", info.renderer, info.version,
            v.sam.vertex_count, sam_runtime_samples_per_vertex(v.rt));
    v.stride = sam_runtime_samples_per_vertex(v.rt);
    sam_runtime_bounds(v.rt, v.centre, &v.radius);
    v.posed = v.scene.deformer_count || v.scene.keyframe_count;
    char warning[512];
    if ((!is_scene && default_lights(&v, &err) != SAM_OK) ||
        sam_runtime_scene_setup(v.rt, &v.scene, NULL, NULL, warning, sizeof warning, &err) != SAM_OK ||
        sam_runtime_scene_keyframes(v.rt, &v.scene, &v.sam, &err) != SAM_OK || make_programs(&v, &err) != SAM_OK)
        goto done;
    load_images(&v, o.truth);
    if (warning[0])
        say(&v, "%s", warning);
    size_t n = v.sam.vertex_count;
    v.positions = malloc(n * 3 * sizeof *v.positions);
    v.sample_index = malloc(n * v.stride * sizeof *v.sample_index);
    v.sample_kprime = malloc(n * v.stride * 3 * sizeof *v.sample_kprime);
    if (!v.positions || !v.sample_index || !v.sample_kprime) {
        sam_fail(&err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the samples view");
        goto done;
    }
    sam_render_view start;
    sam_runtime_scene_view(v.rt, &v.scene, &start, NULL, 0);
    camera_from(&v, start.eye, start.target, start.fov_deg);
    if (v.scene.diffusion == SAM_DIFFUSION_TEXTURE && !sam_runtime_uv_status(v.rt, NULL, 0))
        v.scene.diffusion = SAM_DIFFUSION_SCREEN;
    glfwSetKeyCallback(v.window, on_key);
    glfwSetMouseButtonCallback(v.window, on_button);
    glfwSetCursorPosCallback(v.window, on_cursor);
    glfwSetScrollCallback(v.window, on_scroll);
    glfwGetCursorPos(v.window, &v.cursor_x, &v.cursor_y);
    if (!events)
        fprintf(stderr, "sam_view: press H for help\n");
    run(&v, events, event_count, o.fps);
    code = v.lost ? 1 : 0;
done:
    if (code && !v.lost)
        fprintf(stderr, "sam_view: %s\n", err.message);
    free(events);
    destroy(&v);
    if (glfw_up)
        glfwTerminate();
    return code;
}
