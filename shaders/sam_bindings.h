/*
 * The runtime's binding points, read by both its C code and its shaders
 * (#include "sam_bindings.h" in either; the shader loader expands it from
 * the embedded files), so a buffer's number is written once.
 *
 * Storage buffers (std430), one per per-vertex or shared array; the runtime
 * binds every one of SAM_B_0..SAM_B_COUNT-1 before a pass.
 */
#ifndef SAM_BINDINGS_H
#define SAM_BINDINGS_H

#define SAM_B_POSITIONS 0     /* vec4 per vertex, model units */
#define SAM_B_NORMALS 1       /* vec4 per vertex */
#define SAM_B_SAMPLES 2       /* {uint index; uvec2 packed K'} x N per vertex, slot-major (sample.glsl) */
#define SAM_B_FAN_AREAS 3     /* float per vertex, mm^2 */
#define SAM_B_IRRADIANCE 4    /* vec4 per vertex: L_d */
#define SAM_B_TRANSLUCENCY 5  /* vec4 per vertex: smoothed T */
#define SAM_B_ADJ_OFFSETS 6   /* uint per vertex + 1 */
#define SAM_B_ADJACENCY 7     /* uint per ring entry */
#define SAM_B_LIGHTS 8        /* lights.glsl's Light per light */
#define SAM_B_RHO_DT 9        /* the rho_dt table */
#define SAM_B_TRIANGLES 10    /* 3 uint per triangle (also the index buffer) */
#define SAM_B_CURVATURE 11    /* float per vertex, 1/mm */
#define SAM_B_PRE_DIFFUSE 12  /* pre-integrated diffuse falloff table */
#define SAM_B_PRE_PENUMBRA 13 /* pre-integrated penumbra table */
#define SAM_B_UVS 14          /* vec2 per vertex */
#define SAM_B_NODES 15        /* per tree node {vec4 centroid, area; L_d; mean normal; L_d(child 1) - L_d(child 0)} */
#define SAM_B_NODE_CHILDREN 16 /* uvec2 per tree node: sample indices of its children */
#define SAM_B_NODE_PARENTS 17 /* uint per vertex and node: its parent node, 0xFFFFFFFF for the root */
#define SAM_B_SAMPLE_TAU 18   /* float per sample, slot-major: a node sample's L_d correction along its split */
#define SAM_B_COUNT 19

/* Bound only by the passes that need them, after the shared ones. */
#define SAM_B_REST_POSITIONS 19 /* the rest pose a posed K is carried from */
#define SAM_B_BOUNDS 20         /* the posed box: 6 order-preserving uint keys */
#define SAM_B_TRANSMISSION 21   /* vec4 per vertex: G(t) of the vertex's local thickness */
#define SAM_B_REST_K 22         /* {uint index; uvec2 packed K} per sample, slot-major: its K at rest */
#define SAM_B_LIMIT 23          /* bindings a context must offer */

/* The node pass (nodes.comp) counts each node's arrived children where
 * the posed translucency pass, which runs after it, binds the rest pose. */
#define SAM_B_NODE_ARRIVALS SAM_B_REST_POSITIONS

/* The deform pass reads its inputs where the normals and samples usually
 * are: it writes positions only, and the normals pass runs after it. */
#define SAM_B_KEY_POSITIONS SAM_B_NORMALS
#define SAM_B_DEFORM_REST SAM_B_SAMPLES

/* The engine passes (sam_runtime_set_engine_pose) likewise: they write
 * positions, normals or the engine-order T at the target, and the next
 * pass binds the usual buffers again. */
#define SAM_B_ENGINE_TARGET SAM_B_POSITIONS
#define SAM_B_ENGINE_SOURCE SAM_B_SAMPLES
#define SAM_B_ENGINE_MAP SAM_B_FAN_AREAS

/* The posed translucency pass reads the tree's nodes at rest where the
 * normals pass keeps its bounds. */
#define SAM_B_REST_NODES SAM_B_BOUNDS

/* The texture-space blur reads, per triangle, what lies across its edges
 * and its chart (sam_uv_crossings) where the rest pose would be. */
#define SAM_B_TSD_CROSSINGS SAM_B_REST_POSITIONS
/* ... and lists the texels whose taps leave their chart where the
 * posed box would be, for a second dispatch (tsd_blur.comp). */
#define SAM_B_TSD_DEFERRED SAM_B_BOUNDS

/* Image units of the compute passes over view-sized and atlas images
 * (each program numbers its own). */
#define SAM_IMAGE_SOURCE 0   /* blurs: the input; accumulate: the level */
#define SAM_IMAGE_TARGET 1   /* blurs: the output; accumulate: the running sum */
#define SAM_IMAGE_STRETCH 2  /* texture-space blur: the stretch map */
#define SAM_IMAGE_DEPTH 2    /* screen-space prefilter: depth x coverage */
#define SAM_IMAGE_BLURRED 0  /* compose: the blurred entering light */
#define SAM_IMAGE_FACTOR 1   /* compose: the factor after the blur */
#define SAM_IMAGE_SPECULAR 2 /* compose: the specular */
#define SAM_IMAGE_COMPOSED 3 /* compose: the result */

#endif
