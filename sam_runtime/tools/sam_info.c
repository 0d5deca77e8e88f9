/*
 * sam_info: validates meshes and .sam files and prints a summary of each, or
 * one error line. Exit status: 0 all valid, 1 some file invalid, 2 usage.
 */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "sam/sam_app_scene.h"
#include "sam/sam_args.h"
#include "sam/sam_gl.h"
#include "sam/sam_mesh.h"
#include "sam/sam_profile.h"
#include "sam/sam_runtime_scene.h"
#include "sam/sam_scene.h"
#include "sam/samfile.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_info [--mm-per-unit X] FILE...\n"
            "\n"
            "Validates each FILE and prints its summary, or one error line naming what is wrong.\n"
            "  FILE  a .sam file (from sam_build), a mesh (.obj, .ply ASCII or binary, .off, .stl, .gltf,\n"
            "        .glb), a scene (.json with a \"mesh\" or \"sam\" key) or a material profile (.json, .txt)\n"
            "\n"
            "options:\n"
            "  --mm-per-unit X  scale used to print a mesh's fan areas in mm^2 (default 1)\n"
            "  -h, --help       show this help\n"
            "\n"
            "exit status: 0 when every file is valid, 1 when one is not, 2 on bad usage\n"
            "\n"
            "examples:\n"
            "  sam_info ear.sam\n"
            "  sam_info meshes/ear.obj scenes/ear_backlit.json --mm-per-unit 60\n");
}

/* The bounds, and the loose specks outside the object's body that
 * --size-mm leaves out (sam_mesh_body). */
