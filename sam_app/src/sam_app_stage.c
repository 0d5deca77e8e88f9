/* A bare mesh's scene (sam_app_stage.h). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "sam/sam_app_stage.h"
#include "sam/sam_mesh.h"
#include "sam/sam_thickness.h"
#include "sam/sam_vec3.h"

#define PI_F 3.14159265f
#define FOV_DEG 30.0f
#define ELEVATION_DEG 10.0f

void sam_app_stage_defaults(sam_app_stage_options *options)
{
    memset(options, 0, sizeof *options);
    options->up = -1;
}

static void note(sam_app_stage_notes *notes, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void note(sam_app_stage_notes *notes, const char *fmt, ...)
{
    if (!notes || notes->count >= SAM_APP_STAGE_MAX_NOTES)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(notes->line[notes->count++], sizeof notes->line[0], fmt, ap);
    va_end(ap);
}

static int cmp_float(const void *a, const void *b)
{
    const float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Sorts v[0, n) (n >= 1) and returns the value below which `fraction`
 * of them lie. */
static float sorted_at(float *v, size_t n, float fraction)
{
    qsort(v, n, sizeof *v, cmp_float);
    return v[(size_t)(fraction * (float)(n - 1))];
}

/* The slab thickness in mm through which the material lets `glow` of the
 * light through (mean of RGB), or half of what a slab of no thickness
 * does when that is less. */
static float glow_thickness_mm(const sam_profile *profile, float glow)
{
    float g[3];
    sam_profile_slab_transmission(profile, 0.0f, g);
    float target = fminf(glow, 0.5f * (g[0] + g[1] + g[2]) / 3.0f), lo = 0.0f, hi = 1000.0f;
    for (int i = 0; i < 60; ++i) {
        float mid = 0.5f * (lo + hi);
        sam_profile_slab_transmission(profile, mid, g);
        if ((g[0] + g[1] + g[2]) / 3.0f > target)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5f * (lo + hi);
}

/* What the staging measures of the mesh. */
typedef struct measure {
    float centre[3], extent[3], radius, diagonal;
    float *thin;   /* vertex_count: depth straight through, model units */
    float t_thin;  /* the THIN_FRACTION percentile of thin */
} measure;

/* Measures the mesh's body (sam_mesh_body): a stray speck far from the
 * object would otherwise frame, scale and light the speck. Says what was
 * left out when that moved the box. */
static sam_status measure_mesh(const sam_mesh *m, measure *out, sam_app_stage_notes *notes, sam_error *err)
{
    uint8_t *in_body = malloc((size_t)m->vertex_count + 1);
    if (!in_body)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "stage: out of memory for %u vertices", m->vertex_count);
    sam_mesh_body_info body;
    sam_status st = sam_mesh_body(m, in_body, &body, err);
    if (st != SAM_OK) {
        free(in_body);
        return st;
    }
    if (body.box_changed)
        note(notes,
             "framing and size: %u loose piece%s (%u vertices, %.2g%% of the surface) outside the object left out",
             body.loose_pieces, body.loose_pieces == 1 ? "" : "s", body.loose_vertices,
             100.0 * body.loose_area / body.total_area);
    float d2 = 0, r2 = 0;
    for (int c = 0; c < 3; ++c) {
        out->centre[c] = 0.5f * (body.min[c] + body.max[c]);
        out->extent[c] = body.max[c] - body.min[c];
        d2 += out->extent[c] * out->extent[c];
    }
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        const float *p = m->positions + 3 * (size_t)v;
        float d[3] = {p[0] - out->centre[0], p[1] - out->centre[1], p[2] - out->centre[2]};
        if (in_body[v])
            r2 = fmaxf(r2, sam_vec3_dot(d, d));
    }
    out->diagonal = sqrtf(d2);
    out->radius = sqrtf(r2);
    out->thin = malloc((size_t)m->vertex_count * sizeof *out->thin);
    float *sorted = malloc((size_t)m->vertex_count * sizeof *sorted);
    if (!(out->diagonal > 0))
        st = sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "stage: the mesh has no extent");
    else if (!out->thin || !sorted)
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "stage: out of memory for %u vertices", m->vertex_count);
    if (st == SAM_OK) {
        sam_thickness_settings set;
        sam_thickness_default_settings(&set);
        set.strata = 6;
        set.statistic = SAM_THICKNESS_THROUGH;
        const sam_thickness_surface s = {m->vertex_count, m->positions, m->normals, m->triangle_count, m->triangles};
        st = sam_thickness_compute(&s, 1.0f, &set, NULL, NULL, out->thin, err);
    }
    if (st == SAM_OK) {
        size_t count = 0;
        for (uint32_t v = 0; v < m->vertex_count; ++v)
            if (in_body[v])
                sorted[count++] = out->thin[v];
        out->t_thin = sorted_at(sorted, count, SAM_APP_STAGE_THIN_FRACTION);
    }
    free(sorted);
    free(in_body);
    return st;
}

