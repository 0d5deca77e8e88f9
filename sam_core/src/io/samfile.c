#include "sam/samfile.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "samfile_internal.h"

/* ---- semantic validation, shared by read, write and samfile_validate ---- */

/* True when a byte count computed in 64 bits is addressable on this host. */
static int fits_size(uint64_t bytes)
{
    return (uint64_t)(size_t)bytes == bytes;
}

/* Index of the first byte that is not part of valid UTF-8, or `len`. */
static size_t utf8_error_at(const unsigned char *s, size_t len)
{
    size_t i = 0;
    while (i < len) {
        unsigned c = s[i];
        if (c < 0x80) {
            ++i;
            continue;
        }
        size_t extra;
        uint32_t cp, min;
        if ((c & 0xE0) == 0xC0)
            extra = 1, cp = c & 0x1F, min = 0x80;
        else if ((c & 0xF0) == 0xE0)
            extra = 2, cp = c & 0x0F, min = 0x800;
        else if ((c & 0xF8) == 0xF0)
            extra = 3, cp = c & 0x07, min = 0x10000;
        else
            return i;
        if (len - i <= extra)
            return i;
        for (size_t k = 1; k <= extra; ++k) {
            if ((s[i + k] & 0xC0) != 0x80)
                return i;
            cp = cp << 6 | (s[i + k] & 0x3Fu);
        }
        if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
            return i;
        i += extra + 1;
    }
    return len;
}

static sam_status info_number(const cJSON *root, const char *key, double *value, const char *name,
                              sam_status bad, sam_error *err)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!item)
        return sam_fail(err, bad, "%s: chunk INFO: key \"%s\" is missing", name, key);
    if (!cJSON_IsNumber(item))
        return sam_fail(err, bad, "%s: chunk INFO: key \"%s\" is not a number", name, key);
    *value = item->valuedouble;
    return SAM_OK;
}

static sam_status check_info_fields(const cJSON *root, const samfile_data *d, const char *name,
                                    sam_status bad, sam_error *err)
{
    double v = 0;
    sam_status st = info_number(root, "vertex_count", &v, name, bad, err);
    if (st != SAM_OK)
        return st;
    if (v != (double)d->vertex_count)
        return sam_fail(err, bad,
                        "%s: chunk INFO: vertex_count %.17g disagrees with chunk POS  (%u vertices)", name, v,
                        (unsigned)d->vertex_count);
    if ((st = info_number(root, "triangle_count", &v, name, bad, err)) != SAM_OK)
        return st;
    if (v != (double)d->triangle_count)
        return sam_fail(err, bad,
                        "%s: chunk INFO: triangle_count %.17g disagrees with chunk TRI  (%u triangles)", name,
                        v, (unsigned)d->triangle_count);
    if ((st = info_number(root, "samples_per_vertex", &v, name, bad, err)) != SAM_OK)
        return st;
    if (v != (double)d->samples_per_vertex)
        return sam_fail(
            err, bad,
            "%s: chunk INFO: samples_per_vertex %.17g disagrees with chunk SIDX (%u samples per vertex)",
            name, v, (unsigned)d->samples_per_vertex);
    if ((st = info_number(root, "mm_per_unit", &v, name, bad, err)) != SAM_OK)
        return st;
    if (!isfinite(v) || v <= 0.0)
        return sam_fail(err, bad, "%s: chunk INFO: mm_per_unit %g must be finite and > 0", name, v);
    /* The CRCs cover payloads, not tags, so a damaged "UV  " tag would read
     * as an unknown chunk; a writer that records has_uvs closes that gap. */
    const cJSON *uvs = cJSON_GetObjectItemCaseSensitive(root, "has_uvs");
    if (uvs && !cJSON_IsBool(uvs))
        return sam_fail(err, bad, "%s: chunk INFO: key \"has_uvs\" is not true or false", name);
    if (uvs && cJSON_IsTrue(uvs) != (d->uvs != NULL))
        return sam_fail(err, bad, "%s: chunk INFO: has_uvs is %s but the file %s a UV   chunk", name,
                        cJSON_IsTrue(uvs) ? "true" : "false", d->uvs ? "has" : "has no");
    return SAM_OK;
}

