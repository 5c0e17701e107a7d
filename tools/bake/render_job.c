/*
 * bake/render_job.c - `qibl render`'s work (bake/job.h): the ray-traced ground truth of one sun or
 * point lamp (optionally goniometric), written as PNG (through the same framebuffer code as the
 * bake's truths), PFM, OpenEXR and a depth PFM.
 */
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "bake/job.h"
#include "io/exr.h"
#include "io/pfm.h"
#include "io/png.h"
#include "qtool.h"

int qtool_render_prepare(const qtool_render_opts *o, qtool_render_job *j, char *err, size_t errlen)
{
    memset(j, 0, sizeof *j);
    if (o->ies) {
        char ierr[512];
        if (qtool_ies_read(o->ies, &j->prof, ierr, sizeof ierr) != 0)
            return qtool_errf(err, errlen, "render: %s", ierr);
        j->have_ies = 1;
        if (qtool_ies_lamp_init(&j->lamp, &j->prof, o->aim, o->up) != 0)
            return qtool_errf(err, errlen, "render: %s: a zero --aim, an --up parallel to it, or a dark profile", o->ies);
    }
    if (qtool_scene_load(&o->scene, &j->s, err, errlen) != 0)
        return -1;
    j->have_scene = 1;
    size_t np = (size_t)o->scene.w * o->scene.h;
    j->lin = malloc(np * 3 * sizeof *j->lin);
    j->dep = malloc(np * sizeof *j->dep), j->f3 = malloc(np * 3 * sizeof *j->f3);
    j->rgb8 = malloc(np * 3);
    if (!j->lin || !j->dep || !j->f3 || !j->rgb8)
        return qtool_errf(err, errlen, "render: out of memory");
    return 0;
}

int qtool_render_points(const qtool_rt_scene *s, const qtool_scene_opts *so, double sky_dist, double **pts)
{
    double *p = malloc((size_t)so->w * so->h * 3 * sizeof *p);
    for (uint32_t y = 0; p && y < so->h; ++y)
        for (uint32_t x = 0; x < so->w; ++x) {
            double dir[3], *q = p + 3 * ((size_t)y * so->w + x);
            qtool_rt_hit h;
            qtool_rt_pixel_ray(s, so->w, so->h, (qtool_pano_kind)so->kind, x, y, dir);
            qtool_rt_primary(s, dir, &h);
            qtool_rt_sky_point(s, dir, sky_dist, q);
            if (h.hit)
                memcpy(q, h.p, sizeof h.p);
        }
    *pts = p;
    return p ? 0 : -1;
}

int qtool_render_run(const qtool_render_opts *o, qtool_render_job *j, int *png_written, char *err, size_t errlen)
{
    const qtool_scene_opts *so = &o->scene;
    size_t np = (size_t)so->w * so->h;
    char werr[512];
    *png_written = 0;
    double t0 = qtool_bake_now();
    qtool_rt_render_gonio(&j->s, so->w, so->h, (qtool_pano_kind)so->kind, &o->light,
                          j->have_ies ? qtool_ies_lamp_scale : NULL, j->have_ies ? &j->lamp : NULL, so->threads, j->lin,
                          j->dep, NULL);
    j->ms = (qtool_bake_now() - t0) * 1e3;
    if (o->png) {
        if (j->have_ies) /* the frame just rendered, through the same framebuffer code as truth8 */
            qtool_bake_lin_to8(j->lin, so->w, so->h, j->rgb8);
        else
            qtool_bake_truth8(&j->s, so->w, so->h, (qtool_pano_kind)so->kind, &o->light, so->threads, j->rgb8, NULL);
        if (qtool_png_write_rgb8(o->png, (int)so->w, (int)so->h, j->rgb8, werr, sizeof werr) != 0)
            return qtool_errf(err, errlen, "%s", werr);
        *png_written = 1;
    }
    if (o->pfm || o->exr) {
        for (size_t i = 0; i < np * 3; ++i)
            j->f3[i] = (float)j->lin[i];
        if ((o->pfm && qtool_pfm_write(o->pfm, (int)so->w, (int)so->h, 3, j->f3, werr, sizeof werr) != 0) ||
            (o->exr && qtool_exr_write(o->exr, (int)so->w, (int)so->h, j->f3, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, werr,
                                       sizeof werr) != 0))
            return qtool_errf(err, errlen, "%s", werr);
    }
    if (o->depth && qtool_pfm_write(o->depth, (int)so->w, (int)so->h, 1, j->dep, werr, sizeof werr) != 0)
        return qtool_errf(err, errlen, "%s", werr);
    return 0;
}

void qtool_render_free(qtool_render_job *j)
{
    free(j->lin), free(j->dep), free(j->f3), free(j->rgb8);
    if (j->have_scene)
        qtool_rt_scene_free(&j->s);
    if (j->have_ies)
        qtool_ies_free(&j->prof);
    memset(j, 0, sizeof *j);
}
