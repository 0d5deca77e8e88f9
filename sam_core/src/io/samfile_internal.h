/*
 * Internal: the framing constants and byte encoding shared by the .sam
 * reader (samfile_read.c) and writer (samfile_write.c), and the semantic
 * checks both run on the data (samfile.c).
 */
#ifndef SAMFILE_INTERNAL_H
#define SAMFILE_INTERNAL_H

#include "sam/samfile.h"

#define FILE_HEADER_SIZE 16u
#define CHUNK_HEADER_SIZE 16u
#define CHUNK_TRAILER_SIZE 8u

enum {
    TAG_INFO,
    TAG_POS,
    TAG_NRM,
    TAG_UV,
    TAG_TRI,
    TAG_SIDX,
    TAG_SKPR,
    TAG_FANA,
    TAG_ADJO,
    TAG_ADJV,
    TAG_NODE,
    TAG_NLVL,
    TAG_STAU,
    TAG_SRCV,
    TAG_COUNT
};

/* Also the order in which the writer emits chunks. */
static const char k_tags[TAG_COUNT][5] = {"INFO", "POS ", "NRM ", "UV  ", "TRI ",
                                          "SIDX", "SKPR", "FANA", "ADJO", "ADJV", "NODE", "NLVL", "STAU",
                                          "SRCV"};

/* ---- little-endian encoding, independent of the host's byte order ---- */

static inline uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static inline uint64_t get_u64(const uint8_t *p)
{
    return (uint64_t)get_u32(p) | (uint64_t)get_u32(p + 4) << 32;
}

static inline void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static inline void put_u64(uint8_t *p, uint64_t v)
{
    put_u32(p, (uint32_t)v);
    put_u32(p + 4, (uint32_t)(v >> 32));
}

static inline size_t padding_of(uint64_t length)
{
    return (size_t)((8u - length % 8u) % 8u);
}

/* `bad` is the status for a broken rule: SAM_ERR_CORRUPT when the data came
 * from a file, SAM_ERR_INVALID_ARGUMENT when a caller built it. */
sam_status samfile_check_data(const samfile_data *d, const char *name, sam_status bad, sam_error *err);

/* R_d (RGB, into rd) between vertex v's record and sample index id's in
 * samfile_sample_points' `points` (`stride` floats each), at mm_per_unit;
 * returns the sample's area. Eq. 15's K is K' times area times rd. */
float samfile_sample_rd(const float *points, size_t stride, uint32_t v, uint32_t id, const sam_profile *profile,
                        float mm_per_unit, float rd[3]);

#endif
