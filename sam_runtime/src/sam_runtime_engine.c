/* An engine's posed buffers in, T in its vertex order out (sam_runtime.h,
 * "Embedding"; sam_runtime_engine.h). */
#include <stdlib.h>
#include <string.h>

#include "sam_runtime_deform.h"
#include "sam_runtime_engine.h"
#include "sam_runtime_gpu.h"

/* A GL buffer object of `bytes`, filled from `data`; 0 when the GL refused. */
static GLuint make_buffer(const void *data, size_t bytes)
{
    GLuint b = 0;
    glGenBuffers(1, &b);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(bytes ? bytes : 4), data, GL_STATIC_DRAW);
    if (glGetError() != GL_NO_ERROR) {
        glDeleteBuffers(1, &b);
        return 0;
    }
    return b;
}

/* The two maps between the orders, from SRCV: each SAM vertex reads the
 * engine vertex it came from; each engine vertex shows the T of the SAM
 * vertex it became (a seam's copies carry the same T). */
static sam_status upload_maps(sam_runtime *rt, const samfile_data *sam, sam_error *err)
{
    sam_rt_engine *e = &rt->engine;
    const uint32_t nv = rt->vertex_count, ne = sam->source_vertex_count;
    e->engine_of = make_buffer(sam->vertex_source, (size_t)nv * sizeof *sam->vertex_source);
    e->vertex_of = make_buffer(sam->source_vertex, (size_t)ne * sizeof *sam->source_vertex);
    e->translucency = make_buffer(NULL, (size_t)ne * 4 * sizeof(float));
    if (!e->engine_of || !e->vertex_of || !e->translucency)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not hold the engine's vertex order (%u "
                        "vertices)", ne);
    return SAM_OK;
}

sam_status sam_runtime_engine_create(sam_runtime *rt, const samfile_data *sam, sam_error *err)
{
    sam_rt_engine *e = &rt->engine;
    e->engine_count = sam->vertex_source ? sam->source_vertex_count : rt->vertex_count;
    e->identity = 1;
    if (sam->vertex_source) {
        e->identity = sam->source_vertex_count == rt->vertex_count;
        for (uint32_t v = 0; v < rt->vertex_count && e->identity; ++v)
            e->identity = sam->vertex_source[v] == v;
    }
    return e->identity ? SAM_OK : upload_maps(rt, sam, err);
}

/* The engine passes' programs, compiled when an engine first asks: a
 * runtime that renders by itself never needs them. */
static sam_status engine_programs(sam_runtime *rt, sam_error *err)
{
    sam_rt_engine *e = &rt->engine;
    sam_status st = SAM_OK;
    if (!e->pose_program)
        st = sam_gl_compute_program("engine_pose.comp", NULL, &e->pose_program, err);
    if (st == SAM_OK && !e->order_program)
        st = sam_gl_compute_program("engine_translucency.comp", NULL, &e->order_program, err);
    return st;
}

void sam_runtime_engine_destroy(sam_runtime *rt)
{
    sam_rt_engine *e = &rt->engine;
    sam_runtime_delete_program(&e->pose_program);
    sam_runtime_delete_program(&e->order_program);
    GLuint buffers[3] = {e->engine_of, e->vertex_of, e->translucency};
    glDeleteBuffers(3, buffers);
    memset(e, 0, sizeof *e);
}

uint32_t sam_runtime_engine_vertex_count(const sam_runtime *rt)
{
    return rt->engine.engine_count;
}

/* Checks one of the engine's buffers: a buffer object that holds `count`
 * vertices of 3 floats at offset + e * stride. */
static sam_status check_source(GLuint buffer, uint32_t offset, uint32_t stride, uint32_t count, const char *what,
                               sam_error *err)
{
    if (!glIsBuffer(buffer))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: engine pose: %s buffer %u is not a GL buffer object",
                        what, buffer);
    if (offset % 4 || stride % 4 || stride < 12)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: engine pose: %s offset %u and stride %u must be multiples of 4 bytes, the stride at "
                        "least 12 (3 floats)",
                        what, offset, stride);
    GLint64 size = 0;
    glBindBuffer(GL_COPY_READ_BUFFER, buffer);
    glGetBufferParameteri64v(GL_COPY_READ_BUFFER, GL_BUFFER_SIZE, &size);
    const uint64_t need = (uint64_t)offset + (uint64_t)(count - 1) * stride + 12u;
    if ((uint64_t)size < need)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: engine pose: the %s buffer holds %lld bytes; %u vertices at offset %u and stride %u "
                        "need %llu",
                        what, (long long)size, count, offset, stride, (unsigned long long)need);
    return SAM_OK;
}

