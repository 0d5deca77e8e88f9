#define _POSIX_C_SOURCE 200809L
#include "sam/sam_scene.h"
#include "sam/sam_json.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#define PI_D 3.14159265358979323846

/* ------------------------------------------------------------------------ */
/* Names                                                                     */

static const char *const light_type_names[] = {"point", "spot", "directional", "area"};
static const char *const technique_names[] = {"sam", "none", "tsm", "transmittance"};
static const char *const diffusion_names[] = {"screen", "texture", "preintegrated", "none"};
static const char *const tonemap_names[] = {"aces", "reinhard"};
static const char *const sss_kernel_names[] = {"fit2d", "marginal", "eq1"};
#define COUNT_OF(a) (sizeof(a) / sizeof((a)[0]))

static const char *name_at(const char *const *names, size_t count, int value)
{
    return value >= 0 && (size_t)value < count ? names[value] : "unknown";
}

const char *sam_light_type_name(sam_light_type type)
{
    return name_at(light_type_names, COUNT_OF(light_type_names), (int)type);
}

const char *sam_technique_name(sam_technique technique)
{
    return name_at(technique_names, COUNT_OF(technique_names), (int)technique);
}

const char *sam_diffusion_name(sam_diffusion diffusion)
{
    return name_at(diffusion_names, COUNT_OF(diffusion_names), (int)diffusion);
}

const char *sam_tonemap_name(sam_tonemap tonemap)
{
    return name_at(tonemap_names, COUNT_OF(tonemap_names), (int)tonemap);
}

const char *sam_sss_kernel_name(sam_sss_kernel kernel)
{
    return name_at(sss_kernel_names, COUNT_OF(sss_kernel_names), (int)kernel);
}

/* ------------------------------------------------------------------------ */
/* Scene lifetime                                                            */

