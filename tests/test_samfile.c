#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <zlib.h>

#include "sam/samfile.h"
#include "sam_test.h"

/* ---- a small valid mesh: a tetrahedron, n = 2 samples per vertex ---- */

typedef struct tetra {
    char info[512];
    float pos[12], nrm[12], uv[8];
    uint32_t tri[12];
    uint32_t sidx[8];
    float skpr[24];
    float fana[4];
    uint32_t adjo[5];
    uint32_t adjv[12];
    uint32_t children[6], levels[3];
    float tau[8];
    uint32_t vsrc[4], srcv[6];
    samfile_data d;
} tetra;

#define PAD SAMFILE_NO_SAMPLE

static void set_info(tetra *t, const char *vc, const char *tc, const char *n, const char *mm)
{
    snprintf(t->info, sizeof t->info,
             "{\"vertex_count\":%s,\"triangle_count\":%s,\"samples_per_vertex\":%s,\"mm_per_unit\":%s,"
             "\"material\":{\"name\":\"marble\",\"sigma_a\":[0.0021,0.0041,0.0071]}}",
             vc, tc, n, mm);
}

static void make_tetra(tetra *t, int with_uv)
{
    memset(t, 0, sizeof *t);
    static const float corners[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t tri[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    static const uint32_t sidx[8] = {1, 2, 2, PAD, PAD, PAD, 0, 1};
    static const float fana[4] = {1.0f, 1.25f, 1.5f, 1.75f};
    static const uint32_t adjo[5] = {0, 3, 6, 9, 12};
    static const uint32_t adjv[12] = {1, 2, 3, 0, 3, 2, 0, 1, 3, 0, 2, 1};
    set_info(t, "4", "4", "2", "0.5");
    memcpy(t->pos, corners, sizeof corners);
    for (int i = 0; i < 12; ++i)
        t->nrm[i] = corners[i] / sqrtf(3.0f);
    for (int i = 0; i < 8; ++i)
        t->uv[i] = 0.125f * (float)i;
    memcpy(t->tri, tri, sizeof tri);
    memcpy(t->sidx, sidx, sizeof sidx);
    for (int i = 0; i < 24; ++i)
        t->skpr[i] = 0.01f * (float)(i + 1);
    memcpy(t->fana, fana, sizeof fana);
    memcpy(t->adjo, adjo, sizeof adjo);
    memcpy(t->adjv, adjv, sizeof adjv);
    t->d = (samfile_data){
        .vertex_count = 4,
        .triangle_count = 4,
        .samples_per_vertex = 2,
        .info_json = t->info,
        .positions = t->pos,
        .normals = t->nrm,
        .uvs = with_uv ? t->uv : NULL,
        .triangles = t->tri,
        .sample_index = t->sidx,
        .sample_kprime = t->skpr,
        .fan_area = t->fana,
        .adjacency_offsets = t->adjo,
        .adjacency_count = 12,
        .adjacency = t->adjv,
    };
}

/* Makes t a cut map (version 2): a tree of 3 nodes over the 4 vertices,
 * the root's children two nodes of two vertices each, and vertex 0's first
 * sample the node over vertices 2 and 3, read 0.25 along its split. */
static void add_tree(tetra *t)
{
    static const uint32_t children[6] = {4 + 1, 4 + 2, 0, 1, 2, 3}, levels[3] = {0, 1, 3};
    memcpy(t->children, children, sizeof children);
    memcpy(t->levels, levels, sizeof levels);
    memset(t->tau, 0, sizeof t->tau);
    t->sidx[0] = 4 + 2;
    t->tau[0] = 0.25f;
    t->d.node_count = 3;
    t->d.node_children = t->children;
    t->d.level_count = 2;
    t->d.level_offsets = t->levels;
    t->d.sample_tau = t->tau;
}

/* Gives t the SRCV chunk of a source mesh of 6 vertices: one that no
 * triangle kept, and two that became the same vertex. */
static void add_sources(tetra *t)
{
    static const uint32_t vsrc[4] = {0, 1, 3, 4}, srcv[6] = {0, 1, PAD, 2, 3, 1};
    memcpy(t->vsrc, vsrc, sizeof vsrc);
    memcpy(t->srcv, srcv, sizeof srcv);
    t->d.source_vertex_count = 6;
    t->d.vertex_source = t->vsrc;
    t->d.source_vertex = t->srcv;
}

/* ---- an encoder written independently of the module, to build any file ---- */

typedef struct chunk_spec {
    char tag[4];
    uint8_t *payload;
    size_t len;
} chunk_spec;

typedef struct chunk_list {
    chunk_spec c[16];
    size_t count;
} chunk_list;

typedef struct bytes {
    uint8_t *p;
    size_t n;
} bytes;

static void le32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; ++i)
        p[i] = (uint8_t)(v >> (8 * i));
}

static void insert_chunk(chunk_list *l, size_t at, const char *tag, const void *payload, size_t len)
{
    assert_true(l->count < 16 && at <= l->count);
    memmove(&l->c[at + 1], &l->c[at], (l->count - at) * sizeof l->c[0]);
    chunk_spec *c = &l->c[at];
    memcpy(c->tag, tag, 4);
    c->payload = malloc(len + 1);
    assert_non_null(c->payload);
    if (len)
        memcpy(c->payload, payload, len);
    c->len = len;
    l->count++;
}

static void add_u32s(chunk_list *l, const char *tag, const uint32_t *v, size_t count)
{
    uint8_t *p = malloc(4 * count + 1);
    assert_non_null(p);
    for (size_t i = 0; i < count; ++i)
        le32(p + 4 * i, v[i]);
    insert_chunk(l, l->count, tag, p, 4 * count);
    free(p);
}

static void add_f32s(chunk_list *l, const char *tag, const float *v, size_t count)
{
    uint32_t *u = malloc(4 * count + 1);
    assert_non_null(u);
    if (count)
        memcpy(u, v, 4 * count);
    add_u32s(l, tag, u, count);
    free(u);
}

