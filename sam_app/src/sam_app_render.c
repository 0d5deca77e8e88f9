/* sam_render's job (sam_app_render.h). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sam/sam_app_backlight.h"
#include "sam/sam_app_cache.h"
#include "sam/sam_app_output.h"
#include "sam/sam_app_render.h"
#include "sam/sam_app_stage.h"
#include "sam/sam_mesh.h"
#include "sam/sam_app_thickness.h"
#include "sam/sam_runtime_scene.h"

void sam_app_render_defaults(sam_app_render_job *job)
{
    memset(job, 0, sizeof *job);
    job->technique = job->diffusion = job->sss_kernel = job->tonemap = job->beside = job->up = -1;
    job->exposure = NAN;
    job->frames = 1;
    job->fps = 30.0f;
    job->dt = 1.0f / 60.0f;
}

int sam_app_render_parse_optimizations(const char *list, sam_diffusion_options *options)
{
    sam_diffusion_options probe;
    sam_diffusion_options *o = options ? options : &probe;
    o->culled = o->clipped = o->depth_sized = 0;
    if (!strcmp(list, "none"))
        return 1;
    const char *p = list;
    while (*p) {
        size_t n = strcspn(p, ",");
        if (n == 6 && !strncmp(p, "culled", n))
            o->culled = 1;
        else if (n == 7 && !strncmp(p, "clipped", n))
            o->clipped = 1;
        else if (n == 11 && !strncmp(p, "depth-sized", n))
            o->depth_sized = 1;
        else
            return 0;
        p += n + (p[n] == ',');
    }
    return 1;
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

/* `path` with "_NNNN" before its extension for frame `index` of an
 * animation; `path` itself when index < 0. */
static sam_status numbered(const char *path, long index, char *out, size_t n, sam_error *err)
{
    int len;
    if (index < 0) {
        len = snprintf(out, n, "%s", path);
    } else {
        const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
        if (!dot || (slash && dot < slash))
            dot = path + strlen(path);
        len = snprintf(out, n, "%.*s_%04ld%s", (int)(dot - path), path, index, dot);
    }
    if (len < 0 || (size_t)len >= n)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "output path %s is too long", path);
    return SAM_OK;
}

/* The job's overrides of the scene's view. */
static void apply_overrides(const sam_app_render_job *job, sam_render_view *view)
{
    view->front = !job->translucency_only;
    if (job->sss_kernel >= 0)
        view->options.sss_kernel = (sam_sss_kernel)job->sss_kernel;
    if (job->sss_samples)
        view->options.sss_samples = (uint32_t)job->sss_samples;
    if (job->atlas_size)
        view->options.atlas_size = (uint32_t)job->atlas_size;
    if (job->optimize)
        sam_app_render_parse_optimizations(job->optimize, &view->options);
    if (job->texels_per_pixel > 0)
        view->options.texels_per_pixel = job->texels_per_pixel;
}

/* `v` turned by `angle` radians about the unit `axis` through `centre`
 * (Rodrigues). */
static void turn(const float centre[3], const float axis[3], float angle, const float v[3], float out[3])
{
    const float x[3] = {v[0] - centre[0], v[1] - centre[1], v[2] - centre[2]};
    const float c = cosf(angle), s = sinf(angle), k = axis[0] * x[0] + axis[1] * x[1] + axis[2] * x[2];
    const float cr[3] = {axis[1] * x[2] - axis[2] * x[1], axis[2] * x[0] - axis[0] * x[2],
                         axis[0] * x[1] - axis[1] * x[0]};
    for (int i = 0; i < 3; ++i)
        out[i] = centre[i] + c * x[i] + s * cr[i] + (1 - c) * k * axis[i];
}

/* Picture `index` of a turntable: the view and the scene's lights turned
 * together about the view's up through its target, as if the object turned
 * under fixed lights (the environment, a distant backdrop, stays). */
