/*
 * main.c - the qibl command-line tool: subcommand dispatch, --help, shared argument parsing.
 */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/asset.h" /* QIBL_ASSET_MAX_LUT */
#include "cli/cli.h"
#include "cli/opt.h"
#include "qibl/version.h"
#include "qibl/shmaps.h"
#include "qibl/isa.h"
#include "io/isa_env.h"

int qcli_parse_only; /* see cli.h */

/* the option tables of the commands on them (cli/opt.h), one per subcommand */
static const qcli_opt_cmd *const sh_opts[] = {&qcli_opts_sh_eval, &qcli_opts_sh_plot, NULL};
static const qcli_opt_cmd *const gen_opts[] = {&qcli_opts_gen, NULL};
static const qcli_opt_cmd *const info_opts[] = {&qcli_opts_info, NULL};
static const qcli_opt_cmd *const srgbe_opts[] = {&qcli_opts_srgbe_encode, &qcli_opts_srgbe_decode, NULL};
static const qcli_opt_cmd *const ies_opts[] = {&qcli_opts_ies_info, NULL};
static const qcli_opt_cmd *const study_opts[] = {&qcli_opts_study, NULL};

/* which commands are on them: `qibl help CMD` is made from these, not from the command's usage */
static const struct {
    const char *cmd;
    const qcli_opt_cmd *const *opts;
} tables[] = {{"sh", sh_opts},       {"gen", gen_opts}, {"info", info_opts},
              {"srgbe", srgbe_opts}, {"ies", ies_opts}, {"study", study_opts}};

static const qcli_opt_cmd *const *tables_of(const char *cmd)
{
    for (size_t i = 0; i < sizeof tables / sizeof tables[0]; ++i)
        if (strcmp(tables[i].cmd, cmd) == 0)
            return tables[i].opts;
    return NULL;
}

