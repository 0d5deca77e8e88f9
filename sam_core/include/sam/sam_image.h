/*
 * sam_image: float RGB/RGBA images, read from and written to OpenEXR (through
 * the OpenEXR Core C API) and 8-bit PNG (through libpng).
 *
 * A sam_image holds width * height * channels floats, interleaved per pixel,
 * row-major with the top row first. channels is 3 (RGB) or 4 (RGBA). EXR
 * values are linear; PNG values are 8/16-bit and the caller says whether
 * they are sRGB-encoded (decoded to / encoded from linear here) or stored as
 * given (sam_png_encoding). Alpha is never sRGB-encoded.
 *
 * For display and for judging renders, an HDR image is tonemapped to display
 * values (sam_image_tonemap), and two display images are compared the way
 * they would look as 8-bit sRGB PNGs (sam_image_compare_srgb8).
 *
 * Images larger than SAM_IMAGE_MAX_PIXELS are refused: such a size in a file
 * is far more likely corruption than a real environment map or render.
 *
 * Writers are atomic (sam_atomic_open/commit): on failure no file is left
 * behind and an existing file at the path is untouched.
 *
 * Every function is reentrant; none keeps global state.
 */
#ifndef SAM_IMAGE_H
#define SAM_IMAGE_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 2^28 pixels: a 16384 x 16384 image is the largest square accepted. */
#define SAM_IMAGE_MAX_PIXELS (1u << 28)

typedef struct sam_image {
    uint32_t width;
    uint32_t height;
    uint32_t channels; /* 3 (RGB) or 4 (RGBA) */
    float *pixels;     /* width * height * channels floats, row-major, top row first (owned) */
} sam_image;

typedef enum sam_exr_type {
    SAM_EXR_HALF = 0, /* 16-bit float channels */
    SAM_EXR_FLOAT = 1 /* 32-bit float channels */
} sam_exr_type;

typedef enum sam_png_encoding {
    SAM_PNG_SRGB = 0,  /* file holds sRGB-encoded colour; the image holds linear values */
    SAM_PNG_LINEAR = 1 /* file and image hold the same values (data, or already encoded) */
} sam_png_encoding;

/* Allocates a zero-filled width x height image with `channels` (3 or 4)
 * channels into `image` (its previous contents are overwritten, not freed).
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL image, zero size, channels not 3/4,
 * more than SAM_IMAGE_MAX_PIXELS pixels), SAM_ERR_OUT_OF_MEMORY. On failure
 * `image` is zeroed. */
sam_status sam_image_create(sam_image *image, uint32_t width, uint32_t height, uint32_t channels,
                            sam_error *err);

/* Frees the pixels and zeroes `image`. Safe on a zeroed image and on NULL. */
void sam_image_destroy(sam_image *image);

/* The `count` images side by side, left to right, into `out` (the
 * caller's, destroyed with sam_image_destroy): they must share height and
 * channels. Errors: SAM_ERR_INVALID_ARGUMENT (count 0, a NULL or empty
 * image, heights or channels that differ, naming both), and those of
 * sam_image_create. On failure `out` is zeroed. */
sam_status sam_image_row(const sam_image *images, uint32_t count, sam_image *out, sam_error *err);

