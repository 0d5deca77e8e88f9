/* The viewer's pictures: the render, the samples view, the overlay and
 * screenshots (sam_viewer_draw.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>
/* epoxy provides the GL prototypes; GLFW must not include its own. */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <stb/stb_easy_font.h>

#include "sam/sam_runtime_scene.h"
#include "sam_viewer_draw.h"

#define TEXT_SCALE 2.0f
#define PICK_RADIUS_PX 12.0

/* The runtime's view of the current state at `width` x `height`. */
static void make_view(const sam_viewer_window *w, int width, int height, sam_render_view *view)
{
    char warning[256];
    sam_runtime_scene_view(w->rt, &w->state.scene, view, warning, sizeof warning);
    view->width = (uint32_t)width;
    view->height = (uint32_t)height;
    sam_viewer_apply_view(&w->state, view);
}

/* A new vertex array and buffer, both bound, attribute 0 enabled. */
static void bind_new_array(GLuint *vao, GLuint *vbo)
{
    glGenVertexArrays(1, vao);
    glGenBuffers(1, vbo);
    glBindVertexArray(*vao);
    glBindBuffer(GL_ARRAY_BUFFER, *vbo);
    glEnableVertexAttribArray(0);
}

sam_status sam_viewer_draw_create(sam_viewer_window *w, sam_error *err)
{
    sam_status st = sam_gl_render_program("view_present.vert", "view_present.frag", NULL, &w->present_program, err);
    if (st == SAM_OK)
        st = sam_gl_render_program("view_lines.vert", "view_lines.frag", NULL, &w->lines_program, err);
    if (st == SAM_OK)
        st = sam_gl_render_program("view_text.vert", "view_text.frag", NULL, &w->text_program, err);
    if (st != SAM_OK)
        return st;
    glGenVertexArrays(1, &w->empty_vao);
    bind_new_array(&w->lines_vao, &w->lines_vbo);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, NULL);
    bind_new_array(&w->text_vao, &w->text_vbo);
    /* stb_easy_font's vertices: x, y, z floats and 4 colour bytes. */
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 16, NULL);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 16, (const void *)12);
    glBindVertexArray(0);
    return SAM_OK;
}

/* The vertex under the cursor: the front-most of those within
 * PICK_RADIUS_PX, else the one nearest to it on screen; -1 for none in
 * front of the camera. */