static const qcli_cmd commands[] = {
    {"sh", "evaluate the integer SH basis for a direction",
     /* sh project (cmd_probe.c) is not on an option table yet: its text as it was */
     "usage: qibl sh project PROBE.hdr [--bands B] [--irradiance] [--window none|hann|lanczos]\n"
     "                       [--layout L] [--format table|json|c] [--name ID] [--frame zup|yup]\n"
     "                       [--yaw DEG | --rotate a,b,c,d,e,f,g,h,i]\n"
     "       qibl sh project PROBE.hdr --preset filament|unity|gltf|raw [--window auto|no|CUTOFF]\n"
     "                       [--yaw DEG | --rotate ...] [--layout L] [--name ID]\n"
     "  project: a Radiance probe (layout detected or --layout, resampled to lat-long as qibl lights\n"
     "  does) projected onto bands 0..B-1 by the integer core, row by row (qibl/probe.h): radiance\n"
     "  coefficients, or irradiance (times the clamped-cosine A_l), with an optional Hann or Lanczos\n"
     "  window. --format table (default: l, m, R, G, B), json, or c (a header: ID_BANDS and\n"
     "  `static const float ID[B*B][3]` with a band/order comment per row; --name ID, default\n"
     "  qibl_probe_sh). --frame yup writes them in a y-up frame ((x, z, -y) of qibl's); --yaw DEG\n"
     "  (positive turns +x toward +y) or --rotate turns the probe first, as qibl relight does.\n"
     "  --preset writes an engine's own convention (tools/engine/engine.h has each formula):\n"
     "    filament  cmgen's sh.txt (--deploy): 3 bands of irradiance times A_l, windowed (--window\n"
     "              auto (default), no or a cutoff band, as cmgen's --sh-window), times Sloan's\n"
     "              constants / pi, y up mirrored in x as cmgen's cubemap; paste into sh.txt.\n"
     "    unity     C#: SphericalHarmonicsL2 (Unity's scale and frame) and the unity_SHAr..SHC\n"
     "              constants ShadeSH9 reads; prints the SH9 truncation error against the probe.\n"
     "    gltf      an EXT_lights_image_based JSON object (irradianceCoefficients, y up).\n"
     "    raw       the table, as without --preset.\n"
     "  The layout note goes to stderr except for the table. (--format cmgen is refused: it was not\n"
     "  what cmgen writes; use --preset filament.)\n",
     qcli_cmd_sh},
    {"bench", "benchmarks: speed against error, with RESULT lines",
     "usage: qibl bench [all|sh|relight|baselines|srgbe|lights|paths|asset|probe|hemi|memory|gles] [--quick] [--csv] [--markdown]\n"
     "                  [--svg PATH]  (hemi: the cloth's error against frames per second, as an SVG plot)\n"
     "  sh: integer SH basis against the double reference from Wong et al.'s appendix:\n"
     "      ns per evaluation (median of 7 runs) and max |error| over a fixed-seed sweep.\n"
     "  relight: the relighting kernels on the procedural courtyard, 1024x256, k = 4, 9, 16, 25:\n"
     "      directional and point lights (cube-map LUT 16^2/32^2/64^2, direct SH): ms/frame,\n"
     "      Mpixel/s, PSNR and max abs error in 8-bit units, a plain read of the same map bytes, the\n"
     "      two range-packing schemes; --csv prints the table as CSV.\n"
     "  srgbe: the sRGBE codec against Ward's RGBE (frexp/ldexp), RGB9E5 and binary32 on a real\n"
     "      probe from ../shared/fixtures/probes (QIBL_PROBE=FILE picks one; a procedural sky\n"
     "      when absent) and on signed SH data of it: max/mean relative error of the largest\n"
     "      channel, mean absolute error of the others, encode/decode Mpixel/s (medians).\n"
     "  lights: light-probe sampling on a 1024x512 probe (QIBL_PROBE=FILE, else quarry_01_1k.hdr from\n"
     "      ../shared/fixtures/probes, else a procedural sky) and on it upsampled to 4096x2048: SAT and\n"
     "      cut milliseconds for median cut 64/256, adaptive 64, varmin 64, and the ratio of median cut 64\n"
     "      (SAT included) to one plain read pass over the probe bytes (RESULT lights.sat64_over_read);\n"
     "      then the irradiance error of every method and priority on each real probe.\n"
     "  paths: path lights against today's SH-only relighting, 1024x256, thread CPU time: a sun as\n"
     "      unshadowed k = 9 or 16 x path visibility (hard, soft), sky + sun, lamps on a track and free.\n"
     "  asset: opening a 16 MB asset: nibble CRC, slicing-by-8 CRC, structure only, against a memcpy\n"
     "      of the same bytes (min and median of interleaved repetitions).\n"
     "  probe: SH projection of a 1024x512 probe (quarry_01_1k.hdr, else an integer-made one) against\n"
     "      one 64-bit read pass of its bytes (min and median of interleaved runs), the projection's\n"
     "      error against the double reference on every fixture probe, the rotation's error, and the\n"
     "      ringing of the irradiance with no window, Hann and Lanczos (RESULT probe.*).\n"
     "  memory: not a timing: the resident-memory table of docs/porting.md (--markdown: as there).\n"
     "  all: every timing benchmark (what `make bench` runs). --quick: fewer repetitions.\n",
     qcli_cmd_bench},
    {"gen", "write the procedural courtyard's SH maps (and P map, optional Y LUT) as an asset",
     NULL, qcli_cmd_gen},
    {"render", "ray-trace the ground-truth panorama of a scene under one light (PNG, PFM, depth)",
     "usage: qibl render (--sun X Y Z | --point X Y Z) [--rgb R G B] [--falloff 1|2] [--png OUT] [--pfm OUT]\n"
     "                   [--exr OUT.exr] [--depth OUT.pfm] [--scene builtin|FILE.gltf|FILE.glb|FILE.obj|FILE.ply] [--zup]\n"
     "                   [--raw] [--size WxH] [--equirect] [--threads N] [--ies FILE.ies [--aim X Y Z] [--up X Y Z]]\n"
     "                   [--camera EX,EY,EZ TX,TY,TZ UX,UY,UZ | --camera gltf[:N]] [--fov DEG]\n"
     "  The reference renderer (BVH ray tracer, hard shadows, Lambert + glossy) from the viewpoint at the\n"
     "  origin: what a light really produces, to compare relit frames with. --sun: directional light\n"
     "  from (X, Y, Z) with irradiance --rgb (default 1 1 1); --point: a lamp at (X, Y, Z) with\n"
     "  C0 = --rgb and falloff C0/|L| (or |L|^2); without --rgb, C0 = 2 d (or 2 d^2), d the median\n"
     "  distance from the lamp to what the panorama sees (a note says so); every number within the Q16.16 range relight takes\n"
     "  (|v| <= 32767.99998, --rgb >= 0). --png: sRGB 8-bit through the same framebuffer code\n"
     "  as qibl relight; --pfm: linear RGB floats; --exr: the same floats as OpenEXR (scanline, ZIP, FLOAT\n"
     "  channels, bit for bit); --depth: depth along each pixel's ray (0 for sky).\n"
     "  Scenes: the built-in courtyard (default) or a glTF 2.0 (.gltf, .glb), OBJ or PLY mesh placed as a\n"
     "  prop on a ground plane, 3.5 units along -x: the middle of the panorama, away from its seam at +x\n"
     "  (Y-up turned to Z-up unless --zup; --raw: as given, nothing added). Materials colour the\n"
     "  triangles: glTF baseColorFactor and PNG baseColorTexture, OBJ mtllib/usemtl with Kd and map_Kd\n"
     "  (PNG) and vt. Default 1024x256 cylindrical. A frame whose mean is below 32 of 255 gets a note\n"
     "  that it is almost black.\n"
     "  --ies FILE.ies: the --point lamp is goniometric: C0 times I(direction) / I_peak from the IES\n"
     "  profile in double precision (bilinear in its angle grid), oriented by --aim (default 0 0 -1)\n"
     "  and --up (default 1 0 0) as relight --ies orients it: the truth of relight's tables.\n"
     "  --camera EYE TARGET UP: a fixed perspective camera (a pre-rendered background) instead of the\n"
     "  panorama: --size WxH pixels from EYE looking at TARGET, UP its approximate up, --fov DEG the\n"
     "  vertical field of view (default 60, in (0, 180)); --camera gltf[:N]: the scene file's camera N\n"
     "  (default 0, perspective, its yfov unless --fov), placed as the mesh is. A bad camera (EYE =\n"
     "  TARGET, UP zero or along the view) is named.\n",
     qcli_cmd_render},
    {"transfer", "a mesh self-shadowed by hemispherical rasterization under a probe, beside the ray-cast truth",
     "usage: qibl transfer MESH [MESH...] --probe PROBE.hdr [--layout L] [--png OUT] [--size N] [--mask 16|32|64]\n"
     "                     [--face F] [--rays S] [--coarse T [--ring K]] [--tween N] [--zup] [--flip] [--skip-adjacent]\n"
     "                     [--view AZ,EL] [--threads N]\n"
     "  Per vertex of a glTF (.gltf, .glb: the scene's meshes in world space, skinned; FILE.gltf@T: its\n"
     "  animation at T seconds, so FILE.gltf@0 FILE.gltf@0.5 ... are frames), OBJ or PLY mesh\n"
     "  (welded by position, centred, largest half-extent 1, Y-up turned\n"
     "  to Z-up unless --zup; normals point out of counter-clockwise faces, turned by --flip or when a\n"
     "  mesh with under 2 % open edges has a negative volume), the transfer vector V*\n"
     "  (bands 0..4) from hemispherical rasterization with every triangle a blocker (qibl/hemi.h: mask\n"
     "  --mask, default 32, LUT face --face, default 64), turned to world space and shaded with the\n"
     "  probe's radiance SH (irradiance; pictures at an automatic exposure). --skip-adjacent: the paper's\n"
     "  rule alone (faces around a vertex skipped) instead of also blocking the solid behind them at\n"
     "  creases. Reference: S x S stratified cosine-weighted\n"
     "  rays per vertex (--rays, default 32; 0: none) through a BVH, shaded with the same coefficients.\n"
     "  --coarse T: the paper's two-level hierarchy instead of every triangle: a coarse mesh of about T\n"
     "  triangles (quadric-error half-edge collapses, so its vertices are the mesh's and it animates with\n"
     "  it) plus the full mesh within K edges of each vertex (--ring, default 3).\n"
     "  --png: qibl | ray cast | error (|E - E_ref| / mean E_ref, 0..10 %), drawn by platform/soft's\n"
     "  integer z-buffer rasterizer, orthographic from azimuth / elevation --view (default 35,20);\n"
     "  several MESH files are frames of one animation (same triangles): an animated PNG (--tween N: N - 1\n"
     "  frames interpolated between key frames, the last back into the first). Prints ms per\n"
     "  frame on one core (thread CPU time of the hemi calls) and RESULT transfer.* lines.\n",
     qcli_cmd_transfer},
    {"bake", "bake a scene into a relightable panorama asset (ray-traced, SH-projected, 8-bit packed)",
     "usage: qibl bake (-o ASSET | --shard I/N --sums FILE) [--k K] [--lut-size N] [--dirs N] [--lsq]\n"
     "                 [--budget DB] [--quiet] [--progress=bar|lines|none]\n"
     "                 [--layout planar|interleaved] [--unshadowed-k K] [--sun-path LAT,DECL,T0,T1]\n"
     "                 [--lamp-track X,Y,Z;X,Y,Z;...] [--path-steps N]\n"
     "                 [--lamp-box X0,Y0,Z0,X1,Y1,Z1] [--lamp-samples N] [scene options as for render]\n"
     "                 [--camera EX,EY,EZ TX,TY,TZ UX,UY,UZ | --camera gltf[:N]] [--fov DEG]\n"
     "  Renders the scene under N directional lights (spherical Fibonacci set, equal weights 4 pi / N,\n"
     "  default 512) with hard shadows, projects every pixel's response onto SH (k <= 25, default 16;\n"
     "  quadrature, or --lsq least squares), packs the maps to 8 bits (min/max per map and channel) and\n"
     "  writes SHMP + PMAP (+ a cube-map YLUT of face --lut-size N, default 32; 0 = none). Sums are\n"
     "  exact integers: the asset is bit-identical for any --threads and any sharding.\n"
     "  --shard I/N --sums FILE (no -o): bake only the I-th of N shares of the directions (and of the\n"
     "  rows of the light paths and lamp occlusion), write partial sums for qibl merge (a render farm:\n"
     "  docs/farm.md). --budget DB: choose the smallest band-complete k whose PSNR against ground truth\n"
     "  on 8 novel suns reaches DB, and the smallest LUT within 0.1 dB of direct SH evaluation on 4\n"
     "  lamps, and say so. --progress: a bar on stderr (the default on a terminal), or lines (the\n"
     "  default elsewhere: one flushed line per step, \"progress: stage=S done=D total=T fraction=F\"),\n"
     "  or none (also --quiet). --threads defaults to the CPUs the process may run on (its affinity:\n"
     "  taskset, a job's cgroup), lowered to SLURM_CPUS_PER_TASK where that is set.\n"
     "  --layout interleaved: SH maps streamable by rows (see qibl help gen).\n"
     "  --unshadowed-k K (default 9, 0 = none): also the unshadowed transfer (cosine x BRDF, no shadow\n"
     "  test) as SHMU (planar); free point lights use it (visibility at infinity is wrong for a lamp\n"
     "  inside the scene). --sun-path LAT,DECL,T0,T1 (degrees, degrees, solar hours; +x east, +y north)\n"
     "  and --lamp-track \"x,y,z;x,y,z;...\" (a polyline, t by arc length; up to 8 paths): per pixel the\n"
     "  light's visibility along the path (facing and shadow) as on/off edges of t in 0..65535, sampled\n"
     "  at N + 1 points (--path-steps, default 64) and bisected to one 16-bit step (LPTH chunks; relit\n"
     "  as unshadowed SH x visibility, qibl/lightpath.h). --lamp-box: the region free lamps move in;\n"
     "  per pixel the expected visibility of a lamp there (N Halton positions, default 64), LOCC: free\n"
     "  lamps through SHMU are scaled by it (their cast shadows on average). A shard also writes its\n"
     "  share of the unshadowed sums (FILE.u) and its rows of the LPTH/LOCC chunks (FILE.x, also when\n"
     "  there are none, so merge can refuse a shard baked without the others' paths).\n"
     "  --camera, --fov (as for render): the pixels are a fixed camera's rays instead of the panorama's,\n"
     "  so the maps relight a pre-rendered background seen from one corner (qibl relight as any asset).\n"
     "  Exit status: 0 done, 1 failed (a file, memory; named on stderr, nothing half-written), 2 bad\n"
     "  arguments.\n",
     qcli_cmd_bake},
    {"merge", "combine the partial sums of bake shards into an asset",
     "usage: qibl merge (-o ASSET | --sums OUT | both) [--k K] [--lut-size N] [--lsq]\n"
     "                  [--layout planar|interleaved] [--manifest FILE] SUMS...\n"
     "  Adds the partial sums written by `qibl bake --shard I/N --sums FILE` (every shard exactly once,\n"
     "  same bake) and writes the asset as qibl bake would (byte-identical, with the unshadowed maps,\n"
     "  light paths and lamp occlusion joined from every SUMS.u / SUMS.x when the shards wrote them), and/or the\n"
     "  total sums.\n"
     "  Every file is checked before use (version, CRC-32s, counts within the bake's limits, exact size),\n"
     "  then against the first (split, size, k, directions, P map); sums that would overflow 64 bits, a\n"
     "  shard given twice or missing, and --k above the shards' k are refused by name; so are shards whose\n"
     "  light paths or lamp occlusion (SUMS.x) differ (one baked without the others' --sun-path).\n"
     "  --manifest FILE: the shards named one per line, \"shard I/N SUMS [SUMS.u [SUMS.x]]\" ('-' for a\n"
     "  side file the shard has not; '#' comments), each file's I/N checked against the line.\n"
     "  A partial set (tree merges, --sums OUT without -o): shards I, I+M, I+2M, ... of N (M dividing N)\n"
     "  are written as shard I/M with OUT.u and OUT.x, for a later merge; any other partial set is refused.\n"
     "  Exit status: 0 written, 1 refused or failed (named on stderr, nothing written), 2 bad arguments.\n",
     qcli_cmd_merge},
    {"check", "validate PNG/APNG, PFM, Radiance HDR, OpenEXR and qibl asset files",
     "usage: qibl check FILE...\n"
     "  .png: signature, every chunk CRC, the zlib stream (inflated), Adler-32, APNG frame sequence;\n"
     "  .pfm: header and size; .hdr/.pic: Radiance header, resolution line and every scanline (RLE or\n"
     "  flat) decoded, as qibl lights reads it; .exr (or the EXR magic): header and every chunk decoded;\n"
     "  anything else as a qibl asset (qibl_asset_open).\n"
     "  Exit 1 if any is bad.\n",
     qcli_cmd_check},
    {"demo", "the main demo: bake the scene, relight it by the core, compare with ground truth",
     "usage: qibl demo --out DIR [--small | --full] [--dirs N] [--frames F] [scene options as for render]\n"
     "  What `make demo` runs: bakes the scene (built-in courtyard, or --scene FILE.gltf|.glb|.obj|.ply), writes\n"
     "  the assets for k = 9, 16, 25, relights a sun sweep and a moving lamp with the core (PNG frames and\n"
     "  APNG), a contact sheet (relit | ground truth | error heat map) for novel lights, and prints the\n"
     "  table of k, bytes, ms/frame and PSNR with RESULT lines, then the light paths and the probe-lit rows.\n"
     "  Sizes: default 512x128, 256 directions, 12 frames (`make demo`); --small 256x64, 128 directions,\n"
     "  6 frames (CI); --full 1024x256, 512 directions, 24 frames and the full probe-lit truths (`make demo\n"
     "  FULL=1`, minutes of CPU). --size WxH, --dirs and --frames override the size's values.\n",
     qcli_cmd_demo},
    {"relight", "relight an asset by suns, lamps, a light list or a whole probe into a PNG (core + soft framebuffer)",
     "usage: qibl relight FILE [--sun X Y Z [--rgb R G B]]... [--point X Y Z [--rgb R G B]]...\n"
     "                    [--lights FILE.csv] [--probe PROBE.hdr [--layout L] [--probe-mode sh|lights|sunsky]\n"
     "                    [-n N] [--yaw DEG | --rotate a,b,c,d,e,f,g,h,i]] [--lut poly|nearest|bilinear|off]\n"
     "                    [--falloff 1|2] [--exposure E] [--linear] [--gles] [--png OUT] [--hdr OUT.hdr]\n"
     "                    [--pfm OUT.pfm] [--exr OUT.exr]\n"
     "  Lights add up: any number of --sun and --point (at most 64 together), --lights and --probe.\n"
     "  --sun: directional light from direction (X, Y, Z), colour --rgb (default 1 1 1).\n"
     "  --point: point light at (X, Y, Z) in scene units, C0 = --rgb (default: 2 d, or 2 d^2 with\n"
     "  --falloff 2, d the median distance from the lamp to the asset's P-map points, with a note);\n"
     "  per-pixel Y from the SH polynomials in Q2.14 (--lut poly, the default and the fastest), the\n"
     "  asset's cube-map LUT (--lut nearest or bilinear) or the Q2.30 SH evaluation (--lut off);\n"
     "  --falloff 1 is C0/|L| (Wong et al.), 2 is C0/|L|^2. (The old\n"
     "  spellings, a bare --lut for bilinear and --nearest, still work with a deprecation note.)\n"
     "  --rgb colours the --sun or --point just before it (one given before the first light colours\n"
     "  that light). Suns sum in SH; each point is relit on its own and the frames sum per pixel in\n"
     "  64 bits, saturated once.\n"
     "  --lights FILE.csv: the output of `qibl lights --csv` (header x,y,z,r,g,b,u0,v0,u1,v1; at most\n"
     "  65536 rows), each row a directional light of colour r,g,b.\n"
     "  --probe PROBE.hdr: the whole environment (layout detected, or --layout) as the radiance SH\n"
     "  (PROBE may be an OpenEXR file, known by its magic number, wherever a .hdr is read: its data\n"
     "  window's R G B or Y, negative samples made 0)\n"
     "  of the asset's k maps (no irradiance convolution: the maps already hold the cosine and the\n"
     "  shadows). --probe-mode sh (default): the core's projection; lights: N median-cut lights\n"
     "  (-n N, a power of two, default 64) projected to SH; sunsky: of N median-cut regions (default\n"
     "  64) the sun (those whose mean radiance is at least 32 times the probe's; none on an overcast\n"
     "  sky) as directional lights, the rest of the probe as its SH (qibl_shlight_add_sun_sky).\n"
     "  --yaw DEG: turns the environment about +z (up): a light at azimuth phi (from +x toward +y)\n"
     "  comes from phi + DEG: positive yaw turns +x toward +y (counter-clockwise seen from above in\n"
     "  the right-handed xyz frame), and the probe's lat-long picture slides DEG/360 of its width to\n"
     "  the right (the picture is mirrored against xyz: seen from inside, +y is left of +x).\n"
     "  --rotate: the 3x3 rotation r row by row (orthonormal within 2^-16, det +1): light from d\n"
     "  comes from r d.\n"
     "  Either is applied once to the probe's SH (qibl_shlight_rotate), not by re-projecting.\n"
     "  --png: RGBA8888 with sRGB transfer (or --linear), exposure E (default 1), as an RGB PNG; a\n"
     "  frame whose mean is below 32 of 255 gets a note that it is almost black.\n"
     "  --hdr / --pfm: the same frame linear, before exposure and transfer (the core's Q16.16 output,\n"
     "  negative SH ringing clamped to 0), as Radiance RGBE (RLE) or little-endian PFM, for other\n"
     "  tools; --exr: the same floats as OpenEXR (scanline, ZIP, FLOAT, bit for bit). At least one of\n"
     "  --png/--hdr/--pfm/--exr.\n"
     "  --gles: relight with platform/gles2 on a headless EGL context instead (one --sun or --point,\n"
     "  --png only; the same asset and core weights; within 1 of 255 of the CPU path on Mesa llvmpipe).\n"
     "  --ies FILE.ies [--aim X Y Z] [--up X Y Z] [--ies-size N]: every --point becomes a goniometric\n"
     "  lamp with the IES LM-63 file's profile (see `qibl ies info`): its light toward each pixel's point\n"
     "  of the P map is scaled by I(direction) / I_peak (qibl/gonio.h: the profile resampled into an\n"
     "  N x N octahedral Q1.15 table, default 64, 2..256, bilinear), so --rgb (C0) is the lamp's peak\n"
     "  and an isotropic file gives exactly the isotropic lamp. --aim: the profile's axis (type C nadir,\n"
     "  types A/B the beam centre), default 0 0 -1 (a downlight in the z-up scene); --up: the direction\n"
     "  of horizontal angle 0 (types A/B: vertical angle 90), made orthogonal to the aim, default 1 0 0.\n"
     "  Soft framebuffer only (not --gles). With --path lamp (below) the same options make the track's\n"
     "  lamp goniometric (its light scaled before the track's visibility).\n"
     "  qibl relight FILE --path N|sun|lamp --t T [--rgb R G B] [--soft R] [--sky R G B]\n"
     "               [--ies FILE.ies [--aim X Y Z] [--up X Y Z] [--ies-size N]] (--png|--pfm|--exr OUT):\n"
     "  a light on the asset's baked path N (or its first sun path / lamp track) at T in 0..1: unshadowed\n"
     "  SH x visibility(T), soft over [T - R, T + R]; --sky adds the demo's sky through the shadowed maps.\n",
     qcli_cmd_relight},
    {"view", "a live viewer: drag the sun or a lamp, scrub a baked light path, step probes, yaw, exposure, k (X11)",
     "usage: qibl view FILE [--sun X Y Z] [--probe P.hdr]... [--lamp-rgb C0] [--exposure E] [--truth PNG|DIR]\n"
     "                 [--gles] [--bench [--frames N] [--headless] [--record OUT.png [--turn]]]\n"
     "  A window (X11) showing the asset relit by the core through platform/soft (--gles: platform/gles2\n"
     "  on a headless EGL context, read back), with an overlay under the frame: scheme, light, k,\n"
     "  exposure, ms per frame, fps and, with --truth, the PSNR against a `qibl render` PNG of the same\n"
     "  size, or (a directory) against the one of its sun_X_Y_Z.png frames (`qibl render --sun X Y Z`;\n"
     "  at most 64) whose sun is nearest the dragged one, named with the angle between them. Schemes (s cycles; those the asset or options cannot show are skipped): SUN (drag\n"
     "  with the left button: a window width turns the sun once around, its height sweeps 180 degrees of\n"
     "  elevation), SH / LIGHTS (each --probe's SH or its median-cut lights, as relight --probe and\n"
     "  --probe-mode lights; p next probe, y / Y yaw -/+15 degrees), SUN+SH, LAMP (a point lamp: the\n"
     "  drag picks the P map under the pointer and hangs the lamp 1/10 of the way toward the viewpoint;\n"
     "  C0 --lamp-rgb, default relight --point's), PATH (a baked light path: t / T step 1/32, a drag\n"
     "  scrubs, P next path; sRGB at exposure 1). Keys: + / - exposure x2 / /2, k fewer SH terms\n"
     "  (cycles), l linear / sRGB, q or Escape quits. Every settled change prints `view: sun X Y Z | ...`\n"
     "  (with `| lamp X Y Z rgb R G B` or `| path N tq T`) on stdout: relight with those values gives\n"
     "  the same frame. --bench: --frames N (default 600) frames with the sun dragged 4 pixels a frame\n"
     "  (--turn: one turn over the frames), then `RESULT view.fps F` (--headless: no window, the\n"
     "  framebuffer and overlay only); --record OUT.png: those frames, overlay included, as an APNG.\n"
     "  The window needs a build with X11 (Debian: apt-get install libx11-dev).\n",
     qcli_cmd_view},
    {"info", "validate a qibl asset file and print its contents",
     NULL, qcli_cmd_info},
    {"srgbe", "encode/decode one sRGBE colour (signed shared-exponent RGB in 4 bytes)",
     NULL, qcli_cmd_srgbe},
    {"lights", "sample a .hdr light probe (lat-long, angular, ball, cube cross) into directional lights",
     "usage: qibl lights PROBE.hdr [--method mediancut|adaptive|varmin] [-n N] [--csv | --json] [--png OUT.png]\n"
     "                   [--priority default|energy|energy-size|variance|levels] [--place centroid|centre]\n"
     "                   [--as rgbe|srgbe|f32] [--zoom Z] [--error]\n"
     "                   [--layout auto|latlong|angular|ball|vcross|hcross]\n"
     "                   [--preset gltf [--yaw DEG | --rotate a,b,c,d,e,f,g,h,i]]\n"
     "  --preset gltf: the lights as KHR_lights_punctual JSON: one directional light per light\n"
     "  (intensity = its largest channel, lux for a probe in cd/m^2; color = rgb / intensity) and one\n"
     "  node each whose rotation turns -z to where the light travels, in glTF's y-up frame as\n"
     "  sh project --preset gltf places the probe; --yaw/--rotate turn them as qibl relight does.\n"
     "  Turns a W x H lat-long probe (top row theta = 0 = +z, phi = 0 at the left edge, growing to the\n"
     "  right) into N directional lights with the integer core (qibl/lightprobe.h): median cut\n"
     "  (Debevec; N a power of two, default 64), adaptive median cut (any N) or variance minimisation\n"
     "  (Viriyothai & Debevec; any N). Each light is a unit direction (to its region's energy\n"
     "  centroid), an RGB irradiance (E(n) = sum rgb max(0, n.d) approximates the probe's) and its\n"
     "  region, brightest first.\n"
     "  --csv: one line per light, x,y,z,r,g,b,u0,v0,u1,v1 (region: u0 <= u < u1, v0 <= v < v1),\n"
     "  after a header line (what qibl relight --lights reads). --json: {\"lights\": [{\"dir\", \"rgb\",\n"
     "  \"region\"}...]} with the probe, size, method and count. Otherwise a table.\n"
     "  --png: the tone-mapped probe with the regions (green) and light directions (red), zoomed by Z\n"
     "  (default: to about 1024 pixels wide; the picture may have at most 65535 pixels a side and 2^25\n"
     "  in all). --error: the lights' irradiance against the probe's over 1024 normals.\n"
     "  --as: feed the core the probe as RGBE bytes (default), sRGBE or binary32.\n"
     "  --priority / --place: which region ADAPTIVE/VARMIN split next, centroid or geometric centre.\n"
     "  An all-black probe prints that it has no lights and exits 0.\n"
     "  --layout: the probe's layout; by default it is detected (2:1 latlong, 3:4 vcross, 4:3 hcross\n"
     "  with black empty cells) and printed; a square disc (angular map or mirror ball; a caption may\n"
     "  light up to 5 % of the corners) needs --layout;\n"
     "  other shapes are refused. Non-lat-long probes are resampled to lat-long (io/probe_layout.h).\n"
     "  --auto --error P%: the cheapest representation with mean irradiance error <= P % (the\n"
     "  measure of qibl probe info: |E - E_probe| / max(E_probe, mean E_probe / 10) per normal and\n"
     "  channel, floored so near-black normals cannot blow it up; probes box-averaged to <= 1024 wide)\n"
     "  P is a percentage in (0, 100], the sign optional: --error 2 is 2 %, not 200 %. An all-black\n"
     "  probe is refused: its error would be 0 / 0.\n"
     "  (tools/study): SH irradiance (4/9/16/25), N varmin lights (as sampled, or RGB refitted by NNLS)\n"
     "  or sun plus sky (k lights + SH9); counted in floats stored (6 per light, 3 per coefficient).\n",
     qcli_cmd_lights},
    {"probe", "describe a light probe and advise how to light with it: SH, N lights, or sun plus SH",
     "usage: qibl probe info PROBE.hdr [--layout auto|latlong|angular|ball|vcross|hcross]\n"
     "  Prints the probe's layout (detected, or --layout) and size, its luminance dynamic range\n"
     "  (max over the smallest non-zero pixel, in stops), the share of the energy in the brightest\n"
     "  0.1 % and 1 % of the sphere (pixels weighed by solid angle), and the irradiance error of four\n"
     "  ways to light with it against the probe's own irradiance (tools/study's one measure, as qibl\n"
     "  lights --auto prints it: |E - E_probe| / max(E_probe, mean E_probe / 10) per normal and\n"
     "  channel, mean and max over 4000 normals; probes wider than 1024 are box-averaged to 1024 x\n"
     "  512 for it, so the cost is one pass over the input plus a fixed amount): its SH (9\n"
     "  coefficients, the core's projection), 16 and 64 median-cut lights (the core's), and sun plus\n"
     "  SH (the sun as relight --probe-mode sunsky picks it, lit exactly; the rest as 9 SH\n"
     "  coefficients). Advice: the cheapest scheme (in that order) whose mean error is within 10 %\n"
     "  of the lowest or at most 1 %, with the relight option that uses it.\n",
     qcli_cmd_probe},
    {"ies", "an IES LM-63 photometric file: header facts, candela range, integrated lumens, polar curves",
     NULL, qcli_cmd_ies},
    {"study", "the light-probe approximation study: every method, error against N and time",
     NULL, qcli_cmd_study},
};
#define NCMD (sizeof commands / sizeof commands[0])

