#!/usr/bin/env python3
"""Writes the seed corpus of igi's fuzz harnesses into a folder: the shared Cornell box (as .gltf
with its .bin, as one .glb, and with the buffer embedded as a data URI), small documents that each
exercise a loader feature (index types, sparse accessors, strips and fans, quantized attributes,
textures, lights, cameras, node trees), a few broken ones, and tests/data/fuzz (the regression
inputs of earlier findings). Compact JSON keeps the seeds small, which keeps mutation fast.
Usage: make_seeds.py OUTPUT_DIR [SCENES_DIR]"""
import base64, json, pathlib, shutil, struct, sys, zlib

out = pathlib.Path(sys.argv[1])
scenes = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else pathlib.Path(__file__).resolve().parents[2] / "shared" / "scenes"
out.mkdir(parents=True, exist_ok=True)


def write(name, doc, binary=None, glb=False):
    text = json.dumps(doc, separators=(",", ":")).encode()
    if not glb:
        (out / name).write_bytes(text)
        return
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary is not None:
        binary += b"\0" * (-len(binary) % 4)
        chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    (out / name).write_bytes(struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)


def data_uri(payload, mime="application/octet-stream"):
    return "data:%s;base64,%s" % (mime, base64.b64encode(payload).decode())


def png(width, height, rgba):
    rows = b"".join(b"\0" + bytes(rgba) * width for _ in range(height))
    chunk = lambda kind, body: struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


class Doc:
    """One glTF document whose single buffer is embedded (data URI) or the GLB BIN chunk."""

    def __init__(self):
        self.doc = {"asset": {"version": "2.0"}, "buffers": [], "bufferViews": [], "accessors": [],
                    "meshes": [], "nodes": [], "scenes": [{"nodes": []}]}
        self.bin = b""

    def view(self, payload, stride=0):
        self.bin += b"\0" * (-len(self.bin) % 4)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(payload)}
        if stride:
            view["byteStride"] = stride
        self.bin += payload
        self.doc["bufferViews"].append(view)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, fmt, values, component, kind, **extra):
        self.doc["accessors"].append(dict({"bufferView": self.view(struct.pack("<%d%s" % (len(values), fmt), *values)),
                                           "componentType": component, "count": len(values) // {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[kind],
                                           "type": kind}, **extra))
        return len(self.doc["accessors"]) - 1

    def mesh(self, attributes, indices=None, mode=None, material=None):
        primitive = {"attributes": attributes}
        if indices is not None:
            primitive["indices"] = indices
        if mode is not None:
            primitive["mode"] = mode
        if material is not None:
            primitive["material"] = material
        self.doc["meshes"].append({"primitives": [primitive]})
        self.doc["nodes"].append({"mesh": len(self.doc["meshes"]) - 1})
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)

    def save(self, name):
        write(name + ".gltf", dict(self.doc, buffers=[{"byteLength": len(self.bin), "uri": data_uri(self.bin)}]))
        write(name + ".glb", dict(self.doc, buffers=[{"byteLength": len(self.bin)}]), self.bin, glb=True)


QUAD = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]
FLOAT, U8, U16, U32, I8, I16 = 5126, 5121, 5123, 5125, 5120, 5122


def quad(d, **extra):
    return d.accessor("f", QUAD, FLOAT, "VEC3", min=[0, 0, 0], max=[1, 1, 0], **extra)


# Index types and no indices.
d = Doc()
d.mesh({"POSITION": quad(d)}, d.accessor("B", [0, 1, 2, 0, 2, 3], U8, "SCALAR"))
d.mesh({"POSITION": quad(d)}, d.accessor("H", [0, 1, 2, 0, 2, 3], U16, "SCALAR"))
d.mesh({"POSITION": quad(d)}, d.accessor("I", [0, 1, 2, 0, 2, 3], U32, "SCALAR"))
d.mesh({"POSITION": d.accessor("f", QUAD[:9], FLOAT, "VEC3")})
d.save("indices")

# Strips and fans, quantized normals and uvs, interleaved attributes.
d = Doc()
d.mesh({"POSITION": quad(d)}, d.accessor("B", [0, 1, 3, 2], U8, "SCALAR"), mode=5)
d.mesh({"POSITION": quad(d), "NORMAL": d.accessor("b", [0, 0, 127] * 4, I8, "VEC3", normalized=True),
        "TEXCOORD_0": d.accessor("H", [0, 0, 65535, 0, 65535, 65535, 0, 65535], U16, "VEC2", normalized=True)},
       d.accessor("B", [0, 1, 2, 3], U8, "SCALAR"), mode=6)
