/*
 * sam_scene: scene files (sam_scene.h). This file holds the enum names,
 * the scene's lifetime, the root object with its small sections (material,
 * scale, camera, resolution, diffusion settings) and the entry points that
 * turn text into a scene; the lights, the animation and the writer have
 * files of their own (sam_scene_internal.h says which).
 */
#define _POSIX_C_SOURCE 200809L
#include "sam_scene_internal.h"

#include "sam/sam_mesh.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/* ------------------------------------------------------------------------ */
/* Names                                                                     */

static const char *const technique_names[] = {"sam", "none", "tsm", "transmittance", "thickness"};
static const char *const diffusion_names[] = {"screen", "texture", "preintegrated", "none"};
static const char *const tonemap_names[] = {"aces", "reinhard"};
static const char *const sss_kernel_names[] = {"fit2d", "marginal", "eq1"};

const char *sam_technique_name(sam_technique technique)
{
    return sam_scene_name_at(technique_names, COUNT_OF(technique_names), (int)technique);
}

const char *sam_diffusion_name(sam_diffusion diffusion)
{
    return sam_scene_name_at(diffusion_names, COUNT_OF(diffusion_names), (int)diffusion);
}

const char *sam_tonemap_name(sam_tonemap tonemap)
{
    return sam_scene_name_at(tonemap_names, COUNT_OF(tonemap_names), (int)tonemap);
}

const char *sam_sss_kernel_name(sam_sss_kernel kernel)
{
    return sam_scene_name_at(sss_kernel_names, COUNT_OF(sss_kernel_names), (int)kernel);
}

/* ------------------------------------------------------------------------ */
/* Scene lifetime                                                            */

static const char *const up_axis_names[] = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};

const char *sam_up_axis_name(sam_up_axis axis)
{
    return sam_scene_name_at(up_axis_names, COUNT_OF(up_axis_names), (int)axis);
}

int sam_up_axis_parse(const char *text, sam_up_axis *axis)
{
    if (!text)
        return 0;
    const int negative = text[0] == '-';
    if (text[0] == '-' || text[0] == '+')
        text++;
    const char *const letters = "xyz";
    const char c = (char)tolower((unsigned char)text[0]);
    if (!c || text[1] || !strchr(letters, c))
        return 0;
    *axis = (sam_up_axis)(2 * (int)(strchr(letters, c) - letters) + negative);
    return 1;
}

sam_up_axis sam_scene_axes_for_up(sam_up_axis axis, float up[3], float front[3])
{
    /* The front each up is seen from, as an axis code of the same kind. */
    static const sam_up_axis fronts[SAM_UP_AXIS_COUNT] = {SAM_UP_POS_Z, SAM_UP_POS_Z, SAM_UP_POS_Z,
                                                          SAM_UP_NEG_Z, SAM_UP_NEG_Y, SAM_UP_POS_Y};
    if ((int)axis < 0 || axis >= SAM_UP_AXIS_COUNT)
        axis = SAM_UP_POS_Y;
    const sam_up_axis f = fronts[axis];
    for (int c = 0; c < 3; ++c) {
        up[c] = c == (int)axis / 2 ? ((int)axis % 2 ? -1.0f : 1.0f) : 0.0f;
        front[c] = c == (int)f / 2 ? ((int)f % 2 ? -1.0f : 1.0f) : 0.0f;
    }
    return f;
}

sam_up_axis sam_scene_guess_up(const float extent[3])
{
    return extent[2] > 1.1f * extent[1] && extent[2] >= extent[0] ? SAM_UP_POS_Z : SAM_UP_POS_Y;
}

sam_up_axis sam_scene_default_axes(const float extent[3], float up[3], float front[3])
{
    const sam_up_axis axis = sam_scene_guess_up(extent);
    sam_scene_axes_for_up(axis, up, front);
    return axis;
}

