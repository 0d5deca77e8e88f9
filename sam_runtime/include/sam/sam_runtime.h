/*
 * sam_runtime: a .sam on the GPU and the per-frame SAM passes.
 *
 * Step by step:
 *
 *   Once
 *     1. A current GL 4.3 context on this thread: sam_gl_context_create_headless,
 *        or your own checked with sam_gl_check_current (sam_gl.h). It must
 *        outlive the runtime.
 *     2. sam_runtime_create(sam, profile, mm_per_unit): uploads the map and
 *        compiles every pass.
 *     3. The lighting: sam_runtime_set_lights, _set_environment, and if you
 *        like _set_surface and _set_albedo_map. Call them again whenever the
 *        lighting changes.
 *     4. Animated objects only: sam_runtime_set_deformers and/or
 *        _set_keyframes.
 *     5. The local-thickness technique only: sam_runtime_set_thickness.
 *
 *   Every frame, in this order (the frame sequence)
 *     1. sam_runtime_deform(t)      animated only: poses positions, normals,
 *                                   fan areas, curvature and bounds
 *     2. sam_runtime_walk           animated only: samples follow the pose
 *     3. sam_runtime_irradiance     shadow maps, then L_d at every vertex (eq. 4)
 *     4. sam_runtime_translucency   a cut map's node pass, then T at every
 *                                   vertex (eq. 12), smoothed in time
 *                                   (eq. 17-18)
 *     5. sam_runtime_render         shading and the chosen diffusion and
 *        (or _render_texture)       technique into an image
 *
 *   At the end
 *     sam_runtime_destroy, then the context (the other way round, the
 *     runtime's GL calls find no context: libepoxy aborts the process).
 *
 *   Inside an engine (docs/embedding.md): the engine draws with its own
 *   mesh and shaders and poses its vertices itself (skinning, morphs).
 *     Once: the .sam built from the same asset (its SRCV chunk maps the
 *     asset's vertex order to SAM's), steps 1-3 above with the engine's
 *     context current (sam_gl_check_current), then
 *     sam_runtime_set_engine_pose with the engine's posed buffers.
 *     Every frame, after the engine posed its vertices:
 *       sam_runtime_pose_from_engine   ~ the deform pass (+ a gather)
 *       sam_runtime_walk               the samples follow the pose
 *       sam_runtime_irradiance         shadow maps + L_d
 *       sam_runtime_translucency       T at every vertex
 *       sam_runtime_engine_translucency  a vec4 buffer in the engine's
 *                                      vertex order (a copy pass, or none
 *                                      when the orders agree)
 *     then the engine binds that buffer and adds T x albedo in its own
 *     shader. The runtime changes GL state and does not restore it
 *     (program, VAO, buffer/texture/image bindings, active texture unit,
 *     framebuffer and draw buffers, viewport, scissor, depth test, face
 *     culling left off, clear colour; docs/embedding.md): the engine sets
 *     what it relies on again before it draws.
 *
 * Results stay on the GPU between the steps; the read-back functions
 * (sam_runtime_read_*) exist for tests and tools and wait for the GPU.
 * Calls whose contract starts "Testing aid" are for tests, tools and
 * debugging: an engine embedding SAM never needs them.
 *
 * sam_runtime_create uploads a .sam (samfile_data) as shader-storage
 * buffers laid out for the GPU (std430), at the binding points that
 * shaders/sam_bindings.h gives both the C code and the shaders: positions
 * (vec4 per vertex, model units less the runtime's origin: a multiple of a
 * power of two at least the mesh's radius nearest its centre, so 0 for a
 * mesh about the model's origin; a mesh far from it keeps its own size's
 * float precision on the GPU; every function here takes and returns model
 * units), normals (vec4), samples ({uint index; K'
 * packed into 2 words} x N per vertex, each channel of K' within 2^-14 of
 * the .sam's: one 12-byte read; shaders/sample.glsl), fan areas (mm^2),
 * L_d and T (vec4 per vertex), the adjacency, the lights and the rho_dt
 * table. The deform pass rewrites positions, normals and fan areas for an
 * animated pose, and the walk moves each vertex's samples to better
 * back-side vertices of that pose. The
 * irradiance pass computes L_d (eq. 4): each light's irradiance by the
 * formulas of sam_light_irradiance times rho_dt(N.L) = 1 - k (1 -
 * table(N.L, m)) (d'Eon Sec. 6; k = pi rho_s, the specular lobe's scale),
 * plus the environment's SH-9 irradiance times the cosine-weighted mean of
 * rho_dt over the hemisphere. A cut map's samples may name tree nodes
 * (samfile.h): the node pass sums, from the vertices up, each node's area
 * and its area-weighted centroid, normal and L_d from its two children, so
 * a node is to the translucency pass what a vertex is. The
 * translucency pass evaluates eq. 12 with
 * K = K' F'_b R_d(|v_b - v|) (eq. 15) at rest (computed once per map,
 * sam_runtime_set_rest_k) and, on a deformed pose, K carried from rest
 * (sam_runtime_set_posed_k), and smooths it in time
 * (eq. 17-18), T <- (1 - alpha) T_prev + alpha T, alpha = 1 - (1e-10)^dt.
 *
 * The caller owns the runtime and destroys it before the context.
 */
