/*
 * glTF 2.0 meshes (sam_mesh_load on .gltf and .glb): files written here by
 * hand, each with one embedded buffer. Node transforms apply (a mirroring
 * one keeps the triangles facing out), strips and fans become triangles,
 * TEXCOORD_0 turns to the OBJ convention, and each malformed reference
 * gives one line naming it.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_mesh.h"
#include "sam_test.h"

/* A unit right tetrahedron: 4 positions, UVs, and its 4 faces as 12 u8
 * indices, counter-clockwise from outside. */
typedef struct tetra_buffer {
    float positions[12];
    float uvs[8];
    uint8_t indices[12];
} tetra_buffer;

static const tetra_buffer k_tetra = {
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1},
    {0, 0, 1, 0, 0, 1, 0.25f, 0.75f},
    {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3},
};

static void base64(const uint8_t *in, size_t n, char *out)
{
    static const char *abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = abc[v >> 18 & 63];
        out[o++] = abc[v >> 12 & 63];
        out[o++] = i + 1 < n ? abc[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? abc[v & 63] : '=';
    }
    out[o] = '\0';
}

/* Writes NAME.gltf: the tetrahedron's buffer with its three views
 * (positions, UVs, indices; `views` adds more after them) and accessors 0
 * to 2 over them (`accessors` adds more), and `body` (the scene, nodes,
 * meshes...) spliced into the JSON. Returns the path in `path`. */
static void write_tetra(char *path, size_t n, const char *name, const char *body, const char *views,
                        const char *accessors)
{
    char data[256];
    base64((const uint8_t *)&k_tetra, sizeof k_tetra, data);
    char json[4096];
    snprintf(json, sizeof json,
             "{\"asset\": {\"version\": \"2.0\"}, %s,"
             "\"buffers\": [{\"byteLength\": %zu, \"uri\": \"data:application/octet-stream;base64,%s\"}],"
             "\"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 48},"
             " {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 32},"
             " {\"buffer\": 0, \"byteOffset\": 80, \"byteLength\": 12}%s],"
             "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\","
             " \"min\": [0, 0, 0], \"max\": [1, 1, 1]},"
             " {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},"
             " {\"bufferView\": 2, \"componentType\": 5121, \"count\": 12, \"type\": \"SCALAR\"}%s]}",
             body, sizeof k_tetra, data, views, accessors);
    char file[128];
    snprintf(file, sizeof file, "%s.gltf", name);
    sam_test_tmp_path(path, n, file);
    sam_test_write_text(path, json);
}

/* write_tetra with one mesh of one primitive: `nodes`, `primitive` (its
 * mode and indices) and `scene` spliced in. */
static void write_gltf(char *path, size_t n, const char *name, const char *nodes, const char *primitive,
                       const char *accessors_extra, const char *scene)
{
    char body[1024];
    snprintf(body, sizeof body,
             "%s \"nodes\": [%s], \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, "
             "\"TEXCOORD_0\": 1}%s}]}]",
             scene, nodes, primitive);
    write_tetra(path, n, name, body, "", accessors_extra);
}

static const char *k_scene = "\"scene\": 0, \"scenes\": [{\"nodes\": [0]}],";
static const char *k_triangles = ", \"indices\": 2";

/* Signed volume (model units^3) of a closed mesh: positive when its
 * triangles face out. */
static double volume(const sam_mesh *m)
{
    double v = 0;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
        const float *a = m->positions + 3 * (size_t)m->triangles[3 * t], *b = m->positions + 3 * (size_t)m->triangles[3 * t + 1],
                    *c = m->positions + 3 * (size_t)m->triangles[3 * t + 2];
        v += (a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) - a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
              a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0])) / 6.0;
    }
    return v;
}

