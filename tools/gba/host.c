/*
 * gba/host.c - qibl-gba-run: runs a Game Boy Advance ROM headless over libmgba (mGBA's core) and
 * prints what the ROM writes to mGBA's debug port, until the ROM exits or a cycle limit.
 *
 * usage: qibl-gba-run [--seconds S] [--screenshot OUT.ppm] [--select] ROM.gba
 *   --seconds S        the limit in emulated seconds (default 600; 16 777 216 cycles each)
 *   --screenshot FILE  the screen as a binary PPM (240x160, 8 bits per channel) when the ROM exits
 *   --select           hold the SELECT button the whole run (the demo ROM's cue to exit, demo.c)
 * Protocol (tools/gba/gba_io.c): an INFO message of the "GBA Debug" category is one line, a DEBUG
 * one the first part of a longer line, a WARN "exit <n>" the exit status. Other categories' errors
 * (bad memory accesses and the like) go to stderr as "mgba: ...". Exit status: the ROM's; 124 when
 * the limit passed first; 2 on a usage error, a ROM whose header checksum is wrong (the BIOS of a
 * real GBA would refuse it) or one mGBA would not load.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mgba/core/core.h>
#include <mgba/core/log.h>
#include <mgba-util/vfs.h>

enum { GBA_HZ = 16777216, FRAME_CYCLES = 280896, WIDTH = 240, HEIGHT = 160, MAX_NOTES = 20 };

typedef struct {
    struct mLogger d; /* first: mGBA passes this pointer back */
    int exited, status, notes;
} logger;

static void on_log(struct mLogger *l, int category, enum mLogLevel level, const char *format, va_list args)
{
    logger *g = (logger *)l;
    const char *id = mLogCategoryId(category);
    if (id != NULL && strcmp(id, "gba.debug") == 0) {
        char msg[300];
        vsnprintf(msg, sizeof msg, format, args);
        if (level == mLOG_WARN && strncmp(msg, "exit ", 5) == 0) {
            g->exited = 1, g->status = atoi(msg + 5);
        } else if (level == mLOG_DEBUG) {
            fputs(msg, stdout);
        } else {
            puts(msg);
        }
        return;
    }
    if ((level & (mLOG_FATAL | mLOG_ERROR | mLOG_GAME_ERROR)) && g->notes < MAX_NOTES) {
        ++g->notes;
        fprintf(stderr, "mgba: %s: ", id ? id : "?");
        vfprintf(stderr, format, args);
        fputc('\n', stderr);
    }
}

/* The BIOS boots a cartridge only when byte 0xBD is the complement checksum of 0xA0..0xBC; mGBA
 * does not check it, so this runner does (a ROM that passes here boots on hardware as far as the
 * header goes; the logo is the other half, docs/porting.md). 0 when it holds, else -1 with why. */
static int check_header(const char *rom, char *why, size_t n)
{
    unsigned char h[0xC0];
    FILE *f = fopen(rom, "rb");
    size_t got = f ? fread(h, 1, sizeof h, f) : 0;
    if (f)
        fclose(f);
    if (got != sizeof h) {
        snprintf(why, n, "shorter than the 192-byte cartridge header");
        return -1;
    }
    unsigned sum = 0;
    for (int i = 0xA0; i < 0xBD; ++i)
        sum += h[i];
    unsigned want = (0u - sum - 0x19u) & 0xFFu;
    if (h[0xBD] != want) {
        snprintf(why, n, "header checksum 0x%02x, the header needs 0x%02x (tools/gba/fix_header.py writes it)", h[0xBD], want);
        return -1;
    }
    return 0;
}

static int write_ppm(const char *path, const color_t *px)
{
    FILE *f = fopen(path, "wb");
    if (f == NULL)
        return -1;
    fprintf(f, "P6\n%d %d\n255\n", WIDTH, HEIGHT);
    for (int i = 0; i < WIDTH * HEIGHT; ++i) {
        uint32_t c = (uint32_t)px[i]; /* XBGR8 */
        unsigned char rgb[3] = {(unsigned char)c, (unsigned char)(c >> 8), (unsigned char)(c >> 16)};
        fwrite(rgb, 1, 3, f);
    }
    return fclose(f) == 0 ? 0 : -1;
}

int main(int argc, char **argv)
{
    double seconds = 600;
    const char *shot = NULL, *rom = NULL;
    int select = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
            char *end;
            seconds = strtod(argv[++i], &end);
            if (*end != '\0' || !(seconds > 0 && seconds < 1e6)) {
                fprintf(stderr, "qibl-gba-run: --seconds %s: not a number of seconds in (0, 1e6)\n", argv[i]);
                return 2;
            }
        } else if (strcmp(argv[i], "--screenshot") == 0 && i + 1 < argc) {
            shot = argv[++i];
        } else if (strcmp(argv[i], "--select") == 0) {
            select = 1;
        } else if (argv[i][0] != '-' && rom == NULL) {
            rom = argv[i];
        } else {
            fprintf(stderr, "usage: qibl-gba-run [--seconds S] [--screenshot OUT.ppm] [--select] ROM.gba\n");
            return 2;
        }
    }
    if (rom == NULL) {
        fprintf(stderr, "usage: qibl-gba-run [--seconds S] [--screenshot OUT.ppm] [--select] ROM.gba\n");
        return 2;
    }
    char why[120];
    if (check_header(rom, why, sizeof why) != 0) {
        fprintf(stderr, "qibl-gba-run: %s: %s\n", rom, why);
        return 2;
    }
    logger log = {.d = {.log = on_log, .filter = NULL}};
    mLogSetDefaultLogger(&log.d);

    struct VFile *vf = VFileOpen(rom, O_RDONLY);
    if (vf == NULL) {
        fprintf(stderr, "qibl-gba-run: %s: cannot open\n", rom);
        return 2;
    }
    struct mCore *core = mCoreFindVF(vf);
    if (core == NULL || !core->init(core) || core->platform(core) != mPLATFORM_GBA) {
        fprintf(stderr, "qibl-gba-run: %s: not a ROM mGBA runs as a GBA cartridge\n", rom);
        vf->close(vf);
        return 2;
    }
    mCoreInitConfig(core, NULL);
    core->opts.skipBios = true; /* no BIOS file: mGBA's own (HLE) BIOS, straight to the cartridge */
    mCoreLoadConfig(core);
    static color_t screen[WIDTH * HEIGHT];
    core->setVideoBuffer(core, screen, WIDTH);
    if (!core->loadROM(core, vf)) {
        fprintf(stderr, "qibl-gba-run: %s: mGBA would not load it\n", rom);
        core->deinit(core);
        return 2;
    }
    core->reset(core);
    if (select)
        core->setKeys(core, 1u << 2); /* GBA_KEY_SELECT */

    uint64_t limit = (uint64_t)(seconds * GBA_HZ), frames = 0;
    while (!log.exited && frames * FRAME_CYCLES < limit) {
        core->runFrame(core);
        ++frames;
    }
    fflush(stdout);
    int rc = log.exited ? log.status : 124;
    if (!log.exited)
        fprintf(stderr, "qibl-gba-run: %s: no exit after %g emulated seconds (the limit)\n", rom, seconds);
    fprintf(stderr, "qibl-gba-run: %s: %.1f emulated seconds (%llu frames)\n", rom,
            (double)(frames * FRAME_CYCLES) / GBA_HZ, (unsigned long long)frames);
    if (shot != NULL && write_ppm(shot, screen) != 0) {
        fprintf(stderr, "qibl-gba-run: %s: cannot write\n", shot);
        rc = rc ? rc : 1;
    }
    core->deinit(core);
    return rc;
}
