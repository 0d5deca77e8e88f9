/*
 * A PLY file's header as the pre-check parses it (sam_mesh_preflight.c),
 * and the PLY written again for OpenMesh where its reader would misread
 * the file as written.
 *
 * OpenMesh's PLY reader reads ordinary files right, but some that other
 * tools write it reads wrong without a word, shifting every value after
 * the first it mistakes:
 *   - a list other than the faces' corners (MeshLab's and Metashape's
 *     per-corner `texcoord` list) is skipped as one value;
 *   - a list count typed other than uchar, uint8, uint16 or int (`uint`,
 *     `int32`, `ushort`...) is refused;
 *   - integer positions, normals or texture coordinates are not read at
 *     all, nor integer corner indices typed as floats;
 *   - in a binary file it finds the body by the header's last line, so a
 *     comment, blank line or trailing blank there moves the body.
 * Such a file is written again (binary, little-endian: positions, normals
 * and texture coordinates where the file has them, the faces' corners) and
 * OpenMesh reads that instead; the per-corner texture coordinates it
 * cannot carry come back beside it.
 */
#ifndef SAM_MESH_PLY_H
#define SAM_MESH_PLY_H

#include <stddef.h>
#include <stdint.h>

#include "sam/sam_common.h"

#define SAM_MESH_PLY_MAX_ELEMENTS 16
#define SAM_MESH_PLY_MAX_PROPERTIES 64

typedef enum sam_mesh_ply_type {
    SAM_MESH_PLY_UNKNOWN = 0,
    SAM_MESH_PLY_INT8,
    SAM_MESH_PLY_UINT8,
    SAM_MESH_PLY_INT16,
    SAM_MESH_PLY_UINT16,
    SAM_MESH_PLY_INT32,
    SAM_MESH_PLY_UINT32,
    SAM_MESH_PLY_FLOAT32,
    SAM_MESH_PLY_FLOAT64
} sam_mesh_ply_type;

typedef struct sam_mesh_ply_property {
    char name[32];
    int is_list;
    sam_mesh_ply_type value_type; /* a scalar's, or a list's entries' */
    sam_mesh_ply_type count_type; /* a list's count */
    int count_name_read;          /* 1 when OpenMesh takes the count's type name as written */
} sam_mesh_ply_property;

typedef struct sam_mesh_ply_element {
    char name[32];
    unsigned long long count;
    int property_count;
    sam_mesh_ply_property property[SAM_MESH_PLY_MAX_PROPERTIES];
} sam_mesh_ply_element;

typedef struct sam_mesh_ply_header {
    int format;             /* 0 ASCII, 1 binary little-endian, 2 binary big-endian */
    size_t body;            /* byte offset of the body, past end_header's line */
    size_t reader_body;     /* where OpenMesh's binary reader starts the body */
    int element_count;
    sam_mesh_ply_element element[SAM_MESH_PLY_MAX_ELEMENTS];
} sam_mesh_ply_header;

/* The type a PLY type name (`tok`, `len` bytes) names; SAM_MESH_PLY_UNKNOWN
 * for any other word. */
sam_mesh_ply_type sam_mesh_ply_type_of(const char *tok, int len);

/* Bytes of one value of type `t` (0 for SAM_MESH_PLY_UNKNOWN). */
int sam_mesh_ply_type_size(sam_mesh_ply_type t);

/* 1 when OpenMesh's reader would misread the file `header` describes (see
 * the overview), 0 when it reads it as written. */
int sam_mesh_ply_misread(const sam_mesh_ply_header *header);

/* Writes the file at `data` (`size` bytes, its header parsed into
 * `header`, its body checked by the pre-check against it) again as a
 * binary little-endian PLY that OpenMesh reads right, appended to `out`
 * (check out->oom): the vertices' x, y, z, their nx, ny, nz and their
 * u (or s), v (or t) where the file has them, and each face's corners.
 * When every face has a list named texcoord of two values a corner (as
 * MeshLab and Metashape write them), those values go to *corner_uvs
 * (2 * *corner_uv_count floats, corner by corner in file order; the caller
 * frees it); otherwise *corner_uvs is NULL.
 * Errors: SAM_ERR_FORMAT (a corner index that is negative, fractional or
 * above 2^31 - 1, naming the face), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_ply_rewrite(const char *path, const char *data, size_t size, const sam_mesh_ply_header *header,
                                sam_text *out, float **corner_uvs, uint32_t *corner_uv_count, sam_error *err);

/* The vertex element's red, green and blue (or diffuse_red, ...) of the
 * file at `data` (`size` bytes, its header parsed into `header`, its body
 * checked by the pre-check against it), each scaled to [0, 1] (an integer
 * type by its largest value, a float clamped), 3 * vertex count floats
 * into *rgb (the caller frees it). *rgb is NULL when the vertices have no
 * such scalar properties. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_ply_colors(const char *path, const char *data, size_t size, const sam_mesh_ply_header *header,
                               float **rgb, sam_error *err);

/* The face element's `texnumber` (MeshLab's and Metashape's: which of the
 * header's "comment TextureFile" lines each face reads), one per face into
 * *numbers (the caller frees it), 0xFFFFFFFF for a value that is no
 * index; *numbers NULL when the faces have no such scalar. The file as
 * sam_mesh_ply_colors takes it. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_ply_texnumbers(const char *path, const char *data, size_t size, const sam_mesh_ply_header *header,
                                   uint32_t **numbers, sam_error *err);

#endif
