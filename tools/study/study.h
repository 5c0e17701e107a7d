/*
 * study/study.h - the light-probe approximation study (Madsen & Laursen, extended): ground-truth
 * irradiance of a lat-long probe over a spherical Fibonacci set of normals, every method that
 * replaces the probe by N directional lights or by SH, their irradiance errors, and the plots and
 * summary of `qibl study` and the recommendation of `qibl lights --auto`. Hosted, double.
 *
 * Conventions: those of qibl/lightprobe.h (pixel (u, v) at theta = (v + 1/2) pi / H, phi =
 * (u + 1/2) 2 pi / W; Q(u, v) = P(u, v) sin theta_v 2 pi^2 / (W H), Madsen's eq. 4). Irradiance is
 * per channel (RGB); a light's rgb is the irradiance it gives a surface facing it.
 */
#ifndef QTOOL_STUDY_H
#define QTOOL_STUDY_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "qibl/lightprobe.h"

#define QTOOL_STUDY_MAX_LIGHTS 256
#define QTOOL_STUDY_SH_MAX 25
#define QTOOL_STUDY_FLOATS_PER_LIGHT 6 /* dir xyz + rgb, as qibl stores a light */

/* ---- probe and ground truth (gt.c) ----------------------------------------------------------- */

/* The widest probe the study evaluates: a wider lat-long is box-averaged to QTOOL_STUDY_MAX_W x
 * QTOOL_STUDY_MAX_W / 2 first (energy kept), so ground truth, SH and lights cost O(input pixels) to
 * read plus a fixed amount, whatever the input's size (irradiance is smooth: a 1024 x 512 probe
 * holds it to a fraction of a per cent, see qtool_study_gt_accuracy). */
#define QTOOL_STUDY_MAX_W 1024

typedef struct qtool_study_probe {
    int w, h;        /* the size evaluated (at most QTOOL_STUDY_MAX_W wide) */
    int src_w, src_h; /* the size given */
    uint8_t *rgbe;   /* the RGBE bytes the core samples (w h 4) */
    double *q;       /* 3 w h: Q per channel */
} qtool_study_probe;

/* From RGBE bytes (copied, or box-averaged when wider than QTOOL_STUDY_MAX_W). 0, or -1 with a
 * one-line reason (size not 2:1 / too small / memory). */
int qtool_study_probe_init(qtool_study_probe *p, int w, int h, const uint8_t *rgbe, char *err, size_t errlen);

/* 0 when the probe has light somewhere; -1 with "the probe is black everywhere: …" in err (the
 * study's errors are relative: such a probe would make every one 0 / 0, printed as NaN). */
int qtool_study_probe_lit(const qtool_study_probe *p, char *err, size_t errlen);
void qtool_study_probe_free(qtool_study_probe *p);

/* Ground truth: m normals, their irradiance E[3 m] (channel-major per normal: E[3 k + c]), the
 * mean per channel, and the SH basis at every normal (Y[25 k + i]). */
typedef struct qtool_study_gt {
    int m;
    double (*nrm)[3];
    double *E;
    double mean[3];
    double *Y;
} qtool_study_gt;

/* Irradiance of the whole probe at m Fibonacci normals: eq. 4 over every pixel, evaluated row by
 * row (the lit pixels of a row for a normal are one arc of phi, so each row costs O(1) per normal
 * from prefix sums of Q, Q cos phi, Q sin phi), threads > 1 splitting the rows. 0 or -1 (memory). */
int qtool_study_gt_compute(qtool_study_gt *g, const qtool_study_probe *p, int m, int threads);
void qtool_study_gt_free(qtool_study_gt *g);

/* The plain pixel sum of eq. 4 (long double) at one normal: what gt_compute must equal. */
void qtool_study_gt_brute(const qtool_study_probe *p, const double n[3], double E[3]);

/* Accuracy of gt_compute: the largest relative difference to gt_brute over `count` of the normals
 * (spread evenly), and (when p is at least 4 x 2) the mean relative difference to the irradiance of
 * the probe box-downsampled 2x (the discretisation of the probe itself, for scale). */
void qtool_study_gt_accuracy(const qtool_study_gt *g, const qtool_study_probe *p, int count, double *max_vs_brute,
                             double *mean_vs_half);

/* ---- a model: lights plus optional SH irradiance, and its error (model.c) --------------------- */

typedef struct qtool_study_model {
    int n;                                   /* lights */
    double dir[QTOOL_STUDY_MAX_LIGHTS][3];   /* unit */
    double rgb[QTOOL_STUDY_MAX_LIGHTS][3];   /* irradiance facing the light */
    int sh_n;                                /* 0, 4, 9, 16 or 25 SH irradiance coefficients */
    double sh[3][QTOOL_STUDY_SH_MAX];
} qtool_study_model;

