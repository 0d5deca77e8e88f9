/* samfile_fit_samples and samfile_fold_row: a map's rows cut to their
 * best samples, each row's K at rest kept whole, the dropped samples' K
 * read where it comes from. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "sam/samfile.h"

#define NV 4u
#define N 3u
#define PAD SAMFILE_NO_SAMPLE

/* Four vertices 1-3 mm apart (mm_per_unit 1) and one tree node over
 * vertices 2 and 3 (sample index 4); vertex 3's row holds one sample. */
typedef struct fixture {
    float pos[3 * NV], nrm[3 * NV], fana[NV], kpr[3 * NV * N], tau[NV * N];
    uint32_t sidx[NV * N], children[2], levels[2];
    samfile_data d;
} fixture;

static void make(fixture *f)
{
    static const float pos[3 * NV] = {0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3}, fana[NV] = {1.0f, 2.0f, 0.5f, 1.5f};
    static const uint32_t sidx[NV * N] = {1, 4, 2, 0, 2, 3, 4, 0, 1, 0, PAD, PAD};
    memcpy(f->pos, pos, sizeof pos);
    for (uint32_t v = 0; v < NV; ++v) /* all one way: the fold goes by position */
        f->nrm[3 * v] = f->nrm[3 * v + 1] = 0.0f, f->nrm[3 * v + 2] = 1.0f;
    memcpy(f->fana, fana, sizeof fana);
    memcpy(f->sidx, sidx, sizeof sidx);
    for (uint32_t i = 0; i < 3 * NV * N; ++i)
        f->kpr[i] = 0.1f + 0.05f * (float)(i % 7);
    /* Vertex 1's first sample carries no red: nothing to scale red by. */
    f->kpr[3 * (1 * N + 0)] = 0.0f;
    memset(f->tau, 0, sizeof f->tau);
    f->tau[0 * N + 1] = 0.5f;
    f->tau[2 * N + 0] = -0.25f;
    f->children[0] = 2;
    f->children[1] = 3;
    f->levels[0] = 0;
    f->levels[1] = 1;
    f->d = (samfile_data){.vertex_count = NV,
                          .samples_per_vertex = N,
                          .positions = f->pos,
                          .normals = f->nrm,
                          .fan_area = f->fana,
                          .sample_index = f->sidx,
                          .sample_kprime = f->kpr,
                          .node_count = 1,
                          .node_children = f->children,
                          .level_count = 1,
                          .level_offsets = f->levels,
                          .sample_tau = f->tau};
}

/* Where sample index i stands and its area: a vertex, or the node over
 * vertices 2 and 3 (area-weighted centroid, summed area). */
static void point_of(const fixture *f, uint32_t i, float q[3], float *area)
{
    if (i < NV) {
        memcpy(q, f->pos + 3 * i, 3 * sizeof(float));
        *area = f->fana[i];
        return;
    }
    const float a = f->fana[2], b = f->fana[3];
    for (int c = 0; c < 3; ++c)
        q[c] = (a * f->pos[6 + c] + b * f->pos[9 + c]) / (a + b);
    *area = a + b;
}

/* Row v's K per channel over its first `count` samples of `index`,
 * `kprime` and `tau` (rows of `n`), K = K' A R_d(|q - p|), and its K
 * times each sample's value read from per-vertex `value` as the runtime
 * reads it (a node's area-weighted mean + tau times its second child's
 * minus its first's). */
static void row_k(const fixture *f, const sam_profile *p, uint32_t v, const uint32_t *index, const float *kprime,
                  const float *tau, uint32_t n, uint32_t count, const float value[NV], double k[3], double kl[3])
{
    k[0] = k[1] = k[2] = kl[0] = kl[1] = kl[2] = 0;
    for (uint32_t s = 0; s < count && index[v * n + s] != PAD; ++s) {
        float q[3], area, rd[3];
        const uint32_t i = index[v * n + s];
        point_of(f, i, q, &area);
        const float dx = q[0] - f->pos[3 * v], dy = q[1] - f->pos[3 * v + 1], dz = q[2] - f->pos[3 * v + 2];
        sam_profile_eval(p, sqrtf(dx * dx + dy * dy + dz * dz), rd);
        const double l = i < NV ? value[i]
                                : (f->fana[2] * value[2] + f->fana[3] * value[3]) / (f->fana[2] + f->fana[3]) +
                                      tau[v * n + s] * (value[3] - value[2]);
        for (int c = 0; c < 3; ++c) {
            const double kc = (double)kprime[3 * (v * n + s) + c] * area * rd[c];
            k[c] += kc;
            kl[c] += kc * l;
        }
    }
}

