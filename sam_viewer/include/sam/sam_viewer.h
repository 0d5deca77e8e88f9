/*
 * sam_viewer: the viewer's state machine, apart from any window or GL
 * context, so what a key, a drag or a script event does can be driven and
 * tested alone.
 *
 * A sam_viewer holds the scene a screenshot writes (lights, camera,
 * switches), the orbit camera, the view mode, the animation clock and the
 * text the window shows. Input goes in as GLFW key, button and modifier
 * codes (constants only: nothing here calls GLFW) or as sam_view_event
 * from a script; what the state cannot do alone comes back as a bitmask of
 * SAM_VIEWER_* effects that the window side carries out (push the lights
 * or the environment to the GPU, take a screenshot, quit, ...).
 *
 * Nothing here needs GL: sam_runtime.h is included for sam_render_view and
 * no runtime function is called. The window side is sam_viewer_window.h.
 */
#ifndef SAM_VIEWER_H
#define SAM_VIEWER_H

#include <stddef.h>
#include <stdint.h>

#include "sam/sam_common.h"
#include "sam/sam_runtime.h"
#include "sam/sam_scene.h"
#include "sam/sam_view_script.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sam_viewer_mode {
    SAM_VIEWER_FINAL = 0,
    SAM_VIEWER_TRANSLUCENCY,
    SAM_VIEWER_IRRADIANCE,
    SAM_VIEWER_SAMPLES,     /* lines from the vertex under the cursor to its samples */
    SAM_VIEWER_DIFFERENCE,  /* to the truth image; skipped without one */
    SAM_VIEWER_MODE_COUNT
} sam_viewer_mode;

/* What an input asks of the window side, or-ed together. */
enum {
    SAM_VIEWER_LIGHTS = 1,        /* scene.lights changed: upload them */
    SAM_VIEWER_ENVIRONMENT = 2,   /* environment_on or its rotation changed: upload it */
    SAM_VIEWER_SCREENSHOT = 4,    /* numbered screenshot (P, F12) */
    SAM_VIEWER_QUIT = 8,          /* close the window */
    SAM_VIEWER_RESIZE = 16,       /* script: resize the window to the event's x0 x y0 */
    SAM_VIEWER_SHOT_TO = 32,      /* script: screenshot to the event's path */
    SAM_VIEWER_LOSE_CONTEXT = 64  /* script: act as if the GL context were lost */
};

typedef struct sam_viewer {
    sam_scene scene;         /* owned; the state a screenshot writes */
    char *environment_path;  /* scene.environment.map, kept while the environment is off */
    uint32_t stride;         /* samples the .sam holds per vertex */
    int posed;               /* the scene has deformers or keyframes */
    int uv_ok;               /* the mesh's UVs allow texture-space diffusion (and tsm) */
    int has_environment;     /* an environment map was read */
    int has_truth;           /* a truth image was read */
    float centre[3], radius; /* the object's bounds */

    float target[3], yaw, pitch, distance, fov_deg; /* the orbit camera, +Y up */

    int environment_on;
    sam_viewer_mode mode;
    int help, smoothing, playing, reset_t;
    double anim_time;
    size_t selected_light;

    double cursor_x, cursor_y;
    int button;        /* the button held, -1 for none */
    int button_mods;
    int window_height; /* pixels, for the pan's scale */

    double (*clock)(void); /* seconds, for how long a message shows; NULL: 0 */
    double fps, fps_time;
    int fps_frames;
    char status_line[256];
    char message[256];
    double message_until;

    const char *shot_prefix; /* not owned */
    int shot_number;
} sam_viewer;

/* What one frame runs, from sam_viewer_frame_plan. */
typedef struct sam_viewer_frame {
    int deform;        /* pose the mesh at time_s (and walk it) */
    float time_s;
    int translucency;  /* run the SAM translucency pass */
    int thickness;     /* the local-thickness technique: its thickness must be on the GPU */
    uint32_t samples;  /* samples per vertex for it (0: all) */
    float dt;          /* seconds since the last frame */
    int reset;         /* replace the temporal history rather than blend */
} sam_viewer_frame;

/* A fresh state: an empty scene, smoothing on, nothing held, the history to
 * be reset. `shot_prefix` (not copied; may be NULL until a screenshot) names
 * numbered screenshots. */
void sam_viewer_init(sam_viewer *v, const char *shot_prefix);

/* Takes the object's facts once the runtime has them: `stride` samples per
 * vertex, the bounds (`centre`, `radius`), whether the UVs are usable, and
 * the starting camera (eye, target, vertical fov in degrees). A scene asking
 * for texture-space diffusion without usable UVs falls back to screen space. */
void sam_viewer_start(sam_viewer *v, uint32_t stride, const float centre[3], float radius, int uv_ok,
                      const float eye[3], const float target[3], float fov_deg);

