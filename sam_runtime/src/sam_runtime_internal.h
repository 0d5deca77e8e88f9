/* The runtime's state, shared by its source files (sam_runtime.c: buffers,
 * lights, shadows, the SAM passes and shading; sam_runtime_tsd.c:
 * texture-space diffusion). Not installed. */
#ifndef SAM_RUNTIME_INTERNAL_H
#define SAM_RUNTIME_INTERNAL_H

#include "sam/sam_brdf.h"
#include "sam/sam_deform.h"
#include "sam/sam_runtime.h"
#include "sam_mat4.h"

enum { B_POSITIONS, B_NORMALS, B_SAMPLES, B_FAN_AREAS, B_IRRADIANCE, B_TRANSLUCENCY, B_ADJ_OFFSETS, B_ADJACENCY,
       B_LIGHTS, B_RHO_DT, B_TRIANGLES, B_CURVATURE, B_PRE_DIFFUSE, B_PRE_PENUMBRA, B_UVS, B_COUNT };

/* Pre-integrated skin tables: 64 x 64, curvature up to 2 / mm (a 0.5 mm
 * radius), penumbra width up to 20 mm. */
#define PRE_SIZE 64
#define PRE_MAX_CURVATURE 2.0f
#define PRE_MAX_PENUMBRA_MM 20.0f

#define MAX_CUBE_SHADOWS 4
#define MAX_FLAT_SHADOWS 4
#define CUBE_SHADOW_SIZE 512
#define FLAT_SHADOW_SIZE 1024
/* Texture units: the shadow maps take 0..7, then these (23 in all: GL 4.3
 * promises 16 per stage, llvmpipe and desktop GPUs give 32). Every sampler
 * of a program gets its own unit, used or not: GL rejects a draw with two
 * sampler types on one unit. */
#define UNIT_ATLAS (MAX_CUBE_SHADOWS + MAX_FLAT_SHADOWS)
#define UNIT_ALBEDO (UNIT_ATLAS + 1)
#define UNIT_CUBE_DISTANCE (UNIT_ALBEDO + 1)                    /* the cube maps read as distances */
#define UNIT_FLAT_DISTANCE (UNIT_CUBE_DISTANCE + MAX_CUBE_SHADOWS) /* the 2D maps likewise */
#define UNIT_OVERRIDE (UNIT_FLAT_DISTANCE + MAX_FLAT_SHADOWS)
#define UNIT_TSM_FLAT (UNIT_OVERRIDE + 1)
#define UNIT_TSM_CUBE (UNIT_TSM_FLAT + 1)
#define UNIT_LEVELS (UNIT_TSM_CUBE + 1)
#define UNIT_STRETCH (UNIT_LEVELS + 1)

/* Where a pass's translucency comes from (technique.glsl's TECHNIQUE_*).
 * TSM passes NONE here: its light is added after the texture-space blur. */
enum { TECHNIQUE_VERTEX = 0, TECHNIQUE_NONE = 1, TECHNIQUE_TRANSMITTANCE = 2, TECHNIQUE_OVERRIDE = 3 };

#define RHO_SIZE SAM_BRDF_RHO_DT_TABLE_SIZE
#define SKIN_F0 0.028f

/* The rest pose the deform pass starts from (copies of the first
 * positions, normals, fan areas and samples, made by the first
 * sam_runtime_set_deformers; the samples come back with the rest pose
 * because the walk moves them). */
enum { REST_POSITIONS, REST_NORMALS, REST_FAN_AREAS, REST_SAMPLES, REST_CURVATURE, REST_COUNT };
/* Where the translucency pass finds the rest positions, which it carries a
 * posed K from (fan_form_factor.glsl): the binding after rt->buffer's. */
enum { B_REST_POSITIONS = B_COUNT };
/* The posed bounding box the normals pass reduces into (deform_normals.comp). */
enum { B_BOUNDS = B_COUNT + 1 };

/* Texture-space maps, kept between renders (all atlas_size^2 RGBA32F). */
enum { ATLAS_IRRADIANCE, ATLAS_STRETCH, ATLAS_TEMP, ATLAS_LEVEL_A, ATLAS_LEVEL_B, ATLAS_SUM, ATLAS_COUNT };