/* Vertex 0's row {1, node, 2} and vertex 2's {node, 0, 1} hold no two
 * siblings: their third sample folds into the kept one nearest it.
 * Vertex 1's {0, 2, 3} ends in the node's two children, which merge into
 * the node with the tau that reads their light exactly (in the channels'
 * sum). Vertex 3's {0} fits as it is. */
static void test_rows_keep_their_whole_k_and_merge_siblings_exactly(void **state)
{
    (void)state;
    fixture f;
    make(&f);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    enum { M = 2 };
    uint32_t index[NV * M];
    float kprime[3 * NV * M], tau[NV * M];
    sam_error err;
    assert_int_equal(samfile_fit_samples(&f.d, M, &skin, 1.0f, index, kprime, tau, &err), SAM_OK);
    static const uint32_t want[NV * M] = {1, 4, 0, 4, 4, 0, 0, PAD};
    assert_memory_equal(index, want, sizeof want);
    const float value[NV] = {0.3f, 1.7f, 0.2f, 5.0f};
    for (uint32_t v = 0; v < NV; ++v) {
        double whole[3], kept[3], whole_l[3], kept_l[3];
        row_k(&f, &skin, v, f.sidx, f.kpr, f.tau, N, N, value, whole, whole_l);
        row_k(&f, &skin, v, index, kprime, tau, M, M, value, kept, kept_l);
        for (int c = 0; c < 3; ++c) {
            printf("vertex %u channel %d: K %.6g whole, %.6g kept; K L_d %.6g, %.6g\n", v, c, whole[c], kept[c],
                   whole_l[c], kept_l[c]);
            assert_true(fabs(kept[c] - whole[c]) <= 1e-5 * whole[c]);
            /* Only a merge's tau weighs the channels alike: exact in sum. */
            if (v == 1 || v == 3)
                assert_true(fabs(kept_l[c] - whole_l[c]) <= (v == 1 ? 0.05 : 1e-5) * whole_l[c]);
        }
        if (v == 1) {
            const double sum = kept_l[0] + kept_l[1] + kept_l[2], sum_whole = whole_l[0] + whole_l[1] + whole_l[2];
            printf("vertex 1: K L_d summed over channels %.7g whole, %.7g merged\n", sum_whole, sum);
            assert_true(fabs(sum - sum_whole) <= 1e-5 * sum_whole);
        }
    }
    /* Vertex 1's first sample carries no red, and gets none. */
    assert_true(kprime[3 * (1 * M + 0)] == 0.0f);
}

/* Vertex 0's row {1, node, 2} drops vertex 2, which lies nearer vertex 1
 * than the node's centroid: with every normal alike vertex 1 takes its K;
 * with vertex 2 facing as the node's members do and vertex 1 another way,
 * the node does (the normals read through samfile_fit_samples). */
static void test_fit_folds_by_facing(void **state)
{
    (void)state;
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    enum { M = 2 };
    const float value[NV] = {1, 1, 1, 1};
    double got[2][2][3]; /* [normals alike, facing][slot][channel] */
    for (int facing = 0; facing < 2; ++facing) {
        fixture f;
        make(&f);
        if (facing)
            f.nrm[3 * 1] = 1.0f, f.nrm[3 * 1 + 2] = 0.0f; /* vertex 1 faces +x, the rest +z */
        uint32_t index[NV * M];
        float kprime[3 * NV * M], tau[NV * M];
        assert_int_equal(samfile_fit_samples(&f.d, M, &skin, 1.0f, index, kprime, tau, NULL), SAM_OK);
        assert_int_equal(index[0], 1);
        assert_int_equal(index[1], 4);
        double first[3], both[3], l[3];
        row_k(&f, &skin, 0, index, kprime, tau, M, 1, value, first, l);
        row_k(&f, &skin, 0, index, kprime, tau, M, 2, value, both, l);
        for (int c = 0; c < 3; ++c) {
            got[facing][0][c] = first[c];
            got[facing][1][c] = both[c] - first[c];
        }
    }
    fixture f;
    make(&f);
    double whole_first[3], whole_node[3], whole_2[3], l[3], upto[3];
    row_k(&f, &skin, 0, f.sidx, f.kpr, f.tau, N, 1, value, whole_first, l);
    row_k(&f, &skin, 0, f.sidx, f.kpr, f.tau, N, 2, value, upto, l);
    row_k(&f, &skin, 0, f.sidx, f.kpr, f.tau, N, 3, value, whole_2, l);
    for (int c = 0; c < 3; ++c) {
        whole_node[c] = upto[c] - whole_first[c];
        whole_2[c] -= upto[c];
        printf("channel %d: K vertex 1 %.4g, node %.4g, vertex 2 %.4g; alike %.4g + %.4g, facing %.4g + %.4g\n", c,
               whole_first[c], whole_node[c], whole_2[c], got[0][0][c], got[0][1][c], got[1][0][c], got[1][1][c]);
    }
    /* Red, which both kept entries outweigh: the nearer by position takes
     * it when the normals are alike, the one facing its way otherwise. */
    assert_true(fabs(got[0][0][0] - (whole_first[0] + whole_2[0])) <= 1e-5 * got[0][0][0]);
    assert_true(fabs(got[0][1][0] - whole_node[0]) <= 1e-5 * whole_node[0]);
    assert_true(fabs(got[1][0][0] - whole_first[0]) <= 1e-5 * whole_first[0]);
    assert_true(fabs(got[1][1][0] - (whole_node[0] + whole_2[0])) <= 1e-5 * got[1][1][0]);
}

