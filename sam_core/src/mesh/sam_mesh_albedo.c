/* A mesh file's own albedo texture (sam_mesh_load_albedo in sam_mesh.h):
 * an OBJ's material's map_Kd from its .mtl, or a glTF's base colour. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_mesh.h"
#include "sam_mesh_soup.h"

/* Copies the line's argument after `keyword` (with its leading blanks and
 * trailing blanks and line end removed) into out; 0 when the line is not
 * that keyword. map_Kd's options (-s 1 1 1 ...) come before the file name,
 * which is the last word. */
static int keyword_value(const char *line, const char *keyword, int last_word, char *out, size_t n)
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
    while (len && isspace((unsigned char)v[len - 1]))
        --len;
    if (last_word)
        for (size_t i = len; i-- > 0;)
            if (v[i] == ' ' || v[i] == '\t') {
                v += i + 1;
                len -= i + 1;
                break;
            }
    if (!len || len >= n)
        return 0;
    memcpy(out, v, len);
    out[len] = '\0';
    return 1;
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

/* The texture an OBJ's first used material names (map_Kd), into `texture`;
 * "" with a note when there is none to read. */
static sam_status obj_texture(const char *path, char *texture, size_t n, char *note, size_t note_size,
                              sam_error *err)
{
    texture[0] = '\0';
    uint8_t *text;
    size_t size;
    sam_status st = sam_read_file(path, &text, &size, err);
    if (st != SAM_OK)
        return st;
    char mtllib[512] = "", material[512] = "", line_value[512];
    for (const char *line = (const char *)text; line && line < (const char *)text + size;) {
        if (!mtllib[0] && keyword_value(line, "mtllib", 0, line_value, sizeof line_value))
            snprintf(mtllib, sizeof mtllib, "%s", line_value);
        if (!material[0] && keyword_value(line, "usemtl", 0, line_value, sizeof line_value))
            snprintf(material, sizeof material, "%s", line_value);
        const char *next = memchr(line, '\n', (size_t)((const char *)text + size - line));
        line = next ? next + 1 : NULL;
    }
    free(text);
    if (!mtllib[0])
        return SAM_OK;
    char mtl[1024];
    beside_file(path, mtllib, mtl, sizeof mtl);
    if (sam_read_file(mtl, &text, &size, NULL) != SAM_OK) {
        snprintf(note, note_size, "%s names the material library %s, which cannot be read", path, mtl);
        return SAM_OK;
    }
    /* The first map_Kd of the material the OBJ uses first (any material's
     * when it uses none by name). */
    int inside = !material[0];
    char map[512] = "";
    for (const char *line = (const char *)text; line && line < (const char *)text + size && !map[0];) {
        if (keyword_value(line, "newmtl", 0, line_value, sizeof line_value))
            inside = !material[0] || strcmp(line_value, material) == 0;
        else if (inside && keyword_value(line, "map_Kd", 1, line_value, sizeof line_value))
            snprintf(map, sizeof map, "%s", line_value);
        const char *next = memchr(line, '\n', (size_t)((const char *)text + size - line));
        line = next ? next + 1 : NULL;
    }
    free(text);
    if (map[0])
        beside_file(mtl, map, texture, n);
    return SAM_OK;
}

sam_status sam_mesh_load_albedo(const char *path, sam_image *image, char *note, size_t note_size, sam_error *err)
{
    if (!path || !image || !note || !note_size)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "mesh albedo: NULL argument");
    memset(image, 0, sizeof *image);
    note[0] = '\0';
    if (sam_path_has_extension(path, ".gltf") || sam_path_has_extension(path, ".glb")) {
        float factor[4];
        sam_error gltf_err;
        sam_status st = sam_mesh_gltf_base_color(path, image, factor, &gltf_err);
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
            snprintf(note, note_size, "the base colour texture of %s", path);
        return SAM_OK;
    }
    if (!sam_path_has_extension(path, ".obj"))
        return SAM_OK;
    char texture[1024];
    sam_status st = obj_texture(path, texture, sizeof texture, note, note_size, err);
    if (st != SAM_OK || !texture[0])
        return st;
    sam_error read_err;
    if (sam_image_read_picture(texture, image, SAM_PNG_SRGB, &read_err) != SAM_OK)
        snprintf(note, note_size, "%s: the texture it names cannot be used: %s", path, read_err.message);
    else
        snprintf(note, note_size, "%s (map_Kd of %s)", texture, path);
    return SAM_OK;
}
