/*
 * view/x11.c - the viewer's window (view/view.h): an X11 window and event loop, frames shown with
 * XPutImage (a 32-bit TrueColor visual: the soft framebuffer's BGRA bytes are its pixels on a
 * little-endian machine, byte order told to Xlib). Built with Xlib when QIBL_HAVE_X11 is set; the
 * bench's headless mode needs no display.
 */
#include "view/view.h"

#include "io/png.h"
#include "qtool.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if QIBL_HAVE_X11
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/keysym.h>
#endif

static double view_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* one frame and the overlay into buf (w x (h + overlay) BGRX); 0 or -1 with err */
static int draw(qtool_view *v, const qtool_view_run_opts *o, uint8_t *buf, void *ws, double fps, char *err, size_t n)
{
    const uint32_t w = v->maps.width, h = v->maps.height;
    const size_t stride = (size_t)w * 4;
    qibl_status_t st = QIBL_OK;
    if (o->frame) {
        double t0 = view_now();
        if (o->frame(o->user, v, buf, stride) != 0)
            return snprintf(err, n, "view: the frame failed"), -1;
        v->ms = (view_now() - t0) * 1e3;
    } else if (qtool_view_render(v, buf, stride, ws, &st) != 0) {
        return snprintf(err, n, "view: relight: %s", qibl_status_str(st)), -1;
    }
    if (o->truth) {
        v->psnr = qtool_view_psnr(buf, stride, w, h, o->truth), v->truth_label = NULL;
    } else if (o->ntruths) {
        v->psnr = -1.0, v->truth_label = NULL;
        if (v->scheme == QTOOL_VIEW_SUN) { /* the frame of the nearest sun */
            qibl_q16_t d[3];
            qtool_view_sun_q16(v, d);
            double u[3] = {d[0], d[1], d[2]}, len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]), best = -2;
            uint32_t bi = 0;
            for (uint32_t i = 0; i < o->ntruths; ++i) {
                double dot = (u[0] * o->truth_dirs[i][0] + u[1] * o->truth_dirs[i][1] + u[2] * o->truth_dirs[i][2]) / len;
                if (dot > best)
                    best = dot, bi = i;
            }
            v->psnr = qtool_view_psnr(buf, stride, w, h, o->truths[bi]);
            v->truth_label = o->truth_names[bi];
            v->truth_angle = acos(best > 1 ? 1 : best < -1 ? -1 : best) * 180.0 / QTOOL_PI;
        }
    }
    qtool_view_overlay(v, fps, buf + (size_t)h * stride, w, stride);
    return 0;
}

int qtool_view_record_check(const qtool_view *v, long frames, char *err, size_t errlen)
{
    const size_t one = (size_t)v->maps.width * (v->maps.height + QTOOL_VIEW_OVERLAY_H) * 3;
    if (frames < 2 || (size_t)frames > QTOOL_VIEW_RECORD_MAX_BYTES / one)
        return snprintf(err, errlen, "view: --record: %ld frames of %ux%u are %s the recording's %zu MiB (at least 2 "
                        "frames, at most %zu)", frames, v->maps.width, v->maps.height + QTOOL_VIEW_OVERLAY_H,
                        frames < 2 ? "too few for" : "beyond", QTOOL_VIEW_RECORD_MAX_BYTES >> 20,
                        QTOOL_VIEW_RECORD_MAX_BYTES / one), -1;
    return 0;
}

/* frame i of the recording: the shown BGRX buffer as RGB */
static void record_frame(const qtool_view *v, const uint8_t *buf, uint8_t *rec, long i)
{
    const size_t np = (size_t)v->maps.width * (v->maps.height + QTOOL_VIEW_OVERLAY_H);
    uint8_t *o = rec + (size_t)i * np * 3;
    for (size_t p = 0; p < np; ++p)
        o[3 * p] = buf[4 * p + 2], o[3 * p + 1] = buf[4 * p + 1], o[3 * p + 2] = buf[4 * p];
}

static int drag_dx(const qtool_view_run_opts *o)
{
    return o->drag_dx ? o->drag_dx : 4;
}

/* the headless bench: the sun dragged 4 pixels a frame, frame and overlay each time */
static int bench_headless(qtool_view *v, const qtool_view_run_opts *o, uint8_t *buf, void *ws, uint8_t *rec,
                          char *err, size_t n)
{
    double t0 = view_now(), fps = 0;
    for (long i = 0; i < o->bench_frames; ++i) {
        qtool_view_drag(v, drag_dx(o), (i / 64) % 2 ? 1 : -1, v->maps.width, v->maps.height);
        if (draw(v, o, buf, ws, fps, err, n) != 0)
            return -1;
        fps = (double)(i + 1) / (view_now() - t0);
        if (rec)
            record_frame(v, buf, rec, i);
    }
    if (o->bench_fps)
        *o->bench_fps = fps;
    return 0;
}

