/*
 * bench_frame: the runtime's per-pass costs on the current GL device
 * (llvmpipe without a GPU), measured side by side in one run.
 *
 * For knots at four resolutions (about 2k, 18k "head-sized", 88k and 550k
 * "buddha-sized" vertices; skin, N = 3): the irradiance pass (one shadowed
 * point light + environment), the translucency pass and the shading pass at
 * 1920x1080, the latter with each surface-diffusion technique. For the
 * head- and buddha-sized knots, texture-space diffusion with each of
 * Jimenez and Gutierrez's optimisations (culled, clipped, depth-sized, all)
 * against none, in a close-up, a whole-object and a far view: the cost of
 * the diffusion as the render's time less the same render's without
 * diffusion, and its speed-up. Times are wall-clock medians around
 * glFinish (llvmpipe reports no timer-query time for compute); the
 * diffusion pass's GL timer query is printed too where the driver gives
 * one. The translucency pass is set against its bandwidth lower bound: the
 * bytes it must move per vertex (its own position and T, and per sample the
 * sample record, the back vertex's position, fan area and L_d) over the
 * memory bandwidth measured here with memcpy. Last, the per-frame update of
 * a bending mesh (deform pass + sample walk) per vertex, next to the
 * translucency pass.
 *
 * Usage: bench_frame [--json FILE]   (default bench/results/frame.json)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sam/sam_build.h"
#include "sam/sam_deform.h"
#include "sam/sam_runtime.h"
#include "sam/sam_shape.h"
#include "bench_util.h"

static void die(const char *what, const sam_error *err)
{
    bench_die("bench_frame", what, err);
}

/* Copy bandwidth in bytes per second (read + write counted), best of 5. */
static double memory_bandwidth(void)
{
    size_t n = 256u << 20;
    char *a = malloc(n), *b = malloc(n);
    if (!a || !b)
        die("bandwidth buffers", NULL);
    memset(a, 1, n);
    memset(b, 2, n);
    double best = 0;
    for (int i = 0; i < 5; ++i) {
        double t = sam_seconds();
        memcpy(b, a, n);
        t = sam_seconds() - t;
        best = fmax(best, 2.0 * (double)n / t);
        a[i] = b[n - 1 - i]; /* keep the copies observable */
    }
    free(a);
    free(b);
    return best;
}

typedef sam_status (*pass_fn)(sam_runtime *rt, void *user, sam_error *err);

static sam_status run_irradiance(sam_runtime *rt, void *user, sam_error *err)
{
    (void)user;
    return sam_runtime_irradiance(rt, err);
}

static sam_status run_translucency(sam_runtime *rt, void *user, sam_error *err)
{
    (void)user;
    return sam_runtime_translucency(rt, 0, 1.0f / 60.0f, 0, err);
}

/* One animated frame's update: the pose at the next frame time, then the
 * sample walk (user: the frame counter). */
static sam_status run_update(sam_runtime *rt, void *user, sam_error *err)
{
    int *frame = user;
    sam_status st = sam_runtime_deform(rt, (float)++*frame / 30.0f, err);
    return st == SAM_OK ? sam_runtime_walk(rt, err) : st;
}

static sam_status run_shade(sam_runtime *rt, void *user, sam_error *err)
{
    sam_image img;
    sam_status st = sam_runtime_render(rt, user, &img, err);
    sam_image_destroy(&img);
    return st;
}

/* Median wall time (ms) of `runs` calls, each closed by glFinish; the
 * median GPU time of `pass` (timer query) in *gpu_ms when not NULL
 * (<= 0 where the driver reports none). */
static double median_ms_gpu(sam_runtime *rt, pass_fn fn, void *user, int runs, sam_pass pass, double *gpu_ms)
{
    double t[32], g[32];
    sam_error err;
    for (int i = 0; i < runs; ++i) {
        glFinish();
        double start = sam_seconds();
        if (fn(rt, user, &err) != SAM_OK)
            die("pass", &err);
        glFinish();
        t[i] = 1e3 * (sam_seconds() - start);
        g[i] = gpu_ms ? sam_runtime_pass_ms(rt, pass) : 0;
    }
    qsort(t, (size_t)runs, sizeof *t, bench_cmp_double);
    if (gpu_ms) {
        qsort(g, (size_t)runs, sizeof *g, bench_cmp_double);
        *gpu_ms = g[runs / 2];
    }
    return t[runs / 2];
}

static double median_ms(sam_runtime *rt, pass_fn fn, void *user, int runs)
{
    return median_ms_gpu(rt, fn, user, runs, SAM_PASS_SHADE, NULL);
}

/* Texture-space diffusion with each optimisation against none, in three
 * views of the object (bounding radius r about the origin). The cost of
 * the diffusion is the render's wall time less that of the same view
 * without diffusion (llvmpipe's timer queries are not reliable for these
 * passes), so the speed-up compares what the optimisations act on. */
