/*
 * sam_info: validates meshes and .sam files and prints a summary of each, or
 * one error line. Exit status: 0 all valid, 1 some file invalid, 2 usage.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "sam/sam_mesh.h"
#include "sam/samfile.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_info [--mm-per-unit X] FILE...\n"
            "\n"
            "Validates each FILE and prints its summary, or one error line naming what is wrong.\n"
            "  FILE  a .sam file (from sam_build) or a mesh: .obj, .ply (ASCII or binary), .off, .stl\n"
            "\n"
            "options:\n"
            "  --mm-per-unit X  scale used to print a mesh's fan areas in mm^2 (default 1)\n"
            "  -h, --help       show this help\n"
            "\n"
            "exit status: 0 when every file is valid, 1 when one is not, 2 on bad usage\n");
}

static void print_bounds(const float *pos, uint32_t count)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < count; ++v)
        for (int i = 0; i < 3; ++i) {
            lo[i] = fminf(lo[i], pos[3 * (size_t)v + i]);
            hi[i] = fmaxf(hi[i], pos[3 * (size_t)v + i]);
        }
    double d = sqrt((double)(hi[0] - lo[0]) * (hi[0] - lo[0]) + (double)(hi[1] - lo[1]) * (hi[1] - lo[1]) +
                    (double)(hi[2] - lo[2]) * (hi[2] - lo[2]));
    printf("  bounds:            (%g, %g, %g) .. (%g, %g, %g), diagonal %g units\n", lo[0], lo[1], lo[2],
           hi[0], hi[1], hi[2], d);
}

static void print_range(const char *label, const float *v, uint32_t n, const char *unit)
{
    double lo = INFINITY, hi = -INFINITY, sum = 0;
    for (uint32_t i = 0; i < n; ++i) {
        lo = fmin(lo, v[i]);
        hi = fmax(hi, v[i]);
        sum += v[i];
    }
    printf("  %-18s min %g, mean %g, max %g%s\n", label, lo, n ? sum / n : 0.0, hi, unit);
}

static int info_mesh(const char *path, float mm_per_unit)
{
    sam_mesh m;
    sam_mesh_report rep;
    sam_error err;
    if (sam_mesh_load(path, &m, &rep, &err) != SAM_OK) {
        fprintf(stderr, "sam_info: %s\n", err.message);
        return 1;
    }
    char summary[512];
    printf("%s: mesh\n", path);
    printf("  triangles:         %u\n", m.triangle_count);
    printf("  render vertices:   %u (%u in the file)\n", m.vertex_count, rep.file_vertices);
    printf("  welded vertices:   %u (%u on UV/normal seams, %u on boundaries)\n", m.topo_count,
           rep.seam_vertices, rep.boundary_vertices);
    printf("  attributes:        %s, normals %s\n", m.uvs ? "UVs" : "no UVs",
           rep.normals_from_file ? "from the file" : "computed (area-weighted)");
    printf("  repairs:           %s\n", sam_mesh_report_summary(&rep, summary, sizeof summary));
    print_bounds(m.positions, m.vertex_count);
    float *values = malloc((size_t)m.topo_count * sizeof *values);
    if (!values) {
        fprintf(stderr, "sam_info: %s: out of memory\n", path);
        sam_mesh_destroy(&m);
        return 1;
    }
    sam_mesh_fan_areas(&m, NULL, mm_per_unit, values);
    print_range("fan area:", values, m.topo_count, mm_per_unit == 1.0f ? " units^2" : " mm^2");
    sam_mesh_mean_curvature(&m, values);
    print_range("mean curvature:", values, m.topo_count, " 1/units");
    free(values);
    sam_mesh_destroy(&m);
    return 0;
}

static void print_json_value(const cJSON *item)
{
    char *text = cJSON_PrintUnformatted(item);
    if (!text)
        return;
    /* Strings print bare; objects and arrays as compact JSON. */
    if (cJSON_IsString(item))
        printf("%s", item->valuestring);
    else
        printf("%s", text);
    cJSON_free(text);
}

static int info_sam(const char *path)
{
    samfile_data d;
    sam_error err;
    if (samfile_read(path, &d, &err) != SAM_OK) {
        fprintf(stderr, "sam_info: %s\n", err.message);
        return 1;
    }
    uint32_t n = d.samples_per_vertex, empty = 0;
    uint64_t valid = 0;
    for (uint32_t v = 0; v < d.vertex_count; ++v) {
        uint32_t k = 0;
        while (k < n && d.sample_index[(size_t)v * n + k] != SAMFILE_NO_SAMPLE)
            ++k;
        valid += k;
        empty += k == 0;
    }
    printf("%s: SAM v1\n", path);
    printf("  vertices:          %u\n", d.vertex_count);
    printf("  triangles:         %u\n", d.triangle_count);
    printf("  samples per vertex: %u (mean %.2f used; %u vertices without back-side samples)\n", n,
           d.vertex_count ? (double)valid / d.vertex_count : 0.0, empty);
    printf("  attributes:        %s\n", d.uvs ? "UVs" : "no UVs");
    printf("  adjacency entries: %u\n", d.adjacency_count);
    if (d.unknown_chunk_count)
        printf("  unknown chunks:    %u (skipped)\n", d.unknown_chunk_count);
    print_bounds(d.positions, d.vertex_count);
    print_range("fan area:", d.fan_area, d.vertex_count, " mm^2");
    /* INFO is validated JSON; print every key so new build settings show up. */
    cJSON *info = cJSON_Parse(d.info_json);
    if (info) {
        for (const cJSON *item = info->child; item; item = item->next) {
            if (!strcmp(item->string, "vertex_count") || !strcmp(item->string, "triangle_count") ||
                !strcmp(item->string, "samples_per_vertex"))
                continue;
            printf("  %-18s ", item->string);
            print_json_value(item);
            printf("\n");
        }
        cJSON_Delete(info);
    }
    samfile_free(&d);
    return 0;
}

int main(int argc, char **argv)
{
    float mm_per_unit = 1.0f;
    int files = 0, failed = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            usage(stdout);
            return 0;
        }
        if (!strcmp(argv[i], "--mm-per-unit")) {
            char *end = NULL;
            if (i + 1 >= argc || !((mm_per_unit = strtof(argv[i + 1], &end)) > 0) || *end ||
                !isfinite(mm_per_unit)) {
                fprintf(stderr, "sam_info: --mm-per-unit needs a positive number, got \"%s\"\n",
                        i + 1 < argc ? argv[i + 1] : "");
                return 2;
            }
            ++i;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            fprintf(stderr, "sam_info: unknown option \"%s\" (see --help)\n", argv[i]);
            return 2;
        }
    }
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--mm-per-unit")) {
            ++i;
            continue;
        }
        ++files;
        failed |= sam_path_has_extension(argv[i], ".sam") ? info_sam(argv[i])
                                                           : info_mesh(argv[i], mm_per_unit);
    }
    if (!files) {
        usage(stderr);
        return 2;
    }
    return failed ? 1 : 0;
}
