/*
 * Differential libFuzzer target: the pre-check (sam_mesh_preflight) and
 * OpenMesh's readers must agree on what a file holds. For every input the
 * pre-check accepts with known counts and OpenMesh reads, the vertices and
 * faces OpenMesh delivered must be the pre-check's; a disagreement is a
 * file that would be read other than as written, and aborts. The first
 * byte picks the extension (0 OBJ, 1 PLY, 2 OFF, 3 STL, modulo 4), as in
 * fuzz_mesh; the rest is the content.
 */
#include "fuzz_input_file.h"

#include <stdio.h>
#include <stdlib.h>

#include "sam_mesh_soup.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const ext[] = {"obj", "ply", "off", "stl"};
    char path[256];
    if (!fuzz_input_file(data, size, "fuzz_mesh_counts", ext, 4, path, sizeof path))
        return 0;
    sam_mesh_expect expect;
    sam_mesh_soup soup;
    sam_error err;
    if (sam_mesh_preflight(path, &expect, &err) == SAM_OK && expect.known &&
        sam_mesh_soup_read(path, expect.rewritten, expect.rewritten_size, expect.rewritten_extension, &soup, &err) ==
            SAM_OK) {
        if (soup.vertex_count != expect.vertices || soup.face_count != expect.faces) {
            fprintf(stderr, "fuzz_mesh_counts: the pre-check counts %llu vertices and %llu faces, OpenMesh read %u "
                            "and %u\n",
                    (unsigned long long)expect.vertices, (unsigned long long)expect.faces, soup.vertex_count,
                    soup.face_count);
            abort();
        }
        float *normals = NULL;
        (void)sam_mesh_expect_corner_normals(&expect, &soup, &normals, &err);
        free(normals);
        sam_mesh_soup_free(&soup);
    }
    sam_mesh_expect_free(&expect);
    remove(path);
    return 0;
}
