#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_sha256.h"
#include "sam_test.h"

static void hex_of(const void *data, size_t size, char hex[65])
{
    sam_sha256 ctx;
    uint8_t d[32];
    sam_sha256_init(&ctx);
    sam_sha256_update(&ctx, data, size);
    sam_sha256_final(&ctx, d);
    for (int i = 0; i < 32; ++i)
        snprintf(hex + 2 * i, 3, "%02x", d[i]);
}

/* FIPS 180-4 / NIST example vectors, including the two-block padding case. */
static void test_known_vectors(void **state)
{
    (void)state;
    char hex[65];
    hex_of("", 0, hex);
    assert_string_equal(hex, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    hex_of("abc", 3, hex);
    assert_string_equal(hex, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    const char *two = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    hex_of(two, strlen(two), hex);
    assert_string_equal(hex, "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

static void test_incremental_matches_one_shot_and_file(void **state)
{
    (void)state;
    static uint8_t data[1000003];
    for (size_t i = 0; i < sizeof data; ++i)
        data[i] = (uint8_t)(i * 7919u >> 3);
    char whole[65], pieces[65], file[65];
    hex_of(data, sizeof data, whole);
    sam_sha256 ctx;
    uint8_t d[32];
    sam_sha256_init(&ctx);
    for (size_t off = 0, step = 1; off < sizeof data; off += step, step = step * 3 % 997 + 1)
        sam_sha256_update(&ctx, data + off, off + step > sizeof data ? sizeof data - off : step);
    sam_sha256_final(&ctx, d);
    for (int i = 0; i < 32; ++i)
        snprintf(pieces + 2 * i, 3, "%02x", d[i]);
    assert_string_equal(whole, pieces);
    char path[512];
    sam_test_write_file(sam_test_tmp_path(path, sizeof path, "sha.bin"), data, sizeof data);
    assert_int_equal(sam_sha256_file(path, file, NULL), SAM_OK);
    assert_string_equal(whole, file);
    /* A million 'a's: the NIST long-message vector. */
    memset(data, 'a', 1000000);
    hex_of(data, 1000000, whole);
    assert_string_equal(whole, "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    sam_error err;
    assert_int_equal(sam_sha256_file("/nonexistent/x.obj", file, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/x.obj"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_known_vectors),
        cmocka_unit_test(test_incremental_matches_one_shot_and_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
