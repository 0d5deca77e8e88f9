/*
 * libFuzzer target for material profiles in JSON (gaussians, dipole,
 * burley, table). Besides "no crash, no leak", it checks the contract: a
 * failure comes with a message, and a parsed profile reflects light
 * (finite, non-negative totals, not all zero).
 * Seeds: fuzz/corpus/profile/ (the example materials and test profiles).
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "sam/sam_profile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sam_profile profile;
    sam_error err;
    sam_error_clear(&err);
    if (sam_profile_parse_json((const char *)data, size, "fuzz.json", &profile, &err) != SAM_OK) {
        if (!err.message[0])
            abort();
        return 0;
    }
    float total[3];
    sam_profile_total_reflectance(&profile, total);
    for (int c = 0; c < 3; c++)
        if (!isfinite(total[c]) || total[c] < 0)
            abort();
    if (!(total[0] + total[1] + total[2] > 0))
        abort();
    return 0;
}
