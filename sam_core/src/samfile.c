#include "sam/samfile.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#define FILE_HEADER_SIZE 16u
#define CHUNK_HEADER_SIZE 16u
#define CHUNK_TRAILER_SIZE 8u

enum {
    TAG_INFO,
    TAG_POS,
    TAG_NRM,
    TAG_UV,
    TAG_TRI,
    TAG_SIDX,
    TAG_SKPR,
    TAG_FANA,
    TAG_ADJO,
    TAG_ADJV,
    TAG_COUNT
};

/* Also the order in which the writer emits chunks. */
static const char k_tags[TAG_COUNT][5] = {"INFO", "POS ", "NRM ", "UV  ", "TRI ",
                                          "SIDX", "SKPR", "FANA", "ADJO", "ADJV"};

/* ---- little-endian encoding, independent of the host's byte order ---- */

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t get_u64(const uint8_t *p)
{
    return (uint64_t)get_u32(p) | (uint64_t)get_u32(p + 4) << 32;
}

static void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static void put_u64(uint8_t *p, uint64_t v)
{
    put_u32(p, (uint32_t)v);
    put_u32(p + 4, (uint32_t)(v >> 32));
}

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static size_t padding_of(uint64_t length)
{
    return (size_t)((8u - length % 8u) % 8u);
}

/* True when a byte count computed in 64 bits is addressable on this host. */
static int fits_size(uint64_t bytes)
{
    return (uint64_t)(size_t)bytes == bytes;
}

/* Tags from a damaged file may hold any bytes; keep messages one clean line. */
static void format_tag(const uint8_t *tag, char out[17])
{
    char *o = out;
    for (int i = 0; i < 4; ++i) {
        if (tag[i] >= 0x20 && tag[i] < 0x7f && tag[i] != '\\')
            *o++ = (char)tag[i];
        else
            o += snprintf(o, 5, "\\x%02x", tag[i]);
    }
    *o = '\0';
}

/* ---- semantic validation, shared by read, write and samfile_validate ---- */

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
    double v;
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
            if (list[k] >= d->vertex_count)
                return sam_fail(
                    err, bad,
                    "%s: chunk SIDX: sample index %u of vertex %zu is out of range (vertex_count %u)", name,
                    (unsigned)list[k], v, (unsigned)d->vertex_count);
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

/* `bad` is the status for a broken rule: SAM_ERR_CORRUPT when the data came
 * from a file, SAM_ERR_INVALID_ARGUMENT when a caller built it. */
static sam_status validate_data(const samfile_data *d, const char *name, sam_status bad, sam_error *err)
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
    if ((st = check_samples(d, name, bad, err)) != SAM_OK)
        return st;
    for (size_t v = 0; v < vc; ++v)
        if (!isfinite(d->fan_area[v]) || d->fan_area[v] < 0.0f)
            return sam_fail(err, bad,
                            "%s: chunk FANA: fan area of vertex %zu is %g (must be finite and >= 0)", name, v,
                            (double)d->fan_area[v]);
    return check_adjacency(d, name, bad, err);
}

sam_status samfile_validate(const samfile_data *data, sam_error *err)
{
    return validate_data(data, "samfile data", SAM_ERR_INVALID_ARGUMENT, err);
}

/* ---- writing ---- */

typedef struct chunk_writer {
    FILE *fp;
    int error; /* errno of the first failed write, or 0 */
    uLong crc;
    uint64_t length; /* payload length of the open chunk */
    size_t used;
    uint8_t buf[8192];
} chunk_writer;

static void write_raw(chunk_writer *w, const void *p, size_t n)
{
    if (w->error || n == 0)
        return;
    errno = 0;
    if (fwrite(p, 1, n, w->fp) != n)
        w->error = errno ? errno : EIO;
}

static void flush_payload(chunk_writer *w)
{
    w->crc = crc32_z(w->crc, w->buf, w->used);
    write_raw(w, w->buf, w->used);
    w->used = 0;
}

static void payload_u32(chunk_writer *w, uint32_t v)
{
    if (w->used + 4 > sizeof w->buf)
        flush_payload(w);
    put_u32(w->buf + w->used, v);
    w->used += 4;
}