void sam_scene_init(sam_scene *scene)
{
    if (!scene)
        return;
    memset(scene, 0, sizeof *scene);
    scene->scale_kind = SAM_SCALE_FROM_SAM;
    scene->albedo[0] = scene->albedo[1] = scene->albedo[2] = 0.8f;
    scene->vertex_colors = 1;
    scene->environment.intensity = 1.0f;
    scene->camera.up[1] = 1.0f;
    scene->camera.target[2] = -1.0f;
    scene->camera.fov_deg = 40.0f;
    scene->width = 1280;
    scene->height = 720;
    scene->technique = SAM_TECHNIQUE_SAM;
    scene->diffusion = SAM_DIFFUSION_SCREEN;
    sam_diffusion_options_default(&scene->diffusion_options);
    scene->tonemap = SAM_TONEMAP_ACES;
}

void sam_scene_destroy(sam_scene *scene)
{
    if (!scene)
        return;
    free(scene->mesh_path);
    free(scene->sam_path);
    free(scene->material);
    free(scene->albedo_map);
    free(scene->lights);
    free(scene->environment.map);
    for (size_t i = 0; i < scene->keyframe_count; ++i)
        free(scene->keyframes[i].mesh);
    free(scene->keyframes);
    sam_scene_init(scene);
}

/* ------------------------------------------------------------------------ */
/* The root object and its small sections                                   */

int sam_scene_is_preset(const char *spec)
{
    for (size_t i = 0; i < sam_profile_preset_count(); ++i) {
        if (strcasecmp(spec, sam_profile_preset_name(i)) == 0)
            return 1;
    }
    return 0;
}

static sam_status parse_material(const sam_scene_parser *p, const cJSON *item, sam_scene *scene)
{
    const char *spec;
    sam_status st = sam_json_string(&p->json, item, "material", &spec);
    if (st != SAM_OK)
        return st;
    sam_error perr;
    if (sam_scene_is_preset(spec)) {
        scene->material = sam_strdup(spec);
        if (!scene->material)
            return sam_scene_out_of_memory(p);
        if ((st = sam_profile_from_spec(spec, &scene->profile, &perr)) != SAM_OK)
            return sam_json_fail(&p->json, st, "material", "%s", perr.message);
        return SAM_OK;
    }
    char *abs = sam_scene_absolute_path(p->base_dir, spec);
    if (!abs)
        return sam_scene_out_of_memory(p);
    struct stat sb;
    if (stat(abs, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        char list[256] = "";
        size_t len = 0;
        for (size_t i = 0; i < sam_profile_preset_count() && len < sizeof list; ++i)
            len += (size_t)snprintf(list + len, sizeof list - len, "%s%s", i ? ", " : "",
                                    sam_profile_preset_name(i));
        st = sam_json_fail(&p->json, SAM_ERR_IO, "material",
                           "\"%.60s\" is neither a preset (%s) nor a profile file (not found: %s)", spec,
                           list, abs);
        free(abs);
        return st;
    }
    scene->material = abs;
    if ((st = sam_profile_from_spec(abs, &scene->profile, &perr)) != SAM_OK)
        return sam_json_fail(&p->json, st, "material", "%s", perr.message);
    return SAM_OK;
}

static sam_status parse_scale(const sam_scene_parser *p, const cJSON *item, sam_scene *scene)
{
    static const char *const keys[] = {"mm_per_unit", "size_mm"};
    if (!cJSON_IsObject(item))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "scale",
                             "expected {\"mm_per_unit\": x} or {\"size_mm\": x}, found %s",
                             SAM_JSON_DESCRIBE(item));
    sam_status st = sam_json_check_keys(&p->json, item, "scale", keys, COUNT_OF(keys));
    if (st != SAM_OK)
        return st;
    const cJSON *mm = cJSON_GetObjectItemCaseSensitive(item, "mm_per_unit");
    const cJSON *size = cJSON_GetObjectItemCaseSensitive(item, "size_mm");
    if ((mm != NULL) == (size != NULL))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "scale",
                             "expected exactly one of mm_per_unit and size_mm, found %s",
                             mm ? "both" : "neither");
    scene->scale_kind = mm ? SAM_SCALE_MM_PER_UNIT : SAM_SCALE_SIZE_MM;
    return sam_json_positive(&p->json, mm ? mm : size, mm ? "scale.mm_per_unit" : "scale.size_mm",
                             &scene->scale_value);
}

