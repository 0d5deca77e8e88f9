// Texture-space blur across UV seams. A tap that falls off its texel's
// chart (into the atlas's empty space, or onto a chart that lies elsewhere
// on the surface) is found on the surface instead:
//  1. along the tap's line in the atlas, the last texel still on the chart
//     (a binary search over the triangle ids of the stretch map);
//  2. from there a walk over the triangles, straight on the surface (each
//     crossed edge unfolds the next triangle into the plane of the last),
//     across the first UV seam (sam_uv_crossings says what lies across
//     every edge);
//  3. on that chart, the rest of the tap's distance along the walk's
//     heading as a straight line in its UVs, as taps on a chart are;
//  4. repeated if that line leaves the chart too.
// Where the walk meets the mesh's boundary the tap falls back to the
// centre, as every off-chart tap did before walks. Charts are straight in
// their UVs wherever the blur is (its taps assume so), so only the few
// triangles between a chart's last texel and the next chart are walked.
#include "uv_atlas.glsl"

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_TRIANGLES) readonly buffer Triangles { uint triangles[]; };
layout(std430, binding = SAM_B_UVS) readonly buffer Uvs { vec2 uvs[]; };
// Per triangle: across its edges (4 t' + e', or NO_CROSSING), and its chart.
layout(std430, binding = SAM_B_TSD_CROSSINGS) readonly buffer Crossings { uvec4 crossings[]; };

uniform float u_mm_per_unit;

#define NO_CROSSING 0xFFFFFFFFu
// Charts one tap may pass through, and triangles walked between two.
#define CROSS_MAX_SEAMS 4
#define CROSS_MAX_STEPS 16

// A walk on the surface: in triangle t at x (mm), heading d (unit, in t's
// plane), having come in through edge `entered` (3: none). `side` is a
// second direction carried along as the heading is: the axis of the blur's
// other pass.
struct Walk {
    uint t;
    vec3 x;
    vec3 d;
    vec3 side;
    uint entered;
};

vec3 cross_corner(uint t, uint c)
{
    return positions[triangles[3u * t + c]].xyz * u_mm_per_unit;
}

// In texels of the atlas's used corner (`size` of them along each side).
vec2 cross_corner_texels(uint t, uint c, vec2 size)
{
    return atlas_uv(uvs[triangles[3u * t + c]]) * size;
}

// The triangle under atlas point `at` (texels) by the stretch map + 1, 0
// where there is none.
uint cross_triangle_at(vec2 at, ivec2 size)
{
    return uint(imageLoad(u_stretch, clamp(ivec2(floor(at)), ivec2(0), size - 1)).z);
}

// Where `uv` (texels) lies in triangle t, and the surface direction of the
// atlas direction `dir` there (unit; 0 where t is degenerate in the atlas).
void cross_from_atlas(uint t, vec2 uv, vec2 dir, vec2 size, out vec3 x, out vec3 d)
{
    vec2 a = cross_corner_texels(t, 0u, size), e1 = cross_corner_texels(t, 1u, size) - a,
         e2 = cross_corner_texels(t, 2u, size) - a;
    float det = e1.x * e2.y - e1.y * e2.x;
    vec3 p0 = cross_corner(t, 0u), E1 = cross_corner(t, 1u) - p0, E2 = cross_corner(t, 2u) - p0;
    x = p0;
    d = vec3(0.0);
    if (det == 0.0)
        return;
    vec2 r = uv - a;
    x = p0 + ((r.x * e2.y - r.y * e2.x) * E1 + (e1.x * r.y - e1.y * r.x) * E2) / det;
    d = ((dir.x * e2.y - dir.y * e2.x) * E1 + (e1.x * dir.y - e1.y * dir.x) * E2) / det;
    d = dot(d, d) > 0.0 ? normalize(d) : vec3(0.0);
}