static void load_ok(const char *path, sam_mesh *m)
{
    sam_error err;
    if (sam_mesh_load(path, m, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
}

static void test_node_transforms(void **state)
{
    (void)state;
    char path[512];
    /* Node 0 moves by (10, 0, 0) and holds node 1, which scales by 2. */
    write_gltf(path, sizeof path, "nodes",
               "{\"translation\": [10, 0, 0], \"children\": [1]}, {\"scale\": [2, 2, 2], \"mesh\": 0}", k_triangles,
               "", k_scene);
    sam_mesh m;
    load_ok(path, &m);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 4);
    assert_int_equal(m.source_count, 4);
    float lo[3], hi[3];
    sam_mesh_bounds(&m, lo, hi);
    assert_float_equal(lo[0], 10.0f, 1e-6f);
    assert_float_equal(hi[0], 12.0f, 1e-6f);
    assert_float_equal(hi[1], 2.0f, 1e-6f);
    assert_float_equal(volume(&m), 8.0 / 6.0, 1e-6);
    /* v runs up, as in OBJ: the file's (0.25, 0.75) reads (0.25, 0.25). */
    assert_non_null(m.uvs);
    const uint32_t last = m.render_of_source[3];
    assert_float_equal(m.uvs[2 * last], 0.25f, 1e-6f);
    assert_float_equal(m.uvs[2 * last + 1], 0.25f, 1e-6f);
    sam_mesh_destroy(&m);
    /* A mirror (scale -1 in x) turns the winding; the loader turns it back. */
    write_gltf(path, sizeof path, "mirror", "{\"scale\": [-1, 1, 1], \"mesh\": 0}", k_triangles, "", k_scene);
    load_ok(path, &m);
    assert_true(volume(&m) > 0);
    sam_mesh_destroy(&m);
    /* A node matrix (column-major) instead of TRS, and no scene at all. */
    write_gltf(path, sizeof path, "matrix",
               "{\"matrix\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1], \"mesh\": 0}", k_triangles, "", k_scene);
    load_ok(path, &m);
    sam_mesh_bounds(&m, lo, hi);
    assert_float_equal(lo[2], 5.0f, 1e-6f);
    sam_mesh_destroy(&m);
    write_gltf(path, sizeof path, "no_scene", "{\"mesh\": 0}", k_triangles, "", "");
    load_ok(path, &m);
    assert_int_equal(m.triangle_count, 4);
    sam_mesh_destroy(&m);
}

/* A strip of the first 4 indices (0 2 1 0) and a fan of 4 give two
 * triangles each, before repairs. */
static void test_strips_and_fans(void **state)
{
    (void)state;
    char path[512];
    sam_mesh m;
    sam_mesh_report rep;
    sam_error err;
    /* Indices 0 2 1 3 as a strip: (0 2 1), (2 3 1) after the odd flip. */
    write_gltf(path, sizeof path, "strip", "{\"mesh\": 0}", ", \"mode\": 5, \"indices\": 3",
               ", {\"bufferView\": 2, \"byteOffset\": 0, \"componentType\": 5121, \"count\": 3, \"type\": \"SCALAR\"}",
               k_scene);
    assert_int_equal(sam_mesh_load(path, &m, &rep, &err), SAM_OK);
    assert_int_equal(m.triangle_count, 1);
    sam_mesh_destroy(&m);
    write_gltf(path, sizeof path, "fan", "{\"mesh\": 0}", ", \"mode\": 6, \"indices\": 3",
               ", {\"bufferView\": 2, \"byteOffset\": 6, \"componentType\": 5121, \"count\": 4, \"type\": \"SCALAR\"}",
               k_scene);
    assert_int_equal(sam_mesh_load(path, &m, &rep, &err), SAM_OK);
    assert_int_equal(m.triangle_count, 2);
    sam_mesh_destroy(&m);
}

static void expect_error(const char *name, const char *nodes, const char *primitive, const char *extra,
                         const char *scene, sam_status status, const char *needle)
{
    char path[512];
    write_gltf(path, sizeof path, name, nodes, primitive, extra, scene);
    sam_mesh m;
    sam_error err;
    sam_status st = sam_mesh_load(path, &m, NULL, &err);
    if (st != status || !strstr(err.message, needle) || !strstr(err.message, name))
        fail_msg("%s: expected %s with \"%s\", got %s: \"%s\"", name, sam_status_name(status), needle,
                 sam_status_name(st), err.message);
    assert_null(m.positions);
}

static void test_bad_references(void **state)
{
    (void)state;
    const char *node = "{\"mesh\": 0}";
    /* The positions' float bytes read as u8 indices: 1.0f is 00 00 80 3f. */
    expect_error("index_range", node, ", \"indices\": 3",
                 ", {\"bufferView\": 0, \"byteOffset\": 4, \"componentType\": 5121, \"count\": 12, \"type\": "
                 "\"SCALAR\"}",
                 k_scene, SAM_ERR_FORMAT, "accessor 3 (indices): index 128 at 10 is out of range (4 vertices)");
    expect_error("past_buffer", node, ", \"indices\": 3",
                 ", {\"bufferView\": 2, \"componentType\": 5121, \"count\": 40, \"type\": \"SCALAR\"}", k_scene,
                 SAM_ERR_FORMAT, "accessor 3 (indices): 40 indices do not fit buffer view 2");
    expect_error("no_accessor", node, ", \"indices\": 9", "", k_scene, SAM_ERR_FORMAT,
                 "not a readable glTF file: primitive indices accessor out of bounds");
    expect_error("cycle", "{\"children\": [1]}, {\"children\": [0], \"mesh\": 0}", k_triangles, "", k_scene,
                 SAM_ERR_FORMAT, "node 1: the node hierarchy has a cycle");
    expect_error("no_node", node, k_triangles, "", "\"scene\": 0, \"scenes\": [{\"nodes\": [7]}],", SAM_ERR_FORMAT,
                 "node 7 does not exist (1 nodes)");
    expect_error("points", node, ", \"mode\": 0", "", k_scene, SAM_ERR_EMPTY, "only points or lines");
    expect_error("three_floats", node, ", \"indices\": 3",
                 ", {\"bufferView\": 2, \"componentType\": 5126, \"count\": 3, \"type\": \"SCALAR\"}", k_scene,
                 SAM_ERR_FORMAT, "indices must be unsigned");
}

/* A buffer whose URI names a directory is refused with a message; TinyGLTF
 * alone opened it and asked for 2^63 bytes (found by fuzz/fuzz_mesh). */
static void test_buffer_naming_a_directory(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "dir_buffer.gltf");
    sam_test_write_text(path, "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"byteLength\": 4, \"uri\": \"./\"}]}");
    sam_mesh m;
    sam_error err;
    assert_int_equal(sam_mesh_load(path, &m, NULL, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "dir_buffer.gltf: not a readable glTF file"));
    assert_null(m.positions);
}