static sam_status turntable_step(const sam_app_render_job *job, const sam_scene *scene, sam_runtime *rt, long index,
                                 sam_render_view *view, sam_error *err)
{
    const float angle = 2.0f * 3.14159265f * (float)index / (float)job->turntable;
    float axis[3] = {view->up[0], view->up[1], view->up[2]};
    const float len = sqrtf(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (int c = 0; c < 3; ++c)
        axis[c] /= len;
    turn(view->target, axis, angle, view->eye, view->eye);
    sam_light *lights = calloc(scene->light_count ? scene->light_count : 1, sizeof *lights);
    if (!lights)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
    const float origin[3] = {0, 0, 0};
    for (size_t i = 0; i < scene->light_count; ++i) {
        sam_light *l = &lights[i];
        *l = scene->lights[i];
        turn(view->target, axis, angle, l->position, l->position);
        turn(origin, axis, angle, l->direction, l->direction);
        turn(origin, axis, angle, l->normal, l->normal);
        for (uint32_t k = 0; k < l->vertex_count; ++k)
            turn(view->target, axis, angle, l->vertices[k], l->vertices[k]);
    }
    sam_status st = sam_runtime_set_lights(rt, lights, scene->light_count, err);
    free(lights);
    return st;
}

/* One picture of the current frame into `img`: the view's, and with
 * `beside` that technique's of the same frame to its right. */
static sam_status render_picture(const sam_app_render_job *job, sam_runtime *rt, const sam_render_view *view,
                                 sam_image *img, sam_error *err)
{
    if (job->beside < 0)
        return sam_runtime_render(rt, view, img, err);
    sam_image pair[2] = {{0}, {0}};
    sam_render_view other = *view;
    other.technique = (sam_technique)job->beside;
    sam_status st = sam_runtime_render(rt, view, &pair[0], err);
    if (st == SAM_OK && (st = sam_runtime_render(rt, &other, &pair[1], err)) == SAM_OK)
        st = sam_image_row(pair, 2, img, err);
    sam_image_destroy(&pair[0]);
    sam_image_destroy(&pair[1]);
    return st;
}

/* The frames and pictures: a still picture is the pose at time 0 after
 * `frames` passes; an animation one picture per frame, each a new pose; a
 * turntable one picture per turn, each lit anew. `*exposure` NAN is read
 * from the first picture (sam_app_stage_exposure) and kept for the rest. */
static sam_status run_frames(const sam_app_render_job *job, const char *tool, const sam_scene *scene,
                             sam_runtime *rt, const sam_render_view *start, float *exposure, sam_error *err)
{
    const int posed = scene->deformer_count || scene->keyframe_count;
    const int use_sam = start->technique == SAM_TECHNIQUE_SAM || job->beside == SAM_TECHNIQUE_SAM;
    const long animate = job->animate, turns = job->turntable;
    const long pictures = animate ? animate : turns ? turns : 1, passes = animate ? 1 : job->frames;
    const int numbered_out = animate || turns;
    const float step = animate ? 1.0f / job->fps : job->dt;
    sam_tonemap curve = job->tonemap >= 0 ? (sam_tonemap)job->tonemap : scene->tonemap;
    const int png_out = sam_app_has_extension(job->out, ".png");
    sam_image img = {0};
    sam_status st = SAM_OK;
    for (long picture = 0; picture < pictures && st == SAM_OK; ++picture) {
        sam_render_view view = *start;
        if (turns && (st = turntable_step(job, scene, rt, picture, &view, err)) != SAM_OK)
            break;
        for (long f = 0; f < passes && st == SAM_OK; ++f) {
            long frame = animate ? picture : f;
            if (posed && (frame == 0 || animate) &&
                ((st = sam_runtime_deform(rt, (float)picture / job->fps, err)) != SAM_OK ||
                 (st = sam_runtime_walk(rt, err)) != SAM_OK))
                break;
            /* A turntable's picture is lit anew: no smoothing from the last. */
            if ((st = sam_runtime_irradiance(rt, err)) == SAM_OK && use_sam)
                st = sam_runtime_translucency(rt, scene->samples_per_vertex, step, frame == 0 || turns, err);
        }
        char out_path[4096], png_path[4096];
        if (st != SAM_OK || (st = numbered(job->out, numbered_out ? picture : -1, out_path, sizeof out_path, err)) != SAM_OK ||
            (job->png && (st = numbered(job->png, numbered_out ? picture : -1, png_path, sizeof png_path, err)) != SAM_OK))
            break;
        sam_image_destroy(&img);
        if ((st = render_picture(job, rt, &view, &img, err)) != SAM_OK)
            break;
        if (isnan(*exposure)) {
            *exposure = sam_app_stage_exposure(&img);
            fprintf(stderr, "%s: exposure: %+.2f EV, read from the picture (--exposure to set it)\n", tool,
                    *exposure);
        }
        st = sam_image_write_picture(&img, png_out ? NULL : out_path, png_out ? out_path : job->png ? png_path : NULL,
                                     curve, *exposure, err);
        /* One line rewritten on a terminal; in a log, a line per tenth. */
        const long tenth = pictures >= 10 ? pictures / 10 : 1;
        if (st == SAM_OK && numbered_out && isatty(2))
            fprintf(stderr, "\r%s: picture %ld of %ld%s", tool, picture + 1, pictures,
                    picture + 1 == pictures ? "\n" : "");
        else if (st == SAM_OK && numbered_out && ((picture + 1) % tenth == 0 || picture + 1 == pictures))
            fprintf(stderr, "%s: picture %ld of %ld\n", tool, picture + 1, pictures);
    }
    sam_image_destroy(&img);
    return st;
}

/* The per-vertex L_d and T after the last frame, as CSV: the thickness
 * technique's own T when that was rendered, else SAM's. */
static sam_status dump_vertices(sam_runtime *rt, sam_technique technique, const char *path, uint32_t count,
                                sam_error *err)
{
    float *ld = malloc((size_t)count * 3 * sizeof *ld), *t = malloc((size_t)count * 3 * sizeof *t);
    sam_status st = ld && t ? SAM_OK : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the vertex dump");
    if (st == SAM_OK && (st = sam_runtime_read_irradiance(rt, ld, err)) == SAM_OK &&
        (st = technique == SAM_TECHNIQUE_THICKNESS ? sam_runtime_read_thickness_translucency(rt, t, err)
                                                   : sam_runtime_read_translucency(rt, t, err)) == SAM_OK)
        st = write_vertices(path, ld, t, count, err);
    free(ld);
    free(t);
    return st;
}

/* The thickness technique's thickness, measured on `sam` and given to `rt`. */
static sam_status give_thickness(sam_runtime *rt, const samfile_data *sam, float mm_per_unit, const char *tool,
                                 sam_error *err)
{
    float *mm;
    sam_status st = sam_app_thickness(sam, mm_per_unit, tool, &mm, err);
    if (st != SAM_OK)
        return st;
    st = sam_runtime_set_thickness(rt, mm, sam->vertex_count, err);
    free(mm);
    return st;
}

/* The runtime's part: context, runtime, scene, thickness, frames, dump,
 * summary. */
static sam_status render_map(const sam_app_render_job *job, const char *tool, int staged, sam_scene *scene,
                             const samfile_data *sam, const sam_profile *profile, float mm_per_unit,
                             sam_technique chosen, const sam_gl_context *gl, sam_error *err)
{
    sam_runtime *rt = NULL;
    char warning[512];
    sam_status st;
    if ((st = sam_runtime_create(sam, profile, mm_per_unit, &rt, err)) != SAM_OK ||
        (st = sam_runtime_scene_setup(rt, scene, NULL, NULL, warning, sizeof warning, err)) != SAM_OK ||
        (st = sam_runtime_scene_keyframes(rt, scene, sam, err)) != SAM_OK ||
        ((chosen == SAM_TECHNIQUE_THICKNESS || job->beside == SAM_TECHNIQUE_THICKNESS) &&
         (st = give_thickness(rt, sam, mm_per_unit, tool, err)) != SAM_OK))
        goto done;
    if (warning[0])
        fprintf(stderr, "%s: warning: %s\n", tool, warning);
    if (sam_runtime_fitted_note(rt, warning, sizeof warning))
        fprintf(stderr, "%s: warning: %s\n", tool, warning);
    char note[256];
    if (staged) {
        if ((st = sam_app_backlight_place(rt, sam, scene, SAM_APP_STAGE_BACK_LIGHT, note, sizeof note, err)) != SAM_OK)
            goto done;
        fprintf(stderr, "%s: %s\n", tool, note);
    }
    sam_render_view view;
    sam_runtime_scene_view(rt, scene, &view, warning, sizeof warning);
    if ((chosen == SAM_TECHNIQUE_TSM || job->beside == SAM_TECHNIQUE_TSM) && view.diffusion != 3) {
        char reason[160];
        sam_runtime_uv_status(rt, reason, sizeof reason, NULL);
        st = sam_fail(err, SAM_ERR_UNSUPPORTED, "the tsm technique needs texture-space diffusion, which cannot run: %s",
                      reason);
        goto done;
    }
    if (warning[0])
        fprintf(stderr, "%s: warning: %s\n", tool, warning);
    sam_uv_atlas atlas;
    if (view.diffusion == 3 && sam_runtime_uv_status(rt, NULL, 0, &atlas) && atlas.moved)
        fprintf(stderr, "%s: the UVs reach past [0,1] (u %g..%g, v %g..%g): texture-space diffusion scales them by %.3g "
                        "into its atlas\n",
                tool, (double)atlas.lo[0], (double)atlas.hi[0], (double)atlas.lo[1], (double)atlas.hi[1],
                (double)atlas.scale);
    view.technique = chosen;
    apply_overrides(job, &view);
    if ((st = run_frames(job, tool, scene, rt, &view, &scene->exposure, err)) != SAM_OK ||
        (job->dump && (st = dump_vertices(rt, chosen, job->dump, sam->vertex_count, err)) != SAM_OK))
        goto done;
    long frames = job->animate ? job->animate : job->turntable ? job->turntable : job->frames;
    /* Numbered pictures are what was written, not the -o that named them. */
    char written[2 * 4096 + 8];
    if (job->animate || job->turntable) {
        char first[4096], last[4096];
        if ((st = numbered(job->out, 0, first, sizeof first, err)) != SAM_OK ||
            (st = numbered(job->out, frames - 1, last, sizeof last, err)) != SAM_OK)
            goto done;
        snprintf(written, sizeof written, "%s%s%s", first, frames > 1 ? " .. " : "", frames > 1 ? last : "");
    } else {
        snprintf(written, sizeof written, "%s", job->out);
    }
    /* n/a where the driver gave no time (a pass that did not run, or a
     * timer that cannot be right). */
    const sam_pass timed[4] = {SAM_PASS_IRRADIANCE, SAM_PASS_TRANSLUCENCY, SAM_PASS_SHADE, SAM_PASS_DIFFUSION};
    char ms[4][32];
    for (int i = 0; i < 4; ++i) {
        double t = sam_runtime_pass_ms(rt, timed[i]);
        if (timed[i] == SAM_PASS_TRANSLUCENCY && chosen != SAM_TECHNIQUE_SAM && chosen != SAM_TECHNIQUE_THICKNESS)
            t = -1;
        if (t >= 0)
            snprintf(ms[i], sizeof ms[i], "%.3f", t);
        else
            snprintf(ms[i], sizeof ms[i], "n/a");
    }
    /* A single frame's times hold the driver's first-use work (llvmpipe
     * compiles a shader at its first draw: seconds for "shade" on a
     * 150-vertex mesh), so they are not what a frame costs; llvmpipe's
     * queries time its compute passes' dispatch, not their work. */
    fprintf(stderr, "%s: %s: %ux%u, %u vertices, %ld frame%s; GPU ms%s: irradiance %s, translucency %s, shade %s, "
                    "diffusion %s (%s%s)\n",
            tool, written, view.width, view.height, sam->vertex_count, frames, frames == 1 ? "" : "s",
            frames == 1 ? " of the only frame, shader compilation included (--passes N times the last of N)"
                        : ", last frame",
            ms[0], ms[1], ms[2], ms[3], sam_gl_context_info(gl)->renderer,
            strstr(sam_gl_context_info(gl)->renderer, "llvmpipe") ? ", whose compute passes read about 0" : "");
done:
    sam_runtime_destroy(rt);
    return st;
}

/* A warning for each point, spot or area light inside the object (the
 * winding number of its position, or its polygon's centroid, over one
 * half): it lights nothing a camera sees. */
static void warn_lights_inside(const char *tool, const sam_scene *scene, const samfile_data *sam)
{
    for (size_t i = 0; i < scene->light_count; ++i) {
        const sam_light *l = &scene->lights[i];
        float at[3] = {l->position[0], l->position[1], l->position[2]};
        if (l->type == SAM_LIGHT_DIRECTIONAL)
            continue;
        if (l->type == SAM_LIGHT_AREA)
            for (int c = 0; c < 3; ++c) {
                at[c] = 0;
                for (uint32_t k = 0; k < l->vertex_count; ++k)
                    at[c] += l->vertices[k][c] / (float)l->vertex_count;
            }
        if (sam_mesh_winding_number(sam->positions, sam->triangles, sam->triangle_count, at) > 0.5)
            fprintf(stderr, "%s: warning: light %zu (%s) at %g %g %g is inside the object: it lights nothing seen\n",
                    tool, i, sam_light_type_name(l->type), at[0], at[1], at[2]);
    }
}

/* The outputs and the options that go together, before any work: every
 * picture an animation or a turntable would write. */
static sam_status check_job(const sam_app_render_job *job, int bare, sam_error *err)
{
    static const char *const pictures[] = {".png", ".exr", NULL}, *const pngs[] = {".png", NULL},
                             *const jsons[] = {".json", NULL};
    if (job->png && sam_app_has_extension(job->out, ".png"))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "--png is for an EXR output; -o %s is a PNG already", job->out);
    const long count = job->animate ? job->animate : job->turntable ? job->turntable : 1;
    sam_status st = SAM_OK;
    for (long i = 0; i < count && st == SAM_OK; ++i) {
        char path[4096];
        const long index = job->animate || job->turntable ? i : -1;
        if ((st = numbered(job->out, index, path, sizeof path, err)) == SAM_OK)
            st = sam_app_check_output("-o", path, pictures, job->force, err);
        if (st == SAM_OK && job->png && (st = numbered(job->png, index, path, sizeof path, err)) == SAM_OK)
            st = sam_app_check_output("--png", path, pngs, job->force, err);
    }
    if (st == SAM_OK && job->write_scene)
        st = sam_app_check_output("--write-scene", job->write_scene, jsons, job->force, err);
    if (st == SAM_OK && job->dump)
        st = sam_app_check_output("--dump-vertices", job->dump, NULL, job->force, err);
    if (st != SAM_OK)
        return st;
    if (!bare && (job->material || job->size_mm || job->mm_per_unit || job->angle_deg || job->up >= 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "--material, --size-mm, --mm-per-unit, --angle and --up are for a bare mesh; %s sets its "
                        "own",
                        job->scene_path);
    if (job->animate && job->turntable)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "--animate and --turntable cannot go together");
    return SAM_OK;
}

