/* sam_build's job (sam_app_build.h). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <string.h>

#include "sam/sam_app.h"
#include "sam/sam_app_build.h"
#include "sam/sam_app_output.h"
#include "sam/sam_sha256.h"

void sam_app_build_defaults(sam_app_build_job *job)
{
    memset(job, 0, sizeof *job);
    job->mm_per_unit = job->size_mm = NAN;
    sam_build_default_settings(&job->settings);
}

/* What can be refused before any work: the scale, the settings, the
 * material, an output that exists or cannot be written. Returns the exit
 * code, 0 to go on. */
static int check_job(const sam_app_build_job *job, const char *tool, sam_profile *profile)
{
    if (isnan(job->mm_per_unit) == isnan(job->size_mm)) {
        fprintf(stderr, "%s: give exactly one of --mm-per-unit and --size-mm\n", tool);
        return 2;
    }
    if (!isnan(job->size_mm) && !(job->size_mm > 0)) {
        fprintf(stderr, "%s: --size-mm must be > 0, got %g\n", tool, job->size_mm);
        return 2;
    }
    sam_error err;
    float scale_check = isnan(job->mm_per_unit) ? 1.0f : job->mm_per_unit;
    if (sam_build_check_settings(&job->settings, scale_check, &err) != SAM_OK) {
        fprintf(stderr, "%s: %s\n", tool, err.message);
        return 2;
    }
    if (sam_profile_from_spec(job->material, profile, &err) != SAM_OK) {
        fprintf(stderr, "%s: --material: %s\n", tool, err.message);
        return 1;
    }
    /* Fail on an output that cannot be written now, not after a long
     * build: a folder in its place failed only at the final rename. */
    static const char *const extensions[] = {".sam", NULL};
    if (sam_app_check_output("-o", job->out_path, extensions, job->force, &err) != SAM_OK) {
        fprintf(stderr, "%s: %s\n", tool, err.message);
        return 1;
    }
    return 0;
}

/* The mesh, repaired, and its scale in mm per unit. Returns the exit code. */
static int load_mesh(const sam_app_build_job *job, const char *tool, sam_mesh *mesh, float *mm_per_unit)
{
    sam_error err;
    sam_mesh_report report;
    if (sam_mesh_load(job->mesh_path, mesh, &report, &err) != SAM_OK) {
        fprintf(stderr, "%s: %s\n", tool, err.message);
        return 1;
    }
    char summary[512];
    sam_mesh_report_summary(&report, summary, sizeof summary);
    if (strcmp(summary, "no repairs"))
        fprintf(stderr, "%s: %s: %s\n", tool, job->mesh_path, summary);
    if (sam_mesh_precision_warning(mesh, job->mesh_path, summary, sizeof summary))
        fprintf(stderr, "%s: warning: %s\n", tool, summary);
    if (!job->keep_orientation && sam_mesh_orient_outward(mesh))
        fprintf(stderr, "%s: warning: %s is closed and faces inward (negative volume): turned outside out "
                        "(--keep-orientation keeps it)\n", tool, job->mesh_path);
    *mm_per_unit = job->mm_per_unit;
    if (!isnan(job->size_mm)) {
        /* Measured once for the size and the line on what it leaves out. */
        sam_mesh_body_info body;
        const int measured = sam_mesh_body(mesh, NULL, &body, NULL) == SAM_OK;
        const double diag = measured ? sam_mesh_box_diagonal(body.min, body.max) : sam_mesh_diagonal(mesh);
        if (!(diag > 0)) {
            fprintf(stderr, "%s: %s: the mesh has no extent, so --size-mm cannot scale it\n", tool, job->mesh_path);
            sam_mesh_destroy(mesh);
            return 1;
        }
        *mm_per_unit = (float)(job->size_mm / diag);
        if (measured && body.box_changed)
            fprintf(stderr,
                    "%s: %s: --size-mm measures the object without %u loose piece%s (%u vertices, %.2g%% of the "
                    "surface) outside it\n",
                    tool, job->mesh_path, body.loose_pieces, body.loose_pieces == 1 ? "" : "s", body.loose_vertices,
                    100.0 * body.loose_area / body.total_area);
    }
    return 0;
}

