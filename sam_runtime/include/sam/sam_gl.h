/*
 * sam_gl: the GL context and shader layer of the runtime.
 *
 * A sam_gl_context is an OpenGL 4.3 core context made current on the
 * calling thread. sam_gl_context_create_headless needs no display and no
 * window: it opens EGL's surfaceless platform (EGL_MESA_platform_surfaceless,
 * Mesa's llvmpipe and Mesa GPU drivers) and, where that is missing or fails,
 * each EGL device in turn (EGL_EXT_platform_device: NVIDIA's driver on a
 * headless server). SAM_EGL_DEVICE=i in the environment opens the i-th
 * EGL device only (a GPU of several). Headless contexts have no
 * default framebuffer, so every render goes to an FBO. GL entry points come
 * from libepoxy. Creation checks the version and the limits the runtime
 * needs and fails with one line naming what is missing. Debug output is
 * turned on when the library is built without NDEBUG (and with
 * SAM_GL_DEBUG=1 in the environment in any build).
 *
 * Shaders are GLSL 4.30 files under shaders/, embedded into the library at
 * build time. A line `#include "name.glsl"` pulls in another embedded file
 * (once per program; nested includes allowed). Every compile or link error
 * is rewritten to name the original file and line:
 *     "translucency.comp:42: error: 'kprime' : undeclared identifier".
 *
 * One context per thread; the structs are plain handles owned by the caller.
 */
#ifndef SAM_GL_H
#define SAM_GL_H

#include <epoxy/gl.h>

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_gl_context sam_gl_context;

typedef struct sam_gl_info {
    char renderer[128];
    char version[128];
    int major, minor;
    GLint max_ssbo_size;          /* bytes per shader-storage block */
    GLint max_compute_invocations;
    int debug_output;             /* 1 when GL debug output is on */
} sam_gl_info;

/* Creates a headless GL 4.3 core context and makes it current: the
 * surfaceless platform, else the first EGL device that gives one, or the
 * device SAM_EGL_DEVICE names.
 * Errors: SAM_ERR_UNSUPPORTED naming the missing piece (no headless EGL
 * platform, what each platform and device answered, no GL 4.3 core, a
 * limit below what the runtime needs), SAM_ERR_INVALID_ARGUMENT
 * (SAM_EGL_DEVICE not an index, or past the devices EGL lists),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_gl_context_create_headless(sam_gl_context **ctx, sam_error *err);

/* Checks the context current on this thread, made by anyone (a window
 * toolkit's, say), as sam_gl_context_create_headless checks its own: GL 4.3
 * core and the limits the runtime needs; fills `info` (may be NULL) and, with `debug`,
 * turns GL debug output on (messages to stderr).
 * Errors: SAM_ERR_UNSUPPORTED naming the renderer and what it lacks. */
sam_status sam_gl_check_current(int debug, sam_gl_info *info, sam_error *err);

/* With a context current: whether the GL can render a width x height
 * picture, before any work is done for it: its side against
 * GL_MAX_TEXTURE_SIZE, GL_MAX_RENDERBUFFER_SIZE, GL_MAX_FRAMEBUFFER_WIDTH
 * and _HEIGHT and GL_MAX_VIEWPORT_DIMS, then a proxy RGBA32F texture of
 * that size (the GL's own answer on its memory; nothing is allocated).
 * Errors: SAM_ERR_UNSUPPORTED naming the limit and its value, or the size
 * that does not fit. */
sam_status sam_gl_check_picture_size(uint32_t width, uint32_t height, sam_error *err);

/* 1 when GL debug output is wanted: a build without NDEBUG, or
 * SAM_GL_DEBUG=1 in the environment. */
int sam_gl_debug_requested(void);

/* Releases the context (NULL is fine). */
void sam_gl_context_destroy(sam_gl_context *ctx);

/* Renderer, version and limits of a live context. */
const sam_gl_info *sam_gl_context_info(const sam_gl_context *ctx);

/* Testing aid. Number of embedded shader files and their names. */
size_t sam_gl_shader_file_count(void);
const char *sam_gl_shader_file_name(size_t index);

/* Testing aid. The full text of embedded file `name` after include expansion, with
 * #line directives, as GL will see it; `defines` (may be NULL) is inserted
 * after the #version line. Caller frees. Errors: SAM_ERR_INVALID_ARGUMENT
 * (unknown file, include cycle, malformed include: naming file and line). */
sam_status sam_gl_shader_source(const char *name, const char *defines, char **source, sam_error *err);

/* Compiles and links a compute program from embedded file `name`.
 * Errors: SAM_ERR_FORMAT with the first error rewritten to file:line. */
sam_status sam_gl_compute_program(const char *name, const char *defines, GLuint *program, sam_error *err);

/* Compiles and links a vertex + fragment program. */
sam_status sam_gl_render_program(const char *vertex, const char *fragment, const char *defines, GLuint *program,
                                 sam_error *err);

/* Testing aid. Compiles a program from source text given directly:
 * `file_name` is used in messages. */
sam_status sam_gl_compute_program_from_text(const char *file_name, const char *text, GLuint *program,
                                            sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
