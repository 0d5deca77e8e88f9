/*
 * sam_viewer_window: the viewer's window, on the state machine of
 * sam_viewer.h: a GLFW window with an OpenGL 4.3 core context, the SAM
 * runtime drawing the object, GLFW's input and a script's events fed to the
 * state, the overlay, the samples view and screenshots.
 *
 * Needs a window system and OpenGL 4.3 core (GLFW, epoxy, sam_runtime).
 * One window per process: GLFW is initialised by sam_viewer_window_open and
 * terminated by sam_viewer_window_destroy.
 *
 *     sam_viewer_window w;
 *     sam_viewer_window_init(&w, "sam_view");
 *     ... fill w.state.scene and w.sam (sam_viewer_load.h) ...
 *     if (sam_viewer_window_open(&w, &options, &profile, mm_per_unit, &err) == SAM_OK)
 *         code = sam_viewer_window_run(&w, events, event_count, fps);
 *     sam_viewer_window_destroy(&w);
 */
#ifndef SAM_VIEWER_WINDOW_H
#define SAM_VIEWER_WINDOW_H

#include <stddef.h>
#include <stdint.h>

#include "sam/sam_runtime.h"
#include "sam/sam_view_script.h"
#include "sam/sam_viewer.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_viewer_window {
    sam_viewer state;        /* owned; its scene is the one shown */
    samfile_data sam;        /* owned; the map, filled by the caller before opening */
    struct GLFWwindow *window;
    int glfw_up;
    sam_runtime *rt;
    float mm_per_unit;       /* the map's scale, for the local thickness */
    int thickness_ready;     /* the local thickness is on the GPU (measured on first use) */
    sam_image environment, truth;
    GLuint truth_tex;

    GLuint present_program, lines_program, text_program;
    GLuint empty_vao, lines_vao, lines_vbo, text_vao, text_vbo;
    GLuint shot_fbo, shot_tex;
    int shot_width, shot_height;

    int lost;                /* the GL context was lost */
    uint32_t *sample_index;  /* read back for the samples view */
    float *sample_kprime, *positions;
} sam_viewer_window;

typedef struct sam_viewer_window_options {
    int width, height;       /* pixels; 0: the scene's size, at most 1600 x 1000 */
    int default_lights;      /* 1: light the object with sam_viewer_default_lights (a bare .sam) */
    int staged;              /* 1: a staged bare mesh: its back light is placed (sam_app_backlight.h) */
    const char *truth;       /* a truth EXR for the difference view; may be NULL */
} sam_viewer_window_options;

/* An empty, closed window whose screenshots are named `shot_prefix`_0001
 * ... (not copied; may be NULL: "sam_view"). */
void sam_viewer_window_init(sam_viewer_window *w, const char *shot_prefix);

/* Opens the window for w->state.scene and w->sam (with the material's
 * `profile` and `mm_per_unit`), puts the object on the GPU, reads the
 * scene's environment and `o->truth` (either missing is said, not fatal)
 * and starts the state's camera from the scene's. A warning of the scene's
 * setup is said. Errors (nothing said; the caller reports `err` once):
 * SAM_ERR_UNSUPPORTED (no window system, no OpenGL 4.3 core), those of
 * sam_gl_check_current, sam_runtime_create and sam_runtime_scene_setup,
 * SAM_ERR_OUT_OF_MEMORY. On failure call sam_viewer_window_destroy. */
sam_status sam_viewer_window_open(sam_viewer_window *w, const sam_viewer_window_options *o,
                                  const sam_profile *profile, float mm_per_unit, sam_error *err);

/* Runs frames until the window closes: input and the `event_count` events
 * (may be NULL when 0; the caller keeps them) go to the state, each frame
 * runs the SAM passes and draws. `fps` > 0 makes a fixed clock: each frame
 * advances time by 1/fps, however long it took, so scripts and animation
 * land on exact frames. Returns the exit status: 1 when the GL context was
 * lost (said on stderr), else 0. */
int sam_viewer_window_run(sam_viewer_window *w, const sam_view_event *events, size_t event_count, float fps);

/* Frees everything, the state and the map included, closes the window and
 * ends GLFW. Safe after a failed or no sam_viewer_window_open. */
void sam_viewer_window_destroy(sam_viewer_window *w);

#ifdef __cplusplus
}
#endif

#endif
