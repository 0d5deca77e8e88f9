#include "sam/sam_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_mesh_internal.h"

static sam_status finish(sam_status st, sam_mesh *mesh, sam_mesh_report *report,
                         const sam_mesh_report *rep)
{
    if (st != SAM_OK)
        sam_mesh_destroy(mesh);
    if (report)
        *report = *rep;
    return st;
}

int sam_mesh_is_mesh_path(const char *path)
{
    static const char *const extensions[] = {".obj", ".ply", ".off", ".stl", ".gltf", ".glb"};
    for (size_t i = 0; i < sizeof extensions / sizeof *extensions; ++i)
        if (sam_path_has_extension(path, extensions[i]))
            return 1;
    return 0;
}

sam_status sam_mesh_load(const char *path, sam_mesh *mesh, sam_mesh_report *report, sam_error *err)
{
    sam_mesh_report rep;
    memset(&rep, 0, sizeof rep);
    if (!path || !mesh)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_mesh_load: NULL argument");
    memset(mesh, 0, sizeof *mesh);
    sam_mesh_soup soup;
    memset(&soup, 0, sizeof soup);
    const int gltf = sam_path_has_extension(path, ".gltf") || sam_path_has_extension(path, ".glb");
    sam_mesh_expect expect;
    memset(&expect, 0, sizeof expect);
    /* The readers open the path themselves: refuse a device or pipe first. */
    sam_status st = sam_check_regular_file(path, err);
    if (st == SAM_OK)
        st = gltf ? sam_mesh_gltf_read(path, &soup, err) : sam_mesh_preflight(path, &expect, err);
    if (st == SAM_OK && !gltf)
        st = sam_mesh_soup_read(path, expect.rewritten, expect.rewritten_size, expect.rewritten_extension, &soup,
                                err);
    /* Corner UVs a rewritten PLY carried past the reader, corner by corner. */
    if (st == SAM_OK && expect.corner_uvs && !soup.corner_uvs && expect.corner_uv_count == soup.corner_count) {
        soup.corner_uvs = expect.corner_uvs;
        expect.corner_uvs = NULL;
    }
    /* The reader and the pre-check must agree on what the file holds. */
    if (st == SAM_OK && expect.known && (soup.vertex_count != expect.vertices || soup.face_count != expect.faces))
        st = sam_fail(err, SAM_ERR_FORMAT,
                      "%s: the reader delivered %u vertices and %u faces, but the file holds %llu and %llu; "
                      "refusing a mesh that was not read as written",
                      path, soup.vertex_count, soup.face_count, (unsigned long long)expect.vertices,
                      (unsigned long long)expect.faces);
    if (st == SAM_OK && soup.face_count == 0) {
        if (expect.repeated_corner_faces && expect.repeated_corner_faces == expect.file_faces)
            st = sam_fail(err, SAM_ERR_EMPTY,
                          "%s: all %llu faces repeat a vertex and have fewer than 3 distinct corners (the first on "
                          "line %d): no face is left",
                          path, (unsigned long long)expect.file_faces, expect.first_repeated_line);
        else if (soup.vertex_count)
            st = sam_fail(err, SAM_ERR_EMPTY, "%s: the file has %u vertices but no faces", path, soup.vertex_count);
        else
            /* Lines an OBJ does not know are skipped, so a text file that is
             * no mesh reads as an empty one: say so rather than "0 of". */
            st = sam_fail(err, SAM_ERR_EMPTY, "%s: no vertices and no faces in it: is it a mesh?", path);
    }
    if (st == SAM_OK)
        st = sam_mesh_expect_corner_normals(&expect, &soup, &soup.corner_normals, err);
    if (st == SAM_OK)
        st = sam_mesh_build(&soup, path, mesh, &rep, err);
    sam_mesh_expect_free(&expect);
    /* The faces the reader dropped for repeated corners are the file's too. */
    rep.file_faces += (uint32_t)expect.repeated_corner_faces;
    rep.faces_too_small += (uint32_t)expect.repeated_corner_faces;
    sam_mesh_soup_free(&soup);
    return finish(st, mesh, report, &rep);
}

