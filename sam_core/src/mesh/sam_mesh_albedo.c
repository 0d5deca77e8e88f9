/* A mesh file's own albedo texture (sam_mesh_load_albedo in sam_mesh.h):
 * an OBJ's material's map_Kd from its .mtl, a PLY's TextureFile comment, or
 * a glTF's base colour. */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_mesh.h"
#include "sam_mesh_soup.h"

/* Copies the line's argument after `keyword` (with its leading blanks,
 * trailing blanks and line end removed, and with `comments` a comment after
 * it, a '#' after a blank, as OBJ and MTL have them) into out; 0 when the
 * line is not that keyword. */
static int keyword_value(const char *line, const char *keyword, int comments, char *out, size_t n)
{
    const size_t k = strlen(keyword);
    while (*line == ' ' || *line == '\t')
        ++line;
    if (strncmp(line, keyword, k) != 0 || (line[k] != ' ' && line[k] != '\t'))
        return 0;
    const char *v = line + k;
    while (*v == ' ' || *v == '\t')
        ++v;
    size_t len = strcspn(v, "\r\n");
    for (size_t i = 1; comments && i < len; ++i)
        if (v[i] == '#' && (v[i - 1] == ' ' || v[i - 1] == '\t')) {
            len = i;
            break;
        }
    while (len && isspace((unsigned char)v[len - 1]))
        --len;
    if (!len || len >= n)
        return 0;
    memcpy(out, v, len);
    out[len] = '\0';
    return 1;
}

/* Steps past one blank-separated word of s and the blanks after it. */
static const char *next_word(const char *s)
{
    s += strcspn(s, " \t");
    return s + strspn(s, " \t");
}

/* Whether the word at s is a number (an option's argument, not a file). */
static int is_number_word(const char *s)
{
    char *end;
    (void)strtod(s, &end);
    return end != s && (*end == '\0' || *end == ' ' || *end == '\t');
}

/* The file name in a map statement's argument: what follows its options
 * (MTL spec: -s 1 1 1, -bm 0.2, -mm base gain...). The name is the rest of
 * the line, so a file name with blanks in it survives. */
static const char *map_file_name(const char *value)
{
    static const struct {
        const char *name;
        int min, max; /* arguments */
    } options[] = {{"-blendu", 1, 1}, {"-blendv", 1, 1}, {"-boost", 1, 1},  {"-mm", 2, 2},    {"-o", 1, 3},
                   {"-s", 1, 3},      {"-t", 1, 3},      {"-texres", 1, 1}, {"-clamp", 1, 1}, {"-bm", 1, 1},
                   {"-imfchan", 1, 1}, {"-type", 1, 1},  {"-cc", 1, 1}};
    for (;;) {
        size_t i = 0, word = strcspn(value, " \t");
        while (i < sizeof options / sizeof options[0] &&
               (strlen(options[i].name) != word || strncmp(value, options[i].name, word) != 0))
            ++i;
        if (i == sizeof options / sizeof options[0] || !value[word])
            return value;
        value = next_word(value);
        /* Optional numeric arguments stop at the first word that is not a
         * number: that one is the next option or the file. */
        for (int a = 0; a < options[i].max && *value && (a < options[i].min || is_number_word(value)); ++a)
            value = next_word(value);
    }
}

/* `name` relative to the folder of `beside`, into out. */
static void beside_file(const char *beside, const char *name, char *out, size_t n)
{
    const char *slash = strrchr(beside, '/');
    if (name[0] == '/' || !slash)
        snprintf(out, n, "%s", name);
    else
        snprintf(out, n, "%.*s/%s", (int)(slash - beside), beside, name);
}

/* The materials an OBJ's usemtl lines name, each once, in first-use order,
 * and the first map_Kd of each (its MTL's). Past MATERIALS_COUNTED names
 * the rest go uncounted: the count only tells a user that textures were
 * left out. Names are told apart by a hash first: an OBJ may switch
 * material at every face. */
