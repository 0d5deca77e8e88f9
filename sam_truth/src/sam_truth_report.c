/* The comparison's reports, the samples sweep's plot and the output folder
 * (sam_truth_report.h). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sam/sam_truth_report.h"

#define TECHNIQUES SAM_TRUTH_REPORT_TECHNIQUES

static const char *const diffusion_names[4] = {"none", "screen", "preintegrated", "texture"};

/* JSON has no infinity: an exact match is written as null. */
static void json_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.4f", v);
    else
        fprintf(f, "null");
}

static void md_db(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, " %.2f |", v);
    else
        fprintf(f, " inf |");
}

/* The "truth" object of report.json, from its opening brace to its closing
 * one. */
static void json_truth(FILE *f, const sam_truth_report *r)
{
    const sam_truth_report_step *final = &r->steps[r->step_count - 1];
    fprintf(f, "  \"truth\": {\"samples\": %llu, \"seconds\": %.3f, \"space\": \"%s\", \"translucency_max\": %.6g, "
               "\"translucency_share\": %.4g, \"far_field_tolerance\": %g, \"converged\": %s, \"convergence\": [",
            (unsigned long long)final->samples, final->seconds, r->space, (double)r->truth_max,
            r->translucency_share, (double)r->truth_tolerance, r->converged ? "true" : "false");
    for (int i = 0; i < r->step_count; ++i) {
        fprintf(f, "%s{\"samples\": %llu, \"seconds\": %.3f, \"sam_psnr_db\": ", i ? ", " : "",
                (unsigned long long)r->steps[i].samples, r->steps[i].seconds);
        json_number(f, r->steps[i].sam_psnr_db);
        fprintf(f, ", \"sam_psnr_translucency_db\": ");
        json_number(f, r->steps[i].sam_psnr_normalised_db);
        fprintf(f, "}");
    }
    /* The truth scored against itself checks the scoring: an exact match. */
    fprintf(f, "], \"self_psnr_db\": ");
    json_number(f, r->self->all.psnr_db);
    fprintf(f, ", \"self_differing_pixels\": %llu, \"self_psnr_translucency_db\": ",
            (unsigned long long)r->self->all.differing_pixels);
    json_number(f, r->self->normalised.psnr_db);
    fprintf(f, "}");
}

/* The "techniques" array of report.json. */
static void json_techniques(FILE *f, const sam_truth_report_technique *techniques)
{
    fprintf(f, "  \"techniques\": [\n");
    int first = 1;
    for (int t = 0; t < TECHNIQUES; ++t) {
        const sam_truth_report_technique *r = &techniques[t];
        if (!r->requested)
            continue;
        fprintf(f, "%s    {\"name\": \"%s\", \"available\": %s", first ? "" : ",\n",
                sam_truth_report_technique_name(t), r->available ? "true" : "false");
        first = 0;
        if (!r->available) {
            fprintf(f, ", \"reason\": \"%s\"}", r->reason);
            continue;
        }
        fprintf(f, ", \"pixels\": %llu, \"differing_pixels\": %llu, \"psnr_db\": ", (unsigned long long)r->all.pixels,
                (unsigned long long)r->all.differing_pixels);
        json_number(f, r->all.psnr_db);
        fprintf(f, ", \"rmse\": %.4f, \"psnr_differing_db\": ", r->all.rmse);
        json_number(f, r->all.psnr_differing_db);
        fprintf(f, ", \"rmse_differing\": %.4f, \"psnr_translucency_db\": ", r->all.rmse_differing);
        json_number(f, r->normalised.psnr_db);
        fprintf(f, ", \"rmse_translucency\": %.4f, \"psnr_translucency_differing_db\": ", r->normalised.rmse);
        json_number(f, r->normalised.psnr_differing_db);
        fprintf(f, "}");
    }
    fprintf(f, "\n  ]");
}

