/*
 * view_test.c - `qibl view` (tools/view) in a real window system: an Xvfb server on a free display,
 * the viewer opened on a small courtyard, the sun dragged with xdotool (XTEST pointer events), the
 * window grabbed with XGetImage and compared with `qibl relight --sun` of the light the viewer
 * reports: equal bytes (both are the core's weights through platform/soft's sRGB conversion). Plus
 * the state functions without a window (drag, keys, overlay).
 *
 * Skipped (CMocka skip) where this build has no X11 or Xvfb / xdotool are not installed;
 * QIBL_REQUIRE_VIEW=1 (CI) turns a skip into a failure.
 */
#include "cliutil.h"

#include <math.h>
#include <poll.h>
#include <signal.h>
#include <time.h>

#include "io/hdr_write.h"
#include "io/png.h"
#include "view/view.h"
#include "qibl/asset.h"

#if QIBL_HAVE_X11
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#endif

#define VIEW_W 256
#define VIEW_H 64

static void need(int ok, const char *what)
{
    if (ok)
        return;
    const char *r = getenv("QIBL_REQUIRE_VIEW");
    if (r && strcmp(r, "1") == 0)
        fail_msg("QIBL_REQUIRE_VIEW=1 but %s", what);
    fprintf(stderr, "SKIP: %s\n", what);
    skip();
}


/* a small probe: a warm bright patch over a dim blue sky and a dark ground */
static void write_probe(const char *path)
{
    enum { PW = 64, PH = 32 };
    static float px[PW * PH * 3];
    for (int y = 0; y < PH; ++y)
        for (int x = 0; x < PW; ++x) {
            float *o = px + 3 * (y * PW + x);
            int sunp = abs(x - 20) < 3 && abs(y - 8) < 3;
            o[0] = sunp ? 40.0f : y < PH / 2 ? 0.3f : 0.05f;
            o[1] = sunp ? 30.0f : y < PH / 2 ? 0.4f : 0.05f;
            o[2] = sunp ? 20.0f : y < PH / 2 ? 0.8f : 0.04f;
        }
    char err[256];
    assert_int_equal(qtool_hdr_write(path, PW, PH, px, err, sizeof err), 0);
}

/* a z-up OBJ: a 6 x 6 ground grid over [-1, 1]^2 with a box standing on it (the box shadows the
 * ground, so the transfer is not the unshadowed one) */
static void write_mesh(const char *path)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    enum { G = 6 };
    for (int j = 0; j <= G; ++j)
        for (int i = 0; i <= G; ++i)
            fprintf(f, "v %g %g 0\n", -1 + 2.0 * i / G, -1 + 2.0 * j / G);
    for (int j = 0; j < G; ++j)
        for (int i = 0; i < G; ++i) {
            int a = 1 + j * (G + 1) + i, b = a + 1, c = a + G + 1, d = c + 1;
            fprintf(f, "f %d %d %d\nf %d %d %d\n", a, b, d, a, d, c);
        }
    const int o = (G + 1) * (G + 1); /* the box's 8 corners after the grid */
    for (int k = 0; k < 8; ++k)
        fprintf(f, "v %g %g %g\n", k & 1 ? 0.3 : -0.3, k & 2 ? 0.3 : -0.3, k & 4 ? 0.6 : 0.01);
    static const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int k = 0; k < 6; ++k)
        fprintf(f, "f %d %d %d\nf %d %d %d\n", o + 1 + q[k][0], o + 1 + q[k][1], o + 1 + q[k][2], o + 1 + q[k][0],
                o + 1 + q[k][2], o + 1 + q[k][3]);
    assert_int_equal(fclose(f), 0);
}

#if QIBL_HAVE_X11
static int on_path(const char *prog)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", prog);
    return system(cmd) == 0;
}

static void sleep_ms(long ms)
{
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

/* spawns argv with stdout/stderr to out (NULL: /dev/null) and extra environment `env` (may be NULL) */
static pid_t spawn(char **argv, const char *out, const char *env)
{
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, out ? out : "/dev/null", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    char *envp[256];
    int n = 0;
    for (char **e = environ; *e && n < 250; ++e)
        if (!env || strncmp(*e, "DISPLAY=", 8) != 0)
            envp[n++] = *e;
    if (env)
        envp[n++] = (char *)env;
    envp[n] = NULL;
    pid_t pid;
    int rc = posix_spawnp(&pid, argv[0], &fa, NULL, argv, envp);
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? pid : -1;
}

/* Xvfb with its -displayfd pipe: the read end `closefd` closed in the child, output to /dev/null */
static pid_t spawn_keep(char **argv, int closefd)
{
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addclose(&fa, closefd);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid;
    int rc = posix_spawnp(&pid, argv[0], &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? pid : -1;
}

/* the number of "view: sun" lines in the log, and the last one's direction; plus mesh mode's
 * "view: mesh" lines (one per settled change, as the sun's) */
static int log_lines(const char *path, double sun[3])
{
    char *t = text(path), *p = t;
    int n = 0;
    while ((p = strstr(p, "view: sun ")) != NULL) {
        if (sscanf(p, "view: sun %lf %lf %lf", &sun[0], &sun[1], &sun[2]) == 3)
            ++n;
        p += 10;
    }
    for (p = t; (p = strstr(p, "view: mesh ")) != NULL; p += 11)
        ++n;
    free(t);
    return n;
}

static int wait_lines(const char *path, int want, double sun[3])
{
    for (int i = 0; i < 200; ++i) { /* 10 s */
        if (log_lines(path, sun) >= want)
            return 1;
        sleep_ms(50);
    }
    return 0;
}

static int xdo(const char *display, const char *args)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "DISPLAY=%s xdotool %s >/dev/null 2>&1", display, args);
    return system(cmd);
}

/* one input at a time: the viewer logs once per drawn frame, so inputs sent together may share a
 * line; each is sent only after the line of the one before it */
static int xdo_steps(const char *display, const char *vlog, const char *const *steps, int *lines)
{
    double sun[3];
    for (const char *const *st = steps; *st; ++st) {
        char cmd[400];
        snprintf(cmd, sizeof cmd, "search --sync --name 'qibl view' windowfocus --sync %s", *st);
        if (xdo(display, cmd) != 0 || !wait_lines(vlog, ++*lines, sun))
            return print_error("view_test: '%s' did not reach the viewer\n", *st), -1;
    }
    return 0;
}

/* one Xvfb server and one viewer on it */
typedef struct session {
    char display[16], asset[160], vlog[128];
    pid_t xvfb, viewer;
    Display *dpy;
} session;

static void need_tools(void)
{
    need_qibl();
    need(on_path("Xvfb"), "Xvfb is not installed (Debian: xvfb)");
    need(on_path("xdotool"), "xdotool is not installed (Debian: xdotool)");
}