enum { MATERIALS_COUNTED = 256 };
typedef struct obj_materials {
    char name[MATERIALS_COUNTED][512];
    char map[MATERIALS_COUNTED][512];
    uint32_t hash[MATERIALS_COUNTED];
    size_t count;
} obj_materials;

static uint32_t name_hash(const char *s)
{
    uint32_t h = 2166136261u; /* FNV-1a */
    for (; *s; ++s)
        h = (h ^ (uint8_t)*s) * 16777619u;
    return h;
}

static void material_add(obj_materials *m, const char *name)
{
    const uint32_t h = name_hash(name);
    for (size_t i = 0; i < m->count; ++i)
        if (m->hash[i] == h && !strcmp(m->name[i], name))
            return;
    if (m->count < MATERIALS_COUNTED) {
        m->hash[m->count] = h;
        snprintf(m->name[m->count++], sizeof m->name[0], "%s", name);
    }
}

/* Reads the OBJ at `path` for its first mtllib, into `mtl` (the library's
 * path, beside the OBJ; "" when it names none), and with `used` (may be
 * NULL) its usemtl names. */
static sam_status obj_library(const char *path, char *mtl, size_t n, obj_materials *used, sam_error *err)
{
    mtl[0] = '\0';
    uint8_t *text;
    size_t size;
    sam_status st = sam_read_file(path, &text, &size, err);
    if (st != SAM_OK)
        return st;
    char mtllib[512] = "", line_value[512];
    for (const char *line = (const char *)text; line && line < (const char *)text + size;) {
        if (!mtllib[0] && keyword_value(line, "mtllib", 1, line_value, sizeof line_value))
            snprintf(mtllib, sizeof mtllib, "%s", line_value);
        if (used && keyword_value(line, "usemtl", 1, line_value, sizeof line_value))
            material_add(used, line_value);
        const char *next = memchr(line, '\n', (size_t)((const char *)text + size - line));
        line = next ? next + 1 : NULL;
    }
    free(text);
    if (mtllib[0])
        beside_file(path, mtllib, mtl, n);
    return SAM_OK;
}

/* The first map_Kd of each of `used`'s materials in the library `mtl`
 * (of any material when `used` names none: into map[0]); 0 when the
 * library cannot be read. */
static int mtl_maps(const char *mtl, obj_materials *used)
{
    uint8_t *text;
    size_t size;
    if (sam_read_file(mtl, &text, &size, NULL) != SAM_OK)
        return 0;
    char line_value[512];
    size_t at = used->count ? SIZE_MAX : 0;
    for (const char *line = (const char *)text; line && line < (const char *)text + size;) {
        if (keyword_value(line, "newmtl", 1, line_value, sizeof line_value)) {
            if (used->count) {
                const uint32_t h = name_hash(line_value);
                at = SIZE_MAX;
                for (size_t i = 0; i < used->count && at == SIZE_MAX; ++i)
                    at = used->hash[i] == h && !strcmp(used->name[i], line_value) ? i : SIZE_MAX;
            }
        } else if (at != SIZE_MAX && !used->map[at][0] &&
                   keyword_value(line, "map_Kd", 1, line_value, sizeof line_value)) {
            snprintf(used->map[at], sizeof used->map[0], "%s", map_file_name(line_value));
        }
        const char *next = memchr(line, '\n', (size_t)((const char *)text + size - line));
        line = next ? next + 1 : NULL;
    }
    free(text);
    return 1;
}

/* The texture (map_Kd) of the first material an OBJ uses that names one,
 * into `texture`, and in *others how many other textures its other used
 * materials name; "" with a note when there is none to read. A colour-only
 * material often comes first (an exporter's default). */
