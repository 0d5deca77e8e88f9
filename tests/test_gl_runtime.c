/*
 * The GL runtime on llvmpipe (or any GL 4.3 driver): context, embedded
 * shaders and their error messages, and the translucency pass against a
 * CPU evaluation of eq. 12 and eq. 17-18.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_build.h"
#include "sam/sam_light.h"
#include "sam/sam_runtime.h"
#include "sam/sam_shape.h"
#include "sam_test.h"

static void test_context(void **state)
{
    (void)state;
    const sam_gl_info *i = sam_gl_context_info(sam_test_gl_context());
    printf("GL: %s, %s\n", i->renderer, i->version);
    assert_true(i->major * 10 + i->minor >= 43);
    assert_true(strlen(i->renderer) > 0);
    assert_true(i->max_ssbo_size >= 16 * 1024 * 1024);
}

static void test_every_embedded_compute_shader_compiles(void **state)
{
    (void)state;
    size_t n = sam_gl_shader_file_count(), compiled = 0;
    assert_true(n > 0);
    for (size_t i = 0; i < n; ++i) {
        const char *name = sam_gl_shader_file_name(i);
        if (!sam_path_has_extension(name, ".comp"))
            continue;
        GLuint p;
        sam_error err;
        if (sam_gl_compute_program(name, NULL, &p, &err) != SAM_OK)
            fail_msg("%s", err.message);
        glDeleteProgram(p);
        compiled++;
    }
    assert_true(compiled > 0);
}

static void test_shader_errors_name_file_and_line(void **state)
{
    (void)state;
    GLuint p;
    sam_error err;
    /* An error on line 5 of a file that includes another. */
    const char *bad = "#version 430 core\n#include \"profile.glsl\"\nlayout(local_size_x = 1) in;\n"
                      "void main() {\n  float x = undeclared_thing;\n}\n";
    assert_int_equal(sam_gl_compute_program_from_text("bad.comp", bad, &p, &err), SAM_ERR_FORMAT);
    if (!strstr(err.message, "bad.comp:5:"))
        fail_msg("message does not name bad.comp:5: %s", err.message);
    /* An error inside the included file is reported in that file. */
    const char *good_then_bad = "#version 430 core\nlayout(local_size_x = 1) in;\nvoid main() { }\n";
    assert_int_equal(sam_gl_compute_program_from_text("ok.comp", good_then_bad, &p, &err), SAM_OK);
    glDeleteProgram(p);
    assert_int_equal(sam_gl_compute_program_from_text("inc.comp", "#version 430 core\n#include \"nope.glsl\"\n", &p, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "inc.comp:2: #include \"nope.glsl\""));
    assert_int_equal(sam_gl_compute_program_from_text("nov.comp", "void main() {}\n", &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "#version"));
    assert_int_equal(sam_gl_compute_program("missing.comp", NULL, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    /* The expanded source carries #line directives back to each file. */
    char *src;
    assert_int_equal(sam_gl_shader_source("translucency.comp", "#define X 1", &src, &err), SAM_OK);
    assert_non_null(strstr(src, "#define X 1"));
    assert_non_null(strstr(src, "profile_rd"));
    assert_non_null(strstr(src, "#line 1 "));
    free(src);
}

/* A built .sam of the ear shape at `resolution` for the runtime tests. */
static void build_sam_at(const char *material, int resolution, samfile_data *out, sam_profile *profile)
{
    sam_error err;
    sam_mesh mesh;
    sam_test_shape_mesh("ear", resolution, 0, 0, 0, &mesh);
    assert_int_equal(sam_profile_preset(material, profile, &err), SAM_OK);
    sam_build_settings set;
    sam_build_default_settings(&set);
    set.samples_per_vertex = 4;
    assert_int_equal(sam_build_samfile(&mesh, profile, 60.0f, &set, NULL, NULL, NULL, out, NULL, &err), SAM_OK);
    printf("%s ear at resolution %d: %.1f%% of the map's samples are tree nodes\n", material, resolution,
           100.0 * sam_test_node_share(out->sample_index, out->vertex_count, 4, out->vertex_count));
    sam_mesh_destroy(&mesh);
}

/* A small one. */
static void build_sam(const char *material, samfile_data *out, sam_profile *profile)
{
    build_sam_at(material, 24, out, profile);
}

/* eq. 12 on the CPU, in double precision. */
static void cpu_translucency(const samfile_data *d, const sam_profile *p, float mm, const float *ld, uint32_t used,
                             double *t)
{
    uint32_t n = d->samples_per_vertex;
    /* Vertices and a cut map's nodes alike (the CPU's node pass). */
    float *s = malloc(((size_t)d->vertex_count + d->node_count) * 10 * sizeof *s);
    assert_int_equal(samfile_sample_points(d, ld, 3, s, NULL), SAM_OK);
    for (uint32_t v = 0; v < d->vertex_count; ++v) {
        t[3 * v] = t[3 * v + 1] = t[3 * v + 2] = 0;
        for (uint32_t k = 0; k < used; ++k) {
            uint32_t b = d->sample_index[v * n + k];
            if (b == SAMFILE_NO_SAMPLE)
                break;
            const float *pv = d->positions + 3 * v;
            const float *pb = s + 10 * (size_t)b;
            const float tau = d->node_count ? d->sample_tau[v * n + k] : 0.0f;
            double dx = pb[0] - pv[0], dy = pb[1] - pv[1], dz = pb[2] - pv[2];
            float rd[3];
            sam_profile_eval(p, (float)(mm * sqrt(dx * dx + dy * dy + dz * dz)), rd);
            for (int c = 0; c < 3; ++c)
                t[3 * v + c] += (double)fmaxf(pb[4 + c] + tau * pb[7 + c], 0.0f) * d->sample_kprime[3 * (v * n + k) + c] *
                                pb[3] * rd[c];
        }
    }
    free(s);
}

static void check_translucency(const char *material, int resolution)
{
    samfile_data d;
    sam_profile profile;
    build_sam_at(material, resolution, &d, &profile);
    sam_runtime *rt;
    sam_error err;
    if (sam_runtime_create(&d, &profile, 60.0f, &rt, &err) != SAM_OK)
        fail_msg("%s", err.message);
    uint32_t nv = d.vertex_count;
    float *ld = malloc(nv * 3 * sizeof *ld), *gpu = malloc(nv * 3 * sizeof *gpu);
    double *cpu = malloc(nv * 3 * sizeof *cpu);
    for (uint32_t used = 1; used <= 4; used += 3) {
        /* New L_d each time: at rest the node pass sums L_d alone after its first run. */
        for (uint32_t i = 0; i < 3 * nv; ++i)
            ld[i] = (float)(((i + used) * 2654435761u) % 1000) / 100.0f;
        assert_int_equal(sam_runtime_set_irradiance(rt, ld, &err), SAM_OK);
        assert_int_equal(sam_runtime_translucency(rt, used, 0.016f, 1, &err), SAM_OK);
        assert_int_equal(sam_runtime_read_translucency(rt, gpu, &err), SAM_OK);
        cpu_translucency(&d, &profile, 60.0f, ld, used, cpu);
        double worst = 0, peak = 0;
        for (uint32_t i = 0; i < 3 * nv; ++i)
            peak = fmax(peak, fabs(cpu[i]));
        for (uint32_t i = 0; i < 3 * nv; ++i) {
            /* Relative to the value, with a floor far below anything
             * visible: K' and the cached K are packed, each channel within
             * 2^-14 of itself (shaders/sample.glsl). */
            double rel = fabs(gpu[i] - cpu[i]) / fmax(fabs(cpu[i]), 1e-6 * peak);
            worst = fmax(worst, rel);
        }
        printf("%s, %u vertices, %u tree nodes, %u samples: worst relative error %.2e (peak T %.3g), %.3f ms\n",
               material, nv, d.node_count, used, worst, peak, sam_runtime_pass_ms(rt, SAM_PASS_TRANSLUCENCY));
        assert_true(peak > 0);
        assert_true(worst <= 2.5e-4);
        assert_true(sam_runtime_pass_ms(rt, SAM_PASS_TRANSLUCENCY) >= 0);
    }
    free(ld);
    free(gpu);
    free(cpu);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

static void test_translucency_matches_cpu_skin(void **state)
{
    (void)state;
    check_translucency("skin", 24);
}

/* A tree of many node-pass groups and nodes above them (nodes.comp's two
 * stages), against the CPU's level-by-level sums. */
static void test_translucency_matches_cpu_large_tree(void **state)
{
    (void)state;
    check_translucency("skin", 64);
}

static void test_translucency_matches_cpu_marble(void **state)
{
    (void)state;
    check_translucency("marble", 24);
}

/* The worst relative difference of T on the GPU from `cpu`, with a floor
 * far below anything visible (check_translucency). */
static double worst_relative(const float *gpu, const double *cpu, uint32_t count)
{
    double worst = 0, peak = 0;
    for (uint32_t i = 0; i < count; ++i)
        peak = fmax(peak, fabs(cpu[i]));
    assert_true(peak > 0);
    for (uint32_t i = 0; i < count; ++i)
        worst = fmax(worst, fabs(gpu[i] - cpu[i]) / fmax(fabs(cpu[i]), 1e-6 * peak));
    return worst;
}

/* A map whose samples a GL's storage blocks cannot hold keeps each row's
 * best samples that fit, scaled to the row's whole K: the fitted rows'
 * sums on the GPU, and under L_d even across the back side the whole
 * map's T. */
static void test_map_too_large_keeps_best_samples(void **state)
{
    (void)state;
    samfile_data d;
    sam_profile profile;
    build_sam_at("marble", 24, &d, &profile);
    const uint32_t nv = d.vertex_count;
    const size_t slot = (size_t)nv * 12;
    sam_runtime *rt;
    sam_error err;
    assert_int_equal(sam_runtime_create_fitted(&d, &profile, 60.0f, slot - 1, &rt, &err), SAM_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "one sample per vertex"));
    assert_int_equal(sam_runtime_create_fitted(&d, &profile, 60.0f, 4 * slot, &rt, &err), SAM_OK);
    assert_int_equal(sam_runtime_samples_per_vertex(rt), 4);
    assert_int_equal(sam_runtime_fitted_note(rt, NULL, 0), 0);
    sam_runtime_destroy(rt);

    if (sam_runtime_create_fitted(&d, &profile, 60.0f, 3 * slot - 1, &rt, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(sam_runtime_samples_per_vertex(rt), 2);
    assert_int_equal(sam_runtime_file_samples_per_vertex(rt), 4);
    char note[512];
    assert_int_equal(sam_runtime_fitted_note(rt, note, sizeof note), 1);
    printf("%s\n", note);
    assert_non_null(strstr(note, "2 of the map's 4 samples per vertex"));
    assert_non_null(strstr(note, "--samples 2"));

    samfile_data fitted = d;
    fitted.samples_per_vertex = 2;
    fitted.sample_index = malloc((size_t)nv * 2 * sizeof *fitted.sample_index);
    fitted.sample_kprime = malloc((size_t)nv * 2 * 3 * sizeof *fitted.sample_kprime);
    fitted.sample_tau = malloc((size_t)nv * 2 * sizeof *fitted.sample_tau);
    assert_int_equal(samfile_fit_samples(&d, 2, &profile, 60.0f, fitted.sample_index, fitted.sample_kprime,
                                         fitted.sample_tau, &err),
                     SAM_OK);
    float *ld = malloc(nv * 3 * sizeof *ld), *gpu = malloc(nv * 3 * sizeof *gpu);
    double *cpu = malloc(nv * 3 * sizeof *cpu);
    for (uint32_t i = 0; i < 3 * nv; ++i)
        ld[i] = (float)((i * 2654435761u) % 1000) / 100.0f;
    assert_int_equal(sam_runtime_set_irradiance(rt, ld, &err), SAM_OK);
    assert_int_equal(sam_runtime_translucency(rt, 0, 0.016f, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_translucency(rt, gpu, &err), SAM_OK);
    cpu_translucency(&fitted, &profile, 60.0f, ld, 2, cpu);
    const double fitted_rows = worst_relative(gpu, cpu, 3 * nv);
    for (uint32_t i = 0; i < 3 * nv; ++i)
        ld[i] = 1.0f;
    assert_int_equal(sam_runtime_set_irradiance(rt, ld, &err), SAM_OK);
    assert_int_equal(sam_runtime_translucency(rt, 0, 0.016f, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_translucency(rt, gpu, &err), SAM_OK);
    cpu_translucency(&d, &profile, 60.0f, ld, 4, cpu);
    const double whole_rows = worst_relative(gpu, cpu, 3 * nv);
    printf("2 of 4 samples: worst relative error %.2e against the fitted rows, %.2e against the whole map under "
           "even light\n",
           fitted_rows, whole_rows);
    assert_true(fitted_rows <= 2.5e-4);
    assert_true(whole_rows <= 2.5e-4);
    free(fitted.sample_index);
    free(fitted.sample_kprime);
    free(fitted.sample_tau);
    free(ld);
    free(gpu);
    free(cpu);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

static void test_temporal_smoothing(void **state)
{
    (void)state;
    assert_float_equal(sam_runtime_smoothing_alpha(0.0f), 0.0f, 0.0f);
    assert_float_equal(sam_runtime_smoothing_alpha(1.0f), 1.0f - 1e-10f, 1e-7f);
    assert_float_equal(sam_runtime_smoothing_alpha(0.016f), 1.0 - pow(1e-10, 0.016), 1e-7);
    samfile_data d;
    sam_profile profile;
    build_sam("skin", &d, &profile);
    sam_runtime *rt;
    sam_error err;
    assert_int_equal(sam_runtime_create(&d, &profile, 60.0f, &rt, &err), SAM_OK);
    uint32_t nv = d.vertex_count;
    float *ld = calloc(nv * 3, sizeof *ld), *target = malloc(nv * 3 * sizeof *target), *t = malloc(nv * 3 * sizeof *t);
    /* Dark, then a step to constant light: T approaches its target as
     * 1 - (1 - alpha)^frames. */
    assert_int_equal(sam_runtime_set_irradiance(rt, ld, &err), SAM_OK);
    assert_int_equal(sam_runtime_translucency(rt, 0, 0.016f, 1, &err), SAM_OK);
    for (uint32_t i = 0; i < 3 * nv; ++i)
        ld[i] = 1.0f;
    assert_int_equal(sam_runtime_set_irradiance(rt, ld, &err), SAM_OK);
    assert_int_equal(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_translucency(rt, target, &err), SAM_OK);
    for (uint32_t i = 0; i < 3 * nv; ++i)
        ld[i] = 0.0f;
    assert_int_equal(sam_runtime_set_irradiance(rt, ld, &err), SAM_OK);
    assert_int_equal(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), SAM_OK);
    for (uint32_t i = 0; i < 3 * nv; ++i)
        ld[i] = 1.0f;
    assert_int_equal(sam_runtime_set_irradiance(rt, ld, &err), SAM_OK);
    const float dt = 1.0f / 60.0f;
    double a = sam_runtime_smoothing_alpha(dt);
    for (int frame = 1; frame <= 20; ++frame) {
        assert_int_equal(sam_runtime_translucency(rt, 0, dt, 0, &err), SAM_OK);
        if (frame % 5)
            continue;
        assert_int_equal(sam_runtime_read_translucency(rt, t, &err), SAM_OK);
        double expect = 1.0 - pow(1.0 - a, frame);
        for (uint32_t i = 0; i < 3 * nv; ++i)
            if (target[i] > 0)
                assert_float_equal(t[i] / target[i], expect, 1e-4);
    }
    assert_int_equal(sam_runtime_translucency(rt, 0, -1.0f, 0, &err), SAM_ERR_INVALID_ARGUMENT);
    free(ld);
    free(target);
    free(t);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* eq. 4 on the CPU with sam_light's formulas; n.l for rho_dt as the GPU takes it. */
static void cpu_irradiance(const samfile_data *d, const sam_runtime *rt, const sam_light *lights, size_t count,
                           const float sh[9][3], double *out)
{
    for (uint32_t v = 0; v < d->vertex_count; ++v) {
        const float *p = d->positions + 3 * v, *n = d->normals + 3 * v;
        double sum[3] = {0, 0, 0};
        for (size_t i = 0; i < count; ++i) {
            const sam_light *l = &lights[i];
            float e[3];
            assert_int_equal(sam_light_irradiance(l, p, n, e), SAM_OK);
            double to[3] = {0, 0, 0}, nl;
            if (l->type == SAM_LIGHT_DIRECTIONAL) {
                nl = -(n[0] * l->direction[0] + n[1] * l->direction[1] + n[2] * l->direction[2]);
            } else {
                if (l->type == SAM_LIGHT_AREA) {
                    for (uint32_t k = 0; k < l->vertex_count; ++k)
                        for (int c = 0; c < 3; ++c)
                            to[c] += l->vertices[k][c] / l->vertex_count;
                } else {
                    memcpy(to, (double[3]){l->position[0], l->position[1], l->position[2]}, sizeof to);
                }
                for (int c = 0; c < 3; ++c)
                    to[c] -= p[c];
                double len = sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
                nl = (to[0] * n[0] + to[1] * n[1] + to[2] * n[2]) / len;
            }
            nl = nl < 0 ? 0 : nl > 1 ? 1 : nl;
            double rho = sam_runtime_rho_dt(rt, (float)nl);
            for (int c = 0; c < 3; ++c)
                sum[c] += e[c] * rho;
        }
        if (sh) {
            float e[3];
            sam_light_sh9_irradiance(sh, n, e);
            for (int c = 0; c < 3; ++c)
                sum[c] += e[c] * sam_runtime_environment_rho_dt(rt);
        }
        memcpy(out + 3 * v, sum, sizeof sum);
    }
}

static void test_irradiance_matches_cpu(void **state)
{
    (void)state;
    samfile_data d;
    sam_profile profile;
    build_sam("skin", &d, &profile);
    sam_runtime *rt;
    sam_error err;
    assert_int_equal(sam_runtime_create(&d, &profile, 60.0f, &rt, &err), SAM_OK);
    /* One light of each type around the ear (about 1 unit across). */
    sam_light lights[4];
    memset(lights, 0, sizeof lights);
    for (int i = 0; i < 4; ++i) {
        lights[i].color[0] = 1.0f, lights[i].color[1] = 0.8f, lights[i].color[2] = 0.6f;
        lights[i].intensity = 2.0f + i;
    }
    lights[0].type = SAM_LIGHT_POINT;
    memcpy(lights[0].position, (float[3]){0.2f, 0.3f, 1.5f}, 3 * sizeof(float));
    lights[1].type = SAM_LIGHT_SPOT;
    memcpy(lights[1].position, (float[3]){0.0f, 0.0f, -2.0f}, 3 * sizeof(float));
    memcpy(lights[1].direction, (float[3]){0.0f, 0.0f, 1.0f}, 3 * sizeof(float));
    lights[1].inner_angle_deg = 5.0f, lights[1].outer_angle_deg = 15.0f;
    lights[2].type = SAM_LIGHT_DIRECTIONAL;
    float dir[3] = {0.3f, -0.5f, -0.8f}, len = sqrtf(0.09f + 0.25f + 0.64f);
    for (int c = 0; c < 3; ++c)
        lights[2].direction[c] = dir[c] / len;
    lights[3].type = SAM_LIGHT_AREA;
    lights[3].vertex_count = 4;
    float quad[4][3] = {{-0.5f, -0.5f, -1.0f}, {0.5f, -0.5f, -1.0f}, {0.5f, 0.5f, -1.0f}, {-0.5f, 0.5f, -1.0f}};
    memcpy(lights[3].vertices, quad, sizeof quad);
    memcpy(lights[3].normal, (float[3]){0.0f, 0.0f, 1.0f}, 3 * sizeof(float));
    assert_int_equal(sam_runtime_set_lights(rt, lights, 4, &err), SAM_OK);
    sam_image env;
    float sh[9][3];
    assert_int_equal(sam_light_make_sky(64, 32, SAM_SKY_STUDIO, &env, &err), SAM_OK);
    assert_int_equal(sam_light_sh9_from_latlong(&env, 30.0f, 0.5f, sh, &err), SAM_OK);
    sam_image_destroy(&env);
    sam_runtime_set_environment(rt, sh);
    uint32_t nv = d.vertex_count;
    float *gpu = malloc(nv * 3 * sizeof *gpu);
    double *cpu = malloc(nv * 3 * sizeof *cpu);
    for (int with_env = 1; with_env >= 0; --with_env) {
        sam_runtime_set_environment(rt, with_env ? (const float(*)[3])sh : NULL);
        assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
        assert_int_equal(sam_runtime_read_irradiance(rt, gpu, &err), SAM_OK);
        cpu_irradiance(&d, rt, lights, 4, with_env ? (const float(*)[3])sh : NULL, cpu);
        double worst = 0, peak = 0;
        uint32_t lit = 0;
        for (uint32_t i = 0; i < 3 * nv; ++i)
            peak = fmax(peak, fabs(cpu[i]));
        /* Float against double: where a light grazes the horizon (the
         * polygon clip, a spot's edge) a value of 1e-4 of the peak can
         * differ by 3e-3 of itself (measured: 7.8e-7 absolute), so the
         * relative bound applies above 1% of the peak and an absolute bound
         * of 1e-5 of the peak below. */
        double worst_abs = 0;
        for (uint32_t i = 0; i < 3 * nv; ++i) {
            double diff = fabs(gpu[i] - cpu[i]);
            if (fabs(cpu[i]) >= 0.01 * peak)
                worst = fmax(worst, diff / fabs(cpu[i]));
            else
                worst_abs = fmax(worst_abs, diff / peak);
            lit += cpu[i] > 0;
        }
        printf("irradiance: worst absolute error below 1%% of the peak: %.2e of the peak\n", worst_abs);
        assert_true(worst_abs <= 1e-5);
        printf("irradiance%s: worst relative error %.2e over %u lit values (peak %.3g), %.3f ms\n",
               with_env ? " + environment" : "", worst, lit, peak, sam_runtime_pass_ms(rt, SAM_PASS_IRRADIANCE));
        assert_true(lit > nv);
        assert_true(worst <= 2.5e-4);
    }
    /* The pass feeds the translucency pass on the GPU. */
    assert_int_equal(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), SAM_OK);
    free(gpu);
    free(cpu);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* A 2 x 2 slab `thickness` thick, its top at y = 0.1, over a 1 x 1 x 0.2
 * slab whose top lies `gap` below its bottom, as a .sam in marble at 10 mm
 * per unit. */
static void two_slabs(double thickness, double gap, samfile_data *out, sam_profile *profile)
{
    sam_shape_params sp;
    sam_error err;
    assert_int_equal(sam_shape_default_params("slab", &sp, &err), SAM_OK);
    sam_shape_mesh a, b;
    sp.resolution = 16, sp.size = sp.depth = 2.0, sp.thickness = thickness;
    assert_int_equal(sam_shape_generate("slab", &sp, &a, &err), SAM_OK);
    sp.resolution = 8, sp.size = sp.depth = 1.0, sp.thickness = 0.2;
    assert_int_equal(sam_shape_generate("slab", &sp, &b, &err), SAM_OK);
    uint32_t nv = a.vertex_count + b.vertex_count, nt = a.triangle_count + b.triangle_count;
    float *pos = malloc(nv * 3 * sizeof *pos);
    uint32_t *tri = malloc(nt * 3 * sizeof *tri);
    for (uint32_t v = 0; v < a.vertex_count; ++v) {
        memcpy(pos + 3 * v, a.positions + 3 * v, 3 * sizeof *pos);
        pos[3 * v + 1] += (float)(0.1 - 0.5 * thickness);
    }
    for (uint32_t v = 0; v < b.vertex_count; ++v) {
        memcpy(pos + 3 * (a.vertex_count + v), b.positions + 3 * v, 3 * sizeof *pos);
        pos[3 * (a.vertex_count + v) + 1] += (float)(0.1 - thickness - gap - 0.1);
    }
    memcpy(tri, a.triangles, a.triangle_count * 3 * sizeof *tri);
    for (uint32_t t = 0; t < 3 * b.triangle_count; ++t)
        tri[3 * a.triangle_count + t] = b.triangles[t] + a.vertex_count;
    sam_mesh_input in = {.name = "slabs", .vertex_count = nv, .positions = pos, .triangle_count = nt,
                         .triangles = tri};
    sam_mesh mesh;
    assert_int_equal(sam_mesh_create(&in, &mesh, NULL, &err), SAM_OK);
    assert_int_equal(sam_profile_preset("marble", profile, &err), SAM_OK);
    sam_build_settings set;
    sam_build_default_settings(&set);
    set.map = SAM_BUILD_MAP_FLAT; /* only L_d is read */
    assert_int_equal(sam_build_samfile(&mesh, profile, 10.0f, &set, NULL, NULL, NULL, out, NULL, &err), SAM_OK);
    sam_mesh_destroy(&mesh);
    sam_shape_mesh_destroy(&a);
    sam_shape_mesh_destroy(&b);
    free(pos);
    free(tri);
}

/* Each kind of shadowed light at height `height` above two_slabs(thickness,
 * gap): the lower slab's top, away from the rims, takes none of its light,
 * and the upper slab's top exactly its unshadowed light. */
static void check_slab_shadow(sam_runtime *rt, const samfile_data *d, double thickness, double gap, float height)
{
    const float lower_top = (float)(0.1 - thickness - gap);
    uint32_t nv = d->vertex_count;
    float *gpu = malloc(nv * 3 * sizeof *gpu);
    double *cpu = malloc(nv * 3 * sizeof *cpu);
    sam_error err;
    const char *names[4] = {"point", "spot", "directional", "area"};
    for (int type = 0; type < 4; ++type) {
        sam_light l;
        memset(&l, 0, sizeof l);
        l.type = (sam_light_type)type;
        l.color[0] = l.color[1] = l.color[2] = 1.0f;
        l.intensity = 5.0f;
        l.shadow = 1;
        memcpy(l.position, (float[3]){0.05f, height, 0.1f}, 3 * sizeof(float));
        memcpy(l.direction, (float[3]){0.0f, -1.0f, 0.0f}, 3 * sizeof(float));
        l.inner_angle_deg = 30.0f, l.outer_angle_deg = 45.0f;
        l.vertex_count = 4;
        float quad[4][3] = {{-0.2f, height, -0.2f}, {-0.2f, height, 0.2f}, {0.2f, height, 0.2f}, {0.2f, height, -0.2f}};
        memcpy(l.vertices, quad, sizeof quad);
        memcpy(l.normal, (float[3]){0.0f, -1.0f, 0.0f}, 3 * sizeof(float));
        assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
        sam_runtime_set_environment(rt, NULL);
        assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
        assert_int_equal(sam_runtime_read_irradiance(rt, gpu, &err), SAM_OK);
        cpu_irradiance(d, rt, &l, 1, NULL, cpu);
        uint32_t hidden = 0, lit = 0;
        double worst_hidden = 0, worst_lit = 0;
        for (uint32_t v = 0; v < nv; ++v) {
            const float *p = d->positions + 3 * v;
            if (fabsf(p[0]) > 0.45f || fabsf(p[2]) > 0.45f)
                continue; /* away from rims, where normals bend */
            if (fabsf(p[1] - 0.1f) < 1e-4f) { /* the top of the upper slab: in full light */
                lit++;
                worst_lit = fmax(worst_lit, fabs(gpu[3 * v] - cpu[3 * v]) / cpu[3 * v]);
            } else if (fabsf(p[1] - lower_top) < 1e-4f) { /* the top of the lower slab: behind it */
                hidden++;
                assert_true(cpu[3 * v] > 0);
                worst_hidden = fmax(worst_hidden, gpu[3 * v] / cpu[3 * v]);
            }
        }
        printf("%s light %g above, occluder %g thick, %g above: %u occluded vertices get at most %.2e of their "
               "unshadowed light; %u lit ones are within %.2e of it\n",
               names[type], height, thickness, gap, hidden, worst_hidden, lit, worst_lit);
        assert_true(hidden > 20 && lit > 20);
        assert_true(worst_hidden == 0.0);
        assert_true(worst_lit <= 1e-4);
    }
    free(gpu);
    free(cpu);
}

/* A vertex occluded from a shadowed light by another object gets none of
 * its light; unoccluded ones get exactly the unshadowed value. */
static void test_shadows_block_light(void **state)
{
    (void)state;
    samfile_data d;
    sam_profile profile;
    two_slabs(0.2, 0.8, &d, &profile);
    sam_runtime *rt;
    sam_error err;
    assert_int_equal(sam_runtime_create(&d, &profile, 10.0f, &rt, &err), SAM_OK);
    check_slab_shadow(rt, &d, 0.2, 0.8, 3.0f);
    /* Distant point lights take the 4 maps fitted to the object, then the
     * 4 cubes; five point lights inside the object's bounds need five
     * cubes, more than the runtime keeps. */
    sam_light many[9];
    memset(many, 0, sizeof many);
    for (int i = 0; i < 9; ++i)
        many[i].shadow = 1, many[i].intensity = 1, many[i].position[1] = 3.0f + (float)i;
    assert_int_equal(sam_runtime_set_lights(rt, many, 8, &err), SAM_OK);
    assert_int_equal(sam_runtime_set_lights(rt, many, 9, &err), SAM_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "9 distant point lights"));
    for (int i = 0; i < 5; ++i)
        many[i].position[1] = -0.5f;
    assert_int_equal(sam_runtime_set_lights(rt, many, 5, &err), SAM_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "5 shadowed area or nearby point lights"));
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* A thin sheet a little above a surface, as a crease or a lip holds one:
 * under the sheet no light arrives. Lookups offset by 1% of the object's
 * radius and a depth bias of 0.2% of the map's range, together more than
 * the 0.015 between sheet and surface, let a point light through whole;
 * offsets of about a texel of the map (0.003 to 0.007 here, lights 2
 * units above) hold it. */
static void test_thin_near_occluder_blocks_light(void **state)
{
    (void)state;
    const double thickness = 0.005, gap = 0.01; /* the object is 2.8 across */
    samfile_data d;
    sam_profile profile;
    two_slabs(thickness, gap, &d, &profile);
    sam_runtime *rt;
    sam_error err;
    assert_int_equal(sam_runtime_create(&d, &profile, 10.0f, &rt, &err), SAM_OK);
    check_slab_shadow(rt, &d, thickness, gap, 2.0f);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* A 40 x 40 x 2 mm slab (10 mm per unit) with its UV charts, as a .sam. */
static void uv_slab(const sam_profile *profile, samfile_data *out)
{
    sam_error err;
    sam_mesh mesh;
    sam_test_shape_mesh("slab", 48, 4.0, 0.2, 0, &mesh);
    assert_int_equal(sam_build_samfile(&mesh, profile, 10.0f, NULL, NULL, NULL, NULL, out, NULL, &err), SAM_OK);
    sam_mesh_destroy(&mesh);
}

/* Screen-space and texture-space diffusion: uniform entering light stays
 * uniform away from silhouettes (kernels and level weights sum to 1), a
 * sharp light edge is softened, and the background stays empty. */
static void test_diffusion_energy_and_blur(void **state)
{
    (void)state;
    sam_profile profile;
    assert_int_equal(sam_profile_preset("skin", &profile, NULL), SAM_OK);
    /* Skin's kernel is narrow enough that the central pixels' taps stay on
     * the flat top. */
    sam_separable_kernel kernel;
    assert_int_equal(sam_profile_separable_kernel_direct(&profile, 17, &kernel, NULL), SAM_OK);
    assert_true(kernel.width_mm < 6.0f);
    samfile_data d;
    uv_slab(&profile, &d);
    sam_runtime *rt;
    sam_error err;
    assert_int_equal(sam_runtime_create(&d, &profile, 10.0f, &rt, &err), SAM_OK);
    assert_true(sam_runtime_uv_status(rt, NULL, 0, NULL));
    sam_render_view view;
    memset(&view, 0, sizeof view);
    view.width = view.height = 128;
    view.fov_deg = 30.0f;
    memcpy(view.eye, (float[3]){0.0f, 8.0f, 0.001f}, 3 * sizeof(float));
    memcpy(view.up, (float[3]){0.0f, 0.0f, -1.0f}, 3 * sizeof(float));
    view.albedo[0] = view.albedo[1] = view.albedo[2] = 1.0f;
    view.front = 1;
    const char *names[4] = {"none", "screen", "pre-integrated", "texture"};
    for (int mode = 1; mode <= 3; mode += 2) {
        sam_light l;
        memset(&l, 0, sizeof l);
        l.type = SAM_LIGHT_DIRECTIONAL;
        l.color[0] = l.color[1] = l.color[2] = 1.0f;
        l.intensity = 1.0f;
        memcpy(l.direction, (float[3]){0.0f, -1.0f, 0.0f}, 3 * sizeof(float));
        assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
        assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
        assert_int_equal(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), SAM_OK);
        sam_image plain, blurred;
        view.diffusion = 0;
        assert_int_equal(sam_runtime_render(rt, &view, &plain, &err), SAM_OK);
        view.diffusion = mode;
        if (sam_runtime_render(rt, &view, &blurred, &err) != SAM_OK)
            fail_msg("%s", err.message);
        /* The view spans 43 mm; the central 40 x 40 pixels (13.4 mm) see
         * only the flat top, and their taps stay inside its 20 mm half-width:
         * 6.7 + 6 (screen kernel) or 6.7 + 8.2 (3 sigma of the widest
         * texture-space level). */
        double worst = 0;
        for (int y = 44; y < 84; ++y)
            for (int x = 44; x < 84; ++x)
                for (int c = 0; c < 3; ++c) {
                    float a = plain.pixels[4 * (y * 128 + x) + c], b = blurred.pixels[4 * (y * 128 + x) + c];
                    assert_true(a > 0);
                    worst = fmax(worst, fabs(b - a) / a);
                }
        printf("%s diffusion, uniform light: worst relative change %.2e in the interior\n", names[mode], worst);
        assert_true(worst <= 2.5e-4);
        assert_float_equal(blurred.pixels[3], 0.0f, 0.0f); /* corner: background */
        sam_image_destroy(&plain);
        sam_image_destroy(&blurred);

        /* A spot whose hard cone edge crosses the slab: the blur softens it. */
        l.type = SAM_LIGHT_SPOT;
        memcpy(l.position, (float[3]){0.0f, 3.0f, 0.0f}, 3 * sizeof(float));
        l.inner_angle_deg = l.outer_angle_deg = 8.0f; /* about 0.43 units from the centre */
        l.intensity = 9.0f;
        assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
        assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
        assert_int_equal(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), SAM_OK);
        view.diffusion = 0;
        assert_int_equal(sam_runtime_render(rt, &view, &plain, &err), SAM_OK);
        view.diffusion = mode;
        assert_int_equal(sam_runtime_render(rt, &view, &blurred, &err), SAM_OK);
        double step_plain = 0, step_blurred = 0;
        for (int x = 20; x < 107; ++x) {
            step_plain =
                fmax(step_plain, fabs(plain.pixels[4 * (64 * 128 + x + 1)] - plain.pixels[4 * (64 * 128 + x)]));
            step_blurred = fmax(step_blurred, fabs(blurred.pixels[4 * (64 * 128 + x + 1)] -
                                                   blurred.pixels[4 * (64 * 128 + x)]));
        }
        printf("%s diffusion, spot edge: largest step %.4g without, %.4g with the blur\n", names[mode], step_plain,
               step_blurred);
        assert_true(step_blurred < 0.8 * step_plain);
        sam_image_destroy(&plain);
        sam_image_destroy(&blurred);
    }
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* Pre-integrated skin: on a 10 mm skin sphere lit along +z, pixels just
 * past the terminator (N.L about -0.15) stay black with per-vertex light
 * but receive red-dominated scattered light with pre-integration. */
static void test_preintegrated_wraps_light(void **state)
{
    (void)state;
    sam_shape_params sp;
    sam_error err;
    assert_int_equal(sam_shape_default_params("sphere", &sp, &err), SAM_OK);
    sp.resolution = 64, sp.size = 1.0;
    sam_shape_mesh s;
    assert_int_equal(sam_shape_generate("sphere", &sp, &s, &err), SAM_OK);
    sam_mesh_input in = {.name = "sphere", .vertex_count = s.vertex_count, .positions = s.positions,
                         .triangle_count = s.triangle_count, .triangles = s.triangles};
    sam_mesh mesh;
    assert_int_equal(sam_mesh_create(&in, &mesh, NULL, &err), SAM_OK);
    sam_shape_mesh_destroy(&s);
    sam_profile profile;
    assert_int_equal(sam_profile_preset("skin", &profile, NULL), SAM_OK);
    samfile_data d;
    assert_int_equal(sam_build_samfile(&mesh, &profile, 10.0f, NULL, NULL, NULL, NULL, &d, NULL, &err), SAM_OK);
    sam_mesh_destroy(&mesh);
    sam_runtime *rt;
    assert_int_equal(sam_runtime_create(&d, &profile, 10.0f, &rt, &err), SAM_OK);
    sam_light l;
    memset(&l, 0, sizeof l);
    l.type = SAM_LIGHT_DIRECTIONAL;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    l.intensity = 3.0f;
    memcpy(l.direction, (float[3]){0.0f, 0.0f, -1.0f}, 3 * sizeof(float));
    assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
    sam_render_view view;
    memset(&view, 0, sizeof view);
    view.width = view.height = 128;
    view.fov_deg = 30.0f;
    memcpy(view.eye, (float[3]){3.0f, 0.0f, 0.0f}, 3 * sizeof(float));
    view.up[1] = 1.0f;
    view.albedo[0] = view.albedo[1] = view.albedo[2] = 1.0f;
    view.front = 1;
    sam_image plain, pre;
    assert_int_equal(sam_runtime_render(rt, &view, &plain, &err), SAM_OK);
    view.diffusion = 2;
    if (sam_runtime_render(rt, &view, &pre, &err) != SAM_OK)
        fail_msg("%s", err.message);
    /* Image right is world -z; the sphere's radius covers about 40 pixels. */
    int wrapped = 0;
    for (int x = 69; x <= 71; ++x) {
        const float *a = plain.pixels + 4 * (64 * 128 + x), *b = pre.pixels + 4 * (64 * 128 + x);
        printf("column %d: per-vertex %.4g %.4g %.4g, pre-integrated %.4g %.4g %.4g\n", x, a[0], a[1], a[2], b[0],
               b[1], b[2]);
        assert_float_equal(a[0], 0.0f, 0.0f);
        wrapped += b[0] > 1e-4f && b[0] > b[2];
    }
    assert_int_equal(wrapped, 3);
    /* Fully lit pixels agree roughly: the falloff of a 5 mm sphere is
     * nearly the clamped cosine at N.L = 0.7. */
    const float *a = plain.pixels + 4 * (64 * 128 + 36), *b = pre.pixels + 4 * (64 * 128 + 36);
    printf("column 36: per-vertex %.4g %.4g %.4g, pre-integrated %.4g %.4g %.4g\n", a[0], a[1], a[2], b[0], b[1], b[2]);
    assert_true(a[0] > 0 && fabsf(b[0] - a[0]) < 0.1f * a[0]);
    sam_image_destroy(&plain);
    sam_image_destroy(&pre);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_context),
        cmocka_unit_test(test_every_embedded_compute_shader_compiles),
        cmocka_unit_test(test_shader_errors_name_file_and_line),
        cmocka_unit_test(test_translucency_matches_cpu_skin),
        cmocka_unit_test(test_translucency_matches_cpu_marble),
        cmocka_unit_test(test_translucency_matches_cpu_large_tree),
        cmocka_unit_test(test_map_too_large_keeps_best_samples),
        cmocka_unit_test(test_temporal_smoothing),
        cmocka_unit_test(test_irradiance_matches_cpu),
        cmocka_unit_test(test_shadows_block_light),
        cmocka_unit_test(test_thin_near_occluder_blocks_light),
        cmocka_unit_test(test_diffusion_energy_and_blur),
        cmocka_unit_test(test_preintegrated_wraps_light),
    };
    return cmocka_run_group_tests(tests, sam_test_gl_setup, sam_test_gl_teardown);
}
