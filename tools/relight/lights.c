/*
 * relight/lights.c - `qibl lights`'s computation (lights.h): the probe to lat-long, its lights by
 * the integer core, the picture, the irradiance error and the --auto pick.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/hdr.h"
#include "qibl/srgbe.h"
#include "qtool.h"
#include "ref/lightprobe_ref.h"
#include "relight/light.h"
#include "relight/lights.h"

static double rgbe_f(uint8_t m, uint8_t e)
{
    return e ? ldexp(m, e - 136) : 0.0;
}

int qtool_relight_lights_load(const char *path, qtool_probe_layout_t want, qtool_relight_lights_probe *p,
                              char *note, size_t notelen, char *err, size_t errlen)
{
    int w, h;
    uint8_t *px;
    char why[512];
    qtool_probe_layout_t used;
    memset(p, 0, sizeof *p);
    if (qtool_hdr_read_rgbe(path, &w, &h, &px, why, sizeof why) != 0)
        return qtool_errf(err, errlen, "%s", why);
    int rc = qtool_probe_layout_rgbe_to_latlong(want, w, h, px, &used, &p->w, &p->h, &p->px, why, sizeof why);
    free(px);
    if (rc != 0)
        return qtool_errf(err, errlen, "%s: %s", path, why);
    qtool_relight_probe_note(path, want, used, w, h, p->w, p->h, note, notelen);
    return 0;
}

void qtool_relight_lights_probe_free(qtool_relight_lights_probe *p)
{
    free(p->px);
    p->px = NULL;
}

int qtool_relight_lights_zoom(int w, int h, long zoom)
{
    (void)h;
    return zoom ? (int)zoom : (w >= 512 ? 1 : (1024 + w - 1) / w);
}

int qtool_relight_lights_zoom_fits(int w, int h, int z)
{
    uint64_t pw = (uint64_t)w * (uint64_t)z, ph = (uint64_t)h * (uint64_t)z;
    return pw > QTOOL_RELIGHT_LIGHTS_PNG_MAX_SIDE || ph > QTOOL_RELIGHT_LIGHTS_PNG_MAX_SIDE ||
                   pw * ph > QTOOL_RELIGHT_LIGHTS_PNG_MAX_PIXELS
               ? -1
               : 0;
}

uint64_t qtool_relight_lights_max_zoom(int w, int h)
{
    uint64_t z = 1;
    while ((uint64_t)w * (z + 1) <= QTOOL_RELIGHT_LIGHTS_PNG_MAX_SIDE &&
           (uint64_t)h * (z + 1) <= QTOOL_RELIGHT_LIGHTS_PNG_MAX_SIDE &&
           (uint64_t)w * (z + 1) * (uint64_t)h * (z + 1) <= QTOOL_RELIGHT_LIGHTS_PNG_MAX_PIXELS)
        ++z;
    return z;
}

/* the probe as the core reads it in format as: *conv (malloc'd) holds the converted pixels, NULL for
 * the RGBE bytes as stored; 0, or -1 with err set */
static int probe_image(const qtool_relight_lights_probe *p, qtool_relight_lights_as as, qibl_lightprobe_image_t *img,
                       void **conv, char *err, size_t errlen)
{
    size_t np = (size_t)p->w * (size_t)p->h;
    memset(img, 0, sizeof *img);
    img->width = (uint32_t)p->w, img->height = (uint32_t)p->h, img->pixels = p->px;
    *conv = NULL;
    if (as == QTOOL_RELIGHT_LIGHTS_AS_RGBE)
        return 0;
    uint32_t *f = malloc(sizeof *f * 3 * np);
    if (!f)
        return qtool_errf(err, errlen, "lights: out of memory");
    for (size_t i = 0; i < 3 * np; ++i) {
        float x = (float)rgbe_f(p->px[4 * (i / 3) + i % 3], p->px[4 * (i / 3) + 3]);
        memcpy(&f[i], &x, sizeof x);
    }
    if (as == QTOOL_RELIGHT_LIGHTS_AS_F32) {
        *conv = f, img->format = QIBL_LIGHTPROBE_LINEAR_F32;
    } else {
        uint8_t *s = malloc(4 * np);
        if (!s || qibl_srgbe_encode_f32_n(f, np, s) != QIBL_OK) {
            free(f), free(s);
            return qtool_errf(err, errlen, "lights: sRGBE conversion failed");
        }
        free(f);
        *conv = s, img->format = QIBL_LIGHTPROBE_SRGBE;
    }
    img->pixels = *conv;
    return 0;
}

