/*
 * Internal: the raw polygon soup a mesh file holds, before any welding,
 * triangulation or repair. Produced by the OpenMesh reader
 * (sam_mesh_openmesh.cpp) and the glTF reader (sam_mesh_gltf.cpp), the
 * project's C++, consumed by sam_mesh_build.c.
 */
#ifndef SAM_MESH_SOUP_H
#define SAM_MESH_SOUP_H

#include "sam/sam_common.h"
#include "sam/sam_image.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_mesh_soup {
    uint32_t vertex_count;
    float *positions;       /* 3 * vertex_count */
    float *normals;         /* 3 * vertex_count, or NULL when the file has none */
    float *uvs;             /* 2 * vertex_count per-vertex UVs, or NULL */
    uint32_t face_count;
    uint32_t *face_offsets; /* face_count + 1 offsets into corner arrays */
    uint32_t corner_count;
    uint32_t *corners;      /* vertex index per face corner, < vertex_count */
    float *corner_uvs;      /* 2 * corner_count per-corner UVs (OBJ vt), or NULL */
    float *corner_normals;  /* 3 * corner_count per-corner normals (OBJ vn), or NULL; before `normals` */
    float *colors;          /* 3 * vertex_count linear RGB in [0, 1] (glTF COLOR_0), or NULL */
    uint32_t *face_materials; /* face_count: the glTF material of each face's primitive, or
                               * SAM_MESH_NO_MATERIAL; NULL when no primitive names one */
} sam_mesh_soup;

#define SAM_MESH_NO_MATERIAL 0xFFFFFFFFu

/* Reads OBJ, PLY (ASCII/binary), OFF or STL through OpenMesh's readers into
 * a soup. Every exception is caught. Indices are checked against the vertex
 * count here; coordinates are validated by the caller. `text` (may be
 * NULL: the file is read) is the file written again for the reader,
 * text_size bytes in the format of `extension` (".off", ".ply" or ".obj";
 * sam_mesh_expect.rewritten), read in the file's place from a private
 * temporary file in $TMPDIR (else /tmp), removed after; `path` still names
 * the file in the messages.
 * Errors: SAM_ERR_IO (missing/unreadable, or no temporary file to be had),
 * SAM_ERR_UNSUPPORTED (extension),
 * SAM_ERR_FORMAT (OpenMesh rejected the file; its diagnostics are quoted),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_soup_read(const char *path, const char *text, size_t text_size, const char *extension,
                              sam_mesh_soup *soup, sam_error *err);

void sam_mesh_soup_free(sam_mesh_soup *soup);

/* Reads a glTF 2.0 file (.gltf with its buffers, or .glb) through TinyGLTF
 * into a soup: the triangles (and strips and fans) of every mesh
 * primitive reached from the default scene (every mesh once when the file
 * has no scene), node transforms applied (a mirroring one turns the
 * winding back), NORMAL when every primitive has it, TEXCOORD_0 with v
 * flipped to the project's (OBJ's) convention when every primitive has it,
 * COLOR_0's RGB when any primitive has it (white where one has not).
 * Points and lines are skipped. Every accessor, buffer view, index and
 * node reference is checked against what the file holds before it is
 * read. Every exception is caught.
 * Errors: SAM_ERR_FORMAT (TinyGLTF's message, or the first bad reference,
 * naming it and the values found), SAM_ERR_EMPTY (no triangles),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_gltf_read(const char *path, sam_mesh_soup *soup, sam_error *err);

/* The base-colour texture of a glTF file's first material its primitives
 * use that has one (of any material when none does), as a linear image
 * (sRGB decoded; 16 bits cut to 8; `image` zeroed when no material has
 * one), its baseColorFactor in factor[4] (1s without), and in *others how
 * many other images the base colours of the materials its primitives use
 * read (one albedo map is all the runtime takes: their parts show this
 * one). Errors:
 * SAM_ERR_FORMAT (an unreadable file), SAM_ERR_UNSUPPORTED (an image that
 * is not RGB or RGBA of 8 or 16 bits), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_gltf_base_color(const char *path, sam_image *image, float factor[4], uint32_t *others,
                                    sam_error *err);

/* The base colour of each of a glTF file's materials, in its order: the
 * texture times baseColorFactor (linear), or a 1 x 1 image of the factor
 * when it has none; *count images in *images (caller destroys each and
 * frees the array; NULL and 0 without materials). A texture that cannot
 * be used leaves its material's image empty (pixels NULL) and `note`
 * (note_size bytes) says why for the first; "" when all are read.
 * Errors: SAM_ERR_FORMAT (an unreadable file), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_gltf_base_colors(const char *path, sam_image **images, uint32_t *count, char *note,
                                     size_t note_size, sam_error *err);

/* What a mesh file holds, as the pre-check counts it: what OpenMesh's
 * reader must deliver for the file to have been read as written. */
