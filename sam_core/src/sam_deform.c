/* Deformers and their CPU reference (formulas in sam_deform.h; the GPU's
 * copy is shaders/deform.comp). */
#include "sam/sam_deform.h"

#include <math.h>
#include <string.h>

#define TWO_PI 6.28318530717958647692

static const char *const deformer_names[] = {"bend", "twist", "squash", "wave"};

const char *sam_deformer_type_name(sam_deformer_type type)
{
    return (unsigned)type < sizeof deformer_names / sizeof deformer_names[0] ? deformer_names[type] : "unknown";
}

double sam_deform_strength(const sam_deformer *deformer, double time_s)
{
    return deformer->period_s > 0 ? sin(TWO_PI * time_s / deformer->period_s) : 1.0;
}

static double dot3d(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

int sam_deform_prepare(const sam_deformer *deformers, size_t count, double time_s, sam_deform_step *steps)
{
    int any = 0;
    for (size_t i = 0; i < count; ++i) {
        const sam_deformer *d = &deformers[i];
        sam_deform_step *s = &steps[i];
        memset(s, 0, sizeof *s);
        s->type = d->type;
        memcpy(s->axis, d->axis, sizeof s->axis);
        memcpy(s->direction, d->direction, sizeof s->direction);
        memcpy(s->center, d->center, sizeof s->center);
        double strength = sam_deform_strength(d, time_s);
        switch (d->type) {
        case SAM_DEFORM_BEND:
        case SAM_DEFORM_TWIST:
            s->param[0] = (float)(strength * d->angle_deg * (TWO_PI / 360.0) / d->length);
            s->identity = s->param[0] == 0.0f;
            if (d->type == SAM_DEFORM_BEND) {
                /* The arc's plane needs a direction exactly across the axis. */
                double a[3] = {d->axis[0], d->axis[1], d->axis[2]};
                double n[3] = {d->direction[0], d->direction[1], d->direction[2]};
                double along = dot3d(a, n);
                for (int k = 0; k < 3; ++k)
                    n[k] -= along * a[k];
                double len = sqrt(dot3d(n, n));
                for (int k = 0; k < 3; ++k)
                    s->direction[k] = (float)(n[k] / len);
            }
            break;
        case SAM_DEFORM_SQUASH:
            s->param[0] = (float)(1.0 + strength * d->amount);
            s->param[1] = (float)(1.0 / sqrt((double)s->param[0]));
            s->identity = s->param[0] == 1.0f;
            break;
        case SAM_DEFORM_WAVE: {
            s->param[0] = (float)(strength * d->amplitude);
            s->param[1] = (float)(TWO_PI / d->wavelength);
            /* Reduced in double so a long-running animation keeps its phase exact in float. */
            double phase = fmod(-TWO_PI * d->speed * time_s / d->wavelength, TWO_PI);
            s->param[2] = (float)(phase < 0 ? phase + TWO_PI : phase);
            s->identity = s->param[0] == 0.0f;
            break;
        }
        }
        any |= !s->identity;
    }
    return any;
}

/* One step on one point (v = p - center for every type but wave). */
static void deform_point(const sam_deform_step *s, double p[3])
{
    double a[3], n[3], v[3];
    for (int k = 0; k < 3; ++k) {
        a[k] = s->axis[k];
        n[k] = s->direction[k];
        v[k] = p[k] - s->center[k];
    }
    double u = dot3d(v, a);
    switch (s->type) {
    case SAM_DEFORM_BEND: {
        double w = dot3d(v, n), k = s->param[0], phi = k * u, sn = sin(phi), cs = cos(phi), h = sin(0.5 * phi);
        /* sin(phi) / k and 2 sin^2(phi / 2) / k stay exact as k -> 0, where
         * the arc's radius 1 / k does not. */
        double along = sn / k - w * sn, across = w * cs + 2.0 * h * h / k;
        for (int i = 0; i < 3; ++i)
            p[i] = s->center[i] + (v[i] - u * a[i] - w * n[i]) + along * a[i] + across * n[i];
        break;
    }
    case SAM_DEFORM_TWIST: {
        double phi = s->param[0] * u, sn = sin(phi), cs = cos(phi);
        double c[3] = {a[1] * v[2] - a[2] * v[1], a[2] * v[0] - a[0] * v[2], a[0] * v[1] - a[1] * v[0]};
        for (int i = 0; i < 3; ++i)
            p[i] = s->center[i] + v[i] * cs + c[i] * sn + a[i] * u * (1.0 - cs);
        break;
    }
    case SAM_DEFORM_SQUASH:
        for (int i = 0; i < 3; ++i)
            p[i] = s->center[i] + u * s->param[0] * a[i] + (v[i] - u * a[i]) * s->param[1];
        break;
    case SAM_DEFORM_WAVE: {
        double offset = s->param[0] * sin(s->param[1] * dot3d(p, a) + s->param[2]);
        for (int i = 0; i < 3; ++i)
            p[i] += offset * n[i];
        break;
    }
    }
}

void sam_deform_positions(const sam_deform_step *steps, size_t step_count, const float *in, float *out,
                          size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        double p[3] = {in[3 * i], in[3 * i + 1], in[3 * i + 2]};
        for (size_t k = 0; k < step_count; ++k)
            if (!steps[k].identity)
                deform_point(&steps[k], p);
        for (int k = 0; k < 3; ++k)
            out[3 * i + k] = (float)p[k];
    }
}
