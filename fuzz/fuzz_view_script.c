/*
 * libFuzzer target for sam_view's script parser: no crash, no leak, no read
 * past `size` (the input has no NUL), and on failure no events and a message
 * naming a line. Seeds: fuzz/corpus/view_script/.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_view_script.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sam_view_event *events;
    size_t count;
    sam_error err;
    sam_error_clear(&err);
    sam_status st = sam_view_script_parse((const char *)data, size, "fuzz.txt", &events, &count, &err);
    if (st != SAM_OK && (events || count || strncmp(err.message, "fuzz.txt", 8)))
        abort();
    if (st == SAM_OK && count && !events)
        abort();
    free(events);
    return 0;
}