/* the flags `qibl` itself takes, in place of a command */
typedef struct global_opts {
    int help, version, isa_list;
} global_opts;
static const qcli_opt global_table[] = {
    {.name = "--help", .alias = "-h", .kind = QCLI_OPT_FLAG, .off = offsetof(global_opts, help),
     .help = "this list (qibl help CMD or qibl CMD --help: a command's options)"},
    {.name = "--version", .kind = QCLI_OPT_FLAG, .off = offsetof(global_opts, version),
     .help = "the version, the config id and the kernels this CPU runs"},
    {.name = "--isa-list", .kind = QCLI_OPT_FLAG, .off = offsetof(global_opts, isa_list),
     .help = "the kernel sets this CPU runs, one per line (QIBL_ISA takes one)"},
    {0},
};
/* name "": its refusals read "qibl: ...; see qibl --help" */
static const qcli_opt_cmd global_spec = {.name = "", .opts = global_table, .size = sizeof(global_opts)};

static void print_help(FILE *f)
{
    fprintf(f, "qibl - integer image-based lighting runtime: command-line tool\n\n"
               "usage: qibl <command> [args]\n       qibl help <command>\n       qibl --version\n       qibl --isa-list\n");
    qcli_opt_help_list(f, &global_spec);
    fprintf(f, "\ncommands:\n");
    for (size_t i = 0; i < NCMD; ++i)
        fprintf(f, "  %-8s %s\n", commands[i].name, commands[i].summary);
}