static sam_status check_info(const samfile_data *d, const char *name, sam_status bad, sam_error *err)
{
    const char *text = d->info_json;
    size_t len = strlen(text);
    if (len == 0)
        return sam_fail(err, bad, "%s: chunk INFO: JSON text is empty", name);
    size_t at = utf8_error_at((const unsigned char *)text, len);
    if (at < len)
        return sam_fail(err, bad, "%s: chunk INFO: invalid UTF-8 at byte %zu (0x%02x)", name, at,
                        (unsigned char)text[at]);
    /* Nothing may surround the object: then a damaged INFO length, which
     * cuts or extends the text, can never leave valid JSON behind. */
    if (text[0] != '{' || text[len - 1] != '}')
        return sam_fail(err, bad,
                        "%s: chunk INFO: JSON text must be one object from '{' to '}' "
                        "(%zu bytes, first 0x%02x, last 0x%02x)",
                        name, len, (unsigned char)text[0], (unsigned char)text[len - 1]);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (!root)
        return sam_fail(err, bad, "%s: chunk INFO: JSON syntax error at byte %zu of %zu", name,
                        end ? (size_t)(end - text) : (size_t)0, len);
    sam_status st;
    if (end != text + len)
        st = sam_fail(err, bad, "%s: chunk INFO: unexpected text after the JSON object at byte %zu", name,
                      (size_t)(end - text));
    else
        st = check_info_fields(root, d, name, bad, err);
    cJSON_Delete(root);
    return st;
}

static sam_status check_finite(const float *v, size_t count, size_t per, const char *tag, const char *what,
                               const char *name, sam_status bad, sam_error *err)
{
    for (size_t i = 0; i < count; ++i)
        if (!isfinite(v[i]))
            return sam_fail(err, bad,
                            "%s: chunk %s: component %zu of the %s of vertex %zu is not finite (%g)", name,
                            tag, i % per, what, i / per, (double)v[i]);
    return SAM_OK;
}

static sam_status check_samples(const samfile_data *d, const char *name, sam_status bad, sam_error *err)
{
    size_t vc = d->vertex_count, n = d->samples_per_vertex;
    for (size_t v = 0; v < vc; ++v) {
        const uint32_t *list = d->sample_index + v * n;
        size_t first_pad = n;
        for (size_t k = 0; k < n; ++k) {
            if (list[k] == SAMFILE_NO_SAMPLE) {
                if (first_pad == n)
                    first_pad = k;
                continue;
            }
            if (list[k] >= (uint64_t)d->vertex_count + d->node_count) {
                char range[64] = "";
                if (d->node_count)
                    snprintf(range, sizeof range, " + node_count %u", (unsigned)d->node_count);
                return sam_fail(err, bad,
                                "%s: chunk SIDX: sample index %u of vertex %zu is out of range (vertex_count %u%s)",
                                name, (unsigned)list[k], v, (unsigned)d->vertex_count, range);
            }
            if (first_pad < k)
                return sam_fail(err, bad,
                                "%s: chunk SIDX: vertex %zu has sample index %u in slot %zu after a pad "
                                "(0xFFFFFFFF) in slot %zu",
                                name, v, (unsigned)list[k], k, first_pad);
        }
    }
    const float *kp = d->sample_kprime;
    for (size_t i = 0; i < vc * n * 3; ++i)
        if (!isfinite(kp[i]) || kp[i] < 0.0f)
            return sam_fail(err, bad,
                            "%s: chunk SKPR: K' channel %zu of sample %zu of vertex %zu is %g "
                            "(must be finite and >= 0)",
                            name, i % 3, (i / 3) % n, i / (3 * n), (double)kp[i]);
    return SAM_OK;
}

