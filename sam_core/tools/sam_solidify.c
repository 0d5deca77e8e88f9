/*
 * sam_solidify: gives a single sheet (a leaf, a cloth card) the thickness
 * that translucency needs, and writes it as OBJ or PLY (sam_mesh_solidify).
 */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sam/sam_app_output.h"
#include "sam/sam_args.h"
#include "sam/sam_mesh.h"

#define TOOL "sam_solidify"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_solidify MESH -o OUT.obj|OUT.ply --thickness-mm T (--mm-per-unit X | --size-mm D)\n"
            "                    [--force]\n"
            "\n"
            "A leaf, a petal, paper or a cloth card modelled as one layer of triangles has no\n"
            "back side, so no light comes through it. This makes each open part of MESH the\n"
            "mid-surface of a solid T millimetres thick: two faces T/2 to either side along\n"
            "the normals, with the same UVs, closed by a rim along the boundary. Closed parts\n"
            "are copied as they are. Build, render and compare OUT like any mesh, at the\n"
            "scale printed (normals are recomputed from the faces). MESH's albedo texture (an\n"
            "OBJ's map_Kd, a glTF's base colour) goes with an OBJ: OUT.mtl and OUT_albedo.png.\n"
            "\n"
            "  MESH                .obj, .ply, .off, .stl, .gltf or .glb\n"
            "  -o OUT              .obj or .ply (binary), written atomically; an existing file\n"
            "                      (OUT's .mtl and texture too) needs --force\n"
            "  --thickness-mm T    the solid's thickness in millimetres\n"
            "  --mm-per-unit X     millimetres per model unit, or\n"
            "  --size-mm D         MESH's bounding-box diagonal in millimetres\n"
            "  --force             overwrite OUT (and its .mtl and texture) if they exist\n"
            "  -h, --help          this help;  --version  the version\n"
            "\n"
            "examples (leaf.obj: an open sheet of your own, such as a scanned leaf):\n"
            "  sam_solidify leaf.obj -o leaf_solid.obj --thickness-mm 0.3 --size-mm 80\n"
            "  sam_render leaf_solid.obj --material apple --mm-per-unit 12.5 -o leaf.png --beside none\n");
}