/* a scratch dir, a 256x64 courtyard, Xvfb on a free display, the viewer with extra arguments
 * (NULL-terminated) showing its first frame; 0, or -1 after a message */
static int session_launch(session *ss, char **extra);

static int session_start_asset(session *ss, char **extra, int baked)
{
    memset(ss, 0, sizeof *ss);
    ss->xvfb = ss->viewer = -1;
    assert_int_equal(cli_setup("/tmp/qibl-view-XXXXXX"), 0);
    snprintf(ss->asset, sizeof ss->asset, "%s/a.qibl", dir);
    if (baked) /* ray-traced, with a sun path (LPTH) */
        assert_int_equal(run("bake", "-o", ss->asset, "--size", "256x64", "--dirs", "16", "--k", "9", "--sun-path",
                             "40,10,8,16", "--path-steps", "8", NULL), 0);
    else
        assert_int_equal(run("gen", "-o", ss->asset, "--size", "256x64", "--k", "9", NULL), 0);
    return session_launch(ss, extra);
}

/* Xvfb and the viewer of ss->asset (a file in the scratch dir) with extra arguments */
static int session_launch(session *ss, char **extra)
{
    snprintf(ss->vlog, sizeof ss->vlog, "%s/view.log", dir);
    /* Xvfb picks a free display itself and writes its number to a pipe (-displayfd): no race with
     * other suites or helpers choosing at the same time */
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    char fdarg[16];
    snprintf(fdarg, sizeof fdarg, "%d", fds[1]);
    char *xargv[] = {"Xvfb", "-displayfd", fdarg, "-screen", "0", "640x480x24", "-nolisten", "tcp", NULL};
    ss->xvfb = spawn_keep(xargv, fds[0]);
    close(fds[1]);
    assert_true(ss->xvfb > 0);
    char num[16] = "";
    size_t got = 0;
    struct pollfd pf = {.fd = fds[0], .events = POLLIN};
    while (got < sizeof num - 1 && !strchr(num, '\n') && poll(&pf, 1, 10000) > 0) { /* 10 s at most */
        ssize_t r = read(fds[0], num + got, sizeof num - 1 - got);
        if (r <= 0)
            break;
        got += (size_t)r, num[got] = '\0';
    }
    close(fds[0]);
    if (!strchr(num, '\n'))
        return print_error("view_test: Xvfb did not say its display\n"), -1;
    snprintf(ss->display, sizeof ss->display, ":%d", atoi(num));
    for (int i = 0; i < 100 && !ss->dpy; ++i) { /* 5 s for the server to come up */
        sleep_ms(50);
        ss->dpy = XOpenDisplay(ss->display);
    }
    if (!ss->dpy)
        return print_error("view_test: Xvfb on %s did not start\n", ss->display), -1;
    char denv[32];
    snprintf(denv, sizeof denv, "DISPLAY=%s", ss->display);
    char *vargv[32] = {qibl, "view", ss->asset};
    int n = 3;
    for (char **e = extra; e && *e && n < 31; ++e)
        vargv[n++] = *e;
    vargv[n] = NULL;
    ss->viewer = spawn(vargv, ss->vlog, denv);
    double sun[3];
    if (ss->viewer <= 0 || !wait_lines(ss->vlog, 1, sun))
        return print_error("view_test: the viewer showed no first frame\n"), -1;
    return 0;
}

static int session_start(session *ss, char **extra)
{
    return session_start_asset(ss, extra, 0);
}

/* the viewer's frame (its top-left W x H) as the X server holds it, compared with a PNG: differing
 * channel values (-1: no window) */
static long grab_compare_size(session *ss, const char *png, int W, int H)
{
    Window root = DefaultRootWindow(ss->dpy), r2, parent, *kids = NULL, win = 0;
    unsigned nk = 0;
    if (XQueryTree(ss->dpy, root, &r2, &parent, &kids, &nk))
        for (unsigned i = 0; i < nk && !win; ++i) {
            char *name = NULL;
            if (XFetchName(ss->dpy, kids[i], &name) && name && strcmp(name, "qibl view") == 0)
                win = kids[i];
            if (name)
                XFree(name);
        }
    if (kids)
        XFree(kids);
    if (!win)
        return print_error("view_test: no 'qibl view' window\n"), -1;
    XImage *img = XGetImage(ss->dpy, win, 0, 0, (unsigned)W, (unsigned)H, AllPlanes, ZPixmap);
    if (!img)
        return print_error("view_test: XGetImage failed\n"), -1;
    int w, h, fr;
    uint8_t *ref = NULL;
    char err[256];
    if (qtool_png_read_rgb8(png, &w, &h, &fr, &ref, err, sizeof err) != 0 || w != W || h != H) {
        XDestroyImage(img);
        return print_error("view_test: %s\n", err), -1;
    }
    long diff = 0, maxd = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            unsigned long p = XGetPixel(img, x, y);
            long got[3] = {(long)((p >> 16) & 255), (long)((p >> 8) & 255), (long)(p & 255)};
            for (int c = 0; c < 3; ++c) {
                long d = labs(got[c] - ref[3 * (y * W + x) + c]);
                diff += d != 0, maxd = d > maxd ? d : maxd;
            }
        }
    XDestroyImage(img);
    free(ref);
    if (diff)
        print_error("view_test: the window differs from the offline frame in %ld channel values (max %ld)\n", diff,
                    maxd);
    return diff;
}

static long grab_compare(session *ss, const char *png)
{
    return grab_compare_size(ss, png, VIEW_W, VIEW_H);
}

/* q quits the viewer with status 0; then everything is stopped; ok: keep no scratch files */
static int session_end(session *ss, int ok)
{
    if (ok && ss->viewer > 0) {
        ok = 0;
        xdo(ss->display, "search --name 'qibl view' key --window %1 q");
        for (int i = 0; i < 100; ++i) {
            int st;
            if (waitpid(ss->viewer, &st, WNOHANG) == ss->viewer) {
                ss->viewer = -1;
                ok = WIFEXITED(st) && WEXITSTATUS(st) == 0;
                break;
            }
            sleep_ms(50);
        }
        if (!ok)
            print_error("view_test: q did not end the viewer cleanly\n");
    }
    if (ss->viewer > 0)
        kill(ss->viewer, SIGTERM), waitpid(ss->viewer, NULL, 0);
    if (ss->dpy)
        XCloseDisplay(ss->dpy);
    if (ss->xvfb > 0)
        kill(ss->xvfb, SIGTERM), waitpid(ss->xvfb, NULL, 0);
    if (ok)
        rm_rf(dir);
    else
        fprintf(stderr, "view_test: scratch files kept in %s\n", dir);
    return ok;
}
#endif

