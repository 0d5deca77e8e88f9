#define _POSIX_C_SOURCE 200809L
#include "sam/sam_shape.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SHAPE_PI 3.14159265358979323846

/* ---------------------------------------------------------------- tables */

enum { SHAPE_SPHERE, SHAPE_SLAB, SHAPE_TORUS, SHAPE_EAR, SHAPE_KNOT, SHAPE_BLOBS, SHAPE_COUNT };

static const char *const shape_names[SHAPE_COUNT] = {"sphere", "slab", "torus",
                                                     "ear",    "knot", "blobs"};

static const sam_shape_info shape_infos[SHAPE_COUNT] = {
    {"sphere", "cube-sphere, size = diameter", "segments around the equator", 4, 0, 30.0},
    {"slab", "closed thin box, size = width (x), depth (z), thickness (y)",
     "segments along the width", 1, SAM_SHAPE_USES_DEPTH | SAM_SHAPE_USES_THICKNESS, 50.0},
    {"torus", "torus around z, size = outer diameter, thickness = tube diameter",
     "segments around the major circle", 8, SAM_SHAPE_USES_THICKNESS, 40.0},
    {"ear", "thin curled shell like the rim of an ear, size = height",
     "segments along the rim", 8, SAM_SHAPE_USES_THICKNESS, 60.0},
    {"knot", "tube along a (2,3) torus knot, thickness = tube diameter",
     "segments along the knot", 24, SAM_SHAPE_USES_THICKNESS, 40.0},
    {"blobs", "count disjoint deformed spheres in a cube of edge size",
     "segments around each blob's equator", 4, SAM_SHAPE_USES_COUNT | SAM_SHAPE_USES_SEED, 30.0},
};

static const sam_shape_params shape_defaults[SHAPE_COUNT] = {
    {64, 1.0, 1.0, 0.1, 1, 1},
    {64, 1.0, 1.0, 0.04, 1, 1},
    {96, 1.0, 1.0, 0.3, 1, 1},
    {128, 1.0, 1.0, 2.0 / 60.0, 1, 1},
    {256, 1.0, 1.0, 0.18, 1, 1},
    {32, 1.0, 1.0, 0.1, 6, 1},
};

/* Ear geometry, relative to the height: the inner edge of the plate is an
 * ellipse arc; the plate leaves it tilted out of plane, then curls. */
#define EAR_ELLIPSE_X 0.20
#define EAR_ELLIPSE_Y 0.30
#define EAR_PHI0 (50.0 * SHAPE_PI / 180.0)
#define EAR_PHI1 (300.0 * SHAPE_PI / 180.0)
#define EAR_FLAT 0.12
#define EAR_CURL 0.13
#define EAR_TILT (20.0 * SHAPE_PI / 180.0)
#define EAR_CURL_ANGLE 2.2 /* radians at the top of the rim */
#define EAR_LOBE_CURL 0.3  /* fraction of the curl angle left at the lobe */

/* Torus: the hole must stay open. */
#define TORUS_MAX_RELATIVE_THICKNESS 0.45
/* Knot: tube radius at most this fraction of the tube's geometric limit. */
#define KNOT_SAFETY 0.9
#define KNOT_LIMIT_SAMPLES 600
#define KNOT_ARC_SAMPLES 8192
/* Gap around each chart, as a fraction of sqrt(total chart area). */
#define ATLAS_GAP (1.0 / 128.0)

static int shape_index(const char *name)
{
    if (!name)
        return -1;
    for (int i = 0; i < SHAPE_COUNT; ++i)
        if (strcmp(name, shape_names[i]) == 0)
            return i;
    return -1;
}

static sam_status fail_unknown(sam_error *err, const char *name)
{
    char known[128] = "";
    for (int i = 0; i < SHAPE_COUNT; ++i) {
        size_t used = strlen(known);
        snprintf(known + used, sizeof known - used, "%s%s", i ? ", " : "", shape_names[i]);
    }
    return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape \"%s\": unknown (known: %s)",
                    name ? name : "(null)", known);
}

const char *const *sam_shape_names(size_t *count)
{
    if (count)
        *count = SHAPE_COUNT;
    return shape_names;
}

const sam_shape_info *sam_shape_find(const char *name)
{
    int s = shape_index(name);
    return s < 0 ? NULL : &shape_infos[s];
}

sam_status sam_shape_default_params(const char *name, sam_shape_params *params, sam_error *err)
{
    int s = shape_index(name);
    if (s < 0)
        return fail_unknown(err, name);
    if (!params)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape %s: no params to fill", name);
    *params = shape_defaults[s];
    return SAM_OK;
}

/* ---------------------------------------------------------------- vectors */

static void v3_set(double o[3], double x, double y, double z)
{
    o[0] = x;
    o[1] = y;
    o[2] = z;
}

