#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "sam/sam_mesh.h"
#include "sam/sam_shape.h"
#include "sam_test.h"

#define PI 3.14159265358979323846

/* ------------------------------------------------------------ helpers */

static sam_shape_mesh generate(const char *name, int resolution)
{
    sam_shape_params p;
    sam_error err;
    assert_int_equal(sam_shape_default_params(name, &p, &err), SAM_OK);
    p.resolution = resolution;
    sam_shape_mesh m;
    if (sam_shape_generate(name, &p, &m, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return m;
}

static void pos(const sam_shape_mesh *m, uint32_t v, double o[3])
{
    for (int k = 0; k < 3; ++k)
        o[k] = m->positions[3 * (size_t)v + k];
}

static void sub(const double a[3], const double b[3], double o[3])
{
    for (int k = 0; k < 3; ++k)
        o[k] = a[k] - b[k];
}

static void cross(const double a[3], const double b[3], double o[3])
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2],
           z = a[0] * b[1] - a[1] * b[0];
    o[0] = x;
    o[1] = y;
    o[2] = z;
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Welds with the library and checks the result against a brute-force
 * comparison of position bits. */
static uint32_t *weld(const sam_shape_mesh *m, uint32_t *unique)
{
    uint32_t *ids = malloc(m->vertex_count * sizeof *ids);
    assert_non_null(ids);
    assert_int_equal(sam_shape_weld(m, ids, unique, NULL), SAM_OK);
    for (uint32_t a = 0; a < m->vertex_count; ++a) {
        assert_true(ids[a] < *unique);
        for (uint32_t b = a + 1; b < m->vertex_count; ++b) {
            int same = memcmp(m->positions + 3 * (size_t)a, m->positions + 3 * (size_t)b,
                              3 * sizeof(float)) == 0;
            if (same != (ids[a] == ids[b]))
                fail_msg("weld: vertices %u and %u: same position %d, ids %u %u", a, b, same,
                         ids[a], ids[b]);
        }
    }
    return ids;
}

static int u64_cmp(const void *pa, const void *pb)
{
    uint64_t a = *(const uint64_t *)pa, b = *(const uint64_t *)pb;
    return a < b ? -1 : (a > b);
}

static uint32_t find_root(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

typedef struct topology {
    uint32_t unique;      /* welded vertices */
    uint32_t edges;       /* undirected */
    int euler;            /* V - E + F */
    uint32_t components;  /* connected parts */
    double volume;        /* signed */
    double area;
    double min_quality;   /* min over triangles of area / longest edge^2 */
} topology;

/* Checks that the welded mesh is a closed, consistently oriented 2-manifold
 * (each directed edge once, its reverse once, every vertex link one cycle)
 * and measures it. Returns the welded ids (caller frees). */
static uint32_t *check_closed_manifold(const sam_shape_mesh *m, topology *topo)
{
    memset(topo, 0, sizeof *topo);
    uint32_t *ids = weld(m, &topo->unique);
    size_t tc = m->triangle_count;
    uint64_t *edges = malloc(3 * tc * sizeof *edges);
    assert_non_null(edges);
    topo->min_quality = HUGE_VAL;
    for (size_t t = 0; t < tc; ++t) {
        uint32_t w[3];
        double p[3][3];
        for (int c = 0; c < 3; ++c) {
            assert_true(m->triangles[3 * t + c] < m->vertex_count);
            w[c] = ids[m->triangles[3 * t + c]];
            pos(m, m->triangles[3 * t + c], p[c]);
        }
        if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0])
            fail_msg("triangle %zu repeats a welded vertex (%u %u %u)", t, w[0], w[1], w[2]);
        for (int c = 0; c < 3; ++c)
            edges[3 * t + c] = (uint64_t)w[c] << 32 | w[(c + 1) % 3];
        double e1[3], e2[3], x[3], longest = 0;
        sub(p[1], p[0], e1);
        sub(p[2], p[0], e2);
        cross(e1, e2, x);
        double area = 0.5 * sqrt(dot(x, x));
        for (int c = 0; c < 3; ++c) {
            double e[3];
            sub(p[(c + 1) % 3], p[c], e);
            if (dot(e, e) > longest)
                longest = dot(e, e);
        }
        if (area / longest < topo->min_quality)
            topo->min_quality = area / longest;
        topo->area += area;
        topo->volume += dot(p[0], x) / 6.0;
    }
    qsort(edges, 3 * tc, sizeof *edges, u64_cmp);
    for (size_t k = 0; k < 3 * tc; ++k) {
        if (k > 0 && edges[k] == edges[k - 1])
            fail_msg("directed edge %u->%u used twice (non-manifold or flipped)",
                     (uint32_t)(edges[k] >> 32), (uint32_t)edges[k]);
        uint64_t rev = edges[k] << 32 | edges[k] >> 32;
        if (!bsearch(&rev, edges, 3 * tc, sizeof *edges, u64_cmp))
            fail_msg("edge %u->%u has no opposite (open or inconsistent)",
                     (uint32_t)(edges[k] >> 32), (uint32_t)edges[k]);
    }
    free(edges);
    topo->edges = (uint32_t)(3 * tc / 2);
    topo->euler = (int)topo->unique - (int)topo->edges + (int)tc;

    /* Vertex links: the opposite edges of each vertex's triangles must form
     * one cycle, or the surface is pinched there. */
    uint32_t *offsets = calloc(topo->unique + 1, sizeof *offsets);
    uint32_t *link = malloc(3 * tc * 2 * sizeof *link);
    uint32_t *fill = calloc(topo->unique, sizeof *fill);
    assert_true(offsets && link && fill);
    for (size_t t = 0; t < 3 * tc; ++t)
        offsets[ids[m->triangles[t]] + 1]++;
    for (uint32_t v = 0; v < topo->unique; ++v)
        offsets[v + 1] += offsets[v];
    for (size_t t = 0; t < tc; ++t)
        for (int c = 0; c < 3; ++c) {
            uint32_t v = ids[m->triangles[3 * t + c]];
            uint32_t *slot = link + 2 * (offsets[v] + fill[v]++);
            slot[0] = ids[m->triangles[3 * t + (c + 1) % 3]];
            slot[1] = ids[m->triangles[3 * t + (c + 2) % 3]];
        }
    for (uint32_t v = 0; v < topo->unique; ++v) {
        uint32_t n = offsets[v + 1] - offsets[v];
        const uint32_t *l = link + 2 * offsets[v];
        assert_true(n >= 3);
        uint32_t at = l[1], steps = 1;
        while (at != l[0] && steps <= n) {
            uint32_t k = 0;
            while (k < n && l[2 * k] != at)
                ++k;
            assert_true(k < n);
            at = l[2 * k + 1];
            ++steps;
        }
        if (steps != n)
            fail_msg("vertex %u: link cycle of %u edges, %u triangles (pinched)", v, steps, n);
    }
    free(offsets);
    free(link);
    free(fill);

    uint32_t *parent = malloc(topo->unique * sizeof *parent);
    assert_non_null(parent);
    for (uint32_t v = 0; v < topo->unique; ++v)
        parent[v] = v;
    for (size_t t = 0; t < tc; ++t)
        for (int c = 1; c < 3; ++c) {
            uint32_t a = find_root(parent, ids[m->triangles[3 * t]]);
            uint32_t b = find_root(parent, ids[m->triangles[3 * t + c]]);
            parent[a] = b;
        }
    for (uint32_t v = 0; v < topo->unique; ++v)
        topo->components += find_root(parent, v) == v;
    free(parent);
    return ids;
}

