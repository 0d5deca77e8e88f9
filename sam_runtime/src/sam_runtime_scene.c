/* A scene file applied to a runtime (sam_runtime_scene.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_light.h"
#include "sam/sam_mesh.h"
#include "sam/sam_runtime_scene.h"
#include "sam_runtime_internal.h"

static void set_warning(char *warning, size_t n, const char *text)
{
    if (warning && n)
        snprintf(warning, n, "%s", text);
}

/* Appends `text` to `warning` (size n, may be NULL), after "; " when it
 * holds one already. */
static void add_warning(char *warning, size_t n, const char *text)
{
    if (!warning || !n)
        return;
    const size_t used = strlen(warning);
    snprintf(warning + used, n - used, "%s%s", used ? "; " : "", text);
}

/* The mesh file's vertex colours, if it has any. Colours the map cannot
 * take (a map built from another mesh than the scene names) are a
 * warning, added to what `warning` holds, not an error. */
static sam_status set_vertex_colors(sam_runtime *rt, const char *mesh_path, char *warning, size_t n, sam_error *err)
{
    float *rgb = NULL;
    uint32_t count = 0;
    char note[2304];
    sam_status st = sam_mesh_load_vertex_colors(mesh_path, &rgb, &count, note, sizeof note, err);
    sam_error why;
    const sam_status set = st == SAM_OK && rgb ? sam_runtime_set_vertex_colors(rt, rgb, count, &why) : SAM_OK;
    if (set == SAM_ERR_INVALID_ARGUMENT) {
        char text[2304 + SAM_ERROR_MESSAGE_SIZE + 16];
        snprintf(text, sizeof text, "%s ignored: %s", note, why.message);
        add_warning(warning, n, text);
    } else if (set != SAM_OK && set != SAM_ERR_INVALID_ARGUMENT) {
        st = sam_fail(err, set, "%s", why.message);
    }
    free(rgb);
    return st;
}

/* The albedo maps of a mesh file whose faces read several
 * (sam_mesh_load_albedo_maps), each on its triangles: *several is 1 when
 * the file has them, set or left out with a warning. The mesh is loaded
 * for its triangles' faces: the map's triangles are its own, in order. */
static sam_status set_albedo_maps(sam_runtime *rt, const char *mesh_path, int *several, char *warning, size_t n,
                                  sam_error *err)
{
    sam_albedo_maps maps;
    char note[2304];
    sam_status st = sam_mesh_load_albedo_maps(mesh_path, &maps, note, sizeof note, err);
    *several = st == SAM_OK && maps.map_count;
    if (!*several)
        return st;
    if (note[0])
        add_warning(warning, n, note);
    sam_mesh mesh;
    uint32_t *triangle_map = NULL;
    if ((st = sam_mesh_load(mesh_path, &mesh, NULL, err)) == SAM_OK &&
        !(triangle_map = malloc(((size_t)mesh.triangle_count + 1) * sizeof *triangle_map)))
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %u triangles", mesh_path,
                      mesh.triangle_count);
    for (uint32_t t = 0; st == SAM_OK && t < mesh.triangle_count; ++t) {
        const uint32_t f = mesh.face_of_triangle[t];
        triangle_map[t] = f < maps.face_count ? maps.face_map[f] : SAM_ALBEDO_NO_MAP;
    }
    sam_error why;
    const sam_status set = st == SAM_OK ? sam_runtime_set_albedo_maps(rt, maps.maps, maps.map_count, triangle_map,
                                                                      mesh.triangle_count, &why)
                                        : SAM_OK;
    if (set == SAM_ERR_INVALID_ARGUMENT || set == SAM_ERR_UNSUPPORTED) {
        char text[2304];
        snprintf(text, sizeof text, "the %u albedo maps of %s ignored: %s", maps.map_count, mesh_path, why.message);
        add_warning(warning, n, text);
    } else if (set != SAM_OK) {
        st = sam_fail(err, set, "%s", why.message);
    }
    free(triangle_map);
    sam_mesh_destroy(&mesh);
    sam_albedo_maps_destroy(&maps);
    return st;
}

/* The scene's albedo map, else the one the mesh file brings (an OBJ's
 * map_Kd, a glTF's base colour), or its several. */