static void list_from_data(const samfile_data *d, chunk_list *l)
{
    memset(l, 0, sizeof *l);
    size_t vc = d->vertex_count, n = d->samples_per_vertex;
    insert_chunk(l, 0, "INFO", d->info_json, strlen(d->info_json));
    add_f32s(l, "POS ", d->positions, 3 * vc);
    add_f32s(l, "NRM ", d->normals, 3 * vc);
    if (d->uvs)
        add_f32s(l, "UV  ", d->uvs, 2 * vc);
    add_u32s(l, "TRI ", d->triangles, 3 * (size_t)d->triangle_count);
    add_u32s(l, "SIDX", d->sample_index, n * vc);
    add_f32s(l, "SKPR", d->sample_kprime, 3 * n * vc);
    add_f32s(l, "FANA", d->fan_area, vc);
    add_u32s(l, "ADJO", d->adjacency_offsets, vc + 1);
    add_u32s(l, "ADJV", d->adjacency, d->adjacency_count);
    if (d->node_count) {
        add_u32s(l, "NODE", d->node_children, 2 * (size_t)d->node_count);
        add_u32s(l, "NLVL", d->level_offsets, (size_t)d->level_count + 1);
        add_f32s(l, "STAU", d->sample_tau, n * vc);
    }
    if (d->vertex_source) {
        uint32_t *all = malloc((1 + vc + d->source_vertex_count) * sizeof *all);
        assert_non_null(all);
        all[0] = d->source_vertex_count;
        memcpy(all + 1, d->vertex_source, vc * sizeof *all);
        memcpy(all + 1 + vc, d->source_vertex, d->source_vertex_count * sizeof *all);
        add_u32s(l, "SRCV", all, 1 + vc + d->source_vertex_count);
        free(all);
    }
}

static size_t find_chunk(const chunk_list *l, const char *tag)
{
    for (size_t i = 0; i < l->count; ++i)
        if (memcmp(l->c[i].tag, tag, 4) == 0)
            return i;
    fail_msg("no chunk %s", tag);
    return 0;
}

static void remove_chunk(chunk_list *l, size_t at)
{
    free(l->c[at].payload);
    memmove(&l->c[at], &l->c[at + 1], (l->count - at - 1) * sizeof l->c[0]);
    l->count--;
}

static void replace_payload(chunk_list *l, const char *tag, const void *payload, size_t len)
{
    size_t at = find_chunk(l, tag);
    remove_chunk(l, at);
    insert_chunk(l, at, tag, payload, len);
}

static void free_list(chunk_list *l)
{
    while (l->count)
        remove_chunk(l, l->count - 1);
}

/* Encodes the chunks with correct CRCs and header count; `offsets` (may be
 * NULL) receives each chunk's file offset. */
static bytes encode(const chunk_list *l, size_t *offsets)
{
    size_t total = 16;
    for (size_t i = 0; i < l->count; ++i)
        total += 16 + (l->c[i].len + 7) / 8 * 8 + 8;
    bytes b = {calloc(1, total), total};
    assert_non_null(b.p);
    memcpy(b.p, "SAMF", 4);
    int tree = 0;
    for (size_t i = 0; i < l->count; ++i)
        tree |= memcmp(l->c[i].tag, "NODE", 4) == 0;
    le32(b.p + 4, tree ? 2 : 1);
    le32(b.p + 8, (uint32_t)l->count);
    size_t off = 16;
    for (size_t i = 0; i < l->count; ++i) {
        const chunk_spec *c = &l->c[i];
        if (offsets)
            offsets[i] = off;
        memcpy(b.p + off, c->tag, 4);
        le32(b.p + off + 8, (uint32_t)c->len);
        le32(b.p + off + 12, (uint32_t)((uint64_t)c->len >> 32));
        off += 16;
        if (c->len)
            memcpy(b.p + off, c->payload, c->len);
        off += (c->len + 7) / 8 * 8;
        le32(b.p + off, (uint32_t)crc32(0, c->payload, (uInt)c->len));
        off += 8;
    }
    assert_int_equal(off, total);
    return b;
}

static bytes encode_data(const samfile_data *d)
{
    chunk_list l;
    list_from_data(d, &l);
    bytes b = encode(&l, NULL);
    free_list(&l);
    return b;
}

static int is_zeroed(const samfile_data *d)
{
    samfile_data zero;
    memset(&zero, 0, sizeof zero);
    return memcmp(d, &zero, sizeof zero) == 0;
}

/* Reads `b` named "t.sam"; returns the status and leaves the message in err. */
static sam_status read_bytes(const bytes *b, sam_error *err)
{
    samfile_data d;
    sam_status st = samfile_read_memory(b->p, b->n, "t.sam", &d, err);
    if (st != SAM_OK && !is_zeroed(&d))
        fail_msg("failed read left data behind: %s", err->message);
    samfile_free(&d);
    return st;
}

static void expect_read_error(const bytes *b, sam_status status, const char *needle)
{
    sam_error err;
    sam_error_clear(&err);
    sam_status st = read_bytes(b, &err);
    if (st != status || !strstr(err.message, needle))
        fail_msg("expected %s with \"%s\", got %s: \"%s\"", sam_status_name(status), needle,
                 sam_status_name(st), err.message);
}

static void expect_same_data(const samfile_data *a, const samfile_data *b)
{
    size_t vc = a->vertex_count, n = a->samples_per_vertex;
    assert_int_equal(a->vertex_count, b->vertex_count);
    assert_int_equal(a->triangle_count, b->triangle_count);
    assert_int_equal(a->samples_per_vertex, b->samples_per_vertex);
    assert_int_equal(a->adjacency_count, b->adjacency_count);
    assert_string_equal(a->info_json, b->info_json);
    assert_memory_equal(a->positions, b->positions, 12 * vc);
    assert_memory_equal(a->normals, b->normals, 12 * vc);
    assert_int_equal(a->uvs == NULL, b->uvs == NULL);
    if (a->uvs)
        assert_memory_equal(a->uvs, b->uvs, 8 * vc);
    assert_memory_equal(a->triangles, b->triangles, 12 * (size_t)a->triangle_count);
    assert_memory_equal(a->sample_index, b->sample_index, 4 * n * vc);
    assert_memory_equal(a->sample_kprime, b->sample_kprime, 12 * n * vc);
    assert_memory_equal(a->fan_area, b->fan_area, 4 * vc);
    assert_memory_equal(a->adjacency_offsets, b->adjacency_offsets, 4 * (vc + 1));
    assert_memory_equal(a->adjacency, b->adjacency, 4 * (size_t)a->adjacency_count);
    assert_int_equal(a->source_vertex_count, b->source_vertex_count);
    assert_int_equal(a->vertex_source == NULL, b->vertex_source == NULL);
    if (a->vertex_source) {
        assert_memory_equal(a->vertex_source, b->vertex_source, 4 * vc);
        assert_memory_equal(a->source_vertex, b->source_vertex, 4 * (size_t)a->source_vertex_count);
    }
}