/* A GLB of the same tetrahedron, and every truncated prefix of it. */
static void test_glb_and_truncation(void **state)
{
    (void)state;
    char gltf[512], glb[512];
    write_gltf(gltf, sizeof gltf, "for_glb", "{\"mesh\": 0}", k_triangles, "", k_scene);
    uint8_t *text;
    size_t size;
    sam_error err;
    assert_int_equal(sam_read_file(gltf, &text, &size, &err), SAM_OK);
    /* The JSON chunk is padded with spaces to 4 bytes. */
    const size_t padded = (size + 3) / 4 * 4;
    uint8_t *file = malloc(12 + 8 + padded);
    assert_non_null(file);
    const uint32_t header[5] = {0x46546C67u, 2, (uint32_t)(20 + padded), (uint32_t)padded, 0x4E4F534Au};
    memcpy(file, header, sizeof header);
    memcpy(file + 20, text, size);
    memset(file + 20 + size, ' ', padded - size);
    sam_test_tmp_path(glb, sizeof glb, "tetra.glb");
    sam_test_write_file(glb, file, 20 + padded);
    sam_mesh m;
    load_ok(glb, &m);
    assert_int_equal(m.triangle_count, 4);
    sam_mesh_destroy(&m);
    for (size_t n = 0; n < 20 + padded; n += 7) {
        sam_test_write_file(glb, file, n);
        sam_status st = sam_mesh_load(glb, &m, NULL, &err);
        assert_true(st != SAM_OK);
        assert_non_null(strstr(err.message, "tetra.glb"));
    }
    /* A binary chunk whose length counts its own 8-byte head: TinyGLTF
     * 2.7 took it and read 8 bytes past the file's end. */
    uint8_t *longer = malloc(20 + padded + 12);
    assert_non_null(longer);
    memcpy(longer, file, 20 + padded);
    const uint32_t total = (uint32_t)(20 + padded + 12), chunk[3] = {12, 0x004E4942u, 0};
    memcpy(longer + 8, &total, 4);
    memcpy(longer + 20 + padded, chunk, sizeof chunk);
    sam_test_write_file(glb, longer, 20 + padded + 12);
    assert_int_equal(sam_mesh_load(glb, &m, NULL, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "tetra.glb: not a readable glTF file: the chunk after the JSON, 12 bytes"));
    assert_non_null(strstr(err.message, "runs past the GLB's length"));
    free(longer);
    free(file);
    free(text);
}

/* A tetrahedron draco_transcoder compressed with Draco (tests/data): it
 * loads, every fifth truncated prefix is refused naming the file, and with any
 * byte of its Draco data flipped it loads or is refused, never more. */