/* Reads the first part of an OpenEXR file: scanline or tiled (level 0 of a
 * mip/rip-mapped file), with half, float or uint channels and any compression
 * the Core library decodes. The image covers the data window. Channels R, G,
 * B (any order in the file) give RGB; without them a Y channel is replicated
 * to RGB; an A channel adds alpha (channels = 4). Other channels are ignored.
 * `image` receives a new image (previous contents are overwritten, not
 * freed); the caller frees it with sam_image_destroy. On failure `image` is
 * zeroed.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL path/image), SAM_ERR_IO (cannot
 * open), SAM_ERR_FORMAT (not an EXR, bad header, truncated or corrupt
 * chunks, no usable channels: the message names the channels found),
 * SAM_ERR_UNSUPPORTED (deep data, subsampled channels, more than
 * SAM_IMAGE_MAX_PIXELS pixels), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_image_read_exr(const char *path, sam_image *image, sam_error *err);

/* Writes `image` as a single-part scanline EXR with ZIP compression and
 * channels R, G, B (and A when channels = 4) of the given type. Values that
 * do not fit a half become +-inf in SAM_EXR_HALF.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL arguments, an invalid image, an
 * unknown type), SAM_ERR_IO (create/write/rename failed; nothing is left at
 * `path`), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_image_write_exr(const char *path, const sam_image *image, sam_exr_type type,
                               sam_error *err);

/* Writes `image` as an 8-bit RGB or RGBA PNG. Values are clamped to [0, 1]
 * (NaN becomes 0); with SAM_PNG_SRGB colour channels are sRGB-encoded and the
 * file is tagged sRGB, with SAM_PNG_LINEAR they are stored as given and no
 * colour-space chunk is written.
 * Errors: SAM_ERR_INVALID_ARGUMENT, SAM_ERR_IO (nothing is left at `path`),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_image_write_png(const char *path, const sam_image *image,
                               sam_png_encoding encoding, sam_error *err);

/* Reads any PNG libpng can expand to 8- or 16-bit RGB(A): grey, grey+alpha,
 * palette (with tRNS transparency as alpha), RGB, RGBA, 1..16 bits,
 * interlaced or not. Values are scaled to [0, 1]; with SAM_PNG_SRGB colour
 * channels are decoded from sRGB to linear. The file's gAMA/sRGB/iCCP chunks
 * are ignored: `encoding` alone says how to interpret the values. channels is
 * 4 when the file has alpha, else 3. `image` receives a new image as for
 * sam_image_read_exr; on failure it is zeroed.
 * Errors: SAM_ERR_INVALID_ARGUMENT, SAM_ERR_IO (cannot read), SAM_ERR_FORMAT
 * (not a PNG, truncated, corrupt: libpng's message), SAM_ERR_UNSUPPORTED
 * (more than SAM_IMAGE_MAX_PIXELS pixels), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_image_read_png(const char *path, sam_image *image, sam_png_encoding encoding,
                              sam_error *err);

/* Reads a picture by its extension, as sam_image_read_png does a PNG:
 * .png through libpng, .jpg and .jpeg (baseline and progressive) and .tga
 * (uncompressed and RLE; grey, RGB, RGBA) through stb_image, 8 bits per
 * channel. Grey becomes RGB, grey with alpha RGBA. Same encoding, result
 * and errors as sam_image_read_png; SAM_ERR_UNSUPPORTED names the formats
 * for another extension. */
sam_status sam_image_read_picture(const char *path, sam_image *image, sam_png_encoding encoding,
                                  sam_error *err);

/* sRGB transfer functions (IEC 61966-2-1) on one value; inputs outside
 * [0, 1] follow the same formulas (negative inputs of the linear segment). */
float sam_srgb_to_linear(float encoded);
float sam_linear_to_srgb(float linear);

/* Tone curves from linear HDR x >= 0 to a display value in [0, 1]. */
typedef enum sam_tonemap {
    /* Narkowicz's ACES filmic fit x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14),
     * clamped to 1 (reached at x ~= 7.25) */
    SAM_TONEMAP_ACES = 0,
    SAM_TONEMAP_REINHARD = 1 /* x / (1 + x) */
} sam_tonemap;