static sam_status parse_camera(const sam_scene_parser *p, const cJSON *item, sam_scene *scene)
{
    static const char *const keys[] = {"position", "target", "up", "fov_deg", "near", "far"};
    sam_camera *cam = &scene->camera;
    if (!cJSON_IsObject(item))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "camera", "expected an object, found %s",
                             SAM_JSON_DESCRIBE(item));
    sam_status st = sam_json_check_keys(&p->json, item, "camera", keys, COUNT_OF(keys));
    if (st != SAM_OK)
        return st;
    const cJSON *v;
    if (!(v = cJSON_GetObjectItemCaseSensitive(item, "position")))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "camera.position", "missing");
    if ((st = sam_json_vec3(&p->json, v, "camera.position", 0, cam->position)) != SAM_OK)
        return st;
    if (!(v = cJSON_GetObjectItemCaseSensitive(item, "target")))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "camera.target", "missing");
    if ((st = sam_json_vec3(&p->json, v, "camera.target", 0, cam->target)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "up")) &&
        (st = sam_scene_get_direction(p, v, "camera.up", cam->up)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "fov_deg")) &&
        (st = sam_json_float(&p->json, v, "camera.fov_deg", 0.0, 1, 180.0, 1, "in (0, 180)", &cam->fov_deg)) !=
            SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "near")) &&
        (st = sam_json_positive(&p->json, v, "camera.near", &cam->near_plane)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "far")) &&
        (st = sam_json_positive(&p->json, v, "camera.far", &cam->far_plane)) != SAM_OK)
        return st;
    if (cam->near_plane > 0.0f && cam->far_plane > 0.0f && !(cam->far_plane > cam->near_plane))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "camera.far",
                             "expected a number greater than near (%g), found %g", cam->near_plane,
                             cam->far_plane);

    double view[3], scale = 1.0;
    for (int k = 0; k < 3; ++k) {
        view[k] = (double)cam->target[k] - cam->position[k];
        scale = fmax(scale, fmax(fabs(cam->target[k]), fabs(cam->position[k])));
    }
    double dist = sam_scene_length3(view);
    if (!(dist > 1e-6 * scale))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "camera.target",
                             "equals camera.position [%g, %g, %g]: no view direction", cam->position[0],
                             cam->position[1], cam->position[2]);
    double cross[3] = {cam->up[1] * view[2] - cam->up[2] * view[1],
                       cam->up[2] * view[0] - cam->up[0] * view[2],
                       cam->up[0] * view[1] - cam->up[1] * view[0]};
    /* sin of the angle between up and the view direction: ~0.06 degrees. */
    if (!(sam_scene_length3(cross) / dist > 1e-3))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "camera.up",
                             "[%g, %g, %g] is parallel to the view direction [%g, %g, %g]", cam->up[0],
                             cam->up[1], cam->up[2], view[0] / dist, view[1] / dist, view[2] / dist);
    scene->has_camera = 1;
    return SAM_OK;
}

static sam_status parse_resolution(const sam_scene_parser *p, const cJSON *item, sam_scene *scene)
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 2)
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "resolution", "expected [width, height], found %s",
                             SAM_JSON_DESCRIBE(item));
    uint32_t *out[2] = {&scene->width, &scene->height};
    int i = 0;
    for (const cJSON *e = item->child; e; e = e->next, ++i) {
        char at[32];
        sam_json_index_path(at, sizeof at, "resolution", i);
        sam_status st = sam_json_uint(&p->json, e, at, 1, SAM_SCENE_MAX_RESOLUTION, 0, out[i]);
        if (st != SAM_OK)
            return st;
    }
    return SAM_OK;
}

