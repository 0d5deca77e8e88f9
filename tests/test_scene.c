#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "sam/sam_common.h"
#include "sam/sam_scene.h"
#include "sam_test.h"

/* Every test works in <tmp>/scene, where setup puts the files scenes refer
 * to: only their existence matters to the loader, except the profile. */
static char dir[512];

static void dir_file(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", dir, name);
}

static void put_file(const char *name, const char *text)
{
    char path[640];
    dir_file(path, sizeof path, name);
    sam_test_write_text(path, text);
}

static int setup(void **state)
{
    (void)state;
    sam_test_tmp_path(dir, sizeof dir, "scene");
    mkdir(dir, 0755);
    char sub[640];
    dir_file(sub, sizeof sub, "profiles");
    mkdir(sub, 0755);
    dir_file(sub, sizeof sub, "sub");
    mkdir(sub, 0755);
    put_file("head.obj", "v 0 0 0\n");
    put_file("head.sam", "SAMF");
    put_file("sky.exr", "not read by the scene loader");
    put_file("skin.png", "not read by the scene loader");
    put_file("profiles/custom.json",
             "{\"type\": \"dipole\", \"sigma_s_prime\": [1.0, 1.2, 1.4], "
             "\"sigma_a\": [0.01, 0.02, 0.03], \"eta\": 1.4}");
    put_file("profiles/bad_profile.json",
             "{\"type\": \"dipole\", \"sigma_s_prime\": [1, 1, 1], \"sigma_a\": [0.1, -5, 0.1], "
             "\"eta\": 1.3}");
    return 0;
}

static sam_status parse(const char *text, sam_scene *scene, sam_error *err)
{
    return sam_scene_parse(text, strlen(text), dir, "scene.json", scene, err);
}

/* A scene using every key and every light type. No trailing newline, so
 * every proper prefix is incomplete JSON. */
static const char full_scene[] =
    "{\n"
    "  \"mesh\": \"head.obj\",\n"
    "  \"material\": \"profiles/custom.json\",\n"
    "  \"scale\": {\"size_mm\": 180},\n"
    "  \"albedo\": [0.9, 0.7, 0.6],\n"
    "  \"albedo_map\": \"skin.png\",\n"
    "  \"lights\": [\n"
    "    {\"type\": \"point\", \"position\": [1, 2, 3], \"color\": [1, 0.5, 0.25],\n"
    "     \"intensity\": 10, \"shadow\": false},\n"
    "    {\"type\": \"spot\", \"position\": [0, 5, 0], \"direction\": [0, -2, 0],\n"
    "     \"inner_angle_deg\": 15, \"outer_angle_deg\": 25, \"color\": [1, 1, 1], \"intensity\": 3},\n"
    "    {\"type\": \"directional\", \"direction\": [3, 0, -4], \"color\": [0.1, 0.2, 0.3],\n"
    "     \"intensity\": 2, \"shadow\": true},\n"
    "    {\"type\": \"area\", \"vertices\": [[0, 4, 0], [1, 4, 0], [1, 4, 1], [0, 4, 1]],\n"
    "     \"color\": [2, 2, 2], \"intensity\": 0.5, \"two_sided\": true, \"shadow\": false}\n"
    "  ],\n"
    "  \"environment\": {\"map\": \"sky.exr\", \"intensity\": 0.25, \"rotation_deg\": 90},\n"
    "  \"camera\": {\"position\": [0, 1, 5], \"target\": [0, 1, 0], \"up\": [0, 2, 0],\n"
    "             \"fov_deg\": 35, \"near\": 0.1, \"far\": 100},\n"
    "  \"resolution\": [640, 480],\n"
    "  \"technique\": \"tsm\",\n"
    "  \"diffusion\": \"texture\",\n"
    "  \"screen_space\": {\"kernel\": \"marginal\", \"samples\": 25},\n"
    "  \"texture_space\": {\"atlas_size\": 2048, \"culled\": false, \"depth_sized\": true,\n"
    "                    \"clipped\": false, \"texels_per_pixel\": 0.5},\n"
    "  \"tonemap\": \"reinhard\",\n"
    "  \"exposure\": -1.5,\n"
    "  \"deformers\": [\n"
    "    {\"type\": \"bend\", \"axis\": [0, 2, 0], \"direction\": [1, 0, 0], \"center\": [0, 1, 0],\n"
    "     \"angle_deg\": 45, \"length\": 2, \"period_s\": 4},\n"
    "    {\"type\": \"twist\", \"axis\": [0, 0, 1], \"angle_deg\": -30, \"length\": 0.5},\n"
    "    {\"type\": \"squash\", \"axis\": [1, 0, 0], \"center\": [2, 0, 0], \"amount\": -0.25,\n"
    "     \"period_s\": 1.5},\n"
    "    {\"type\": \"wave\", \"axis\": [1, 0, 0], \"direction\": [0, 3, 4], \"amplitude\": 0.1,\n"
    "     \"wavelength\": 2, \"speed\": 0.5}\n"
    "  ],\n"
    "  \"keyframes\": [{\"mesh\": \"head.obj\", \"time_s\": 0.5}, {\"time_s\": 1.25, \"mesh\": \"sub/../head.obj\"}]\n"
    "}";

static void assert_vec3(const float v[3], float x, float y, float z)
{
    assert_float_equal(v[0], x, 1e-6f);
    assert_float_equal(v[1], y, 1e-6f);
    assert_float_equal(v[2], z, 1e-6f);
}

/* Field by field, so a failure names the field. */
static void assert_options(const sam_diffusion_options *o, sam_diffusion_options want)
{
    assert_int_equal(o->sss_kernel, want.sss_kernel);
    assert_int_equal(o->sss_samples, want.sss_samples);
    assert_int_equal(o->atlas_size, want.atlas_size);
    assert_int_equal(o->culled, want.culled);
    assert_int_equal(o->depth_sized, want.depth_sized);
    assert_int_equal(o->clipped, want.clipped);
    assert_float_equal(o->texels_per_pixel, want.texels_per_pixel, 0.0f);
}