static sam_status obj_texture(const char *path, char *texture, size_t n, uint32_t *others, char *note,
                              size_t note_size, sam_error *err)
{
    texture[0] = '\0';
    *others = 0;
    obj_materials *used = calloc(1, sizeof *used);
    if (!used)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    char mtl[1024];
    sam_status st = obj_library(path, mtl, sizeof mtl, used, err);
    if (st != SAM_OK || !mtl[0] || !mtl_maps(mtl, used)) {
        if (st == SAM_OK && mtl[0])
            snprintf(note, note_size, "%s names the material library %s, which cannot be read", path, mtl);
        free(used);
        return st;
    }
    const size_t materials = used->count ? used->count : 1;
    size_t first = 0;
    while (first < materials && !used->map[first][0])
        ++first;
    if (first < materials)
        beside_file(mtl, used->map[first], texture, n);
    for (size_t i = first + 1; i < materials; ++i) {
        int seen = !used->map[i][0] || !strcmp(used->map[i], used->map[first]);
        for (size_t j = first + 1; j < i && !seen; ++j)
            seen = !strcmp(used->map[i], used->map[j]);
        *others += (uint32_t)!seen;
    }
    free(used);
    return SAM_OK;
}

/* The textures a PLY's header names as MeshLab and Metashape write them
 * ("comment TextureFile NAME", in order: a face's texnumber counts them),
 * at most `max` paths of `n` bytes into `textures` (beside the PLY), their
 * count into *count. Only the header is read: a scan's body may be large. */
