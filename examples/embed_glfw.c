/*
 * embed_glfw: SAM translucency inside a program that is not SAM's: its
 * own window (GLFW), its own mesh in its own vertex buffer, its own shader
 * and its own vertex animation (an ear-like shell swaying, posed on the
 * CPU each frame). SAM reads the posed buffer, runs its passes and hands
 * back a buffer of per-vertex translucency, which the program's shader
 * reads as one more vertex attribute. The SAM calls are the lines between
 * "SAM:" and "end of SAM" below (docs/embedding.md walks through them).
 *
 *   embed_glfw [--frames N] [--screenshot OUT.png] [--no-sam] [--size WxH]
 *
 * Without --frames it runs until the window is closed (Esc closes it).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>

#include "sam/sam_build.h"
#include "sam/sam_runtime.h"
#include "sam/sam_shape.h"

/* ---- The program's own asset, animation and drawing ---- */

typedef struct asset {
    uint32_t vertex_count, triangle_count;
    float *rest;          /* 3 per vertex */
    uint32_t *triangles;
    float *vertices;      /* the vertex buffer's contents: position, normal (6 floats per vertex) */
    float lo[3], hi[3];
} asset;

static void load_asset(asset *a)
{
    sam_shape_params params;
    sam_shape_mesh s;
    sam_error err;
    if (sam_shape_default_params("ear", &params, &err) != SAM_OK || sam_shape_generate("ear", &params, &s, &err)) {
        fprintf(stderr, "embed_glfw: %s\n", err.message);
        exit(1);
    }
    a->vertex_count = s.vertex_count;
    a->triangle_count = s.triangle_count;
    a->rest = s.positions;
    a->triangles = s.triangles;
    free(s.uvs);
    a->vertices = calloc(6 * (size_t)a->vertex_count, sizeof *a->vertices);
    for (int c = 0; c < 3; ++c)
        a->lo[c] = INFINITY, a->hi[c] = -INFINITY;
    for (uint32_t v = 0; v < a->vertex_count; ++v)
        for (int c = 0; c < 3; ++c) {
            a->lo[c] = fminf(a->lo[c], a->rest[3 * v + c]);
            a->hi[c] = fmaxf(a->hi[c], a->rest[3 * v + c]);
        }
}

/* The animation: the shell sways about its vertical axis, more at the top. */
static void pose_asset(asset *a, double t)
{
    const float height = a->hi[1] - a->lo[1];
    const float cx = 0.5f * (a->lo[0] + a->hi[0]), cz = 0.5f * (a->lo[2] + a->hi[2]);
    for (uint32_t v = 0; v < a->vertex_count; ++v) {
        const float *r = a->rest + 3 * v;
        const float angle = 0.5f * (float)sin(1.3 * t) * (r[1] - a->lo[1]) / height;
        const float x = r[0] - cx, z = r[2] - cz;
        float *p = a->vertices + 6 * v;
        p[0] = cx + x * cosf(angle) - z * sinf(angle);
        p[1] = r[1];
        p[2] = cz + x * sinf(angle) + z * cosf(angle);
        p[3] = p[4] = p[5] = 0.0f;
    }
    for (uint32_t t3 = 0; t3 < 3 * a->triangle_count; t3 += 3) {
        float *p[3], e1[3], e2[3];
        for (int k = 0; k < 3; ++k)
            p[k] = a->vertices + 6 * (size_t)a->triangles[t3 + k];
        for (int c = 0; c < 3; ++c)
            e1[c] = p[1][c] - p[0][c], e2[c] = p[2][c] - p[0][c];
        const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c)
                p[k][3 + c] += n[c];
    }
}

static const char *vertex_source =
    "#version 430 core\n"
    "layout(location = 0) in vec3 a_position;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec4 a_translucency;\n"
    "uniform mat4 u_view_projection;\n"
    "out vec3 v_normal;\n"
    "out vec3 v_translucency;\n"
    "void main() {\n"
    "    v_normal = a_normal;\n"
    "    v_translucency = a_translucency.rgb;\n"
    "    gl_Position = u_view_projection * vec4(a_position, 1.0);\n"
    "}\n";

/* The program's own look: a key light from the front left, a little
 * ambient, and SAM's translucency added as light leaving the surface. */