#ifndef SAM_RUNTIME_H
#define SAM_RUNTIME_H

#include "sam/sam_deform.h"
#include "sam/sam_gl.h"
#include "sam/sam_image.h"
#include "sam/sam_light.h"
#include "sam/sam_profile.h"
#include "sam/sam_technique.h"
#include "sam/sam_uv.h"
#include "sam/samfile.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_runtime sam_runtime;

typedef enum sam_pass {
    SAM_PASS_IRRADIANCE = 0, /* shadow maps + L_d at every vertex */
    SAM_PASS_TRANSLUCENCY,   /* eq. 12 + smoothing, or the thickness technique's pass */
    SAM_PASS_SHADE,          /* the forward shading pass */
    SAM_PASS_DIFFUSION,      /* screen or texture-space diffusion (atlas, blurs, sum; compose) */
    SAM_PASS_DEFORM,         /* deformed positions, then normals and fan areas */
    SAM_PASS_WALK,           /* the sample walk (Sec. 3.4) */
    SAM_PASS_NODES,          /* a cut map's tree nodes: area, centroid, normal and L_d of each */
    SAM_PASS_COUNT
} sam_pass;

/* Uploads `sam` (the caller keeps it) and compiles the passes. `profile`
 * and `mm_per_unit` are the material and scale the map was built with:
 * read them from the map's INFO (samfile_info_read: info.profile,
 * info.mm_per_unit). They are not checked against it: another material
 * or scale is applied to K' as eq. 15 applies a pose (a tenth of the
 * scale gives a hundredth of the light, not an error), which sam_render
 * allows on purpose (a scene's material overrides its map's).
 * Errors: those of samfile_validate (`sam` breaks a rule of samfile.h; a
 * map read by samfile_read never does), SAM_ERR_UNSUPPORTED (a buffer
 * larger than the context's storage block limit), SAM_ERR_FORMAT (shader
 * errors, naming file:line), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_create(const samfile_data *sam, const sam_profile *profile, float mm_per_unit,
                              sam_runtime **rt, sam_error *err);
/* sam_runtime_create with the map's per-sample buffers held to at most
 * `max_sample_bytes` each (0: no limit but the GL's). Each sample takes 12
 * bytes of the two largest (its index and K', and its K at rest). Where a
 * map's N samples per vertex do not fit, every row is fitted to the M that
 * do (M = max_sample_bytes / (12 vertex_count), or the same of the GL's
 * storage block limit, whichever is smaller; samfile_fit_samples: sibling
 * samples merged into their parent node, the rest folded into the kept
 * sample nearest them), and carries its whole K at rest: translucency
 * under light that is even across a row's back side is unchanged, and
 * elsewhere the dropped samples' light is read near where it comes from.
 * sam_runtime_create does this with the GL's limit alone, so a map too
 * large for a GL's storage blocks (128 MiB on llvmpipe and the GL minimum:
 * about 350k vertices at N = 32, 700k at 16) still renders; sam_runtime_samples_per_vertex
 * against sam_runtime_file_samples_per_vertex tells. Errors: those of
 * sam_runtime_create, and SAM_ERR_UNSUPPORTED where not one sample per
 * vertex fits. */
sam_status sam_runtime_create_fitted(const samfile_data *sam, const sam_profile *profile, float mm_per_unit,
                                     size_t max_sample_bytes, sam_runtime **rt, sam_error *err);
void sam_runtime_destroy(sam_runtime *rt);

uint32_t sam_runtime_vertex_count(const sam_runtime *rt);
/* Samples per vertex on the GPU: the .sam's n, or fewer where they did not
 * fit (sam_runtime_create_fitted). */
uint32_t sam_runtime_samples_per_vertex(const sam_runtime *rt);
/* The .sam's n samples per vertex, whatever the GPU holds. */
uint32_t sam_runtime_file_samples_per_vertex(const sam_runtime *rt);
/* 1 when the GPU holds fewer samples per vertex than the .sam
 * (sam_runtime_create_fitted), with a sentence for the user saying so and
 * what to do in `note` (`size` bytes, NUL-terminated, truncated to fit;
 * may be NULL); else 0 and `note` untouched. */
int sam_runtime_fitted_note(const sam_runtime *rt, char *note, size_t size);
/* Tree nodes of a cut map (the .sam's node_count); 0 for a flat map. */
uint32_t sam_runtime_node_count(const sam_runtime *rt);

