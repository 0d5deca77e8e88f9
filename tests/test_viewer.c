/* The viewer's state machine (sam_viewer.h), driven with no window and no
 * GL context: keys, drags, the wheel, script events and the frame plan. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "sam/sam_viewer.h"
#include "sam_test.h"

/* A started viewer: 4 samples per vertex, a unit object at (1, 2, 3) seen
 * from 5 units along +Z, one point light, usable UVs as asked. */
static void start(sam_viewer *v, int uv_ok)
{
    sam_viewer_init(v, "shot");
    v->scene.lights = calloc(1, sizeof *v->scene.lights);
    assert_non_null(v->scene.lights);
    v->scene.light_count = 1;
    v->scene.lights[0].type = SAM_LIGHT_POINT;
    v->scene.lights[0].position[2] = 6.0f;
    v->scene.lights[0].intensity = 1.0f;
    const float centre[3] = {1, 2, 3}, eye[3] = {1, 2, 8};
    sam_viewer_start(v, 4, centre, 1.0f, uv_ok, eye, centre, 40.0f);
    v->window_height = 200;
}

static float distance_to(const float a[3], const float b[3])
{
    return sqrtf((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

static unsigned key(sam_viewer *v, int k)
{
    return sam_viewer_key(v, k, GLFW_PRESS);
}

static sam_view_event drag(int button, float x0, float y0, float x1, float y1)
{
    sam_view_event e = {.action = SAM_VIEW_DRAG, .button = button, .x0 = x0, .y0 = y0, .x1 = x1, .y1 = y1};
    return e;
}

static void test_start_takes_the_camera(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    float eye[3];
    sam_viewer_eye(&v, eye);
    assert_float_equal(eye[0], 1.0f, 1e-5f);
    assert_float_equal(eye[1], 2.0f, 1e-5f);
    assert_float_equal(eye[2], 8.0f, 1e-5f);
    assert_float_equal(v.distance, 5.0f, 1e-5f);
    assert_int_equal(v.button, -1);
    assert_true(v.smoothing && v.reset_t);
    sam_viewer_destroy(&v);
}

static void test_technique_key_cycles(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    static const sam_technique order[] = {SAM_TECHNIQUE_NONE, SAM_TECHNIQUE_TSM, SAM_TECHNIQUE_TRANSMITTANCE,
                                          SAM_TECHNIQUE_THICKNESS, SAM_TECHNIQUE_SAM};
    for (int i = 0; i < 5; ++i) {
        v.reset_t = 0;
        assert_int_equal(key(&v, GLFW_KEY_T), 0);
        assert_int_equal(v.scene.technique, order[i]);
        assert_int_equal(v.reset_t, 1);
        /* Only SAM runs its translucency pass; only thickness needs its thickness. */
        sam_viewer_frame f;
        sam_viewer_frame_plan(&v, 0.0, &f);
        assert_int_equal(f.translucency, order[i] == SAM_TECHNIQUE_SAM);
        assert_int_equal(f.thickness, order[i] == SAM_TECHNIQUE_THICKNESS);
        /* tsm brings texture-space diffusion with it. */
        if (order[i] == SAM_TECHNIQUE_TSM)
            assert_int_equal(v.scene.diffusion, SAM_DIFFUSION_TEXTURE);
    }
    sam_viewer_destroy(&v);
}

static void test_tsm_needs_uvs(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 0);
    key(&v, GLFW_KEY_T);
    key(&v, GLFW_KEY_T);
    assert_int_equal(v.scene.technique, SAM_TECHNIQUE_TRANSMITTANCE);
    assert_non_null(strstr(v.message, "tsm skipped"));
    /* Diffusion skips texture space too. */
    key(&v, GLFW_KEY_D);
    assert_int_equal(v.scene.diffusion, SAM_DIFFUSION_PREINTEGRATED);
    key(&v, GLFW_KEY_D);
    assert_int_equal(v.scene.diffusion, SAM_DIFFUSION_NONE);
    key(&v, GLFW_KEY_D);
    assert_int_equal(v.scene.diffusion, SAM_DIFFUSION_SCREEN);
    sam_viewer_destroy(&v);
}

static void test_diffusion_leaving_texture_drops_tsm(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    key(&v, GLFW_KEY_T);
    key(&v, GLFW_KEY_T);
    assert_int_equal(v.scene.technique, SAM_TECHNIQUE_TSM);
    key(&v, GLFW_KEY_D);
    assert_int_equal(v.scene.diffusion, SAM_DIFFUSION_PREINTEGRATED);
    assert_int_equal(v.scene.technique, SAM_TECHNIQUE_SAM);
    sam_viewer_destroy(&v);
}

static void test_orbit_keeps_the_distance(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    float before[3], after[3];
    sam_viewer_eye(&v, before);
    sam_view_event e = drag(GLFW_MOUSE_BUTTON_LEFT, 100, 100, 160, 70);
    assert_int_equal(sam_viewer_event(&v, &e), 0);
    sam_viewer_eye(&v, after);
    assert_true(distance_to(before, after) > 0.5f);
    assert_float_equal(distance_to(after, v.target), 5.0f, 1e-4f);
    assert_float_equal(v.target[0], 1.0f, 1e-6f);
    assert_int_equal(v.button, -1);
    /* A long vertical drag stops short of the pole. */
    e = drag(GLFW_MOUSE_BUTTON_LEFT, 0, 0, 0, 10000);
    sam_viewer_event(&v, &e);
    assert_float_equal(v.pitch, 1.55f, 1e-6f);
    sam_viewer_destroy(&v);
}

static void test_pan_moves_the_target_not_the_view(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    sam_view_event e = drag(GLFW_MOUSE_BUTTON_RIGHT, 100, 100, 150, 100);
    sam_viewer_event(&v, &e);
    /* Dragging right moves the target left (-X seen from +Z). */
    assert_true(v.target[0] < 1.0f);
    assert_float_equal(v.target[1], 2.0f, 1e-5f);
    assert_float_equal(v.distance, 5.0f, 1e-6f);
    /* Shift + left drag pans too. */
    float x = v.target[0];
    sam_viewer_button(&v, GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, GLFW_MOD_SHIFT);
    sam_viewer_cursor(&v, v.cursor_x + 50, v.cursor_y);
    assert_true(v.target[0] < x);
    sam_viewer_destroy(&v);
}

static void test_zoom_is_clamped(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    sam_viewer_scroll(&v, 1);
    assert_float_equal(v.distance, 4.5f, 1e-5f);
    sam_viewer_scroll(&v, -1);
    assert_float_equal(v.distance, 5.0f, 1e-5f);
    sam_viewer_scroll(&v, 1000);
    assert_float_equal(v.distance, 1e-3f * v.radius, 1e-9f);
    sam_viewer_destroy(&v);
}

static void test_light_drag_turns_about_the_centre(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    float before[3];
    memcpy(before, v.scene.lights[0].position, sizeof before);
    sam_view_event e = drag(GLFW_MOUSE_BUTTON_MIDDLE, 10, 10, 60, 30);
    assert_int_equal(sam_viewer_event(&v, &e), SAM_VIEWER_LIGHTS);
    const float *after = v.scene.lights[0].position;
    assert_true(distance_to(before, after) > 0.1f);
    assert_float_equal(distance_to(after, v.centre), distance_to(before, v.centre), 1e-4f);
    /* The camera stays. */
    assert_float_equal(v.distance, 5.0f, 1e-6f);
    /* Ctrl + left drag moves the light as well. */
    sam_viewer_button(&v, GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, GLFW_MOD_CONTROL);
    assert_int_equal(sam_viewer_cursor(&v, v.cursor_x + 20, v.cursor_y), SAM_VIEWER_LIGHTS);
    sam_viewer_destroy(&v);
}

static void test_light_keys(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    assert_int_equal(key(&v, GLFW_KEY_EQUAL), SAM_VIEWER_LIGHTS);
    assert_float_equal(v.scene.lights[0].intensity, 1.25f, 1e-6f);
    key(&v, GLFW_KEY_MINUS);
    assert_float_equal(v.scene.lights[0].intensity, 1.0f, 1e-6f);
    /* White (calloc: black counts as none of the colours) then warm. */
    assert_int_equal(key(&v, GLFW_KEY_C), SAM_VIEWER_LIGHTS);
    assert_float_equal(v.scene.lights[0].color[1], 1.0f, 1e-6f);
    key(&v, GLFW_KEY_C);
    assert_float_equal(v.scene.lights[0].color[1], 0.8f, 1e-6f);
    key(&v, GLFW_KEY_L);
    assert_int_equal(v.selected_light, 0);
    assert_non_null(strstr(v.message, "light 1 of 1"));
    /* Without an environment, E only says so. */
    assert_int_equal(key(&v, GLFW_KEY_E), 0);
    assert_int_equal(v.environment_on, 0);
    assert_int_equal(key(&v, GLFW_KEY_COMMA), SAM_VIEWER_ENVIRONMENT);
    assert_float_equal(v.scene.environment.rotation_deg, 345.0f, 1e-4f);
    sam_viewer_destroy(&v);
}

static void test_samples_keys(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    assert_int_equal(sam_viewer_samples_used(&v), 4);
    key(&v, GLFW_KEY_RIGHT_BRACKET);
    assert_int_equal(v.scene.samples_per_vertex, 0); /* all: no more than the stride */
    for (int i = 0; i < 5; ++i)
        key(&v, GLFW_KEY_LEFT_BRACKET);
    assert_int_equal(v.scene.samples_per_vertex, 1);
    key(&v, GLFW_KEY_RIGHT_BRACKET);
    assert_int_equal(sam_viewer_samples_used(&v), 2);
    key(&v, GLFW_KEY_RIGHT_BRACKET);
    key(&v, GLFW_KEY_RIGHT_BRACKET);
    assert_int_equal(v.scene.samples_per_vertex, 0);
    sam_viewer_destroy(&v);
}

static void test_switches_and_releases(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    /* The view mode skips the difference view without a truth image. */
    for (int i = 0; i < 4; ++i)
        key(&v, GLFW_KEY_V);
    assert_int_equal(v.mode, SAM_VIEWER_FINAL);
    v.has_truth = 1;
    for (int i = 0; i < 4; ++i)
        key(&v, GLFW_KEY_V);
    assert_int_equal(v.mode, SAM_VIEWER_DIFFERENCE);
    key(&v, GLFW_KEY_S);
    assert_int_equal(v.smoothing, 0);
    key(&v, GLFW_KEY_H);
    assert_int_equal(v.help, 1);
    /* Nothing to play in a still scene. */
    key(&v, GLFW_KEY_SPACE);
    assert_int_equal(v.playing, 0);
    assert_non_null(strstr(v.message, "nothing to play"));
    /* Releases do nothing, and a held P takes one screenshot. */
    assert_int_equal(sam_viewer_key(&v, GLFW_KEY_T, GLFW_RELEASE), 0);
    assert_int_equal(v.scene.technique, SAM_TECHNIQUE_SAM);
    assert_int_equal(key(&v, GLFW_KEY_P), SAM_VIEWER_SCREENSHOT);
    assert_int_equal(sam_viewer_key(&v, GLFW_KEY_P, GLFW_REPEAT), 0);
    assert_int_equal(key(&v, GLFW_KEY_Q), SAM_VIEWER_QUIT);
    assert_int_equal(key(&v, GLFW_KEY_ESCAPE), SAM_VIEWER_QUIT);
    sam_viewer_destroy(&v);
}

static void test_frame_plan(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    sam_viewer_frame f;
    sam_viewer_frame_plan(&v, 0.1, &f);
    assert_true(f.translucency && f.reset && !f.deform);
    sam_viewer_frame_plan(&v, 0.1, &f);
    assert_int_equal(f.reset, 0); /* the reset is used up */
    assert_float_equal(f.dt, 0.1f, 1e-7f);
    /* A posed scene deforms on its first frame and while playing. */
    v.posed = 1;
    v.reset_t = 1;
    sam_viewer_frame_plan(&v, 0.1, &f);
    assert_true(f.deform && f.time_s == 0.0f);
    sam_viewer_frame_plan(&v, 0.1, &f);
    assert_int_equal(f.deform, 0);
    key(&v, GLFW_KEY_SPACE);
    sam_viewer_frame_plan(&v, 0.25, &f);
    assert_true(f.deform);
    assert_float_equal(f.time_s, 0.25f, 1e-6f);
    key(&v, GLFW_KEY_T);
    sam_viewer_frame_plan(&v, 0.25, &f);
    assert_int_equal(f.translucency, 0); /* none */
    /* No smoothing: every frame replaces the history. */
    key(&v, GLFW_KEY_S);
    sam_viewer_frame_plan(&v, 0.1, &f);
    assert_int_equal(f.reset, 1);
    sam_viewer_destroy(&v);
}

static void test_script_sequence(void **state)
{
    (void)state;
    static const char script[] = "0 key T\n"
                                 "0 key D\n"
                                 "0 key ]\n"
                                 "0 key [\n"
                                 "0 key V\n"
                                 "0 drag left 160 120 260 120\n"
                                 "0 scroll 6\n"
                                 "0 key F\n"
                                 "0 resize 200 150\n"
                                 "0 screenshot out/a\n"
                                 "0 lose-context\n"
                                 "0 quit\n";
    sam_view_event *e;
    size_t n;
    sam_error err;
    if (sam_view_script_parse(script, strlen(script), "s.txt", &e, &n, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(n, 12);
    sam_viewer v;
    start(&v, 1);
    unsigned effects[12];
    for (size_t i = 0; i < n; ++i)
        effects[i] = sam_viewer_event(&v, &e[i]);
    assert_int_equal(v.scene.technique, SAM_TECHNIQUE_NONE);
    assert_int_equal(v.scene.diffusion, SAM_DIFFUSION_TEXTURE);
    assert_int_equal(v.scene.samples_per_vertex, 3);
    assert_int_equal(v.mode, SAM_VIEWER_TRANSLUCENCY);
    assert_float_equal(v.yaw, -1.0f, 1e-5f); /* 100 pixels left to right */
    /* F framed the object again after the wheel. */
    assert_float_equal(v.distance, 1.0f / sinf(20.0f * 3.14159265f / 180.0f) * 1.05f, 1e-4f);
    for (size_t i = 0; i < 8; ++i)
        assert_int_equal(effects[i], 0);
    assert_int_equal(effects[8], SAM_VIEWER_RESIZE);
    assert_int_equal(effects[9], SAM_VIEWER_SHOT_TO);
    assert_int_equal(effects[10], SAM_VIEWER_LOSE_CONTEXT);
    assert_int_equal(effects[11], SAM_VIEWER_QUIT);
    free(e);
    sam_viewer_destroy(&v);
}

static void test_text(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    assert_int_equal(sam_viewer_count_frame(&v, 1.0), 1);
    sam_viewer_set_status(&v, " irr 0.10");
    assert_int_equal(sam_viewer_count_frame(&v, 1.2), 0);
    assert_non_null(strstr(v.status_line, "sam | screen | N 4/4 | smoothing | final\n"));
    assert_non_null(strstr(v.status_line, "GPU ms: irr 0.10"));
    char title[400], overlay[512];
    sam_viewer_title(&v, title, sizeof title);
    assert_null(strchr(title, '\n'));
    assert_memory_equal(title, "sam_view - sam | screen", 23);
    sam_viewer_say(&v, "hello %d", 7);
    sam_viewer_overlay(&v, 3.0, overlay, sizeof overlay);
    assert_non_null(strstr(overlay, "\nhello 7"));
    sam_viewer_overlay(&v, 5.0, overlay, sizeof overlay); /* four seconds later, gone */
    assert_null(strstr(overlay, "hello"));
    char name[64];
    sam_viewer_shot_name(&v, NULL, name, sizeof name);
    assert_string_equal(name, "shot_0001");
    sam_viewer_shot_name(&v, "x/y", name, sizeof name);
    assert_string_equal(name, "x/y");
    sam_viewer_shot_name(&v, NULL, name, sizeof name);
    assert_string_equal(name, "shot_0002");
    sam_viewer_destroy(&v);
}

static void test_apply_view(void **state)
{
    (void)state;
    sam_viewer v;
    start(&v, 1);
    sam_render_view view = {.front = 1, .diffusion = 1, .albedo = {0.5f, 0.5f, 0.5f}};
    sam_viewer_apply_view(&v, &view);
    assert_float_equal(view.eye[2], 8.0f, 1e-5f);
    assert_true(view.up[1] == 1.0f && view.front == 1);
    key(&v, GLFW_KEY_V);
    sam_viewer_apply_view(&v, &view);
    assert_int_equal(view.front, 0);
    key(&v, GLFW_KEY_V);
    sam_viewer_apply_view(&v, &view);
    assert_true(view.technique == SAM_TECHNIQUE_NONE && view.diffusion == 0 && view.albedo[0] == 1.0f);
    sam_viewer_destroy(&v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_start_takes_the_camera),
        cmocka_unit_test(test_technique_key_cycles),
        cmocka_unit_test(test_tsm_needs_uvs),
        cmocka_unit_test(test_diffusion_leaving_texture_drops_tsm),
        cmocka_unit_test(test_orbit_keeps_the_distance),
        cmocka_unit_test(test_pan_moves_the_target_not_the_view),
        cmocka_unit_test(test_zoom_is_clamped),
        cmocka_unit_test(test_light_drag_turns_about_the_centre),
        cmocka_unit_test(test_light_keys),
        cmocka_unit_test(test_samples_keys),
        cmocka_unit_test(test_switches_and_releases),
        cmocka_unit_test(test_frame_plan),
        cmocka_unit_test(test_script_sequence),
        cmocka_unit_test(test_text),
        cmocka_unit_test(test_apply_view),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
