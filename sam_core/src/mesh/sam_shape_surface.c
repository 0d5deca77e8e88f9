#include <stdlib.h>
#include <string.h>

#include "sam_shape_internal.h"

#define SHAPE_PI 3.14159265358979323846

/* Ear geometry, relative to the height: the inner edge of the plate is an
 * ellipse arc; the plate leaves it tilted out of plane, then curls. */
#define EAR_ELLIPSE_X 0.20
#define EAR_ELLIPSE_Y 0.30
#define EAR_PHI0 (50.0 * SHAPE_PI / 180.0)
#define EAR_PHI1 (300.0 * SHAPE_PI / 180.0)
#define EAR_FLAT 0.12
#define EAR_CURL 0.13
#define EAR_TILT (20.0 * SHAPE_PI / 180.0)
#define EAR_CURL_ANGLE 2.2 /* radians at the top of the rim */
#define EAR_LOBE_CURL 0.3  /* fraction of the curl angle left at the lobe */

/* Perforated plate: hole radius as a fraction of the holes' pitch. */
#define PERFORATED_HOLE_RADIUS 0.3

/* Torus: the hole must stay open. */
#define TORUS_MAX_RELATIVE_THICKNESS 0.45
/* Knot: tube radius at most this fraction of the tube's geometric limit. */
#define KNOT_SAFETY 0.9
#define KNOT_LIMIT_SAMPLES 600
#define KNOT_ARC_SAMPLES 8192

/* ---------------------------------------------------------------- random */

/* splitmix64: small, fast and good enough for placing blobs; the state is the
 * caller's, so generation stays reentrant. */
static uint64_t rng_next(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double rng_uniform(uint64_t *state, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(rng_next(state) >> 11) * (1.0 / 9007199254740992.0));
}

static void rng_unit_vector(uint64_t *state, double o[3])
{
    double z = rng_uniform(state, -1.0, 1.0);
    double a = rng_uniform(state, 0.0, 2.0 * SHAPE_PI);
    double r = sqrt(fmax(0.0, 1.0 - z * z));
    v3_set(o, r * cos(a), r * sin(a), z);
}

/* ---------------------------------------------------------------- surfaces */

/* Equal-angle cube-sphere direction of lattice point c on a cube of n
 * segments per edge. */
static void cube_direction(const int c[3], int n, double d[3])
{
    for (int k = 0; k < 3; ++k)
        d[k] = tan(SHAPE_PI / 4.0 * (2.0 * c[k] / n - 1.0));
    v3_normalize(d);
}

static double ear_curl_angle(double s)
{
    double x = (s - 0.6) / 0.4;
    x = x < 0 ? 0 : (x > 1 ? 1 : x);
    double smooth = x * x * (3.0 - 2.0 * x);
    return EAR_CURL_ANGLE * (1.0 - (1.0 - EAR_LOBE_CURL) * smooth);
}

/* Mid-surface of the ear: s along the C, t across from the inner edge. */
static void ear_mid(double height, double s, double t, double o[3])
{
    double phi = EAR_PHI0 + s * (EAR_PHI1 - EAR_PHI0);
    double ax = EAR_ELLIPSE_X * height, ay = EAR_ELLIPSE_Y * height;
    double flat = EAR_FLAT * height, curl = EAR_CURL * height;
    double out[3] = {ay * cos(phi), ax * sin(phi), 0.0};
    v3_normalize(out);
    double l = t * (flat + curl);
    double r, z;
    if (l <= flat) {
        r = l * cos(EAR_TILT);
        z = l * sin(EAR_TILT);
    } else {
        double kappa = ear_curl_angle(s) / curl;
        double m = l - flat;
        r = flat * cos(EAR_TILT) + (sin(EAR_TILT + kappa * m) - sin(EAR_TILT)) / kappa;
        z = flat * sin(EAR_TILT) + (cos(EAR_TILT) - cos(EAR_TILT + kappa * m)) / kappa;
    }
    v3_set(o, ax * cos(phi) + r * out[0], ay * sin(phi) + r * out[1], z);
}

static void ear_point(const sam_shape_surface *sf, double s, double t, double offset, double o[3])
{
    const double e = 1e-5;
    double a[3], b[3], c[3], d[3], ds[3], dt[3], nrm[3];
    ear_mid(sf->size, s + e, t, a);
    ear_mid(sf->size, s - e, t, b);
    ear_mid(sf->size, s, t + e, c);
    ear_mid(sf->size, s, t - e, d);
    for (int k = 0; k < 3; ++k) {
        ds[k] = a[k] - b[k];
        dt[k] = c[k] - d[k];
    }
    v3_cross(ds, dt, nrm);
    v3_normalize(nrm);
    ear_mid(sf->size, s, t, o);
    for (int k = 0; k < 3; ++k)
        o[k] += offset * nrm[k];
}