static void write_json(FILE *f, const void *what)
{
    const sam_truth_report *r = what;
    fprintf(f, "{\n  \"scene\": \"%s\",\n  \"resolution\": [%u, %u],\n  \"vertices\": %u,\n",
            sam_path_basename(r->scene_path), r->width, r->height, r->vertex_count);
    if (r->animated)
        fprintf(f, "  \"frame\": %ld,\n  \"time_s\": %.6g,\n  \"fps\": %g,\n", r->frame,
                (double)((float)r->frame / r->fps), (double)r->fps);
    fprintf(f, "  \"samples_per_vertex\": %u,\n  \"map\": \"%s\",\n  \"map_build_seconds\": %.3f,\n"
               "  \"diffusion\": \"%s\",\n",
            r->samples_per_vertex, r->map ? r->map : "", r->build_seconds, diffusion_names[r->diffusion]);
    json_truth(f, r);
    fprintf(f, ",\n");
    json_techniques(f, r->techniques);
    if (r->sweep_count) {
        fprintf(f, ",\n  \"samples_sweep\": {\"rmse_falls_monotonically\": %s, \"points\": [",
                r->monotonic ? "true" : "false");
        for (int i = 0; i < r->sweep_count; ++i) {
            const sam_truth_report_sweep_point *p = &r->sweep[i];
            fprintf(f, "%s{\"n\": %ld, \"build_seconds\": %.3f, \"rmse\": %.4f, \"rmse_translucency\": %.4f, "
                       "\"psnr_db\": ",
                    i ? ", " : "", p->n, p->build_seconds, p->all.rmse, p->normalised.rmse);
            json_number(f, p->all.psnr_db);
            if (p->cut_budget)
                fprintf(f, ", \"cut_budget\": %u", p->cut_budget);
            if (p->has_flat)
                fprintf(f, ", \"flat_rmse\": %.4f, \"flat_rmse_translucency\": %.4f, \"flat_scaled_rmse\": %.4f, "
                           "\"flat_scaled_rmse_translucency\": %.4f",
                        p->flat_all.rmse, p->flat_normalised.rmse, p->scaled_all.rmse, p->scaled_normalised.rmse);
            fprintf(f, "}");
        }
        fprintf(f, "]}");
    }
    fprintf(f, "\n}\n");
}

/* report.md's table of the techniques. */
static void md_techniques(FILE *f, const sam_truth_report_technique *techniques)
{
    fprintf(f, "| technique | PSNR (dB) | RMSE | PSNR differing (dB) | differing pixels | translucency PSNR (dB) | "
               "translucency RMSE |\n| --- | --- | --- | --- | --- | --- | --- |\n");
    for (int t = 0; t < TECHNIQUES; ++t) {
        const sam_truth_report_technique *r = &techniques[t];
        const char *name = sam_truth_report_technique_name(t);
        if (!r->requested)
            continue;
        if (!r->available) {
            fprintf(f, "| %s | unavailable: %s | | | | | |\n", name, r->reason);
            continue;
        }
        fprintf(f, "| %s |", name);
        md_db(f, r->all.psnr_db);
        fprintf(f, " %.3f |", r->all.rmse);
        md_db(f, r->all.psnr_differing_db);
        fprintf(f, " %llu of %llu |", (unsigned long long)r->all.differing_pixels, (unsigned long long)r->all.pixels);
        md_db(f, r->normalised.psnr_db);
        fprintf(f, " %.3f |\n", r->normalised.rmse);
    }
}

