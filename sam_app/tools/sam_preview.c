/*
 * sam_preview: a CPU picture of the translucency a .sam encodes; the job
 * itself is sam_app_preview_write.
 */
#include <stdio.h>
#include <string.h>

#include "sam/sam_app_output.h"
#include "sam/sam_app_preview.h"
#include "sam/sam_args.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_preview FILE.sam -o OUT.png [--size N] [--view x|y|z|-x|-y|-z] [--force]\n"
            "\n"
            "Renders the translucency a .sam encodes, on the CPU: a point light behind the\n"
            "object (with Embree shadows), the light carried through by the stored back-side\n"
            "samples (SAM eq. 12) in colour, the surface dimly lit from the camera in grey.\n"
            "  -o OUT.png   output (sRGB PNG, written atomically)\n"
            "  --size N     image height and width in pixels, 16..4096 (default 512)\n"
            "  --view AXIS  the camera looks along AXIS; default: along the object's thinnest\n"
            "               extent, so the light shines through it towards the camera\n"
            "  --force      replace OUT.png if it exists\n"
            "\n"
            "examples (ear.sam and knot32.sam as sam_build --help makes them):\n"
            "  sam_preview ear.sam -o ear_preview.png\n"
            "  sam_preview knot32.sam -o knot_side.png --view -x --size 1024\n");
}

int main(int argc, char **argv)
{
    static const char *const views[] = {"x", "y", "z", "-x", "-y", "-z", NULL};
    sam_app_preview_job job;
    sam_app_preview_defaults(&job);
    int view = -1, force = 0;
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &job.out, .value = "OUT.png", .required = 1},
        {"--size", SAM_ARG_INT, &job.size, .lo = 16, .hi = 4096},
        {"--view", SAM_ARG_CHOICE, &view, .choices = views},
        {"--force", SAM_ARG_FLAG, .target = &force},
    };
    const sam_args_spec spec = {"sam_preview", args, sizeof args / sizeof *args, &job.in, 1, 1, "FILE.sam", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (view >= 0) {
        job.axis = view % 3;
        job.sign = view < 3 ? 1 : -1;
    }
    sam_error err;
    static const char *const pngs[] = {".png", NULL};
    if (sam_app_check_output("-o", job.out, pngs, force, &err) != SAM_OK ||
        sam_app_preview_write(&job, "sam_preview", &err) != SAM_OK) {
        fprintf(stderr, "sam_preview: %s\n", err.message);
        return 1;
    }
    return 0;
}