static void optimization_table(sam_runtime *rt, sam_render_view view, const float centre[3], float r, FILE *json)
{
    static const struct {
        const char *name;
        float distance; /* in bounding radii from the centre */
    } views[3] = {{"close", 1.6f}, {"whole", 3.2f}, {"far", 16.0f}};
    static const struct {
        const char *name;
        int culled, clipped, depth_sized;
    } configs[5] = {{"none", 0, 0, 0},
                    {"culled", 1, 0, 0},
                    {"clipped", 0, 1, 0},
                    {"depth-sized", 0, 0, 1},
                    {"all", 1, 1, 1}};
    printf("          texture-space diffusion cost, ms (speed-up against no optimisation):\n");
    fprintf(json, ", \"texture_space_optimizations\": [");
    for (int v = 0; v < 3; ++v) {
        memcpy(view.target, centre, sizeof view.target);
        memcpy(view.eye, centre, sizeof view.eye);
        view.eye[2] += views[v].distance * r;
        view.eye[1] += 0.2f * r;
        view.diffusion = 0;
        double plain = median_ms(rt, run_shade, &view, 5);
        view.diffusion = 3;
        printf("            %-6s (render without diffusion %.1f ms)", views[v].name, plain);
        fprintf(json, "%s{\"view\": \"%s\", \"eye_distance_radii\": %.1f, \"render_without_diffusion_ms\": %.3f",
                v ? ", " : "", views[v].name, views[v].distance, plain);
        double base = 0;
        for (int c = 0; c < 5; ++c) {
            view.options.culled = configs[c].culled;
            view.options.clipped = configs[c].clipped;
            view.options.depth_sized = configs[c].depth_sized;
            double cost = median_ms(rt, run_shade, &view, 5) - plain;
            if (c == 0)
                base = cost;
            printf(" %s %.1f (%.2fx)", configs[c].name, cost, base / cost);
            fprintf(json, ", \"%s_ms\": %.3f, \"%s_speedup\": %.3f", configs[c].name, cost, configs[c].name,
                    base / cost);
        }
        printf("\n");
        fprintf(json, "}");
    }
    fprintf(json, "]");
}

