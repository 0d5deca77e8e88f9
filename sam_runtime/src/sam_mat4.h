/* Internal: 4x4 column-major matrices for light and camera transforms. */
#ifndef SAM_MAT4_H
#define SAM_MAT4_H

typedef struct sam_mat4 {
    float m[16]; /* column-major, as glUniformMatrix4fv expects with transpose = GL_FALSE */
} sam_mat4;

sam_mat4 sam_mat4_identity(void);
sam_mat4 sam_mat4_mul(sam_mat4 a, sam_mat4 b);
/* The translation by `t`. */
sam_mat4 sam_mat4_translate(const float t[3]);
/* Right-handed view matrix looking from `eye` at `target`. */
sam_mat4 sam_mat4_look_at(const float eye[3], const float target[3], const float up[3]);
/* OpenGL perspective (depth -1..1), vertical field of view in radians. */
sam_mat4 sam_mat4_perspective(float fov_y, float aspect, float near_plane, float far_plane);
sam_mat4 sam_mat4_ortho(float left, float right, float bottom, float top, float near_plane, float far_plane);

#endif