void sam_scene_init(sam_scene *scene)
{
    if (!scene)
        return;
    memset(scene, 0, sizeof *scene);
    scene->scale_kind = SAM_SCALE_FROM_SAM;
    scene->albedo[0] = scene->albedo[1] = scene->albedo[2] = 0.8f;
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
/* The current directory in a new malloc'd string, or NULL. */
static char *current_dir(void)
{
    for (size_t n = 256; n <= (1u << 20); n *= 2) {
        char *buf = malloc(n);
        if (!buf)
            return NULL;
        if (getcwd(buf, n))
            return buf;
        free(buf);
        if (errno != ERANGE)
            return NULL;
    }
    return NULL;
}

/* Absolute form of `path`: itself when absolute, else joined to `base_dir`
 * (itself made absolute against the current directory; NULL or "" means
 * the current directory). Empty and "." components are dropped; ".." is
 * kept, since resolving it by text would be wrong across symbolic links.
 * Returns a malloc'd string, or NULL when out of memory or the current
 * directory cannot be found. */
static char *absolute_path(const char *base_dir, const char *path)
{
    char *cwd = NULL;
    const char *parts[3] = {NULL, NULL, path};
    if (path[0] != '/') {
        parts[1] = base_dir && base_dir[0] ? base_dir : NULL;
        if (!parts[1] || parts[1][0] != '/') {
            cwd = current_dir();
            if (!cwd)
                return NULL;
            parts[0] = cwd;
        }
    }
    size_t total = 2;
    for (int i = 0; i < 3; ++i)
        total += parts[i] ? strlen(parts[i]) + 1 : 0;
    char *out = malloc(total);
    if (!out) {
        free(cwd);
        return NULL;
    }
    size_t len = 0;
    for (int i = 0; i < 3; ++i) {
        const char *s = parts[i];
        while (s && *s) {
            while (*s == '/')
                ++s;
            const char *end = s;
            while (*end && *end != '/')
                ++end;
            size_t n = (size_t)(end - s);
            if (n > 0 && !(n == 1 && s[0] == '.')) {
                out[len++] = '/';
                memcpy(out + len, s, n);
                len += n;
            }
            s = end;
        }
    }
    if (len == 0)
        out[len++] = '/';
    out[len] = 0;
    free(cwd);
    return out;
}

/* ------------------------------------------------------------------------ */
/* Parser state and messages                                                 */

typedef struct parser {
    sam_json_ctx json;    /* the scene's name and error, for messages */
    const char *base_dir; /* for relative paths; NULL = current directory */
} parser;

static sam_status out_of_memory(const parser *p)
{
    return sam_fail(p->json.err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", p->json.name);
}

/* ------------------------------------------------------------------------ */
/* Typed values                                                              */

static double length3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* Normalises in place. A vector already of unit length within float
 * rounding is kept bit for bit, so a written scene reloads identically. */
static void normalize3(float v[3])
{
    double d[3] = {v[0], v[1], v[2]};
    double len = length3(d);
    if (fabs(len - 1.0) <= 1e-6)
        return;
    for (int k = 0; k < 3; ++k)
        v[k] = (float)(d[k] / len);
}

/* A non-zero vector, normalised. */
static sam_status get_direction(const parser *p, const cJSON *item, const char *path,
                                float out[3])
{
    sam_status st = sam_json_vec3(&p->json, item, path, 0, out);
    if (st != SAM_OK)
        return st;
    double d[3] = {out[0], out[1], out[2]};
    if (!(length3(d) > 1e-12))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, path, "expected a non-zero direction, found [%g, %g, %g]",
                             out[0], out[1], out[2]);
    normalize3(out);
    return SAM_OK;
}

/* Resolves a file reference and checks that it names an existing regular
 * file; on success *out is a malloc'd absolute path. */
static sam_status get_file(const parser *p, const cJSON *item, const char *path, char **out)
{
    const char *s;
    sam_status st = sam_json_string(&p->json, item, path, &s);
    if (st != SAM_OK)
        return st;
    char *abs = absolute_path(p->base_dir, s);
    if (!abs)
        return sam_json_fail(&p->json, SAM_ERR_IO, path, "cannot resolve \"%s\" (current directory unknown)",
                             s);
    struct stat sb;
    if (stat(abs, &sb) != 0) {
        int e = errno;
        st = sam_json_fail(&p->json, SAM_ERR_IO, path, "%s: %s", e == ENOENT ? "file not found" : strerror(e),
                           abs);
        free(abs);
        return st;
    }
    if (!S_ISREG(sb.st_mode)) {
        st = sam_json_fail(&p->json, SAM_ERR_IO, path, "not a regular file: %s", abs);
        free(abs);
        return st;
    }
    *out = abs;
    return SAM_OK;
}

/* ------------------------------------------------------------------------ */
/* Sections                                                                  */

static int is_preset(const char *spec)
{
    for (size_t i = 0; i < sam_profile_preset_count(); ++i) {
        if (strcasecmp(spec, sam_profile_preset_name(i)) == 0)
            return 1;
    }
    return 0;
}

static sam_status parse_material(const parser *p, const cJSON *item, sam_scene *scene)
{
    const char *spec;
    sam_status st = sam_json_string(&p->json, item, "material", &spec);
    if (st != SAM_OK)
        return st;
    sam_error perr;
    if (is_preset(spec)) {
        scene->material = sam_strdup(spec);
        if (!scene->material)
            return out_of_memory(p);
        if ((st = sam_profile_from_spec(spec, &scene->profile, &perr)) != SAM_OK)
            return sam_json_fail(&p->json, st, "material", "%s", perr.message);
        return SAM_OK;
    }
    char *abs = absolute_path(p->base_dir, spec);
    if (!abs)
        return out_of_memory(p);
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

static sam_status parse_scale(const parser *p, const cJSON *item, sam_scene *scene)
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

/* Checks an area light's polygon and derives its normal and area. */
static sam_status check_polygon(const parser *p, const char *path, sam_light *light)
{
    const uint32_t n = light->vertex_count;
    double v[SAM_AREA_LIGHT_MAX_VERTICES][3];
    double centre[3] = {0, 0, 0}, lo[3], hi[3];
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            v[i][k] = light->vertices[i][k];
            centre[k] += v[i][k] / n;
            lo[k] = i ? fmin(lo[k], v[i][k]) : v[i][k];
            hi[k] = i ? fmax(hi[k], v[i][k]) : v[i][k];
        }
    }
    double extent[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    double size = length3(extent);
    char at[300];
    sam_json_key_path(at, sizeof at, path, "vertices");
    /* Newell's method: the normal's length is twice the area, for any
     * planar polygon, and its direction follows the winding. */
    double newell[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; ++i) {
        const double *a = v[i], *b = v[(i + 1) % n];
        newell[0] += (a[1] - b[1]) * (a[2] + b[2]);
        newell[1] += (a[2] - b[2]) * (a[0] + b[0]);
        newell[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    double twice_area = length3(newell);
    if (!(size > 0.0) || !(twice_area > 1e-6 * size * size))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, at,
                             "degenerate polygon: area %g for a size of %g (points coincide or are "
                             "collinear)", twice_area / 2, size);
    double normal[3] = {newell[0] / twice_area, newell[1] / twice_area, newell[2] / twice_area};
    for (uint32_t i = 0; i < n; ++i) {
        double off = (v[i][0] - centre[0]) * normal[0] + (v[i][1] - centre[1]) * normal[1] +
                     (v[i][2] - centre[2]) * normal[2];
        if (fabs(off) > 1e-3 * size)
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at,
                                 "not planar: vertices[%u] is %g from the polygon's plane (tolerance "
                                 "%g)", i, fabs(off), 1e-3 * size);
    }
    for (uint32_t i = 0; i < n; ++i) {
        const double *a = v[i], *b = v[(i + 1) % n];
        double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        if (length3(e) <= 1e-6 * size)
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at, "vertices[%u] and vertices[%u] coincide", i,
                                 (i + 1) % n);
    }
    /* Convex: every corner turns the same way as the winding, and the turns
     * add up to one revolution (a star polygon turns twice). */
    double turning = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double *a = v[(i + n - 1) % n], *b = v[i], *c = v[(i + 1) % n];
        double e0[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e1[3] = {c[0] - b[0], c[1] - b[1], c[2] - b[2]};
        double cross[3] = {e0[1] * e1[2] - e0[2] * e1[1], e0[2] * e1[0] - e0[0] * e1[2],
                           e0[0] * e1[1] - e0[1] * e1[0]};
        double s = cross[0] * normal[0] + cross[1] * normal[1] + cross[2] * normal[2];
        double c_ = e0[0] * e1[0] + e0[1] * e1[1] + e0[2] * e1[2];
        if (s <= 1e-6 * length3(e0) * length3(e1)) {
            if (fabs(s) <= 1e-6 * length3(e0) * length3(e1))
                return sam_json_fail(&p->json, SAM_ERR_FORMAT, at,
                                     "vertices[%u] is collinear with its neighbours", i);
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at, "not convex: the outline turns back at "
                                 "vertices[%u]", i);
        }
        turning += atan2(s, c_);
    }
    if (turning > 2.0 * PI_D + 1e-3)
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, at,
                             "not convex: the outline winds around %.3g times (self-intersecting)",
                             turning / (2.0 * PI_D));
    for (int k = 0; k < 3; ++k)
        light->normal[k] = (float)normal[k];
    light->area = (float)(twice_area / 2);
    return SAM_OK;
}

