/*
 * qibl/gles2.h - the OpenGL ES 2.0 backend: the core's relighting (qibl/shmap.h) done per pixel on a
 * GPU, from the same asset bytes and the same per-frame weights the core computes.
 *
 * What it does: uploads the 8-bit SH maps (four planes per RGBA8 texture), the P map (split bytes,
 * below) and the cube-map Y LUT (split bytes) as textures; per frame draws one full-panorama quad
 * per pass with a generated GLSL ES 1.00 fragment shader doing the expand and multiply-add with the
 * core's weights as uniforms (directional lights, several lights, environments: anything that is a
 * qibl_shmap_weights_t), or the point-light sum (L from the P map, Y_i by the SH polynomials or from
 * the LUT, the core's attenuation) with a prepared qibl_shmap_point_t. When the maps need more
 * texture units or uniform vectors than one pass has, passes accumulate in RGBA8 textures holding
 * sRGBE (Granier et al.: no float render targets in GLES2), ping-ponging two targets; the last pass
 * adds exposure and the sRGB transfer and writes RGBA into the framebuffer bound at the call.
 *
 * Passes. A pass binds as many map textures as fit GL_MAX_TEXTURE_IMAGE_UNITS (or desc.max_units)
 * after its other inputs: 3 P-map textures and the LUT cube maps its maps need (point lights), 2
 * accumulator textures (every pass but the first). Uniform vec4s: 4 + 1 per map texture
 * (directional, 3 for grey maps) or 9 + 2 per map texture (points), against
 * GL_MAX_FRAGMENT_UNIFORM_VECTORS. Each non-final pass draws twice, because GLES2 has a single
 * colour attachment: once storing the sRGBE code of the running sum, once the code of what that
 * code leaves out (sum - decode(code)). One code alone keeps a pixel to 1/510 of its largest
 * channel, which the sRGB curve turns into up to 12 levels in a dark channel beside a bright one;
 * the pair keeps it to about 2^-18. Each pass adds the range-packing bias of its own maps, so
 * partial sums stay the size of the decoded terms instead of cancelling only at the end.
 * Optional: with desc.float_accum and OES_texture_float (plus a float colour attachment, which
 * GLES2 alone does not promise: the backend checks framebuffer completeness and falls back), passes
 * accumulate in one RGBA float texture instead: one draw and one unit per pass. Measured against
 * the 8-bit path in tests/gles2_test.c (Mesa: same max, mean 0.0117 against 0.0127 levels).
 *
 * What it does not do: create or make current an EGL/GLES context, windows or swap chains (the
 * caller owns the context and must make it current around every call), compute anything per frame
 * that the core computes (weights, point-light preparation), or allocate on the heap (the state is
 * this caller-owned struct; GL objects are the driver's). No extension is required.
 *
 * Orientation: row y of the maps lands on framebuffer row y (GL's rows count from the bottom), so
 * glReadPixels returns the panorama top row first, as the core's rows and platform/soft's are.
 * GL state a draw call changes and leaves: the viewport (0, 0, width, height), the program, the
 * active texture unit and the 2D/cube bindings of the units it uses, GL_ARRAY_BUFFER, vertex attrib
 * array 0, and it disables GL_BLEND, GL_DEPTH_TEST, GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_CULL_FACE
 * and GL_DITHER. The caller's framebuffer binding is restored before the last pass.
 *
 * Precision. Every shader asks for highp floats and samplers (GLSL ES 1.00 samplers default to
 * lowp, and the texel then carries lowp into the arithmetic: Mesa computes that in fp16), and every
 * byte is rebuilt exactly (floor(t * 255 + 0.5)) before use. The P map needs highp (positions are
 * 24-bit integers times a power of two), so do the LUT's split bytes and the sums. A GPU without
 * highp in fragment shaders (GL_FRAGMENT_PRECISION_HIGH undefined, fp16 mediump only): point lights
 * are refused with QIBL_E_GLES2_NO_HIGHP; directional relighting still runs at mediump, whose
 * 11-bit significand costs about 2^-11 of the largest term (several 8-bit levels on bright pixels),
 * and the sRGBE accumulator's exponents above 2^15 overflow.
 * Measured against platform/soft on the golden relight scenes (tests/gles2_test.c, llvmpipe): at
 * most 1 level (RGBA8888 sRGB) in every case, one pass or up to 17, mean <= 0.013; nearest LUT
 * texels may differ at texel edges (one pixel of the fixture).
 *
 * P map encoding: split bytes, not sRGBE. Each coordinate becomes (v - min) >> s in 24 bits (s the
 * smallest shift that fits the coordinate's range; 0 for scenes up to 256 units across), stored as
 * three bytes of an RGB texture; the shader rebuilds it exactly in highp. Error: 2^(s-1) Q16.16
 * LSB (none for s = 0). sRGBE would cost up to 1/255 of the largest coordinate of the point
 * (a visible shift of near-light pixels); three textures instead of one is its price.
 * LUT encoding: each Q2.14 value as 16 bits (value + 32768) in two channels, two maps per RGBA
 * cube map texture; bilinear filtering is linear, so filtering the bytes then combining them is
 * filtering the value (to the GPU's filter precision).
 *
 * Errors: every GL error, shader compile or link failure and incomplete framebuffer becomes a named
 * status (below) with the driver's message in qibl_gles2_log(); a failing call deletes what it
 * created. qibl_gles2_destroy releases every GL object (needs the context current).
 */