int qtool_relight_lights_fit(const qtool_relight_lights_opts *o, const qtool_relight_lights_probe *p,
                             qibl_lightprobe_light_t **L, qibl_lightprobe_result_t *res, char *err, size_t errlen)
{
    qibl_lightprobe_image_t img;
    void *conv;
    *L = NULL;
    if (probe_image(p, o->as, &img, &conv, err, errlen) != 0)
        return -1;
    qibl_lightprobe_method_t build_for =
        o->core.method == QIBL_LIGHTPROBE_VARMIN || o->core.priority == QIBL_LIGHTPROBE_PRIORITY_VARIANCE
            ? QIBL_LIGHTPROBE_VARMIN
            : QIBL_LIGHTPROBE_MEDIANCUT;
    size_t wsz = qibl_lightprobe_workspace_size(img.width, img.height, build_for);
    void *ws = wsz ? malloc(wsz) : NULL;
    qibl_lightprobe_light_t *l = malloc(sizeof *l * (size_t)o->n);
    int rc = -1;
    if (!ws || !l) {
        qtool_errf(err, errlen, "lights: %s", wsz ? "out of memory" : "probe too large (W, H <= 32768, W H <= 2^26)");
        goto out;
    }
    qibl_lightprobe_t lp;
    qibl_status_t st = qibl_lightprobe_build(&lp, &img, build_for, ws, wsz);
    if (st == QIBL_OK)
        st = qibl_lightprobe_lights(&lp, &o->core, l, (uint32_t)o->n, res);
    if (st != QIBL_OK) {
        qtool_errf(err, errlen, "%s: %s", o->path, qibl_status_str(st));
        rc = st == QIBL_E_PROBE_BLACK ? 1 : -1; /* black: a valid answer, no lights */
        goto out;
    }
    *L = l, l = NULL;
    rc = 0;
out:
    free(ws), free(l), free(conv);
    return rc;
}

void qtool_relight_lights_turned(const qibl_lightprobe_light_t *L, uint32_t n, int32_t rgb_exp, int rotate,
                                 const double r[3][3], double (*dir)[3], double (*rgb)[3])
{
    for (uint32_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) { /* turned as relight turns the probe: light from d comes from r d */
            double v = 0.0;
            for (int j = 0; j < 3; ++j)
                v += (rotate ? r[k][j] : (double)(k == j)) * (L[i].dir[j] / 1073741824.0);
            dir[i][k] = v;
            rgb[i][k] = ldexp(L[i].rgb[k], rgb_exp);
        }
}

/* ---- the picture -------------------------------------------------------------------------------- */

/* pixel-space position of a direction: u = phi W / 2 pi, v = theta H / pi */
static void dir_to_uv(const qibl_lightprobe_light_t *l, int w, int h, double *u, double *v)
{
    double x = l->dir[0] / 1073741824.0, y = l->dir[1] / 1073741824.0, z = l->dir[2] / 1073741824.0;
    double phi = atan2(y, x);
    if (phi < 0)
        phi += 2 * QTOOL_PI;
    *u = phi * w / (2 * QTOOL_PI);
    *v = acos(fmax(-1.0, fmin(1.0, z))) * h / QTOOL_PI;
}

static void put(uint8_t *img, int W, int H, int x, int y, const uint8_t c[3])
{
    if (x < 0 || y < 0 || x >= W || y >= H)
        return;
    memcpy(img + 3 * ((size_t)y * (size_t)W + (size_t)x), c, 3);
}

/* the probe tone-mapped into img (W x H, zoom z) */
static void tone_map(const qtool_relight_lights_probe *p, int z, uint8_t *img)
{
    int w = p->w, h = p->h, W = w * z, H = h * z;
    double logsum = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) {
        const uint8_t *q = p->px + 4 * i;
        double l = 0.2126 * rgbe_f(q[0], q[3]) + 0.7152 * rgbe_f(q[1], q[3]) + 0.0722 * rgbe_f(q[2], q[3]);
        logsum += log(1e-6 + l);
    }
    double key = exp(logsum / ((double)w * h)), a = 0.18 / key;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const uint8_t *q = p->px + 4 * ((size_t)(y / z) * (size_t)w + (size_t)(x / z));
            uint8_t *o = img + 3 * ((size_t)y * (size_t)W + (size_t)x);
            for (int c = 0; c < 3; ++c) {
                double s = a * rgbe_f(q[c], q[3]);
                o[c] = (uint8_t)lrint(255.0 * pow(s / (1.0 + s), 1.0 / 2.2));
            }
        }
}

