#!/usr/bin/env python3
"""Writes the hand-made seeds of the scene, env_image, gaze and camera targets into
corpus/ (the others are real files: see docs/fuzzing.md). Run from anywhere."""
import base64, json, math, os, struct, sys, zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from hostile_inputs import exr, png, gltf as structured_gltf  # noqa: E402

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def put(target, name, data):
    os.makedirs(os.path.join(here, target), exist_ok=True)
    with open(os.path.join(here, target, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


# Scenes: a textured triangle pair as glTF (data-URI buffer), GLB, and OBJ. Byte 0 picks
# the format in scene_fuzz.cpp: 0 glTF, 1 GLB, 2 OBJ.
positions = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
uvs = struct.pack("<8f", 0, 0, 1, 0, 1, 1, 0, 1)
indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0"
blob = positions + uvs + indices


def gltf(uri):
    g = {
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [0, 0, -2]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "alphaMode": "MASK"}],
        "textures": [{"source": 0}], "images": [{"uri": "tex.png"}],
        "buffers": [{"byteLength": len(blob)} | ({"uri": uri} if uri else {})],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                        {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                      {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
    }
    return json.dumps(g, indent=1)


put("scene", "quad.gltf", b"\0" + gltf("data:application/octet-stream;base64," + base64.b64encode(blob).decode()).encode())
js = gltf(None).encode()
js += b" " * (-len(js) % 4)
glb = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(blob))
glb += struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(blob), 0x004E4942) + blob
put("scene", "quad.glb", b"\1" + glb)
put("scene", "quad.obj", b"\2" + b"v 0 0 -2\nv 1 0 -2\nv 1 1 -2\nv 0 1 -2\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    b"vn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")

# Structure the byte-level mutations seldom reach (issue 30): a node chain past the depth
# bound, JSON nested past its bound, non-finite and huge vertices, a node scaling its mesh
# to nothing, buffers that are a device or missing, a camera placed far away, sparse
# accessors (one of 3.4 GB: a fuzz finding), a buffer claiming more than its file, a light.
flat = [0, 0, 0, 1, 0, 0, 1, 1, 0]
for name, kwargs in {"deep-nodes": {"depth": 300}, "deep-json": {"json_nesting": 100},
                     "inf-vertex": {"positions": flat + [0, 0, 0, math.inf, 0, 0, 1, 1, 0]},
                     "huge-vertex": {"positions": flat + [0, 0, 0, 3e38, 0, 0, 1, 1, 0]},
                     "tiny-scale": {"scale": [1e-30, 1e-30, 1e-30]}, "device-buffer": {"buffer_uri": "/dev/zero"},
                     "missing-buffer": {"buffer_uri": "absent.bin"},
                     "device-texture": {"image_uri": "/dev/zero"}, "sparse": {"sparse_uv_count": 3},
                     "sparse-huge": {"sparse_uv_count": 430309376},
                     "long-buffer": {"buffer_uri": "tex.png", "buffer_length": 2000000000},
                     "light": {"light_intensity": "3"}}.items():
    put("scene", "structure-" + name + ".gltf", b"\0" + structured_gltf(**kwargs)[0].encode())
far = json.loads(structured_gltf()[0])
far["nodes"].append({"camera": 0, "translation": [1e30, 0, 0]})
far["scenes"][0]["nodes"].append(1)
far["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]
put("scene", "structure-far-camera.gltf", b"\0" + json.dumps(far).encode())

# fovbench's reference sidecars: one as fovbench writes it, one with a wrong type.
meta = {"scene": "builtin", "spp": 256, "seed": 7, "ms": 812.5, "rays": 2359296, "sampler": "sobol",
        "render_settings": "exposure 0 EV"}
put("reference_meta", "written.json", json.dumps(meta, indent=2) + "\n")
put("reference_meta", "wrong-type.json", json.dumps(dict(meta, render_settings=3)))

# Camera flags, a value per line (--eye, --look-at, --up, --hfov; an empty line: not given).
put("camera_flags", "look.txt", "0,1,4\n0,0,0\n0,1,0\n60\n")
put("camera_flags", "far-eye.txt", "1e20,0,0\n")
put("camera_flags", "overflow.txt", "3e38,0,0\n-3e38,0,0\n")
put("camera_flags", "eye-only.txt", "2,2,2\n\n\n\n")

# env: images, 8 x 4 pixels. Byte 0 picks the format in env_image_fuzz.cpp: 0 HDR, 1 EXR, 2 PNG.
w, h = 8, 4
texels = [(0.2 + x / w, 0.3 + y / h, 0.5) for y in range(h) for x in range(w)]


def rgbe(r, g, b):
    import math
    v = max(r, g, b)
    m, e = math.frexp(v)
    s = m * 256 / v
    return bytes((int(r * s), int(g * s), int(b * s), e + 128))


hdr = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w) + b"".join(rgbe(*t) for t in texels)
put("env_image", "sky.hdr", b"\0" + hdr)


put("env_image", "sky.exr", b"\1" + exr(w, h, texels))


put("env_image", "sky.png", b"\2" + png(w, h, texels))

# Gaze traces, camera paths and datagrams, as recorders and the docs write them.
put("gaze_trace", "pixels.csv", "t_ms,x,y\n0,32,24\n16.7,33.5,24.2\n33.3,40,20\n50,64,48\n")
put("gaze_trace", "normalised.csv", "t_ms,x_norm,y_norm\n0,0.5,0.5\n10,0.25,0.75\n10,0.3,0.7\n\n500,1,0\n")
put("camera_path", "orbit.csv", "t_ms,x,y,z,tx,ty,tz\n0,0,1,4,0,0,0\n500,2,1,3,0,0,0\n1000,4,1,0,0,0.5,0\n")
put("gaze_datagram", "centre", "0.5 0.5")
put("gaze_datagram", "corner", "1 0\n")
put("gaze_datagram", "exponent", "5e-1 2.5E-1")
put("gaze_datagram", "v2", "v2 1234.5678 0.97 l 0.31 0.42\n")
put("gaze_datagram", "v2-commas", "v2,7,1,B,0.5,0.5")


# Pupil Labs gaze messages: the topic, a NUL, then the msgpack payload as Pupil packs it.
def mp_str(t):
    b = t.encode()
    return bytes([0xA0 | len(b)]) + b


def mp_f64(v):
    return b"\xcb" + struct.pack(">d", v)


gaze_map = (b"\x83" + mp_str("norm_pos") + b"\x92" + mp_f64(0.25) + mp_f64(0.75) + mp_str("confidence")
            + mp_f64(0.95) + mp_str("timestamp") + mp_f64(1234.5))
put("pupil_gaze", "binocular", b"gaze.3d.01.\0" + gaze_map)
put("pupil_gaze", "right-eye-ints", b"gaze.2d.0.\0" + b"\x83" + mp_str("norm_pos") + b"\x92\x00\x01"
    + mp_str("confidence") + b"\x01" + mp_str("timestamp") + b"\xcd\x04\xd2")
put("pupil_gaze", "huge-array", b"gaze.3d.1.\0" + b"\x81" + mp_str("norm_pos") + b"\xdd\xff\xff\xff\xff")
put("pupil_gaze", "missing-confidence", b"gaze.3d.1.\0" + b"\x82" + mp_str("norm_pos") + b"\x92" + mp_f64(0.1)
    + mp_f64(0.2) + mp_str("timestamp") + mp_f64(1.0))
put("pupil_gaze", "not-gaze", b"pupil.0.2d\0" + gaze_map)
surface_datum = (b"\x84" + mp_str("topic") + mp_str("gaze.3d.0._on_surface") + mp_str("norm_pos") + b"\x92" + mp_f64(0.4)
                 + mp_f64(0.6) + mp_str("confidence") + mp_f64(0.9) + mp_str("timestamp") + mp_f64(1234.5))
put("pupil_gaze", "surface", b"surfaces.screen\0" + b"\x82" + mp_str("name") + mp_str("screen") + mp_str("gaze_on_surfaces")
    + b"\x92" + surface_datum + surface_datum)

# Gaze calibrations, the three forms and a degenerate grid.
put("gaze_calibration", "affine.json", '{"offset": [0.01, -0.02], "scale": [1.05, 0.97]}\n')
put("gaze_calibration", "homography.json", '{"homography": [1, 0.01, 0, 0, 1, 0, 0.001, 0, 1]}\n')
put("gaze_calibration", "grid.json",
    '{"grid": [[0.1,0.1,0.12,0.09],[0.9,0.1,0.88,0.1],[0.1,0.9,0.1,0.91],[0.9,0.9,0.9,0.9],[0.5,0.5,0.5,0.51]]}\n')
put("gaze_calibration", "collinear.json", '{"grid": [[0,0,0,0],[0.5,0.5,0.5,0.5],[1,1,1,1],[0.25,0.25,0.25,0.25]]}\n')