static void begin_chunk(chunk_writer *w, int tag, uint64_t length)
{
    uint8_t h[CHUNK_HEADER_SIZE];
    memcpy(h, k_tags[tag], 4);
    put_u32(h + 4, 0);
    put_u64(h + 8, length);
    write_raw(w, h, sizeof h);
    w->crc = crc32_z(0L, Z_NULL, 0);
    w->length = length;
}

static void end_chunk(chunk_writer *w)
{
    flush_payload(w);
    uint8_t t[7 + CHUNK_TRAILER_SIZE] = {0};
    size_t pad = padding_of(w->length);
    put_u32(t + pad, (uint32_t)w->crc);
    write_raw(w, t, pad + CHUNK_TRAILER_SIZE);
}

static void write_u32_chunk(chunk_writer *w, int tag, const uint32_t *v, size_t count)
{
    begin_chunk(w, tag, (uint64_t)count * 4u);
    for (size_t i = 0; i < count; ++i)
        payload_u32(w, v[i]);
    end_chunk(w);
}

static void write_f32_chunk(chunk_writer *w, int tag, const float *v, size_t count)
{
    begin_chunk(w, tag, (uint64_t)count * 4u);
    for (size_t i = 0; i < count; ++i)
        payload_u32(w, float_bits(v[i]));
    end_chunk(w);
}

sam_status samfile_write(const char *path, const samfile_data *data, sam_error *err)
{
    if (!path || !path[0])
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "samfile write: no output path given");
    sam_status st = validate_data(data, path, SAM_ERR_INVALID_ARGUMENT, err);
    if (st != SAM_OK)
        return st;
    sam_atomic_file file;
    if ((st = sam_atomic_open(&file, path, err)) != SAM_OK)
        return st;
    chunk_writer *w = calloc(1, sizeof *w);
    if (!w) {
        sam_atomic_abort(&file);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    w->fp = file.fp;

    size_t vc = data->vertex_count, n = data->samples_per_vertex;
    uint8_t header[FILE_HEADER_SIZE];
    memcpy(header, "SAMF", 4);
    put_u32(header + 4, SAMFILE_VERSION);
    put_u32(header + 8, data->uvs ? TAG_COUNT : TAG_COUNT - 1);
    put_u32(header + 12, 0);
    write_raw(w, header, sizeof header);

    size_t info_len = strlen(data->info_json);
    begin_chunk(w, TAG_INFO, info_len);
    w->crc = crc32_z(w->crc, (const Bytef *)data->info_json, info_len);
    write_raw(w, data->info_json, info_len);
    end_chunk(w);
    write_f32_chunk(w, TAG_POS, data->positions, 3 * vc);
    write_f32_chunk(w, TAG_NRM, data->normals, 3 * vc);
    if (data->uvs)
        write_f32_chunk(w, TAG_UV, data->uvs, 2 * vc);
    write_u32_chunk(w, TAG_TRI, data->triangles, 3 * (size_t)data->triangle_count);
    write_u32_chunk(w, TAG_SIDX, data->sample_index, n * vc);
    write_f32_chunk(w, TAG_SKPR, data->sample_kprime, 3 * n * vc);
    write_f32_chunk(w, TAG_FANA, data->fan_area, vc);
    write_u32_chunk(w, TAG_ADJO, data->adjacency_offsets, vc + 1);
    write_u32_chunk(w, TAG_ADJV, data->adjacency, data->adjacency_count);

    int e = w->error;
    free(w);
    if (e) {
        st = sam_fail(err, SAM_ERR_IO, "%s: write of %s failed: %s", path, file.temp_path, strerror(e));
        sam_atomic_abort(&file);
        return st;
    }
    return sam_atomic_commit(&file, err);
}

/* ---- reading ---- */

typedef struct chunk_ref {
    const uint8_t *payload; /* NULL when the chunk is absent */
    size_t length;
    size_t offset; /* of the chunk header in the file */
} chunk_ref;

