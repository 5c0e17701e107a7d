/*
 * ref/lightprobe_ref.h - double-precision light-probe sampling, written from the conventions in
 * core/include/qibl/lightprobe.h and the papers (Madsen & Laursen section 3.1 and 4.2; Debevec's
 * median cut; Viriyothai & Debevec's variance minimisation), not from the integer code: libm sin,
 * long double summed-area tables, plain loops. Hosted; the ground truth for tests/lightprobe_test.c
 * and the quality columns of `qibl bench lights` and `qibl lights --error`.
 *
 * Irradiance is luminance irradiance: E(n) = sum over pixels of L(u, v) sin(theta_v) 2 pi^2 / (W H)
 * max(0, n . w(u, v)), with the core's Q16 luminance weights.
 */
#ifndef QTOOL_REF_LIGHTPROBE_REF_H
#define QTOOL_REF_LIGHTPROBE_REF_H

#define QTOOL_REF_LUMA_R (13933.0 / 65536.0)
#define QTOOL_REF_LUMA_G (46871.0 / 65536.0)
#define QTOOL_REF_LUMA_B (4732.0 / 65536.0)

typedef struct qtool_ref_probe {
    int w, h;
    double *rgb;        /* 3 w h radiance values P, rows top first */
    long double *sat;   /* (w + 1)(h + 1) SAT of L sin(theta) */
    long double *mom;   /* 5 (w + 1)(h + 1): SATs of e, e u, e u^2, e v, e v^2 (e = L sin theta) */
    double *rowsin;     /* h: sin(theta_v) */
} qtool_ref_probe;

/* Copies rgb (3 w h doubles) and builds the tables. Returns 0, or -1 (bad size, out of memory). */
int qtool_ref_probe_init(qtool_ref_probe *p, int w, int h, const double *rgb);
void qtool_ref_probe_free(qtool_ref_probe *p);

/* Direction of pixel-space point (x, y) (pixel centres at integer + 0.5). */
void qtool_ref_probe_dir(const qtool_ref_probe *p, double x, double y, double d[3]);

/* sum of L sin(theta) over [u0, u1) x [v0, v1), by direct summation in long double */
long double qtool_ref_probe_energy(const qtool_ref_probe *p, int u0, int v0, int u1, int v1);

/* per-channel irradiance of the region: sum of P sin(theta) 2 pi^2 / (W H) */
void qtool_ref_probe_rgb(const qtool_ref_probe *p, int u0, int v0, int u1, int v1, double rgb[3]);

/* direction to the energy centroid (centre = 0) or geometric centre (centre = 1) of a region */
void qtool_ref_probe_place(const qtool_ref_probe *p, int u0, int v0, int u1, int v1, int centre, double d[3]);

typedef struct qtool_ref_light {
    int u0, v0, u1, v1;
    double dir[3], rgb[3];
} qtool_ref_light;

enum { QTOOL_REF_MEDIANCUT = 0, QTOOL_REF_ADAPTIVE = 1, QTOOL_REF_VARMIN = 2 };
enum { QTOOL_REF_PRI_DEFAULT = 0, QTOOL_REF_PRI_ENERGY, QTOOL_REF_PRI_ENERGY_SIZE, QTOOL_REF_PRI_VARIANCE,
       QTOOL_REF_PRI_LEVELS };

/* The samplers, with the core's rules (cut along the longer side on the sphere, median to one pixel
 * with ties to the smaller cut, halves without energy dropped, greedy order by key then (v0, u0)),
 * in double. Lights come out brightest first. Returns the count (>= 0), -1 on bad arguments. */
int qtool_ref_lights(const qtool_ref_probe *p, int method, int priority, int centre, int max, qtool_ref_light *out);

/* n directions spread evenly over the sphere (spherical Fibonacci lattice) */
void qtool_ref_sphere_dirs(int n, double (*d)[3]);

/* E(n) of the probe for n normals, luminance, exact sum over pixels (threads > 1 splits the work) */
void qtool_ref_probe_irradiance(const qtool_ref_probe *p, int n, const double (*normals)[3], double *E, int threads);

/* E(n) of a light list: sum luminance(rgb_i) max(0, n . d_i) */
double qtool_ref_lights_irradiance(const qtool_ref_light *l, int count, const double n[3]);

/* Irradiance error of a light list against the probe's E over the normals: mean and max of
 * |E_lights - E_probe| divided by the mean of E_probe over the sphere (Madsen's "percent" measure). */
void qtool_ref_irradiance_error(const qtool_ref_light *l, int count, int n, const double (*normals)[3],
                               const double *E_probe, double *mean_err, double *max_err);

#endif