// The atlas point (texels) of surface point x in triangle t, and the atlas
// direction of surface direction d there, in texels per mm (0 where t is
// degenerate on the surface).
void cross_to_atlas(uint t, vec3 x, vec3 d, vec2 size, out vec2 uv, out vec2 texels_per_mm)
{
    vec3 p0 = cross_corner(t, 0u), E1 = cross_corner(t, 1u) - p0, E2 = cross_corner(t, 2u) - p0;
    vec2 a = cross_corner_texels(t, 0u, size), e1 = cross_corner_texels(t, 1u, size) - a,
         e2 = cross_corner_texels(t, 2u, size) - a;
    // Least squares in the triangle's plane: v = s E1 + q E2.
    float g11 = dot(E1, E1), g12 = dot(E1, E2), g22 = dot(E2, E2), det = g11 * g22 - g12 * g12;
    uv = a;
    texels_per_mm = vec2(0.0);
    if (!(det > 0.0))
        return;
    vec3 r = x - p0;
    float rs = (g22 * dot(r, E1) - g12 * dot(r, E2)) / det, rq = (g11 * dot(r, E2) - g12 * dot(r, E1)) / det;
    float ds = (g22 * dot(d, E1) - g12 * dot(d, E2)) / det, dq = (g11 * dot(d, E2) - g12 * dot(d, E1)) / det;
    uv = a + rs * e1 + rq * e2;
    texels_per_mm = ds * e1 + dq * e2;
}

// Walks w on until `len` mm are done (returns 1, *left 0) or it crosses a
// UV seam (returns 2, *left the mm still to go). Returns 0 where it leaves
// the mesh (a boundary, a non-manifold edge), meets a degenerate triangle
// or runs out of steps.
int cross_walk(inout Walk w, float len, out float left)
{
    left = len;
    for (int step = 0; step < CROSS_MAX_STEPS; ++step) {
        vec3 p[3] = vec3[3](cross_corner(w.t, 0u), cross_corner(w.t, 1u), cross_corner(w.t, 2u));
        vec3 n = cross(p[1] - p[0], p[2] - p[0]);
        if (!(dot(n, n) > 0.0))
            return 0;
        // The nearest edge ahead, by its outward normal m in the plane.
        float exit_at = 3.0e38;
        uint exit_edge = 3u;
        for (uint e = 0u; e < 3u; ++e) {
            vec3 m = cross(p[(e + 1u) % 3u] - p[e], n);
            float towards = dot(w.d, m);
            if (e == w.entered || towards <= 0.0)
                continue;
            float s = dot(p[e] - w.x, m) / towards;
            if (s < exit_at) {
                exit_at = s;
                exit_edge = e;
            }
        }
        if (exit_edge == 3u)
            return 0;
        exit_at = max(exit_at, 0.0);
        if (left <= exit_at) {
            w.x += left * w.d;
            left = 0.0;
            return 1;
        }
        uint next = crossings[w.t][exit_edge];
        if (next == NO_CROSSING)
            return 0;
        w.x += exit_at * w.d;
        left -= exit_at;
        // Unfold: the heading keeps its part along the edge; its part
        // across the edge turns from this triangle's plane into the next's.
        vec3 a = p[exit_edge], b = p[(exit_edge + 1u) % 3u];
        vec3 edge = normalize(b - a), out_m = normalize(cross(b - a, n));
        uint t2 = next >> 2u, e2 = next & 3u;
        vec3 q0 = cross_corner(t2, 0u), n2 = cross(cross_corner(t2, 1u) - q0, cross_corner(t2, 2u) - q0);
        vec3 in_m = -cross(cross_corner(t2, (e2 + 1u) % 3u) - cross_corner(t2, e2), n2);
        if (!(dot(in_m, in_m) > 0.0))
            return 0;
        in_m = normalize(in_m);
        w.d = normalize(dot(w.d, edge) * edge + dot(w.d, out_m) * in_m);
        w.side = dot(w.side, edge) * edge + dot(w.side, out_m) * in_m;
        // A UV seam: the edge's ends are other vertices (copies with other
        // UVs) in the next triangle, which may be of this chart (a chart
        // that wraps around a tube meets itself).
        bool seam = triangles[3u * w.t + exit_edge] != triangles[3u * t2 + (e2 + 1u) % 3u] ||
                    triangles[3u * w.t + (exit_edge + 1u) % 3u] != triangles[3u * t2 + e2];
        w.t = t2;
        w.entered = e2;
        if (seam)
            return 2;
    }
    return 0;
}

