/*
 * gba/demo.c - the relighting demo ROM: the courtyard (SH maps from `qibl gen`, in cartridge ROM)
 * relit by a sun moving around the sky, drawn in mode 3 (240 x 160, BGR555 in VRAM).
 *
 * First it measures: one frame with k = 4 maps and one with k = 9, CPU cycles of the relight and of
 * the RGB565 write from the hardware timers, printed as RESULT lines with the frame's CRC-32 (which
 * tools/gba/run.sh compares with the host's, demo_ref.c), and one screen update of the interactive
 * loop below. If SELECT is held then (qibl-gba-run --select does) it exits with the k = 9 frame on
 * screen for the screenshot; otherwise the sun keeps moving as long as the power is on (mGBA's
 * window, or hardware).
 *
 * The interactive loop refreshes the screen in part: an update relights every 32nd row (5 rows,
 * in a bit-reversed order of the 32 phases so that the picture fills in evenly), so the screen
 * changes more than 10 times a second while a whole frame takes 1.5-3 s; the sun moves one step
 * after each full pass of 32 updates, so the picture converges to each sun position before it
 * moves on.
 */
#include <stdint.h>

#include "demo_frame.h"
#include "iwram_relight.h"
#include "semi.h"
#include "stack.h"

#define REG_DISPCNT (*(volatile uint16_t *)0x04000000u)
#define REG_KEYINPUT (*(volatile uint16_t *)0x04000130u)
#define VRAM ((volatile uint16_t *)0x06000000u)
enum { KEY_SELECT = 1 << 2, DEMO_CHECK_STEP = 10, PHASES = 32 };

/* rows y = phase (mod 16) of the frame at step s */
static qibl_status_t update(const qibl_shmaps_t *m, uint32_t s, uint32_t phase, demo_buffers_t *b, demo_hooks_t *h)
{
    static const uint8_t order[PHASES] = {0, 16, 8, 24, 4, 20, 12, 28, 2, 18, 10, 26, 6, 22, 14, 30,
                                          1, 17, 9,  25, 5, 21, 13, 29, 3, 19, 11, 27, 7, 23, 15, 31};
    qibl_status_t st = QIBL_OK;
    for (uint32_t y = order[phase % PHASES]; y < m->height && st == QIBL_OK; y += PHASES)
        st = demo_frame(m, s, y, y + 1u, b, h);
    return st;
}

extern const uint8_t demo_asset_k4[], demo_asset_k4_end[], demo_asset_k9[], demo_asset_k9_end[];

typedef struct {
    uint32_t crc;
    int with_crc; /* the measured frames only: it costs more than the conversion */
} frame_state;

/* RGB565 (R high) to the GBA's BGR555 (R low), into the screen's row y; the CRC of the RGB565
 * bytes (little-endian) as platform/soft wrote them */
static void to_screen(void *user, uint32_t y, const uint16_t *px, uint32_t n)
{
    frame_state *f = (frame_state *)user;
    volatile uint16_t *dst = VRAM + 240u * y;
    for (uint32_t x = 0; x < n; ++x) {
        uint32_t v = px[x];
        if (f->with_crc) {
            uint8_t le[2] = {(uint8_t)v, (uint8_t)(v >> 8)};
            f->crc = qibl_crc32(f->crc, le, 2);
        }
        dst[x] = (uint16_t)((v >> 11) | ((v >> 6) & 31u) << 5 | (v & 31u) << 10);
    }
}

static uint32_t cycles(void *user)
{
    (void)user;
    return (uint32_t)bm_insn_clock();
}

static void put_tenths(uint64_t num, uint64_t den)
{
    uint64_t t = (num * 10u + den / 2u) / den;
    bm_putu((uint32_t)(t / 10u)), bm_puts("."), bm_putu((uint32_t)(t % 10u));
}

/* in IWRAM (32-bit bus, no wait states; gba.ld copies .iwram from ROM): the relight reads and
 * writes them for every pixel */
static demo_buffers_t bufs __attribute__((section(".iwram.demo_buffers")));

/* the relight of a row: the core's (NULL), or with DEMO_ARM_KERNEL the port's own (iwram_relight.c,
 * ARM assembly kernels in IWRAM; the same bytes) */
#if DEMO_ARM_KERNEL
#define DEMO_RELIGHT gba_relight_row
#else
#define DEMO_RELIGHT NULL
#endif

