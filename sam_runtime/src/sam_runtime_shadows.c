/* Shadow maps (sam_runtime_shadows.h): a 512^2 cube of distances for area
 * lights and for point lights close to the object, a 1024^2 map for spot
 * and directional lights and for the other point lights (fitted to the
 * object); shaders/shadows.glsl filters both. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sam/sam_vec3.h"
#include "sam_runtime_gpu.h"
#include "sam_runtime_lights.h"
#include "sam_runtime_shadows.h"

sam_status sam_runtime_shadows_create(sam_runtime *rt, sam_error *err)
{
    glGenFramebuffers(1, &rt->shadows.fbo);
    return sam_gl_render_program("shadow.vert", "shadow.frag", NULL, &rt->shadows.program, err);
}

void sam_runtime_shadows_destroy(sam_runtime *rt)
{
    sam_runtime_delete_program(&rt->shadows.program);
    glDeleteFramebuffers(1, &rt->shadows.fbo);
    glDeleteTextures(MAX_CUBE_SHADOWS, rt->shadows.cube_tex);
    glDeleteTextures(MAX_FLAT_SHADOWS, rt->shadows.flat_tex);
}

static GLuint shadow_texture(GLenum target, GLsizei size)
{
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(target, tex);
    if (target == GL_TEXTURE_CUBE_MAP)
        for (int f = 0; f < 6; ++f)
            glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_DEPTH_COMPONENT32F, size, size, 0,
                         GL_DEPTH_COMPONENT, GL_FLOAT, NULL);
    else
        glTexImage2D(target, 0, GL_DEPTH_COMPONENT32F, size, size, 0, GL_DEPTH_COMPONENT, GL_FLOAT, NULL);
    sam_runtime_texture_sampling(target, GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return tex;
}

static void draw_depth(sam_runtime *rt, GLenum attach_target, GLuint tex, GLsizei size, sam_mat4 view_proj,
                       int distance, const float light[3], float far_plane)
{
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, attach_target, tex, 0);
    glViewport(0, 0, size, size);
    glClear(GL_DEPTH_BUFFER_BIT);
    GLuint p = rt->shadows.program;
    sam_mat4 identity = sam_mat4_identity();
    glUniformMatrix4fv(glGetUniformLocation(p, "u_model"), 1, GL_FALSE, identity.m);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_view_proj"), 1, GL_FALSE, view_proj.m);
    glUniform1i(glGetUniformLocation(p, "u_distance"), distance);
    glUniform3fv(glGetUniformLocation(p, "u_light"), 1, light);
    glUniform1f(glGetUniformLocation(p, "u_far"), far_plane);
    glDrawElements(GL_TRIANGLES, (GLsizei)rt->triangle_count * 3, GL_UNSIGNED_INT, NULL);
}

sam_mat4 sam_runtime_cube_face(const float origin[3], float far_plane, int face)
{
    static const float face_dir[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const float face_up[6][3] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    float target[3] = {origin[0] + face_dir[face][0], origin[1] + face_dir[face][1], origin[2] + face_dir[face][2]};
    return sam_mat4_mul(sam_mat4_perspective(3.14159265f / 2, 1.0f, 1e-4f * far_plane, far_plane),
                        sam_mat4_look_at(origin, target, face_up[face]));
}

void sam_runtime_render_shadows(sam_runtime *rt)
{
    if (!rt->lights.cube_count && !rt->lights.flat_count)
        return;
    glBindFramebuffer(GL_FRAMEBUFFER, rt->shadows.fbo);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(rt->vao);
    glUseProgram(rt->shadows.program);
    for (sam_runtime_shadow s = {0}; sam_runtime_next_shadow(rt, &s);) {
        const sam_light *l = &rt->lights.lights[s.light];
        if (s.cube) {
            uint32_t cube = s.map;
            float o[3];
            memcpy(o, l->position, sizeof o);
            if (l->type == SAM_LIGHT_AREA) {
                o[0] = o[1] = o[2] = 0;
                for (uint32_t k = 0; k < l->vertex_count; ++k)
                    for (int c = 0; c < 3; ++c)
                        o[c] += l->vertices[k][c] / (float)l->vertex_count;
            }
            float to[3], far_plane = 1.01f * (sam_runtime_to_centre(rt, o, to) + rt->radius);
            if (!rt->shadows.cube_tex[cube])
                rt->shadows.cube_tex[cube] = shadow_texture(GL_TEXTURE_CUBE_MAP, CUBE_SHADOW_SIZE);
            for (int f = 0; f < 6; ++f)
                draw_depth(rt, GL_TEXTURE_CUBE_MAP_POSITIVE_X + (GLenum)f, rt->shadows.cube_tex[cube], CUBE_SHADOW_SIZE,
                           sam_runtime_cube_face(o, far_plane, f), 1, o, far_plane);
            memcpy(rt->shadows.cube_origin[cube], o, sizeof o);
            rt->shadows.cube_far[cube] = far_plane;
        } else {
            uint32_t flat = s.map;
            float d[3], dc = sam_runtime_to_centre(rt, l->position, d);
            if (l->type == SAM_LIGHT_POINT && dc > 0) /* it looks at the object */
                sam_vec3_normalize(d);
            else
                memcpy(d, l->direction, sizeof d);
            float up[3] = {0, 1, 0};
            if (fabsf(d[1]) > 0.9f)
                up[0] = 1, up[1] = 0;
            sam_mat4 vp;
            float far_plane = 0.0f;
            if (l->type != SAM_LIGHT_DIRECTIONAL) {
                far_plane = 1.01f * (dc + rt->radius);
                /* A point light looks at the object, fitted to the cone it
                 * fills now: a deforming object may have grown since
                 * sam_runtime_set_lights chose the map, up to the same
                 * 170 degrees a spot's map spans at most. */
                float fov = l->type == SAM_LIGHT_POINT
                                ? 2.0f * sam_runtime_object_half_angle(rt, l->position)
                                : l->outer_angle_deg * 3.14159265f / 90.0f;
                fov = fminf(fov, 170.0f * 3.14159265f / 180.0f);
                float target[3] = {l->position[0] + d[0], l->position[1] + d[1], l->position[2] + d[2]};
                vp = sam_mat4_mul(sam_mat4_perspective(fov, 1.0f, 1e-3f * far_plane, far_plane),
                                  sam_mat4_look_at(l->position, target, up));
                rt->shadows.flat_texel[flat] = 2.0f * tanf(0.5f * fov) / FLAT_SHADOW_SIZE;
            } else {
                float r = 1.01f * rt->radius;
                float eye[3] = {rt->centre[0] - d[0] * 2 * r, rt->centre[1] - d[1] * 2 * r,
                                rt->centre[2] - d[2] * 2 * r};
                vp = sam_mat4_mul(sam_mat4_ortho(-r, r, -r, r, 0.0f, 4 * r), sam_mat4_look_at(eye, rt->centre, up));
                rt->shadows.flat_range[flat] = 4 * r;
                rt->shadows.flat_texel[flat] = 2 * r / FLAT_SHADOW_SIZE;
            }
            if (!rt->shadows.flat_tex[flat])
                rt->shadows.flat_tex[flat] = shadow_texture(GL_TEXTURE_2D, FLAT_SHADOW_SIZE);
            /* A spot map stores distance / far like a cube map: projected
             * depth crowds near 1 and leaves no room for a bias. */
            draw_depth(rt, GL_TEXTURE_2D, rt->shadows.flat_tex[flat], FLAT_SHADOW_SIZE, vp, far_plane > 0, l->position,
                       far_plane);
            rt->shadows.flat_matrix[flat] = vp;
            memcpy(rt->shadows.flat_origin[flat], l->position, sizeof rt->shadows.flat_origin[flat]);
            rt->shadows.flat_far[flat] = far_plane;
        }
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

