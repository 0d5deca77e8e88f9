#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#include "sam/sam_common.h"
#include "sam_test.h"

static void test_fail_formats_and_truncates(void **state)
{
    (void)state;
    sam_error err;
    char long_text[4000];
    memset(long_text, 'x', sizeof long_text - 1);
    long_text[sizeof long_text - 1] = 0;
    assert_int_equal(sam_fail(&err, SAM_ERR_FORMAT, "chunk %s: %s", "POS ", long_text),
                     SAM_ERR_FORMAT);
    assert_int_equal(err.status, SAM_ERR_FORMAT);
    assert_int_equal(strlen(err.message), SAM_ERROR_MESSAGE_SIZE - 1);
    assert_memory_equal(err.message, "chunk POS : x", 13);
    assert_int_equal(sam_fail(NULL, SAM_ERR_IO, "no error object"), SAM_ERR_IO);
    sam_error_clear(&err);
    assert_int_equal(err.status, SAM_OK);
    assert_string_equal(err.message, "");
}

/* A text grows past its first allocation, keeps bytes after a NUL, stays
 * NUL-terminated, and takes appends of 0 bytes. */
static void test_text_grows_and_stays_terminated(void **state)
{
    (void)state;
    sam_text t = {0};
    sam_text_append(&t, "", 0);
    assert_non_null(t.p);
    assert_int_equal(t.len, 0);
    assert_string_equal(t.p, "");
    char piece[1000];
    memset(piece, 'x', sizeof piece);
    for (int i = 0; i < 10; ++i)
        sam_text_append(&t, piece, sizeof piece);
    sam_text_append(&t, "a\0b", 3);
    assert_false(t.oom);
    assert_int_equal(t.len, 10003);
    assert_true(t.cap > t.len);
    assert_int_equal(t.p[9999], 'x');
    assert_memory_equal(t.p + 10000, "a\0b", 4);
    free(t.p);
}

static void test_atomic_commit_replaces_target(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "atomic_commit.txt");
    sam_test_write_text(path, "old");
    sam_atomic_file f;
    sam_error err;
    assert_int_equal(sam_atomic_open(&f, path, &err), SAM_OK);
    fputs("new contents", f.fp);
    /* Until commit the old file is untouched. */
    uint8_t *data;
    size_t size;
    assert_int_equal(sam_read_file(path, &data, &size, &err), SAM_OK);
    assert_string_equal((char *)data, "old");
    free(data);
    assert_int_equal(sam_atomic_commit(&f, &err), SAM_OK);
    assert_int_equal(sam_read_file(path, &data, &size, &err), SAM_OK);
    assert_int_equal(size, 12);
    assert_string_equal((char *)data, "new contents");
    free(data);
}

static void test_atomic_abort_keeps_target_and_removes_temp(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "atomic_abort.txt");
    sam_test_write_text(path, "keep me");
    sam_atomic_file f;
    assert_int_equal(sam_atomic_open(&f, path, NULL), SAM_OK);
    char temp[1024];
    snprintf(temp, sizeof temp, "%s", f.temp_path);
    fputs("half written", f.fp);
    sam_atomic_abort(&f);
    assert_false(sam_test_file_exists(temp));
    uint8_t *data;
    size_t size;
    assert_int_equal(sam_read_file(path, &data, &size, NULL), SAM_OK);
    assert_string_equal((char *)data, "keep me");
    free(data);
    sam_atomic_abort(&f); /* twice is harmless */
}

static void test_atomic_open_in_missing_dir_fails_clearly(void **state)
{
    (void)state;
    sam_atomic_file f;
    sam_error err;
    assert_int_equal(sam_atomic_open(&f, "/nonexistent-dir/out.sam", &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent-dir/out.sam"));
    assert_null(f.fp);
}

static void test_read_missing_file_names_it(void **state)
{
    (void)state;
    uint8_t *data;
    size_t size;
    sam_error err;
    assert_int_equal(sam_read_file("/nonexistent/file.obj", &data, &size, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/file.obj"));
    assert_null(data);
}

/* A killed writer's temporary is removed by the next write of the same
 * output; a live process's, another output's and an odd name stay. */
static void test_atomic_open_removes_dead_writers_temporaries(void **state)
{
    (void)state;
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0)
        _exit(0);
    assert_int_equal(waitpid(child, NULL, 0), child);
    char out[512], dead[600], live[600], other[600], odd[600];
    sam_test_tmp_path(out, sizeof out, "stale.sam");
    snprintf(dead, sizeof dead, "%s.tmp.%ld.3", out, (long)child);
    snprintf(live, sizeof live, "%s.tmp.%ld.0", out, (long)getppid());
    snprintf(other, sizeof other, "%s.other.tmp.%ld.0", out, (long)child);
    snprintf(odd, sizeof odd, "%s.tmp.%ld.x", out, (long)child);
    const char *names[4] = {dead, live, other, odd};
    for (int i = 0; i < 4; ++i)
        sam_test_write_text(names[i], "half a map");
    sam_atomic_file f;
    sam_error err;
    assert_int_equal(sam_atomic_open(&f, out, &err), SAM_OK);
    assert_int_equal(sam_atomic_commit(&f, &err), SAM_OK);
    assert_false(sam_test_file_exists(dead));
    for (int i = 1; i < 4; ++i) {
        assert_true(sam_test_file_exists(names[i]));
        remove(names[i]);
    }
    remove(out);
}

/* Only regular files are read. */
static void test_read_refuses_what_is_not_a_file(void **state)
{
    (void)state;
    uint8_t *data;
    size_t size;
    sam_error err;
    assert_int_equal(sam_read_file("/dev/zero", &data, &size, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/dev/zero: not a regular file (a character device)"));
    assert_int_equal(sam_read_file("/", &data, &size, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "not a regular file (a directory)"));
    assert_int_equal(sam_check_regular_file("/dev/null", &err), SAM_ERR_IO);
    assert_int_equal(sam_check_regular_file("/nonexistent/x", &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "cannot open"));
}

static void test_paths(void **state)
{
    (void)state;
    assert_string_equal(sam_path_basename("/a/b/c.obj"), "c.obj");
    assert_string_equal(sam_path_basename("c.obj"), "c.obj");
    assert_true(sam_path_has_extension("X.OBJ", ".obj"));
    assert_false(sam_path_has_extension("obj", ".obj"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fail_formats_and_truncates),
        cmocka_unit_test(test_text_grows_and_stays_terminated),
        cmocka_unit_test(test_atomic_commit_replaces_target),
        cmocka_unit_test(test_atomic_abort_keeps_target_and_removes_temp),
        cmocka_unit_test(test_atomic_open_in_missing_dir_fails_clearly),
        cmocka_unit_test(test_read_missing_file_names_it),
        cmocka_unit_test(test_atomic_open_removes_dead_writers_temporaries),
        cmocka_unit_test(test_read_refuses_what_is_not_a_file),
        cmocka_unit_test(test_paths),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
