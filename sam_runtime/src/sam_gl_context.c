/* Headless GL contexts through EGL's surfaceless or device platform. */
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

/* Initialises `display`, binds desktop GL and makes a configless 4.3 core
 * context current on it. On failure terminates the display, leaves `c`
 * without one, and writes the step and EGL error to `why`. */
static int open_display(sam_gl_context *c, EGLDisplay display, int debug, char *why, size_t why_size)
{
    EGLint major, minor;
    const char *step = NULL;
    c->display = display;
    c->context = EGL_NO_CONTEXT;
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_CONTEXT_OPENGL_DEBUG, debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    if (display == EGL_NO_DISPLAY)
        step = "no display";
    else if (!eglInitialize(display, &major, &minor))
        step = "cannot initialise the display";
    else if (!eglBindAPI(EGL_OPENGL_API))
        step = "cannot bind desktop OpenGL";
    else if ((c->context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs)) ==
             EGL_NO_CONTEXT)
        step = "no OpenGL 4.3 core context (the driver offers less)";
    else if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, c->context))
        step = "cannot make the surfaceless context current";
    if (!step)
        return 1;
    snprintf(why, why_size, "%s (EGL error 0x%04x)", step, (unsigned)eglGetError());
    if (display != EGL_NO_DISPLAY) {
        if (c->context != EGL_NO_CONTEXT)
            eglDestroyContext(display, c->context);
        eglTerminate(display);
    }
    c->display = EGL_NO_DISPLAY;
    c->context = EGL_NO_CONTEXT;
    return 0;
}

/* SAM_EGL_DEVICE=i picks the i-th EGL device; unset, -1. */
static sam_status requested_device(int *index, sam_error *err)
{
    const char *env = getenv("SAM_EGL_DEVICE");
    *index = -1;
    if (!env || !env[0])
        return SAM_OK;
    char *end = NULL;
    long v = strtol(env, &end, 10);
    if (*end != '\0' || v < 0 || v > 1000)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "GL: SAM_EGL_DEVICE is '%s'; it takes an EGL device index (0 for the first)", env);
    *index = (int)v;
    return SAM_OK;
}

#define MAX_EGL_DEVICES 16

sam_status sam_gl_context_create_headless(sam_gl_context **out, sam_error *err)
{
    *out = NULL;
    int want_device;
    sam_status st = requested_device(&want_device, err);
    if (st != SAM_OK)
        return st;
    sam_gl_context *c = calloc(1, sizeof *c);
    if (!c)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "GL: out of memory");
    c->display = EGL_NO_DISPLAY;
    c->context = EGL_NO_CONTEXT;
    int debug = sam_gl_debug_requested();
    int have_surfaceless = epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless");
    int have_devices = epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device") &&
                       epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration");
    char tried[512] = "", why[160];
    size_t used = 0;
    int opened = 0;
    /* Mesa's surfaceless platform first: it is what every test runs on.
     * GPU drivers without it (NVIDIA's, headless) offer their devices. */
    if (want_device < 0 && have_surfaceless) {
        opened = open_display(c, eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL),
                              debug, why, sizeof why);
        if (!opened)
            used += (size_t)snprintf(tried + used, sizeof tried - used, "surfaceless platform: %s", why);
    }
    if (!opened && have_devices) {
        EGLDeviceEXT devices[MAX_EGL_DEVICES];
        EGLint count = 0;
        if (!eglQueryDevicesEXT(MAX_EGL_DEVICES, devices, &count))
            count = 0;
        if (want_device >= count) {
            sam_gl_context_destroy(c);
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "GL: SAM_EGL_DEVICE is %d but EGL lists %d device%s (0 to %d)", want_device, (int)count,
                            count == 1 ? "" : "s", (int)count - 1);
        }
        for (EGLint i = want_device < 0 ? 0 : want_device; i < count && !opened; i++) {
            opened = open_display(c, eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL), debug, why,
                                  sizeof why);
            if (!opened && used < sizeof tried)
                used += (size_t)snprintf(tried + used, sizeof tried - used, "%sdevice %d: %s", used ? "; " : "",
                                         (int)i, why);
            if (want_device >= 0)
                break;
        }
    } else if (!opened && want_device >= 0) {
        sam_gl_context_destroy(c);
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "GL: SAM_EGL_DEVICE is set but EGL has no device platform (EGL_EXT_platform_device)");
    }
    if (!opened) {
        sam_gl_context_destroy(c);
        if (!have_surfaceless && !have_devices)
            return sam_fail(err, SAM_ERR_UNSUPPORTED,
                            "GL: EGL has neither the surfaceless platform (EGL_MESA_platform_surfaceless) nor "
                            "the device platform (EGL_EXT_platform_device); install Mesa's libegl-mesa0 or a GPU "
                            "driver with EGL");
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "GL: no headless OpenGL 4.3 context: %s",
                        used ? tried : "EGL lists no devices");
    }
    st = sam_gl_check_current(debug, &c->info, err);
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