static sam_status check_adjacency(const samfile_data *d, const char *name, sam_status bad, sam_error *err)
{
    const uint32_t *off = d->adjacency_offsets;
    size_t vc = d->vertex_count;
    if (off[0] != 0)
        return sam_fail(err, bad, "%s: chunk ADJO: first offset is %u, expected 0", name, (unsigned)off[0]);
    for (size_t v = 0; v < vc; ++v)
        if (off[v + 1] < off[v])
            return sam_fail(err, bad,
                            "%s: chunk ADJO: offset %u of vertex %zu is below offset %u of vertex %zu", name,
                            (unsigned)off[v + 1], v + 1, (unsigned)off[v], v);
    if (off[vc] != d->adjacency_count)
        return sam_fail(err, bad, "%s: chunk ADJO: last offset %u disagrees with chunk ADJV (%u entries)",
                        name, (unsigned)off[vc], (unsigned)d->adjacency_count);
    for (size_t v = 0; v < vc; ++v)
        for (size_t e = off[v]; e < off[v + 1]; ++e)
            if (d->adjacency[e] >= d->vertex_count)
                return sam_fail(err, bad,
                                "%s: chunk ADJV: neighbour %u at entry %zu (vertex %zu) is out of range "
                                "(vertex_count %u)",
                                name, (unsigned)d->adjacency[e], e, v, (unsigned)d->vertex_count);
    return SAM_OK;
}
/* The tree's rules (samfile.h): levels partition the nodes in order, a
 * node's children are vertices or nodes of the next level, which also
 * rules out cycles, and every vertex and node has at most one parent, every
 * node below level 0 exactly one: the runtime sums a node when the second
 * of its two children reaches it (shaders/nodes.comp), which a node shared
 * by two parents or skipped by all would break. */
static sam_status check_tree(const samfile_data *d, const char *name, sam_status bad, sam_error *err)
{
    const uint32_t vc = d->vertex_count, nc = d->node_count, *lo = d->level_offsets;
    if ((uint64_t)vc + nc >= SAMFILE_NO_SAMPLE)
        return sam_fail(err, bad, "%s: chunk NODE: %u vertices + %u nodes do not fit 32-bit sample indices", name,
                        (unsigned)vc, (unsigned)nc);
    if (d->level_count == 0 || lo[0] != 0 || lo[d->level_count] != nc)
        return sam_fail(err, bad, "%s: chunk NLVL: %u levels from node %u to %u, expected from 0 to node_count %u",
                        name, (unsigned)d->level_count, (unsigned)lo[0], (unsigned)lo[d->level_count],
                        (unsigned)nc);
    for (uint32_t l = 0; l < d->level_count; ++l)
        if (lo[l + 1] <= lo[l])
            return sam_fail(err, bad, "%s: chunk NLVL: level %u is empty or reversed (nodes %u to %u)", name,
                            (unsigned)l, (unsigned)lo[l], (unsigned)lo[l + 1]);
    uint32_t *parent = malloc(((size_t)vc + nc) * sizeof *parent);
    if (!parent)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory to check a tree of %u nodes", name,
                        (unsigned)nc);
    for (size_t i = 0; i < (size_t)vc + nc; ++i)
        parent[i] = SAMFILE_NO_SAMPLE;
    sam_status st = SAM_OK;
    for (uint32_t l = 0; l < d->level_count && st == SAM_OK; ++l) {
        const uint32_t next_lo = lo[l + 1], next_hi = l + 2 <= d->level_count ? lo[l + 2] : nc;
        for (uint32_t j = lo[l]; j < lo[l + 1] && st == SAM_OK; ++j)
            for (int c = 0; c < 2 && st == SAM_OK; ++c) {
                uint32_t child = d->node_children[2 * (size_t)j + c];
                if (child >= vc && (child - vc >= nc || child - vc < next_lo || child - vc >= next_hi))
                    st = sam_fail(err, bad,
                                  "%s: chunk NODE: child %d of node %u (level %u) is %u, expected a vertex < %u or a "
                                  "node of the next level (%u..%u)",
                                  name, c, (unsigned)j, (unsigned)l, (unsigned)child, (unsigned)vc,
                                  (unsigned)(vc + next_lo), (unsigned)(vc + next_hi - 1));
                else if (parent[child] != SAMFILE_NO_SAMPLE)
                    st = sam_fail(err, bad, "%s: chunk NODE: %s %u is a child of nodes %u and %u (a tree gives each "
                                  "one parent)",
                                  name, child < vc ? "vertex" : "node", (unsigned)(child < vc ? child : child - vc),
                                  (unsigned)parent[child], (unsigned)j);
                else
                    parent[child] = j;
            }
    }
    for (uint32_t j = lo[1]; j < nc && st == SAM_OK; ++j)
        if (parent[(size_t)vc + j] == SAMFILE_NO_SAMPLE)
            st = sam_fail(err, bad, "%s: chunk NODE: node %u is below level 0 but no node's child", name, (unsigned)j);
    free(parent);
    if (st != SAM_OK)
        return st;
    const size_t n = (size_t)vc * d->samples_per_vertex;
    for (size_t i = 0; i < n; ++i)
        if (!(fabsf(d->sample_tau[i]) <= 1.0f))
            return sam_fail(err, bad, "%s: chunk STAU: tau of sample %zu of vertex %zu is %g (must be in [-1, 1])", name,
                            i % d->samples_per_vertex, i / d->samples_per_vertex, (double)d->sample_tau[i]);
    return SAM_OK;
}

