/*
 * sam_shape: procedural triangle meshes with UVs, for tests, demos and
 * benchmarks at any resolution.
 *
 * Every shape is built from rectangular grid patches ("charts"). A chart's
 * vertices carry positions and UVs; where two charts meet, or where a
 * periodic chart closes on itself, the vertices are duplicated (same
 * position, different UV), exactly like the render vertices of a real
 * asset. Seam copies are computed from the same integer lattice point by the
 * same arithmetic, so their positions are bit-identical and welding by exact
 * position recovers the surface.
 *
 * Guarantees for every shape:
 *   - after welding by position, each connected part is a closed, oriented
 *     2-manifold: triangles are counter-clockwise seen from outside, so the
 *     right-hand-rule normals point out and the signed volume is positive;
 *   - no degenerate triangles (each quad is split along its shorter
 *     diagonal, so the corners of a cube-sphere stay well shaped);
 *   - UVs lie in [0,1]; every chart has its own rectangle in the atlas, with
 *     a gap around it, so no two triangles share texture space (texture-space
 *     diffusion needs that); charts are scaled with one common factor, so
 *     texel density is about uniform over the surface; long charts are cut
 *     into pieces to fill the square; every triangle is counter-clockwise
 *     in UV space too.
 *
 * Shapes (units are arbitrary; `suggested_mm_per_unit` of sam_shape_info
 * gives a physically plausible scale for the default size):
 *   sphere  cube-sphere (equal-angle warp, no poles). size = diameter.
 *           resolution = segments around the equator (4 per cube face edge,
 *           rounded up to a multiple of 4).
 *   slab    closed box, width (x) = size, depth (z) = depth, thickness (y)
 *           = thickness, centred at the origin. resolution = segments along
 *           the width; depth and thickness get the same spacing (at least
 *           one segment). Top and bottom use one (x,z) lattice, so every top
 *           vertex has a bottom vertex exactly below it.
 *   torus   axis z. size = outer diameter 2(R + r), thickness = tube
 *           diameter 2r. resolution = segments around the major circle;
 *           the tube gets the same spacing (at least 3 segments).
 *   ear     a thin closed shell: a C-shaped plate around an ellipse whose
 *           outer edge curls over like the helix of an ear, offset by
 *           +-thickness/2 along its normal, closed by a rim. size = height;
 *           thickness = shell thickness (default 2 mm at 60 mm). resolution
 *           = segments along the C; across and through the shell get the
 *           same spacing.
 *   knot    a tube along a (2,3) torus knot (trefoil); strands pass close
 *           to each other (heavy self-occlusion). size = diameter of the
 *           centre line's extent, thickness = tube diameter. resolution =
 *           segments along the knot; the tube gets the same spacing (at
 *           least 6 segments).
 *   blobs   `count` disconnected closed blobs (deformed cube-spheres) in
 *           a cube of edge size, one blob per cell of a grid, so they never
 *           touch; shapes and placement come from `seed`. resolution = as
 *           for sphere, per blob.
 *   perforated  a thin square plate in the x-z plane, centred at the
 *           origin: width and depth = size, thickness (y) = thickness,
 *           with count x count round through-holes, one in the middle of
 *           each cell of a square grid, their diameter 0.6 of the grid's
 *           pitch (genus count^2). resolution = segments along the width,
 *           rounded to a multiple of count with at least 2 per hole
 *           (8 around each hole); the thickness and the ring from a hole
 *           out to its cell's edge get the same spacing (at least one
 *           segment).
 * Parameters a shape does not use are ignored (sam_shape_info says which
 * ones it uses); `seed` is used only by blobs. A thickness must be at least
 * SAM_SHAPE_MIN_RELATIVE_THICKNESS * size, so the two sides of a thin shape
 * stay apart in float precision.
 *
 * Static tables only; every function is thread-safe.
 */
#ifndef SAM_SHAPE_H
#define SAM_SHAPE_H

#include "sam/sam_common.h"
#include "sam/sam_image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bounds on the parameters (inclusive); a mesh must also stay below
 * SAM_SHAPE_MAX_VERTICES render vertices. */
#define SAM_SHAPE_MAX_RESOLUTION 8192
#define SAM_SHAPE_MAX_COUNT 512
#define SAM_SHAPE_MAX_VERTICES 0x7fffffffu
#define SAM_SHAPE_MIN_RELATIVE_THICKNESS 1e-4

typedef struct sam_shape_params {
    int resolution;   /* rough segment count along the main direction (see overview) */
    double size;      /* overall extent, > 0 (see overview per shape) */
    double depth;     /* slab depth (z), > 0 */
    double thickness; /* slab/ear/plate thickness, torus/knot tube diameter, > 0 */
    int count;        /* number of blobs, or holes along each side of the perforated
                         plate, 1..SAM_SHAPE_MAX_COUNT */
    uint64_t seed;    /* blobs' shapes and placement */
} sam_shape_params;

/* Which parameters a shape reads. */
enum {
    SAM_SHAPE_USES_DEPTH = 1,
    SAM_SHAPE_USES_THICKNESS = 2,
    SAM_SHAPE_USES_COUNT = 4,
    SAM_SHAPE_USES_SEED = 8
};

typedef struct sam_shape_info {
    const char *name;
    const char *summary;          /* one line for --help */
    const char *resolution_means; /* what resolution counts, one short phrase */
    int min_resolution;
    unsigned uses;                /* SAM_SHAPE_USES_* flags (resolution and size always used) */
    double suggested_mm_per_unit; /* for the default size */
} sam_shape_info;

