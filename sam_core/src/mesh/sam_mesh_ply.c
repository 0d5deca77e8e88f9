#include "sam_mesh_ply.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sam_mesh_ply_type sam_mesh_ply_type_of(const char *tok, int len)
{
    static const struct {
        const char *name;
        sam_mesh_ply_type type;
    } names[] = {{"char", SAM_MESH_PLY_INT8},      {"uchar", SAM_MESH_PLY_UINT8},     {"short", SAM_MESH_PLY_INT16},
                 {"ushort", SAM_MESH_PLY_UINT16},  {"int", SAM_MESH_PLY_INT32},       {"uint", SAM_MESH_PLY_UINT32},
                 {"float", SAM_MESH_PLY_FLOAT32},  {"double", SAM_MESH_PLY_FLOAT64},  {"int8", SAM_MESH_PLY_INT8},
                 {"uint8", SAM_MESH_PLY_UINT8},    {"int16", SAM_MESH_PLY_INT16},     {"uint16", SAM_MESH_PLY_UINT16},
                 {"int32", SAM_MESH_PLY_INT32},    {"uint32", SAM_MESH_PLY_UINT32},   {"float32", SAM_MESH_PLY_FLOAT32},
                 {"float64", SAM_MESH_PLY_FLOAT64}};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i)
        if (len == (int)strlen(names[i].name) && !strncmp(tok, names[i].name, (size_t)len))
            return names[i].type;
    return SAM_MESH_PLY_UNKNOWN;
}

int sam_mesh_ply_type_size(sam_mesh_ply_type t)
{
    static const int sizes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[t];
}

static int is_float(sam_mesh_ply_type t)
{
    return t == SAM_MESH_PLY_FLOAT32 || t == SAM_MESH_PLY_FLOAT64;
}

/* What a vertex property is to OpenMesh's reader: 0..2 position, 3..5
 * normal, 6..7 texture coordinate, -1 anything else. */
static int vertex_role(const char *name)
{
    static const char *const roles[] = {"x", "y", "z", "nx", "ny", "nz", "u", "v"};
    for (int r = 0; r < 8; ++r)
        if (!strcmp(name, roles[r]))
            return r;
    return !strcmp(name, "s") ? 6 : !strcmp(name, "t") ? 7 : -1;
}

int sam_mesh_ply_misread(const sam_mesh_ply_header *h)
{
    /* The reader stops after the face element. */
    for (int e = 0; e < h->element_count; ++e) {
        const sam_mesh_ply_element *el = &h->element[e];
        const int face = !strcmp(el->name, "face"), vertex = !strcmp(el->name, "vertex");
        for (int k = 0; k < el->property_count; ++k) {
            const sam_mesh_ply_property *pr = &el->property[k];
            if (face && k == 0 && pr->is_list) {
                /* A count type it does not know; corner indices typed as floats. */
                if (!pr->count_name_read || is_float(pr->value_type))
                    return 1;
            } else if (pr->is_list) {
                return 1; /* skipped as one value */
            } else if (vertex && vertex_role(pr->name) >= 0 && !is_float(pr->value_type)) {
                return 1; /* integer positions, normals or texture coordinates: not read */
            }
        }
        if (face)
            break;
    }
    /* A comment, blank line or trailing blank before end_header. */
    return h->format != 0 && h->reader_body != h->body;
}

/* Walks a body value by value, ASCII or binary. */
typedef struct ply_cursor {
    const char *p, *end;
    int format;
} ply_cursor;

static double read_value(ply_cursor *c, sam_mesh_ply_type t)
{
    if (c->format == 0) {
        char *stop;
        double v = strtod(c->p, &stop);
        c->p = stop;
        return v;
    }
    const int n = sam_mesh_ply_type_size(t);
    unsigned char b[8];
    for (int i = 0; i < n; ++i)
        b[i] = (unsigned char)c->p[c->format == 2 ? n - 1 - i : i]; /* to little-endian */
    c->p += n;
    uint64_t bits = 0;
    for (int i = n - 1; i >= 0; --i)
        bits = bits << 8 | b[i];
    switch (t) {
    case SAM_MESH_PLY_INT8: return (double)(int8_t)bits;
    case SAM_MESH_PLY_INT16: return (double)(int16_t)bits;
    case SAM_MESH_PLY_INT32: return (double)(int32_t)bits;
    case SAM_MESH_PLY_FLOAT32: {
        uint32_t u = (uint32_t)bits;
        float f;
        memcpy(&f, &u, sizeof f);
        return f;
    }
    case SAM_MESH_PLY_FLOAT64: {
        double d;
        memcpy(&d, &bits, sizeof d);
        return d;
    }
    default: return (double)bits;
    }
}