/* The irradiance error of qibl (one measure, printed by `qibl lights --auto`, `qibl probe info` and
 * `qibl study`): per normal and channel |E - E_gt| / max(E_gt, QTOOL_STUDY_ERR_FLOOR mean(E_gt)),
 * its mean and max over the normals and channels. Relative where the probe lights the normal, and
 * floored at a tenth of the mean irradiance where it leaves it near black, so a dark side cannot
 * blow the figure up (without the floor 1e-13 of light on a normal gave 10^13 %). Over
 * QTOOL_STUDY_ERR_NORMALS Fibonacci normals. */
#define QTOOL_STUDY_ERR_FLOOR 0.1
#define QTOOL_STUDY_ERR_NORMALS 4000
#define QTOOL_STUDY_ERR_WHAT "|E - E_probe| / max(E_probe, mean E_probe / 10), per normal and channel"

typedef struct qtool_study_err {
    double mean_rel, max_rel;   /* the measure above */
    double mean_norm, max_norm; /* |E - E_gt| / mean(E_gt) of the channel */
} qtool_study_err;

/* Floats stored: 6 per light, 3 per SH coefficient. */
int qtool_study_model_numbers(const qtool_study_model *md);
/* E[3] of the model at normal k of g */
void qtool_study_model_eval(const qtool_study_model *md, const qtool_study_gt *g, int k, double E[3]);
void qtool_study_model_error(const qtool_study_model *md, const qtool_study_gt *g, qtool_study_err *e);

/* ---- non-negative least squares (nnls.c) ------------------------------------------------------ */

/* min |A x - b| subject to x >= 0 for A (rows x n, row-major) by Lawson-Hanson's active set on the
 * normal equations G = A^T A, h = A^T b (given: n x n and n). x gets n values. Returns the number of
 * outer iterations, or -1 (n outside 1..QTOOL_STUDY_MAX_LIGHTS, memory, or no convergence in 3 n
 * iterations: x is then the last feasible point). */
int qtool_study_nnls(int n, const double *G, const double *h, double *x);
/* Solves L L^T x = b in place (b becomes x): L lower triangular, k x k, row-major, as a Cholesky
 * factorisation leaves it; forward then back substitution. */
void qtool_study_chol_solve(const double *L, int k, double *b);

/* Refit: keeps md's directions and sets every light's RGB by NNLS against g's irradiance (rows
 * weighted by 1 / (E_gt + mean E_gt / 10), so relative error dominates where E is large, absolute
 * where it is near zero). md->sh_n must be 0. 0, or -1. */
int qtool_study_refit(qtool_study_model *md, const qtool_study_gt *g);

/* ---- methods (methods.c, kmeans.c, irropt.c, sunsky.c) ---------------------------------------- */

/* The methods in value order (0 up) as X(name, text): the one list the enum and
 * qtool_study_method_name's names are made from. */
#define QTOOL_STUDY_METHOD_LIST(X)                                                                        \
    X(QTOOL_STUDY_MEDIANCUT, "mediancut")                                                                 \
    X(QTOOL_STUDY_ADAPTIVE, "adaptive")                                                                   \
    X(QTOOL_STUDY_VARMIN, "varmin")                                                                       \
    X(QTOOL_STUDY_SH, "sh")                                                                               \
    X(QTOOL_STUDY_REFIT_MC, "refit-mc")                                                                   \
    X(QTOOL_STUDY_REFIT_VM, "refit-vm")                                                                   \
    X(QTOOL_STUDY_SUNSKY, "sun+sky")                                                                      \
    X(QTOOL_STUDY_KMEANS, "kmeans")                                                                       \
    X(QTOOL_STUDY_IRROPT, "irropt")

enum {
#define QTOOL_STUDY_METHOD_ENUM_(name, text) name,
    QTOOL_STUDY_METHOD_LIST(QTOOL_STUDY_METHOD_ENUM_)
#undef QTOOL_STUDY_METHOD_ENUM_
    QTOOL_STUDY_METHOD_COUNT
};

/* the method's name from QTOOL_STUDY_METHOD_LIST, "?" for another number */
const char *qtool_study_method_name(int method);

/* The core's lights of p by method m (qibl_lightprobe_build and _lights, workspace on the heap):
 * at most n into L, *res their count and exponent. 0, or -1 with "what: reason" in err. */
int qtool_study_probe_lights(const qtool_study_probe *p, qibl_lightprobe_method_t m, qibl_lightprobe_light_t *L, int n,
                             qibl_lightprobe_result_t *res, const char *what, char *err, size_t errlen);
/* The core's samplers (method MEDIANCUT, ADAPTIVE, VARMIN) with n lights into md; 0, or -1 with a
 * reason (core status). */
int qtool_study_core_lights(const qtool_study_probe *p, int method, int n, qtool_study_model *md, char *err,
                            size_t errlen);

/* The core's SH irradiance projection (qibl_probe_sh_project, irradiance on) with coeffs = 4, 9, 16
 * or 25; 0 or -1. */
int qtool_study_core_sh(const qtool_study_probe *p, int coeffs, qtool_study_model *md, char *err, size_t errlen);