/* UVs in [0,1], every UV triangle counter-clockwise with positive area, and
 * no texel centre strictly inside two triangles (charts do not overlap). */
static void check_uvs(const sam_shape_mesh *m)
{
    for (size_t k = 0; k < 2 * (size_t)m->vertex_count; ++k)
        if (!(m->uvs[k] >= 0.0f && m->uvs[k] <= 1.0f))
            fail_msg("uv component %zu = %g outside [0,1]", k, m->uvs[k]);
    enum { R = 512 };
    uint8_t *hits = calloc(R * R, 1);
    assert_non_null(hits);
    double covered = 0.0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        double u[3], v[3];
        for (int c = 0; c < 3; ++c) {
            u[c] = m->uvs[2 * (size_t)m->triangles[3 * t + c]] * R;
            v[c] = m->uvs[2 * (size_t)m->triangles[3 * t + c] + 1] * R;
        }
        double area2 = (u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0]);
        if (!(area2 > 0))
            fail_msg("uv triangle %zu is not counter-clockwise (twice area %g)", t, area2);
        covered += area2 / 2;
        int x0 = (int)floor(fmin(u[0], fmin(u[1], u[2]))), x1 = (int)ceil(fmax(u[0], fmax(u[1], u[2])));
        int y0 = (int)floor(fmin(v[0], fmin(v[1], v[2]))), y1 = (int)ceil(fmax(v[0], fmax(v[1], v[2])));
        for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < R; ++y)
            for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < R; ++x) {
                double px = x + 0.5, py = y + 0.5;
                int inside = 1;
                for (int c = 0; c < 3; ++c) {
                    int d = (c + 1) % 3;
                    if ((u[d] - u[c]) * (py - v[c]) - (v[d] - v[c]) * (px - u[c]) <= 0)
                        inside = 0;
                }
                if (inside && hits[y * R + x]++)
                    fail_msg("uv triangle %zu overlaps another at texel (%d, %d)", t, x, y);
            }
    }
    free(hits);
    /* The atlas is used reasonably (charts fill a fair part of the square). */
    assert_true(covered / (R * R) > 0.3);
}

/* Segment-triangle tests between every edge and every triangle that shares
 * no welded vertex with it: any hit means the surface crosses itself. */