int main(int argc, char **argv)
{
    const char *json_path = argc > 2 && !strcmp(argv[1], "--json") ? argv[2] : "bench/results/frame.json";
    sam_gl_context *gl;
    sam_error err;
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK)
        die("GL", &err);
    const sam_gl_info *info = sam_gl_context_info(gl);
    double bandwidth = memory_bandwidth();
    FILE *json = fopen(json_path, "w");
    if (!json)
        die(json_path, NULL);
    fprintf(json, "{\n  \"renderer\": \"%s\",\n  \"memcpy_bandwidth_gb_s\": %.2f,\n  \"meshes\": [\n", info->renderer,
            bandwidth * 1e-9);
    printf("GL: %s; memcpy bandwidth %.1f GB/s\n", info->renderer, bandwidth * 1e-9);
    printf("%9s %11s %13s %11s %12s %13s %10s %11s\n", "vertices", "irradiance", "translucency", "shade 1080p",
           "Mvertices/s", "bound (ms)", "of bound", "SAM share");
    const int resolutions[4] = {120, 400, 900, 2250};
    sam_profile skin;
    sam_profile_preset("skin", &skin, NULL);
    for (int m = 0; m < 4; ++m) {
        sam_shape_params sp;
        sam_shape_default_params("knot", &sp, NULL);
        sp.resolution = resolutions[m];
        sam_shape_mesh s;
        if (sam_shape_generate("knot", &sp, &s, &err) != SAM_OK)
            die("knot", &err);
        sam_mesh_input in = {.name = "knot", .vertex_count = s.vertex_count, .positions = s.positions,
                             .uvs = s.uvs, .triangle_count = s.triangle_count, .triangles = s.triangles};
        sam_mesh mesh;
        if (sam_mesh_create(&in, &mesh, NULL, &err) != SAM_OK)
            die("mesh", &err);
        sam_shape_mesh_destroy(&s);
        samfile_data d;
        if (sam_build_samfile(&mesh, &skin, 40.0f, NULL, NULL, NULL, NULL, &d, NULL, &err) != SAM_OK)
            die("build", &err);
        sam_runtime *rt;
        if (sam_runtime_create(&d, &skin, 40.0f, &rt, &err) != SAM_OK)
            die("runtime", &err);
        sam_light light;
        memset(&light, 0, sizeof light);
        light.type = SAM_LIGHT_POINT;
        light.color[0] = light.color[1] = light.color[2] = 1.0f;
        light.intensity = 2.0f;
        light.shadow = 1;
        light.position[2] = -2.0f;
        float sh[9][3] = {{1.0f, 1.0f, 1.0f}};
        if (sam_runtime_set_lights(rt, &light, 1, &err) != SAM_OK)
            die("lights", &err);
        sam_runtime_set_environment(rt, sh);
        sam_render_view view;
        memset(&view, 0, sizeof view);
        view.width = 1920, view.height = 1080, view.fov_deg = 40.0f, view.front = 1;
        view.eye[2] = 3.0f, view.up[1] = 1.0f;
        view.albedo[0] = view.albedo[1] = view.albedo[2] = 0.8f;
        double irr = median_ms(rt, run_irradiance, NULL, 15);
        double tra = median_ms(rt, run_translucency, NULL, 15);
        double sha = median_ms(rt, run_shade, &view, 5);
        /* Every surface-diffusion technique on the same frame. */
        static const char *diffusion_names[4] = {"none", "screen", "preintegrated", "texture"};
        double diffusion_ms[4], diffusion_gpu[4];
        for (int t = 0; t < 4; ++t) {
            view.diffusion = t;
            diffusion_ms[t] = median_ms_gpu(rt, run_shade, &view, 3, SAM_PASS_DIFFUSION, &diffusion_gpu[t]);
        }
        view.diffusion = 0;
        /* Bytes the translucency pass must move per vertex. */
        double bytes = 16 + 16 + 16 + (double)d.samples_per_vertex * (16 + 16 + 4 + 16);
        double bound = 1e3 * bytes * d.vertex_count / bandwidth;
        double share = tra / (irr + tra + sha);
        printf("%9u %9.3f ms %11.3f ms %8.2f ms %12.1f %13.3f %9.0f%% %10.1f%%\n", d.vertex_count, irr, tra, sha,
               1e-3 * d.vertex_count / tra, bound, 100 * bound / tra, 100 * share);
        printf("          1080p shading by diffusion: none %.1f ms, screen %.1f ms, pre-integrated %.1f ms, "
               "texture %.1f ms",
               diffusion_ms[0], diffusion_ms[1], diffusion_ms[2], diffusion_ms[3]);
        if (diffusion_gpu[1] > 0)
            printf(" (diffusion pass GPU ms: screen %.3f, texture %.3f)", diffusion_gpu[1], diffusion_gpu[3]);
        printf("\n");
        fprintf(json,
                "    {\"vertices\": %u, \"samples_per_vertex\": %u, \"irradiance_ms\": %.4f, \"translucency_ms\": "
                "%.4f, \"shade_1080p_ms\": %.3f, \"translucency_vertices_per_s\": %.0f, \"bytes_per_vertex\": %.0f, "
                "\"bandwidth_bound_ms\": %.4f, \"fraction_of_bound\": %.4f, \"translucency_share_1080p\": %.4f, "
                "\"shade_1080p_ms_by_diffusion\": {\"%s\": %.3f, \"%s\": %.3f, \"%s\": %.3f, \"%s\": %.3f}, "
                "\"diffusion_pass_gpu_ms\": {\"screen\": %.4f, \"texture\": %.4f}",
                d.vertex_count, d.samples_per_vertex, irr, tra, sha, 1e3 * d.vertex_count / tra, bytes, bound,
                bound / tra, share, diffusion_names[0], diffusion_ms[0], diffusion_names[1], diffusion_ms[1],
                diffusion_names[2], diffusion_ms[2], diffusion_names[3], diffusion_ms[3], diffusion_gpu[1],
                diffusion_gpu[3]);
        if (m == 1 || m == 3) {
            float centre[3], radius;
            sam_runtime_bounds(rt, centre, &radius);
            optimization_table(rt, view, centre, radius, json);
        }
        /* Last, so the other passes ran on the rest pose: the per-frame
         * update of a bending mesh (SAM paper Sec. 3.4; its Fig. 12 says an
         * animated model's frame costs only slightly more). */
        sam_deformer bend = {.type = SAM_DEFORM_BEND, .axis = {1, 0, 0}, .direction = {0, 1, 0}, .length = 1.0f,
                             .angle_deg = 60.0f, .period_s = 2.0f};
        if (sam_runtime_set_deformers(rt, &bend, 1, &err) != SAM_OK)
            die("deformers", &err);
        int frame = 0;
        double upd = median_ms(rt, run_update, &frame, 15);
        printf("          animated update (deform + walk): %.3f ms, %.1f ns per vertex (translucency %.1f ns per "
               "vertex); SAM passes of a frame %.2fx the static ones\n",
               upd, 1e6 * upd / d.vertex_count, 1e6 * tra / d.vertex_count, (irr + tra + upd) / (irr + tra));
        fprintf(json, ", \"update_ms\": %.4f, \"update_ns_per_vertex\": %.2f, \"translucency_ns_per_vertex\": %.2f",
                upd, 1e6 * upd / d.vertex_count, 1e6 * tra / d.vertex_count);
        fprintf(json, "}%s\n", m < 3 ? "," : "");
        sam_runtime_destroy(rt);
        samfile_free(&d);
        sam_mesh_destroy(&mesh);
    }
    fprintf(json, "  ]\n}\n");
    fclose(json);
    sam_gl_context_destroy(gl);
    return 0;
}