#if QIBL_HAVE_X11
static void log_state(const qtool_view *v, const qtool_view_run_opts *o)
{
    if (!o->log)
        return;
    qibl_q16_t d[3];
    char l1[160], l2[160];
    qtool_view_sun_q16(v, d);
    qtool_view_describe(v, 0, l1, l2, sizeof l1);
    /* the sun exactly (decimal of the Q16.16 values), so `qibl relight --sun` gives the same light */
    fprintf((FILE *)o->log, "view: sun %.17g %.17g %.17g | %s | %s", d[0] / 65536.0, d[1] / 65536.0, d[2] / 65536.0, l1,
            l2);
    if (v->scheme == QTOOL_VIEW_PATH) /* `qibl relight --path N --t T` with T = tq / 65535 */
        fprintf((FILE *)o->log, " | path %u tq %u", v->path_index, v->path_t);
    if (v->scheme == QTOOL_VIEW_LAMP) /* the lamp exactly, for `qibl relight --point X Y Z --rgb R G B` */
        fprintf((FILE *)o->log, " | lamp %.17g %.17g %.17g rgb %.17g %.17g %.17g", v->lamp_pos[0] / 65536.0,
                v->lamp_pos[1] / 65536.0, v->lamp_pos[2] / 65536.0, v->lamp_rgb[0] / 65536.0, v->lamp_rgb[1] / 65536.0,
                v->lamp_rgb[2] / 65536.0);
    fputc('\n', (FILE *)o->log);
    fflush((FILE *)o->log);
}

int qtool_view_have_window(void)
{
    return 1;
}

static int x_run(qtool_view *v, const qtool_view_run_opts *o, uint8_t *buf, void *ws, uint8_t *rec, char *err,
                 size_t n)
{
    const uint32_t w = v->maps.width, h = v->maps.height, wh = h + QTOOL_VIEW_OVERLAY_H;
    Display *dpy = XOpenDisplay(NULL);
    if (!dpy)
        return snprintf(err, n, "view: cannot open the X display '%s' (set DISPLAY, or use --bench --headless)",
                        getenv("DISPLAY") ? getenv("DISPLAY") : ""), -1;
    int scr = DefaultScreen(dpy);
    XVisualInfo vi;
    if (!XMatchVisualInfo(dpy, scr, 24, TrueColor, &vi) || vi.red_mask != 0xff0000 || vi.green_mask != 0xff00 ||
        vi.blue_mask != 0xff) {
        XCloseDisplay(dpy);
        return snprintf(err, n, "view: the display has no 24-bit TrueColor visual with 8-8-8 RGB masks"), -1;
    }
    XSetWindowAttributes wa = {.background_pixel = 0, .border_pixel = 0,
                               .colormap = XCreateColormap(dpy, RootWindow(dpy, scr), vi.visual, AllocNone),
                               .event_mask = ExposureMask | KeyPressMask | ButtonPressMask | ButtonReleaseMask |
                                             PointerMotionMask | StructureNotifyMask};
    Window win = XCreateWindow(dpy, RootWindow(dpy, scr), 0, 0, w, wh, 0, vi.depth, InputOutput, vi.visual,
                               CWBackPixel | CWBorderPixel | CWColormap | CWEventMask, &wa);
    XStoreName(dpy, win, o->title ? o->title : "qibl view");
    XSizeHints hints = {.flags = PMinSize | PMaxSize, .min_width = (int)w, .max_width = (int)w,
                        .min_height = (int)wh, .max_height = (int)wh};
    XSetWMNormalHints(dpy, win, &hints);
    Atom wm_delete = XInternAtom(dpy, "WM_DELETE_WINDOW", False);
    XSetWMProtocols(dpy, win, &wm_delete, 1);
    XMapWindow(dpy, win);
    GC gc = XCreateGC(dpy, win, 0, NULL);
    XImage *img = XCreateImage(dpy, vi.visual, (unsigned)vi.depth, ZPixmap, 0, (char *)buf, w, wh, 32, (int)w * 4);
    int rc = 0;
    if (!img) {
        rc = -1, snprintf(err, n, "view: XCreateImage failed");
        goto out;
    }
    img->byte_order = LSBFirst; /* B, G, R, X in memory: the pixel 0x00RRGGBB little-endian */
    {
        int dirty = 1, dragging = 0, lx = 0, ly = 0, moved = 1, running = 1; /* the first frame is logged */
        double fps = 0, t_last = view_now(), t0 = t_last;
        long frames = 0;
        for (;;) { /* wait for the window to be mapped */
            XEvent e;
            XNextEvent(dpy, &e);
            if (e.type == MapNotify)
                break;
        }
        while (running) {
            while (XPending(dpy) || (!dirty && !o->bench_frames)) {
                XEvent e;
                XNextEvent(dpy, &e);
                if (e.type == Expose)
                    dirty = 1;
                else if (e.type == ClientMessage && (Atom)e.xclient.data.l[0] == wm_delete)
                    running = 0;
                else if (e.type == KeyPress) {
                    KeySym ks = XLookupKeysym(&e.xkey, (e.xkey.state & ShiftMask) ? 1 : 0);
                    if (ks == XK_Escape || ks == XK_q)
                        running = 0;
                    else if (ks == XK_plus || ks == XK_KP_Add)
                        dirty |= qtool_view_key(v, '+'), moved = 1;
                    else if (ks == XK_minus || ks == XK_KP_Subtract)
                        dirty |= qtool_view_key(v, '-'), moved = 1;
                    else if (ks < 256 && qtool_view_key(v, (int)ks))
                        dirty = 1, moved = 1;
                } else if (e.type == ButtonPress && e.xbutton.button == Button1) {
                    dragging = 1, lx = e.xbutton.x, ly = e.xbutton.y;
                    if (v->scheme == QTOOL_VIEW_LAMP) /* the lamp: picked under the pointer */
                        dirty |= qtool_view_pick(v, lx, ly);
                } else if (e.type == MotionNotify && dragging) {
                    if (v->scheme == QTOOL_VIEW_LAMP)
                        dirty |= qtool_view_pick(v, e.xmotion.x, e.xmotion.y);
                    else if (v->scheme == QTOOL_VIEW_PATH)
                        qtool_view_scrub(v, e.xmotion.x - lx, w), dirty = 1;
                    else
                        qtool_view_drag(v, e.xmotion.x - lx, e.xmotion.y - ly, w, h), dirty = 1;
                    lx = e.xmotion.x, ly = e.xmotion.y;
                } else if (e.type == ButtonRelease && e.xbutton.button == Button1 && dragging) {
                    if (v->scheme == QTOOL_VIEW_LAMP)
                        qtool_view_pick(v, e.xbutton.x, e.xbutton.y);
                    else if (v->scheme == QTOOL_VIEW_PATH)
                        qtool_view_scrub(v, e.xbutton.x - lx, w);
                    else
                        qtool_view_drag(v, e.xbutton.x - lx, e.xbutton.y - ly, w, h);
                    dragging = 0, dirty = 1, moved = 1;
                }
                if (!running)
                    break;
            }
            if (!running)
                break;
            if (o->bench_frames) {
                qtool_view_drag(v, drag_dx(o), (frames / 64) % 2 ? 1 : -1, w, h);
                dirty = 1;
            }
            if (dirty) {
                if (draw(v, o, buf, ws, fps, err, n) != 0) {
                    rc = -1;
                    break;
                }
                XPutImage(dpy, win, gc, img, 0, 0, 0, 0, w, wh);
                XSync(dpy, False); /* the frame is on the server before it is logged */
                if (rec && o->bench_frames)
                    record_frame(v, buf, rec, frames);
                double t = view_now();
                ++frames;
                fps = o->bench_frames ? frames / (t - t0) : 1.0 / (t - t_last > 1e-6 ? t - t_last : 1e-6);
                t_last = t, dirty = 0;
                if (moved)
                    log_state(v, o), moved = 0;
                if (o->bench_frames && frames >= o->bench_frames) {
                    if (o->bench_fps)
                        *o->bench_fps = fps;
                    break;
                }
            }
        }
    }
    img->data = NULL; /* buf is the caller's */
    XDestroyImage(img);
out:
    XFreeGC(dpy, gc);
    XDestroyWindow(dpy, win);
    XCloseDisplay(dpy);
    return rc;
}
#else
int qtool_view_have_window(void)
{
    return 0;
}
#endif