static void write_md(FILE *f, const void *what)
{
    const sam_truth_report *r = what;
    const sam_truth_report_step *final = &r->steps[r->step_count - 1];
    fprintf(f, "# sam_compare: %s\n\n", sam_path_basename(r->scene_path));
    fprintf(f, "%ux%u, %u vertices, N = %u back-side samples per vertex (%s map), %s diffusion.\n\n", r->width,
            r->height, r->vertex_count, r->samples_per_vertex, r->map && r->map[0] ? r->map : "unrecorded kind of",
            diffusion_names[r->diffusion]);
    if (r->animated)
        fprintf(f, "Frame %ld of the animation at %g fps (t = %.4g s): the pose, the truth and every technique "
                   "at that time; the frames before it were played as `sam_render --animate` plays them (the "
                   "sample walk every frame, T smoothed with dt = 1/fps).\n\n",
                r->frame, (double)r->fps, (double)((float)r->frame / r->fps));
    fprintf(f, "Ground truth: %llu surface samples, %.2f s, evaluated per %s, far-field tolerance %g. Doubling "
               "the samples:\n\n",
            (unsigned long long)final->samples, final->seconds, r->space, (double)r->truth_tolerance);
    fprintf(f, "| truth samples | seconds | SAM PSNR (dB) | SAM translucency PSNR (dB) |\n| --- | --- | --- | --- |\n");
    for (int i = 0; i < r->step_count; ++i) {
        fprintf(f, "| %llu | %.2f |", (unsigned long long)r->steps[i].samples, r->steps[i].seconds);
        md_db(f, r->steps[i].sam_psnr_db);
        md_db(f, r->steps[i].sam_psnr_normalised_db);
        fprintf(f, "\n");
    }
    fprintf(f, r->converged ? "\nThe last doubling moved SAM's scores by under %.1f dB.\n"
                            : "\n**Not converged**: the last doubling still moved SAM's scores by %.1f dB or more.\n",
            SAM_TRUTH_REPORT_CONVERGED_DB);
    fprintf(f, "\nPSNR on tonemapped 8-bit sRGB over the object's pixels; \"differing\" counts only pixels that "
               "differ from the truth (the paper's Fig. 11); translucency images are normalised by the truth's "
               "maximum (%.4g). The truth's translucency is %.3g%% of its light%s.\n\n",
            (double)r->truth_max, 100.0 * r->translucency_share,
            r->translucency_share < 0.01 ? ": the translucency scores judge a part of the picture hardly seen" : "");
    md_techniques(f, r->techniques);
    if (r->sweep_count) {
        const int flat = r->sweep[0].has_flat;
        const int cut = r->sweep[0].cut_budget != 0;
        fprintf(f, "\nSAM against the truth as the map is rebuilt with N samples per vertex (rmse_vs_samples.png); "
                   "RMSE %s monotonically%s:\n\n| N |%s build s | RMSE | translucency RMSE |%s\n| --- |%s --- | --- | --- |%s\n",
                r->monotonic ? "falls" : "does not fall",
                flat ? " (the flat map's and the flat-scaled baseline's beside it)" : "", cut ? " cut budget |" : "",
                flat ? " flat map RMSE | flat map translucency RMSE | flat-scaled RMSE | flat-scaled translucency RMSE |"
                     : "",
                cut ? " --- |" : "", flat ? " --- | --- | --- | --- |" : "");
        for (int i = 0; i < r->sweep_count; ++i) {
            fprintf(f, "| %ld |", r->sweep[i].n);
            if (cut)
                fprintf(f, " %u |", r->sweep[i].cut_budget);
            fprintf(f, " %.2f | %.4f | %.4f |", r->sweep[i].build_seconds, r->sweep[i].all.rmse,
                    r->sweep[i].normalised.rmse);
            if (flat)
                fprintf(f, " %.4f | %.4f | %.4f | %.4f |", r->sweep[i].flat_all.rmse,
                        r->sweep[i].flat_normalised.rmse, r->sweep[i].scaled_all.rmse,
                        r->sweep[i].scaled_normalised.rmse);
            fprintf(f, "\n");
        }
    }
}

/* Writes dir/name atomically with `write`. */
static sam_status write_file(const char *dir, const char *name, void (*write)(FILE *, const void *),
                             const void *what, sam_error *err)
{
    char path[4096];
    sam_atomic_file f;
    sam_status st = sam_truth_report_path(path, sizeof path, dir, name, err);
    if (st == SAM_OK)
        st = sam_atomic_open(&f, path, err);
    if (st != SAM_OK)
        return st;
    write(f.fp, what);
    return sam_atomic_commit(&f, err);
}

sam_status sam_truth_report_write(const char *dir, const sam_truth_report *report, sam_error *err)
{
    sam_status st = write_file(dir, "report.json", write_json, report, err);
    if (st == SAM_OK)
        st = write_file(dir, "report.md", write_md, report, err);
    return st;
}

void sam_truth_report_frame_dir(char *out, size_t n, long frame)
{
    snprintf(out, n, "frame_%04ld", frame);
}

/* An animation's summary, as write_file's `what`. */
typedef struct summary {
    const char *scene_path;
    float fps;
    const sam_truth_report_pose *poses;
    int count;
} summary;

/* " a / b / c |": a technique's PSNRs on differing pixels, all pixels and
 * the normalised translucency, as the README's tables give them. */
static void md_scores(FILE *f, const sam_truth_report_technique *r)
{
    if (!r->requested)
        return;
    if (!r->available) {
        fprintf(f, " unavailable |");
        return;
    }
    const double v[3] = {r->all.psnr_differing_db, r->all.psnr_db, r->normalised.psnr_db};
    for (int i = 0; i < 3; ++i)
        fprintf(f, isfinite(v[i]) ? "%s%.2f" : "%sinf", i ? " / " : " ", v[i]);
    fprintf(f, " |");
}