static bytes load(const char *path)
{
    bytes b;
    sam_error err;
    if (sam_read_file(path, &b.p, &b.n, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return b;
}

/* ---- round trips and the exact layout ---- */

static void round_trip(int with_uv)
{
    tetra t;
    make_tetra(&t, with_uv);
    char path[512], again[512];
    sam_test_tmp_path(path, sizeof path, with_uv ? "samfile_rt_uv.sam" : "samfile_rt.sam");
    sam_test_tmp_path(again, sizeof again, with_uv ? "samfile_rt_uv2.sam" : "samfile_rt2.sam");
    sam_error err;
    assert_int_equal(samfile_write(path, &t.d, &err), SAM_OK);

    samfile_data d;
    if (samfile_read(path, &d, &err) != SAM_OK)
        fail_msg("%s", err.message);
    expect_same_data(&t.d, &d);
    assert_int_equal(d.unknown_chunk_count, 0);
    assert_int_equal(samfile_write(again, &d, &err), SAM_OK);
    samfile_free(&d);
    assert_true(is_zeroed(&d));

    bytes first = load(path), second = load(again), independent = encode_data(&t.d);
    assert_int_equal(first.n, second.n);
    assert_memory_equal(first.p, second.p, first.n);
    /* The module's writer and this file's encoder agree byte for byte. */
    assert_int_equal(first.n, independent.n);
    assert_memory_equal(first.p, independent.p, first.n);
    free(first.p);
    free(second.p);
    free(independent.p);
}

static void test_round_trip_without_uv(void **state)
{
    (void)state;
    round_trip(0);
}

static void test_round_trip_with_uv(void **state)
{
    (void)state;
    round_trip(1);
}

static void test_on_disk_layout(void **state)
{
    (void)state;
    tetra t;
    make_tetra(&t, 0);
    strcpy(t.info, "{\"vertex_count\":4,\"triangle_count\":4,\"samples_per_vertex\":2,\"mm_per_unit\":1}");
    size_t info_len = strlen(t.info); /* 76 bytes: 4 of padding to 80 */
    assert_int_equal(info_len, 76);
    char path[512];
    sam_test_tmp_path(path, sizeof path, "samfile_layout.sam");
    assert_int_equal(samfile_write(path, &t.d, NULL), SAM_OK);
    bytes b = load(path);

    static const uint8_t head[32] = {
        'S', 'A', 'M', 'F', 1, 0, 0, 0, 9,  0, 0, 0, 0, 0, 0, 0, /* magic, version, 9 chunks, flags */
        'I', 'N', 'F', 'O', 0, 0, 0, 0, 76, 0, 0, 0, 0, 0, 0, 0, /* tag, reserved, u64 length */
    };
    assert_true(b.n > 32 + 80 + 8 + 16 + 4);
    assert_memory_equal(b.p, head, sizeof head);
    assert_memory_equal(b.p + 32, t.info, info_len);
    static const uint8_t zero_pad[4] = {0, 0, 0, 0};
    assert_memory_equal(b.p + 32 + 76, zero_pad, 4);
    uint32_t crc = (uint32_t)crc32(0, (const Bytef *)t.info, (uInt)info_len);
    const uint8_t trailer[8] = {
        (uint8_t)crc, (uint8_t)(crc >> 8), (uint8_t)(crc >> 16), (uint8_t)(crc >> 24), 0, 0, 0, 0};
    assert_memory_equal(b.p + 112, trailer, 8);
    /* POS follows: 48 payload bytes, and its first float 1.0f is 0x3f800000. */
    static const uint8_t pos_head[20] = {'P', 'O', 'S', ' ', 0, 0, 0,    0,    48,   0,
                                         0,   0,   0,   0,   0, 0, 0x00, 0x00, 0x80, 0x3f};
    assert_memory_equal(b.p + 120, pos_head, sizeof pos_head);
    free(b.p);
}

/* ---- damage: truncation and single-byte flips ---- */

static void test_every_truncated_prefix_fails(void **state)
{
    (void)state;
    for (int kind = 0; kind < 4; ++kind) {
        tetra t;
        make_tetra(&t, kind & 1);
        if (kind & 2)
            add_tree(&t);
        bytes b = encode_data(&t.d);
        sam_error err;
        assert_int_equal(read_bytes(&b, &err), SAM_OK);
        for (size_t n = 0; n < b.n; ++n) {
            bytes prefix = {b.p, n};
            expect_read_error(&prefix, SAM_ERR_FORMAT, "truncated");
        }
        free(b.p);
    }
}

/*
 * Why every flip is caught: a flipped byte in a payload fails its CRC (CRC-32
 * detects every error within 32 bits); in the file header it breaks the
 * magic, version, flags or the chunk count (which must match the chunks
 * present, with no bytes after them); in padding, reserved or trailer fields
 * they must be zero; in a stored CRC it mismatches; in a payload length it
 * runs past the file or changes that chunk's element count, which every
 * required chunk cross-checks against INFO or POS (INFO's own text must end
 * at its closing brace and hold no NUL); in a tag, the chunk becomes unknown
 * and a required chunk goes missing (NODE, NLVL and STAU are required in
 * version 2, refused in version 1), or it duplicates another tag. The one
 * exception is the optional UV chunk: a damaged UV tag reads as an unknown
 * chunk and the file loads without UVs.
 */
static void test_every_single_byte_flip_fails(void **state)
{
    (void)state;
    for (int kind = 0; kind < 4; ++kind) {
        const int with_uv = kind & 1;
        tetra t;
        make_tetra(&t, with_uv);
        if (kind & 2)
            add_tree(&t);
        chunk_list l;
        list_from_data(&t.d, &l);
        size_t offsets[16];
        bytes b = encode(&l, offsets);
        size_t uv_tag = with_uv ? offsets[find_chunk(&l, "UV  ")] : 0;
        free_list(&l);
        static const uint8_t masks[2] = {0x01, 0xFF};
        for (size_t pos = 0; pos < b.n; ++pos) {
            for (int m = 0; m < 2; ++m) {
                b.p[pos] ^= masks[m];
                samfile_data d;
                sam_error err;
                sam_status st = samfile_read_memory(b.p, b.n, "t.sam", &d, &err);
                if (with_uv && pos >= uv_tag && pos < uv_tag + 4) {
                    assert_int_equal(st, SAM_OK);
                    assert_int_equal(d.unknown_chunk_count, 1);
                    assert_null(d.uvs);
                } else if (st == SAM_OK) {
                    fail_msg("flip 0x%02x at byte %zu of %zu was not detected (uv %d)", masks[m], pos, b.n,
                             with_uv);
                } else {
                    assert_true(is_zeroed(&d));
                    assert_non_null(strstr(err.message, "t.sam: "));
                }
                samfile_free(&d);
                b.p[pos] ^= masks[m];
            }
        }
        free(b.p);
    }
}

/* ---- framing errors ---- */

static bytes tetra_bytes(void)
{
    tetra t;
    make_tetra(&t, 0);
    return encode_data(&t.d);
}

static void test_header_errors(void **state)
{
    (void)state;
    bytes b = tetra_bytes();
    b.p[3] = 'G';
    expect_read_error(&b, SAM_ERR_FORMAT, "t.sam: not a .sam file: magic is \"SAMG\", expected \"SAMF\"");
    b.p[3] = 'F';
    b.p[4] = 3;
    expect_read_error(&b, SAM_ERR_UNSUPPORTED,
                      "t.sam: version 3 is not supported (this build reads versions 1 to 2)");
    b.p[4] = 2; /* a flat map's chunks without the tree version 2 needs */
    expect_read_error(&b, SAM_ERR_FORMAT, "t.sam: chunk NODE is missing (required in version 2)");
    b.p[4] = 1;
    b.p[12] = 4;
    expect_read_error(&b, SAM_ERR_UNSUPPORTED, "t.sam: header flags 0x00000004 are not supported");
    b.p[12] = 0;
    b.p[8] = 10;
    expect_read_error(&b, SAM_ERR_FORMAT,
                      "t.sam: truncated: the header declares 10 chunks but the file ends after 9, at offset");
    b.p[8] = 8;
    expect_read_error(&b, SAM_ERR_FORMAT, "bytes after the last of the 8 declared chunks");
    b.p[8] = 9;
    sam_error err;
    assert_int_equal(read_bytes(&b, &err), SAM_OK);
    free(b.p);
}

static void test_chunk_framing_errors(void **state)
{
    (void)state;
    tetra t;
    make_tetra(&t, 0);
    chunk_list l;
    list_from_data(&t.d, &l);
    size_t off[16];
    bytes b = encode(&l, off);
    size_t pos = off[find_chunk(&l, "POS ")], info = off[0];
    char expect[256];

    b.p[pos + 5] = 1;
    snprintf(expect, sizeof expect,
             "t.sam: chunk POS  at offset %zu: reserved field is 0x00000100, expected 0", pos);
    expect_read_error(&b, SAM_ERR_FORMAT, expect);
    b.p[pos + 5] = 0;

    memset(b.p + pos + 8, 0xFF, 8);
    expect_read_error(&b, SAM_ERR_FORMAT, "t.sam: truncated: chunk POS  at offset");
    expect_read_error(&b, SAM_ERR_FORMAT, "declares 18446744073709551615 payload bytes but only");
    memset(b.p + pos + 8, 0, 8);
    b.p[pos + 8] = 48;

    /* INFO's text is not a multiple of 8 long, so it has padding. */
    size_t info_len = l.c[0].len;
    assert_true(info_len % 8 != 0);
    b.p[info + 16 + info_len] = 0x20;
    snprintf(expect, sizeof expect, "t.sam: chunk INFO at offset %zu: padding byte 0 is 0x20, expected 0",
             info);
    expect_read_error(&b, SAM_ERR_FORMAT, expect);
    b.p[info + 16 + info_len] = 0;

    size_t pos_crc = pos + 16 + 48;
    b.p[pos_crc + 4] = 7;
    expect_read_error(&b, SAM_ERR_FORMAT, "t.sam: chunk POS  at offset");
    expect_read_error(&b, SAM_ERR_FORMAT, "field after the CRC is 0x00000007, expected 0");
    b.p[pos_crc + 4] = 0;

    uint32_t stored = (uint32_t)crc32(0, l.c[1].payload, 48);
    b.p[pos + 16] ^= 0x40;
    uint32_t computed = (uint32_t)crc32(0, b.p + pos + 16, 48);
    snprintf(expect, sizeof expect, "t.sam: chunk POS : CRC mismatch (stored 0x%08x, computed 0x%08x)",
             (unsigned)stored, (unsigned)computed);
    expect_read_error(&b, SAM_ERR_CORRUPT, expect);
    b.p[pos + 16] ^= 0x40;

    sam_error err;
    assert_int_equal(read_bytes(&b, &err), SAM_OK);
    free(b.p);
    free_list(&l);
}

static void test_missing_and_duplicate_chunks(void **state)
{
    (void)state;
    static const char *required[] = {"INFO", "POS ", "NRM ", "TRI ", "SIDX", "SKPR", "FANA", "ADJO", "ADJV"};
    tetra t;
    make_tetra(&t, 1);
    for (size_t i = 0; i < 9; ++i) {
        chunk_list l;
        list_from_data(&t.d, &l);
        remove_chunk(&l, find_chunk(&l, required[i]));
        bytes b = encode(&l, NULL);
        char expect[128];
        snprintf(expect, sizeof expect, "t.sam: chunk %s is missing (required)", required[i]);
        expect_read_error(&b, SAM_ERR_FORMAT, expect);
        free(b.p);
        free_list(&l);
    }

    chunk_list l;
    list_from_data(&t.d, &l);
    size_t f = find_chunk(&l, "FANA");
    insert_chunk(&l, l.count, "FANA", l.c[f].payload, l.c[f].len);
    size_t off[16];
    bytes b = encode(&l, off);
    char expect[128];
    snprintf(expect, sizeof expect, "t.sam: chunk FANA at offset %zu repeats the chunk at offset %zu",
             off[l.count - 1], off[f]);
    expect_read_error(&b, SAM_ERR_FORMAT, expect);
    free(b.p);
    free_list(&l);

    list_from_data(&t.d, &l);
    insert_chunk(&l, 2, "CURV", "abc", 3);
    insert_chunk(&l, 5, "CURV", "abcd", 4);
    b = encode(&l, off);
    snprintf(expect, sizeof expect, "t.sam: chunk CURV at offset %zu repeats the chunk at offset %zu", off[5],
             off[2]);
    expect_read_error(&b, SAM_ERR_FORMAT, expect);
    free(b.p);
    free_list(&l);
}

static void test_unknown_chunks_are_skipped_and_counted(void **state)
{
    (void)state;
    tetra t;
    make_tetra(&t, 1);
    chunk_list l;
    list_from_data(&t.d, &l);
    insert_chunk(&l, 3, "CURV", "curvature", 9);
    insert_chunk(&l, l.count, "\x01z\xff ", "", 0);
    bytes b = encode(&l, NULL);
    free_list(&l);

    samfile_data d;
    sam_error err;
    if (samfile_read_memory(b.p, b.n, "t.sam", &d, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(d.unknown_chunk_count, 2);
    expect_same_data(&t.d, &d);

    /* Unknown chunks are not kept: a rewrite is the canonical file. */
    char path[512];
    sam_test_tmp_path(path, sizeof path, "samfile_unknown.sam");
    assert_int_equal(samfile_write(path, &d, &err), SAM_OK);
    samfile_free(&d);
    bytes rewritten = load(path), canonical = encode_data(&t.d);
    assert_int_equal(rewritten.n, canonical.n);
    assert_memory_equal(rewritten.p, canonical.p, canonical.n);
    free(rewritten.p);
    free(canonical.p);
    free(b.p);
}

/* ---- payload sizes that disagree between chunks (read only) ---- */

static void expect_resized(const char *tag, size_t len, sam_status status, const char *needle)
{
    tetra t;
    make_tetra(&t, 1);
    chunk_list l;
    list_from_data(&t.d, &l);
    uint8_t *payload = calloc(1, len + 1);
    assert_non_null(payload);
    size_t old = l.c[find_chunk(&l, tag)].len;
    memcpy(payload, l.c[find_chunk(&l, tag)].payload, len < old ? len : old);
    replace_payload(&l, tag, payload, len);
    free(payload);
    bytes b = encode(&l, NULL);
    expect_read_error(&b, status, needle);
    free(b.p);
    free_list(&l);
}

static void test_payload_sizes_must_agree(void **state)
{
    (void)state;
    expect_resized("POS ", 47, SAM_ERR_FORMAT,
                   "t.sam: chunk POS : payload of 47 bytes is not a multiple of 12 (f32 x,y,z per vertex)");
    expect_resized("POS ", 0, SAM_ERR_EMPTY, "t.sam: chunk POS : no vertices");
    expect_resized("NRM ", 36, SAM_ERR_CORRUPT,
                   "t.sam: chunk NRM : payload is 36 bytes, expected 48 (12 per vertex for the 4 vertices of "
                   "chunk POS )");
    expect_resized("UV  ", 40, SAM_ERR_CORRUPT, "t.sam: chunk UV  : payload is 40 bytes, expected 32");
    expect_resized("FANA", 12, SAM_ERR_CORRUPT, "t.sam: chunk FANA: payload is 12 bytes, expected 16");
    expect_resized("ADJO", 16, SAM_ERR_CORRUPT, "t.sam: chunk ADJO: payload is 16 bytes, expected 20");
    expect_resized("TRI ", 40, SAM_ERR_FORMAT,
                   "t.sam: chunk TRI : payload of 40 bytes is not a multiple of 12");
    expect_resized("TRI ", 0, SAM_ERR_EMPTY, "t.sam: chunk TRI : no triangles");
    expect_resized("TRI ", 24, SAM_ERR_CORRUPT,
                   "t.sam: chunk INFO: triangle_count 4 disagrees with chunk TRI  (2 triangles)");
    expect_resized("SIDX", 36, SAM_ERR_FORMAT,
                   "t.sam: chunk SIDX: payload of 36 bytes is not a multiple of 16");
    expect_resized("SIDX", 0, SAM_ERR_CORRUPT, "t.sam: chunk SIDX: 0 samples per vertex");
    expect_resized(
        "SIDX", 65 * 16, SAM_ERR_CORRUPT,
        "t.sam: chunk SIDX: 65 samples per vertex (1040 bytes for 4 vertices); supported range is 1..64");
    expect_resized("SKPR", 72, SAM_ERR_CORRUPT, "t.sam: chunk SKPR: payload is 72 bytes, expected 96");
    expect_resized("ADJV", 46, SAM_ERR_FORMAT,
                   "t.sam: chunk ADJV: payload of 46 bytes is not a multiple of 4");
    expect_resized("ADJV", 44, SAM_ERR_CORRUPT,
                   "t.sam: chunk ADJO: last offset 12 disagrees with chunk ADJV (11 entries)");

    /* A NUL inside INFO, as a damaged length reaching into padding would give. */
    tetra t;
    make_tetra(&t, 0);
    chunk_list l;
    list_from_data(&t.d, &l);
    size_t len = strlen(t.info);
    replace_payload(&l, "INFO", t.info, len + 1);
    bytes b = encode(&l, NULL);
    char expect[128];
    snprintf(expect, sizeof expect, "t.sam: chunk INFO: NUL byte at offset %zu of the %zu-byte JSON text",
             len, len + 1);
    expect_read_error(&b, SAM_ERR_CORRUPT, expect);
    free(b.p);
    free_list(&l);
}

/* ---- semantic violations: validate, read and write all refuse them ---- */

static void v_vc_mismatch(tetra *t) { set_info(t, "5", "4", "2", "0.5"); }
static void v_vc_fraction(tetra *t) { set_info(t, "4.5", "4", "2", "0.5"); }
static void v_tc_mismatch(tetra *t) { set_info(t, "4", "3", "2", "0.5"); }
static void v_n_mismatch(tetra *t) { set_info(t, "4", "4", "3", "0.5"); }
static void v_vc_string(tetra *t) { set_info(t, "\"4\"", "4", "2", "0.5"); }
static void v_mm_zero(tetra *t) { set_info(t, "4", "4", "2", "0"); }
static void v_mm_negative(tetra *t) { set_info(t, "4", "4", "2", "-2.5"); }
static void v_mm_infinite(tetra *t) { set_info(t, "4", "4", "2", "1e999"); }
static void v_mm_missing(tetra *t)
{
    strcpy(t->info, "{\"vertex_count\":4,\"triangle_count\":4,\"samples_per_vertex\":2}");
}
static void v_json_syntax(tetra *t) { strcpy(t->info, "{\"vertex_count\":4,}"); }
static void v_json_space(tetra *t) { strcat(t->info, "\n"); }
static void v_json_array(tetra *t) { strcpy(t->info, "[4,4,2]"); }
static void v_json_two(tetra *t) { strcat(t->info, "{}"); }
static void v_json_empty(tetra *t) { t->info[0] = '\0'; }
static void v_json_utf8(tetra *t) { strcpy(t->info, "{\"name\":\"caf\xc3\x28\"}"); }
static void v_json_overlong(tetra *t) { strcpy(t->info, "{\"name\":\"\xc0\xaf\"}"); }
static void v_pos_nan(tetra *t) { t->pos[5] = NAN; }
static void v_nrm_inf(tetra *t) { t->nrm[9] = -INFINITY; }
static void v_nrm_long(tetra *t)
{
    for (int i = 6; i < 9; ++i)
        t->nrm[i] *= 1.01f;
}
static void v_uv_nan(tetra *t) { t->uv[7] = NAN; }
static void v_tri_range(tetra *t) { t->tri[4] = 4; }
static void v_sidx_range(tetra *t) { t->sidx[3] = 7; }
static void v_sidx_after_pad(tetra *t) { t->sidx[5] = 3; }
static void v_skpr_negative(tetra *t) { t->skpr[7] = -0.5f; }
static void v_skpr_nan(tetra *t) { t->skpr[23] = NAN; }
static void v_fana_negative(tetra *t) { t->fana[3] = -1.0f; }
static void v_fana_inf(tetra *t) { t->fana[0] = INFINITY; }
static void v_adjo_first(tetra *t) { t->adjo[0] = 1; }
static void v_adjo_decreasing(tetra *t) { t->adjo[2] = 2; }
static void v_adjo_last(tetra *t) { t->adjo[4] = 11; }
static void v_adjv_range(tetra *t) { t->adjv[5] = 9; }
static void v_no_vertices(tetra *t) { t->d.vertex_count = 0; }
static void v_no_triangles(tetra *t) { t->d.triangle_count = 0; }

typedef struct violation {
    void (*mutate)(tetra *t);
    int empty;           /* SAM_ERR_EMPTY everywhere instead of invalid argument / corrupt */
    const char *message; /* after the "<name>: " prefix */
} violation;

static const violation k_violations[] = {
    {v_vc_mismatch, 0, "chunk INFO: vertex_count 5 disagrees with chunk POS  (4 vertices)"},
    {v_vc_fraction, 0, "chunk INFO: vertex_count 4.5 disagrees with chunk POS  (4 vertices)"},
    {v_tc_mismatch, 0, "chunk INFO: triangle_count 3 disagrees with chunk TRI  (4 triangles)"},
    {v_n_mismatch, 0, "chunk INFO: samples_per_vertex 3 disagrees with chunk SIDX (2 samples per vertex)"},
    {v_vc_string, 0, "chunk INFO: key \"vertex_count\" is not a number"},
    {v_mm_zero, 0, "chunk INFO: mm_per_unit 0 must be finite and > 0"},
    {v_mm_negative, 0, "chunk INFO: mm_per_unit -2.5 must be finite and > 0"},
    {v_mm_infinite, 0, "chunk INFO: mm_per_unit inf must be finite and > 0"},
    {v_mm_missing, 0, "chunk INFO: key \"mm_per_unit\" is missing"},
    {v_json_syntax, 0, "chunk INFO: JSON syntax error at byte 18 of 19"},
    {v_json_space, 0, "chunk INFO: JSON text must be one object from '{' to '}'"},
    {v_json_array, 0,
     "chunk INFO: JSON text must be one object from '{' to '}' (7 bytes, first 0x5b, last 0x5d)"},
    {v_json_two, 0, "chunk INFO: unexpected text after the JSON object at byte"},
    {v_json_empty, 0, "chunk INFO: JSON text is empty"},
    {v_json_utf8, 0, "chunk INFO: invalid UTF-8 at byte 12 (0xc3)"},
    {v_json_overlong, 0, "chunk INFO: invalid UTF-8 at byte 9 (0xc0)"},
    {v_pos_nan, 0, "chunk POS : component 2 of the position of vertex 1 is not finite (nan)"},
    {v_nrm_inf, 0, "chunk NRM : component 0 of the normal of vertex 3 is not finite (-inf)"},
    {v_nrm_long, 0, "chunk NRM : normal of vertex 2 has length 1.01 (expected 1 within 0.001)"},
    {v_uv_nan, 0, "chunk UV  : component 1 of the uv of vertex 3 is not finite (nan)"},
    {v_tri_range, 0, "chunk TRI : index 4 of triangle 1 is out of range (vertex_count 4)"},
    {v_sidx_range, 0, "chunk SIDX: sample index 7 of vertex 1 is out of range (vertex_count 4)"},
    {v_sidx_after_pad, 0,
     "chunk SIDX: vertex 2 has sample index 3 in slot 1 after a pad (0xFFFFFFFF) in slot 0"},
    {v_skpr_negative, 0,
     "chunk SKPR: K' channel 1 of sample 0 of vertex 1 is -0.5 (must be finite and >= 0)"},
    {v_skpr_nan, 0, "chunk SKPR: K' channel 2 of sample 1 of vertex 3 is nan"},
    {v_fana_negative, 0, "chunk FANA: fan area of vertex 3 is -1 (must be finite and >= 0)"},
    {v_fana_inf, 0, "chunk FANA: fan area of vertex 0 is inf"},
    {v_adjo_first, 0, "chunk ADJO: first offset is 1, expected 0"},
    {v_adjo_decreasing, 0, "chunk ADJO: offset 2 of vertex 2 is below offset 3 of vertex 1"},
    {v_adjo_last, 0, "chunk ADJO: last offset 11 disagrees with chunk ADJV (12 entries)"},
    {v_adjv_range, 0, "chunk ADJV: neighbour 9 at entry 5 (vertex 1) is out of range (vertex_count 4)"},
    {v_no_vertices, 1, "chunk POS : no vertices"},
    {v_no_triangles, 1, "chunk TRI : no triangles"},
};

static void test_semantic_violations(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "samfile_invalid.sam");
    remove(path);
    for (size_t i = 0; i < sizeof k_violations / sizeof k_violations[0]; ++i) {
        const violation *v = &k_violations[i];
        tetra t;
        make_tetra(&t, 1);
        v->mutate(&t);
        char expect[1100];
        sam_error err;

        sam_status st = samfile_validate(&t.d, &err);
        snprintf(expect, sizeof expect, "samfile data: %s", v->message);
        sam_status want = v->empty ? SAM_ERR_EMPTY : SAM_ERR_INVALID_ARGUMENT;
        if (st != want || !strstr(err.message, expect))
            fail_msg("validate %zu: expected \"%s\", got %s: \"%s\"", i, expect, sam_status_name(st),
                     err.message);

        bytes b = encode_data(&t.d);
        snprintf(expect, sizeof expect, "t.sam: %s", v->message);
        expect_read_error(&b, v->empty ? SAM_ERR_EMPTY : SAM_ERR_CORRUPT, expect);
        free(b.p);

        st = samfile_write(path, &t.d, &err);
        snprintf(expect, sizeof expect, "%s: %s", path, v->message);
        if (st != want || !strstr(err.message, expect))
            fail_msg("write %zu: expected \"%s\", got %s: \"%s\"", i, expect, sam_status_name(st),
                     err.message);
        assert_false(sam_test_file_exists(path));
    }
    assert_false(sam_test_count_temp_files("samfile_invalid.sam"));
}

static void test_validate_accepts_edge_cases(void **state)
{
    (void)state;
    tetra t;
    make_tetra(&t, 0);
    for (int i = 0; i < 3; ++i)
        t.nrm[i] *= 1.0005f; /* within the 1e-3 tolerance */
    for (int i = 0; i < 8; ++i)
        t.sidx[i] = PAD; /* a vertex may have no back side at all */
    t.fana[1] = 0.0f;
    t.adjo[1] = t.adjo[2] = t.adjo[3] = t.adjo[4] = 0; /* no adjacency at all */
    t.d.adjacency_count = 0;
    t.d.adjacency = NULL;
    set_info(&t, "4.0", "4e0", "2", "1e-3");
    sam_error err;
    if (samfile_validate(&t.d, &err) != SAM_OK)
        fail_msg("%s", err.message);
    bytes b = encode_data(&t.d);
    samfile_data d;
    if (samfile_read_memory(b.p, b.n, NULL, &d, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(d.adjacency_count, 0);
    assert_null(d.adjacency);
    samfile_free(&d);
    free(b.p);
}

static void test_validate_rejects_null_arrays(void **state)
{
    (void)state;
    tetra t;
    make_tetra(&t, 0);
    t.d.sample_kprime = NULL;
    sam_error err;
    assert_int_equal(samfile_validate(&t.d, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_string_equal(err.message, "samfile data: chunk SKPR: array is NULL");
    make_tetra(&t, 0);
    t.d.adjacency = NULL;
    assert_int_equal(samfile_validate(&t.d, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_string_equal(err.message, "samfile data: chunk ADJV: array is NULL");
    assert_int_equal(samfile_validate(NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    t.d.samples_per_vertex = 65;
    t.d.adjacency = t.adjv;
    assert_int_equal(samfile_validate(&t.d, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_string_equal(err.message,
                        "samfile data: chunk SIDX: 65 samples per vertex; supported range is 1..64");
}

/* ---- files ---- */

static void test_write_keeps_old_file_when_validation_fails(void **state)
{
    (void)state;
    tetra t;
    make_tetra(&t, 0);
    char path[512];
    sam_test_tmp_path(path, sizeof path, "samfile_keep.sam");
    sam_error err;
    assert_int_equal(samfile_write(path, &t.d, &err), SAM_OK);
    bytes before = load(path);
    t.tri[0] = 99;
    assert_int_equal(samfile_write(path, &t.d, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "chunk TRI : index 99 of triangle 0 is out of range"));
    bytes after = load(path);
    assert_int_equal(before.n, after.n);
    assert_memory_equal(before.p, after.p, before.n);
    assert_false(sam_test_count_temp_files("samfile_keep.sam"));
    free(before.p);
    free(after.p);
}

static void test_write_to_missing_directory_fails(void **state)
{
    (void)state;
    tetra t;
    make_tetra(&t, 0);
    char path[512];
    sam_test_tmp_path(path, sizeof path, "samfile-no-such-dir/out.sam");
    sam_error err;
    assert_int_equal(samfile_write(path, &t.d, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, path));
    assert_non_null(strstr(err.message, "No such file or directory"));
    assert_int_equal(samfile_write(NULL, &t.d, &err), SAM_ERR_INVALID_ARGUMENT);
}

static void test_read_errors_name_the_file(void **state)
{
    (void)state;
    samfile_data d;
    sam_error err;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "samfile_missing.sam");
    remove(path);
    assert_int_equal(samfile_read(path, &d, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, path));
    assert_true(is_zeroed(&d));

    tetra t;
    make_tetra(&t, 0);
    t.sidx[0] = 5123;
    bytes b = encode_data(&t.d);
    sam_test_tmp_path(path, sizeof path, "samfile_bad_sidx.sam");
    sam_test_write_file(path, b.p, b.n);
    free(b.p);
    assert_int_equal(samfile_read(path, &d, &err), SAM_ERR_CORRUPT);
    char expect[700];
    snprintf(expect, sizeof expect,
             "%s: chunk SIDX: sample index 5123 of vertex 0 is out of range (vertex_count 4)", path);
    assert_string_equal(err.message, expect);
    assert_true(is_zeroed(&d));

    assert_int_equal(samfile_read_memory(NULL, 0, NULL, &d, &err), SAM_ERR_FORMAT);
    assert_string_equal(err.message, "<memory>: truncated: 0 bytes, shorter than the 16-byte header");
    samfile_free(&d);
    samfile_free(NULL);
}

/* The fuzz seeds are this test's tetrahedra as the current writer writes
 * them, so a format change shows up here first. */
static void test_fuzz_seeds_match_writer(void **state)
{
    (void)state;
    static const char *seeds[4] = {"tetra.sam", "tetra_uv.sam", "tetra_tree.sam", "tetra_sources.sam"};
    for (int kind = 0; kind < 4; ++kind) {
        tetra t;
        make_tetra(&t, kind == 1);
        if (kind >= 2)
            add_tree(&t);
        if (kind == 3)
            add_sources(&t);
        char seed[512], path[512];
        snprintf(seed, sizeof seed, "%s/fuzz/corpus/samfile/%s", SAM_SOURCE_DIR, seeds[kind]);
        snprintf(path, sizeof path, "%s/samfile_seed_%s", SAM_TEST_TMP_DIR, seeds[kind]);
        assert_int_equal(samfile_write(path, &t.d, NULL), SAM_OK);
        bytes want = load(path), have = load(seed);
        assert_int_equal(have.n, want.n);
        assert_memory_equal(have.p, want.p, want.n);
        free(want.p);
        free(have.p);
    }
}

/* SRCV, the source mesh's vertex order: a round trip in either version, a
 * reader's checks, and a file without it still loads. */
static void test_source_vertices(void **state)
{
    (void)state;
    for (int tree = 0; tree < 2; ++tree) {
        tetra t;
        make_tetra(&t, 1);
        if (tree)
            add_tree(&t);
        add_sources(&t);
        bytes b = encode_data(&t.d);
        samfile_data d;
        sam_error err;
        if (samfile_read_memory(b.p, b.n, "t.sam", &d, &err) != SAM_OK)
            fail_msg("%s", err.message);
        expect_same_data(&t.d, &d);
        assert_int_equal(d.unknown_chunk_count, 0);
        samfile_free(&d);
        free(b.p);
    }
    tetra t;
    make_tetra(&t, 0);
    add_sources(&t);
    sam_error err;
    t.srcv[4] = 9;
    assert_int_equal(samfile_validate(&t.d, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "chunk SRCV: source vertex 4 became vertex 9, out of range (vertex_count 4)"));
    bytes b = encode_data(&t.d);
    expect_read_error(&b, SAM_ERR_CORRUPT, "t.sam: chunk SRCV: source vertex 4 became vertex 9");
    free(b.p);
    t.srcv[4] = 3;
    t.vsrc[2] = 6;
    assert_int_equal(samfile_validate(&t.d, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "chunk SRCV: vertex 2 comes from source vertex 6, out of range (6 source"));
    t.vsrc[2] = 3;
    chunk_list l;
    list_from_data(&t.d, &l);
    replace_payload(&l, "SRCV", "ab", 2);
    b = encode(&l, NULL);
    expect_read_error(&b, SAM_ERR_FORMAT, "t.sam: chunk SRCV: payload of 2 bytes has no source vertex count");
    free(b.p);
    static const uint32_t none[1] = {0}, short_one[3] = {6, 0, 1};
    replace_payload(&l, "SRCV", none, sizeof none);
    b = encode(&l, NULL);
    expect_read_error(&b, SAM_ERR_CORRUPT, "t.sam: chunk SRCV: a source mesh of 0 vertices");
    free(b.p);
    replace_payload(&l, "SRCV", short_one, sizeof short_one);
    b = encode(&l, NULL);
    expect_read_error(&b, SAM_ERR_CORRUPT, "t.sam: chunk SRCV: payload is 12 bytes, expected 44");
    free(b.p);
    free_list(&l);
    t.d.source_vertex = NULL;
    assert_int_equal(samfile_validate(&t.d, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "chunk SRCV: array is NULL"));
}

/* A cut map's tree: round trip, and each rule of samfile.h broken once. */
static void test_tree_rules(void **state)
{
    (void)state;
    tetra t;
    make_tetra(&t, 0);
    add_tree(&t);
    char path[512];
    snprintf(path, sizeof path, "%s/samfile_tree.sam", SAM_TEST_TMP_DIR);
    sam_error err;
    assert_int_equal(samfile_write(path, &t.d, &err), SAM_OK);
    samfile_data d;
    assert_int_equal(samfile_read(path, &d, &err), SAM_OK);
    assert_int_equal(d.node_count, 3);
    assert_int_equal(d.level_count, 2);
    assert_memory_equal(d.node_children, t.children, sizeof t.children);
    assert_memory_equal(d.sample_tau, t.tau, sizeof t.tau);
    assert_int_equal(d.sample_index[0], 6);
    samfile_free(&d);
    static const struct {
        int what;
        uint32_t value;
        const char *needle;
    } cases[] = {
        {0, 4 + 0, "child 0 of node 0 (level 0) is 4, expected a vertex < 4 or a node of the next level (5..6)"},
        {5, 0, "chunk NODE: vertex 0 is a child of nodes 1 and 1 (a tree gives each one parent)"},
        {1, 4 + 1, "chunk NODE: node 1 is a child of nodes 0 and 0"},
        {1, 4 + 3, "child 1 of node 0 (level 0) is 7"},
        {2, 3, "chunk NLVL: level 1 is empty or reversed (nodes 3 to 3)"},
        {3, 4 + 3, "sample index 7 of vertex 0 is out of range (vertex_count 4 + node_count 3)"},
        {4, 0, "chunk STAU: tau of sample 0 of vertex 0 is 1.5"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
        make_tetra(&t, 0);
        add_tree(&t);
        switch (cases[c].what) {
        case 0: t.children[0] = cases[c].value; break;
        case 1: t.children[1] = cases[c].value; break;
        case 2: t.levels[1] = cases[c].value; break;
        case 3: t.sidx[0] = cases[c].value; break;
        case 5: t.children[3] = cases[c].value; break;
        default: t.tau[0] = 1.5f; break;
        }
        if (samfile_validate(&t.d, &err) != SAM_ERR_INVALID_ARGUMENT || !strstr(err.message, cases[c].needle))
            fail_msg("case %zu: expected \"%s\", got \"%s\"", c, cases[c].needle, err.message);
    }
    /* The tree's chunks belong to version 2 only, and version 2 needs them. */
    make_tetra(&t, 0);
    add_tree(&t);
    chunk_list l;
    list_from_data(&t.d, &l);
    remove_chunk(&l, find_chunk(&l, "STAU"));
    bytes b = encode(&l, NULL);
    expect_read_error(&b, SAM_ERR_FORMAT, "t.sam: chunk STAU is missing (required in version 2)");
    free(b.p);
    b = encode(&l, NULL);
    le32(b.p + 4, 1);
    expect_read_error(&b, SAM_ERR_FORMAT, "chunk NODE at offset");
    free(b.p);
    free_list(&l);
}

/* A recorded has_uvs must match the UV chunk: that is what catches a
 * damaged "UV  " tag, which the payload CRCs cannot. */
static void test_has_uvs_must_match_uv_chunk(void **state)
{
    (void)state;
    for (int with_uv = 0; with_uv < 2; ++with_uv) {
        tetra t;
        make_tetra(&t, with_uv);
        samfile_data d = t.d;
        snprintf(t.info, sizeof t.info,
                 "{\"vertex_count\":4,\"triangle_count\":4,\"samples_per_vertex\":2,\"mm_per_unit\":1,"
                 "\"has_uvs\":%s}",
                 with_uv ? "false" : "true");
        sam_error err;
        assert_int_not_equal(samfile_validate(&d, &err), SAM_OK);
        assert_non_null(strstr(err.message, "has_uvs"));
        snprintf(t.info, sizeof t.info,
                 "{\"vertex_count\":4,\"triangle_count\":4,\"samples_per_vertex\":2,\"mm_per_unit\":1,"
                 "\"has_uvs\":%s}",
                 with_uv ? "true" : "false");
        assert_int_equal(samfile_validate(&d, &err), SAM_OK);
        snprintf(t.info, sizeof t.info,
                 "{\"vertex_count\":4,\"triangle_count\":4,\"samples_per_vertex\":2,\"mm_per_unit\":1,"
                 "\"has_uvs\":1}");
        assert_int_not_equal(samfile_validate(&d, &err), SAM_OK);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_has_uvs_must_match_uv_chunk),
        cmocka_unit_test(test_round_trip_without_uv),
        cmocka_unit_test(test_round_trip_with_uv),
        cmocka_unit_test(test_on_disk_layout),
        cmocka_unit_test(test_tree_rules),
        cmocka_unit_test(test_source_vertices),
        cmocka_unit_test(test_every_truncated_prefix_fails),
        cmocka_unit_test(test_every_single_byte_flip_fails),
        cmocka_unit_test(test_header_errors),
        cmocka_unit_test(test_chunk_framing_errors),
        cmocka_unit_test(test_missing_and_duplicate_chunks),
        cmocka_unit_test(test_unknown_chunks_are_skipped_and_counted),
        cmocka_unit_test(test_payload_sizes_must_agree),
        cmocka_unit_test(test_semantic_violations),
        cmocka_unit_test(test_validate_accepts_edge_cases),
        cmocka_unit_test(test_validate_rejects_null_arrays),
        cmocka_unit_test(test_write_keeps_old_file_when_validation_fails),
        cmocka_unit_test(test_write_to_missing_directory_fails),
        cmocka_unit_test(test_read_errors_name_the_file),
        cmocka_unit_test(test_fuzz_seeds_match_writer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
