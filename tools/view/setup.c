/*
 * view/setup.c - what `qibl view` prepares before the window opens (view/view.h): the asset's maps
 * into the viewer's state, the lamp placed and given its default brightness where the asset has a
 * P map, the sun from a direction, and the truth frames (one PNG or a directory of sun_X_Y_Z.png).
 *
 * Invariants: a failing call leaves nothing allocated (truths freed, state untouched beyond what
 * qtool_view_init reset) and says why in one line.
 */
#include "view/view.h"
#include "io/asset_write.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/png.h"
#include "qibl/asset.h"
#include "qibl/soft.h"
#include "qtool.h"

void qtool_view_set_sun(qtool_view *v, const qibl_q16_t sun[3])
{
    double x = sun[0], y = sun[1], z = sun[2], r = sqrt(x * x + y * y);
    v->az = fmod(atan2(y, x) * 180.0 / QTOOL_PI + 360.0, 360.0);
    v->el = atan2(z, r) * 180.0 / QTOOL_PI;
    v->el = v->el > QTOOL_VIEW_EL_MAX ? QTOOL_VIEW_EL_MAX : v->el < -QTOOL_VIEW_EL_MAX ? -QTOOL_VIEW_EL_MAX : v->el;
}

/* the lamp's default C0 for its starting position: o->lamp_default over the P map's points */
static int lamp_default_c0(const qtool_view *v, const qtool_view_asset_opts *o, double *c0)
{
    const qibl_shmaps_t *m = &v->maps;
    size_t np = (size_t)m->width * m->height;
    double *pts = malloc(np * 3 * sizeof *pts), lp[3], d = 1;
    for (int c = 0; c < 3; ++c)
        lp[c] = v->lamp_pos[c] / 65536.0;
    for (uint32_t y = 0; pts && y < m->height; ++y)
        for (uint32_t x = 0; x < m->width; ++x) {
            qibl_q16_t q[3];
            qibl_pmap_point(&v->pmap, x, y, q);
            for (int c = 0; c < 3; ++c)
                pts[3 * ((size_t)y * m->width + x) + (size_t)c] = q[c] / 65536.0;
        }
    int prc = pts ? o->lamp_default(pts, np, lp, 1, c0, &d) : -1;
    free(pts);
    return prc;
}

/* the lamp scheme where the asset has a P map: its maps, P map and lamp occlusion, the lamp placed */
static void lamp_setup(qtool_view *v, const qibl_asset_t *as, const char *name, char *note, size_t notelen)
{
    const qibl_shmaps_t *m = &v->maps;
    if (qibl_asset_pmap(as, &v->pmap) != QIBL_OK || qibl_asset_point_shmaps(as, &v->point_maps) != QIBL_OK ||
        v->pmap.width != m->width || v->pmap.height != m->height)
        return;
    qibl_chunk_t shmu, locc;
    v->have_lamp = 1;
    if (qibl_asset_find_nth(as, QIBL_CHUNK_SHMU, 0, &shmu) == QIBL_OK &&
        qibl_asset_find_nth(as, QIBL_CHUNK_LOCC, 0, &locc) == QIBL_OK) {
        qibl_status_t ost = qibl_lightpath_occl_from_asset(as, &v->occ);
        v->have_occ = ost == QIBL_OK;
        if (ost != QIBL_OK)
            snprintf(note, notelen, "%s: its LOCC chunk is not usable (%s): the lamp is drawn without lamp occlusion",
                     name, qibl_soft_status_str(ost));
    }
    /* the lamp starts over the middle of the frame's lower half (the ground), else anywhere not sky */
    int placed = qtool_view_pick(v, (int)m->width / 2, (int)(m->height * 3 / 4));
    for (uint32_t y = m->height; !placed && y-- > 0;)
        for (uint32_t x = 0; x < m->width && !placed; x += 7)
            placed = qtool_view_pick(v, (int)x, (int)y);
    if (!placed)
        v->have_lamp = 0; /* all sky: nowhere to put it */
}

int qtool_view_open_asset(qtool_view *v, const uint8_t *bytes, size_t n, const char *name,
                          const qtool_view_asset_opts *o, char *note, size_t notelen, char *err, size_t errlen)
{
    qibl_asset_t as;
    qibl_shmaps_t m;
    if (notelen)
        note[0] = '\0';
    qibl_status_t st = qtool_asset_open(&as, bytes, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&as, &m);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "%s: %s", name, qibl_soft_status_str(st));
    if (qtool_view_init(v, &m) != 0)
        return qtool_errf(err, errlen, "%s: its maps are not usable", name);
    v->exposure = (uint32_t)lrint(o->exposure * 65536.0);
    v->asset = bytes, v->asset_n = n, v->npaths = qibl_lightpath_count(&as); /* the path scheme (LPTH) */
    lamp_setup(v, &as, name, note, notelen);
    if (v->have_lamp) {
        double c0 = o->lamp_c0;
        if (c0 == 0 && (!o->lamp_default || lamp_default_c0(v, o, &c0) != 0))
            return qtool_errf(err, errlen, "view: out of memory");
        v->lamp_rgb[0] = v->lamp_rgb[1] = v->lamp_rgb[2] = (qibl_q16_t)nearbyint(c0 * 65536.0);
    } else if (o->lamp_c0 != 0) {
        snprintf(note, notelen, "%s has no P map to place a lamp in: --lamp-rgb is ignored", name);
    }
    if (o->sun)
        qtool_view_set_sun(v, o->sun);
    return 0;
}