/* One line on what was written: samples per vertex used, vertices with none, time. */
static void print_summary(const char *tool, const char *path, const samfile_data *data, const sam_build_result *result)
{
    uint64_t used = 0, empty = 0;
    const uint32_t n = data->samples_per_vertex;
    for (uint32_t v = 0; v < data->vertex_count; ++v) {
        uint32_t k = 0;
        while (k < n && data->sample_index[(size_t)v * n + k] != SAMFILE_NO_SAMPLE)
            ++k;
        used += k;
        empty += k == 0;
    }
    const double vertices = data->vertex_count ? data->vertex_count : 1;
    fprintf(stderr,
            "%s: wrote %s: %u vertices, %.2f back-side samples per vertex (%.1f%% have none), "
            "%.2f s (%.2f us per vertex)\n",
            tool, path, data->vertex_count, (double)used / vertices, 100.0 * (double)empty / vertices,
            result->seconds, 1e6 * result->seconds / vertices);
}

/* Hands the heap's free pages back to the system. The mesh readers
 * (OpenMesh, TinyGLTF) free about twice the mesh's size in small blocks,
 * and the build its tree and scratch, which glibc keeps resident: trimmed
 * after each, they stay out of the peak that the next step's arrays set
 * (on a 39k-vertex knot 56 MB became 44 MB with the result's arrays made
 * at their final size; docs/performance.md). */
static void return_free_memory(void)
{
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

int sam_app_build_run(const sam_app_build_job *job, const char *tool)
{
    sam_profile profile;
    float mm_per_unit;
    sam_mesh mesh;
    int code = check_job(job, tool, &profile);
    if (code || (code = load_mesh(job, tool, &mesh, &mm_per_unit)) != 0)
        return code;
    return_free_memory();
    code = 1;
    sam_error err;
    char sha[65];
    sam_app_progress view;
    sam_app_progress_init(&view, tool, job->quiet, job->cancel);
    sam_build_context *ctx = NULL;
    sam_build_result result;
    memset(&result, 0, sizeof result);
    samfile_data data;
    memset(&data, 0, sizeof data);
    if (sam_sha256_file(job->mesh_path, sha, &err) != SAM_OK ||
        sam_build_context_create(&mesh, &profile, mm_per_unit, &job->settings, &ctx, &err) != SAM_OK)
        goto done;
    view.start = sam_seconds();
    if (!job->quiet)
        fprintf(stderr, "%s: %s: %u vertices (%u welded), %s at %g mm per unit, %s map, N=%u, search radius %.3g mm\n",
                tool, job->mesh_path, mesh.vertex_count, mesh.topo_count, profile.name, mm_per_unit,
                sam_build_map_name(job->settings.map),
                sam_build_samples(&job->settings), sam_profile_radius(&profile, job->settings.radius_tolerance));
    if (sam_build_run(ctx, sam_app_progress_update, &view, &result, &err) != SAM_OK)
        goto done;
    return_free_memory();
    sam_build_source source = {job->mesh_path, sha};
    if (sam_build_move_to_samfile(ctx, &result, &source, &data, &err) != SAM_OK ||
        samfile_write(job->out_path, &data, &err) != SAM_OK)
        goto done;
    print_summary(tool, job->out_path, &data, &result);
    char why[1024];
    if (sam_build_explain_empty(&data, mm_per_unit, sam_profile_radius(&profile, job->settings.radius_tolerance),
                                job->mesh_path, why, sizeof why) ||
        sam_build_explain_small(&data, mm_per_unit, sam_profile_radius(&profile, 0.99f), job->mesh_path, why,
                                sizeof why))
        fprintf(stderr, "%s: warning: %s\n", tool, why);
    code = 0;
done:
    if (code)
        fprintf(stderr, "%s%s: %s\n", view.open_line ? "\n" : "", tool,
                job->cancel && *job->cancel ? "interrupted; no output written" : err.message);
    samfile_free(&data);
    sam_build_result_destroy(&result);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
    return code;
}
