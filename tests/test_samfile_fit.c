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
    float pos[3 * NV], fana[NV], kpr[3 * NV * N], tau[NV * N];
    uint32_t sidx[NV * N], children[2], levels[2];
    samfile_data d;
} fixture;

static void make(fixture *f)
{
    static const float pos[3 * NV] = {0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3}, fana[NV] = {1.0f, 2.0f, 0.5f, 1.5f};
    static const uint32_t sidx[NV * N] = {1, 4, 2, 0, 2, 3, 4, 0, 1, 0, PAD, PAD};
    memcpy(f->pos, pos, sizeof pos);
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

/* Row v's K per channel over its first `count` samples of `index` and
 * `kprime` (rows of `n`), K = K' A R_d(|q - p|). */
static void row_k(const fixture *f, const sam_profile *p, uint32_t v, const uint32_t *index, const float *kprime,
                  uint32_t n, uint32_t count, double k[3])
{
    k[0] = k[1] = k[2] = 0;
    for (uint32_t s = 0; s < count && index[v * n + s] != PAD; ++s) {
        float q[3], area, rd[3];
        point_of(f, index[v * n + s], q, &area);
        const float dx = q[0] - f->pos[3 * v], dy = q[1] - f->pos[3 * v + 1], dz = q[2] - f->pos[3 * v + 2];
        sam_profile_eval(p, sqrtf(dx * dx + dy * dy + dz * dz), rd);
        for (int c = 0; c < 3; ++c)
            k[c] += (double)kprime[3 * (v * n + s) + c] * area * rd[c];
    }
}

static void test_rows_keep_their_best_samples_and_whole_k(void **state)
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
    for (uint32_t v = 0; v < NV; ++v) {
        for (uint32_t s = 0; s < M; ++s) {
            assert_int_equal(index[v * M + s], f.sidx[v * N + s]);
            assert_true(tau[v * M + s] == f.tau[v * N + s]);
        }
        double whole[3], kept[3];
        row_k(&f, &skin, v, f.sidx, f.kpr, N, N, whole);
        row_k(&f, &skin, v, index, kprime, M, M, kept);
        for (int c = 0; c < 3; ++c) {
            printf("vertex %u channel %d: K %.6g whole, %.6g kept\n", v, c, whole[c], kept[c]);
            assert_true(fabs(kept[c] - whole[c]) <= 1e-5 * whole[c]);
        }
    }
    /* A channel the kept samples carry none of is not scaled. */
    assert_true(kprime[3 * (1 * M + 0)] == 0.0f);
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

/* Three kept entries on a line and three dropped ones: each dropped K goes
 * to the nearest kept entry that carries its channel, and nowhere when no
 * kept entry does. */
static void test_fold_hands_each_dropped_k_to_the_nearest_kept_entry(void **state)
{
    (void)state;
    static const float at[6 * 3] = {0, 0, 0, 10, 0, 0, 20, 0, 0, /* kept */
                                    9, 0, 0, 16, 0, 0, 5, 0, 0};  /* dropped */
    static const float k[6 * 3] = {
        4, 4, 0, 3, 3, 0, 2, 0, 0, /* entry 2 carries no green, none of the three blue */
        1, 1, 1, 0.5f, 0.5f, 0, 0.25f, 0.125f, 0,
    };
    float out[9];
    samfile_fold_row(at, 3, k, 6, 3, out);
    /* Red: 9 and 5 go to 10 (5 ties with 0 and goes to the better entry
     * 0), 16 to 20. Green: 16 has no green kept at 20, so 10 takes it.
     * Blue: no kept entry carries it. */
    const float want[9] = {4 + 0.25f, 4 + 0.125f, 0, 3 + 1, 3 + 1 + 0.5f, 0, 2 + 0.5f, 0, 0};
    for (int i = 0; i < 9; ++i) {
        printf("out[%d] = %g, want %g\n", i, (double)out[i], (double)want[i]);
        assert_true(out[i] == want[i]);
    }
    /* Keeping the whole row copies it. */
    float whole[18];
    samfile_fold_row(at, 3, k, 6, 6, whole);
    assert_memory_equal(whole, k, sizeof whole);
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
        cmocka_unit_test(test_rows_keep_their_best_samples_and_whole_k),
        cmocka_unit_test(test_fitting_the_whole_row_changes_nothing),
        cmocka_unit_test(test_fold_hands_each_dropped_k_to_the_nearest_kept_entry),
        cmocka_unit_test(test_fit_rejects_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