static void test_full_scene_loads(void **state)
{
    (void)state;
    char path[640], want[640];
    dir_file(path, sizeof path, "full.json");
    sam_test_write_text(path, full_scene);
    sam_scene s;
    sam_error err;
    if (sam_scene_load(path, &s, &err) != SAM_OK)
        fail_msg("%s", err.message);

    dir_file(want, sizeof want, "head.obj");
    assert_string_equal(s.mesh_path, want);
    assert_null(s.sam_path);
    dir_file(want, sizeof want, "profiles/custom.json");
    assert_string_equal(s.material, want);
    assert_int_equal(s.profile.kind, SAM_PROFILE_DIPOLE);
    assert_float_equal(s.profile.sigma_s_prime[2], 1.4f, 1e-6f);
    assert_float_equal(s.profile.eta, 1.4f, 1e-6f);
    assert_int_equal(s.scale_kind, SAM_SCALE_SIZE_MM);
    assert_float_equal(s.scale_value, 180.0f, 0.0f);
    assert_vec3(s.albedo, 0.9f, 0.7f, 0.6f);
    dir_file(want, sizeof want, "skin.png");
    assert_string_equal(s.albedo_map, want);

    assert_int_equal(s.light_count, 4);
    const sam_light *l = s.lights;
    assert_int_equal(l[0].type, SAM_LIGHT_POINT);
    assert_vec3(l[0].position, 1, 2, 3);
    assert_vec3(l[0].color, 1, 0.5f, 0.25f);
    assert_float_equal(l[0].intensity, 10.0f, 0.0f);
    assert_int_equal(l[0].shadow, 0);

    assert_int_equal(l[1].type, SAM_LIGHT_SPOT);
    assert_vec3(l[1].position, 0, 5, 0);
    assert_vec3(l[1].direction, 0, -1, 0); /* normalised */
    assert_float_equal(l[1].inner_angle_deg, 15.0f, 0.0f);
    assert_float_equal(l[1].outer_angle_deg, 25.0f, 0.0f);
    assert_float_equal(l[1].intensity, 3.0f, 0.0f);
    assert_int_equal(l[1].shadow, 1); /* default */

    assert_int_equal(l[2].type, SAM_LIGHT_DIRECTIONAL);
    assert_vec3(l[2].direction, 0.6f, 0, -0.8f);
    assert_vec3(l[2].color, 0.1f, 0.2f, 0.3f);
    assert_int_equal(l[2].shadow, 1);

    assert_int_equal(l[3].type, SAM_LIGHT_AREA);
    assert_int_equal(l[3].vertex_count, 4);
    assert_vec3(l[3].vertices[2], 1, 4, 1);
    /* (x, z) = (0,0) -> (1,0) -> (1,1) -> (0,1) winds counter-clockwise
     * seen from below: the light faces -y, down onto the object. */
    assert_vec3(l[3].normal, 0, -1, 0);
    assert_float_equal(l[3].area, 1.0f, 1e-6f);
    assert_int_equal(l[3].two_sided, 1);
    assert_int_equal(l[3].shadow, 0);

    dir_file(want, sizeof want, "sky.exr");
    assert_string_equal(s.environment.map, want);
    assert_float_equal(s.environment.intensity, 0.25f, 0.0f);
    assert_float_equal(s.environment.rotation_deg, 90.0f, 0.0f);

    assert_int_equal(s.has_camera, 1);
    assert_vec3(s.camera.position, 0, 1, 5);
    assert_vec3(s.camera.target, 0, 1, 0);
    assert_vec3(s.camera.up, 0, 1, 0);
    assert_float_equal(s.camera.fov_deg, 35.0f, 0.0f);
    assert_float_equal(s.camera.near_plane, 0.1f, 0.0f);
    assert_float_equal(s.camera.far_plane, 100.0f, 0.0f);
    assert_int_equal(s.width, 640);
    assert_int_equal(s.height, 480);
    assert_int_equal(s.technique, SAM_TECHNIQUE_TSM);
    assert_int_equal(s.diffusion, SAM_DIFFUSION_TEXTURE);
    assert_options(&s.diffusion_options,
                   (sam_diffusion_options){.sss_kernel = SAM_SSS_KERNEL_MARGINAL, .sss_samples = 25, .atlas_size = 2048,
                                           .depth_sized = 1, .texels_per_pixel = 0.5f});
    assert_int_equal(s.tonemap, SAM_TONEMAP_REINHARD);
    assert_float_equal(s.exposure, -1.5f, 0.0f);
    assert_int_equal(s.deformer_count, 4);
    const sam_deformer *d = s.deformers;
    assert_int_equal(d[0].type, SAM_DEFORM_BEND);
    assert_vec3(d[0].axis, 0, 1, 0);
    assert_vec3(d[0].direction, 1, 0, 0);
    assert_vec3(d[0].center, 0, 1, 0);
    assert_float_equal(d[0].angle_deg, 45.0f, 0.0f);
    assert_float_equal(d[0].length, 2.0f, 0.0f);
    assert_float_equal(d[0].period_s, 4.0f, 0.0f);
    assert_int_equal(d[1].type, SAM_DEFORM_TWIST);
    assert_vec3(d[1].center, 0, 0, 0); /* default */
    assert_float_equal(d[1].angle_deg, -30.0f, 0.0f);
    assert_float_equal(d[1].length, 0.5f, 0.0f);
    assert_float_equal(d[1].period_s, 0.0f, 0.0f); /* default: static */
    assert_int_equal(d[2].type, SAM_DEFORM_SQUASH);
    assert_vec3(d[2].center, 2, 0, 0);
    assert_float_equal(d[2].amount, -0.25f, 0.0f);
    assert_float_equal(d[2].period_s, 1.5f, 0.0f);
    assert_int_equal(d[3].type, SAM_DEFORM_WAVE);
    assert_vec3(d[3].direction, 0, 0.6f, 0.8f);
    assert_float_equal(d[3].amplitude, 0.1f, 0.0f);
    assert_float_equal(d[3].wavelength, 2.0f, 0.0f);
    assert_float_equal(d[3].speed, 0.5f, 0.0f);
    assert_int_equal(s.keyframe_count, 2);
    char head[640];
    dir_file(head, sizeof head, "head.obj");
    assert_string_equal(s.keyframes[0].mesh, head);
    assert_float_equal(s.keyframes[0].time_s, 0.5f, 0.0f);
    assert_non_null(strstr(s.keyframes[1].mesh, "head.obj"));
    assert_float_equal(s.keyframes[1].time_s, 1.25f, 0.0f);
    sam_scene_destroy(&s);
    assert_null(s.keyframes);
    assert_null(s.lights);
    assert_null(s.albedo_map);
    sam_scene_destroy(&s); /* twice is harmless */
}

/* The documented defaults of sam_diffusion_options. */
static void assert_default_options(const sam_diffusion_options *o)
{
    assert_options(o, (sam_diffusion_options){.sss_kernel = SAM_SSS_KERNEL_FIT2D, .sss_samples = 17, .atlas_size = 1024,
                                              .clipped = 1, .texels_per_pixel = 1.0f});
}

static void test_defaults(void **state)
{
    (void)state;
    sam_scene s;
    sam_error err;
    assert_int_equal(parse("{\"sam\": \"head.sam\"}", &s, &err), SAM_OK);
    char want[640];
    dir_file(want, sizeof want, "head.sam");
    assert_string_equal(s.sam_path, want);
    assert_null(s.mesh_path);
    assert_null(s.material);
    assert_int_equal(s.scale_kind, SAM_SCALE_FROM_SAM);
    assert_vec3(s.albedo, 0.8f, 0.8f, 0.8f);
    assert_null(s.albedo_map);
    assert_int_equal(s.light_count, 0);
    assert_int_equal(s.deformer_count, 0);
    assert_null(s.lights);
    assert_null(s.environment.map);
    assert_int_equal(s.has_camera, 0);
    assert_int_equal(s.width, 1280);
    assert_int_equal(s.height, 720);
    assert_int_equal(s.technique, SAM_TECHNIQUE_SAM);
    assert_int_equal(s.diffusion, SAM_DIFFUSION_SCREEN);
    assert_default_options(&s.diffusion_options);
    assert_int_equal(s.tonemap, SAM_TONEMAP_ACES);
    assert_float_equal(s.exposure, 0.0f, 0.0f);
    sam_scene_destroy(&s);

    /* Defaults inside lights, environment and camera; a preset material;
     * "./" and repeated slashes in paths. */
    assert_int_equal(
        parse("{\"mesh\": \"./sub/..//head.obj\", \"material\": \"Marble\", "
              "\"scale\": {\"mm_per_unit\": 2.5},"
              " \"lights\": [{\"type\": \"point\", \"position\": [0, 1, 0]},"
              "              {\"type\": \"spot\", \"position\": [0, 1, 0], \"direction\": [0, -1, 0]},"
              "              {\"type\": \"spot\", \"position\": [0, 1, 0], \"direction\": [0, -1, 0],"
              "               \"outer_angle_deg\": 60},"
              "              {\"type\": \"area\", \"vertices\": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}],"
              " \"environment\": {\"map\": \"sky.exr\"},"
              " \"camera\": {\"position\": [0, 0, 3], \"target\": [0, 0, 0]}}",
              &s, &err),
        SAM_OK);
    dir_file(want, sizeof want, "sub/../head.obj");
    assert_string_equal(s.mesh_path, want);
    assert_string_equal(s.material, "Marble");
    assert_int_equal(s.profile.kind, SAM_PROFILE_DIPOLE);
    assert_int_equal(s.scale_kind, SAM_SCALE_MM_PER_UNIT);
    assert_float_equal(s.scale_value, 2.5f, 0.0f);
    assert_vec3(s.lights[0].color, 1, 1, 1);
    assert_float_equal(s.lights[0].intensity, 1.0f, 0.0f);
    assert_int_equal(s.lights[0].shadow, 1);
    assert_float_equal(s.lights[1].outer_angle_deg, 30.0f, 0.0f);
    assert_float_equal(s.lights[1].inner_angle_deg, 20.0f, 1e-5f);
    assert_float_equal(s.lights[2].inner_angle_deg, 40.0f, 1e-5f);
    assert_int_equal(s.lights[3].two_sided, 0);
    assert_vec3(s.lights[3].normal, 0, 0, 1);
    assert_float_equal(s.lights[3].area, 0.5f, 1e-6f);
    assert_float_equal(s.environment.intensity, 1.0f, 0.0f);
    assert_float_equal(s.environment.rotation_deg, 0.0f, 0.0f);
    assert_int_equal(s.has_camera, 1);
    assert_vec3(s.camera.up, 0, 1, 0);
    assert_float_equal(s.camera.fov_deg, 40.0f, 0.0f);
    assert_float_equal(s.camera.near_plane, 0.0f, 0.0f);
    assert_float_equal(s.camera.far_plane, 0.0f, 0.0f);
    sam_scene_destroy(&s);

    /* sam_scene_init gives the same defaults as an empty file would. */
    sam_scene init;
    sam_scene_init(&init);
    assert_int_equal(init.width, 1280);
    assert_vec3(init.albedo, 0.8f, 0.8f, 0.8f);
    assert_float_equal(init.camera.fov_deg, 40.0f, 0.0f);
    assert_float_equal(init.environment.intensity, 1.0f, 0.0f);
    assert_null(init.albedo_map);
    assert_default_options(&init.diffusion_options);
    sam_diffusion_options options;
    memset(&options, 0xff, sizeof options);
    sam_diffusion_options_default(&options);
    assert_default_options(&options);
    sam_diffusion_options_default(NULL);
}

/* Valid values of the diffusion settings, including the ends of each range;
 * keys left out of "screen_space" and "texture_space" keep their defaults. */
