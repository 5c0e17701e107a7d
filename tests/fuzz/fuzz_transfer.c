/*
 * fuzz_transfer.c - libFuzzer target: the mesh pipeline of `qibl transfer` (tools/transfer/transfer.c
 * and tools/gen/simplify.c) on fuzzed small meshes: weld, adjacency, simplification, the two-level
 * hierarchy and the PVS over two frames.
 *
 * Input: a flags byte (ring 1..4, sometimes 0 or 17; crease), the coarse target, a frame-2 motion
 * byte, a vertex count byte, the vertices (int8 triples on a 1/8 grid, so corners coincide and
 * weld), then triangles as index bytes to the end (up to 64; some past the vertex count).
 *
 * Invariants (abort on violation): a refused call returns its named status and leaves its output
 * empty; an index past the vertices is refused by the check, the adjacency and the hierarchy alike;
 * welded triangles index vertices whose first corner has the corner's position; the adjacency lists
 * each triangle once around each of its distinct vertices; coarse triangles index the mesh's
 * vertices; every hierarchy list equals a brute-force one built from graph distances (near faces,
 * far coarse faces, crease wedges); PVS lists are in range, no longer than their source's, and give
 * the very same hemi masks as the source on both frames.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "gen/simplify.h"
#include "qibl/hemi.h"
#include "transfer/transfer.h"

enum { MAX_RAW_V = 40, MAX_T = 64 };

static int cmp_tri(const void *a, const void *b)
{
    const uint32_t *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

static void sort3(uint32_t t[3])
{
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2 - i; ++j)
            if (t[j] > t[j + 1]) {
                const uint32_t x = t[j];
                t[j] = t[j + 1], t[j + 1] = x;
            }
}

static int is_empty(const qtool_transfer_hier *h)
{
    return !h->voff && !h->boff && !h->vl && !h->blk;
}

/* the hierarchy of every vertex against graph distances (see tests/transfer_pipeline_test.c) */
static void check_hier(const qtool_transfer_mesh *m, const uint32_t *off, const uint32_t *adj, const uint32_t (*ct)[3],
                       uint32_t nct, int ring, int crease, const qtool_transfer_hier *h)
{
    static int dist[3 * MAX_T];
    static uint32_t queue[3 * MAX_T], want[2 * MAX_T + 4 * MAX_T][3], got[2 * MAX_T + 4 * MAX_T][3];
    FUZZ_CHECK(h->voff[0] == 0 && h->boff[0] == 0);
    for (uint32_t v = 0; v < m->nv; ++v) {
        for (uint32_t i = 0; i < m->nv; ++i)
            dist[i] = -1;
        uint32_t head = 0, tail = 0;
        dist[v] = 0, queue[tail++] = v;
        while (head < tail) {
            const uint32_t x = queue[head++];
            for (uint32_t k = off[x]; k < off[x + 1]; ++k)
                for (int c = 0; c < 3; ++c)
                    if (dist[m->tri[adj[k]][c]] < 0)
                        dist[m->tri[adj[k]][c]] = dist[x] + 1, queue[tail++] = m->tri[adj[k]][c];
        }
        size_t nw = 0;
        for (uint32_t t = 0; t < m->nt; ++t) {
            int near = 0;
            for (int c = 0; c < 3; ++c)
                near |= dist[m->tri[t][c]] >= 0 && dist[m->tri[t][c]] <= ring;
            if (near)
                memcpy(want[nw++], m->tri[t], sizeof want[0]);
        }
        for (uint32_t t = 0; t < nct; ++t) {
            int near = 0;
            for (int c = 0; c < 3; ++c)
                near |= dist[ct[t][c]] >= 0 && dist[ct[t][c]] <= ring;
            if (!near)
                memcpy(want[nw++], ct[t], sizeof want[0]);
        }
        if (crease)
            for (uint32_t k = off[v]; k < off[v + 1]; ++k) {
                const uint32_t *t = m->tri[adj[k]];
                const int r = t[0] == v ? 0 : t[1] == v ? 1 : 2;
                want[nw][0] = m->nv, want[nw][1] = t[(r + 1) % 3], want[nw][2] = t[(r + 2) % 3], ++nw;
            }
        FUZZ_CHECK(h->voff[v + 1] >= h->voff[v] && h->boff[v + 1] - h->boff[v] == nw);
        const size_t n = h->voff[v + 1] - h->voff[v];
        FUZZ_CHECK(n <= m->nv);
        int self = 0;
        for (size_t i = 0; i < n; ++i) {
            FUZZ_CHECK(h->vl[h->voff[v] + i] < m->nv);
            self |= h->vl[h->voff[v] + i] == v;
            for (size_t j = 0; j < i; ++j)
                FUZZ_CHECK(h->vl[h->voff[v] + i] != h->vl[h->voff[v] + j]);
        }
        FUZZ_CHECK(self);
        for (size_t b = 0; b < nw; ++b)
            for (int c = 0; c < 3; ++c) {
                const uint32_t l = h->blk[h->boff[v] + b][c];
                FUZZ_CHECK(l <= n);
                got[b][c] = l == n ? m->nv : h->vl[h->voff[v] + l];
            }
        for (size_t b = 0; b < nw; ++b)
            sort3(want[b]), sort3(got[b]);
        qsort(want, nw, sizeof want[0], cmp_tri), qsort(got, nw, sizeof got[0], cmp_tri);
        FUZZ_CHECK(memcmp(want, got, sizeof want[0] * nw) == 0);
    }
}