static void test_drag_matches_relight(void **state)
{
    (void)state;
#if !QIBL_HAVE_X11
    need(0, "qibl was built without X11 (libx11-dev)");
#else
    need_tools();
    session ss;
    char *extra[] = {"--sun", "1", "0", "0.5", NULL};
    int ok = 0;
    double sun[3];
    char png[128], sun_s[3][40];
    if (session_start(&ss, extra) != 0)
        goto out;
    snprintf(png, sizeof png, "%s/relight.png", dir);
    /* drag: 60 pixels left-to-right, 10 up, in three moves (motion events in between) */
    if (xdo(ss.display, "search --sync --name 'qibl view' windowfocus --sync "
                        "mousemove --window %1 100 40 mousedown 1 mousemove --window %1 130 35 "
                        "mousemove --window %1 160 30 mouseup 1") != 0 ||
        !wait_lines(ss.vlog, 2, sun)) {
        print_error("view_test: the drag did not reach the viewer\n");
        goto out;
    }
    /* the drag's meaning: the start sun (az 0, el atan(1/2)) turned by -360 * 60/256 in azimuth and
     * raised by 180 * 10/64 in elevation (qtool_view_drag) */
    {
        const double pi = 3.14159265358979323846;
        double az = -360.0 * 60 / VIEW_W * pi / 180.0, el = atan(0.5) + 180.0 * 10 / VIEW_H * pi / 180.0;
        double want[3] = {cos(el) * cos(az), cos(el) * sin(az), sin(el)};
        for (int c = 0; c < 3; ++c)
            if (fabs(sun[c] - want[c]) > 1e-3) {
                print_error("view_test: after the drag the sun is %g %g %g, not %g %g %g\n", sun[0], sun[1], sun[2],
                            want[0], want[1], want[2]);
                goto out;
            }
    }
    for (int c = 0; c < 3; ++c)
        snprintf(sun_s[c], sizeof sun_s[c], "%.17g", sun[c]);
    if (run("relight", ss.asset, "--sun", sun_s[0], sun_s[1], sun_s[2], "--png", png, NULL) != 0) {
        print_error("view_test: qibl relight failed\n");
        goto out;
    }
    ok = grab_compare(&ss, png) == 0;
out:
    assert_true(session_end(&ss, ok));
#endif
}

/* keys: s three times (sun + SH -> lamp -> sun -> the probe's SH alone), Y (yaw +15 degrees): the window equals
 * `qibl relight --probe P --yaw 15`; s again (its median-cut lights): `--probe-mode lights` */
static void test_probe_yaw_matches_relight(void **state)
{
    (void)state;
#if !QIBL_HAVE_X11
    need(0, "qibl was built without X11 (libx11-dev)");
#else
    need_tools();
    /* a small probe: a warm bright patch over a dim blue sky and a dark ground */
    char probe[160], png[128];
    char tmpl[] = "/tmp/qibl-viewprobe-XXXXXX";
    assert_non_null(mkdtemp(tmpl));
    snprintf(probe, sizeof probe, "%s/p.hdr", tmpl);
    {
        enum { PW = 64, PH = 32 };
        static float px[PW * PH * 3];
        for (int y = 0; y < PH; ++y)
            for (int x = 0; x < PW; ++x) {
                float *o = px + 3 * (y * PW + x);
                int sunp = abs(x - 20) < 3 && abs(y - 8) < 3;
                o[0] = sunp ? 40.0f : y < PH / 2 ? 0.3f : 0.05f;
                o[1] = sunp ? 30.0f : y < PH / 2 ? 0.4f : 0.05f;
                o[2] = sunp ? 20.0f : y < PH / 2 ? 0.8f : 0.04f;
            }
        char err[256];
        assert_int_equal(qtool_hdr_write(probe, PW, PH, px, err, sizeof err), 0);
    }
    session ss;
    char *extra[] = {"--probe", probe, NULL};
    int ok = 0;
    if (session_start(&ss, extra) != 0)
        goto out;
    snprintf(png, sizeof png, "%s/relight.png", dir);
    int lines = 1;
    const char *const keys[] = {"key --window %1 s", "key --window %1 s", "key --window %1 s", "key --window %1 Y",
                                NULL};
    if (xdo_steps(ss.display, ss.vlog, keys, &lines) != 0)
        goto out;
    {
        char *t = text(ss.vlog);
        int seen = strstr(t, "SH | PROBE 1/1 p.hdr YAW 15") != NULL;
        if (!seen)
            print_error("view_test: the log does not show the SH scheme at yaw 15:\n%s", t);
        free(t);
        if (!seen)
            goto out;
    }
    if (run("relight", ss.asset, "--probe", probe, "--yaw", "15", "--png", png, NULL) != 0) {
        print_error("view_test: qibl relight failed\n");
        goto out;
    }
    if (grab_compare(&ss, png) != 0)
        goto out;
    /* s once more: the probe's median-cut lights, as relight --probe-mode lights */
    const char *const key_s[] = {"key --window %1 s", NULL};
    if (xdo_steps(ss.display, ss.vlog, key_s, &lines) != 0)
        goto out;
    if (run("relight", ss.asset, "--probe", probe, "--probe-mode", "lights", "--yaw", "15", "--png", png, NULL) != 0) {
        print_error("view_test: qibl relight failed\n");
        goto out;
    }
    ok = grab_compare(&ss, png) == 0;
out:
    rm_rf(tmpl);
    assert_true(session_end(&ss, ok));
#endif
}

/* the state without a window: drags wrap the azimuth and clamp the elevation; keys name their limits */
static void test_state(void **state)
{
    (void)state;
    static uint8_t planes[4 * 2 * 9 * 3], params[9 * 3 * 8];
    qibl_shmaps_t m = {.width = 4, .height = 2, .k = 9, .channels = 3, .params = params, .planes = planes};
    qtool_view v;
    assert_int_equal(qtool_view_init(&v, &m), 0);
    qtool_view_drag(&v, 0, -1000, 4, 2);
    assert_true(v.el == QTOOL_VIEW_EL_MAX);
    qtool_view_drag(&v, 0, 1000, 4, 2);
    assert_true(v.el == -QTOOL_VIEW_EL_MAX);
    qtool_view_drag(&v, 2, 0, 4, 2); /* half a width: 180 degrees */
    assert_true(fabs(v.az - 225.0) < 1e-9);
    assert_int_equal(qtool_view_key(&v, 's'), 0); /* no probe: the sun is the only scheme */
    assert_int_equal(qtool_view_key(&v, 'k'), 1);
    assert_int_equal(v.k, 4);
    assert_int_equal(qtool_view_key(&v, 'k'), 1);
    assert_int_equal(v.k, 1);
    assert_int_equal(qtool_view_key(&v, 'k'), 1);
    assert_int_equal(v.k, 9);
    int n = 0;
    while (qtool_view_key(&v, '+'))
        ++n;
    assert_int_equal(v.exposure, QTOOL_VIEW_EXPOSURE_MAX);
    assert_int_equal(n, 8);
    while (qtool_view_key(&v, '-'))
        ;
    assert_int_equal(v.exposure, QTOOL_VIEW_EXPOSURE_MIN);
    char l1[160], l2[160];
    qtool_view_describe(&v, 60.0, l1, l2, sizeof l1);
    assert_non_null(strstr(l1, "SUN"));
    assert_non_null(strstr(l2, "K 9"));
    assert_non_null(strstr(l2, "60 FPS"));
}