/* The deformers of an animated pose (copied; `count` <= SAM_DEFORM_MAX,
 * each as sam_scene accepts them), replacing any earlier ones; 0 removes
 * them. Nothing moves until sam_runtime_deform. The first call (of this or
 * sam_runtime_set_keyframes) keeps the current positions, normals, fan
 * areas and samples on the GPU as the rest pose (36 + 16 n bytes per
 * vertex, n samples). Errors: SAM_ERR_INVALID_ARGUMENT (too many, NULL
 * with count > 0), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_set_deformers(sam_runtime *rt, const sam_deformer *deformers, size_t count,
                                     sam_error *err);

/* The keyframes of an animated pose (copied), replacing any earlier ones;
 * 0 removes them. `positions[i]` is keyframe i's 3 * vertex_count
 * positions in model units, render vertices in the .sam's order (the
 * caller checks that they belong to the same mesh:
 * sam_runtime_scene_keyframes does); `times[i]` its time in seconds,
 * finite, > 0 and strictly increasing. The rest pose is the key at time 0;
 * sam_runtime_deform interpolates linearly between the two keys around its
 * time, holds the last key after it and the rest pose before 0. Nothing
 * moves until sam_runtime_deform. Keeps the rest pose as
 * sam_runtime_set_deformers does, plus 16 bytes per vertex and keyframe.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL arrays with count > 0, a NULL
 * keyframe, times out of order or <= 0: naming the keyframe and time),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_set_keyframes(sam_runtime *rt, const float *const *positions, const float *times,
                                     size_t count, sam_error *err);

/* Poses the object at time `time_s` (seconds): a compute pass writes the
 * rest positions (or, with keyframes, the keyframe pose interpolated at
 * that time) moved by the deformers (sam_deform.h; sam_deform_positions
 * is its CPU reference), a second one every vertex's normal (the
 * area-weighted sum of the cross products of consecutive ring neighbours
 * in the adjacency buffer, normalised) and reduced fan area F'_i of eq. 16
 * in mm^2 (sam_mesh_fan_areas' sum in float). Every later pass reads the
 * new buffers: shadow maps, L_d, translucency (the posed K, from the new
 * positions and fan areas), shading and the diffusion techniques. When no deformer
 * moves anything at that time (none set, or all at strength 0) and the
 * keyframe pose is the rest pose (no keyframes, or time_s <= 0) the rest
 * positions, normals and fan areas are restored bit for bit, and so are
 * the bounds. On a deformed pose the normals pass also reduces the pose's
 * bounding box, which is read back (24 bytes, waiting for the deform
 * passes) for sam_runtime_bounds, the shadow maps' and the automatic
 * camera ranges. The mean curvature of pre-integrated shading is
 * recomputed from the pose too. Not updated: the surface area (depth-sized
 * atlases) stays the rest pose's.
 * The samples are walked to better back-side vertices by
 * sam_runtime_walk, not here; the rest pose also restores the .sam's
 * samples. On a deformed pose the translucency pass skips every vertex
 * sample that is no longer on the back side (eq. 13-14 at the pose, failed
 * by more than float rounding, so that a pose equal to rest but for
 * rounding keeps the rest's samples): it adds 0 rather than light through
 * the front.
 * Errors: SAM_ERR_INVALID_ARGUMENT (time not finite). */
sam_status sam_runtime_deform(sam_runtime *rt, float time_s, sam_error *err);

/* The sample walk of Sec. 3.4, one step: call it after every
 * sam_runtime_deform, before the translucency pass. For every vertex, each
 * one-ring neighbour (adjacency buffer) of its current samples that is on
 * the back side at the current pose (eq. 13-14 passed by more than float
 * rounding), and not chosen yet,
 * replaces the sample with the smallest approximated K (mean of R, G, B of
 * K' F'_b R_d(|v_b - v|), eq. 15; 0 for a sample off the back side, so
 * those go first) when its own approximated K is larger. The samples are
 * then sorted by approximated K, best first (empty slots last).
 *
 * K' of an adopted vertex: 1: its rest K is taken to be the point
 * estimate F'_i R_d(|v_i - v_o|) the builder ranks candidates by, and the
 * translucency pass carries it to the pose like any other. A stored K' is the
 * correction for one pair of fans; handed to another vertex (the replaced
 * slot's, or the one it was reached from) a far sample's large K' landed on
 * near vertices and, on a twisted ear, T came out 5.6 times the reference.
 *
 * Measured in tests/test_gl_walk.c (skin, n = 4, 4096 Monte Carlo pairs;
 * T's relative RMSE against a fresh build of the pose, K carried): a slab
 * bent 240 degrees 0.075 stale, 0.039 updated and walked; an ear twisted 90
 * degrees 0.222 stale, 0.093; a thin slab under a wave 0.077 stale, 0.040.
 *
 * The chosen set stays in the samples buffer from frame to frame, so
 * samples travel one ring per call as the pose moves. Seam copies of a
 * vertex share position, normal, ring and samples, so they stay identical.
 * On the rest pose (never deformed, or no deformer moving anything at the
 * last sam_runtime_deform, which restores the .sam's samples) the walk does
 * nothing: the builder's Monte Carlo choice is exact there, and samples and
 * K stay bit for bit. On a cut map (a .sam with a tree), whose rows count
 * every back-side vertex in reach once, the walk only replaces vertex
 * samples the pose took off the back side, and fills no spare slot; so a
 * pose near rest (an engine's pose that equals it, say) gives the rest's T.
 * Never fails today; `err` is for the contract. */
sam_status sam_runtime_walk(sam_runtime *rt, sam_error *err);

/* How the translucency pass takes K on a deformed pose (at rest K is the
 * builder's either way). */