sam_status sam_runtime_set_engine_pose(sam_runtime *rt, const sam_engine_pose *pose, sam_error *err)
{
    sam_rt_engine *e = &rt->engine;
    if (!pose) {
        memset(&e->pose, 0, sizeof e->pose);
        return SAM_OK;
    }
    sam_engine_pose p = *pose;
    if (!p.position_stride)
        p.position_stride = 12;
    if (!p.normal_stride)
        p.normal_stride = 12;
    if (!p.positions)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: engine pose: no positions buffer (0)");
    if (p.vertex_count != e->engine_count)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: engine pose: %u vertices, but the .sam %s %u: build the .sam from the asset the "
                        "engine draws, in its vertex order",
                        p.vertex_count, e->identity && e->engine_count == rt->vertex_count ? "has" : "was built from",
                        e->engine_count);
    sam_status st = check_source(p.positions, p.position_offset, p.position_stride, p.vertex_count, "positions", err);
    if (st == SAM_OK && p.normals)
        st = check_source(p.normals, p.normal_offset, p.normal_stride, p.vertex_count, "normals", err);
    if (st == SAM_OK)
        st = engine_programs(rt, err);
    if (st == SAM_OK)
        st = sam_runtime_deform_keep_rest(rt, err);
    if (st != SAM_OK)
        return st;
    rt->deform.deformer_count = 0;
    st = sam_runtime_set_keyframes(rt, NULL, NULL, 0, err);
    e->pose = p;
    return st;
}

/* One gather of the engine's positions (normals = 0) or normals into the
 * buffer of `binding`. */
static void gather(sam_runtime *rt, GLuint source, uint32_t offset, uint32_t stride, int normals, int binding)
{
    const sam_rt_engine *e = &rt->engine;
    GLuint p = e->pose_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_offset"), offset / 4);
    glUniform1ui(glGetUniformLocation(p, "u_stride"), stride / 4);
    glUniform1i(glGetUniformLocation(p, "u_identity"), e->identity);
    glUniform1i(glGetUniformLocation(p, "u_normals"), normals);
    glUniform3fv(glGetUniformLocation(p, "u_frame"), 1, rt->frame);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_ENGINE_TARGET, rt->buffer[binding]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_ENGINE_SOURCE, source);
    /* Without a map the shader never reads it; any buffer keeps the block bound. */
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_ENGINE_MAP, e->identity ? source : e->engine_of);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
}

sam_status sam_runtime_pose_from_engine(sam_runtime *rt, sam_error *err)
{
    const sam_engine_pose *p = &rt->engine.pose;
    if (!p->positions)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: no engine pose to read: call sam_runtime_set_engine_pose first");
    /* The engine wrote its buffers with its own draws or passes. */
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    sam_runtime_begin_timer(rt, SAM_PASS_DEFORM);
    gather(rt, p->positions, p->position_offset, p->position_stride, 0, SAM_B_POSITIONS);
    sam_runtime_deform_finish(rt);
    if (p->normals) {
        /* After the normals pass, which computes them from the positions. */
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gather(rt, p->normals, p->normal_offset, p->normal_stride, 1, SAM_B_NORMALS);
    }
    sam_runtime_end_timer(rt, SAM_PASS_DEFORM);
    rt->deform.posed = 1;
    sam_runtime_bind_buffers(rt);
    sam_runtime_deform_read_box(rt);
    return SAM_OK;
}

sam_status sam_runtime_engine_translucency(sam_runtime *rt, GLuint *buffer, sam_error *err)
{
    const sam_rt_engine *e = &rt->engine;
    sam_status st;
    if (!e->identity && (st = engine_programs(rt, err)) != SAM_OK)
        return st;
    if (e->identity) {
        *buffer = rt->buffer[SAM_B_TRANSLUCENCY];
    } else {
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        GLuint p = e->order_program;
        glUseProgram(p);
        glUniform1ui(glGetUniformLocation(p, "u_engine_count"), e->engine_count);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_TRANSLUCENCY, rt->buffer[SAM_B_TRANSLUCENCY]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_ENGINE_TARGET, e->translucency);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_ENGINE_MAP, e->vertex_of);
        glDispatchCompute((e->engine_count + 63) / 64, 1, 1);
        sam_runtime_bind_buffers(rt);
        *buffer = e->translucency;
    }
    /* The engine reads it as a vertex attribute or a storage buffer. */
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    return SAM_OK;
}
