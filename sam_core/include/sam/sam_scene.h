/*
 * sam_scene: scene files. A scene is a JSON object naming the object to
 * render (a mesh plus material and scale, or a prebuilt .sam), its lights,
 * environment, camera, output resolution and rendering choices. The viewer,
 * the headless renderer, the comparison tool and the benchmarks all read
 * the same files; the viewer writes them back to record a screenshot's scene.
 *
 * File format (keys not listed are errors, so a typo never goes unnoticed):
 *
 *   "mesh": "head.obj"  and/or  "sam": "head.sam"  at least one; with both,
 *        the .sam is the prebuilt map of that mesh (a renderer refuses it
 *        when its recorded source hash is another file's)
 *   "material": "skin" | "marble" | ... | "my_profile.json"
 *        a sam_profile preset name, else a profile file (sam_profile_load).
 *        Required with "mesh"; optional with "sam" (absent: the material the
 *        .sam records applies).
 *   "scale": {"mm_per_unit": 1.0} OR {"size_mm": 180.0}
 *        exactly one key, value > 0. Required with "mesh"; optional with
 *        "sam" (absent: the scale the .sam records applies).
 *   "albedo": [r, g, b]            each in [0, 1]; default [0.8, 0.8, 0.8]
 *   "albedo_map": "skin.png"       optional sRGB PNG, JPEG or TGA at the mesh's UVs; the
 *        albedo multiplies it (d'Eon Sec. 5.3: sqrt before and after scattering)
 *   "vertex_colors": true          default true: the mesh file's vertex colours
 *        (sam_mesh_load_vertex_colors) multiply the albedo too; false ignores them
 *   "lights": [light, ...]         default none; at most SAM_SCENE_MAX_LIGHTS
 *   "environment": {"map": "sky.exr", "intensity": 1.0, "rotation_deg": 0.0}
 *        optional; "map" required inside it (a latitude-longitude EXR),
 *        intensity >= 0 (default 1), rotation about +Y in degrees (default 0)
 *   "camera": {"position": [x,y,z], "target": [x,y,z], "up": [0,1,0],
 *              "fov_deg": 40, "near": n, "far": f}
 *        optional (absent: has_camera = 0 and the renderer frames the
 *        object from the front sam_scene_default_axes gives). position and target required inside it and distinct;
 *        up default [0,1,0], not parallel to the view direction; fov_deg is
 *        the vertical field of view in (0, 180), default 40; near > 0 and
 *        far > near, each default 0 = chosen by the renderer from the
 *        object's bounds.
 *   "resolution": [width, height]  integers in 1..16384; default [1280, 720]
 *   "technique": "sam" | "none" | "tsm" | "transmittance" | "thickness"   default "sam"
 *   "samples_per_vertex": N  the SAM samples each vertex sums, 1..64 (more than
 *        the .sam holds means all); default 0 = all
 *   "diffusion": "screen" | "texture" | "preintegrated" | "none"   default "screen"
 *   "screen_space": {"kernel": "fit2d" | "marginal" | "eq1", "samples": 17}
 *        optional; samples odd in 9..33 (sam_diffusion_options)
 *   "texture_space": {"atlas_size": 1024, "culled": false, "depth_sized": false,
 *                     "clipped": true, "texels_per_pixel": 1.0}
 *        optional; atlas_size in 64..4096, texels_per_pixel in (0, 16]
 *   "tonemap": "aces" | "reinhard"                           default "aces"
 *   "exposure": EV, finite, in [-32, 32]                     default 0
 *   "deformers": [deformer, ...]   default none; at most SAM_DEFORM_MAX,
 *        applied in order to the rest positions (formulas in sam_deform.h)
 *   "keyframes": [{"mesh": "pose1.obj", "time_s": 0.5}, ...]   default none
 *        poses of the object over time, each a mesh with the rest mesh's
 *        topology (the same render vertices and triangles after
 *        sam_mesh_load; checked when a runtime loads them,
 *        sam_runtime_scene_keyframes). Both keys required; time_s > 0 and
 *        strictly increasing. The rest mesh is the pose at time 0; between
 *        two keys the positions are interpolated linearly; after the last
 *        key the animation holds its pose (before time 0, the rest pose).
 *        The deformers apply on top of the interpolated positions.
 *
 * Deformers ("type" required; keys marked (required) must be given, the
 * others default to the value shown; vectors are normalised on load):
 *   {"type": "bend", "axis": [..] (required), "direction": [..] (required),
 *    "center": [0,0,0], "angle_deg" (required), "length" (required),
 *    "period_s": 0}
 *        the axis line through center curls towards direction (not
 *        parallel to axis) by angle_deg for every `length` model units
 *   {"type": "twist", "axis": [..] (required), "center": [0,0,0],
 *    "angle_deg" (required), "length" (required), "period_s": 0}
 *        rotation about the axis line by angle_deg every `length` units
 *   {"type": "squash", "axis": [..] (required), "center": [0,0,0],
 *    "amount" (required), "period_s": 0}
 *        scale 1 + amount along axis, 1 / sqrt(1 + amount) across it
 *   {"type": "wave", "axis": [..] (required), "direction": [..] (required),
 *    "amplitude" (required), "wavelength" (required), "speed": 0,
 *    "period_s": 0}
 *        displacement along direction, a sine travelling along axis
 *   angle_deg, amplitude, speed: finite; length, wavelength: > 0 (model
 *   units); amount in (-1, 1); period_s >= 0 (seconds). With period_s > 0
 *   the strength (angle, amount, amplitude) is multiplied by
 *   sin(2 pi t / period_s), so the animation repeats and starts at rest.
 *
 * Lights ("type" required; every other key optional unless marked):
 *   {"type": "point", "position": [..] (required), "color", "intensity", "shadow"}
 *   {"type": "spot", "position": [..] (required), "direction": [..] (required),
 *    "inner_angle_deg", "outer_angle_deg", "color", "intensity", "shadow"}
 *   {"type": "directional", "direction": [..] (required), "color",
 *    "intensity", "shadow"}
 *   {"type": "area", "vertices": [[x,y,z], ...] (required), "color",
 *    "intensity", "two_sided", "shadow"}
 *   color: [r,g,b] each >= 0, default [1,1,1]; intensity >= 0, default 1;
 *   shadow: default true; two_sided: default false.
 *   Spot angles are half-angles from the axis in degrees with
 *   0 <= inner <= outer < 90; outer defaults to 30, inner to 2/3 of outer.
 *   Directions are the way light travels, non-zero, stored normalised.
 *   Area vertices: 3..SAM_AREA_LIGHT_MAX_VERTICES, planar (every vertex
 *   within 1e-3 of the polygon's size from its plane), convex, with no
 *   repeated or collinear consecutive vertices; the light emits on the side
 *   its vertices wind counter-clockwise around (the stored normal), or on
 *   both sides when two_sided.
 *   Units: positions are in the mesh's model units. Point and spot lights
 *   give irradiance color * intensity / d^2 at distance d, a directional
 *   light irradiance color * intensity, an area light radiance
 *   color * intensity.
 *
 * Relative paths (mesh, sam, albedo map, environment map, profile file,
 * keyframe meshes)
 * resolve against the scene file's directory; the scene stores absolute
 * paths, and each referenced file must exist when the scene is loaded.
 *
 * Every error names the scene file and the key's path with the value found,
 * e.g. "scene.json: lights[0].intensity: expected a finite number >= 0,
 * found -1". A JSON syntax error gives the line and column.
 *
 * A sam_scene is plain data. All its pointers are malloc'd and owned by the
 * scene; sam_scene_destroy frees them. Nothing here keeps global state.
 * The light and rendering-choice types a scene holds belong to sam_light.h
 * and sam_technique.h, which the runtime uses without the parser; this
 * header includes both.
 */
