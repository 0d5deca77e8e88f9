/*
 * sam_mesh: triangle meshes with the topology the SAM builder and runtime
 * need.
 *
 * A mesh has two vertex sets:
 *   - render vertices: what a GPU draws. A position may appear several times
 *     when a UV or normal seam splits it. `triangles` index render vertices.
 *   - topological vertices ("topo"): render vertices welded by exact
 *     position, then split again only where the surface is not a 2-manifold
 *     there (one topo vertex per fan). Fans, one-rings, back-side choice,
 *     fan areas and curvature live here; every render copy of a topo vertex
 *     shares its result (topo_of maps render -> topo, topo_rep back).
 *
 * One-rings are stored in fan order (counter-clockwise around the outward
 * normal). Consecutive entries (ring[k], ring[k+1]) span one triangle of the
 * fan, so a closed fan (interior vertex) repeats its first neighbour at the
 * end, and an open fan (boundary vertex) starts and ends at its two boundary
 * neighbours. Either way, a vertex with t fan triangles has t + 1 entries,
 * and eq. 16 of the SAM paper is a sum over consecutive pairs with no
 * special case.
 *
 * Loading repairs what cannot be used and reports it (sam_mesh_report):
 * polygons are fan-triangulated; triangles that repeat a welded vertex or
 * have (near-)zero area, and duplicates of a triangle, are dropped; vertices
 * no triangle uses are dropped; non-manifold vertices are split per fan.
 * Coordinates that are not finite, indices out of range and files with no
 * usable triangle are errors.
 *
 * The caller owns a sam_mesh and frees it with sam_mesh_destroy. Loads may
 * run on several threads at once: OBJ, PLY, OFF and STL reads (OpenMesh's
 * readers keep the state of the read under way) take turns on one
 * process-wide lock, glTF reads run side by side. While an OpenMesh read
 * runs, std::cerr's buffer is swapped to capture its diagnostics: the host
 * must not write to std::cerr from another thread during such a load (a
 * data race on that buffer).
 * The computations on a loaded mesh are thread-safe.
 */
#ifndef SAM_MESH_H
#define SAM_MESH_H

#include "sam/sam_common.h"
#include "sam/sam_image.h"
#include "sam/sam_shape.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_mesh {
    /* Render vertices. */
    uint32_t vertex_count;
    float *positions;          /* 3 * vertex_count, model units */
    float *normals;            /* 3 * vertex_count, unit length */
    float *uvs;                /* 2 * vertex_count, or NULL when the mesh has none */
    uint32_t triangle_count;
    uint32_t *triangles;       /* 3 * triangle_count render vertex indices, CCW from outside */

    /* Topology on welded positions. */
    uint32_t topo_count;
    uint32_t *topo_of;         /* vertex_count: render vertex -> topo vertex */
    uint32_t *topo_rep;        /* topo_count: lowest-index render vertex of each topo vertex */
    float *topo_normals;       /* 3 * topo_count: area-weighted geometric normals, unit */
    uint32_t *ring_offsets;    /* topo_count + 1 offsets into ring */
    uint32_t *ring;            /* topo vertex indices in fan order (see overview) */

    /* The input's vertices (a file's, or sam_mesh_input's) against the
     * render vertices, both ways: which input vertex each render vertex
     * came from (its first corner's in triangle order: seam and
     * non-manifold copies share one, merged duplicates take the first), and which render vertex each
     * input vertex became (its first kept corner's), or SAM_MESH_DROPPED
     * when no kept triangle uses it. An engine that loaded the same asset
     * in the same vertex order finds SAM's vertices through them
     * (samfile.h SRCV). */
    uint32_t source_count;
    uint32_t *source_of_render; /* vertex_count, each < source_count */
    uint32_t *render_of_source; /* source_count, each < vertex_count or SAM_MESH_DROPPED */
    /* The input's face (a file's polygon, or sam_mesh_input's triangle)
     * each triangle came from, in the input's order: what a face's
     * material applies to (sam_mesh_load_albedo_maps). NULL in a mesh
     * filled by hand. */
    uint32_t face_count;
    uint32_t *face_of_triangle; /* triangle_count, each < face_count */
} sam_mesh;

#define SAM_MESH_DROPPED 0xFFFFFFFFu