/* one vertex's mask from hierarchy-style lists in frame f (as qibl transfer makes it); 0 or -1 */
static int mask_of(const qibl_hemi_t *hm, const qtool_transfer_hier *L, const qibl_q16_t (*pos)[3],
                   const int32_t (*nrm)[3], uint32_t v, uint32_t *mask)
{
    static qibl_q16_t gp[3 * MAX_T][3];
    static int32_t loc[3 * MAX_T + 1][3];
    qibl_hemi_frame_t fr;
    if (qibl_hemi_frame_init(&fr, pos[v], nrm[v]) != QIBL_OK)
        return -1;
    const size_t n = L->voff[v + 1] - L->voff[v];
    for (size_t k = 0; k < n; ++k)
        memcpy(gp[k], pos[L->vl[L->voff[v] + k]], sizeof gp[k]);
    if (qibl_hemi_transform(&fr, (const qibl_q16_t(*)[3])gp, (uint32_t)n, loc) != QIBL_OK)
        return -1;
    loc[n][0] = 0, loc[n][1] = 0, loc[n][2] = -(1 << 20);
    FUZZ_CHECK(qibl_hemi_clear(hm, mask) == QIBL_OK);
    return qibl_hemi_raster(hm, (const int32_t(*)[3])loc, (uint32_t)n + 1, L->blk + L->boff[v],
                            (uint32_t)(L->boff[v + 1] - L->boff[v]), mask, NULL) == QIBL_OK ? 0 : -1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in = {data, size};
    const uint8_t flags = fuzz_u8(&in), target = fuzz_u8(&in), motion = fuzz_u8(&in);
    int ring = 1 + (flags & 3);
    if ((flags & 0xC0u) == 0xC0u)
        ring = (flags & 0x20u) ? QTOOL_TRANSFER_MAX_RING + 1 : 0;
    const int crease = (flags >> 2) & 1;
    const uint32_t nraw = 3 + fuzz_u8(&in) % (MAX_RAW_V - 2);
    static double rp[MAX_RAW_V][3];
    for (uint32_t i = 0; i < nraw; ++i)
        for (int k = 0; k < 3; ++k)
            rp[i][k] = (int8_t)fuzz_u8(&in) / 8.0;
    static uint32_t raw[MAX_T][3];
    uint32_t nt = 0;
    int bad_index = 0;
    while (in.n >= 3 && nt < MAX_T) {
        for (int k = 0; k < 3; ++k) {
            raw[nt][k] = fuzz_u8(&in) % (nraw + 2);
            bad_index |= raw[nt][k] >= nraw;
        }
        ++nt;
    }
    if (nt == 0)
        return 0;
    /* the indexed mesh as given: an index past the vertices is refused everywhere, nothing written */
    qtool_transfer_mesh rm = {nraw, nt, 1, raw, &rp[0][0]};
    uint32_t *off = (uint32_t *)1, *adj = (uint32_t *)1;
    if (bad_index) {
        FUZZ_CHECK(qtool_transfer_check(&rm) == QTOOL_TRANSFER_E_INDEX);
        FUZZ_CHECK(qtool_transfer_adjacency(&rm, &off, &adj) == QTOOL_TRANSFER_E_INDEX && !off && !adj);
        for (uint32_t t = 0; t < nt; ++t)
            for (int k = 0; k < 3; ++k)
                raw[t][k] %= nraw;
    }
    /* the soup of those triangles, welded back */
    static double soup[MAX_T * 9];
    static uint32_t tri[MAX_T][3], first[3 * MAX_T], vof[3 * MAX_T];
    for (uint32_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k)
            memcpy(soup + 9 * t + 3 * k, rp[raw[t][k]], sizeof rp[0]);
    uint32_t nv = 0;
    FUZZ_CHECK(qtool_transfer_weld(soup, nt, tri, first, vof, &nv) == QTOOL_TRANSFER_OK);
    FUZZ_CHECK(nv >= 1 && nv <= 3 * nt && nv <= nraw);
    static double pos[3 * MAX_T][3];
    for (uint32_t v = 0; v < nv; ++v) {
        FUZZ_CHECK(first[v] < 3 * nt && vof[first[v]] == v);
        memcpy(pos[v], soup + 3 * first[v], sizeof pos[v]);
    }
    for (uint32_t c = 0; c < 3 * nt; ++c) {
        FUZZ_CHECK(vof[c] < nv && tri[c / 3][c % 3] == vof[c]);
        for (int k = 0; k < 3; ++k)
            FUZZ_CHECK(pos[vof[c]][k] == soup[3 * c + k]);
    }
    qtool_transfer_mesh m = {nv, nt, 2, tri, &pos[0][0]};
    FUZZ_CHECK(qtool_transfer_adjacency(&m, &off, &adj) == QTOOL_TRANSFER_OK);
    FUZZ_CHECK(off[0] == 0);
    size_t listed = 0;
    for (uint32_t t = 0; t < nt; ++t)
        listed += 1 + (tri[t][1] != tri[t][0]) + (tri[t][2] != tri[t][0] && tri[t][2] != tri[t][1]);
    FUZZ_CHECK(off[nv] == listed);
    for (uint32_t v = 0; v < nv; ++v)
        for (uint32_t k = off[v]; k < off[v + 1]; ++k) {
            FUZZ_CHECK(adj[k] < nt && (tri[adj[k]][0] == v || tri[adj[k]][1] == v || tri[adj[k]][2] == v));
            FUZZ_CHECK(k == off[v] || adj[k] > adj[k - 1]); /* each triangle once, in order */
        }
    uint32_t (*ct)[3] = NULL, nct = 0;
    FUZZ_CHECK(qtool_simplify(&pos[0][0], nv, (const uint32_t(*)[3])tri, nt, target, &ct, &nct) == 0);
    FUZZ_CHECK(nct <= nt);
    for (uint32_t t = 0; t < nct; ++t)
        for (int k = 0; k < 3; ++k)
            FUZZ_CHECK(ct[t][k] < nv);
    qtool_transfer_hier h, pv;
    const qtool_transfer_status st =
        qtool_transfer_hier_build(&m, off, adj, (const uint32_t(*)[3])ct, nct, ring, crease, &h);
    if (ring < 1 || ring > QTOOL_TRANSFER_MAX_RING) {
        FUZZ_CHECK(st == QTOOL_TRANSFER_E_RING && is_empty(&h));
        goto out;
    }
    FUZZ_CHECK(st == QTOOL_TRANSFER_OK);
    check_hier(&m, off, adj, (const uint32_t(*)[3])ct, nct, ring, crease, &h);
    if (nct > 0) { /* a coarse index past the vertices */
        const uint32_t keep = ct[nct - 1][motion % 3];
        ct[nct - 1][motion % 3] = nv + motion;
        FUZZ_CHECK(qtool_transfer_hier_build(&m, off, adj, (const uint32_t(*)[3])ct, nct, ring, crease, &pv) ==
                       QTOOL_TRANSFER_E_INDEX &&
                   is_empty(&pv));
        ct[nct - 1][motion % 3] = keep;
    }
    /* two frames: as given, then scaled and shifted by the motion byte; area-weighted normals */
    static qibl_q16_t ipos[2 * 3 * MAX_T][3];
    static int32_t inrm[2 * 3 * MAX_T][3];
    for (uint32_t f = 0; f < 2; ++f) {
        double N[3 * MAX_T][3];
        memset(N, 0, sizeof(double) * 3 * nv);
        const double s = f ? 0.5 + (motion & 15) / 16.0 : 1, d = f ? ((motion >> 4) - 8) / 8.0 : 0;
        for (uint32_t t = 0; t < nt; ++t) {
            const double *a = pos[tri[t][0]], *b = pos[tri[t][1]], *c = pos[tri[t][2]];
            const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            const double fn[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
            for (int k = 0; k < 3; ++k)
                for (int j = 0; j < 3; ++j)
                    N[tri[t][k]][j] += fn[j];
        }
        for (uint32_t v = 0; v < nv; ++v) {
            const double l = sqrt(N[v][0] * N[v][0] + N[v][1] * N[v][1] + N[v][2] * N[v][2]);
            for (int k = 0; k < 3; ++k) {
                ipos[f * nv + v][k] = (qibl_q16_t)lrint((pos[v][k] * s + d) * 65536.0);
                inrm[f * nv + v][k] = l > 0 ? (int32_t)lrint(N[v][k] / l * 1073741824.0 * 0.999) : 0;
            }
        }
    }
    static uint8_t hws[1 << 16];
    static qibl_hemi_t hm;
    static int hm_ready;
    if (!hm_ready) {
        FUZZ_CHECK(qibl_hemi_workspace_size(16, 2) <= sizeof hws);
        FUZZ_CHECK(qibl_hemi_init(&hm, 16, 2, hws, sizeof hws) == QIBL_OK);
        hm_ready = 1;
    }
    for (int use_src = 0; use_src < 2; ++use_src) {
        const qtool_transfer_hier *src = use_src ? &h : NULL;
        FUZZ_CHECK(qtool_transfer_pvs_build(&m, src, (const qibl_q16_t(*)[3])ipos, (const int32_t(*)[3])inrm, off, adj,
                                            crease, 1, &pv) == QTOOL_TRANSFER_OK);
        for (uint32_t v = 0; v < nv; ++v) {
            const size_t n = pv.voff[v + 1] - pv.voff[v];
            FUZZ_CHECK(pv.voff[v + 1] >= pv.voff[v] && pv.boff[v + 1] >= pv.boff[v] && n <= nv);
            FUZZ_CHECK(pv.boff[v + 1] - pv.boff[v] <= (src ? h.boff[v + 1] - h.boff[v] : nt + off[v + 1] - off[v]));
            for (size_t k = pv.voff[v]; k < pv.voff[v + 1]; ++k)
                FUZZ_CHECK(pv.vl[k] < nv);
            for (size_t b = pv.boff[v]; b < pv.boff[v + 1]; ++b)
                for (int k = 0; k < 3; ++k)
                    FUZZ_CHECK(pv.blk[b][k] <= n);
        }
        /* the same masks from the PVS as from its source, on both frames (hierarchy source only:
         * every-triangle lists are not built here) */
        for (uint32_t f = 0; use_src && f < 2; ++f)
            for (uint32_t v = 0; v < nv; ++v) {
                uint32_t a[QIBL_HEMI_MAX_WORDS], b[QIBL_HEMI_MAX_WORDS];
                const int ra = mask_of(&hm, &h, (const qibl_q16_t(*)[3])(ipos + f * nv),
                                       (const int32_t(*)[3])(inrm + f * nv), v, a);
                const int rb = mask_of(&hm, &pv, (const qibl_q16_t(*)[3])(ipos + f * nv),
                                       (const int32_t(*)[3])(inrm + f * nv), v, b);
                if (ra == 0 && rb == 0)
                    FUZZ_CHECK(memcmp(a, b, sizeof(uint32_t) * hm.words) == 0);
            }
        qtool_transfer_hier_free(&pv);
    }
    qtool_transfer_hier_free(&h);
out:
    free(ct), free(off), free(adj);
    return 0;
}