#ifndef SAM_SCENE_H
#define SAM_SCENE_H

#include "sam/sam_common.h"
#include "sam/sam_deform.h"
#include "sam/sam_image.h" /* sam_tonemap */
#include "sam/sam_light.h"
#include "sam/sam_profile.h"
#include "sam/sam_technique.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The light limit of sam_light.h, by the name scene code has used. */
#define SAM_SCENE_MAX_LIGHTS SAM_LIGHT_MAX_COUNT
#define SAM_SCENE_MAX_RESOLUTION 16384

typedef enum sam_scale_kind {
    SAM_SCALE_FROM_SAM = 0,    /* no "scale" key: the .sam's recorded scale applies */
    SAM_SCALE_MM_PER_UNIT = 1, /* scale_value millimetres per model unit */
    SAM_SCALE_SIZE_MM = 2      /* scale_value = bounding-box diagonal in millimetres */
} sam_scale_kind;

typedef struct sam_environment {
    char *map;          /* absolute path of the EXR, NULL when the scene has no environment */
    float intensity;    /* >= 0 */
    float rotation_deg; /* about +Y */
} sam_environment;

typedef struct sam_camera {
    float position[3];
    float target[3];
    float up[3];      /* unit */
    float fov_deg;    /* vertical, (0, 180) */
    float near_plane; /* > 0, or 0 = automatic */
    float far_plane;  /* > near_plane, or 0 = automatic */
} sam_camera;