static void test_fitting_the_whole_row_changes_nothing(void **state)
{
    (void)state;
    fixture f;
    make(&f);
    sam_profile marble;
    assert_int_equal(sam_profile_preset("marble", &marble, NULL), SAM_OK);
    uint32_t index[NV * N];
    float kprime[3 * NV * N], tau[NV * N];
    assert_int_equal(samfile_fit_samples(&f.d, N, &marble, 1.0f, index, kprime, tau, NULL), SAM_OK);
    assert_memory_equal(index, f.sidx, sizeof index);
    assert_memory_equal(tau, f.tau, sizeof tau);
    for (uint32_t i = 0; i < 3 * NV * N; ++i)
        assert_true(fabsf(kprime[i] - f.kpr[i]) <= 1e-6f * f.kpr[i]);
}

/* Three kept entries on a line and four dropped ones: each dropped K goes
 * to the nearest kept entry that carries at least as much of its channel;
 * what none outweighs is shared as the kept K is, and nowhere when no kept
 * entry carries the channel. */
static void test_fold_hands_each_dropped_k_to_the_nearest_kept_entry(void **state)
{
    (void)state;
    enum { F = SAMFILE_FOLD_POINT_FLOATS };
    static const float x[7] = {0, 10, 20, /* kept */ 9, 16, 5, 19 /* dropped */};
    float at[7 * F];
    for (int i = 0; i < 7; ++i) /* no normals: positions alone decide */
        samfile_fold_point((const float[3]){x[i], 0, 0}, (const float[3]){0, 0, 0}, (const float[3]){0, 5, 0},
                           at + F * i);
    static const float k[7 * 3] = {
        4, 4, 0.1f, 3, 3, 0, 2, 0, 0, /* entry 2 carries no green, entry 0 a little blue */
        1, 1, 1, 0.5f, 0.5f, 0, 0.25f, 0.125f, 0, 2.5f, 0, 0,
    };
    float out[9];
    samfile_fold_row(at, F, k, 7, 3, out);
    /* Red: 9 goes to 10, 16 to 20, 5 ties between 0 and 10 and goes to the
     * better entry 0, and 19's 2.5 outweighs 20's 2, so 10 takes it.
     * Green: 20 has none, so 10 takes 16's. Blue: entry 0 does not
     * outweigh 9's, which is shared as the kept blue is: all to entry 0. */
    const float want[9] = {4 + 0.25f, 4 + 0.125f, 1.1f, 3 + 1 + 2.5f, 3 + 1 + 0.5f, 0, 2 + 0.5f, 0, 0};
    for (int i = 0; i < 9; ++i) {
        printf("out[%d] = %g, want %g\n", i, (double)out[i], (double)want[i]);
        assert_true(fabsf(out[i] - want[i]) <= 1e-6f * want[i]);
    }
    /* Keeping the whole row copies it. */
    float whole[21];
    samfile_fold_row(at, F, k, 7, 7, whole);
    assert_memory_equal(whole, k, sizeof whole);
}

/* A tube's far wall seen from a receiver at the origin: a dropped entry
 * goes to the kept entry that faces its way, though another kept entry
 * lies nearer, when the turn between their normals, seen from the
 * receiver, spans more than the distance between them. */
