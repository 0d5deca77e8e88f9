#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <GLFW/glfw3.h>

#include "sam/sam_view_script.h"
#include "sam_test.h"

static const char good[] = "# a comment line\n"
                           "0 key shift+T   # trailing comment\n"
                           "\n"
                           "0.5 mouse 10 20.5\n"
                           "0.5 drag middle 1 2 3 4\n"
                           "1 scroll -2\n"
                           "1 resize 640 480\n"
                           "2 key F12\n"
                           "2 key [\n"
                           "2 screenshot out/shot\n"
                           "3 lose-context\n"
                           "3 quit";

static void test_parses_every_action(void **state)
{
    (void)state;
    sam_view_event *e;
    size_t n;
    sam_error err;
    if (sam_view_script_parse(good, strlen(good), "s.txt", &e, &n, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(n, 10);
    assert_int_equal(e[0].action, SAM_VIEW_KEY);
    assert_int_equal(e[0].key, GLFW_KEY_T);
    assert_int_equal(e[0].mods, GLFW_MOD_SHIFT);
    assert_int_equal(e[0].line, 2);
    assert_int_equal(e[1].action, SAM_VIEW_MOUSE);
    assert_true(e[1].x0 == 10.0f && e[1].y0 == 20.5f);
    assert_int_equal(e[2].button, GLFW_MOUSE_BUTTON_MIDDLE);
    assert_true(e[2].x0 == 1 && e[2].y0 == 2 && e[2].x1 == 3 && e[2].y1 == 4);
    assert_true(e[3].y0 == -2.0f);
    assert_true(e[4].action == SAM_VIEW_RESIZE && e[4].x0 == 640 && e[4].y0 == 480);
    assert_int_equal(e[5].key, GLFW_KEY_F12);
    assert_int_equal(e[6].key, GLFW_KEY_LEFT_BRACKET);
    assert_string_equal(e[7].path, "out/shot");
    assert_int_equal(e[8].action, SAM_VIEW_LOSE_CONTEXT);
    assert_int_equal(e[9].action, SAM_VIEW_QUIT);
    assert_true(e[9].time_s == 3.0);
    free(e);
}

static void expect_error(const char *text, const char *message)
{
    sam_view_event *e = (sam_view_event *)1;
    size_t n = 7;
    sam_error err;
    assert_int_equal(sam_view_script_parse(text, strlen(text), "s.txt", &e, &n, &err), SAM_ERR_FORMAT);
    assert_null(e);
    assert_int_equal(n, 0);
    if (strcmp(err.message, message))
        fail_msg("for \"%s\": expected \"%s\", got \"%s\"", text, message, err.message);
}

static void test_errors_name_line_and_value(void **state)
{
    (void)state;
    expect_error("0 key A\nsoon key B", "s.txt:2: expected a time in seconds in [0, 1e6], found \"soon\"");
    expect_error("1 jump", "s.txt:1: unknown action \"jump\" (expected key, mouse, drag, scroll, resize, "
                           "screenshot, lose-context or quit)");
    expect_error("1 key", "s.txt:1: key takes 1 argument, found 0");
    expect_error("1 quit now", "s.txt:1: quit takes 0 arguments, found 1");
    expect_error("1 key F13", "s.txt:1: unknown key \"F13\" (a letter, a digit, [ ] , . - = /, SPACE, ESCAPE, ENTER, "
                              "TAB, LEFT, RIGHT, UP, DOWN or F1..F12)");
    expect_error("1 drag top 0 0 1 1", "s.txt:1: unknown button \"top\" (expected left, right or middle)");
    expect_error("1 mouse 1 x", "s.txt:1: mouse: expected a pixel coordinate, found \"x\"");
    expect_error("1 resize 0 10", "s.txt:1: resize: expected a size in 1..16384, found \"0\"");
    expect_error("1 scroll 1e9", "s.txt:1: scroll: expected notches in [-100, 100], found \"1e9\"");
    expect_error("2 quit\n1 quit", "s.txt:2: time 1 s is before the previous event's 2 s");
    expect_error("7", "s.txt:1: expected TIME ACTION [ARGS], found only \"7\"");
    expect_error("nan key A", "s.txt:1: expected a time in seconds in [0, 1e6], found \"nan\"");
}

/* Every prefix of a valid script parses or fails cleanly (ASan checks the reads). */
static void test_every_truncation(void **state)
{
    (void)state;
    for (size_t k = 0; k <= strlen(good); ++k) {
        char *copy = malloc(k ? k : 1); /* exactly k bytes: no NUL to lean on */
        assert_non_null(copy);
        memcpy(copy, good, k);
        sam_view_event *e;
        size_t n;
        sam_error err;
        sam_status st = sam_view_script_parse(copy, k, NULL, &e, &n, &err);
        assert_true(st == SAM_OK || st == SAM_ERR_FORMAT);
        if (st == SAM_OK)
            assert_true(n <= 10);
        free(e);
        free(copy);
    }
}

static void test_empty_and_missing(void **state)
{
    (void)state;
    sam_view_event *e;
    size_t n;
    sam_error err;
    assert_int_equal(sam_view_script_parse(NULL, 0, NULL, &e, &n, &err), SAM_OK);
    assert_null(e);
    assert_int_equal(n, 0);
    assert_int_equal(sam_view_script_load("/nonexistent/script.txt", &e, &n, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/script.txt"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parses_every_action),
        cmocka_unit_test(test_errors_name_line_and_value),
        cmocka_unit_test(test_every_truncation),
        cmocka_unit_test(test_empty_and_missing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
