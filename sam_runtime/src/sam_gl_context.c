/* Headless GL contexts through EGL's surfaceless platform. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/egl.h>

#include "sam/sam_gl.h"
#include "sam_bindings.h"

struct sam_gl_context {
    EGLDisplay display;
    EGLContext context;
    sam_gl_info info;
};

/* What the runtime's compute passes and buffers need at least. */
#define NEED_SSBO_SIZE (16 * 1024 * 1024)
#define NEED_COMPUTE_INVOCATIONS 256
#define NEED_SSBO_BINDINGS SAM_B_LIMIT

static void APIENTRY debug_message(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                   const GLchar *message, const void *user)
{
    (void)source, (void)id, (void)length, (void)user;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION)
        return;
    fprintf(stderr, "GL debug (%s): %s\n", type == GL_DEBUG_TYPE_ERROR ? "error" : "message", message);
}

static sam_status fail_egl(sam_gl_context *c, sam_error *err, const char *what)
{
    sam_status st = sam_fail(err, SAM_ERR_UNSUPPORTED, "GL: %s (EGL error 0x%04x)", what, (unsigned)eglGetError());
    sam_gl_context_destroy(c);
    return st;
}

sam_status sam_gl_check_current(int debug, sam_gl_info *info, sam_error *err)
{
    sam_gl_info unused, *i = info ? info : &unused;
    memset(i, 0, sizeof *i);
    snprintf(i->renderer, sizeof i->renderer, "%s", (const char *)glGetString(GL_RENDERER));
    snprintf(i->version, sizeof i->version, "%s", (const char *)glGetString(GL_VERSION));
    glGetIntegerv(GL_MAJOR_VERSION, &i->major);
    glGetIntegerv(GL_MINOR_VERSION, &i->minor);
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &i->max_ssbo_size);
    glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &i->max_compute_invocations);
    if (i->major * 10 + i->minor < 43)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "GL: %s offers OpenGL %d.%d; the runtime needs 4.3", i->renderer,
                        i->major, i->minor);
    GLint bindings = 0;
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
    if (i->max_ssbo_size < NEED_SSBO_SIZE || i->max_compute_invocations < NEED_COMPUTE_INVOCATIONS ||
        bindings < NEED_SSBO_BINDINGS)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "GL: %s allows %d-byte storage blocks, %d compute invocations per group and %d storage "
                        "bindings; the runtime needs %d, %d and %d",
                        i->renderer, i->max_ssbo_size, i->max_compute_invocations, bindings, NEED_SSBO_SIZE,
                        NEED_COMPUTE_INVOCATIONS, NEED_SSBO_BINDINGS);
    if (debug) {
        glEnable(GL_DEBUG_OUTPUT);
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageCallback(debug_message, NULL);
        i->debug_output = 1;
    }
    return SAM_OK;
}

sam_status sam_gl_check_picture_size(uint32_t width, uint32_t height, sam_error *err)
{
    static const struct {
        GLenum name;
        int sides; /* 3: both; 1: the width; 2: the height */
        const char *what;
    } limits[] = {
        {GL_MAX_TEXTURE_SIZE, 3, "GL_MAX_TEXTURE_SIZE"},
        {GL_MAX_RENDERBUFFER_SIZE, 3, "GL_MAX_RENDERBUFFER_SIZE"},
        {GL_MAX_FRAMEBUFFER_WIDTH, 1, "GL_MAX_FRAMEBUFFER_WIDTH"},
        {GL_MAX_FRAMEBUFFER_HEIGHT, 2, "GL_MAX_FRAMEBUFFER_HEIGHT"},
        {GL_MAX_VIEWPORT_DIMS, 3, "GL_MAX_VIEWPORT_DIMS"},
    };
    for (size_t i = 0; i < sizeof limits / sizeof limits[0]; ++i) {
        GLint value[2] = {0, 0};
        glGetIntegerv(limits[i].name, value);
        /* The viewport's two dimensions: the smaller holds for both. */
        const GLint limit = limits[i].name == GL_MAX_VIEWPORT_DIMS && value[1] < value[0] ? value[1] : value[0];
        const uint32_t side = limits[i].sides == 1   ? width
                              : limits[i].sides == 2 ? height
                              : width > height       ? width
                                                     : height;
        if (limit > 0 && side > (uint32_t)limit)
            return sam_fail(err, SAM_ERR_UNSUPPORTED,
                            "a %ux%u picture passes the GL's %s of %d (%s): choose a smaller resolution", width,
                            height, limits[i].what, limit, (const char *)glGetString(GL_RENDERER));
    }
    /* Within the limits, the GL may still lack the memory for one
     * RGBA32F target; its proxy texture says so without allocating. */
    while (glGetError() != GL_NO_ERROR) {
    }
    glTexImage2D(GL_PROXY_TEXTURE_2D, 0, GL_RGBA32F, (GLsizei)width, (GLsizei)height, 0, GL_RGBA, GL_FLOAT, NULL);
    GLint got = 0;
    glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &got);
    while (glGetError() != GL_NO_ERROR) {
    }
    if (got == 0)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "the GL (%s) cannot hold a %ux%u RGBA32F picture (%.2f GiB a target): choose a smaller "
                        "resolution",
                        (const char *)glGetString(GL_RENDERER), width, height,
                        (double)width * height * 16 / (1024.0 * 1024 * 1024));
    return SAM_OK;
}

int sam_gl_debug_requested(void)
{
    const char *env = getenv("SAM_GL_DEBUG");
#ifndef NDEBUG
    (void)env;
    return 1;
#else
    return env && env[0] == '1';
#endif
}

sam_status sam_gl_context_create_headless(sam_gl_context **out, sam_error *err)
{
    *out = NULL;
    sam_gl_context *c = calloc(1, sizeof *c);
    if (!c)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "GL: out of memory");
    c->display = EGL_NO_DISPLAY;
    c->context = EGL_NO_CONTEXT;
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless") &&
        !epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base")) {
        sam_gl_context_destroy(c);
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "GL: EGL has no surfaceless platform (EGL_MESA_platform_surfaceless); install Mesa's "
                        "libegl-mesa0 or a GPU driver with EGL");
    }
    c->display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    EGLint major, minor;
    if (c->display == EGL_NO_DISPLAY || !eglInitialize(c->display, &major, &minor))
        return fail_egl(c, err, "cannot open a surfaceless EGL display");
    if (!eglBindAPI(EGL_OPENGL_API))
        return fail_egl(c, err, "EGL cannot bind desktop OpenGL");
    int debug = sam_gl_debug_requested();
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_CONTEXT_OPENGL_DEBUG, debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    c->context = eglCreateContext(c->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (c->context == EGL_NO_CONTEXT)
        return fail_egl(c, err, "no OpenGL 4.3 core context (the driver offers less)");
    if (!eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, c->context))
        return fail_egl(c, err, "cannot make the surfaceless context current");
    sam_status st = sam_gl_check_current(debug, &c->info, err);
    if (st != SAM_OK) {
        sam_gl_context_destroy(c);
        return st;
    }
    *out = c;
    return SAM_OK;
}

void sam_gl_context_destroy(sam_gl_context *c)
{
    if (!c)
        return;
    if (c->display != EGL_NO_DISPLAY) {
        eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (c->context != EGL_NO_CONTEXT)
            eglDestroyContext(c->display, c->context);
        eglTerminate(c->display);
        /* EGL keeps per-thread state (the bound API, the last error) until
         * the thread releases it. */
        eglReleaseThread();
    }
    free(c);
}

const sam_gl_info *sam_gl_context_info(const sam_gl_context *c)
{
    return &c->info;
}