/* The largest value of an integer type (1 for a float: taken as it is). */
static double type_max(sam_mesh_ply_type t)
{
    switch (t) {
    case SAM_MESH_PLY_INT8: return 127.0;
    case SAM_MESH_PLY_UINT8: return 255.0;
    case SAM_MESH_PLY_INT16: return 32767.0;
    case SAM_MESH_PLY_UINT16: return 65535.0;
    case SAM_MESH_PLY_INT32: return 2147483647.0;
    case SAM_MESH_PLY_UINT32: return 4294967295.0;
    default: return 1.0;
    }
}

/* Which colour channel a vertex property holds: 0..2, or -1. */
static int color_channel(const sam_mesh_ply_property *pr)
{
    static const char *const names[2][3] = {{"red", "green", "blue"}, {"diffuse_red", "diffuse_green", "diffuse_blue"}};
    for (int set = 0; set < 2 && !pr->is_list; ++set)
        for (int k = 0; k < 3; ++k)
            if (!strcmp(pr->name, names[set][k]))
                return k;
    return -1;
}

/* Walks the body up to element `target` (the pre-check checked it), giving
 * `take` each of its rows' scalar values whose property `slot` names
 * (>= 0), as read. */
static void walk_element(const char *data, size_t size, const sam_mesh_ply_header *h, int target,
                         int (*slot)(const sam_mesh_ply_property *), void (*take)(void *, unsigned long long, int,
                                                                                  const sam_mesh_ply_property *, double),
                         void *to)
{
    ply_cursor c = {data + h->body, data + size, h->format};
    for (int e = 0; e <= target; ++e)
        for (unsigned long long i = 0; i < h->element[e].count; ++i)
            for (int k = 0; k < h->element[e].property_count; ++k) {
                const sam_mesh_ply_property *pr = &h->element[e].property[k];
                const double n = pr->is_list ? read_value(&c, pr->count_type) : 1;
                for (double j = 0; j < n; ++j) {
                    const double x = read_value(&c, pr->value_type);
                    const int at = e == target && !pr->is_list ? slot(pr) : -1;
                    if (at >= 0)
                        take(to, i, at, pr, x);
                }
            }
}

/* The element named `name`, or -1. */
static int element_named(const sam_mesh_ply_header *h, const char *name)
{
    for (int e = 0; e < h->element_count; ++e)
        if (!strcmp(h->element[e].name, name))
            return e;
    return -1;
}

static void take_color(void *to, unsigned long long row, int channel, const sam_mesh_ply_property *pr, double x)
{
    ((float *)to)[3 * row + (unsigned)channel] = (float)fmin(fmax(x / type_max(pr->value_type), 0.0), 1.0);
}

sam_status sam_mesh_ply_colors(const char *path, const char *data, size_t size, const sam_mesh_ply_header *h,
                               float **rgb, sam_error *err)
{
    *rgb = NULL;
    const int vertex = element_named(h, "vertex");
    int found = 0;
    for (int k = 0; vertex >= 0 && k < h->element[vertex].property_count; ++k) {
        const int ch = color_channel(&h->element[vertex].property[k]);
        found |= ch >= 0 ? 1 << ch : 0;
    }
    if (found != 7 || !h->element[vertex].count)
        return SAM_OK;
    const sam_mesh_ply_element *el = &h->element[vertex];
    float *out = malloc((size_t)el->count * 3 * sizeof *out);
    if (!out)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %llu vertex colours", path, el->count);
    walk_element(data, size, h, vertex, color_channel, take_color, out);
    *rgb = out;
    return SAM_OK;
}

static int is_texnumber(const sam_mesh_ply_property *pr)
{
    return !strcmp(pr->name, "texnumber") ? 0 : -1;
}

static void take_texnumber(void *to, unsigned long long row, int slot, const sam_mesh_ply_property *pr, double x)
{
    (void)slot, (void)pr;
    ((uint32_t *)to)[row] = x >= 0 && x < 4294967295.0 && x == floor(x) ? (uint32_t)x : 0xFFFFFFFFu;
}

sam_status sam_mesh_ply_texnumbers(const char *path, const char *data, size_t size, const sam_mesh_ply_header *h,
                                   uint32_t **numbers, sam_error *err)
{
    *numbers = NULL;
    const int face = element_named(h, "face");
    int found = 0;
    for (int k = 0; face >= 0 && k < h->element[face].property_count; ++k)
        found |= !h->element[face].property[k].is_list && is_texnumber(&h->element[face].property[k]) == 0;
    if (!found || !h->element[face].count)
        return SAM_OK;
    const sam_mesh_ply_element *el = &h->element[face];
    uint32_t *out = malloc((size_t)el->count * sizeof *out);
    if (!out)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %llu faces' texture numbers", path,
                        el->count);
    walk_element(data, size, h, face, is_texnumber, take_texnumber, out);
    *numbers = out;
    return SAM_OK;
}

static void put_u32(sam_text *out, uint32_t v)
{
    const char b[4] = {(char)(v & 0xff), (char)(v >> 8 & 0xff), (char)(v >> 16 & 0xff), (char)(v >> 24 & 0xff)};
    sam_text_append(out, b, 4);
}