/* One pose of "keyframes". */
typedef struct sam_keyframe {
    char *mesh;   /* absolute path of a mesh with the rest mesh's topology */
    float time_s; /* > 0, larger than the previous keyframe's */
} sam_keyframe;

typedef struct sam_scene {
    char *mesh_path; /* absolute; at least one of mesh_path and sam_path is non-NULL */
    char *sam_path;

    char *material;      /* preset name as written, absolute profile path, or NULL ("sam" only) */
    sam_profile profile; /* the material's profile; meaningful when material != NULL */

    sam_scale_kind scale_kind;
    float scale_value; /* > 0 unless scale_kind == SAM_SCALE_FROM_SAM */

    float albedo[3]; /* each in [0, 1] */
    char *albedo_map; /* absolute path of an sRGB PNG, JPEG or TGA read at the mesh's UVs (times albedo), or NULL */
    int vertex_colors; /* 1: the mesh file's vertex colours multiply the albedo (default); 0: ignored */

    sam_light *lights; /* light_count entries */
    size_t light_count;

    sam_environment environment;

    int has_camera; /* 0: no "camera" key; `camera` holds defaults and is not used */
    sam_camera camera;

    uint32_t width, height; /* 1..SAM_SCENE_MAX_RESOLUTION */
    sam_technique technique;
    uint32_t samples_per_vertex; /* SAM samples a vertex sums, 1..64; 0 = all the .sam holds */
    sam_diffusion diffusion;
    sam_diffusion_options diffusion_options;
    sam_tonemap tonemap;
    float exposure; /* EV */

    sam_deformer deformers[SAM_DEFORM_MAX]; /* deformer_count used, applied in order */
    size_t deformer_count;

    sam_keyframe *keyframes; /* keyframe_count entries, times strictly increasing, or NULL */
    size_t keyframe_count;
} sam_scene;

/* Sets every field to its default: no mesh, no material, no lights, no
 * environment, no camera. Frees nothing: call it on a new scene only. A
 * caller building a scene by hand sets mesh_path etc. to malloc'd strings
 * and `lights` and `keyframes` (with their `mesh` strings) to malloc'd
 * arrays; sam_scene_destroy frees them. */
void sam_scene_init(sam_scene *scene);

/* A model axis that points up in the object's own frame. */
typedef enum sam_up_axis {
    SAM_UP_POS_X,
    SAM_UP_NEG_X,
    SAM_UP_POS_Y,
    SAM_UP_NEG_Y,
    SAM_UP_POS_Z,
    SAM_UP_NEG_Z,
    SAM_UP_AXIS_COUNT
} sam_up_axis;