/* the last "lamp X Y Z rgb R G B" of the log; 1 if found */
static int last_lamp(const char *path, double lamp[6])
{
    char *t = text(path), *p = t;
    int found = 0;
    while ((p = strstr(p, " lamp ")) != NULL) {
        found |= sscanf(p, " lamp %lf %lf %lf rgb %lf %lf %lf", &lamp[0], &lamp[1], &lamp[2], &lamp[3], &lamp[4],
                        &lamp[5]) == 6;
        p += 6;
    }
    free(t);
    return found;
}

/* s (the lamp), then a drag: the lamp follows the P map under the pointer (1/10 of the way toward
 * the viewpoint), and the window equals `qibl relight --point X Y Z --rgb R G B` */
static void test_lamp_pick_matches_relight(void **state)
{
    (void)state;
#if !QIBL_HAVE_X11
    need(0, "qibl was built without X11 (libx11-dev)");
#else
    need_tools();
    session ss;
    int ok = 0;
    double lamp[6];
    char png[128], ls[6][40];
    if (session_start(&ss, NULL) != 0)
        goto out;
    snprintf(png, sizeof png, "%s/relight.png", dir);
    int lines = 1;
    const char *const steps[] = {"key --window %1 s",
                                 "mousemove --window %1 128 50 mousedown 1 mousemove --window %1 90 49 "
                                 "mousemove --window %1 60 48 mouseup 1",
                                 NULL};
    if (xdo_steps(ss.display, ss.vlog, steps, &lines) != 0 || !last_lamp(ss.vlog, lamp)) {
        print_error("view_test: the lamp drag did not reach the viewer\n");
        goto out;
    }
    { /* the P map's point under (60, 48), 1/10 of the way toward the origin */
        uint8_t *bytes = NULL;
        size_t n;
        char err[256];
        qibl_asset_t a;
        qibl_pmap_t pm;
        qibl_q16_t q[3];
        assert_int_equal(qtool_io_read_asset(ss.asset, &bytes, &n, err, sizeof err), 0);
        assert_int_equal(qibl_asset_open(&a, bytes, n), QIBL_OK);
        assert_int_equal(qibl_asset_pmap(&a, &pm), QIBL_OK);
        qibl_pmap_point(&pm, 60, 48, q);
        free(bytes);
        for (int c = 0; c < 3; ++c)
            if (lamp[c] * 65536.0 != (double)(q[c] - q[c] / 10)) {
                print_error("view_test: the lamp is at %.17g %.17g %.17g, not 9/10 of the picked point %g %g %g\n",
                            lamp[0], lamp[1], lamp[2], q[0] / 65536.0, q[1] / 65536.0, q[2] / 65536.0);
                goto out;
            }
    }
    for (int c = 0; c < 6; ++c)
        snprintf(ls[c], sizeof ls[c], "%.17g", lamp[c]);
    if (run("relight", ss.asset, "--point", ls[0], ls[1], ls[2], "--rgb", ls[3], ls[4], ls[5], "--png", png, NULL) !=
        0) {
        print_error("view_test: qibl relight --point failed\n");
        goto out;
    }
    ok = grab_compare(&ss, png) == 0;
out:
    assert_true(session_end(&ss, ok));
#endif
}

/* --truth DIR: the frame of the nearest sun is compared (PSNR in the overlay and the log) */
static void test_truth_dir(void **state)
{
    (void)state;
#if !QIBL_HAVE_X11
    need(0, "qibl was built without X11 (libx11-dev)");
#else
    need_tools();
    /* the truths: frames of the same courtyard (gen is deterministic) under two suns */
    char tdir[] = "/tmp/qibl-viewtruth-XXXXXX", a[160], f1[200], f2[200];
    assert_non_null(mkdtemp(tdir));
    snprintf(a, sizeof a, "%s/a.qibl", tdir);
    snprintf(f1, sizeof f1, "%s/sun_2_0_1.png", tdir); /* the viewer's sun (1 0 0.5), named with integers */
    snprintf(f2, sizeof f2, "%s/sun_0_0_1.png", tdir);
    assert_int_equal(cli_setup("/tmp/qibl-view-XXXXXX"), 0);
    assert_int_equal(run("gen", "-o", a, "--size", "256x64", "--k", "9", NULL), 0);
    assert_int_equal(run("relight", a, "--sun", "1", "0", "0.5", "--png", f1, NULL), 0);
    assert_int_equal(run("relight", a, "--sun", "0", "0", "1", "--png", f2, NULL), 0);
    unlink(a);
    rm_rf(dir);
    session ss;
    char *extra[] = {"--sun", "1", "0", "0.5", "--truth", tdir, NULL};
    int ok = 0;
    if (session_start(&ss, extra) == 0) {
        char *t = text(ss.vlog), *p = strstr(t, "PSNR ");
        double db = 0;
        ok = p && sscanf(p, "PSNR %lf DB VS sun_2_0_1 (", &db) == 1 && db > 50.0 && strstr(p, "sun_2_0_1 (0.0 DEG)");
        if (!ok)
            print_error("view_test: want a PSNR above 50 dB against sun_2_0_1 at 0.0 degrees in: %s", t);
        free(t);
    }
    rm_rf(tdir);
    assert_true(session_end(&ss, ok));
#endif
}

/* s s (sun -> lamp -> path), t t (2 steps), a drag of a quarter width (scrubs a quarter of the
 * path): the window equals `qibl relight --path 0 --t T` of the reported t */