typedef enum sam_posed_k {
    /* The default: K = (rest K) Q(pose) / Q(rest), Q a quadrature of eq. 11
     * over the two fans (one point per fan triangle, two one-sided rules
     * averaged; shaders/fan_form_factor.glsl). Eq. 15's point estimate
     * overreacts when a shear tilts the fans against the line between
     * their centres: on a slab under a wave its T was worse than the stale
     * map's (0.098 against 0.077), the carried K's 0.040. It costs about 12
     * R_d evaluations per sample more (on llvmpipe 10 to 24x the rest pass). */
    SAM_POSED_K_CARRIED = 0,
    /* The paper's eq. 15, K = K' F'_b R_d(|v_b - v|): as cheap as the rest
     * pass, good under bends, poor under shear. */
    SAM_POSED_K_EQ15 = 1
} sam_posed_k;

/* Chooses the posed K; takes effect at the next sam_runtime_translucency.
 * Errors: SAM_ERR_INVALID_ARGUMENT (an unknown mode). */
sam_status sam_runtime_set_posed_k(sam_runtime *rt, sam_posed_k mode, sam_error *err);

/* How the translucency pass takes the rest pose's K. */
typedef enum sam_rest_k {
    /* The default: every stored sample's K at rest, K' F'_b R_d(|v_b - v|)
     * (eq. 15), computed once at sam_runtime_create into a buffer of 16
     * bytes per stored sample (samples_per_vertex x vertex_count), so the
     * rest pass sums L_d K without evaluating R_d, and a posed frame reads
     * a tree node's rest K from it. On llvmpipe the flat map's rest pass
     * took a quarter to an eighth of its evaluated time
     * (docs/performance.md). */
    SAM_REST_K_CACHED = 0,
    /* Eq. 15 evaluated per sample every frame, as the paper does: no
     * buffer, for a GL short of memory. sam_runtime_create falls back to
     * it when the GL cannot hold the buffer. */
    SAM_REST_K_EVALUATED = 1
} sam_rest_k;

/* Chooses the rest K; takes effect at the next sam_runtime_translucency.
 * CACHED allocates and fills the buffer (from the rest pose, posed or
 * not), EVALUATED frees it; either compiles its programs on first use.
 * The two give the same T up to float rounding. Errors:
 * SAM_ERR_INVALID_ARGUMENT (an unknown mode), SAM_ERR_OUT_OF_MEMORY and
 * SAM_ERR_UNSUPPORTED (the GL cannot hold the buffer; the mode is left as
 * it was), SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_set_rest_k(sam_runtime *rt, sam_rest_k mode, sam_error *err);

/* The rest K in use (SAM_REST_K_EVALUATED after a fallback). */
sam_rest_k sam_runtime_rest_k_mode(const sam_runtime *rt);

/* Testing aid. Reads the samples buffer: `index` (vertex_count * n, n =
 * sam_runtime_samples_per_vertex) the back-side vertex of each sample (or
 * vertex_count + node for a cut map's tree node),
 * SAMFILE_NO_SAMPLE for an empty slot, and `kprime` (vertex_count * n * 3)
 * its K' as the GPU holds it, packed (each channel within 2^-14 of the
 * .sam's); row v holds vertex v's n samples, as in the .sam (the GPU keeps
 * them slot-major). For tests and tools. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_read_samples(sam_runtime *rt, uint32_t *index, float *kprime, sam_error *err);

/* Testing aid. Reads the current positions (model units) or unit normals (3 *
 * vertex_count floats), or the fan areas (vertex_count floats, mm^2).
 * Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_read_positions(sam_runtime *rt, float *xyz, sam_error *err);
sam_status sam_runtime_read_normals(sam_runtime *rt, float *xyz, sam_error *err);
sam_status sam_runtime_read_fan_areas(sam_runtime *rt, float *mm2, sam_error *err);
/* Testing aid. The mean curvature pre-integrated shading reads, 1/mm per vertex
 * (vertex_count floats): sam_mesh_ring_curvature of the .sam's positions and
 * normals at rest, of the pose's (computed on the GPU) once deformed. */
sam_status sam_runtime_read_curvature(sam_runtime *rt, float *per_mm, sam_error *err);

/* Each vertex's local thickness in mm (`count` = the vertex count, values
 * finite and >= 0, e.g. from sam_thickness_compute in the builder), for the
 * THICKNESS technique; NULL with count 0 removes it. The runtime keeps the
 * profile's slab transmission G(t) = 2 pi int_t^inf s R_d(s) ds of each
 * (sam_profile_slab_transmission): 16 bytes per vertex, and 16 more for the
 * technique's T. The thickness belongs to the rest pose; a deformed pose
 * keeps it. Errors: SAM_ERR_INVALID_ARGUMENT (a count other than the
 * vertex count, a NULL array, a value not finite or < 0, naming the vertex
 * and value), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_set_thickness(sam_runtime *rt, const float *mm, uint32_t count, sam_error *err);

/* The GDC talk's distortion of the THICKNESS technique: each point, spot
 * and directional light's cosine becomes that of -N with L + N distortion
 * (L towards the light) instead of with L, bending the light that comes
 * through towards the normal. 0 (the default) is the plain inverted
 * normal, the back side's own irradiance. Errors: SAM_ERR_INVALID_ARGUMENT
 * (outside [0, 1]). */