static void knot_curve(const sam_shape_surface *sf, double phi, double p[3], double dp[3])
{
    double R = sf->major, r = sf->minor;
    double rho = R + r * cos(3 * phi), drho = -3 * r * sin(3 * phi);
    v3_set(p, rho * cos(2 * phi), rho * sin(2 * phi), r * sin(3 * phi));
    v3_set(dp, drho * cos(2 * phi) - 2 * rho * sin(2 * phi),
           drho * sin(2 * phi) + 2 * rho * cos(2 * phi), 3 * r * cos(3 * phi));
}

/* Tube point at segment i along the centre line and j around it. The normal
 * N is the direction from the torus core circle to the curve, which is
 * exactly perpendicular to the tangent for both the torus and the knot, so
 * the frame closes on itself without twist correction. */
static void tube_point(const sam_shape_surface *sf, int i, int j, double o[3])
{
    double p[3], t[3], nrm[3], b[3];
    if (sf->map == MAP_TORUS) {
        double phi = 2.0 * SHAPE_PI * i / sf->n[0];
        v3_set(p, sf->major * cos(phi), sf->major * sin(phi), 0.0);
        v3_set(t, -sin(phi), cos(phi), 0.0);
        v3_set(nrm, cos(phi), sin(phi), 0.0);
    } else {
        double phi = sf->knot_phi[i];
        knot_curve(sf, phi, p, t);
        v3_set(nrm, cos(3 * phi) * cos(2 * phi), cos(3 * phi) * sin(2 * phi), sin(3 * phi));
    }
    v3_normalize(t);
    v3_cross(t, nrm, b);
    double theta = 2.0 * SHAPE_PI * j / sf->n[1];
    double c = cos(theta), s = sin(theta);
    for (int k = 0; k < 3; ++k)
        o[k] = p[k] + sf->radius * (c * nrm[k] + s * b[k]);
}

static double blob_radius_factor(const sam_shape_surface *sf, const double d[3])
{
    double rho = 1.0;
    for (int m = 0; m < BLOB_BUMPS; ++m) {
        double w = sf->bump_width[m];
        rho += sf->bump_amp[m] * exp((v3_dot(d, sf->bump_dir[m]) - 1.0) / (w * w));
    }
    return rho;
}

/* The perforated plate's x (or z) at lattice index g, 0..holes * n[0]
 * along the width: every face, wall and rim that meets at a point reaches it
 * through the same integers. */
static double plate_coord(const sam_shape_surface *sf, int g)
{
    return -sf->half[0] + (2.0 * sf->half[0]) * ((double)g / (sf->holes * sf->n[0]));
}

static double plate_y(const sam_shape_surface *sf, int j)
{
    return -sf->half[1] + (2.0 * sf->half[1]) * ((double)j / sf->n[1]);
}

/* Lattice point g = (x, z) at step i (0..4 side - 1) around the square of
 * `side` segments with corner (x0, z0), starting there along +x. */
