/*
 * sam_viewer_draw (internal to sam_viewer): the window's pictures, for
 * sam_viewer_window.c: the tonemapped render, the samples view's lines, the
 * overlay text and screenshots. Each needs the window's GL context current.
 */
#ifndef SAM_VIEWER_DRAW_H
#define SAM_VIEWER_DRAW_H

#include "sam/sam_viewer_window.h"

/* Compiles the present, lines and text programs and makes their vertex
 * arrays. Errors: those of sam_gl_render_program. */
sam_status sam_viewer_draw_create(sam_viewer_window *w, sam_error *err);

/* Deletes what sam_viewer_draw_create and screenshots made (0 names are
 * skipped by GL). */
void sam_viewer_draw_destroy(sam_viewer_window *w);

/* The picture of the current state into the bound framebuffer, `width` x
 * `height` pixels: the render and the samples view's lines; `text` adds the
 * overlay at `now` seconds and the help. Returns 0 when the render failed
 * (the message is said and the picture is dark red). */
int sam_viewer_draw_frame(sam_viewer_window *w, int width, int height, int text, double now);

/* Writes PREFIX.exr (the HDR render), PREFIX.png (the picture shown, no
 * text) and PREFIX.json (a scene sam_render reproduces it from) at the
 * framebuffer's size; `prefix` NULL takes the next numbered name. Success
 * or failure is said. */
void sam_viewer_draw_screenshot(sam_viewer_window *w, const char *prefix);

#endif
