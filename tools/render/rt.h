/*
 * render/rt.h - the reference renderer behind `qibl render` and `qibl bake`: a small CPU ray tracer
 * (triangles, a median-split BVH, double precision) that renders panoramas seen from the viewpoint
 * E = origin, lit by one directional or point light with hard shadows.
 *
 * Shading (the transfer function the bake projects onto SH; w the unit direction to the light):
 *   T(w) = V(w) [ albedo / pi max(0, n.w) + ks (s + 2) / (2 pi) max(0, r.w)^s ]   if ng.w > 0, else 0
 * n the interpolated normal and ng the geometric normal, both turned towards the viewer, r the
 * view ray mirrored about n, V the hard-shadow visibility. A directional light of colour E gives
 * E T(w) (same convention as qibl_shlight_add_dir); a point light at S with colour C0 gives
 * C0 T(w) / |S - P| (Wong's C0/|L|; falloff 2 divides by |S - P|^2), V tested up to the light.
 * Sky pixels (no hit) are 0 and their P-map point is 1000 units along the ray.
 *
 * Panoramas: cylindrical (Wong: column x at azimuth phi = 2 pi (x + 0.5) / W, row y at height
 * h = (1/2 - (y + 0.5) / H) 2 pi H / W on the unit cylinder, square pixels) or equirectangular
 * (theta = pi (y + 0.5) / H from +z); z is up. The same mapping as tools/gen/scene.c.
 * Deterministic: every pixel is computed independently, in double, whatever the thread count.
 */
#ifndef QTOOL_RENDER_RT_H
#define QTOOL_RENDER_RT_H

#include <stddef.h>
#include <stdint.h>

#include "gen/scene.h" /* qtool_pano_kind */
#include "io/obj.h"

#define QTOOL_RT_MAX_MATS 16

/* A fixed perspective camera (a pre-rendered background seen from one corner) instead of the
 * panorama from the origin: pixel (x, y) of a w x h frame looks from eye along the unit vector of
 *   fwd + (2 (x + 0.5) / w - 1) tan(fov / 2) (w / h) right + (1 - 2 (y + 0.5) / h) tan(fov / 2) up
 * (fov the vertical field of view, square pixels; right = fwd x up, up made orthogonal to fwd). */
typedef struct qtool_rt_camera {
    double eye[3], fwd[3], right[3], up[3]; /* fwd, right, up: orthonormal */
    double tan_half;                        /* tan(fov / 2) */
} qtool_rt_camera;

#define QTOOL_RT_CAMERA_FOV_DEFAULT 60.0 /* degrees, vertical */
#define QTOOL_RT_CAMERA_MAX_COORD 1.0e6  /* |eye|, |target|, |up| components */

/* The camera at eye looking at target, up its approximate up, fov degrees. 0, or -1 with a named
 * reason in err and c untouched: a coordinate not finite or beyond QTOOL_RT_CAMERA_MAX_COORD, eye
 * == target, an up that is zero or parallel to the view, a fov outside (0, 180). */
int qtool_rt_camera_init(qtool_rt_camera *c, const double eye[3], const double target[3], const double up[3],
                         double fov_deg, char *err, size_t errlen);

typedef struct qtool_rt_material {
    double albedo[3], ks, shininess;
} qtool_rt_material;

typedef struct qtool_rt_node {
    double lo[3], hi[3];
    uint32_t first, count; /* leaf: triangles [first, first + count); inner: count 0, children first, first + 1 */
} qtool_rt_node;

typedef struct qtool_rt_scene {
    size_t ntri;
    double *v;    /* 9 per triangle */
    double *n;    /* 9 per triangle: corner normals */
    uint8_t *mat; /* per triangle */
    qtool_rt_material mats[QTOOL_RT_MAX_MATS];
    int nmat;
    qtool_rt_node *nodes;
    size_t nnodes;
    double scale; /* scene size, for ray offsets */
    /* Optional per-triangle colour (NULL: every triangle takes mats[mat].albedo): alb 3 linear
     * values per triangle replace the material's albedo; tex (-1: none) and uv (6 per triangle)
     * point into texs, whose texel at the hit's interpolated uv (bilinear, repeating, sRGB decoded)
     * multiplies it. ks and shininess stay the material's. */
    double *alb;
    double *uv;
    int32_t *tex;
    qtool_mesh_texture *texs;
    size_t ntex;
    /* has_cam: the frames are cam's perspective (qtool_rt_pixel_ray, qtool_rt_primary), not
     * panoramas from the origin; 0 after the scene builders, set by the caller. */
    int has_cam;
    qtool_rt_camera cam;
} qtool_rt_scene;

/* The built-in courtyard (no files): ground, walls, two arcades of pillars and round arches, boxes
 * and spheres, z up, viewpoint at the origin 1.6 above the ground. 0 or -1 (no memory). */
int qtool_rt_scene_builtin(qtool_rt_scene *s);
/* Where a mesh prop stands: on the -x axis, the centre column of every panorama (phi = pi). +x is
 * phi = 0, the left/right edge, where a prop would be cut in half across the seam. */