static double v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void v3_cross(const double a[3], const double b[3], double o[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    v3_set(o, x, y, z);
}

static double v3_dist(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(v3_dot(d, d));
}

static void v3_normalize(double v[3])
{
    double n = sqrt(v3_dot(v, v));
    if (n > 0) {
        v[0] /= n;
        v[1] /= n;
        v[2] /= n;
    }
}

/* ---------------------------------------------------------------- random */

/* splitmix64: small, fast and good enough for placing blobs; the state is the
 * caller's, so generation stays reentrant. */
static uint64_t rng_next(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double rng_uniform(uint64_t *state, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(rng_next(state) >> 11) * (1.0 / 9007199254740992.0));
}

static void rng_unit_vector(uint64_t *state, double o[3])
{
    double z = rng_uniform(state, -1.0, 1.0);
    double a = rng_uniform(state, 0.0, 2.0 * SHAPE_PI);
    double r = sqrt(fmax(0.0, 1.0 - z * z));
    v3_set(o, r * cos(a), r * sin(a), z);
}

/* ---------------------------------------------------------------- surfaces */

typedef enum map_kind { MAP_SPHERE, MAP_SLAB, MAP_EAR, MAP_BLOB, MAP_TORUS, MAP_KNOT } map_kind;

#define BLOB_BUMPS 4

typedef struct surface {
    map_kind map;
    int n[3];           /* box: lattice segments per axis; tube: n[0] along, n[1] around */
    double center[3];   /* sphere, blob */
    double radius;      /* sphere/blob base radius, tube radius */
    double half[3];     /* slab half extents */
    double size;        /* ear height */
    double thickness;   /* ear shell thickness */
    double matrix[9];   /* blob: rotation times axis scales, row-major */
    double bump_dir[BLOB_BUMPS][3];
    double bump_amp[BLOB_BUMPS];
    double bump_width[BLOB_BUMPS];
    double major, minor; /* torus R; knot R and r */
    const double *knot_phi; /* knot: curve parameter at each of n[0] arc-length steps */
} surface;

static int is_tube(const surface *s)
{
    return s->map == MAP_TORUS || s->map == MAP_KNOT;
}

/* Equal-angle cube-sphere direction of lattice point c on a cube of n
 * segments per edge. */
static void cube_direction(const int c[3], int n, double d[3])
{
    for (int k = 0; k < 3; ++k)
        d[k] = tan(SHAPE_PI / 4.0 * (2.0 * c[k] / n - 1.0));
    v3_normalize(d);
}

static double ear_curl_angle(double s)
{
    double x = (s - 0.6) / 0.4;
    x = x < 0 ? 0 : (x > 1 ? 1 : x);
    double smooth = x * x * (3.0 - 2.0 * x);
    return EAR_CURL_ANGLE * (1.0 - (1.0 - EAR_LOBE_CURL) * smooth);
}

/* Mid-surface of the ear: s along the C, t across from the inner edge. */
static void ear_mid(double height, double s, double t, double o[3])
{
    double phi = EAR_PHI0 + s * (EAR_PHI1 - EAR_PHI0);
    double ax = EAR_ELLIPSE_X * height, ay = EAR_ELLIPSE_Y * height;
    double flat = EAR_FLAT * height, curl = EAR_CURL * height;
    double out[3] = {ay * cos(phi), ax * sin(phi), 0.0};
    v3_normalize(out);
    double l = t * (flat + curl);
    double r, z;
    if (l <= flat) {
        r = l * cos(EAR_TILT);
        z = l * sin(EAR_TILT);
    } else {
        double kappa = ear_curl_angle(s) / curl;
        double m = l - flat;
        r = flat * cos(EAR_TILT) + (sin(EAR_TILT + kappa * m) - sin(EAR_TILT)) / kappa;
        z = flat * sin(EAR_TILT) + (cos(EAR_TILT) - cos(EAR_TILT + kappa * m)) / kappa;
    }
    v3_set(o, ax * cos(phi) + r * out[0], ay * sin(phi) + r * out[1], z);
}

static void ear_point(const surface *sf, double s, double t, double offset, double o[3])
{
    const double e = 1e-5;
    double a[3], b[3], c[3], d[3], ds[3], dt[3], nrm[3];
    ear_mid(sf->size, s + e, t, a);
    ear_mid(sf->size, s - e, t, b);
    ear_mid(sf->size, s, t + e, c);
    ear_mid(sf->size, s, t - e, d);
    for (int k = 0; k < 3; ++k) {
        ds[k] = a[k] - b[k];
        dt[k] = c[k] - d[k];
    }
    v3_cross(ds, dt, nrm);
    v3_normalize(nrm);
    ear_mid(sf->size, s, t, o);
    for (int k = 0; k < 3; ++k)
        o[k] += offset * nrm[k];
}

static void knot_curve(const surface *sf, double phi, double p[3], double dp[3])
{
    double R = sf->major, r = sf->minor;
    double rho = R + r * cos(3 * phi), drho = -3 * r * sin(3 * phi);
    v3_set(p, rho * cos(2 * phi), rho * sin(2 * phi), r * sin(3 * phi));
    v3_set(dp, drho * cos(2 * phi) - 2 * rho * sin(2 * phi),
           drho * sin(2 * phi) + 2 * rho * cos(2 * phi), 3 * r * cos(3 * phi));
}

/* Tube point at segment i along the centre line and j around it. The normal
 * N is the direction from the torus core circle to the curve, which is
 * exactly perpendicular to the tangent for both the torus and the knot, so
 * the frame closes on itself without twist correction. */
static void tube_point(const surface *sf, int i, int j, double o[3])
{
    double p[3], t[3], nrm[3], b[3];
    if (sf->map == MAP_TORUS) {
        double phi = 2.0 * SHAPE_PI * i / sf->n[0];
        v3_set(p, sf->major * cos(phi), sf->major * sin(phi), 0.0);
        v3_set(t, -sin(phi), cos(phi), 0.0);
        v3_set(nrm, cos(phi), sin(phi), 0.0);
    } else {
        double phi = sf->knot_phi[i];
        knot_curve(sf, phi, p, t);
        v3_set(nrm, cos(3 * phi) * cos(2 * phi), cos(3 * phi) * sin(2 * phi), sin(3 * phi));
    }
    v3_normalize(t);
    v3_cross(t, nrm, b);
    double theta = 2.0 * SHAPE_PI * j / sf->n[1];
    double c = cos(theta), s = sin(theta);
    for (int k = 0; k < 3; ++k)
        o[k] = p[k] + sf->radius * (c * nrm[k] + s * b[k]);
}

static double blob_radius_factor(const surface *sf, const double d[3])
{
    double rho = 1.0;
    for (int m = 0; m < BLOB_BUMPS; ++m) {
        double w = sf->bump_width[m];
        rho += sf->bump_amp[m] * exp((v3_dot(d, sf->bump_dir[m]) - 1.0) / (w * w));
    }
    return rho;
}

/* Box face f: axis f/2, at the lattice minimum (even f) or maximum (odd f).
 * The chart's i runs along axis (a+1)%3 and j along (a+2)%3, so i x j is
 * +axis: outward on the maximum side, inward on the minimum side. */
static void face_axes(int face, int *a, int *u, int *v)
{
    *a = face / 2;
    *u = (*a + 1) % 3;
    *v = (*a + 2) % 3;
}

static void box_point(const surface *sf, int face, int i, int j, double o[3])
{
    int a, u, v, c[3];
    face_axes(face, &a, &u, &v);
    c[a] = (face % 2) ? sf->n[a] : 0;
    c[u] = i;
    c[v] = j;
    switch (sf->map) {
    case MAP_SPHERE: {
        double d[3];
        cube_direction(c, sf->n[0], d);
        for (int k = 0; k < 3; ++k)
            o[k] = sf->center[k] + sf->radius * d[k];
        break;
    }
    case MAP_BLOB: {
        double d[3];
        cube_direction(c, sf->n[0], d);
        double r = sf->radius * blob_radius_factor(sf, d);
        for (int k = 0; k < 3; ++k)
            o[k] = sf->center[k] + r * (sf->matrix[3 * k] * d[0] + sf->matrix[3 * k + 1] * d[1] +
                                        sf->matrix[3 * k + 2] * d[2]);
        break;
    }
    case MAP_SLAB:
        for (int k = 0; k < 3; ++k)
            o[k] = -sf->half[k] + (2.0 * sf->half[k]) * ((double)c[k] / sf->n[k]);
        break;
    case MAP_EAR:
        ear_point(sf, (double)c[0] / sf->n[0], (double)c[2] / sf->n[2],
                  ((double)c[1] / sf->n[1] - 0.5) * sf->thickness, o);
        break;
    case MAP_TORUS:
    case MAP_KNOT:
        break;
    }
}

/* Position of chart lattice point (i, j). Every seam copy of a point reaches
 * the same integer arguments here, hence bit-identical coordinates. */
static void surface_point(const surface *sf, int face, int i, int j, double o[3])
{
    if (is_tube(sf))
        tube_point(sf, i % sf->n[0], j % sf->n[1], o);
    else
        box_point(sf, face, i, j, o);
}

/* ---------------------------------------------------------------- charts */

typedef struct chart {
    size_t surface;
    int face;            /* box face 0..5, or -1 on a tube */
    int i0, j0, nu, nv;  /* lattice window */
    int flip;            /* triangles reversed relative to the (i, j) orientation */
    double w, h;         /* world lengths along i and j (through the middle) */
    int rotated;         /* placed with i vertical */
    double x, y;         /* atlas placement, world units */
    uint32_t first_vertex, first_triangle;
} chart;

typedef struct builder {
    surface *surfaces;
    size_t surface_count;
    chart *charts;
    size_t chart_count, chart_cap;
    double *knot_phi;
} builder;

static void builder_free(builder *b)
{
    free(b->surfaces);
    free(b->charts);
    free(b->knot_phi);
    memset(b, 0, sizeof *b);
}

static int push_chart(builder *b, const chart *c)
{
    if (b->chart_count == b->chart_cap) {
        size_t cap = b->chart_cap ? 2 * b->chart_cap : 64;
        chart *grown = realloc(b->charts, cap * sizeof *grown);
        if (!grown)
            return 0;
        b->charts = grown;
        b->chart_cap = cap;
    }
    b->charts[b->chart_count++] = *c;
    return 1;
}

static void measure_chart(const builder *b, chart *c)
{
    const surface *sf = &b->surfaces[c->surface];
    double prev[3], p[3];
    c->w = 0.0;
    c->h = 0.0;
    int jm = c->j0 + c->nv / 2, im = c->i0 + c->nu / 2;
    surface_point(sf, c->face, c->i0, jm, prev);
    for (int i = 1; i <= c->nu; ++i) {
        surface_point(sf, c->face, c->i0 + i, jm, p);
        c->w += v3_dist(prev, p);
        memcpy(prev, p, sizeof p);
    }
    surface_point(sf, c->face, im, c->j0, prev);
    for (int j = 1; j <= c->nv; ++j) {
        surface_point(sf, c->face, im, c->j0 + j, p);
        c->h += v3_dist(prev, p);
        memcpy(prev, p, sizeof p);
    }
}

static int add_surface_charts(builder *b, size_t s)
{
    const surface *sf = &b->surfaces[s];
    chart c;
    memset(&c, 0, sizeof c);
    c.surface = s;
    if (is_tube(sf)) {
        c.face = -1;
        c.nu = sf->n[0];
        c.nv = sf->n[1];
        /* i along the tangent, j around: i x j points into the tube. */
        c.flip = 1;
        return push_chart(b, &c);
    }
    for (int f = 0; f < 6; ++f) {
        int a, u, v;
        face_axes(f, &a, &u, &v);
        c.face = f;
        c.nu = sf->n[u];
        c.nv = sf->n[v];
        c.flip = (f % 2) == 0;
        if (!push_chart(b, &c))
            return 0;
    }
    return 1;
}

/* Cuts charts longer than about the atlas side into pieces along their long
 * direction, so a long tube or rim does not squeeze the whole atlas into a
 * strip. */
static int split_long_charts(builder *b)
{
    double area = 0.0;
    for (size_t k = 0; k < b->chart_count; ++k) {
        measure_chart(b, &b->charts[k]);
        area += b->charts[k].w * b->charts[k].h;
    }
    double limit = sqrt(area);
    size_t original = b->chart_count;
    for (size_t k = 0; k < original; ++k) {
        chart c = b->charts[k];
        int along_i = c.w >= c.h;
        double len = along_i ? c.w : c.h;
        int segs = along_i ? c.nu : c.nv;
        int pieces = (int)ceil(len / limit);
        if (pieces > segs)
            pieces = segs;
        if (pieces <= 1)
            continue;
        for (int p = 0; p < pieces; ++p) {
            int lo = (int)((long long)segs * p / pieces);
            int hi = (int)((long long)segs * (p + 1) / pieces);
            chart piece = c;
            if (along_i) {
                piece.i0 = c.i0 + lo;
                piece.nu = hi - lo;
            } else {
                piece.j0 = c.j0 + lo;
                piece.nv = hi - lo;
            }
            measure_chart(b, &piece);
            if (p == 0) {
                b->charts[k] = piece;
            } else if (!push_chart(b, &piece)) {
                return 0;
            }
        }
    }
    return 1;
}

/* ---------------------------------------------------------------- atlas */

typedef struct pack_item {
    double w, h;
    size_t index;
} pack_item;

static int pack_item_cmp(const void *pa, const void *pb)
{
    const pack_item *a = pa, *b = pb;
    if (a->h != b->h)
        return a->h > b->h ? -1 : 1;
    return a->index < b->index ? -1 : (a->index > b->index);
}

/* Shelf packing; returns the side of the square that holds everything. */
static double shelf_pack(const pack_item *items, size_t count, double limit, double gap,
                         chart *charts)
{
    double x = gap, y = gap, shelf = 0.0, extent_x = 0.0;
    for (size_t k = 0; k < count; ++k) {
        if (x > gap && x + items[k].w + gap > limit) {
            y += shelf + gap;
            x = gap;
            shelf = 0.0;
        }
        if (charts) {
            charts[items[k].index].x = x;
            charts[items[k].index].y = y;
        }
        x += items[k].w + gap;
        if (items[k].h > shelf)
            shelf = items[k].h;
        if (x > extent_x)
            extent_x = x;
    }
    double extent_y = y + shelf + gap;
    return extent_x > extent_y ? extent_x : extent_y;
}

static int pack_atlas(builder *b, double *side)
{
    size_t n = b->chart_count;
    pack_item *items = malloc(n * sizeof *items);
    if (!items)
        return 0;
    double area = 0.0, widest = 0.0;
    for (size_t k = 0; k < n; ++k) {
        chart *c = &b->charts[k];
        c->rotated = c->h > c->w;
        items[k].w = c->rotated ? c->h : c->w;
        items[k].h = c->rotated ? c->w : c->h;
        items[k].index = k;
        area += c->w * c->h;
        if (items[k].w > widest)
            widest = items[k].w;
    }
    double gap = ATLAS_GAP * sqrt(area);
    double padded = 0.0;
    for (size_t k = 0; k < n; ++k)
        padded += (items[k].w + gap) * (items[k].h + gap);
    qsort(items, n, sizeof *items, pack_item_cmp);
    /* Try a few shelf widths around the square root of the area. */
    double best_limit = 0.0, best = HUGE_VAL;
    for (int t = 0; t <= 12; ++t) {
        double limit = sqrt(padded) * (0.9 + 0.1 * t) + gap;
        if (limit < widest + 2.0 * gap)
            limit = widest + 2.0 * gap;
        double s = shelf_pack(items, n, limit, gap, NULL);
        if (s < best) {
            best = s;
            best_limit = limit;
        }
    }
    *side = shelf_pack(items, n, best_limit, gap, b->charts);
    free(items);
    return 1;
}

/* ---------------------------------------------------------------- emission */

static double dist2f(const float *a, const float *b)
{
    double d0 = (double)a[0] - b[0], d1 = (double)a[1] - b[1], d2 = (double)a[2] - b[2];
    return d0 * d0 + d1 * d1 + d2 * d2;
}

static void emit_chart(const builder *b, const chart *c, sam_shape_mesh *m)
{
    const surface *sf = &b->surfaces[c->surface];
    uint32_t row = (uint32_t)c->nu + 1;
    for (int j = 0; j <= c->nv; ++j)
        for (int i = 0; i <= c->nu; ++i) {
            double p[3];
            surface_point(sf, c->face, c->i0 + i, c->j0 + j, p);
            float *o = m->positions + 3 * ((size_t)c->first_vertex + (size_t)j * row + i);
            o[0] = (float)p[0];
            o[1] = (float)p[1];
            o[2] = (float)p[2];
        }
    uint32_t *t = m->triangles + 3 * (size_t)c->first_triangle;
    for (int j = 0; j < c->nv; ++j)
        for (int i = 0; i < c->nu; ++i) {
            uint32_t v00 = c->first_vertex + (uint32_t)j * row + (uint32_t)i;
            uint32_t v10 = v00 + 1, v01 = v00 + row, v11 = v01 + 1;
            uint32_t q[6];
            /* The shorter diagonal keeps skewed quads (cube-sphere corners)
             * from producing slivers. */
            if (dist2f(m->positions + 3 * (size_t)v00, m->positions + 3 * (size_t)v11) <=
                dist2f(m->positions + 3 * (size_t)v10, m->positions + 3 * (size_t)v01)) {
                uint32_t a[6] = {v00, v10, v11, v00, v11, v01};
                memcpy(q, a, sizeof q);
            } else {
                uint32_t a[6] = {v00, v10, v01, v10, v11, v01};
                memcpy(q, a, sizeof q);
            }
            if (c->flip) {
                uint32_t s0 = q[1], s1 = q[4];
                q[1] = q[2];
                q[2] = s0;
                q[4] = q[5];
                q[5] = s1;
            }
            memcpy(t, q, sizeof q);
            t += 6;
        }
}

static void chart_uvs(const chart *c, double side, sam_shape_mesh *m)
{
    uint32_t row = (uint32_t)c->nu + 1;
    /* Swapping axes or reversing the triangles each mirror the UV winding;
     * mirroring u once more keeps every UV triangle counter-clockwise. */
    int mirror = c->flip ^ c->rotated;
    double width = c->rotated ? c->h : c->w;
    for (int j = 0; j <= c->nv; ++j)
        for (int i = 0; i <= c->nu; ++i) {
            double fi = (double)i / c->nu, fj = (double)j / c->nv;
            double u = c->rotated ? fj * c->h : fi * c->w;
            double v = c->rotated ? fi * c->w : fj * c->h;
            if (mirror)
                u = width - u;
            float *o = m->uvs + 2 * ((size_t)c->first_vertex + (size_t)j * row + i);
            o[0] = (float)((c->x + u) / side);
            o[1] = (float)((c->y + v) / side);
        }
}

/* Reverses every triangle of a surface whose signed volume comes out
 * negative, so outwardness does not depend on each map's handedness. */
static void orient_surfaces(builder *b, sam_shape_mesh *m)
{
    size_t k = 0;
    while (k < b->chart_count) {
        size_t end = k;
        while (end < b->chart_count && b->charts[end].surface == b->charts[k].surface)
            ++end;
        uint32_t t0 = b->charts[k].first_triangle;
        uint32_t t1 = end < b->chart_count ? b->charts[end].first_triangle : m->triangle_count;
        const float *origin = m->positions + 3 * (size_t)m->triangles[3 * (size_t)t0];
        double volume = 0.0;
        for (uint32_t t = t0; t < t1; ++t) {
            double p[3][3];
            for (int c = 0; c < 3; ++c)
                for (int d = 0; d < 3; ++d)
                    p[c][d] = (double)m->positions[3 * (size_t)m->triangles[3 * (size_t)t + c] + d] -
                              origin[d];
            double x[3];
            v3_cross(p[1], p[2], x);
            volume += v3_dot(p[0], x);
        }
        if (volume < 0) {
            for (uint32_t t = t0; t < t1; ++t) {
                uint32_t *tri = m->triangles + 3 * (size_t)t;
                uint32_t s = tri[1];
                tri[1] = tri[2];
                tri[2] = s;
            }
            for (size_t c = k; c < end; ++c)
                b->charts[c].flip ^= 1;
        }
        k = end;
    }
}

/* ---------------------------------------------------------------- shapes */

static double ear_max_thickness(double size)
{
    /* The inner side of the curl is offset by thickness/2 toward its centre
     * of curvature; keep it at least half the curl radius away from it. */
    return EAR_CURL * size / EAR_CURL_ANGLE;
}

static void knot_setup(surface *sf, double size)
{
    sf->map = MAP_KNOT;
    sf->major = size / 3.0;
    sf->minor = size / 6.0;
}

/* Largest tube radius of the knot: the smaller of the centre line's least
 * radius of curvature and half the closest approach of distant strands. */
static double knot_max_radius(const surface *sf)
{
    enum { K = KNOT_LIMIT_SAMPLES };
    double p[K][3], dp[3];
    for (int k = 0; k < K; ++k)
        knot_curve(sf, 2.0 * SHAPE_PI * k / K, p[k], dp);
    double closest = HUGE_VAL, curvature_radius = HUGE_VAL;
    for (int a = 0; a < K; ++a) {
        /* Points a quarter period apart or more are different strands. */
        for (int b = a + K / 8; b <= a + K - K / 8 && b < K; ++b) {
            double d = v3_dist(p[a], p[b]);
            if (d < closest)
                closest = d;
        }
        const double *q0 = p[(a + K - 1) % K], *q1 = p[a], *q2 = p[(a + 1) % K];
        double e0 = v3_dist(q0, q1), e1 = v3_dist(q1, q2), e2 = v3_dist(q2, q0);
        double u[3] = {q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]};
        double v[3] = {q2[0] - q0[0], q2[1] - q0[1], q2[2] - q0[2]};
        double x[3];
        v3_cross(u, v, x);
        double twice_area = sqrt(v3_dot(x, x));
        if (twice_area > 0) {
            double rc = e0 * e1 * e2 / (2.0 * twice_area);
            if (rc < curvature_radius)
                curvature_radius = rc;
        }
    }
    double r = 0.5 * closest < curvature_radius ? 0.5 * closest : curvature_radius;
    return KNOT_SAFETY * r;
}

