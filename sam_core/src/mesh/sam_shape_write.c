#define _POSIX_C_SOURCE 200809L
#include "sam/sam_shape.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---------------------------------------------------------------- welding */

typedef struct weld_key {
    uint32_t bits[3];
    uint32_t index;
} weld_key;

static int weld_key_cmp(const void *pa, const void *pb)
{
    const weld_key *a = pa, *b = pb;
    for (int k = 0; k < 3; ++k)
        if (a->bits[k] != b->bits[k])
            return a->bits[k] < b->bits[k] ? -1 : 1;
    return a->index < b->index ? -1 : (a->index > b->index);
}

sam_status sam_shape_weld(const sam_shape_mesh *mesh, uint32_t *ids, uint32_t *unique_count,
                          sam_error *err)
{
    if (!mesh || !ids || !unique_count || (mesh->vertex_count && !mesh->positions))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape weld: mesh, ids and count required");
    uint32_t n = mesh->vertex_count;
    weld_key *keys = malloc((size_t)n * sizeof *keys + 1);
    if (!keys)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape weld: out of memory for %u vertices",
                        n);
    for (uint32_t v = 0; v < n; ++v) {
        memcpy(keys[v].bits, mesh->positions + 3 * (size_t)v, sizeof keys[v].bits);
        keys[v].index = v;
    }
    qsort(keys, n, sizeof *keys, weld_key_cmp);
    /* ids first holds each vertex's lowest-index twin, then is renumbered
     * in order of first appearance (the twin always precedes). */
    for (uint32_t k = 0, first = 0; k < n; ++k) {
        if (k == 0 || memcmp(keys[k].bits, keys[k - 1].bits, sizeof keys[k].bits) != 0)
            first = keys[k].index;
        ids[keys[k].index] = first;
    }
    free(keys);
    uint32_t next = 0;
    for (uint32_t v = 0; v < n; ++v)
        ids[v] = ids[v] == v ? next++ : ids[ids[v]];
    *unique_count = next;
    return SAM_OK;
}

/* ---------------------------------------------------------------- writers */

static sam_status check_mesh(const char *path, const sam_shape_mesh *mesh, sam_error *err)
{
    if (!mesh || !mesh->vertex_count || !mesh->triangle_count || !mesh->positions || !mesh->triangles)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: no mesh to write",
                        path ? path : "(null)");
    if (mesh->vertex_count > SAM_SHAPE_MAX_VERTICES || mesh->triangle_count > SAM_SHAPE_MAX_VERTICES)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: %u vertices, %u triangles: too many",
                        path, mesh->vertex_count, mesh->triangle_count);
    for (size_t k = 0; k < 3 * (size_t)mesh->triangle_count; ++k)
        if (mesh->triangles[k] >= mesh->vertex_count)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "%s: triangle %zu has index %u, vertex count %u", path, k / 3,
                            mesh->triangles[k], mesh->vertex_count);
    return SAM_OK;
}

static sam_status finish_write(sam_atomic_file *f, const char *path, sam_error *err)
{
    if (ferror(f->fp)) {
        sam_atomic_abort(f);
        return sam_fail(err, SAM_ERR_IO, "%s: write failed", path);
    }
    return sam_atomic_commit(f, err);
}

/* The OBJ, naming the material `material` of the library `mtllib` when
 * mtllib is not NULL. */
static sam_status write_obj(const char *path, const sam_shape_mesh *mesh, const char *mtllib,
                            const char *material, sam_error *err)
{
    sam_status st = check_mesh(path, mesh, err);
    if (st != SAM_OK)
        return st;
    uint32_t n = mesh->vertex_count, unique = 0;
    uint32_t *ids = malloc((size_t)n * sizeof *ids);
    if (!ids)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    st = sam_shape_weld(mesh, ids, &unique, err);
    if (st != SAM_OK) {
        free(ids);
        return st;
    }
    sam_atomic_file f;
    st = sam_atomic_open(&f, path, err);
    if (st != SAM_OK) {
        free(ids);
        return st;
    }
    fprintf(f.fp, "# sam_shape: %u positions, %u uvs, %u triangles\n", unique, mesh->uvs ? n : 0,
            mesh->triangle_count);
    if (mtllib)
        fprintf(f.fp, "mtllib %s\nusemtl %s\n", mtllib, material);
    for (uint32_t v = 0, written = 0; v < n; ++v)
        if (ids[v] == written) {
            const float *p = mesh->positions + 3 * (size_t)v;
            fprintf(f.fp, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
            ++written;
        }
    for (uint32_t v = 0; mesh->uvs && v < n; ++v)
        fprintf(f.fp, "vt %.9g %.9g\n", mesh->uvs[2 * (size_t)v], mesh->uvs[2 * (size_t)v + 1]);
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
        const uint32_t *tri = mesh->triangles + 3 * (size_t)t;
        if (mesh->uvs)
            fprintf(f.fp, "f %u/%u %u/%u %u/%u\n", ids[tri[0]] + 1, tri[0] + 1, ids[tri[1]] + 1,
                    tri[1] + 1, ids[tri[2]] + 1, tri[2] + 1);
        else
            fprintf(f.fp, "f %u %u %u\n", ids[tri[0]] + 1, ids[tri[1]] + 1, ids[tri[2]] + 1);
    }
    free(ids);
    return finish_write(&f, path, err);
}