sam_status sam_mesh_create(const sam_mesh_input *input, sam_mesh *mesh, sam_mesh_report *report,
                           sam_error *err)
{
    sam_mesh_report rep;
    memset(&rep, 0, sizeof rep);
    if (!input || !mesh || !input->positions || !input->triangles)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_mesh_create: NULL argument");
    memset(mesh, 0, sizeof *mesh);
    const char *name = input->name ? input->name : "mesh";
    if (input->triangle_count == 0)
        return finish(sam_fail(err, SAM_ERR_EMPTY, "%s: no triangles", name), mesh, report, &rep);
    if (input->triangle_count > UINT32_MAX / 4)
        return finish(sam_fail(err, SAM_ERR_UNSUPPORTED, "%s: %u triangles exceed the index range", name,
                               input->triangle_count),
                      mesh, report, &rep);
    sam_mesh_soup soup = {
        .vertex_count = input->vertex_count,
        .positions = (float *)input->positions,
        .normals = (float *)input->normals,
        .uvs = (float *)input->uvs,
        .face_count = input->triangle_count,
        .corner_count = 3 * input->triangle_count,
        .corners = (uint32_t *)input->triangles,
    };
    soup.face_offsets = malloc(((size_t)input->triangle_count + 1) * sizeof *soup.face_offsets);
    if (!soup.face_offsets)
        return finish(sam_mesh_oom(err, name), mesh, report, &rep);
    for (uint32_t f = 0; f <= input->triangle_count; ++f)
        soup.face_offsets[f] = 3 * f;
    sam_status st = sam_mesh_build(&soup, name, mesh, &rep, err);
    free(soup.face_offsets);
    return finish(st, mesh, report, &rep);
}

void sam_mesh_destroy(sam_mesh *mesh)
{
    if (!mesh)
        return;
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->uvs);
    free(mesh->triangles);
    free(mesh->topo_of);
    free(mesh->topo_rep);
    free(mesh->topo_normals);
    free(mesh->ring_offsets);
    free(mesh->ring);
    free(mesh->source_of_render);
    free(mesh->face_of_triangle);
    free(mesh->render_of_source);
    memset(mesh, 0, sizeof *mesh);
}

void sam_mesh_bounds(const sam_mesh *mesh, float min[3], float max[3])
{
    for (int i = 0; i < 3; ++i)
        min[i] = INFINITY, max[i] = -INFINITY;
    for (uint32_t v = 0; v < mesh->vertex_count; ++v)
        for (int i = 0; i < 3; ++i) {
            float x = mesh->positions[3 * (size_t)v + i];
            min[i] = fminf(min[i], x);
            max[i] = fmaxf(max[i], x);
        }
}

double sam_mesh_box_diagonal(const float min[3], const float max[3])
{
    double d2 = 0;
    for (int i = 0; i < 3; ++i)
        d2 += ((double)max[i] - min[i]) * ((double)max[i] - min[i]);
    return sqrt(d2);
}

double sam_mesh_diagonal(const sam_mesh *mesh)
{
    sam_mesh_body_info body;
    if (sam_mesh_body(mesh, NULL, &body, NULL) == SAM_OK)
        return sam_mesh_box_diagonal(body.min, body.max);
    float lo[3], hi[3];
    sam_mesh_bounds(mesh, lo, hi);
    return sam_mesh_box_diagonal(lo, hi);
}

static const float *topo_position(const sam_mesh *mesh, const float *positions, uint32_t t)
{
    return positions + 3 * (size_t)mesh->topo_rep[t];
}

void sam_mesh_fan_areas(const sam_mesh *mesh, const float *positions, float mm_per_unit, float *out)
{
    if (!positions)
        positions = mesh->positions;
    double scale = (double)mm_per_unit * mm_per_unit;
    for (uint32_t t = 0; t < mesh->topo_count; ++t) {
        const float *v = topo_position(mesh, positions, t);
        double sum = 0;
        for (uint32_t k = mesh->ring_offsets[t] + 1; k < mesh->ring_offsets[t + 1]; ++k) {
            double a[3], b[3], n[3];
            sub3(topo_position(mesh, positions, mesh->ring[k - 1]), v, a);
            sub3(topo_position(mesh, positions, mesh->ring[k]), v, b);
            cross3(a, b, n);
            sum += len3(n);
        }
        out[t] = (float)(sum / 6.0 * scale);
    }
}

static double cotangent(const double *u, const double *w)
{
    double c[3];
    cross3(u, w, c);
    double s = len3(c);
    return s > 0 ? dot3(u, w) / s : 0.0;
}

