/*
 * Internal: what the sam_image_*.c files share.
 *   sam_image.c          memory, size checks, sRGB
 *   sam_image_exr.c      OpenEXR reading and writing
 *   sam_image_png.c      PNG reading and writing
 *   sam_image_stb.c      JPEG and TGA reading (stb_image), and the reader by extension
 *   sam_image_display.c  tonemapping, the tools' pictures, 8-bit comparison
 */
#ifndef SAM_IMAGE_INTERNAL_H
#define SAM_IMAGE_INTERNAL_H

#include "sam/sam_image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Checks an image size; `what` prefixes the message (a file name or
 * "image"). A size read from a file is a format problem when empty and
 * unsupported when too big; a size from a caller is an invalid argument. */
sam_status sam_image_check_size(uint64_t width, uint64_t height, uint64_t channels, int from_file,
                                const char *what, sam_error *err);

/* Checks an image passed in by a caller; `what` prefixes the message. */
sam_status sam_image_check(const char *what, const sam_image *image, sam_error *err);

/* Checks a writer's output path and image. */
sam_status sam_image_check_output(const char *path, const sam_image *image, sam_error *err);

/* A new image from 8-bit samples (w * h * c of them, c 3 or 4, rows top
 * first): colour decoded from sRGB with SAM_PNG_SRGB, alpha as it is.
 * Errors: those of sam_image_create. */
sam_status sam_image_from_bytes(sam_image *image, const uint8_t *raw, uint32_t w, uint32_t h, uint32_t c,
                                sam_png_encoding encoding, sam_error *err);

/* One value as an 8-bit PNG sample: sRGB-encoded when `srgb`, clamped to
 * [0, 1], rounded to nearest. The PNG writer and the 8-bit comparison share
 * it so that a comparison measures exactly the bytes a PNG would hold. */
static inline uint8_t sam_image_to_byte(float v, int srgb)
{
    if (srgb)
        v = sam_linear_to_srgb(v);
    v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* NaN fails v > 0 and becomes 0 */
    return (uint8_t)(v * 255.0f + 0.5f);
}

#ifdef __cplusplus
}
#endif

#endif
