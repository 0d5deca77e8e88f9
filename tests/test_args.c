/* sam_args: the programs' option parser; and sam_app's interrupt handling. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "sam/sam_app.h"
#include "sam/sam_args.h"
#include "sam/sam_scene.h"
#include "sam/sam_version.h"
#include "sam_test.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: tool SCENE -o OUT [options]\n");
}

typedef struct options {
    const char *out, *scene;
    float fps;
    long frames;
    int quiet, technique, frames_given;
} options;

/* Parses the NULL-terminated arguments after the program's name and returns
 * the parser's result; `message` gets what it printed on stderr. */
static int parse(options *o, char *message, size_t n, ...)
{
    static const char *const techniques[] = {"sam", "none", NULL};
    memset(o, 0, sizeof *o);
    o->fps = 30;
    o->frames = 1;
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &o->out, .value = "OUT", .required = 1},
        {"--fps", SAM_ARG_FLOAT, &o->fps, .lo = 0, .hi = 1000, .lo_open = 1},
        {"--frames", SAM_ARG_INT, &o->frames, .lo = 1, .hi = 100, .given = &o->frames_given},
        {"--technique", SAM_ARG_CHOICE, &o->technique, .choices = techniques},
        {"--quiet", SAM_ARG_FLAG, .target = &o->quiet},
    };
    const sam_args_spec spec = {"tool", args, sizeof args / sizeof *args, &o->scene, 1, 1, "SCENE", usage};
    char *argv[16] = {"tool"};
    int argc = 1;
    va_list ap;
    va_start(ap, n);
    for (char *a; argc < 16 && (a = va_arg(ap, char *));)
        argv[argc++] = a;
    va_end(ap);
    char path[512];
    sam_test_tmp_path(path, sizeof path, "args_stderr.txt");
    fflush(stderr);
    int saved = dup(2);
    FILE *f = fopen(path, "w+");
    assert_non_null(f);
    dup2(fileno(f), 2);
    int r = sam_args_parse(&spec, argc, argv);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    rewind(f);
    size_t got = fread(message, 1, n - 1, f);
    message[got] = 0;
    fclose(f);
    return r;
}

static void test_values_land_in_their_targets(void **state)
{
    (void)state;
    options o;
    char msg[256];
    assert_int_equal(parse(&o, msg, sizeof msg, "s.json", "--fps", "24", "-o", "x.exr", "--quiet", "--technique",
                           "none", "--frames", "7", NULL),
                     SAM_ARGS_OK);
    assert_string_equal(msg, "");
    assert_string_equal(o.scene, "s.json");
    assert_string_equal(o.out, "x.exr");
    assert_true(o.fps == 24.0f);
    assert_int_equal(o.frames, 7);
    assert_int_equal(o.frames_given, 1);
    assert_int_equal(o.quiet, 1);
    assert_int_equal(o.technique, 1);
    /* "--" ends the options: a file may start with a dash. */
    assert_int_equal(parse(&o, msg, sizeof msg, "-o", "x", "--", "-scene.json", NULL), SAM_ARGS_OK);
    assert_string_equal(o.scene, "-scene.json");
}

static void test_bad_input_is_named(void **state)
{
    (void)state;
    options o;
    char msg[256];
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "-o", "x", "--fsp", "3", NULL), SAM_ARGS_BAD);
    assert_string_equal(msg, "tool: unknown option \"--fsp\" (see --help)\n");
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "-o", NULL), SAM_ARGS_BAD);
    assert_string_equal(msg, "tool: -o needs a value: OUT (see --help)\n");
    assert_int_equal(parse(&o, msg, sizeof msg, "s", NULL), SAM_ARGS_BAD);
    assert_string_equal(msg, "tool: missing -o OUT (see --help)\n");
    assert_int_equal(parse(&o, msg, sizeof msg, "-o", "x", NULL), SAM_ARGS_BAD);
    assert_string_equal(msg, "tool: missing SCENE (see --help)\n");
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "t", "-o", "x", NULL), SAM_ARGS_BAD);
    assert_string_equal(msg, "tool: unexpected argument \"t\" (see --help)\n");
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "-o", "x", "--fps", "0", NULL), SAM_ARGS_BAD);
    assert_string_equal(msg, "tool: --fps must be a number in (0, 1000], got \"0\"\n");
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "-o", "x", "--fps", "", NULL), SAM_ARGS_BAD);
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "-o", "x", "--fps", "1e999", NULL), SAM_ARGS_BAD);
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "-o", "x", "--frames", "2.5", NULL), SAM_ARGS_BAD);
    assert_string_equal(msg, "tool: --frames must be a whole number in 1..100, got \"2.5\"\n");
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "-o", "x", "--technique", "tsm", NULL), SAM_ARGS_BAD);
    assert_string_equal(msg, "tool: --technique must be sam or none, got \"tsm\"\n");
    /* A rejected value leaves the default in place. */
    assert_true(o.fps == 30.0f);
}