static void test_draco_truncated_and_flipped(void **state)
{
    (void)state;
    uint8_t *file;
    size_t size;
    sam_error err;
    assert_int_equal(sam_read_file(SAM_TEST_DATA_DIR "/tetra_draco.glb", &file, &size, &err), SAM_OK);
    char glb[512];
    sam_test_tmp_path(glb, sizeof glb, "draco.glb");
    sam_test_write_file(glb, file, size);
    sam_mesh m;
    load_ok(glb, &m);
    assert_int_equal(m.triangle_count, 4);
    sam_mesh_destroy(&m);
    for (size_t n = 0; n < size; n += 5) {
        sam_test_write_file(glb, file, n);
        assert_true(sam_mesh_load(glb, &m, NULL, &err) != SAM_OK);
        assert_non_null(strstr(err.message, "draco.glb"));
    }
    /* The binary chunk, which holds the Draco data, follows the JSON. */
    uint32_t json;
    memcpy(&json, file + 12, 4);
    size_t loaded = 0;
    for (size_t at = 20 + json + 8; at < size; ++at) {
        file[at] ^= 0xFF;
        sam_test_write_file(glb, file, size);
        if (sam_mesh_load(glb, &m, NULL, &err) == SAM_OK) {
            loaded++;
            sam_mesh_destroy(&m);
        } else {
            assert_non_null(strstr(err.message, "draco.glb"));
        }
        file[at] ^= 0xFF;
    }
    print_message("draco: %zu of %zu flipped bytes still loaded\n", loaded, size - (20 + json + 8));
    free(file);
}

/* A .gltf cut inside its embedded buffer: the JSON parser quotes what it
 * last read (the base64 so far); the message keeps a short head of it. */
static void test_truncated_buffer_message_is_short(void **state)
{
    (void)state;
    char path[512];
    write_gltf(path, sizeof path, "cut_in_base64", "{\"mesh\": 0}", k_triangles, "", k_scene);
    uint8_t *text;
    size_t size;
    sam_error err;
    assert_int_equal(sam_read_file(path, &text, &size, &err), SAM_OK);
    const char *data = strstr((const char *)text, "base64,");
    assert_non_null(data);
    sam_test_write_file(path, text, (size_t)(data - (const char *)text) + 7 + 100);
    free(text);
    sam_mesh m;
    assert_int_equal(sam_mesh_load(path, &m, NULL, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "cut_in_base64.gltf: not a readable glTF file"));
    if (!strstr(err.message, "..."))
        fail_msg("no shortened word in \"%s\"", err.message);
    size_t word = 0, longest = 0;
    for (const char *c = err.message; *c; ++c) {
        word = *c == ' ' ? 0 : word + 1;
        longest = word > longest ? word : longest;
    }
    if (longest > 64)
        fail_msg("a %zu-character word in \"%s\"", longest, err.message);
}

/* The tetrahedron's vertex at render vertex `v` of `m`. */
static int tetra_vertex(const sam_mesh *m, uint32_t v)
{
    int k = 0;
    while (k < 4 && memcmp(&m->positions[3 * v], &k_tetra.positions[3 * k], 3 * sizeof(float)))
        k++;
    assert_true(k < 4);
    return k;
}

/* Every UV of `m` is the file's, v turned to the OBJ convention. */
static void assert_file_uvs(const sam_mesh *m)
{
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        const int k = tetra_vertex(m, v);
        assert_float_equal(m->uvs[2 * v], k_tetra.uvs[2 * k], 0);
        assert_float_equal(m->uvs[2 * v + 1], 1.0f - k_tetra.uvs[2 * k + 1], 1e-7);
    }
}

/* The base colour texture's KHR_texture_transform moves the UVs, as
 * gltfpack's quantized UVs need: offset x rotation x scale, the rotation
 * as the extension's GLSL writes it, then v turned to the OBJ convention.
 * Without a transform the UVs stay the file's (v turned). */
