/*
 * probe_cli_test.c - the probe side of the qibl CLI run as a program: relight by a probe (SH
 * against a many-light reference, --yaw against a probe rotated by resampling, the modes),
 * lights that add up (suns, points), --lights FILE.csv and its errors, sh project --format,
 * lights --json, probe info's advice on procedural probes (and on fixture probes when present),
 * and the help texts.
 *
 * Probes are made here (io/hdr_write.h); the binary is found as cliutil.h says (tests skip when it
 * is missing).
 */
#include "cliutil.h"

#include <math.h>

#include "engine/engine.h"
#include "io/hdr.h"
#include "io/hdr_write.h"
#include "io/pfm.h"
#include "study/study.h"

#define PI_ 3.14159265358979323846
#define FIXTURES "../shared/fixtures/probes"

CLI_FIXTURES("/tmp/qibl_probe_cli_test_XXXXXX")


/* exit status and a phrase on stderr (want may be NULL), and out (may be NULL) not created */
static void expect(int want_rc, const char *want, const char *out, const char *first, ...)
{
    va_list ap;
    va_start(ap, first);
    int rc = run_v(first, ap);
    va_end(ap);
    char *msg = text(errlog);
    if (rc != want_rc)
        fail_msg("qibl %s ...: exit %d, want %d; stderr: %s", first, rc, want_rc, msg);
    if (want && strstr(msg, want) == NULL)
        fail_msg("qibl %s ...: stderr '%s' does not say '%s'", first, msg, want);
    if (out && access(out, F_OK) == 0)
        fail_msg("qibl %s ...: left %s behind", first, out);
    free(msg);
}

/* runs qibl and fails the test unless it exits 0 */
#define OK(...)                                                                                              \
    do {                                                                                                     \
        int rc_ = run(__VA_ARGS__, NULL);                                                                    \
        if (rc_ != 0) {                                                                                      \
            char *m_ = text(errlog);                                                                         \
            fail_msg("qibl exit %d: %s", rc_, m_);                                                           \
        }                                                                                                    \
    } while (0)

typedef void (*probe_fn)(double theta, double phi, double rgb[3], void *ctx);

/* a w x h lat-long probe (qibl's directions: theta from +z, phi from +x toward +y) */
static void make_probe(const char *path, int w, int h, probe_fn f, void *ctx)
{
    float *px = malloc(sizeof *px * 3 * (size_t)w * (size_t)h);
    assert_non_null(px);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            double rgb[3];
            f((v + 0.5) * PI_ / h, (u + 0.5) * 2 * PI_ / w, rgb, ctx);
            for (int c = 0; c < 3; ++c)
                px[3 * ((size_t)v * (size_t)w + (size_t)u) + (size_t)c] = (float)rgb[c];
        }
    char err[512];
    if (qtool_hdr_write(path, w, h, px, err, sizeof err) != 0)
        fail_msg("%s", err);
    free(px);
}

/* overcast: a bright zenith fading to the horizon, a dim grey ground (smooth: SH's case) */
static void overcast(double t, double p, double rgb[3], void *ctx)
{
    (void)p, (void)ctx;
    double z = cos(t);
    double s = z > 0 ? 0.4 + 0.6 * z : 0.12;
    rgb[0] = s * 0.95, rgb[1] = s, rgb[2] = s * 1.05;
}

/* a sunny sky: a bluish sky gradient, a ground, and a small sun 30 degrees up at phi = 0.6 (not
 * symmetric about any axis, so a rotation shows) */
static void sunny(double t, double p, double rgb[3], void *ctx)
{
    double big = ctx ? *(const double *)ctx : 2000.0;
    double z = cos(t), d[3] = {sin(t) * cos(p), sin(t) * sin(p), z};
    double st = cos(60 * PI_ / 180), s[3] = {sin(60 * PI_ / 180) * cos(0.6), sin(60 * PI_ / 180) * sin(0.6), st};
    double c = d[0] * s[0] + d[1] * s[1] + d[2] * s[2];
    double sky = z > 0 ? 0.05 + 0.05 * z + 0.02 * cos(p) : 0.02 + 0.01 * sin(p);
    rgb[0] = sky * 0.7, rgb[1] = sky * 0.85, rgb[2] = sky;
    if (c > cos(4.0 * PI_ / 180)) /* a disc of 4 degrees */
        rgb[0] += big, rgb[1] += big * 0.95, rgb[2] += big * 0.85;
}

