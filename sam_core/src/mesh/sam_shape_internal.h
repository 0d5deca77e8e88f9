/*
 * Internal: what the sam_shape_*.c files share. Who calls whom (each calls
 * only files below it):
 *   sam_shape.c          the tables, parameter checks and sam_shape_generate
 *   sam_shape_chart.c    charts on the surfaces, the atlas, emission of the mesh
 *   sam_shape_surface.c  each family's surfaces: set-up, limits and the point
 *                        of a lattice coordinate
 * sam_shape_write.c (welding, OBJ and PLY) needs only the public header.
 */
#ifndef SAM_SHAPE_INTERNAL_H
#define SAM_SHAPE_INTERNAL_H

#include <math.h>

#include "sam/sam_shape.h"

enum {
    SHAPE_SPHERE,
    SHAPE_SLAB,
    SHAPE_TORUS,
    SHAPE_EAR,
    SHAPE_KNOT,
    SHAPE_BLOBS,
    SHAPE_PERFORATED,
    SHAPE_COUNT
};

static inline void v3_set(double o[3], double x, double y, double z)
{
    o[0] = x;
    o[1] = y;
    o[2] = z;
}

static inline double v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void v3_cross(const double a[3], const double b[3], double o[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    v3_set(o, x, y, z);
}

static inline double v3_dist(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(v3_dot(d, d));
}

static inline void v3_normalize(double v[3])
{
    double n = sqrt(v3_dot(v, v));
    if (n > 0) {
        v[0] /= n;
        v[1] /= n;
        v[2] /= n;
    }
}

typedef enum map_kind {
    MAP_SPHERE,
    MAP_SLAB,
    MAP_EAR,
    MAP_BLOB,
    MAP_TORUS,
    MAP_KNOT,
    MAP_PERFORATED
} map_kind;

/* The perforated plate's charts: for each hole a ring on the top face, one
 * on the bottom face and the hole's wall, then the plate's outer rim. A
 * chart's face is PERFORATED_PARTS * hole + part; the rim's is
 * PERFORATED_PARTS * holes^2. */
enum { PERFORATED_TOP, PERFORATED_BOTTOM, PERFORATED_WALL, PERFORATED_PARTS };

#define BLOB_BUMPS 4

typedef struct sam_shape_surface {
    map_kind map;
    int n[3];           /* box: lattice segments per axis; tube: n[0] along, n[1] around;
                           perforated: n[0] per hole along x and z, n[1] through the
                           thickness, n[2] from a hole out to its cell's edge */
    double center[3];   /* sphere, blob */
    double radius;      /* sphere/blob base radius, tube radius */
    double half[3];     /* slab and perforated plate half extents */
    double size;        /* ear height */
    double thickness;   /* ear shell thickness */
    double matrix[9];   /* blob: rotation times axis scales, row-major */
    double bump_dir[BLOB_BUMPS][3];
    double bump_amp[BLOB_BUMPS];
    double bump_width[BLOB_BUMPS];
    double major, minor; /* torus R; knot R and r */
    const double *knot_phi; /* knot: curve parameter at each of n[0] arc-length steps */
    int holes;          /* perforated: holes along x and along z */
    double hole_radius; /* perforated */
} sam_shape_surface;

static inline int is_tube(const sam_shape_surface *s)
{
    return s->map == MAP_TORUS || s->map == MAP_KNOT;
}

/* Box face f: axis f/2, at the lattice minimum (even f) or maximum (odd f).
 * The chart's i runs along axis (a+1)%3 and j along (a+2)%3, so i x j is
 * +axis: outward on the maximum side, inward on the minimum side. */
static inline void face_axes(int face, int *a, int *u, int *v)
{
    *a = face / 2;
    *u = (*a + 1) % 3;
    *v = (*a + 2) % 3;
}

typedef struct sam_shape_chart {
    size_t surface;
    int face;            /* box face 0..5, -1 on a tube, perforated: see PERFORATED_PARTS */
    int i0, j0, nu, nv;  /* lattice window */
    int flip;            /* triangles reversed relative to the (i, j) orientation */
    double w, h;         /* world lengths along i and j (through the middle) */
    int rotated;         /* placed with i vertical */
    double x, y;         /* atlas placement, world units */
    uint32_t first_vertex, first_triangle;
} sam_shape_chart;

typedef struct sam_shape_builder {
    sam_shape_surface *surfaces;
    size_t surface_count;
    sam_shape_chart *charts;
    size_t chart_count, chart_cap;
    double *knot_phi;
} sam_shape_builder;

/* sam_shape_surface.c */

/* Position of chart lattice point (i, j). Every seam copy of a point reaches
 * the same integer arguments here, hence bit-identical coordinates. */
void sam_shape_surface_point(const sam_shape_surface *sf, int face, int i, int j, double o[3]);

/* Allocates and sets up the surfaces of shape `shape` (`name` for messages)
 * from parameters already validated. */
sam_status sam_shape_setup_surfaces(int shape, const char *name, const sam_shape_params *p,
                                   sam_shape_builder *b, sam_error *err);

/* Largest thickness of shape `shape` at `size` (see sam_shape_max_thickness). */
double sam_shape_thickness_limit(int shape, double size);

/* sam_shape_chart.c */

/* Adds the charts of surface s: six box faces, one tube or the perforated
 * plate's rings, walls and rim; 0 when out of memory. */
int sam_shape_add_surface_charts(sam_shape_builder *b, size_t s);

/* Cuts charts longer than about the atlas side into pieces along their long
 * direction, so a long tube or rim does not squeeze the whole atlas into a
 * strip; 0 when out of memory. */
int sam_shape_split_long_charts(sam_shape_builder *b);

/* Places every chart in the atlas; *side receives the atlas side in world
 * units; 0 when out of memory. */
int sam_shape_pack_atlas(sam_shape_builder *b, double *side);

/* Writes the positions, triangles and UVs of every chart into `m`, whose
 * arrays hold the counted vertices and triangles. */
void sam_shape_emit(sam_shape_builder *b, double side, sam_shape_mesh *m);

#endif
