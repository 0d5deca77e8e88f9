#include "sam/sam_uv.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* UVs are snapped to 1/256 texel, as GPUs do: a vertex moves by at most
 * 1/512 texel, which coverage cannot see, and from then on every test is
 * exact integer arithmetic, so shared edges are decided identically for
 * both triangles. With |uv| <= SAM_UV_RASTER_LIMIT (256 = 2^8) and
 * resolution <= 8192 (2^13), coordinates stay within 2^29, edge
 * coefficients within 2^30 and edge values within 2^61. */
#define SUBTEXEL_BITS 8
#define SUBTEXEL ((int64_t)1 << SUBTEXEL_BITS)
#define HALF_TEXEL (SUBTEXEL / 2)

typedef struct fixed_point {
    int64_t x, y;
} fixed_point;

/* E(x, y) = a x + b y + c is >= 0 exactly where a texel centre (x, y)
 * belongs to the triangle, tie rule included. */
typedef struct edge_function {
    int64_t a, b, c;
} edge_function;

/* Floor and ceiling of a / b for b > 0 (C division truncates toward 0). */
static int64_t floor_div(int64_t a, int64_t b)
{
    int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

static int64_t ceil_div(int64_t a, int64_t b)
{
    return -floor_div(-a, b);
}

/* Edge p -> q of a counter-clockwise triangle: the inside is on its left.
 * A centre exactly on the edge (E = 0) belongs to the triangle only when
 * the edge "owns" it, and of the two directions a line can be walked in
 * exactly one owns it (a half-plane of directions: downward, or
 * horizontal leftward). Two counter-clockwise triangles sharing an edge
 * walk it in opposite directions, so exactly one of them gets such a
 * centre; because the owning directions form a half-plane, the same holds
 * for a centre on a vertex shared by a whole fan. */
static edge_function edge_setup(fixed_point p, fixed_point q)
{
    int64_t dx = q.x - p.x, dy = q.y - p.y;
    edge_function e = { -dy, dx, dy * p.x - dx * p.y };
    int owns = dy < 0 || (dy == 0 && dx < 0);
    if (!owns)
        e.c -= 1; /* E > 0 is E - 1 >= 0 in integers */
    return e;
}

static fixed_point snap(const float *uv, double scale)
{
    fixed_point p = { (int64_t)llrint((double)uv[0] * scale), (int64_t)llrint((double)uv[1] * scale) };
    return p;
}

static int uv_outside(const float *uv)
{
    return uv[0] < 0.0f || uv[0] > 1.0f || uv[1] < 0.0f || uv[1] > 1.0f;
}

static int uv_beyond_limit(const float *uv)
{
    return fabsf(uv[0]) > SAM_UV_RASTER_LIMIT || fabsf(uv[1]) > SAM_UV_RASTER_LIMIT;
}

/* Adds 1 (saturating) to the counter of every texel centre inside the
 * counter-clockwise triangle p0 p1 p2. Each row's inside is an interval
 * (the triangle is convex), found exactly from the three edge functions
 * instead of testing every texel of the bounding box, so a large triangle
 * costs its rows, not its area, in tests. */
static void rasterise(fixed_point p0, fixed_point p1, fixed_point p2, uint8_t *grid, uint32_t resolution)
{
    int64_t min_x = p0.x, max_x = p0.x, min_y = p0.y, max_y = p0.y;
    const fixed_point ps[2] = { p1, p2 };
    for (int k = 0; k < 2; ++k) {
        min_x = ps[k].x < min_x ? ps[k].x : min_x;
        max_x = ps[k].x > max_x ? ps[k].x : max_x;
        min_y = ps[k].y < min_y ? ps[k].y : min_y;
        max_y = ps[k].y > max_y ? ps[k].y : max_y;
    }
    /* Texel i's centre is at i * SUBTEXEL + HALF_TEXEL. */
    int64_t last = (int64_t)resolution - 1;
    int64_t x0 = ceil_div(min_x - HALF_TEXEL, SUBTEXEL), x1 = floor_div(max_x - HALF_TEXEL, SUBTEXEL);
    int64_t y0 = ceil_div(min_y - HALF_TEXEL, SUBTEXEL), y1 = floor_div(max_y - HALF_TEXEL, SUBTEXEL);
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > last ? last : x1;
    y1 = y1 > last ? last : y1;
    if (x0 > x1 || y0 > y1)
        return;

    const edge_function edges[3] = { edge_setup(p0, p1), edge_setup(p1, p2), edge_setup(p2, p0) };
    for (int64_t j = y0; j <= y1; ++j) {
        int64_t y = j * SUBTEXEL + HALF_TEXEL;
        int64_t lo = x0, hi = x1;
        for (int k = 0; k < 3 && lo <= hi; ++k) {
            /* E at column i is base + step * i. */
            const edge_function *e = &edges[k];
            int64_t base = e->a * HALF_TEXEL + e->b * y + e->c, step = e->a * SUBTEXEL;
            if (step > 0) {
                int64_t from = ceil_div(-base, step);
                lo = from > lo ? from : lo;
            } else if (step < 0) {
                int64_t to = floor_div(base, -step);
                hi = to < hi ? to : hi;
            } else if (base < 0) {
                hi = lo - 1;
            }
        }
        uint8_t *row = grid + (size_t)j * resolution;
        for (int64_t i = lo; i <= hi; ++i)
            row[i] = (uint8_t)(row[i] + (row[i] != UINT8_MAX));
    }
}

/* Checks what every sam_uv function reads: finite UVs, indices in range. */
static sam_status validate_mesh(const char *fn, const float *uvs, uint32_t vertex_count, const uint32_t *triangles,
                                uint32_t triangle_count, sam_error *err)
{
    if (!uvs && vertex_count > 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: NULL uvs for %u vertices", fn, vertex_count);
    if (!triangles && triangle_count > 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: NULL triangles for %u triangles", fn, triangle_count);
    for (uint32_t v = 0; v < vertex_count; ++v) {
        const float *uv = uvs + 2 * (size_t)v;
        if (!isfinite(uv[0]) || !isfinite(uv[1]))
            return sam_fail(err, SAM_ERR_FORMAT, "%s: vertex %u has a non-finite UV (%g, %g)", fn, v,
                            (double)uv[0], (double)uv[1]);
    }
    for (uint32_t t = 0; t < triangle_count; ++t) {
        for (unsigned c = 0; c < 3; ++c) {
            uint32_t index = triangles[3 * (size_t)t + c];
            if (index >= vertex_count)
                return sam_fail(err, SAM_ERR_FORMAT, "%s: triangle %u corner %u has index %u (vertex count %u)",
                                fn, t, c, index, vertex_count);
        }
    }
    return SAM_OK;
}

static sam_status validate(const float *uvs, uint32_t vertex_count, const uint32_t *triangles,
                           uint32_t triangle_count, uint32_t resolution, const sam_uv_report *report,
                           sam_error *err)
{
    if (!report)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_uv_check: NULL report");
    if (resolution == 0 || resolution > SAM_UV_MAX_RESOLUTION)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "sam_uv_check: resolution %u is outside 1..%u texels", resolution,
                        SAM_UV_MAX_RESOLUTION);
    return validate_mesh("sam_uv_check", uvs, vertex_count, triangles, triangle_count, err);
}

sam_status sam_uv_fit_atlas(const float *uvs, uint32_t vertex_count, const uint32_t *triangles,
                            uint32_t triangle_count, sam_uv_atlas *atlas, float *out, sam_error *err)
{
    if (!atlas || (!out && vertex_count > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_uv_fit_atlas: NULL atlas or output");
    memset(atlas, 0, sizeof *atlas);
    atlas->scale = 1.0f;
    sam_status st = validate_mesh("sam_uv_fit_atlas", uvs, vertex_count, triangles, triangle_count, err);
    if (st != SAM_OK)
        return st;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < 3 * (size_t)triangle_count; ++i)
        for (int c = 0; c < 2; ++c) {
            double x = uvs[2 * (size_t)triangles[i] + c];
            lo[c] = fmin(lo[c], x);
            hi[c] = fmax(hi[c], x);
        }
    const int inside = triangle_count == 0 || (lo[0] >= 0.0 && lo[1] >= 0.0 && hi[0] <= 1.0 && hi[1] <= 1.0);
    const double extent = triangle_count ? fmax(hi[0] - lo[0], hi[1] - lo[1]) : 0.0;
    /* One scale for both axes: texels stay square, as the layout's author
     * drew them, so the blur's stretch map sees the surface they chose. */
    atlas->moved = !inside && extent > 0.0;
    const double scale = atlas->moved ? 1.0 / extent : 1.0;
    atlas->scale = (float)scale;
    for (int c = 0; c < 2; ++c) {
        atlas->lo[c] = triangle_count ? (float)lo[c] : 0.0f;
        atlas->hi[c] = triangle_count ? (float)hi[c] : 0.0f;
        atlas->offset[c] = atlas->moved ? (float)(0.0 - lo[c] * scale) : 0.0f;
    }
    for (size_t i = 0; i < 2 * (size_t)vertex_count; ++i) {
        /* Rounding may put a UV an ulp past the square it lies in. */
        double x = (double)uvs[i] * atlas->scale + atlas->offset[i & 1];
        out[i] = atlas->moved ? (float)fmin(fmax(x, 0.0), 1.0) : uvs[i];
    }
    return SAM_OK;
}

sam_status sam_uv_check(const float *uvs, uint32_t vertex_count, const uint32_t *triangles,
                        uint32_t triangle_count, uint32_t resolution, sam_uv_report *report,
                        sam_error *err)
{
    if (report)
        memset(report, 0, sizeof *report);
    sam_status st = validate(uvs, vertex_count, triangles, triangle_count, resolution, report, err);
    if (st != SAM_OK)
        return st;

    size_t cells = (size_t)resolution * resolution;
    uint8_t *grid = calloc(cells, 1);
    if (!grid)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY,
                        "sam_uv_check: out of memory for a %ux%u coverage grid (%zu bytes)", resolution,
                        resolution, cells);

    sam_uv_report rep = { 0 };
    rep.resolution = resolution;
    rep.first_outside_triangle = UINT32_MAX;
    double scale = (double)resolution * (double)SUBTEXEL; /* exact: float * 2^21 at most fits a double */
    for (uint32_t t = 0; t < triangle_count; ++t) {
        const uint32_t *tri = triangles + 3 * (size_t)t;
        const float *uv0 = uvs + 2 * (size_t)tri[0], *uv1 = uvs + 2 * (size_t)tri[1],
                    *uv2 = uvs + 2 * (size_t)tri[2];
        if (uv_outside(uv0) || uv_outside(uv1) || uv_outside(uv2)) {
            if (rep.outside_triangles++ == 0)
                rep.first_outside_triangle = t;
            if (uv_beyond_limit(uv0) || uv_beyond_limit(uv1) || uv_beyond_limit(uv2)) {
                /* Too far out for the fixed-point range; it is already
                 * reported as outside, so only its degeneracy is counted. */
                double area2 = ((double)uv1[0] - uv0[0]) * ((double)uv2[1] - uv0[1]) -
                               ((double)uv1[1] - uv0[1]) * ((double)uv2[0] - uv0[0]);
                rep.degenerate_triangles += area2 == 0.0;
                continue;
            }
        }
        fixed_point p0 = snap(uv0, scale), p1 = snap(uv1, scale), p2 = snap(uv2, scale);
        int64_t area2 = (p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x);
        if (area2 == 0) {
            rep.degenerate_triangles++;
            continue;
        }
        /* Mirrored (clockwise) triangles are reordered, not rejected: only
         * coverage matters, and the tie rule needs one orientation. */
        if (area2 > 0)
            rasterise(p0, p1, p2, grid, resolution);
        else
            rasterise(p0, p2, p1, grid, resolution);
    }

    /* 32-bit row sums let the compiler vectorise the count (twice as fast
     * as 64-bit sums at 8192^2); a row holds at most 8192 texels. */
    uint64_t covered = 0, overlap = 0;
    for (uint32_t j = 0; j < resolution; ++j) {
        const uint8_t *row = grid + (size_t)j * resolution;
        uint32_t row_covered = 0, row_overlap = 0;
        for (uint32_t i = 0; i < resolution; ++i) {
            row_covered += row[i] != 0;
            row_overlap += row[i] > 1;
        }
        covered += row_covered;
        overlap += row_overlap;
    }
    free(grid);
    rep.covered_texels = covered;
    rep.overlap_texels = overlap;
    rep.overlap_fraction = covered ? (float)((double)overlap / (double)covered) : 0.0f;
    *report = rep;
    return SAM_OK;
}

/* Appends a printf-formatted part to reason (size n) at *len, with "; "
 * before every part but the first; truncates, never overruns. */
static void append_reason(char *reason, size_t n, size_t *len, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

static void append_reason(char *reason, size_t n, size_t *len, const char *fmt, ...)
{
    if (!reason || *len + 1 >= n)
        return;
    if (*len > 0) {
        int w = snprintf(reason + *len, n - *len, "; ");
        *len += (size_t)w < n - *len ? (size_t)w : n - *len - 1;
        if (*len + 1 >= n)
            return;
    }
    va_list ap;
    va_start(ap, fmt);
    int w = vsnprintf(reason + *len, n - *len, fmt, ap);
    va_end(ap);
    if (w > 0)
        *len += (size_t)w < n - *len ? (size_t)w : n - *len - 1;
}

int sam_uv_usable(const sam_uv_report *report, char *reason, size_t n)
{
    if (reason && n > 0)
        reason[0] = '\0';
    size_t len = 0;
    if (!report) {
        append_reason(reason, n, &len, "no UV report");
        return 0;
    }
    int usable = 1;
    if (report->outside_triangles > 0) {
        usable = 0;
        if (report->outside_triangles == 1)
            append_reason(reason, n, &len, "1 triangle (triangle %u) has UVs outside [0,1]",
                          report->first_outside_triangle);
        else
            append_reason(reason, n, &len, "%u triangles have UVs outside [0,1] (the first is triangle %u)",
                          report->outside_triangles, report->first_outside_triangle);
    }
    if (report->covered_texels == 0) {
        usable = 0;
        append_reason(reason, n, &len,
                      "the UVs cover no texel centre of the %ux%u grid (no triangles, or all degenerate "
                      "or smaller than a texel)",
                      report->resolution, report->resolution);
    } else if (!(report->overlap_fraction <= SAM_UV_MAX_OVERLAP)) {
        /* The negated test also rejects a NaN from a hand-filled report. */
        usable = 0;
        append_reason(reason, n, &len,
                      "%.3g%% of the covered atlas texels are covered by more than one triangle "
                      "(mirrored or stacked UV islands)",
                      100.0 * (double)report->overlap_fraction);
    }
    return usable;
}
