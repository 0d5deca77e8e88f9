#include <stdlib.h>
#include <string.h>

#include "sam_shape_internal.h"

/* Gap around each chart, as a fraction of sqrt(total chart area). */
#define ATLAS_GAP (1.0 / 128.0)

/* ---------------------------------------------------------------- charts */

static int push_chart(sam_shape_builder *b, const sam_shape_chart *c)
{
    if (b->chart_count == b->chart_cap) {
        size_t cap = b->chart_cap ? 2 * b->chart_cap : 64;
        sam_shape_chart *grown = realloc(b->charts, cap * sizeof *grown);
        if (!grown)
            return 0;
        b->charts = grown;
        b->chart_cap = cap;
    }
    b->charts[b->chart_count++] = *c;
    return 1;
}

static void measure_chart(const sam_shape_builder *b, sam_shape_chart *c)
{
    const sam_shape_surface *sf = &b->surfaces[c->surface];
    double prev[3], p[3];
    c->w = 0.0;
    c->h = 0.0;
    int jm = c->j0 + c->nv / 2, im = c->i0 + c->nu / 2;
    sam_shape_surface_point(sf, c->face, c->i0, jm, prev);
    for (int i = 1; i <= c->nu; ++i) {
        sam_shape_surface_point(sf, c->face, c->i0 + i, jm, p);
        c->w += v3_dist(prev, p);
        memcpy(prev, p, sizeof p);
    }
    sam_shape_surface_point(sf, c->face, im, c->j0, prev);
    for (int j = 1; j <= c->nv; ++j) {
        sam_shape_surface_point(sf, c->face, im, c->j0 + j, p);
        c->h += v3_dist(prev, p);
        memcpy(prev, p, sizeof p);
    }
}

/* The rings and wall of every hole, then the rim. i runs around a hole (or
 * the plate's edge) from its cell's (min x, min z) corner along +x first, j
 * outward on the rings and up (+y) the walls: i x j is +y on the rings, so
 * the bottom ring is reversed; it points into the hole on a wall, which is
 * outward, and into the plate on the rim, which is reversed. */
static int add_perforated_charts(sam_shape_builder *b, sam_shape_chart c)
{
    const sam_shape_surface *sf = &b->surfaces[c.surface];
    static const int flips[PERFORATED_PARTS] = {0, 1, 0};
    int holes = sf->holes * sf->holes;
    c.nu = 4 * sf->n[0];
    for (int h = 0; h < holes; ++h)
        for (int part = 0; part < PERFORATED_PARTS; ++part) {
            c.face = PERFORATED_PARTS * h + part;
            c.nv = part == PERFORATED_WALL ? sf->n[1] : sf->n[2];
            c.flip = flips[part];
            if (!push_chart(b, &c))
                return 0;
        }
    c.face = PERFORATED_PARTS * holes;
    c.nu = 4 * sf->holes * sf->n[0];
    c.nv = sf->n[1];
    c.flip = 1;
    return push_chart(b, &c);
}

int sam_shape_add_surface_charts(sam_shape_builder *b, size_t s)
{
    const sam_shape_surface *sf = &b->surfaces[s];
    sam_shape_chart c;
    memset(&c, 0, sizeof c);
    c.surface = s;
    if (sf->map == MAP_PERFORATED)
        return add_perforated_charts(b, c);
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

int sam_shape_split_long_charts(sam_shape_builder *b)
{
    double area = 0.0;
    for (size_t k = 0; k < b->chart_count; ++k) {
        measure_chart(b, &b->charts[k]);
        area += b->charts[k].w * b->charts[k].h;
    }
    double limit = sqrt(area);
    size_t original = b->chart_count;
    for (size_t k = 0; k < original; ++k) {
        sam_shape_chart c = b->charts[k];
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
            sam_shape_chart piece = c;
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
                         sam_shape_chart *charts)
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

int sam_shape_pack_atlas(sam_shape_builder *b, double *side)
{
    size_t n = b->chart_count;
    pack_item *items = malloc(n * sizeof *items);
    if (!items)
        return 0;
    double area = 0.0, widest = 0.0;
    for (size_t k = 0; k < n; ++k) {
        sam_shape_chart *c = &b->charts[k];
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

static void emit_chart(const sam_shape_builder *b, const sam_shape_chart *c, sam_shape_mesh *m)
{
    const sam_shape_surface *sf = &b->surfaces[c->surface];
    uint32_t row = (uint32_t)c->nu + 1;
    for (int j = 0; j <= c->nv; ++j)
        for (int i = 0; i <= c->nu; ++i) {
            double p[3];
            sam_shape_surface_point(sf, c->face, c->i0 + i, c->j0 + j, p);
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

static void chart_uvs(const sam_shape_chart *c, double side, sam_shape_mesh *m)
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
static void orient_surfaces(sam_shape_builder *b, sam_shape_mesh *m)
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

void sam_shape_emit(sam_shape_builder *b, double side, sam_shape_mesh *m)
{
    for (size_t k = 0; k < b->chart_count; ++k)
        emit_chart(b, &b->charts[k], m);
    /* Orienting may flip a chart, which mirrors its UVs: UVs come after. */
    orient_surfaces(b, m);
    for (size_t k = 0; k < b->chart_count; ++k)
        chart_uvs(&b->charts[k], side, m);
}