/* `qibl help CMD`: each option table's usage, options and prose, then the text not on a table */
static void print_cmd_help(FILE *f, const qcli_cmd *c)
{
    const qcli_opt_cmd *const *t = tables_of(c->name);
    for (size_t k = 0; t && t[k]; ++k) {
        if (k > 0)
            fputc('\n', f);
        qcli_opt_help(f, t[k]);
    }
    if (c->usage) {
        if (t)
            fputc('\n', f);
        fputs(c->usage, f);
    }
}

static const qcli_cmd *find(const char *name)
{
    for (size_t i = 0; i < NCMD; ++i)
        if (strcmp(commands[i].name, name) == 0)
            return &commands[i];
    return NULL;
}

int qcli_usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("qibl: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return 2;
}

int qcli_parse_q16(const char *s, int32_t *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
        return -1;
    double q = nearbyint(v * 65536.0);
    if (q > 2147483647.0 || q < -2147483648.0)
        return -1;
    *out = (int32_t)q;
    return 0;
}

int qcli_parse_int(const char *s, long lo, long hi, long *out)
{
    return qcli_opt_int_value(s, lo, hi, out);
}

int qcli_parse_num(const char *opt, const char *s, double lo, double hi, const char *why, double *out)
{
    switch (qcli_opt_num_value(s, lo, hi, out)) {
    case 0:
        return 0;
    case 1:
        return qcli_usage_error("%s: '%s' is not a number", opt, s);
    case 2:
        return qcli_usage_error("%s: '%s' is not a finite number", opt, s);
    default:
        return qcli_usage_error("%s: %s is outside %.10g..%.10g%s%s%s", opt, s, lo, hi, why ? " (" : "",
                                why ? why : "", why ? ")" : "");
    }
}

