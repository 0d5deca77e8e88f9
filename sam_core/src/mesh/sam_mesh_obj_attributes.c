/* An OBJ's vertex colours and faces' materials, gathered while the
 * pre-check reads its lines (sam_mesh_soup.h, sam_mesh_preflight.c's
 * walk_obj) into sam_mesh_expect.vertex_colors, material_names and
 * face_materials: OpenMesh's importer keeps neither. */
#include <stdlib.h>
#include <string.h>

#include "sam_mesh_soup.h"

int sam_mesh_obj_gather_color(sam_mesh_expect *e, sam_mesh_obj_colors *c, uint64_t v, const float *rgb)
{
    if (!c->ok)
        return 1;
    if (!rgb) {
        c->ok = 0;
        return 1;
    }
    if (3 * (v + 1) > c->cap) {
        const size_t cap = c->cap ? 2 * c->cap : 3 * 1024;
        float *grown = realloc(e->vertex_colors, cap * sizeof *grown);
        if (!grown)
            return 0;
        e->vertex_colors = grown, c->cap = cap;
    }
    for (int k = 0; k < 3; ++k) {
        e->vertex_colors[3 * v + (unsigned)k] = rgb[k];
        c->max = rgb[k] > c->max ? rgb[k] : c->max;
    }
    return 1;
}

void sam_mesh_obj_colors_finish(sam_mesh_expect *e, const sam_mesh_obj_colors *c, uint64_t vertices)
{
    if (!c->ok || !vertices) {
        free(e->vertex_colors);
        e->vertex_colors = NULL;
        return;
    }
    /* Values past 1.5 mean the file wrote bytes; a float a hair past 1 is
     * clamped. */
    const float scale = c->max > 1.5f ? 1.0f / 255.0f : 1.0f;
    for (size_t i = 0; i < 3 * vertices; ++i) {
        const float x = e->vertex_colors[i] * scale;
        e->vertex_colors[i] = x > 1.0f ? 1.0f : x > 0.0f ? x : 0.0f;
    }
}

int sam_mesh_obj_use_material(sam_mesh_expect *e, sam_mesh_obj_materials *m, const char *name, const char *eol)
{
    const char *end = eol;
    for (const char *p = name + 1; p < eol; ++p)
        if (*p == '#' && (p[-1] == ' ' || p[-1] == '\t')) {
            end = p;
            break;
        }
    while (end > name && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\r'))
        --end;
    const size_t len = (size_t)(end - name);
    for (uint32_t i = 0; i < e->material_count; ++i)
        if (strlen(e->material_names[i]) == len && !memcmp(e->material_names[i], name, len)) {
            m->current = i;
            return 1;
        }
    m->current = SAM_MESH_NO_MATERIAL;
    if (e->material_count == SAM_MESH_MAX_MATERIALS)
        return 1;
    char **grown = realloc(e->material_names, (e->material_count + 1) * sizeof *grown);
    if (!grown)
        return 0;
    e->material_names = grown;
    if (!(grown[e->material_count] = malloc(len + 1)))
        return 0;
    memcpy(grown[e->material_count], name, len);
    grown[e->material_count][len] = '\0';
    m->current = e->material_count++;
    return 1;
}

int sam_mesh_obj_face_material(sam_mesh_expect *e, sam_mesh_obj_materials *m, uint64_t face)
{
    if (!e->material_count)
        return 1;
    if (face >= m->face_cap) {
        const size_t old = m->face_cap, cap = old ? 2 * old : 1024;
        uint32_t *grown = realloc(e->face_materials, cap * sizeof *grown);
        if (!grown)
            return 0;
        for (size_t f = old; f < cap; ++f)
            grown[f] = SAM_MESH_NO_MATERIAL;
        e->face_materials = grown, m->face_cap = cap;
    }
    e->face_materials[face] = m->current;
    return 1;
}