/* LightGen-style clustering: energy-weighted spherical k-means of the pixel directions (of the
 * probe box-averaged to at most 256 x 128), k-means++ seeding from a fixed seed, up to `iters`
 * Lloyd rounds; lights at the clusters' energy centroids with their summed Q. 0 or -1. */
int qtool_study_kmeans(const qtool_study_probe *p, int n, int iters, qtool_study_model *md);

/* Irradiance optimisation (Madsen et al. 2003): Levenberg-Marquardt on RGB + (theta, phi) per light
 * against the irradiance of `fit` normals of g (spread evenly), weighted as the refit, analytic
 * Jacobian, RGB kept >= 0; md holds the start (e.g. adaptive median cut) and gets the result.
 * *iters gets the iterations run; returns 1 converged (relative cost decrease below 1e-6, or a
 * zero gradient), 0 not converged within max_iter (or the damping ran away), -1 on error. */
int qtool_study_irropt(qtool_study_model *md, const qtool_study_gt *g, int fit, int max_iter, int *iters);

/* Sun plus sky: the k brightest regions of the probe's variance-minimisation lights (64 regions)
 * as lights, the rest of the probe (those regions' pixels taken out) as 9 SH irradiance
 * coefficients (the core's projection minus the regions' own projection). */
int qtool_study_sunsky(const qtool_study_probe *p, int k, qtool_study_model *md, char *err, size_t errlen);

/* The error budget: the smallest k in 0..kmax whose mean relative error is <= budget (then *k_out,
 * *e_out and md are that model, returns 1), else the k of smallest error (returns 0); -1 on error. */
int qtool_study_sunsky_budget(const qtool_study_probe *p, const qtool_study_gt *g, double budget, int kmax,
                              qtool_study_model *md, int *k_out, qtool_study_err *e_out, char *err, size_t errlen);

/* The whole curve k = 0..kmax at once (one build): e[k] and ms[k] (the build plus that k's sky). */
int qtool_study_sunsky_sweep(const qtool_study_probe *p, const qtool_study_gt *g, int kmax, qtool_study_err *e,
                             double *ms, qtool_study_model *at16, char *err, size_t errlen);

/* ---- SVG plots (svg.c) ------------------------------------------------------------------------ */

typedef struct qtool_study_series {
    const char *name;      /* NULL: no legend entry (a dashed max beside its mean) */
    int n;
    const double *x, *y;   /* points; non-finite or non-positive (on a log axis) y break the line */
    int color;             /* index into a fixed palette */
    int dashed;
} qtool_study_series;

/* Writes an SVG line plot: axes with ticks (log axes by decades, or powers of two when log2x), a
 * line per series, a legend. 0, or -1 with a reason (no series, no finite point, file). */
int qtool_study_svg_plot(const char *path, const char *title, const char *xlabel, const char *ylabel, int logx,
                         int log2x, int logy, const qtool_study_series *s, int ns, char *err, size_t errlen);

/* ---- the study and the recommendation (run.c, auto.c) ---------------------------------------- */

typedef struct qtool_study_opts {
    int quick;
    int threads;
    const char *out_dir;
} qtool_study_opts;

/* Runs every method on every probe (paths; none: procedural skies, said on stdout) and writes
 * study.csv, plots, overlays and summary.md into out_dir; prints RESULT lines. 0 or 1. */
int qtool_study_run(const char *const *paths, int np, const qtool_study_opts *o);

/* A procedural sky as RGBE (sunny = 1: a sun 2^14 times the sky; 0: overcast), w x h (2:1). */
uint8_t *qtool_study_procedural(int w, int h, int sunny);

/* What qtool_study_auto picked: the cheapest candidate within the budget (met = 1) or, when none
 * meets it, the most accurate (met = 0); its name, floats stored, mean error (the measure above) and
 * the model itself: lights (unit dir, rgb = irradiance facing the light; refitted RGB where the
 * name says so) plus sh_n SH irradiance coefficients of qibl's real basis (qibl/sh.h order, z-up),
 * E(n) = sum_j rgb_j max(0, n . dir_j) + sum_i sh[c][i] Y_i(n). */
typedef struct qtool_study_pick {
    char what[64];
    int floats;
    double err;
    int met;
    qtool_study_model model;
} qtool_study_pick;

/* The cheapest representation with mean relative error <= budget: SH (4/9/16/25), the core's
 * variance-minimisation lights and their refit (N = 1..256), or sun plus sky. Prints a table of
 * the candidates and the choice with its reason to log (stdout for the text output, stderr when
 * stdout carries the pick as a document); fills *pick (may be NULL). 0 (found), 1 (none meets it:
 * the most accurate is named and picked), -1 on error (*pick untouched). */
int qtool_study_auto(const qtool_study_probe *p, double budget, int threads, FILE *log, qtool_study_pick *pick,
                     char *err, size_t errlen);

#endif