#ifndef QIBL_GLES2_H
#define QIBL_GLES2_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/fixed.h"
#include "qibl/gonio.h"
#include "qibl/shmap.h"
#include "qibl/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* This backend's statuses (range QIBL_STATUS_GLES2_BASE of status.h). */
#define QIBL_E_GLES2_GL_ERROR  QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 1) /* glGetError reported an error (log names the call) */
#define QIBL_E_GLES2_COMPILE   QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 2) /* a shader did not compile (log: driver's info log) */
#define QIBL_E_GLES2_LINK      QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 3) /* a program did not link (log: driver's info log) */
#define QIBL_E_GLES2_FRAMEBUFFER QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 4) /* accumulation framebuffer incomplete */
#define QIBL_E_GLES2_UNITS     QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 5) /* too few texture units or uniform vectors for one texture per pass */
#define QIBL_E_GLES2_SIZE      QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 6) /* maps or LUT larger than GL_MAX_TEXTURE_SIZE / cube size */
#define QIBL_E_GLES2_NO_HIGHP  QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 7) /* point lights need highp fragment floats */
#define QIBL_E_GLES2_STATE     QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 8) /* not initialised, nothing uploaded, or no P map for a point light */
#define QIBL_E_GLES2_MISMATCH  QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 9) /* weights or point light made for other maps than uploaded */
#define QIBL_E_GLES2_CONTEXT   QIBL_CAST(qibl_status_t, QIBL_STATUS_GLES2_BASE + 10) /* no current context (glGetString failed) */

/* QIBL_GLES2_STATUS_LIST(X): the statuses above in value order (base + 1, + 2, ...) as X(name,
 * message); qibl_gles2_status_str's messages come from it alone. Append only: values are ABI. */
#define QIBL_GLES2_STATUS_LIST(X) \
    X(QIBL_E_GLES2_GL_ERROR, "gles2: GL error (see the log)") \
    X(QIBL_E_GLES2_COMPILE, "gles2: shader compile failed (see the log)") \
    X(QIBL_E_GLES2_LINK, "gles2: program link failed (see the log)") \
    X(QIBL_E_GLES2_FRAMEBUFFER, "gles2: accumulation framebuffer incomplete") \
    X(QIBL_E_GLES2_UNITS, "gles2: too few texture units or uniform vectors") \
    X(QIBL_E_GLES2_SIZE, "gles2: maps or LUT larger than the GL's texture size") \
    X(QIBL_E_GLES2_NO_HIGHP, "gles2: point lights need highp fragment floats") \
    X(QIBL_E_GLES2_STATE, "gles2: not initialised, nothing uploaded, or no P map/LUT") \
    X(QIBL_E_GLES2_MISMATCH, "gles2: weights or light made for other maps") \
    X(QIBL_E_GLES2_CONTEXT, "gles2: no current GL ES context")

/* qibl_status_str for this backend's statuses too; never NULL. */
const char *qibl_gles2_status_str(qibl_status_t s);

#define QIBL_GLES2_MAX_TEX 19u     /* map textures: ceil(25 * 3 / 4) */
#define QIBL_GLES2_MAX_LUT_TEX 13u /* LUT cube maps: ceil(25 / 2) */
#define QIBL_GLES2_MAX_PASSES 19u  /* at least one map texture per pass */
#define QIBL_GLES2_LOG_SIZE 2048u