static void point_light(sam_light *l, const float at[3], float intensity)
{
    memset(l, 0, sizeof *l);
    l->type = SAM_LIGHT_POINT;
    l->shadow = 1;
    l->intensity = intensity;
    for (int c = 0; c < 3; ++c) {
        l->color[c] = 1.0f;
        l->position[c] = at[c];
    }
}

/* Camera and lights around the measured mesh. */
static sam_status place(const measure *ms, const sam_app_stage_options *o, sam_scene *scene,
                        sam_app_stage_notes *notes, sam_error *err)
{
    /* Up is the axis given, else +Z where the mesh is clearly tallest
     * along Z (scanners' and CAD's convention, front then -Y), else +Y
     * (OBJ's and glTF's, front +Z). A part much flatter along up than
     * across (a plate, a leaf lying down) is seen from higher up. */
    const float *ext = ms->extent;
    float up_axis[3], front[3];
    const sam_up_axis axis = o->up >= 0 ? (sam_up_axis)o->up : sam_scene_guess_up(ext);
    const sam_up_axis seen_from = sam_scene_axes_for_up(axis, up_axis, front);
    const int u = (int)axis / 2;
    float side[3];
    sam_vec3_cross(up_axis, front, side);
    const float tall = ext[u], across = fminf(ext[(u + 1) % 3], ext[(u + 2) % 3]);
    const float elevation = tall < 0.25f * across ? 50.0f : ELEVATION_DEG;
    const float a = o->angle_deg * PI_F / 180.0f, e = elevation * PI_F / 180.0f;
    float dir[3];
    for (int c = 0; c < 3; ++c)
        dir[c] = cosf(e) * (cosf(a) * front[c] + sinf(a) * side[c]) + sinf(e) * up_axis[c];
    const float dist = ms->radius / sinf(0.5f * FOV_DEG * PI_F / 180.0f) * 1.05f;
    sam_camera *cam = &scene->camera;
    scene->has_camera = 1;
    for (int c = 0; c < 3; ++c) {
        cam->target[c] = ms->centre[c];
        cam->position[c] = ms->centre[c] + dist * dir[c];
        cam->up[c] = up_axis[c];
    }
    cam->fov_deg = FOV_DEG;
    cam->near_plane = cam->far_plane = 0.0f;
    float forward[3] = {-dir[0], -dir[1], -dir[2]}, right[3], up[3];
    sam_vec3_cross(forward, cam->up, right);
    sam_vec3_normalize(right);
    sam_vec3_cross(right, forward, up);
    scene->lights = calloc(2, sizeof *scene->lights);
    if (!scene->lights)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "stage: out of memory");
    scene->light_count = 2;
    /* Key: above, left of and in front of the camera, irradiance 0.5 at the
     * centre, an eighth of the back light's, so that the glow reads. */
    float key_dir[3], key[3];
    for (int c = 0; c < 3; ++c)
        key_dir[c] = dir[c] + 0.6f * up[c] - 0.6f * right[c];
    sam_vec3_normalize(key_dir);
    const float key_dist = 3.0f * ms->radius;
    for (int c = 0; c < 3; ++c)
        key[c] = ms->centre[c] + key_dist * key_dir[c];
    point_light(&scene->lights[0], key, 0.5f * key_dist * key_dist);
    /* Back: straight behind the object, irradiance 4 at the centre, until
     * sam_app_backlight_place moves it where it shows the most. */
    float back[3];
    const float back_dist = 2.0f * ms->radius;
    for (int c = 0; c < 3; ++c)
        back[c] = ms->centre[c] - back_dist * dir[c];
    point_light(&scene->lights[1], back, 4.0f * back_dist * back_dist);
    note(notes,
         "camera: up %s (%s), from the front (%s) turned %.0f degrees about up and raised %.0f, %.0f degree field "
         "of view, the whole object in view",
         sam_up_axis_name(axis), o->up >= 0 ? "given" : "guessed; --up to change", sam_up_axis_name(seen_from),
         o->angle_deg, elevation, FOV_DEG);
    note(notes, "key light: a point light above-left of the camera, %.3g units from the centre", key_dist);
    return SAM_OK;
}