/* Frees the scene. `v` may be NULL. */
void sam_viewer_destroy(sam_viewer *v);

/* A message on stderr ("sam_view: ...") and for four seconds in the window. */
void sam_viewer_say(sam_viewer *v, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* ---- input (sam_viewer.c) ---- */

/* A key (GLFW_KEY_*) pressed, repeated or released (GLFW_PRESS, _REPEAT,
 * _RELEASE); releases do nothing, and a repeat takes no screenshot.
 * Returns SAM_VIEWER_* effects. */
unsigned sam_viewer_key(sam_viewer *v, int key, int action);

/* A mouse button (GLFW_MOUSE_BUTTON_*) pressed or released with `mods`
 * (GLFW_MOD_* bits); the first pressed is held until it is released. */
void sam_viewer_button(sam_viewer *v, int button, int action, int mods);

/* The cursor moved to window pixel (x, y): orbits, pans or drags the
 * selected light by the button held. Returns SAM_VIEWER_* effects. */
unsigned sam_viewer_cursor(sam_viewer *v, double x, double y);

/* The wheel turned `dy` notches: zoom, never nearer than 1e-3 radius. */
void sam_viewer_scroll(sam_viewer *v, double dy);

/* A script event as the input it stands for (a key is pressed and released,
 * a drag is a press, eight moves and a release). Resize, screenshot, lost
 * context and quit come back as effects. */
unsigned sam_viewer_event(sam_viewer *v, const sam_view_event *e);

/* ---- frames and text (sam_viewer.c) ---- */

/* Samples per vertex in use (scene's choice, at most stride). */
uint32_t sam_viewer_samples_used(const sam_viewer *v);

/* Advances the animation by `dt` seconds when playing and says in `f` what
 * this frame runs; the history reset asked for is used up. */
void sam_viewer_frame_plan(sam_viewer *v, double dt, sam_viewer_frame *f);

/* Counts a frame drawn at `now` seconds; returns 1 (and updates fps) when
 * the readout is due again, every half second. */
int sam_viewer_count_frame(sam_viewer *v, double now);

/* Writes the two-line readout into status_line: the switches, then fps and
 * `gpu_ms` (text of each pass's milliseconds; may be NULL). */
void sam_viewer_set_status(sam_viewer *v, const char *gpu_ms);

/* The window title: "sam_view - " and the readout on one line, into `out`
 * of `n` bytes. */
void sam_viewer_title(const sam_viewer *v, char *out, size_t n);

/* The overlay's text at `now`: the readout and, while it shows, the last
 * message, into `out` of `n` bytes. */
void sam_viewer_overlay(const sam_viewer *v, double now, char *out, size_t n);

/* The help shown under the overlay (H, F1): a static string. */
const char *sam_viewer_help_text(void);

/* ---- screenshots (sam_viewer.c) ---- */

/* The name of a screenshot without extension into `out` of `n` bytes:
 * `prefix` when not NULL, else the next "SHOT_PREFIX_0001". */
void sam_viewer_shot_name(sam_viewer *v, const char *prefix, char *out, size_t n);

/* Writes the scene of the current state to `path` for a `width` x `height`
 * picture, so sam_render reproduces the final view (the environment named
 * only while it is on). Errors: those of sam_scene_write. */
sam_status sam_viewer_write_scene(sam_viewer *v, const char *path, int width, int height, sam_error *err);

/* ---- camera and lights (sam_viewer_camera.c) ---- */

/* The camera's eye from its orbit. */
void sam_viewer_eye(const sam_viewer *v, float eye[3]);

/* The orbit of a look-at camera at `eye` looking at `target`. */
void sam_viewer_camera_from(sam_viewer *v, const float eye[3], const float target[3], float fov_deg);

/* The camera's right and up unit vectors. */
void sam_viewer_camera_axes(const sam_viewer *v, float right[3], float up[3]);

/* Aims at the object's centre from a distance that shows all of it. */
void sam_viewer_frame_all(sam_viewer *v);

/* Turns the camera about its target by a drag of (dx, dy) pixels; the
 * pitch stays within +-1.55 radians. */
void sam_viewer_orbit(sam_viewer *v, double dx, double dy);

/* Moves the target with a drag of (dx, dy) pixels, so the point under the
 * cursor follows it in a window `height` pixels high. */
void sam_viewer_pan(sam_viewer *v, double dx, double dy, int height);

/* Turns the selected light (and its direction, normal, vertices) about the
 * object's centre by a drag of (dx, dy) pixels. Returns 0 with no lights. */
int sam_viewer_drag_light(sam_viewer *v, double dx, double dy);

/* Sets the camera, technique and view mode's changes on `view`, whose other
 * fields the caller has from the scene (sam_runtime_scene_view). */
void sam_viewer_apply_view(const sam_viewer *v, sam_render_view *view);

#ifdef __cplusplus
}
#endif

#endif