sam_status sam_runtime_set_thickness_distortion(sam_runtime *rt, float distortion, sam_error *err);

/* The lights of a scene (copied; `count` <= SAM_LIGHT_MAX_COUNT). Lights
 * with `shadow` get a shadow map with 4x4-texel PCF: a 1024^2 map for spot
 * and directional lights, and for point lights that see the object's
 * bounding sphere within a cone of 120 degrees (fitted to that cone each
 * frame); a 512^2 cube of distances for area lights (seen from the
 * polygon's centroid) and the other point lights. At most 4 cubes and 4
 * 1024^2 maps: distant point lights take a cube once the 1024^2 maps are
 * spent. Which kind a point light gets is chosen here, from the current
 * bounds (sam_runtime_bounds). Errors: SAM_ERR_INVALID_ARGUMENT,
 * SAM_ERR_UNSUPPORTED (too many shadowed lights, naming the counts). */
sam_status sam_runtime_set_lights(sam_runtime *rt, const sam_light *lights, size_t count, sam_error *err);

/* The environment's radiance SH (sam_light_sh9_from_latlong), or NULL for none. */
void sam_runtime_set_environment(sam_runtime *rt, const float sh[9][3]);

/* The specular lobe that rho_dt removes: Beckmann roughness m in
 * (0, 1] and rho_s (d'Eon's skin: m = 0.3, rho_s = 0.18, the defaults).
 * Errors: SAM_ERR_INVALID_ARGUMENT. */
sam_status sam_runtime_set_surface(sam_runtime *rt, float roughness, float rho_s, sam_error *err);

/* rho_dt for a light at cosine n_dot_l, and the environment's mean, as the
 * GPU evaluates them (for references and tools). */
float sam_runtime_rho_dt(const sam_runtime *rt, float n_dot_l);
float sam_runtime_environment_rho_dt(const sam_runtime *rt);

/* Renders the shadow maps from the current positions, then runs the
 * irradiance pass: L_d at every vertex. */
sam_status sam_runtime_irradiance(sam_runtime *rt, sam_error *err);

/* Sets L_d for every vertex from the CPU (3 * vertex_count floats). */
sam_status sam_runtime_set_irradiance(sam_runtime *rt, const float *rgb, sam_error *err);

/* Runs the translucency pass. `samples` is how many of the stored samples
 * to use (0 = all); `dt` the frame time in seconds; `reset` non-zero
 * replaces the history instead of blending (first frame, jumps).
 * Errors: SAM_ERR_INVALID_ARGUMENT (dt < 0 or not finite). */
sam_status sam_runtime_translucency(sam_runtime *rt, uint32_t samples, float dt, int reset, sam_error *err);

/* A view of the object for sam_runtime_render. Zero-initialise it and set
 * what you need: zero fields take their defaults. */
typedef struct sam_render_view {
    uint32_t width, height;  /* pixels */
    float eye[3], target[3], up[3];
    float fov_deg;           /* vertical */
    float near_plane, far_plane; /* 0: from the object's bounds */
    float albedo[3];         /* times the albedo map, if one is set */
    int front;               /* 1: front lighting + translucency; 0: translucency only */
    int diffusion;           /* 0: none; 1: screen-space separable SSS of the entering light;
                              * 2: pre-integrated skin (local, no blur);
                              * 3: texture-space sum of Gaussians (needs usable UVs) */
    /* Screen and texture space settings. Zero fields mean: fit2d kernel,
     * 17 samples, a 1024 atlas, no optimisation, 1 texel per pixel. */
    sam_diffusion_options options;
    /* Where the translucency comes from (zero: SAM_TECHNIQUE_SAM, the
     * per-vertex T of sam_runtime_translucency). NONE adds none;
     * TRANSMITTANCE, TSM and THICKNESS are described at sam_runtime_render. */
    sam_technique technique;
    /* NULL, or the translucency itself, replacing the technique's: linear
     * RGB or RGBA floats in T's units (light entering the surface, added to
     * R_total L_d before any blur). Without texture space it is view-sized,
     * row 0 at the top like the rendered image, one value per pixel; with
     * texture space it is atlas-sized (options.atlas_size, or 1024, with
     * depth_sized off), row v = texel row v like sam_runtime_read_atlas.
     * The caller keeps it; it is read during the call only. */
    const sam_image *translucency;
} sam_render_view;

