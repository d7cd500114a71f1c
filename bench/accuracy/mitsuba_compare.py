"""Renders ../shared/scenes/cornell/cornell_box.gltf with Mitsuba 3's path tracer, built from the
glTF's own numbers (Mitsuba 3 does not read glTF): the same meshes and vertex normals, diffuse
albedos = baseColorFactor, the luminaire's radiance = emissiveFactor x emissiveStrength on its
front side, the glTF camera (vertical field of view, aspect 1), a box pixel filter, unlimited
depth. Writes one EXR per seed. Run by mitsuba_compare.sh inside its own virtual environment."""
import json
import math
import struct
import sys
from pathlib import Path

import mitsuba as mi

mi.set_variant("scalar_rgb")


def accessor(gltf, binary, index):
    """The accessor's elements as a list of tuples (VEC3 floats) or ints (SCALAR indices)."""
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    offset = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    formats = {5126: "f", 5125: "I", 5123: "H", 5121: "B"}
    sizes = {5126: 4, 5125: 4, 5123: 2, 5121: 1}
    components = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[a["type"]]
    size = sizes[a["componentType"]]
    stride = view.get("byteStride", size * components)
    values = []
    for i in range(a["count"]):
        start = offset + i * stride
        element = struct.unpack_from("<" + formats[a["componentType"]] * components, binary, start)
        values.append(element if components > 1 else element[0])
    return values


def write_ply(path, positions, normals, indices):
    """An ASCII PLY of one triangle mesh with vertex normals (what Mitsuba's ply plugin reads)."""
    lines = ["ply", "format ascii 1.0", f"element vertex {len(positions)}", "property float x", "property float y",
             "property float z", "property float nx", "property float ny", "property float nz",
             f"element face {len(indices) // 3}", "property list uchar int vertex_indices", "end_header"]
    lines += [" ".join(repr(float(c)) for c in (*p, *n)) for p, n in zip(positions, normals)]
    lines += [f"3 {indices[i]} {indices[i + 1]} {indices[i + 2]}" for i in range(0, len(indices), 3)]
    Path(path).write_text("\n".join(lines) + "\n")


def scene_dict(path, width, height, spp, seed, work):
    gltf = json.loads(Path(path).read_text())
    binary = (Path(path).parent / gltf["buffers"][0]["uri"]).read_bytes()
    scene = {"type": "scene", "integrator": {"type": "path", "max_depth": -1}}
    for node in gltf["nodes"]:
        if "mesh" in node:
            assert "matrix" not in node and "translation" not in node and "rotation" not in node, "nodes must be identity"
            mesh = gltf["meshes"][node["mesh"]]
            for k, primitive in enumerate(mesh["primitives"]):
                positions = accessor(gltf, binary, primitive["attributes"]["POSITION"])
                normals = accessor(gltf, binary, primitive["attributes"]["NORMAL"])
                indices = accessor(gltf, binary, primitive["indices"])
                material = gltf["materials"][primitive["material"]]
                ply = Path(work) / f"{mesh['name']}_{k}.ply"
                write_ply(ply, positions, normals, indices)
                base = material["pbrMetallicRoughness"]["baseColorFactor"]
                shape = {"type": "ply", "filename": str(ply), "face_normals": False,
                         "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": base[:3]}}}
                if "emissiveFactor" in material:
                    strength = material.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
                    radiance = [c * strength for c in material["emissiveFactor"]]
                    shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": radiance}}
                scene[f"{mesh['name']}_{k}"] = shape
        elif "camera" in node:
            camera = gltf["cameras"][node["camera"]]["perspective"]
            t = node["translation"]
            x, y, z, w = node["rotation"]
            # glTF cameras look down their local -Z; rotate that axis by the node's quaternion.
            forward = (-(2 * (x * z + w * y)), -(2 * (y * z - w * x)), -(1 - 2 * (x * x + y * y)))
            up = (2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x))
            target = [t[i] + forward[i] for i in range(3)]
            scene["sensor"] = {
                "type": "perspective",
                "fov_axis": "y",
                "fov": math.degrees(camera["yfov"]),
                "near_clip": camera.get("znear", 0.01),
                "to_world": mi.ScalarTransform4f.look_at(origin=t, target=target, up=up),
                "sampler": {"type": "independent", "sample_count": spp, "seed": seed},
                "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                         "pixel_format": "rgb", "component_format": "float32"},
            }
    return scene


def main():
    gltf_path, output_prefix, width, height, spp = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
    seeds = [int(s) for s in sys.argv[6:]] or [0]
    for seed in seeds:
        scene = mi.load_dict(scene_dict(gltf_path, width, height, spp, seed, Path(output_prefix).parent))
        image = mi.render(scene, spp=spp, seed=seed)
        out = f"{output_prefix}{seed}.exr"
        mi.util.write_bitmap(out, image)
        print(f"wrote {out}")


if __name__ == "__main__":
    main()
