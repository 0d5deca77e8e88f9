#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "sam/sam_image.h"
#include "sam/sam_mesh.h"
#include "sam_test.h"

/* A unit cube with one UV chart per face: 8 positions, 24 UV corners. */
static const char *cube_obj =
    "# cube with per-face UV charts\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "vt 0 0\nvt 0.3 0\nvt 0.3 0.3\nvt 0 0.3\n"
    "vt 0.35 0\nvt 0.65 0\nvt 0.65 0.3\nvt 0.35 0.3\n"
    "vt 0.7 0\nvt 1 0\nvt 1 0.3\nvt 0.7 0.3\n"
    "vt 0 0.35\nvt 0.3 0.35\nvt 0.3 0.65\nvt 0 0.65\n"
    "vt 0.35 0.35\nvt 0.65 0.35\nvt 0.65 0.65\nvt 0.35 0.65\n"
    "vt 0.7 0.35\nvt 1 0.35\nvt 1 0.65\nvt 0.7 0.65\n"
    "f 1/1 4/2 3/3 2/4\n"      /* z = 0, normal -z */
    "f 5/5 6/6 7/7 8/8\n"      /* z = 1, +z */
    "f 1/9 2/10 6/11 5/12\n"   /* y = 0, -y */
    "f 4/13 8/14 7/15 3/16\n"  /* y = 1, +y */
    "f 1/17 5/18 8/19 4/20\n"  /* x = 0, -x */
    "f 2/21 3/22 7/23 6/24\n"; /* x = 1, +x */

static void write_tmp(char *path, size_t n, const char *name, const char *text)
{
    sam_test_tmp_path(path, n, name);
    sam_test_write_text(path, text);
}

static int ring_is_closed(const sam_mesh *m, uint32_t t)
{
    return m->ring[m->ring_offsets[t]] == m->ring[m->ring_offsets[t + 1] - 1];
}

static uint32_t ring_size(const sam_mesh *m, uint32_t t)
{
    return m->ring_offsets[t + 1] - m->ring_offsets[t];
}

/* Every consecutive ring pair (p, q) of topo vertex t must be a triangle
 * (t, p, q) of the mesh in that winding: this is what eq. 16 relies on. */
static void assert_rings_match_triangles(const sam_mesh *m)
{
    for (uint32_t t = 0; t < m->topo_count; ++t) {
        for (uint32_t k = m->ring_offsets[t] + 1; k < m->ring_offsets[t + 1]; ++k) {
            uint32_t p = m->ring[k - 1], q = m->ring[k];
            int found = 0;
            for (uint32_t f = 0; f < m->triangle_count && !found; ++f) {
                for (int c = 0; c < 3; ++c) {
                    if (m->topo_of[m->triangles[3 * f + c]] == t &&
                        m->topo_of[m->triangles[3 * f + (c + 1) % 3]] == p &&
                        m->topo_of[m->triangles[3 * f + (c + 2) % 3]] == q)
                        found = 1;
                }
            }
            if (!found)
                fail_msg("ring pair (%u, %u) of topo vertex %u is not a triangle", p, q, t);
        }
    }
}

static void test_cube_obj_with_uv_seams(void **state)
{
    (void)state;
    char path[512];
    write_tmp(path, sizeof path, "cube.obj", cube_obj);
    sam_mesh m;
    sam_mesh_report rep;
    sam_error err;
    assert_int_equal(sam_mesh_load(path, &m, &rep, &err), SAM_OK);
    assert_int_equal(m.triangle_count, 12);
    assert_int_equal(m.topo_count, 8);
    assert_int_equal(m.vertex_count, 24); /* each corner of each face is its own UV */
    assert_non_null(m.uvs);
    assert_int_equal(rep.polygons_triangulated, 6);
    assert_int_equal(rep.seam_vertices, 8);
    assert_int_equal(rep.boundary_vertices, 0);
    assert_int_equal(rep.non_manifold_vertices, 0);
    assert_int_equal(rep.non_manifold_edges, 0);
    assert_false(rep.normals_from_file);
    assert_float_equal(sam_mesh_diagonal(&m), sqrt(3.0), 1e-6); /* the unit cube */

    float *area = malloc(m.topo_count * sizeof *area);
    sam_mesh_fan_areas(&m, NULL, 10.0f, area); /* 10 mm per unit: faces are 100 mm^2 */
    double total = 0;
    for (uint32_t t = 0; t < m.topo_count; ++t) {
        assert_true(ring_is_closed(&m, t));
        total += area[t];
        /* Every corner has 3 faces; its fan triangles depend on the diagonals,
         * but the fan area is a third of its triangles' area, between 50 and 100. */
        assert_true(area[t] > 49.0f && area[t] < 101.0f);
    }
    assert_float_equal(total, 600.0, 1e-3);
    assert_rings_match_triangles(&m);

    /* Render copies of a corner share the topo vertex, position, normal. */
    for (uint32_t r = 0; r < m.vertex_count; ++r) {
        uint32_t t = m.topo_of[r], rep_r = m.topo_rep[t];
        assert_true(rep_r <= r);
        assert_memory_equal(m.positions + 3 * r, m.positions + 3 * rep_r, 3 * sizeof(float));
        assert_memory_equal(m.normals + 3 * r, m.normals + 3 * rep_r, 3 * sizeof(float));
        /* Area-weighted normal of a cube corner points out along the diagonal-ish. */
        const float *p = m.positions + 3 * r, *n = m.normals + 3 * r;
        for (int i = 0; i < 3; ++i)
            assert_true((p[i] - 0.5f) * n[i] > 0.0f);
    }
    /* A cube is flat per face: curvature is concentrated at corners, all convex. */
    float *h = malloc(m.topo_count * sizeof *h);
    sam_mesh_mean_curvature(&m, h);
    for (uint32_t t = 0; t < m.topo_count; ++t)
        assert_true(h[t] > 0.0f);
    free(h);
    free(area);
    sam_mesh_destroy(&m);
}