void qtool_view_truths_free(qtool_view_truths *t)
{
    for (uint32_t i = 0; i < t->n; ++i)
        free(t->rgb[i]), free(t->name[i]);
    free(t->one);
    memset(t, 0, sizeof *t);
}

/* one sun_X_Y_Z.png of the directory: 0 kept, 1 not a truth frame's name, -1 with err */
static int truth_entry(const char *path, const char *fname, uint32_t w, uint32_t h, qtool_view_truths *t, char *err,
                       size_t errlen)
{
    double v[3];
    int end = 0;
    size_t len = strlen(fname);
    char stem[256];
    if (len < 8 || len >= sizeof stem || strcmp(fname + len - 4, ".png") != 0)
        return 1;
    memcpy(stem, fname, len - 4), stem[len - 4] = '\0'; /* "sun_0_0_1.png": strtod would take "1." */
    if (sscanf(stem, "sun_%lf_%lf_%lf%n", &v[0], &v[1], &v[2], &end) != 3 || (size_t)end != len - 4)
        return 1;
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(l > 0) || !isfinite(l))
        return qtool_errf(err, errlen, "--truth %s/%s: not a sun direction", path, fname);
    if (t->n >= QTOOL_VIEW_MAX_TRUTHS || (size_t)(t->n + 1) * w * h * 3 > QTOOL_VIEW_TRUTH_MAX_BYTES)
        return qtool_errf(err, errlen, "--truth %s: more than %u sun_X_Y_Z.png frames of %ux%u (at most %u, %zu MiB)",
                          path, t->n, w, h, QTOOL_VIEW_MAX_TRUTHS, QTOOL_VIEW_TRUTH_MAX_BYTES >> 20);
    char file[4096];
    int tw, th, tf;
    uint8_t *rgb = NULL;
    snprintf(file, sizeof file, "%s/%s", path, fname);
    if (qtool_png_read_rgb8(file, &tw, &th, &tf, &rgb, err, errlen) != 0)
        return -1;
    if ((uint32_t)tw != w || (uint32_t)th != h) {
        free(rgb);
        return qtool_errf(err, errlen, "--truth %s is %dx%d, the asset %ux%u: not the same frame", file, tw, th, w, h);
    }
    char *nm = strdup(fname);
    if (!nm)
        return free(rgb), qtool_errf(err, errlen, "view: out of memory");
    nm[len - 4] = '\0';
    t->rgb[t->n] = rgb, t->name[t->n] = nm;
    for (int c = 0; c < 3; ++c)
        t->dir[t->n][c] = v[c] / l;
    ++t->n;
    return 0;
}

/* --truth DIR: the `qibl render --sun X Y Z --png DIR/sun_X_Y_Z.png` frames of a directory */
static int truths_dir(const char *path, uint32_t w, uint32_t h, qtool_view_truths *t, char *err, size_t errlen)
{
    DIR *d = opendir(path);
    if (!d)
        return qtool_errf(err, errlen, "--truth %s: %s", path, strerror(errno));
    struct dirent *e;
    int rc = 0;
    while (rc == 0 && (e = readdir(d)) != NULL)
        rc = truth_entry(path, e->d_name, w, h, t, err, errlen) < 0 ? -1 : 0;
    closedir(d);
    if (rc == 0 && t->n == 0)
        rc = qtool_errf(err, errlen, "--truth %s: no sun_X_Y_Z.png frames (qibl render --sun X Y Z --png "
                        "DIR/sun_X_Y_Z.png)", path);
    return rc;
}

int qtool_view_truths_load(const char *path, uint32_t w, uint32_t h, qtool_view_truths *t, char *err, size_t errlen)
{
    struct stat tst;
    memset(t, 0, sizeof *t);
    int rc = 0;
    if (stat(path, &tst) == 0 && S_ISDIR(tst.st_mode)) { /* a directory of sun_X_Y_Z.png frames */
        rc = truths_dir(path, w, h, t, err, errlen);
    } else {
        int tw, th, tf;
        if (qtool_png_read_rgb8(path, &tw, &th, &tf, &t->one, err, errlen) != 0)
            rc = -1;
        else if ((uint32_t)tw != w || (uint32_t)th != h)
            rc = qtool_errf(err, errlen, "--truth %s is %dx%d, the asset %ux%u: not the same frame", path, tw, th, w, h);
    }
    if (rc != 0)
        qtool_view_truths_free(t);
    return rc;
}
