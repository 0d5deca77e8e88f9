/* sam_mesh_solidify: single sheets turned into thin closed solids. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_mesh.h"
#include "sam_test.h"

/* A flat sheet of 2 x 2 quads, 2 x 2 units in z = 0 (normal +z), shifted
 * by `dx`, with UVs when `with_uvs`; 9 vertices, 8 triangles, 8 boundary
 * edges. */
#define SHEET_VERTICES 9
#define SHEET_TRIANGLES 8
static void sheet(float dx, float *pos, float *uv)
{
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            float *p = pos + 3 * (3 * j + i);
            p[0] = dx + (float)i, p[1] = (float)j, p[2] = 0.0f;
            if (uv)
                uv[2 * (3 * j + i)] = 0.5f * (float)i, uv[2 * (3 * j + i) + 1] = 0.5f * (float)j;
        }
}
static const uint32_t sheet_tri[SHEET_TRIANGLES * 3] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4,
                                                        3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7};

static void make_sheet(int with_uvs, sam_mesh *m)
{
    float pos[SHEET_VERTICES * 3], uv[SHEET_VERTICES * 2];
    sheet(0.0f, pos, with_uvs ? uv : NULL);
    sam_mesh_input in = {.name = "sheet", .vertex_count = SHEET_VERTICES, .positions = pos,
                         .uvs = with_uvs ? uv : NULL, .triangle_count = SHEET_TRIANGLES, .triangles = sheet_tri};
    sam_error err;
    assert_int_equal(sam_mesh_create(&in, m, NULL, &err), SAM_OK);
}

/* The solid loaded back as a mesh, as a tool would after writing it:
 * every triangle already wound as its neighbours are (none turned), so
 * the back and the rim face out as the front does. */
static void reload(const sam_shape_mesh *s, sam_mesh *m)
{
    sam_mesh_input in = {.name = "solid", .vertex_count = s->vertex_count, .positions = s->positions,
                         .uvs = s->uvs, .triangle_count = s->triangle_count, .triangles = s->triangles};
    sam_error err;
    sam_mesh_report rep;
    assert_int_equal(sam_mesh_create(&in, m, &rep, &err), SAM_OK);
    assert_int_equal(rep.triangles_turned, 0);
    assert_int_equal(rep.non_manifold_edges, 0);
}

static void test_a_sheet_becomes_a_closed_slab(void **state)
{
    (void)state;
    sam_mesh m;
    make_sheet(1, &m);
    sam_shape_mesh s;
    sam_mesh_solidify_report rep;
    sam_error err;
    assert_int_equal(sam_mesh_solidify(&m, 0.1f, &s, &rep, &err), SAM_OK);
    assert_int_equal(rep.open_parts, 1);
    assert_int_equal(rep.closed_parts, 0);
    assert_int_equal(rep.rim_edges, 8);
    assert_int_equal(rep.folded_vertices, 0);
    assert_int_equal(s.vertex_count, 2 * SHEET_VERTICES);
    assert_int_equal(s.triangle_count, 2 * SHEET_TRIANGLES + 2 * 8);
    /* The sheet is the mid-surface: the front half the thickness above it,
     * the back half below, with the same UVs. */
    for (uint32_t v = 0; v < SHEET_VERTICES; ++v) {
        assert_float_equal(s.positions[3 * v + 2], 0.05f, 1e-7);
        assert_float_equal(s.positions[3 * (SHEET_VERTICES + v) + 2], -0.05f, 1e-7);
        assert_float_equal(s.positions[3 * (SHEET_VERTICES + v)], s.positions[3 * v], 0);
        assert_memory_equal(s.uvs + 2 * (SHEET_VERTICES + v), s.uvs + 2 * v, 2 * sizeof(float));
    }
    sam_mesh solid;
    reload(&s, &solid);
    assert_true(sam_mesh_is_closed(&solid));
    /* Wound out everywhere: the volume is the sheet's area times the
     * thickness, positive. */
    assert_float_equal(sam_mesh_signed_volume(&solid), 4.0 * 0.1, 1e-6);
    sam_mesh_destroy(&solid);
    sam_shape_mesh_destroy(&s);
    sam_mesh_destroy(&m);
}