static void write_summary_json(FILE *f, const void *what)
{
    const summary *s = what;
    char name[32];
    fprintf(f, "{\n  \"scene\": \"%s\",\n  \"fps\": %g,\n  \"frames\": [", sam_path_basename(s->scene_path),
            (double)s->fps);
    for (int i = 0; i < s->count; ++i) {
        const sam_truth_report_pose *p = &s->poses[i];
        sam_truth_report_frame_dir(name, sizeof name, p->frame);
        fprintf(f, "%s\n    {\"frame\": %ld, \"time_s\": %.6g, \"dir\": \"%s\", \"truth_samples\": %llu, "
                   "\"truth_converged\": %s, \"techniques\": [",
                i ? "," : "", p->frame, (double)((float)p->frame / s->fps), name,
                (unsigned long long)p->truth_samples, p->converged ? "true" : "false");
        int first = 1;
        for (int t = 0; t < TECHNIQUES; ++t) {
            const sam_truth_report_technique *r = &p->techniques[t];
            if (!r->requested)
                continue;
            fprintf(f, "%s{\"name\": \"%s\", \"available\": %s", first ? "" : ", ",
                    sam_truth_report_technique_name(t), r->available ? "true" : "false");
            first = 0;
            if (r->available) {
                fprintf(f, ", \"psnr_db\": ");
                json_number(f, r->all.psnr_db);
                fprintf(f, ", \"psnr_differing_db\": ");
                json_number(f, r->all.psnr_differing_db);
                fprintf(f, ", \"psnr_translucency_db\": ");
                json_number(f, r->normalised.psnr_db);
            }
            fprintf(f, "}");
        }
        fprintf(f, "]}");
    }
    fprintf(f, "\n  ]\n}\n");
}

static void write_summary_md(FILE *f, const void *what)
{
    const summary *s = what;
    char name[32];
    fprintf(f, "# sam_compare: %s, animated\n\n", sam_path_basename(s->scene_path));
    fprintf(f, "Each frame is the pose at t = frame / %g s, played from frame 0 as `sam_render --animate` plays "
               "it (the sample walk every frame, T smoothed with dt = 1/fps), and compared against a ground truth "
               "of that pose. Each frame's images and full report are in its folder. PSNR in dB: differing "
               "pixels / all object pixels / translucency normalised by the truth's maximum.\n\n",
            (double)s->fps);
    fprintf(f, "| frame | t (s) | truth samples |");
    for (int t = 0; t < TECHNIQUES; ++t)
        if (s->poses[0].techniques[t].requested)
            fprintf(f, " %s |", sam_truth_report_technique_name(t));
    fprintf(f, "\n| --- | --- | --- |");
    for (int t = 0; t < TECHNIQUES; ++t)
        if (s->poses[0].techniques[t].requested)
            fprintf(f, " --- |");
    fprintf(f, "\n");
    for (int i = 0; i < s->count; ++i) {
        const sam_truth_report_pose *p = &s->poses[i];
        sam_truth_report_frame_dir(name, sizeof name, p->frame);
        fprintf(f, "| [%ld](%s/report.md) | %.4g | %llu%s |", p->frame, name, (double)((float)p->frame / s->fps),
                (unsigned long long)p->truth_samples, p->converged ? "" : " (not converged)");
        for (int t = 0; t < TECHNIQUES; ++t)
            md_scores(f, &p->techniques[t]);
        fprintf(f, "\n");
    }
}

sam_status sam_truth_report_write_summary(const char *dir, const char *scene_path, float fps,
                                          const sam_truth_report_pose *poses, int count, sam_error *err)
{
    const summary s = {scene_path, fps, poses, count};
    sam_status st = write_file(dir, "report.json", write_summary_json, &s, err);
    if (st == SAM_OK)
        st = write_file(dir, "report.md", write_summary_md, &s, err);
    return st;
}

/* Runs gnuplot on `script`. */
static sam_status run_gnuplot(const char *script, const char *dat, sam_error *err)
{
    pid_t pid = fork();
    if (pid == 0) {
        execlp("gnuplot", "gnuplot", script, (char *)NULL);
        _exit(127);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) < 0)
        return sam_fail(err, SAM_ERR_IO, "could not run gnuplot: %s", strerror(errno));
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return sam_fail(err, SAM_ERR_IO,
                        WIFEXITED(status) && WEXITSTATUS(status) == 127
                            ? "gnuplot is not installed (scripts/deps.sh installs gnuplot-nox); %s and %s are written"
                            : "gnuplot failed on %s (data in %s)",
                        script, dat);
    return SAM_OK;
}