/* The up axis named by `text`: "+X", "-X", "+Y", "-Y", "+Z" or "-Z", either
 * case, the sign optional ("z" is +Z). Returns 1 and fills *axis, or 0
 * (text NULL or anything else; *axis untouched). */
int sam_up_axis_parse(const char *text, sam_up_axis *axis);

/* "+X" ... "-Z"; "unknown" outside the enum. */
const char *sam_up_axis_name(sam_up_axis axis);

/* Unit vectors for an object whose `axis` points up: up[3], and front[3],
 * from the object towards the camera of its front view. +Y is seen from +Z
 * (OBJ's and glTF's convention), +Z from -Y (scanners' and CAD's); the
 * others from the front a half turn about X (-Y from -Z, -Z from +Y) or a
 * quarter turn about Z (+X and -X from +Z) brings there. Outside the enum:
 * +Y's. Returns the axis front[3] lies along. */
sam_up_axis sam_scene_axes_for_up(sam_up_axis axis, float up[3], float front[3]);

/* The up axis guessed for an object whose bounding box measures `extent`
 * (model units) when no camera is given: +Z where the box is clearly
 * tallest along Z (more than 1.1 times its Y and at least its X: scanners'
 * and CAD's convention), else +Y. */
sam_up_axis sam_scene_guess_up(const float extent[3]);

/* sam_scene_axes_for_up of sam_scene_guess_up(extent): the guessed axis,
 * its vectors into up[3] and front[3]. */
sam_up_axis sam_scene_default_axes(const float extent[3], float up[3], float front[3]);

/* Reads and parses the scene file at `path`. On success the caller owns
 * `scene` and frees it with sam_scene_destroy; on failure `scene` holds
 * nothing to free (it is left as by sam_scene_init).
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL arguments), SAM_ERR_IO (cannot
 * read the scene, or a referenced file is missing: the message gives its
 * absolute path), SAM_ERR_FORMAT (JSON syntax with line and column, unknown
 * keys, wrong types, values out of range: key path and value), and the
 * profile loader's errors for "material", SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_scene_load(const char *path, sam_scene *scene, sam_error *err);

/* Parses `size` bytes of JSON text (no NUL terminator needed). Relative
 * paths resolve against `base_dir` (NULL: the current directory); messages
 * start with `name` (NULL: "scene"). Errors and ownership as sam_scene_load. */
sam_status sam_scene_parse(const char *text, size_t size, const char *base_dir, const char *name,
                           sam_scene *scene, sam_error *err);

/* Writes `scene` as a scene file at `path`, atomically. Paths are written
 * absolute (a relative one in `scene` is taken against the current
 * directory), numbers in the shortest form that reads back to the same
 * float, optional values always explicitly, so loading the file gives the
 * same scene. The text is checked by parsing it back before anything is
 * written, so an invalid scene (a missing file, a value out of range) fails
 * with the parser's message and leaves no file.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL arguments), the parser's errors
 * for an invalid scene (an enum or value out of range, a missing file:
 * SAM_ERR_FORMAT or SAM_ERR_IO naming `path` and the key), SAM_ERR_IO,
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_scene_write(const char *path, const sam_scene *scene, sam_error *err);

/* Frees everything the scene owns and re-initialises it (sam_scene_init).
 * Safe on an initialised or destroyed scene and on NULL. */
void sam_scene_destroy(sam_scene *scene);

/* Names used in scene files ("point", "sam", "screen", "aces", ...);
 * "unknown" for a value outside the enum. */
const char *sam_light_type_name(sam_light_type type);
const char *sam_technique_name(sam_technique technique);
const char *sam_diffusion_name(sam_diffusion diffusion);
const char *sam_tonemap_name(sam_tonemap tonemap);
const char *sam_sss_kernel_name(sam_sss_kernel kernel);

#ifdef __cplusplus
}
#endif

#endif