static void test_texture_transform(void **state)
{
    (void)state;
    char path[512];
    write_gltf(path, sizeof path, "texture_transform", "{\"mesh\": 0}", ", \"indices\": 2, \"material\": 0", "",
               "\"scene\": 0, \"scenes\": [{\"nodes\": [0]}], \"materials\": [{\"pbrMetallicRoughness\": "
               "{\"baseColorTexture\": {\"index\": 0, \"extensions\": {\"KHR_texture_transform\": "
               "{\"offset\": [0.5, 0.25], \"scale\": [0.5, 2], \"rotation\": 1.5707963267948966}}}}}],");
    sam_mesh m;
    load_ok(path, &m);
    assert_non_null(m.uvs);
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        const int k = tetra_vertex(&m, v);
        const double u0 = k_tetra.uvs[2 * k], v0 = k_tetra.uvs[2 * k + 1];
        /* cos = 0, sin = 1: u' = -2 v + 0.5, v' = 0.5 u + 0.25. */
        assert_float_equal(m.uvs[2 * v], -2.0 * v0 + 0.5, 1e-6);
        assert_float_equal(m.uvs[2 * v + 1], 1.0 - (0.5 * u0 + 0.25), 1e-6);
    }
    sam_mesh_destroy(&m);
    /* None, and one of another UV set (its texCoord 1): the file's UVs. */
    write_gltf(path, sizeof path, "no_texture_transform", "{\"mesh\": 0}", k_triangles, "", k_scene);
    load_ok(path, &m);
    assert_file_uvs(&m);
    sam_mesh_destroy(&m);
    write_gltf(path, sizeof path, "other_set_transform", "{\"mesh\": 0}", ", \"indices\": 2, \"material\": 0", "",
               "\"scene\": 0, \"scenes\": [{\"nodes\": [0]}], \"materials\": [{\"pbrMetallicRoughness\": "
               "{\"baseColorTexture\": {\"index\": 0, \"extensions\": {\"KHR_texture_transform\": "
               "{\"offset\": [0.5, 0.25], \"texCoord\": 1}}}}}],");
    load_ok(path, &m);
    assert_file_uvs(&m);
    sam_mesh_destroy(&m);
}

/* COLOR_0 as it is (glTF's colours are linear), white on a primitive
 * without it, in the soup's order (the file's vertices, primitive by
 * primitive: sam_mesh.source_of_render's); a count unlike POSITION's is
 * refused, naming it. */
static void test_vertex_colors(void **state)
{
    (void)state;
    char body[1024], accessor[128], path[512], note[256];
    static const char *const colour[] = {"\"VEC3\", \"count\": 4", "\"VEC4\", \"count\": 3"};
    for (int bad = 0; bad < 2; ++bad) {
        snprintf(body, sizeof body,
                 "%s \"nodes\": [{\"mesh\": 0}], \"meshes\": [{\"primitives\": [{\"attributes\": "
                 "{\"POSITION\": 0, \"COLOR_0\": 3}, \"indices\": 2}, {\"attributes\": {\"POSITION\": 0}, "
                 "\"indices\": 2}]}]",
                 k_scene);
        snprintf(accessor, sizeof accessor, ", {\"bufferView\": 0, \"componentType\": 5126, \"type\": %s}",
                 colour[bad]);
        write_tetra(path, sizeof path, "colors", body, "", accessor);
        float *rgb = NULL;
        uint32_t count = 0;
        sam_error err;
        const sam_status st = sam_mesh_load_vertex_colors(path, &rgb, &count, note, sizeof note, &err);
        if (bad) {
            printf("%s\n", err.message);
            assert_int_equal(st, SAM_ERR_FORMAT);
            assert_non_null(strstr(err.message, "COLOR_0 has another count than POSITION's 4"));
            assert_null(rgb);
            continue;
        }
        assert_int_equal(st, SAM_OK);
        assert_string_equal(note, "the COLOR_0 of colors.gltf");
        assert_int_equal(count, 8);
        for (int k = 0; k < 12; ++k) {
            assert_float_equal(rgb[k], k_tetra.positions[k], 0.0f);
            assert_float_equal(rgb[12 + k], 1.0f, 0.0f);
        }
        sam_mesh m;
        load_ok(path, &m);
        assert_int_equal(m.source_count, count);
        sam_mesh_destroy(&m);
        free(rgb);
    }
    remove(path);
}

/* An image whose buffer view runs past its buffer: TinyGLTF 2.7 handed
 * stb_image the bytes past the buffer's end (an over-read under ASan,
 * found by fuzz_mesh); the texture is now refused with a note, and the
 * geometry still loads. */