sam_status samfile_check_data(const samfile_data *d, const char *name, sam_status bad, sam_error *err)
{
    if (!d)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: no data given", name);
    const char *missing = !d->info_json                           ? "INFO"
                          : !d->positions                         ? "POS "
                          : !d->normals                           ? "NRM "
                          : !d->triangles                         ? "TRI "
                          : !d->sample_index                      ? "SIDX"
                          : !d->sample_kprime                     ? "SKPR"
                          : !d->fan_area                          ? "FANA"
                          : !d->adjacency_offsets                 ? "ADJO"
                          : (!d->adjacency && d->adjacency_count) ? "ADJV"
                          : (!d->node_children && d->node_count)  ? "NODE"
                          : (!d->level_offsets && d->node_count)  ? "NLVL"
                          : (!d->sample_tau && d->node_count)     ? "STAU"
                          : (!d->vertex_source != !d->source_vertex) ? "SRCV"
                          : (!d->vertex_source && d->source_vertex_count) ? "SRCV"
                                                                  : NULL;
    if (missing)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: chunk %s: array is NULL", name, missing);
    if (d->vertex_count == 0)
        return sam_fail(err, SAM_ERR_EMPTY, "%s: chunk POS : no vertices (vertex_count 0)", name);
    if (d->triangle_count == 0)
        return sam_fail(err, SAM_ERR_EMPTY, "%s: chunk TRI : no triangles (triangle_count 0)", name);
    if (d->samples_per_vertex == 0 || d->samples_per_vertex > SAMFILE_MAX_SAMPLES_PER_VERTEX)
        return sam_fail(err, bad, "%s: chunk SIDX: %u samples per vertex; supported range is 1..%u", name,
                        (unsigned)d->samples_per_vertex, SAMFILE_MAX_SAMPLES_PER_VERTEX);
    /* Only a 32-bit host can fail these. SKPR, 3*n*vc floats, is the largest
     * per-vertex array. */
    if (!fits_size((uint64_t)d->vertex_count * d->samples_per_vertex * 12u))
        return sam_fail(err, bad, "%s: chunk SKPR: %u vertices x %u samples is too large for this host", name,
                        (unsigned)d->vertex_count, (unsigned)d->samples_per_vertex);
    if (!fits_size((uint64_t)d->triangle_count * 12u))
        return sam_fail(err, bad, "%s: chunk TRI : %u triangles is too large for this host", name,
                        (unsigned)d->triangle_count);
    if (!fits_size((uint64_t)d->adjacency_count * 4u))
        return sam_fail(err, bad, "%s: chunk ADJV: %u entries is too large for this host", name,
                        (unsigned)d->adjacency_count);

    sam_status st = check_info(d, name, bad, err);
    size_t vc = d->vertex_count;
    if (st == SAM_OK)
        st = check_finite(d->positions, 3 * vc, 3, "POS ", "position", name, bad, err);
    if (st == SAM_OK)
        st = check_finite(d->normals, 3 * vc, 3, "NRM ", "normal", name, bad, err);
    if (st != SAM_OK)
        return st;
    for (size_t v = 0; v < vc; ++v) {
        const float *n = d->normals + 3 * v;
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        if (fabs(len - 1.0) > SAMFILE_NORMAL_TOLERANCE)
            return sam_fail(err, bad,
                            "%s: chunk NRM : normal of vertex %zu has length %.6g (expected 1 within %g)",
                            name, v, len, SAMFILE_NORMAL_TOLERANCE);
    }
    if (d->uvs && (st = check_finite(d->uvs, 2 * vc, 2, "UV  ", "uv", name, bad, err)) != SAM_OK)
        return st;
    for (size_t i = 0; i < 3 * (size_t)d->triangle_count; ++i)
        if (d->triangles[i] >= d->vertex_count)
            return sam_fail(err, bad,
                            "%s: chunk TRI : index %u of triangle %zu is out of range (vertex_count %u)",
                            name, (unsigned)d->triangles[i], i / 3, (unsigned)d->vertex_count);
    if (d->node_count && (st = check_tree(d, name, bad, err)) != SAM_OK)
        return st;
    if ((st = check_samples(d, name, bad, err)) != SAM_OK)
        return st;
    for (size_t v = 0; v < vc; ++v)
        if (!isfinite(d->fan_area[v]) || d->fan_area[v] < 0.0f)
            return sam_fail(err, bad,
                            "%s: chunk FANA: fan area of vertex %zu is %g (must be finite and >= 0)", name, v,
                            (double)d->fan_area[v]);
    if (d->vertex_source && d->source_vertex_count == 0)
        return sam_fail(err, bad, "%s: chunk SRCV: a source mesh of 0 vertices", name);
    for (size_t v = 0; d->vertex_source && v < vc; ++v)
        if (d->vertex_source[v] >= d->source_vertex_count)
            return sam_fail(err, bad,
                            "%s: chunk SRCV: vertex %zu comes from source vertex %u, out of range (%u source vertices)",
                            name, v, (unsigned)d->vertex_source[v], (unsigned)d->source_vertex_count);
    for (uint32_t s = 0; d->source_vertex && s < d->source_vertex_count; ++s)
        if (d->source_vertex[s] >= vc && d->source_vertex[s] != SAMFILE_NO_SAMPLE)
            return sam_fail(err, bad, "%s: chunk SRCV: source vertex %u became vertex %u, out of range (vertex_count %u)",
                            name, (unsigned)s, (unsigned)d->source_vertex[s], (unsigned)vc);
    return check_adjacency(d, name, bad, err);
}

sam_status samfile_validate(const samfile_data *data, sam_error *err)
{
    return samfile_check_data(data, "samfile data", SAM_ERR_INVALID_ARGUMENT, err);
}

void samfile_free(samfile_data *data)
{
    if (!data)
        return;
    free(data->info_json);
    free(data->positions);
    free(data->normals);
    free(data->uvs);
    free(data->triangles);
    free(data->sample_index);
    free(data->sample_kprime);
    free(data->fan_area);
    free(data->adjacency_offsets);
    free(data->adjacency);
    free(data->node_children);
    free(data->level_offsets);
    free(data->sample_tau);
    free(data->vertex_source);
    free(data->source_vertex);
    memset(data, 0, sizeof *data);
}