struct sam_runtime {
    uint32_t vertex_count, stride;
    float mm_per_unit;
    sam_profile profile;
    GLuint buffer[B_COUNT];
    GLuint translucency_program, translucency_posed_program, translucency_eq15_program, irradiance_program;
    sam_posed_k posed_k;
    GLuint deform_program, deform_normals_program, walk_program;
    GLuint rest_buffer[REST_COUNT]; /* 0 until the first sam_runtime_set_deformers or _set_keyframes */
    int posed;                      /* 1 while the buffers hold a deformed pose, not the rest pose */
    sam_deformer deformers[SAM_DEFORM_MAX];
    size_t deformer_count;
    GLuint keyframe_buffer; /* keyframe_count poses of vertex_count vec4 positions, or 0 */
    float *keyframe_times;  /* keyframe_count seconds, > 0, strictly increasing */
    size_t keyframe_count;
    GLuint query[SAM_PASS_COUNT];
    int query_used[SAM_PASS_COUNT];
    uint32_t light_count;
    int has_environment;
    float sh[9][3];
    float roughness, rho_s, environment_rho_dt;
    float rho_table[RHO_SIZE * RHO_SIZE];

    uint32_t triangle_count;
    float centre[3], radius;  /* bounding sphere of the positions, model units (of the pose) */
    float box_lo[3], box_hi[3];
    float rest_box_lo[3], rest_box_hi[3]; /* the rest pose's, restored bit for bit with it */
    GLuint bounds_buffer;     /* 6 order-preserving uint keys: min xyz, max xyz */
    float surface_area;       /* model units^2 */
    GLuint vao, fbo, shadow_program, shade_program, blur_program, compose_program;
    float total_reflectance[3];

    /* Screen space: the kernel of the last render's kind and taps. */
    sam_separable_kernel kernel;
    sam_sss_kernel kernel_kind;

    /* Pre-integrated skin. */
    int preint_ready;
    float min_penumbra_mm;  /* the penumbra table's floor: the profile's 99% radius */

    /* Texture space. */
    int has_uvs, uv_usable;
    char uv_reason[160];
    float uv_coverage;      /* fraction of the atlas the charts cover */
    sam_gaussian_fit fit;
    GLuint tsd_program, tsd_blur_program, tsd_accumulate_program, tsd_fbo;
    GLuint atlas_tex[ATLAS_COUNT];
    uint32_t atlas_allocated, atlas_used; /* texture side, and the side of the last render */
    /* Every convolved level, kept for translucent shadow maps (allocated on
     * their first use): a 2D array, and a 2D view of each layer for the blur. */
    GLuint level_array, level_view[SAM_PROFILE_FIT_GAUSSIANS];
    uint32_t level_count;
    GLuint albedo_tex;

    /* View-sized targets of sam_runtime_render, re-created on resize. */
    GLuint view_fbo, view_tex[5], view_depth;
    uint32_t view_width, view_height;

    /* Shadow maps. */
    GLuint cube_tex[MAX_CUBE_SHADOWS], flat_tex[MAX_FLAT_SHADOWS];
    uint32_t cube_count, flat_count;
    float cube_origin[MAX_CUBE_SHADOWS][3], cube_far[MAX_CUBE_SHADOWS];
    sam_mat4 flat_matrix[MAX_FLAT_SHADOWS];
    float flat_origin[MAX_FLAT_SHADOWS][3], flat_far[MAX_FLAT_SHADOWS]; /* far = 0: projected depth */
    float flat_range[MAX_FLAT_SHADOWS]; /* directional: model units from window depth 0 to 1 */
    sam_light *lights;
    GLuint distance_sampler; /* nearest, no comparison: shadow maps read as distances */

    /* Translucent shadow maps (allocated on first use): layers 2k and 2k + 1
     * of shadow map k hold (u, v, distance, 1) and (normal, 1). */
    GLuint tsm_program, tsm_fbo, tsm_depth, tsm_flat_tex, tsm_cube_tex;
    uint32_t tsm_flat_count, tsm_cube_count; /* maps the textures have room for */
};