static sam_status set_albedo(sam_runtime *rt, const sam_scene *scene, char *warning, size_t n, sam_error *err)
{
    sam_image map;
    memset(&map, 0, sizeof map);
    const char *source = scene->albedo_map;
    sam_status st;
    if (source) {
        if ((st = sam_image_read_picture(source, &map, SAM_PNG_SRGB, err)) != SAM_OK)
            return st;
    } else if (scene->mesh_path) {
        char note[2304]; /* as sam_app_stage.c's */
        int several = 0;
        if ((st = set_albedo_maps(rt, scene->mesh_path, &several, warning, n, err)) != SAM_OK || several)
            return st;
        if ((st = sam_mesh_load_albedo(scene->mesh_path, &map, note, sizeof note, err)) != SAM_OK)
            return st;
        if (note[0] && !map.pixels)
            add_warning(warning, n, note);
        source = scene->mesh_path;
    }
    st = map.pixels ? sam_runtime_set_albedo_map(rt, &map, err) : SAM_OK;
    sam_image_destroy(&map);
    if (st != SAM_ERR_UNSUPPORTED)
        return st;
    char text[2304];
    snprintf(text, sizeof text, "albedo map of %s ignored: the mesh has no UVs", source);
    add_warning(warning, n, text);
    return SAM_OK;
}

sam_status sam_runtime_scene_setup(sam_runtime *rt, const sam_scene *scene, float sh[9][3], int *has_environment,
                                   char *warning, size_t n, sam_error *err)
{
    set_warning(warning, n, "");
    if (has_environment)
        *has_environment = 0;
    if (!rt || !scene)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene setup: NULL runtime or scene");
    sam_status st = sam_runtime_set_lights(rt, scene->lights, scene->light_count, err);
    if (st == SAM_OK && scene->deformer_count)
        st = sam_runtime_set_deformers(rt, scene->deformers, scene->deformer_count, err);
    if (st != SAM_OK)
        return st;
    float env_sh[9][3];
    sam_runtime_set_environment(rt, NULL);
    if (scene->environment.map) {
        sam_image env;
        if ((st = sam_image_read_exr(scene->environment.map, &env, err)) != SAM_OK)
            return st;
        st = sam_light_sh9_from_latlong(&env, scene->environment.rotation_deg, scene->environment.intensity, env_sh,
                                        err);
        sam_image_destroy(&env);
        if (st != SAM_OK)
            return st;
        sam_runtime_set_environment(rt, (const float(*)[3])env_sh);
        if (sh)
            memcpy(sh, env_sh, sizeof env_sh);
        if (has_environment)
            *has_environment = 1;
    }
    /* A scene set up again (sam_view reloading it) keeps none of the last
     * one's maps or colours. */
    sam_runtime_set_albedo_map(rt, NULL, NULL);
    sam_runtime_set_vertex_colors(rt, NULL, 0, NULL);
    st = set_albedo(rt, scene, warning, n, err);
    if (st == SAM_OK && scene->vertex_colors && scene->mesh_path)
        st = set_vertex_colors(rt, scene->mesh_path, warning, n, err);
    return st;
}

/* The rest mesh's topology a keyframe must have: render vertices and
 * triangles, in order. */
typedef struct rest_topology {
    uint32_t vertex_count, triangle_count;
    const uint32_t *triangles;
} rest_topology;

/* Loads keyframe mesh `path` into `mesh`, turned as the rest mesh was when
 * its map was built, and refuses it when its render vertices or triangles
 * are not the rest mesh's: its positions would land on other vertices. */
static sam_status load_keyframe(const char *path, const rest_topology *rest, sam_mesh *mesh, sam_error *err)
{
    sam_status st = sam_mesh_load(path, mesh, NULL, err);
    if (st != SAM_OK)
        return st;
    sam_mesh_orient_outward(mesh);
    if (mesh->vertex_count != rest->vertex_count)
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: %u vertices, the rest mesh has %u", path, mesh->vertex_count,
                      rest->vertex_count);
    else if (mesh->triangle_count != rest->triangle_count)
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: %u triangles, the rest mesh has %u", path, mesh->triangle_count,
                      rest->triangle_count);
    for (uint32_t t = 0; st == SAM_OK && t < mesh->triangle_count; ++t) {
        const uint32_t *a = mesh->triangles + 3 * t, *b = rest->triangles + 3 * t;
        if (memcmp(a, b, 3 * sizeof *a) != 0)
            st = sam_fail(err, SAM_ERR_FORMAT, "%s: triangle %u is (%u, %u, %u), the rest mesh's is (%u, %u, %u)",
                          path, t, a[0], a[1], a[2], b[0], b[1], b[2]);
    }
    if (st != SAM_OK)
        sam_mesh_destroy(mesh);
    return st;
}