static sam_status parse_light(const parser *p, const cJSON *item, int index, sam_light *light)
{
    static const char *const point_keys[] = {"type", "position", "color", "intensity", "shadow"};
    static const char *const spot_keys[] = {"type",  "position",        "direction",
                                            "inner_angle_deg", "outer_angle_deg", "color",
                                            "intensity",       "shadow"};
    static const char *const directional_keys[] = {"type", "direction", "color", "intensity",
                                                   "shadow"};
    static const char *const area_keys[] = {"type",      "vertices",  "color",
                                            "intensity", "two_sided", "shadow"};
    char path[64], at[128];
    sam_json_index_path(path, sizeof path, "lights", index);
    int t;
    sam_status st = sam_json_typed_object(&p->json, item, path, "light type", light_type_names,
                                          COUNT_OF(light_type_names), &t);
    if (st != SAM_OK)
        return st;
    light->type = (sam_light_type)t;
    switch (light->type) {
    case SAM_LIGHT_POINT: st = sam_json_check_keys(&p->json, item, path, point_keys, COUNT_OF(point_keys)); break;
    case SAM_LIGHT_SPOT: st = sam_json_check_keys(&p->json, item, path, spot_keys, COUNT_OF(spot_keys)); break;
    case SAM_LIGHT_DIRECTIONAL:
        st = sam_json_check_keys(&p->json, item, path, directional_keys, COUNT_OF(directional_keys));
        break;
    case SAM_LIGHT_AREA: st = sam_json_check_keys(&p->json, item, path, area_keys, COUNT_OF(area_keys)); break;
    }
    if (st != SAM_OK)
        return st;

    light->color[0] = light->color[1] = light->color[2] = 1.0f;
    light->intensity = 1.0f;
    light->shadow = 1;
    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "color")) &&
        (st = sam_json_vec3(&p->json, v, sam_json_key_path(at, sizeof at, path, "color"), 1, light->color)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "intensity")) &&
        (st = sam_json_non_negative(&p->json, v, sam_json_key_path(at, sizeof at, path, "intensity"),
                                    &light->intensity)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "shadow")) &&
        (st = sam_json_bool(&p->json, v, sam_json_key_path(at, sizeof at, path, "shadow"), &light->shadow)) != SAM_OK)
        return st;

    if (light->type == SAM_LIGHT_POINT || light->type == SAM_LIGHT_SPOT) {
        sam_json_key_path(at, sizeof at, path, "position");
        if (!(v = cJSON_GetObjectItemCaseSensitive(item, "position")))
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at, "missing (required for a %s light)",
                                 sam_light_type_name(light->type));
        if ((st = sam_json_vec3(&p->json, v, at, 0, light->position)) != SAM_OK)
            return st;
    }
    if (light->type == SAM_LIGHT_SPOT || light->type == SAM_LIGHT_DIRECTIONAL) {
        sam_json_key_path(at, sizeof at, path, "direction");
        if (!(v = cJSON_GetObjectItemCaseSensitive(item, "direction")))
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at, "missing (required for a %s light)",
                                 sam_light_type_name(light->type));
        if ((st = get_direction(p, v, at, light->direction)) != SAM_OK)
            return st;
    }
    if (light->type == SAM_LIGHT_SPOT) {
        light->outer_angle_deg = 30.0f;
        if ((v = cJSON_GetObjectItemCaseSensitive(item, "outer_angle_deg")) &&
            (st = sam_json_float(&p->json, v, sam_json_key_path(at, sizeof at, path, "outer_angle_deg"), 0.0, 1, 90.0,
                                 1, "in (0, 90)", &light->outer_angle_deg)) != SAM_OK)
            return st;
        light->inner_angle_deg = light->outer_angle_deg * (2.0f / 3.0f);
        sam_json_key_path(at, sizeof at, path, "inner_angle_deg");
        if ((v = cJSON_GetObjectItemCaseSensitive(item, "inner_angle_deg"))) {
            if ((st = sam_json_float(&p->json, v, at, 0.0, 0, 90.0, 1, "in [0, 90)",
                                     &light->inner_angle_deg)) != SAM_OK)
                return st;
            if (light->inner_angle_deg > light->outer_angle_deg)
                return sam_json_fail(&p->json, SAM_ERR_FORMAT, at,
                                     "expected a number <= outer_angle_deg (%g), found %g",
                                     light->outer_angle_deg, light->inner_angle_deg);
        }
    }
    if (light->type == SAM_LIGHT_AREA) {
        sam_json_key_path(at, sizeof at, path, "vertices");
        if (!(v = cJSON_GetObjectItemCaseSensitive(item, "vertices")))
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at, "missing (required for an area light)");
        int count = cJSON_IsArray(v) ? cJSON_GetArraySize(v) : -1;
        if (count < 3 || count > SAM_AREA_LIGHT_MAX_VERTICES)
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at,
                                 "expected an array of 3 to %d points [x, y, z], found %s",
                                 SAM_AREA_LIGHT_MAX_VERTICES, SAM_JSON_DESCRIBE(v));
        light->vertex_count = (uint32_t)count;
        int i = 0;
        for (const cJSON *e = v->child; e; e = e->next, ++i) {
            char vat[160];
            if ((st = sam_json_vec3(&p->json, e, sam_json_index_path(vat, sizeof vat, at, i), 0,
                                    light->vertices[i])) != SAM_OK)
                return st;
        }
        if ((v = cJSON_GetObjectItemCaseSensitive(item, "two_sided")) &&
            (st = sam_json_bool(&p->json, v, sam_json_key_path(at, sizeof at, path, "two_sided"), &light->two_sided)) !=
            SAM_OK)
            return st;
        if ((st = check_polygon(p, path, light)) != SAM_OK)
            return st;
    }
    return SAM_OK;
}