static void test_path_scrub_matches_relight(void **state)
{
    (void)state;
#if !QIBL_HAVE_X11
    need(0, "qibl was built without X11 (libx11-dev)");
#else
    need_tools();
    session ss;
    int ok = 0;

    char png[128], ts[40];
    if (session_start_asset(&ss, NULL, 1) != 0)
        goto out;
    snprintf(png, sizeof png, "%s/relight.png", dir);
    int lines = 1;
    const char *const steps[] = {"key --window %1 s", "key --window %1 s", "key --window %1 t", "key --window %1 t",
                                 "mousemove --window %1 100 30 mousedown 1 mousemove --window %1 130 31 "
                                 "mousemove --window %1 164 32 mouseup 1",
                                 NULL};
    if (xdo_steps(ss.display, ss.vlog, steps, &lines) != 0)
        goto out;
    unsigned idx = 99, tq = 0;
    {
        char *t = text(ss.vlog), *p = t, *last = NULL;
        while ((p = strstr(p, " | path ")) != NULL)
            last = p++;
        int got = last && sscanf(last, " | path %u tq %u", &idx, &tq) == 2;
        free(t);
        /* 2 steps of 2048 and a quarter of 65535 (rounded per motion event) */
        if (!got || idx != 0 || tq + 2 < 2 * 2048 + 16384 || tq > 2 * 2048 + 16384 + 2) {
            print_error("view_test: path %u at tq %u, want path 0 near tq %u\n", idx, tq, 2 * 2048 + 16384);
            goto out;
        }
    }
    snprintf(ts, sizeof ts, "%.17g", tq / 65535.0);
    if (run("relight", ss.asset, "--path", "0", "--t", ts, "--png", png, NULL) != 0) {
        print_error("view_test: qibl relight --path failed\n");
        goto out;
    }
    ok = grab_compare(&ss, png) == 0;
out:
    assert_true(session_end(&ss, ok));
#endif
}

/* --gles: the window shows platform/gles2's frame, equal to `qibl relight --gles` of the same sun */
static void test_gles_matches_relight_gles(void **state)
{
    (void)state;
#if !QIBL_HAVE_X11 || !QIBL_HAVE_GLES2
    need(0, "qibl was built without X11 or without EGL/GLES2");
#else
    need_tools();
    /* Under ASan: Mesa keeps a few hundred bytes past eglTerminate (tests/gles2_test.c says why no
     * suppression can name them), so the qibl processes of this test run without leak checking;
     * ASan and UBSan still check every access. */
    char asan[512];
    const char *prev = getenv("ASAN_OPTIONS");
    snprintf(asan, sizeof asan, "%s%sdetect_leaks=0", prev ? prev : "", prev && *prev ? ":" : "");
    char *saved = prev ? strdup(prev) : NULL;
    setenv("ASAN_OPTIONS", asan, 1);
    { /* EGL usable here? (relight --gles on a tiny asset) */
        assert_int_equal(cli_setup("/tmp/qibl-viewegl-XXXXXX"), 0);
        char a[128], o[128];
        snprintf(a, sizeof a, "%s/t.qibl", dir);
        snprintf(o, sizeof o, "%s/t.png", dir);
        int egl = run("gen", "-o", a, "--size", "16x8", "--k", "4", NULL) == 0 &&
                  run("relight", a, "--gles", "--sun", "0", "0", "1", "--png", o, NULL) == 0;
        rm_rf(dir);
        if (!egl) {
            if (saved)
                setenv("ASAN_OPTIONS", saved, 1);
            else
                unsetenv("ASAN_OPTIONS");
            free(saved);
        }
        need(egl, "no usable EGL/GLES2 context here (qibl relight --gles fails)");
    }
    session ss;
    char *extra[] = {"--gles", "--sun", "0.3", "-1", "0.6", NULL};
    int ok = 0;
    double sun[3];
    char png[128], sun_s[3][40];
    if (session_start(&ss, extra) != 0)
        goto out;
    log_lines(ss.vlog, sun);
    { /* which way the frame reached the window: an EGL window surface, or read back where EGL has no
       * X11 platform; both must equal relight --gles */
        char *t = text(ss.vlog);
        const int said = strstr(t, "view: --gles draws into the window") || strstr(t, "view: --gles reads the frames back");
        if (!said)
            print_error("view_test: the log does not say how --gles reaches the window:\n%s", t);
        else if (!strstr(t, "draws into the window"))
            fprintf(stderr, "view_test: note: --gles read back here (no EGL window surface)\n");
        free(t);
        if (!said)
            goto out;
    }
    snprintf(png, sizeof png, "%s/relight.png", dir);
    for (int c = 0; c < 3; ++c)
        snprintf(sun_s[c], sizeof sun_s[c], "%.17g", sun[c]);
    if (run("relight", ss.asset, "--gles", "--sun", sun_s[0], sun_s[1], sun_s[2], "--png", png, NULL) != 0) {
        char *e = text(errlog);
        print_error("view_test: qibl relight --gles failed: %s", e);
        free(e);
        goto out;
    }
    ok = grab_compare(&ss, png) == 0;
out:
    ok = session_end(&ss, ok);
    if (saved)
        setenv("ASAN_OPTIONS", saved, 1);
    else
        unsetenv("ASAN_OPTIONS");
    free(saved);
    assert_true(ok);
#endif
}

/* PSNR against a truth (8-bit RGB of the BGRX frame) and the overlay strip (text on a dark ground,
 * every pixel opaque, nothing written past the strip) */
static void test_psnr_overlay(void **state)
{
    (void)state;
    uint8_t frame[2 * 4] = {30, 20, 10, 255, 60, 50, 40, 255}; /* B G R X: RGB 10 20 30 and 40 50 60 */
    uint8_t truth[6] = {10, 20, 30, 40, 50, 60};
    assert_true(qtool_view_psnr(frame, 8, 2, 1, truth) == 99.0);
    truth[5] = 61; /* one value off by 1 in 6: MSE 1/6 */
    assert_true(fabs(qtool_view_psnr(frame, 8, 2, 1, truth) - 10.0 * log10(255.0 * 255.0 * 6.0)) < 1e-9);

    static uint8_t planes[4 * 2 * 9 * 3], params[9 * 3 * 8];
    qibl_shmaps_t m = {.width = 4, .height = 2, .k = 9, .channels = 3, .params = params, .planes = planes};
    qtool_view v;
    assert_int_equal(qtool_view_init(&v, &m), 0);
    enum { W = 320, H = QTOOL_VIEW_OVERLAY_H };
    static uint8_t strip[(H + 1) * W * 4];
    memset(strip, 0xA5, sizeof strip);
    qtool_view_overlay(&v, 61.0, strip, W, W * 4);
    long text = 0, ground = 0;
    for (size_t i = 0; i < (size_t)H * W; ++i) {
        assert_int_equal(strip[4 * i + 3], 255);
        if (strip[4 * i] == 24 && strip[4 * i + 1] == 24 && strip[4 * i + 2] == 24)
            ++ground;
        else
            ++text;
    }
    assert_true(text > 200 && ground > text);
    for (size_t i = (size_t)H * W * 4; i < sizeof strip; ++i) /* the guard row untouched */
        assert_int_equal(strip[i], 0xA5);
}