typedef struct sam_mesh_expect {
    int known;                         /* 1 for OBJ, OFF and PLY; STL's reader merges and drops vertices */
    uint64_t vertices, faces;          /* what the reader must deliver */
    uint64_t file_faces;               /* face records, those with repeated corners included */
    uint64_t repeated_corner_faces;    /* OBJ faces with fewer than 3 distinct corners: the reader drops them */
    int first_repeated_line;           /* the line of the first of them, 0 when none */
    /* OBJ whose every kept face names a normal at every corner (v//n,
     * v/t/n): OpenMesh's importer gives a vertex one normal, the last a
     * corner named, so a hard edge's normals are kept here. Owned; NULL
     * otherwise (sam_mesh_expect_free). */
    float *obj_normals;                /* 3 * obj_normal_count: the vn lines */
    uint32_t obj_normal_count;
    uint32_t *obj_face_offsets;        /* faces + 1: each kept face's corners in the two arrays below */
    uint32_t *obj_corner_vertex;       /* 0-based position, in file order, repeated corners included */
    uint32_t *obj_corner_normal;       /* 0-based vn */
    /* The file written again as OpenMesh reads it right (the same vertices
     * and faces), which the reader reads instead: an OFF file with
     * comments, counts on the keyword's line, no edge count or face
     * colours; a PLY it would misread (sam_mesh_ply.h); an OBJ with
     * comments after values or continued lines. Owned; NULL when
     * the file goes as it is (sam_mesh_expect_free). */
    char *rewritten;
    size_t rewritten_size;             /* bytes, without the terminating NUL */
    const char *rewritten_extension;   /* ".off", ".ply" or ".obj" (static) */
    /* A rewritten PLY's per-corner texture coordinates, which OpenMesh's
     * reader does not carry: 2 * corner_uv_count floats, every face's
     * corners in file order. Owned; NULL when the file has none. */
    float *corner_uvs;
    uint32_t corner_uv_count;
    /* The vertices' colours, as a PLY's red, green and blue or an OBJ's
     * "v x y z r g b" give them (sRGB-encoded, scaled to [0, 1]): 3 *
     * vertices floats. Owned; NULL when not every vertex has one. */
    float *vertex_colors;
    /* An OBJ's materials: the names its usemtl lines give, each once in
     * first-use order (at most SAM_MESH_MAX_MATERIALS; later ones count
     * as none), and each kept face's, in the order the reader delivers
     * the faces: expect->faces entries, SAM_MESH_NO_MATERIAL before the
     * first usemtl. Owned; NULL and 0 when the file has no usemtl. A
     * PLY's faces' texnumber goes to face_materials (sam_mesh_ply.h), its
     * names being its TextureFile comments, not listed here. */
    char **material_names;
    uint32_t material_count;
    uint32_t *face_materials;
} sam_mesh_expect;

#define SAM_MESH_MAX_MATERIALS 4096

void sam_mesh_expect_free(sam_mesh_expect *expect);

/* The pre-check's gathering of an OBJ's per-corner normals into `expect`
 * (sam_mesh_obj_normals.c), in the order it reads the file:
 *   sam_mesh_obj_gather g = {1};   (ok, nothing gathered)
 *   for each vn line:            sam_mesh_obj_gather_normal(e, &g, its 0-based index, its value)
 *   for each face corner:        sam_mesh_obj_gather_corner(e, &g, its place in the face, its 0-based
 *                                vertex, whether it names a normal, the normal's 0-based index)
 *   after a face the reader keeps (3 or more distinct corners):
 *                                sam_mesh_obj_gather_face(e, &g, its corner count)
 *   at the end:                  sam_mesh_obj_gather_finish(e, &g)
 * A corner without a normal lets everything go (the mesh keeps its vertex
 * normals). Each returns 0 when out of memory (then free `expect`). */