static sam_status parse_lights(const parser *p, const cJSON *item, sam_scene *scene)
{
    if (!cJSON_IsArray(item))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "lights", "expected an array of lights, found %s",
                             SAM_JSON_DESCRIBE(item));
    int count = cJSON_GetArraySize(item);
    if (count > SAM_SCENE_MAX_LIGHTS)
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "lights", "%d lights, more than the limit of %d", count,
                             SAM_SCENE_MAX_LIGHTS);
    if (count == 0)
        return SAM_OK;
    scene->lights = calloc((size_t)count, sizeof *scene->lights);
    if (!scene->lights)
        return out_of_memory(p);
    int i = 0;
    for (const cJSON *e = item->child; e; e = e->next, ++i) {
        sam_status st = parse_light(p, e, i, &scene->lights[i]);
        if (st != SAM_OK)
            return st;
        scene->light_count = (size_t)i + 1;
    }
    return SAM_OK;
}

static sam_status parse_environment(const parser *p, const cJSON *item, sam_scene *scene)
{
    static const char *const keys[] = {"map", "intensity", "rotation_deg"};
    if (!cJSON_IsObject(item))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "environment", "expected an object, found %s",
                             SAM_JSON_DESCRIBE(item));
    sam_status st = sam_json_check_keys(&p->json, item, "environment", keys, COUNT_OF(keys));
    if (st != SAM_OK)
        return st;
    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "intensity")) &&
        (st = sam_json_non_negative(&p->json, v, "environment.intensity", &scene->environment.intensity)) !=
        SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(item, "rotation_deg")) &&
        (st = sam_json_any_float(&p->json, v, "environment.rotation_deg", &scene->environment.rotation_deg)) !=
        SAM_OK)
        return st;
    if (!(v = cJSON_GetObjectItemCaseSensitive(item, "map")))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "environment.map", "missing (an EXR file)");
    return get_file(p, v, "environment.map", &scene->environment.map);
}

static sam_status parse_camera(const parser *p, const cJSON *item, sam_scene *scene)
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
        (st = get_direction(p, v, "camera.up", cam->up)) != SAM_OK)
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
    double dist = length3(view);
    if (!(dist > 1e-6 * scale))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "camera.target",
                             "equals camera.position [%g, %g, %g]: no view direction", cam->position[0],
                             cam->position[1], cam->position[2]);
    double cross[3] = {cam->up[1] * view[2] - cam->up[2] * view[1],
                       cam->up[2] * view[0] - cam->up[0] * view[2],
                       cam->up[0] * view[1] - cam->up[1] * view[0]};
    /* sin of the angle between up and the view direction: ~0.06 degrees. */
    if (!(length3(cross) / dist > 1e-3))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "camera.up",
                             "[%g, %g, %g] is parallel to the view direction [%g, %g, %g]", cam->up[0],
                             cam->up[1], cam->up[2], view[0] / dist, view[1] / dist, view[2] / dist);
    scene->has_camera = 1;
    return SAM_OK;
}