#define QTOOL_RT_PROP_X (-3.5)

/* A mesh as a prop (its albedo, uv and textures, when it has them, carried per triangle; the ground
 * keeps its material): turned from Y-up to Z-up unless zup, then a quarter turn about z so the
 * model's front (+z of a Y-up model, -y of a Z-up one) faces the viewer; scaled so its largest side
 * is 2.5 units, standing on the ground (z = -1.6, a 40 x 40 ground plane is added) centred 3.5 units
 * along -x from the viewpoint (QTOOL_RT_PROP_X: the middle of the panorama, away from the seam at
 * +x); raw: the mesh exactly as given and nothing added. 0 or -1 (no memory). */
int qtool_rt_scene_from_obj(qtool_rt_scene *s, const qtool_obj_mesh *m, int zup, int raw);
/* Where qtool_rt_scene_from_obj(s, m, zup, raw) puts the mesh-space point p (direction 0) or
 * turns the direction p (direction 1: rotated only), e.g. a glTF camera's eye, forward and up
 * (io/gltf.h) for a fixed-camera render of the same scene. Bit for bit the prop's own arithmetic. */
void qtool_rt_prop_place(const qtool_obj_mesh *m, int zup, int raw, const double p[3], int direction, double out[3]);
void qtool_rt_scene_free(qtool_rt_scene *s);

/* What the viewing ray of a pixel sees (the light-independent part of shading). */
typedef struct qtool_rt_hit {
    int hit;          /* 0: sky */
    double p[3];      /* hit point (P map) */
    double n[3], ng[3], r[3];
    double t;         /* depth along the unit ray */
    const qtool_rt_material *m;
    double albedo[3]; /* m->albedo, or the triangle's own colour times its texel (see qtool_rt_scene) */
} qtool_rt_hit;

void qtool_rt_pixel_dir(uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t x, uint32_t y, double d[3]);
/* The viewing ray of a pixel of s's frames: its camera's when it has one, else the panorama's. */
void qtool_rt_pixel_ray(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, uint32_t x, uint32_t y,
                        double d[3]);
/* What the ray from the viewpoint (the camera's eye, else the origin) along unit d sees. */
void qtool_rt_primary(const qtool_rt_scene *s, const double d[3], qtool_rt_hit *h);
/* The P-map point of a sky pixel: dist along the ray from the viewpoint. */
void qtool_rt_sky_point(const qtool_rt_scene *s, const double d[3], double dist, double out[3]);
/* 1 if the segment from the hit point along unit w (up to tmax) is blocked */
int qtool_rt_occluded(const qtool_rt_scene *s, const qtool_rt_hit *h, const double w[3], double tmax);
/* Lambert and glossy factors of T for unit w (without albedo / ks); 0 when w is below the surface
 * or shadowed (tmax <= 0: no shadow test, the unshadowed transfer). Returns 1 if lit. */
int qtool_rt_response(const qtool_rt_scene *s, const qtool_rt_hit *h, const double w[3], double tmax, double *diff,
                     double *gloss);

/* Light for qtool_rt_render. */
typedef struct qtool_rt_light {
    int point;          /* 0: directional from dir; 1: point at pos */
    double dir[3], pos[3], rgb[3];
    int falloff;        /* point: 1 (C0/|L|, default when 0) or 2 */
} qtool_rt_light;

/* Renders a w x h panorama (3 doubles per pixel, linear) with threads (>= 1). rgb may be NULL;
 * depth (w * h, 0 for sky) and pmap (3 per pixel, Q16.16) may be NULL. 0 or -1 (no memory). */
int qtool_rt_render(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_rt_light *l,
                   int threads, double *rgb, float *depth, int32_t *pmap);
/* The same with a goniometric point lamp: C0 times gonio(ctx, d) for the unit world direction d from
 * the lamp to the shaded point (e.g. qtool_ies_lamp_scale, io/ies.h); gonio NULL: qtool_rt_render. */
int qtool_rt_render_gonio(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind,
                         const qtool_rt_light *l, double (*gonio)(const void *ctx, const double d[3]),
                         const void *ctx, int threads, double *rgb, float *depth, int32_t *pmap);

/* Per pixel what the truth does with light l: 0 sky, 1 lit, 2 cast shadow, 3 facing away (or a
 * point light nearer than 1/256). 0. */
int qtool_rt_classify(const qtool_rt_scene *s, uint32_t w, uint32_t h, qtool_pano_kind kind, const qtool_rt_light *l,
                      int threads, uint8_t *cls);

/* Runs fn(ctx, row) for row = 0..rows-1 on threads (>= 1) pthreads, rows handed out in order.
 * progress (may be NULL) is called under a lock with the number of rows done. */
int qtool_rt_parallel(int threads, uint32_t rows, void (*fn)(void *ctx, uint32_t row), void *ctx,
                     void (*progress)(void *ctx, uint32_t done, uint32_t rows));

#endif