static sam_status parse_screen_space(const sam_scene_parser *p, const cJSON *item,
                                     sam_diffusion_options *options)
{
    static const char *const keys[] = {"kernel", "samples"};
    if (!cJSON_IsObject(item))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "screen_space", "expected an object, found %s",
                             SAM_JSON_DESCRIBE(item));
    sam_status st = sam_json_check_keys(&p->json, item, "screen_space", keys, COUNT_OF(keys));
    if (st != SAM_OK)
        return st;
    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "kernel"))) {
        int e = 0;
        if ((st = sam_json_enum(&p->json, v, "screen_space.kernel", "kernel", sss_kernel_names,
                                COUNT_OF(sss_kernel_names), &e)) != SAM_OK)
            return st;
        options->sss_kernel = (sam_sss_kernel)e;
    }
    /* Odd: the kernel has a centre tap and as many on each side. */
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "samples")) &&
        (st = sam_json_uint(&p->json, v, "screen_space.samples", 9, 33, 1, &options->sss_samples)) != SAM_OK)
        return st;
    return SAM_OK;
}

static sam_status parse_texture_space(const sam_scene_parser *p, const cJSON *item,
                                      sam_diffusion_options *options)
{
    static const char *const keys[] = {"atlas_size", "culled", "depth_sized", "clipped",
                                       "texels_per_pixel"};
    if (!cJSON_IsObject(item))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "texture_space", "expected an object, found %s",
                             SAM_JSON_DESCRIBE(item));
    sam_status st = sam_json_check_keys(&p->json, item, "texture_space", keys, COUNT_OF(keys));
    if (st != SAM_OK)
        return st;
    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "atlas_size")) &&
        (st = sam_json_uint(&p->json, v, "texture_space.atlas_size", 64, 4096, 0, &options->atlas_size)) !=
            SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "culled")) &&
        (st = sam_json_bool(&p->json, v, "texture_space.culled", &options->culled)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "depth_sized")) &&
        (st = sam_json_bool(&p->json, v, "texture_space.depth_sized", &options->depth_sized)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "clipped")) &&
        (st = sam_json_bool(&p->json, v, "texture_space.clipped", &options->clipped)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "texels_per_pixel")) &&
        (st = sam_json_float(&p->json, v, "texture_space.texels_per_pixel", 0.0, 1, 16.0, 0, "in (0, 16]",
                             &options->texels_per_pixel)) != SAM_OK)
        return st;
    return SAM_OK;
}