double sam_shape_max_thickness(const char *name, const sam_shape_params *params)
{
    int s = shape_index(name);
    if (s < 0 || !params || !isfinite(params->size) || params->size <= 0)
        return 0.0;
    switch (s) {
    case SHAPE_SLAB: return HUGE_VAL;
    case SHAPE_TORUS: return TORUS_MAX_RELATIVE_THICKNESS * params->size;
    case SHAPE_EAR: return ear_max_thickness(params->size);
    case SHAPE_KNOT: {
        surface sf;
        memset(&sf, 0, sizeof sf);
        knot_setup(&sf, params->size);
        return 2.0 * knot_max_radius(&sf);
    }
    default: return 0.0;
    }
}

static sam_status validate(int s, const sam_shape_params *p, sam_error *err)
{
    const char *name = shape_names[s];
    const sam_shape_info *info = &shape_infos[s];
    if (p->resolution < info->min_resolution || p->resolution > SAM_SHAPE_MAX_RESOLUTION)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "shape %s: resolution %d out of range [%d, %d]", name, p->resolution,
                        info->min_resolution, SAM_SHAPE_MAX_RESOLUTION);
    if (!isfinite(p->size) || p->size <= 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "shape %s: size %g must be a positive finite number", name, p->size);
    if ((info->uses & SAM_SHAPE_USES_DEPTH) && (!isfinite(p->depth) || p->depth <= 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "shape %s: depth %g must be a positive finite number", name, p->depth);
    if (info->uses & SAM_SHAPE_USES_THICKNESS) {
        double lo = SAM_SHAPE_MIN_RELATIVE_THICKNESS * p->size;
        double hi = sam_shape_max_thickness(name, p);
        if (!isfinite(p->thickness) || p->thickness < lo || p->thickness > hi) {
            if (isfinite(hi))
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                                "shape %s: thickness %g out of range [%g, %g] for size %g", name,
                                p->thickness, lo, hi, p->size);
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "shape %s: thickness %g must be finite and at least %g for size %g",
                            name, p->thickness, lo, p->size);
        }
    }
    if ((info->uses & SAM_SHAPE_USES_COUNT) && (p->count < 1 || p->count > SAM_SHAPE_MAX_COUNT))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape %s: count %d out of range [1, %d]",
                        name, p->count, SAM_SHAPE_MAX_COUNT);
    return SAM_OK;
}