/* The scene of the mesh, material, scale and resolution only, through the
 * scene parser like any scene file. */
static sam_status parse_bare(const char *mesh_path, const char *material, int size_kind, float scale,
                             const sam_app_stage_options *o, sam_scene *scene, sam_error *err)
{
    cJSON *root = cJSON_CreateObject(), *sc = NULL, *res = NULL;
    if (root && cJSON_AddStringToObject(root, "mesh", mesh_path) &&
        cJSON_AddStringToObject(root, "material", material) && (sc = cJSON_AddObjectToObject(root, "scale")))
        cJSON_AddNumberToObject(sc, size_kind ? "size_mm" : "mm_per_unit", scale);
    if (root && o->width && (res = cJSON_AddArrayToObject(root, "resolution"))) {
        cJSON_AddItemToArray(res, cJSON_CreateNumber(o->width));
        cJSON_AddItemToArray(res, cJSON_CreateNumber(o->height));
    }
    char *text = root ? cJSON_PrintUnformatted(root) : NULL;
    cJSON_Delete(root);
    if (!text)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "stage: out of memory");
    sam_status st = sam_scene_parse(text, strlen(text), NULL, mesh_path, scene, err);
    free(text);
    return st;
}

static sam_status check_options(const sam_app_stage_options *o, sam_error *err)
{
    if (o->size_mm && o->mm_per_unit)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "give the size in mm or the mm per unit, not both");
    if (o->size_mm && !(o->size_mm > 0 && isfinite(o->size_mm)))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "size: expected a finite number of mm > 0, got %g",
                        o->size_mm);
    if (o->mm_per_unit && !(o->mm_per_unit > 0 && isfinite(o->mm_per_unit)))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "mm per unit: expected a finite number > 0, got %g",
                        o->mm_per_unit);
    if (o->up < -1 || o->up >= SAM_UP_AXIS_COUNT)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "up: expected -1 (guess) or a sam_up_axis, got %d", o->up);
    if (!isfinite(o->angle_deg))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "camera angle: expected a finite number, got %g",
                        o->angle_deg);
    if ((o->width || o->height) && (o->width < 1 || o->height < 1 || o->width > SAM_SCENE_MAX_RESOLUTION ||
                                    o->height > SAM_SCENE_MAX_RESOLUTION))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "resolution: expected 1..%d pixels each way, got %ux%u",
                        SAM_SCENE_MAX_RESOLUTION, o->width, o->height);
    return SAM_OK;
}