static void square_step(int x0, int z0, int side, int i, int g[2])
{
    static const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    static const int along[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    int s = i / side, t = i % side;
    g[0] = x0 + side * corner[s][0] + t * along[s][0];
    g[1] = z0 + side * corner[s][1] + t * along[s][1];
}

/* Point (i, j) of a perforated plate chart (see add_perforated_charts): a
 * ring blends the hole's circle (j = 0) into its cell's square (j = n[2]),
 * matching angle steps to square steps, so both ends are exactly the wall's
 * and the neighbouring cells' points. */
static void perforated_point(const sam_shape_surface *sf, int face, int i, int j, double o[3])
{
    int m = sf->n[0], hole = face / PERFORATED_PARTS, part = face % PERFORATED_PARTS;
    int g[2];
    if (hole == sf->holes * sf->holes) {
        square_step(0, 0, sf->holes * m, i % (4 * sf->holes * m), g);
        v3_set(o, plate_coord(sf, g[0]), plate_y(sf, j), plate_coord(sf, g[1]));
        return;
    }
    int a = hole % sf->holes, b = hole / sf->holes;
    i %= 4 * m;
    /* Step 0 is the cell's corner, at -135 degrees from the hole's centre. */
    double theta = 0.5 * SHAPE_PI * ((double)i / m - 1.5);
    double x = 0.5 * (plate_coord(sf, a * m) + plate_coord(sf, (a + 1) * m)) +
               sf->hole_radius * cos(theta);
    double z = 0.5 * (plate_coord(sf, b * m) + plate_coord(sf, (b + 1) * m)) +
               sf->hole_radius * sin(theta);
    if (part == PERFORATED_WALL) {
        v3_set(o, x, plate_y(sf, j), z);
        return;
    }
    if (j > 0) {
        square_step(a * m, b * m, m, i, g);
        double sx = plate_coord(sf, g[0]), sz = plate_coord(sf, g[1]);
        if (j == sf->n[2]) {
            x = sx;
            z = sz;
        } else {
            double t = (double)j / sf->n[2];
            x += t * (sx - x);
            z += t * (sz - z);
        }
    }
    v3_set(o, x, plate_y(sf, part == PERFORATED_TOP ? sf->n[1] : 0), z);
}

static void box_point(const sam_shape_surface *sf, int face, int i, int j, double o[3])
{
    int a, u, v, c[3];
    face_axes(face, &a, &u, &v);
    c[a] = (face % 2) ? sf->n[a] : 0;
    c[u] = i;
    c[v] = j;
    switch (sf->map) {
    case MAP_SPHERE: {
        double d[3];
        cube_direction(c, sf->n[0], d);
        for (int k = 0; k < 3; ++k)
            o[k] = sf->center[k] + sf->radius * d[k];
        break;
    }
    case MAP_BLOB: {
        double d[3];
        cube_direction(c, sf->n[0], d);
        double r = sf->radius * blob_radius_factor(sf, d);
        for (int k = 0; k < 3; ++k)
            o[k] = sf->center[k] + r * (sf->matrix[3 * k] * d[0] + sf->matrix[3 * k + 1] * d[1] +
                                        sf->matrix[3 * k + 2] * d[2]);
        break;
    }
    case MAP_SLAB:
        for (int k = 0; k < 3; ++k)
            o[k] = -sf->half[k] + (2.0 * sf->half[k]) * ((double)c[k] / sf->n[k]);
        break;
    case MAP_EAR:
        ear_point(sf, (double)c[0] / sf->n[0], (double)c[2] / sf->n[2],
                  ((double)c[1] / sf->n[1] - 0.5) * sf->thickness, o);
        break;
    case MAP_TORUS:
    case MAP_KNOT:
    case MAP_PERFORATED:
        break;
    }
}

void sam_shape_surface_point(const sam_shape_surface *sf, int face, int i, int j, double o[3])
{
    if (sf->map == MAP_PERFORATED)
        perforated_point(sf, face, i, j, o);
    else if (is_tube(sf))
        tube_point(sf, i % sf->n[0], j % sf->n[1], o);
    else
        box_point(sf, face, i, j, o);
}

/* ---------------------------------------------------------------- set-up and limits */

static double ear_max_thickness(double size)
{
    /* The inner side of the curl is offset by thickness/2 toward its centre
     * of curvature; keep it at least half the curl radius away from it. */
    return EAR_CURL * size / EAR_CURL_ANGLE;
}

static void knot_setup(sam_shape_surface *sf, double size)
{
    sf->map = MAP_KNOT;
    sf->major = size / 3.0;
    sf->minor = size / 6.0;
}

/* Largest tube radius of the knot: the smaller of the centre line's least
 * radius of curvature and half the closest approach of distant strands. */
static double knot_max_radius(const sam_shape_surface *sf)
{
    enum { K = KNOT_LIMIT_SAMPLES };
    double p[K][3], dp[3];
    for (int k = 0; k < K; ++k)
        knot_curve(sf, 2.0 * SHAPE_PI * k / K, p[k], dp);
    double closest = HUGE_VAL, curvature_radius = HUGE_VAL;
    for (int a = 0; a < K; ++a) {
        /* Points a quarter period apart or more are different strands. */
        for (int b = a + K / 8; b <= a + K - K / 8 && b < K; ++b) {
            double d = v3_dist(p[a], p[b]);
            if (d < closest)
                closest = d;
        }
        const double *q0 = p[(a + K - 1) % K], *q1 = p[a], *q2 = p[(a + 1) % K];
        double e0 = v3_dist(q0, q1), e1 = v3_dist(q1, q2), e2 = v3_dist(q2, q0);
        double u[3] = {q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]};
        double v[3] = {q2[0] - q0[0], q2[1] - q0[1], q2[2] - q0[2]};
        double x[3];
        v3_cross(u, v, x);
        double twice_area = sqrt(v3_dot(x, x));
        if (twice_area > 0) {
            double rc = e0 * e1 * e2 / (2.0 * twice_area);
            if (rc < curvature_radius)
                curvature_radius = rc;
        }
    }
    double r = 0.5 * closest < curvature_radius ? 0.5 * closest : curvature_radius;
    return KNOT_SAFETY * r;
}