static void test_diffusion_options(void **state)
{
    (void)state;
    sam_scene s;
    sam_error err;
    if (parse("{\"sam\": \"head.sam\", \"screen_space\": {\"kernel\": \"eq1\", \"samples\": 9},"
              " \"texture_space\": {\"atlas_size\": 64, \"culled\": false, \"depth_sized\": true,"
              " \"clipped\": false, \"texels_per_pixel\": 16}}",
              &s, &err) != SAM_OK)
        fail_msg("%s", err.message);
    const sam_diffusion_options *o = &s.diffusion_options;
    assert_options(o, (sam_diffusion_options){.sss_kernel = SAM_SSS_KERNEL_EQ1, .sss_samples = 9, .atlas_size = 64,
                                              .depth_sized = 1, .texels_per_pixel = 16.0f});
    sam_scene_destroy(&s);

    if (parse("{\"sam\": \"head.sam\", \"screen_space\": {\"samples\": 33},"
              " \"texture_space\": {\"atlas_size\": 4096, \"texels_per_pixel\": 0.001}}",
              &s, &err) != SAM_OK)
        fail_msg("%s", err.message);
    /* The keys left out keep their defaults. */
    assert_options(o, (sam_diffusion_options){.sss_kernel = SAM_SSS_KERNEL_FIT2D, .sss_samples = 33, .atlas_size = 4096,
                                              .clipped = 1, .texels_per_pixel = 0.001f});
    sam_scene_destroy(&s);

    /* Empty objects are all defaults; an atlas side need not be a power of 2. */
    if (parse("{\"sam\": \"head.sam\", \"screen_space\": {}, \"texture_space\": {}}", &s,
              &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_default_options(o);
    sam_scene_destroy(&s);
    if (parse("{\"sam\": \"head.sam\", \"texture_space\": {\"atlas_size\": 1000}}", &s, &err) !=
        SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(o->atlas_size, 1000);
    sam_scene_destroy(&s);

    /* Every odd sample count in range loads; every even one is refused. */
    for (int n = 9; n <= 33; ++n) {
        char json[128];
        snprintf(json, sizeof json, "{\"sam\": \"head.sam\", \"screen_space\": {\"samples\": %d}}",
                 n);
        sam_status st = parse(json, &s, &err);
        if (n % 2) {
            if (st != SAM_OK)
                fail_msg("%d samples: %s", n, err.message);
            assert_int_equal(o->sss_samples, (uint32_t)n);
            sam_scene_destroy(&s);
        } else {
            assert_int_equal(st, SAM_ERR_FORMAT);
            char want[128];
            snprintf(want, sizeof want,
                     "scene.json: screen_space.samples: expected an odd integer in [9, 33], "
                     "found %d", n);
            assert_string_equal(err.message, want);
        }
    }
}

static void assert_same_floats(const float *a, const float *b, size_t n, const char *what)
{
    if (memcmp(a, b, n * sizeof *a) != 0)
        fail_msg("%s differs after the round trip", what);
}

static void assert_same_string(const char *a, const char *b)
{
    if (!a || !b)
        assert_true(a == b);
    else
        assert_string_equal(a, b);
}

static void assert_scenes_equal(const sam_scene *a, const sam_scene *b)
{
    assert_same_string(a->mesh_path, b->mesh_path);
    assert_same_string(a->sam_path, b->sam_path);
    assert_same_string(a->material, b->material);
    if (a->material)
        assert_memory_equal(&a->profile, &b->profile, sizeof a->profile);
    assert_int_equal(a->scale_kind, b->scale_kind);
    assert_same_floats(&a->scale_value, &b->scale_value, 1, "scale");
    assert_same_floats(a->albedo, b->albedo, 3, "albedo");
    assert_same_string(a->albedo_map, b->albedo_map);
    assert_int_equal(a->light_count, b->light_count);
    for (size_t i = 0; i < a->light_count; ++i) {
        const sam_light *x = &a->lights[i], *y = &b->lights[i];
        assert_int_equal(x->type, y->type);
        assert_same_floats(x->color, y->color, 3, "light color");
        assert_same_floats(&x->intensity, &y->intensity, 1, "light intensity");
        assert_int_equal(x->shadow, y->shadow);
        if (x->type == SAM_LIGHT_POINT || x->type == SAM_LIGHT_SPOT)
            assert_same_floats(x->position, y->position, 3, "light position");
        if (x->type == SAM_LIGHT_SPOT || x->type == SAM_LIGHT_DIRECTIONAL)
            assert_same_floats(x->direction, y->direction, 3, "light direction");
        if (x->type == SAM_LIGHT_SPOT) {
            assert_same_floats(&x->inner_angle_deg, &y->inner_angle_deg, 1, "inner angle");
            assert_same_floats(&x->outer_angle_deg, &y->outer_angle_deg, 1, "outer angle");
        }
        if (x->type == SAM_LIGHT_AREA) {
            assert_int_equal(x->vertex_count, y->vertex_count);
            assert_same_floats(&x->vertices[0][0], &y->vertices[0][0], 3 * x->vertex_count,
                               "area vertices");
            assert_same_floats(x->normal, y->normal, 3, "area normal");
            assert_same_floats(&x->area, &y->area, 1, "area");
            assert_int_equal(x->two_sided, y->two_sided);
        }
    }
    assert_same_string(a->environment.map, b->environment.map);
    assert_same_floats(&a->environment.intensity, &b->environment.intensity, 1, "env intensity");
    assert_same_floats(&a->environment.rotation_deg, &b->environment.rotation_deg, 1,
                       "env rotation");
    assert_int_equal(a->has_camera, b->has_camera);
    if (a->has_camera) {
        assert_same_floats(a->camera.position, b->camera.position, 3, "camera position");
        assert_same_floats(a->camera.target, b->camera.target, 3, "camera target");
        assert_same_floats(a->camera.up, b->camera.up, 3, "camera up");
        assert_same_floats(&a->camera.fov_deg, &b->camera.fov_deg, 1, "fov");
        assert_same_floats(&a->camera.near_plane, &b->camera.near_plane, 1, "near");
        assert_same_floats(&a->camera.far_plane, &b->camera.far_plane, 1, "far");
    }
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    assert_int_equal(a->technique, b->technique);
    assert_int_equal(a->samples_per_vertex, b->samples_per_vertex);
    assert_int_equal(a->diffusion, b->diffusion);
    const sam_diffusion_options *x = &a->diffusion_options, *y = &b->diffusion_options;
    assert_int_equal(x->sss_kernel, y->sss_kernel);
    assert_int_equal(x->sss_samples, y->sss_samples);
    assert_int_equal(x->atlas_size, y->atlas_size);
    assert_int_equal(x->culled, y->culled);
    assert_int_equal(x->depth_sized, y->depth_sized);
    assert_int_equal(x->clipped, y->clipped);
    assert_same_floats(&x->texels_per_pixel, &y->texels_per_pixel, 1, "texels per pixel");
    assert_int_equal(a->tonemap, b->tonemap);
    assert_same_floats(&a->exposure, &b->exposure, 1, "exposure");
    assert_int_equal(a->deformer_count, b->deformer_count);
    for (size_t i = 0; i < a->deformer_count; ++i) {
        const sam_deformer *x = &a->deformers[i], *y = &b->deformers[i];
        assert_int_equal(x->type, y->type);
        assert_same_floats(x->axis, y->axis, 3, "deformer axis");
        /* Keys a type does not have are not written; their fields are 0 on load. */
        assert_same_floats(x->direction, y->direction, 3, "deformer direction");
        assert_same_floats(x->center, y->center, 3, "deformer center");
        assert_same_floats(&x->angle_deg, &y->angle_deg, 1, "deformer angle");
        assert_same_floats(&x->length, &y->length, 1, "deformer length");
        assert_same_floats(&x->amount, &y->amount, 1, "deformer amount");
        assert_same_floats(&x->amplitude, &y->amplitude, 1, "deformer amplitude");
        assert_same_floats(&x->wavelength, &y->wavelength, 1, "deformer wavelength");
        assert_same_floats(&x->speed, &y->speed, 1, "deformer speed");
        assert_same_floats(&x->period_s, &y->period_s, 1, "deformer period");
    }
    assert_int_equal(a->keyframe_count, b->keyframe_count);
    for (size_t i = 0; i < a->keyframe_count; ++i) {
        assert_same_string(a->keyframes[i].mesh, b->keyframes[i].mesh);
        assert_same_floats(&a->keyframes[i].time_s, &b->keyframes[i].time_s, 1, "keyframe time");
    }
}

/* Writes `a` to `path` and checks that loading it gives `a` back. */
static void assert_round_trip(const sam_scene *a, const char *path)
{
    sam_scene b;
    sam_error err;
    if (sam_scene_write(path, a, &err) != SAM_OK)
        fail_msg("%s", err.message);
    if (sam_scene_load(path, &b, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_scenes_equal(a, &b);
    sam_scene_destroy(&b);
}

static void test_round_trip(void **state)
{
    (void)state;
    char in[640], out[640];
    dir_file(in, sizeof in, "full.json");
    sam_test_write_text(in, full_scene);
    sam_scene a;
    sam_error err;
    assert_int_equal(sam_scene_load(in, &a, &err), SAM_OK);
    /* Written into another directory: absolute paths keep it loadable. */
    dir_file(out, sizeof out, "sub/written.json");
    assert_round_trip(&a, out);

    /* Numbers are written short: 0.9f as 0.9, not 0.899999976. */
    uint8_t *text;
    size_t size;
    assert_int_equal(sam_read_file(out, &text, &size, &err), SAM_OK);
    assert_non_null(strstr((char *)text, "0.9"));
    assert_null(strstr((char *)text, "0.8999"));
    free(text);

    /* Awkward floats survive bit for bit. */
    a.albedo[0] = 0.1f;
    a.albedo[1] = nextafterf(0.3f, 1.0f);
    a.albedo[2] = 1e-30f;
    a.exposure = -0.0f;
    a.lights[0].position[0] = 3.4e38f;
    a.lights[0].position[1] = -1.17549435e-38f;
    a.camera.fov_deg = 179.99998f;
    a.diffusion_options.texels_per_pixel = nextafterf(0.3f, 1.0f);
    a.deformers[0].angle_deg = nextafterf(45.0f, 90.0f);
    a.deformers[3].speed = -1e-20f;
    a.keyframes[1].time_s = nextafterf(0.5f, 1.0f);
    assert_round_trip(&a, out);
    sam_scene_destroy(&a);
}

static void test_write_hand_built_scene(void **state)
{
    (void)state;
    char out[640], sam_file[640];
    sam_scene a, b;
    sam_error err;
    sam_scene_init(&a);
    dir_file(sam_file, sizeof sam_file, "head.sam");
    a.sam_path = strdup(sam_file);
    a.material = strdup("skin");
    a.light_count = 2;
    a.lights = calloc(2, sizeof *a.lights);
    a.lights[0].type = SAM_LIGHT_DIRECTIONAL;
    a.lights[0].direction[2] = -1.0f;
    a.lights[0].color[0] = a.lights[0].color[1] = a.lights[0].color[2] = 1.0f;
    a.lights[0].intensity = 4.0f;
    a.lights[1].type = SAM_LIGHT_AREA;
    a.lights[1].vertex_count = 3;
    const float tri[3][3] = {{0, 0, 2}, {0, 1, 2}, {1, 0, 2}};
    memcpy(a.lights[1].vertices, tri, sizeof tri);
    a.lights[1].intensity = 1.0f;
    a.lights[1].normal[2] = -1.0f;
    a.lights[1].area = 0.5f;
    a.technique = SAM_TECHNIQUE_TRANSMITTANCE;
    a.diffusion = SAM_DIFFUSION_NONE;
    a.samples_per_vertex = 2;
    dir_file(out, sizeof out, "hand.json");
    if (sam_scene_write(out, &a, &err) != SAM_OK)
        fail_msg("%s", err.message);
    if (sam_scene_load(out, &b, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(b.profile.kind, SAM_PROFILE_GAUSSIAN_SUM);
    a.profile = b.profile; /* the hand-built scene never resolved its material */
    assert_scenes_equal(&a, &b);
    sam_scene_destroy(&b);

    /* Default diffusion settings are written out too, so a change of the
     * defaults cannot change what a recorded scene renders. */
    uint8_t *text;
    size_t size;
    assert_int_equal(sam_read_file(out, &text, &size, &err), SAM_OK);
    /* Without the layout's whitespace, which is cJSON's to choose. */
    char *written = malloc(size + 1);
    assert_non_null(written);
    size_t len = 0;
    for (size_t i = 0; i < size; ++i) {
        if (!strchr(" \t\r\n", text[i]))
            written[len++] = (char)text[i];
    }
    written[len] = 0;
    free(text);
    const char *const keys[] = {"\"screen_space\":{", "\"kernel\":\"fit2d\"", "\"samples\":17",
                                "\"texture_space\":{", "\"atlas_size\":1024", "\"culled\":false",
                                "\"depth_sized\":false", "\"clipped\":true",
                                "\"texels_per_pixel\":1"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i) {
        if (!strstr(written, keys[i]))
            fail_msg("%s not written in:\n%s", keys[i], written);
    }
    assert_null(strstr(written, "albedo_map")); /* none set */
    free(written);

    /* An albedo map and non-default settings survive the trip. */
    char map[640];
    dir_file(map, sizeof map, "skin.png");
    a.albedo_map = strdup(map);
    a.diffusion_options.sss_kernel = SAM_SSS_KERNEL_EQ1;
    a.diffusion_options.sss_samples = 31;
    a.diffusion_options.atlas_size = 512;
    a.diffusion_options.culled = 1;
    a.diffusion_options.depth_sized = 1;
    a.diffusion_options.clipped = 0;
    a.diffusion_options.texels_per_pixel = 2.5f;
    assert_round_trip(&a, out);

    /* An invalid scene is refused with the loader's message, and no file. */
    remove(out);
    a.diffusion_options.sss_samples = 18;
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "hand.json: screen_space.samples: expected an odd integer "
                                        "in [9, 33], found 18"));
    a.diffusion_options.sss_samples = 17;
    a.diffusion_options.sss_kernel = (sam_sss_kernel)7;
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "hand.json: screen_space.kernel: unknown kernel "
                                        "\"unknown\""));
    a.diffusion_options.sss_kernel = SAM_SSS_KERNEL_FIT2D;
    a.diffusion_options.atlas_size = 8192;
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "hand.json: texture_space.atlas_size: expected an integer "
                                        "in [64, 4096], found 8192"));
    a.diffusion_options.atlas_size = 1024;
    a.diffusion_options.texels_per_pixel = 0.0f;
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "hand.json: texture_space.texels_per_pixel: expected a "
                                        "number in (0, 16], found 0"));
    a.diffusion_options.texels_per_pixel = 1.0f;
    free(a.albedo_map);
    dir_file(map, sizeof map, "gone.png");
    a.albedo_map = strdup(map);
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "hand.json: albedo_map: file not found: "));
    assert_non_null(strstr(err.message, map));
    assert_false(sam_test_file_exists(out));
    free(a.albedo_map);
    a.albedo_map = NULL;
    a.has_camera = 1;
    a.camera.position[2] = 3.0f;
    a.camera.fov_deg = 200.0f;
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "hand.json: camera.fov_deg: expected a number in (0, 180), "
                                        "found 200"));
    assert_false(sam_test_file_exists(out));
    a.camera.fov_deg = 40.0f;
    a.technique = (sam_technique)9;
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "technique: unknown technique"));
    a.technique = SAM_TECHNIQUE_SAM;
    a.lights[0].intensity = NAN;
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "lights[0].intensity: expected a number >= 0"));
    assert_false(sam_test_file_exists(out));
    a.lights[0].intensity = 1.0f;
    assert_int_equal(sam_scene_write("/nonexistent-dir/s.json", &a, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent-dir/s.json"));
    free(a.sam_path);
    a.sam_path = NULL;
    assert_int_equal(sam_scene_write(out, &a, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "hand.json: mesh: missing"));
    assert_false(sam_test_file_exists(out));
    assert_int_equal(sam_scene_write(out, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    sam_scene_destroy(&a);
}

typedef struct error_case {
    const char *json;
    sam_status status;
    const char *message; /* expected substring; "@" stands for the scene directory */
} error_case;

static const error_case error_cases[] = {
    {"{\"sam\": \"head.sam\", \"keyframes\": {}}", SAM_ERR_FORMAT,
     "scene.json: keyframes: expected an array of keyframes, found an object"},
    {"{\"sam\": \"head.sam\", \"keyframes\": [3]}", SAM_ERR_FORMAT,
     "scene.json: keyframes[0]: expected an object, found 3"},
    {"{\"sam\": \"head.sam\", \"keyframes\": [{\"mesh\": \"head.obj\", \"time\": 1}]}", SAM_ERR_FORMAT,
     "scene.json: keyframes[0].time: unknown key (expected one of: mesh, time_s)"},
    {"{\"sam\": \"head.sam\", \"keyframes\": [{\"mesh\": \"head.obj\"}]}", SAM_ERR_FORMAT,
     "scene.json: keyframes[0].time_s: missing"},
    {"{\"sam\": \"head.sam\", \"keyframes\": [{\"time_s\": 1}]}", SAM_ERR_FORMAT,
     "scene.json: keyframes[0].mesh: missing"},
    {"{\"sam\": \"head.sam\", \"keyframes\": [{\"mesh\": \"head.obj\", \"time_s\": 0}]}", SAM_ERR_FORMAT,
     "scene.json: keyframes[0].time_s: expected a number > 0 (finite), found 0"},
    {"{\"sam\": \"head.sam\", \"keyframes\": [{\"mesh\": \"head.obj\", \"time_s\": 1}, "
     "{\"mesh\": \"head.obj\", \"time_s\": 1}]}",
     SAM_ERR_FORMAT, "scene.json: keyframes[1].time_s: expected a time after keyframes[0].time_s = 1, found 1"},
    {"{\"sam\": \"head.sam\", \"keyframes\": [{\"mesh\": \"head.obj\", \"time_s\": 1}, "
     "{\"mesh\": \"pose.obj\", \"time_s\": 2}]}",
     SAM_ERR_IO, "scene.json: keyframes[1].mesh: file not found: @/pose.obj"},
    {"{\"sam\": \"head.sam\", \"deformers\": {}}", SAM_ERR_FORMAT,
     "scene.json: deformers: expected an array of deformers, found an object"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"axis\": [1, 0, 0]}]}", SAM_ERR_FORMAT,
     "scene.json: deformers[0].type: missing (expected bend, twist, squash, wave)"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"melt\"}]}", SAM_ERR_FORMAT,
     "scene.json: deformers[0].type: unknown deformer type \"melt\" (expected bend, twist, squash, wave)"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"twist\", \"axis\": [1, 0, 0], "
     "\"angle_deg\": 10, \"length\": 1, \"amount\": 2}]}",
     SAM_ERR_FORMAT, "scene.json: deformers[0].amount: unknown key (expected one of: type, axis, center, "},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"bend\", \"axis\": [1, 0, 0], "
     "\"angle_deg\": 10, \"length\": 1}]}",
     SAM_ERR_FORMAT, "scene.json: deformers[0].direction: missing (required for a bend deformer)"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"bend\", \"axis\": [1, 0, 0], "
     "\"direction\": [-2, 0, 0], \"angle_deg\": 10, \"length\": 1}]}",
     SAM_ERR_FORMAT, "scene.json: deformers[0].direction: [-1, 0, 0] is parallel to the axis [1, 0, 0]"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"twist\", \"axis\": [0, 0, 0], "
     "\"angle_deg\": 10, \"length\": 1}]}",
     SAM_ERR_FORMAT, "scene.json: deformers[0].axis: expected a non-zero direction, found [0, 0, 0]"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"twist\", \"axis\": [0, 0, 1], "
     "\"angle_deg\": 10, \"length\": 0}]}",
     SAM_ERR_FORMAT, "scene.json: deformers[0].length: expected a number > 0 (finite), found 0"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"squash\", \"axis\": [0, 0, 1], "
     "\"amount\": -1}]}",
     SAM_ERR_FORMAT, "scene.json: deformers[0].amount: expected a number in (-1, 1), found -1"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"wave\", \"axis\": [0, 0, 1], "
     "\"direction\": [0, 1, 0], \"amplitude\": 1, \"wavelength\": 1, \"period_s\": -2}]}",
     SAM_ERR_FORMAT, "scene.json: deformers[0].period_s: expected a number >= 0 (finite), found -2"},
    {"{\"sam\": \"head.sam\", \"deformers\": [{\"type\": \"wave\", \"axis\": [0, 0, 1], "
     "\"direction\": [0, 1, 0], \"wavelength\": 1}]}",
     SAM_ERR_FORMAT, "scene.json: deformers[0].amplitude: missing (required for a wave deformer)"},
    {"{\"sam\": \"head.sam\", \"deformers\": [1,2,3,4,5,6,7,8,9]}", SAM_ERR_FORMAT,
     "scene.json: deformers: 9 deformers, more than the limit of 8"},
    /* the messages the contract quotes */
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"point\", \"position\": [0,0,0]},"
     " {\"type\": \"point\", \"position\": [0,0,0], \"colour\": [1,1,1]}]}",
     SAM_ERR_FORMAT,
     "scene.json: lights[1].colour: unknown key (expected one of: type, position, color, "
     "intensity, shadow)"},
    {"{\"sam\": \"head.sam\", \"camera\": {\"position\": [0,0,1], \"target\": [0,0,0], "
     "\"fov_deg\": 200}}",
     SAM_ERR_FORMAT, "scene.json: camera.fov_deg: expected a number in (0, 180), found 200"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"sun\"}]}", SAM_ERR_FORMAT,
     "scene.json: lights[0].type: unknown light type \"sun\" (expected point, spot, "
     "directional, area)"},
    {"{\"sam\": \"head.sam\", \"material\": \"profiles/bad_profile.json\"}", SAM_ERR_FORMAT,
     "scene.json: material: @/profiles/bad_profile.json"},
    {"{\"sam\": \"head.sam\", \"material\": \"velvet\"}", SAM_ERR_IO,
     "scene.json: material: \"velvet\" is neither a preset (skin, apple"},
    {"{\"mesh\": \"missing.obj\", \"material\": \"skin\", \"scale\": {\"size_mm\": 1}}",
     SAM_ERR_IO, "scene.json: mesh: file not found: @/missing.obj"},
    {"{\"sam\": \"nothing/here.sam\"}", SAM_ERR_IO, "scene.json: sam: file not found: @/nothing/here.sam"},
    {"{\"sam\": \"profiles\"}", SAM_ERR_IO, "scene.json: sam: not a regular file: @/profiles"},
    {"{\"sam\": \"head.sam\", \"environment\": {\"map\": \"night.exr\"}}", SAM_ERR_IO,
     "scene.json: environment.map: file not found: @/night.exr"},
    {"{\"sam\": \"head.sam\", \"albedo_map\": \"maps/missing.png\"}", SAM_ERR_IO,
     "scene.json: albedo_map: file not found: @/maps/missing.png"},
    {"{\"sam\": \"head.sam\", \"albedo_map\": \"profiles\"}", SAM_ERR_IO,
     "scene.json: albedo_map: not a regular file: @/profiles"},
    {"{\"sam\": \"head.sam\", \"albedo_map\": 3}", SAM_ERR_FORMAT,
     "scene.json: albedo_map: expected a non-empty string, found 3"},
    {"{\"sam\": \"head.sam\", \"albedo_map\": \"\"}", SAM_ERR_FORMAT,
     "scene.json: albedo_map: expected a non-empty string, found \"\""},
    {"{\n  \"sam\": \"head.sam\",\n  \"albedo\": [0.5, 0.5,, 0.5]\n}", SAM_ERR_FORMAT,
     "scene.json: line 3, column 23: JSON syntax error at \", 0.5]\""},
    {"{\"sam\": \"head.sam\",\n\"exposure\": 1,\n}", SAM_ERR_FORMAT,
     "scene.json: line 2, column 14: a comma before \"}\" (JSON allows none after the last item)"},
    {"{\"sam\": \"head.sam\", \"albedo\": [0.5, 0.5, 0.5, ]}", SAM_ERR_FORMAT,
     "scene.json: line 1, column 45: a comma before \"]\" (JSON allows none after the last item)"},
    {"{\"sam\": \"head.sam\",\n\"exposure\": 1} trailing", SAM_ERR_FORMAT,
     "scene.json: line 2, column 16: unexpected text after the JSON object"},
    {"", SAM_ERR_FORMAT, "scene.json: empty scene"},
    {" \n ", SAM_ERR_FORMAT, "scene.json: empty scene"},
    {"[1, 2]", SAM_ERR_FORMAT, "scene.json: expected a JSON object, found an array of 2 elements"},
    /* structure */
    {"{\"sam\": \"head.sam\", \"sam\": \"head.sam\"}", SAM_ERR_FORMAT, "scene.json: sam: duplicate key"},
    {"{\"sam\": \"head.sam\", \"Mesh\": 1}", SAM_ERR_FORMAT,
     "scene.json: Mesh: unknown key (expected one of: mesh, sam, material"},
    {"{\"albedo\": [1, 1, 1]}", SAM_ERR_FORMAT, "scene.json: mesh: missing (give \"mesh\" or \"sam\")"},
    {"{\"sam\": 5}", SAM_ERR_FORMAT, "scene.json: sam: expected a non-empty string, found 5"},
    {"{\"sam\": \"\"}", SAM_ERR_FORMAT, "scene.json: sam: expected a non-empty string, found \"\""},
    {"{\"mesh\": \"head.obj\", \"scale\": {\"size_mm\": 1}}", SAM_ERR_FORMAT,
     "scene.json: material: missing (required with \"mesh\" unless \"sam\" names its map)"},
    {"{\"mesh\": \"head.obj\", \"material\": \"skin\"}", SAM_ERR_FORMAT,
     "scene.json: scale: missing (required with \"mesh\""},
    {"{\"sam\": \"head.sam\", \"scale\": {\"size_mm\": 1, \"mm_per_unit\": 1}}", SAM_ERR_FORMAT,
     "scene.json: scale: expected exactly one of mm_per_unit and size_mm, found both"},
    {"{\"sam\": \"head.sam\", \"scale\": {}}", SAM_ERR_FORMAT,
     "scene.json: scale: expected exactly one of mm_per_unit and size_mm, found neither"},
    {"{\"sam\": \"head.sam\", \"scale\": {\"size_mm\": -3}}", SAM_ERR_FORMAT,
     "scene.json: scale.size_mm: expected a number > 0 (finite), found -3"},
    {"{\"sam\": \"head.sam\", \"scale\": {\"inches\": 3}}", SAM_ERR_FORMAT,
     "scene.json: scale.inches: unknown key (expected one of: mm_per_unit, size_mm)"},
    {"{\"sam\": \"head.sam\", \"scale\": 3}", SAM_ERR_FORMAT, "scene.json: scale: expected {"},
    /* vectors and colours */
    {"{\"sam\": \"head.sam\", \"albedo\": [0.5, 0.5]}", SAM_ERR_FORMAT,
     "scene.json: albedo: expected an array of 3 numbers, found an array of 2 elements"},
    {"{\"sam\": \"head.sam\", \"albedo\": [0.5, 1.5, 0.5]}", SAM_ERR_FORMAT,
     "scene.json: albedo: expected values in [0, 1], found albedo[1] = 1.5"},
    {"{\"sam\": \"head.sam\", \"albedo\": [0.5, \"x\", 0.5]}", SAM_ERR_FORMAT,
     "scene.json: albedo[1]: expected a number >= 0 (finite), found \"x\""},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"point\", \"position\": [0, 1e999, 0]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].position[1]: expected a number (finite), found inf"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"point\", \"position\": [0, 1e39, 0]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].position[1]: expected a number (finite), found 1e+39"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 0], "
     "\"color\": [1, -1, 1]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].color[1]: expected a number >= 0 (finite), found -1"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 0], "
     "\"intensity\": -2}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].intensity: expected a number >= 0 (finite), found -2"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 0], "
     "\"shadow\": 1}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].shadow: expected true or false, found 1"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 0]}]}",
     SAM_ERR_FORMAT,
     "scene.json: lights[0].direction: expected a non-zero direction, found [0, 0, 0]"},
    /* lights */
    {"{\"sam\": \"head.sam\", \"lights\": {}}", SAM_ERR_FORMAT,
     "scene.json: lights: expected an array of lights, found an object"},
    {"{\"sam\": \"head.sam\", \"lights\": [7]}", SAM_ERR_FORMAT,
     "scene.json: lights[0]: expected an object, found 7"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"position\": [0, 0, 0]}]}", SAM_ERR_FORMAT,
     "scene.json: lights[0].type: missing (expected point, spot, directional, area)"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"point\"}]}", SAM_ERR_FORMAT,
     "scene.json: lights[0].position: missing (required for a point light)"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"spot\", \"position\": [0, 0, 0]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].direction: missing (required for a spot light)"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], "
     "\"position\": [0, 0, 0]}]}",
     SAM_ERR_FORMAT,
     "scene.json: lights[0].position: unknown key (expected one of: type, direction, color, "
     "intensity, shadow)"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"spot\", \"position\": [0, 0, 0], "
     "\"direction\": [0, 0, 1], \"inner_angle_deg\": 40, \"outer_angle_deg\": 30}]}",
     SAM_ERR_FORMAT,
     "scene.json: lights[0].inner_angle_deg: expected a number <= outer_angle_deg (30), found 40"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"spot\", \"position\": [0, 0, 0], "
     "\"direction\": [0, 0, 1], \"outer_angle_deg\": 90}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].outer_angle_deg: expected a number in (0, 90), found 90"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\"}]}", SAM_ERR_FORMAT,
     "scene.json: lights[0].vertices: missing (required for an area light)"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,0,0], [1,0,0]]}]}",
     SAM_ERR_FORMAT,
     "scene.json: lights[0].vertices: expected an array of 3 to 8 points [x, y, z], found an "
     "array of 2 elements"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,0,0], [1,0,0], "
     "[1,1,0], [0.5,1.5,0], [0,1,0], [0,0.9,0], [0,0.8,0], [0,0.7,0], [0,0.6,0]]}]}",
     SAM_ERR_FORMAT, "found an array of 9 elements"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,0,0], [1,0,0], "
     "[1,1]]}]}",
     SAM_ERR_FORMAT,
     "scene.json: lights[0].vertices[2]: expected an array of 3 numbers, found an array of 2 "
     "elements"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,0,0], [1,0,0], "
     "[2,0,0]]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].vertices: degenerate polygon"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,0,0], [1,0,0], "
     "[1,1,0.1], [0,1,0]]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].vertices: not planar: vertices[0] is"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,0,0], [2,0,0], "
     "[2,2,0], [1,0.5,0], [0,2,0]]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].vertices: not convex: the outline turns back at "
     "vertices[3]"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,0,0], [1,0,0], "
     "[2,0,0], [2,1,0], [0,1,0]]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].vertices: vertices[1] is collinear with its neighbours"},
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,0,0], [1,0,0], "
     "[1,0,0], [0,1,0]]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].vertices: vertices[1] and vertices[2] coincide"},
    /* a pentagram: every corner turns left, but the outline goes round twice */
    {"{\"sam\": \"head.sam\", \"lights\": [{\"type\": \"area\", \"vertices\": [[0,1,0], "
     "[0.587785,-0.809017,0], [-0.951057,0.309017,0], [0.951057,0.309017,0], "
     "[-0.587785,-0.809017,0]]}]}",
     SAM_ERR_FORMAT, "scene.json: lights[0].vertices: not convex: the outline winds around 2 times"},
    /* environment and camera */
    {"{\"sam\": \"head.sam\", \"environment\": {\"intensity\": 2}}", SAM_ERR_FORMAT,
     "scene.json: environment.map: missing"},
    {"{\"sam\": \"head.sam\", \"environment\": {\"map\": \"sky.exr\", \"intensity\": -1}}",
     SAM_ERR_FORMAT, "scene.json: environment.intensity: expected a number >= 0 (finite), found -1"},
    {"{\"sam\": \"head.sam\", \"environment\": \"sky.exr\"}", SAM_ERR_FORMAT,
     "scene.json: environment: expected an object, found \"sky.exr\""},
    {"{\"sam\": \"head.sam\", \"camera\": {\"target\": [0,0,0]}}", SAM_ERR_FORMAT,
     "scene.json: camera.position: missing"},
    {"{\"sam\": \"head.sam\", \"camera\": {\"position\": [1,2,3], \"target\": [1,2,3]}}",
     SAM_ERR_FORMAT, "scene.json: camera.target: equals camera.position [1, 2, 3]"},
    {"{\"sam\": \"head.sam\", \"camera\": {\"position\": [0,5,0], \"target\": [0,0,0]}}",
     SAM_ERR_FORMAT,
     "scene.json: camera.up: [0, 1, 0] is parallel to the view direction [0, -1, 0]"},
    {"{\"sam\": \"head.sam\", \"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], "
     "\"near\": 0}}",
     SAM_ERR_FORMAT, "scene.json: camera.near: expected a number > 0 (finite), found 0"},
    {"{\"sam\": \"head.sam\", \"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], "
     "\"near\": 10, \"far\": 5}}",
     SAM_ERR_FORMAT, "scene.json: camera.far: expected a number greater than near (10), found 5"},
    {"{\"sam\": \"head.sam\", \"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], "
     "\"aperture\": 2}}",
     SAM_ERR_FORMAT,
     "scene.json: camera.aperture: unknown key (expected one of: position, target, up, fov_deg, "
     "near, far)"},
    /* image and technique settings */
    {"{\"sam\": \"head.sam\", \"resolution\": [0, 480]}", SAM_ERR_FORMAT,
     "scene.json: resolution[0]: expected an integer in [1, 16384], found 0"},
    {"{\"sam\": \"head.sam\", \"resolution\": [640, 16385]}", SAM_ERR_FORMAT,
     "scene.json: resolution[1]: expected an integer in [1, 16384], found 16385"},
    {"{\"sam\": \"head.sam\", \"resolution\": [640.5, 480]}", SAM_ERR_FORMAT,
     "scene.json: resolution[0]: expected an integer in [1, 16384], found 640.5"},
    {"{\"sam\": \"head.sam\", \"resolution\": [640]}", SAM_ERR_FORMAT,
     "scene.json: resolution: expected [width, height], found an array of 1 elements"},
    {"{\"sam\": \"head.sam\", \"technique\": \"magic\"}", SAM_ERR_FORMAT,
     "scene.json: technique: unknown technique \"magic\" (expected sam, none, tsm, transmittance, thickness)"},
    {"{\"sam\": \"head.sam\", \"diffusion\": \"SCREEN\"}", SAM_ERR_FORMAT,
     "scene.json: diffusion: unknown diffusion \"SCREEN\" (expected screen, texture, "
     "preintegrated, none)"},
    {"{\"sam\": \"head.sam\", \"samples_per_vertex\": 65}", SAM_ERR_FORMAT,
     "scene.json: samples_per_vertex: expected an integer in [0, 64], found 65"},
    {"{\"sam\": \"head.sam\", \"tonemap\": null}", SAM_ERR_FORMAT,
     "scene.json: tonemap: expected a non-empty string, found null"},
    {"{\"sam\": \"head.sam\", \"exposure\": 40}", SAM_ERR_FORMAT,
     "scene.json: exposure: expected a number in [-32, 32], found 40"},
    /* diffusion settings (after a valid albedo map, which must be freed) */
    {"{\"sam\": \"head.sam\", \"albedo_map\": \"skin.png\", \"screen_space\": {\"samples\": 18}}",
     SAM_ERR_FORMAT,
     "scene.json: screen_space.samples: expected an odd integer in [9, 33], found 18"},
    {"{\"sam\": \"head.sam\", \"screen_space\": {\"samples\": 7}}", SAM_ERR_FORMAT,
     "scene.json: screen_space.samples: expected an odd integer in [9, 33], found 7"},
    {"{\"sam\": \"head.sam\", \"screen_space\": {\"samples\": 35}}", SAM_ERR_FORMAT,
     "scene.json: screen_space.samples: expected an odd integer in [9, 33], found 35"},
    {"{\"sam\": \"head.sam\", \"screen_space\": {\"samples\": 17.5}}", SAM_ERR_FORMAT,
     "scene.json: screen_space.samples: expected an odd integer in [9, 33], found 17.5"},
    {"{\"sam\": \"head.sam\", \"screen_space\": {\"samples\": \"17\"}}", SAM_ERR_FORMAT,
     "scene.json: screen_space.samples: expected an odd integer in [9, 33], found \"17\""},
    {"{\"sam\": \"head.sam\", \"screen_space\": {\"kernel\": \"gauss\"}}", SAM_ERR_FORMAT,
     "scene.json: screen_space.kernel: unknown kernel \"gauss\" (expected fit2d, marginal, eq1)"},
    {"{\"sam\": \"head.sam\", \"screen_space\": {\"kernel\": 2}}", SAM_ERR_FORMAT,
     "scene.json: screen_space.kernel: expected a non-empty string, found 2"},
    {"{\"sam\": \"head.sam\", \"screen_space\": {\"taps\": 17}}", SAM_ERR_FORMAT,
     "scene.json: screen_space.taps: unknown key (expected one of: kernel, samples)"},
    {"{\"sam\": \"head.sam\", \"screen_space\": {\"samples\": 9, \"samples\": 11}}",
     SAM_ERR_FORMAT, "scene.json: screen_space.samples: duplicate key"},
    {"{\"sam\": \"head.sam\", \"screen_space\": 17}", SAM_ERR_FORMAT,
     "scene.json: screen_space: expected an object, found 17"},
    {"{\"sam\": \"head.sam\", \"texture_space\": [1024]}", SAM_ERR_FORMAT,
     "scene.json: texture_space: expected an object, found an array of 1 elements"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"size\": 1024}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.size: unknown key (expected one of: atlas_size, culled, "
     "depth_sized, clipped, texels_per_pixel)"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"atlas_size\": 63}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.atlas_size: expected an integer in [64, 4096], found 63"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"atlas_size\": 4097}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.atlas_size: expected an integer in [64, 4096], found 4097"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"atlas_size\": 512.5}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.atlas_size: expected an integer in [64, 4096], found 512.5"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"culled\": 1}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.culled: expected true or false, found 1"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"depth_sized\": \"yes\"}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.depth_sized: expected true or false, found \"yes\""},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"clipped\": null}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.clipped: expected true or false, found null"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"texels_per_pixel\": 0}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.texels_per_pixel: expected a number in (0, 16], found 0"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"texels_per_pixel\": 16.5}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.texels_per_pixel: expected a number in (0, 16], found 16.5"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"texels_per_pixel\": -1}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.texels_per_pixel: expected a number in (0, 16], found -1"},
    {"{\"sam\": \"head.sam\", \"texture_space\": {\"texels_per_pixel\": 1e999}}", SAM_ERR_FORMAT,
     "scene.json: texture_space.texels_per_pixel: expected a number in (0, 16], found inf"},
    /* a double that is 0 as a float */
    {"{\"sam\": \"head.sam\", \"scale\": {\"mm_per_unit\": 1e-300}}", SAM_ERR_FORMAT,
     "scene.json: scale.mm_per_unit: expected a number > 0 (finite), found 1e-300, which a 32-bit float holds as 0"},
    /* each file under its own key */
    {"{\"mesh\": \"head.sam\", \"material\": \"skin\", \"scale\": {\"size_mm\": 1}}", SAM_ERR_FORMAT,
     "scene.json: mesh: @/head.sam is a .sam map; give it as \"sam\""},
    {"{\"sam\": \"head.obj\"}", SAM_ERR_FORMAT,
     "scene.json: sam: @/head.obj is not a .sam map; give a mesh as \"mesh\""},
    {"{\"mesh\": \"sky.exr\", \"material\": \"skin\", \"scale\": {\"size_mm\": 1}}", SAM_ERR_FORMAT,
     "scene.json: mesh: @/sky.exr is not a mesh file (.obj, .ply, .off, .stl, .gltf or .glb)"},
};