static float *pfm(const char *path, int *w, int *h)
{
    int ch;
    float *px;
    char err[512];
    if (qtool_pfm_read(path, w, h, &ch, &px, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(ch, 3);
    return px;
}

/* sum |a - b| / sum |a| and max |a - b| / max |a| of two PFMs of the same size */
static void pfm_diff(const char *pa, const char *pb, double *rel_l1, double *rel_max)
{
    int w, h, w2, h2;
    float *a = pfm(pa, &w, &h), *b = pfm(pb, &w2, &h2);
    assert_int_equal(w, w2);
    assert_int_equal(h, h2);
    double s = 0, sa = 0, m = 0, ma = 0;
    for (size_t i = 0; i < 3 * (size_t)w * (size_t)h; ++i) {
        double d = fabs((double)a[i] - b[i]);
        s += d, sa += fabs(a[i]), m = fmax(m, d), ma = fmax(ma, fabs(a[i]));
    }
    *rel_l1 = sa > 0 ? s / sa : s;
    *rel_max = ma > 0 ? m / ma : m;
    free(a), free(b);
}

static void asset(const char *path)
{
    OK("gen", "-o", path, "--size", "64x16", "--k", "9", "--lut-size", "8");
}

/* ---- relight by a probe ----------------------------------------------------------------------- */

/* the probe's radiance SH against 1024 median-cut lights of the same probe (as SH of the same k),
 * and --lights of `qibl lights --csv` against --probe-mode lights: the same lights both ways */
static void test_relight_probe_sh_against_lights(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *pr = at("sky.hdr"), *csv = at("l.csv");
    asset(g);
    make_probe(pr, 64, 32, sunny, NULL);
    OK("relight", g, "--probe", pr, "--pfm", at("sh.pfm"));
    OK("relight", g, "--probe", pr, "--probe-mode", "lights", "-n", "1024", "--pfm", at("l1024.pfm"));
    OK("relight", g, "--probe", pr, "--probe-mode", "sunsky", "--pfm", at("ss.pfm"));
    OK("relight", g, "--probe", pr, "--probe-mode", "lights", "-n", "4", "--pfm", at("l4.pfm"));
    char *o = text(outlog);
    assert_non_null(strstr(o, "4 median-cut lights"));
    free(o);
    /* lights --csv to a file: stdout of the run */
    OK("lights", pr, "-n", "1024", "--csv");
    {
        char *t = text(outlog);
        FILE *f = fopen(csv, "wb");
        assert_non_null(f);
        fputs(t, f);
        fclose(f);
        free(t);
    }
    OK("relight", g, "--lights", csv, "--pfm", at("csv.pfm"));
    double l1, mx;
    pfm_diff(at("sh.pfm"), at("l1024.pfm"), &l1, &mx);
    printf("relight: probe SH against 1024 median-cut lights: rel L1 %.2e, max %.2e of the max\n", l1, mx);
    if (l1 > 5e-3 || mx > 5e-3)
        fail_msg("SH and 1024 lights of one probe differ: %.3e / %.3e", l1, mx);
    pfm_diff(at("sh.pfm"), at("ss.pfm"), &l1, &mx);
    printf("relight: probe SH against sun plus sky: rel L1 %.2e, max %.2e\n", l1, mx);
    if (l1 > 5e-3 || mx > 5e-3)
        fail_msg("SH and sun plus sky of one probe differ: %.3e / %.3e", l1, mx);
    pfm_diff(at("l1024.pfm"), at("csv.pfm"), &l1, &mx);
    if (l1 > 1e-4 || mx > 1e-4)
        fail_msg("--lights of lights --csv and --probe-mode lights differ: %.3e / %.3e", l1, mx);
    /* and 4 lights is visibly coarser (the comparison can fail) */
    pfm_diff(at("sh.pfm"), at("l4.pfm"), &l1, &mx);
    if (l1 < 1e-3)
        fail_msg("4 median-cut lights agree with SH to %.3e: the comparison above proves nothing", l1);
}

/* shifts a lat-long RGB float image right by s columns (a yaw of 360 s / w degrees) */
static void shifted_probe(const char *path, int w, int h, int s)
{
    float *px = malloc(sizeof *px * 3 * (size_t)w * (size_t)h), *o = malloc(sizeof *o * 3 * (size_t)w * (size_t)h);
    assert_non_null(px);
    assert_non_null(o);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            double rgb[3];
            sunny((v + 0.5) * PI_ / h, (u + 0.5) * 2 * PI_ / w, rgb, NULL);
            int du = (u + s) % w;
            for (int c = 0; c < 3; ++c)
                o[3 * ((size_t)v * (size_t)w + (size_t)du) + (size_t)c] = (float)rgb[c];
        }
    char err[512];
    if (qtool_hdr_write(path, w, h, o, err, sizeof err) != 0)
        fail_msg("%s", err);
    free(px), free(o);
}

/* --yaw 90 equals the probe resampled a quarter turn to the right; -90 does not; --rotate with
 * the same matrix equals --yaw */
static void test_relight_yaw_sign(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *pr = at("sun.hdr"), *rot = at("sun_rot.hdr");
    asset(g);
    make_probe(pr, 64, 32, sunny, NULL);
    shifted_probe(rot, 64, 32, 8);
    OK("relight", g, "--probe", rot, "--pfm", at("resampled45.pfm"));
    OK("relight", g, "--probe", pr, "--yaw", "45", "--pfm", at("yaw45.pfm"));
    shifted_probe(rot, 64, 32, 16);
    OK("relight", g, "--probe", rot, "--pfm", at("resampled.pfm"));
    OK("relight", g, "--probe", pr, "--yaw", "90", "--pfm", at("yaw.pfm"));
    OK("relight", g, "--probe", pr, "--yaw", "-90", "--pfm", at("yawneg.pfm"));
    OK("relight", g, "--probe", pr, "--rotate", "0,-1,0,1,0,0,0,0,1", "--pfm", at("rot.pfm"));
    OK("relight", g, "--probe", pr, "--probe-mode", "lights", "-n", "256", "--yaw", "90", "--pfm", at("yawl.pfm"));
    double l1, mx;
    pfm_diff(at("resampled.pfm"), at("yaw.pfm"), &l1, &mx);
    printf("relight: --yaw 90 against the probe resampled by 90 degrees: rel L1 %.2e, max %.2e\n", l1, mx);
    if (l1 > 1e-3 || mx > 1e-3)
        fail_msg("--yaw 90 is not the probe turned 90 degrees toward +y: %.3e / %.3e", l1, mx);
    pfm_diff(at("resampled45.pfm"), at("yaw45.pfm"), &l1, &mx);
    printf("relight: --yaw 45 against the probe resampled by 45 degrees: rel L1 %.2e, max %.2e\n", l1, mx);
    if (l1 > 1e-3 || mx > 1e-3)
        fail_msg("--yaw 45 is not the probe turned 45 degrees toward +y: %.3e / %.3e", l1, mx);
    pfm_diff(at("yaw.pfm"), at("rot.pfm"), &l1, &mx);
    if (l1 > 1e-5 || mx > 1e-5)
        fail_msg("--rotate of the same matrix differs from --yaw: %.3e / %.3e", l1, mx);
    pfm_diff(at("resampled.pfm"), at("yawl.pfm"), &l1, &mx);
    if (l1 > 2e-2)
        fail_msg("--yaw with --probe-mode lights is not the resampled probe: %.3e", l1);
    pfm_diff(at("resampled.pfm"), at("yawneg.pfm"), &l1, &mx);
    if (l1 < 2e-2)
        fail_msg("--yaw -90 matches the probe turned +90 degrees (%.3e): the sign test proves nothing", l1);
}

/* ---- lights that add up ------------------------------------------------------------------------- */

static void test_relight_lights_add_up(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl");
    asset(g);
    OK("relight", g, "--sun", "0.3", "0.2", "1", "--pfm", at("one.pfm"));
    OK("relight", g, "--sun", "0.3", "0.2", "1", "--rgb", "0.5", "0.5", "0.5", "--sun", "0.3", "0.2", "1", "--rgb",
       "0.5", "0.5", "0.5", "--pfm", at("halves.pfm"));
    double l1, mx;
    pfm_diff(at("one.pfm"), at("halves.pfm"), &l1, &mx);
    if (mx > 1e-4)
        fail_msg("two half suns differ from one sun: %.3e of the max", mx);
    /* a second sun is no longer dropped: A + B = both, and both != A */
    OK("relight", g, "--sun", "-1", "0.5", "0.4", "--rgb", "2", "1", "0.5", "--pfm", at("b.pfm"));
    OK("relight", g, "--sun", "0.3", "0.2", "1", "--sun", "-1", "0.5", "0.4", "--rgb", "2", "1", "0.5", "--pfm",
       at("both.pfm"));
    int w, h;
    float *a = pfm(at("one.pfm"), &w, &h), *b = pfm(at("b.pfm"), &w, &h), *ab = pfm(at("both.pfm"), &w, &h);
    double worst = 0, differs = 0;
    for (size_t i = 0; i < 3 * (size_t)w * (size_t)h; ++i) {
        /* pixels where a sun's ringing went negative are clamped to 0 in the PFM: skip them */
        if (a[i] == 0 || b[i] == 0 || ab[i] == 0)
            continue;
        worst = fmax(worst, fabs((double)a[i] + b[i] - ab[i]));
        differs = fmax(differs, fabs((double)ab[i] - a[i]));
    }
    free(a), free(b), free(ab);
    if (worst > 4.0 / 65536)
        fail_msg("sun A + sun B differs from both at once by %.3e", worst);
    if (differs < 1e-2)
        fail_msg("the second --sun changed nothing (%.3e): dropped", differs);
    /* points: two lamps of half C0 at one place equal one lamp */
    OK("relight", g, "--point", "0", "0", "0", "--rgb", "4", "4", "4", "--pfm", at("p1.pfm"));
    OK("relight", g, "--point", "0", "0", "0", "--rgb", "2", "2", "2", "--point", "0", "0", "0", "--rgb", "2", "2", "2",
       "--pfm", at("p2.pfm"));
    pfm_diff(at("p1.pfm"), at("p2.pfm"), &l1, &mx);
    if (mx > 1e-4)
        fail_msg("two half lamps differ from one lamp: %.3e of the max", mx);
    /* a sun plus a lamp: both show */
    OK("relight", g, "--sun", "0.3", "0.2", "1", "--point", "0", "0", "0", "--rgb", "4", "4", "4", "--pfm",
       at("sp.pfm"));
    pfm_diff(at("p1.pfm"), at("sp.pfm"), &l1, &mx);
    if (l1 < 1e-2)
        fail_msg("--sun with --point: the sun is missing (%.3e)", l1);
}

/* ---- --lights FILE.csv -------------------------------------------------------------------------- */

static void write_file(const char *path, const char *s)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(s, f);
    fclose(f);
}