static void check_no_self_intersection(const sam_shape_mesh *m, const uint32_t *ids)
{
    size_t tc = m->triangle_count;
    double(*box)[6] = malloc(tc * sizeof *box);
    assert_non_null(box);
    for (size_t t = 0; t < tc; ++t)
        for (int k = 0; k < 3; ++k) {
            double lo = HUGE_VAL, hi = -HUGE_VAL;
            for (int c = 0; c < 3; ++c) {
                double x = m->positions[3 * (size_t)m->triangles[3 * t + c] + k];
                lo = fmin(lo, x);
                hi = fmax(hi, x);
            }
            box[t][k] = lo;
            box[t][3 + k] = hi;
        }
    for (size_t e = 0; e < 3 * tc; ++e) {
        uint32_t va = m->triangles[e], vb = m->triangles[e - e % 3 + (e % 3 + 1) % 3];
        if (ids[va] > ids[vb])
            continue; /* each undirected edge once */
        double a[3], b[3], d[3];
        pos(m, va, a);
        pos(m, vb, b);
        sub(b, a, d);
        for (size_t t = 0; t < tc; ++t) {
            int skip = 0;
            for (int k = 0; k < 3 && !skip; ++k)
                skip = fmin(a[k], b[k]) > box[t][3 + k] || fmax(a[k], b[k]) < box[t][k];
            for (int c = 0; c < 3 && !skip; ++c) {
                uint32_t w = ids[m->triangles[3 * t + c]];
                skip = w == ids[va] || w == ids[vb];
            }
            if (skip)
                continue;
            double p0[3], p1[3], p2[3], e1[3], e2[3], h[3], s[3], q[3];
            pos(m, m->triangles[3 * t], p0);
            pos(m, m->triangles[3 * t + 1], p1);
            pos(m, m->triangles[3 * t + 2], p2);
            sub(p1, p0, e1);
            sub(p2, p0, e2);
            cross(d, e2, h);
            double det = dot(e1, h);
            /* An edge in a triangle's plane to within float precision (the
             * perforated plate's walls are planar quads) touches it at most:
             * the test below cannot tell the two apart there. */
            if (fabs(det) <= 1e-6 * sqrt(dot(d, d) * dot(e1, e1) * dot(e2, e2)))
                continue;
            sub(a, p0, s);
            double u = dot(s, h) / det;
            cross(s, e1, q);
            double v = dot(d, q) / det, r = dot(e2, q) / det;
            if (u >= 0 && v >= 0 && u + v <= 1 && r >= 0 && r <= 1)
                fail_msg("edge %u-%u crosses triangle %zu", va, vb, t);
        }
    }
    free(box);
}

/* ------------------------------------------------------------ shapes */

static void test_names_and_defaults(void **state)
{
    (void)state;
    size_t n = 0;
    const char *const *names = sam_shape_names(&n);
    assert_int_equal(n, 7);
    for (size_t k = 0; k < n; ++k) {
        const sam_shape_info *info = sam_shape_find(names[k]);
        assert_non_null(info);
        assert_string_equal(info->name, names[k]);
        assert_true(info->suggested_mm_per_unit > 0);
        sam_shape_params p;
        assert_int_equal(sam_shape_default_params(names[k], &p, NULL), SAM_OK);
        assert_true(p.resolution >= info->min_resolution);
        /* Defaults generate and stay closed (topology checked at full size). */
        sam_shape_mesh m;
        sam_error err;
        if (sam_shape_generate(names[k], &p, &m, &err) != SAM_OK)
            fail_msg("%s defaults: %s", names[k], err.message);
        assert_true(m.vertex_count > 0 && m.triangle_count > 0);
        sam_shape_mesh_destroy(&m);
    }
    assert_null(sam_shape_find("cube"));
    sam_shape_params p;
    sam_error err;
    assert_int_equal(sam_shape_default_params("cube", &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "cube"));
}

static void test_sphere(void **state)
{
    (void)state;
    sam_shape_mesh m = generate("sphere", 32);
    topology t;
    uint32_t *ids = check_closed_manifold(&m, &t);
    assert_int_equal(t.euler, 2);
    assert_int_equal(t.components, 1);
    assert_true(t.min_quality > 0.1);
    double r = 0.5;
    assert_true(fabs(t.area / (4 * PI * r * r) - 1) < 0.03);
    assert_true(fabs(t.volume / (4.0 / 3.0 * PI * r * r * r) - 1) < 0.05);
    /* Every vertex on the sphere. */
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        double p[3];
        pos(&m, v, p);
        assert_true(fabs(sqrt(dot(p, p)) - r) < 1e-6);
    }
    /* Six cube faces: seams duplicate positions. */
    assert_true(m.vertex_count > t.unique);
    check_uvs(&m);
    check_no_self_intersection(&m, ids);
    free(ids);
    sam_shape_mesh_destroy(&m);

    /* The coarsest sphere is a cube of 12 good triangles, no pole fans. */
    m = generate("sphere", 4);
    ids = check_closed_manifold(&m, &t);
    assert_int_equal(t.unique, 8);
    assert_int_equal(m.triangle_count, 12);
    assert_true(t.volume > 0);
    free(ids);
    sam_shape_mesh_destroy(&m);
}

