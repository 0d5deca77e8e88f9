#include "sam/samfile.h"

#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "samfile_internal.h"

/* ---- reading ---- */

static float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
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
    if (version < 1 || version > SAMFILE_VERSION)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "%s: version %u is not supported (this build reads versions 1 to %u)", name,
                        (unsigned)version, SAMFILE_VERSION);
    if (flags != 0)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "%s: header flags 0x%08x are not supported (version %u has none)", name,
                        (unsigned)flags, (unsigned)version);

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
    for (int t = 0; t < TAG_COUNT; ++t) {
        const int tree = t == TAG_NODE || t == TAG_NLVL || t == TAG_STAU;
        if (t != TAG_UV && t != TAG_SRCV && !known[t].payload && (!tree || version >= 2))
            return sam_fail(err, SAM_ERR_FORMAT, "%s: chunk %s is missing (required%s)", name, k_tags[t],
                            tree ? " in version 2" : "");
        if (tree && known[t].payload && version < 2)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: chunk %s at offset %zu is not allowed in version %u", name,
                            k_tags[t], known[t].offset, (unsigned)version);
    }
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
    uint32_t vc = 0;
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

    uint32_t tc = 0;
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

    uint32_t adj = 0;
    if ((st = record_count(&k[TAG_ADJV], TAG_ADJV, 4, "u32 per neighbour", &adj, name, err)) != SAM_OK)
        return st;
    if (k[TAG_NODE].payload) {
        uint32_t nodes = 0, offsets = 0;
        if ((st = record_count(&k[TAG_NODE], TAG_NODE, 8, "u32 child pair per node", &nodes, name, err)) !=
                SAM_OK ||
            (st = record_count(&k[TAG_NLVL], TAG_NLVL, 4, "u32 per level offset", &offsets, name, err)) != SAM_OK)
            return st;
        if (nodes == 0 || offsets < 2)
            return sam_fail(err, SAM_ERR_CORRUPT, "%s: chunk %s: empty tree (%u nodes, %u level offsets)", name,
                            k_tags[nodes == 0 ? TAG_NODE : TAG_NLVL], (unsigned)nodes, (unsigned)offsets);
        d->node_count = nodes;
        d->level_count = offsets - 1;
        snprintf(why, sizeof why, "1 f32 for each of the %zu samples of the %u vertices of chunk SIDX", n, (unsigned)vc);
        if ((st = expect_length(&k[TAG_STAU], TAG_STAU, (uint64_t)vc * n * 4u, why, name, err)) != SAM_OK)
            return st;
    }
    if (k[TAG_SRCV].payload) {
        const chunk_ref *c = &k[TAG_SRCV];
        if (c->length < 4)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: chunk SRCV: payload of %zu bytes has no source vertex count",
                            name, c->length);
        d->source_vertex_count = get_u32(c->payload);
        if (d->source_vertex_count == 0)
            return sam_fail(err, SAM_ERR_CORRUPT, "%s: chunk SRCV: a source mesh of 0 vertices", name);
        snprintf(why, sizeof why, "a u32 count, then 4 for each of the %u vertices of chunk POS  and the %u source "
                 "vertices", (unsigned)vc, (unsigned)d->source_vertex_count);
        if ((st = expect_length(c, TAG_SRCV, 4u + ((uint64_t)vc + d->source_vertex_count) * 4u, why, name, err)) !=
            SAM_OK)
            return st;
    }
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
    if (d->node_count) {
        d->node_children = decode_u32(&k[TAG_NODE]);
        d->level_offsets = decode_u32(&k[TAG_NLVL]);
        d->sample_tau = decode_f32(&k[TAG_STAU]);
        failed |= !d->node_children || !d->level_offsets || !d->sample_tau;
    }
    if (d->source_vertex_count) {
        chunk_ref part = k[TAG_SRCV];
        part.payload += 4;
        part.length = 4 * (size_t)d->vertex_count;
        d->vertex_source = decode_u32(&part);
        part.payload += part.length;
        part.length = 4 * (size_t)d->source_vertex_count;
        d->source_vertex = decode_u32(&part);
        failed |= !d->vertex_source || !d->source_vertex;
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
        st = samfile_check_data(&d, name, SAM_ERR_CORRUPT, err);
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
