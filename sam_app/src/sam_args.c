/* The programs' option parser (sam_args.h). */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_args.h"
#include "sam/sam_common.h"
#include "sam/sam_scene.h"
#include "sam/sam_version.h"

int sam_args_fail(const char *tool, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", tool);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return SAM_ARGS_BAD;
}

/* What a valid value of `a` is, for messages. */
static void describe(const sam_arg *a, char *buf, size_t n)
{
    if (a->must) {
        snprintf(buf, n, "%s", a->must);
    } else if (a->kind == SAM_ARG_CHOICE) {
        size_t len = 0, count = 0;
        while (a->choices[count])
            count++;
        for (size_t i = 0; i < count && len < n; ++i)
            len += (size_t)snprintf(buf + len, n - len, "%s%s", i == 0 ? "" : i + 1 == count ? " or " : ", ",
                                    a->choices[i]);
    } else if (a->kind == SAM_ARG_INT) {
        snprintf(buf, n, "a whole number in %.0f..%.0f", a->lo, a->hi);
    } else {
        snprintf(buf, n, "a number in %c%g, %g%c", a->lo_open ? '(' : '[', a->lo, a->hi, a->hi_open ? ')' : ']');
    }
}

/* Stores `text` as option `a`'s value; 0 when it is not a valid one. */
static int store(const sam_arg *a, const char *text)
{
    switch (a->kind) {
    case SAM_ARG_STRING:
        *(const char **)a->target = text;
        return 1;
    case SAM_ARG_CHOICE:
        for (int i = 0; a->choices[i]; ++i)
            if (!strcmp(a->choices[i], text)) {
                *(int *)a->target = i;
                return 1;
            }
        return 0;
    case SAM_ARG_INT: {
        char *end;
        long v = strtol(text, &end, 10);
        if (end == text || *end || v < a->lo || v > a->hi)
            return 0;
        *(long *)a->target = v;
        return 1;
    }
    case SAM_ARG_FLOAT:
    case SAM_ARG_DOUBLE: {
        double v;
        if (!sam_parse_double(text, &v) || !isfinite(v) || (a->kind == SAM_ARG_FLOAT && !isfinite((float)v)))
            return 0;
        if (v < a->lo || v > a->hi || (a->lo_open && v == a->lo) || (a->hi_open && v == a->hi))
            return 0;
        if (a->kind == SAM_ARG_FLOAT)
            *(float *)a->target = (float)v;
        else
            *(double *)a->target = v;
        return 1;
    }
    case SAM_ARG_FLAG:
        *(int *)a->target = 1;
        return 1;
    }
    return 0;
}

static const sam_arg *find(const sam_args_spec *spec, const char *name)
{
    for (size_t i = 0; i < spec->arg_count; ++i)
        if (!strcmp(spec->args[i].name, name))
            return &spec->args[i];
    return NULL;
}

int sam_args_int_list(const char *text, long lo, long hi, long *out, int max, int *count)
{
    *count = 0;
    const char *p = text;
    while (*p) {
        if (*p < '0' || *p > '9')
            return 0; /* strtol would take spaces and signs */
        char *end;
        long v = strtol(p, &end, 10);
        if (end == p || (*end && *end != ',') || v < lo || v > hi || *count == max)
            return 0;
        out[(*count)++] = v;
        if (*end && !end[1])
            return 0; /* a trailing comma */
        p = *end ? end + 1 : end;
    }
    return *count > 0;
}

int sam_args_size(const char *text, uint32_t *w, uint32_t *h)
{
    long a, b;
    char tail;
    if (sscanf(text, "%ldx%ld%c", &a, &b, &tail) != 2 || a < 1 || b < 1 || a > 16384 || b > 16384)
        return 0;
    *w = (uint32_t)a;
    *h = (uint32_t)b;
    return 1;
}

int sam_args_parse(const sam_args_spec *spec, int argc, char **argv)
{
    const char *tool = spec->tool;
    unsigned char seen[64] = {0};
    size_t positional = 0;
    int options_done = 0;
    if (spec->arg_count > sizeof seen)
        return sam_args_fail(tool, "internal error: %zu options, at most %zu", spec->arg_count, sizeof seen);
    for (int i = 1; i < argc; ++i) {
        const char *text = argv[i];
        int is_option = !options_done && text[0] == '-' && text[1];
        if (is_option && !strcmp(text, "--")) {
            options_done = 1;
            continue;
        }
        if (is_option && (!strcmp(text, "-h") || !strcmp(text, "--help"))) {
            spec->usage(stdout);
            return SAM_ARGS_EXIT;
        }
        if (is_option && !strcmp(text, "--version")) {
            printf("%s %s\n", tool, sam_version());
            return SAM_ARGS_EXIT;
        }
        if (!is_option) {
            if (positional >= spec->positional_max)
                return sam_args_fail(tool, "unexpected argument \"%s\" (see --help)", text);
            spec->positional[positional++] = text;
            continue;
        }
        const sam_arg *a = find(spec, text);
        if (!a)
            return sam_args_fail(tool, "unknown option \"%s\" (see --help)", text);
        seen[a - spec->args] = 1;
        if (a->given)
            *a->given = 1;
        if (a->now) {
            fprintf(stderr, "%s: warning: %s is now %s (the old spelling still works)\n", tool, text, a->now);
            const sam_arg *today = find(spec, a->now);
            if (today)
                seen[today - spec->args] = 1;
        }
        if (a->kind == SAM_ARG_FLAG) {
            store(a, NULL);
            continue;
        }
        if (i + 1 >= argc)
            return sam_args_fail(tool, "%s needs a value%s%s (see --help)", text, a->value ? ": " : "",
                                 a->value ? a->value : "");
        const char *value = argv[++i];
        if (!store(a, value)) {
            char must[256];
            describe(a, must, sizeof must);
            return sam_args_fail(tool, "%s must be %s, got \"%s\"", text, must, value);
        }
    }
    if (positional < spec->positional_min)
        return sam_args_fail(tool, "missing %s (see --help)", spec->positional_name ? spec->positional_name : "argument");
    for (size_t k = 0; k < spec->arg_count; ++k)
        if (spec->args[k].required && !seen[k])
            return sam_args_fail(tool, "missing %s %s (see --help)", spec->args[k].name,
                                 spec->args[k].value ? spec->args[k].value : "");
    return SAM_ARGS_OK;
}

int sam_args_up(const char *tool, const char *text, int *up)
{
    sam_up_axis axis;
    if (!text)
        return SAM_ARGS_OK;
    if (!sam_up_axis_parse(text, &axis))
        return sam_args_fail(tool, "--up must be +X, -X, +Y, -Y, +Z or -Z, got \"%s\"", text);
    *up = (int)axis;
    return SAM_ARGS_OK;
}