/* Options; zero-initialised fields mean the defaults noted. */
typedef struct qibl_gles2_desc {
    uint32_t max_units;           /* texture units a pass may use; 0 = GL_MAX_TEXTURE_IMAGE_UNITS.
                                   * A lower cap forces more passes (tests use it). */
    uint32_t max_uniform_vectors; /* fragment uniform vec4s; 0 = GL_MAX_FRAGMENT_UNIFORM_VECTORS */
    uint32_t float_accum;         /* nonzero: accumulate passes in an RGBA float texture when
                                   * OES_texture_float is present and such a texture is a complete
                                   * colour attachment (else the default RGBA8 sRGBE path) */
} qibl_gles2_desc_t;

/* How the last pass writes the framebuffer, as platform/soft's RGBA8888 with the same fields. */
typedef struct qibl_gles2_out {
    qibl_uq16_t exposure; /* multiplier, UQ16.16; 0 = 1.0 */
    uint8_t srgb;         /* nonzero = sRGB transfer (IEC 61966-2-1), else linear */
} qibl_gles2_out_t;

/* Draw modes: the _GONIO ones are the point modes with a goniometric lamp's table (one more unit). */
enum {
    QIBL_GLES2_MODE_DIR = 0,
    QIBL_GLES2_MODE_POINT_SH,
    QIBL_GLES2_MODE_POINT_LUT,
    QIBL_GLES2_MODE_POINT_SH_GONIO,
    QIBL_GLES2_MODE_POINT_LUT_GONIO,
    QIBL_GLES2_MODE_COUNT
};

/* Backend state: caller-owned, opaque in practice (fields may change). */
typedef struct qibl_gles2 {
    uint32_t ready, loaded;
    uint32_t units, uvecs, max_tex_size, max_cube_size, highp;
    uint32_t want_float, float_acc; /* asked for / in use: float accumulator (one texture, one draw) */
    uint32_t width, height, k, channels, planes, ntex;
    uint32_t has_pmap, has_lut, lut_n, lut_k;
    float scale[75], bias[75]; /* per plane, decoded Q8.24 */
    float poff[3], pscale[3];  /* P map decode: v = poff + u * pscale, scene units */
    uint32_t map_tex[QIBL_GLES2_MAX_TEX], p_tex[3], lut_tex[QIBL_GLES2_MAX_LUT_TEX];
    uint32_t acc_tex[4], fbo[2], vbo, vs; /* accumulators: high and low sRGBE codes, ping and pong */
    uint32_t npass[QIBL_GLES2_MODE_COUNT];
    uint8_t pass_first[QIBL_GLES2_MODE_COUNT][QIBL_GLES2_MAX_PASSES + 1]; /* map textures of each pass */
    uint32_t prog[QIBL_GLES2_MODE_COUNT][QIBL_GLES2_MAX_PASSES];
    uint32_t gonio_tex, gonio_n; /* the goniometric table (LUMINANCE_ALPHA: low, high byte), its side */
    uint32_t last_passes;
    char log[QIBL_GLES2_LOG_SIZE];
} qibl_gles2_t;

/* Queries the current context's limits and creates the shared objects (vertex shader, quad).
 * d may be NULL (defaults).
 * Formats: none (GL limits and object names). Bound: exact.
 * Errors, in this order: QIBL_E_NULL_POINTER (g NULL), QIBL_E_GLES2_CONTEXT (no current context),
 * QIBL_E_GLES2_UNITS (fewer than 2 units or 8 uniform vectors, after desc's caps),
 * QIBL_E_GLES2_COMPILE (the vertex shader; QIBL_E_GLES2_GL_ERROR if glCreateShader raised one),
 * QIBL_E_GLES2_GL_ERROR (creating the quad).
 * On failure: *g is zeroed first, so it holds zeros (or the limits queried before the failure)
 * and the message in qibl_gles2_log(); no GL object it created is left. */
QIBL_NODISCARD qibl_status_t qibl_gles2_init(qibl_gles2_t *g, const qibl_gles2_desc_t *d);