static void test_slab(void **state)
{
    (void)state;
    sam_shape_params p;
    assert_int_equal(sam_shape_default_params("slab", &p, NULL), SAM_OK);
    p.resolution = 16;
    p.size = 2.0;
    p.depth = 1.5;
    p.thickness = 0.1;
    sam_shape_mesh m;
    assert_int_equal(sam_shape_generate("slab", &p, &m, NULL), SAM_OK);
    topology t;
    uint32_t *ids = check_closed_manifold(&m, &t);
    assert_int_equal(t.euler, 2);
    assert_true(t.volume > 0);
    double w = p.size, d = p.depth, h = p.thickness;
    assert_true(fabs(t.area / (2 * (w * d + w * h + d * h)) - 1) < 1e-5);
    assert_true(fabs(t.volume / (w * d * h) - 1) < 1e-5);
    float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fminf(lo[k], m.positions[3 * v + k]);
            hi[k] = fmaxf(hi[k], m.positions[3 * v + k]);
        }
    assert_float_equal(hi[0] - lo[0], w, 1e-6);
    assert_float_equal(hi[1] - lo[1], h, 1e-6);
    assert_float_equal(hi[2] - lo[2], d, 1e-6);
    /* Every top vertex has a bottom vertex exactly below it, and the top is
     * tessellated at the resolution (16 x 12 segments). */
    uint32_t top = 0;
    for (uint32_t a = 0; a < m.vertex_count; ++a) {
        if (m.positions[3 * a + 1] != hi[1])
            continue;
        ++top;
        int found = 0;
        for (uint32_t b = 0; b < m.vertex_count && !found; ++b)
            found = m.positions[3 * b + 1] == lo[1] && m.positions[3 * b] == m.positions[3 * a] &&
                    m.positions[3 * b + 2] == m.positions[3 * a + 2];
        if (!found)
            fail_msg("top vertex %u has no bottom vertex below it", a);
    }
    assert_true(top >= 17 * 13);
    check_uvs(&m);
    check_no_self_intersection(&m, ids);
    free(ids);
    sam_shape_mesh_destroy(&m);
}

static void test_torus(void **state)
{
    (void)state;
    sam_shape_mesh m = generate("torus", 32);
    topology t;
    uint32_t *ids = check_closed_manifold(&m, &t);
    assert_int_equal(t.euler, 0);
    assert_int_equal(t.components, 1);
    double r = 0.15, R = 0.35; /* defaults: size 1, thickness 0.3 */
    assert_true(fabs(t.area / (4 * PI * PI * R * r) - 1) < 0.03);
    assert_true(fabs(t.volume / (2 * PI * PI * R * r * r) - 1) < 0.05);
    check_uvs(&m);
    check_no_self_intersection(&m, ids);
    free(ids);
    sam_shape_mesh_destroy(&m);
}

static void check_thin_shape(const char *name, int resolution, double thickness, int euler)
{
    sam_shape_params p;
    assert_int_equal(sam_shape_default_params(name, &p, NULL), SAM_OK);
    p.resolution = resolution;
    if (thickness > 0)
        p.thickness = thickness;
    sam_shape_mesh m;
    sam_error err;
    if (sam_shape_generate(name, &p, &m, &err) != SAM_OK)
        fail_msg("%s", err.message);
    topology t;
    uint32_t *ids = check_closed_manifold(&m, &t);
    assert_int_equal(t.euler, euler);
    assert_int_equal(t.components, 1);
    assert_true(t.volume > 0);
    assert_true(t.min_quality > 0.01);
    check_uvs(&m);
    check_no_self_intersection(&m, ids);
    free(ids);
    sam_shape_mesh_destroy(&m);
}

static void test_ear(void **state)
{
    (void)state;
    check_thin_shape("ear", 24, 0, 2);
    sam_shape_params p;
    assert_int_equal(sam_shape_default_params("ear", &p, NULL), SAM_OK);
    check_thin_shape("ear", 24, sam_shape_max_thickness("ear", &p), 2);
    /* A thin shell: its volume is about the thickness times half its area
     * (a little less, as the rim adds area but no volume). */
    sam_shape_mesh m = generate("ear", 24);
    topology t;
    free(check_closed_manifold(&m, &t));
    double ratio = t.volume / (p.thickness * t.area / 2);
    assert_true(ratio > 0.75 && ratio <= 1.0);
    sam_shape_mesh_destroy(&m);
}

static void test_knot(void **state)
{
    (void)state;
    check_thin_shape("knot", 64, 0, 0);
    sam_shape_params p;
    assert_int_equal(sam_shape_default_params("knot", &p, NULL), SAM_OK);
    double max = sam_shape_max_thickness("knot", &p);
    assert_true(max > p.thickness);
    check_thin_shape("knot", 64, max, 0);
    p.thickness = max * 1.01;
    sam_shape_mesh m;
    sam_error err;
    assert_int_equal(sam_shape_generate("knot", &p, &m, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "thickness"));
}