/* Renders the object with its current L_d and T into a linear HDR RGBA
 * image (caller destroys it with sam_image_destroy): per pixel
 * rho_dt(N.V) / pi * (R_total L_d [if front] + T) * albedo plus specular,
 * alpha 1 on the object and 0 on the background.
 *
 * Albedo follows d'Eon Sec. 5.3: with a blur, the light entering the
 * surface is multiplied by sqrt(albedo) before it and the result by
 * sqrt(albedo) after it; without one, by the albedo.
 *
 * Screen diffusion blurs the entering light R_total L_d + T by two 1D passes
 * of the profile's separable kernel (options.sss_kernel, sss_samples taps),
 * its millimetre offsets scaled to pixels by each pixel's depth, taps across
 * depth jumps or off the object replaced by the centre.
 *
 * Pre-integrated shading (Penner) computes the front light per pixel:
 * point, spot and directional lights through the diffuse-falloff table at
 * the vertex's mean curvature (from the .sam's rings) and N.L, their shadow
 * through the penumbra table; area lights and the environment as in L_d.
 *
 * Texture-space diffusion (d'Eon) unwraps the entering light into a UV
 * atlas (options.atlas_size square) with a stretch map, blurs it
 * hierarchically with 7-tap Gaussians, one level per Gaussian of the
 * profile's 8-Gaussian fit, and sums the levels with the fit's weights; the
 * mesh then reads it at its UVs. Jimenez and Gutierrez's optimisations,
 * each a switch in `options`: `culled` leaves texels facing away from the
 * eye out of the atlas and the blur, past the silhouette by more than the
 * paper's 15 degrees or, where larger, the angle that spans four standard
 * deviations of the widest Gaussian at the vertex's curvature;
 * `clipped` leaves out texels outside the view frustum, widened by three
 * standard deviations of the widest Gaussian so light scattering in from
 * just off screen is kept; `depth_sized` shrinks the atlas to
 * T = min(1, d_ref / d) atlas_size, d the distance to the nearest point of
 * the object's bounding box and d_ref the distance at which a texel spans
 * 1 / texels_per_pixel of a pixel there (from the resolution, field of view,
 * surface area and atlas coverage, instead of the paper's hand-set d_ref).
 *
 * Techniques (view->technique; all give only their translucency with
 * front = 0; TRANSMITTANCE and TSM none for area lights or the
 * environment):
 * TRANSMITTANCE (Jimenez et al. 2010) evaluates, per pixel (per texel with
 * texture space), for every point, spot and directional light with a
 * shadow map: the thickness s in mm between the point and the surface the
 * map saw (looked up at the point moved 1% of the object's radius inside),
 * sum_i w_i exp(-s^2 / 2 v_i) over the profile's Gaussian fit, times the
 * light's unshadowed irradiance as if facing it, times
 * saturate(0.3 + N.(-L)); this is added where T would be.
 * TSM (d'Eon et al. 2007, Sec. 5.2) needs texture-space diffusion: each such
 * light also renders a translucent shadow map (the light-facing surface's
 * UV, distance and normal), every level of the blur is kept, and a
 * shadowed pixel adds sum_i w_i exp(-d^2 / 2 v_i) fadeOut_i level_i(uv_A),
 * d the distance through the object corrected by d'Eon's cosine term,
 * fadeOut_i rising from 0 at the pixel's own UV to 1 at 6 sqrt(v_i) mm
 * away. A TSM costs 32 MiB of maps for a 2D shadow map, 48 MiB for a cube
 * (sam_runtime_set_lights says which light gets which), and the levels
 * atlas_size^2 * 16 bytes each.
 * THICKNESS (Barre-Brisebois and Bouchard, GDC 2011, local thickness) runs
 * a per-vertex pass first and shades its result exactly where T goes (so
 * every diffusion mode applies): T = E_back G(t), t the vertex's thickness
 * (sam_runtime_set_thickness), G its slab transmission, and E_back every
 * light's irradiance on the plane facing -N (the cosine optionally
 * distorted, sam_runtime_set_thickness_distortion) times rho_dt of that
 * cosine, as L_d takes light in, plus the environment's SH-9 irradiance at
 * -N times its mean rho_dt. Point, spot, directional and area lights and
 * the environment all count, and none is shadowed: the back side counts as
 * lit wherever a light faces it, as engines ship the technique.
 *
 * Errors: SAM_ERR_INVALID_ARGUMENT (size, field of view, options or
 * technique out of range; a translucency override of the wrong size or
 * channel count, naming both sizes; THICKNESS without a thickness), SAM_ERR_UNSUPPORTED (texture space,
 * or the tsm technique, without usable UVs: see sam_runtime_uv_status; tsm
 * without texture-space diffusion; an incomplete framebuffer),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_render(sam_runtime *rt, const sam_render_view *view, sam_image *out, sam_error *err);

/* sam_runtime_render without the read-back, for a caller that shows the
 * picture on the GPU (a viewer): `*texture` gets the runtime's RGBA32F
 * texture holding the same linear HDR image, view->width x view->height,
 * row 0 at the BOTTOM as GL keeps it. The runtime owns the texture; it stays
 * valid until the next render, a render of another size, or
 * sam_runtime_destroy. On error `*texture` is 0. Errors as
 * sam_runtime_render. */
sam_status sam_runtime_render_texture(sam_runtime *rt, const sam_render_view *view, GLuint *texture,
                                      sam_error *err);

/* The view's view-projection matrix as sam_runtime_render uses it
 * (column-major, model units to clip space; `view` as checked by the
 * render: a size and field of view in range). */
void sam_runtime_view_projection(const sam_runtime *rt, const sam_render_view *view, float m[16]);

/* Where sam_runtime_gbuffer samples the surface. */
typedef enum sam_gbuffer_space {
    SAM_GBUFFER_SCREEN = 0, /* the view's pixels */
    SAM_GBUFFER_ATLAS = 1   /* the texture-space atlas's texels */
} sam_gbuffer_space;