static int segments_for(double length, double spacing, int minimum)
{
    double n = floor(length / spacing + 0.5);
    if (n < minimum)
        return minimum;
    if (n > SAM_SHAPE_MAX_RESOLUTION)
        return SAM_SHAPE_MAX_RESOLUTION;
    return (int)n;
}

static void blob_setup(surface *sf, int n, const double cell_center[3], double cell,
                       uint64_t *rng)
{
    sf->map = MAP_BLOB;
    sf->n[0] = sf->n[1] = sf->n[2] = n;
    /* Random rotation from a unit quaternion (Shoemake), random axis scales. */
    double u1 = rng_uniform(rng, 0, 1), u2 = rng_uniform(rng, 0, 2 * SHAPE_PI),
           u3 = rng_uniform(rng, 0, 2 * SHAPE_PI);
    double qw = sqrt(1 - u1) * sin(u2), qx = sqrt(1 - u1) * cos(u2), qy = sqrt(u1) * sin(u3),
           qz = sqrt(u1) * cos(u3);
    double rot[9] = {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw),
                     2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw),
                     2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)};
    double scale[3], largest = 0.0;
    for (int k = 0; k < 3; ++k) {
        scale[k] = rng_uniform(rng, 0.6, 1.0);
        if (scale[k] > largest)
            largest = scale[k];
    }
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            sf->matrix[3 * r + c] = rot[3 * r + c] * scale[c];
    double bulge = 1.0;
    for (int m = 0; m < BLOB_BUMPS; ++m) {
        rng_unit_vector(rng, sf->bump_dir[m]);
        sf->bump_amp[m] = rng_uniform(rng, -0.2, 0.5);
        sf->bump_width[m] = rng_uniform(rng, 0.35, 0.7);
        if (sf->bump_amp[m] > 0)
            bulge += sf->bump_amp[m];
    }
    /* The blob's bounding sphere (radius * bulge * largest scale) stays
     * inside a cube of 0.9 cell, so blobs in different cells never touch. */
    double room = 0.45 * cell;
    double reach = room * rng_uniform(rng, 0.7, 1.0);
    sf->radius = reach / (bulge * largest);
    for (int k = 0; k < 3; ++k)
        sf->center[k] = cell_center[k] + rng_uniform(rng, -(room - reach), room - reach);
}

