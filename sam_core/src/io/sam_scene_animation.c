/*
 * sam_scene_animation: the "deformers" and "keyframes" keys of a scene
 * file (formats in sam_scene.h; the deformers' formulas in sam_deform.h).
 */
#include "sam_scene_internal.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* A deformer's number keys: where each goes, whether it must be given,
 * and its range (0 finite, 1 > 0, 2 >= 0, 3 in (-1, 1)). */
typedef struct deformer_number {
    const char *key;
    size_t offset;
    int required, range;
} deformer_number;

static sam_status get_deformer_number(const sam_scene_parser *p, const cJSON *item, const char *path, int range,
                                      float *out)
{
    switch (range) {
    case 1: return sam_json_positive(&p->json, item, path, out);
    case 2: return sam_json_non_negative(&p->json, item, path, out);
    case 3: return sam_json_float(&p->json, item, path, -1.0, 1, 1.0, 1, "in (-1, 1)", out);
    default: return sam_json_any_float(&p->json, item, path, out);
    }
}

static sam_status parse_deformer(const sam_scene_parser *p, const cJSON *item, int index, sam_deformer *d)
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
            if (v && (st = center ? sam_json_vec3(&p->json, v, at, 0, out)
                                  : sam_scene_get_direction(p, v, at, out)) != SAM_OK)
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
        if (!(sam_scene_length3(cross) > 1e-3))
            return sam_json_fail(&p->json, SAM_ERR_FORMAT, sam_json_key_path(at, sizeof at, path, "direction"),
                                 "[%g, %g, %g] is parallel to the axis [%g, %g, %g]", d->direction[0], d->direction[1],
                                 d->direction[2], d->axis[0], d->axis[1], d->axis[2]);
    }
    return SAM_OK;
}

sam_status sam_scene_parse_deformers(const sam_scene_parser *p, const cJSON *item, sam_scene *scene)
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

sam_status sam_scene_parse_keyframes(const sam_scene_parser *p, const cJSON *item, sam_scene *scene)
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
        return sam_scene_out_of_memory(p);
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
        if ((st = sam_scene_get_file(p, cJSON_GetObjectItemCaseSensitive(e, "mesh"),
                                     sam_json_key_path(at, sizeof at, path, "mesh"), &k->mesh)) != SAM_OK)
            return st;
        scene->keyframe_count = (size_t)i + 1;
    }
    return SAM_OK;
}