/* updates per second of the interactive loop: the cycles of one update (phase 0 at the next step) */
static void measure_update(const qibl_shmaps_t *m)
{
    frame_state f = {0};
    demo_hooks_t h = {.row = to_screen, .user = &f, .relight = DEMO_RELIGHT};
    uint32_t t0 = cycles(NULL);
    qibl_status_t st = update(m, DEMO_CHECK_STEP + 1u, 0, &bufs, &h);
    uint32_t t = cycles(NULL) - t0;
    if (st == QIBL_OK && t != 0) {
        bm_puts("RESULT gba.demo_k9_updates_per_s "), put_tenths(16777216u, t), bm_puts("\n");
        bm_puts("RESULT gba.demo_k9_full_refresh_s "), put_tenths((uint64_t)t * PHASES, 16777216u), bm_puts("\n");
    }
    (void)update(m, DEMO_CHECK_STEP, 0, &bufs, &h); /* (the checked frame back on screen) */
}

static int open_maps(const uint8_t *a, const uint8_t *end, qibl_asset_t *asset, qibl_shmaps_t *m)
{
    qibl_status_t st = qibl_asset_open(asset, a, (size_t)(end - a));
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(asset, m);
    if (st != QIBL_OK) {
        bm_puts("demo: the asset in ROM: "), bm_puts(qibl_soft_status_str(st)), bm_puts("\n");
        return -1;
    }
    return 0;
}

/* one measured frame at DEMO_CHECK_STEP */
static int measure(const char *tag, const qibl_shmaps_t *m)
{
    frame_state f = {0, 1};
    demo_hooks_t h = {.row = to_screen, .clock = cycles, .user = &f, .relight = DEMO_RELIGHT};
    uint32_t t0 = cycles(NULL);
    qibl_status_t st = demo_frame(m, DEMO_CHECK_STEP, 0, m->height, &bufs, &h);
    uint32_t total = cycles(NULL) - t0;
    if (st != QIBL_OK) {
        bm_puts("demo: frame: "), bm_puts(qibl_soft_status_str(st)), bm_puts("\n");
        return -1;
    }
    const uint64_t px = (uint64_t)m->width * m->height;
    bm_puts("frame "), bm_puts(tag), bm_puts(" step "), bm_putu(DEMO_CHECK_STEP), bm_puts(" crc32 ");
    static const char hx[] = "0123456789abcdef";
    char c[9];
    for (int i = 0; i < 8; ++i)
        c[i] = hx[(f.crc >> (28 - 4 * i)) & 15u];
    c[8] = '\0';
    bm_puts(c), bm_puts(" frame_cycles "), bm_putu(total), bm_puts("\n");
    bm_puts("RESULT gba.sun_"), bm_puts(tag), bm_puts("_cycles_per_px "), put_tenths(h.relight_ticks, px), bm_puts("\n");
    bm_puts("RESULT gba.sun_"), bm_puts(tag), bm_puts("_write_cycles_per_px "), put_tenths(h.write_ticks, px), bm_puts("\n");
    bm_puts("RESULT gba.sun_"), bm_puts(tag), bm_puts("_frame_ms "), put_tenths((uint64_t)total * 1000u, 16777216u), bm_puts("\n");
    return 0;
}

int main(void)
{
    qibl_asset_t a4, a9;
    qibl_shmaps_t m4, m9;
    REG_DISPCNT = 0x0403; /* mode 3, BG2 on */
    bm_clock_start();
    if (open_maps(demo_asset_k4, demo_asset_k4_end, &a4, &m4) != 0 ||
        open_maps(demo_asset_k9, demo_asset_k9_end, &a9, &m9) != 0)
        return 1;
    if (measure("k4", &m4) != 0 || measure("k9", &m9) != 0)
        return 1;
    measure_update(&m9);
    /* the stack shares IWRAM with .iwram (more of it with arm-iwram-asm's kernels): run.sh
     * checks this against the stack's size */
    bm_puts("demo stack high-water "), bm_putu((uint32_t)bm_stack_high_water()), bm_puts(" of "),
        bm_putu((uint32_t)bm_stack_size()), bm_puts("\n");
    if ((REG_KEYINPUT & KEY_SELECT) == 0)
        return 0; /* SELECT held: measured, k = 9 frame on screen */
    frame_state f = {0};
    demo_hooks_t h = {.row = to_screen, .user = &f, .relight = DEMO_RELIGHT};
    for (uint32_t u = PHASES * (DEMO_CHECK_STEP + 1u);; ++u)
        if (update(&m9, u / PHASES % DEMO_SUN_STEPS, u % PHASES, &bufs, &h) != QIBL_OK)
            return 1;
}