typedef struct sam_mesh_report {
    uint32_t file_vertices;              /* vertices in the file */
    uint32_t file_faces;                 /* faces (polygons) in the file */
    uint32_t polygons_triangulated;      /* faces with more than 3 corners */
    uint32_t crack_vertices_welded;      /* boundary vertices a hair (1e-5 of the size) from another, welded */
    uint32_t faces_too_small;            /* faces with fewer than 3 corners, dropped */
    uint32_t degenerate_triangles;       /* repeat a welded vertex, dropped */
    uint32_t zero_area_triangles;        /* area ~ 0 relative to their edges, dropped */
    uint32_t duplicate_triangles;        /* same welded vertices as an earlier one, dropped */
    uint32_t triangles_turned;           /* wound against their neighbours, turned to agree */
    uint32_t unreferenced_vertices;      /* file vertices no kept triangle uses, dropped */
    uint32_t non_manifold_vertices;      /* welded positions split into several fans */
    uint32_t non_manifold_edges;         /* edges with >2 triangles or inconsistent winding */
    uint32_t boundary_vertices;          /* topo vertices with an open fan */
    uint32_t seam_vertices;              /* topo vertices with more than one render copy */
    int normals_from_file;               /* 1 when the file's normals were used */
    int invalid_file_normals;            /* file normals of zero length replaced */
} sam_mesh_report;

/* Raw input for sam_mesh_create (a polygon-free triangle list). */
typedef struct sam_mesh_input {
    const char *name;          /* for messages, e.g. a file name; may be NULL */
    uint32_t vertex_count;
    const float *positions;    /* 3 * vertex_count, required */
    const float *normals;      /* 3 * vertex_count, or NULL: area-weighted normals are computed */
    const float *uvs;          /* 2 * vertex_count, or NULL */
    uint32_t triangle_count;
    const uint32_t *triangles; /* 3 * triangle_count indices < vertex_count */
} sam_mesh_input;

/* Loads OBJ, PLY (ASCII and binary), OFF or STL through OpenMesh, or glTF
 * 2.0 (.gltf, .glb: every triangle primitive of the default scene with its
 * node transforms, TEXCOORD_0; geometry compressed with meshopt or Draco
 * decoded) through TinyGLTF, then welds, repairs and builds the topology as
 * described above.
 * `report` may be NULL. On failure `mesh` is zeroed (nothing to free).
 * Errors: SAM_ERR_IO (missing/unreadable), SAM_ERR_UNSUPPORTED (extension, or
 * a compression it does not decode),
 * SAM_ERR_FORMAT (unparseable, non-finite coordinate, index out of range:
 * the message names the element and value), SAM_ERR_EMPTY (empty file, no
 * usable triangle), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_load(const char *path, sam_mesh *mesh, sam_mesh_report *report, sam_error *err);

/* Builds a mesh from arrays the caller keeps owning (copied). Same repairs,
 * report and errors as sam_mesh_load. */
sam_status sam_mesh_create(const sam_mesh_input *input, sam_mesh *mesh, sam_mesh_report *report,
                           sam_error *err);

/* The albedo texture a mesh file brings along: the map_Kd of an OBJ's
 * first used material that has one (through its mtllib; PNG, JPEG or TGA),
 * a PLY's "comment TextureFile NAME" header line (MeshLab's and
 * Metashape's), or the base-colour texture of a glTF's first used material
 * that has one, times its baseColorFactor. A linear image in `image`
 * (caller destroys; zeroed when the file brings none). `note` (note_size
 * bytes, > 0; 2 KiB hold any) names the texture when `image` holds one (for
 * the tools' list of what they assumed), and how many other textures the
 * file's used materials name: one map is read at every part's UVs, so
 * their parts show this one. A texture the file names but that
 * cannot be used is no error: `image` is then empty and `note` says why,
 * for a warning; "" when the file names none.
 * Errors: SAM_ERR_INVALID_ARGUMENT, SAM_ERR_IO (the mesh file cannot be
 * read), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_load_albedo(const char *path, sam_image *image, char *note, size_t note_size, sam_error *err);

/* The albedo maps of a file whose faces read more than one (an OBJ's
 * materials with their map_Kd, a PLY's TextureFile comments by its faces'
 * texnumber, a glTF's materials with their base colours), for
 * sam_runtime_set_albedo_maps. Caller frees with sam_albedo_maps_destroy. */
typedef struct sam_albedo_maps {
    uint32_t map_count;
    sam_image *maps;     /* map_count linear images: an OBJ's or PLY's distinct texture files; a glTF's used
                          * materials' base colour, its texture times its factor (1 x 1 without one) */
    uint32_t face_count; /* the file's faces, as sam_mesh.face_of_triangle numbers them */
    uint32_t *face_map;  /* face_count: the map each face reads, or SAM_ALBEDO_NO_MAP (white) */
} sam_albedo_maps;

#define SAM_ALBEDO_NO_MAP 0xFFFFFFFFu