static const char *fragment_source =
    "#version 430 core\n"
    "in vec3 v_normal;\n"
    "in vec3 v_translucency;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec3 albedo = vec3(0.85, 0.62, 0.52);\n"
    "    vec3 n = normalize(v_normal);\n"
    "    float key = max(dot(n, normalize(vec3(-0.4, 0.5, 1.0))), 0.0);\n"
    "    vec3 c = albedo * (0.08 + 0.35 * key) + albedo * v_translucency;\n"
    "    o_color = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);\n"
    "}\n";

static GLuint compile(GLenum type, const char *text)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &text, NULL);
    glCompileShader(s);
    GLint ok;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "embed_glfw: shader: %s\n", log);
        exit(1);
    }
    return s;
}

/* A perspective camera on +z looking down -z at the asset's centre:
 * projection times a translation, column-major. */
static void view_projection(const asset *a, float aspect, float m[16])
{
    const float size = fmaxf(a->hi[0] - a->lo[0], a->hi[1] - a->lo[1]);
    const float eye[3] = {0.5f * (a->lo[0] + a->hi[0]), 0.5f * (a->lo[1] + a->hi[1]), a->hi[2] + 2.2f * size};
    const float near = 0.1f * size, far = 10.0f * size, f = 1.0f / tanf(0.35f);
    float p[16] = {0}, v[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -eye[0], -eye[1], -eye[2], 1};
    p[0] = f / aspect;
    p[5] = f;
    p[10] = (far + near) / (near - far);
    p[11] = -1.0f;
    p[14] = 2.0f * far * near / (near - far);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            m[4 * c + r] = 0.0f;
            for (int k = 0; k < 4; ++k)
                m[4 * c + r] += p[4 * k + r] * v[4 * c + k];
        }
}