static sam_status parse_resolution(const parser *p, const cJSON *item, sam_scene *scene)
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

static sam_status parse_screen_space(const parser *p, const cJSON *item,
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

static sam_status parse_texture_space(const parser *p, const cJSON *item,
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

/* A deformer's number keys: where each goes, whether it must be given,
 * and its range (0 finite, 1 > 0, 2 >= 0, 3 in (-1, 1)). */
typedef struct deformer_number {
    const char *key;
    size_t offset;
    int required, range;
} deformer_number;

static sam_status get_deformer_number(const parser *p, const cJSON *item, const char *path, int range,
                                      float *out)
{
    switch (range) {
    case 1: return sam_json_positive(&p->json, item, path, out);
    case 2: return sam_json_non_negative(&p->json, item, path, out);
    case 3: return sam_json_float(&p->json, item, path, -1.0, 1, 1.0, 1, "in (-1, 1)", out);
    default: return sam_json_any_float(&p->json, item, path, out);
    }
}

static sam_status parse_deformer(const parser *p, const cJSON *item, int index, sam_deformer *d)
{
#define NUMBER(key, required, range) {#key, offsetof(sam_deformer, key), required, range}
    static const deformer_number numbers[] = {
        NUMBER(angle_deg, 1, 0), NUMBER(length, 1, 1),     NUMBER(amount, 1, 3), NUMBER(amplitude, 1, 0),
        NUMBER(wavelength, 1, 1), NUMBER(speed, 0, 0), NUMBER(period_s, 0, 2)};
#undef NUMBER
    /* Per type: its keys, the first `vectors` of them the vectors after "type". */
    static const char *const bend_keys[] = {"type", "axis", "direction", "center", "angle_deg", "length", "period_s"};
    static const char *const twist_keys[] = {"type", "axis", "center", "angle_deg", "length", "period_s"};
    static const char *const squash_keys[] = {"type", "axis", "center", "amount", "period_s"};
    static const char *const wave_keys[] = {"type",       "axis",  "direction", "amplitude",
                                            "wavelength", "speed", "period_s"};
    static const struct {
        const char *const *keys;
        size_t count;
    } types[] = {{bend_keys, COUNT_OF(bend_keys)},
                 {twist_keys, COUNT_OF(twist_keys)},
                 {squash_keys, COUNT_OF(squash_keys)},
                 {wave_keys, COUNT_OF(wave_keys)}};
    const char *names[COUNT_OF(types)];
    for (size_t i = 0; i < COUNT_OF(types); ++i)
        names[i] = sam_deformer_type_name((sam_deformer_type)i);
    char path[64], at[128];
    sam_json_index_path(path, sizeof path, "deformers", index);
    int t;
    sam_status st = sam_json_typed_object(&p->json, item, path, "deformer type", names, COUNT_OF(names), &t);
    if (st != SAM_OK || (st = sam_json_check_keys(&p->json, item, path, types[t].keys, types[t].count)) != SAM_OK)
        return st;
    memset(d, 0, sizeof *d);
    d->type = (sam_deformer_type)t;
    const char *const *keys = types[t].keys;
    for (size_t k = 1; k < types[t].count; ++k) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(item, keys[k]);
        sam_json_key_path(at, sizeof at, path, keys[k]);
        if (!strcmp(keys[k], "axis") || !strcmp(keys[k], "direction") || !strcmp(keys[k], "center")) {
            int center = !strcmp(keys[k], "center");
            float *out = center ? d->center : !strcmp(keys[k], "axis") ? d->axis : d->direction;
            if (!v && !center)
                return sam_json_fail(&p->json, SAM_ERR_FORMAT, at, "missing (required for a %s deformer)", names[t]);
            if (v && (st = center ? sam_json_vec3(&p->json, v, at, 0, out) : get_direction(p, v, at, out)) != SAM_OK)
                return st;
            continue;
        }
        size_t n = 0;
        while (strcmp(numbers[n].key, keys[k]) != 0)
            ++n;
        if (!v && numbers[n].required)
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at, "missing (required for a %s deformer)", names[t]);
        if (v && (st = get_deformer_number(p, v, at, numbers[n].range,
                                           (float *)((char *)d + numbers[n].offset))) != SAM_OK)
            return st;
    }
    if (d->type == SAM_DEFORM_BEND) {
        double a[3] = {d->axis[0], d->axis[1], d->axis[2]}, n[3] = {d->direction[0], d->direction[1], d->direction[2]};
        double cross[3] = {a[1] * n[2] - a[2] * n[1], a[2] * n[0] - a[0] * n[2], a[0] * n[1] - a[1] * n[0]};
        if (!(length3(cross) > 1e-3))
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, sam_json_key_path(at, sizeof at, path, "direction"),
                                 "[%g, %g, %g] is parallel to the axis [%g, %g, %g]", d->direction[0], d->direction[1],
                                 d->direction[2], d->axis[0], d->axis[1], d->axis[2]);
    }
    return SAM_OK;
}

