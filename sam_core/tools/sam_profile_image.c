/*
 * sam_profile_image: draws a material to a PNG (sam_profile_plot): a point
 * of light entering it, the energy per log radius with its 8-Gaussian fit
 * on labelled axes, and a sphere and a wedge lit from behind.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>

#include "sam/sam_app_output.h"
#include "sam/sam_args.h"
#include "sam/sam_image.h"
#include "sam/sam_profile.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_profile_image MATERIAL -o OUT.png [--size N] [--force]\n"
            "\n"
            "Draws a material: a point of light seen through it (top left); the energy per log\n"
            "radius 2 pi r^2 R_d(r) per channel from 1/1000 of the radius holding 99%% of the\n"
            "energy to that radius, the profile solid and its 8-Gaussian fit dotted, ticks in mm\n"
            "(top right); a sphere half that radius across and a wedge from 0 to that radius thick,\n"
            "both lit from behind (below).\n"
            "  MATERIAL   a preset (skin, marble, apple, chicken1, chicken2, cream, ketchup,\n"
            "             potato, skimmilk, skin1, skin2, wholemilk) or a material file (.json,\n"
            "             .txt): gaussians, dipole, burley (albedo and mean free path or scatter\n"
            "             radius) or a table of R_d(r)\n"
            "  -o OUT.png output image (written atomically)\n"
            "  --size N   height of the top row in pixels, 64..4096 (default 512); the picture\n"
            "             is 2N x 3N/2, labelled from N = 256\n"
            "  --force    replace OUT.png if it exists\n"
            "\n"
            "examples:\n"
            "  sam_profile_image skin -o skin.png\n"
            "  sam_profile_image scenes/materials/skin_burley.json -o mine.png --size 256\n");
}

int main(int argc, char **argv)
{
    const char *material = NULL, *out = NULL;
    long size = 512;
    int force = 0;
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &out, .value = "OUT.png", .required = 1},
        {"--size", SAM_ARG_INT, &size, .lo = 64, .hi = 4096},
        {"--force", SAM_ARG_FLAG, .target = &force},
    };
    const sam_args_spec spec = {"sam_profile_image", args, sizeof args / sizeof *args, &material, 1, 1, "MATERIAL",
                                usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    sam_profile profile;
    sam_image img;
    sam_error err;
    float extent;
    static const char *const pngs[] = {".png", NULL};
    sam_status st = sam_app_check_output("-o", out, pngs, force, &err);
    if (st == SAM_OK)
        st = sam_profile_from_spec(material, &profile, &err);
    if (st == SAM_OK && (st = sam_profile_plot(&profile, (uint32_t)size, &img, &extent, &err)) == SAM_OK) {
        st = sam_image_write_png(out, &img, SAM_PNG_LINEAR, &err);
        sam_image_destroy(&img);
    }
    if (st != SAM_OK) {
        fprintf(stderr, "sam_profile_image: %s\n", err.message);
        return 1;
    }
    float total[3];
    sam_profile_total_reflectance(&profile, total);
    fprintf(stderr,
            "sam_profile_image: %s: total diffuse reflectance (%.3f, %.3f, %.3f), 99%% of the energy "
            "within %.3g mm; wrote %s\n",
            profile.name, total[0], total[1], total[2], extent, out);
    return 0;
}
