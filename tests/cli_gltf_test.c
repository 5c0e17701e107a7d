/*
 * cli_gltf_test.c - glTF scenes and OBJ materials through the qibl program: `render --scene` on the
 * Khronos Box (fixtures/gltf, a red base colour) draws red where it hits the box and the grey ground
 * elsewhere; a textured OBJ (mtllib, usemtl, map_Kd, vt) shows its texture; `bake --scene` takes a
 * .gltf; a broken glTF is refused with its named one-line error and no output.
 */
#include "cliutil.h"
#include "io/png.h"

CLI_FIXTURES("/tmp/qibl_cli_gltf_XXXXXX")

/* counts pixels that are clearly red (R > 3 G and R > 3 B, R > 20) */
static int red_pixels(const char *png)
{
    int w, h, frames;
    uint8_t *rgb;
    char err[256];
    if (qtool_png_read_rgb8(png, &w, &h, &frames, &rgb, err, sizeof err) != 0)
        fail_msg("%s", err);
    int n = 0;
    for (int i = 0; i < w * h; ++i)
        n += rgb[3 * i] > 20 && rgb[3 * i] > 3 * rgb[3 * i + 1] && rgb[3 * i] > 3 * rgb[3 * i + 2];
    free(rgb);
    return n;
}

static void test_render_gltf_box(void **state)
{
    (void)state;
    need_qibl();
    const char *box = "fixtures/gltf/Box.gltf"; /* suites run from the source root */
    if (access(box, R_OK) != 0) {
        print_message("skip: %s absent (not run from the source root)\n", box);
        skip();
    }
    assert_int_equal(run("render", "--sun", "1", "0.5", "1", "--scene", box, "--size", "128x32", "--threads", "1",
                         "--png", at("box.png"), NULL),
                     0);
    int red = red_pixels(at("box.png"));
    assert_true(red > 20); /* the box covers a few hundred pixels of the 4096; the ground is grey */
    assert_int_equal(run("bake", "--scene", box, "--size", "32x8", "--k", "4", "--dirs", "32", "--quiet", "--threads",
                         "1", "-o", at("box.qibl"), NULL),
                     0);
    /* a broken file: named, nothing written */
    FILE *f = fopen(at("bad.gltf"), "w");
    assert_non_null(f);
    fputs("{\"asset\":{\"version\":\"2.0\"},\"nodes\":[{\"mesh\":0}]}", f);
    fclose(f);
    assert_int_equal(run("render", "--sun", "1", "0.5", "1", "--scene", at("bad.gltf"), "--size", "32x8", "--png",
                         at("bad.png"), NULL),
                     1);
    char *e = text(errlog);
    if (!strstr(e, "bad.gltf: nodes[0].mesh: 0 refers to an empty or missing array"))
        fail_msg("stderr: %s", e);
    free(e);
    assert_int_equal(access(at("bad.png"), F_OK), -1);
}

/* an OBJ quad facing the viewer with a red texture through mtllib / usemtl / map_Kd / vt; the same
 * quad without its usemtl line is the default grey */
static void test_render_obj_texture(void **state)
{
    (void)state;
    need_qibl();
    uint8_t px[12] = {230, 10, 10, 230, 10, 10, 230, 10, 10, 230, 10, 10};
    char err[256];
    assert_int_equal(qtool_png_write_rgb8(at("red.png"), 2, 2, px, err, sizeof err), 0);
    FILE *f = fopen(at("q.mtl"), "w");
    assert_non_null(f);
    fputs("newmtl paint\nKd 1 1 1\nmap_Kd red.png\n", f);
    fclose(f);
    const char *quad = "mtllib q.mtl\nv -1 0 0\nv 1 0 0\nv 1 2 0\nv -1 2 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                       "%sf 1/1 2/2 3/3 4/4\n";
    char text_[512];
    for (int k = 0; k < 2; ++k) {
        snprintf(text_, sizeof text_, quad, k ? "" : "usemtl paint\n");
        f = fopen(at(k ? "plain.obj" : "q.obj"), "w");
        assert_non_null(f);
        fputs(text_, f);
        fclose(f);
        assert_int_equal(run("render", "--sun", "1", "0.5", "1", "--scene", at(k ? "plain.obj" : "q.obj"), "--size",
                             "128x32", "--threads", "1", "--png", at(k ? "plain.png" : "q.png"), NULL),
                         0);
    }
    assert_true(red_pixels(at("q.png")) > 20);
    assert_int_equal(red_pixels(at("plain.png")), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_render_gltf_box, setup, teardown),
        cmocka_unit_test_setup_teardown(test_render_obj_texture, setup, teardown),
    };
    return cmocka_run_group_tests_name("cli_gltf", tests, NULL, NULL);
}