static void test_lights_csv_errors(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *png = at("x.png"), *c = at("l.csv");
    asset(g);
    static const struct {
        const char *body, *want;
    } cases[] = {
        {"", "empty: want the header line"},
        {"x,y,z,r,g,b\n0,0,1,1,1,1\n", "header 'x,y,z,r,g,b' is not"},
        {"x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,abc,1,1,0,0,1,1\n", "l.csv:2: r 'abc' is not a number"},
        {"x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,nan,1,1,0,0,1,1\n", "l.csv:2: r is nan: not finite"},
        {"x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,1,inf,1,0,0,1,1\n", "l.csv:2: g is inf: not finite"},
        {"x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,1,1,-2,0,0,1,1\n", "l.csv:2: b is -2: negative"},
        {"x,y,z,r,g,b,u0,v0,u1,v1\n0,0,0,1,1,1,0,0,1,1\n", "l.csv:2: direction 0,0,0"},
        {"x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,1,1,1,0,0,1\n", "l.csv:2: 9 columns, want 10"},
        {"x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,1,1,1,0,0,1,1,7\n", "more than 10 columns"},
        {"x,y,z,r,g,b,u0,v0,u1,v1\n0,0,1,1,1,1,0.5,0,1,1\n", "u0 is 0.5: not a pixel index"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        write_file(c, cases[i].body);
        expect(1, cases[i].want, png, "relight", g, "--lights", c, "--png", png, NULL);
    }
    expect(1, "cannot open", png, "relight", g, "--lights", at("missing.csv"), "--png", png, NULL);
    /* too many rows: 65537 */
    FILE *f = fopen(c, "wb");
    assert_non_null(f);
    fputs("x,y,z,r,g,b,u0,v0,u1,v1\n", f);
    for (int i = 0; i < 65537; ++i)
        fputs("0,0,1,0.001,0.001,0.001,0,0,1,1\n", f);
    fclose(f);
    expect(1, "l.csv:65538: more than 65536 lights", png, "relight", g, "--lights", c, "--png", png, NULL);
    /* a good file lights the asset like the same suns do */
    write_file(c, "x,y,z,r,g,b,u0,v0,u1,v1\n0.3,0.2,1,1,1,1,0,0,1,1\n-1,0.5,0.4,2,1,0.5,0,0,1,1\n");
    OK("relight", g, "--lights", c, "--pfm", at("csv.pfm"));
    OK("relight", g, "--sun", "0.3", "0.2", "1", "--sun", "-1", "0.5", "0.4", "--rgb", "2", "1", "0.5", "--pfm",
       at("suns.pfm"));
    double l1, mx;
    pfm_diff(at("suns.pfm"), at("csv.pfm"), &l1, &mx);
    if (mx > 1e-4)
        fail_msg("--lights of two rows differs from the two --sun: %.3e", mx);
}

static void test_relight_option_errors(void **state)
{
    (void)state;
    need_qibl();
    const char *g = at("g.qibl"), *png = at("x.png"), *pr = at("p.hdr");
    asset(g);
    make_probe(pr, 32, 16, overcast, NULL);
    expect(2, "--rotate: '1,0,0,0,2,0,0,0,1' is not a rotation", png, "relight", g, "--probe", pr, "--rotate",
           "1,0,0,0,2,0,0,0,1", "--png", png, NULL);
    expect(2, "det -1", png, "relight", g, "--probe", pr, "--rotate", "-1,0,0,0,1,0,0,0,1", "--png", png, NULL);
    expect(2, "not nine comma-separated numbers", png, "relight", g, "--probe", pr, "--rotate", "1,0,0", "--png", png,
           NULL);
    expect(2, "need --probe", png, "relight", g, "--sun", "0", "0", "1", "--yaw", "10", "--png", png, NULL);
    expect(2, "comes after a --yaw or --rotate", png, "relight", g, "--probe", pr, "--yaw", "10", "--rotate",
           "1,0,0,0,1,0,0,0,1", "--png", png, NULL);
    expect(2, "-n: '3' is not a power of two", png, "relight", g, "--probe", pr, "--probe-mode", "lights", "-n", "3",
           "--png", png, NULL);
    expect(2, "-n counts median-cut lights", png, "relight", g, "--probe", pr, "-n", "16", "--png", png, NULL);
    expect(2, "--probe-mode: 'soft' is not sh, lights or sunsky", png, "relight", g, "--probe", pr, "--probe-mode",
           "soft", "--png", png, NULL);
    expect(2, "--layout: 'cube' is not a probe layout", png, "relight", g, "--probe", pr, "--layout", "cube", "--png",
           png, NULL);
    expect(2, "--gles takes exactly one", png, "relight", g, "--sun", "0", "0", "1", "--sun", "1", "0", "0", "--gles",
           "--png", png, NULL);
    expect(2, "there is none", png, "relight", g, "--rgb", "1", "1", "1", "--probe", pr, "--png", png, NULL);
    expect(2, "--rgb: given twice", png, "relight", g, "--sun", "0", "0", "1", "--rgb", "1", "1", "1", "--rgb", "2",
           "2", "2", "--png", png, NULL);
    expect(2, "relight needs a light", png, "relight", g, "--png", png, NULL);
    expect(1, NULL, png, "relight", g, "--probe", at("missing.hdr"), "--png", png, NULL);
    /* a probe that does not fit the layout asked for is refused, by name */
    expect(1, "vcross needs 3F x 4F", png, "relight", g, "--probe", pr, "--layout", "vcross", "--png", png, NULL);
    /* the old order, --rgb before --sun, still colours the sun */
    OK("relight", g, "--rgb", "2", "2", "2", "--sun", "0", "0", "1", "--pfm", at("a.pfm"));
    OK("relight", g, "--sun", "0", "0", "1", "--rgb", "2", "2", "2", "--pfm", at("b.pfm"));
    double l1, mx;
    pfm_diff(at("a.pfm"), at("b.pfm"), &l1, &mx);
    assert_true(mx == 0.0);
}

/* ---- sh project --format, lights --json ----------------------------------------------------------- */

static void test_sh_project_formats(void **state)
{
    (void)state;
    need_qibl();
    const char *pr = at("p.hdr");
    make_probe(pr, 64, 32, sunny, NULL);
    double tab[9][3];
    OK("sh", "project", pr, "--bands", "3", "--irradiance");
    char *t = text(outlog);
    int n = 0;
    for (char *line = strtok(t, "\n"); line; line = strtok(NULL, "\n")) {
        int l, m;
        if (line[0] != '#' && n < 9 && sscanf(line, "%d %d %lf %lf %lf", &l, &m, &tab[n][0], &tab[n][1], &tab[n][2]) == 5)
            ++n;
    }
    free(t);
    assert_int_equal(n, 9);
    /* --format cmgen wrote qibl's radiance in cmgen's line layout: refused, pointing to the preset */
    expect(2, "--preset filament writes cmgen's sh.txt", NULL, "sh", "project", pr, "--format", "cmgen", NULL);
    OK("sh", "project", pr, "--bands", "2", "--format", "json");
    t = text(outlog);
    n = 0;
    for (char *p = t; (p = strstr(p, "{\"l\": ")) != NULL; ++p)
        ++n;
    assert_int_equal(n, 4);
    assert_non_null(strstr(t, "\"irradiance\": false"));
    assert_true(t[0] == '{' && strstr(t, "]}\n") != NULL);
    free(t);
    OK("sh", "project", pr, "--bands", "3", "--format", "c", "--name", "sky");
    t = text(outlog);
    assert_non_null(strstr(t, "#define sky_BANDS 3"));
    assert_non_null(strstr(t, "static const float sky[9][3] = {"));
    assert_non_null(strstr(t, "/* [8] l = 2, m = +2 */"));
    free(t);
    expect(2, "--format: 'xml' is not table, json or c", NULL, "sh", "project", pr, "--format", "xml", NULL);
    expect(2, "--name: '9x' is not a C identifier", NULL, "sh", "project", pr, "--format", "c", "--name", "9x", NULL);
}

/* A refused probe leaves stdout empty: sh project printed "# " before loading, so a refusal left a
 * stray "# " on stdout (issue 24); probe info printed its first lines before later failures. */
static void test_probe_refusal_stdout_empty(void **state)
{
    (void)state;
    need_qibl();
    const char *sq = at("square.hdr"), *bad = at("bad.hdr");
    make_probe(sq, 48, 48, overcast, NULL); /* square, corners lit: no layout by itself */
    FILE *f = fopen(bad, "wb");
    assert_non_null(f);
    fputs("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n", f); /* no pixels */
    fclose(f);
    const char *files[2] = {sq, bad}, *why[2] = {"could be angular or ball", bad};
    for (int k = 0; k < 2; ++k) {
        for (int c = 0; c < 2; ++c) {
            int rc = c ? run("probe", "info", files[k], NULL) : run("sh", "project", files[k], NULL);
            char *o = text(outlog), *e = text(errlog);
            if (rc != 1 || o[0] != '\0' || !strstr(e, why[k]))
                fail_msg("%s %s: exit %d, stdout '%s', stderr '%s'", c ? "probe info" : "sh project", files[k], rc, o, e);
            free(o), free(e);
        }
    }
    /* and a good probe still gets its note as the table's first comment line */
    const char *pr = at("p.hdr");
    make_probe(pr, 64, 32, overcast, NULL);
    OK("sh", "project", pr, "--bands", "2");
    char *o = text(outlog);
    assert_true(strncmp(o, "# ", 2) == 0 && strstr(o, "layout latlong") != NULL);
    free(o);
}

/* the table's 9 coefficients of `sh project ARGS...` (radiance unless the args say otherwise) */
static void table9(double t9[9][3], const char *pr, const char *a1, const char *a2)
{
    OK("sh", "project", pr, "--bands", "3", a1, a2);
    char *t = text(outlog);
    int n = 0;
    for (char *line = strtok(t, "\n"); line; line = strtok(NULL, "\n")) {
        int l, m;
        if (line[0] != '#' && n < 9 && sscanf(line, "%d %d %lf %lf %lf", &l, &m, &t9[n][0], &t9[n][1], &t9[n][2]) == 5)
            ++n;
    }
    free(t);
    assert_int_equal(n, 9);
}

/* --preset: the CLI writes what tools/engine computes from the table's radiance (the formulas
 * themselves are tests/engine_test's); --yaw and --frame turn the table as relight turns light */
static void test_sh_project_presets(void **state)
{
    (void)state;
    need_qibl();
    const char *pr = at("p.hdr");
    make_probe(pr, 64, 32, sunny, NULL);
    double t9[9][3], yaw[9][3], yup[9][3];
    table9(t9, pr, "--format", "table");
    qtool_engine_sh e = {.bands = 3};
    memcpy(e.c, t9, sizeof t9);
    double want[9][3], big = 0;
    assert_int_equal(qtool_engine_filament(&e, QTOOL_ENGINE_WINDOW_AUTO, want, NULL, NULL, 0), 0);
    OK("sh", "project", pr, "--preset", "filament");
    char *t = text(outlog);
    int n = 0;
    for (char *line = strtok(t, "\n"); line; line = strtok(NULL, "\n"), ++n) {
        double v[3];
        int l, m;
        if (n >= 9 || sscanf(line, "(%lf, %lf, %lf); // L%1d%d, irradiance, pre-scaled base", &v[0], &v[1], &v[2], &l,
                             &m) != 5 || l * l + l + m != n)
            fail_msg("--preset filament line %d '%s' is not cmgen's sh.txt line", n, line);
        for (int c = 0; c < 3; ++c)
            big = fmax(big, fabs(want[n][c]));
        for (int c = 0; c < 3; ++c)
            if (fabs(v[c] - want[n][c]) > 1e-6 * big)
                fail_msg("--preset filament coefficient %d: %.15g, the library gives %.15g", n, v[c], want[n][c]);
    }
    free(t);
    assert_int_equal(n, 9);
    OK("sh", "project", pr, "--preset", "filament", "--window", "no");
    OK("sh", "project", pr, "--preset", "unity");
    t = text(outlog);
    assert_non_null(strstr(t, "var sh = new UnityEngine.Rendering.SphericalHarmonicsL2();"));
    assert_non_null(strstr(t, "SH9 truncation error"));
    assert_non_null(strstr(t, "var unity_SHC = new Vector4("));
    free(t);
    OK("sh", "project", pr, "--preset", "gltf", "--name", "sky", "--yaw", "30");
    t = text(outlog);
    assert_non_null(strstr(t, "\"irradianceCoefficients\": ["));
    assert_non_null(strstr(t, "\"name\": \"sky\""));
    free(t);
    /* raw, turned: --yaw 90 brings light from +x to +y (Y11 = -c x, Y1-1 = -c y) */
    table9(yaw, pr, "--yaw", "90");
    table9(yup, pr, "--frame", "yup");
    for (int c = 0; c < 3; ++c) {
        double s = 1e-6 * (fabs(t9[0][c]) + fabs(t9[1][c]) + fabs(t9[3][c]));
        assert_true(fabs(yaw[0][c] - t9[0][c]) <= s && fabs(yaw[2][c] - t9[2][c]) <= s);
        assert_true(fabs(yaw[1][c] - t9[3][c]) <= s && fabs(yaw[3][c] + t9[1][c]) <= s);
        /* y up: (x, z, -y) of qibl's */
        assert_true(fabs(yup[2][c] - t9[1][c]) <= s && fabs(yup[1][c] + t9[2][c]) <= s && fabs(yup[3][c] - t9[3][c]) <= s);
    }
    expect(2, "--preset: 'unreal' is not raw, filament, unity or gltf", NULL, "sh", "project", pr, "--preset", "unreal",
           NULL);
    expect(2, "the unity preset is not windowed", NULL, "sh", "project", pr, "--preset", "unity", "--window", "auto", NULL);
    expect(2, "--window: '0' is not auto, no or a cutoff", NULL, "sh", "project", pr, "--preset", "filament", "--window",
           "0", NULL);
    expect(2, "--irradiance: the filament preset has its own scale", NULL, "sh", "project", pr, "--preset", "filament",
           "--irradiance", NULL);
    expect(2, "--frame is for --preset raw", NULL, "sh", "project", pr, "--preset", "gltf", "--frame", "yup", NULL);
    expect(2, "--frame: 'xup' is not zup or yup", NULL, "sh", "project", pr, "--frame", "xup", NULL);
    expect(2, "--bands 2: the unity preset needs 3 bands", NULL, "sh", "project", pr, "--preset", "unity", "--bands", "2",
           NULL);
    expect(2, "--format is for --preset raw", NULL, "sh", "project", pr, "--preset", "gltf", "--format", "json", NULL);
    expect(2, "--yaw: '2' comes after a --yaw or --rotate: give one of them, once", NULL, "sh", "project", pr, "--yaw", "1", "--yaw", "2", NULL);
    expect(2, "is not a rotation", NULL, "sh", "project", pr, "--rotate", "1,0,0,0,1,0,0,0,-1", NULL);
    /* lights as KHR_lights_punctual */
    OK("lights", pr, "-n", "4", "--preset", "gltf");
    t = text(outlog);
    n = 0;
    for (char *q = t; (q = strstr(q, "\"type\": \"directional\"")) != NULL; ++q)
        ++n;
    assert_int_equal(n, 4);
    assert_true(strncmp(t, "{\"extensionsUsed\": [\"KHR_lights_punctual\"]", 40) == 0);
    free(t);
    OK("lights", pr, "-n", "4", "--preset", "gltf", "--yaw", "45");
    expect(2, "--preset gltf writes its own JSON: it does not go with --csv or --json", NULL, "lights", pr, "--preset", "gltf", "--csv", NULL);
    expect(2, "lights are written for gltf", NULL, "lights", pr, "--preset", "unity", NULL);
    expect(2, "--yaw and --rotate turn the lights of --preset gltf", NULL, "lights", pr, "--yaw", "10", NULL);
}

static void test_lights_json(void **state)
{
    (void)state;
    need_qibl();
    const char *pr = at("p.hdr");
    make_probe(pr, 64, 32, sunny, NULL);
    OK("lights", pr, "-n", "8", "--json");
    char *t = text(outlog);
    int n = 0;
    for (char *p = t; (p = strstr(p, "\"dir\": [")) != NULL; ++p)
        ++n;
    assert_int_equal(n, 8);
    assert_non_null(strstr(t, "\"count\": 8"));
    assert_true(t[0] == '{');
    free(t);
    expect(2, "--csv and --json", NULL, "lights", pr, "--csv", "--json", NULL);
    /* an all-black probe: still a JSON document, with no lights */
    float px[3 * 8 * 4] = {0};
    char err[256];
    assert_int_equal(qtool_hdr_write(at("black.hdr"), 8, 4, px, err, sizeof err), 0);
    OK("lights", at("black.hdr"), "-n", "4", "--json");
    t = text(outlog);
    assert_non_null(strstr(t, "\"count\": 0, \"lights\": []"));
    free(t);
}

/* ---- probe info --------------------------------------------------------------------------------- */

static char *advice(const char *probe)
{
    OK("probe", "info", probe);
    char *t = text(outlog);
    char *a = strstr(t, "advice: ");
    if (!a)
        fail_msg("probe info %s: no advice in '%s'", probe, t);
    char *r = strdup(a);
    printf("%s", t);
    free(t);
    return r;
}

static void test_probe_info_advice(void **state)
{
    (void)state;
    need_qibl();
    const char *soft = at("overcast.hdr"), *sun = at("sun.hdr"), *blk = at("black.hdr");
    make_probe(soft, 128, 64, overcast, NULL);
    make_probe(sun, 128, 64, sunny, NULL);
    char *a = advice(soft);
    if (strncmp(a, "advice: SH", 10) != 0)
        fail_msg("overcast probe: '%s', want SH", a);
    free(a);
    a = advice(sun);
    if (strncmp(a, "advice: sun plus SH", 19) != 0 && strstr(a, "median-cut lights") == NULL)
        fail_msg("sun probe: '%s', want lights or sun plus SH", a);
    free(a);
    OK("probe", "info", sun);
    char *t = text(outlog);
    assert_non_null(strstr(t, "layout latlong"));
    assert_non_null(strstr(t, "dynamic range"));
    assert_non_null(strstr(t, "brightest 0.1 %"));
    free(t);
    float px[3 * 8 * 4] = {0};
    char err[256];
    assert_int_equal(qtool_hdr_write(blk, 8, 4, px, err, sizeof err), 0);
    OK("probe", "info", blk);
    t = text(outlog);
    assert_non_null(strstr(t, "all-black"));
    free(t);
    expect(2, "'show' is not a subcommand (info)", NULL, "probe", "show", sun, NULL);
    expect(2, "--layout: 'disc'", NULL, "probe", "info", sun, "--layout", "disc", NULL);
    expect(1, NULL, NULL, "probe", "info", at("missing.hdr"), NULL);
    /* a lat-long that is not 2:1 (read as lat-long on request) is refused by name, stdout empty */
    const char *odd = at("odd.hdr");
    make_probe(odd, 64, 40, overcast, NULL);
    expect(1, "64 x 40 is not a 2:1 lat-long", NULL, "probe", "info", odd, "--layout", "latlong", NULL);
    t = text(outlog);
    assert_string_equal(t, "");
    free(t);
}

/* the figure on the line of stdout that starts (after spaces) with label, the first number after
 * skip (a phrase on that line); NAN when absent */
static double figure_after(const char *out, const char *label, const char *skip)
{
    for (const char *l = out; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
        const char *b = l;
        while (*b == ' ')
            ++b;
        if (strncmp(b, label, strlen(label)) != 0)
            continue;
        const char *k = strstr(b, skip);
        const char *nl = strchr(b, '\n');
        double v;
        if (k && (!nl || k < nl) && sscanf(k + strlen(skip), "%lf", &v) == 1)
            return v;
    }
    return NAN;
}

/* probe info and lights --auto print one irradiance error, the same number for the same
 * representation (they printed 9.4 % and 3.47 % for Grace's SH9: two measures), and both say
 * what it is */
static void test_probe_info_auto_same_measure(void **state)
{
    (void)state;
    need_qibl();
    const char *pr = at("sun.hdr");
    make_probe(pr, 128, 64, sunny, NULL);
    OK("probe", "info", pr);
    char *t = text(outlog);
    double info = figure_after(t, "SH, 9 coefficients", "coefficients");
    assert_non_null(strstr(t, "|E - E_probe| / max(E_probe, mean E_probe / 10)"));
    free(t);
    if (!isfinite(info))
        fail_msg("probe info printed no SH9 error");
    /* a budget SH9 just meets (auto lists the cheapest SH that meets it; SH4 is far worse here) */
    char budget[64];
    snprintf(budget, sizeof budget, "%.3f%%", info + 0.0005);
    OK("lights", pr, "--auto", "--error", budget);
    t = text(outlog);
    double aut = figure_after(t, "SH irradiance, 9 coefficients", "mean error");
    assert_non_null(strstr(t, "|E - E_probe| / max(E_probe, mean E_probe / 10)"));
    if (!(fabs(aut - info) < 1e-9))
        fail_msg("SH9: probe info %.3f %%, lights --auto %.3f %%\n%s", info, aut, t);
    free(t);
}

/* up to per numbers after each occurrence of key in s (up to max in all), in order; how many */
static int numbers_after(const char *s, const char *key, int per, double *v, int max)
{
    int n = 0;
    for (const char *q = strstr(s, key); q && n < max; q = strstr(q + 1, key)) {
        q += strlen(key);
        char *e;
        for (int k = 0; k < per && n < max; ++k) {
            while (*q == ' ' || *q == '[' || *q == ',' || *q == '\n' || *q == ']')
                ++q;
            double x = strtod(q, &e);
            if (e == q)
                break;
            v[n++] = x, q = e;
        }
    }
    return n;
}

/* lights --auto writes what it picks: the JSON's lights (their refitted colours where the pick
 * refits) and SH coefficients, put back into the study's model, give the mean error --auto
 * printed, measured again here from the probe's own bytes; --csv and --format c carry the same
 * numbers; a budget nothing meets still writes the most accurate, marked so. */
static void test_lights_auto_writes_pick(void **state)
{
    (void)state;
    need_qibl();
    const char *pr = at("sun.hdr");
    double big = 300.0;
    make_probe(pr, 128, 64, sunny, &big);
    static const char *const budgets[] = {"3%", "0.5%", "40%", "0.0001%"};
    int kinds = 0;
    for (int b = 0; b < 4; ++b) {
        OK("lights", pr, "--auto", "--error", budgets[b], "--json");
        char *t = text(outlog), *log = text(errlog);
        const char *lights = strstr(t, "\"lights\": ["), *sh = strstr(t, "\"sh\": [");
        if (!lights || !sh || !strstr(log, "auto: "))
            fail_msg("--json: no lights/sh arrays on stdout or no table on stderr\n%s\n%s", t, log);
        qtool_study_model md;
        memset(&md, 0, sizeof md);
        double v[6 * QTOOL_STUDY_MAX_LIGHTS], err = NAN;
        numbers_after(t, "\"mean_error\": ", 1, &err, 1);
        char *shpart = strdup(sh);
        ((char *)sh)[0] = '\0'; /* the lights part ends where the SH part starts */
        int nd = numbers_after(lights, "\"dir\": ", 3, v, 3 * QTOOL_STUDY_MAX_LIGHTS);
        md.n = nd / 3;
        for (int i = 0; i < md.n; ++i)
            for (int c = 0; c < 3; ++c)
                md.dir[i][c] = v[3 * i + c];
        int nr = numbers_after(lights, "\"rgb\": ", 3, v, 3 * QTOOL_STUDY_MAX_LIGHTS);
        assert_int_equal(nr, 3 * md.n);
        for (int i = 0; i < md.n; ++i)
            for (int c = 0; c < 3; ++c)
                md.rgb[i][c] = v[3 * i + c];
        double s[3 * QTOOL_STUDY_SH_MAX];
        int ns = numbers_after(shpart, "\"sh\": [", 3 * QTOOL_STUDY_SH_MAX, s, 3 * QTOOL_STUDY_SH_MAX);
        md.sh_n = ns / 3;
        assert_int_equal(ns % 3, 0);
        for (int i = 0; i < md.sh_n; ++i)
            for (int c = 0; c < 3; ++c)
                md.sh[c][i] = s[3 * i + c];
        kinds |= (md.n > 0) << 0 | (md.sh_n > 0) << 1;
        /* the error again, from the exported numbers */
        int w, h;
        uint8_t *rgbe;
        char e2[256];
        assert_int_equal(qtool_hdr_read_rgbe(pr, &w, &h, &rgbe, e2, sizeof e2), 0);
        qtool_study_probe p;
        assert_int_equal(qtool_study_probe_init(&p, w, h, rgbe, e2, sizeof e2), 0);
        qtool_study_gt g;
        assert_int_equal(qtool_study_gt_compute(&g, &p, QTOOL_STUDY_ERR_NORMALS, 1), 0);
        qtool_study_err e;
        qtool_study_model_error(&md, &g, &e);
        if (!(fabs(e.mean_rel - err) <= 1e-6 * err + 1e-9))
            fail_msg("budget %s: the exported model gives %.9g, --auto printed %.9g\n%s", budgets[b], e.mean_rel, err, t);
        const int met = strstr(t, "\"met\": true") != NULL;
        assert_int_equal(met, b != 3); /* 0.0001 % is beyond every candidate */
        qtool_study_gt_free(&g);
        qtool_study_probe_free(&p);
        free(rgbe);
        /* --csv: rows light,i,x,y,z,r,g,b then sh,i,,,,r,g,b; the same numbers */
        OK("lights", pr, "--auto", "--error", budgets[b], "--csv");
        char *csv = text(outlog);
        assert_non_null(strstr(csv, "kind,index,x,y,z,r,g,b\n"));
        int rows = 0;
        for (const char *q = strchr(csv, '\n') + 1; *q; q = strchr(q, '\n') + 1, ++rows) {
            int i;
            double x[6];
            if (sscanf(q, "light,%d,%lf,%lf,%lf,%lf,%lf,%lf", &i, &x[0], &x[1], &x[2], &x[3], &x[4], &x[5]) == 7) {
                assert_true(i == rows && i < md.n);
                for (int c = 0; c < 3; ++c)
                    assert_true(fabs(x[c] - md.dir[i][c]) < 1e-8 && fabs(x[3 + c] - md.rgb[i][c]) <= 1e-8 * fabs(md.rgb[i][c]));
            } else if (sscanf(q, "sh,%d,,,,%lf,%lf,%lf", &i, &x[0], &x[1], &x[2]) == 4) {
                assert_true(i == rows - md.n && i < md.sh_n);
                for (int c = 0; c < 3; ++c)
                    assert_true(fabs(x[c] - md.sh[c][i]) <= 1e-8 * fabs(md.sh[c][i]));
            } else {
                fail_msg("--csv row %d: %.60s", rows, q);
            }
        }
        assert_int_equal(rows, md.n + md.sh_n);
        /* --format c: the counts and the arrays */
        OK("lights", pr, "--auto", "--error", budgets[b], "--format", "c");
        char *cf = text(outlog);
        char want[128];
        snprintf(want, sizeof want, "QIBL_AUTO_LIGHT_COUNT = %d, QIBL_AUTO_SH_COUNT = %d", md.n, md.sh_n);
        if (!strstr(cf, want) || !strstr(cf, "static const float qibl_auto_lights[") ||
            !strstr(cf, "static const float qibl_auto_sh["))
            fail_msg("--format c: no '%s' or arrays\n%s", want, cf);
        free(cf), free(csv), free(shpart), free(t), free(log);
    }
    assert_int_equal(kinds, 3); /* some pick had lights, some SH (the budgets span both) */
    expect(2, "--format c writes the pick of --auto", NULL, "lights", pr, "--format", "c", NULL);
    expect(2, "--format: 'yaml' is not c, csv or json", NULL, "lights", pr, "--auto", "--error", "3%", "--format", "yaml", NULL);
}

/* the real probes, when ../shared is there: a soft one wants SH, a sunny one does not */
static void test_probe_info_fixtures(void **state)
{
    (void)state;
    need_qibl();
    if (access(FIXTURES "/venice_sunset_1k.hdr", R_OK) != 0 || access(FIXTURES "/quarry_01_1k.hdr", R_OK) != 0) {
        fprintf(stderr, "SKIP: %s not present\n", FIXTURES);
        skip();
    }
    char *a = advice(FIXTURES "/venice_sunset_1k.hdr");
    if (strncmp(a, "advice: SH", 10) != 0)
        fail_msg("venice_sunset: '%s', want SH", a);
    free(a);
    a = advice(FIXTURES "/quarry_01_1k.hdr");
    if (strncmp(a, "advice: SH", 10) == 0)
        fail_msg("quarry_01 (a sun): '%s', want lights or sun plus SH", a);
    free(a);
}

static void test_help_texts(void **state)
{
    (void)state;
    need_qibl();
    static const struct {
        const char *cmd, *want;
    } h[] = {{"relight", "positive yaw turns +x toward +y"},
             {"relight", "--lights FILE.csv"},
             {"relight", "--probe-mode sh"},
             {"probe", "usage: qibl probe info [--layout L] PROBE.hdr"},
             {"sh", "--format table|json|c"},
             {"sh", "--preset raw|filament|unity|gltf"},
             {"lights", "--preset gltf"},
             {"lights", "--json"}};
    for (size_t i = 0; i < sizeof h / sizeof h[0]; ++i) {
        OK("help", h[i].cmd);
        char *t = text(outlog);
        if (!strstr(t, h[i].want))
            fail_msg("qibl help %s does not say '%s'", h[i].cmd, h[i].want);
        free(t);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_relight_probe_sh_against_lights, setup, teardown),
        cmocka_unit_test_setup_teardown(test_relight_yaw_sign, setup, teardown),
        cmocka_unit_test_setup_teardown(test_relight_lights_add_up, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lights_csv_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_relight_option_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sh_project_formats, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sh_project_presets, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lights_json, setup, teardown),
        cmocka_unit_test_setup_teardown(test_probe_refusal_stdout_empty, setup, teardown),
        cmocka_unit_test_setup_teardown(test_probe_info_advice, setup, teardown),
        cmocka_unit_test_setup_teardown(test_probe_info_fixtures, setup, teardown),
        cmocka_unit_test_setup_teardown(test_probe_info_auto_same_measure, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lights_auto_writes_pick, setup, teardown),
        cmocka_unit_test_setup_teardown(test_help_texts, setup, teardown),
    };
    return cmocka_run_group_tests_name("probe_cli", tests, NULL, NULL);
}
