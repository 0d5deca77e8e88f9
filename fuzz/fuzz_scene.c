/*
 * libFuzzer target for the scene parser. Besides "no crash, no leak", it
 * checks the contract: a failure leaves the scene as sam_scene_init made it,
 * with a message, and a parsed scene is destroyed cleanly. Paths resolve
 * against "/nonexistent", so a scene naming a file fails with an I/O error
 * (the seeds' meshes included) instead of reading the disk.
 * Seeds: fuzz/corpus/scene/ (copies of example scenes).
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sam_scene scene;
    sam_error err;
    sam_error_clear(&err);
    sam_status st = sam_scene_parse((const char *)data, size, "/nonexistent", "fuzz.json", &scene, &err);
    if (st != SAM_OK && (!err.message[0] || scene.mesh_path || scene.sam_path || scene.lights || scene.keyframes ||
                         scene.light_count || scene.keyframe_count))
        abort();
    sam_scene_destroy(&scene);
    return 0;
}