d.mesh({"POSITION": d.accessor("h", [0, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 0, 1, 1, 0], I16, "VEC3")})
d.doc["extensionsUsed"] = d.doc["extensionsRequired"] = ["KHR_mesh_quantization"]
d.save("strips_fans_quantized")

# Sparse accessors, with and without a base bufferView.
d = Doc()
base = quad(d)
indices_view, values_view = d.view(struct.pack("<B", 2)), d.view(struct.pack("<3f", 2, 2, 1))
d.doc["accessors"][base]["sparse"] = {"count": 1, "indices": {"bufferView": indices_view, "componentType": U8},
                                      "values": {"bufferView": values_view}}
d.doc["accessors"].append({"componentType": FLOAT, "count": 4, "type": "VEC3", "sparse": {
    "count": 1, "indices": {"bufferView": indices_view, "componentType": U8}, "values": {"bufferView": values_view}}})
d.mesh({"POSITION": base}, d.accessor("B", [0, 1, 2, 0, 2, 3], U8, "SCALAR"))
d.mesh({"POSITION": len(d.doc["accessors"]) - 1}, d.accessor("B", [0, 1, 2, 0, 2, 3], U8, "SCALAR"))
d.save("sparse")

# Materials with textures (PNG in a bufferView and as a data URI), lights, cameras, a node tree.
d = Doc()
image_view = d.view(png(2, 2, [200, 100, 50, 255]))
d.doc["images"] = [{"bufferView": image_view, "mimeType": "image/png"}, {"uri": data_uri(png(1, 1, [9, 9, 9, 255]), "image/png")}]
d.doc["textures"] = [{"source": 0}, {"source": 1}]
d.doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0},
                       "emissiveTexture": {"index": 1}, "emissiveFactor": [1, 1, 1], "alphaMode": "MASK",
                       "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0},
                                      "KHR_materials_transmission": {"transmissionFactor": 0.5},
                                      "KHR_materials_ior": {"ior": 1.3}}}]
d.doc["extensionsUsed"] = ["KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_lights_punctual"]
d.mesh({"POSITION": quad(d), "TEXCOORD_0": d.accessor("f", [0, 0, 1, 0, 1, 1, 0, 1], FLOAT, "VEC2")},
       d.accessor("B", [0, 1, 2, 0, 2, 3], U8, "SCALAR"), material=0)
d.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
    {"type": "point", "intensity": 5, "color": [1, 0.9, 0.8]},
    {"type": "spot", "intensity": 20, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
    {"type": "directional", "intensity": 2}]}}
d.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01, "aspectRatio": 1.5}}]
d.doc["nodes"] += [
    {"translation": [0.5, 0.5, 2], "rotation": [0, 0, 0, 1], "scale": [1, 1, 1], "children": [2]},
    {"camera": 0},
    {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1], "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"translation": [0, 3, 0], "rotation": [-0.7071, 0, 0, 0.7071], "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"extensions": {"KHR_lights_punctual": {"light": 2}}}]
d.doc["scenes"][0]["nodes"] = [0, 1, 3, 4, 5]
d.save("materials_lights_cameras")

# Broken: index past the vertices, accessor past its view, a cycle in the nodes.
d = Doc()
d.mesh({"POSITION": quad(d)}, d.accessor("B", [0, 1, 9], U8, "SCALAR"))
d.save("broken_index")
d = Doc()
d.mesh({"POSITION": quad(d, byteOffset=40)})
d.save("broken_accessor")
d = Doc()
d.mesh({"POSITION": quad(d)})
d.doc["nodes"][0]["children"] = [0]
d.save("broken_cycle")

# The shared Cornell box three ways (Sponza and the bunny are too large to mutate quickly).
cornell = scenes / "cornell" / "cornell_box.gltf"
if cornell.exists():
    doc = json.loads(cornell.read_text())
    payload = (scenes / "cornell" / "cornell_box.bin").read_bytes()
    write("cornell_external.gltf", doc)
    write("cornell_embedded.gltf", dict(doc, buffers=[{"byteLength": len(payload), "uri": data_uri(payload)}]))
    write("cornell.glb", dict(doc, buffers=[{"byteLength": len(payload)}]), payload, glb=True)

# Regression inputs of earlier findings.
for found in sorted((pathlib.Path(__file__).resolve().parents[1] / "tests" / "data" / "fuzz").glob("*")):
    shutil.copy(found, out / found.name)
print("%d seeds in %s" % (len(list(out.iterdir())), out))
