/*
 * sam_render: renders a scene headless (EGL, no display) to an HDR EXR and
 * an optional sRGB PNG, running the SAM passes for N frames.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#include "sam/sam_build.h"
#include "sam/sam_light.h"
#include "sam/sam_runtime.h"
#include "sam/sam_sha256.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_render SCENE.json -o OUT.exr [options]\n"
            "\n"
            "Renders the scene headless (no window, no display) at its resolution and writes the\n"
            "linear HDR image (RGBA float EXR, written atomically).\n"
            "  --png OUT.png          also write a tonemapped sRGB preview (the scene's tonemap/exposure)\n"
            "  --frames N             frames to run the SAM passes before the picture (default 1)\n"
            "  --dt S                 frame time in seconds for temporal smoothing (default 1/60)\n"
            "  --technique sam|none   translucency technique (default: the scene's)\n"
            "  --translucency-only    the translucency alone, without front lighting\n"
            "  --diffusion none|screen|texture|preintegrated\n"
            "                         surface diffusion (default: the scene's): screen-space separable\n"
            "                         SSS, texture-space sum of Gaussians (meshes without UVs fall back\n"
            "                         to screen space with a warning), or pre-integrated skin\n"
            "  --dump-vertices FILE   write per-vertex L_d and T as CSV\n"
            "A scene naming a mesh builds its .sam first (N = 3, the scene's material and scale).\n"
            "Per-pass GPU times are printed to stderr.\n");
}

static int fail(const char *message)
{
    fprintf(stderr, "sam_render: %s\n", message);
    return 1;
}

/* ACES filmic curve (Narkowicz's fit) or Reinhard, on linear values. */
static float tonemap(float x, sam_tonemap kind)
{
    if (kind == SAM_TONEMAP_REINHARD)
        return x / (1.0f + x);
    float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    return y < 0 ? 0 : y > 1 ? 1 : y;
}

/* The .sam of the scene: read, or built from its mesh. Fills the profile
 * and scale the runtime needs. */
static sam_status load_object(const sam_scene *scene, samfile_data *sam, sam_profile *profile, float *mm_per_unit,
                              sam_error *err)
{
    memset(sam, 0, sizeof *sam);
    if (scene->sam_path) {
        sam_status st = samfile_read(scene->sam_path, sam, err);
        if (st != SAM_OK)
            return st;
        sam_build_info info;
        st = sam_build_info_read(sam, scene->sam_path, &info, err);
        *mm_per_unit = info.mm_per_unit;
        /* The scene's material replaces the one INFO records. */
        if (scene->material && st == SAM_ERR_FORMAT)
            st = SAM_OK;
        if (st == SAM_OK && !scene->material && !info.has_material)
            st = sam_fail(err, SAM_ERR_FORMAT, "%s: INFO records no material and the scene gives none",
                          scene->sam_path);
        if (st == SAM_OK)
            *profile = scene->material ? scene->profile : info.profile;
        /* With "mesh" too, the .sam must be that mesh's map. */
        if (st == SAM_OK && scene->mesh_path) {
            char hex[65];
            st = sam_sha256_file(scene->mesh_path, hex, err);
            if (st == SAM_OK && !info.source_sha256[0])
                st = sam_fail(err, SAM_ERR_FORMAT, "%s: records no source hash, so it cannot be checked against %s",
                              scene->sam_path, scene->mesh_path);
            else if (st == SAM_OK && strcmp(info.source_sha256, hex))
                st = sam_fail(err, SAM_ERR_FORMAT,
                              "%s was built from another mesh (%s, sha256 %.12s...), not from %s (sha256 %.12s...)",
                              scene->sam_path, info.source_file[0] ? info.source_file : "unnamed",
                              info.source_sha256, scene->mesh_path, hex);
        }
        if (scene->scale_kind == SAM_SCALE_MM_PER_UNIT)
            *mm_per_unit = scene->scale_value;
        if (st == SAM_OK && !(*mm_per_unit > 0))
            st = sam_fail(err, SAM_ERR_FORMAT, "%s: no scale (INFO has no mm_per_unit)", scene->sam_path);
        if (st != SAM_OK)
            samfile_free(sam);
        return st;
    }
    sam_mesh mesh;
    sam_status st = sam_mesh_load(scene->mesh_path, &mesh, NULL, err);
    if (st != SAM_OK)
        return st;
    *profile = scene->profile;
    *mm_per_unit = scene->scale_kind == SAM_SCALE_SIZE_MM ? (float)(scene->scale_value / sam_mesh_diagonal(&mesh))
                                                          : scene->scale_value;
    sam_build_source source = {scene->mesh_path, NULL};
    double seconds = 0;
    st = sam_build_samfile(&mesh, profile, *mm_per_unit, NULL, &source, NULL, NULL, sam, &seconds, err);
    if (st == SAM_OK)
        fprintf(stderr, "sam_render: built the map of %s (%u vertices) in %.2f s\n", scene->mesh_path,
                mesh.vertex_count, seconds);
    sam_mesh_destroy(&mesh);
    return st;
}

