/* The GL tests' shared fixture: one headless context per test group. */
#include "sam_test.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "sam/sam_gl.h"

static sam_gl_context *test_gl;

int sam_test_gl_setup(void **state)
{
    (void)state;
    sam_error err;
    if (sam_gl_context_create_headless(&test_gl, &err) != SAM_OK) {
        fprintf(stderr, "%s\n", err.message);
        return -1;
    }
    return 0;
}

int sam_test_gl_teardown(void **state)
{
    (void)state;
    sam_gl_context_destroy(test_gl);
    test_gl = NULL;
    return 0;
}

sam_gl_context *sam_test_gl_context(void)
{
    return test_gl;
}