/* The maps of a file whose faces read more than one: faces of materials
 * with different textures, or some with a texture and some without. A
 * file that needs one map at most (one texture on every face; OFF, STL)
 * gives map_count 0: sam_mesh_load_albedo reads it. A texture that
 * cannot be used leaves its faces white and `note` (note_size bytes, > 0)
 * says why, for a warning; else "". On failure `maps` is zeroed.
 * Errors: SAM_ERR_INVALID_ARGUMENT, SAM_ERR_IO, SAM_ERR_FORMAT (a file
 * sam_mesh_load refuses too), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_load_albedo_maps(const char *path, sam_albedo_maps *maps, char *note, size_t note_size,
                                     sam_error *err);
void sam_albedo_maps_destroy(sam_albedo_maps *maps);

/* The colours a mesh file gives its vertices: a PLY's red, green and
 * blue (or diffuse_red...; sRGB-encoded, any integer type scaled by its
 * largest value), an OBJ's "v x y z r g b" on every vertex line (0..1, or
 * 0..255 when a value passes 1; sRGB-encoded), a glTF's COLOR_0 (linear;
 * white on primitives without it). OFF and STL colours are not read.
 * Linear RGB, one per vertex of the file in its order (the order of
 * sam_mesh.source_of_render's values and of a .sam's SRCV): *count
 * vertices, 3 * *count floats in *rgb (caller frees); *rgb NULL and
 * *count 0 when the file has none. `note` (note_size bytes, > 0) names
 * them when there are some ("the vertex colours of NAME"), else "".
 * Errors: SAM_ERR_INVALID_ARGUMENT, SAM_ERR_IO, SAM_ERR_FORMAT (a file
 * sam_mesh_load would refuse too), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_load_vertex_colors(const char *path, float **rgb, uint32_t *count, char *note, size_t note_size,
                                       sam_error *err);

/* 1 when `path` ends in an extension sam_mesh_load reads (.obj, .ply,
 * .off, .stl, .gltf, .glb; case-insensitive), else 0. */
int sam_mesh_is_mesh_path(const char *path);

/* Frees everything a mesh owns and zeroes it. Safe on a zeroed mesh. */
void sam_mesh_destroy(sam_mesh *mesh);

/* Axis-aligned bounds of the render positions (model units). This reads
 * only `positions` and `vertex_count`, sam_mesh_diagonal those and the
 * triangles, so a mesh struct holding just those (a map's, say) may be
 * passed. */
void sam_mesh_bounds(const sam_mesh *mesh, float min[3], float max[3]);

/* A piece of the surface (triangles joined through shared or coincident
 * vertices) with less than this fraction of the largest piece's area is a
 * loose speck: a scan's stray triangle, a forgotten fin. */
#define SAM_MESH_LOOSE_FRACTION 0.01

typedef struct sam_mesh_body_info {
    float min[3], max[3];     /* bounds of the body (every piece but the specks), model units */
    int box_changed;          /* 1 when the specks lie outside the body's bounds */
    uint32_t loose_pieces;    /* specks left out */
    uint32_t loose_vertices;  /* render vertices in them */
    double loose_area, total_area; /* model units^2 */
} sam_mesh_body_info;

/* The mesh's body: every piece but the loose specks (see
 * SAM_MESH_LOOSE_FRACTION). Reads `positions`, `vertex_count`, `triangles`
 * and `triangle_count` only (a map's arrays may be passed); without
 * triangles every vertex is the body, with them a vertex no triangle uses
 * is a speck of its own (a loaded mesh has none). `in_body` (vertex_count bytes, may
 * be NULL) gets 1 for a body vertex, 0 for a speck's.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL, or a triangle naming a vertex
 * past vertex_count), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_body(const sam_mesh *mesh, uint8_t *in_body, sam_mesh_body_info *info, sam_error *err);

/* Length (model units) of the diagonal of the box from min to max. */
double sam_mesh_box_diagonal(const float min[3], const float max[3]);

/* Length of the body's bounds' diagonal (model units; sam_mesh_body, all
 * the bounds when that runs out of memory), which --size-mm and the
 * scenes' "size_mm" scale to: a stray speck far from the object does not
 * change its size. 0 for a mesh with no extent, infinity for one with no
 * vertices. */
double sam_mesh_diagonal(const sam_mesh *mesh);

/* Reduced fan area F' of every topo vertex (SAM paper eq. 16): one third of
 * the area of the triangles around it, in (mm_per_unit)^2 * model units^2,
 * i.e. mm^2 when mm_per_unit converts model units to millimetres.
 * `out` has topo_count elements. `positions` (3 * vertex_count, render
 * vertex layout) may be NULL to use the mesh's own, or a deformed pose. */
void sam_mesh_fan_areas(const sam_mesh *mesh, const float *positions, float mm_per_unit, float *out);

/* Mean curvature H of every topo vertex in 1/model units (cotangent
 * Laplacian over the one-ring, mixed Voronoi area), positive where the
 * surface is convex along its outward normal (a sphere of radius R gives
 * 1/R). Boundary vertices, where the cotangent formula is incomplete, take
 * the mean of their interior ring neighbours (0 if none).
 * `out` has topo_count elements. */
void sam_mesh_mean_curvature(const sam_mesh *mesh, float *out);