static void test_blobs(void **state)
{
    (void)state;
    sam_shape_params p;
    assert_int_equal(sam_shape_default_params("blobs", &p, NULL), SAM_OK);
    p.resolution = 8;
    p.count = 5;
    p.seed = 42;
    sam_shape_mesh m;
    assert_int_equal(sam_shape_generate("blobs", &p, &m, NULL), SAM_OK);
    topology t;
    uint32_t *ids = check_closed_manifold(&m, &t);
    assert_int_equal(t.components, 5);
    assert_int_equal(t.euler, 2 * 5);
    assert_true(t.volume > 0);
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        for (int k = 0; k < 3; ++k)
            assert_true(fabsf(m.positions[3 * v + k]) <= 0.5f * (float)p.size);
    check_uvs(&m);
    check_no_self_intersection(&m, ids);
    free(ids);
    sam_shape_mesh_destroy(&m);
}

/* The plate is planar with polygonal holes, so its area and volume are
 * known exactly: 4m-gons of circumradius r in a square of side `size`. */
static void check_perforated(int resolution, int count, double thickness, int steps_per_hole)
{
    sam_shape_params p;
    assert_int_equal(sam_shape_default_params("perforated", &p, NULL), SAM_OK);
    p.resolution = resolution;
    p.count = count;
    p.thickness = thickness;
    sam_shape_mesh m;
    sam_error err;
    if (sam_shape_generate("perforated", &p, &m, &err) != SAM_OK)
        fail_msg("%s", err.message);
    topology t;
    uint32_t *ids = check_closed_manifold(&m, &t);
    int holes = count * count;
    assert_int_equal(t.euler, 2 - 2 * holes);
    assert_int_equal(t.components, 1);
    assert_true(t.min_quality > 0.05);
    int sides = 4 * steps_per_hole;
    double pitch = p.size / count, r = 0.3 * pitch;
    double hole_area = 0.5 * sides * r * r * sin(2 * PI / sides);
    double hole_perimeter = sides * 2 * r * sin(PI / sides);
    double face = p.size * p.size - holes * hole_area;
    double area = 2 * face + holes * hole_perimeter * thickness + 4 * p.size * thickness;
    assert_true(fabs(t.area / area - 1) < 1e-5);
    assert_true(fabs(t.volume / (face * thickness) - 1) < 1e-5);
    /* Every hole is open: no vertex inside the polygon's inscribed circle. */
    double inner = r * cos(PI / sides);
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        double q[3];
        pos(&m, v, q);
        assert_true(fabs(q[0]) <= 0.5 * p.size + 1e-6 && fabs(q[2]) <= 0.5 * p.size + 1e-6);
        assert_true(fabs(q[1]) <= 0.5 * thickness + 1e-6);
        int a = (int)floor((q[0] + 0.5 * p.size) / pitch), b = (int)floor((q[2] + 0.5 * p.size) / pitch);
        a = a < count ? a : count - 1;
        b = b < count ? b : count - 1;
        double dx = q[0] - (-0.5 * p.size + (a + 0.5) * pitch), dz = q[2] - (-0.5 * p.size + (b + 0.5) * pitch);
        if (sqrt(dx * dx + dz * dz) < inner - 1e-6)
            fail_msg("vertex %u lies inside hole (%d, %d)", v, a, b);
    }
    check_uvs(&m);
    check_no_self_intersection(&m, ids);
    free(ids);
    sam_shape_mesh_destroy(&m);
}

static void test_perforated(void **state)
{
    (void)state;
    check_perforated(12, 3, 0.05, 4);
    /* One hole, a thick plate; too low a resolution still gets 2 steps per
     * side of each hole's cell. */
    check_perforated(8, 1, 0.4, 8);
    check_perforated(8, 5, 0.02, 2);
    sam_shape_params p;
    assert_int_equal(sam_shape_default_params("perforated", &p, NULL), SAM_OK);
    assert_true(isinf(sam_shape_max_thickness("perforated", &p)));
}

static void test_deterministic(void **state)
{
    (void)state;
    size_t n;
    const char *const *names = sam_shape_names(&n);
    for (size_t k = 0; k < n; ++k) {
        sam_shape_params p;
        assert_int_equal(sam_shape_default_params(names[k], &p, NULL), SAM_OK);
        p.resolution = sam_shape_find(names[k])->min_resolution * 2;
        sam_shape_mesh a, b;
        assert_int_equal(sam_shape_generate(names[k], &p, &a, NULL), SAM_OK);
        assert_int_equal(sam_shape_generate(names[k], &p, &b, NULL), SAM_OK);
        assert_int_equal(a.vertex_count, b.vertex_count);
        assert_int_equal(a.triangle_count, b.triangle_count);
        assert_memory_equal(a.positions, b.positions, 3 * sizeof(float) * a.vertex_count);
        assert_memory_equal(a.uvs, b.uvs, 2 * sizeof(float) * a.vertex_count);
        assert_memory_equal(a.triangles, b.triangles, 3 * sizeof(uint32_t) * a.triangle_count);
        sam_shape_mesh_destroy(&b);
        /* The seed changes blobs only. */
        p.seed += 1;
        assert_int_equal(sam_shape_generate(names[k], &p, &b, NULL), SAM_OK);
        int same = memcmp(a.positions, b.positions, 3 * sizeof(float) * a.vertex_count) == 0;
        assert_int_equal(same, strcmp(names[k], "blobs") != 0);
        sam_shape_mesh_destroy(&a);
        sam_shape_mesh_destroy(&b);
    }
}