uint8_t *qtool_relight_lights_draw(const qtool_relight_lights_probe *p, int z, const qibl_lightprobe_light_t *L,
                                   uint32_t n)
{
    int W = p->w * z, H = p->h * z;
    uint8_t *img = malloc((size_t)W * (size_t)H * 3);
    if (!img)
        return NULL;
    tone_map(p, z, img);
    const uint8_t edge[3] = {40, 220, 60}, dot[3] = {255, 30, 20}, rim[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; ++i) {
        int x0 = (int)L[i].u0 * z, x1 = (int)L[i].u1 * z - 1, y0 = (int)L[i].v0 * z, y1 = (int)L[i].v1 * z - 1;
        for (int x = x0; x <= x1; ++x)
            put(img, W, H, x, y0, edge), put(img, W, H, x, y1, edge);
        for (int y = y0; y <= y1; ++y)
            put(img, W, H, x0, y, edge), put(img, W, H, x1, y, edge);
    }
    int r = W >= 512 ? 3 : 2;
    for (uint32_t i = 0; i < n; ++i) {
        double u, v;
        dir_to_uv(&L[i], p->w, p->h, &u, &v);
        int cx = (int)lrint(u * z - 0.5), cy = (int)lrint(v * z - 0.5);
        for (int dy = -r - 1; dy <= r + 1; ++dy)
            for (int dx = -r - 1; dx <= r + 1; ++dx) {
                int d2 = dx * dx + dy * dy;
                if (d2 <= r * r)
                    put(img, W, H, cx + dx, cy + dy, dot);
                else if (d2 <= (r + 1) * (r + 1))
                    put(img, W, H, cx + dx, cy + dy, rim);
            }
    }
    return img;
}

/* ---- the error and --auto ----------------------------------------------------------------------- */

int qtool_relight_lights_error(const qtool_relight_lights_probe *p, const qibl_lightprobe_light_t *L, uint32_t n,
                               int32_t rgb_exp, double *mean, double *max)
{
    enum { NN = QTOOL_RELIGHT_LIGHTS_ERROR_NORMALS };
    size_t np = (size_t)p->w * (size_t)p->h;
    double *d = malloc(sizeof *d * 3 * np);
    qtool_ref_light *R = malloc(sizeof *R * (n ? n : 1));
    double (*nrm)[3] = malloc(sizeof *nrm * NN), *E = malloc(sizeof *E * NN);
    qtool_ref_probe rp;
    int rc = -1;
    if (!d || !R || !nrm || !E)
        goto out;
    for (size_t i = 0; i < np; ++i)
        for (int c = 0; c < 3; ++c)
            d[3 * i + (size_t)c] = rgbe_f(p->px[4 * i + (size_t)c], p->px[4 * i + 3]);
    if (qtool_ref_probe_init(&rp, p->w, p->h, d) != 0)
        goto out;
    qtool_ref_sphere_dirs(NN, nrm);
    qtool_ref_probe_irradiance(&rp, NN, (const double (*)[3])nrm, E, 4);
    for (uint32_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            R[i].dir[c] = L[i].dir[c] / 1073741824.0;
            R[i].rgb[c] = ldexp(L[i].rgb[c], rgb_exp);
        }
    qtool_ref_irradiance_error(R, (int)n, NN, (const double (*)[3])nrm, E, mean, max);
    qtool_ref_probe_free(&rp);
    rc = 0;
out:
    free(d), free(R), free(nrm), free(E);
    return rc;
}

int qtool_relight_lights_auto(const qtool_relight_lights_probe *p, double budget, FILE *log, qtool_study_pick *pick,
                              char *err, size_t errlen)
{
    qtool_study_probe sp;
    if (qtool_study_probe_init(&sp, p->w, p->h, p->px, err, errlen) != 0)
        return -1;
    int rc = qtool_study_auto(&sp, budget, 2, log, pick, err, errlen);
    qtool_study_probe_free(&sp);
    return rc < 0 ? -1 : 0;
}