void sam_mesh_ring_curvature(uint32_t count, const float *positions, const uint32_t *position_of,
                             const float *normals, const uint32_t *ring_offsets, const uint32_t *ring, float *out)
{
#define POS(i) (positions + 3 * (size_t)(position_of ? position_of[i] : (i)))
    for (uint32_t t = 0; t < count; ++t) {
        uint32_t begin = ring_offsets[t], end = ring_offsets[t + 1];
        if (end - begin < 2 || ring[begin] != ring[end - 1]) {
            out[t] = NAN; /* boundary: filled in below */
            continue;
        }
        const float *v = POS(t);
        double lap[3] = {0, 0, 0}, area = 0;
        for (uint32_t k = begin + 1; k < end; ++k) {
            const float *p = POS(ring[k - 1]);
            const float *q = POS(ring[k]);
            double vp[3], vq[3], pv[3], pq[3], qv[3], qp[3], n[3];
            sub3(p, v, vp);
            sub3(q, v, vq);
            sub3(v, p, pv);
            sub3(q, p, pq);
            sub3(v, q, qv);
            sub3(p, q, qp);
            /* The angle at q faces edge v-p; the angle at p faces edge v-q. */
            double cot_q = cotangent(qv, qp), cot_p = cotangent(pv, pq);
            for (int i = 0; i < 3; ++i)
                lap[i] += cot_q * vp[i] + cot_p * vq[i];
            cross3(vp, vq, n);
            /* Mixed Voronoi area (Meyer et al. 2003): the barycentric third
             * overestimates H by up to 1.5x at irregular (valence 4) vertices. */
            double tri_area = len3(n) / 2.0;
            if (dot3(vp, vq) < 0)
                area += tri_area / 2.0;
            else if (dot3(pv, pq) < 0 || dot3(qv, qp) < 0)
                area += tri_area / 4.0;
            else
                area += (dot3(vp, vp) * cot_q + dot3(vq, vq) * cot_p) / 8.0;
        }
        double nrm[3] = {normals[3 * (size_t)t], normals[3 * (size_t)t + 1], normals[3 * (size_t)t + 2]};
        /* Laplace-Beltrami of position = -2 H n. */
        out[t] = area > 0 ? (float)(-dot3(lap, nrm) / (2.0 * area) / 2.0) : 0.0f;
    }
#undef POS
    for (uint32_t t = 0; t < count; ++t) {
        if (!isnan(out[t]))
            continue;
        double sum = 0;
        uint32_t n = 0;
        for (uint32_t k = ring_offsets[t]; k < ring_offsets[t + 1]; ++k) {
            uint32_t u = ring[k];
            uint32_t ub = ring_offsets[u], ue = ring_offsets[u + 1];
            if (ue - ub >= 2 && ring[ub] == ring[ue - 1]) {
                sum += out[u];
                n++;
            }
        }
        out[t] = n ? (float)(sum / n) : 0.0f;
    }
}

void sam_mesh_mean_curvature(const sam_mesh *mesh, float *out)
{
    sam_mesh_ring_curvature(mesh->topo_count, mesh->positions, mesh->topo_rep, mesh->topo_normals,
                            mesh->ring_offsets, mesh->ring, out);
}

char *sam_mesh_report_summary(const sam_mesh_report *r, char *buf, size_t n)
{
    struct item {
        uint32_t count;
        const char *what;
    } items[] = {
        {r->faces_too_small, "faces with < 3 distinct corners dropped"},
        {r->degenerate_triangles, "degenerate triangles dropped"},
        {r->zero_area_triangles, "zero-area triangles dropped"},
        {r->duplicate_triangles, "duplicate triangles dropped"},
        {r->triangles_turned, "triangles turned to agree with their neighbours"},
        {r->unreferenced_vertices, "unreferenced vertices dropped"},
        {r->crack_vertices_welded, "boundary vertices welded to a neighbour a hair away"},
        {r->non_manifold_vertices, "non-manifold vertices split"},
        {r->non_manifold_edges, "non-manifold edges"},
        {r->invalid_file_normals, "zero-length normals recomputed"},
        {r->polygons_triangulated, "polygons triangulated"},
    };
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < sizeof items / sizeof items[0]; ++i) {
        if (!items[i].count || used >= n)
            continue;
        int w = snprintf(buf + used, n - used, "%s%u %s", used ? ", " : "", items[i].count, items[i].what);
        if (w > 0)
            used += (size_t)w;
    }
    if (!used)
        snprintf(buf, n, "no repairs");
    return buf;
}
