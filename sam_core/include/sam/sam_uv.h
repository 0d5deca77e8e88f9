/*
 * sam_uv: checks that a mesh's UV atlas can carry texture-space diffusion.
 *
 * Texture-space subsurface diffusion (d'Eon et al. 2007) rasterises the
 * irradiance of the surface into its UV atlas and blurs it there, so every
 * texel must stand for one place on the surface: UVs must lie in [0,1]^2
 * and no two triangles may share texture space. Layouts that reach past
 * [0,1]^2 (exporters write them for tiling, wrap-around seams and UDIM
 * tiles) are first moved there whole by sam_uv_fit_atlas: one scale and
 * offset for every UV, so charts that did not overlap still do not, and
 * no triangle needs splitting. A mirrored or stacked UV
 * island (common in game assets, where both halves of a face share one
 * texture) would add the light of two surface places into one texel. A mesh
 * that fails falls back to screen-space diffusion, and sam_uv_usable gives
 * the one-line reason to print.
 *
 * The check rasterises each triangle's UV footprint on a grid of texel
 * centres, counting per texel how many triangles cover its centre. The
 * rasteriser is watertight: UVs are snapped to fixed point (1/256 texel)
 * and the edge functions are evaluated exactly in integers with a top-left
 * tie rule, so a texel centre lying exactly on an edge or a vertex shared by
 * neighbouring triangles is counted once, never twice and never zero times.
 * Any overlap it reports is therefore real, not an artefact of shared
 * edges. Winding does not matter: a mirrored island is legitimate on its
 * own; only coverage counts.
 *
 * sam_uv_crossings gives the blur what it needs to follow the surface
 * across UV seams rather than stop at them: the triangle across every
 * edge, and every triangle's chart.
 *
 * Stateless; every function is thread-safe.
 */
#ifndef SAM_UV_H
#define SAM_UV_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest coverage grid side sam_uv_check accepts (a 64 MiB counter grid). */
#define SAM_UV_MAX_RESOLUTION 8192u

/* Largest overlap_fraction sam_uv_usable accepts. Shared edges and vertices
 * never count as overlap (see the overview), so this tolerance only absorbs
 * float noise: islands that abut along a line without sharing vertices, or
 * T-junctions, whose edges may differ by an ulp and then cover a texel
 * centre on that line twice. That is at most about one texel row along
 * such seams; 0.1% of the covered texels allows roughly 1000 such texels on
 * a 1024^2 atlas, while a real mirrored or stacked island covers at least
 * several percent. */
#define SAM_UV_MAX_OVERLAP 0.001f

/* UVs farther than this from the origin are not rasterised (see
 * sam_uv_check); it keeps the fixed-point edge functions inside int64. */
#define SAM_UV_RASTER_LIMIT 256.0f

typedef struct sam_uv_report {
    uint32_t resolution;             /* the coverage grid's side, texels */
    uint64_t covered_texels;         /* texel centres inside at least one triangle */
    uint64_t overlap_texels;         /* texel centres inside two or more triangles */
    float overlap_fraction;          /* overlap_texels / covered_texels, 0 when nothing is covered */
    uint32_t outside_triangles;      /* triangles with a UV outside [0,1]^2 */
    uint32_t first_outside_triangle; /* index of the first of them, UINT32_MAX when none */
    uint32_t degenerate_triangles;   /* zero UV area (not an error by itself) */
} sam_uv_report;

/* Where a layout's UVs lie in the texture-space atlas:
 * atlas_uv = uv * scale + offset. */
typedef struct sam_uv_atlas {
    int moved;          /* 1 when the UVs reach past [0,1]^2 and were moved into it */
    float scale;        /* > 0; 1 when not moved */
    float offset[2];    /* (0, 0) when not moved */
    float lo[2], hi[2]; /* bounds of the UVs the triangles use, (0,0) when there are no triangles */
} sam_uv_atlas;

/* Fits the UV layout of `triangle_count` triangles (`triangles`:
 * 3 * triangle_count indices < vertex_count) over `uvs` (2 * vertex_count
 * floats) into the atlas's [0,1]^2 and writes every vertex's atlas UV to
 * `out` (2 * vertex_count floats, may be `uvs` itself).
 *
 * When the UVs the triangles use already lie in [0,1]^2 they are kept as
 * they are. Otherwise their bounding box is scaled, by one factor on both
 * axes so texels stay square, to a side of 1 and moved to the origin: a
 * layout from u = -0.05 to 0.99 loses 5% of its texel density, a tiled one
 * from 0 to 4 three quarters, a row of ten UDIM tiles 90% (the atlas's
 * side is sized from the covered fraction, so the blur keeps its reach).
 * Wrapping into [0,1] instead would stack the tiles of a tiled or UDIM
 * layout on one another. Atlas UVs of vertices no triangle uses are
 * clamped into [0,1]^2.
 *
 * `uvs` and `out` may be NULL when vertex_count is 0, `triangles` when
 * triangle_count is 0. Errors: SAM_ERR_INVALID_ARGUMENT (NULL atlas, or a
 * NULL array with a non-zero count), SAM_ERR_FORMAT (as sam_uv_check). */