int sam_runtime_next_shadow(const sam_runtime *rt, sam_runtime_shadow *s)
{
    for (; s->next < rt->lights.count; ++s->next) {
        if (!rt->lights.lights[s->next].shadow)
            continue;
        s->cube = rt->lights.cube[s->next];
        s->light = s->next++;
        s->map = s->cube ? s->cubes++ : s->flats++;
        return 1;
    }
    return 0;
}

void sam_runtime_bind_shadows(const sam_runtime *rt, GLuint p)
{
    /* Every sampler gets a unit of its own type, used or not: GL rejects
     * two sampler types on one unit. */
    for (int i = 0; i < MAX_CUBE_SHADOWS; ++i) {
        char name[32];
        glActiveTexture(GL_TEXTURE0 + (GLenum)i);
        glBindTexture(GL_TEXTURE_CUBE_MAP, rt->shadows.cube_tex[i]);
        snprintf(name, sizeof name, "u_cube_shadow[%d]", i);
        glUniform1i(glGetUniformLocation(p, name), i);
    }
    for (int i = 0; i < MAX_FLAT_SHADOWS; ++i) {
        char name[32];
        glActiveTexture(GL_TEXTURE0 + MAX_CUBE_SHADOWS + (GLenum)i);
        glBindTexture(GL_TEXTURE_2D, rt->shadows.flat_tex[i]);
        snprintf(name, sizeof name, "u_flat_shadow[%d]", i);
        glUniform1i(glGetUniformLocation(p, name), MAX_CUBE_SHADOWS + i);
    }
    glActiveTexture(GL_TEXTURE0);
    glUniform1fv(glGetUniformLocation(p, "u_cube_far"), MAX_CUBE_SHADOWS, rt->shadows.cube_far);
    glUniform3fv(glGetUniformLocation(p, "u_cube_origin"), MAX_CUBE_SHADOWS, &rt->shadows.cube_origin[0][0]);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_flat_matrix"), MAX_FLAT_SHADOWS, GL_FALSE, rt->shadows.flat_matrix[0].m);
    glUniform3fv(glGetUniformLocation(p, "u_flat_origin"), MAX_FLAT_SHADOWS, &rt->shadows.flat_origin[0][0]);
    glUniform1fv(glGetUniformLocation(p, "u_flat_far"), MAX_FLAT_SHADOWS, rt->shadows.flat_far);
    glUniform1fv(glGetUniformLocation(p, "u_flat_texel"), MAX_FLAT_SHADOWS, rt->shadows.flat_texel);
    glUniform1fv(glGetUniformLocation(p, "u_flat_range"), MAX_FLAT_SHADOWS, rt->shadows.flat_range);
}
