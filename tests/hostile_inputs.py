#!/usr/bin/env python3
"""Hand-made inputs for the hostile-input tests and the fuzz corpus: small glTF scenes with
chosen structure (node chains, JSON nesting, vertex values, node scales, buffer files),
uncompressed OpenEXR and PNG images with chosen texels. Imported by tests/fuzz/seeds.py;
run as `hostile_inputs.py DIR` it writes the scene and image files that
tests/hostile_input_test.sh uses into DIR."""
import base64, json, math, os, struct, sys, zlib


def gltf(positions=None, depth=1, buffer_uri=None, scale=None, json_nesting=0, image_uri=None, buffer_length=None,
         sparse_uv_count=None, light_intensity=None):
    """A glTF 2.0 scene (JSON text, and the buffer's bytes): one mesh of the given vertex
    positions (x, y, z, ...; indices 0, 1, 2, ...), placed by a chain of `depth` nested nodes
    whose last one has `scale`; the buffer inline (data: URI) unless `buffer_uri` names a
    file, its stated length `buffer_length` when given; `json_nesting` brackets nested inside
    an "extras" array; a base-colour texture when `image_uri` is given; texture coordinates
    from a sparse accessor of `sparse_uv_count` elements without a bufferView when given; a
    KHR_lights_punctual point light of `light_intensity` (a number, written as given) when given."""
    pos = positions or [0, 0, 0, 1, 0, 0, 1, 1, 0]
    count = len(pos) // 3
    uvs = [0.0] * (2 * count)
    indices = struct.pack("<%dH" % count, *range(count))
    indices += b"\0" * (-len(indices) % 4)
    blob = struct.pack("<%df" % len(pos), *pos) + struct.pack("<%df" % len(uvs), *uvs) + indices
    nodes = [{"children": [i + 1]} for i in range(depth - 1)] + [{"mesh": 0}]
    nodes[0]["translation"] = [0, 0, -2]
    if scale is not None:
        nodes[-1]["scale"] = scale
    attributes = {"POSITION": 0}
    if image_uri or sparse_uv_count is not None:
        attributes["TEXCOORD_0"] = 2
    g = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes,
        "meshes": [{"primitives": [{"attributes": attributes, "indices": 1, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}} if image_uri else {}}],
        "buffers": [{"byteLength": len(blob),
                     "uri": buffer_uri or "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * count},
                        {"buffer": 0, "byteOffset": 20 * count, "byteLength": 2 * count},
                        {"buffer": 0, "byteOffset": 12 * count, "byteLength": 8 * count}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
                       "min": [min(pos[c::3]) for c in range(3)], "max": [max(pos[c::3]) for c in range(3)]},
                      {"bufferView": 1, "componentType": 5123, "count": count, "type": "SCALAR"},
                      {"bufferView": 2, "componentType": 5126, "count": count, "type": "VEC2"}],
    }
    if image_uri:
        g["textures"], g["images"] = [{"source": 0}], [{"uri": image_uri}]
    if buffer_length is not None:
        g["buffers"][0]["byteLength"] = buffer_length
    if sparse_uv_count is not None:  # zeros, but for the first vertex's, which is the first two floats
        g["accessors"][2] = {"componentType": 5126, "count": sparse_uv_count, "type": "VEC2",
                             "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123},
                                        "values": {"bufferView": 2}}}
    text = json.dumps(g)
    if light_intensity is not None:  # as text: json.dumps writes no number past a double's range
        g["extensionsUsed"] = ["KHR_lights_punctual"]
        g["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 12345}]}}
        g["nodes"].append({"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}})
        g["scenes"][0]["nodes"].append(len(g["nodes"]) - 1)
        text = json.dumps(g).replace("12345", str(light_intensity))
    if json_nesting:
        text = text[:-1] + ', "extras": ' + "[" * json_nesting + "]" * json_nesting + "}"
    return text, blob


def exr(w, h, texels):
    """An uncompressed float RGB OpenEXR image; texels: (r, g, b) row by row from the top."""
    def attr(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value
    chans = b"".join(c + b"\0" + struct.pack("<iBBBBii", 2, 0, 0, 0, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    head = struct.pack("<ii", 20000630, 2)
    head += attr("channels", "chlist", chans)
    head += attr("compression", "compression", b"\0")
    head += attr("dataWindow", "box2i", struct.pack("<4i", 0, 0, w - 1, h - 1))
    head += attr("displayWindow", "box2i", struct.pack("<4i", 0, 0, w - 1, h - 1))
    head += attr("lineOrder", "lineOrder", b"\0")
    head += attr("pixelAspectRatio", "float", struct.pack("<f", 1))
    head += attr("screenWindowCenter", "v2f", struct.pack("<2f", 0, 0))
    head += attr("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0"
    lines = []
    for y in range(h):
        row = texels[y * w:(y + 1) * w]
        data = b"".join(struct.pack("<f", t[c]) for c in (2, 1, 0) for t in row)
        lines.append(struct.pack("<ii", y, len(data)) + data)
    table, at = b"", len(head) + 8 * h
    for line in lines:
        table += struct.pack("<Q", at)
        at += len(line)
    return head + table + b"".join(lines)


def png(w, h, texels):
    """An 8-bit RGB PNG; texels in [0, 1] as for exr()."""
    raw = b"".join(b"\0" + b"".join(bytes(max(0, min(255, int(255 * c))) for c in t) for t in texels[y * w:(y + 1) * w])
                   for y in range(h))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def write_test_files(out):
    def put(name, data):
        with open(os.path.join(out, name), "wb") as f:
            f.write(data if isinstance(data, bytes) else data.encode())
    two = [0, 0, 0, 1, 0, 0, 1, 1, 0]
    for name, kwargs in {
        "ok": {},
        "deep-nodes": {"depth": 20000},
        "deep-json": {"json_nesting": 200000},
        "inf-vertex": {"positions": two + [0, 0, 0, math.inf, 0, 0, 1, 1, 0]},
        "huge-vertex": {"positions": two + [0, 0, 0, 3e38, 0, 0, 1, 1, 0]},
        "tiny-scale": {"scale": [1e-30, 1e-30, 1e-30]},
        "fifo-buffer": {"buffer_uri": "fifo.bin"},
        "empty-buffer": {"buffer_uri": "empty.bin"},
        "textured": {"image_uri": "tex.png"},
        # What Assimp allocated from a claim alone: a 3.4 GB sparse accessor (a fuzz finding)
        # and a buffer longer than its file.
        "sparse-huge": {"sparse_uv_count": 430309376},
        "long-buffer": {"buffer_uri": "tex.png", "buffer_length": 2000000000},
        "infinite-light": {"light_intensity": "1e39"},
    }.items():
        text, _ = gltf(**kwargs)
        put(name + ".gltf", text)
    put("empty.bin", b"")
    # A binary glTF whose JSON chunk claims 3.8 GB (Assimp allocated it: a fuzz finding).
    json_chunk = b'{"asset":{"version":"2.0"}}  '
    put("chunk-past-end.glb", struct.pack("<4sII", b"glTF", 2, 20 + len(json_chunk))
        + struct.pack("<I4s", 3808429344, b"JSON") + json_chunk)
    put("tex.png", png(2, 2, [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)]))
    w, h = 16, 8
    grey = [(0.5, 0.5, 0.5)] * (w * h)
    put("grey.exr", exr(w, h, grey))
    put("nan.exr", exr(w, h, [(math.nan,) * 3] * (w * h)))
    put("huge.exr", exr(w, h, grey[:-1] + [(3e38, 0, 0)]))
    put("negative.exr", exr(w, h, [(-0.5, 0.5, 0.5)] + grey[1:]))
    put("negative-sky.exr", exr(w, h, grey[:-2] + [(-1, 0.5, 0.5), (3e38, 0.5, 0.5)]))


if __name__ == "__main__":
    write_test_files(sys.argv[1])