/* a refusal of the arguments (exit 2) is the option table's one line, "qibl view: ...; see qibl help
 * view"; a failure while working (exit 1) is "qibl: ..." */
static int refusal_shape(const char *e, int rc)
{
    static const char tail[] = "; see qibl help view\n";
    const size_t n = strlen(e), tn = strlen(tail);
    if (rc != 2)
        return strncmp(e, "qibl: ", 6) == 0;
    return strncmp(e, "qibl view: ", 11) == 0 && n >= tn && strcmp(e + n - tn, tail) == 0 &&
           strchr(e, '\n') == e + n - 1;
}

/* the command's options and limits without a window: each bad one a named one-line error, nothing written */
static void test_cli(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(cli_setup("/tmp/qibl-viewcli-XXXXXX"), 0);
    char asset[128], rec[128], small[128];
    snprintf(asset, sizeof asset, "%s/a.qibl", dir);
    snprintf(rec, sizeof rec, "%s/rec.png", dir);
    snprintf(small, sizeof small, "%s/small.png", dir);
    assert_int_equal(run("gen", "-o", asset, "--size", "256x64", "--k", "9", NULL), 0);
    struct { int rc; const char *msg; const char *args[12]; } cases[] = {
        {2, "needs an asset FILE", {"view", NULL}},
        {2, "--record needs --bench", {"view", asset, "--record", rec, NULL}},
        {2, "--record needs --frames of at least 2",
         {"view", asset, "--bench", "--headless", "--frames", "1", "--record", rec, NULL}},
        {2, "--exposure", {"view", asset, "--exposure", "1000", NULL}},
        {2, "--headless is for --bench", {"view", asset, "--headless", NULL}},
        {1, "beyond the recording's 256 MiB",
         {"view", asset, "--bench", "--headless", "--frames", "4000", "--record", rec, NULL}},
        {1, "not the same frame", {"view", asset, "--bench", "--headless", "--truth", small, NULL}},
        {1, "nonexistent", {"view", "nonexistent.qibl", "--bench", "--headless", NULL}},
    };
    /* a truth of another size */
    assert_int_equal(run("relight", asset, "--sun", "0", "0", "1", "--png", rec, NULL), 0);
    {
        uint8_t px[3 * 8 * 4] = {0};
        char err[128];
        assert_int_equal(qtool_png_write_rgb8(small, 8, 4, px, err, sizeof err), 0);
    }
    unlink(rec);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const char **a = cases[i].args;
        int rc = run(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8], a[9], a[10], NULL);
        char *e = text(errlog);
        if (rc != cases[i].rc || strstr(e, cases[i].msg) == NULL || !refusal_shape(e, rc))
            fail_msg("case %zu: exit %d, stderr '%s' (want %d and '%s')", i, rc, e, cases[i].rc, cases[i].msg);
        free(e);
        assert_int_equal(access(rec, F_OK), -1); /* nothing recorded by a refused command */
    }
    { /* --truth DIR refusals: no frames, a zero direction, another size */
        char td[160], f[200];
        snprintf(td, sizeof td, "%s/truths", dir);
        assert_int_equal(mkdir(td, 0755), 0);
        const char *want[] = {"no sun_X_Y_Z.png frames", "not a sun direction", "not the same frame"};
        for (int k = 0; k < 3; ++k) {
            if (k == 1) {
                snprintf(f, sizeof f, "%s/sun_0_0_0.png", td);
                assert_int_equal(link(small, f), 0);
            } else if (k == 2) {
                unlink(f);
                snprintf(f, sizeof f, "%s/sun_0_0_1.png", td);
                assert_int_equal(link(small, f), 0);
            }
            assert_int_equal(run("view", asset, "--bench", "--headless", "--truth", td, NULL), 1);
            char *e = text(errlog);
            if (!strstr(e, want[k]) || strncmp(e, "qibl: ", 6) != 0)
                fail_msg("--truth DIR case %d: '%s' (want '%s')", k, e, want[k]);
            free(e);
        }
    }
    /* a ninth probe (refused while parsing: the files are never read) */
    assert_int_equal(run("view", asset, "--probe", "p", "--probe", "p", "--probe", "p", "--probe", "p", "--probe", "p",
                         "--probe", "p", "--probe", "p", "--probe", "p", "--probe", "p", NULL), 2);
    char *e9 = text(errlog);
    assert_non_null(strstr(e9, "qibl view: --probe: at most 8, and 'p' is one more; see qibl help view\n"));
    free(e9);
    assert_int_equal(run("view", asset, "--bench", "--frames", "0", NULL), 2);
    e9 = text(errlog);
    assert_non_null(strstr(e9, "qibl view: --frames: '0' is not an integer in 1..1000000; see qibl help view\n"));
    free(e9);
#if QIBL_HAVE_X11
    { /* no display: named, exit 1 */
        const char *d = getenv("DISPLAY");
        char *saved = d ? strdup(d) : NULL;
        setenv("DISPLAY", "", 1);
        int rc = run("view", asset, NULL);
        if (saved)
            setenv("DISPLAY", saved, 1), free(saved);
        else
            unsetenv("DISPLAY");
        assert_int_equal(rc, 1);
        e9 = text(errlog);
        assert_non_null(strstr(e9, "qibl: view: cannot open the X display"));
        free(e9);
    }
#endif
    /* the headless bench and its recording */
    assert_int_equal(run("view", asset, "--bench", "--headless", "--frames", "4", "--turn", "--record", rec, NULL), 0);
    char *o = text(outlog);
    assert_non_null(strstr(o, "RESULT view.fps "));
    free(o);
    int w, h, fr;
    uint8_t *px = NULL;
    char err[256];
    assert_int_equal(qtool_png_read_rgb8(rec, &w, &h, &fr, &px, err, sizeof err), 0);
    assert_int_equal(w, 256);
    assert_int_equal(h, 64 + QTOOL_VIEW_OVERLAY_H);
    assert_int_equal(fr, 4);
    free(px);
    rm_rf(dir);
}


/* mesh mode's state without a window: the light's rotation convention (band 1 turns as a vector:
 * yaw about +z, pitch about +x, pitch first), the drags and keys of mesh mode */