static sam_status setup_surfaces(int s, const sam_shape_params *p, builder *b, sam_error *err)
{
    size_t count = s == SHAPE_BLOBS ? (size_t)p->count : 1;
    b->surfaces = calloc(count, sizeof *b->surfaces);
    if (!b->surfaces)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape %s: out of memory", shape_names[s]);
    b->surface_count = count;
    surface *sf = b->surfaces;
    int res = p->resolution;
    switch (s) {
    case SHAPE_SPHERE:
        sf->map = MAP_SPHERE;
        sf->n[0] = sf->n[1] = sf->n[2] = (res + 3) / 4;
        sf->radius = 0.5 * p->size;
        break;
    case SHAPE_SLAB: {
        double spacing = p->size / res;
        sf->map = MAP_SLAB;
        sf->n[0] = res;
        sf->n[1] = segments_for(p->thickness, spacing, 1);
        sf->n[2] = segments_for(p->depth, spacing, 1);
        v3_set(sf->half, 0.5 * p->size, 0.5 * p->thickness, 0.5 * p->depth);
        break;
    }
    case SHAPE_TORUS:
        sf->map = MAP_TORUS;
        sf->radius = 0.5 * p->thickness;
        sf->major = 0.5 * p->size - sf->radius;
        sf->n[0] = res;
        sf->n[1] = segments_for(res * sf->radius / sf->major, 1.0, 3);
        break;
    case SHAPE_EAR: {
        sf->map = MAP_EAR;
        sf->size = p->size;
        sf->thickness = p->thickness;
        double length = 0.0, a[3], c[3];
        ear_mid(p->size, 0.0, 0.5, a);
        for (int k = 1; k <= 512; ++k) {
            ear_mid(p->size, k / 512.0, 0.5, c);
            length += v3_dist(a, c);
            memcpy(a, c, sizeof a);
        }
        double spacing = length / res;
        sf->n[0] = res;
        sf->n[1] = segments_for(p->thickness, spacing, 1);
        sf->n[2] = segments_for((EAR_FLAT + EAR_CURL) * p->size, spacing, 2);
        break;
    }
    case SHAPE_KNOT: {
        knot_setup(sf, p->size);
        sf->radius = 0.5 * p->thickness;
        sf->n[0] = res;
        /* Arc-length parameterisation, so segments have equal length. */
        double *cum = malloc((KNOT_ARC_SAMPLES + 1) * sizeof *cum);
        b->knot_phi = malloc((size_t)res * sizeof *b->knot_phi);
        if (!cum || !b->knot_phi) {
            free(cum);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape knot: out of memory");
        }
        double q[3], dq[3], prev_speed;
        knot_curve(sf, 0.0, q, dq);
        prev_speed = sqrt(v3_dot(dq, dq));
        cum[0] = 0.0;
        for (int k = 1; k <= KNOT_ARC_SAMPLES; ++k) {
            knot_curve(sf, 2.0 * SHAPE_PI * k / KNOT_ARC_SAMPLES, q, dq);
            double speed = sqrt(v3_dot(dq, dq));
            cum[k] = cum[k - 1] + 0.5 * (speed + prev_speed) * (2.0 * SHAPE_PI / KNOT_ARC_SAMPLES);
            prev_speed = speed;
        }
        double length = cum[KNOT_ARC_SAMPLES];
        int k = 0;
        for (int i = 0; i < res; ++i) {
            double target = length * i / res;
            while (k + 1 < KNOT_ARC_SAMPLES && cum[k + 1] <= target)
                ++k;
            double f = (target - cum[k]) / (cum[k + 1] - cum[k]);
            b->knot_phi[i] = 2.0 * SHAPE_PI * (k + f) / KNOT_ARC_SAMPLES;
        }
        free(cum);
        sf->knot_phi = b->knot_phi;
        sf->n[1] = segments_for(2.0 * SHAPE_PI * sf->radius, length / res, 6);
        break;
    }
    case SHAPE_BLOBS: {
        int g = 1;
        while (g * g * g < p->count)
            ++g;
        int cells = g * g * g;
        int *order = malloc((size_t)cells * sizeof *order);
        if (!order)
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape blobs: out of memory");
        for (int c = 0; c < cells; ++c)
            order[c] = c;
        uint64_t rng = p->seed;
        for (int c = cells - 1; c > 0; --c) {
            int r = (int)(rng_next(&rng) % (uint64_t)(c + 1));
            int t = order[c];
            order[c] = order[r];
            order[r] = t;
        }
        double cell = p->size / g;
        for (int k = 0; k < p->count; ++k) {
            int c = order[k];
            double centre[3] = {(c % g + 0.5) * cell - 0.5 * p->size,
                                ((c / g) % g + 0.5) * cell - 0.5 * p->size,
                                (c / (g * g) + 0.5) * cell - 0.5 * p->size};
            blob_setup(&b->surfaces[k], (res + 3) / 4, centre, cell, &rng);
        }
        free(order);
        break;
    }
    default:
        break;
    }
    return SAM_OK;
}

