/* A mesh file's vertex colours (sam_mesh_load_vertex_colors in sam_mesh.h):
 * a PLY's red, green and blue, an OBJ's "v x y z r g b", a glTF's COLOR_0. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_mesh.h"
#include "sam_mesh_soup.h"

sam_status sam_mesh_load_vertex_colors(const char *path, float **rgb, uint32_t *count, char *note, size_t note_size,
                                       sam_error *err)
{
    if (!path || !rgb || !count || !note || !note_size)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "vertex colours: NULL argument");
    *rgb = NULL;
    *count = 0;
    note[0] = '\0';
    sam_status st = sam_check_regular_file(path, err);
    if (st != SAM_OK)
        return st;
    const char *name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    if (sam_path_has_extension(path, ".gltf") || sam_path_has_extension(path, ".glb")) {
        sam_mesh_soup soup;
        if ((st = sam_mesh_gltf_read(path, &soup, err)) != SAM_OK)
            return st;
        if (soup.colors) {
            /* glTF's colours are linear already. */
            *rgb = soup.colors;
            *count = soup.vertex_count;
            soup.colors = NULL;
            snprintf(note, note_size, "the COLOR_0 of %s", name);
        }
        sam_mesh_soup_free(&soup);
        return SAM_OK;
    }
    if (!sam_path_has_extension(path, ".ply") && !sam_path_has_extension(path, ".obj"))
        return SAM_OK;
    sam_mesh_expect expect;
    if ((st = sam_mesh_preflight(path, &expect, err)) != SAM_OK)
        return st;
    if (expect.vertex_colors && expect.vertices) {
        /* PLY and OBJ colours are what a screen shows: sRGB-encoded. */
        const size_t n = 3 * (size_t)expect.vertices;
        for (size_t i = 0; i < n; ++i)
            expect.vertex_colors[i] = sam_srgb_to_linear(expect.vertex_colors[i]);
        *rgb = expect.vertex_colors;
        *count = (uint32_t)expect.vertices;
        expect.vertex_colors = NULL;
        snprintf(note, note_size, "the vertex colours of %s", name);
    }
    sam_mesh_expect_free(&expect);
    return SAM_OK;
}