static sam_status parse_deformers(const parser *p, const cJSON *item, sam_scene *scene)
{
    if (!cJSON_IsArray(item))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "deformers", "expected an array of deformers, found %s",
                             SAM_JSON_DESCRIBE(item));
    int count = cJSON_GetArraySize(item);
    if (count > SAM_DEFORM_MAX)
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "deformers", "%d deformers, more than the limit of %d", count,
                             SAM_DEFORM_MAX);
    int i = 0;
    for (const cJSON *e = item->child; e; e = e->next, ++i) {
        sam_status st = parse_deformer(p, e, i, &scene->deformers[i]);
        if (st != SAM_OK)
            return st;
        scene->deformer_count = (size_t)i + 1;
    }
    return SAM_OK;
}

static sam_status parse_keyframes(const parser *p, const cJSON *item, sam_scene *scene)
{
    static const char *const keys[] = {"mesh", "time_s"};
    if (!cJSON_IsArray(item))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "keyframes", "expected an array of keyframes, found %s",
                             SAM_JSON_DESCRIBE(item));
    int count = cJSON_GetArraySize(item);
    if (count == 0)
        return SAM_OK;
    scene->keyframes = calloc((size_t)count, sizeof *scene->keyframes);
    if (!scene->keyframes)
        return out_of_memory(p);
    int i = 0;
    for (const cJSON *e = item->child; e; e = e->next, ++i) {
        char path[64], at[96];
        sam_json_index_path(path, sizeof path, "keyframes", i);
        if (!cJSON_IsObject(e))
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, path, "expected an object, found %s",
                                 SAM_JSON_DESCRIBE(e));
        sam_status st = sam_json_check_keys(&p->json, e, path, keys, COUNT_OF(keys));
        if (st != SAM_OK)
            return st;
        sam_keyframe *k = &scene->keyframes[i];
        for (size_t n = 0; n < COUNT_OF(keys); ++n) {
            if (!cJSON_GetObjectItemCaseSensitive(e, keys[n]))
                return sam_json_fail(&p->json, SAM_ERR_FORMAT, sam_json_key_path(at, sizeof at, path, keys[n]),
                                     "missing");
        }
        if ((st = sam_json_positive(&p->json, cJSON_GetObjectItemCaseSensitive(e, "time_s"),
                                    sam_json_key_path(at, sizeof at, path, "time_s"), &k->time_s)) != SAM_OK)
            return st;
        if (i > 0 && k->time_s <= k[-1].time_s)
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, at,
                                 "expected a time after keyframes[%d].time_s = %g, found %g", i - 1, k[-1].time_s,
                                 k->time_s);
        if ((st = get_file(p, cJSON_GetObjectItemCaseSensitive(e, "mesh"),
                           sam_json_key_path(at, sizeof at, path, "mesh"), &k->mesh)) != SAM_OK)
            return st;
        scene->keyframe_count = (size_t)i + 1;
    }
    return SAM_OK;
}

static sam_status parse_root(const parser *p, const cJSON *root, sam_scene *scene)
{
    static const char *const keys[] = {"mesh",         "sam",        "material",  "scale",
                                       "albedo",       "albedo_map", "lights",    "environment",
                                       "camera",       "resolution", "technique", "diffusion",
                                       "screen_space", "texture_space", "tonemap", "exposure",
                                       "deformers",    "keyframes",  "samples_per_vertex"};
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
    if (mesh && (st = get_file(p, mesh, "mesh", &scene->mesh_path)) != SAM_OK)
        return st;
    if (sam && (st = get_file(p, sam, "sam", &scene->sam_path)) != SAM_OK)
        return st;

    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "material"))) {
        if ((st = parse_material(p, v, scene)) != SAM_OK)
            return st;
    } else if (mesh) {
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "material", "missing (required with \"mesh\")");
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "scale"))) {
        if ((st = parse_scale(p, v, scene)) != SAM_OK)
            return st;
    } else if (mesh) {
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, "scale",
                             "missing (required with \"mesh\": {\"mm_per_unit\": x} or "
                             "{\"size_mm\": x})");
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
        (st = get_file(p, v, "albedo_map", &scene->albedo_map)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "lights")) &&
        (st = parse_lights(p, v, scene)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "environment")) &&
        (st = parse_environment(p, v, scene)) != SAM_OK)
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
        (st = parse_deformers(p, v, scene)) != SAM_OK)
        return st;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "keyframes")) &&
        (st = parse_keyframes(p, v, scene)) != SAM_OK)
        return st;
    return SAM_OK;
}

sam_status sam_scene_parse(const char *text, size_t size, const char *base_dir, const char *name,
                           sam_scene *scene, sam_error *err)
{
    if (!scene)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene parse: NULL scene");
    sam_scene_init(scene);
    parser p = {{name ? name : "scene", err}, base_dir};
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
        if (offset >= size || sam_json_ends_early(text, size)) {
            sam_json_line_column(text, size, &line, &column);
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s: line %zu, column %zu: the JSON text ends before its value "
                            "is complete (truncated?)",
                            p.json.name, line, column);
        }
        sam_json_line_column(text, offset, &line, &column);
        char near[24];
        size_t n = 0;
        for (size_t i = offset; i < size && n < 20 && text[i] != '\n'; ++i)
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