sam_status sam_shape_write_obj(const char *path, const sam_shape_mesh *mesh, sam_error *err)
{
    return write_obj(path, mesh, NULL, NULL, err);
}

static const char *file_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

sam_status sam_shape_obj_companions(const char *path, char *mtl, char *png, size_t n, sam_error *err)
{
    if (!path || !mtl || !png || !n)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "OBJ companions: path and buffers required");
    const char *name = file_name(path), *dot = strrchr(name, '.');
    /* The material library names its texture as its last word, and most
     * readers split the names on blanks. */
    if (strpbrk(name, " \t"))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "%s: an OBJ cannot name material files whose names have blanks in them", path);
    const int stem = dot && dot > name ? (int)(dot - path) : (int)strlen(path);
    const int a = snprintf(mtl, n, "%.*s.mtl", stem, path), b = snprintf(png, n, "%.*s_albedo.png", stem, path);
    if (a < 0 || b < 0 || (size_t)a >= n || (size_t)b >= n)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: the name is too long for its material files", path);
    return SAM_OK;
}

sam_status sam_shape_write_obj_albedo(const char *path, const sam_shape_mesh *mesh, const sam_image *albedo,
                                      sam_error *err)
{
    if (!path || !albedo || !albedo->pixels || !mesh || !mesh->uvs)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: a texture needs a path, an image and the mesh's UVs",
                        path ? path : "(null)");
    sam_status st = check_mesh(path, mesh, err);
    if (st != SAM_OK)
        return st;
    char mtl[4096], png[4096];
    if ((st = sam_shape_obj_companions(path, mtl, png, sizeof mtl, err)) != SAM_OK)
        return st;
    /* A companion that was there is replaced, not removed, when a later
     * file fails: an OBJ already at `path` (kept by its atomic write) may
     * name it. */
    const int had_mtl = access(mtl, F_OK) == 0, had_png = access(png, F_OK) == 0;
    if ((st = sam_image_write_png(png, albedo, SAM_PNG_SRGB, err)) != SAM_OK)
        return st;
    sam_atomic_file f;
    if ((st = sam_atomic_open(&f, mtl, err)) == SAM_OK) {
        fprintf(f.fp, "# sam_shape: the albedo of %s\nnewmtl albedo\nKd 1 1 1\nmap_Kd %s\n", file_name(path),
                file_name(png));
        st = finish_write(&f, mtl, err);
    }
    if (st == SAM_OK && (st = write_obj(path, mesh, file_name(mtl), "albedo", err)) != SAM_OK && !had_mtl)
        remove(mtl);
    if (st != SAM_OK && !had_png)
        remove(png);
    return st;
}

static void put_le32(uint8_t *o, uint32_t x)
{
    o[0] = (uint8_t)x;
    o[1] = (uint8_t)(x >> 8);
    o[2] = (uint8_t)(x >> 16);
    o[3] = (uint8_t)(x >> 24);
}

static void put_float(uint8_t *o, float f)
{
    uint32_t x;
    memcpy(&x, &f, sizeof x);
    put_le32(o, x);
}

sam_status sam_shape_write_ply(const char *path, const sam_shape_mesh *mesh, int binary,
                               sam_error *err)
{
    sam_status st = check_mesh(path, mesh, err);
    if (st != SAM_OK)
        return st;
    sam_atomic_file f;
    st = sam_atomic_open(&f, path, err);
    if (st != SAM_OK)
        return st;
    fprintf(f.fp,
            "ply\nformat %s 1.0\ncomment sam_shape render vertices (seams are split)\n"
            "element vertex %u\nproperty float x\nproperty float y\nproperty float z\n%s"
            "element face %u\nproperty list uchar int vertex_indices\nend_header\n",
            binary ? "binary_little_endian" : "ascii", mesh->vertex_count,
            mesh->uvs ? "property float u\nproperty float v\n" : "", mesh->triangle_count);
    const int fields = mesh->uvs ? 5 : 3;
    for (uint32_t v = 0; v < mesh->vertex_count; ++v) {
        float x[5];
        memcpy(x, mesh->positions + 3 * (size_t)v, 3 * sizeof *x);
        if (mesh->uvs)
            memcpy(x + 3, mesh->uvs + 2 * (size_t)v, 2 * sizeof *x);
        if (binary) {
            uint8_t rec[20];
            for (int k = 0; k < fields; ++k)
                put_float(rec + 4 * k, x[k]);
            fwrite(rec, 4, (size_t)fields, f.fp);
        } else {
            for (int k = 0; k < fields; ++k)
                fprintf(f.fp, k + 1 < fields ? "%.9g " : "%.9g\n", x[k]);
        }
    }
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
        const uint32_t *tri = mesh->triangles + 3 * (size_t)t;
        if (binary) {
            uint8_t rec[13];
            rec[0] = 3;
            for (int k = 0; k < 3; ++k)
                put_le32(rec + 1 + 4 * k, tri[k]);
            fwrite(rec, 1, sizeof rec, f.fp);
        } else {
            fprintf(f.fp, "3 %u %u %u\n", tri[0], tri[1], tri[2]);
        }
    }
    return finish_write(&f, path, err);
}