static long pick_vertex(sam_viewer_window *w, const float vp[16], int width, int height)
{
    uint32_t n = w->sam.vertex_count;
    sam_error err;
    if (sam_runtime_read_positions(w->rt, w->positions, &err) != SAM_OK) {
        sam_viewer_say(&w->state, "samples view: %s", err.message);
        return -1;
    }
    long best = -1, nearest = -1;
    float best_depth = INFINITY;
    double nearest_d2 = INFINITY;
    for (uint32_t i = 0; i < n; ++i) {
        const float *p = w->positions + 3 * i;
        float clip[4];
        for (int r = 0; r < 4; ++r)
            clip[r] = vp[r] * p[0] + vp[4 + r] * p[1] + vp[8 + r] * p[2] + vp[12 + r];
        if (clip[3] <= 0)
            continue;
        double sx = (clip[0] / clip[3] * 0.5 + 0.5) * width, sy = (0.5 - clip[1] / clip[3] * 0.5) * height;
        double dx = sx - w->state.cursor_x, dy = sy - w->state.cursor_y;
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
static void draw_samples(sam_viewer_window *w, const float vp[16], int width, int height)
{
    long picked = pick_vertex(w, vp, width, height);
    if (picked < 0)
        return;
    sam_error err;
    if (sam_runtime_read_samples(w->rt, w->sample_index, w->sample_kprime, &err) != SAM_OK) {
        sam_viewer_say(&w->state, "samples view: %s", err.message);
        return;
    }
    float lines[2 * 64 * 3 + 3];
    uint32_t count = 0, used = sam_viewer_samples_used(&w->state);
    const float *from = w->positions + 3 * picked;
    for (uint32_t k = 0; k < used; ++k) {
        uint32_t b = w->sample_index[(size_t)picked * w->state.stride + k];
        if (b >= w->sam.vertex_count)
            continue;
        memcpy(lines + 6 * count, from, 3 * sizeof(float));
        memcpy(lines + 6 * count + 3, w->positions + 3 * (size_t)b, 3 * sizeof(float));
        ++count;
    }
    memcpy(lines + 6 * count, from, 3 * sizeof(float));
    glBindBuffer(GL_ARRAY_BUFFER, w->lines_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((6 * count + 3) * sizeof(float)), lines, GL_STREAM_DRAW);
    glUseProgram(w->lines_program);
    glUniformMatrix4fv(glGetUniformLocation(w->lines_program, "u_view_proj"), 1, GL_FALSE, vp);
    glBindVertexArray(w->lines_vao);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUniform4f(glGetUniformLocation(w->lines_program, "u_color"), 1.0f, 0.85f, 0.1f, 1.0f);
    /* Core profiles need not draw lines wider than a pixel: three pixels
     * wide from nine one-pixel copies, shifted in clip space. */
    GLint shift = glGetUniformLocation(w->lines_program, "u_shift");
    for (int i = 0; i < 9; ++i) {
        glUniform2f(shift, (float)(i % 3 - 1) * 2.0f / (float)width, (float)(i / 3 - 1) * 2.0f / (float)height);
        glDrawArrays(GL_LINES, 0, (GLsizei)(2 * count));
    }
    glUniform2f(shift, 0, 0);
    glUniform4f(glGetUniformLocation(w->lines_program, "u_color"), 0.1f, 0.9f, 1.0f, 1.0f);
    glDrawArrays(GL_POINTS, (GLsizei)(2 * count), 1);
    glBindVertexArray(0);
}

/* Text (and a dark panel behind it) at pixel (x, y) of a window `width` x `height`. */
static void draw_text(sam_viewer_window *w, float x, float y, const char *text, int width, int height)
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
            const float *src =
                q == 0 ? panel[order[i]] : (const float *)(quads + ((size_t)(q - 1) * 4 + order[i]) * 16);
            o[0] = q == 0 ? src[0] : x + src[0] * TEXT_SCALE;
            o[1] = q == 0 ? src[1] : y + src[1] * TEXT_SCALE;
            o[2] = 0;
            memcpy(&o[3], q == 0 ? dark : (const unsigned char *)src + 12, 4);
        }
    }
    free(quads);
    glBindBuffer(GL_ARRAY_BUFFER, w->text_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(floats * sizeof *tri), tri, GL_STREAM_DRAW);
    free(tri);
    glUseProgram(w->text_program);
    glUniform2f(glGetUniformLocation(w->text_program, "u_window"), (float)width, (float)height);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(w->text_vao);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)((n + 1) * 6));
    glBindVertexArray(0);
    glDisable(GL_BLEND);
}

/* The picture of the current state into the bound framebuffer: the
 * tonemapped render and the samples view's lines; `text` adds the readout
 * and help. Returns 0 when the render failed (the message is shown). */
int sam_viewer_draw_frame(sam_viewer_window *w, int width, int height, int text, double now)
{
    sam_render_view view;
    make_view(w, width, height, &view);
    GLuint image;
    sam_error err;
    GLint target;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    if (sam_runtime_render_texture(w->rt, &view, &image, &err) != SAM_OK) {
        sam_viewer_say(&w->state, "render: %s", err.message);
        glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
        glViewport(0, 0, width, height);
        glClearColor(0.3f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        return 0;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    GLuint p = w->present_program;
    glUseProgram(p);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, image);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, w->truth_tex);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_image"), 0);
    glUniform1i(glGetUniformLocation(p, "u_truth"), 1);
    glUniform1i(glGetUniformLocation(p, "u_mode"), w->state.mode == SAM_VIEWER_DIFFERENCE);
    glUniform1i(glGetUniformLocation(p, "u_curve"), w->state.scene.tonemap == SAM_TONEMAP_REINHARD);
    glUniform1f(glGetUniformLocation(p, "u_scale"), exp2f(w->state.scene.exposure));
    glUniform1f(glGetUniformLocation(p, "u_backdrop"), SAM_IMAGE_PICTURE_BACKDROP);
    glUniform1f(glGetUniformLocation(p, "u_gain"), 4.0f);
    glBindVertexArray(w->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    if (w->state.mode == SAM_VIEWER_SAMPLES) {
        float vp[16];
        sam_runtime_view_projection(w->rt, &view, vp);
        draw_samples(w, vp, width, height);
    }
    if (text) {
        char line[512];
        sam_viewer_overlay(&w->state, now, line, sizeof line);
        draw_text(w, 10, 10, line, width, height);
        if (w->state.help)
            draw_text(w, 10, 40 + (float)stb_easy_font_height(line) * TEXT_SCALE, sam_viewer_help_text(), width,
                      height);
    }
    return 1;
}

static sam_status ensure_shot_target(sam_viewer_window *w, int width, int height, sam_error *err)
{
    if (w->shot_fbo && w->shot_width == width && w->shot_height == height)
        return SAM_OK;
    if (w->shot_fbo) {
        glDeleteFramebuffers(1, &w->shot_fbo);
        glDeleteTextures(1, &w->shot_tex);
    }
    glGenFramebuffers(1, &w->shot_fbo);
    glGenTextures(1, &w->shot_tex);
    glBindTexture(GL_TEXTURE_2D, w->shot_tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, w->shot_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, w->shot_tex, 0);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        glDeleteFramebuffers(1, &w->shot_fbo);
        glDeleteTextures(1, &w->shot_tex);
        w->shot_fbo = w->shot_tex = 0;
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "screenshot: framebuffer incomplete (0x%04x) at %dx%d", status,
                        width, height);
    }
    w->shot_width = width;
    w->shot_height = height;
    return SAM_OK;
}