static void test_help_and_version_exit(void **state)
{
    (void)state;
    options o;
    char msg[256];
    assert_int_equal(parse(&o, msg, sizeof msg, "--version", NULL), SAM_ARGS_EXIT);
    assert_int_equal(parse(&o, msg, sizeof msg, "s", "-h", NULL), SAM_ARGS_EXIT);
    assert_string_equal(sam_version(), SAM_VERSION_STRING);
    assert_int_equal(sam_version_number(), SAM_VERSION_MAJOR * 10000 + SAM_VERSION_MINOR * 100 + SAM_VERSION_PATCH);
    assert_int_equal(sam_args_fail("tool", "%d and %s", 3, "x"), SAM_ARGS_BAD);
}

static volatile sig_atomic_t caught;

static void on_signal(int sig)
{
    caught = sig;
}

static void expect_default(int sig)
{
    struct sigaction now;
    assert_int_equal(sigaction(sig, NULL, &now), 0);
    assert_true(now.sa_handler == SIG_DFL);
}

/* Lists of whole numbers: each entry in range, no empty entry, no more
 * than the room given. */
static void test_int_lists(void **state)
{
    (void)state;
    long v[3];
    int n;
    assert_int_equal(sam_args_int_list("3,32,64", 1, 64, v, 3, &n), 1);
    assert_int_equal(n, 3);
    assert_int_equal(v[0], 3);
    assert_int_equal(v[2], 64);
    assert_int_equal(sam_args_int_list("7", 1, 64, v, 3, &n), 1);
    assert_int_equal(n, 1);
    static const char *const bad[] = {"", "0", "65", "3,,4", "3,", "1,2,3,4", "x", "3 4", "2.5", " 3", "+3", "3, 4"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i)
        assert_int_equal(sam_args_int_list(bad[i], 1, 64, v, 3, &n), 0);
}

/* --up: not given leaves the guess, an axis is stored, anything else is
 * refused (its one line goes to stderr) and stores nothing. */
static void test_up_axis_option(void **state)
{
    (void)state;
    int up = -1;
    assert_int_equal(sam_args_up("tool", NULL, &up), SAM_ARGS_OK);
    assert_int_equal(up, -1);
    assert_int_equal(sam_args_up("tool", "-z", &up), SAM_ARGS_OK);
    assert_int_equal(up, SAM_UP_NEG_Z);
    assert_int_equal(sam_args_up("tool", "sideways", &up), SAM_ARGS_BAD);
    assert_int_equal(up, SAM_UP_NEG_Z);
}

/* The first SIGINT or SIGTERM reaches the handler (a clean cancel); the
 * next one would end the program, which a build that never reads the flag
 * (a long load) needs. */
static void test_interrupts_are_caught_once(void **state)
{
    (void)state;
    const int sigs[] = {SIGINT, SIGTERM};
    for (int k = 0; k < 2; ++k) {
        caught = 0;
        sam_app_catch_interrupts(on_signal);
        assert_int_equal(raise(sigs[k]), 0);
        assert_int_equal(caught, sigs[k]);
        expect_default(sigs[k]);
        sam_app_catch_interrupts(NULL);
        expect_default(SIGINT);
        expect_default(SIGTERM);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_values_land_in_their_targets),
        cmocka_unit_test(test_bad_input_is_named),
        cmocka_unit_test(test_help_and_version_exit),
        cmocka_unit_test(test_int_lists),
        cmocka_unit_test(test_up_axis_option),
        cmocka_unit_test(test_interrupts_are_caught_once),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