/* The same mean curvature for any vertices with fan-ordered rings (the
 * layout above, also a .sam's ADJO/ADJV): `count` vertices; vertex i's
 * position is positions[3 * position_of[i]] (position_of NULL: identity),
 * its normal normals[3 * i]; ring entries are vertex indices. `out` has
 * `count` elements, 1/position units. */
void sam_mesh_ring_curvature(uint32_t count, const float *positions, const uint32_t *position_of,
                             const float *normals, const uint32_t *ring_offsets, const uint32_t *ring, float *out);

/* The volume the triangles enclose, model units^3: positive when they wind
 * counter-clockwise seen from outside (the convention above), negative for
 * a closed mesh turned inside out; meaningless for an open one. */
double sam_mesh_signed_volume(const sam_mesh *mesh);

/* 1 when every topo vertex's fan is closed (no boundary), else 0. */
int sam_mesh_is_closed(const sam_mesh *mesh);

/* Turns a closed mesh with negative signed volume (its normals pointing
 * in, as some exporters write) outside out: triangles rewound, render and
 * topo normals negated, rings reversed. Returns 1 when it did, 0 for an
 * open mesh or one already facing out (left as it is). A mesh facing in
 * renders black: its back side is its front. */
int sam_mesh_orient_outward(sam_mesh *mesh);

/* The winding number of `point` about the `triangle_count` triangles
 * (3 indices each into `positions`, 3 floats per vertex, counter-clockwise
 * seen from outside): about 1 inside a closed mesh, 0 outside, something
 * between near or inside an open one. Takes one pass over the triangles;
 * works on a mesh's or a .sam's arrays. */
double sam_mesh_winding_number(const float *positions, const uint32_t *triangles, uint32_t triangle_count,
                               const float point[3]);

/* Whether 32-bit floats place the mesh's vertices finely enough: 1 when
 * the spacing of floats at its farthest coordinate from the origin is over
 * a twentieth of its mean edge (a scan left in georeferenced coordinates,
 * say, whose vertices the loader rounded to a grid as coarse as its
 * triangles: its normals and shading come out blotched), with a one-line
 * warning naming the offset, the spacing and what to do in buf (size n);
 * else 0 and buf "". Reads positions and triangles only. `name` (for the
 * message; NULL: "the mesh") may be NULL; a mesh without triangles, a NULL
 * buf or n = 0 give 0 (buf untouched for the last two). */
int sam_mesh_precision_warning(const sam_mesh *mesh, const char *name, char *buf, size_t n);

/* What sam_mesh_solidify did. */
typedef struct sam_mesh_solidify_report {
    uint32_t open_parts;      /* connected parts with a boundary: given thickness */
    uint32_t closed_parts;    /* closed parts: copied as they are */
    uint32_t rim_edges;       /* boundary edges, each closed by a quad of the rim */
    uint32_t folded_vertices; /* vertices of open parts curved tighter than half the thickness
                               * (|mean curvature| * thickness > 1: a cylinder's radius under
                               * half the thickness): the inner face may cross itself there */
} sam_mesh_solidify_report;

/* Gives every open connected part of `mesh` (a single sheet: a leaf, a
 * cloth card, paper) a thickness of `thickness` model units, so that light
 * has a back side to come through: the sheet becomes the mid-surface of a
 * thin solid, its render vertices moved half the thickness along their
 * topo normal (the front, triangles as they were) and copied half the
 * thickness the other way (the back, triangles wound the other way, the
 * same UVs), and each boundary edge closed by a quad between the two.
 * Closed parts are copied unchanged. In `out` (caller frees with
 * sam_shape_mesh_destroy; zeroed on failure): the mesh's render vertices
 * in their order, then the back copies in render order; the mesh's
 * triangles, then the back's, then the rim's two per boundary edge in
 * triangle order. `uvs` is NULL when the mesh has none. Write it with
 * sam_shape_write_obj or _ply and load it again: welded by position it is
 * closed where the sheet was open. `report` may be NULL.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL mesh or out; a thickness outside
 * SAM_SHAPE_MIN_RELATIVE_THICKNESS..1 times the mesh's diagonal: the
 * message gives both; faces that would leave float range, on a mesh near
 * FLT_MAX; a result past SAM_SHAPE_MAX_VERTICES),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_mesh_solidify(const sam_mesh *mesh, float thickness, sam_shape_mesh *out,
                             sam_mesh_solidify_report *report, sam_error *err);

/* One-line summary of a report's repairs into buf (size n), e.g.
 * "dropped 2 degenerate, 1 zero-area triangles; split 1 non-manifold vertex"
 * or "no repairs". Returns buf. */
char *sam_mesh_report_summary(const sam_mesh_report *report, char *buf, size_t n);

#ifdef __cplusplus
}
#endif

#endif
