/* The runtime's state, shared by its source files (sam_runtime.c: buffers,
 * lights, shadows, the SAM passes and shading; sam_runtime_tsd.c:
 * texture-space diffusion). Not installed. */
#ifndef SAM_RUNTIME_INTERNAL_H
#define SAM_RUNTIME_INTERNAL_H

#include "sam/sam_brdf.h"
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
/* Texture units: the shadow maps take 0..7, then these. */
#define UNIT_ATLAS (MAX_CUBE_SHADOWS + MAX_FLAT_SHADOWS)
#define UNIT_ALBEDO (UNIT_ATLAS + 1)

#define RHO_SIZE SAM_BRDF_RHO_DT_TABLE_SIZE
#define SKIN_F0 0.028f

/* Texture-space maps, kept between renders (all atlas_size^2 RGBA32F). */
enum { ATLAS_IRRADIANCE, ATLAS_STRETCH, ATLAS_TEMP, ATLAS_LEVEL_A, ATLAS_LEVEL_B, ATLAS_SUM, ATLAS_COUNT };

struct sam_runtime {
    uint32_t vertex_count, stride;
    float mm_per_unit;
    sam_profile profile;
    GLuint buffer[B_COUNT];
    GLuint translucency_program, irradiance_program;
    GLuint query[SAM_PASS_COUNT];
    int query_used[SAM_PASS_COUNT];
    uint32_t light_count;
    int has_environment;
    float sh[9][3];
    float roughness, rho_s, environment_rho_dt;
    float rho_table[RHO_SIZE * RHO_SIZE];

    uint32_t triangle_count;
    float centre[3], radius;  /* bounding sphere of the positions, model units */
    float box_lo[3], box_hi[3];
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
    sam_light *lights;
};

/* sam_runtime_tsd.c. Runs texture-space diffusion of the entering light
 * for `view` (view_proj its camera matrix, proj its projection) into
 * rt->atlas_tex[ATLAS_SUM]; sets rt->atlas_used. */
sam_status sam_runtime_texture_space(sam_runtime *rt, const sam_render_view *view, const sam_mat4 *view_proj,
                                     const sam_mat4 *proj, sam_error *err);
void sam_runtime_texture_space_destroy(sam_runtime *rt);

/* Binds the albedo map (or a white texel's absence: u_has_albedo_map = 0)
 * for program p. */
void sam_runtime_bind_albedo(const sam_runtime *rt, GLuint p);

#endif