/* Display values from the linear HDR image `hdr` (3 or 4 channels): each
 * colour channel is multiplied by 2^exposure_ev and put through `curve`;
 * negative and NaN values give 0, +inf gives 1. With 4 channels (straight,
 * not premultiplied, alpha) the result is composited over `backdrop`
 * (3 linear display values, each in [0, 1]; NULL = black) as
 * alpha * curve + (1 - alpha) * backdrop, alpha clamped to [0, 1] (NaN: 0).
 * `out` receives a new image of the same size with 3 channels, linear
 * (not yet sRGB-encoded: sam_image_write_png with SAM_PNG_SRGB encodes it),
 * every value in [0, 1]; previous contents are overwritten, not freed; the
 * caller frees it with sam_image_destroy. On failure `out` is zeroed.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL hdr/out, an invalid image, an
 * unknown curve, a non-finite exposure, a backdrop value outside [0, 1]:
 * the message gives the value), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_image_tonemap(const sam_image *hdr, sam_tonemap curve, float exposure_ev,
                             const float backdrop[3], sam_image *out, sam_error *err);

/* The backdrop sam_image_write_picture composites a render's background
 * over: a dark grey, so a black object stays visible. */
#define SAM_IMAGE_PICTURE_BACKDROP 0.02f

/* A render as the tools write it: the linear HDR image `hdr` to `exr`
 * (float EXR, alpha kept) when `exr` is not NULL and, when `png` is not
 * NULL, its display version (sam_image_tonemap with `curve` and
 * `exposure_ev` over the grey SAM_IMAGE_PICTURE_BACKDROP) to `png` as
 * sRGB; each written atomically.
 * Errors: SAM_ERR_INVALID_ARGUMENT (both NULL), those of
 * sam_image_write_exr, sam_image_tonemap and sam_image_write_png (the EXR
 * may exist when the PNG fails). */
sam_status sam_image_write_picture(const sam_image *hdr, const char *exr, const char *png, sam_tonemap curve,
                                   float exposure_ev, sam_error *err);

/* How far apart two display images are as 8-bit sRGB. Errors are in 8-bit
 * levels (0..255) over the 3 colour channels; PSNR = 20 log10(255 / rmse). */
typedef struct sam_image_comparison {
    uint64_t pixels;           /* pixels compared (those the mask selects) */
    uint64_t differing_pixels; /* of those, pixels where any 8-bit channel differs */
    double rmse;               /* over pixels x 3 channels */
    double psnr_db;            /* INFINITY when rmse == 0 */
    double rmse_differing;     /* over differing_pixels x 3 channels; 0 when none differ */
    double psnr_differing_db;  /* from rmse_differing; INFINITY when none differ */
} sam_image_comparison;

/* Compares display images `a` and `b` (values in [0, 1], linear; the same
 * width and height; 3 or 4 channels, of which the first 3 are compared)
 * after encoding each value to an 8-bit sRGB sample exactly as
 * sam_image_write_png with SAM_PNG_SRGB does (clamped, NaN as 0). `mask`
 * (same width and height, or NULL for every pixel) selects the pixels whose
 * last channel is > 0 (alpha for RGBA, blue for RGB): the object's pixels
 * of a render. The figures over the differing pixels only keep a local
 * error from being diluted by the many pixels that match exactly. On
 * success `out` holds the result; on failure it is zeroed.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL a/b/out, an invalid image, sizes
 * differ: the message names both, a mask that selects no pixel). */
sam_status sam_image_compare_srgb8(const sam_image *a, const sam_image *b, const sam_image *mask,
                                   sam_image_comparison *out, sam_error *err);

/* Draws `text` (ASCII; '\n' starts a line) into an image of 3 or 4
 * channels with its top-left corner at pixel (x, y), in colour `rgb` (the
 * first three channels), each pixel of stb_easy_font's segment font
 * `scale` x `scale` image pixels (a glyph is about 6 x 12 font pixels).
 * Clipped to the image. Returns the width of its longest line in image
 * pixels; 0, drawing nothing, for a NULL or invalid argument or when out of
 * memory. */
int sam_image_draw_text(sam_image *img, int x, int y, int scale, const float rgb[3], const char *text);

/* The width in image pixels sam_image_draw_text gives `text` at `scale`. */
int sam_image_text_width(const char *text, int scale);

#ifdef __cplusplus
}
#endif

#endif