double sam_shape_thickness_limit(int shape, double size)
{
    switch (shape) {
    case SHAPE_SLAB:
    case SHAPE_PERFORATED: return HUGE_VAL;
    case SHAPE_TORUS: return TORUS_MAX_RELATIVE_THICKNESS * size;
    case SHAPE_EAR: return ear_max_thickness(size);
    case SHAPE_KNOT: {
        sam_shape_surface sf;
        memset(&sf, 0, sizeof sf);
        knot_setup(&sf, size);
        return 2.0 * knot_max_radius(&sf);
    }
    default: return 0.0;
    }
}

static int segments_for(double length, double spacing, int minimum)
{
    double n = floor(length / spacing + 0.5);
    if (n < minimum)
        return minimum;
    if (n > SAM_SHAPE_MAX_RESOLUTION)
        return SAM_SHAPE_MAX_RESOLUTION;
    return (int)n;
}

static void blob_setup(sam_shape_surface *sf, int n, const double cell_center[3], double cell,
                       uint64_t *rng)
{
    sf->map = MAP_BLOB;
    sf->n[0] = sf->n[1] = sf->n[2] = n;
    /* Random rotation from a unit quaternion (Shoemake), random axis scales. */
    double u1 = rng_uniform(rng, 0, 1), u2 = rng_uniform(rng, 0, 2 * SHAPE_PI),
           u3 = rng_uniform(rng, 0, 2 * SHAPE_PI);
    double qw = sqrt(1 - u1) * sin(u2), qx = sqrt(1 - u1) * cos(u2), qy = sqrt(u1) * sin(u3),
           qz = sqrt(u1) * cos(u3);
    double rot[9] = {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw),
                     2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw),
                     2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)};
    double scale[3], largest = 0.0;
    for (int k = 0; k < 3; ++k) {
        scale[k] = rng_uniform(rng, 0.6, 1.0);
        if (scale[k] > largest)
            largest = scale[k];
    }
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            sf->matrix[3 * r + c] = rot[3 * r + c] * scale[c];
    double bulge = 1.0;
    for (int m = 0; m < BLOB_BUMPS; ++m) {
        rng_unit_vector(rng, sf->bump_dir[m]);
        sf->bump_amp[m] = rng_uniform(rng, -0.2, 0.5);
        sf->bump_width[m] = rng_uniform(rng, 0.35, 0.7);
        if (sf->bump_amp[m] > 0)
            bulge += sf->bump_amp[m];
    }
    /* The blob's bounding sphere (radius * bulge * largest scale) stays
     * inside a cube of 0.9 cell, so blobs in different cells never touch. */
    double room = 0.45 * cell;
    double reach = room * rng_uniform(rng, 0.7, 1.0);
    sf->radius = reach / (bulge * largest);
    for (int k = 0; k < 3; ++k)
        sf->center[k] = cell_center[k] + rng_uniform(rng, -(room - reach), room - reach);
}

