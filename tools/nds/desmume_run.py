#!/usr/bin/env python3
"""nds/desmume_run.py - runs a Nintendo DS ROM headless under desmume-cli and prints what the ROM
prints, until the ROM exits or a wall-clock limit.

usage: desmume_run.py [--seconds S] [--log FILE] ROM.nds
  --seconds S   the limit in wall-clock seconds (default 600): DeSmuME has no limit of its own
  --log FILE    where DeSmuME's own messages go (default: dropped)
The ROM's lines come through DeSmuME's debug print (SWI 0xFC, tools/nds/nds_io.c) on the
emulator's standard output, among its own messages: "nds: <line>" is a line of the ROM, "nds+
<rest>" continues the previous one, "nds-exit <n>" is the exit status. DeSmuME never stops by
itself, so on the exit line this runner ends the emulator it started (SIGTERM, then SIGKILL).
Runs with SDL's dummy video and audio drivers (no display, no sound card), the frame limiter off
and the JIT on; stdbuf makes the emulator's stdout line-buffered, so each line arrives as printed.
Exit status: the ROM's; 124 when the limit passed first; 125 when DeSmuME ended without the exit
line; 2 on a usage error, a missing desmume-cli or a ROM whose header CRC is wrong.
"""
import os
import resource
import shutil
import subprocess
import sys
import threading
import time

from ndsrom import crc16


def find_desmume():
    for d in os.environ.get("PATH", "").split(os.pathsep) + ["/usr/games"]:
        p = os.path.join(d, "desmume-cli")
        if os.access(p, os.X_OK):
            return p
    return None


def check_header(rom):
    """DeSmuME boots a ROM whatever its header CRC; the DS's BIOS does not, so this runner checks
    it (GBATEK: CRC-16/MODBUS of bytes 0x000..0x15D, at 0x15E). None when it holds, else why."""
    with open(rom, "rb") as f:
        h = f.read(0x160)
    if len(h) < 0x160:
        return "shorter than the cartridge header"
    want, got = crc16(h[:0x15E]), h[0x15E] | h[0x15F] << 8
    if got != want:
        return "header CRC-16 0x%04x, the header needs 0x%04x (tools/nds/ndsrom.py writes it)" % (got, want)
    return None


def main(argv):
    seconds, log, rom = 600.0, None, None
    args = argv[1:]
    while args:
        a = args.pop(0)
        if a == "--seconds" and args:
            try:
                seconds = float(args.pop(0))
            except ValueError:
                seconds = -1
            if not 0 < seconds < 1e6:
                sys.exit("desmume_run: --seconds: not a number of seconds in (0, 1e6)")
        elif a == "--log" and args:
            log = args.pop(0)
        elif not a.startswith("-") and rom is None:
            rom = a
        else:
            rom = None
            break
    if rom is None:
        print("usage: desmume_run.py [--seconds S] [--log FILE] ROM.nds", file=sys.stderr)
        return 2
    desmume = find_desmume()
    if desmume is None:
        print("desmume_run: desmume-cli not found (Debian: apt-get install desmume)", file=sys.stderr)
        return 2
    if not os.path.isfile(rom):
        print("desmume_run: %s: no such file" % rom, file=sys.stderr)
        return 2
    why = check_header(rom)
    if why is not None:
        print("desmume_run: %s: %s" % (rom, why), file=sys.stderr)
        return 2
    env = dict(os.environ, SDL_VIDEODRIVER="dummy", SDL_AUDIODRIVER="dummy")
    # an absolute path: desmume-cli 0.9.11 aborts on a ROM path without a directory
    cmd = [desmume, "--disable-sound", "--disable-limiter", "--cpu-mode=1", "--3d-engine=0",
           "--load-type=1", os.path.abspath(rom)]
    if shutil.which("stdbuf"):
        cmd = ["stdbuf", "-oL"] + cmd
    logf = open(log, "w") if log else None
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=logf or subprocess.DEVNULL, env=env)
    timer = threading.Timer(seconds, proc.terminate)
    timer.start()
    status, pending = None, None
    for raw in proc.stdout:
        text = raw.decode("latin-1").rstrip("\n")
        if text.startswith("nds+ ") and pending is not None:
            pending += text[5:]
            continue
        if pending is not None:
            print(pending, flush=True)
            pending = None
        if text.startswith("nds: "):
            pending = text[5:]
        elif text.startswith("nds-exit "):
            status = int(text[9:])
            break
        elif logf:
            logf.write(text + "\n")
    if pending is not None:
        print(pending, flush=True)
    timed_out = not timer.is_alive() and status is None
    timer.cancel()
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    wall = time.monotonic() - t0
    use = resource.getrusage(resource.RUSAGE_CHILDREN)  # the emulator's own: load-independent
    cpu = use.ru_utime + use.ru_stime
    if logf:
        logf.close()
    if status is None:
        why = "no exit after %g s (the limit)" % seconds if timed_out else "DeSmuME ended without the exit line"
        print("desmume_run: %s: %s" % (rom, why), file=sys.stderr)
        return 124 if timed_out else 125
    print("desmume_run: %s: exit %d after %.1f s of wall-clock time, %.1f s of CPU time" % (rom, status, wall, cpu),
          file=sys.stderr)
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
