/* The INFO chunk read back: its fields (samfile_info_read) and its keys
 * printed (samfile_info_print). INFO is parsed only here and, for the
 * container's own checks, in samfile.c. */
#include <stdio.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "sam/samfile.h"

sam_status samfile_info_read(const samfile_data *data, const char *name, samfile_info *out, sam_error *err)
{
    memset(out, 0, sizeof *out);
    if (!name)
        name = "INFO";
    cJSON *info = cJSON_Parse(data->info_json);
    if (!info)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory parsing INFO (%zu bytes)", name,
                        strlen(data->info_json));
    const cJSON *scale = cJSON_GetObjectItemCaseSensitive(info, "mm_per_unit");
    if (cJSON_IsNumber(scale))
        out->mm_per_unit = (float)scale->valuedouble;
    const cJSON *seconds = cJSON_GetObjectItemCaseSensitive(info, "build_seconds");
    if (cJSON_IsNumber(seconds) && seconds->valuedouble >= 0)
        out->build_seconds = seconds->valuedouble;
    const cJSON *source = cJSON_GetObjectItemCaseSensitive(info, "source");
    const cJSON *file = cJSON_GetObjectItemCaseSensitive(source, "file");
    const cJSON *sha = cJSON_GetObjectItemCaseSensitive(source, "sha256");
    if (cJSON_IsString(file))
        snprintf(out->source_file, sizeof out->source_file, "%s", file->valuestring);
    if (cJSON_IsString(sha))
        snprintf(out->source_sha256, sizeof out->source_sha256, "%s", sha->valuestring);
    const cJSON *map = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(info, "builder"), "map");
    if (cJSON_IsString(map))
        snprintf(out->map, sizeof out->map, "%s", map->valuestring);
    sam_status st = SAM_OK;
    const cJSON *material = cJSON_GetObjectItemCaseSensitive(info, "material");
    if (material) {
        char *text = cJSON_PrintUnformatted(material);
        st = text ? sam_profile_parse_json(text, strlen(text), name, &out->profile, err)
                  : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory printing INFO's material", name);
        out->has_material = st == SAM_OK;
        cJSON_free(text);
    }
    cJSON_Delete(info);
    return st;
}

void samfile_info_print(const samfile_data *data, FILE *out)
{
    cJSON *info = cJSON_Parse(data->info_json);
    if (!info)
        return;
    for (const cJSON *item = info->child; item; item = item->next) {
        if (!strcmp(item->string, "vertex_count") || !strcmp(item->string, "triangle_count") ||
            !strcmp(item->string, "samples_per_vertex"))
            continue;
        char *text = cJSON_IsString(item) ? NULL : cJSON_PrintUnformatted(item);
        fprintf(out, "  %-18s %s\n", item->string, cJSON_IsString(item) ? item->valuestring : text ? text : "");
        cJSON_free(text);
    }
    cJSON_Delete(info);
}