sam_status sam_truth_report_plot_sweep(const char *dir, const char *mesh_path,
                                       const sam_truth_report_sweep_point *sweep, int count, sam_error *err)
{
    char dat[4096], script[4096], png[4096];
    sam_status st = sam_truth_report_path(dat, sizeof dat, dir, "sweep.dat", err);
    if (st == SAM_OK)
        st = sam_truth_report_path(script, sizeof script, dir, "sweep.gnuplot", err);
    if (st == SAM_OK)
        st = sam_truth_report_path(png, sizeof png, dir, "rmse_vs_samples.png", err);
    if (st != SAM_OK)
        return st;
    sam_atomic_file f;
    if ((st = sam_atomic_open(&f, dat, err)) != SAM_OK)
        return st;
    const int flat = count > 0 && sweep[0].has_flat;
    /* The x axis says what N is: all of a cut, or fitted from a larger one. */
    int whole = count > 0 && sweep[0].cut_budget != 0;
    for (int i = 0; i < count; ++i)
        whole = whole && sweep[i].cut_budget == (uint32_t)sweep[i].n;
    const char *xlabel = !flat    ? "back-side samples per vertex N"
                         : whole ? "cut budget = back-side samples per vertex N (the whole cut stored)"
                                 : "back-side samples per vertex N (of a cut of the larger of N and 32)";
    fprintf(f.fp, "# N rmse rmse_translucency%s (8-bit levels)\n",
            flat ? " flat_rmse flat_rmse_translucency flat_scaled_rmse flat_scaled_rmse_translucency" : "");
    for (int i = 0; i < count; ++i) {
        fprintf(f.fp, "%ld %.6f %.6f", sweep[i].n, sweep[i].all.rmse, sweep[i].normalised.rmse);
        if (flat)
            fprintf(f.fp, " %.6f %.6f %.6f %.6f", sweep[i].flat_all.rmse, sweep[i].flat_normalised.rmse,
                    sweep[i].scaled_all.rmse, sweep[i].scaled_normalised.rmse);
        fprintf(f.fp, "\n");
    }
    if ((st = sam_atomic_commit(&f, err)) != SAM_OK)
        return st;
    if ((st = sam_atomic_open(&f, script, err)) != SAM_OK)
        return st;
    /* gnuplot writes the PNG itself; a temporary name keeps a failed run
     * from leaving half a picture. */
    fprintf(f.fp,
            "set terminal pngcairo size 800,500 noenhanced\nset output '%s.tmp'\n"
            "set title 'SAM against the ground truth (%s)'\nset xlabel '%s'\n"
            "set ylabel 'RMSE (8-bit sRGB levels)'\nset grid\nset key top right\n"
            "plot '%s' using 1:2 with linespoints lw 2 title 'full shading', '' using 1:3 with linespoints lw 2 "
            "title 'translucency (normalised)'%s\n",
            png, sam_path_basename(mesh_path ? mesh_path : "scene"), xlabel, dat,
            flat ? ", '' using 1:4 with linespoints lw 2 dt 2 title 'full shading, flat map', '' using 1:5 with "
                   "linespoints lw 2 dt 2 title 'translucency, flat map', '' using 1:6 with linespoints lw 2 dt 3 "
                   "title 'full shading, flat-scaled', '' using 1:7 with linespoints lw 2 dt 3 title "
                   "'translucency, flat-scaled'"
                 : "");
    if ((st = sam_atomic_commit(&f, err)) != SAM_OK || (st = run_gnuplot(script, dat, err)) != SAM_OK)
        return st;
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", png);
    if (rename(tmp, png) != 0)
        return sam_fail(err, SAM_ERR_IO, "%s: %s", png, strerror(errno));
    return SAM_OK;
}

sam_status sam_truth_report_check_dir(const char *dir, int force, sam_error *err)
{
    struct stat sb;
    if (stat(dir, &sb) != 0)
        return errno == ENOENT ? SAM_OK : sam_fail(err, SAM_ERR_IO, "%s: %s", dir, strerror(errno));
    if (!S_ISDIR(sb.st_mode))
        return sam_fail(err, SAM_ERR_IO, "%s is not a directory", dir);
    char report[4096];
    sam_status st = sam_truth_report_path(report, sizeof report, dir, "report.json", err);
    if (st == SAM_OK && !force && access(report, F_OK) == 0)
        st = sam_fail(err, SAM_ERR_IO, "%s already holds a report (report.json); give --force to overwrite it", dir);
    return st;
}

sam_status sam_truth_report_make_dir(const char *dir, sam_error *err)
{
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return sam_fail(err, SAM_ERR_IO, "cannot create %s: %s", dir, strerror(errno));
    return SAM_OK;
}