static void test_errors(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof error_cases / sizeof error_cases[0]; ++i) {
        const error_case *c = &error_cases[i];
        char want[1024];
        const char *at = strchr(c->message, '@');
        if (at)
            snprintf(want, sizeof want, "%.*s%s%s", (int)(at - c->message), c->message, dir,
                     at + 1);
        else
            snprintf(want, sizeof want, "%s", c->message);
        sam_scene s;
        sam_error err;
        sam_status st = parse(c->json, &s, &err);
        if (st != c->status || !strstr(err.message, want))
            fail_msg("case %zu: expected status %d and \"%s\", got status %d and \"%s\"", i,
                     (int)c->status, want, (int)st, st == SAM_OK ? "" : err.message);
        /* A failed parse leaves nothing to free. */
        assert_null(s.lights);
        assert_null(s.mesh_path);
        assert_null(s.sam_path);
        assert_null(s.material);
        assert_null(s.environment.map);
        assert_null(s.albedo_map);
        assert_null(s.keyframes);
    }
}

/* Nesting deeper than the JSON parser goes is named as such, not as a
 * syntax error at the bracket where it stopped. */
static void test_nesting_too_deep(void **state)
{
    (void)state;
    enum { DEPTH = 1200 };
    char *text = malloc(2 * DEPTH + 64);
    assert_non_null(text);
    size_t n = (size_t)sprintf(text, "{\"sam\": \"head.sam\", \"x\": ");
    for (int i = 0; i < DEPTH; ++i)
        text[n++] = '[';
    for (int i = 0; i < DEPTH; ++i)
        text[n++] = ']';
    text[n++] = '}';
    text[n] = 0;
    sam_scene s;
    sam_error err;
    assert_int_equal(parse(text, &s, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "objects and arrays nest deeper than 1000 levels"));
    free(text);
}

