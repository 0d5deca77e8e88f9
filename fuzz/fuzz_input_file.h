/*
 * For the fuzz targets whose readers open files by name (OpenMesh,
 * TinyGLTF): writes an input to a private temporary file whose extension
 * the first byte picks (data[0] modulo `count` into `extensions`), the rest
 * being the content. Header-only: each target is one program.
 */
#ifndef FUZZ_INPUT_FILE_H
#define FUZZ_INPUT_FILE_H

#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

/* Fills `path` (size n) and writes the file; returns 0 for an empty input
 * (nothing written). Aborts when the file cannot be written. */
static int fuzz_input_file(const uint8_t *data, size_t size, const char *target, const char *const *extensions,
                           size_t count, char *path, size_t n)
{
    if (size < 1)
        return 0;
    snprintf(path, n, "/tmp/sam_%s_%ld.%s", target, (long)getpid(), extensions[data[0] % count]);
    FILE *fp = fopen(path, "wb");
    if (!fp)
        abort();
    if (size > 1 && fwrite(data + 1, 1, size - 1, fp) != size - 1)
        abort();
    fclose(fp);
    return 1;
}

#endif