static void test_image_view_past_buffer(void **state)
{
    (void)state;
    char body[1024], path[512], note[2304];
    snprintf(body, sizeof body,
             "%s \"nodes\": [{\"mesh\": 0}], \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, "
             "\"TEXCOORD_0\": 1}, \"indices\": 2, \"material\": 0}]}],"
             "\"materials\": [{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}],"
             "\"textures\": [{\"source\": 0}], \"images\": [{\"bufferView\": 3, \"mimeType\": \"image/png\"}]",
             k_scene);
    write_tetra(path, sizeof path, "image_past", body, ", {\"buffer\": 0, \"byteOffset\": 88, \"byteLength\": 4000}",
                "");
    sam_image image;
    sam_error err;
    assert_int_equal(sam_mesh_load_albedo(path, &image, note, sizeof note, &err), SAM_OK);
    printf("%s\n", note);
    assert_null(image.pixels);
    assert_non_null(strstr(note, "buffer view 3 (4000 bytes at 88) runs past its 92-byte buffer"));
    sam_mesh m;
    load_ok(path, &m);
    sam_mesh_destroy(&m);
    remove(path);
}

/* Primitives of different materials read different maps: each used
 * material's base colour (here a factor alone, as 1 x 1; an unused one
 * none), faces of a primitive without a material none, in the soup's face
 * order. */
static void test_albedo_maps(void **state)
{
    (void)state;
    char body[1024], path[512], note[256];
    snprintf(body, sizeof body,
             "%s \"nodes\": [{\"mesh\": 0}], \"meshes\": [{\"primitives\": ["
             "{\"attributes\": {\"POSITION\": 0}, \"indices\": 2, \"material\": 1},"
             " {\"attributes\": {\"POSITION\": 0}, \"indices\": 2, \"material\": 0},"
             " {\"attributes\": {\"POSITION\": 0}, \"indices\": 2}]}],"
             "\"materials\": [{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.5, 0.25, 1, 1]}}, {},"
             " {\"pbrMetallicRoughness\": {\"baseColorFactor\": [0, 1, 0, 1]}}]",
             k_scene);
    write_tetra(path, sizeof path, "materials", body, "", "");
    sam_albedo_maps maps;
    sam_error err;
    assert_int_equal(sam_mesh_load_albedo_maps(path, &maps, note, sizeof note, &err), SAM_OK);
    assert_int_equal(maps.map_count, 2);
    assert_int_equal(maps.face_count, 12);
    for (uint32_t f = 0; f < 12; ++f)
        assert_int_equal(maps.face_map[f], f < 4 ? 1u : f < 8 ? 0u : SAM_ALBEDO_NO_MAP);
    const float factor[3] = {0.5f, 0.25f, 1.0f};
    for (uint32_t c = 0; c < 3; ++c) {
        assert_float_equal(maps.maps[0].pixels[c], factor[c], 0.0f);
        assert_float_equal(maps.maps[1].pixels[c], 1.0f, 0.0f);
    }
    sam_albedo_maps_destroy(&maps);

    /* An image TinyGLTF cannot decode fails the whole read: a note, no maps
     * (and sam_mesh_load_albedo's note likewise), not an error. */
    snprintf(body, sizeof body,
             "%s \"nodes\": [{\"mesh\": 0}], \"meshes\": [{\"primitives\": ["
             "{\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1}, \"indices\": 2, \"material\": 1},"
             " {\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1}, \"indices\": 2, \"material\": 0}]}],"
             "\"materials\": [{}, {\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}],"
             "\"textures\": [{\"source\": 0}], \"images\": [{\"bufferView\": 3, \"mimeType\": \"image/png\"}]",
             k_scene);
    write_tetra(path, sizeof path, "materials", body, ", {\"buffer\": 0, \"byteOffset\": 88, \"byteLength\": 4000}",
                "");
    assert_int_equal(sam_mesh_load_albedo_maps(path, &maps, note, sizeof note, &err), SAM_OK);
    printf("%s\n", note);
    assert_int_equal(maps.map_count, 0);
    assert_non_null(strstr(note, "runs past its 92-byte buffer"));
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_node_transforms),
        cmocka_unit_test(test_texture_transform),
        cmocka_unit_test(test_strips_and_fans),
        cmocka_unit_test(test_bad_references),
        cmocka_unit_test(test_truncated_buffer_message_is_short),
        cmocka_unit_test(test_glb_and_truncation),
        cmocka_unit_test(test_draco_truncated_and_flipped),
        cmocka_unit_test(test_buffer_naming_a_directory),
        cmocka_unit_test(test_vertex_colors),
        cmocka_unit_test(test_image_view_past_buffer),
        cmocka_unit_test(test_albedo_maps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
