#define _POSIX_C_SOURCE 200809L
#include "sam_test.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <dirent.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "sam/sam_mesh.h"
#include "sam/sam_shape.h"

char *sam_test_tmp_path(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", SAM_TEST_TMP_DIR, name);
    return buf;
}

void sam_test_write_file(const char *path, const void *data, size_t size)
{
    FILE *fp = fopen(path, "wb");
    if (!fp)
        fail_msg("cannot create %s", path);
    if (size && fwrite(data, 1, size, fp) != size)
        fail_msg("cannot write %s", path);
    if (fclose(fp) != 0)
        fail_msg("cannot close %s", path);
}

void sam_test_write_text(const char *path, const char *text)
{
    sam_test_write_file(path, text, strlen(text));
}

int sam_test_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

int sam_test_count_temp_files(const char *name)
{
    char prefix[512];
    snprintf(prefix, sizeof prefix, "%s.tmp.", name);
    DIR *dir = opendir(SAM_TEST_TMP_DIR);
    if (!dir)
        fail_msg("cannot list %s", SAM_TEST_TMP_DIR);
    int count = 0;
    for (struct dirent *e; (e = readdir(dir)) != NULL;)
        count += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    closedir(dir);
    return count;
}

void sam_test_shape_mesh(const char *name, int resolution, double size, double thickness, int count, sam_mesh *mesh)
{
    sam_shape_params p;
    sam_error err;
    if (sam_shape_default_params(name, &p, &err) != SAM_OK)
        fail_msg("%s", err.message);
    p.resolution = resolution;
    if (size > 0)
        p.size = p.depth = size;
    if (thickness > 0)
        p.thickness = thickness;
    if (count > 0)
        p.count = count;
    sam_shape_mesh s;
    if (sam_shape_generate(name, &p, &s, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_mesh_input in = {.name = name, .vertex_count = s.vertex_count, .positions = s.positions,
                         .uvs = s.uvs, .triangle_count = s.triangle_count, .triangles = s.triangles};
    sam_status st = sam_mesh_create(&in, mesh, NULL, &err);
    sam_shape_mesh_destroy(&s);
    if (st != SAM_OK)
        fail_msg("%s", err.message);
}

double sam_test_node_share(const uint32_t *sample, uint32_t rows, uint32_t stride, uint32_t first_node)
{
    uint64_t used = 0, nodes = 0;
    for (size_t at = 0; at < (size_t)rows * stride; ++at)
        if (sample[at] != UINT32_MAX) {
            ++used;
            nodes += sample[at] >= first_node;
        }
    return used ? (double)nodes / (double)used : 0.0;
}
