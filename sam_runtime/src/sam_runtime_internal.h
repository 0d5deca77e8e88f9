/*
 * The runtime's state: one sub-struct per pass, each owned by the file that
 * names it below, plus the mesh's shared buffers. Not installed.
 *
 * Files and who calls whom (each file calls only files below it, never one
 * that called it; sam_runtime.c creates and destroys them all):
 *   sam_runtime.c              create, destroy, the frame's shared accessors
 *   sam_runtime_view.c         render, G-buffer: calls tsd, technique, diffusion,
 *                              shadows, surface
 *   sam_runtime_tsd.c          texture-space diffusion: calls technique, shadows, surface
 *   sam_runtime_technique.c    transmittance, overrides, translucent shadow maps: calls shadows, thickness
 *   sam_runtime_thickness.c    the local-thickness technique's T: calls surface
 *   sam_runtime_diffusion.c    screen-space kernel and blur, pre-integrated tables
 *   sam_runtime_irradiance.c   L_d: calls shadows, surface
 *   sam_runtime_translucency.c eq. 12 and the smoothing: calls rest_k, nodes
 *   sam_runtime_rest_k.c       each sample's K at rest, once: calls nodes
 *   sam_runtime_deform.c       deformers, keyframes, the pose, the walk: calls nodes
 *   sam_runtime_nodes.c        a cut map's tree nodes
 *   sam_runtime_shadows.c      shadow maps of the shadowed lights
 *   sam_runtime_lights.c       lights and environment
 *   sam_runtime_surface.c      rho_dt, the specular lobe, the albedo map
 *   sam_runtime_readback.c     per-vertex and texture read-backs
 *   sam_runtime_gpu.c          buffer upload, textures, timed dispatch (called by all)
 * Adding a pass: a file with its sub-struct here, its create/destroy in
 * sam_runtime.c, and its call in the frame sequence (sam_runtime.h).
 */
#ifndef SAM_RUNTIME_INTERNAL_H
#define SAM_RUNTIME_INTERNAL_H

#include "sam/sam_brdf.h"
#include "sam/sam_deform.h"
#include "sam/sam_runtime.h"
#include "sam_bindings.h"
#include "sam_mat4.h"

/* Pre-integrated skin tables: 64 x 64, curvature up to 2 / mm (a 0.5 mm
 * radius), penumbra width up to 20 mm. */
#define PRE_SIZE 64
#define PRE_MAX_CURVATURE 2.0f
#define PRE_MAX_PENUMBRA_MM 20.0f

#define MAX_CUBE_SHADOWS 4
#define MAX_FLAT_SHADOWS 4
#define CUBE_SHADOW_SIZE 512
#define FLAT_SHADOW_SIZE 1024
/* Texture units: the shadow maps take 0..7, then these (25 in all: GL 4.3
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
#define UNIT_ALBEDO_ARRAY (UNIT_STRETCH + 1)  /* the albedo maps of a file with several */
#define UNIT_TRIANGLE_MAP (UNIT_STRETCH + 2)  /* which of them each triangle reads */

/* Where a pass's translucency comes from (technique.glsl's TECHNIQUE_*).
 * TSM passes NONE here: its light is added after the texture-space blur.
 * THICKNESS reads the per-vertex T like VERTEX, from the thickness pass's
 * buffer. */
enum {
    TECHNIQUE_VERTEX = 0,
    TECHNIQUE_NONE = 1,
    TECHNIQUE_TRANSMITTANCE = 2,
    TECHNIQUE_OVERRIDE = 3,
    TECHNIQUE_THICKNESS = 4
};

#define RHO_SIZE SAM_BRDF_RHO_DT_TABLE_SIZE
#define SKIN_F0 0.028f

/* The rest pose the deform pass starts from (copies of the first
 * positions, normals, fan areas and samples, made by the first
 * sam_runtime_set_deformers; the samples come back with the rest pose
 * because the walk moves them). */
enum { REST_POSITIONS, REST_NORMALS, REST_FAN_AREAS, REST_SAMPLES, REST_CURVATURE, REST_COUNT };

/* Texture-space maps, kept between renders (all atlas_size^2 RGBA32F). */
enum { ATLAS_IRRADIANCE, ATLAS_STRETCH, ATLAS_TEMP, ATLAS_LEVEL_A, ATLAS_LEVEL_B, ATLAS_SUM, ATLAS_COUNT };

/* sam_runtime_lights.c */
typedef struct sam_rt_lights {
    sam_light *lights;
    unsigned char *cube; /* per light: 1 when its shadow map is a cube (sam_runtime_set_lights says which) */
    uint32_t count;
    uint32_t cube_count, flat_count; /* shadowed lights with a cube map, with a 2D map */
    int has_environment;
    float sh[9][3];
} sam_rt_lights;