/* Assigns each chart its first vertex and triangle and totals them; returns
 * 0 when the mesh would exceed SAM_SHAPE_MAX_VERTICES. */
static int count_elements(builder *b, uint64_t *vertices, uint64_t *triangles)
{
    *vertices = 0;
    *triangles = 0;
    for (size_t k = 0; k < b->chart_count; ++k) {
        chart *c = &b->charts[k];
        c->first_vertex = (uint32_t)*vertices;
        c->first_triangle = (uint32_t)*triangles;
        *vertices += (uint64_t)(c->nu + 1) * (uint64_t)(c->nv + 1);
        *triangles += 2 * (uint64_t)c->nu * (uint64_t)c->nv;
        if (*vertices > SAM_SHAPE_MAX_VERTICES || *triangles > SAM_SHAPE_MAX_VERTICES)
            return 0;
    }
    return 1;
}

sam_status sam_shape_generate(const char *name, const sam_shape_params *params,
                              sam_shape_mesh *mesh, sam_error *err)
{
    if (mesh)
        memset(mesh, 0, sizeof *mesh);
    int s = shape_index(name);
    if (s < 0)
        return fail_unknown(err, name);
    if (!params || !mesh)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shape %s: params and mesh are required",
                        name);
    sam_status st = validate(s, params, err);
    if (st != SAM_OK)
        return st;

    builder b;
    memset(&b, 0, sizeof b);
    st = setup_surfaces(s, params, &b, err);
    if (st != SAM_OK) {
        builder_free(&b);
        return st;
    }
    for (size_t k = 0; k < b.surface_count; ++k)
        if (!add_surface_charts(&b, k)) {
            builder_free(&b);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape %s: out of memory", name);
        }
    /* Count before splitting too, so an oversized request fails before the
     * charts are measured. */
    uint64_t vertices, triangles;
    int fits = count_elements(&b, &vertices, &triangles);
    if (fits) {
        if (!split_long_charts(&b)) {
            builder_free(&b);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape %s: out of memory", name);
        }
        fits = count_elements(&b, &vertices, &triangles);
    }
    if (!fits) {
        builder_free(&b);
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "shape %s: resolution %d gives more than %u vertices or triangles", name,
                        params->resolution, SAM_SHAPE_MAX_VERTICES);
    }
    mesh->vertex_count = (uint32_t)vertices;
    mesh->triangle_count = (uint32_t)triangles;
    mesh->positions = malloc((size_t)vertices * 3 * sizeof(float));
    mesh->uvs = malloc((size_t)vertices * 2 * sizeof(float));
    mesh->triangles = malloc((size_t)triangles * 3 * sizeof(uint32_t));
    double side = 0.0;
    if (!mesh->positions || !mesh->uvs || !mesh->triangles || !pack_atlas(&b, &side)) {
        builder_free(&b);
        sam_shape_mesh_destroy(mesh);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY,
                        "shape %s: out of memory for %llu vertices, %llu triangles", name,
                        (unsigned long long)vertices, (unsigned long long)triangles);
    }
    for (size_t k = 0; k < b.chart_count; ++k)
        emit_chart(&b, &b.charts[k], mesh);
    orient_surfaces(&b, mesh);
    for (size_t k = 0; k < b.chart_count; ++k)
        chart_uvs(&b.charts[k], side, mesh);
    builder_free(&b);
    return SAM_OK;
}

