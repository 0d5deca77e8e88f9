/* GL helpers every pass of the runtime uses: buffers, textures, timed
 * dispatches, the profile's uniforms and the bounds. Calls no other file of
 * the runtime. Not installed. */
#ifndef SAM_RUNTIME_GPU_H
#define SAM_RUNTIME_GPU_H

#include "sam_runtime_internal.h"

/* The most bytes one storage block of the current GL may hold. */
size_t sam_runtime_block_limit(void);

/* SAM_OK when `bytes` fit one storage block of the GL; else
 * SAM_ERR_UNSUPPORTED naming `what`, its size and the limit. */
sam_status sam_runtime_check_block_size(const char *what, size_t bytes, sam_error *err);

/* (Re)allocates rt->buffer[binding] with `bytes` of `data` (NULL: undefined
 * contents; 0 bytes get 16) and binds it there. Errors: SAM_ERR_UNSUPPORTED
 * (more than the context's storage block limit), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_upload(sam_runtime *rt, int binding, const void *data, size_t bytes, sam_error *err);

/* A new array of `count` vec4 from 3 floats each, w = `w`; NULL when out of
 * memory. The caller frees it. */
float *sam_runtime_widen(const float *xyz, uint32_t count, float w);

/* K (3 floats) packed into `packed` (2 words) as shaders/sample.glsl's
 * make_sample packs it: each channel float's exponent and the top 13 bits
 * of its mantissa, rounded, so each comes back within 2^-14 of itself;
 * negative and NaN channels as 0, above 1e38 as 1e38. */
void sam_runtime_pack_k(const float k[3], uint32_t packed[2]);

/* The 3 channels of a packed K (sample_k in shaders/sample.glsl). */
void sam_runtime_unpack_k(const uint32_t packed[2], float k[3]);

/* Binds every shared storage buffer (SAM_B_0 .. SAM_B_COUNT - 1). */
void sam_runtime_bind_buffers(const sam_runtime *rt);

/* GL timer query of `pass` around what follows, until sam_runtime_end_timer. */
void sam_runtime_begin_timer(sam_runtime *rt, sam_pass pass);
void sam_runtime_end_timer(sam_runtime *rt, sam_pass pass);

/* The bound compute program once per vertex (groups of 64), timed as
 * `pass`, its storage writes made visible to later passes and read-backs. */
void sam_runtime_dispatch_per_vertex(sam_runtime *rt, sam_pass pass);

/* Deletes `*program` when it is not 0, and zeroes it. */
void sam_runtime_delete_program(GLuint *program);

/* Sets profile.glsl's uniforms of `program` (made current) to `p`. */
void sam_runtime_set_profile_uniforms(GLuint program, const sam_profile *p);

/* Chooses rt->frame for a rest pose within `lo`..`hi` (model units; see
 * sam_runtime_internal.h). Call once, before anything reaches the GPU. */
void sam_runtime_choose_frame(sam_runtime *rt, const float lo[3], const float hi[3]);

/* Model position `p` into the frame (`out`), and back; `p` and `out` may be
 * the same array. */
void sam_runtime_to_frame(const sam_runtime *rt, const float p[3], float out[3]);
void sam_runtime_from_frame(const sam_runtime *rt, const float p[3], float out[3]);

/* Sets the bounds every range is taken from (shadow maps, automatic near and
 * far planes, depth-sized atlases): the box, in the frame, and the sphere
 * around it. */
void sam_runtime_set_box(sam_runtime *rt, const float lo[3], const float hi[3]);

/* Sets the bound `target` texture's filters (min and mag) to `filter` and
 * its S and T wrap modes to clamp-to-edge: every map the runtime samples. */
void sam_runtime_texture_sampling(GLenum target, GLint filter);

/* A new RGBA32F texture of `image` (3 or 4 channels; rows bottom-up when
 * `flip`: image rows run top-down, GL's and UV's v up), with `levels` mip
 * levels (the caller generates them); 0 when the GL could not store it. */
GLuint sam_runtime_image_texture(const sam_image *image, GLsizei levels, int flip);

/* Reads the w x h corner of texture `tex` (RGBA32F, `full` texels wide)
 * into a new RGBA image, rows flipped to run top-down when `flip`.
 * Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_read_texture(GLuint tex, uint32_t full_width, uint32_t full_height, uint32_t w, uint32_t h,
                                    int flip, sam_image *out, sam_error *err);

#endif