static void print_bounds(const float *pos, uint32_t count, const uint32_t *triangles, uint32_t triangle_count)
{
    const sam_mesh view = {
        .vertex_count = count, .positions = (float *)pos, .triangle_count = triangle_count,
        .triangles = (uint32_t *)triangles};
    float lo[3], hi[3];
    sam_mesh_bounds(&view, lo, hi);
    printf("  bounds:            (%g, %g, %g) .. (%g, %g, %g), diagonal %g units\n", lo[0], lo[1], lo[2],
           hi[0], hi[1], hi[2], sam_mesh_box_diagonal(lo, hi));
    sam_mesh_body_info body;
    if (sam_mesh_body(&view, NULL, &body, NULL) == SAM_OK && body.box_changed)
        printf("  loose specks:      %u piece%s (%u vertices, %.2g%% of the surface) outside the object; its size "
               "(--size-mm) is the diagonal %g units\n",
               body.loose_pieces, body.loose_pieces == 1 ? "" : "s", body.loose_vertices,
               100.0 * body.loose_area / body.total_area, sam_mesh_box_diagonal(body.min, body.max));
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
    if (sam_mesh_precision_warning(&m, NULL, summary, sizeof summary))
        printf("  precision:         %s\n", summary);
    if (!rep.boundary_vertices && sam_mesh_signed_volume(&m) < 0)
        printf("  orientation:       closed and facing inward (negative volume): sam_build and sam_render turn it "
               "outside out\n");
    print_bounds(m.positions, m.vertex_count, m.triangles, m.triangle_count);
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

static int info_sam(const char *path)
{
    samfile_data d;
    sam_error err;
    if (samfile_read(path, &d, &err) != SAM_OK) {
        fprintf(stderr, "sam_info: %s\n", err.message);
        return 1;
    }
    uint32_t n = d.samples_per_vertex, empty = 0;
    uint64_t valid = 0, nodes = 0;
    for (uint32_t v = 0; v < d.vertex_count; ++v) {
        uint32_t k = 0;
        for (; k < n && d.sample_index[(size_t)v * n + k] != SAMFILE_NO_SAMPLE; ++k)
            nodes += d.sample_index[(size_t)v * n + k] >= d.vertex_count;
        valid += k;
        empty += k == 0;
    }
    printf("%s: SAM v%u\n", path, d.node_count ? 2u : 1u);
    printf("  vertices:          %u\n", d.vertex_count);
    printf("  triangles:         %u\n", d.triangle_count);
    printf("  samples per vertex: %u (mean %.2f used; %u vertices without back-side samples)\n", n,
           d.vertex_count ? (double)valid / d.vertex_count : 0.0, empty);
    if (d.node_count)
        printf("  tree nodes:        %u (%.1f%% of the samples used; the rest are vertices)\n", d.node_count,
               valid ? 100.0 * (double)nodes / (double)valid : 0.0);
    printf("  attributes:        %s\n", d.uvs ? "UVs" : "no UVs");
    printf("  adjacency entries: %u\n", d.adjacency_count);
    if (d.unknown_chunk_count)
        printf("  unknown chunks:    %u (skipped)\n", d.unknown_chunk_count);
    print_bounds(d.positions, d.vertex_count, d.triangles, d.triangle_count);
    print_range("fan area:", d.fan_area, d.vertex_count, " mm^2");
    samfile_info_print(&d, stdout);
    samfile_free(&d);
    return 0;
}

static int info_scene(const char *path)
{
    sam_scene scene;
    sam_error err;
    if (sam_scene_load(path, &scene, &err) != SAM_OK) {
        fprintf(stderr, "sam_info: %s\n", err.message);
        return 1;
    }
    /* sam_render's one check beyond the scene's own, before any work:
     * whether the GL holds the picture. Without a GL it cannot be made. */
    sam_gl_context *gl = NULL;
    char gl_note[SAM_ERROR_MESSAGE_SIZE + 32] = "";
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK)
        snprintf(gl_note, sizeof gl_note, "not checked (%s)", err.message);
    else if (sam_gl_check_picture_size(scene.width, scene.height, &err) != SAM_OK) {
        sam_gl_context_destroy(gl);
        sam_scene_destroy(&scene);
        fprintf(stderr, "sam_info: %s: %s\n", path, err.message);
        return 1;
    }
    sam_gl_context_destroy(gl);
    if (sam_runtime_scene_check_keyframes(&scene, &err) != SAM_OK) {
        sam_scene_destroy(&scene);
        fprintf(stderr, "sam_info: %s\n", err.message);
        return 1;
    }
    /* A prebuilt map is read as sam_render reads it: checked against the
     * mesh, its material and scale resolved. */
    sam_profile map_profile;
    float map_mm = 0;
    if (scene.sam_path) {
        samfile_data sam;
        if (sam_app_scene_object(&scene, "sam_info", NULL, NULL, NULL, &sam, &map_profile, &map_mm, NULL, &err) !=
            SAM_OK) {
            sam_scene_destroy(&scene);
            fprintf(stderr, "sam_info: %s: %s\n", path, err.message);
            return 1;
        }
        samfile_free(&sam);
    }
    printf("%s: scene\n", path);
    printf("  object:            %s\n", scene.mesh_path ? scene.mesh_path : scene.sam_path);
    if (scene.mesh_path && scene.sam_path)
        printf("  map:               %s (prebuilt)\n", scene.sam_path);
    if (scene.material)
        printf("  material:          %s\n", scene.material);
    else
        printf("  material:          %s (from the .sam)\n", map_profile.name);
    if (scene.scale_kind == SAM_SCALE_MM_PER_UNIT)
        printf("  scale:             %g mm per unit\n", scene.scale_value);
    else if (scene.scale_kind == SAM_SCALE_SIZE_MM)
        printf("  scale:             %g mm diagonal\n", scene.scale_value);
    else
        printf("  scale:             %g mm per unit (from the .sam)\n", (double)map_mm);
    if (scene.sam_path && scene.scale_kind == SAM_SCALE_SIZE_MM)
        printf("                     %g mm per unit on the map's positions\n", (double)map_mm);
    size_t count[4] = {0, 0, 0, 0};
    for (size_t i = 0; i < scene.light_count; ++i)
        count[scene.lights[i].type]++;
    printf("  lights:            %zu (%zu point, %zu spot, %zu directional, %zu area)\n", scene.light_count,
           count[SAM_LIGHT_POINT], count[SAM_LIGHT_SPOT], count[SAM_LIGHT_DIRECTIONAL], count[SAM_LIGHT_AREA]);
    printf("  environment:       %s\n", scene.environment.map ? scene.environment.map : "none");
    printf("  camera:            %s\n", scene.has_camera ? "given" : "framed automatically");
    if (scene.keyframe_count)
        printf("  keyframes:         %zu, each of the rest mesh's topology\n", scene.keyframe_count);

    printf("  output:            %ux%u, technique %s, diffusion %s, tonemap %s, exposure %g EV\n",
           scene.width, scene.height, sam_technique_name(scene.technique), sam_diffusion_name(scene.diffusion),
           sam_tonemap_name(scene.tonemap), scene.exposure);
    if (gl_note[0])
        printf("  GL:                %s\n", gl_note);
    sam_scene_destroy(&scene);
    return 0;
}