/* sam_runtime_surface.c */
typedef struct sam_rt_surface {
    float roughness, rho_s, environment_rho_dt;
    float rho_table[RHO_SIZE * RHO_SIZE];
    GLuint albedo_tex;
    /* Several maps (sam_runtime_set_albedo_maps): a 2D array texture, and
     * per triangle its layer (a buffer texture of uints); 0 without. */
    GLuint albedo_array, triangle_map_buffer, triangle_map_tex;
    GLuint color_buffer; /* vec4 per vertex, the vertex array's attribute 3; 0 without vertex colours */
    /* The .sam's vertex_source (SRCV), the order vertex colours come in;
     * NULL when the map has none (then they come in the map's order). */
    uint32_t *vertex_source;
    uint32_t source_count;
} sam_rt_surface;

/* sam_runtime_shadows.c */
typedef struct sam_rt_shadows {
    GLuint program, fbo;
    GLuint cube_tex[MAX_CUBE_SHADOWS], flat_tex[MAX_FLAT_SHADOWS];
    float cube_origin[MAX_CUBE_SHADOWS][3], cube_far[MAX_CUBE_SHADOWS];
    sam_mat4 flat_matrix[MAX_FLAT_SHADOWS];
    float flat_origin[MAX_FLAT_SHADOWS][3], flat_far[MAX_FLAT_SHADOWS]; /* far = 0: projected depth */
    float flat_range[MAX_FLAT_SHADOWS]; /* directional: model units from window depth 0 to 1 */
    float flat_texel[MAX_FLAT_SHADOWS]; /* a texel's width per unit of distance (perspective) or in model units */
} sam_rt_shadows;

/* sam_runtime_deform.c */
typedef struct sam_rt_deform {
    GLuint program, normals_program, walk_program;
    GLuint rest_buffer[REST_COUNT]; /* 0 until the first sam_runtime_set_deformers or _set_keyframes */
    int posed;                      /* 1 while the buffers hold a deformed pose, not the rest pose */
    sam_deformer deformers[SAM_DEFORM_MAX];
    size_t deformer_count;
    GLuint keyframe_buffer; /* keyframe_count poses of vertex_count vec4 positions, or 0 */
    float *keyframe_times;  /* keyframe_count seconds, > 0, strictly increasing */
    size_t keyframe_count;
    GLuint bounds_buffer;   /* 6 order-preserving uint keys: min xyz, max xyz */
} sam_rt_deform;

/* sam_runtime_engine.c: an engine's own vertex buffers in, T in its order out. */
typedef struct sam_rt_engine {
    GLuint pose_program, order_program;
    uint32_t engine_count;    /* vertices in the engine's order: the .sam's SRCV count, else vertex_count */
    int identity;             /* 1: engine vertex e is SAM vertex e */
    GLuint engine_of;         /* uint per SAM vertex: the engine vertex it reads (0 when identity) */
    GLuint vertex_of;         /* uint per engine vertex: its SAM vertex or 0xFFFFFFFF (0 when identity) */
    GLuint translucency;      /* vec4 per engine vertex (0 when identity) */
    sam_engine_pose pose;     /* pose.positions 0 until sam_runtime_set_engine_pose */
} sam_rt_engine;

/* sam_runtime_irradiance.c */
typedef struct sam_rt_irradiance {
    GLuint program;
} sam_rt_irradiance;

/* sam_runtime_translucency.c: its programs by rest-K mode and pose (rest,
 * posed with the carried K, posed by eq. 15), each 0 until first needed. */
enum { TRANSLUCENCY_REST, TRANSLUCENCY_CARRIED, TRANSLUCENCY_EQ15, TRANSLUCENCY_PROGRAMS };
typedef struct sam_rt_translucency {
    GLuint program[2][TRANSLUCENCY_PROGRAMS]; /* [sam_rest_k][TRANSLUCENCY_*] */
    sam_posed_k posed_k;
} sam_rt_translucency;

/* sam_runtime_rest_k.c */
typedef struct sam_rt_rest_k {
    GLuint program;
    GLuint buffer; /* {uint index; float K rgb} per stored sample; 0 is the mode SAM_REST_K_EVALUATED */
} sam_rt_rest_k;

/* sam_runtime_nodes.c */
typedef struct sam_rt_nodes {
    GLuint program, light_program; /* all of a node, or its L_d alone (SAM_NODES_LIGHT) */
    int rest_geometry;       /* 1 while the node buffer holds the rest pose's centroids, areas and normals */
    GLuint rest_nodes;       /* the node buffer of the rest pose, once a pose was set; else 0 */
    GLuint arrivals;         /* uint per node, 0 between passes (nodes.comp) */
    uint32_t node_count;
} sam_rt_nodes;

/* sam_runtime_technique.c: transmittance's distance reads and the
 * translucent shadow maps (allocated on first use: layers 2k and 2k + 1 of
 * shadow map k hold (u, v, distance, 1) and (normal, 1)). */
typedef struct sam_rt_technique {
    GLuint distance_sampler; /* nearest, no comparison: shadow maps read as distances */
    GLuint tsm_program, tsm_fbo, tsm_depth, tsm_flat_tex, tsm_cube_tex;
    uint32_t tsm_flat_count, tsm_cube_count; /* maps the textures have room for */
} sam_rt_technique;