int qcli_lut_size_opt(int argc, char **argv, int *i, long lo, long *out)
{
    const char *a = argv[*i];
    int old = strcmp(a, "--lut") == 0;
    if ((!old && strcmp(a, "--lut-size") != 0) || *i + 1 >= argc)
        return 0;
    const char *v = argv[++*i];
    if (qcli_parse_int(v, lo, (long)QIBL_ASSET_MAX_LUT, out) != 0) {
        qcli_usage_error("--lut-size: '%s' is not a face size in %ld..%u%s", v, lo, QIBL_ASSET_MAX_LUT,
                             lo == 0 ? " (0: no LUT)" : "");
        return -1;
    }
    if (old)
        fprintf(stderr, "qibl: note: --lut N is deprecated here; say --lut-size %s (relight's --lut is the sampling "
                        "mode)\n", v);
    return 1;
}

int qcli_parse_size(const char *opt, const char *s, long max, long *w, long *h)
{
    long wh[2];
    if (qcli_opt_size_value(s, max, wh) != 0)
        return qcli_usage_error("%s needs WxH with both in 1..%ld, got '%s'", opt, max, s);
    *w = wh[0], *h = wh[1];
    return 0;
}

int qcli_parse_layout(const char *s, uint32_t *layout)
{
    if (strcmp(s, "planar") == 0)
        *layout = QIBL_SHMAPS_PLANAR;
    else if (strcmp(s, "interleaved") == 0)
        *layout = QIBL_SHMAPS_INTERLEAVED;
    else
        return -1;
    return 0;
}

