#include "sam/samfile.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "samfile_internal.h"

/* ---- writing ---- */

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

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
    sam_status st = samfile_check_data(data, path, SAM_ERR_INVALID_ARGUMENT, err);
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
    /* A flat map stays version 1, readable by version-1 readers. */
    const int tree = data->node_count > 0;
    put_u32(header + 4, tree ? SAMFILE_VERSION : 1u);
    put_u32(header + 8, TAG_COUNT - (data->uvs ? 0 : 1) - (tree ? 0 : 3) - (data->vertex_source ? 0 : 1));
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
    if (tree) {
        write_u32_chunk(w, TAG_NODE, data->node_children, 2 * (size_t)data->node_count);
        write_u32_chunk(w, TAG_NLVL, data->level_offsets, (size_t)data->level_count + 1);
        write_f32_chunk(w, TAG_STAU, data->sample_tau, n * vc);
    }
    if (data->vertex_source) {
        begin_chunk(w, TAG_SRCV, 4u + 4u * ((uint64_t)vc + data->source_vertex_count));
        payload_u32(w, data->source_vertex_count);
        for (size_t v = 0; v < vc; ++v)
            payload_u32(w, data->vertex_source[v]);
        for (uint32_t s = 0; s < data->source_vertex_count; ++s)
            payload_u32(w, data->source_vertex[s]);
        end_chunk(w);
    }

    int e = w->error;
    free(w);
    if (e) {
        st = sam_fail(err, SAM_ERR_IO, "%s: write of %s failed: %s", path, file.temp_path, strerror(e));
        sam_atomic_abort(&file);
        return st;
    }
    return sam_atomic_commit(&file, err);
}
