/*
 * demo/nearfield.c - the near-field row of `qibl demo`: the built-in luminaire (a patterned shade
 * around an emitter) captured as Granier et al.'s near-field source, rendered as its grid of
 * textured spotlights against the luminaire ray-traced through its shade, beside the same source
 * treated as a far-field (IES-like) point lamp, at several distances from the lamp; then the
 * near-field kernel's time per frame in the courtyard. The library calls of `qibl luminaire study`
 * (tools/luminaire), sized by the demo's sizes table.
 */
#include <stdio.h>
#include <time.h>

#include "demo/demo.h"
#include "luminaire/luminaire.h"
#include "qtool.h"

int qtool_demo_nearfield(const qtool_demo_view *v, const qtool_demo_size *sz, char *err, size_t errlen)
{
    clock_t c0 = clock(); /* the process's CPU time: the ray tracer's threads included */
    double t0 = qtool_demo_now();
    const int quick = sz->nf_size < 96u;
    qtool_luminaire_study_opts o = {.grid = sz->nf_grid, .res = 32, .size = sz->nf_size, .quick = quick,
                                    .threads = v->threads};
    fprintf(v->out, "\nnear-field source (Granier et al.): the built-in luminaire captured on a %ux%u grid, its "
                    "spotlights against the luminaire ray-traced through its shade and against its far-field "
                    "(point lamp) treatment, on a %ux%u ground patch at %s heights (in lamp sizes), then in the "
                    "courtyard\n", sz->nf_grid, sz->nf_grid, sz->nf_size, sz->nf_size, quick ? "3" : "5");
    fflush(v->out);
    if (qtool_luminaire_study(&o, v->out) != 0)
        return qtool_errf(err, errlen, "demo: the near-field row failed (out of memory)");
    fprintf(v->out, "near-field row: %.1f s wall, %.1f s CPU\n", qtool_demo_now() - t0,
            (double)(clock() - c0) / CLOCKS_PER_SEC);
    return 0;
}
