#!/usr/bin/env python3
# gen-gltf-room.py - writes fixtures/gltf/TexturedRoom.gltf, qibl's own textured glTF scene for the
# fixed-camera tests and pictures: a floor slab with a checker texture, two walls with a brick
# texture, a box and a pillar (base colour factors), and a perspective camera in the open corner
# looking at the box. Everything embedded (data: URIs), Y up, so one file is the whole scene.
# Deterministic: the same bytes on every run (python3 tools/scripts/gen-gltf-room.py > FILE).
import base64
import json
import math
import struct
import sys
import zlib


def png_rgb(w, h, rgb):
    """An 8-bit RGB PNG (colour type 2) of rows of (r, g, b) tuples."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rgb)

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def checker():
    a, b = (200, 190, 160), (90, 110, 150)
    return png_rgb(8, 8, [[a if (x // 2 + y // 2) % 2 == 0 else b for x in range(8)] for y in range(8)])


def bricks():
    mortar, brick = (210, 205, 195), (170, 80, 60)
    rows = []
    for y in range(8):
        off = 0 if (y // 4) % 2 == 0 else 4
        rows.append([mortar if y % 4 == 3 or (x + off) % 8 == 7 else brick for x in range(8)])
    return png_rgb(8, 8, rows)


positions, normals, uvs = [], [], []
prims = []  # (first vertex, vertex count, material)


def quad(p0, p1, p2, p3, n, uvscale, mat):
    """Two triangles p0 p1 p2, p0 p2 p3 (counter-clockwise seen from n), uv over the quad."""
    first = len(positions)
    u = [(0, 0), (uvscale[0], 0), (uvscale[0], uvscale[1]), (0, uvscale[1])]
    for i in (0, 1, 2, 0, 2, 3):
        positions.append([p0, p1, p2, p3][i])
        normals.append(n)
        uvs.append(u[i])
    prims.append((first, 6, mat))


def box(lo, hi, mat, uvscale=(1, 1)):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    quad((x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (0, 1, 0), uvscale, mat)  # top
    quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1), (0, -1, 0), uvscale, mat)  # bottom
    quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (0, 0, 1), uvscale, mat)  # +z
    quad((x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (0, 0, -1), uvscale, mat)  # -z
    quad((x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (1, 0, 0), uvscale, mat)  # +x
    quad((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0), (-1, 0, 0), uvscale, mat)  # -x


# materials: 0 checker floor, 1 brick walls, 2 the box, 3 the pillar
box((-2, -0.1, -2), (2, 0, 2), 0, (4, 4))                 # floor slab
box((-2, 0, -2.2), (2, 2, -2), 1, (4, 2))                 # back wall
box((-2.2, 0, -2.2), (-2, 2, 2), 1, (4, 2))               # left wall
box((-0.9, 0, -0.9), (0.1, 1, 0.1), 2)                   # box
box((0.8, 0, -1.4), (1.2, 1.6, -1.0), 3)                 # pillar

# the buffer: positions, normals, uvs (float32), then one uint16 index list per primitive
def f32(vals):
    return b"".join(struct.pack("<f", v) for t in vals for v in t)


nv = len(positions)
pos_b, nrm_b, uv_b = f32(positions), f32(normals), f32(uvs)
idx_b = b"".join(struct.pack("<H", i) for i in range(nv))
idx_b += b"\x00" * (-len(idx_b) % 4)
buf = pos_b + nrm_b + uv_b + idx_b
views = [
    {"buffer": 0, "byteOffset": 0, "byteLength": len(pos_b)},
    {"buffer": 0, "byteOffset": len(pos_b), "byteLength": len(nrm_b)},
    {"buffer": 0, "byteOffset": len(pos_b) + len(nrm_b), "byteLength": len(uv_b)},
    {"buffer": 0, "byteOffset": len(pos_b) + len(nrm_b) + len(uv_b), "byteLength": 2 * nv},
]
lo = [min(p[j] for p in positions) for j in range(3)]
hi = [max(p[j] for p in positions) for j in range(3)]
accessors = [
    {"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": lo, "max": hi},
    {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
    {"bufferView": 2, "componentType": 5126, "count": nv, "type": "VEC2"},
]
primitives = []
for first, count, mat in prims:
    accessors.append({"bufferView": 3, "byteOffset": 2 * first, "componentType": 5123, "count": count,
                      "type": "SCALAR"})
    primitives.append({"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                       "indices": len(accessors) - 1, "material": mat})

# the camera: in the open corner, a little above the box, looking at the box's top corner
eye, target = (1.9, 1.5, 1.9), (-0.6, 0.5, -0.6)
f = [target[j] - eye[j] for j in range(3)]
fl = math.sqrt(sum(c * c for c in f))
f = [c / fl for c in f]
r = [f[1] * 0 - f[2] * 1, f[2] * 0 - f[0] * 0, f[0] * 1 - f[1] * 0]  # f x (0, 1, 0)
rl = math.sqrt(sum(c * c for c in r))
r = [c / rl for c in r]
u = [r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]]
# columns: x = right, y = up, z = -forward (a glTF camera looks down its -z), translation = eye
matrix = [round(v, 6) for v in r + [0] + u + [0] + [-c for c in f] + [0] + list(eye) + [1]]


def data_uri(kind, b):
    return "data:%s;base64,%s" % (kind, base64.b64encode(b).decode("ascii"))


gltf = {
    "asset": {"version": "2.0", "generator": "qibl tools/scripts/gen-gltf-room.py"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0, "name": "room"}, {"camera": 0, "name": "corner", "matrix": matrix}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": round(math.radians(60), 6), "aspectRatio": 1.333333,
                                                        "znear": 0.05, "zfar": 100}}],
    "meshes": [{"name": "room", "primitives": primitives}],
    "materials": [
        {"name": "floor", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
        {"name": "bricks", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}},
        {"name": "box", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.45, 0.7, 1]}},
        {"name": "pillar", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.75, 0.3, 1]}},
    ],
    "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
    "samplers": [{"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497}],
    "images": [{"uri": data_uri("image/png", checker())}, {"uri": data_uri("image/png", bricks())}],
    "buffers": [{"byteLength": len(buf), "uri": data_uri("application/octet-stream", buf)}],
    "bufferViews": views,
    "accessors": accessors,
}
sys.stdout.write(json.dumps(gltf, indent=1) + "\n")