/* The displayed picture (without text) as an 8-bit image, top row first. */
static sam_status read_display(sam_viewer_window *w, int width, int height, sam_image *out, sam_error *err)
{
    sam_status st = ensure_shot_target(w, width, height, err);
    if (st != SAM_OK)
        return st;
    glBindFramebuffer(GL_FRAMEBUFFER, w->shot_fbo);
    int ok = sam_viewer_draw_frame(w, width, height, 0, 0.0);
    glBindFramebuffer(GL_FRAMEBUFFER, w->shot_fbo);
    unsigned char *rgba = malloc((size_t)width * height * 4);
    if (rgba) {
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!ok) {
        free(rgba);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "screenshot: the render failed: %s", w->state.message);
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

void sam_viewer_draw_screenshot(sam_viewer_window *w, const char *prefix)
{
    char base[4096], exr[4120], png[4120], json[4120];
    sam_viewer_shot_name(&w->state, prefix, base, sizeof base);
    snprintf(exr, sizeof exr, "%s.exr", base);
    snprintf(png, sizeof png, "%s.png", base);
    snprintf(json, sizeof json, "%s.json", base);
    int width, height;
    glfwGetFramebufferSize(w->window, &width, &height);
    sam_render_view view;
    make_view(w, width, height, &view);
    sam_image hdr = {0}, shown = {0};
    int translucency = w->state.mode == SAM_VIEWER_TRANSLUCENCY;
    sam_error err;
    if (sam_runtime_render(w->rt, &view, &hdr, &err) != SAM_OK ||
        sam_image_write_exr(exr, &hdr, SAM_EXR_FLOAT, &err) != SAM_OK ||
        read_display(w, width, height, &shown, &err) != SAM_OK ||
        sam_image_write_png(png, &shown, SAM_PNG_LINEAR, &err) != SAM_OK ||
        sam_viewer_write_scene(&w->state, json, width, height, &err) != SAM_OK)
        sam_viewer_say(&w->state, "screenshot failed: %s", err.message);
    else
        sam_viewer_say(&w->state,
                       "wrote %s, %s and %s; sam_render %s -o OUT.exr --png OUT.png%s reproduces the %s view", exr,
                       png, json, json, translucency ? " --translucency-only" : "",
                       translucency ? "translucency" : "final");
    sam_image_destroy(&hdr);
    sam_image_destroy(&shown);
}

void sam_viewer_draw_destroy(sam_viewer_window *w)
{
    glDeleteProgram(w->present_program);
    glDeleteProgram(w->lines_program);
    glDeleteProgram(w->text_program);
    glDeleteVertexArrays(1, &w->empty_vao);
    glDeleteVertexArrays(1, &w->lines_vao);
    glDeleteVertexArrays(1, &w->text_vao);
    glDeleteBuffers(1, &w->lines_vbo);
    glDeleteBuffers(1, &w->text_vbo);
    if (w->shot_fbo) {
        glDeleteFramebuffers(1, &w->shot_fbo);
        glDeleteTextures(1, &w->shot_tex);
    }
}