typedef struct unknown_chunk {
    uint32_t tag;
    size_t offset;
} unknown_chunk;

static int compare_unknown(const void *a, const void *b)
{
    const unknown_chunk *x = a, *y = b;
    if (x->tag != y->tag)
        return x->tag < y->tag ? -1 : 1;
    return x->offset < y->offset ? -1 : x->offset > y->offset;
}

static int known_tag(const uint8_t *tag)
{
    for (int t = 0; t < TAG_COUNT; ++t)
        if (memcmp(tag, k_tags[t], 4) == 0)
            return t;
    return -1;
}

/* Checks one chunk's framing at `off` and returns its padded payload size
 * through *padded. */
static sam_status check_chunk(const uint8_t *b, size_t size, size_t off, uint32_t index, const char *name,
                              size_t *length, size_t *padded, sam_error *err)
{
    size_t remain = size - off;
    if (remain < CHUNK_HEADER_SIZE)
        return sam_fail(
            err, SAM_ERR_FORMAT,
            "%s: truncated: chunk %u at offset %zu needs a 16-byte header but only %zu bytes remain", name,
            (unsigned)index, off, remain);
    char tag[17];
    format_tag(b + off, tag);
    uint32_t reserved = get_u32(b + off + 4);
    if (reserved != 0)
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: chunk %s at offset %zu: reserved field is 0x%08x, expected 0", name, tag, off,
                        (unsigned)reserved);
    uint64_t declared = get_u64(b + off + 8);
    size_t body = remain - CHUNK_HEADER_SIZE;
    if (declared > body)
        return sam_fail(
            err, SAM_ERR_FORMAT,
            "%s: truncated: chunk %s at offset %zu declares %llu payload bytes but only %zu remain", name,
            tag, off, (unsigned long long)declared, body);
    size_t len = (size_t)declared, pad = padding_of(declared);
    if (body - len < pad + CHUNK_TRAILER_SIZE)
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: truncated: chunk %s at offset %zu: its %zu payload bytes need %zu padding and "
                        "%u trailer bytes but only %zu remain",
                        name, tag, off, len, pad, CHUNK_TRAILER_SIZE, body - len);
    const uint8_t *p = b + off + CHUNK_HEADER_SIZE;
    for (size_t i = 0; i < pad; ++i)
        if (p[len + i] != 0)
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s: chunk %s at offset %zu: padding byte %zu is 0x%02x, expected 0", name, tag,
                            off, i, p[len + i]);
    uint32_t stored = get_u32(p + len + pad);
    uint32_t computed = (uint32_t)crc32_z(crc32_z(0L, Z_NULL, 0), p, len);
    if (stored != computed)
        return sam_fail(err, SAM_ERR_CORRUPT, "%s: chunk %s: CRC mismatch (stored 0x%08x, computed 0x%08x)",
                        name, tag, (unsigned)stored, (unsigned)computed);
    uint32_t trailer = get_u32(p + len + pad + 4);
    if (trailer != 0)
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: chunk %s at offset %zu: field after the CRC is 0x%08x, expected 0", name, tag,
                        off, (unsigned)trailer);
    *length = len;
    *padded = len + pad;
    return SAM_OK;
}

static sam_status check_unknown_duplicates(unknown_chunk *list, size_t count, const char *name,
                                           sam_error *err)
{
    if (count < 2)
        return SAM_OK;
    qsort(list, count, sizeof *list, compare_unknown);
    for (size_t i = 1; i < count; ++i)
        if (list[i].tag == list[i - 1].tag) {
            uint8_t raw[4];
            put_u32(raw, list[i].tag);
            char tag[17];
            format_tag(raw, tag);
            return sam_fail(err, SAM_ERR_FORMAT, "%s: chunk %s at offset %zu repeats the chunk at offset %zu",
                            name, tag, list[i].offset, list[i - 1].offset);
        }
    return SAM_OK;
}

/* Walks the header and every chunk's framing, filling `known` and counting
 * unknown chunks. */
