/* A program outside the SAM tree, built against an installed SAM (with
 * find_package and with pkg-config, tests/install/run.sh): the version it
 * was compiled with is the one it links, and a back-lit ear builds, uploads
 * and lets light through. Exit 0 when all holds. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sam/sam_build.h>
#include <sam/sam_runtime.h>
#include <sam/sam_shape.h>
#include <sam/sam_version.h>

static int fail(const char *what, const sam_error *err)
{
    fprintf(stderr, "consumer: %s: %s\n", what, err ? err->message : "failed");
    return 1;
}

int main(void)
{
    if (strcmp(sam_version(), SAM_VERSION_STRING) != 0) {
        fprintf(stderr, "consumer: compiled against SAM %s, linked %s\n", SAM_VERSION_STRING, sam_version());
        return 1;
    }
    sam_error err;
    sam_shape_params params;
    sam_shape_mesh shape;
    if (sam_shape_default_params("ear", &params, &err) != SAM_OK ||
        sam_shape_generate("ear", &params, &shape, &err) != SAM_OK)
        return fail("shape", &err);
    sam_mesh_input in = {.name = "ear", .vertex_count = shape.vertex_count, .positions = shape.positions,
                         .uvs = shape.uvs, .triangle_count = shape.triangle_count, .triangles = shape.triangles};
    sam_mesh mesh;
    sam_profile skin;
    samfile_data map;
    sam_gl_context *gl;
    sam_runtime *rt;
    if (sam_mesh_create(&in, &mesh, NULL, &err) != SAM_OK)
        return fail("mesh", &err);
    sam_shape_mesh_destroy(&shape);
    if (sam_profile_preset("skin", &skin, &err) != SAM_OK ||
        sam_build_samfile(&mesh, &skin, 60.0f, NULL, NULL, NULL, NULL, &map, NULL, &err) != SAM_OK)
        return fail("build", &err);
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK)
        return fail("GL", &err);
    if (sam_runtime_create(&map, &skin, 60.0f, &rt, &err) != SAM_OK)
        return fail("runtime", &err);
    sam_light light = {.type = SAM_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 4, .position = {0, 0, -1}};
    if (sam_runtime_set_lights(rt, &light, 1, &err) != SAM_OK || sam_runtime_irradiance(rt, &err) != SAM_OK ||
        sam_runtime_translucency(rt, 0, 1.0f / 60.0f, 1, &err) != SAM_OK)
        return fail("passes", &err);
    const uint32_t n = sam_runtime_vertex_count(rt);
    float *t = malloc(3 * (size_t)n * sizeof *t);
    if (!t || sam_runtime_read_translucency(rt, t, &err) != SAM_OK)
        return fail("read back", t ? &err : NULL);
    uint32_t lit = 0;
    for (uint32_t v = 0; v < n; ++v)
        lit += t[3 * (size_t)v] > 0;
    printf("consumer: SAM %s, %u vertices, %u with translucency\n", sam_version(), n, lit);
    free(t);
    sam_runtime_destroy(rt);
    sam_gl_context_destroy(gl);
    samfile_free(&map);
    sam_mesh_destroy(&mesh);
    return lit > 0 ? 0 : 1;
}