int main(int argc, char **argv)
{
    const char *mesh_path = NULL, *out_path = NULL;
    float thickness_mm = NAN, mm_per_unit = NAN, size_mm = NAN;
    int force = 0;
    const char *positive = "a positive number that fits a 32-bit float";
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &out_path, .value = "OUT.obj|OUT.ply", .required = 1},
        {"--thickness-mm", SAM_ARG_FLOAT, &thickness_mm, .lo = 0, .hi = FLT_MAX, .lo_open = 1, .must = positive,
         .required = 1},
        {"--mm-per-unit", SAM_ARG_FLOAT, &mm_per_unit, .lo = 0, .hi = FLT_MAX, .lo_open = 1, .must = positive},
        {"--size-mm", SAM_ARG_FLOAT, &size_mm, .lo = 0, .hi = FLT_MAX, .lo_open = 1, .must = positive},
        {"--force", SAM_ARG_FLAG, .target = &force},
    };
    const sam_args_spec spec = {TOOL, args, sizeof args / sizeof *args, &mesh_path, 1, 1, "MESH", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (isnan(mm_per_unit) == isnan(size_mm))
        return sam_args_fail(TOOL, "give exactly one of --mm-per-unit and --size-mm");
    sam_error err;
    static const char *const extensions[] = {".obj", ".ply", NULL};
    if (sam_app_check_output("-o", out_path, extensions, force, &err) != SAM_OK) {
        fprintf(stderr, TOOL ": %s\n", err.message);
        return 1;
    }

    sam_mesh mesh;
    sam_mesh_report report;
    if (sam_mesh_load(mesh_path, &mesh, &report, &err) != SAM_OK) {
        fprintf(stderr, TOOL ": %s\n", err.message);
        return 1;
    }
    char line[512];
    sam_mesh_report_summary(&report, line, sizeof line);
    if (strcmp(line, "no repairs"))
        fprintf(stderr, TOOL ": %s: %s\n", mesh_path, line);
    if (sam_mesh_is_closed(&mesh)) {
        fprintf(stderr, TOOL ": %s is closed: it has a back side already, and nothing was written\n", mesh_path);
        sam_mesh_destroy(&mesh);
        return 1;
    }
    const double diagonal = sam_mesh_diagonal(&mesh);
    if (isnan(mm_per_unit)) {
        if (!(diagonal > 0)) {
            fprintf(stderr, TOOL ": %s has no extent, so --size-mm cannot scale it\n", mesh_path);
            sam_mesh_destroy(&mesh);
            return 1;
        }
        mm_per_unit = (float)(size_mm / diagonal);
    }
    const float thickness = thickness_mm / mm_per_unit;
    sam_shape_mesh solid;
    sam_mesh_solidify_report done;
    sam_status st = sam_mesh_solidify(&mesh, thickness, &solid, &done, &err);
    if (st != SAM_OK) {
        fprintf(stderr, TOOL ": %s: %s (--thickness-mm %g at %g mm per unit)\n", mesh_path, err.message,
                (double)thickness_mm, (double)mm_per_unit);
        sam_mesh_destroy(&mesh);
        return st == SAM_ERR_INVALID_ARGUMENT ? 2 : 1;
    }
    if (done.folded_vertices)
        fprintf(stderr,
                TOOL ": warning: %u vertices are curved tighter than half of %g mm: the two faces may cross "
                "there (a thinner solid, or a smoother sheet, keeps them apart)\n",
                done.folded_vertices, (double)thickness_mm);
    /* A texture that cannot go with OUT leaves OUT untextured, said on a
     * line; only a companion file in the way (without --force) stops. */
    sam_image albedo = {0};
    sam_error albedo_err;
    char texture[2304] = "", mtl[4096] = "", png[4096] = "";
    const int obj = !sam_app_has_extension(out_path, ".ply");
    int carry = 0;
    if (sam_mesh_load_albedo(mesh_path, &albedo, texture, sizeof texture, &albedo_err) != SAM_OK)
        fprintf(stderr, TOOL ": warning: the texture cannot be read (%s): %s is written without one\n",
                albedo_err.message, out_path);
    else if (!albedo.pixels && texture[0])
        fprintf(stderr, TOOL ": warning: %s: %s is written without a texture\n", texture, out_path);
    else if (albedo.pixels && (!obj || !solid.uvs))
        fprintf(stderr, TOOL ": note: %s is not carried: %s\n", texture,
                obj ? "the mesh has no UVs" : "a PLY holds none (write an .obj to keep it)");
    else if (albedo.pixels && sam_shape_obj_companions(out_path, mtl, png, sizeof mtl, &albedo_err) != SAM_OK)
        fprintf(stderr, TOOL ": note: %s is not carried: %s\n", texture, albedo_err.message);
    else if (albedo.pixels && (sam_app_check_output("-o's material library", mtl, NULL, force, &err) != SAM_OK ||
                               sam_app_check_output("-o's texture", png, NULL, force, &err) != SAM_OK)) {
        fprintf(stderr, TOOL ": %s\n", err.message);
        sam_image_destroy(&albedo);
        sam_shape_mesh_destroy(&solid);
        sam_mesh_destroy(&mesh);
        return 1;
    } else if (albedo.pixels) {
        carry = 1;
    }
    if (!carry)
        sam_image_destroy(&albedo);
    sam_mesh_destroy(&mesh);

    st = !obj             ? sam_shape_write_ply(out_path, &solid, 1, &err)
         : carry         ? sam_shape_write_obj_albedo(out_path, &solid, &albedo, &err)
                         : sam_shape_write_obj(out_path, &solid, &err);
    if (st != SAM_OK) {
        fprintf(stderr, TOOL ": %s\n", err.message);
        sam_image_destroy(&albedo);
        sam_shape_mesh_destroy(&solid);
        return 1;
    }
    if (carry)
        fprintf(stderr, TOOL ": wrote %s and %s, from %s\n", mtl, png, texture);
    sam_image_destroy(&albedo);
    fprintf(stderr,
            TOOL ": wrote %s: %u open part%s %g mm thick (%g units), %u closed part%s kept, %u rim edges; "
            "%u vertices, %u triangles. Give it --mm-per-unit %g (its diagonal grew with the thickness)\n",
            out_path, done.open_parts, done.open_parts == 1 ? "" : "s", (double)thickness_mm, (double)thickness,
            done.closed_parts, done.closed_parts == 1 ? "" : "s",
            done.rim_edges, solid.vertex_count, solid.triangle_count, (double)mm_per_unit);
    sam_shape_mesh_destroy(&solid);
    return 0;
}
