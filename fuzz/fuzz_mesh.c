/*
 * libFuzzer target for the mesh loader. OpenMesh and TinyGLTF read from
 * files, so each input is written to a private temporary file; its first
 * byte picks the extension (and so the reader: 0 OBJ, 1 PLY, 2 OFF, 3 STL,
 * 4 glTF, 5 GLB, modulo 6) and the rest is the content.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "sam/sam_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const ext[] = {"obj", "ply", "off", "stl", "gltf", "glb"};
    if (size < 1)
        return 0;
    char path[256];
    snprintf(path, sizeof path, "/tmp/sam_fuzz_mesh_%ld.%s", (long)getpid(), ext[data[0] % 6]);
    FILE *fp = fopen(path, "wb");
    if (!fp)
        abort();
    if (size > 1 && fwrite(data + 1, 1, size - 1, fp) != size - 1)
        abort();
    fclose(fp);
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
        sam_mesh_destroy(&mesh);
    }
    remove(path);
    return 0;
}
