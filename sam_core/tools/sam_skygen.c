/*
 * sam_skygen: writes a procedural lat-long HDR environment map (a studio or
 * an outdoor sky, see sam_light_make_sky) as a half-float EXR.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sam/sam_args.h"
#include "sam/sam_image.h"
#include "sam/sam_light.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_skygen studio|outdoor -o OUT.exr [--width W] [--force]\n"
            "\n"
            "Writes a latitude-longitude HDR environment map (W x W/2, RGB half float EXR;\n"
            "+Y up, the top row looks up, the left column faces +Z, a quarter across +X).\n"
            "  studio      grey floor, soft gradient, three large soft light boxes (radiance 4..12)\n"
            "  outdoor     blue sky to a hazy horizon, ground, a small sun disk (radiance 5000)\n"
            "  -o OUT.exr  output file (written atomically)\n"
            "  --width W   even width in pixels, 8..16384 (default 1024)\n"
            "  --force     overwrite OUT.exr if it exists\n"
            "\n"
            "examples:\n"
            "  sam_skygen studio -o studio.exr\n"
            "  sam_skygen outdoor -o outdoor.exr --width 2048\n");
}

int main(int argc, char **argv)
{
    const char *kind_name = NULL, *out = NULL;
    long width = 1024;
    int force = 0;
    static const char even_width[] = "an even integer in 8..16384";
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &out, .value = "OUT.exr", .required = 1},
        {"--width", SAM_ARG_INT, &width, .lo = 8, .hi = 16384, .must = even_width},
        {"--force", SAM_ARG_FLAG, .target = &force},
    };
    const sam_args_spec spec = {"sam_skygen", args, sizeof args / sizeof *args, &kind_name, 1, 1,
                                "the kind, studio or outdoor", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (width % 2)
        return sam_args_fail("sam_skygen", "--width must be %s, got \"%ld\"", even_width, width);
    int kind;
    if (!strcmp(kind_name, "studio")) {
        kind = SAM_SKY_STUDIO;
    } else if (!strcmp(kind_name, "outdoor")) {
        kind = SAM_SKY_OUTDOOR;
    } else {
        fprintf(stderr, "sam_skygen: unknown kind \"%s\" (expected studio or outdoor)\n", kind_name);
        return 2;
    }
    struct stat info;
    if (!force && stat(out, &info) == 0) {
        fprintf(stderr, "sam_skygen: %s exists; use --force to overwrite it\n", out);
        return 1;
    }

    sam_image img;
    sam_error err;
    if (sam_light_make_sky((uint32_t)width, (uint32_t)(width / 2), kind, &img, &err) != SAM_OK) {
        fprintf(stderr, "sam_skygen: %s\n", err.message);
        return 1;
    }
    sam_status st = sam_image_write_exr(out, &img, SAM_EXR_HALF, &err);
    sam_image_destroy(&img);
    if (st != SAM_OK) {
        fprintf(stderr, "sam_skygen: %s\n", err.message);
        return 1;
    }
    fprintf(stderr, "sam_skygen: wrote %s (%s, %ldx%ld)\n", out, kind_name, width, width / 2);
    return 0;
}