static void test_closed_parts_are_kept_and_uvs_optional(void **state)
{
    (void)state;
    /* A closed tetrahedron beside the sheet, no UVs. */
    float pos[(SHEET_VERTICES + 4) * 3];
    sheet(0.0f, pos, NULL);
    static const float tet[12] = {5, 0, 0, 6, 0, 0, 5, 1, 0, 5, 0, 1};
    memcpy(pos + 3 * SHEET_VERTICES, tet, sizeof tet);
    uint32_t tri[(SHEET_TRIANGLES + 4) * 3];
    memcpy(tri, sheet_tri, sizeof sheet_tri);
    static const uint32_t tet_tri[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    for (int k = 0; k < 12; ++k)
        tri[3 * SHEET_TRIANGLES + k] = SHEET_VERTICES + tet_tri[k];
    sam_mesh_input in = {.name = "both", .vertex_count = SHEET_VERTICES + 4, .positions = pos,
                         .triangle_count = SHEET_TRIANGLES + 4, .triangles = tri};
    sam_mesh m;
    sam_error err;
    assert_int_equal(sam_mesh_create(&in, &m, NULL, &err), SAM_OK);
    sam_shape_mesh s;
    sam_mesh_solidify_report rep;
    assert_int_equal(sam_mesh_solidify(&m, 0.2f, &s, &rep, &err), SAM_OK);
    assert_int_equal(rep.open_parts, 1);
    assert_int_equal(rep.closed_parts, 1);
    assert_null(s.uvs);
    assert_int_equal(s.vertex_count, m.vertex_count + SHEET_VERTICES);
    /* The tetrahedron's vertices keep their bits. */
    uint32_t kept = 0;
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        if (m.positions[3 * v] >= 5.0f) {
            assert_memory_equal(s.positions + 3 * v, m.positions + 3 * v, 3 * sizeof(float));
            ++kept;
        }
    assert_int_equal(kept, 4);
    sam_mesh solid;
    reload(&s, &solid);
    assert_true(sam_mesh_is_closed(&solid));
    assert_float_equal(sam_mesh_signed_volume(&solid), 4.0 * 0.2 + 1.0 / 6.0, 1e-5);
    sam_mesh_destroy(&solid);
    sam_shape_mesh_destroy(&s);
    sam_mesh_destroy(&m);
}

static void test_written_and_read_back(void **state)
{
    (void)state;
    sam_mesh m;
    make_sheet(1, &m);
    sam_shape_mesh s;
    sam_error err;
    assert_int_equal(sam_mesh_solidify(&m, 0.05f, &s, NULL, &err), SAM_OK);
    static const char *const names[] = {"solid.obj", "solid.ply"};
    for (int k = 0; k < 2; ++k) {
        for (int uvs = 0; uvs < 2; ++uvs) {
            float *kept_uvs = s.uvs;
            if (!uvs)
                s.uvs = NULL;
            char path[512];
            sam_test_tmp_path(path, sizeof path, names[k]);
            assert_int_equal(k ? sam_shape_write_ply(path, &s, 1, &err) : sam_shape_write_obj(path, &s, &err),
                             SAM_OK);
            s.uvs = kept_uvs;
            sam_mesh back;
            assert_int_equal(sam_mesh_load(path, &back, NULL, &err), SAM_OK);
            assert_true(sam_mesh_is_closed(&back));
            assert_int_equal(back.triangle_count, s.triangle_count);
            assert_int_equal(back.topo_count, 2 * SHEET_VERTICES);
            assert_true(uvs ? back.uvs != NULL : back.uvs == NULL);
            assert_float_equal(sam_mesh_signed_volume(&back), 4.0 * 0.05, 1e-6);
            sam_mesh_destroy(&back);
        }
    }
    sam_shape_mesh_destroy(&s);
    sam_mesh_destroy(&m);
}

static void test_a_tight_curve_is_reported(void **state)
{
    (void)state;
    /* Half a cylinder of radius 1 along y, open along its two straight
     * edges and its ends. */
    enum { AROUND = 16, ALONG = 4 };
    float pos[(AROUND + 1) * (ALONG + 1) * 3];
    uint32_t tri[AROUND * ALONG * 6], *t = tri;
    for (int j = 0; j <= ALONG; ++j)
        for (int i = 0; i <= AROUND; ++i) {
            const double a = 3.14159265358979 * i / AROUND;
            float *p = pos + 3 * (j * (AROUND + 1) + i);
            p[0] = (float)cos(a), p[1] = (float)j, p[2] = (float)sin(a);
        }
    for (int j = 0; j < ALONG; ++j)
        for (int i = 0; i < AROUND; ++i) {
            const uint32_t a = (uint32_t)(j * (AROUND + 1) + i), b = a + 1, c = a + AROUND + 2, d = a + AROUND + 1;
            *t++ = a, *t++ = c, *t++ = b, *t++ = a, *t++ = d, *t++ = c;
        }
    sam_mesh_input in = {.name = "arc", .vertex_count = (AROUND + 1) * (ALONG + 1), .positions = pos,
                         .triangle_count = AROUND * ALONG * 2, .triangles = tri};
    sam_mesh m;
    sam_error err;
    assert_int_equal(sam_mesh_create(&in, &m, NULL, &err), SAM_OK);
    sam_shape_mesh s;
    sam_mesh_solidify_report rep;
    assert_int_equal(sam_mesh_solidify(&m, 0.2f, &s, &rep, &err), SAM_OK);
    assert_int_equal(rep.folded_vertices, 0);
    sam_shape_mesh_destroy(&s);
    /* Half of 3 is past the radius of 1: the inner face turns inside out. */
    assert_int_equal(sam_mesh_solidify(&m, 3.0f, &s, &rep, &err), SAM_OK);
    assert_true(rep.folded_vertices > m.topo_count / 2);
    sam_shape_mesh_destroy(&s);
    sam_mesh_destroy(&m);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    sam_mesh m;
    make_sheet(0, &m);
    sam_shape_mesh s;
    sam_error err;
    const float bad[] = {0.0f, -0.1f, 1e-5f, NAN, INFINITY, 10.0f};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; ++k) {
        memset(&s, 0xAB, sizeof s);
        assert_int_equal(sam_mesh_solidify(&m, bad[k], &s, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
        assert_null(s.positions);
        assert_non_null(strstr(err.message, "diagonal"));
    }
    assert_int_equal(sam_mesh_solidify(NULL, 0.1f, &s, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    sam_mesh_destroy(&m);
    /* A sheet 1e38 across at z = 3e38: faces half its diagonal away would
     * lie past FLT_MAX. */
    float pos[SHEET_VERTICES * 3];
    sheet(0.0f, pos, NULL);
    for (int v = 0; v < SHEET_VERTICES; ++v) {
        pos[3 * v] *= 0.5e38f, pos[3 * v + 1] *= 0.5e38f;
        pos[3 * v + 2] = 3e38f;
    }
    sam_mesh_input in = {.name = "far", .vertex_count = SHEET_VERTICES, .positions = pos,
                         .triangle_count = SHEET_TRIANGLES, .triangles = sheet_tri};
    assert_int_equal(sam_mesh_create(&in, &m, NULL, &err), SAM_OK);
    assert_int_equal(sam_mesh_solidify(&m, 1e38f, &s, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_null(s.positions);
    assert_non_null(strstr(err.message, "range of 32-bit floats"));
    assert_int_equal(sam_mesh_solidify(&m, 1e36f, &s, NULL, &err), SAM_OK);
    sam_shape_mesh_destroy(&s);
    assert_int_equal(sam_mesh_solidify(&m, 0.1f, NULL, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    sam_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_sheet_becomes_a_closed_slab),
        cmocka_unit_test(test_closed_parts_are_kept_and_uvs_optional),
        cmocka_unit_test(test_written_and_read_back),
        cmocka_unit_test(test_a_tight_curve_is_reported),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