int main(int argc, char **argv)
{
    /* line by line into a pipe or a log too: a farm or `make demo | tee` sees each step as it ends */
    setvbuf(stdout, NULL, _IOLBF, 0);
    /* qibl's own flags come alone, in place of a command: the table reads argv[1] only */
    global_opts g = {.help = 0};
    if (argc >= 2 && argv[1][0] == '-' && argv[1][1] != '\0' && qcli_opt_parse(&global_spec, 2, argv, 1, &g) != 0)
        return 2;
    if (argc < 2 || g.help) {
        print_help(stdout);
        return argc < 2 ? 2 : 0;
    }
    /* the kernel sets this CPU runs, one per line, lowest first (make golden and make test loop over them) */
    if (g.isa_list) {
        for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i)
            if (qibl_isa_available() & QIBL_ISA_BIT(i))
                printf("%s\n", qibl_isa_name((qibl_isa_t)i));
        return 0;
    }
    /* QIBL_ISA names a kernel set this CPU runs, or nothing runs (io/isa_env.h) */
    char isa_err[160];
    if (qtool_isa_env_check(isa_err, sizeof isa_err) != 0) {
        fprintf(stderr, "qibl: %s\n", isa_err);
        return 2;
    }
    if (g.version) {
        char isa[160];
        qtool_isa_describe(isa, sizeof isa);
        printf("qibl %s (config id %08lx)\nkernels: %s\n", qibl_version(), (unsigned long)qibl_config_id(), isa);
        return qibl_init_check() == QIBL_OK ? 0 : 1;
    }
    if (strcmp(argv[1], "help") == 0) {
        if (argc == 2) {
            print_help(stdout);
            return 0;
        }
        /* --flags CMD: the tables and their flags, as qcli_opt_flags prints them (tests/cli_opts_test.c) */
        int flags = strcmp(argv[2], "--flags") == 0;
        if (flags && argc < 4)
            return qcli_usage_error("help --flags needs a command (see qibl --help)");
        const qcli_cmd *c = find(argv[2 + flags]);
        if (!c)
            return qcli_usage_error("no such command '%s' (see qibl --help)", argv[2 + flags]);
        const qcli_opt_cmd *const *t = tables_of(c->name);
        for (size_t k = 0; flags && t && t[k]; ++k)
            qcli_opt_flags(stdout, t[k]);
        if (!flags)
            print_cmd_help(stdout, c);
        return 0;
    }
    const qcli_cmd *c = find(argv[1]);
    if (!c)
        return qcli_usage_error("no such command '%s' (see qibl --help)", argv[1]);
    for (int i = 2; i < argc; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            print_cmd_help(stdout, c);
            return 0;
        }
    return c->run(argc - 1, argv + 1);
}