static void expect_invalid(const char *name, sam_shape_params p, const char *needle)
{
    sam_shape_mesh m;
    sam_error err;
    memset(&m, 0xab, sizeof m);
    assert_int_equal(sam_shape_generate(name, &p, &m, &err), SAM_ERR_INVALID_ARGUMENT);
    if (!strstr(err.message, needle))
        fail_msg("message \"%s\" lacks \"%s\"", err.message, needle);
    assert_null(m.positions);
    assert_int_equal(m.vertex_count, 0);
}

static void test_invalid_params(void **state)
{
    (void)state;
    sam_shape_params p;
    assert_int_equal(sam_shape_default_params("sphere", &p, NULL), SAM_OK);
    expect_invalid("pyramid", p, "pyramid");
    sam_shape_params q = p;
    q.resolution = 0;
    expect_invalid("sphere", q, "resolution 0");
    q = p;
    q.size = -1;
    expect_invalid("sphere", q, "size -1");
    q = p;
    q.size = NAN;
    expect_invalid("sphere", q, "size nan");
    assert_int_equal(sam_shape_default_params("slab", &p, NULL), SAM_OK);
    q = p;
    q.depth = 0;
    expect_invalid("slab", q, "depth 0");
    q = p;
    q.thickness = INFINITY;
    expect_invalid("slab", q, "thickness inf");
    assert_int_equal(sam_shape_default_params("torus", &p, NULL), SAM_OK);
    q = p;
    q.thickness = 0.6;
    expect_invalid("torus", q, "thickness 0.6");
    q.thickness = 1e-9;
    expect_invalid("torus", q, "thickness 1e-09");
    assert_int_equal(sam_shape_default_params("blobs", &p, NULL), SAM_OK);
    q = p;
    q.count = 0;
    expect_invalid("blobs", q, "count 0");
    q.count = SAM_SHAPE_MAX_COUNT;
    q.resolution = SAM_SHAPE_MAX_RESOLUTION;
    expect_invalid("blobs", q, "resolution 8192");
    assert_int_equal(sam_shape_default_params("perforated", &p, NULL), SAM_OK);
    q = p;
    q.count = 0;
    expect_invalid("perforated", q, "count 0");
    q = p;
    q.thickness = 0;
    expect_invalid("perforated", q, "thickness 0");
    sam_shape_mesh m;
    assert_int_equal(sam_shape_generate("sphere", NULL, &m, NULL), SAM_ERR_INVALID_ARGUMENT);
    assert_true(sam_shape_max_thickness("sphere", &p) == 0.0);
    assert_true(sam_shape_max_thickness("nothing", &p) == 0.0);
}

/* ------------------------------------------------------------ writers */

static char *slurp(const char *path, size_t *size)
{
    uint8_t *data;
    size_t n;
    sam_error err;
    if (sam_read_file(path, &data, &n, &err) != SAM_OK)
        fail_msg("%s", err.message);
    if (size)
        *size = n;
    return (char *)data;
}