/* sam_runtime.c. The view-projection of face `face` of a cube map at
 * `origin` reaching `far_plane` (the shadow maps' and the TSMs'). */
sam_mat4 sam_runtime_cube_face(const float origin[3], float far_plane, int face);

/* Binds the shadow maps and their uniforms (shadows.glsl) to program p. */
void sam_runtime_bind_shadows(const sam_runtime *rt, GLuint p);

/* One step of a walk over the shadowed lights (sam_runtime_next_shadow). */
typedef struct sam_runtime_shadow {
    uint32_t light; /* index in rt->lights */
    int cube;       /* 1: a cube map (point and area lights); 0: a flat map (spot and directional) */
    uint32_t map;   /* its index among the cube maps, or among the flat ones */
    uint32_t next, cubes, flats; /* the walk's own state */
} sam_runtime_shadow;

/* Steps `s` (zeroed before the first call) to the next shadowed light and
 * returns 1; 0 after the last. The maps are numbered as
 * sam_runtime_set_lights numbers them for the shaders, so every pass that
 * draws them walks this way. */
int sam_runtime_next_shadow(const sam_runtime *rt, sam_runtime_shadow *s);

/* sam_runtime_technique.c. The translucency source of `view`'s passes
 * (TECHNIQUE_*). */
int sam_runtime_technique_mode(const sam_render_view *view);

/* Sets technique.glsl's uniforms for program p: `mode`, the fit, the
 * shadow maps read as distances, and `override_tex` (0: none) on its unit. */
void sam_runtime_bind_technique(const sam_runtime *rt, GLuint p, int mode, GLuint override_tex);

/* Binds tsm_read.glsl's maps for program p (the shading program); the
 * levels and stretch map come from the last texture-space render. */
void sam_runtime_bind_tsm(const sam_runtime *rt, GLuint p);

/* Renders a TSM for every shadowed point, spot and directional light, from
 * the shadow maps' last positions. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_render_tsm(sam_runtime *rt, sam_error *err);
void sam_runtime_tsm_destroy(sam_runtime *rt);

/* A new RGBA32F texture of `image` (3 or 4 channels; rows bottom-up when
 * `flip`: image rows run top-down, GL's and UV's v up), with `levels` mip
 * levels (the caller generates them); 0 when the GL could not store it. */
GLuint sam_runtime_image_texture(const sam_image *image, GLsizei levels, int flip);

/* Reads the w x h corner of texture `tex` (RGBA32F, `full` texels wide)
 * into a new RGBA image, rows flipped to run top-down when `flip`.
 * Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_read_texture(GLuint tex, uint32_t full_width, uint32_t full_height, uint32_t w, uint32_t h,
                                    int flip, sam_image *out, sam_error *err);

/* sam_runtime_tsd.c. Runs texture-space diffusion of the entering light
 * for `view` (view_proj its camera matrix, proj its projection) into
 * rt->atlas_tex[ATLAS_SUM] with translucency `mode` (override_tex: the
 * override's texture or 0); sets rt->atlas_used. `tsm`: front light goes
 * in whatever view->front says, and every level is kept for the TSMs. */
sam_status sam_runtime_texture_space(sam_runtime *rt, const sam_render_view *view, const sam_mat4 *view_proj,
                                     const sam_mat4 *proj, int mode, GLuint override_tex, int tsm, sam_error *err);

/* The atlas side `view` asks for (options.atlas_size or the default). */
uint32_t sam_runtime_atlas_size(const sam_render_view *view);

/* Draws the mesh unwrapped into the bound framebuffer's side x side corner
 * with the texture-space program: the entering light and stretch map, or
 * with `gbuffer` the position and normal (no culling or clipping). */
void sam_runtime_draw_atlas(sam_runtime *rt, const sam_render_view *view, const sam_mat4 *view_proj,
                            const sam_mat4 *proj, uint32_t side, int mode, GLuint override_tex, int front,
                            int gbuffer);
void sam_runtime_texture_space_destroy(sam_runtime *rt);

/* Binds the albedo map (or a white texel's absence: u_has_albedo_map = 0)
 * for program p. */
void sam_runtime_bind_albedo(const sam_runtime *rt, GLuint p);

#endif