static void test_too_many_lights(void **state)
{
    (void)state;
    size_t cap = 64 + 70 * (SAM_SCENE_MAX_LIGHTS + 1);
    char *json = malloc(cap);
    size_t len = (size_t)snprintf(json, cap, "{\"sam\": \"head.sam\", \"lights\": [");
    for (int i = 0; i <= SAM_SCENE_MAX_LIGHTS; ++i)
        len += (size_t)snprintf(json + len, cap - len,
                                "%s{\"type\": \"point\", \"position\": [0, %d, 0]}", i ? ", " : "",
                                i);
    snprintf(json + len, cap - len, "]}");
    sam_scene s;
    sam_error err;
    assert_int_equal(parse(json, &s, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "lights: 65 lights, more than the limit of 64"));
    free(json);
}

static void test_every_truncation_fails(void **state)
{
    (void)state;
    const size_t size = strlen(full_scene);
    assert_int_equal(full_scene[size - 1], '}');
    sam_scene s;
    sam_error err;
    assert_int_equal(parse(full_scene, &s, &err), SAM_OK);
    sam_scene_destroy(&s);
    for (size_t len = 0; len < size; ++len) {
        /* An exact-size copy without a terminator: reading past it is a bug
         * the sanitizer build catches. */
        char *copy = malloc(len ? len : 1);
        memcpy(copy, full_scene, len);
        sam_status st = sam_scene_parse(copy, len, dir, "scene.json", &s, &err);
        free(copy);
        if (st == SAM_OK)
            fail_msg("a prefix of %zu of %zu bytes parsed", len, size);
        assert_int_equal(st, SAM_ERR_FORMAT);
        assert_non_null(strstr(err.message, "scene.json: "));
        assert_null(s.lights);
        assert_null(s.mesh_path);
    }
    /* The syntax errors say where. */
    assert_int_equal(sam_scene_parse(full_scene, 40, dir, "scene.json", &s, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "scene.json: line 3, column 17: the JSON text ends before "
                                        "its value is complete"));
}

