/* Why a map leaves most of its vertices without light, or an object too
 * small for its material gets none (sam_build.h). */
#include <stdio.h>
#include <string.h>

#include "sam/sam_build.h"

/* Whether vertex v's one-ring is open: a closed fan repeats its first
 * neighbour at the end (sam_mesh.h), and the .sam keeps the rings so. */
static int ring_open(const samfile_data *map, uint32_t v)
{
    const uint32_t first = map->adjacency_offsets[v], end = map->adjacency_offsets[v + 1];
    return end - first < 2 || map->adjacency[first] != map->adjacency[end - 1];
}

/* The map's render mesh as a sam_mesh without topology: enough for the
 * mesh helpers that read only positions and triangles. */
static sam_mesh triangle_view(const samfile_data *map)
{
    sam_mesh m;
    memset(&m, 0, sizeof m);
    m.vertex_count = map->vertex_count;
    m.positions = map->positions;
    m.triangle_count = map->triangle_count;
    m.triangles = map->triangles;
    return m;
}

int sam_build_explain_empty(const samfile_data *map, float mm_per_unit, float reach_mm, const char *name, char *buf,
                            size_t n)
{
    if (n)
        buf[0] = '\0';
    if (!map || !map->vertex_count || !map->sample_index || !map->adjacency_offsets || !buf || !n)
        return 0;
    uint32_t empty = 0, open = 0;
    for (uint32_t v = 0; v < map->vertex_count; ++v) {
        empty += map->sample_index[(size_t)v * map->samples_per_vertex] == SAMFILE_NO_SAMPLE;
        open += (uint32_t)ring_open(map, v);
    }
    if (2 * (uint64_t)empty < map->vertex_count)
        return 0;
    const char *what = name ? name : "the mesh";
    int used = snprintf(buf, n,
                        "%.0f%% of the vertices (%u of %u) have no back side within the material's reach (%.3g mm), "
                        "so they get no translucency.",
                        100.0 * empty / map->vertex_count, empty, map->vertex_count, (double)reach_mm);
    if (open && used >= 0 && (size_t)used < n)
        used += snprintf(buf + used, n - (size_t)used,
                         " %s is open (%u vertices on its boundary): if it is a single sheet, a leaf or a cloth "
                         "card, it has no back side for light to come through, and needs thickness (two faces "
                         "and a rim: sam_solidify gives it that).",
                         what, open);
    const sam_mesh view = triangle_view(map);
    if (!open && sam_mesh_signed_volume(&view) < 0) {
        if (used >= 0 && (size_t)used < n)
            snprintf(buf + used, n - (size_t)used,
                     " %s is closed and faces inward (negative volume): what lies behind its vertices is outside "
                     "it. Turn it outside out (sam_build does unless given --keep-orientation).",
                     what);
        return 1;
    }
    if (used >= 0 && (size_t)used < n)
        snprintf(buf + used, n - (size_t)used,
                 " %s thicker than this light crosses at %.4g mm across: if its units are not %.4g mm, give its "
                 "scale (--mm-per-unit or --size-mm; a scene's \"scale\").",
                 open ? "If it is a solid, it is" : "It is closed, a solid", sam_mesh_diagonal(&view) * mm_per_unit,
                 (double)mm_per_unit);
    return 1;
}

int sam_build_explain_small(const samfile_data *map, float mm_per_unit, float near_mm, const char *name, char *buf,
                            size_t n)
{
    if (n)
        buf[0] = '\0';
    if (!map || !map->vertex_count || !map->positions || !buf || !n)
        return 0;
    const sam_mesh view = triangle_view(map);
    const double size_mm = sam_mesh_diagonal(&view) * mm_per_unit;
    if (!(size_mm < near_mm))
        return 0;
    snprintf(buf, n,
             "%s is %.3g mm across, and the material spreads 99%% of the light it takes in farther than %.3g mm: "
             "it gets next to no translucency. If its units are not %.4g mm, give its scale (--mm-per-unit or "
             "--size-mm; a scene's \"scale\").",
             name ? name : "the mesh", size_mm, (double)near_mm, (double)mm_per_unit);
    return 1;
}
