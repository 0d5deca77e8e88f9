/*
 * sam_sha256: SHA-256 (FIPS 180-4) of memory and files, so a .sam can record
 * the exact source mesh it was built from. Incremental: init, update any
 * number of times, final. A context is plain data; no global state.
 */
#ifndef SAM_SHA256_H
#define SAM_SHA256_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_sha256 {
    uint32_t state[8];
    uint64_t length;      /* bytes hashed so far */
    uint8_t block[64];
    uint32_t block_used;  /* bytes in `block` */
} sam_sha256;

void sam_sha256_init(sam_sha256 *ctx);
/* Hashes `size` bytes of `data` (may be NULL when size is 0). */
void sam_sha256_update(sam_sha256 *ctx, const void *data, size_t size);
/* Writes the 32-byte digest; the context must be re-initialised before reuse. */
void sam_sha256_final(sam_sha256 *ctx, uint8_t digest[32]);

/* The digest of a whole file as 64 lowercase hex digits plus NUL in `hex`.
 * Errors: SAM_ERR_IO naming the file. */
sam_status sam_sha256_file(const char *path, char hex[65], sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
