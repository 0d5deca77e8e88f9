/*
 * sam_view_script: scripted input for sam_view (`--script FILE`), so a test
 * can drive the viewer with no input tool and no person.
 *
 * A script is a text file of one event per line, `#` to the end of a line a
 * comment, blank lines ignored:
 *
 *     TIME key [shift+][ctrl+]NAME        press and release a key
 *     TIME mouse X Y                      move the cursor to pixel (X, Y)
 *     TIME drag left|right|middle X0 Y0 X1 Y1
 *                                         press at (X0, Y0), move to (X1, Y1), release
 *     TIME scroll DY                      turn the wheel by DY notches
 *     TIME resize W H                     resize the window to W x H pixels
 *     TIME screenshot PREFIX              write PREFIX.exr, PREFIX.png, PREFIX.json
 *     TIME lose-context                   act as if the GL context were lost
 *     TIME quit                           close the window
 *
 * TIME is seconds since the first frame, non-decreasing down the file.
 * Pixels are window coordinates, (0, 0) at the top left. NAME is a letter,
 * a digit, one of [ ] , . - = / or SPACE, ESCAPE, ENTER, TAB, LEFT, RIGHT,
 * UP, DOWN, F1..F12 (case-insensitive).
 *
 * Events carry GLFW key and button codes; the viewer feeds them to the same
 * handlers as real input.
 */
#ifndef SAM_VIEW_SCRIPT_H
#define SAM_VIEW_SCRIPT_H

#include <stddef.h>

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SAM_VIEW_SCRIPT_PATH_MAX 1024

typedef enum sam_view_action {
    SAM_VIEW_KEY = 0,
    SAM_VIEW_MOUSE,
    SAM_VIEW_DRAG,
    SAM_VIEW_SCROLL,
    SAM_VIEW_RESIZE,
    SAM_VIEW_SCREENSHOT,
    SAM_VIEW_LOSE_CONTEXT,
    SAM_VIEW_QUIT
} sam_view_action;

typedef struct sam_view_event {
    double time_s;
    sam_view_action action;
    int line;                /* 1-based line of the script, for messages */
    int key, mods;           /* KEY: GLFW_KEY_* and GLFW_MOD_* bits */
    int button;              /* DRAG: GLFW_MOUSE_BUTTON_* */
    float x0, y0, x1, y1;    /* MOUSE: (x0, y0); DRAG: from, to; SCROLL: y0 notches; RESIZE: x0 x y0 */
    char path[SAM_VIEW_SCRIPT_PATH_MAX]; /* SCREENSHOT: the prefix */
} sam_view_event;

/* Parses `size` bytes of script text (no NUL needed). `name` (may be NULL:
 * "script") starts messages. On success `*events` is a new array of
 * `*count` events in file order (the caller frees it with free(); NULL when
 * the script has none).
 * Errors: SAM_ERR_FORMAT naming the line and what was found (an unknown
 * action, key or button, a missing or extra argument, a number that does
 * not parse or is out of range, a time before the previous line's, a
 * prefix longer than SAM_VIEW_SCRIPT_PATH_MAX - 1 bytes),
 * SAM_ERR_OUT_OF_MEMORY, SAM_ERR_INVALID_ARGUMENT (NULL text with size > 0,
 * NULL outputs). On failure *events is NULL and *count 0. */
sam_status sam_view_script_parse(const char *text, size_t size, const char *name, sam_view_event **events,
                                 size_t *count, sam_error *err);

/* Reads the file at `path` and parses it, messages naming the file.
 * Errors: SAM_ERR_IO (cannot read it, with the system's reason), and those
 * of sam_view_script_parse. */
sam_status sam_view_script_load(const char *path, sam_view_event **events, size_t *count, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