static sam_status parse_root(const sam_scene_parser *p, const cJSON *root, sam_scene *scene)
{
    static const char *const keys[] = {"mesh",         "sam",        "material",  "scale",
                                       "albedo",       "albedo_map", "lights",    "environment",
                                       "camera",       "resolution", "technique", "diffusion",
                                       "screen_space", "texture_space", "tonemap", "exposure",
                                       "deformers",    "keyframes",  "samples_per_vertex", "vertex_colors"};
    if (!cJSON_IsObject(root))
        return sam_fail(p->json.err, SAM_ERR_FORMAT, "%s: expected a JSON object, found %s", p->json.name,
                        SAM_JSON_DESCRIBE(root));
    sam_status st = sam_json_check_keys(&p->json, root, "", keys, COUNT_OF(keys));
    if (st != SAM_OK)
        return st;

    const cJSON *mesh = cJSON_GetObjectItemCaseSensitive(root, "mesh");
    const cJSON *sam = cJSON_GetObjectItemCaseSensitive(root, "sam");
    if (!mesh && !sam)
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "mesh", "missing (give \"mesh\" or \"sam\")");
    if (mesh && (st = sam_scene_get_file(p, mesh, "mesh", &scene->mesh_path)) != SAM_OK)
        return st;
    if (sam && (st = sam_scene_get_file(p, sam, "sam", &scene->sam_path)) != SAM_OK)
        return st;
    /* Each key's file goes to its own reader: say so here, where sam_info
     * sees it too, not when the wrong reader fails. */
    if (mesh && !sam_mesh_is_mesh_path(scene->mesh_path))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "mesh", "%s is %s", scene->mesh_path,
                             sam_path_has_extension(scene->mesh_path, ".sam")
                                 ? "a .sam map; give it as \"sam\""
                                 : "not a mesh file (.obj, .ply, .off, .stl, .gltf or .glb)");
    if (sam && !sam_path_has_extension(scene->sam_path, ".sam"))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "sam", "%s is not a .sam map%s", scene->sam_path,
                             sam_mesh_is_mesh_path(scene->sam_path) ? "; give a mesh as \"mesh\"" : "");

    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "material"))) {
        if ((st = parse_material(p, v, scene)) != SAM_OK)
            return st;
    } else if (mesh && !sam) {
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "material",
                             "missing (required with \"mesh\" unless \"sam\" names its map)");
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "scale"))) {
        if ((st = parse_scale(p, v, scene)) != SAM_OK)
            return st;
    } else if (mesh && !sam) {
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "scale",
                             "missing (required with \"mesh\" unless \"sam\" names its map: "
                             "{\"mm_per_unit\": x} or {\"size_mm\": x})");
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "albedo"))) {
        if ((st = sam_json_vec3(&p->json, v, "albedo", 1, scene->albedo)) != SAM_OK)
            return st;
        for (int k = 0; k < 3; ++k) {
            if (scene->albedo[k] > 1.0f)
                return sam_json_fail(&p->json, SAM_ERR_FORMAT, "albedo", "expected values in [0, 1], found "
                                     "albedo[%d] = %g", k, scene->albedo[k]);
        }
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "albedo_map")) &&
        (st = sam_scene_get_file(p, v, "albedo_map", &scene->albedo_map)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "vertex_colors")) &&
        (st = sam_json_bool(&p->json, v, "vertex_colors", &scene->vertex_colors)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "lights")) &&
        (st = sam_scene_parse_lights(p, v, scene)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "environment")) &&
        (st = sam_scene_parse_environment(p, v, scene)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "camera")) &&
        (st = parse_camera(p, v, scene)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "resolution")) &&
        (st = parse_resolution(p, v, scene)) != SAM_OK)
        return st;
    int e = 0;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "technique"))) {
        if ((st = sam_json_enum(&p->json, v, "technique", "technique", technique_names,
                                COUNT_OF(technique_names), &e)) != SAM_OK)
            return st;
        scene->technique = (sam_technique)e;
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "samples_per_vertex")) &&
        (st = sam_json_uint(&p->json, v, "samples_per_vertex", 0, 64, 0, &scene->samples_per_vertex)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "diffusion"))) {
        if ((st = sam_json_enum(&p->json, v, "diffusion", "diffusion", diffusion_names,
                                COUNT_OF(diffusion_names), &e)) != SAM_OK)
            return st;
        scene->diffusion = (sam_diffusion)e;
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "screen_space")) &&
        (st = parse_screen_space(p, v, &scene->diffusion_options)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "texture_space")) &&
        (st = parse_texture_space(p, v, &scene->diffusion_options)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "tonemap"))) {
        if ((st = sam_json_enum(&p->json, v, "tonemap", "tonemap", tonemap_names, COUNT_OF(tonemap_names),
                                &e)) != SAM_OK)
            return st;
        scene->tonemap = (sam_tonemap)e;
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "exposure")) &&
        (st = sam_json_float(&p->json, v, "exposure", -32.0, 0, 32.0, 0, "in [-32, 32]", &scene->exposure)) !=
            SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "deformers")) &&
        (st = sam_scene_parse_deformers(p, v, scene)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "keyframes")) &&
        (st = sam_scene_parse_keyframes(p, v, scene)) != SAM_OK)
        return st;
    return SAM_OK;
}

/* ------------------------------------------------------------------------ */
/* Text                                                                      */

