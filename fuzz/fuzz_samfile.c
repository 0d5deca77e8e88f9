/*
 * libFuzzer target for the .sam reader. Besides "no crash, no leak", it
 * checks the reader's contract: a failure leaves the output zeroed with a
 * message, and whatever a read accepts also passes samfile_validate and can
 * be asked why it is dark (sam_build_explain_empty, which walks its rings).
 *
 * Each input is read twice: as given, and with every chunk's CRC recomputed,
 * because random mutations almost never keep a CRC valid and would otherwise
 * never reach the checks behind it (sizes, JSON, indices).
 * Seeds: fuzz/corpus/samfile/ (the tetrahedra of tests/test_samfile.c).
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "sam/sam_build.h"
#include "sam/samfile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_read(const uint8_t *data, size_t size)
{
    samfile_data d;
    sam_error err;
    sam_error_clear(&err);
    sam_status st = samfile_read_memory(data, size, "fuzz.sam", &d, &err);
    if (st == SAM_OK) {
        if (samfile_validate(&d, &err) != SAM_OK)
            abort();
        char why[512];
        sam_build_explain_empty(&d, 1.0f, 1.0f, "fuzz.obj", why, sizeof why);
        if (strlen(why) >= sizeof why)
            abort();
    } else {
        samfile_data zero;
        memset(&zero, 0, sizeof zero);
        if (memcmp(&d, &zero, sizeof d) != 0 || err.status != st || err.message[0] == '\0')
            abort();
    }
    samfile_free(&d);
}

static uint64_t le64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i)
        v = v << 8 | p[i];
    return v;
}

/* Rewrites the CRC of every chunk whose framing fits in the buffer. */
static void fix_crcs(uint8_t *b, size_t size)
{
    size_t off = 16;
    while (off <= size && size - off >= 24) {
        uint64_t len = le64(b + off + 8);
        size_t body = size - off - 16;
        if (len > body)
            return;
        size_t padded = (size_t)len + (size_t)((8 - len % 8) % 8);
        if (padded > body || body - padded < 8)
            return;
        uint32_t crc = (uint32_t)crc32_z(0, b + off + 16, (size_t)len);
        uint8_t *at = b + off + 16 + padded;
        for (int i = 0; i < 4; ++i)
            at[i] = (uint8_t)(crc >> (8 * i));
        off += 16 + padded + 8;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    check_read(data, size);
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    memcpy(copy, data, size);
    fix_crcs(copy, size);
    check_read(copy, size);
    free(copy);
    return 0;
}
