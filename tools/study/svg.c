/*
 * svg.c - a small SVG line-plot writer for the study: axes with ticks (log by decades, or by powers
 * of two), one polyline per series (dashed for max errors), a legend. Text is XML-escaped.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/atomic.h"
#include "study/study.h"

static const char *palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

static void esc(FILE *f, const char *s)
{
    for (; s && *s; ++s) {
        if (*s == '<')
            fputs("&lt;", f);
        else if (*s == '>')
            fputs("&gt;", f);
        else if (*s == '&')
            fputs("&amp;", f);
        else if (*s == '"')
            fputs("&quot;", f);
        else
            fputc(*s, f);
    }
}

static int usable(double v, int lg)
{
    return isfinite(v) && (!lg || v > 0);
}

int qtool_study_svg_plot(const char *path, const char *title, const char *xlabel, const char *ylabel, int logx,
                         int log2x, int logy, const qtool_study_series *s, int ns, char *err, size_t errlen)
{
    if (ns < 1 || !s) {
        snprintf(err, errlen, "%s: no series to plot", path);
        return -1;
    }
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int i = 0; i < ns; ++i)
        for (int k = 0; k < s[i].n; ++k)
            if (usable(s[i].x[k], logx) && usable(s[i].y[k], logy)) {
                double x = logx ? log10(s[i].x[k]) : s[i].x[k], y = logy ? log10(s[i].y[k]) : s[i].y[k];
                x0 = fmin(x0, x), x1 = fmax(x1, x), y0 = fmin(y0, y), y1 = fmax(y1, y);
            }
    if (!(x0 <= x1)) {
        snprintf(err, errlen, "%s: no finite point to plot", path);
        return -1;
    }
    if (logy) /* whole decades */
        y0 = floor(y0), y1 = ceil(y1);
    if (logx && !log2x)
        x0 = floor(x0), x1 = ceil(x1);
    if (x1 - x0 < 1e-12)
        x0 -= 0.5, x1 += 0.5;
    if (y1 - y0 < 1e-12)
        y0 -= 0.5, y1 += 0.5;
    /* atomic: a planted link is refused, a full disc leaves no truncated plot */
    qtool_io_atomic at;
    if (qtool_io_atomic_open(&at, path, err, errlen) != 0)
        return -1;
    FILE *f = at.f;
    const double W = 760, H = 480, L = 70, R = 190, T = 40, B = 50, pw = W - L - R, ph = H - T - B;
#define PX(v) (L + ((v) - x0) / (x1 - x0) * pw)
#define PY(v) (T + ph - ((v) - y0) / (y1 - y0) * ph)
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" "
               "font-family=\"sans-serif\" font-size=\"11\">\n", W, H, W, H);
    fprintf(f, "<rect x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\" fill=\"white\"/>\n", W, H);
    fprintf(f, "<text x=\"%.0f\" y=\"20\" font-size=\"14\" text-anchor=\"middle\">", L + pw / 2);
    esc(f, title);
    fprintf(f, "</text>\n<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"black\"/>\n",
            L, T, pw, ph);
    /* x ticks */
    if (logx && log2x) {
        for (double e = ceil(x0 / log10(2.0) - 1e-9); e * log10(2.0) <= x1 + 1e-9; e += 1) {
            double x = e * log10(2.0);
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", PX(x), T, PX(x), T + ph);
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%.0f</text>\n", PX(x), T + ph + 15, pow(2, e));
        }
    } else {
        int nt = logx ? (int)(x1 - x0) : 5;
        for (int i = 0; i <= nt; ++i) {
            double x = x0 + (x1 - x0) * i / (nt ? nt : 1);
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", PX(x), T, PX(x), T + ph);
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n", PX(x), T + ph + 15,
                    logx ? pow(10, x) : x);
        }
    }
    /* y ticks */
    int nty = logy ? (int)(y1 - y0) : 5;
    for (int i = 0; i <= nty; ++i) {
        double y = y0 + (y1 - y0) * i / (nty ? nty : 1);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", L, PY(y), L + pw, PY(y));
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", L - 4, PY(y) + 4, logy ? pow(10, y) : y);
    }
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">", L + pw / 2, H - 12);
    esc(f, xlabel);
    fprintf(f, "</text>\n<text x=\"16\" y=\"%.0f\" text-anchor=\"middle\" transform=\"rotate(-90 16 %.0f)\">", T + ph / 2,
            T + ph / 2);
    esc(f, ylabel);
    fprintf(f, "</text>\n");
    int nl = 0;
    for (int i = 0; i < ns; ++i) {
        const char *col = palette[(s[i].color % 10 + 10) % 10];
        int open = 0;
        for (int k = 0; k < s[i].n; ++k) {
            if (!usable(s[i].x[k], logx) || !usable(s[i].y[k], logy)) {
                if (open)
                    fprintf(f, "\"/>\n");
                open = 0;
                continue;
            }
            double x = logx ? log10(s[i].x[k]) : s[i].x[k], y = logy ? log10(s[i].y[k]) : s[i].y[k];
            if (!open)
                fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.6\"%s points=\"", col,
                        s[i].dashed ? " stroke-dasharray=\"5,3\"" : "");
            fprintf(f, "%s%.1f,%.1f", open ? " " : "", PX(x), PY(y));
            open = 1;
        }
        if (open)
            fprintf(f, "\"/>\n");
        if (!s[i].name)
            continue; /* a companion line (the max of a mean): no legend entry of its own */
        double ly = T + 10 + 15 * nl++;
        fprintf(f, "<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"1.6\"%s/>\n",
                L + pw + 10, ly, L + pw + 34, ly, col, s[i].dashed ? " stroke-dasharray=\"5,3\"" : "");
        fprintf(f, "<text x=\"%.0f\" y=\"%.1f\">", L + pw + 40, ly + 4);
        esc(f, s[i].name);
        fprintf(f, "</text>\n");
    }
    fprintf(f, "</svg>\n");
#undef PX
#undef PY
    return qtool_io_atomic_commit(&at, err, errlen);
}
