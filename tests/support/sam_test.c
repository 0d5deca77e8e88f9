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