int qtool_view_run(qtool_view *v, const qtool_view_run_opts *o, char *err, size_t errlen)
{
    const uint32_t w = v->maps.width, h = v->maps.height;
    if ((size_t)w * (h + QTOOL_VIEW_OVERLAY_H) > ((size_t)1 << 28))
        return snprintf(err, errlen, "view: %ux%u is too large a window", w, h), -1;
    uint8_t *buf = calloc((size_t)w * (h + QTOOL_VIEW_OVERLAY_H), 4);
    void *ws = malloc(qtool_view_workspace_size(v));
    uint8_t *rec = NULL;
    int rc;
    if (o->record && (o->bench_frames <= 0 || qtool_view_record_check(v, o->bench_frames, err, errlen) != 0)) {
        if (o->bench_frames <= 0)
            snprintf(err, errlen, "view: --record needs --bench (the frames it sweeps)");
        free(buf), free(ws);
        return -1;
    }
    if (o->record)
        rec = malloc((size_t)o->bench_frames * w * (h + QTOOL_VIEW_OVERLAY_H) * 3);
    if (!buf || !ws || (o->record && !rec))
        rc = -1, snprintf(err, errlen, "view: out of memory");
    else if (o->headless && o->bench_frames > 0)
        rc = bench_headless(v, o, buf, ws, rec, err, errlen);
    else {
#if QIBL_HAVE_X11
        rc = x_run(v, o, buf, ws, rec, err, errlen);
#else
        rc = -1, snprintf(err, errlen, "view: this qibl was built without X11 (Debian: apt-get install libx11-dev, "
                                       "then rebuild); --bench --headless still runs");
#endif
    }
    /* the recording is written only when every frame was drawn (atomically: no partial file) */
    if (rc == 0 && rec &&
        qtool_apng_write_rgb8(o->record, (int)w, (int)(h + QTOOL_VIEW_OVERLAY_H), (int)o->bench_frames, rec, 1, 15,
                              err, errlen) != 0)
        rc = -1;
    free(buf), free(ws), free(rec);
    return rc;
}