/* ------------------------------------------------------------------------ */
/* Writing                                                                   */

/* Shortest decimal text that reads back (as the parser reads it: double,
 * then float) to exactly `v`. Non-finite values become null, which the
 * parse-back check then reports with the key's path. */
static cJSON *number_item(float v)
{
    char buf[40];
    if (!isfinite(v))
        return cJSON_CreateNull();
    for (int digits = 6; digits <= 9; ++digits) {
        snprintf(buf, sizeof buf, "%.*g", digits, (double)v);
        if ((float)strtod(buf, NULL) == v)
            break;
    }
    return cJSON_CreateRaw(buf);
}

/* cJSON's add functions return NULL on failure; the build tracks that in
 * one flag instead of testing every call. */
typedef struct builder {
    int failed;
} builder;

static void add(builder *b, cJSON *object, const char *key, cJSON *item)
{
    if (!item || !object || !cJSON_AddItemToObject(object, key, item)) {
        cJSON_Delete(item);
        b->failed = 1;
    }
}

static void append(builder *b, cJSON *array, cJSON *item)
{
    if (!item || !array || !cJSON_AddItemToArray(array, item)) {
        cJSON_Delete(item);
        b->failed = 1;
    }
}

static cJSON *vec3_item(builder *b, const float v[3])
{
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; k < 3; ++k)
        append(b, a, number_item(v[k]));
    return a;
}

static void add_path(builder *b, cJSON *object, const char *key, const char *path)
{
    char *abs = absolute_path(NULL, path);
    if (!abs) {
        b->failed = 1;
        return;
    }
    add(b, object, key, cJSON_CreateString(abs));
    free(abs);
}

static cJSON *light_item(builder *b, const sam_light *l)
{
    cJSON *o = cJSON_CreateObject();
    add(b, o, "type", cJSON_CreateString(sam_light_type_name(l->type)));
    if (l->type == SAM_LIGHT_POINT || l->type == SAM_LIGHT_SPOT)
        add(b, o, "position", vec3_item(b, l->position));
    if (l->type == SAM_LIGHT_SPOT || l->type == SAM_LIGHT_DIRECTIONAL)
        add(b, o, "direction", vec3_item(b, l->direction));
    if (l->type == SAM_LIGHT_SPOT) {
        add(b, o, "inner_angle_deg", number_item(l->inner_angle_deg));
        add(b, o, "outer_angle_deg", number_item(l->outer_angle_deg));
    }
    if (l->type == SAM_LIGHT_AREA) {
        cJSON *vertices = cJSON_CreateArray();
        for (uint32_t i = 0; i < l->vertex_count && i < SAM_AREA_LIGHT_MAX_VERTICES; ++i)
            append(b, vertices, vec3_item(b, l->vertices[i]));
        add(b, o, "vertices", vertices);
        add(b, o, "two_sided", cJSON_CreateBool(l->two_sided));
    }
    add(b, o, "color", vec3_item(b, l->color));
    add(b, o, "intensity", number_item(l->intensity));
    add(b, o, "shadow", cJSON_CreateBool(l->shadow));
    return o;
}

static cJSON *deformer_item(builder *b, const sam_deformer *d)
{
    cJSON *o = cJSON_CreateObject();
    add(b, o, "type", cJSON_CreateString(sam_deformer_type_name(d->type)));
    add(b, o, "axis", vec3_item(b, d->axis));
    if (d->type == SAM_DEFORM_BEND || d->type == SAM_DEFORM_WAVE)
        add(b, o, "direction", vec3_item(b, d->direction));
    if (d->type != SAM_DEFORM_WAVE)
        add(b, o, "center", vec3_item(b, d->center));
    if (d->type == SAM_DEFORM_BEND || d->type == SAM_DEFORM_TWIST) {
        add(b, o, "angle_deg", number_item(d->angle_deg));
        add(b, o, "length", number_item(d->length));
    }
    if (d->type == SAM_DEFORM_SQUASH)
        add(b, o, "amount", number_item(d->amount));
    if (d->type == SAM_DEFORM_WAVE) {
        add(b, o, "amplitude", number_item(d->amplitude));
        add(b, o, "wavelength", number_item(d->wavelength));
        add(b, o, "speed", number_item(d->speed));
    }
    add(b, o, "period_s", number_item(d->period_s));
    return o;
}