sam_status sam_shape_setup_surfaces(int s, const char *name, const sam_shape_params *p,
                                   sam_shape_builder *b, sam_error *err)
{
    size_t count = s == SHAPE_BLOBS ? (size_t)p->count : 1;
    b->surfaces = calloc(count, sizeof *b->surfaces);
    if (!b->surfaces)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape %s: out of memory", name);
    b->surface_count = count;
    sam_shape_surface *sf = b->surfaces;
    int res = p->resolution;
    switch (s) {
    case SHAPE_SPHERE:
        sf->map = MAP_SPHERE;
        sf->n[0] = sf->n[1] = sf->n[2] = (res + 3) / 4;
        sf->radius = 0.5 * p->size;
        break;
    case SHAPE_SLAB: {
        double spacing = p->size / res;
        sf->map = MAP_SLAB;
        sf->n[0] = res;
        sf->n[1] = segments_for(p->thickness, spacing, 1);
        sf->n[2] = segments_for(p->depth, spacing, 1);
        v3_set(sf->half, 0.5 * p->size, 0.5 * p->thickness, 0.5 * p->depth);
        break;
    }
    case SHAPE_TORUS:
        sf->map = MAP_TORUS;
        sf->radius = 0.5 * p->thickness;
        sf->major = 0.5 * p->size - sf->radius;
        sf->n[0] = res;
        sf->n[1] = segments_for(res * sf->radius / sf->major, 1.0, 3);
        break;
    case SHAPE_EAR: {
        sf->map = MAP_EAR;
        sf->size = p->size;
        sf->thickness = p->thickness;
        double length = 0.0, a[3], c[3];
        ear_mid(p->size, 0.0, 0.5, a);
        for (int k = 1; k <= 512; ++k) {
            ear_mid(p->size, k / 512.0, 0.5, c);
            length += v3_dist(a, c);
            memcpy(a, c, sizeof a);
        }
        double spacing = length / res;
        sf->n[0] = res;
        sf->n[1] = segments_for(p->thickness, spacing, 1);
        sf->n[2] = segments_for((EAR_FLAT + EAR_CURL) * p->size, spacing, 2);
        break;
    }
    case SHAPE_KNOT: {
        knot_setup(sf, p->size);
        sf->radius = 0.5 * p->thickness;
        sf->n[0] = res;
        /* Arc-length parameterisation, so segments have equal length. */
        double *cum = malloc((KNOT_ARC_SAMPLES + 1) * sizeof *cum);
        b->knot_phi = malloc((size_t)res * sizeof *b->knot_phi);
        if (!cum || !b->knot_phi) {
            free(cum);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape knot: out of memory");
        }
        double q[3], dq[3], prev_speed;
        knot_curve(sf, 0.0, q, dq);
        prev_speed = sqrt(v3_dot(dq, dq));
        cum[0] = 0.0;
        for (int k = 1; k <= KNOT_ARC_SAMPLES; ++k) {
            knot_curve(sf, 2.0 * SHAPE_PI * k / KNOT_ARC_SAMPLES, q, dq);
            double speed = sqrt(v3_dot(dq, dq));
            cum[k] = cum[k - 1] + 0.5 * (speed + prev_speed) * (2.0 * SHAPE_PI / KNOT_ARC_SAMPLES);
            prev_speed = speed;
        }
        double length = cum[KNOT_ARC_SAMPLES];
        int k = 0;
        for (int i = 0; i < res; ++i) {
            double target = length * i / res;
            while (k + 1 < KNOT_ARC_SAMPLES && cum[k + 1] <= target)
                ++k;
            double f = (target - cum[k]) / (cum[k + 1] - cum[k]);
            b->knot_phi[i] = 2.0 * SHAPE_PI * (k + f) / KNOT_ARC_SAMPLES;
        }
        free(cum);
        sf->knot_phi = b->knot_phi;
        sf->n[1] = segments_for(2.0 * SHAPE_PI * sf->radius, length / res, 6);
        break;
    }
    case SHAPE_PERFORATED: {
        int m = (int)floor((double)res / p->count + 0.5);
        double pitch = p->size / p->count;
        sf->map = MAP_PERFORATED;
        sf->holes = p->count;
        sf->hole_radius = PERFORATED_HOLE_RADIUS * pitch;
        sf->n[0] = m < 2 ? 2 : m;
        sf->n[1] = segments_for(p->thickness, pitch / sf->n[0], 1);
        sf->n[2] = segments_for(0.5 * pitch - sf->hole_radius, pitch / sf->n[0], 1);
        v3_set(sf->half, 0.5 * p->size, 0.5 * p->thickness, 0.5 * p->size);
        break;
    }
    case SHAPE_BLOBS: {
        int g = 1;
        while (g * g * g < p->count)
            ++g;
        int cells = g * g * g;
        int *order = malloc((size_t)cells * sizeof *order);
        if (!order)
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "shape blobs: out of memory");
        for (int c = 0; c < cells; ++c)
            order[c] = c;
        uint64_t rng = p->seed;
        for (int c = cells - 1; c > 0; --c) {
            int r = (int)(rng_next(&rng) % (uint64_t)(c + 1));
            int t = order[c];
            order[c] = order[r];
            order[r] = t;
        }
        double cell = p->size / g;
        for (int k = 0; k < p->count; ++k) {
            int c = order[k];
            double centre[3] = {(c % g + 0.5) * cell - 0.5 * p->size,
                                ((c / g) % g + 0.5) * cell - 0.5 * p->size,
                                (c / (g * g) + 0.5) * cell - 0.5 * p->size};
            blob_setup(&b->surfaces[k], (res + 3) / 4, centre, cell, &rng);
        }
        free(order);
        break;
    }
    default:
        break;
    }
    return SAM_OK;
}