int main(int argc, char **argv)
{
    int frames = 0, use_sam = 1, width = 640, height = 480;
    const char *screenshot = NULL;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--frames") && i + 1 < argc)
            frames = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--screenshot") && i + 1 < argc)
            screenshot = argv[++i];
        else if (!strcmp(argv[i], "--no-sam"))
            use_sam = 0;
        else if (!strcmp(argv[i], "--size") && i + 1 < argc && sscanf(argv[++i], "%dx%d", &width, &height) == 2)
            continue;
        else {
            fprintf(stderr, "usage: embed_glfw [--frames N] [--screenshot OUT.png] [--no-sam] [--size WxH]\n");
            return !(!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) * 2;
        }
    }
    if (!glfwInit()) {
        fprintf(stderr, "embed_glfw: no display for a window (GLFW could not start)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_VISIBLE, frames ? GLFW_FALSE : GLFW_TRUE);
    GLFWwindow *window = glfwCreateWindow(width, height, "SAM inside someone else's program", NULL, NULL);
    if (!window) {
        fprintf(stderr, "embed_glfw: no OpenGL 4.3 core window\n");
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(window);

    asset a;
    load_asset(&a);
    GLuint vao, vbo, ibo, program = glCreateProgram();
    glAttachShader(program, compile(GL_VERTEX_SHADER, vertex_source));
    glAttachShader(program, compile(GL_FRAGMENT_SHADER, fragment_source));
    glLinkProgram(program);
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &vbo);
    glGenBuffers(1, &ibo);
    glBindVertexArray(vao);
    pose_asset(&a, 0.0);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, 6 * sizeof(float) * a.vertex_count, a.vertices, GL_DYNAMIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(3 * sizeof(float)));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, 3 * sizeof(uint32_t) * a.triangle_count, a.triangles, GL_STATIC_DRAW);
    glVertexAttrib4f(2, 0.0f, 0.0f, 0.0f, 0.0f); /* no translucency until SAM gives some */

    /* SAM: a map of the same asset, the runtime on this context, a light behind it. */
    sam_error err;
    sam_runtime *rt = NULL;
    if (use_sam) {
        sam_mesh mesh;
        sam_profile skin;
        samfile_data map;
        sam_mesh_input in = {.name = "ear", .vertex_count = a.vertex_count, .positions = a.rest,
                             .triangle_count = a.triangle_count, .triangles = a.triangles};
        sam_light back = {.type = SAM_LIGHT_POINT, .color = {1, 0.95f, 0.9f}, .intensity = 6, .shadow = 1,
                          .position = {0.5f * (a.lo[0] + a.hi[0]), a.hi[1], a.lo[2] - 1.0f}};
        sam_engine_pose pose = {.positions = vbo, .position_stride = 6 * sizeof(float), .normals = vbo,
                                .normal_offset = 3 * sizeof(float), .normal_stride = 6 * sizeof(float),
                                .vertex_count = a.vertex_count};
        if (sam_gl_check_current(0, NULL, &err) || sam_mesh_create(&in, &mesh, NULL, &err) ||
            sam_profile_preset("skin", &skin, &err) ||
            sam_build_samfile(&mesh, &skin, 60.0f, NULL, NULL, NULL, NULL, &map, NULL, &err) ||
            sam_runtime_create(&map, &skin, 60.0f, &rt, &err) || sam_runtime_set_lights(rt, &back, 1, &err) ||
            sam_runtime_set_engine_pose(rt, &pose, &err)) {
            fprintf(stderr, "embed_glfw: SAM: %s\n", err.message);
            return 1;
        }
        samfile_free(&map);
        sam_mesh_destroy(&mesh);
    }
    /* end of SAM setup */

    for (int frame = 0; !glfwWindowShouldClose(window) && (!frames || frame < frames); ++frame) {
        const double t = frames ? frame / 30.0 : glfwGetTime();
        pose_asset(&a, t);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferSubData(GL_ARRAY_BUFFER, 0, 6 * sizeof(float) * a.vertex_count, a.vertices);

        /* SAM: follow the pose, light it, and bind T as attribute 2. */
        if (rt) {
            GLuint translucency;
            if (sam_runtime_pose_from_engine(rt, &err) || sam_runtime_walk(rt, &err) ||
                sam_runtime_irradiance(rt, &err) || sam_runtime_translucency(rt, 0, 1.0f / 30.0f, frame == 0, &err) ||
                sam_runtime_engine_translucency(rt, &translucency, &err)) {
                fprintf(stderr, "embed_glfw: SAM: %s\n", err.message);
                return 1;
            }
            glBindVertexArray(vao);
            glBindBuffer(GL_ARRAY_BUFFER, translucency);
            glEnableVertexAttribArray(2);
            glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), (void *)0);
        }
        /* end of SAM per frame */

        int w, h;
        glfwGetFramebufferSize(window, &w, &h);
        glBindFramebuffer(GL_FRAMEBUFFER, 0); /* SAM's shadow maps drew elsewhere */
        glViewport(0, 0, w, h);
        glEnable(GL_DEPTH_TEST);
        glClearColor(0.05f, 0.05f, 0.06f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        float m[16];
        view_projection(&a, (float)w / (float)h, m);
        glUseProgram(program);
        glUniformMatrix4fv(glGetUniformLocation(program, "u_view_projection"), 1, GL_FALSE, m);
        glBindVertexArray(vao);
        glDrawElements(GL_TRIANGLES, (GLsizei)(3 * a.triangle_count), GL_UNSIGNED_INT, NULL);
        if (screenshot && frames && frame == frames - 1) {
            sam_image img;
            if (sam_image_create(&img, (uint32_t)w, (uint32_t)h, 3, &err) != SAM_OK)
                return 1;
            unsigned char *rgb = malloc(3 * (size_t)w * h);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb);
            for (int y = 0; y < h; ++y) /* GL's rows run bottom up */
                for (int x = 0; x < 3 * w; ++x)
                    img.pixels[(size_t)y * 3 * w + x] = rgb[(size_t)(h - 1 - y) * 3 * w + x] / 255.0f;
            free(rgb);
            if (sam_image_write_png(screenshot, &img, SAM_PNG_LINEAR, &err) != SAM_OK) {
                fprintf(stderr, "embed_glfw: %s\n", err.message);
                return 1;
            }
            sam_image_destroy(&img);
        }
        glfwSwapBuffers(window);
        glfwPollEvents();
        if (glfwGetKey(window, GLFW_KEY_ESCAPE) == GLFW_PRESS)
            glfwSetWindowShouldClose(window, 1);
    }
    sam_runtime_destroy(rt); /* SAM: before the context goes */
    glfwDestroyWindow(window);
    glfwTerminate();
    free(a.rest);
    free(a.triangles);
    free(a.vertices);
    return 0;
}