static sam_status parse_frame(const uint8_t *b, size_t size, const char *name, chunk_ref known[TAG_COUNT],
                              uint32_t *unknown_count, sam_error *err)
{
    if (size >= 4 && memcmp(b, "SAMF", 4) != 0) {
        char magic[17];
        format_tag(b, magic);
        return sam_fail(err, SAM_ERR_FORMAT, "%s: not a .sam file: magic is \"%s\", expected \"SAMF\"", name,
                        magic);
    }
    if (size < FILE_HEADER_SIZE)
        return sam_fail(err, SAM_ERR_FORMAT, "%s: truncated: %zu bytes, shorter than the 16-byte header",
                        name, size);
    uint32_t version = get_u32(b + 4), declared = get_u32(b + 8), flags = get_u32(b + 12);
    if (version != SAMFILE_VERSION)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "%s: version %u is not supported (this build reads version %u)", name,
                        (unsigned)version, SAMFILE_VERSION);
    if (flags != 0)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "%s: header flags 0x%08x are not supported (version 1 has none)", name,
                        (unsigned)flags);

    /* Every chunk takes at least 24 bytes, which bounds this allocation by
     * the input size whatever the header declares. */
    size_t cap = (size - FILE_HEADER_SIZE) / (CHUNK_HEADER_SIZE + CHUNK_TRAILER_SIZE);
    if (cap > declared)
        cap = declared;
    unknown_chunk *unknown = cap ? malloc(cap * sizeof *unknown) : NULL;
    if (cap && !unknown)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %zu chunk records", name, cap);

    sam_status st = SAM_OK;
    size_t off = FILE_HEADER_SIZE, unknowns = 0;
    uint32_t i = 0;
    for (; i < declared && off < size; ++i) {
        size_t len = 0, padded = 0;
        if ((st = check_chunk(b, size, off, i, name, &len, &padded, err)) != SAM_OK)
            break;
        int t = known_tag(b + off);
        if (t < 0) {
            unknown[unknowns].tag = get_u32(b + off);
            unknown[unknowns++].offset = off;
        } else if (known[t].payload) {
            st = sam_fail(err, SAM_ERR_FORMAT, "%s: chunk %s at offset %zu repeats the chunk at offset %zu",
                          name, k_tags[t], off, known[t].offset);
            break;
        } else {
            known[t].payload = b + off + CHUNK_HEADER_SIZE;
            known[t].length = len;
            known[t].offset = off;
        }
        off += CHUNK_HEADER_SIZE + padded + CHUNK_TRAILER_SIZE;
    }
    if (st == SAM_OK && i < declared)
        st =
            sam_fail(err, SAM_ERR_FORMAT,
                     "%s: truncated: the header declares %u chunks but the file ends after %u, at offset %zu",
                     name, (unsigned)declared, (unsigned)i, off);
    if (st == SAM_OK && off < size)
        st = sam_fail(err, SAM_ERR_FORMAT,
                      "%s: %zu bytes after the last of the %u declared chunks, at offset %zu", name,
                      size - off, (unsigned)declared, off);
    if (st == SAM_OK)
        st = check_unknown_duplicates(unknown, unknowns, name, err);
    free(unknown);
    if (st != SAM_OK)
        return st;
    for (int t = 0; t < TAG_COUNT; ++t)
        if (t != TAG_UV && !known[t].payload)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: chunk %s is missing (required)", name, k_tags[t]);
    *unknown_count = (uint32_t)unknowns;
    return SAM_OK;
}

static sam_status expect_length(const chunk_ref *c, int tag, uint64_t expected, const char *why,
                                const char *name, sam_error *err)
{
    if (c->length != expected)
        return sam_fail(err, SAM_ERR_CORRUPT, "%s: chunk %s: payload is %zu bytes, expected %llu (%s)", name,
                        k_tags[tag], c->length, (unsigned long long)expected, why);
    return SAM_OK;
}

