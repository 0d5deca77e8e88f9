/*
 * sam_scene_lights: the "lights" and "environment" keys of a scene file
 * (formats in sam_scene.h), area lights' polygons checked and their normal
 * and area derived.
 */
#include "sam_scene_internal.h"

#include <math.h>
#include <stdlib.h>

#define PI_D 3.14159265358979323846

static const char *const light_type_names[] = {"point", "spot", "directional", "area"};

const char *sam_light_type_name(sam_light_type type)
{
    return sam_scene_name_at(light_type_names, COUNT_OF(light_type_names), (int)type);
}

/* Checks an area light's polygon and derives its normal and area. */
static sam_status check_polygon(const sam_scene_parser *p, const char *path, sam_light *light)
{
    const uint32_t n = light->vertex_count;
    double v[SAM_AREA_LIGHT_MAX_VERTICES][3];
    double centre[3] = {0, 0, 0}, lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            v[i][k] = light->vertices[i][k];
            centre[k] += v[i][k] / n;
            lo[k] = fmin(lo[k], v[i][k]);
            hi[k] = fmax(hi[k], v[i][k]);
        }
    }
    double extent[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    double size = sam_scene_length3(extent);
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
    double twice_area = sam_scene_length3(newell);
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
        if (sam_scene_length3(e) <= 1e-6 * size)
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
        if (s <= 1e-6 * sam_scene_length3(e0) * sam_scene_length3(e1)) {
            if (fabs(s) <= 1e-6 * sam_scene_length3(e0) * sam_scene_length3(e1))
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

static sam_status parse_light(const sam_scene_parser *p, const cJSON *item, int index, sam_light *light)
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
        if ((st = sam_scene_get_direction(p, v, at, light->direction)) != SAM_OK)
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

sam_status sam_scene_parse_lights(const sam_scene_parser *p, const cJSON *item, sam_scene *scene)
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
        return sam_scene_out_of_memory(p);
    int i = 0;
    for (const cJSON *e = item->child; e; e = e->next, ++i) {
        sam_status st = parse_light(p, e, i, &scene->lights[i]);
        if (st != SAM_OK)
            return st;
        scene->light_count = (size_t)i + 1;
    }
    return SAM_OK;
}

sam_status sam_scene_parse_environment(const sam_scene_parser *p, const cJSON *item, sam_scene *scene)
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
    return sam_scene_get_file(p, v, "environment.map", &scene->environment.map);
}