sam_status sam_app_stage_scene(const char *mesh_path, const char *material, const sam_app_stage_options *options,
                               sam_scene *scene, sam_app_stage_notes *notes, sam_error *err)
{
    sam_scene_init(scene);
    if (notes)
        memset(notes, 0, sizeof *notes);
    sam_status st = check_options(options, err);
    if (st != SAM_OK)
        return st;
    const char *mat = material ? material : "skin";
    sam_profile profile;
    sam_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    measure ms = {{0, 0, 0}, {0, 0, 0}, 0, 0, NULL, 0};
    if ((st = sam_profile_from_spec(mat, &profile, err)) != SAM_OK ||
        (st = sam_mesh_load(mesh_path, &mesh, NULL, err)) != SAM_OK)
        goto done;
    /* As the map's build will turn it (sam_app_scene_object). */
    sam_mesh_orient_outward(&mesh);
    char rounding[256];
    if (sam_mesh_precision_warning(&mesh, NULL, rounding, sizeof rounding))
        note(notes, "warning: %s", rounding);
    if ((st = measure_mesh(&mesh, &ms, notes, err)) != SAM_OK)
        goto done;
    float mm_per_unit;
    if (options->mm_per_unit > 0) {
        mm_per_unit = options->mm_per_unit;
        note(notes, "size: %.4g mm per model unit, %.4g mm across (given)", mm_per_unit, mm_per_unit * ms.diagonal);
    } else if (options->size_mm > 0) {
        mm_per_unit = options->size_mm / ms.diagonal;
        note(notes, "size: %.4g mm across (given)", options->size_mm);
    } else {
        const float glow = glow_thickness_mm(&profile, SAM_APP_STAGE_GLOW);
        const float wanted = glow / ms.t_thin * ms.diagonal;
        const float size = fminf(fmaxf(wanted, SAM_APP_STAGE_MIN_MM), SAM_APP_STAGE_MAX_MM);
        mm_per_unit = size / ms.diagonal;
        if (notes)
            notes->size_guessed = 1;
        if (size == wanted)
            note(notes,
                 "size: NOT GIVEN; assuming %.4g mm across (%.4g mm per unit), at which the thinnest %.0f%% of the "
                 "surface is %.2f mm thick, where %s lets %.0f%% of back light through; give --size-mm or "
                 "--mm-per-unit for the real size",
                 size, mm_per_unit, 100.0f * SAM_APP_STAGE_THIN_FRACTION, glow, mat, 100.0f * SAM_APP_STAGE_GLOW);
        else
            note(notes,
                 "size: NOT GIVEN; assuming %.4g mm across (%.4g mm per unit): the thinnest %.0f%% of the surface "
                 "would be %.2f mm thick, where %s lets %.0f%% of back light through, at %.4g mm, outside %g..%g mm; "
                 "give --size-mm or --mm-per-unit for the real size",
                 size, mm_per_unit, 100.0f * SAM_APP_STAGE_THIN_FRACTION, glow, mat, 100.0f * SAM_APP_STAGE_GLOW,
                 wanted, SAM_APP_STAGE_MIN_MM, SAM_APP_STAGE_MAX_MM);
    }
    note(notes, "material: %s%s", mat, material ? "" : " (not given)");
    if ((st = parse_bare(mesh_path, mat, 0, mm_per_unit, options, scene, err)) == SAM_OK)
        st = place(&ms, options, scene, notes, err);
    /* The renderer takes the texture the file names (sam_runtime_scene_setup):
     * say which, as every assumption is said. One that cannot be used is its
     * warning. */
    sam_image albedo;
    sam_albedo_maps maps;
    char texture[2304]; /* a texture path, the mesh's, and a count of other textures */
    sam_error albedo_err;
    if (st == SAM_OK && sam_mesh_load_albedo_maps(mesh_path, &maps, texture, sizeof texture, &albedo_err) == SAM_OK &&
        maps.map_count) {
        uint32_t white = 0;
        for (uint32_t f = 0; f < maps.face_count; ++f)
            white += maps.face_map[f] == SAM_ALBEDO_NO_MAP;
        note(notes, "albedo maps: %u for the materials of %s, each on its own faces%s, times the albedo (a scene's "
                    "\"albedo_map\" replaces them)",
             maps.map_count, mesh_path, white ? " (faces without one white)" : "");
        sam_albedo_maps_destroy(&maps);
    } else if (st == SAM_OK &&
               sam_mesh_load_albedo(mesh_path, &albedo, texture, sizeof texture, &albedo_err) == SAM_OK &&
               albedo.pixels) {
        note(notes, "albedo map: %s, %ux%u, times the albedo (a scene's \"albedo_map\" replaces it)", texture,
             albedo.width, albedo.height);
        sam_image_destroy(&albedo);
    }
    float *colors = NULL;
    uint32_t color_count = 0;
    if (st == SAM_OK &&
        sam_mesh_load_vertex_colors(mesh_path, &colors, &color_count, texture, sizeof texture, &albedo_err) == SAM_OK &&
        colors)
        note(notes, "vertex colours: %s, %u vertices, times the albedo (a scene's \"vertex_colors\": false ignores "
                    "them)", texture, color_count);
    free(colors);
done:
    free(ms.thin);
    sam_mesh_destroy(&mesh);
    if (st != SAM_OK)
        sam_scene_destroy(scene);
    return st;
}

float sam_app_stage_exposure(const sam_image *hdr)
{
    if (!hdr || !hdr->pixels || hdr->channels < 3)
        return 0.0f;
    const size_t n = (size_t)hdr->width * hdr->height;
    float *lum = malloc((n ? n : 1) * sizeof *lum);
    if (!lum)
        return 0.0f;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        const float *p = hdr->pixels + i * hdr->channels;
        if (hdr->channels == 4 && !(p[3] > 0.5f))
            continue;
        /* The brightest channel, not the luminance: a strongly coloured
         * material (ketchup, apple) read by its luminance was exposed until
         * its own colour clipped, and the back light's rims with it. */
        float y = fmaxf(p[0], fmaxf(p[1], p[2]));
        if (isfinite(y))
            lum[count++] = y;
    }
    float ev = 0.0f;
    if (count) {
        float top = sorted_at(lum, count, 0.97f);
        if (top > 0)
            ev = fminf(fmaxf(log2f(1.2f / top), -32.0f), 32.0f);
    }
    free(lum);
    return ev;
}