static sam_status ply_textures(const char *path, char *textures, size_t n, size_t max, size_t *count, sam_error *err)
{
    *count = 0;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return sam_fail(err, SAM_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    enum { HEADER_BYTES = 65536 };
    char *head = malloc(HEADER_BYTES + 1);
    if (!head) {
        fclose(fp);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    const size_t size = fread(head, 1, HEADER_BYTES, fp);
    fclose(fp);
    head[size] = '\0';
    char comment[512], name[512];
    for (const char *line = head; line && line < head + size && *count < max;) {
        if (!strncmp(line, "end_header", 10))
            break;
        if (keyword_value(line, "comment", 0, comment, sizeof comment) &&
            keyword_value(comment, "TextureFile", 0, name, sizeof name))
            beside_file(path, name, textures + n * (*count)++, n);
        const char *next = memchr(line, '\n', (size_t)(head + size - line));
        line = next ? next + 1 : NULL;
    }
    free(head);
    return SAM_OK;
}

/* The first texture a PLY's header names, into `texture`; "" when none. */
static sam_status ply_texture(const char *path, char *texture, size_t n, sam_error *err)
{
    size_t count;
    texture[0] = '\0';
    return ply_textures(path, texture, n, 1, &count, err);
}

/* What a note adds, after `lead`, when a file's materials name `others`
 * more textures: one map is all the runtime reads, at every part's UVs. */
static const char *others_note(uint32_t others, const char *lead, char *buf, size_t n)
{
    if (!others)
        return "";
    snprintf(buf, n, "%s%u other texture%s of its materials not read: their parts show this one at their UVs", lead,
             others, others == 1 ? "" : "s");
    return buf;
}

sam_status sam_mesh_load_albedo(const char *path, sam_image *image, char *note, size_t note_size, sam_error *err)
{
    char buf[128];
    if (!path || !image || !note || !note_size)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "mesh albedo: NULL argument");
    memset(image, 0, sizeof *image);
    note[0] = '\0';
    if (sam_path_has_extension(path, ".gltf") || sam_path_has_extension(path, ".glb")) {
        float factor[4];
        uint32_t others;
        sam_error gltf_err;
        sam_status st = sam_mesh_gltf_base_color(path, image, factor, &others, &gltf_err);
        if (st == SAM_ERR_UNSUPPORTED || st == SAM_ERR_FORMAT) {
            snprintf(note, note_size, "%s", gltf_err.message);
            return SAM_OK;
        }
        if (st != SAM_OK)
            return sam_fail(err, st, "%s", gltf_err.message);
        for (size_t i = 0; image->pixels && i < (size_t)image->width * image->height; ++i)
            for (uint32_t c = 0; c < 3; ++c)
                image->pixels[i * image->channels + c] *= factor[c];
        if (image->pixels)
            snprintf(note, note_size, "the base colour texture of %s%s%s", path, others_note(others, " (", buf, sizeof buf),
                     others ? ")" : "");
        return SAM_OK;
    }
    const int obj = sam_path_has_extension(path, ".obj"), ply = sam_path_has_extension(path, ".ply");
    if (!obj && !ply)
        return SAM_OK;
    char texture[1024];
    uint32_t others = 0;
    sam_status st = obj ? obj_texture(path, texture, sizeof texture, &others, note, note_size, err)
                        : ply_texture(path, texture, sizeof texture, err);
    if (st != SAM_OK || !texture[0])
        return st;
    sam_error read_err;
    if (sam_image_read_picture(texture, image, SAM_PNG_SRGB, &read_err) != SAM_OK)
        snprintf(note, note_size, "%s: the texture it names cannot be used: %s", path, read_err.message);
    else
        snprintf(note, note_size, "%s (%s of %s%s)", texture, obj ? "map_Kd" : "TextureFile", path,
                 others_note(others, "; ", buf, sizeof buf));
    return SAM_OK;
}

void sam_albedo_maps_destroy(sam_albedo_maps *maps)
{
    if (!maps)
        return;
    for (uint32_t m = 0; m < maps->map_count; ++m)
        sam_image_destroy(&maps->maps[m]);
    free(maps->maps);
    free(maps->face_map);
    memset(maps, 0, sizeof *maps);
}

/* Fills maps->face_map from each face's material and each material's map
 * (SAM_ALBEDO_NO_MAP for either missing); 1 when the faces read more than
 * one map, or some read one and some none: one map at every face is
 * sam_mesh_load_albedo's. */
static int assign_faces(sam_albedo_maps *maps, const uint32_t *face_material, uint32_t material_count,
                        const uint32_t *material_map)
{
    int several = 0;
    for (uint32_t f = 0; f < maps->face_count; ++f) {
        const uint32_t m = face_material[f];
        maps->face_map[f] = m < material_count ? material_map[m] : SAM_ALBEDO_NO_MAP;
        several |= f > 0 && maps->face_map[f] != maps->face_map[0];
    }
    return several;
}

/* Bytes of each path in the lists of texture files below. */
enum { PATH_BYTES = 1024 };

/* The maps of `count` materials whose texture files are `files` (PATH_BYTES
 * apart; "" for none): a map per distinct file, each of the `face_count`
 * faces' by its material (`face_material`), the files decoded when the
 * faces read more than one; otherwise `maps` is left empty. A file that
 * cannot be read leaves its faces white, and the first says why in `note`,
 * naming its material (`names`, or its number when NULL). */
static sam_status maps_from_files(const char *path, const char *files, uint32_t count, const char *const *names,
                                  const uint32_t *face_material, uint32_t face_count, sam_albedo_maps *maps,
                                  char *note, size_t note_size, sam_error *err)
{
    uint32_t *material_map = calloc(count ? count : 1, sizeof *material_map);
    maps->face_count = face_count;
    maps->face_map = malloc(((size_t)face_count + 1) * sizeof *maps->face_map);
    maps->maps = calloc(count ? count : 1, sizeof *maps->maps);
    sam_status st = material_map && maps->face_map && maps->maps
                        ? SAM_OK
                        : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %u materials", path, count);
    int several = 0;
    if (st == SAM_OK) {
        for (uint32_t m = 0; m < count; ++m) {
            const char *file = files + (size_t)m * PATH_BYTES;
            material_map[m] = file[0] ? maps->map_count : SAM_ALBEDO_NO_MAP;
            for (uint32_t k = 0; k < m && file[0] && material_map[m] == maps->map_count; ++k)
                if (!strcmp(files + (size_t)k * PATH_BYTES, file))
                    material_map[m] = material_map[k];
            maps->map_count += file[0] && material_map[m] == maps->map_count;
        }
        several = assign_faces(maps, face_material, count, material_map);
    }
    /* Decoded only when they are needed: one map is sam_mesh_load_albedo's. */
    for (uint32_t m = 0; st == SAM_OK && several && m < count; ++m) {
        sam_image *map = material_map[m] == SAM_ALBEDO_NO_MAP ? NULL : &maps->maps[material_map[m]];
        if (!map || map->pixels)
            continue;
        sam_error why;
        const sam_status read = sam_image_read_picture(files + (size_t)m * PATH_BYTES, map, SAM_PNG_SRGB, &why);
        if (read == SAM_ERR_OUT_OF_MEMORY)
            st = sam_fail(err, read, "%s", why.message);
        else if (read != SAM_OK && !note[0] && names)
            snprintf(note, note_size, "%s: the texture of material %s cannot be used: %s", path, names[m],
                     why.message);
        else if (read != SAM_OK && !note[0])
            snprintf(note, note_size, "%s: its texture %u cannot be used: %s", path, m, why.message);
    }
    if (st != SAM_OK || !several)
        sam_albedo_maps_destroy(maps);
    free(material_map);
    return st;
}

/* An OBJ's materials' map_Kd textures, each distinct file once. */
static sam_status obj_maps(const char *path, sam_albedo_maps *maps, char *note, size_t note_size, sam_error *err)
{
    sam_mesh_expect expect;
    sam_status st = sam_mesh_preflight(path, &expect, err);
    if (st != SAM_OK || !expect.face_materials) {
        sam_mesh_expect_free(&expect);
        return st;
    }
    obj_materials *used = calloc(1, sizeof *used);
    char *files = calloc(expect.material_count, PATH_BYTES);
    char mtl[1024] = "";
    if (!used || !files)
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %u materials", path, expect.material_count);
    /* The preflight's names, in its order: used->map[i] is material i's. */
    for (uint32_t m = 0; st == SAM_OK && m < expect.material_count && m < MATERIALS_COUNTED; ++m) {
        snprintf(used->name[m], sizeof used->name[0], "%s", expect.material_names[m]);
        used->hash[m] = name_hash(used->name[m]);
        used->count = m + 1;
    }
    if (st == SAM_OK)
        st = obj_library(path, mtl, sizeof mtl, NULL, err);
    if (st == SAM_OK && mtl[0] && mtl_maps(mtl, used)) {
        for (size_t m = 0; m < used->count; ++m)
            if (used->map[m][0])
                beside_file(mtl, used->map[m], files + m * PATH_BYTES, PATH_BYTES);
        st = maps_from_files(path, files, expect.material_count, (const char *const *)expect.material_names,
                             expect.face_materials, (uint32_t)expect.faces, maps, note, note_size, err);
    }
    if (st == SAM_OK && maps->map_count && expect.material_count > MATERIALS_COUNTED && !note[0])
        snprintf(note, note_size, "%s: %u materials; those past the first %d read no texture", path,
                 expect.material_count, MATERIALS_COUNTED);
    free(used);
    free(files);
    sam_mesh_expect_free(&expect);
    return st;
}

/* A glTF's materials' base colours, one map per used material. */
static sam_status gltf_maps(const char *path, sam_albedo_maps *maps, char *note, size_t note_size, sam_error *err)
{
    sam_mesh_soup soup;
    sam_status st = sam_mesh_gltf_read(path, &soup, err);
    if (st != SAM_OK || !soup.face_materials) {
        sam_mesh_soup_free(&soup);
        return st;
    }
    int several = 0;
    for (uint32_t f = 1; f < soup.face_count; ++f)
        several |= soup.face_materials[f] != soup.face_materials[0];
    sam_image *colors = NULL;
    uint32_t count = 0;
    if (several) {
        /* Images TinyGLTF cannot decode make the whole read fail: a note,
         * as sam_mesh_load_albedo makes it, and no maps. */
        sam_error why;
        st = sam_mesh_gltf_base_colors(path, &colors, &count, note, note_size, &why);
        if (st == SAM_ERR_FORMAT || st == SAM_ERR_UNSUPPORTED) {
            snprintf(note, note_size, "%s", why.message);
            several = 0, st = SAM_OK;
        } else if (st != SAM_OK) {
            sam_fail(err, st, "%s", why.message);
        }
    }
    uint32_t *material_map = several && st == SAM_OK ? malloc((count ? count : 1) * sizeof *material_map) : NULL;
    if (several && st == SAM_OK) {
        maps->face_count = soup.face_count;
        maps->face_map = malloc((size_t)soup.face_count * sizeof *maps->face_map);
        maps->maps = calloc(count ? count : 1, sizeof *maps->maps);
        if (!material_map || !maps->face_map || !maps->maps)
            st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %u materials", path, count);
    }
    if (several && st == SAM_OK) {
        /* Each used material with a usable colour its own map, taken over. */
        for (uint32_t m = 0; m < count; ++m)
            material_map[m] = SAM_ALBEDO_NO_MAP;
        for (uint32_t f = 0; f < soup.face_count; ++f)
            if (soup.face_materials[f] < count)
                material_map[soup.face_materials[f]] = 0;
        for (uint32_t m = 0; m < count; ++m) {
            const int used = material_map[m] == 0;
            material_map[m] = used && colors[m].pixels ? maps->map_count : SAM_ALBEDO_NO_MAP;
            if (used && colors[m].pixels) {
                maps->maps[maps->map_count++] = colors[m];
                memset(&colors[m], 0, sizeof colors[m]);
            }
        }
        several = assign_faces(maps, soup.face_materials, count, material_map);
    }
    for (uint32_t m = 0; m < count; ++m)
        sam_image_destroy(&colors[m]);
    free(colors);
    free(material_map);
    if (st != SAM_OK || !several)
        sam_albedo_maps_destroy(maps);
    sam_mesh_soup_free(&soup);
    return st;
}

/* A PLY's TextureFile textures, each face's by its texnumber (MeshLab's
 * and Metashape's several texture pages), each distinct file once. */
static sam_status ply_maps(const char *path, sam_albedo_maps *maps, char *note, size_t note_size, sam_error *err)
{
    enum { PLY_TEXTURES = 256 };
    sam_mesh_expect expect;
    sam_status st = sam_mesh_preflight(path, &expect, err);
    char *files = NULL;
    size_t count = 0;
    if (st == SAM_OK && expect.face_materials) {
        files = calloc(PLY_TEXTURES, PATH_BYTES);
        st = files ? ply_textures(path, files, PATH_BYTES, PLY_TEXTURES, &count, err)
                   : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for its textures", path);
    }
    if (st == SAM_OK && count)
        st = maps_from_files(path, files, (uint32_t)count, NULL, expect.face_materials, (uint32_t)expect.faces, maps,
                             note, note_size, err);
    free(files);
    sam_mesh_expect_free(&expect);
    return st;
}

sam_status sam_mesh_load_albedo_maps(const char *path, sam_albedo_maps *maps, char *note, size_t note_size,
                                     sam_error *err)
{
    if (!path || !maps || !note || !note_size)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "mesh albedo maps: NULL argument");
    memset(maps, 0, sizeof *maps);
    note[0] = '\0';
    sam_status st = sam_check_regular_file(path, err);
    if (st != SAM_OK)
        return st;
    if (sam_path_has_extension(path, ".gltf") || sam_path_has_extension(path, ".glb"))
        return gltf_maps(path, maps, note, note_size, err);
    if (sam_path_has_extension(path, ".obj"))
        return obj_maps(path, maps, note, note_size, err);
    if (sam_path_has_extension(path, ".ply"))
        return ply_maps(path, maps, note, note_size, err);
    return SAM_OK;
}