/* Uploads maps (planar layout, as qibl_asset_shmaps gives), and optionally the P map and the LUT
 * (NULL: none), replacing an earlier upload.
 * Formats: map bytes u8 with Q8.24 params (kept as floats for the shaders); P map Q16.16 as split
 * bytes (top of this file); LUT Q2.14 as two bytes.
 * Bound: maps and LUT exact; the P map within 2^(s-1) Q16.16 LSB (exact for s = 0, see above).
 * Errors, in this order: QIBL_E_NULL_POINTER (g or m NULL), QIBL_E_GLES2_STATE (not initialised),
 * those of qibl_shmap_check, QIBL_E_NULL_POINTER (p->points or lut->values NULL),
 * QIBL_E_SHMAP_MISMATCH (P map size, LUT k below the maps' or above QIBL_SH_MAX_COUNT, LUT face size
 * outside 1..QIBL_ASSET_MAX_LUT), QIBL_E_SHMAP_LUT_SHORT (lut->size below its 12 N N k bytes),
 * QIBL_E_GLES2_SIZE (maps or LUT beyond the GL's texture sizes), QIBL_E_GLES2_GL_ERROR.
 * On failure: the checks before QIBL_E_GLES2_GL_ERROR change nothing (an earlier upload stays
 * usable; QIBL_E_GLES2_SIZE writes the log); after a GL error nothing stays uploaded. */
QIBL_NODISCARD qibl_status_t qibl_gles2_upload(qibl_gles2_t *g, const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_ylut_t *lut);

/* Draws the maps relit with weights w (qibl_shmap_weights for the uploaded maps) into the bound
 * framebuffer. out may be NULL (exposure 1, linear).
 * Formats: w as qibl_shmap_weights makes it; out RGBA8 as platform/soft's RGBA8888 (exposure
 * UQ16.16, linear or sRGB); accumulators sRGBE pairs (or float).
 * Bound: the GPU's float arithmetic (Precision, above): no LSB bound is promised;
 * tests/gles2_test.c holds it to 2 levels of RGBA8 per channel against platform/soft.
 * Errors, in this order: QIBL_E_NULL_POINTER (g or w NULL), QIBL_E_GLES2_STATE (not initialised or
 * nothing uploaded), QIBL_E_GLES2_MISMATCH (k or channels differ), QIBL_E_GLES2_UNITS (no pass
 * plan fits), QIBL_E_GLES2_COMPILE, QIBL_E_GLES2_LINK, QIBL_E_GLES2_FRAMEBUFFER,
 * QIBL_E_GLES2_GL_ERROR.
 * On failure: the checks up to QIBL_E_GLES2_MISMATCH change nothing; a later failure leaves the GL
 * state listed at the top changed, the caller's framebuffer binding restored, and that framebuffer
 * possibly part-drawn (a GL error in the last pass). */
QIBL_NODISCARD qibl_status_t qibl_gles2_relight(qibl_gles2_t *g, const qibl_shmap_weights_t *w, const qibl_gles2_out_t *out);

/* Draws the maps relit by a prepared point light (qibl_shmap_point_prepare on the uploaded maps,
 * P map and, when pt->lut is not NULL, LUT; the uploaded LUT is used, with pt's filter).
 * Formats: pt as qibl_shmap_point_prepare makes it (Q16.16 position and colour); out as
 * qibl_gles2_relight.
 * Bound: the GPU's highp float arithmetic: no LSB bound is promised; tests/gles2_test.c holds
 * it to 2 levels of RGBA8 per channel against platform/soft (nearest LUT texels may flip at texel
 * edges).
 * Errors, in this order: QIBL_E_NULL_POINTER (g or pt NULL), QIBL_E_GLES2_STATE (not initialised or
 * nothing uploaded), QIBL_E_GLES2_MISMATCH (pt->maps NULL, or k or channels differ),
 * QIBL_E_GLES2_STATE (no P map, or a LUT asked for and none uploaded), QIBL_E_GLES2_NO_HIGHP, then
 * those of the draw as in qibl_gles2_relight (UNITS, COMPILE, LINK, FRAMEBUFFER, GL_ERROR).
 * On failure: as qibl_gles2_relight (the two later checks write the log only). */
QIBL_NODISCARD qibl_status_t qibl_gles2_point(qibl_gles2_t *g, const qibl_shmap_point_t *pt, const qibl_gles2_out_t *out);