static cJSON *scene_item(builder *b, const sam_scene *s)
{
    cJSON *root = cJSON_CreateObject();
    if (s->mesh_path)
        add_path(b, root, "mesh", s->mesh_path);
    if (s->sam_path)
        add_path(b, root, "sam", s->sam_path);
    if (s->material) {
        if (is_preset(s->material))
            add(b, root, "material", cJSON_CreateString(s->material));
        else
            add_path(b, root, "material", s->material);
    }
    if (s->scale_kind != SAM_SCALE_FROM_SAM) {
        cJSON *scale = cJSON_CreateObject();
        add(b, scale, s->scale_kind == SAM_SCALE_MM_PER_UNIT ? "mm_per_unit" : "size_mm",
            number_item(s->scale_value));
        add(b, root, "scale", scale);
    }
    add(b, root, "albedo", vec3_item(b, s->albedo));
    if (s->albedo_map)
        add_path(b, root, "albedo_map", s->albedo_map);
    cJSON *lights = cJSON_CreateArray();
    for (size_t i = 0; i < s->light_count; ++i)
        append(b, lights, light_item(b, &s->lights[i]));
    add(b, root, "lights", lights);
    if (s->environment.map) {
        cJSON *env = cJSON_CreateObject();
        add_path(b, env, "map", s->environment.map);
        add(b, env, "intensity", number_item(s->environment.intensity));
        add(b, env, "rotation_deg", number_item(s->environment.rotation_deg));
        add(b, root, "environment", env);
    }
    if (s->has_camera) {
        const sam_camera *c = &s->camera;
        cJSON *cam = cJSON_CreateObject();
        add(b, cam, "position", vec3_item(b, c->position));
        add(b, cam, "target", vec3_item(b, c->target));
        add(b, cam, "up", vec3_item(b, c->up));
        add(b, cam, "fov_deg", number_item(c->fov_deg));
        /* 0 means automatic, which is the key's absence. */
        if (c->near_plane != 0.0f)
            add(b, cam, "near", number_item(c->near_plane));
        if (c->far_plane != 0.0f)
            add(b, cam, "far", number_item(c->far_plane));
        add(b, root, "camera", cam);
    }
    cJSON *res = cJSON_CreateArray();
    append(b, res, cJSON_CreateNumber(s->width));
    append(b, res, cJSON_CreateNumber(s->height));
    add(b, root, "resolution", res);
    add(b, root, "technique", cJSON_CreateString(sam_technique_name(s->technique)));
    add(b, root, "samples_per_vertex", cJSON_CreateNumber(s->samples_per_vertex));
    add(b, root, "diffusion", cJSON_CreateString(sam_diffusion_name(s->diffusion)));
    const sam_diffusion_options *o = &s->diffusion_options;
    cJSON *screen = cJSON_CreateObject();
    add(b, screen, "kernel", cJSON_CreateString(sam_sss_kernel_name(o->sss_kernel)));
    add(b, screen, "samples", cJSON_CreateNumber(o->sss_samples));
    add(b, root, "screen_space", screen);
    cJSON *texture = cJSON_CreateObject();
    add(b, texture, "atlas_size", cJSON_CreateNumber(o->atlas_size));
    add(b, texture, "culled", cJSON_CreateBool(o->culled));
    add(b, texture, "depth_sized", cJSON_CreateBool(o->depth_sized));
    add(b, texture, "clipped", cJSON_CreateBool(o->clipped));
    add(b, texture, "texels_per_pixel", number_item(o->texels_per_pixel));
    add(b, root, "texture_space", texture);
    add(b, root, "tonemap", cJSON_CreateString(sam_tonemap_name(s->tonemap)));
    add(b, root, "exposure", number_item(s->exposure));
    cJSON *deformers = cJSON_CreateArray();
    for (size_t i = 0; i < s->deformer_count && i < SAM_DEFORM_MAX; ++i)
        append(b, deformers, deformer_item(b, &s->deformers[i]));
    add(b, root, "deformers", deformers);
    cJSON *keyframes = cJSON_CreateArray();
    for (size_t i = 0; i < s->keyframe_count; ++i) {
        cJSON *k = cJSON_CreateObject();
        add_path(b, k, "mesh", s->keyframes[i].mesh);
        add(b, k, "time_s", number_item(s->keyframes[i].time_s));
        append(b, keyframes, k);
    }
    add(b, root, "keyframes", keyframes);
    return root;
}

sam_status sam_scene_write(const char *path, const sam_scene *scene, sam_error *err)
{
    if (!path || !path[0] || !scene)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene write: NULL %s",
                        scene ? "path" : "scene");
    builder b = {0};
    cJSON *root = scene_item(&b, scene);
    char *text = root && !b.failed ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory building the scene", path);

    /* Parsing the text back validates the scene with the loader's own rules
     * and messages (an unknown enum value, a light out of range, a missing
     * file), so a file that is written always loads. */
    size_t len = strlen(text);
    sam_scene check;
    sam_status st = sam_scene_parse(text, len, NULL, path, &check, err);
    sam_scene_destroy(&check);
    if (st != SAM_OK) {
        cJSON_free(text);
        return st;
    }
    sam_atomic_file file;
    if ((st = sam_atomic_open(&file, path, err)) != SAM_OK) {
        cJSON_free(text);
        return st;
    }
    int ok = fwrite(text, 1, len, file.fp) == len && fputc('\n', file.fp) != EOF;
    cJSON_free(text);
    if (!ok) {
        int e = errno;
        sam_atomic_abort(&file);
        return sam_fail(err, SAM_ERR_IO, "%s: write failed: %s", path, strerror(e));
    }
    return sam_atomic_commit(&file, err);
}
