"""An outdoor glTF scene for timing what foliage costs: a 100 m square of ground, TREES trees
(each a trunk node and a crown node: six crossed leaf cards and a flat one, whose 64x64 texture
is alpha-masked, glTF alphaMode MASK), a camera at eye height and a low sun. 2 TREES + 3 nodes.

usage: python3 bench/scenes/forest.py TREES OUT_DIR   (writes OUT_DIR/forest_TREES.gltf and leaf.png)
Then e.g. igi-render OUT_DIR/forest_2000.gltf --size 640x480 --vpls 12 --frames 5 --temporal 0 --stats json
(--temporal 0: single frames, each by itself, as the timings of docs/performance.md).
Deterministic (seeded): the same TREES gives the same file.
"""

import base64
import json
import math
import random
import struct
import sys
import zlib
from pathlib import Path


def png_rgba(width, height, rows):
    """An 8-bit RGBA PNG of `rows` (lists of width x 4 bytes), written with zlib alone."""
    raw = b"".join(b"\x00" + bytes(row) for row in rows)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def leaf_texture(size=64, cell=16, radius2=40):
    """Green discs on a transparent ground: the leaves' alpha mask."""
    rows = []
    for y in range(size):
        row = []
        for x in range(size):
            dx, dy = x % cell - cell // 2, y % cell - cell // 2
            row += [40, 120 + (x * y) % 60, 30, 255 if dx * dx + dy * dy < radius2 else 0]
        rows.append(row)
    return png_rgba(size, size, rows)


class MeshBuilder:
    """Positions, normals, uvs and indices of one mesh, quad by quad."""

    def __init__(self):
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def quad(self, corners, normal):
        base = len(self.positions) // 3
        for corner, uv in zip(corners, ((0, 0), (1, 0), (1, 1), (0, 1))):
            self.positions += corner
            self.normals += normal
            self.uvs += uv
        self.indices += [base, base + 1, base + 2, base, base + 2, base + 3]


def ground():
    mesh = MeshBuilder()
    mesh.quad(((-50, 0, -50), (-50, 0, 50), (50, 0, 50), (50, 0, -50)), (0, 1, 0))
    return mesh


def trunk(half=0.15, height=3.0):
    mesh = MeshBuilder()
    s, h = half, height
    mesh.quad(((-s, 0, s), (s, 0, s), (s, h, s), (-s, h, s)), (0, 0, 1))
    mesh.quad(((s, 0, -s), (-s, 0, -s), (-s, h, -s), (s, h, -s)), (0, 0, -1))
    mesh.quad(((s, 0, s), (s, 0, -s), (s, h, -s), (s, h, s)), (1, 0, 0))
    mesh.quad(((-s, 0, -s), (-s, 0, s), (-s, h, s), (-s, h, -s)), (-1, 0, 0))
    return mesh


def crown(cards=6, reach=1.5):
    mesh = MeshBuilder()
    for k in range(cards):
        angle = k * math.pi / cards
        c, s = math.cos(angle) * reach, math.sin(angle) * reach
        mesh.quad(((-c, 2.2, -s), (c, 2.2, s), (c, 5, s), (-c, 5, -s)), (-s, 0, c))
    mesh.quad(((-reach, 4, -reach), (reach, 4, -reach), (reach, 4, reach), (-reach, 4, reach)), (0, 1, 0))
    return mesh


def quaternion_from_to(a, b):
    """The rotation taking unit vector a to unit vector b (not opposite), as glTF's (x, y, z, w)."""
    axis = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    norm = math.sqrt(sum(v * v for v in axis))
    angle = math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b)))))
    return [v / norm * math.sin(angle / 2) for v in axis] + [math.cos(angle / 2)]


def main():
    trees, out = int(sys.argv[1]), Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    (out / "leaf.png").write_bytes(leaf_texture())
    random.seed(3)
    buffer, views, accessors, meshes = bytearray(), [], [], []

    def add(values, form, count, kind, component, target):
        data = struct.pack("<%d%s" % (len(values), form), *values)
        while len(buffer) % 4:
            buffer.append(0)
        views.append({"buffer": 0, "byteOffset": len(buffer), "byteLength": len(data), "target": target})
        buffer.extend(data)
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": count, "type": kind}
        if kind == "VEC3":
            accessor["min"] = [min(values[i::3]) for i in range(3)]
            accessor["max"] = [max(values[i::3]) for i in range(3)]
        accessors.append(accessor)
        return len(accessors) - 1

    for material, mesh in enumerate((ground(), trunk(), crown())):
        attributes = {"POSITION": add(mesh.positions, "f", len(mesh.positions) // 3, "VEC3", 5126, 34962),
                      "NORMAL": add(mesh.normals, "f", len(mesh.normals) // 3, "VEC3", 5126, 34962),
                      "TEXCOORD_0": add(mesh.uvs, "f", len(mesh.uvs) // 2, "VEC2", 5126, 34962)}
        indices = add(mesh.indices, "I", len(mesh.indices), "SCALAR", 5125, 34963)
        meshes.append({"primitives": [{"attributes": attributes, "indices": indices, "material": material}]})
    nodes = [{"mesh": 0}]
    for _ in range(trees):
        x, z, turn = random.uniform(-45, 45), random.uniform(-45, 45), random.uniform(0, 2 * math.pi)
        rotation = [0, math.sin(turn / 2), 0, math.cos(turn / 2)]
        nodes.append({"mesh": 1, "translation": [x, 0, z], "rotation": rotation})
        nodes.append({"mesh": 2, "translation": [x, 0, z], "rotation": rotation})
    nodes.append({"camera": 0, "translation": [0, 1.7, 30], "rotation": [-0.05, 0, 0, 0.9987]})
    sun = (-0.4, -0.8, -0.45)
    length = math.sqrt(sum(v * v for v in sun))
    nodes.append({"rotation": quaternion_from_to((0, 0, -1), tuple(v / length for v in sun)),
                  "extensions": {"KHR_lights_punctual": {"light": 0}}})
    gltf = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes,
        "meshes": meshes,
        "materials": [
            {"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.4, 0.35, 0.25, 1], "metallicFactor": 0}},
            {"name": "bark", "pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.2, 0.1, 1], "metallicFactor": 0}},
            {"name": "leaves", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0},
             "alphaMode": "MASK", "doubleSided": True}],
        "textures": [{"source": 0}], "images": [{"uri": "leaf.png"}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05}}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3.0, "color": [1, 0.95, 0.85]}]}},
        "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": len(buffer),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buffer)).decode()}],
    }
    path = out / f"forest_{trees}.gltf"
    path.write_text(json.dumps(gltf))
    print(f"forest: wrote {path} ({len(nodes)} nodes)")


if __name__ == "__main__":
    main()