static void test_fold_prefers_the_entry_facing_the_same_way(void **state)
{
    (void)state;
    enum { F = SAMFILE_FOLD_POINT_FLOATS };
    const float receiver[3] = {0, 0, 0};
    /* Kept: straight across (normal +y) and around the wall (normal +x, 4
     * away from the drop); dropped: 3 from the first, facing +x. */
    const float p[3][3] = {{0, 10, 0}, {7, 10, 0}, {3, 10, 0}};
    const float n[3][3] = {{0, 2, 0}, {1, 0, 0}, {1, 0, 0}};
    float at[3 * F];
    for (int i = 0; i < 3; ++i)
        samfile_fold_point(p[i], n[i], receiver, at + F * i);
    /* Unit normals and the distance from the receiver. */
    assert_float_equal(at[4], 1.0f, 1e-6f);
    assert_float_equal(at[F + 3], 1.0f, 1e-6f);
    assert_float_equal(at[F + 6], sqrtf(149.0f), 1e-5f);
    const float k[9] = {2, 2, 2, 2, 2, 2, 1, 1, 1};
    float out[6];
    samfile_fold_row(at, F, k, 3, 2, out);
    for (int c = 0; c < 3; ++c) {
        assert_float_equal(out[c], 2.0f, 0.0f);
        assert_float_equal(out[3 + c], 3.0f, 0.0f);
    }
    /* With no normals the nearer one takes it. */
    for (int i = 0; i < 3; ++i)
        samfile_fold_point(p[i], receiver, receiver, at + F * i);
    samfile_fold_row(at, F, k, 3, 2, out);
    assert_float_equal(out[0], 3.0f, 0.0f);
    assert_float_equal(out[3], 2.0f, 0.0f);
}

static void unit_of(void *user, uint32_t id, float out[3])
{
    (void)id;
    out[0] = out[1] = out[2] = *(const float *)user;
}

/* Two vertices of areas 1 and 3 under one node: they merge into it with
 * tau = 1/4 - K_0 / (K_0 + K_1), unless the node's unit K cannot hold
 * their K. */
static void test_siblings_merge_where_their_parent_holds_them(void **state)
{
    (void)state;
    static const uint32_t parent[3] = {2, 2, PAD}, children[2] = {0, 1};
    static const float area[3] = {1, 3, 4};
    for (int tiny = 0; tiny < 2; ++tiny) {
        uint32_t id[2] = {0, 1};
        float k[6] = {2, 2, 2, 1, 1, 1}, tau[2] = {0, 0}, unit = tiny ? 0.5f * SAMFILE_MIN_UNIT_K : 0.25f;
        const uint32_t left = samfile_merge_siblings(parent, children, 2, area, 1, unit_of, &unit, id, k, tau, 2, 1);
        printf("unit %g: %u entries, id %u, K %g, tau %g\n", (double)unit, left, id[0], (double)k[0], (double)tau[0]);
        if (tiny) {
            assert_int_equal(left, 2);
            assert_int_equal(id[0], 0);
            assert_int_equal(id[1], 1);
            assert_true(k[0] == 2 && k[3] == 1);
        } else {
            assert_int_equal(left, 1);
            assert_int_equal(id[0], 2);
            assert_true(k[0] == 3 && k[1] == 3 && k[2] == 3);
            assert_true(fabsf(tau[0] - (0.25f - 2.0f / 3.0f)) < 1e-6f);
        }
    }
}

static void test_fit_rejects_bad_arguments(void **state)
{
    (void)state;
    fixture f;
    make(&f);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    uint32_t index[NV * N];
    float kprime[3 * NV * N], tau[NV * N];
    sam_error err;
    assert_int_equal(samfile_fit_samples(&f.d, 0, &skin, 1.0f, index, kprime, tau, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "0 samples of the map's 3"));
    assert_int_equal(samfile_fit_samples(&f.d, N + 1, &skin, 1.0f, index, kprime, tau, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(samfile_fit_samples(&f.d, 2, &skin, 0.0f, index, kprime, tau, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(samfile_fit_samples(&f.d, 2, NULL, 1.0f, index, kprime, tau, &err), SAM_ERR_INVALID_ARGUMENT);
    /* A cut map needs somewhere for its tau; a flat one does not. */
    assert_int_equal(samfile_fit_samples(&f.d, 2, &skin, 1.0f, index, kprime, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    f.d.node_count = 0;
    f.d.level_count = 0;
    f.sidx[0 * N + 1] = 3;
    f.sidx[2 * N + 0] = 1;
    assert_int_equal(samfile_fit_samples(&f.d, 2, &skin, 1.0f, index, kprime, NULL, &err), SAM_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_keep_their_whole_k_and_merge_siblings_exactly),
        cmocka_unit_test(test_fit_folds_by_facing),
        cmocka_unit_test(test_fitting_the_whole_row_changes_nothing),
        cmocka_unit_test(test_fold_hands_each_dropped_k_to_the_nearest_kept_entry),
        cmocka_unit_test(test_fold_prefers_the_entry_facing_the_same_way),
        cmocka_unit_test(test_siblings_merge_where_their_parent_holds_them),
        cmocka_unit_test(test_fit_rejects_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