/* The surface points a render evaluates translucency at, so a caller can
 * compute its own and give it back as view->translucency. Two new RGBA
 * float images (the caller destroys both): `positions` xyz the interpolated
 * model-space position (model units), `normals` xyz the interpolated,
 * re-normalised vertex normal as shading uses it (turned towards the eye on
 * back faces in SCREEN), alpha 1 where the object covers the pixel or texel
 * and 0 (xyz 0) elsewhere. SCREEN: view->width x view->height, row 0 at the
 * top, the same rasterisation as sam_runtime_render (its alpha mask).
 * ATLAS: atlas_size^2 (options.atlas_size or 1024; depth_sized must be off)
 * in sam_runtime_read_atlas's row order, every texel a chart covers
 * (culling and clipping do not apply). Only the view's camera, size and
 * options matter. Leaves the maps sam_runtime_read_atlas returns alone.
 * Errors: SAM_ERR_INVALID_ARGUMENT (the view's size or field of view, an
 * unknown space, a depth-sized atlas), SAM_ERR_UNSUPPORTED (ATLAS without
 * usable UVs), SAM_ERR_OUT_OF_MEMORY; on error both images are empty. */
sam_status sam_runtime_gbuffer(sam_runtime *rt, const sam_render_view *view, sam_gbuffer_space space,
                               sam_image *positions, sam_image *normals, sam_error *err);

/* Sets the albedo map (linear RGB or RGBA, read at the mesh's UVs; copied
 * to the GPU), or clears it with NULL; either clears several maps
 * (sam_runtime_set_albedo_maps). Errors: SAM_ERR_UNSUPPORTED (the
 * mesh has no UVs), SAM_ERR_INVALID_ARGUMENT (fewer than 3 channels, or
 * larger than the GL's texture limit). */
sam_status sam_runtime_set_albedo_map(sam_runtime *rt, const sam_image *map, sam_error *err);

/* Sets several albedo maps, each read by its own triangles (a file whose
 * materials have different textures: sam_mesh_load_albedo_maps), in place
 * of one map. `maps`: `count` linear images (3 or 4 channels; one without
 * pixels reads as white). `triangle_map`: per triangle of the map
 * (triangle_count, the map's), the map it reads at its UVs, or
 * SAM_ALBEDO_NO_MAP (sam_mesh.h) for none. The maps go to the GPU as one
 * array of sRGB bytes at the largest map's size (smaller maps resampled,
 * bilinear), halved until it holds at most 1 GiB (its mipmaps a third
 * more) and fits the GL's limits.
 * sam_runtime_set_albedo_map clears them, and they clear it. Errors:
 * SAM_ERR_INVALID_ARGUMENT (NULL or no maps, another triangle count, a
 * triangle naming no map), SAM_ERR_UNSUPPORTED (the mesh has no UVs; more
 * maps or triangles than the GL's array and buffer textures hold),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_set_albedo_maps(sam_runtime *rt, const sam_image *maps, uint32_t count,
                                       const uint32_t *triangle_map, uint32_t triangle_count, sam_error *err);

/* Sets the vertex colours (linear RGB, 3 * count floats, copied to the
 * GPU) that multiply the albedo and its map in sam_runtime_render, or
 * clears them with NULL. They come in the order of the mesh the map was
 * built from (its file's vertices, or an engine's: the map's SRCV, as
 * sam_mesh_load_vertex_colors gives them), count being that mesh's vertex
 * count; a map without SRCV takes them in its own order, count its vertex
 * count. Values are clamped to [0, 1]. The engine translucency buffer
 * (sam_runtime_engine_translucency) does not hold them: an engine
 * multiplies by its own colours. Errors: SAM_ERR_INVALID_ARGUMENT (a NULL
 * runtime, another count), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_set_vertex_colors(sam_runtime *rt, const float *rgb, uint32_t count, sam_error *err);

/* 1 when texture-space diffusion can run: the .sam has UVs whose charts,
 * moved into [0, 1]^2 when they reach past it (sam_uv_fit_atlas), do not
 * overlap (sam_uv_check at 1024^2). Otherwise 0, and `reason` (size n, may
 * be NULL) gets one line saying why. `atlas` (may be NULL) gets where the
 * UVs lie in the atlas, moved or not; the albedo map is read at the
 * mesh's own UVs, wrapping (GL_REPEAT) for tiled layouts. */
int sam_runtime_uv_status(const sam_runtime *rt, char *reason, size_t n, sam_uv_atlas *atlas);

/* The texture-space maps of the last texture-space render, T x T RGBA
 * floats (T the atlas side it used; caller destroys `out`). */
typedef enum sam_atlas_map {
    SAM_ATLAS_IRRADIANCE = 0, /* entering light; alpha 1 on texels the blur used */
    SAM_ATLAS_STRETCH = 1,    /* mm of surface per texel along u (r) and v (g) */
    SAM_ATLAS_DIFFUSED = 2    /* the weighted sum of the levels */
} sam_atlas_map;
/* Testing aid. Errors: SAM_ERR_INVALID_ARGUMENT (no texture-space render
 * yet, or an unknown map), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_read_atlas(sam_runtime *rt, sam_atlas_map map, sam_image *out, sam_error *err);

/* The object's bounding sphere in model units, around the box of the
 * current pose (the rest pose until sam_runtime_deform moves it). */