static const float cube_verts[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
static const int cube_tris[12][3] = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                     {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};

/* The cube as a binary little-endian PLY in buf (>= 1024 bytes); returns its size. */
static size_t cube_binary_ply(unsigned char *buf)
{
    const char *hdr = "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 12\n"
                      "property list uchar int vertex_indices\nend_header\n";
    size_t n = strlen(hdr);
    memcpy(buf, hdr, n);
    memcpy(buf + n, cube_verts, sizeof cube_verts);
    n += sizeof cube_verts;
    for (int f = 0; f < 12; ++f) {
        buf[n++] = 3;
        for (int c = 0; c < 3; ++c) {
            int32_t i = cube_tris[f][c];
            memcpy(buf + n, &i, 4);
            n += 4;
        }
    }
    return n;
}

static void test_same_cube_in_every_format(void **state)
{
    (void)state;
    static const char *off = "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                             "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n";
    /* Comments and obj_info lines (without header keywords) are read past. */
    static const char *ply = "ply\nformat ascii 1.0\ncomment made by hand\nobj_info scanner 3, units mm\n"
                             "element vertex 8\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 6\n"
                             "property list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                             "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n";
    char path[512];
    const char *names[] = {"cube.off", "cube_ascii.ply", "cube_bin.ply", "cube.stl"};
    write_tmp(path, sizeof path, names[0], off);
    write_tmp(path, sizeof path, names[1], ply);

    {
        unsigned char buf[1024];
        size_t n = cube_binary_ply(buf);
        sam_test_write_file(sam_test_tmp_path(path, sizeof path, names[2]), buf, n);
    }
    {
        unsigned char buf[84 + 12 * 50];
        memset(buf, 0, sizeof buf);
        uint32_t count = 12;
        memcpy(buf + 80, &count, 4);
        for (int f = 0; f < 12; ++f) {
            unsigned char *rec = buf + 84 + 50 * f;
            for (int c = 0; c < 3; ++c)
                memcpy(rec + 12 + 12 * c, cube_verts[cube_tris[f][c]], 12);
        }
        sam_test_write_file(sam_test_tmp_path(path, sizeof path, names[3]), buf, sizeof buf);
    }
    for (int i = 0; i < 4; ++i) {
        sam_mesh m;
        sam_error err;
        sam_test_tmp_path(path, sizeof path, names[i]);
        sam_status st = sam_mesh_load(path, &m, NULL, &err);
        if (st != SAM_OK)
            fail_msg("%s: %s", names[i], err.message);
        assert_int_equal(m.triangle_count, 12);
        assert_int_equal(m.topo_count, 8);
        assert_int_equal(m.vertex_count, 8);
        assert_null(m.uvs);
        float area[8];
        sam_mesh_fan_areas(&m, NULL, 1.0f, area);
        double total = 0;
        for (int t = 0; t < 8; ++t)
            total += area[t];
        assert_float_equal(total, 6.0, 1e-5);
        assert_rings_match_triangles(&m);
        sam_mesh_destroy(&m);
    }
}

/* Loads from several threads at once, each going through the files in
 * its own order so that the same format's reader is asked at once: every
 * load gives what it gives alone. OpenMesh's readers keep the state of the
 * read under way, and its diagnostics are captured process-wide. */
enum { LOAD_FILES = 4, LOAD_THREADS = 4, LOAD_ROUNDS = 25 };
typedef struct load_job {
    char path[LOAD_FILES][512];
    uint32_t triangles[LOAD_FILES], vertices[LOAD_FILES];
    int start, failures;
} load_job;

static void *load_in_turn(void *arg)
{
    load_job *job = arg;
    for (int r = 0; r < LOAD_ROUNDS; ++r)
        for (int k = 0; k < LOAD_FILES; ++k) {
            const int f = (job->start + k + r) % LOAD_FILES;
            sam_mesh m;
            sam_error err;
            if (sam_mesh_load(job->path[f], &m, NULL, &err) != SAM_OK) {
                job->failures++;
                continue;
            }
            job->failures += m.triangle_count != job->triangles[f] || m.vertex_count != job->vertices[f];
            sam_mesh_destroy(&m);
        }
    return NULL;
}

static void test_loads_from_several_threads(void **state)
{
    (void)state;
    static const char *texts[LOAD_FILES] = {
        NULL, /* cube_obj */
        "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
        "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n",
        "NOFF\n4 4 0\n0 0 0 0 0 -1\n1 0 0 0 0 -1\n0 1 0 0 0 -1\n0 0 1 0 0 1\n"
        "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
    };
    static const char *names[LOAD_FILES] = {"threads.obj", "threads.off", "threads_normals.off", "threads.ply"};
    load_job jobs[LOAD_THREADS];
    for (int f = 0; f < LOAD_FILES; ++f) {
        write_tmp(jobs[0].path[f], sizeof jobs[0].path[f], names[f], texts[f] ? texts[f] : cube_obj);
        sam_mesh m;
        sam_error err;
        if (sam_mesh_load(jobs[0].path[f], &m, NULL, &err) != SAM_OK)
            fail_msg("%s alone: %s", names[f], err.message);
        jobs[0].triangles[f] = m.triangle_count;
        jobs[0].vertices[f] = m.vertex_count;
        sam_mesh_destroy(&m);
    }
    pthread_t threads[LOAD_THREADS];
    for (int t = 0; t < LOAD_THREADS; ++t) {
        jobs[t] = jobs[0];
        jobs[t].start = t;
        jobs[t].failures = 0;
        assert_int_equal(pthread_create(&threads[t], NULL, load_in_turn, &jobs[t]), 0);
    }
    for (int t = 0; t < LOAD_THREADS; ++t) {
        assert_int_equal(pthread_join(threads[t], NULL), 0);
        if (jobs[t].failures)
            fail_msg("thread %d: %d of %d loads differed from the load alone", t, jobs[t].failures,
                     LOAD_ROUNDS * LOAD_FILES);
    }
}

/* OFF files as other tools write them, which OpenMesh alone misreads or
 * refuses: '#' comments on lines of their own and after values
 * (Geomview), the counts on the keyword's line and glued to it
 * (ModelNet's "OFF8 6 0"), no edge count, and face colours of 1, 3 and 4
 * values (MeshLab). Each loads as the plain cube, vertex for vertex. */
static void test_off_as_other_tools_write_it(void **state)
{
    (void)state;
    static const char *const variants[][2] = {
        {"plain.off", "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n"},
        {"comments.off", "# made by hand\nOFF # a cube\n\n# counts next\n8 6 0\n0 0 0 # origin\n1 0 0\n1 1 0\n"
                         "0 1 0\n#\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n4 0 3 2 1 # bottom\n4 4 5 6 7\n4 0 1 5 4\n"
                         "4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n# end\n"},
        {"inline.off", "OFF 8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                       "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n"},
        {"glued.off", "OFF8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n"},
        {"two_counts.off", "OFF\n8 6\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                           "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n"},
        {"face_colours.off", "COFF\n8 6 0\n0 0 0 1 0 0\n1 0 0 1 0 0\n1 1 0 1 0 0\n0 1 0 1 0 0\n0 0 1 1 0 0\n"
                             "1 0 1 1 0 0\n1 1 1 1 0 0\n0 1 1 1 0 0 1\n4 0 3 2 1 255 0 0\n4 4 5 6 7 0.5 0.5 0.5 1\n"
                             "4 0 1 5 4 3\n4 3 7 6 2 1 1 1\n4 0 4 7 3 0 0 0 0\n4 1 2 6 5\n"},
    };
    sam_mesh plain = {0};
    for (size_t v = 0; v < sizeof variants / sizeof *variants; ++v) {
        char path[512];
        write_tmp(path, sizeof path, variants[v][0], variants[v][1]);
        sam_mesh m;
        sam_error err;
        if (sam_mesh_load(path, &m, NULL, &err) != SAM_OK)
            fail_msg("%s: %s", variants[v][0], err.message);
        assert_int_equal(m.vertex_count, 8);
        assert_int_equal(m.triangle_count, 12);
        if (v == 0) {
            plain = m;
            continue;
        }
        assert_memory_equal(m.positions, plain.positions, 3 * 8 * sizeof *m.positions);
        assert_memory_equal(m.triangles, plain.triangles, 3 * 12 * sizeof *m.triangles);
        sam_mesh_destroy(&m);
    }
    sam_mesh_destroy(&plain);
}

/* A PLY file as it is written, value by value: ASCII, or binary in either
 * byte order (format 0 ASCII, 1 little-endian, 2 big-endian). */
typedef struct ply_out {
    unsigned char buf[8192];
    size_t n;
    int format;
} ply_out;

static void ply_text(ply_out *o, const char *s)
{
    size_t len = strlen(s);
    assert_true(o->n + len <= sizeof o->buf);
    memcpy(o->buf + o->n, s, len);
    o->n += len;
}

/* One value of the PLY type `type`; in ASCII followed by a blank. */
static void ply_value(ply_out *o, const char *type, double v)
{
    if (o->format == 0) {
        char s[64];
        snprintf(s, sizeof s, "%.9g ", v);
        ply_text(o, s);
        return;
    }
    unsigned char le[8];
    int size;
    if (!strcmp(type, "float") || !strcmp(type, "float32")) {
        float f = (float)v;
        memcpy(le, &f, size = 4);
    } else if (!strcmp(type, "double") || !strcmp(type, "float64")) {
        memcpy(le, &v, size = 8);
    } else {
        size = strstr(type, "char") || strstr(type, "8") ? 1 : strstr(type, "short") || strstr(type, "16") ? 2 : 4;
        const int64_t i = (int64_t)v;
        for (int b = 0; b < size; ++b)
            le[b] = (unsigned char)((uint64_t)i >> (8 * b));
    }
    assert_true(o->n + (size_t)size <= sizeof o->buf);
    for (int b = 0; b < size; ++b)
        o->buf[o->n++] = le[o->format == 2 ? size - 1 - b : b];
}

typedef struct ply_variant {
    const char *name;
    const char *count_type, *index_type, *coord_type; /* the corners' list and the positions */
    int vertex_list;  /* a list property after each vertex's position */
    int texcoords;    /* MeshLab's per-corner texcoord list and texnumber after the corners */
    int normals;      /* short nx, ny, nz: integer normals */
    const char *before_end; /* a header line before end_header */
    const char *line_end;   /* after each header line */
} ply_variant;

/* The cube of cube_tris as `v` lays it out. Corner c of face f has the
 * texture coordinate (0.05 f, 0.05 cube_tris[f][c]). */
static size_t ply_cube(const ply_variant *v, int format, unsigned char *buf, size_t cap)
{
    static const char *const formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    ply_out *o = calloc(1, sizeof *o);
    assert_non_null(o);
    o->format = format;
    const char *eol = v->line_end ? v->line_end : "\n";
    char line[160];
#define PLY_LINE(...) (snprintf(line, sizeof line, __VA_ARGS__), ply_text(o, line), ply_text(o, eol))
    PLY_LINE("ply");
    PLY_LINE("format %s 1.0", formats[format]);
    PLY_LINE("element vertex 8");
    for (int a = 0; a < 3; ++a)
        PLY_LINE("property %s %c", v->coord_type, "xyz"[a]);
    if (v->normals)
        PLY_LINE("property short nx"), PLY_LINE("property short ny"), PLY_LINE("property short nz");
    if (v->vertex_list)
        PLY_LINE("property list uchar int neighbours");
    PLY_LINE("property uchar red");
    PLY_LINE("element face 12");
    PLY_LINE("property list %s %s vertex_indices", v->count_type, v->index_type);
    if (v->texcoords)
        PLY_LINE("property list uchar float texcoord"), PLY_LINE("property int texnumber");
    if (v->before_end)
        ply_text(o, v->before_end);
    PLY_LINE("end_header");
#undef PLY_LINE
    for (int i = 0; i < 8; ++i) {
        for (int a = 0; a < 3; ++a)
            ply_value(o, v->coord_type, cube_verts[i][a]);
        for (int a = 0; a < 3 * v->normals; ++a)
            ply_value(o, "short", 2 * cube_verts[i][a] - 1);
        if (v->vertex_list) {
            ply_value(o, "uchar", 2);
            ply_value(o, "int", (i + 1) % 8);
            ply_value(o, "int", (i + 7) % 8);
        }
        ply_value(o, "uchar", 200);
        if (format == 0)
            ply_text(o, "\n");
    }
    for (int f = 0; f < 12; ++f) {
        ply_value(o, v->count_type, 3);
        for (int c = 0; c < 3; ++c)
            ply_value(o, v->index_type, cube_tris[f][c]);
        if (v->texcoords) {
            ply_value(o, "uchar", 6);
            for (int c = 0; c < 3; ++c)
                ply_value(o, "float", 0.05 * f), ply_value(o, "float", 0.05 * cube_tris[f][c]);
            ply_value(o, "int", 0);
        }
        if (format == 0)
            ply_text(o, "\n");
    }
    const size_t n = o->n;
    assert_true(n <= cap);
    memcpy(buf, o->buf, n);
    free(o);
    return n;
}

/* The source vertex of the cube at `p`. */
static int cube_vertex_at(const float *p)
{
    for (int i = 0; i < 8; ++i)
        if (p[0] == cube_verts[i][0] && p[1] == cube_verts[i][1] && p[2] == cube_verts[i][2])
            return i;
    fail_msg("(%g, %g, %g) is no vertex of the cube", (double)p[0], (double)p[1], (double)p[2]);
    return -1;
}

/* PLY files as other tools write them, which OpenMesh's reader alone
 * refuses or misreads without a word (sam_mesh_ply.h): list counts typed
 * uint, int32, ushort, short or char; integer positions and normals; corner indices typed
 * as floats; a list on the vertices; MeshLab's and Metashape's per-corner
 * texcoord lists; a comment, a blank line or a trailing blank at the end of
 * a binary header. Each loads as the plain cube, vertex for vertex, in
 * ASCII and in both byte orders, and the texcoord lists give every
 * corner its own texture coordinate. */
static void test_ply_as_other_tools_write_it(void **state)
{
    (void)state;
    static const ply_variant variants[] = {
        {"plain", "uchar", "int", "float", 0, 0, 0, NULL, NULL},
        {"count_uint", "uint", "uint", "float", 0, 0, 0, NULL, NULL},
        {"count_int32", "int32", "int32", "float", 0, 0, 0, NULL, NULL},
        {"count_uint32", "uint32", "int", "float", 0, 0, 0, NULL, NULL},
        {"count_ushort", "ushort", "int", "float", 0, 0, 0, NULL, NULL},
        {"count_short", "short", "ushort", "float", 0, 0, 0, NULL, NULL},
        {"count_char", "char", "int", "float", 0, 0, 0, NULL, NULL},
        {"count_int8", "int8", "uint8", "float", 0, 0, 0, NULL, NULL},
        {"float_indices", "uchar", "float", "float", 0, 0, 0, NULL, NULL},
        {"short_positions", "uchar", "int", "short", 0, 0, 0, NULL, NULL},
        {"int_positions", "uchar", "int", "int", 0, 0, 0, NULL, NULL},
        {"double_positions", "uchar", "int", "double", 0, 0, 0, NULL, NULL},
        {"vertex_list", "uchar", "int", "float", 1, 0, 0, NULL, NULL},
        {"meshlab_texcoord", "uchar", "int", "float", 0, 1, 0, NULL, NULL},
        {"short_normals", "uchar", "int", "float", 0, 0, 1, NULL, NULL},
        {"comment_last", "uchar", "int", "float", 0, 0, 0, "comment written last\n", NULL},
        {"obj_info_comment_last", "uchar", "int", "float", 0, 0, 0, "obj_info units comment mm\n", NULL},
        {"blank_last", "uchar", "int", "float", 0, 0, 0, "\n", NULL},
        {"trailing_blanks", "uchar", "int", "float", 0, 0, 0, NULL, " \n"},
        {"crlf", "uchar", "int", "float", 0, 0, 0, NULL, "\r\n"},
    };
    for (size_t k = 0; k < sizeof variants / sizeof *variants; ++k) {
        const ply_variant *v = &variants[k];
        for (int format = 0; format < 3; ++format) {
            unsigned char buf[8192];
            char name[96], path[512];
            snprintf(name, sizeof name, "ply_%s_%d.ply", v->name, format);
            const size_t n = ply_cube(v, format, buf, sizeof buf);
            sam_test_write_file(sam_test_tmp_path(path, sizeof path, name), buf, n);
            sam_mesh m;
            sam_error err;
            if (sam_mesh_load(path, &m, NULL, &err) != SAM_OK)
                fail_msg("%s: %s", name, err.message);
            assert_int_equal(m.topo_count, 8);
            assert_int_equal(m.triangle_count, 12);
            for (uint32_t t = 0; t < 12; ++t) {
                int corner[3];
                for (int c = 0; c < 3; ++c)
                    corner[c] = cube_vertex_at(&m.positions[3 * (size_t)m.triangles[3 * t + c]]);
                /* Which of the file's faces this triangle is, in any rotation. */
                int face = -1;
                for (int f = 0; f < 12 && face < 0; ++f)
                    for (int r = 0; r < 3; ++r)
                        if (cube_tris[f][r] == corner[0] && cube_tris[f][(r + 1) % 3] == corner[1] &&
                            cube_tris[f][(r + 2) % 3] == corner[2])
                            face = f;
                if (face < 0)
                    fail_msg("%s: triangle %u (%d %d %d) is none of the file's faces", name, t, corner[0], corner[1],
                             corner[2]);
                if (!v->texcoords)
                    continue;
                assert_non_null(m.uvs);
                for (int c = 0; c < 3; ++c) {
                    const float *uv = &m.uvs[2 * (size_t)m.triangles[3 * t + c]];
                    assert_float_equal(uv[0], 0.05f * (float)face, 1e-6);
                    assert_float_equal(uv[1], 0.05f * (float)corner[c], 1e-6);
                }
            }
            if (v->texcoords)
                assert_int_equal(m.vertex_count, 36);
            else
                assert_null(m.uvs);
            if (v->normals) {
                assert_non_null(m.normals);
                for (uint32_t i = 0; i < m.vertex_count; ++i) {
                    const int s = cube_vertex_at(&m.positions[3 * (size_t)i]);
                    for (int a = 0; a < 3; ++a)
                        assert_float_equal(m.normals[3 * i + a], (2 * cube_verts[s][a] - 1) / sqrtf(3.0f), 1e-5);
                }
            }
            sam_mesh_destroy(&m);
        }
    }
}

/* Loads `text` as `name`; fails the test with the loader's message. */
static void load_text(const char *name, const char *text, sam_mesh *m)
{
    char path[512];
    sam_error err;
    write_tmp(path, sizeof path, name, text);
    if (sam_mesh_load(path, m, NULL, &err) != SAM_OK)
        fail_msg("%s: %s", name, err.message);
}

/* OBJ files OpenMesh's reader alone refuses: a comment after a face's
 * corners (or after a vertex, a UV, a material), and a face continued on
 * the next line with a backslash (LF and CRLF; a comment's backslash
 * continues nothing). Each loads as the plain
 * cube, vertex for vertex and UV for UV, and an error after a continued
 * line names the file's own line. */
static void test_obj_as_other_tools_write_it(void **state)
{
    (void)state;
    static const char *const variants[][2] = {
        {"obj_comments.obj",
         "# cube\nv 0 0 0 # origin\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
         "vt 0 0 # corner\nvt 0.3 0\nvt 0.3 0.3\nvt 0 0.3\nvt 0.35 0\nvt 0.65 0\nvt 0.65 0.3\nvt 0.35 0.3\n"
         "vt 0.7 0\nvt 1 0\nvt 1 0.3\nvt 0.7 0.3\nvt 0 0.35\nvt 0.3 0.35\nvt 0.3 0.65\nvt 0 0.65\n"
         "vt 0.35 0.35\nvt 0.65 0.35\nvt 0.65 0.65\nvt 0.35 0.65\nvt 0.7 0.35\nvt 1 0.35\nvt 1 0.65\nvt 0.7 0.65\n"
         "usemtl skin # the only one\nf 1/1 4/2 3/3 2/4 # bottom\nf 5/5 6/6 7/7 8/8\t#top\nf 1/9 2/10 6/11 5/12\n"
         "f 4/13 8/14 7/15 3/16\nf 1/17 5/18 8/19 4/20\nf 2/21 3/22 7/23 6/24 #\n"},
        {"obj_continued.obj",
         "# exported from C:\\models\\\n"
         "mtllib cube.mtl # its material\n"
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
         "vt 0 0\nvt 0.3 0\nvt 0.3 0.3\nvt 0 0.3\nvt 0.35 0\nvt 0.65 0\nvt 0.65 0.3\nvt 0.35 0.3\n"
         "vt 0.7 0\nvt 1 0\nvt 1 0.3\nvt 0.7 0.3\nvt 0 0.35\nvt 0.3 0.35\nvt 0.3 0.65\nvt 0 0.65\n"
         "vt 0.35 0.35\nvt 0.65 0.35\nvt 0.65 0.65\nvt 0.35 0.65\nvt 0.7 0.35\nvt 1 0.35\nvt 1 0.65\nvt 0.7 0.65\n"
         "f 1/1 4/2 \\\n3/3 2/4\nf 5/5 \\\r\n 6/6 \\\n 7/7 8/8\nf 1/9 2/10 6/11 5/12\\\n\n"
         "f 4/13 8/14 7/15 3/16\nf 1/17 5/18 8/19 4/20\nf 2/21 3/22 7/23 6/24\n"},
    };
    sam_mesh plain;
    load_text("obj_plain.obj", cube_obj, &plain);
    for (size_t v = 0; v < sizeof variants / sizeof *variants; ++v) {
        sam_mesh m;
        load_text(variants[v][0], variants[v][1], &m);
        assert_int_equal(m.vertex_count, plain.vertex_count);
        assert_int_equal(m.triangle_count, plain.triangle_count);
        assert_memory_equal(m.positions, plain.positions, 3 * (size_t)m.vertex_count * sizeof *m.positions);
        assert_memory_equal(m.uvs, plain.uvs, 2 * (size_t)m.vertex_count * sizeof *m.uvs);
        assert_memory_equal(m.triangles, plain.triangles, 3 * (size_t)m.triangle_count * sizeof *m.triangles);
        sam_mesh_destroy(&m);
    }
    sam_mesh_destroy(&plain);
    /* Lines 4 and 5 are one face; the bad corner is on line 6. */
    char path[512];
    write_tmp(path, sizeof path, "obj_continued_bad.obj",
              "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n 2 3\nf 1 2 9\n");
    sam_mesh m;
    sam_error err;
    assert_int_equal(sam_mesh_load(path, &m, NULL, &err), SAM_ERR_FORMAT);
    if (!strstr(err.message, "line 6"))
        fail_msg("the message does not name line 6: %s", err.message);
}

/* An OFF written again keeps its own layout, whatever OFF was read before
 * it: OpenMesh's OFF reader keeps the layout of the last file it opened,
 * and read from memory a commented OFF after a NOFF took six values a
 * vertex. A commented NOFF keeps its normals, a commented STOFF its UVs. */
static void test_rewritten_off_keeps_its_layout(void **state)
{
    (void)state;
    static const char *const faces = "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n";
    static const float corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    char noff[1024], stoff[1024], noff_c[1100], stoff_c[1100];
    int n = snprintf(noff, sizeof noff, "NOFF\n8 6 0\n"), t = snprintf(stoff, sizeof stoff, "STOFF\n8 6 0\n");
    for (int v = 0; v < 8; ++v) {
        const float *c = corner[v];
        n += snprintf(noff + n, sizeof noff - (size_t)n, "%g %g %g %g %g %g\n", c[0], c[1], c[2], 2 * c[0] - 1,
                      2 * c[1] - 1, 2 * c[2] - 1);
        t += snprintf(stoff + t, sizeof stoff - (size_t)t, "%g %g %g %g %g\n", c[0], c[1], c[2], 0.1 + 0.1 * v,
                      0.9 - 0.1 * v);
    }
    snprintf(noff + n, sizeof noff - (size_t)n, "%s", faces);
    snprintf(stoff + t, sizeof stoff - (size_t)t, "%s", faces);
    snprintf(noff_c, sizeof noff_c, "# normals\n%s", noff);
    snprintf(stoff_c, sizeof stoff_c, "# texture coordinates\n%s", stoff);
    sam_mesh plain, m;
    load_text("layout_noff.off", noff, &plain);
    load_text("layout_comment.off", "# a plain cube after a NOFF\nOFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
                                    "1 0 1\n1 1 1\n0 1 1\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n"
                                    "4 1 2 6 5\n",
              &m);
    assert_int_equal(m.vertex_count, 8);
    assert_memory_equal(m.positions, plain.positions, 3 * 8 * sizeof *m.positions);
    sam_mesh_destroy(&m);
    load_text("layout_noff_comment.off", noff_c, &m);
    assert_non_null(m.normals);
    assert_memory_equal(m.normals, plain.normals, 3 * (size_t)m.vertex_count * sizeof *m.normals);
    sam_mesh_destroy(&m);
    sam_mesh_destroy(&plain);
    load_text("layout_stoff.off", stoff, &plain);
    load_text("layout_stoff_comment.off", stoff_c, &m);
    assert_non_null(plain.uvs);
    assert_non_null(m.uvs);
    assert_int_equal(m.vertex_count, plain.vertex_count);
    assert_memory_equal(m.uvs, plain.uvs, 2 * (size_t)m.vertex_count * sizeof *m.uvs);
    sam_mesh_destroy(&m);
    sam_mesh_destroy(&plain);
}

/* The body of a mesh leaves out loose specks only: a stray triangle far
 * from a cube whose every face is split from the next by a UV seam (so the
 * cube is one piece only through its welded positions) is left out of the
 * bounds and the diagonal; pieces of the same size are all kept; a piece
 * of 1/48 of the largest's area is kept, one of 1/600 is not; positions
 * alone (no triangles) keep every vertex. */
static void test_body_leaves_out_loose_specks(void **state)
{
    (void)state;
    char path[512];
    write_tmp(path, sizeof path, "cube_body.obj", cube_obj);
    sam_mesh cube;
    sam_error err;
    assert_int_equal(sam_mesh_load(path, &cube, NULL, &err), SAM_OK);
    assert_int_equal(cube.vertex_count, 24);
    /* Add a triangle at (5, 5, 5) of side s. */
    const uint32_t n = cube.vertex_count;
    for (int k = 0; k < 4; ++k) {
        const float side[4] = {0.01f, 0.14f, 0.5f, 1.0f}; /* areas 0.00005, 0.0098, 0.125, 0.5 of the cube's 6 */
        float pos[27 * 3];
        uint32_t tri[13 * 3];
        memcpy(pos, cube.positions, 3 * (size_t)n * sizeof *pos);
        memcpy(tri, cube.triangles, 3 * 12 * sizeof *tri);
        const float at[3][3] = {{5, 5, 5}, {5 + side[k], 5, 5}, {5, 5 + side[k], 5}};
        memcpy(pos + 3 * n, at, sizeof at);
        tri[36] = n, tri[37] = n + 1, tri[38] = n + 2;
        const sam_mesh m = {.vertex_count = n + 3, .positions = pos, .triangle_count = 13, .triangles = tri};
        uint8_t in_body[27];
        sam_mesh_body_info body;
        assert_int_equal(sam_mesh_body(&m, in_body, &body, &err), SAM_OK);
        const int speck = k < 2; /* under 1% of the cube's area */
        assert_int_equal(body.loose_pieces, speck);
        assert_int_equal(body.loose_vertices, 3 * speck);
        assert_int_equal(body.box_changed, speck);
        for (uint32_t v = 0; v < n + 3; ++v)
            assert_int_equal(in_body[v], v < n || !speck);
        assert_float_equal(body.total_area, 6.0 + 0.5 * side[k] * side[k], 1e-5);
        const double whole = sqrt(2.0 * (5 + side[k]) * (5 + side[k]) + 25.0); /* every vertex's bounds */
        assert_float_equal(sam_mesh_diagonal(&m), speck ? sqrt(3.0) : whole, 1e-5);
        for (int c = 0; c < 3; ++c) {
            assert_float_equal(body.min[c], 0, 0);
            assert_float_equal(body.max[c], speck ? 1 : 5 + (c < 2 ? side[k] : 0), 1e-6);
        }
        /* The same positions without triangles: every vertex counts. */
        const sam_mesh points = {.vertex_count = n + 3, .positions = pos};
        assert_float_equal(sam_mesh_diagonal(&points), whole, 1e-5);
        assert_int_equal(sam_mesh_body(&points, NULL, &body, &err), SAM_OK);
        assert_int_equal(body.loose_pieces, 0);
    }
    /* Two cubes of one size, far apart: both are the body. */
    float two[48 * 3];
    uint32_t tri2[24 * 3];
    memcpy(two, cube.positions, 3 * (size_t)n * sizeof *two);
    for (uint32_t v = 0; v < n; ++v)
        for (int c = 0; c < 3; ++c)
            two[3 * (n + v) + c] = cube.positions[3 * v + c] + 10.0f;
    memcpy(tri2, cube.triangles, 36 * sizeof *tri2);
    for (int i = 0; i < 36; ++i)
        tri2[36 + i] = cube.triangles[i] + n;
    const sam_mesh pair = {.vertex_count = 2 * n, .positions = two, .triangle_count = 24, .triangles = tri2};
    sam_mesh_body_info body;
    assert_int_equal(sam_mesh_body(&pair, NULL, &body, &err), SAM_OK);
    assert_int_equal(body.loose_pieces, 0);
    assert_false(body.box_changed);
    assert_float_equal(sam_mesh_diagonal(&pair), sqrt(3.0) * 11, 1e-5);
    /* A tiny triangle joined to a large one only where one has +0 and the
     * other -0 (equal positions, which topology welds) is part of it. */
    {
        const float pos[6 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, -0.0f, 0, 0, -0.001f, 0, 0, 0, 0, 0.001f};
        const uint32_t tri[6] = {0, 1, 2, 3, 4, 5};
        const sam_mesh joined = {.vertex_count = 6, .positions = (float *)pos, .triangle_count = 2,
                                 .triangles = (uint32_t *)tri};
        assert_int_equal(sam_mesh_body(&joined, NULL, &body, &err), SAM_OK);
        assert_int_equal(body.loose_pieces, 0);
    }
    /* A triangle naming a vertex past the count is refused. */
    tri2[5] = 2 * n;
    assert_int_equal(sam_mesh_body(&pair, NULL, &body, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "triangle 1 names vertex 48 of 48"));
    sam_mesh_destroy(&cube);
}

/* A 2x2 grid of unit quads in the plane z = 0 (an open square sheet, 3x3
 * vertices), each cut along the same diagonal, moved `offset` units along x. */
static sam_status sheet_at(float offset, sam_mesh *m, sam_mesh_report *rep, sam_error *err)
{
    float pos[9 * 3];
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            pos[3 * (3 * j + i)] = offset + (float)i;
            pos[3 * (3 * j + i) + 1] = (float)j;
            pos[3 * (3 * j + i) + 2] = 0.0f;
        }
    static const uint32_t tri[8 * 3] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7};
    sam_mesh_input in = {.name = "sheet", .vertex_count = 9, .positions = pos, .triangle_count = 8, .triangles = tri};
    return sam_mesh_create(&in, m, rep, err);
}

static void test_open_sheet_rings_and_fan_areas(void **state)
{
    (void)state;
    sam_mesh m;
    sam_mesh_report rep;
    sam_error err;
    assert_int_equal(sheet_at(0.0f, &m, &rep, &err), SAM_OK);
    assert_int_equal(m.topo_count, 9);
    assert_int_equal(rep.boundary_vertices, 8);
    /* Centre vertex 4: interior, 6 triangles (the diagonals a-c meet it in
     * two quads), closed ring of 7 entries. */
    assert_true(ring_is_closed(&m, 4));
    assert_int_equal(ring_size(&m, 4), 7);
    /* Corner 0: open fan of 2 triangles -> 3 entries, starting and ending at
     * its boundary neighbours 1 and 3 (CCW around +z: 1 -> 4 -> 3). */
    assert_false(ring_is_closed(&m, 0));
    assert_int_equal(ring_size(&m, 0), 3);
    assert_int_equal(m.ring[m.ring_offsets[0]], 1);
    assert_int_equal(m.ring[m.ring_offsets[0] + 1], 4);
    assert_int_equal(m.ring[m.ring_offsets[0] + 2], 3);
    /* Corner 2 has a single triangle: ring [5, 1]. */
    assert_int_equal(ring_size(&m, 2), 2);
    assert_int_equal(m.ring[m.ring_offsets[2]], 5);
    float area[9];
    sam_mesh_fan_areas(&m, NULL, 2.0f, area); /* 2 mm per unit: areas x4 */
    /* Each triangle has area 0.5; the centre has 6 -> 1 unit^2 -> 4 mm^2. */
    assert_float_equal(area[4], 4.0f, 1e-5);
    assert_float_equal(area[0], 4.0f * 2 * 0.5f / 3.0f, 1e-5);
    assert_float_equal(area[2], 4.0f * 0.5f / 3.0f, 1e-5);
    assert_rings_match_triangles(&m);
    /* Deformed pose: stretch x by 3; fan areas scale by 3. */
    float moved[9 * 3];
    memcpy(moved, m.positions, sizeof moved);
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        moved[3 * v] *= 3.0f;
    float area2[9];
    sam_mesh_fan_areas(&m, moved, 2.0f, area2);
    for (int t = 0; t < 9; ++t)
        assert_float_equal(area2[t], 3.0f * area[t], 1e-4);
    /* Flat sheet: zero curvature inside, and the boundary takes the mean of
     * interior neighbours (0 too). Normals +z. */
    float h[9];
    sam_mesh_mean_curvature(&m, h);
    for (int t = 0; t < 9; ++t) {
        assert_float_equal(h[t], 0.0f, 1e-6);
        assert_float_equal(m.topo_normals[3 * t + 2], 1.0f, 1e-6);
    }
    sam_mesh_destroy(&m);
}

/* An octahedron-like sphere approximation refined by subdivision gives
 * curvature ~ 1/R and total fan area ~ 4 pi R^2. */
static void test_sphere_curvature(void **state)
{
    (void)state;
    /* Subdivide an octahedron 5 times, projecting onto radius 2. */
    uint32_t nv = 6, nt = 8;
    float *pos = malloc(6 * 3 * sizeof *pos);
    uint32_t *tri = malloc(8 * 3 * sizeof *tri);
    static const float o[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const uint32_t ot[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                      {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    memcpy(pos, o, sizeof o);
    memcpy(tri, ot, sizeof ot);
    for (int level = 0; level < 4; ++level) {
        /* Midpoints are duplicated per triangle; welding merges them. */
        float *p2 = malloc(((size_t)nv + 3 * nt) * 3 * sizeof *p2);
        uint32_t *t2 = malloc((size_t)nt * 4 * 3 * sizeof *t2);
        memcpy(p2, pos, nv * 3 * sizeof *pos);
        uint32_t nv2 = nv;
        for (uint32_t f = 0; f < nt; ++f) {
            uint32_t v[3] = {tri[3 * f], tri[3 * f + 1], tri[3 * f + 2]}, mid[3];
            for (int e = 0; e < 3; ++e) {
                /* Canonical order of the endpoints makes both sides' midpoints bit-identical. */
                uint32_t a = v[e] < v[(e + 1) % 3] ? v[e] : v[(e + 1) % 3];
                uint32_t b = v[e] < v[(e + 1) % 3] ? v[(e + 1) % 3] : v[e];
                float m[3];
                double l = 0;
                for (int i = 0; i < 3; ++i) {
                    m[i] = 0.5f * (p2[3 * a + i] + p2[3 * b + i]);
                    l += (double)m[i] * m[i];
                }
                for (int i = 0; i < 3; ++i)
                    p2[3 * nv2 + i] = (float)(m[i] / sqrt(l));
                mid[e] = nv2++;
            }
            uint32_t sub[12] = {v[0], mid[0], mid[2], mid[0], v[1], mid[1],
                                mid[2], mid[1], v[2], mid[0], mid[1], mid[2]};
            memcpy(t2 + 12 * f, sub, sizeof sub);
        }
        free(pos);
        free(tri);
        pos = p2;
        tri = t2;
        nv = nv2;
        nt *= 4;
    }
    for (uint32_t i = 0; i < 3 * nv; ++i)
        pos[i] *= 2.0f;
    sam_mesh_input in = {.name = "sphere", .vertex_count = nv, .positions = pos,
                         .triangle_count = nt, .triangles = tri};
    sam_mesh m;
    sam_mesh_report rep;
    sam_error err;
    assert_int_equal(sam_mesh_create(&in, &m, &rep, &err), SAM_OK);
    assert_int_equal(m.topo_count, 4 * 256 + 2); /* V = 4 * 4^4 + 2 */
    assert_int_equal(rep.unreferenced_vertices, 0);
    float *h = malloc(m.topo_count * sizeof *h), *area = malloc(m.topo_count * sizeof *area);
    sam_mesh_mean_curvature(&m, h);
    sam_mesh_fan_areas(&m, NULL, 1.0f, area);
    double total = 0, mean_h = 0;
    for (uint32_t t = 0; t < m.topo_count; ++t) {
        total += area[t];
        mean_h += h[t];
        assert_float_equal(h[t], 0.5f, 0.05f);
        /* Outward normals. */
        const float *p = m.positions + 3 * m.topo_rep[t];
        const float *n = m.topo_normals + 3 * t;
        assert_true(p[0] * n[0] + p[1] * n[1] + p[2] * n[2] > 1.9f);
    }
    mean_h /= m.topo_count;
    assert_float_equal(mean_h, 0.5, 0.01);
    assert_float_equal(total, 16.0 * 3.14159265358979, 0.02 * 16.0 * 3.14159265358979);
    free(h);
    free(area);
    free(pos);
    free(tri);
    sam_mesh_destroy(&m);
}

static void test_repairs_are_reported(void **state)
{
    (void)state;
    /* Two tetrahedra touching at one vertex (a bow tie: non-manifold vertex),
     * plus a degenerate triangle, a zero-area sliver, a duplicate triangle,
     * an unused vertex and a face with a repeated corner (which OpenMesh's
     * reader drops, and the report still counts as the file's). */
    static const char *obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"          /* tet A: 1..4, apex 1 shared */
        "v -1 0 0\nv 0 -1 0\nv 0 0 -1\n"                /* tet B: 1,5,6,7 */
        "v 5 5 5\n"                                     /* 8: unused */
        "v 2 0 0\nv 3 0 0\n"                            /* 9, 10: for the sliver */
        "v 1 0 0\n"                                     /* 11: same position as 2 */
        "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
        "f 1 5 6\nf 1 6 7\nf 1 7 5\nf 5 7 6\n"
        "f 1 2 11\n"                                    /* degenerate after welding */
        "f 2 9 10\n"                                    /* collinear: zero area */
        "f 2 4 1\n"                                     /* duplicate of f 1 2 4 */
        "f 1 2 1\n";                                    /* fewer than 3 distinct corners */
    char path[512];
    write_tmp(path, sizeof path, "repairs.obj", obj);
    sam_mesh m;
    sam_mesh_report rep;
    sam_error err;
    assert_int_equal(sam_mesh_load(path, &m, &rep, &err), SAM_OK);
    assert_int_equal(m.triangle_count, 8);
    assert_int_equal(rep.degenerate_triangles, 1);
    assert_int_equal(rep.zero_area_triangles, 1);
    assert_int_equal(rep.duplicate_triangles, 1);
    assert_int_equal(rep.non_manifold_vertices, 1);
    assert_int_equal(rep.faces_too_small, 1);
    assert_int_equal(rep.file_faces, 12);
    /* 8 (unused), 9, 10 (only in the sliver) are dropped; 11 welds with 2 but
     * is used only by the degenerate triangle. */
    assert_int_equal(rep.unreferenced_vertices, 4);
    /* 7 positions, the shared apex split into 2 -> 8 topo vertices. */
    assert_int_equal(m.topo_count, 8);
    assert_int_equal(m.vertex_count, 8);
    for (uint32_t t = 0; t < m.topo_count; ++t)
        assert_true(ring_is_closed(&m, t));
    assert_rings_match_triangles(&m);
    char summary[256];
    sam_mesh_report_summary(&rep, summary, sizeof summary);
    assert_non_null(strstr(summary, "1 degenerate triangles dropped"));
    assert_non_null(strstr(summary, "1 non-manifold vertices split"));
    sam_mesh_destroy(&m);
}

/* The unit cube [0, 1]^3 as 12 triangles wound outward. */
static const float unit_cube[8 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t unit_cube_tri[36] = {0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                           1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};

/* Triangles written backwards are turned to agree with their neighbours:
 * a closed cube with some of its 12 triangles reversed becomes one closed
 * surface again (no boundary, no non-manifold edge, one fan per corner)
 * with the winding most of its triangles had, so the few are turned and a
 * cube mostly reversed stays reversed for sam_mesh_orient_outward. */
static void test_backward_triangles_are_turned(void **state)
{
    (void)state;
    static const struct {
        uint32_t reversed; /* the first this many triangles are written backwards */
        uint32_t turned;
        int outward;
    } cases[] = {{0, 0, 1}, {1, 1, 1}, {5, 5, 1}, {9, 3, 0}, {12, 0, 0}};
    for (size_t k = 0; k < sizeof cases / sizeof *cases; ++k) {
        uint32_t tri[36];
        memcpy(tri, unit_cube_tri, sizeof tri);
        for (uint32_t t = 0; t < cases[k].reversed; ++t) {
            const uint32_t x = tri[3 * t + 1];
            tri[3 * t + 1] = tri[3 * t + 2];
            tri[3 * t + 2] = x;
        }
        sam_mesh_input in = {.name = "cube", .vertex_count = 8, .positions = unit_cube,
                             .triangle_count = 12, .triangles = tri};
        sam_mesh m;
        sam_mesh_report rep;
        assert_int_equal(sam_mesh_create(&in, &m, &rep, NULL), SAM_OK);
        assert_int_equal(rep.triangles_turned, cases[k].turned);
        assert_int_equal(rep.non_manifold_edges, 0);
        assert_int_equal(rep.non_manifold_vertices, 0);
        assert_int_equal(rep.boundary_vertices, 0);
        assert_int_equal(m.topo_count, 8);
        assert_rings_match_triangles(&m);
        assert_true((sam_mesh_signed_volume(&m) > 0) == cases[k].outward);
        assert_true(fabs(fabs(sam_mesh_signed_volume(&m)) - 1.0) < 1e-6);
        sam_mesh_destroy(&m);
    }
    /* An open strip of two triangles, the second backwards: turned, and
     * the strip's middle edge is shared, not two boundaries. */
    static const float quad[4 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    uint32_t strip[6] = {0, 1, 2, 0, 3, 2};
    sam_mesh_input in = {.name = "strip", .vertex_count = 4, .positions = quad, .triangle_count = 2,
                         .triangles = strip};
    sam_mesh m;
    sam_mesh_report rep;
    assert_int_equal(sam_mesh_create(&in, &m, &rep, NULL), SAM_OK);
    assert_int_equal(rep.triangles_turned, 1);
    assert_int_equal(rep.non_manifold_vertices, 0);
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        assert_float_equal(fabsf(m.normals[3 * v + 2]), 1.0f, 1e-6);
    assert_float_equal(m.normals[2], m.normals[3 * (m.vertex_count - 1) + 2], 1e-6);
    sam_mesh_destroy(&m);
}

/* A soup (every triangle its own three vertices) whose corners were
 * rounded apart by 1e-6 of the size closes into one surface; a real gap of
 * 1e-3 of the size stays open, and a closed mesh's vertices are never
 * merged, however close. */
static void test_cracks_a_hair_wide_are_closed(void **state)
{
    (void)state;
    for (int gap = 0; gap < 2; ++gap) {
        float pos[36 * 3];
        uint32_t soup[36];
        for (uint32_t c = 0; c < 36; ++c) {
            soup[c] = c;
            for (int k = 0; k < 3; ++k) {
                /* A different rounding per corner, up to 1e-6; the gap moves vertex 6's copies 1e-3 along x. */
                const float jitter = 1e-6f * (float)((c * 7 + (uint32_t)k * 3) % 5) / 4.0f;
                const float moved = gap && unit_cube_tri[c] == 6 && k == 0 && c % 2 ? 1e-3f : 0.0f;
                pos[3 * c + k] = unit_cube[3 * unit_cube_tri[c] + k] + jitter + moved;
            }
        }
        sam_mesh_input in = {.name = "soup", .vertex_count = 36, .positions = pos, .triangle_count = 12,
                             .triangles = soup};
        sam_mesh m;
        sam_mesh_report rep;
        assert_int_equal(sam_mesh_create(&in, &m, &rep, NULL), SAM_OK);
        if (!gap) {
            assert_int_equal(m.topo_count, 8);
            assert_true(rep.crack_vertices_welded > 0);
            assert_int_equal(rep.boundary_vertices, 0);
            assert_rings_match_triangles(&m);
        } else {
            assert_int_equal(m.topo_count, 9); /* vertex 6 in two places, a real hole between them */
            assert_true(rep.boundary_vertices > 0);
        }
        sam_mesh_destroy(&m);
    }
    /* Closed: two vertices 1e-7 apart inside a closed surface stay two. */
    float fold[8 * 3];
    memcpy(fold, unit_cube, sizeof fold);
    sam_mesh_input in = {.name = "cube", .vertex_count = 8, .positions = fold, .triangle_count = 12,
                         .triangles = unit_cube_tri};
    fold[3 * 6] = fold[3 * 5] + 1e-7f, fold[3 * 6 + 1] = fold[3 * 5 + 1], fold[3 * 6 + 2] = fold[3 * 5 + 2];
    sam_mesh m;
    sam_mesh_report rep;
    assert_int_equal(sam_mesh_create(&in, &m, &rep, NULL), SAM_OK);
    assert_int_equal(rep.crack_vertices_welded, 0);
    sam_mesh_destroy(&m);
}

static void test_non_manifold_edge(void **state)
{
    (void)state;
    /* Three triangles sharing the edge 0-1 (a "book" with three pages). */
    float pos[5 * 3] = {0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, 0.5f, 0, 1};
    uint32_t tri[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    sam_mesh_input in = {.name = "book", .vertex_count = 5, .positions = pos,
                         .triangle_count = 3, .triangles = tri};
    sam_mesh m;
    sam_mesh_report rep;
    assert_int_equal(sam_mesh_create(&in, &m, &rep, NULL), SAM_OK);
    assert_int_equal(rep.non_manifold_edges, 1);
    assert_rings_match_triangles(&m);
    /* Every topo vertex's fans still cover each triangle exactly once. */
    uint32_t pairs = 0;
    for (uint32_t t = 0; t < m.topo_count; ++t)
        pairs += ring_size(&m, t) - 1;
    assert_int_equal(pairs, 3 * m.triangle_count);
    sam_mesh_destroy(&m);
}

static void test_file_normals_are_used_and_normalised(void **state)
{
    (void)state;
    static const char *obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                             "vn 0 0 2\nvn 0 0 3\nvn 0 0 0\n"
                             "f 1//1 2//2 3//3\n";
    char path[512];
    write_tmp(path, sizeof path, "normals.obj", obj);
    sam_mesh m;
    sam_mesh_report rep;
    sam_error err;
    sam_status st = sam_mesh_load(path, &m, &rep, &err);
    if (st != SAM_OK)
        fail_msg("%s", err.message);
    assert_true(rep.normals_from_file);
    assert_int_equal(rep.invalid_file_normals, 1);
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        assert_float_equal(m.normals[3 * v + 2], 1.0f, 1e-6);
    sam_mesh_destroy(&m);
}

/* A cube whose faces name their own normal at every corner (v//n, v/t/n):
 * each corner keeps the normal its face names, so a hard edge stays hard.
 * OpenMesh's importer gives a vertex one normal (the last a corner
 * named); the render vertices must split by normal as they do by UV. The
 * face with a repeated corner, which the reader drops, must not shift
 * the normals of the faces after it. */
static void test_obj_corner_normals_keep_hard_edges(void **state)
{
    (void)state;
    static const char *const corner[] = {"%d//%d", "%d/1/%d"};
    for (int form = 0; form < 2; ++form) {
        static const int face[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 4, 8, 7}, {4, 1, 5, 8}};
        static const float normal[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
        char text[2048], *p = text;
        p += sprintf(p, "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nvt 0.5 0.5\n");
        for (int f = 0; f < 6; ++f)
            p += sprintf(p, "vn %g %g %g\n", normal[f][0], normal[f][1], normal[f][2]);
        for (int f = 0; f < 6; ++f) {
            if (f == 3) /* a face the reader drops: two distinct corners */
                p += sprintf(p, "f 1//1 2//2 1//3\n");
            p += sprintf(p, "f");
            for (int c = 0; c < 4; ++c) {
                p += sprintf(p, " ");
                p += sprintf(p, corner[form], face[f][c], f + 1);
            }
            p += sprintf(p, "\n");
        }
        char path[512];
        write_tmp(path, sizeof path, form ? "corner_normals_vtn.obj" : "corner_normals_vn.obj", text);
        sam_mesh m;
        sam_mesh_report rep;
        sam_error err;
        if (sam_mesh_load(path, &m, &rep, &err) != SAM_OK)
            fail_msg("%s", err.message);
        assert_true(rep.normals_from_file);
        assert_int_equal(m.topo_count, 8);
        assert_int_equal(m.vertex_count, 24);
        /* Every triangle lies in one face of the cube: its corners carry
         * that face's normal. */
        for (uint32_t t = 0; t < m.triangle_count; ++t) {
            const uint32_t *tri = m.triangles + 3 * t;
            int axis = -1;
            for (int a = 0; a < 3; ++a)
                if (m.positions[3 * tri[0] + a] == m.positions[3 * tri[1] + a] &&
                    m.positions[3 * tri[1] + a] == m.positions[3 * tri[2] + a])
                    axis = a;
            assert_true(axis >= 0);
            for (int c = 0; c < 3; ++c)
                for (int a = 0; a < 3; ++a)
                    assert_float_equal(m.normals[3 * tri[c] + a], a == axis ? m.positions[3 * tri[c] + a] : 0.0f,
                                       1e-6);
        }
        sam_mesh_destroy(&m);
    }
}

static void expect_error(const char *name, const char *text, sam_status expected, const char *needle)
{
    char path[512];
    if (text)
        write_tmp(path, sizeof path, name, text);
    else
        sam_test_tmp_path(path, sizeof path, name);
    sam_mesh m;
    sam_error err;
    sam_status st = sam_mesh_load(path, &m, NULL, &err);
    if (st != expected)
        fail_msg("%s: expected status %s, got %s (%s)", name, sam_status_name(expected),
                 sam_status_name(st), st ? err.message : "");
    if (!strstr(err.message, needle))
        fail_msg("%s: message \"%s\" lacks \"%s\"", name, err.message, needle);
    if (!strstr(err.message, name))
        fail_msg("%s: message \"%s\" does not name the file", name, err.message);
    assert_null(m.positions);
    assert_int_equal(m.vertex_count, 0);
}

static void test_bad_inputs_give_one_clear_error(void **state)
{
    (void)state;
    expect_error("does_not_exist.obj", NULL, SAM_ERR_IO, "cannot open");
    expect_error("empty.obj", "", SAM_ERR_EMPTY, "empty");
    expect_error("garbage.ply", "\x7f\x01 this is not a ply file \xff\xfe", SAM_ERR_FORMAT, "");
    expect_error("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", SAM_ERR_FORMAT,
                 "line 2: \"nan\" is not a finite number");
    expect_error("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", SAM_ERR_FORMAT,
                 "line 4: face corner 3 is not a valid index");
    expect_error("normal_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n", SAM_ERR_FORMAT,
                 "face corner 2");
    expect_error("garbage_corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2/* 3\n", SAM_ERR_FORMAT,
                 "face corner 2");
    {
        const char *hdr = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 1\n"
                          "property list uchar int vertex_indices\nend_header\n";
        unsigned char buf[512];
        size_t n = strlen(hdr);
        memcpy(buf, hdr, n);
        float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        v[4] = NAN;
        memcpy(buf + n, v, sizeof v);
        n += sizeof v;
        buf[n++] = 3;
        int32_t idx[3] = {0, 1, 2};
        memcpy(buf + n, idx, sizeof idx);
        n += sizeof idx;
        char path[512];
        sam_test_write_file(sam_test_tmp_path(path, sizeof path, "nan.ply"), buf, n);
        expect_error("nan.ply", NULL, SAM_ERR_FORMAT, "vertex 1 has a non-finite coordinate");
    }
    expect_error("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", SAM_ERR_FORMAT, "indices below 3");
    expect_error("no_faces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", SAM_ERR_EMPTY, "no faces");
    expect_error("prose.obj", "hello world\nthis is no mesh\n", SAM_ERR_EMPTY, "no vertices and no faces in it");
    expect_error("all_degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", SAM_ERR_EMPTY,
                 "no usable triangle");
    expect_error("mesh.xyz", "1 2 3\n", SAM_ERR_UNSUPPORTED, "unsupported");
    /* Header counts beyond the file's size are refused before OpenMesh
     * would allocate for them. */
    expect_error("huge.ply",
                 "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n0 0 0\n",
                 SAM_ERR_FORMAT, "declares 4000000000 elements");
    expect_error("no_end_header.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", SAM_ERR_FORMAT,
                 "no end_header");
    expect_error("bad_keyword.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\npropevty float x\nend_header\n0\n0\n0\n",
                 SAM_ERR_FORMAT, "line 4 is not valid");
    expect_error("property_first.ply",
                 "ply\nformat ascii 1.0\nproperty float x\nelement vertex 3\nend_header\n0\n0\n0\n",
                 SAM_ERR_FORMAT, "line 3 is not valid");
    /* Found by fuzz_mesh: a float count was walked as an integer of its
     * size and written again as a float's value. */
    expect_error("float_count.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty list float int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                 "3 0 1 2\n",
                 SAM_ERR_FORMAT, "line 8: a list's count must have an integer type");
    /* A PLY written again for OpenMesh still checks every corner index. */
    expect_error("fractional_index.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty list uchar float vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                 "3 0 1 1.5\n",
                 SAM_ERR_FORMAT, "face 0: corner 2 is 1.5, which is no vertex index");
    expect_error("negative.off", "OFF\n2 -4 0\n0 0 0\n1 0 0\n", SAM_ERR_FORMAT, "expected vertex and face counts");
    expect_error("binary.off", "OFF BINARY\n", SAM_ERR_UNSUPPORTED, "binary OFF");
    expect_error("inline_counts.off", "OFF 0 00  ", SAM_ERR_EMPTY, "0 vertices and 0 faces");
    expect_error("four_counts.off", "OFF\n3 1 0 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", SAM_ERR_FORMAT,
                 "expected vertex and face counts");
    expect_error("glued.off", "OFFX 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", SAM_ERR_FORMAT, "not an OFF file");
    expect_error("face_colour_word.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 red\n", SAM_ERR_FORMAT,
                 "line 6: face 0");
    expect_error("comment_in_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 # 2\n", SAM_ERR_FORMAT,
                 "line 6: face 0");
    /* 2^64 - 1 corners: k + 1 wrapped to 0 and passed, and OpenMesh then
     * took 4 billion corners. */
    expect_error("corner_overflow.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n18446744073709551615 0 1\n",
                 SAM_ERR_FORMAT, "line 6: face 0");
    expect_error("zero.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", SAM_ERR_EMPTY, "3 vertices and 0 faces");
    expect_error("lone_cr.ply",
                 "ply\nformat ascii 1.0\nelement vev\r\rx 3\nproperty float x\nend_header\n0\n0\n0\n",
                 SAM_ERR_FORMAT, "line 3 contains the control character 0x0d");
    /* OpenMesh's header parser takes a keyword inside obj_info for an
     * entry; "x" then stood where a count was read, and it looped forever. */
    expect_error("obj_info_keyword.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty list uchar int vertex_indices\nobj_info element\nend_header\nx\n",
                 SAM_ERR_UNSUPPORTED, "line 9: obj_info holds the keyword \"element\"");
    expect_error("obj_info_end.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nobj_info made by end_header\nproperty float x\n"
                 "end_header\n0\n0\n0\n",
                 SAM_ERR_UNSUPPORTED, "line 4: obj_info holds the keyword \"end_header\"");
    expect_error("bad_format.ply", "ply\nformat ascii 1.facement vertex 4\nend_header\n", SAM_ERR_FORMAT,
                 "expected \"format");
    expect_error("huge.off", "OFF\n3 999999999 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", SAM_ERR_FORMAT,
                 "999999999 faces");
    {
        unsigned char stl[84 + 50];
        memset(stl, 0, sizeof stl);
        stl[83] = 0x10; /* 268 million triangles in a 134-byte file */
        char path[512];
        sam_test_write_file(sam_test_tmp_path(path, sizeof path, "huge.stl"), stl, sizeof stl);
        expect_error("huge.stl", NULL, SAM_ERR_FORMAT, "declares 268435456 triangles");
    }
}

/* Inputs that once loaded wrongly or said the wrong thing: each gives
 * one line naming what is wrong, and a number too large for a float never
 * shifts the indices after it. */
static void test_hostile_inputs(void **state)
{
    (void)state;
    expect_error("float_range.obj", "v 0 0 0\nv 1e39 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 5 5 5\nf 1 3 4\nf 1 4 5\n",
                 SAM_ERR_FORMAT, "OBJ line 2: \"1e39\" is not a finite number that fits a 32-bit float");
    expect_error("float_range.off", "OFF\n4 2 0\n0 0 0\n1e39 0 0\n0 1 0\n0 0 1\n3 0 2 3\n3 0 1 2\n", SAM_ERR_FORMAT,
                 "OFF line 4: vertex 1: \"1e39\" is not a finite number that fits a 32-bit float");
    expect_error("float_range.ply",
                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1e39 0 0\n0 1 0\n"
                 "0 0 1\n3 0 2 3\n3 0 1 2\n",
                 SAM_ERR_FORMAT, "PLY vertex 1: \"1e39\" is not a finite number that fits a 32-bit float");
    expect_error("float_range_ascii.stl",
                 "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e39 0 0\nvertex 0 1 0\n"
                 "endloop\nendfacet\nendsolid x\n",
                 SAM_ERR_FORMAT, "STL line 5: \"1e39\" is not a finite number");
    /* Found by the differential fuzzer: PLY layouts OpenMesh reads other
     * than as written. */
    expect_error("face_list_name.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty list uchar int corners\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                 SAM_ERR_UNSUPPORTED, "its first property must be the list vertex_indices (or vertex_index), found "
                                      "the list corners");
    expect_error("face_flags_first.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty uchar flags\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0\n1 0 0\n0 1 0\n7 3 0 1 2\n",
                 SAM_ERR_UNSUPPORTED, "found the scalar flags");
    expect_error("face_before_vertex.ply",
                 "ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nelement vertex 3\n"
                 "property float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
                 SAM_ERR_UNSUPPORTED, "PLY element vertex (element 2) comes after element face (element 1)");
    expect_error("two_vertex_elements.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty list uchar int vertex_indices\nelement vertex 1\nproperty float x\n"
                 "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0 0 1\n",
                 SAM_ERR_FORMAT, "PLY header line 9 declares a second element \"vertex\"");
    expect_error("hex.obj", "v 0 0 0\nv 1 0xce 8\nv 0 1 0\nf 1 2 3\n", SAM_ERR_FORMAT,
                 "OBJ line 2: \"0xce\" is not a valid number");
    expect_error("repeated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 1\nf 2 2 3\n", SAM_ERR_EMPTY,
                 "all 2 faces repeat a vertex and have fewer than 3 distinct corners (the first on line 4)");
    expect_error("count_max.ply",
                 "ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty float x\nend_header\n",
                 SAM_ERR_FORMAT, "declares 18446744073709551615 elements");
    expect_error("count_overflow.ply",
                 "ply\nformat ascii 1.0\nelement vertex 18446744073709551616\nproperty float x\nend_header\n",
                 SAM_ERR_FORMAT, "is too large (above 2^64 - 1)");
    {
        /* A binary STL with a NaN corner. */
        unsigned char stl[84 + 50];
        memset(stl, 0, sizeof stl);
        stl[80] = 1;
        const float nan_corner[3] = {NAN, 0, 0};
        memcpy(stl + 84 + 12 + 12, nan_corner, sizeof nan_corner);
        char path[512];
        sam_test_write_file(sam_test_tmp_path(path, sizeof path, "nan.stl"), stl, sizeof stl);
        expect_error("nan.stl", NULL, SAM_ERR_FORMAT, "binary STL triangle 0, vertex 1 has a non-finite coordinate");
    }
    /* What is not a regular file is refused, not read without end. */
    char path[512], dir[512];
    sam_test_tmp_path(path, sizeof path, "zero.obj");
    remove(path);
    assert_int_equal(symlink("/dev/zero", path), 0);
    expect_error("zero.obj", NULL, SAM_ERR_IO, "not a regular file (a character device)");
    remove(path);
    sam_test_tmp_path(dir, sizeof dir, "folder.obj");
    rmdir(dir);
    assert_int_equal(mkdir(dir, 0700), 0);
    expect_error("folder.obj", NULL, SAM_ERR_IO, "not a regular file (a directory)");
    rmdir(dir);
}

static void test_create_rejects_bad_arrays(void **state)
{
    (void)state;
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t tri[3] = {0, 1, 3};
    sam_mesh_input in = {.name = "arrays", .vertex_count = 3, .positions = pos,
                         .triangle_count = 1, .triangles = tri};
    sam_mesh m;
    sam_error err;
    assert_int_equal(sam_mesh_create(&in, &m, NULL, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "arrays"));
    in.triangle_count = 0;
    assert_int_equal(sam_mesh_create(&in, &m, NULL, &err), SAM_ERR_EMPTY);
    in.positions = NULL;
    assert_int_equal(sam_mesh_create(&in, &m, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
}

/* Loads `name` holding the first `len` bytes of `data`: either a valid
 * mesh or one clear error, never a crash or a hang. Returns 1 when it loaded. */
static int load_prefix(const char *name, const void *data, size_t len)
{
    char path[512];
    sam_test_write_file(sam_test_tmp_path(path, sizeof path, name), data, len);
    sam_mesh m;
    sam_error err;
    if (sam_mesh_load(path, &m, NULL, &err) != SAM_OK) {
        assert_non_null(strstr(err.message, name));
        return 0;
    }
    assert_true(m.triangle_count > 0);
    assert_rings_match_triangles(&m);
    sam_mesh_destroy(&m);
    return 1;
}

/* Every truncated prefix of a small OBJ, ASCII OFF and binary PLY. */
static void test_truncated_prefixes(void **state)
{
    (void)state;
    static const char *off = "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                             "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n";
    unsigned char ply[1024];
    size_t ply_size = cube_binary_ply(ply);
    for (size_t len = 0; len < strlen(cube_obj); len += 3)
        load_prefix("prefix.obj", cube_obj, len);
    /* A binary PLY or an OFF missing any byte of its data is refused. */
    for (size_t len = 0; len < ply_size; ++len)
        assert_false(load_prefix("prefix.ply", ply, len));
    assert_true(load_prefix("prefix.ply", ply, ply_size));
    for (size_t len = 0; len + 1 < strlen(off); ++len)
        assert_false(load_prefix("prefix.off", off, len));
    assert_true(load_prefix("prefix.off", off, strlen(off)));
}

static void test_body_counts_are_checked(void **state)
{
    (void)state;
    /* A face whose list count runs past the end of a binary PLY. */
    unsigned char ply[1024];
    size_t n = cube_binary_ply(ply);
    ply[n - 13] = 200;
    char path[512];
    sam_test_write_file(sam_test_tmp_path(path, sizeof path, "list_count.ply"), ply, n);
    expect_error("list_count.ply", NULL, SAM_ERR_FORMAT, "truncated in face 11 of 12");
    expect_error("ascii_list.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n",
                 SAM_ERR_FORMAT, "truncated in face 0 of 1");
    expect_error("not_number.ply",
                 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nabc\n",
                 SAM_ERR_FORMAT, "\"abc\" is not a number");
    expect_error("face_count.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n300000000 0 1 2\n", SAM_ERR_FORMAT,
                 "face 0 must be a corner count");
    expect_error("extra_face_values.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7 7\n", SAM_ERR_FORMAT,
                 "face 0 must be a corner count");
    expect_error("short_vertex.off", "OFF\n3 1 0\n0 0\n1 0 0\n0 1 0\n3 0 1 2\n", SAM_ERR_FORMAT,
                 "vertex 0 must be 3 finite numbers");
    expect_error("control.off", "OFF\n3 1 0\n0 0 0\n1 0 0\x02\n0 1 0\n3 0 1 2\n", SAM_ERR_FORMAT,
                 "line 4 contains the control character 0x02");
}

/* A sphere wound inside out (every triangle reversed, so its computed
 * normals point in): negative volume, turned outside out with normals
 * pointing away from the centre and fans with the same areas, and then a
 * winding number of 1 inside and 0 outside; the same sphere facing out,
 * and an open sheet, are left alone. */
static void test_inside_out_mesh_is_turned(void **state)
{
    (void)state;
    sam_mesh good;
    sam_test_shape_mesh("sphere", 16, 1.0, 0, 0, &good);
    uint32_t *tri = malloc((size_t)good.triangle_count * 3 * sizeof *tri);
    assert_non_null(tri);
    for (uint32_t t = 0; t < good.triangle_count; ++t) {
        tri[3 * t] = good.triangles[3 * t];
        tri[3 * t + 1] = good.triangles[3 * t + 2];
        tri[3 * t + 2] = good.triangles[3 * t + 1];
    }
    sam_mesh_input in = {.name = "inside out", .vertex_count = good.vertex_count, .positions = good.positions,
                         .uvs = good.uvs, .triangle_count = good.triangle_count, .triangles = tri};
    sam_mesh bad;
    sam_error err;
    if (sam_mesh_create(&in, &bad, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    const double volume = sam_mesh_signed_volume(&good);
    print_message("sphere: volume %.6f, inside out %.6f\n", volume, sam_mesh_signed_volume(&bad));
    assert_true(volume > 0.45 && volume < 4.0 / 3.0 * 3.1416 * 0.125);
    assert_true(fabs(sam_mesh_signed_volume(&bad) + volume) < 1e-9);
    assert_true(sam_mesh_is_closed(&bad));
    assert_int_equal(sam_mesh_orient_outward(&good), 0);
    assert_int_equal(sam_mesh_orient_outward(&bad), 1);
    assert_true(fabs(sam_mesh_signed_volume(&bad) - volume) < 1e-9);
    for (uint32_t v = 0; v < bad.vertex_count; ++v) {
        const float *p = bad.positions + 3 * v, *n = bad.normals + 3 * v;
        assert_true(p[0] * n[0] + p[1] * n[1] + p[2] * n[2] > 0);
    }
    for (uint32_t t = 0; t < bad.topo_count; ++t) {
        const float *p = bad.positions + 3 * bad.topo_rep[t], *n = bad.topo_normals + 3 * t;
        assert_true(p[0] * n[0] + p[1] * n[1] + p[2] * n[2] > 0);
    }
    float *fa = malloc(good.topo_count * sizeof *fa), *fb = malloc(bad.topo_count * sizeof *fb);
    assert_non_null(fa);
    assert_non_null(fb);
    assert_int_equal(good.topo_count, bad.topo_count);
    sam_mesh_fan_areas(&good, NULL, 1.0f, fa);
    sam_mesh_fan_areas(&bad, NULL, 1.0f, fb);
    for (uint32_t t = 0; t < good.topo_count; ++t)
        assert_true(fabsf(fa[t] - fb[t]) <= 1e-6f * fa[t]);
    free(fa);
    free(fb);
    free(tri);
    const float centre[3] = {0, 0, 0}, near_skin[3] = {0.45f, 0, 0}, outside[3] = {0.6f, 0, 0},
                far_away[3] = {3, 2, 1};
    print_message("winding numbers: centre %.6f, just inside %.6f, just outside %.6f, far %.6f\n",
                  sam_mesh_winding_number(bad.positions, bad.triangles, bad.triangle_count, centre),
                  sam_mesh_winding_number(bad.positions, bad.triangles, bad.triangle_count, near_skin),
                  sam_mesh_winding_number(bad.positions, bad.triangles, bad.triangle_count, outside),
                  sam_mesh_winding_number(bad.positions, bad.triangles, bad.triangle_count, far_away));
    assert_true(fabs(sam_mesh_winding_number(bad.positions, bad.triangles, bad.triangle_count, centre) - 1) < 1e-6);
    assert_true(fabs(sam_mesh_winding_number(bad.positions, bad.triangles, bad.triangle_count, near_skin) - 1) < 1e-6);
    assert_true(fabs(sam_mesh_winding_number(bad.positions, bad.triangles, bad.triangle_count, outside)) < 1e-6);
    assert_true(fabs(sam_mesh_winding_number(bad.positions, bad.triangles, bad.triangle_count, far_away)) < 1e-6);
    sam_mesh_destroy(&bad);
    sam_mesh_destroy(&good);
    /* An open sheet has no inside to face. */
    const float pos[4 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t sheet_tri[6] = {0, 2, 1, 0, 3, 2};
    sam_mesh_input sheet_in = {.name = "sheet", .vertex_count = 4, .positions = pos, .triangle_count = 2,
                               .triangles = sheet_tri};
    sam_mesh sheet;
    if (sam_mesh_create(&sheet_in, &sheet, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_false(sam_mesh_is_closed(&sheet));
    assert_int_equal(sam_mesh_orient_outward(&sheet), 0);
    sam_mesh_destroy(&sheet);
}

/* The input's vertices against the render vertices: a clean input keeps
 * its order, a vertex no triangle uses is dropped, and two identical
 * vertices become one that came from the first. */
static void test_render_of_source(void **state)
{
    (void)state;
    /* A quad of 4 corners, an unused vertex 4, and vertex 5 a copy of 2. */
    static const float pos[6 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 5, 5, 5, 1, 1, 0};
    static const uint32_t tri[6] = {0, 1, 2, 0, 5, 3};
    sam_mesh_input in = {.name = "quad", .vertex_count = 6, .positions = pos, .triangle_count = 2,
                         .triangles = tri};
    sam_mesh m;
    sam_error err;
    assert_int_equal(sam_mesh_create(&in, &m, NULL, &err), SAM_OK);
    assert_int_equal(m.source_count, 6);
    assert_int_equal(m.vertex_count, 4);
    for (uint32_t s = 0; s < 4; ++s)
        assert_int_equal(m.render_of_source[s], s);
    assert_int_equal(m.render_of_source[4], SAM_MESH_DROPPED);
    assert_int_equal(m.render_of_source[5], 2);
    for (uint32_t r = 0; r < 4; ++r)
        assert_int_equal(m.source_of_render[r], r);
    sam_mesh_destroy(&m);
    /* A file's vertices: the OBJ's own order, its unused vertex dropped. */
    char path[512];
    write_tmp(path, sizeof path, "source_order.obj", "v 0 0 0\nv 9 9 9\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 3 4\nf 1 4 5\n");
    if (sam_mesh_load(path, &m, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    static const uint32_t want[5] = {0, SAM_MESH_DROPPED, 1, 2, 3};
    assert_int_equal(m.source_count, 5);
    assert_memory_equal(m.render_of_source, want, sizeof want);
    static const uint32_t from[4] = {0, 2, 3, 4};
    assert_memory_equal(m.source_of_render, from, sizeof from);
    sam_mesh_destroy(&m);
}

static void test_far_from_the_origin_is_warned(void **state)
{
    (void)state;
    char msg[256];
    sam_mesh m;
    /* Floats at 1e5 are 1/128 apart, under 1% of the mean edge (1.14):
     * nothing to say. At 4e6 they are 0.25 apart, 22% of it. */
    assert_int_equal(sheet_at(1e5f, &m, NULL, NULL), SAM_OK);
    assert_int_equal(sam_mesh_precision_warning(&m, "sheet.obj", msg, sizeof msg), 0);
    assert_string_equal(msg, "");
    sam_mesh_destroy(&m);
    assert_int_equal(sheet_at(4e6f, &m, NULL, NULL), SAM_OK);
    assert_int_equal(sam_mesh_precision_warning(&m, "sheet.obj", msg, sizeof msg), 1);
    assert_non_null(strstr(msg, "sheet.obj lies 4e+06 units from its origin"));
    assert_non_null(strstr(msg, "to 0.25 units there (22% of an edge)"));
    assert_non_null(strstr(msg, "move it near the origin"));
    assert_int_equal(sam_mesh_precision_warning(&m, NULL, msg, sizeof msg), 1);
    assert_non_null(strstr(msg, "the mesh lies"));
    /* A short buffer is cut, never overrun; NULLs give 0. */
    char tiny[8];
    assert_int_equal(sam_mesh_precision_warning(&m, NULL, tiny, sizeof tiny), 1);
    assert_int_equal(strlen(tiny), 7);
    assert_int_equal(sam_mesh_precision_warning(NULL, NULL, msg, sizeof msg), 0);
    assert_int_equal(sam_mesh_precision_warning(&m, NULL, NULL, 0), 0);
    assert_int_equal(sam_mesh_precision_warning(&m, NULL, NULL, sizeof msg), 0);
    sam_mesh_destroy(&m);
}

/* A map_Kd names its file after its options, and the name is the rest of
 * the line: blanks in it are the file's, numbers after -s/-o/-t are
 * options' up to three. */
static void test_obj_texture_name_after_options(void **state)
{
    (void)state;
    static const struct {
        const char *map; /* the map_Kd statement's argument */
        const char *file;
        uint32_t width;
    } cases[] = {
        {"albedo.png", "albedo.png", 3},
        {"my albedo.png", "my albedo.png", 2},
        {"-s 1 1 1 albedo.png", "albedo.png", 3},
        {"-o 0.5 -s 2 2 -bm 0.2 my albedo.png", "my albedo.png", 2},
        {"-mm 0 1 -clamp on -blendu off albedo.png", "albedo.png", 3},
        {"-t 0.1 0.2 0.3 -imfchan r  my albedo.png  ", "my albedo.png", 2},
        {"albedo.png # the skin", "albedo.png", 3},
    };
    sam_error err;
    char path[512], png[512];
    for (uint32_t w = 2; w <= 3; ++w) {
        sam_image image;
        assert_int_equal(sam_image_create(&image, w, 1, 3, &err), SAM_OK);
        for (uint32_t k = 0; k < 3 * w; ++k)
            image.pixels[k] = 0.5f;
        sam_test_tmp_path(png, sizeof png, w == 2 ? "my albedo.png" : "albedo.png");
        assert_int_equal(sam_image_write_png(png, &image, SAM_PNG_SRGB, &err), SAM_OK);
        sam_image_destroy(&image);
    }
    char obj[2048];
    snprintf(obj, sizeof obj, "mtllib texture_names.mtl\nusemtl skin\n%s", cube_obj);
    write_tmp(path, sizeof path, "texture_names.obj", obj);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char mtl[512], text[512], note[1200];
        snprintf(text, sizeof text, "newmtl other\nmap_Kd none.png\nnewmtl skin\nKd 1 1 1\nmap_Kd %s\n", cases[i].map);
        write_tmp(mtl, sizeof mtl, "texture_names.mtl", text);
        sam_image image;
        assert_int_equal(sam_mesh_load_albedo(path, &image, note, sizeof note, &err), SAM_OK);
        if (!image.pixels)
            fail_msg("map_Kd %s: no texture (%s)", cases[i].map, note);
        assert_int_equal(image.width, cases[i].width);
        char want[600];
        snprintf(want, sizeof want, "/%s (map_Kd of", cases[i].file);
        if (!strstr(note, want))
            fail_msg("map_Kd %s: the note '%s' does not name %s", cases[i].map, note, cases[i].file);
        sam_image_destroy(&image);
    }
}

/* The runtime reads one albedo map at every part's UVs: an OBJ whose
 * materials name other textures than the first says how many. */
static void test_obj_other_materials_textures(void **state)
{
    (void)state;
    sam_error err;
    char path[512], png[512], mtl[512], note[1200];
    sam_image image;
    assert_int_equal(sam_image_create(&image, 2, 2, 3, &err), SAM_OK);
    for (uint32_t k = 0; k < 12; ++k)
        image.pixels[k] = 0.5f;
    assert_int_equal(sam_image_write_png(sam_test_tmp_path(png, sizeof png, "skin.png"), &image, SAM_PNG_SRGB, &err),
                     SAM_OK);
    sam_image_destroy(&image);
    write_tmp(mtl, sizeof mtl, "materials.mtl",
              "newmtl skin\nmap_Kd skin.png\nnewmtl eyes\nmap_Kd eyes.png\nnewmtl teeth\nKd 1 1 1\n"
              "newmtl lips\nmap_Kd skin.png\nnewmtl nails\nmap_Kd nails.png\nnewmtl unused\nmap_Kd unused.png\n");
    static const struct {
        const char *uses; /* usemtl lines */
        const char *tail; /* what the note must end with */
    } cases[] = {
        {"usemtl skin\n", "materials.obj)"},
        {"usemtl skin\nusemtl lips\nusemtl teeth\n", "materials.obj)"},
        {"usemtl skin\nusemtl eyes\nusemtl skin\n",
         "materials.obj; 1 other texture of its materials not read: their parts show this one at their UVs)"},
        {"usemtl skin\nusemtl eyes\nusemtl lips\nusemtl nails\nusemtl eyes\n",
         "materials.obj; 2 other textures of its materials not read: their parts show this one at their UVs)"},
        /* A colour-only material first: the first used one with a map. */
        {"usemtl teeth\nusemtl skin\nusemtl eyes\n",
         "materials.obj; 1 other texture of its materials not read: their parts show this one at their UVs)"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char obj[2048];
        snprintf(obj, sizeof obj, "mtllib materials.mtl\n%s%s", cases[i].uses, cube_obj);
        write_tmp(path, sizeof path, "materials.obj", obj);
        assert_int_equal(sam_mesh_load_albedo(path, &image, note, sizeof note, &err), SAM_OK);
        if (!image.pixels)
            fail_msg("case %zu: no texture (%s)", i, note);
        sam_image_destroy(&image);
        const size_t n = strlen(note), t = strlen(cases[i].tail);
        if (n < t || strcmp(note + n - t, cases[i].tail) || !strstr(note, "/skin.png (map_Kd of"))
            fail_msg("case %zu: the note '%s' does not end with '%s'", i, note, cases[i].tail);
    }
}

/* MeshLab and Metashape name a PLY's texture in a header comment
 * ("comment TextureFile NAME", the name's blanks its own); a PLY without
 * one brings no texture and no note. */
static void test_ply_texture_file(void **state)
{
    (void)state;
    sam_error err;
    char path[512], png[512], note[1200];
    sam_image image;
    assert_int_equal(sam_image_create(&image, 3, 2, 3, &err), SAM_OK);
    for (uint32_t k = 0; k < 3 * 3 * 2; ++k)
        image.pixels[k] = 0.25f;
    sam_test_tmp_path(png, sizeof png, "ply albedo.png");
    assert_int_equal(sam_image_write_png(png, &image, SAM_PNG_SRGB, &err), SAM_OK);
    sam_image_destroy(&image);
    const ply_variant textured = {"textured", "uchar", "int", "float", 0, 1, 0, "comment TextureFile ply albedo.png\n",
                                  NULL};
    unsigned char buf[8192];
    size_t n = ply_cube(&textured, 1, buf, sizeof buf);
    sam_test_write_file(sam_test_tmp_path(path, sizeof path, "textured.ply"), buf, n);
    assert_int_equal(sam_mesh_load_albedo(path, &image, note, sizeof note, &err), SAM_OK);
    if (!image.pixels)
        fail_msg("textured.ply: no texture (%s)", note);
    assert_int_equal(image.width, 3);
    assert_int_equal(image.height, 2);
    if (!strstr(note, "/ply albedo.png (TextureFile of"))
        fail_msg("textured.ply: the note '%s' does not name the texture", note);
    sam_image_destroy(&image);
    const ply_variant plain = {"plain", "uchar", "int", "float", 0, 0, 0, "comment made by hand\n", NULL};
    n = ply_cube(&plain, 0, buf, sizeof buf);
    sam_test_write_file(sam_test_tmp_path(path, sizeof path, "untextured.ply"), buf, n);
    assert_int_equal(sam_mesh_load_albedo(path, &image, note, sizeof note, &err), SAM_OK);
    assert_null(image.pixels);
    assert_string_equal(note, "");
}

/* Vertex colours of PLY and OBJ files, sRGB-decoded to linear, one per
 * file vertex: a PLY's red, green and blue of any type (bytes, big-endian
 * shorts named diffuse_*, floats clamped), an OBJ's on every v line (0..1,
 * or bytes when a value passes 1). None for a file without them, or an
 * OBJ with one v line short of them. */
static void test_vertex_colors(void **state)
{
    (void)state;
    static const char *const faces = "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n";
    static const struct {
        const char *name, *text;
        int expect; /* 0 none, 1 the colours below */
    } cases[] = {
        {"colors.ply",
         "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 4\n"
         "property list uchar int vertex_indices\nend_header\n"
         "0 0 0 255 128 0\n1 0 0 0 255 128\n0 1 0 128 0 255\n0 0 1 255 255 255\n",
         1},
        {"colors_float.ply",
         "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
         "property float red\nproperty float green\nproperty float blue\nproperty float alpha\nelement face 4\n"
         "property list uchar int vertex_indices\nend_header\n"
         "0 0 0 1.5 0.50196 -1 0.5\n1 0 0 0 1 0.50196 0.5\n0 1 0 0.50196 0 1 0.5\n0 0 1 1 1 1 0.5\n",
         1},
        {"colors.obj",
         "v 0 0 0 1 0.50196 0\nv 1 0 0 0 1 0.50196\nv 0 1 0 0.50196 0 1\nv 0 0 1 1 1 1\n"
         "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n",
         1},
        /* A float a hair past 1 is clamped, not taken for a byte. */
        {"colors_past_one.obj",
         "v 0 0 0 1.0002 0.50196 0\nv 1 0 0 0 1 0.50196\nv 0 1 0 0.50196 0 1\nv 0 0 1 1 1 1\n"
         "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n",
         1},
        {"colors_bytes.obj",
         "v 0 0 0 255 128 0\nv 1 0 0 0 255 128\nv 0 1 0 128 0 255\nv 0 0 1 255 255 255\n"
         "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n",
         1},
        {"colors_short.obj",
         "v 0 0 0 1 0.5 0\nv 1 0 0\nv 0 1 0 0.5 0 1\nv 0 0 1 1 1 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n", 0},
        {"plain.ply",
         "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n",
         0},
    };
    const float half = sam_srgb_to_linear(128.0f / 255.0f);
    const float want[12] = {1, half, 0, 0, 1, half, half, 0, 1, 1, 1, 1};
    char path[512], note[256], text[1024];
    sam_error err;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const int ply = strstr(cases[i].name, ".ply") != NULL;
        snprintf(text, sizeof text, "%s%s", cases[i].text, ply ? faces : "");
        write_tmp(path, sizeof path, cases[i].name, text);
        float *rgb = NULL;
        uint32_t count = 7;
        assert_int_equal(sam_mesh_load_vertex_colors(path, &rgb, &count, note, sizeof note, &err), SAM_OK);
        printf("%s: %u colours, note \"%s\"\n", cases[i].name, count, note);
        if (!cases[i].expect) {
            assert_null(rgb);
            assert_int_equal(count, 0);
            assert_string_equal(note, "");
        } else {
            assert_int_equal(count, 4);
            for (int k = 0; k < 12; ++k)
                assert_float_equal(rgb[k], want[k], 2e-5f);
            assert_non_null(strstr(note, cases[i].name));
        }
        free(rgb);
        remove(path);
    }
    /* Big-endian shorts named diffuse_red...: 65535 is 1, 0 is 0. */
    const char *head = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                       "property float z\nproperty ushort diffuse_red\nproperty ushort diffuse_green\n"
                       "property ushort diffuse_blue\nelement face 4\nproperty list uchar int vertex_indices\n"
                       "end_header\n";
    unsigned char buf[1024];
    size_t n = strlen(head);
    memcpy(buf, head, n);
    static const float xyz[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int v = 0; v < 4; ++v) {
        for (int k = 0; k < 3; ++k) {
            uint32_t bits;
            memcpy(&bits, &xyz[3 * v + k], 4);
            for (int b = 3; b >= 0; --b)
                buf[n++] = (unsigned char)(bits >> (8 * b));
        }
        for (int k = 0; k < 3; ++k) {
            const uint16_t c = (v + k) % 2 ? 65535 : 0;
            buf[n++] = (unsigned char)(c >> 8), buf[n++] = (unsigned char)c;
        }
    }
    static const int corners[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    for (int f = 0; f < 4; ++f) {
        buf[n++] = 3;
        for (int k = 0; k < 3; ++k)
            buf[n++] = 0, buf[n++] = 0, buf[n++] = 0, buf[n++] = (unsigned char)corners[f][k];
    }
    sam_test_write_file(sam_test_tmp_path(path, sizeof path, "colors_be.ply"), buf, n);
    float *rgb = NULL;
    uint32_t count = 0;
    assert_int_equal(sam_mesh_load_vertex_colors(path, &rgb, &count, note, sizeof note, &err), SAM_OK);
    assert_int_equal(count, 4);
    for (int v = 0; v < 4; ++v)
        for (int k = 0; k < 3; ++k) {
            const float expected = (v + k) % 2 ? 1.0f : 0.0f;
            assert_float_equal(rgb[3 * v + k], expected, 0.0f);
        }
    free(rgb);
    sam_mesh m;
    sam_mesh_report report;
    assert_int_equal(sam_mesh_load(path, &m, &report, &err), SAM_OK);
    sam_mesh_destroy(&m);
    remove(path);
}

/* The cube's six quads, each after a usemtl line of `uses` (6 names). */
static void write_cube_materials(char *path, size_t n, const char *const uses[6])
{
    char obj[4096];
    int len = snprintf(obj, sizeof obj, "mtllib materials.mtl\n");
    const char *v = cube_obj, *f = strstr(cube_obj, "\nf ") + 1;
    len += snprintf(obj + len, sizeof obj - (size_t)len, "%.*s", (int)(f - v), v);
    for (int k = 0; k < 6; ++k) {
        const char *end = strchr(f, '\n') + 1;
        len += snprintf(obj + len, sizeof obj - (size_t)len, "usemtl %s\n%.*s", uses[k], (int)(end - f), f);
        f = end;
    }
    write_tmp(path, n, "materials.obj", obj);
}

/* An OBJ whose faces' materials read several textures gives a map per
 * distinct texture file and each face's (none for a colour-only
 * material), in the order sam_mesh.face_of_triangle numbers the faces:
 * each quad's two triangles read its map. One texture on every face
 * needs no maps (sam_mesh_load_albedo's), nor does a texture that
 * cannot be read leave anything but white. */
static void test_albedo_maps(void **state)
{
    (void)state;
    sam_error err;
    char path[512], png[512], mtl[512], note[2304];
    const float tones[2] = {0.5f, 0.25f};
    const char *const names[2] = {"skin.png", "eyes.png"};
    for (int k = 0; k < 2; ++k) {
        sam_image image;
        assert_int_equal(sam_image_create(&image, 2 + 2 * (uint32_t)k, 2, 3, &err), SAM_OK);
        for (size_t i = 0; i < (size_t)image.width * image.height * 3; ++i)
            image.pixels[i] = tones[k];
        assert_int_equal(sam_image_write_png(sam_test_tmp_path(png, sizeof png, names[k]), &image, SAM_PNG_SRGB,
                                             &err), SAM_OK);
        sam_image_destroy(&image);
    }
    write_tmp(mtl, sizeof mtl, "materials.mtl",
              "newmtl skin\nmap_Kd skin.png\nnewmtl lips\nmap_Kd -s 1 1 1 skin.png\nnewmtl eyes\nmap_Kd eyes.png\n"
              "newmtl teeth\nKd 1 1 1\nnewmtl broken\nmap_Kd missing.png\n");
    const char *const uses[6] = {"skin", "eyes", "teeth # a comment", "lips", "eyes", "skin"};
    write_cube_materials(path, sizeof path, uses);
    sam_albedo_maps maps;
    assert_int_equal(sam_mesh_load_albedo_maps(path, &maps, note, sizeof note, &err), SAM_OK);
    assert_string_equal(note, "");
    assert_int_equal(maps.map_count, 2);
    assert_int_equal(maps.face_count, 6);
    const uint32_t want[6] = {0, 1, SAM_ALBEDO_NO_MAP, 0, 1, 0};
    assert_memory_equal(maps.face_map, want, sizeof want);
    for (uint32_t m = 0; m < 2; ++m) {
        assert_int_equal(maps.maps[m].width, 2 + 2 * m);
        assert_float_equal(maps.maps[m].pixels[0], sam_srgb_to_linear(sam_linear_to_srgb(tones[m])), 0.01f);
    }
    sam_mesh mesh;
    assert_int_equal(sam_mesh_load(path, &mesh, NULL, &err), SAM_OK);
    assert_int_equal(mesh.face_count, 6);
    assert_int_equal(mesh.triangle_count, 12);
    for (uint32_t t = 0; t < 12; ++t)
        assert_int_equal(mesh.face_of_triangle[t], t / 2);
    sam_mesh_destroy(&mesh);
    sam_albedo_maps_destroy(&maps);

    /* One texture everywhere (two materials naming it): no maps. */
    const char *const one[6] = {"skin", "lips", "skin", "lips", "skin", "skin"};
    write_cube_materials(path, sizeof path, one);
    assert_int_equal(sam_mesh_load_albedo_maps(path, &maps, note, sizeof note, &err), SAM_OK);
    assert_int_equal(maps.map_count, 0);
    assert_null(maps.face_map);

    /* A texture that cannot be read: its faces white, and a note. */
    const char *const broken[6] = {"skin", "broken", "skin", "skin", "skin", "skin"};
    write_cube_materials(path, sizeof path, broken);
    assert_int_equal(sam_mesh_load_albedo_maps(path, &maps, note, sizeof note, &err), SAM_OK);
    printf("%s\n", note);
    assert_non_null(strstr(note, "the texture of material broken cannot be used"));
    assert_int_equal(maps.map_count, 2);
    assert_non_null(maps.maps[0].pixels);
    assert_null(maps.maps[1].pixels);
    sam_albedo_maps_destroy(&maps);
    remove(path);
}

/* A PLY as MeshLab and Metashape write several texture pages: a
 * TextureFile comment per page, and each face's page in its texnumber
 * (ASCII here; binary goes through the same walk). The same file twice
 * is one map; a texnumber past the comments reads none. */
static void test_ply_texture_pages(void **state)
{
    (void)state;
    sam_error err;
    char path[512], png[512], note[2304];
    const char *const names[2] = {"page0.png", "page1.png"};
    for (int k = 0; k < 2; ++k) {
        sam_image image;
        assert_int_equal(sam_image_create(&image, 2, 2, 3, &err), SAM_OK);
        for (size_t i = 0; i < 12; ++i)
            image.pixels[i] = 0.2f + 0.5f * (float)k;
        assert_int_equal(sam_image_write_png(sam_test_tmp_path(png, sizeof png, names[k]), &image, SAM_PNG_SRGB,
                                             &err), SAM_OK);
        sam_image_destroy(&image);
    }
    write_tmp(path, sizeof path, "pages.ply",
              "ply\nformat ascii 1.0\ncomment TextureFile page0.png\ncomment TextureFile page1.png\n"
              "comment TextureFile page0.png\nelement vertex 4\nproperty float x\nproperty float y\n"
              "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
              "property list uchar float texcoord\nproperty int texnumber\nend_header\n"
              "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
              "3 0 1 2 6 0 0 1 0 0 1 1\n3 0 3 1 6 0 0 1 0 0 1 0\n3 0 2 3 6 0 0 1 0 0 1 2\n"
              "3 1 3 2 6 0 0 1 0 0 1 7\n");
    sam_albedo_maps maps;
    assert_int_equal(sam_mesh_load_albedo_maps(path, &maps, note, sizeof note, &err), SAM_OK);
    assert_string_equal(note, "");
    assert_int_equal(maps.map_count, 2);
    const uint32_t want[4] = {1, 0, 0, SAM_ALBEDO_NO_MAP};
    assert_memory_equal(maps.face_map, want, sizeof want);
    assert_float_equal(maps.maps[1].pixels[0], sam_srgb_to_linear(sam_linear_to_srgb(0.7f)), 0.01f);
    sam_albedo_maps_destroy(&maps);
    sam_mesh mesh;
    assert_int_equal(sam_mesh_load(path, &mesh, NULL, &err), SAM_OK);
    assert_int_equal(mesh.face_count, 4);
    sam_mesh_destroy(&mesh);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_obj_with_uv_seams),
        cmocka_unit_test(test_same_cube_in_every_format),
        cmocka_unit_test(test_loads_from_several_threads),
        cmocka_unit_test(test_off_as_other_tools_write_it),
        cmocka_unit_test(test_rewritten_off_keeps_its_layout),
        cmocka_unit_test(test_ply_as_other_tools_write_it),
        cmocka_unit_test(test_ply_texture_file),
        cmocka_unit_test(test_obj_other_materials_textures),
        cmocka_unit_test(test_vertex_colors),
        cmocka_unit_test(test_albedo_maps),
        cmocka_unit_test(test_ply_texture_pages),
        cmocka_unit_test(test_obj_as_other_tools_write_it),
        cmocka_unit_test(test_body_leaves_out_loose_specks),
        cmocka_unit_test(test_open_sheet_rings_and_fan_areas),
        cmocka_unit_test(test_sphere_curvature),
        cmocka_unit_test(test_repairs_are_reported),
        cmocka_unit_test(test_inside_out_mesh_is_turned),
        cmocka_unit_test(test_non_manifold_edge),
        cmocka_unit_test(test_cracks_a_hair_wide_are_closed),
        cmocka_unit_test(test_backward_triangles_are_turned),
        cmocka_unit_test(test_file_normals_are_used_and_normalised),
        cmocka_unit_test(test_obj_corner_normals_keep_hard_edges),
        cmocka_unit_test(test_bad_inputs_give_one_clear_error),
        cmocka_unit_test(test_create_rejects_bad_arrays),
        cmocka_unit_test(test_hostile_inputs),
        cmocka_unit_test(test_truncated_prefixes),
        cmocka_unit_test(test_body_counts_are_checked),
        cmocka_unit_test(test_render_of_source),
        cmocka_unit_test(test_far_from_the_origin_is_warned),
        cmocka_unit_test(test_obj_texture_name_after_options),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