sam_status sam_uv_fit_atlas(const float *uvs, uint32_t vertex_count, const uint32_t *triangles,
                            uint32_t triangle_count, sam_uv_atlas *atlas, float *out, sam_error *err);

/* Measures the coverage of the UV atlas of `triangle_count` triangles
 * (`triangles`: 3 * triangle_count indices < vertex_count) over `uvs`
 * (2 * vertex_count floats, (u, v) per vertex) on a resolution x resolution
 * grid whose texel (i, j) has its centre at ((i + 0.5) / resolution,
 * (j + 0.5) / resolution), and fills `report`.
 *
 * A triangle is degenerate when its area is zero at the grid's fixed-point
 * precision (1/256 texel); it covers nothing. A triangle with a UV outside
 * [0,1]^2 is counted in outside_triangles and still rasterised where it
 * overlaps the grid, unless one of its UVs lies beyond
 * +-SAM_UV_RASTER_LIMIT: it then covers nothing (the atlas is unusable
 * anyway). Every vertex's UV must be finite, referenced or not.
 *
 * `uvs` may be NULL when vertex_count is 0, `triangles` when triangle_count
 * is 0; `report` must not be NULL and is zeroed on failure. Allocates
 * resolution^2 bytes, freed before returning.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL array with a non-zero count, NULL
 * report, resolution 0 or above SAM_UV_MAX_RESOLUTION), SAM_ERR_FORMAT (an
 * index >= vertex_count: the message names the triangle and the index; a
 * non-finite UV: the message names the vertex), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_uv_check(const float *uvs, uint32_t vertex_count, const uint32_t *triangles,
                        uint32_t triangle_count, uint32_t resolution, sam_uv_report *report,
                        sam_error *err);

/* Returns 1 when the atlas `report` describes can carry texture-space
 * diffusion: no triangle outside [0,1]^2, overlap_fraction <=
 * SAM_UV_MAX_OVERLAP and at least one texel covered. Otherwise returns 0 and
 * writes one line (no newline) naming every failed condition into `reason`
 * (size n, always NUL-terminated, truncated if too small), e.g. "12.5% of
 * the covered atlas texels are covered by more than one triangle (mirrored
 * or stacked UV islands)". `reason` may be NULL or n 0; on success it gets
 * an empty string. A NULL report is unusable. */
int sam_uv_usable(const sam_uv_report *report, char *reason, size_t n);

/* sam_uv_crossings: an edge with no triangle across it. */
#define SAM_UV_NO_CROSSING 0xFFFFFFFFu
/* The most triangles sam_uv_crossings takes: it writes 4 * triangle + edge
 * in 32 bits. */
#define SAM_UV_MAX_CROSSING_TRIANGLES 0x3FFFFFFFu

/* Where the surface goes on past each edge, for a blur in the atlas that
 * follows the surface across UV seams instead of stopping at them.
 *
 * Edge e of triangle t runs from its corner e to corner (e + 1) % 3.
 * across[3 * t + e] is 4 * t' + e' for the one other triangle t' whose edge
 * e' joins the same two places, or SAM_UV_NO_CROSSING where the edge is on
 * the mesh's boundary, shared by three or more triangles, or has both ends
 * at one place. Places are positions: seam copies of a vertex (split for
 * their UVs) keep its position bit for bit, as sam_mesh writes them, and
 * distinct vertices at one position count as one place.
 *
 * chart[t] numbers the charts 0, 1, ... in the order of their first
 * triangle: two triangles across an edge are in one chart when they give
 * both its ends the same UVs (bit for bit), and a chart is everything
 * joined by such edges. A UV seam is an edge with a crossing between two
 * charts.
 *
 * positions: 3 * vertex_count floats; uvs: 2 * vertex_count (either may be
 * NULL when vertex_count is 0); triangles: 3 * triangle_count indices <
 * vertex_count; across: 3 * triangle_count and chart: triangle_count,
 * written by the call (the caller owns all of them; NULL only when
 * triangle_count is 0). Allocates about 20 bytes per vertex and 40 per
 * triangle, freed before returning.
 * Errors: SAM_ERR_INVALID_ARGUMENT (a NULL array with a non-zero count,
 * more than SAM_UV_MAX_CROSSING_TRIANGLES triangles), SAM_ERR_FORMAT (an
 * index >= vertex_count: the message names the triangle, corner and
 * index), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_uv_crossings(const float *positions, const float *uvs, uint32_t vertex_count,
                            const uint32_t *triangles, uint32_t triangle_count, uint32_t *across, uint32_t *chart,
                            sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