static void test_write_obj(void **state)
{
    (void)state;
    sam_shape_mesh m = generate("torus", 12);
    char path[512];
    sam_test_tmp_path(path, sizeof path, "shape_torus.obj");
    sam_error err;
    assert_int_equal(sam_shape_write_obj(path, &m, &err), SAM_OK);
    uint32_t unique;
    uint32_t *ids = malloc(m.vertex_count * sizeof *ids);
    assert_int_equal(sam_shape_weld(&m, ids, &unique, NULL), SAM_OK);
    free(ids);

    char *text = slurp(path, NULL);
    float *v = malloc(3 * sizeof(float) * m.vertex_count);
    float *vt = malloc(2 * sizeof(float) * m.vertex_count);
    uint32_t nv = 0, nvt = 0, nf = 0;
    char *save = NULL;
    for (char *line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        char *end;
        if (strncmp(line, "v ", 2) == 0) {
            assert_true(nv < m.vertex_count);
            end = line + 2;
            for (int k = 0; k < 3; ++k)
                v[3 * nv + k] = strtof(end, &end);
            ++nv;
        } else if (strncmp(line, "vt ", 3) == 0) {
            assert_true(nvt < m.vertex_count);
            end = line + 3;
            for (int k = 0; k < 2; ++k)
                vt[2 * nvt + k] = strtof(end, &end);
            ++nvt;
        } else if (strncmp(line, "f ", 2) == 0) {
            assert_true(nf < m.triangle_count);
            end = line + 2;
            for (int c = 0; c < 3; ++c) {
                unsigned long a = strtoul(end, &end, 10);
                assert_true(*end == '/');
                unsigned long b = strtoul(end + 1, &end, 10);
                assert_true(a >= 1 && a <= nv && b >= 1 && b <= nvt);
                uint32_t r = m.triangles[3 * nf + c];
                /* The corner's position and UV read back bit-exactly. */
                assert_memory_equal(&v[3 * (a - 1)], &m.positions[3 * r], 3 * sizeof(float));
                assert_memory_equal(&vt[2 * (b - 1)], &m.uvs[2 * r], 2 * sizeof(float));
            }
            ++nf;
        } else {
            assert_true(line[0] == '#');
        }
    }
    assert_int_equal(nv, unique);
    assert_true(nv < m.vertex_count); /* seams share positions */
    assert_int_equal(nvt, m.vertex_count);
    assert_int_equal(nf, m.triangle_count);
    free(text);
    free(v);
    free(vt);

    /* A failed write leaves an existing file alone. */
    sam_shape_mesh empty;
    memset(&empty, 0, sizeof empty);
    size_t before, after;
    free(slurp(path, &before));
    assert_int_equal(sam_shape_write_obj(path, &empty, &err), SAM_ERR_INVALID_ARGUMENT);
    free(slurp(path, &after));
    assert_int_equal(before, after);
    assert_int_equal(sam_shape_write_obj("/nonexistent-dir/x.obj", &m, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent-dir/x.obj"));
    sam_shape_mesh_destroy(&m);
}

static void test_obj_companions(void **state)
{
    (void)state;
    char mtl[64], png[64];
    sam_error err;
    assert_int_equal(sam_shape_obj_companions("dir.v2/leaf.obj", mtl, png, sizeof mtl, &err), SAM_OK);
    assert_string_equal(mtl, "dir.v2/leaf.mtl");
    assert_string_equal(png, "dir.v2/leaf_albedo.png");
    /* A dot in a folder's name, or one that starts a file's, is no extension. */
    assert_int_equal(sam_shape_obj_companions("dir.v2/leaf", mtl, png, sizeof mtl, &err), SAM_OK);
    assert_string_equal(mtl, "dir.v2/leaf.mtl");
    assert_int_equal(sam_shape_obj_companions(".leaf", mtl, png, sizeof mtl, &err), SAM_OK);
    assert_string_equal(png, ".leaf_albedo.png");
    assert_int_equal(sam_shape_obj_companions("a-rather-long-name-for-a-leaf-of-a-tree.obj", mtl, png, 40, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "a-rather-long-name"));
    assert_int_equal(sam_shape_obj_companions(NULL, mtl, png, sizeof mtl, &err), SAM_ERR_INVALID_ARGUMENT);
    /* The material lines could not name them; a blank in a folder is fine. */
    assert_int_equal(sam_shape_obj_companions("my leaf.obj", mtl, png, sizeof mtl, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "blanks"));
    assert_int_equal(sam_shape_obj_companions("my dir/leaf.obj", mtl, png, sizeof mtl, &err), SAM_OK);
}

/* The albedo goes with the OBJ and comes back through the loader that
 * reads a mesh's own texture, as 8-bit sRGB; a failed OBJ takes its
 * companions with it. */
static void test_write_obj_albedo(void **state)
{
    (void)state;
    sam_shape_mesh m = generate("torus", 12);
    sam_image albedo;
    sam_error err;
    assert_int_equal(sam_image_create(&albedo, 3, 2, 3, &err), SAM_OK);
    for (uint32_t k = 0; k < 18; ++k)
        albedo.pixels[k] = (float)k / 17.0f;
    char path[512], mtl[512], png[512];
    sam_test_tmp_path(path, sizeof path, "shape_albedo.obj");
    assert_int_equal(sam_shape_write_obj_albedo(path, &m, &albedo, &err), SAM_OK);
    assert_int_equal(sam_shape_obj_companions(path, mtl, png, sizeof mtl, &err), SAM_OK);
    char *text = slurp(mtl, NULL);
    assert_non_null(strstr(text, "\nmap_Kd shape_albedo_albedo.png\n"));
    free(text);
    sam_image back;
    char note[1200];
    assert_int_equal(sam_mesh_load_albedo(path, &back, note, sizeof note, &err), SAM_OK);
    assert_non_null(back.pixels);
    assert_int_equal(back.width, 3);
    assert_int_equal(back.height, 2);
    assert_int_equal(back.channels, 3);
    /* Half an 8-bit sRGB step, in linear terms, at its steepest (1.0). */
    for (uint32_t k = 0; k < 18; ++k)
        assert_true(fabsf(back.pixels[k] - albedo.pixels[k]) < 0.0045f);
    sam_image_destroy(&back);
    /* The OBJ reads back as the plain writer's mesh. */
    sam_mesh mesh;
    assert_int_equal(sam_mesh_load(path, &mesh, NULL, &err), SAM_OK);
    assert_int_equal(mesh.triangle_count, m.triangle_count);
    sam_mesh_destroy(&mesh);

    assert_int_equal(sam_shape_write_obj_albedo(path, &m, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    float *uvs = m.uvs;
    m.uvs = NULL;
    assert_int_equal(sam_shape_write_obj_albedo(path, &m, &albedo, &err), SAM_ERR_INVALID_ARGUMENT);
    m.uvs = uvs;
    /* An OBJ that cannot be put in place (a folder is there) leaves no
     * texture or material library behind. */
    sam_test_tmp_path(path, sizeof path, "shape_albedo_dir.obj");
    mkdir(path, 0755);
    assert_int_equal(sam_shape_write_obj_albedo(path, &m, &albedo, &err), SAM_ERR_IO);
    assert_int_equal(sam_shape_obj_companions(path, mtl, png, sizeof mtl, &err), SAM_OK);
    assert_false(sam_test_file_exists(mtl));
    assert_false(sam_test_file_exists(png));
    /* Companions that were there are replaced and kept: an OBJ there
     * before would still name them. */
    sam_test_write_text(mtl, "old");
    sam_test_write_text(png, "old");
    assert_int_equal(sam_shape_write_obj_albedo(path, &m, &albedo, &err), SAM_ERR_IO);
    text = slurp(mtl, NULL);
    assert_non_null(strstr(text, "map_Kd shape_albedo_dir_albedo.png"));
    free(text);
    sam_image kept;
    assert_int_equal(sam_image_read_png(png, &kept, SAM_PNG_SRGB, &err), SAM_OK);
    assert_int_equal(kept.width, 3);
    sam_image_destroy(&kept);
    remove(mtl);
    remove(png);
    rmdir(path);
    sam_image_destroy(&albedo);
    sam_shape_mesh_destroy(&m);
}

/* Parses the PLY header; returns the offset of the body. */
static size_t ply_header(const char *data, const char *format, uint32_t vc, uint32_t tc)
{
    const char *end = strstr(data, "end_header\n");
    assert_non_null(end);
    char expect[256];
    snprintf(expect, sizeof expect, "format %s 1.0\n", format);
    assert_non_null(strstr(data, expect));
    snprintf(expect, sizeof expect, "element vertex %u\n", vc);
    assert_non_null(strstr(data, expect));
    snprintf(expect, sizeof expect, "element face %u\n", tc);
    assert_non_null(strstr(data, expect));
    assert_non_null(strstr(data, "property float u\nproperty float v\n"));
    return (size_t)(end - data) + strlen("end_header\n");
}

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void test_write_ply(void **state)
{
    (void)state;
    sam_shape_mesh m = generate("sphere", 8);
    char path[512];
    sam_test_tmp_path(path, sizeof path, "shape_sphere_bin.ply");
    assert_int_equal(sam_shape_write_ply(path, &m, 1, NULL), SAM_OK);
    size_t size;
    char *data = slurp(path, &size);
    size_t body = ply_header(data, "binary_little_endian", m.vertex_count, m.triangle_count);
    assert_int_equal(size, body + 20 * (size_t)m.vertex_count + 13 * (size_t)m.triangle_count);
    const uint8_t *b = (const uint8_t *)data + body;
    for (uint32_t v = 0; v < m.vertex_count; ++v, b += 20)
        for (int k = 0; k < 5; ++k) {
            uint32_t x = le32(b + 4 * k);
            float f;
            memcpy(&f, &x, sizeof f);
            float want = k < 3 ? m.positions[3 * v + k] : m.uvs[2 * v + k - 3];
            assert_memory_equal(&f, &want, sizeof f);
        }
    for (uint32_t t = 0; t < m.triangle_count; ++t, b += 13) {
        assert_int_equal(b[0], 3);
        for (int c = 0; c < 3; ++c)
            assert_int_equal(le32(b + 1 + 4 * c), m.triangles[3 * t + c]);
    }
    free(data);

    sam_test_tmp_path(path, sizeof path, "shape_sphere_ascii.ply");
    assert_int_equal(sam_shape_write_ply(path, &m, 0, NULL), SAM_OK);
    data = slurp(path, NULL);
    char *p = data + ply_header(data, "ascii", m.vertex_count, m.triangle_count);
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        for (int k = 0; k < 5; ++k) {
            float f = strtof(p, &p);
            float want = k < 3 ? m.positions[3 * v + k] : m.uvs[2 * v + k - 3];
            assert_memory_equal(&f, &want, sizeof f);
        }
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        assert_int_equal(strtoul(p, &p, 10), 3);
        for (int c = 0; c < 3; ++c)
            assert_int_equal(strtoul(p, &p, 10), m.triangles[3 * t + c]);
    }
    while (*p == '\n')
        ++p;
    assert_int_equal(*p, '\0');
    free(data);
    sam_shape_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names_and_defaults),
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_slab),
        cmocka_unit_test(test_torus),
        cmocka_unit_test(test_ear),
        cmocka_unit_test(test_knot),
        cmocka_unit_test(test_blobs),
        cmocka_unit_test(test_perforated),
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_invalid_params),
        cmocka_unit_test(test_write_obj),
        cmocka_unit_test(test_obj_companions),
        cmocka_unit_test(test_write_obj_albedo),
        cmocka_unit_test(test_write_ply),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
