#include "sam/sam_image.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_image_internal.h"

/* ------------------------------------------------------------------------ */
/* Image memory and size checks                                              */

sam_status sam_image_check_size(uint64_t width, uint64_t height, uint64_t channels, int from_file,
                                const char *what, sam_error *err)
{
    if (width == 0 || height == 0)
        return sam_fail(err, from_file ? SAM_ERR_FORMAT : SAM_ERR_INVALID_ARGUMENT,
                        "%s: empty image (%llu x %llu pixels)", what, (unsigned long long)width,
                        (unsigned long long)height);
    if (channels != 3 && channels != 4)
        return sam_fail(err, from_file ? SAM_ERR_FORMAT : SAM_ERR_INVALID_ARGUMENT,
                        "%s: %llu channels (expected 3 or 4)", what, (unsigned long long)channels);
    /* Testing the factors first keeps the product from wrapping. */
    if (width > SAM_IMAGE_MAX_PIXELS || height > SAM_IMAGE_MAX_PIXELS ||
        width * height > SAM_IMAGE_MAX_PIXELS)
        return sam_fail(err, from_file ? SAM_ERR_UNSUPPORTED : SAM_ERR_INVALID_ARGUMENT,
                        "%s: %llu x %llu pixels is more than the limit of %u pixels", what,
                        (unsigned long long)width, (unsigned long long)height,
                        SAM_IMAGE_MAX_PIXELS);
    return SAM_OK;
}

sam_status sam_image_create(sam_image *image, uint32_t width, uint32_t height, uint32_t channels,
                            sam_error *err)
{
    if (!image)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image create: NULL image");
    memset(image, 0, sizeof *image);
    sam_status st = sam_image_check_size(width, height, channels, 0, "image", err);
    if (st != SAM_OK)
        return st;
    size_t count = (size_t)width * height * channels;
    float *pixels = calloc(count, sizeof *pixels);
    if (!pixels)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "image: out of memory for %u x %u x %u floats",
                        width, height, channels);
    image->width = width;
    image->height = height;
    image->channels = channels;
    image->pixels = pixels;
    return SAM_OK;
}

void sam_image_destroy(sam_image *image)
{
    if (!image)
        return;
    free(image->pixels);
    memset(image, 0, sizeof *image);
}

sam_status sam_image_row(const sam_image *images, uint32_t count, sam_image *out, sam_error *err)
{
    if (!out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image row: NULL output image");
    memset(out, 0, sizeof *out);
    if (!images || !count)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image row: no images");
    uint64_t width = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const sam_image *a = &images[i];
        if (!a->pixels || !a->width || !a->height)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image row: image %u is empty", i);
        if (a->height != images[0].height || a->channels != images[0].channels)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "image row: image %u is %ux%u with %u channels, image 0 %ux%u with %u", i, a->width,
                            a->height, a->channels, images[0].width, images[0].height, images[0].channels);
        width += a->width;
    }
    if (width > UINT32_MAX)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image row: %llu pixels wide", (unsigned long long)width);
    const uint32_t c = images[0].channels, h = images[0].height;
    sam_status st = sam_image_create(out, (uint32_t)width, h, c, err);
    for (uint32_t i = 0, x0 = 0; st == SAM_OK && i < count; x0 += images[i++].width)
        for (uint32_t y = 0; y < h; ++y)
            memcpy(out->pixels + ((size_t)y * out->width + x0) * c, images[i].pixels + (size_t)y * images[i].width * c,
                   (size_t)images[i].width * c * sizeof *out->pixels);
    return st;
}

sam_status sam_image_check(const char *what, const sam_image *image, sam_error *err)
{
    if (!image || !image->pixels)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: no image given", what);
    return sam_image_check_size(image->width, image->height, image->channels, 0, what, err);
}

sam_status sam_image_check_output(const char *path, const sam_image *image, sam_error *err)
{
    if (!path || !path[0])
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image write: no output path given");
    return sam_image_check(path, image, err);
}

/* ------------------------------------------------------------------------ */
/* sRGB                                                                      */

float sam_srgb_to_linear(float encoded)
{
    if (encoded <= 0.04045f)
        return encoded / 12.92f;
    return powf((encoded + 0.055f) / 1.055f, 2.4f);
}

float sam_linear_to_srgb(float linear)
{
    if (linear <= 0.0031308f)
        return linear * 12.92f;
    return 1.055f * powf(linear, 1.0f / 2.4f) - 0.055f;
}

sam_status sam_image_from_bytes(sam_image *image, const uint8_t *raw, uint32_t w, uint32_t h, uint32_t c,
                                sam_png_encoding encoding, sam_error *err)
{
    sam_status st = sam_image_create(image, w, h, c, err);
    if (st != SAM_OK)
        return st;
    float table[256];
    for (int v = 0; v < 256; ++v)
        table[v] = encoding == SAM_PNG_SRGB ? sam_srgb_to_linear(v / 255.0f) : v / 255.0f;
    const size_t count = (size_t)w * h * c;
    for (size_t i = 0; i < count; ++i)
        image->pixels[i] = i % c == 3 ? raw[i] / 255.0f : table[raw[i]];
    return SAM_OK;
}
