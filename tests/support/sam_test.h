/*
 * Shared helpers for the cmocka tests. Every test writes only below
 * SAM_TEST_TMP_DIR (the build tree), never into the source tree.
 */
#ifndef SAM_TEST_H
#define SAM_TEST_H

#include <stddef.h>
#include <stdint.h>

/* Writes "<SAM_TEST_TMP_DIR>/<name>" into buf (size n) and returns buf. */
char *sam_test_tmp_path(char *buf, size_t n, const char *name);

/* Writes `size` bytes to `path`, replacing it; fails the running test on error. */
void sam_test_write_file(const char *path, const void *data, size_t size);

/* Writes a NUL-terminated string to `path` (see sam_test_write_file). */
void sam_test_write_text(const char *path, const char *text);

/* Number of files in SAM_TEST_TMP_DIR whose names start with "<name>.tmp.":
 * temporaries an atomic write to <name> left behind. */
int sam_test_count_temp_files(const char *name);

/* Returns 1 when `path` exists. */
int sam_test_file_exists(const char *path);

/* The share of a map's used samples that are tree nodes: `sample` holds
 * `rows` rows of `stride` entries, an entry >= first_node names a node,
 * UINT32_MAX ends a row. 0 when no sample is used. A cut map stores its
 * budget's best vertices instead where they hold nearly all the light
 * (skin on small meshes), so a test of the node paths checks that its map
 * has nodes at all. */
double sam_test_node_share(const uint32_t *sample, uint32_t rows, uint32_t stride, uint32_t first_node);

struct sam_mesh;

/* The built-in shape `name` (sam_shape_generate, with its UVs) as a mesh:
 * `resolution`, and where > 0 `size` (a square slab: depth too),
 * `thickness` and `count` replace the defaults. Fails the running test on
 * error; the caller destroys the mesh. */
void sam_test_shape_mesh(const char *name, int resolution, double size, double thickness, int count,
                         struct sam_mesh *mesh);

struct sam_gl_context;

/* cmocka group setup and teardown of the GL tests: a headless GL context,
 * current on this thread for every test of the group. Setup prints why
 * there is none and fails the group. */
int sam_test_gl_setup(void **state);
int sam_test_gl_teardown(void **state);

/* The context sam_test_gl_setup opened. */
struct sam_gl_context *sam_test_gl_context(void);

#endif
