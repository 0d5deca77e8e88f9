/* The node pass (sam_runtime_nodes.h). */
#include <stdlib.h>
#include <string.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_nodes.h"

sam_status sam_runtime_nodes_create(sam_runtime *rt, const samfile_data *sam, sam_error *err)
{
    sam_rt_nodes *t = &rt->nodes;
    const size_t nc = sam->node_count, total = (size_t)sam->vertex_count + nc;
    t->node_count = sam->node_count;
    const size_t nv = sam->vertex_count, stride = sam->samples_per_vertex, samples = nv * stride;
    /* A flat map binds one zeroed node so every buffer exists. */
    float *zero = calloc((nc ? nc : 1) * 16, sizeof *zero);
    float *tau = malloc((nc ? samples : 1) * sizeof *tau);
    uint32_t *parent = malloc(total * sizeof *parent);
    if (!zero || !tau || !parent) {
        free(zero);
        free(tau);
        free(parent);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for the tree of %zu nodes", nc);
    }
    /* Slot-major on the GPU (translucency.comp): a warp's invocations read
     * one slot of neighbouring vertices as one contiguous run. */
    tau[0] = 0.0f;
    if (nc)
        for (size_t v = 0; v < nv; ++v)
            for (size_t k = 0; k < stride; ++k)
                tau[k * nv + v] = sam->sample_tau[v * stride + k];
    for (size_t i = 0; i < total; ++i)
        parent[i] = SAMFILE_NO_SAMPLE;
    for (size_t j = 0; j < 2 * nc; ++j)
        parent[sam->node_children[j]] = (uint32_t)(j / 2);
    const uint32_t none[2] = {SAMFILE_NO_SAMPLE, SAMFILE_NO_SAMPLE};
    sam_status st;
    if ((st = sam_runtime_upload(rt, SAM_B_NODES, zero, (nc ? nc : 1) * 16 * sizeof(float), err)) == SAM_OK &&
        (st = sam_runtime_upload(rt, SAM_B_SAMPLE_TAU, tau, (nc ? samples : 1) * sizeof(float), err)) == SAM_OK &&
        (st = sam_runtime_upload(rt, SAM_B_NODE_CHILDREN, nc ? (const void *)sam->node_children : none,
                                 (nc ? nc : 1) * 2 * sizeof(uint32_t), err)) == SAM_OK &&
        (st = sam_runtime_upload(rt, SAM_B_NODE_PARENTS, parent, total * sizeof(uint32_t), err)) == SAM_OK &&
        (st = sam_gl_compute_program("nodes.comp", NULL, &t->program, err)) == SAM_OK &&
        (st = sam_gl_compute_program("nodes.comp", "#define SAM_NODES_LIGHT 1\n", &t->light_program, err)) ==
            SAM_OK) {
        /* Zeros: no child has arrived anywhere (nodes.comp). */
        while (glGetError() != GL_NO_ERROR)
            ;
        glGenBuffers(1, &t->arrivals);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, t->arrivals);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)((nc ? nc : 1) * sizeof(uint32_t)), zero, GL_DYNAMIC_DRAW);
        if (glGetError() != GL_NO_ERROR)
            st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not allocate the counters of %zu nodes",
                          nc);
    }
    free(zero);
    free(tau);
    free(parent);
    return st;
}

void sam_runtime_nodes_destroy(sam_runtime *rt)
{
    sam_runtime_delete_program(&rt->nodes.program);
    sam_runtime_delete_program(&rt->nodes.light_program);
    if (rt->nodes.rest_nodes)
        glDeleteBuffers(1, &rt->nodes.rest_nodes);
    rt->nodes.rest_nodes = 0;
    if (rt->nodes.arrivals)
        glDeleteBuffers(1, &rt->nodes.arrivals);
    rt->nodes.arrivals = 0;
}

uint32_t sam_runtime_node_count(const sam_runtime *rt)
{
    return rt->nodes.node_count;
}

void sam_runtime_nodes_update(sam_runtime *rt)
{
    sam_rt_nodes *t = &rt->nodes;
    if (!t->node_count)
        return;
    /* At rest only L_d changes, once a full pass has summed the rest pose. */
    const int light = !rt->deform.posed && t->rest_geometry;
    GLuint p = light ? t->light_program : t->program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    sam_runtime_bind_buffers(rt);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_NODE_ARRIVALS, t->arrivals);
    sam_runtime_begin_timer(rt, SAM_PASS_NODES);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    sam_runtime_end_timer(rt, SAM_PASS_NODES);
    if (!light)
        t->rest_geometry = !rt->deform.posed;
}

sam_status sam_runtime_nodes_keep_rest(sam_runtime *rt, sam_error *err)
{
    sam_rt_nodes *t = &rt->nodes;
    if (!t->node_count || t->rest_nodes)
        return SAM_OK;
    sam_runtime_nodes_update(rt);
    const GLsizeiptr bytes = (GLsizeiptr)t->node_count * 16 * sizeof(float);
    glGenBuffers(1, &t->rest_nodes);
    glBindBuffer(GL_COPY_WRITE_BUFFER, t->rest_nodes);
    glBufferData(GL_COPY_WRITE_BUFFER, bytes, NULL, GL_STATIC_DRAW);
    glBindBuffer(GL_COPY_READ_BUFFER, rt->buffer[SAM_B_NODES]);
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, bytes);
    if (glGetError() != GL_NO_ERROR) {
        glDeleteBuffers(1, &t->rest_nodes);
        t->rest_nodes = 0;
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not keep the rest pose of %u tree nodes",
                        t->node_count);
    }
    return SAM_OK;
}
