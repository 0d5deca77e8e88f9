/*
 * libFuzzer target for the mesh loader. OpenMesh and TinyGLTF read from
 * files, so each input is written to a private temporary file; its first
 * byte picks the extension (and so the reader: 0 OBJ, 1 PLY, 2 OFF, 3 STL,
 * 4 glTF, 5 GLB, modulo 6) and the rest is the content. The albedo, albedo
 * maps and vertex colour readers take the same file: a glTF's embedded
 * images reach stb_image through them; every face must read a map there
 * is, every colour come out in [0, 1].
 */
#include "fuzz_input_file.h"

#include <stdlib.h>

#include "sam/sam_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const ext[] = {"obj", "ply", "off", "stl", "gltf", "glb"};
    char path[256];
    if (!fuzz_input_file(data, size, "fuzz_mesh", ext, 6, path, sizeof path))
        return 0;
    sam_mesh mesh;
    sam_mesh_report report;
    sam_error err;
    if (sam_mesh_load(path, &mesh, &report, &err) == SAM_OK) {
        float *area = malloc(mesh.topo_count * sizeof *area);
        if (!area)
            abort();
        sam_mesh_fan_areas(&mesh, NULL, 1.0f, area);
        sam_mesh_mean_curvature(&mesh, area);
        free(area);
        char warning[256];
        sam_mesh_precision_warning(&mesh, path, warning, sizeof warning);
        /* Whatever the loader let through must solidify, or be refused
         * with a status: never a crash. */
        sam_shape_mesh solid;
        if (sam_mesh_solidify(&mesh, (float)(0.01 * sam_mesh_diagonal(&mesh)), &solid, NULL, &err) == SAM_OK)
            sam_shape_mesh_destroy(&solid);
        sam_mesh_destroy(&mesh);
    }
    sam_image albedo;
    char note[2304];
    if (sam_mesh_load_albedo(path, &albedo, note, sizeof note, &err) == SAM_OK) {
        if (albedo.pixels && (albedo.width == 0 || albedo.height == 0))
            abort();
        sam_image_destroy(&albedo);
    }
    sam_albedo_maps maps;
    if (sam_mesh_load_albedo_maps(path, &maps, note, sizeof note, &err) == SAM_OK) {
        for (uint32_t f = 0; f < maps.face_count; ++f)
            if (maps.face_map[f] >= maps.map_count && maps.face_map[f] != SAM_ALBEDO_NO_MAP)
                abort();
        sam_albedo_maps_destroy(&maps);
    }
    float *colors = NULL;
    uint32_t color_count = 0;
    if (sam_mesh_load_vertex_colors(path, &colors, &color_count, note, sizeof note, &err) == SAM_OK) {
        for (size_t i = 0; i < 3 * (size_t)color_count; ++i)
            if (!(colors[i] >= 0.0f && colors[i] <= 1.0f))
                abort();
        free(colors);
    }
    remove(path);
    return 0;
}