sam_status sam_scene_parse(const char *text, size_t size, const char *base_dir, const char *name,
                           sam_scene *scene, sam_error *err)
{
    if (!scene)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene parse: NULL scene");
    sam_scene_init(scene);
    sam_scene_parser p = {{name ? name : "scene", err}, base_dir};
    if (!text)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: NULL text", p.json.name);

    size_t first = 0;
    while (first < size && text[first] && strchr(" \t\r\n", text[first]))
        ++first;
    if (first == size)
        return sam_fail(err, SAM_ERR_FORMAT, "%s: empty scene (no JSON object)", p.json.name);

    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, size, &end, 0);
    if (!root) {
        size_t offset = end && end >= text ? (size_t)(end - text) : 0;
        if (offset > size)
            offset = size;
        size_t line, column;
        if (sam_json_too_deep(text, size)) {
            sam_json_line_column(text, offset, &line, &column);
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s: line %zu, column %zu: objects and arrays nest deeper than %d levels",
                            p.json.name, line, column, CJSON_NESTING_LIMIT);
        }
        if (offset >= size || sam_json_ends_early(text, size)) {
            sam_json_line_column(text, size, &line, &column);
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s: line %zu, column %zu: the JSON text ends before its value "
                            "is complete (truncated?)",
                            p.json.name, line, column);
        }
        /* cJSON stops on the blank after the last good token: show the
         * text that follows it, and name the most common slip. */
        size_t at = offset, before = offset;
        while (at < size && strchr(" \t\r\n", text[at]))
            ++at;
        while (before > 0 && strchr(" \t\r\n", text[before - 1]))
            --before;
        if (before > 0 && text[before - 1] == ',' && at < size && (text[at] == '}' || text[at] == ']')) {
            sam_json_line_column(text, before - 1, &line, &column);
            return sam_fail(err, SAM_ERR_FORMAT, "%s: line %zu, column %zu: a comma before \"%c\" (JSON allows "
                            "none after the last item)", p.json.name, line, column, text[at]);
        }
        sam_json_line_column(text, at, &line, &column);
        char near[24];
        size_t n = 0;
        for (size_t i = at; i < size && n < 20 && text[i] != '\n'; ++i)
            near[n++] = (text[i] >= 32 && text[i] < 127) ? text[i] : '?';
        near[n] = 0;
        return sam_fail(err, SAM_ERR_FORMAT, "%s: line %zu, column %zu: JSON syntax error at \"%s\"",
                        p.json.name, line, column, near);
    }
    size_t after = end ? (size_t)(end - text) : size;
    while (after < size && text[after] && strchr(" \t\r\n", text[after]))
        ++after;
    if (after < size) {
        cJSON_Delete(root);
        size_t line, column;
        sam_json_line_column(text, after, &line, &column);
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: line %zu, column %zu: unexpected text after the JSON object", p.json.name,
                        line, column);
    }
    sam_status st = parse_root(&p, root, scene);
    cJSON_Delete(root);
    if (st != SAM_OK)
        sam_scene_destroy(scene);
    return st;
}

sam_status sam_scene_load(const char *path, sam_scene *scene, sam_error *err)
{
    if (!path || !scene)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene load: NULL %s",
                        path ? "scene" : "path");
    sam_scene_init(scene);
    uint8_t *data;
    size_t size;
    sam_status st = sam_read_file(path, &data, &size, err);
    if (st != SAM_OK)
        return st;
    /* Relative references are relative to the scene file's directory. */
    const char *slash = strrchr(path, '/');
    char *dir = NULL;
    if (slash) {
        size_t n = slash == path ? 1 : (size_t)(slash - path);
        dir = malloc(n + 1);
        if (!dir) {
            free(data);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
        }
        memcpy(dir, path, n);
        dir[n] = 0;
    }
    st = sam_scene_parse((const char *)data, size, dir, path, scene, err);
    free(dir);
    free(data);
    return st;
}