static sam_status write_vertices(const char *path, const float *ld, const float *t, uint32_t n, sam_error *err)
{
    sam_atomic_file f;
    sam_status st = sam_atomic_open(&f, path, err);
    if (st != SAM_OK)
        return st;
    fprintf(f.fp, "vertex,ld_r,ld_g,ld_b,t_r,t_g,t_b\n");
    for (uint32_t v = 0; v < n; ++v)
        fprintf(f.fp, "%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", v, ld[3 * v], ld[3 * v + 1], ld[3 * v + 2], t[3 * v],
                t[3 * v + 1], t[3 * v + 2]);
    return sam_atomic_commit(&f, err);
}

int main(int argc, char **argv)
{
    const char *scene_path = NULL, *out = NULL, *png = NULL, *dump = NULL, *technique = NULL, *diffusion = NULL;
    long frames = 1;
    float dt = 1.0f / 60.0f;
    int translucency_only = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--translucency-only")) {
            translucency_only = 1;
        } else if (a[0] == '-' && a[1] && !v) {
            fprintf(stderr, "sam_render: %s needs a value (see --help)\n", a);
            return 2;
        } else if (!strcmp(a, "-o")) {
            out = argv[++i];
        } else if (!strcmp(a, "--png")) {
            png = argv[++i];
        } else if (!strcmp(a, "--dump-vertices")) {
            dump = argv[++i];
        } else if (!strcmp(a, "--technique")) {
            technique = argv[++i];
        } else if (!strcmp(a, "--diffusion")) {
            diffusion = argv[++i];
            if (strcmp(diffusion, "none") && strcmp(diffusion, "screen") && strcmp(diffusion, "texture") &&
                strcmp(diffusion, "preintegrated")) {
                fprintf(stderr,
                        "sam_render: --diffusion must be none, screen, texture or preintegrated, got \"%s\"\n",
                        diffusion);
                return 2;
            }
        } else if (!strcmp(a, "--frames")) {
            char *end;
            frames = strtol(argv[++i], &end, 10);
            if (*end || frames < 1 || frames > 100000) {
                fprintf(stderr, "sam_render: --frames must be in 1..100000, got \"%s\"\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--dt")) {
            char *end;
            dt = strtof(argv[++i], &end);
            if (*end || !(dt >= 0) || !isfinite(dt)) {
                fprintf(stderr, "sam_render: --dt must be a finite number >= 0, got \"%s\"\n", argv[i]);
                return 2;
            }
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "sam_render: unknown option \"%s\" (see --help)\n", a);
            return 2;
        } else if (!scene_path) {
            scene_path = a;
        } else {
            fprintf(stderr, "sam_render: unexpected argument \"%s\"\n", a);
            return 2;
        }
    }
    if (!scene_path || !out) {
        usage(stderr);
        return 2;
    }
    if (technique && strcmp(technique, "sam") && strcmp(technique, "none")) {
        fprintf(stderr, "sam_render: --technique must be sam or none (tsm and transmittance come with sam_compare), "
                        "got \"%s\"\n",
                technique);
        return 2;
    }
    sam_error err;
    sam_scene scene;
    if (sam_scene_load(scene_path, &scene, &err) != SAM_OK)
        return fail(err.message);
    int use_sam = technique ? !strcmp(technique, "sam") : scene.technique == SAM_TECHNIQUE_SAM;
    if (!technique && scene.technique != SAM_TECHNIQUE_SAM && scene.technique != SAM_TECHNIQUE_NONE) {
        sam_scene_destroy(&scene);
        return fail("the scene's technique is not available in sam_render yet (sam or none)");
    }
    /* 0 none, 1 screen, 2 pre-integrated, 3 texture (sam_render_view.diffusion) */
    int use_diffusion = scene.diffusion == SAM_DIFFUSION_PREINTEGRATED ? 2
                        : scene.diffusion == SAM_DIFFUSION_TEXTURE    ? 3
                                                                      : 1;
    if (diffusion)
        use_diffusion = !strcmp(diffusion, "screen")          ? 1
                        : !strcmp(diffusion, "preintegrated") ? 2
                        : !strcmp(diffusion, "texture")       ? 3
                                                              : 0;
    samfile_data sam;
    sam_profile profile;
    float mm_per_unit;
    if (load_object(&scene, &sam, &profile, &mm_per_unit, &err) != SAM_OK) {
        sam_scene_destroy(&scene);
        return fail(err.message);
    }
    int code = 1;
    float sh[9][3];
    int has_env = 0;
    sam_gl_context *gl = NULL;
    sam_runtime *rt = NULL;
    sam_image img = {0};
    float *ld = NULL, *t = NULL;
    if (scene.environment.map) {
        sam_image env;
        if (sam_image_read_exr(scene.environment.map, &env, &err) != SAM_OK)
            goto done;
        sam_status st =
            sam_light_sh9_from_latlong(&env, scene.environment.rotation_deg, scene.environment.intensity, sh, &err);
        sam_image_destroy(&env);
        if (st != SAM_OK)
            goto done;
        has_env = 1;
    }
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK ||
        sam_runtime_create(&sam, &profile, mm_per_unit, &rt, &err) != SAM_OK ||
        sam_runtime_set_lights(rt, scene.lights, scene.light_count, &err) != SAM_OK)
        goto done;
    sam_runtime_set_environment(rt, has_env ? (const float(*)[3])sh : NULL);
    for (long f = 0; f < frames; ++f) {
        if (sam_runtime_irradiance(rt, &err) != SAM_OK)
            goto done;
        if (use_sam && sam_runtime_translucency(rt, 0, dt, f == 0, &err) != SAM_OK)
            goto done;
    }
    sam_render_view view;
    memset(&view, 0, sizeof view);
    view.width = scene.width;
    view.height = scene.height;
    memcpy(view.albedo, scene.albedo, sizeof view.albedo);
    view.front = !translucency_only;
    if (use_diffusion == 3 && !sam_runtime_has_uvs(rt)) {
        fprintf(stderr, "sam_render: warning: the mesh has no UVs; texture-space diffusion falls back to screen space\n");
        use_diffusion = 1;
    }
    view.diffusion = use_diffusion;
    if (scene.has_camera) {
        memcpy(view.eye, scene.camera.position, sizeof view.eye);
        memcpy(view.target, scene.camera.target, sizeof view.target);
        memcpy(view.up, scene.camera.up, sizeof view.up);
        view.fov_deg = scene.camera.fov_deg;
        view.near_plane = scene.camera.near_plane;
        view.far_plane = scene.camera.far_plane;
    } else {
        /* Frame the bounding sphere from +Z. */
        float centre[3], radius;
        sam_runtime_bounds(rt, centre, &radius);
        view.fov_deg = 40.0f;
        float dist = radius / sinf(0.5f * view.fov_deg * 3.14159265f / 180.0f) * 1.05f;
        memcpy(view.target, centre, sizeof view.target);
        memcpy(view.eye, centre, sizeof view.eye);
        view.eye[2] += dist;
        view.up[1] = 1.0f;
    }
    if (sam_runtime_render(rt, &view, &img, &err) != SAM_OK)
        goto done;
    if (sam_image_write_exr(out, &img, SAM_EXR_FLOAT, &err) != SAM_OK)
        goto done;
    if (png) {
        /* Tonemapped, over a dark grey backdrop (the EXR keeps alpha). */
        sam_image preview;
        if (sam_image_create(&preview, img.width, img.height, 3, &err) != SAM_OK)
            goto done;
        float exposure = exp2f(scene.exposure);
        size_t n = (size_t)img.width * img.height;
        for (size_t i = 0; i < n; ++i) {
            float a = img.pixels[4 * i + 3];
            for (int c = 0; c < 3; ++c)
                preview.pixels[3 * i + c] =
                    a * tonemap(img.pixels[4 * i + c] * exposure, scene.tonemap) + (1 - a) * 0.02f;
        }
        sam_status st = sam_image_write_png(png, &preview, SAM_PNG_SRGB, &err);
        sam_image_destroy(&preview);
        if (st != SAM_OK)
            goto done;
    }
    if (dump) {
        ld = malloc((size_t)sam.vertex_count * 3 * sizeof *ld);
        t = malloc((size_t)sam.vertex_count * 3 * sizeof *t);
        if (!ld || !t) {
            sam_fail(&err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the vertex dump");
            goto done;
        }
        if (sam_runtime_read_irradiance(rt, ld, &err) != SAM_OK || sam_runtime_read_translucency(rt, t, &err) != SAM_OK ||
            write_vertices(dump, ld, t, sam.vertex_count, &err) != SAM_OK)
            goto done;
    }
    fprintf(stderr, "sam_render: %s: %ux%u, %u vertices, %ld frame%s; GPU ms: irradiance %.3f, translucency %.3f, "
                    "shade %.3f (%s)\n",
            out, scene.width, scene.height, sam.vertex_count, frames, frames == 1 ? "" : "s",
            sam_runtime_pass_ms(rt, SAM_PASS_IRRADIANCE), use_sam ? sam_runtime_pass_ms(rt, SAM_PASS_TRANSLUCENCY) : 0.0,
            sam_runtime_pass_ms(rt, SAM_PASS_SHADE), sam_gl_context_info(gl)->renderer);
    code = 0;
done:
    if (code)
        fprintf(stderr, "sam_render: %s\n", err.message);
    free(ld);
    free(t);
    sam_image_destroy(&img);
    sam_runtime_destroy(rt);
    sam_gl_context_destroy(gl);
    samfile_free(&sam);
    sam_scene_destroy(&scene);
    return code;
}
