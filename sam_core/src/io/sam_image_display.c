#include "sam/sam_image.h"

#include <math.h>
#include <string.h>

#include "sam_image_internal.h"

/* ------------------------------------------------------------------------ */
/* Display: tonemapping and 8-bit comparison                                 */

/* `curve` at x. No light (negative, NaN) is black. Both curves are 1 long
 * before their polynomials overflow (ACES clamps from x ~= 7.25, Reinhard
 * rounds to 1 in float from 2^24), so large values and +inf give 1
 * directly instead of inf / inf. */
static float tone_curve(sam_tonemap curve, float x)
{
    if (!(x > 0.0f))
        return 0.0f;
    if (x >= 0x1p24f)
        return 1.0f;
    if (curve == SAM_TONEMAP_REINHARD)
        return x / (1.0f + x);
    float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    return y < 1.0f ? y : 1.0f;
}

sam_status sam_image_tonemap(const sam_image *hdr, sam_tonemap curve, float exposure_ev,
                             const float backdrop[3], sam_image *out, sam_error *err)
{
    if (!out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image tonemap: NULL output image");
    memset(out, 0, sizeof *out);
    sam_status st = sam_image_check("image tonemap", hdr, err);
    if (st != SAM_OK)
        return st;
    if (curve != SAM_TONEMAP_ACES && curve != SAM_TONEMAP_REINHARD)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image tonemap: unknown curve %d",
                        (int)curve);
    if (!isfinite(exposure_ev))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "image tonemap: exposure %g EV is not finite", exposure_ev);
    float back[3] = {0.0f, 0.0f, 0.0f};
    for (int k = 0; backdrop && k < 3; ++k) {
        if (!(backdrop[k] >= 0.0f && backdrop[k] <= 1.0f))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "image tonemap: backdrop[%d] = %g is outside [0, 1]", k, backdrop[k]);
        back[k] = backdrop[k];
    }
    if ((st = sam_image_create(out, hdr->width, hdr->height, 3, err)) != SAM_OK)
        return st;
    const float scale = exp2f(exposure_ev);
    const uint32_t c = hdr->channels;
    const size_t n = (size_t)hdr->width * hdr->height;
    for (size_t i = 0; i < n; ++i) {
        const float *in = hdr->pixels + i * c;
        float *o = out->pixels + i * 3;
        float a = 1.0f;
        if (c == 4)
            a = in[3] > 0.0f ? (in[3] < 1.0f ? in[3] : 1.0f) : 0.0f; /* NaN becomes 0 */
        for (int k = 0; k < 3; ++k)
            o[k] = a * tone_curve(curve, in[k] * scale) + (1.0f - a) * back[k];
    }
    return SAM_OK;
}

sam_status sam_image_write_picture(const sam_image *hdr, const char *exr, const char *png, sam_tonemap curve,
                                   float exposure_ev, sam_error *err)
{
    if (!exr && !png)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "write picture: neither an EXR nor a PNG path");
    sam_status st = exr ? sam_image_write_exr(exr, hdr, SAM_EXR_FLOAT, err) : SAM_OK;
    if (st != SAM_OK || !png)
        return st;
    static const float backdrop[3] = {SAM_IMAGE_PICTURE_BACKDROP, SAM_IMAGE_PICTURE_BACKDROP,
                                      SAM_IMAGE_PICTURE_BACKDROP};
    sam_image preview;
    st = sam_image_tonemap(hdr, curve, exposure_ev, backdrop, &preview, err);
    if (st == SAM_OK)
        st = sam_image_write_png(png, &preview, SAM_PNG_SRGB, err);
    sam_image_destroy(&preview);
    return st;
}

/* RMSE of `values` values whose squared errors sum to `sum`, and its PSNR
 * in dB for 8-bit samples; 0 and INFINITY for a zero sum. */
static void rmse_psnr(uint64_t sum, uint64_t values, double *rmse, double *psnr_db)
{
    *rmse = sum ? sqrt((double)sum / (double)values) : 0.0;
    *psnr_db = sum ? 20.0 * log10(255.0 / *rmse) : INFINITY;
}

sam_status sam_image_compare_srgb8(const sam_image *a, const sam_image *b, const sam_image *mask,
                                   sam_image_comparison *out, sam_error *err)
{
    if (!out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image compare: NULL result");
    memset(out, 0, sizeof *out);
    sam_status st = sam_image_check("image compare: first image", a, err);
    if (st == SAM_OK)
        st = sam_image_check("image compare: second image", b, err);
    if (st == SAM_OK && mask)
        st = sam_image_check("image compare: mask", mask, err);
    if (st != SAM_OK)
        return st;
    if (a->width != b->width || a->height != b->height)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "image compare: the images differ in size: %u x %u and %u x %u pixels",
                        a->width, a->height, b->width, b->height);
    if (mask && (mask->width != a->width || mask->height != a->height))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "image compare: the mask is %u x %u pixels, the images %u x %u",
                        mask->width, mask->height, a->width, a->height);

    /* Squared byte differences are integers: summed exactly in 64 bits
     * (at most 2^28 pixels x 3 x 255^2 < 2^46), so the result does not
     * depend on the order of the sum. */
    uint64_t pixels = 0, differing = 0, sum = 0;
    const size_t n = (size_t)a->width * a->height;
    for (size_t i = 0; i < n; ++i) {
        if (mask && !(mask->pixels[i * mask->channels + mask->channels - 1] > 0.0f))
            continue;
        const float *pa = a->pixels + i * a->channels, *pb = b->pixels + i * b->channels;
        uint64_t d2 = 0;
        for (int k = 0; k < 3; ++k) {
            int d = (int)sam_image_to_byte(pa[k], 1) - (int)sam_image_to_byte(pb[k], 1);
            d2 += (uint64_t)(d * d);
        }
        ++pixels;
        differing += d2 != 0;
        sum += d2;
    }
    if (pixels == 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "image compare: the mask selects none of the %u x %u pixels (no last "
                        "channel > 0)", mask->width, mask->height);
    out->pixels = pixels;
    out->differing_pixels = differing;
    rmse_psnr(sum, 3 * pixels, &out->rmse, &out->psnr_db);
    rmse_psnr(sum, 3 * differing, &out->rmse_differing, &out->psnr_differing_db);
    return SAM_OK;
}