/* Element count of a chunk made of `elem`-byte records, checked to fit a u32. */
static sam_status record_count(const chunk_ref *c, int tag, size_t elem, const char *what, uint32_t *count,
                               const char *name, sam_error *err)
{
    if (c->length % elem != 0)
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: chunk %s: payload of %zu bytes is not a multiple of %zu (%s)", name, k_tags[tag],
                        c->length, elem, what);
    uint64_t n = c->length / elem;
    if (n > UINT32_MAX)
        return sam_fail(err, SAM_ERR_FORMAT, "%s: chunk %s: %llu records exceed the limit of 4294967295",
                        name, k_tags[tag], (unsigned long long)n);
    *count = (uint32_t)n;
    return SAM_OK;
}

/* Derives the counts from the payload sizes and checks that chunks agree. */
static sam_status check_sizes(const chunk_ref *k, const char *name, samfile_data *d, sam_error *err)
{
    sam_status st;
    uint32_t vc;
    if ((st = record_count(&k[TAG_POS], TAG_POS, 12, "f32 x,y,z per vertex", &vc, name, err)) != SAM_OK)
        return st;
    if (vc == 0)
        return sam_fail(err, SAM_ERR_EMPTY, "%s: chunk POS : no vertices (payload of 0 bytes)", name);
    char why[128];
    snprintf(why, sizeof why, "12 per vertex for the %u vertices of chunk POS ", (unsigned)vc);
    if ((st = expect_length(&k[TAG_NRM], TAG_NRM, (uint64_t)vc * 12u, why, name, err)) != SAM_OK)
        return st;
    if (k[TAG_UV].payload) {
        snprintf(why, sizeof why, "8 per vertex for the %u vertices of chunk POS ", (unsigned)vc);
        if ((st = expect_length(&k[TAG_UV], TAG_UV, (uint64_t)vc * 8u, why, name, err)) != SAM_OK)
            return st;
    }
    snprintf(why, sizeof why, "4 per vertex for the %u vertices of chunk POS ", (unsigned)vc);
    if ((st = expect_length(&k[TAG_FANA], TAG_FANA, (uint64_t)vc * 4u, why, name, err)) != SAM_OK)
        return st;
    snprintf(why, sizeof why, "4 per vertex plus one for the %u vertices of chunk POS ", (unsigned)vc);
    if ((st = expect_length(&k[TAG_ADJO], TAG_ADJO, ((uint64_t)vc + 1u) * 4u, why, name, err)) != SAM_OK)
        return st;

    uint32_t tc;
    if ((st = record_count(&k[TAG_TRI], TAG_TRI, 12, "u32 a,b,c per triangle", &tc, name, err)) != SAM_OK)
        return st;
    if (tc == 0)
        return sam_fail(err, SAM_ERR_EMPTY, "%s: chunk TRI : no triangles (payload of 0 bytes)", name);

    size_t per_sample_row = (size_t)vc * 4u;
    const chunk_ref *sidx = &k[TAG_SIDX];
    if (sidx->length % per_sample_row != 0)
        return sam_fail(
            err, SAM_ERR_FORMAT,
            "%s: chunk SIDX: payload of %zu bytes is not a multiple of %zu (u32 per sample for the %u "
            "vertices of chunk POS )",
            name, sidx->length, per_sample_row, (unsigned)vc);
    size_t n = sidx->length / per_sample_row;
    if (n == 0 || n > SAMFILE_MAX_SAMPLES_PER_VERTEX)
        return sam_fail(
            err, SAM_ERR_CORRUPT,
            "%s: chunk SIDX: %zu samples per vertex (%zu bytes for %u vertices); supported range is 1..%u",
            name, n, sidx->length, (unsigned)vc, SAMFILE_MAX_SAMPLES_PER_VERTEX);
    snprintf(why, sizeof why, "3 f32 for each of the %zu samples of the %u vertices of chunk SIDX", n,
             (unsigned)vc);
    if ((st = expect_length(&k[TAG_SKPR], TAG_SKPR, (uint64_t)vc * n * 12u, why, name, err)) != SAM_OK)
        return st;

    uint32_t adj;
    if ((st = record_count(&k[TAG_ADJV], TAG_ADJV, 4, "u32 per neighbour", &adj, name, err)) != SAM_OK)
        return st;
    const chunk_ref *info = &k[TAG_INFO];
    const void *nul = memchr(info->payload, 0, info->length);
    if (nul)
        return sam_fail(err, SAM_ERR_CORRUPT,
                        "%s: chunk INFO: NUL byte at offset %zu of the %zu-byte JSON text", name,
                        (size_t)((const uint8_t *)nul - info->payload), info->length);
    d->vertex_count = vc;
    d->triangle_count = tc;
    d->samples_per_vertex = (uint32_t)n;
    d->adjacency_count = adj;
    return SAM_OK;
}