/* qibl_gles2_point with a goniometric lamp: each pixel's light from the lamp scaled by the table
 * of gonio (qibl/gonio.h) toward the pixel's P-map point, as qibl_gonio_scale_span does after
 * qibl_shmap_point_span on the soft path. The table (gonio->n squared Q1.15 entries) is uploaded
 * as a 16-bit LUMINANCE_ALPHA texture at every call (at most 128 KiB; the caller may change it
 * between frames); the shader takes the lamp-frame direction, its octahedral texel position and
 * the bilinear mix of the four nearest texels from exact byte fetches (no GPU filtering), rounds
 * the scale to Q1.15 as the core does, and multiplies the lamp's term by it. One more texture
 * unit and 4 uniform vectors per pass than qibl_gles2_point: with a LUT, a pass over a map texture
 * whose planes span two LUT cube maps needs 9 units, one more than GLES2 promises (an 8-unit GPU
 * then refuses with QIBL_E_GLES2_UNITS; the direct SH mode fits in 8).
 * Formats: pt as qibl_gles2_point; gonio's table Q1.15 unsigned, frame Q2.30 (sent as floats).
 * Bound: the GPU's highp arithmetic; tests/gles2_test.c holds it to qibl_gles2_point's 2 levels
 * (mean 0.5) against platform/soft with qibl_gonio_scale_span.
 * Errors, in this order: QIBL_E_NULL_POINTER (g, pt, gonio or gonio->table NULL), then those of
 * qibl_gles2_point up to QIBL_E_GLES2_NO_HIGHP, QIBL_E_GONIO_SIZE (gonio->n outside
 * QIBL_GONIO_MIN_N .. QIBL_GONIO_MAX_N, or above GL_MAX_TEXTURE_SIZE), then the draw's.
 * On failure: as qibl_gles2_point. */
QIBL_NODISCARD qibl_status_t qibl_gles2_point_gonio(qibl_gles2_t *g, const qibl_shmap_point_t *pt,
                                                    const qibl_gonio_t *gonio, const qibl_gles2_out_t *out);

/* Passes the last successful draw used (1: no accumulation). */
uint32_t qibl_gles2_passes(const qibl_gles2_t *g);

/* The driver's message for the last failure ("" if none). Never NULL for a non-NULL g. */
const char *qibl_gles2_log(const qibl_gles2_t *g);

/* Self-check of the GLSL sRGBE codec for ports: for each of n codes (4 bytes each) draws
 * encode(decode(code) * mul) with the shaders the accumulation uses and reads the codes back into
 * out (4 n bytes). n <= GL_MAX_TEXTURE_SIZE. Needs qibl_gles2_init only (no upload).
 * Formats: codes and out sRGBE bytes; mul a float multiplier.
 * Bound: the GPU's; tests/gles2_test.c holds each channel within 1 code of the C codec
 * (qibl_srgbe_*_f32) and the exponent byte equal.
 * Errors, in this order: QIBL_E_NULL_POINTER (g, codes or out NULL), QIBL_E_GLES2_STATE (not
 * initialised), QIBL_E_GLES2_SIZE (n == 0 or above GL_MAX_TEXTURE_SIZE), QIBL_E_GLES2_COMPILE,
 * QIBL_E_GLES2_LINK, QIBL_E_GLES2_FRAMEBUFFER, QIBL_E_GLES2_GL_ERROR.
 * On failure: out unwritten, except after a GL error reported once the pass was read back (out
 * then holds what glReadPixels gave); the objects it made are deleted, the caller's framebuffer
 * binding restored. */
QIBL_NODISCARD qibl_status_t qibl_gles2_srgbe_check(qibl_gles2_t *g, const uint8_t *codes, uint32_t n, float mul, uint8_t *out);

/* The backend's sRGBE codec in GLSL ES 1.00, for a caller's own shaders that read or write the same
 * RGBA8 codes (tools/luminaire's spotlights and passes): vec3 srgbe_dec(vec4) and vec4
 * srgbe_enc(vec3), placed after the precision statement; qibl_gles2_srgbe_check tests these very
 * functions. */
extern const char qibl_gles2_glsl_srgbe[];

/* qibl_gonio_lookup in GLSL ES 1.00, the backend's own (qibl_gles2_point_gonio), for a caller's
 * shaders: float gonio(vec3 dw), the scale toward lamp-frame direction dw. Before it the caller
 * declares uniform vec3 u_gx, u_gy, u_gz (the lamp's frame), uniform float u_gn (the table's side)
 * and float gonio_tex(vec2 ij), the table's 16-bit entry at texel (i, j) (where the table lives is
 * the caller's: tools/luminaire reads it from an atlas). */
extern const char qibl_gles2_glsl_gonio[];

/* Deletes every GL object of g and zeroes it; safe on a zeroed or failed g. */
void qibl_gles2_destroy(qibl_gles2_t *g);

#ifdef __cplusplus
}
#endif

#endif /* QIBL_GLES2_H */
