/*
 * sam_app_stage: the scene a bare mesh gets when the user writes none, so
 * that their own OBJ/PLY/OFF/STL/glTF gives a picture where back-lit thin parts
 * glow: the object's size when it is not given, a camera that frames it, a
 * key light in front and a back light (placed on the runtime where the
 * camera sees the most light come through), and, once rendered, an
 * exposure read from the picture. sam_render
 * and sam_view use it; each assumption comes back as one line of text for
 * the tool to print, and the scene can be saved (sam_scene_write) to be
 * edited from there. Part of sam_app_build: the thickness is measured with
 * the builder's ray caster.
 *
 * Step by step:
 *   1. sam_app_stage_defaults(&options), then set what the user gave.
 *   2. sam_app_stage_scene(mesh_path, material, &options, &scene, &notes, &err):
 *      loads and measures the mesh and fills a whole scene.
 *   3. With the map on a runtime, sam_app_backlight_place(rt, sam, &scene,
 *      SAM_APP_STAGE_BACK_LIGHT, ...) places the back light.
 *   4. Render it; sam_app_stage_exposure(&hdr) gives the EV to tonemap with
 *      (store it in scene.exposure before saving the scene).
 *
 * How the choices are made (docs/staging.md has the reasoning):
 *   - Thin parts: each vertex's depth straight through, the mean over its
 *     rays within 30 degrees of the inverted normal (sam_thickness,
 *     SAM_THICKNESS_THROUGH, 12 of 36 rays);
 *     "thin" is the thinnest SAM_APP_STAGE_THIN_FRACTION of the vertices.
 *   - Size, when neither size_mm nor mm_per_unit is given: the scale at
 *     which those thin parts are as thick as a slab of the material that
 *     lets SAM_APP_STAGE_GLOW of the light through (the profile's slab
 *     transmission, mean of RGB), so that they glow whatever the material,
 *     kept within SAM_APP_STAGE_MIN_MM..SAM_APP_STAGE_MAX_MM across (the
 *     objects people render translucent, from a grape to a torso).
 *   - Camera: up is the axis given, else +Z where the mesh is clearly
 *     tallest along Z, else +Y; seen from the front sam_scene_axes_for_up
 *     gives that axis (+Y from +Z, +Z from -Y); 30 degrees of vertical
 *     field of view, looking at the bounding box's centre from the front turned by
 *     angle_deg about up and raised 10 degrees (50 for a part much flatter
 *     along up than across), far enough that the bounding sphere fits.
 *   - Key light: a point light above, left of and in front of the camera,
 *     irradiance 0.5 at the centre. Back light (scene->lights[1]): a point
 *     light straight behind the object, irradiance 4 at the centre, which
 *     a renderer then moves where it shows the most translucency
 *     (sam_app_backlight.h). Both cast shadows.
 *   - Exposure: the 97th percentile of the object's luminance maps to 1.2
 *     (0.82 after ACES).
 */
#ifndef SAM_APP_STAGE_H
#define SAM_APP_STAGE_H

#include "sam/sam_image.h"
#include "sam/sam_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SAM_APP_STAGE_MAX_NOTES 8
#define SAM_APP_STAGE_THIN_FRACTION 0.05f
#define SAM_APP_STAGE_GLOW 0.05f
#define SAM_APP_STAGE_BACK_LIGHT 1 /* the staged scene's back light's index */
#define SAM_APP_STAGE_MIN_MM 10.0f
#define SAM_APP_STAGE_MAX_MM 500.0f

typedef struct sam_app_stage_options {
    float size_mm;     /* > 0: the bounding-box diagonal in mm; 0: not given */
    float mm_per_unit; /* > 0: millimetres per model unit; 0: not given (not with size_mm) */
    float angle_deg;   /* the camera's turn about up from the front, degrees, finite */
    int up;            /* -1: guessed from the mesh's box; else the sam_up_axis that points up */
    uint32_t width, height; /* the picture, 1..SAM_SCENE_MAX_RESOLUTION; 0: the scene default */
} sam_app_stage_options;

/* The assumptions made, one line each, for the tool to print. */
typedef struct sam_app_stage_notes {
    char line[SAM_APP_STAGE_MAX_NOTES][256];
    int count;
    int size_guessed; /* 1: neither size was given and one was chosen */
} sam_app_stage_notes;

/* Zero sizes (not given), angle 0, up guessed, the scene's default resolution. */
void sam_app_stage_defaults(sam_app_stage_options *options);

/* A whole scene for the mesh at `mesh_path` in `material` (a preset or a
 * profile file; NULL: skin) into `scene` (the caller's, freed with
 * sam_scene_destroy whatever the result), with `notes` (may be NULL)
 * saying what was assumed.
 * Errors: SAM_ERR_INVALID_ARGUMENT (both sizes given, a size not finite and
 * > 0, an angle not finite, an up outside -1..SAM_UP_AXIS_COUNT - 1, a
 * resolution out of range), those of
 * sam_scene_parse (a missing file, an unknown material), sam_mesh_load and
 * sam_thickness_compute. */
sam_status sam_app_stage_scene(const char *mesh_path, const char *material, const sam_app_stage_options *options,
                               sam_scene *scene, sam_app_stage_notes *notes, sam_error *err);

/* The exposure in EV that maps the 97th percentile of the brightest
 * channel (the largest of R, G, B) of the picture's covered pixels (alpha > 0.5 in an RGBA image; every pixel of
 * an RGB one) to 1.2, clamped to [-32, 32]; 0 when no pixel is covered or
 * lit. */
float sam_app_stage_exposure(const sam_image *hdr);

#ifdef __cplusplus
}
#endif

#endif