typedef struct sam_shape_mesh {
    uint32_t vertex_count;
    float *positions;        /* 3 * vertex_count */
    float *uvs;              /* 2 * vertex_count, in [0,1] for a generated shape; NULL for a
                              * solidified mesh without UVs (sam_mesh_solidify), written without */
    uint32_t triangle_count;
    uint32_t *triangles;     /* 3 * triangle_count, counter-clockwise seen from outside */
} sam_shape_mesh;

/* The shape names, in a fixed order; *count receives how many (may be NULL).
 * The array and strings are static. */
const char *const *sam_shape_names(size_t *count);

/* Static description of shape `name`, or NULL when there is no such shape. */
const sam_shape_info *sam_shape_find(const char *name);

/* Fills `params` with the defaults of shape `name`.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL params, unknown name: the message
 * names it and lists the shapes). */
sam_status sam_shape_default_params(const char *name, sam_shape_params *params, sam_error *err);

/* Generates shape `name` into `mesh` (caller frees with
 * sam_shape_mesh_destroy). Same name and params give bit-identical arrays.
 * On failure `mesh` is zeroed.
 * Errors: SAM_ERR_INVALID_ARGUMENT (unknown name; a parameter out of range,
 * e.g. a thickness that would make the surface intersect itself: the
 * message names the parameter, its value and the allowed range; a
 * resolution whose mesh would exceed SAM_SHAPE_MAX_VERTICES),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_shape_generate(const char *name, const sam_shape_params *params,
                              sam_shape_mesh *mesh, sam_error *err);

/* Largest thickness shape `name` accepts with `params` (its size; for the
 * knot and the ear the limit keeps the surface from intersecting itself):
 * 0 for an unknown name or a shape without thickness, HUGE_VAL for the slab
 * and the perforated plate.
 * Reads only params->size; 0 when the size is not a positive finite number. */
double sam_shape_max_thickness(const char *name, const sam_shape_params *params);

/* Frees the arrays and zeroes `mesh`. Safe on a zeroed mesh and NULL. */
void sam_shape_mesh_destroy(sam_shape_mesh *mesh);

/* Welds render vertices by exact (bitwise) position: ids[v] (vertex_count
 * elements, caller-allocated) receives the index of v's position among the
 * distinct positions, numbered in order of first appearance; *unique_count
 * receives how many there are. Errors: SAM_ERR_INVALID_ARGUMENT (NULL
 * arguments), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_shape_weld(const sam_shape_mesh *mesh, uint32_t *ids, uint32_t *unique_count,
                          sam_error *err);

/* Writes a Wavefront OBJ atomically: each distinct position once as `v`,
 * each render vertex's UV as `vt` (in render vertex order), and faces
 * `f p/t p/t p/t`, so seams are UV splits of one position as in real assets
 * (`f p p p` and no `vt` when `uvs` is NULL).
 * Floats are printed with 9 significant digits (they read back exactly).
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL or empty mesh), SAM_ERR_IO (the
 * message names the path), SAM_ERR_OUT_OF_MEMORY. An existing file at
 * `path` survives a failure. */
sam_status sam_shape_write_obj(const char *path, const sam_shape_mesh *mesh, sam_error *err);

/* The two files sam_shape_write_obj_albedo writes beside an OBJ at `path`:
 * PATH with its extension replaced by ".mtl" and by "_albedo.png" (a path
 * without an extension gets them appended), into `mtl` and `png` (n bytes
 * each). Errors: SAM_ERR_INVALID_ARGUMENT (NULL arguments, a file name
 * with blanks, which an OBJ's material lines cannot name, or names that do
 * not fit in n bytes). */
sam_status sam_shape_obj_companions(const char *path, char *mtl, char *png, size_t n, sam_error *err);

/* Writes the OBJ as sam_shape_write_obj does, carrying `albedo` (a linear
 * image, 3 or 4 channels, such as sam_mesh_load_albedo gives) as the
 * diffuse texture of one material on every face: the texture as an 8-bit
 * sRGB PNG, then a material library naming it (`map_Kd`), then the OBJ
 * with `mtllib` and `usemtl` lines, at the paths sam_shape_obj_companions
 * gives and named in each other by file name alone (so the three move
 * together). Each is written atomically, the OBJ last. Files at the
 * companions' paths are replaced (check first where they must not be).
 * When a later file fails, the companions this call created are removed
 * and those it replaced keep their new contents, so an OBJ that was at
 * `path` (which survives a failure) still names files that exist.
 * `mesh` needs `uvs`. Errors: those of sam_shape_write_obj,
 * sam_shape_obj_companions and sam_image_write_png, and
 * SAM_ERR_INVALID_ARGUMENT (NULL path, albedo or uvs, an empty image). */
sam_status sam_shape_write_obj_albedo(const char *path, const sam_shape_mesh *mesh, const sam_image *albedo,
                                      sam_error *err);

/* Writes a PLY atomically, one PLY vertex per render vertex with float
 * properties x y z u v (x y z when `uvs` is NULL), and faces as `list uchar int vertex_indices`;
 * binary_little_endian when `binary` is non-zero, else ascii (9 significant
 * digits). Errors as sam_shape_write_obj. */
sam_status sam_shape_write_ply(const char *path, const sam_shape_mesh *mesh, int binary,
                               sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