/* sam_runtime_thickness.c: the local-thickness technique (its buffers are
 * filled by sam_runtime_set_thickness). */
typedef struct sam_rt_thickness {
    GLuint program;
    GLuint transmission; /* vec4 per vertex: G(t) RGB, the thickness t in mm in w */
    GLuint result;       /* vec4 per vertex: the technique's T */
    int ready;           /* 1 once a thickness was given */
    float distortion;    /* the talk's L + N distortion, [0, 1] */
} sam_rt_thickness;

/* sam_runtime_diffusion.c */
typedef struct sam_rt_diffusion {
    GLuint prefilter_program, mips_program, blur_program, compose_program;
    sam_separable_kernel kernel; /* of the last screen-space render's kind and taps */
    sam_sss_kernel kernel_kind;
    int preint_ready;
    float min_penumbra_mm; /* the penumbra table's floor: the profile's 99% radius */
} sam_rt_diffusion;

/* sam_runtime_tsd.c */
typedef struct sam_rt_tsd {
    int has_uvs, uv_usable;
    char uv_reason[160];
    float uv_coverage; /* fraction of the atlas the charts cover */
    sam_uv_atlas uv_atlas; /* where the UVs lie in the atlas (the GL buffers keep the mesh's own) */
    GLuint program, blur_program, blur_listed_program, accumulate_program, fbo;
    /* Per triangle, what lies across its edges and its chart (a uvec4:
     * sam_uv_crossings), for the blur's walks across UV seams; `cross` is 0
     * where there are none (no usable UVs, 2^24 triangles or more). */
    GLuint crossings;
    int cross;
    /* The texels a blur pass leaves to its second dispatch (tsd_blur.comp):
     * 16 bytes of indirect dispatch arguments and count, then a uint per
     * texel of the allocated atlas. */
    GLuint deferred;
    GLuint atlas_tex[ATLAS_COUNT];
    uint32_t atlas_allocated, atlas_used; /* texture side, and the side of the last render */
    /* Every convolved level, kept for translucent shadow maps (allocated on
     * their first use): a 2D array, and a 2D view of each layer for the blur. */
    GLuint level_array, level_view[SAM_PROFILE_FIT_GAUSSIANS];
    uint32_t level_count;
} sam_rt_tsd;

/* sam_runtime_view.c: the view-sized targets of sam_runtime_render,
 * re-created on resize. */
typedef struct sam_rt_view {
    GLuint shade_program;
    GLuint fbo, tex[5], depth;
    GLuint sss_mips[2]; /* the screen-space blur's mipmapped light (RGBA) and depth (R), times coverage */
    uint32_t width, height;
} sam_rt_view;

struct sam_runtime {
    /* The mesh and its material (sam_runtime.c). */
    uint32_t vertex_count, stride, triangle_count;
    uint32_t file_samples; /* the .sam's samples per vertex; stride may be fewer (sam_runtime_create) */
    float mm_per_unit;
    sam_profile profile;
    sam_gaussian_fit fit;         /* the profile's 8-Gaussian fit */
    float total_reflectance[3];
    GLuint buffer[SAM_B_COUNT];
    GLuint vao;
    /* The GPU's origin, in model units: every position the GPU holds or is
     * given (vertex buffers, lights, cameras, shadow maps, the bounds
     * below) is the model position minus `frame`, so that a mesh far from
     * its own origin keeps the float precision of its own size through the
     * rasteriser's interpolation and the matrix products (far from the
     * origin a shadow lookup erred by several texels). A multiple of a
     * power of two at least the rest pose's radius, nearest its centre:
     * 0 for a mesh about the origin (nothing changes), and for one far
     * from it a vertex moves into the frame and back exactly
     * (sam_runtime_choose_frame). The public API speaks
     * model units; the conversions happen where it meets the GPU. */
    float frame[3];
    /* The pose's bounds (sam_runtime_set_box), in the frame: every range is
     * taken from them. */
    float centre[3], radius; /* bounding sphere */
    float box_lo[3], box_hi[3];
    float rest_box_lo[3], rest_box_hi[3]; /* the rest pose's, restored bit for bit with it */
    float surface_area;                   /* model units^2, of the rest pose */
    /* Each pass's GPU time (sam_runtime_gpu.c). */
    GLuint query[SAM_PASS_COUNT];
    int query_used[SAM_PASS_COUNT];
    double query_begun[SAM_PASS_COUNT]; /* sam_seconds() when each pass's query last began */

    sam_rt_lights lights;
    sam_rt_surface surface;
    sam_rt_shadows shadows;
    sam_rt_deform deform;
    sam_rt_engine engine;
    sam_rt_irradiance irradiance;
    sam_rt_nodes nodes;
    sam_rt_translucency translucency;
    sam_rt_rest_k rest_k;
    sam_rt_technique technique;
    sam_rt_thickness thickness;
    sam_rt_diffusion diffusion;
    sam_rt_tsd tsd;
    sam_rt_view view;
};

#endif