static int info_profile(const char *path)
{
    sam_profile profile;
    sam_gaussian_fit fit;
    sam_error err;
    if (sam_profile_load(path, &profile, &err) != SAM_OK ||
        sam_profile_fit_gaussians(&profile, &fit, &err) != SAM_OK) {
        fprintf(stderr, "sam_info: %s\n", err.message);
        return 1;
    }
    float total[3];
    sam_profile_total_reflectance(&profile, total);
    printf("%s: material profile \"%s\" (%s)\n", path, profile.name,
           profile.kind == SAM_PROFILE_DIPOLE ? "dipole" : "sum of Gaussians");
    printf("  total reflectance: (%.4f, %.4f, %.4f)\n", total[0], total[1], total[2]);
    printf("  radius:            %.3f mm holds 99%%, %.3f mm holds 99.9%% of the energy\n",
           sam_profile_radius(&profile, 0.01f), sam_profile_radius(&profile, 0.001f));
    const float *source = profile.fit_source_error;
    if (source[0] > 0 || source[1] > 0 || source[2] > 0)
        printf("  fitted to its source (a burley or table material): at most %.2f%%, %.2f%%, %.2f%% of the energy "
               "lands at another radius\n",
               100 * source[0], 100 * source[1], 100 * source[2]);
    printf("  8-Gaussian fit:    error %.3f%%, %.3f%%, %.3f%% (d'Eon eq. 10)\n",
           100 * sam_profile_fit_error(&profile, &fit, 0), 100 * sam_profile_fit_error(&profile, &fit, 1),
           100 * sam_profile_fit_error(&profile, &fit, 2));
    return 0;
}

/* A .json file is a material profile when it says its type ("type" or
 * "kind", which every profile needs) or has a key only profiles have, else
 * a scene, which the scene loader checks as sam_render does (a scene
 * without "mesh" or "sam" included). */
static int is_scene(const char *path)
{
    static const char *const profile_keys[] = {"type",      "kind",           "gaussians",      "sigma_s_prime",
                                               "sigma_a",   "eta",            "mean_free_path", "scatter_radius",
                                               "radius_mm", "rd"};
    uint8_t *text;
    size_t size;
    if (sam_read_file(path, &text, &size, NULL) != SAM_OK)
        return 1; /* let the scene loader report the I/O error */
    cJSON *root = cJSON_ParseWithLength((const char *)text, size);
    int scene = 1;
    for (size_t i = 0; root && i < sizeof profile_keys / sizeof *profile_keys; ++i)
        scene &= !cJSON_HasObjectItem(root, profile_keys[i]);
    cJSON_Delete(root);
    free(text);
    return scene;
}

int main(int argc, char **argv)
{
    float mm_per_unit = 1.0f;
    const char *paths[256] = {0};
    const sam_arg args[] = {
        {"--mm-per-unit", SAM_ARG_FLOAT, &mm_per_unit, .lo = 0, .hi = FLT_MAX, .lo_open = 1,
         .must = "a positive number"},
    };
    const sam_args_spec spec = {"sam_info", args, 1, paths, 1, sizeof paths / sizeof *paths, "FILE", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    int files = 0, failed = 0;
    for (; files < (int)(sizeof paths / sizeof *paths) && paths[files]; ++files) {
        const char *f = paths[files];
        if (sam_path_has_extension(f, ".sam"))
            failed |= info_sam(f);
        else if (sam_path_has_extension(f, ".json"))
            failed |= is_scene(f) ? info_scene(f) : info_profile(f);
        else if (sam_path_has_extension(f, ".txt"))
            failed |= info_profile(f);
        else
            failed |= info_mesh(f, mm_per_unit);
    }
    return failed ? 1 : 0;
}