static uint32_t *decode_u32(const chunk_ref *c)
{
    size_t count = c->length / 4;
    uint32_t *v = malloc(count * sizeof *v);
    if (v)
        for (size_t i = 0; i < count; ++i)
            v[i] = get_u32(c->payload + 4 * i);
    return v;
}

static float *decode_f32(const chunk_ref *c)
{
    size_t count = c->length / 4;
    float *v = malloc(count * sizeof *v);
    if (v)
        for (size_t i = 0; i < count; ++i)
            v[i] = bits_float(get_u32(c->payload + 4 * i));
    return v;
}

static sam_status decode_arrays(const chunk_ref *k, const char *name, samfile_data *d, sam_error *err)
{
    const chunk_ref *info = &k[TAG_INFO];
    d->info_json = malloc(info->length + 1);
    if (d->info_json) {
        memcpy(d->info_json, info->payload, info->length);
        d->info_json[info->length] = '\0';
    }
    d->positions = decode_f32(&k[TAG_POS]);
    d->normals = decode_f32(&k[TAG_NRM]);
    d->triangles = decode_u32(&k[TAG_TRI]);
    d->sample_index = decode_u32(&k[TAG_SIDX]);
    d->sample_kprime = decode_f32(&k[TAG_SKPR]);
    d->fan_area = decode_f32(&k[TAG_FANA]);
    d->adjacency_offsets = decode_u32(&k[TAG_ADJO]);
    int failed = !d->info_json || !d->positions || !d->normals || !d->triangles || !d->sample_index ||
                 !d->sample_kprime || !d->fan_area || !d->adjacency_offsets;
    if (k[TAG_UV].payload) {
        d->uvs = decode_f32(&k[TAG_UV]);
        failed |= !d->uvs;
    }
    if (d->adjacency_count) {
        d->adjacency = decode_u32(&k[TAG_ADJV]);
        failed |= !d->adjacency;
    }
    if (failed)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory decoding %u vertices", name,
                        (unsigned)d->vertex_count);
    return SAM_OK;
}

sam_status samfile_read_memory(const uint8_t *bytes, size_t size, const char *name, samfile_data *out,
                               sam_error *err)
{
    if (!name)
        name = "<memory>";
    if (!out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: no output given", name);
    memset(out, 0, sizeof *out);
    if (!bytes && size)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: NULL input of %zu bytes", name, size);
    if (!bytes)
        bytes = (const uint8_t *)"";

    chunk_ref known[TAG_COUNT];
    memset(known, 0, sizeof known);
    samfile_data d;
    memset(&d, 0, sizeof d);
    sam_status st = parse_frame(bytes, size, name, known, &d.unknown_chunk_count, err);
    if (st == SAM_OK)
        st = check_sizes(known, name, &d, err);
    if (st == SAM_OK)
        st = decode_arrays(known, name, &d, err);
    if (st == SAM_OK)
        st = validate_data(&d, name, SAM_ERR_CORRUPT, err);
    if (st != SAM_OK) {
        samfile_free(&d);
        return st;
    }
    *out = d;
    return SAM_OK;
}

sam_status samfile_read(const char *path, samfile_data *out, sam_error *err)
{
    if (out)
        memset(out, 0, sizeof *out);
    if (!path || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "samfile read: NULL %s", path ? "output" : "path");
    uint8_t *bytes;
    size_t size;
    sam_status st = sam_read_file(path, &bytes, &size, err);
    if (st != SAM_OK)
        return st;
    st = samfile_read_memory(bytes, size, path, out, err);
    free(bytes);
    return st;
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
    memset(data, 0, sizeof *data);
}