void sam_runtime_bounds(const sam_runtime *rt, float centre[3], float *radius);

/* Reads L_d or T back (3 * vertex_count floats). */
sam_status sam_runtime_read_irradiance(sam_runtime *rt, float *rgb, sam_error *err);
sam_status sam_runtime_read_translucency(sam_runtime *rt, float *rgb, sam_error *err);
/* Testing aid. The THICKNESS technique's T as its last render left it (3 * vertex_count
 * floats; its own buffer: SAM's T stays as sam_runtime_translucency left
 * it). Errors: SAM_ERR_INVALID_ARGUMENT (no thickness given),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_read_thickness_translucency(sam_runtime *rt, float *rgb, sam_error *err);

/* GPU time of the last run of `pass` in milliseconds (GL timer queries),
 * or a negative value when it has not run or the driver's answer cannot be
 * right (longer than the wall time since the query began: llvmpipe's for
 * texture-space diffusion). Waits for the result. llvmpipe's queries read
 * about 0 for compute passes (irradiance without shadow maps, translucency,
 * deform, walk, nodes): it times their dispatch, not their work. */
double sam_runtime_pass_ms(sam_runtime *rt, sam_pass pass);

/* ---- Embedding: an engine's own buffers in, a translucency buffer out.
 * The engine keeps its mesh, shaders and frame; see "Inside an engine" at
 * the top of this header. */

/* Where an engine keeps its posed vertices: GL buffer objects of floats in
 * its own layout (interleaved or not). Vertex e's x is at byte offset +
 * e * stride, then y and z. */
typedef struct sam_engine_pose {
    GLuint positions;         /* posed positions, model units (the .sam's); required */
    uint32_t position_offset; /* bytes, a multiple of 4 */
    uint32_t position_stride; /* bytes, a multiple of 4 and >= 12; 0 means 12 (packed) */
    GLuint normals;           /* posed normals (need not be unit), or 0: SAM computes them */
    uint32_t normal_offset;   /* as for positions */
    uint32_t normal_stride;
    uint32_t vertex_count;    /* vertices in the engine's buffers: sam_runtime_engine_vertex_count */
} sam_engine_pose;

/* Vertices in the engine's order: the source mesh's vertex count when the
 * .sam records it (chunk SRCV, which sam_build writes), else the .sam's own
 * vertex count (the engine must then draw the .sam's vertices as they are). */
uint32_t sam_runtime_engine_vertex_count(const sam_runtime *rt);

/* Takes the engine's posed buffers as the pose, in place of deformers and
 * keyframes (which this call removes): every sam_runtime_pose_from_engine
 * reads them. The first call keeps the current pose as the rest pose, as
 * sam_runtime_set_deformers does, so call it while the runtime is still
 * at rest. NULL stops reading the engine (the rest pose comes back at the
 * next sam_runtime_deform). The buffers stay the engine's: it keeps them
 * alive and must not shrink them while they are set.
 * Errors: SAM_ERR_INVALID_ARGUMENT naming the field and value: no
 * positions buffer, not a buffer object, an offset or stride not a
 * multiple of 4 or a stride below 12, a vertex count other than
 * sam_runtime_engine_vertex_count, a buffer too small for its vertices;
 * SAM_ERR_FORMAT (the engine passes' shaders, compiled at the first call);
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_set_engine_pose(sam_runtime *rt, const sam_engine_pose *pose, sam_error *err);

/* Per frame, in place of sam_runtime_deform: reads the engine's posed
 * positions (and normals) into the runtime, then the pose's normals (when
 * the engine gives none), fan areas, curvature and bounds, as the deform
 * pass does; sam_runtime_walk and the carried K then follow the pose.
 * Timed as SAM_PASS_DEFORM; one 24-byte read-back (the bounds).
 * Errors: SAM_ERR_INVALID_ARGUMENT (no engine pose set). */
sam_status sam_runtime_pose_from_engine(sam_runtime *rt, sam_error *err);

/* The translucency for the engine's shaders: a GL buffer of one vec4 per
 * engine vertex (RGB T of eq. 12, smoothed; w unspecified), in the
 * engine's vertex order (0 for a vertex no triangle uses; a vertex SAM
 * split at a seam shows its first copy's T). Bind it as a
 * vertex attribute (4 floats, stride 16) or as a shader storage buffer
 * (vec4 t[]). When the orders agree it is the runtime's own T buffer;
 * otherwise a small pass writes it. Call it after sam_runtime_translucency
 * each frame; the buffer stays the runtime's (valid until it is
 * destroyed). Errors: SAM_ERR_FORMAT (shaders, at the first call),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_engine_translucency(sam_runtime *rt, GLuint *buffer, sam_error *err);

/* The smoothing weight of eq. 18 for a frame time dt (seconds). */
float sam_runtime_smoothing_alpha(float dt);

#ifdef __cplusplus
}
#endif

#endif