/* The scene of the job's input: a scene file, or a bare mesh staged with
 * each assumption printed. */
static sam_status job_scene(const sam_app_render_job *job, const char *tool, int bare, sam_scene *scene,
                            sam_error *err)
{
    if (!bare) {
        sam_status st = sam_scene_load(job->scene_path, scene, err);
        if (st == SAM_OK && job->width) {
            scene->width = job->width;
            scene->height = job->height;
        }
        return st;
    }
    sam_app_stage_options options;
    sam_app_stage_defaults(&options);
    options.size_mm = job->size_mm;
    options.mm_per_unit = job->mm_per_unit;
    options.angle_deg = job->angle_deg;
    options.up = job->up;
    options.width = job->width;
    options.height = job->height;
    sam_app_stage_notes notes;
    sam_status st = sam_app_stage_scene(job->scene_path, job->material, &options, scene, &notes, err);
    for (int i = 0; st == SAM_OK && i < notes.count; ++i)
        fprintf(stderr, "%s: %s\n", tool, notes.line[i]);
    return st;
}

sam_status sam_app_render_run(const sam_app_render_job *job, const char *tool, sam_error *err)
{
    const int bare = !sam_app_has_extension(job->scene_path, ".json");
    sam_scene scene;
    sam_scene_init(&scene);
    sam_status st = check_job(job, bare, err);
    if (st != SAM_OK || (st = job_scene(job, tool, bare, &scene, err)) != SAM_OK)
        return st;
    if (job->animate && !scene.deformer_count && !scene.keyframe_count) {
        sam_scene_destroy(&scene);
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s has no \"deformers\" or \"keyframes\" to animate",
                        job->scene_path);
    }
    sam_technique chosen = job->technique >= 0 ? (sam_technique)job->technique : scene.technique;
    if (job->diffusion >= 0)
        scene.diffusion = (sam_diffusion)job->diffusion;
    if ((chosen == SAM_TECHNIQUE_TSM || job->beside == SAM_TECHNIQUE_TSM) && scene.diffusion != SAM_DIFFUSION_TEXTURE) {
        sam_scene_destroy(&scene);
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "the tsm technique needs texture-space diffusion (--diffusion texture or the scene's "
                        "\"diffusion\": \"texture\")");
    }
    /* A bare mesh's exposure is read from its first picture unless given. */
    scene.exposure = !isnan(job->exposure) ? job->exposure : bare ? NAN : scene.exposure;
    char cache_dir[4096];
    sam_app_cache_dir(job->cache_dir, cache_dir, sizeof cache_dir);
    samfile_data sam;
    sam_profile profile;
    float mm_per_unit;
    /* The GL's limits before any work: a picture it cannot hold fails now,
     * not after the map is built. */
    sam_gl_context *gl = NULL;
    if ((st = sam_gl_context_create_headless(&gl, err)) != SAM_OK ||
        (st = sam_gl_check_picture_size(scene.width, scene.height, err)) != SAM_OK) {
        sam_gl_context_destroy(gl);
        sam_scene_destroy(&scene);
        return st;
    }
    if ((st = sam_app_cache_object(&scene, NULL, cache_dir, !job->no_cache, tool, &sam, &profile, &mm_per_unit, NULL,
                                   err)) ==
        SAM_OK) {
        if (!scene.light_count && !scene.environment.map)
            fprintf(stderr, "%s: warning: %s has no lights and no environment: only the black of no light will show\n",
                    tool, job->scene_path);
        warn_lights_inside(tool, &scene, &sam);
        st = render_map(job, tool, bare, &scene, &sam, &profile, mm_per_unit, chosen, gl, err);
        samfile_free(&sam);
    }
    sam_gl_context_destroy(gl);
    if (st == SAM_OK && job->write_scene && (st = sam_scene_write(job->write_scene, &scene, err)) == SAM_OK)
        fprintf(stderr, "%s: wrote the scene to %s\n", tool, job->write_scene);
    sam_scene_destroy(&scene);
    return st;
}