void sam_shape_mesh_destroy(sam_shape_mesh *mesh)
{
    if (!mesh)
        return;
    free(mesh->positions);
    free(mesh->uvs);
    free(mesh->triangles);
    memset(mesh, 0, sizeof *mesh);
}

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
    if (!mesh || !mesh->vertex_count || !mesh->triangle_count || !mesh->positions || !mesh->uvs ||
        !mesh->triangles)
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

sam_status sam_shape_write_obj(const char *path, const sam_shape_mesh *mesh, sam_error *err)
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
    fprintf(f.fp, "# sam_shape: %u positions, %u uvs, %u triangles\n", unique, n,
            mesh->triangle_count);
    for (uint32_t v = 0, written = 0; v < n; ++v)
        if (ids[v] == written) {
            const float *p = mesh->positions + 3 * (size_t)v;
            fprintf(f.fp, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
            ++written;
        }
    for (uint32_t v = 0; v < n; ++v)
        fprintf(f.fp, "vt %.9g %.9g\n", mesh->uvs[2 * (size_t)v], mesh->uvs[2 * (size_t)v + 1]);
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
        const uint32_t *tri = mesh->triangles + 3 * (size_t)t;
        fprintf(f.fp, "f %u/%u %u/%u %u/%u\n", ids[tri[0]] + 1, tri[0] + 1, ids[tri[1]] + 1,
                tri[1] + 1, ids[tri[2]] + 1, tri[2] + 1);
    }
    free(ids);
    return finish_write(&f, path, err);
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
            "element vertex %u\nproperty float x\nproperty float y\nproperty float z\n"
            "property float u\nproperty float v\nelement face %u\n"
            "property list uchar int vertex_indices\nend_header\n",
            binary ? "binary_little_endian" : "ascii", mesh->vertex_count, mesh->triangle_count);
    for (uint32_t v = 0; v < mesh->vertex_count; ++v) {
        const float *p = mesh->positions + 3 * (size_t)v, *uv = mesh->uvs + 2 * (size_t)v;
        if (binary) {
            uint8_t rec[20];
            for (int k = 0; k < 3; ++k)
                put_float(rec + 4 * k, p[k]);
            put_float(rec + 12, uv[0]);
            put_float(rec + 16, uv[1]);
            fwrite(rec, 1, sizeof rec, f.fp);
        } else {
            fprintf(f.fp, "%.9g %.9g %.9g %.9g %.9g\n", p[0], p[1], p[2], uv[0], uv[1]);
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