// Where a tap's line crossed its first seam: the other taps on that side
// of the texel cross it there too, and only go on from it (cross_after).
struct CrossSeam {
    bool valid;
    uint triangle;    // + 1, across the seam
    vec3 side;        // cross_tap's side, carried to the seam
    vec2 from;        // texels, on the chart across
    vec2 dir;         // unit, in texels there
    float per_mm;     // texels per mm along dir
    float done_mm;    // from the texel to the seam, on the surface
    uint chart;
    vec2 side_texels; // as cross_tap's
};

// A tap `len` texels from `from` (texels; a texel centre of triangle
// t + 1 = `triangle`) along atlas direction `dir` (unit), the texels there
// `mm_per_texel` apart: where on the atlas the tap lies once the surface is
// followed across seams (`at`), and on which chart (`landed`). `side`, a
// direction on the surface at `from`, comes back as the same direction
// there in texels per mm (`side_texels`). `first` gets where the line
// crossed its first seam. False where the surface ends first.
bool cross_tap(uint triangle, vec2 from, vec2 dir, float len, float mm_per_texel, ivec2 size, vec3 side,
               out vec2 at, out uint landed, out vec2 side_texels, out CrossSeam first)
{
    uint chart = crossings[triangle - 1u].w;
    vec2 fsize = vec2(size);
    const float total_mm = len * mm_per_texel;
    at = from;
    landed = chart;
    side_texels = vec2(0.0);
    first.valid = false;
    for (int seam = 0; seam < CROSS_MAX_SEAMS; ++seam) {
        at = from + dir * len;
        uint t = cross_triangle_at(at, size);
        if (t > 0u && crossings[t - 1u].w == chart)
            return true;
        // The last point on the chart, to within two texels.
        float on = 0.0, off = len;
        while (off - on >= 2.0) {
            float mid = floor(0.5 * (on + off));
            t = cross_triangle_at(from + dir * mid, size);
            if (t > 0u && crossings[t - 1u].w == chart) {
                on = mid;
                triangle = t;
            } else {
                off = mid;
            }
        }
        Walk w;
        w.t = triangle - 1u;
        w.entered = 3u;
        w.side = side;
        cross_from_atlas(w.t, from + dir * on, dir, fsize, w.x, w.d);
        if (dot(w.d, w.d) == 0.0)
            return false;
        float left;
        int walked = cross_walk(w, (len - on) * mm_per_texel, left);
        if (walked == 0)
            return false;
        vec2 texels_per_mm, unused;
        cross_to_atlas(w.t, w.x, w.d, fsize, from, texels_per_mm);
        cross_to_atlas(w.t, w.x, w.side, fsize, unused, side_texels);
        side = w.side;
        landed = crossings[w.t].w;
        if (walked == 1) {
            at = from;
            return true;
        }
        float per_mm = length(texels_per_mm);
        if (!(per_mm > 0.0))
            return false;
        triangle = w.t + 1u;
        chart = landed;
        dir = texels_per_mm / per_mm;
        mm_per_texel = 1.0 / per_mm;
        len = left * per_mm;
        if (seam == 0)
            first = CrossSeam(true, triangle, side, from, dir, per_mm, total_mm - left, chart, side_texels);
    }
    return false;
}

// A tap `mm` from the texel on a side whose line crossed its first seam at
// `s`: where it lies, when that is on the chart across (true); false
// where it needs cross_tap (before the seam, or, from the seam on, past
// that chart).
bool cross_after(CrossSeam s, float mm, ivec2 size, out vec2 at)
{
    at = s.from + s.dir * ((mm - s.done_mm) * s.per_mm);
    if (!s.valid || mm < s.done_mm)
        return false;
    uint t = cross_triangle_at(at, size);
    return t > 0u && crossings[t - 1u].w == s.chart;
}
