/* GL helpers every pass of the runtime uses (sam_runtime_gpu.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam_runtime_gpu.h"

size_t sam_runtime_block_limit(void)
{
    GLint limit = 0;
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &limit);
    return limit > 0 ? (size_t)limit : 0;
}

sam_status sam_runtime_check_block_size(const char *what, size_t bytes, sam_error *err)
{
    const size_t limit = sam_runtime_block_limit();
    if (bytes > limit)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "runtime: %s needs %zu bytes but the GL allows %zu per storage block",
                        what, bytes, limit);
    return SAM_OK;
}

sam_status sam_runtime_upload(sam_runtime *rt, int binding, const void *data, size_t bytes, sam_error *err)
{
    char what[32];
    snprintf(what, sizeof what, "buffer %d", binding);
    sam_status st = sam_runtime_check_block_size(what, bytes, err);
    if (st != SAM_OK)
        return st;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->buffer[binding]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(bytes ? bytes : 16), data, GL_DYNAMIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)binding, rt->buffer[binding]);
    return glGetError() == GL_NO_ERROR
               ? SAM_OK
               : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not allocate %zu bytes", bytes);
}

float *sam_runtime_widen(const float *xyz, uint32_t count, float w)
{
    float *out = malloc((size_t)count * 4 * sizeof *out);
    if (out)
        for (uint32_t v = 0; v < count; ++v) {
            memcpy(out + 4 * (size_t)v, xyz + 3 * (size_t)v, 3 * sizeof(float));
            out[4 * (size_t)v + 3] = w;
        }
    return out;
}

void sam_runtime_pack_k(const float k[3], uint32_t packed[2])
{
    uint32_t c[3];
    for (int i = 0; i < 3; ++i) {
        const float x = k[i] > 0.0f ? fminf(k[i], 1.0e38f) : 0.0f; /* NaN fails k > 0 */
        memcpy(&c[i], &x, sizeof x);
        c[i] = (c[i] + 0x200u) >> 10;
    }
    packed[0] = c[0] | c[1] << 21;
    packed[1] = c[1] >> 11 | c[2] << 10;
}

void sam_runtime_unpack_k(const uint32_t packed[2], float k[3])
{
    const uint32_t c[3] = {packed[0] & 0x1FFFFFu, (packed[0] >> 21 | packed[1] << 11) & 0x1FFFFFu,
                           (packed[1] >> 10) & 0x1FFFFFu};
    for (int i = 0; i < 3; ++i) {
        const uint32_t bits = c[i] << 10;
        memcpy(&k[i], &bits, sizeof bits);
    }
}

void sam_runtime_bind_buffers(const sam_runtime *rt)
{
    for (int b = 0; b < SAM_B_COUNT; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, rt->buffer[b]);
}

void sam_runtime_begin_timer(sam_runtime *rt, sam_pass pass)
{
    rt->query_begun[pass] = sam_seconds();
    glBeginQuery(GL_TIME_ELAPSED, rt->query[pass]);
}

void sam_runtime_end_timer(sam_runtime *rt, sam_pass pass)
{
    glEndQuery(GL_TIME_ELAPSED);
    rt->query_used[pass] = 1;
}

void sam_runtime_dispatch_per_vertex(sam_runtime *rt, sam_pass pass)
{
    sam_runtime_begin_timer(rt, pass);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
    sam_runtime_end_timer(rt, pass);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void sam_runtime_delete_program(GLuint *program)
{
    if (*program)
        glDeleteProgram(*program);
    *program = 0;
}

void sam_runtime_set_profile_uniforms(GLuint program, const sam_profile *p)
{
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "u_profile_kind"), p->kind == SAM_PROFILE_DIPOLE ? 1 : 0);
    if (p->kind == SAM_PROFILE_DIPOLE) {
        sam_dipole_terms t;
        sam_profile_dipole_terms(p, &t);
        glUniform3fv(glGetUniformLocation(program, "u_dipole_alpha"), 1, t.alpha);
        glUniform3fv(glGetUniformLocation(program, "u_dipole_sigma_tr"), 1, t.sigma_tr);
        glUniform3fv(glGetUniformLocation(program, "u_dipole_zr"), 1, t.z_r);
        glUniform3fv(glGetUniformLocation(program, "u_dipole_zv"), 1, t.z_v);
    } else {
        float g[SAM_PROFILE_MAX_GAUSSIANS][4];
        for (uint32_t i = 0; i < p->gaussian_count; ++i) {
            memcpy(g[i], p->weight[i], 3 * sizeof(float));
            g[i][3] = p->variance[i];
        }
        glUniform1i(glGetUniformLocation(program, "u_gaussian_count"), (GLint)p->gaussian_count);
        glUniform4fv(glGetUniformLocation(program, "u_gaussians"), (GLsizei)p->gaussian_count, &g[0][0]);
    }
}