static void test_mesh_state(void **state)
{
    (void)state;
    char tmpl[] = "/tmp/qibl-viewmstate-XXXXXX", mesh[96], probe[96], err[300], note[300];
    assert_non_null(mkdtemp(tmpl));
    snprintf(mesh, sizeof mesh, "%s/scene.obj", tmpl), snprintf(probe, sizeof probe, "%s/p.hdr", tmpl);
    write_mesh(mesh);
    write_probe(probe);
    const char *probes[1] = {probe};
    qtool_view_mesh_opts o = QTOOL_VIEW_MESH_OPTS_DEFAULT;
    o.mesh = mesh, o.probes = probes, o.nprobes = 1, o.zup = 1, o.size = 64;
    qtool_view v;
    if (qtool_view_open_mesh(&v, &o, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    int32_t l0[3][25], l[3][25];
    assert_int_equal(qtool_view_mesh_light(&v, l0), QIBL_OK);
    /* band 1 (sh.h, Condon-Shortley phase): index 1 ~ -y, 2 ~ z, 3 ~ -x; a turn R maps the light's
     * vector a to R a: yaw 90 (x, y) -> (-y, x), pitch 90 (y, z) -> (-z, y) */
    v.yaw = 90;
    assert_int_equal(qtool_view_mesh_light(&v, l), QIBL_OK);
    for (int c = 0; c < 3; ++c) {
        assert_true(abs(l[c][3] + l0[c][1]) <= 4 && abs(l[c][1] - l0[c][3]) <= 4 && abs(l[c][2] - l0[c][2]) <= 4);
        assert_true(abs(l[c][0] - l0[c][0]) <= 1);
    }
    v.yaw = 0, v.pitch = 90;
    assert_int_equal(qtool_view_mesh_light(&v, l), QIBL_OK);
    for (int c = 0; c < 3; ++c)
        assert_true(abs(l[c][3] - l0[c][3]) <= 4 && abs(l[c][1] - l0[c][2]) <= 4 && abs(l[c][2] + l0[c][1]) <= 4);
    assert_true(abs(l0[0][1]) + abs(l0[0][2]) + abs(l0[0][3]) > 1000); /* the probe is directional */
    v.pitch = 0;
    qtool_view_drag(&v, 16, -32, 64, 64); /* a quarter width: +90 of yaw; half a height: -90 of pitch */
    assert_true(fabs(v.yaw - 90) < 1e-9 && fabs(v.pitch + 90) < 1e-9);
    qtool_view_drag(&v, -32, -8, 64, 64); /* yaw wraps, pitch clamps */
    assert_true(fabs(v.yaw - 270) < 1e-9 && v.pitch == -90);
    qtool_view_orbit(&v, 32, 1000, 64, 64); /* half a width: -180 of azimuth; elevation clamped */
    assert_true(fabs(v.cam_az - 215) < 1e-9 && v.cam_el == QTOOL_VIEW_CAM_EL_MAX);
    assert_int_equal(qtool_view_key(&v, ']'), 1);
    assert_true(fabs(v.cam_az - 230) < 1e-9);
    assert_int_equal(qtool_view_key(&v, 'p'), 0); /* one probe */
    assert_int_equal(qtool_view_key(&v, 's'), 0); /* no schemes, SH terms or linear in mesh mode */
    assert_int_equal(qtool_view_key(&v, 'k'), 0);
    assert_int_equal(qtool_view_key(&v, 'l'), 0);
    const uint32_t e = v.exposure;
    assert_int_equal(qtool_view_key(&v, '+'), 1);
    assert_int_equal(v.exposure, 2 * e);
    uint32_t nv, nt, nc;
    qtool_view_mesh_counts(&v, &nv, &nt, &nc);
    assert_int_equal(nv, 49 + 8);
    assert_int_equal(nt, 72 + 12);
    assert_int_equal(nc, 25);
    qtool_view_close_mesh(&v);
    assert_null(v.mesh);
    /* refusals, nothing kept */
    o.size = 8;
    assert_int_equal(qtool_view_open_mesh(&v, &o, note, sizeof note, err, sizeof err), -1);
    assert_non_null(strstr(err, "--size 8 outside"));
    assert_null(v.mesh);
    o.size = 64, o.nprobes = 0;
    assert_int_equal(qtool_view_open_mesh(&v, &o, note, sizeof note, err, sizeof err), -1);
    assert_null(v.mesh);
    rm_rf(tmpl);
}

#define MESH_SIZE 128

/* the last "view: mesh" line's values (0), or -1 */
static int mesh_values(const char *vlog, double *yaw, double *pitch, double *az, double *el, double *expo)
{
    char *t = text(vlog), *p = t, *last = NULL;
    while ((p = strstr(p, "view: mesh ")) != NULL)
        last = p, p += 11;
    int ok = last && sscanf(last, "view: mesh --light-yaw %lf --light-pitch %lf --camera %lf,%lf --exposure %lf", yaw,
                            pitch, az, el, expo) == 5;
    free(t);
    return ok ? 0 : -1;
}

/* mesh mode in a window: the lighting dragged (button 1) and stepped (Y), the camera orbited (button
 * 3) and turned (]), the exposure doubled (+); each value as the inputs mean it, and the window
 * equals `qibl view MESH --png` of the values the log prints */
static void test_mesh_drag_matches_png(void **state)
{
    (void)state;
#if !QIBL_HAVE_X11
    need(0, "qibl was built without X11 (libx11-dev)");
#else
    need_tools();
    session ss;
    memset(&ss, 0, sizeof ss);
    ss.xvfb = ss.viewer = -1;
    assert_int_equal(cli_setup("/tmp/qibl-viewmesh-XXXXXX"), 0);
    char probe[160], png[160];
    snprintf(ss.asset, sizeof ss.asset, "%s/scene.obj", dir);
    snprintf(probe, sizeof probe, "%s/p.hdr", dir);
    snprintf(png, sizeof png, "%s/frame.png", dir);
    write_mesh(ss.asset);
    write_probe(probe);
    char *extra[] = {"--zup", "--probe", probe, "--size", "128", "--threads", "1", NULL};
    int ok = 0, lines = 1;
    double y0, p0, a0, e0, x0, y1, p1, a1, e1, x1;
    if (session_launch(&ss, extra) != 0 || mesh_values(ss.vlog, &y0, &p0, &a0, &e0, &x0) != 0)
        goto out;
    const char *const steps[] = {
        "mousemove --window %1 40 60 mousedown 1 mousemove --window %1 56 56 mousemove --window %1 72 52 mouseup 1",
        "key --window %1 Y",
        "mousemove --window %1 60 60 mousedown 3 mousemove --window %1 50 64 mousemove --window %1 44 68 mouseup 3",
        "key --window %1 bracketright", "key --window %1 plus", NULL};
    if (xdo_steps(ss.display, ss.vlog, steps, &lines) != 0 || mesh_values(ss.vlog, &y1, &p1, &a1, &e1, &x1) != 0)
        goto out;
    { /* the drag: +32 px of 128 = 90 degrees of yaw, -8 px of 128 = -11.25 of pitch; Y: +15; the orbit:
       * -16 px = +45 degrees of azimuth, +8 px = +11.25 of elevation; ]: +15 of azimuth; +: exposure x 2 */
        const double want[5] = {fmod(y0 + 90 + 15, 360), p0 - 11.25, fmod(a0 + 45 + 15, 360), e0 + 11.25, 2 * x0};
        const double got[5] = {y1, p1, a1, e1, x1};
        for (int k = 0; k < 5; ++k)
            if (fabs(got[k] - want[k]) > 1e-9) {
                print_error("view_test: mesh value %d is %.17g, want %.17g\n", k, got[k], want[k]);
                goto out;
            }
    }
    char ys[40], ps[40], cam[80], xs[40];
    snprintf(ys, sizeof ys, "%.17g", y1), snprintf(ps, sizeof ps, "%.17g", p1);
    snprintf(cam, sizeof cam, "%.17g,%.17g", a1, e1), snprintf(xs, sizeof xs, "%.17g", x1);
    if (run("view", ss.asset, "--zup", "--probe", probe, "--size", "128", "--threads", "1", "--light-yaw", ys,
            "--light-pitch", ps, "--camera", cam, "--exposure", xs, "--png", png, NULL) != 0) {
        print_error("view_test: qibl view --png failed\n");
        goto out;
    }
    ok = grab_compare_size(&ss, png, MESH_SIZE, MESH_SIZE) == 0;
out:
    assert_true(session_end(&ss, ok));
#endif
}

/* mesh mode without a window: a transfer read from `qibl transfer --export` draws the frame the
 * computed one draws; turning the light changes it; the bench's figure; each misuse refused by name */
static void test_mesh_cli(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(cli_setup("/tmp/qibl-viewmcli-XXXXXX"), 0);
    char mesh[128], probe[128], qtr[128], a[128], b[128], c[128], asset[128];
    snprintf(mesh, sizeof mesh, "%s/scene.obj", dir), snprintf(probe, sizeof probe, "%s/p.hdr", dir);
    snprintf(qtr, sizeof qtr, "%s/scene.qtr", dir), snprintf(asset, sizeof asset, "%s/a.qibl", dir);
    snprintf(a, sizeof a, "%s/a.png", dir), snprintf(b, sizeof b, "%s/b.png", dir), snprintf(c, sizeof c, "%s/c.png", dir);
    write_mesh(mesh);
    write_probe(probe);
    assert_int_equal(run("transfer", mesh, "--zup", "--probe", probe, "--rays", "0", "--threads", "1", "--export", qtr,
                         NULL), 0);
    assert_int_equal(run("view", mesh, "--zup", "--probe", probe, "--size", "96", "--threads", "1", "--light-yaw", "30",
                         "--png", a, NULL), 0);
    assert_int_equal(run("view", mesh, "--zup", "--probe", probe, "--size", "96", "--transfer", qtr, "--light-yaw", "30",
                         "--png", b, NULL), 0);
    assert_int_equal(run("view", mesh, "--zup", "--probe", probe, "--size", "96", "--transfer", qtr, "--light-yaw", "120",
                         "--png", c, NULL), 0);
    {
        int w, h, fr;
        uint8_t *pa = NULL, *pb = NULL, *pc = NULL;
        char err[256];
        assert_int_equal(qtool_png_read_rgb8(a, &w, &h, &fr, &pa, err, sizeof err), 0);
        assert_int_equal(qtool_png_read_rgb8(b, &w, &h, &fr, &pb, err, sizeof err), 0);
        assert_int_equal(qtool_png_read_rgb8(c, &w, &h, &fr, &pc, err, sizeof err), 0);
        assert_int_equal(w, 96);
        assert_memory_equal(pa, pb, (size_t)w * h * 3);                 /* the export draws as the computation */
        assert_true(memcmp(pa, pc, (size_t)w * h * 3) != 0);            /* the light's yaw shows */
        long lit = 0;
        for (size_t i = 0; i < (size_t)w * h * 3; ++i)
            lit += pa[i] > 8;
        assert_true(lit > w * h / 4); /* the scene covers the frame and is lit */
        free(pa), free(pb), free(pc);
    }
    assert_int_equal(run("view", mesh, "--zup", "--probe", probe, "--size", "64", "--bench", "--headless", "--frames",
                         "3", NULL), 0);
    char *o = text(outlog);
    assert_non_null(strstr(o, "RESULT view.mesh_fps "));
    free(o);
    assert_int_equal(run("gen", "-o", asset, "--size", "16x8", "--k", "4", NULL), 0);
    char tri[128];
    snprintf(tri, sizeof tri, "%s/tri.obj", dir);
    FILE *tf = fopen(tri, "w");
    assert_non_null(tf);
    fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", tf);
    assert_int_equal(fclose(tf), 0);
    struct { int rc; const char *msg; const char *args[10]; } cases[] = {
        {2, "needs --probe P.hdr", {"view", mesh, NULL}},
        {2, "--gles is for an asset", {"view", mesh, "--probe", probe, "--gles", NULL}},
        {2, "--light-yaw is for a mesh", {"view", asset, "--light-yaw", "10", NULL}},
        {2, "--camera: '10' is not AZ,EL", {"view", mesh, "--probe", probe, "--camera", "10", NULL}},
        {2, "--size: '8' is not an integer in 64..2048", {"view", mesh, "--probe", probe, "--size", "8", NULL}},
        {2, "--png writes one frame", {"view", mesh, "--probe", probe, "--bench", "--png", a, NULL}},
        {1, "holds", {"view", tri, "--probe", probe, "--transfer", qtr, "--png", c, NULL}}, /* not its export */
        {1, "not a transfer export", {"view", mesh, "--probe", probe, "--transfer", asset, "--png", c, NULL}}, /* not an export */
    };
    unlink(c);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const char **g = cases[i].args;
        int rc = run(g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], NULL);
        char *e = text(errlog);
        if (rc != cases[i].rc || strstr(e, cases[i].msg) == NULL || !refusal_shape(e, rc))
            fail_msg("mesh case %zu: exit %d, stderr '%s' (want %d and '%s')", i, rc, e, cases[i].rc, cases[i].msg);
        free(e);
    }
    assert_int_equal(access(c, F_OK), -1); /* nothing written by a refused command */
    rm_rf(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_state),
        cmocka_unit_test(test_psnr_overlay),
        cmocka_unit_test(test_cli),
        cmocka_unit_test(test_drag_matches_relight),
        cmocka_unit_test(test_probe_yaw_matches_relight),
        cmocka_unit_test(test_lamp_pick_matches_relight),
        cmocka_unit_test(test_path_scrub_matches_relight),
        cmocka_unit_test(test_truth_dir),
        cmocka_unit_test(test_gles_matches_relight_gles),
        cmocka_unit_test(test_mesh_state),
        cmocka_unit_test(test_mesh_cli),
        cmocka_unit_test(test_mesh_drag_matches_png),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
