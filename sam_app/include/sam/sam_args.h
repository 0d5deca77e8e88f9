/*
 * sam_args: the one command-line parser of the programs, so they agree on
 * how options are spelled, checked and reported.
 *
 * A program describes its options as a table of sam_arg and calls
 * sam_args_parse once:
 *
 *     float fps = 30;
 *     int quiet = 0;
 *     const char *out = NULL, *scene = NULL;
 *     const sam_arg args[] = {
 *         {"-o", SAM_ARG_STRING, &out, .value = "OUT.exr", .required = 1},
 *         {"--fps", SAM_ARG_FLOAT, &fps, .lo = 0, .hi = 1000, .lo_open = 1},
 *         {"--quiet", SAM_ARG_FLAG, .target = &quiet}, // designated: -Wextra wants every field or one name
 *     };
 *     const sam_args_spec spec = {"sam_render", args, 3, &scene, 1, 1, "SCENE.json", usage};
 *     int r = sam_args_parse(&spec, argc, argv);
 *     if (r != SAM_ARGS_OK)
 *         return r == SAM_ARGS_EXIT ? 0 : 2;
 *
 * Every message is one line on stderr that starts with the program's name
 * and names the option and the value found: an unknown option is called
 * unknown, a missing value or a missing required option or argument is
 * named, a number out of range gives the range. -h/--help prints the usage
 * to stdout and --version the project's version. An old spelling (`now`
 * set) still works and warns once with the new one.
 *
 * The vocabulary every program keeps: -o for the output, --size WxH for a
 * picture's pixels, --size-mm (or --mm-per-unit) for an object's real
 * size, --force wherever an existing file would be replaced.
 */
#ifndef SAM_ARGS_H
#define SAM_ARGS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sam_arg_kind {
    SAM_ARG_FLAG,   /* no value; *(int *)target = 1 */
    SAM_ARG_STRING, /* *(const char **)target = the value (argv's own, not copied) */
    SAM_ARG_CHOICE, /* *(int *)target = the value's index in `choices` */
    SAM_ARG_INT,    /* *(long *)target = a whole number in [lo, hi] */
    SAM_ARG_FLOAT,  /* *(float *)target = a finite number in [lo, hi] (ends open as flagged) */
    SAM_ARG_DOUBLE  /* *(double *)target, as FLOAT */
} sam_arg_kind;

typedef struct sam_arg {
    const char *name;            /* as typed: "-o", "--fps" */
    sam_arg_kind kind;
    void *target;                /* what kind says; written only when the option is given */
    double lo, hi;               /* INT, FLOAT, DOUBLE: the range */
    int lo_open, hi_open;        /* 1: the range excludes lo (hi) */
    const char *const *choices;  /* CHOICE: NULL-terminated names */
    const char *value;           /* the value's name in messages ("OUT.exr"); may be NULL */
    const char *must;            /* what a valid value is, for the message ("an odd number in 9..33");
                                  * NULL: said from the kind and range */
    int required;                /* 1: missing is an error that names it */
    int *given;                  /* may be NULL; set to 1 when the option appears */
    const char *now;             /* an old spelling kept for scripts: its name today, which a warning
                                  * gives when this one is used (the entry stores into the same target;
                                  * usage texts list only the new name) */
} sam_arg;

typedef struct sam_args_spec {
    const char *tool;             /* prefixes every message */
    const sam_arg *args;
    size_t arg_count;
    const char **positional;      /* receives the arguments that are not options, in order; may be NULL */
    size_t positional_min, positional_max;
    const char *positional_name;  /* names them in messages ("SCENE.json") */
    void (*usage)(FILE *out);     /* the program's help text */
} sam_args_spec;

enum {
    SAM_ARGS_OK = 0,   /* parsed: go on */
    SAM_ARGS_EXIT = 1, /* help or version printed: exit 0 */
    SAM_ARGS_BAD = 2   /* one message printed: exit 2 */
};

/* Parses argv[1..argc-1] by `spec`. Options and arguments may come in any
 * order; "--" ends the options. Returns SAM_ARGS_*. */
int sam_args_parse(const sam_args_spec *spec, int argc, char **argv);

/* Prints "TOOL: MESSAGE" on stderr and returns SAM_ARGS_BAD, for the checks
 * a program makes after parsing (options that exclude each other). */
int sam_args_fail(const char *tool, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Parses a comma-separated list of whole numbers (digits only: no spaces
 * or signs), each in [lo, hi], into
 * out (room for `max`), their number in *count. Returns 0 on an empty list,
 * a bad or out-of-range entry, or more than `max` entries; out and *count
 * are then unspecified. */
int sam_args_int_list(const char *text, long lo, long hi, long *out, int max, int *count);

/* Parses a picture size "WxH" (each a whole number in 1..16384) into `w`
 * and `h`. Returns 0, writing nothing, on anything else. */
int sam_args_size(const char *text, uint32_t *w, uint32_t *h);

/* Stores the sam_up_axis that --up's `text` names (sam_up_axis_parse) in
 * *up and returns SAM_ARGS_OK; `text` NULL (not given) leaves *up alone.
 * Anything else prints one line naming the axes ("TOOL: --up must be ...")
 * and returns SAM_ARGS_BAD. */
int sam_args_up(const char *tool, const char *text, int *up);

#ifdef __cplusplus
}
#endif

#endif