/* The radius of the sphere around the box lo..hi. */
static double box_radius(const float lo[3], const float hi[3])
{
    double r2 = 0;
    for (int c = 0; c < 3; ++c)
        r2 += 0.25 * ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
    return sqrt(r2);
}

void sam_runtime_choose_frame(sam_runtime *rt, const float lo[3], const float hi[3])
{
    const double radius = box_radius(lo, hi);
    /* A grid step 2^e >= the radius, and the multiple of it nearest the
     * centre: 0 (no change at all) for a mesh about the origin; for one far
     * from it, a float whose difference with a vertex's coordinate comes
     * out exact (Sterbenz), and so does adding the frame back. */
    int e;
    frexp(radius, &e);
    for (int c = 0; c < 3; ++c) {
        const double centre = 0.5 * ((double)lo[c] + hi[c]);
        rt->frame[c] = radius > 0 && isfinite(centre) ? (float)ldexp(nearbyint(ldexp(centre, -e)), e) : 0.0f;
    }
}

void sam_runtime_to_frame(const sam_runtime *rt, const float p[3], float out[3])
{
    for (int c = 0; c < 3; ++c)
        out[c] = p[c] - rt->frame[c];
}

void sam_runtime_from_frame(const sam_runtime *rt, const float p[3], float out[3])
{
    for (int c = 0; c < 3; ++c)
        out[c] = p[c] + rt->frame[c];
}

void sam_runtime_set_box(sam_runtime *rt, const float lo[3], const float hi[3])
{
    for (int c = 0; c < 3; ++c)
        rt->centre[c] = 0.5f * (lo[c] + hi[c]);
    rt->radius = (float)box_radius(lo, hi);
    memcpy(rt->box_lo, lo, 3 * sizeof(float));
    memcpy(rt->box_hi, hi, 3 * sizeof(float));
}

void sam_runtime_texture_sampling(GLenum target, GLint filter)
{
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

GLuint sam_runtime_image_texture(const sam_image *image, GLsizei levels, int flip)
{
    while (glGetError() != GL_NO_ERROR) {
    }
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, levels, GL_RGBA32F, (GLsizei)image->width, (GLsizei)image->height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    GLenum format = image->channels == 4 ? GL_RGBA : GL_RGB;
    for (uint32_t y = 0; y < image->height; ++y)
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, (GLint)(flip ? image->height - 1 - y : y), (GLsizei)image->width, 1,
                        format, GL_FLOAT, image->pixels + (size_t)y * image->width * image->channels);
    sam_runtime_texture_sampling(GL_TEXTURE_2D, GL_LINEAR);
    if (glGetError() != GL_NO_ERROR) {
        glDeleteTextures(1, &tex);
        return 0;
    }
    return tex;
}

sam_status sam_runtime_read_texture(GLuint tex, uint32_t full_width, uint32_t full_height, uint32_t w, uint32_t h,
                                    int flip, sam_image *out, sam_error *err)
{
    sam_image whole;
    sam_status st = sam_image_create(&whole, full_width, full_height, 4, err);
    if (st != SAM_OK)
        return st;
    if ((st = sam_image_create(out, w, h, 4, err)) != SAM_OK) {
        sam_image_destroy(&whole);
        return st;
    }
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, whole.pixels);
    for (uint32_t y = 0; y < h; ++y)
        memcpy(out->pixels + (size_t)(flip ? h - 1 - y : y) * w * 4, whole.pixels + (size_t)y * full_width * 4,
               (size_t)w * 4 * sizeof(float));
    sam_image_destroy(&whole);
    return SAM_OK;
}