typedef struct sam_mesh_obj_gather {
    int ok;
    size_t normal_cap, vertex_cap, corner_cap, face_cap;
    uint32_t corner_count, face_count;
} sam_mesh_obj_gather;
int sam_mesh_obj_gather_normal(sam_mesh_expect *e, sam_mesh_obj_gather *g, uint64_t index, const float v[3]);
int sam_mesh_obj_gather_corner(sam_mesh_expect *e, sam_mesh_obj_gather *g, uint32_t corner, uint64_t vertex,
                               int has_normal, uint64_t normal);
int sam_mesh_obj_gather_face(sam_mesh_expect *e, sam_mesh_obj_gather *g, uint32_t corners);
void sam_mesh_obj_gather_finish(sam_mesh_expect *e, sam_mesh_obj_gather *g);

/* The pre-check's gathering of an OBJ's vertex colours and faces'
 * materials into `expect` (sam_mesh_obj_attributes.c), in the order it
 * reads the file:
 *   sam_mesh_obj_colors c = {0, 1, 0};  sam_mesh_obj_materials m = {SAM_MESH_NO_MATERIAL, 0};
 *   for each v line:       sam_mesh_obj_gather_color(e, &c, its 0-based index, its r g b, or NULL
 *                          when it has none: then no vertex keeps one)
 *   for each usemtl line:  sam_mesh_obj_use_material(e, &m, the name's first character, the line's end)
 *                          (the name is the rest of the line, a comment after a blank and trailing
 *                          blanks left out; SAM_MESH_MAX_MATERIALS names, later ones none)
 *   for each kept face:    sam_mesh_obj_face_material(e, &m, its 0-based index among the kept)
 *   at the end:            sam_mesh_obj_colors_finish(e, &c, the vertex count): the colours scaled
 *                          to [0, 1] (bytes when a value passes 1.5), or dropped
 * Each int function returns 0 when out of memory (then free `expect`). */
typedef struct sam_mesh_obj_colors {
    size_t cap; /* floats of expect->vertex_colors */
    int ok;     /* every vertex so far has a colour */
    float max;
} sam_mesh_obj_colors;
typedef struct sam_mesh_obj_materials {
    uint32_t current; /* the last usemtl's index, or SAM_MESH_NO_MATERIAL */
    size_t face_cap;  /* entries of expect->face_materials */
} sam_mesh_obj_materials;
int sam_mesh_obj_gather_color(sam_mesh_expect *e, sam_mesh_obj_colors *c, uint64_t v, const float *rgb);
void sam_mesh_obj_colors_finish(sam_mesh_expect *e, const sam_mesh_obj_colors *c, uint64_t vertices);
int sam_mesh_obj_use_material(sam_mesh_expect *e, sam_mesh_obj_materials *m, const char *name, const char *eol);
int sam_mesh_obj_face_material(sam_mesh_expect *e, sam_mesh_obj_materials *m, uint64_t face);

/* The file's normal at every corner of `soup` (read from the file that
 * filled `expect`), 3 * corner_count floats into *out (caller frees), the
 * normal of the first corner of the file's face at the same position.
 * Returns SAM_OK with *out NULL when the file names no normals at every
 * corner, or when a face of the soup is not one of the file's (then its
 * vertex normals stand). Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_expect_corner_normals(const sam_mesh_expect *expect, const sam_mesh_soup *soup, float **out,
                                          sam_error *err);

/* Checks the structure of a PLY, OFF, OBJ or STL file before OpenMesh
 * reads it (sam_mesh_preflight.c): OpenMesh's readers trust the counts they
 * parse and loop, crash or allocate gigabytes on corrupt ones, and drop a
 * vertex line whose number does not fit a float (every later index would
 * shift), so every number must fit a 32-bit float. Fills `expect` (zeroed
 * first; known stays 0 for STL and for a file that cannot be opened, which
 * passes: the reader reports it); the caller frees it with
 * sam_mesh_expect_free whatever is returned.
 * Errors: SAM_ERR_FORMAT naming the line or element and the value,
 * SAM_ERR_UNSUPPORTED, SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_preflight(const char *path, sam_mesh_expect *expect, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