sam_status sam_runtime_scene_keyframes(sam_runtime *rt, const sam_scene *scene, const samfile_data *sam,
                                       sam_error *err)
{
    if (!rt || !scene || !sam)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene keyframes: NULL runtime, scene or map");
    const size_t count = scene->keyframe_count;
    if (!count)
        return sam_runtime_set_keyframes(rt, NULL, NULL, 0, err);
    const rest_topology rest = {sam->vertex_count, sam->triangle_count, sam->triangles};
    float **positions = calloc(count, sizeof *positions);
    float *times = malloc(count * sizeof *times);
    sam_status st = positions && times ? SAM_OK
                                       : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "scene keyframes: out of memory for %zu",
                                                  count);
    for (size_t i = 0; i < count && st == SAM_OK; ++i) {
        sam_mesh mesh;
        times[i] = scene->keyframes[i].time_s;
        if ((st = load_keyframe(scene->keyframes[i].mesh, &rest, &mesh, err)) != SAM_OK)
            break;
        /* Taken over, not copied: the mesh's positions outlive it. */
        positions[i] = mesh.positions;
        mesh.positions = NULL;
        sam_mesh_destroy(&mesh);
    }
    if (st == SAM_OK)
        st = sam_runtime_set_keyframes(rt, (const float *const *)positions, times, count, err);
    for (size_t i = 0; positions && i < count; ++i)
        free(positions[i]);
    free(positions);
    free(times);
    return st;
}

sam_status sam_runtime_scene_check_keyframes(const sam_scene *scene, sam_error *err)
{
    if (!scene)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene keyframes: NULL scene");
    if (!scene->keyframe_count)
        return SAM_OK;
    samfile_data map;
    sam_mesh rest_mesh;
    memset(&map, 0, sizeof map);
    memset(&rest_mesh, 0, sizeof rest_mesh);
    rest_topology rest;
    sam_status st;
    if (scene->sam_path) {
        st = samfile_read(scene->sam_path, &map, err);
        rest = (rest_topology){map.vertex_count, map.triangle_count, map.triangles};
    } else {
        /* As the map built from it will be: loaded and turned outward. */
        st = sam_mesh_load(scene->mesh_path, &rest_mesh, NULL, err);
        if (st == SAM_OK)
            sam_mesh_orient_outward(&rest_mesh);
        rest = (rest_topology){rest_mesh.vertex_count, rest_mesh.triangle_count, rest_mesh.triangles};
    }
    for (size_t i = 0; i < scene->keyframe_count && st == SAM_OK; ++i) {
        sam_mesh mesh;
        if ((st = load_keyframe(scene->keyframes[i].mesh, &rest, &mesh, err)) == SAM_OK)
            sam_mesh_destroy(&mesh);
    }
    samfile_free(&map);
    sam_mesh_destroy(&rest_mesh);
    return st;
}

void sam_runtime_scene_view(const sam_runtime *rt, const sam_scene *scene, sam_render_view *view, char *warning,
                            size_t n)
{
    set_warning(warning, n, "");
    memset(view, 0, sizeof *view);
    view->width = scene->width;
    view->height = scene->height;
    memcpy(view->albedo, scene->albedo, sizeof view->albedo);
    view->front = 1;
    view->options = scene->diffusion_options;
    /* sam_render_view.diffusion: 0 none, 1 screen, 2 pre-integrated, 3 texture */
    view->diffusion = scene->diffusion == SAM_DIFFUSION_PREINTEGRATED ? 2
                      : scene->diffusion == SAM_DIFFUSION_TEXTURE    ? 3
                      : scene->diffusion == SAM_DIFFUSION_NONE       ? 0
                                                                     : 1;
    char reason[160];
    if (view->diffusion == 3 && !sam_runtime_uv_status(rt, reason, sizeof reason, NULL)) {
        if (warning && n)
            snprintf(warning, n, "texture-space diffusion falls back to screen space: %s", reason);
        view->diffusion = 1;
    }
    if (scene->has_camera) {
        memcpy(view->eye, scene->camera.position, sizeof view->eye);
        memcpy(view->target, scene->camera.target, sizeof view->target);
        memcpy(view->up, scene->camera.up, sizeof view->up);
        view->fov_deg = scene->camera.fov_deg;
        view->near_plane = scene->camera.near_plane;
        view->far_plane = scene->camera.far_plane;
    } else {
        /* From the front a bare mesh is staged from (sam_app_stage.h), so
         * that a Z-up scan is not seen from above. */
        float centre[3], radius, extent[3], front[3];
        sam_runtime_bounds(rt, centre, &radius);
        for (int c = 0; c < 3; ++c)
            extent[c] = rt->box_hi[c] - rt->box_lo[c];
        sam_scene_default_axes(extent, view->up, front);
        view->fov_deg = 40.0f;
        const float dist = radius / sinf(0.5f * view->fov_deg * 3.14159265f / 180.0f) * 1.05f;
        memcpy(view->target, centre, sizeof view->target);
        for (int c = 0; c < 3; ++c)
            view->eye[c] = centre[c] + dist * front[c];
    }
}
