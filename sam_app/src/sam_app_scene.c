/* sam_app_scene_object: a scene's object as a map, read or built. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "sam/sam_app_scene.h"
#include "sam/sam_sha256.h"

/* A warning line on stderr, prefixed with `tool` where there is one. */
static void warn(const char *tool, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void warn(const char *tool, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s%swarning: ", tool ? tool : "", tool ? ": " : "");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* A prebuilt .sam: its material and scale unless the scene overrides them,
 * and proof that it is the map of the scene's mesh when one is named. */
static sam_status read_prebuilt(const sam_scene *scene, const char *tool, samfile_data *sam, sam_profile *profile,
                                float *mm_per_unit, sam_error *err)
{
    sam_status st = samfile_read(scene->sam_path, sam, err);
    if (st != SAM_OK)
        return st;
    samfile_info info;
    st = samfile_info_read(sam, scene->sam_path, &info, err);
    *mm_per_unit = info.mm_per_unit;
    /* An unreadable recorded material does not matter when the scene gives one. */
    if (scene->material && st == SAM_ERR_FORMAT)
        st = SAM_OK;
    if (st == SAM_OK && !scene->material && !info.has_material)
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: INFO records no material and the scene gives none", scene->sam_path);
    if (st == SAM_OK)
        *profile = scene->material ? scene->profile : info.profile;
    if (st == SAM_OK && scene->mesh_path) {
        char hex[65];
        st = sam_sha256_file(scene->mesh_path, hex, err);
        if (st == SAM_OK && !info.source_sha256[0])
            st = sam_fail(err, SAM_ERR_FORMAT, "%s: records no source hash, so it cannot be checked against %s",
                          scene->sam_path, scene->mesh_path);
        else if (st == SAM_OK && strcmp(info.source_sha256, hex))
            st = sam_fail(err, SAM_ERR_FORMAT,
                          "%s was built from another mesh (%s, sha256 %.12s...), not from %s (sha256 %.12s...)",
                          scene->sam_path, info.source_file[0] ? info.source_file : "unnamed", info.source_sha256,
                          scene->mesh_path, hex);
    }
    if (scene->scale_kind == SAM_SCALE_MM_PER_UNIT)
        *mm_per_unit = scene->scale_value;
    if (st == SAM_OK && scene->scale_kind == SAM_SCALE_SIZE_MM) {
        /* The map holds the mesh's positions and triangles in model units,
         * so its diagonal is the mesh's, specks left out alike. */
        sam_mesh extent = {.positions = sam->positions,
                           .vertex_count = sam->vertex_count,
                           .triangles = sam->triangles,
                           .triangle_count = sam->triangle_count};
        *mm_per_unit = (float)(scene->scale_value / sam_mesh_diagonal(&extent));
    }
    if (st == SAM_OK && !(*mm_per_unit > 0))
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: no scale (INFO has no mm_per_unit)", scene->sam_path);
    /* The map's cuts and candidates were chosen for its own material and
     * scale: rendered with others, it is not the map the scene would get. */
    if (st == SAM_OK && scene->material && info.has_material && strcmp(scene->profile.name, info.profile.name))
        warn(tool, "%s was built for %s; the scene renders it as %s (a map built for %s would look otherwise)",
             scene->sam_path, info.profile.name, scene->profile.name, scene->profile.name);
    if (st == SAM_OK && info.mm_per_unit > 0 && fabsf(*mm_per_unit / info.mm_per_unit - 1.0f) > 0.01f)
        warn(tool, "%s was built at %g mm per unit; the scene renders it at %g (a map built at %g would look "
             "otherwise)", scene->sam_path, (double)info.mm_per_unit, (double)*mm_per_unit, (double)*mm_per_unit);
    if (st != SAM_OK)
        samfile_free(sam);
    return st;
}

sam_status sam_app_scene_object(const sam_scene *scene, const char *tool, const sam_build_settings *settings,
                                sam_build_progress_fn progress, void *user, samfile_data *sam, sam_profile *profile,
                                float *mm_per_unit, double *built_seconds, sam_error *err)
{
    if (sam)
        memset(sam, 0, sizeof *sam);
    if (built_seconds)
        *built_seconds = 0;
    if (!scene || !sam || !profile || !mm_per_unit)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene object: NULL argument");
    if (!scene->sam_path && !scene->mesh_path)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene object: the scene names neither a mesh nor a .sam");
    if (scene->sam_path)
        return read_prebuilt(scene, tool, sam, profile, mm_per_unit, err);
    sam_mesh mesh;
    sam_status st = sam_mesh_load(scene->mesh_path, &mesh, NULL, err);
    if (st != SAM_OK)
        return st;
    if (sam_mesh_orient_outward(&mesh))
        warn(tool, "%s is closed and faces inward (negative volume): turned outside out", scene->mesh_path);
    *profile = scene->profile;
    *mm_per_unit = scene->scale_kind == SAM_SCALE_SIZE_MM ? (float)(scene->scale_value / sam_mesh_diagonal(&mesh))
                                                          : scene->scale_value;
    /* The hash lets a saved copy of this map be checked against the mesh
     * later (a viewer's cache, a screenshot's scene). */
    char hex[65];
    if ((st = sam_sha256_file(scene->mesh_path, hex, err)) != SAM_OK) {
        sam_mesh_destroy(&mesh);
        return st;
    }
    sam_build_source source = {scene->mesh_path, hex};
    st = sam_build_samfile(&mesh, profile, *mm_per_unit, settings, &source, progress, user, sam, built_seconds, err);
    sam_mesh_destroy(&mesh);
    return st;
}

void sam_app_scene_from_mesh(const sam_scene *scene, const sam_profile *profile, float mm_per_unit,
                             sam_scene *out)
{
    *out = *scene;
    out->sam_path = NULL;
    out->profile = *profile;
    out->scale_kind = SAM_SCALE_MM_PER_UNIT;
    out->scale_value = mm_per_unit;
}