static void put_float(sam_text *out, double v)
{
    const float f = (float)v;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put_u32(out, u);
}

static void put_line(sam_text *out, const char *s)
{
    sam_text_append(out, s, strlen(s));
}

sam_status sam_mesh_ply_rewrite(const char *path, const char *data, size_t size, const sam_mesh_ply_header *h,
                                sam_text *out, float **corner_uvs, uint32_t *corner_uv_count, sam_error *err)
{
    *corner_uvs = NULL;
    *corner_uv_count = 0;
    const sam_mesh_ply_element *vertex = NULL, *face = NULL;
    int normals = 0, uvs = 0;
    for (int e = 0; e < h->element_count && !face; ++e) {
        const sam_mesh_ply_element *el = &h->element[e];
        if (!strcmp(el->name, "vertex")) {
            vertex = el;
            for (int k = 0; k < el->property_count; ++k) {
                const int role = el->property[k].is_list ? -1 : vertex_role(el->property[k].name);
                normals |= role >= 3 && role <= 5;
                uvs |= role >= 6;
            }
        } else if (!strcmp(el->name, "face")) {
            face = el;
        }
    }
    char line[96];
    put_line(out, "ply\nformat binary_little_endian 1.0\n");
    snprintf(line, sizeof line, "element vertex %llu\n", vertex ? vertex->count : 0ull);
    put_line(out, line);
    put_line(out, "property float x\nproperty float y\nproperty float z\n");
    if (normals)
        put_line(out, "property float nx\nproperty float ny\nproperty float nz\n");
    if (uvs)
        put_line(out, "property float u\nproperty float v\n");
    snprintf(line, sizeof line, "element face %llu\n", face ? face->count : 0ull);
    put_line(out, line);
    put_line(out, "property list int int vertex_indices\nend_header\n");

    /* Per-corner texture coordinates, gathered while every face has them. */
    float *uv = NULL;
    size_t uv_len = 0, uv_cap = 0;
    int uv_ok = face && face->count > 0;
    ply_cursor c = {data + h->body, data + size, h->format};
    for (int e = 0; e < h->element_count; ++e) {
        const sam_mesh_ply_element *el = &h->element[e];
        for (unsigned long long i = 0; i < el->count; ++i) {
            double v[8] = {0, 0, 0, 0, 0, 0, 0, 0};
            uint32_t corners = 0, texcoords = 0; /* counts of at most 4 bytes, never negative (the walk) */
            for (int k = 0; k < el->property_count; ++k) {
                const sam_mesh_ply_property *pr = &el->property[k];
                if (!pr->is_list) {
                    const double x = read_value(&c, pr->value_type);
                    const int role = el == vertex ? vertex_role(pr->name) : -1;
                    if (role >= 0)
                        v[role] = x;
                    continue;
                }
                const double n = read_value(&c, pr->count_type);
                const int is_corners = el == face && k == 0;
                const int is_uv = el == face && !strcmp(pr->name, "texcoord");
                if (is_corners) {
                    corners = (uint32_t)n;
                    put_u32(out, corners);
                } else if (is_uv) {
                    texcoords = (uint32_t)n;
                }
                for (double j = 0; j < n; ++j) {
                    const double x = read_value(&c, pr->value_type);
                    if (is_corners) {
                        if (!(x >= 0 && x <= 2147483647.0 && x == floor(x))) {
                            free(uv);
                            return sam_fail(err, SAM_ERR_FORMAT,
                                            "%s: PLY face %llu: corner %.0f is %g, which is no vertex index", path,
                                            i, j, x);
                        }
                        put_u32(out, (uint32_t)x);
                    } else if (is_uv && uv_ok) {
                        if (uv_len == uv_cap) {
                            const size_t cap = uv_cap ? 2 * uv_cap : 1024;
                            float *grown = realloc(uv, cap * sizeof *uv);
                            if (!grown) {
                                free(uv);
                                return sam_fail(err, SAM_ERR_OUT_OF_MEMORY,
                                                "%s: out of memory for the faces' texture coordinates", path);
                            }
                            uv = grown, uv_cap = cap;
                        }
                        /* MeshLab's v runs up, as OBJ's does. */
                        uv[uv_len++] = (float)x;
                    }
                }
            }
            if (el == vertex) {
                for (int r = 0; r < 3 + 3 * normals; ++r)
                    put_float(out, v[r]);
                if (uvs)
                    put_float(out, v[6]), put_float(out, v[7]);
            } else if (el == face && texcoords != 2ull * corners) {
                uv_ok = 0;
            }
        }
        if (el == face)
            break;
    }
    if (uv_ok && uv_len <= 2ull * UINT32_MAX) {
        *corner_uvs = uv;
        *corner_uv_count = (uint32_t)(uv_len / 2);
    } else {
        free(uv);
    }
    return SAM_OK;
}