static void test_load_errors_and_relative_paths(void **state)
{
    (void)state;
    sam_scene s;
    sam_error err;
    assert_int_equal(sam_scene_load("/nonexistent/scene.json", &s, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/scene.json"));
    assert_int_equal(sam_scene_parse(NULL, 0, NULL, NULL, &s, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_scene_load("x.json", NULL, &err), SAM_ERR_INVALID_ARGUMENT);

    /* A scene in a subdirectory resolves against its own directory. */
    char path[640], want[640];
    dir_file(path, sizeof path, "sub/up.json");
    sam_test_write_text(path, "{\"sam\": \"../head.sam\", \"material\": \"../profiles/custom.json\","
                              " \"albedo_map\": \"../skin.png\","
                              " \"environment\": {\"map\": \"../sky.exr\"}}");
    if (sam_scene_load(path, &s, &err) != SAM_OK)
        fail_msg("%s", err.message);
    dir_file(want, sizeof want, "sub/../head.sam");
    assert_string_equal(s.sam_path, want);
    dir_file(want, sizeof want, "sub/../profiles/custom.json");
    assert_string_equal(s.material, want);
    dir_file(want, sizeof want, "sub/../skin.png");
    assert_string_equal(s.albedo_map, want);
    assert_int_equal(s.profile.kind, SAM_PROFILE_DIPOLE);
    sam_scene_destroy(&s);

    /* The same names from the scene directory itself are missing files. */
    dir_file(path, sizeof path, "up.json");
    sam_test_write_text(path, "{\"sam\": \"../head.sam\"}");
    assert_int_equal(sam_scene_load(path, &s, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "up.json: sam: file not found: "));
    assert_non_null(strstr(err.message, "/scene/../head.sam"));

    /* Absolute references are used as they are. */
    char json[1024], abs[640];
    dir_file(abs, sizeof abs, "head.obj");
    snprintf(json, sizeof json,
             "{\"mesh\": \"%s\", \"material\": \"skin\", \"scale\": {\"mm_per_unit\": 1}}", abs);
    assert_int_equal(sam_scene_parse(json, strlen(json), "/nonexistent", "abs.json", &s, &err),
                     SAM_OK);
    assert_string_equal(s.mesh_path, abs);
    sam_scene_destroy(&s);
}

/* "mesh" with "sam": the .sam is that mesh's prebuilt map; both paths
 * are kept, and the material and scale may come from the map. */
static void test_mesh_with_prebuilt_sam(void **state)
{
    (void)state;
    sam_scene s;
    sam_error err;
    assert_int_equal(parse("{\"mesh\": \"head.obj\", \"sam\": \"head.sam\", \"material\": \"skin\", "
                           "\"scale\": {\"mm_per_unit\": 2}}",
                           &s, &err),
                     SAM_OK);
    assert_non_null(s.mesh_path);
    assert_non_null(s.sam_path);
    sam_scene_destroy(&s);
    /* The map records its material and scale, so the scene may leave them out. */
    assert_int_equal(parse("{\"mesh\": \"head.obj\", \"sam\": \"head.sam\"}", &s, &err), SAM_OK);
    assert_null(s.material);
    assert_int_equal(s.scale_kind, SAM_SCALE_FROM_SAM);
    sam_scene_destroy(&s);
}

/* "thickness" names the local-thickness technique, and a written scene
 * keeps it. */
static void test_thickness_technique(void **state)
{
    (void)state;
    sam_scene s, back;
    sam_error err;
    char out[4096];
    assert_int_equal(parse("{\"sam\": \"head.sam\", \"technique\": \"thickness\"}", &s, &err), SAM_OK);
    assert_int_equal(s.technique, SAM_TECHNIQUE_THICKNESS);
    dir_file(out, sizeof out, "thickness.json");
    if (sam_scene_write(out, &s, &err) != SAM_OK || sam_scene_load(out, &back, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(back.technique, SAM_TECHNIQUE_THICKNESS);
    sam_scene_destroy(&s);
    sam_scene_destroy(&back);
}

static void test_names(void **state)
{
    (void)state;
    assert_string_equal(sam_light_type_name(SAM_LIGHT_AREA), "area");
    assert_string_equal(sam_light_type_name((sam_light_type)17), "unknown");
    assert_string_equal(sam_technique_name(SAM_TECHNIQUE_TRANSMITTANCE), "transmittance");
    assert_string_equal(sam_technique_name(SAM_TECHNIQUE_THICKNESS), "thickness");
    assert_string_equal(sam_technique_name((sam_technique)5), "unknown");
    assert_string_equal(sam_diffusion_name(SAM_DIFFUSION_PREINTEGRATED), "preintegrated");
    assert_string_equal(sam_tonemap_name(SAM_TONEMAP_REINHARD), "reinhard");
    assert_string_equal(sam_tonemap_name((sam_tonemap)-1), "unknown");
    assert_string_equal(sam_sss_kernel_name(SAM_SSS_KERNEL_FIT2D), "fit2d");
    assert_string_equal(sam_sss_kernel_name(SAM_SSS_KERNEL_MARGINAL), "marginal");
    assert_string_equal(sam_sss_kernel_name(SAM_SSS_KERNEL_EQ1), "eq1");
    assert_string_equal(sam_sss_kernel_name((sam_sss_kernel)3), "unknown");
}

/* A scene without a camera is seen from the front its box suggests: a
 * Z-tall scan from -Y with +Z up, anything else from +Z with +Y up. */
static void test_default_axes(void **state)
{
    (void)state;
    static const struct {
        float extent[3];
        int z_up;
    } cases[] = {{{1, 1, 3}, 1}, {{1, 2, 1}, 0}, {{3, 1, 2}, 0}, {{1, 1, 1}, 0}, {{1, 1, 1.2f}, 1}, {{2, 1, 2}, 1}};
    for (size_t k = 0; k < sizeof cases / sizeof *cases; ++k) {
        float up[3], front[3];
        const sam_up_axis want = cases[k].z_up ? SAM_UP_POS_Z : SAM_UP_POS_Y;
        assert_int_equal(sam_scene_guess_up(cases[k].extent), want);
        assert_int_equal(sam_scene_default_axes(cases[k].extent, up, front), want);
        const float want_up[3] = {0, cases[k].z_up ? 0.0f : 1.0f, cases[k].z_up ? 1.0f : 0.0f};
        const float want_front[3] = {0, cases[k].z_up ? -1.0f : 0.0f, cases[k].z_up ? 0.0f : 1.0f};
        for (int c = 0; c < 3; ++c) {
            assert_true(up[c] == want_up[c]);
            assert_true(front[c] == want_front[c]);
        }
    }
}

/* Every up axis has a front at right angles to it, the one the name
 * promises, and parses back from its name in either case, the sign
 * optional; anything else is refused. */
static void test_up_axes(void **state)
{
    (void)state;
    static const float want_front[SAM_UP_AXIS_COUNT][3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1},
                                                           {0, 0, -1}, {0, -1, 0}, {0, 1, 0}};
    static const char *const lower[SAM_UP_AXIS_COUNT] = {"x", "-x", "y", "-y", "z", "-z"};
    for (int a = 0; a < SAM_UP_AXIS_COUNT; ++a) {
        float up[3], front[3];
        const sam_up_axis f = sam_scene_axes_for_up((sam_up_axis)a, up, front);
        for (int c = 0; c < 3; ++c) {
            assert_true(up[c] == (c == a / 2 ? (a % 2 ? -1.0f : 1.0f) : 0.0f));
            assert_true(front[c] == want_front[a][c]);
            assert_true(front[c] == (c == (int)f / 2 ? ((int)f % 2 ? -1.0f : 1.0f) : 0.0f));
        }
        assert_true(up[0] * front[0] + up[1] * front[1] + up[2] * front[2] == 0.0f);
        sam_up_axis parsed = SAM_UP_AXIS_COUNT;
        assert_true(sam_up_axis_parse(sam_up_axis_name((sam_up_axis)a), &parsed));
        assert_int_equal(parsed, a);
        parsed = SAM_UP_AXIS_COUNT;
        assert_true(sam_up_axis_parse(lower[a], &parsed));
        assert_int_equal(parsed, a);
    }
    static const char *const bad[] = {"", "+", "-", "w", "+xy", "xx", "--x", "+ x", "y "};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; ++k) {
        sam_up_axis parsed = SAM_UP_NEG_Z;
        assert_false(sam_up_axis_parse(bad[k], &parsed));
        assert_int_equal(parsed, SAM_UP_NEG_Z);
    }
    sam_up_axis parsed = SAM_UP_NEG_Z;
    assert_false(sam_up_axis_parse(NULL, &parsed));
    assert_string_equal(sam_up_axis_name(SAM_UP_AXIS_COUNT), "unknown");
    float up[3], front[3];
    assert_int_equal(sam_scene_axes_for_up(SAM_UP_AXIS_COUNT, up, front), SAM_UP_POS_Z);
    assert_true(up[1] == 1.0f && front[2] == 1.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_scene_loads),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_diffusion_options),
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_write_hand_built_scene),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_nesting_too_deep),
        cmocka_unit_test(test_too_many_lights),
        cmocka_unit_test(test_every_truncation_fails),
        cmocka_unit_test(test_load_errors_and_relative_paths),
        cmocka_unit_test(test_mesh_with_prebuilt_sam),
        cmocka_unit_test(test_thickness_technique),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_default_axes),
        cmocka_unit_test(test_up_axes),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
