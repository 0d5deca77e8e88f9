/*
 * sam_app_backlight: the back light of a staged scene (sam_app_stage.h)
 * placed where it shows the most translucency. Candidates on a cone behind
 * the object, as the camera sees it, are each tried alone on the runtime:
 * its L_d and T, then the translucency the camera-facing side receives
 * (luminance of T times fan area). A light straight behind a thin part
 * that is attached to a thicker one (an ear on a head) is shadowed by the
 * thick part; one behind and to the side reaches it. Part of
 * sam_app_render (it runs the runtime's passes).
 */
#ifndef SAM_APP_BACKLIGHT_H
#define SAM_APP_BACKLIGHT_H

#include <stddef.h>

#include "sam/sam_runtime.h"
#include "sam/sam_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Candidates tried: straight behind, and 8 around each of 3 rings. */
#define SAM_APP_BACKLIGHT_CANDIDATES 25

/* Moves scene->lights[light] (a point light) to the best candidate: at
 * twice the bounding radius from the centre of the object's box (its
 * loose specks left out, sam_mesh_body), its intensity giving
 * irradiance 4 at the centre. `sam` is the runtime's map (for the rest
 * pose's normals and fan areas); the scene must have a camera. Leaves the
 * runtime lit by all the scene's lights again. `note` (may be NULL, `n`
 * bytes) gets one line saying where the light went, or that no candidate
 * sends any translucency to the side the camera sees (it is then straight
 * behind).
 * Errors: SAM_ERR_INVALID_ARGUMENT (no camera, `light` out of range or not
 * a point light), SAM_ERR_OUT_OF_MEMORY, and the runtime's. */
sam_status sam_app_backlight_place(sam_runtime *rt, const samfile_data *sam, sam_scene *scene, size_t light,
                                   char *note, size_t n, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
