"""Environment-light check against Mitsuba 3: writes a small outdoor scene as glTF (a grey ground
quad, a red box and a tall blue-green box, Lambertian, a camera that sees the horizon) and an
equirectangular sky (256 x 128 EXR and PFM: a blue-to-white gradient that also changes colour
with azimuth, a dark ground below the horizon, and a 5 x 3 texel sun at 35 degrees elevation), then
renders the scene with Mitsuba 3's path tracer lit by its `envmap` emitter reading the same EXR.
The scene's meshes, materials and camera reach Mitsuba through mitsuba_compare.py's scene_dict (the
glTF's own numbers). Run by mitsuba_envmap.sh inside its own virtual environment.

Mitsuba's envmap maps a local direction d to u = atan2(d.x, -d.z) / 2 pi, v = acos(d.y) / pi, the
convention igi's --environment reads, so the emitter takes no to_world. The orientation check
renders two wrong ones as well (`turned`: 180 degrees about +Y; `mirrored`: x -> -x) that must not
match.

usage: mitsuba_envmap.py scene WORK_DIR                   writes WORK_DIR/envmap_scene.gltf, sky.exr, sky.pfm
       mitsuba_envmap.py render WORK_DIR W H SPP VARIANT SEED...   writes WORK_DIR/mitsuba_[VARIANT_]SEED.exr
       mitsuba_envmap.py ground WORK_DIR IGI_PATH_RENDER SPP      the open ground's light against its analytic value
"""
import json
import math
import struct
import sys
from pathlib import Path

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
sys.path.insert(0, str(Path(__file__).resolve().parent))
from mitsuba_compare import scene_dict  # noqa: E402  (the glTF -> Mitsuba conversion)

SUN_ELEVATION = math.radians(35.0)
SUN_U = 0.30  # azimuth of the sun: u = atan2(x, -z) / 2 pi, so towards +X and a little +Z
SUN_RADIANCE = np.array([1500.0, 1350.0, 1100.0])


def direction(u, v):
    """The unit direction of map coordinates (u, v) (inverse of u = atan2(x, -z)/2pi, v = acos(y)/pi)."""
    phi, theta = 2 * math.pi * u, math.pi * v
    return np.array([math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi)])


def sky_map(width=256, height=128):
    image = np.zeros((height, width, 3), dtype=np.float32)
    for j in range(height):
        v = (j + 0.5) / height
        elevation = math.pi / 2 - math.pi * v
        for i in range(width):
            u = (i + 0.5) / width
            if elevation > 0:
                t = math.sin(elevation)  # 0 at the horizon, 1 at the zenith
                warm = 0.5 + 0.5 * math.cos(2 * math.pi * (u - SUN_U))  # warmer towards the sun's azimuth
                image[j, i] = (np.array([1.0, 1.0, 1.0]) * (1 - t) + np.array([0.25, 0.45, 1.0]) * t) * \
                    (0.8 + 0.4 * warm * np.array([1.0, 0.8, 0.5]))
            else:
                image[j, i] = [0.12, 0.10, 0.08]  # ground
    # The sun: 5 x 3 texels around its direction.
    sun_i = int(SUN_U * width)
    sun_j = int((math.pi / 2 - SUN_ELEVATION) / math.pi * height)
    image[sun_j - 1:sun_j + 2, sun_i - 2:sun_i + 3] = SUN_RADIANCE
    return image


def box(x0, y0, z0, x1, y1, z1):
    """24 vertices with face normals and 36 indices of an axis-aligned box, faces outwards."""
    positions, normals, indices = [], [], []
    faces = [((1, 0, 0), [(x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)]),
             ((-1, 0, 0), [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)]),
             ((0, 1, 0), [(x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0)]),
             ((0, -1, 0), [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)]),
             ((0, 0, 1), [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]),
             ((0, 0, -1), [(x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)])]
    for normal, corners in faces:
        base = len(positions)
        positions += corners
        normals += [normal] * 4
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, indices


def camera_quaternion(eye, target):
    """glTF node rotation (x, y, z, w) that turns the camera's -Z towards target with +Y up."""
    forward = np.array(target, float) - np.array(eye, float)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    m = np.column_stack([right, up, -forward])  # columns: camera X, Y, Z in world
    w = math.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    x = (m[2, 1] - m[1, 2]) / (4 * w)
    y = (m[0, 2] - m[2, 0]) / (4 * w)
    z = (m[1, 0] - m[0, 1]) / (4 * w)
    return [x, y, z, w]


def write_scene(work):
    work = Path(work)
    work.mkdir(parents=True, exist_ok=True)
    meshes = [("ground", ([(-12, 0, 12), (12, 0, 12), (12, 0, -12), (-12, 0, -12)], [(0, 1, 0)] * 4, [0, 1, 2, 0, 2, 3]),
               [0.5, 0.5, 0.5]),
              ("red_box", box(-1.6, 0.0, -0.6, -0.4, 1.2, 0.6), [0.7, 0.15, 0.1]),
              ("tall_box", box(0.5, 0.0, -1.4, 1.3, 2.4, -0.6), [0.15, 0.45, 0.6])]
    binary = bytearray()
    gltf = {"asset": {"version": "2.0", "generator": "igi bench/accuracy/mitsuba_envmap.py"}, "scene": 0,
            "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [], "accessors": [], "bufferViews": [],
            "buffers": [], "extensionsUsed": ["KHR_materials_specular"]}

    def add(values, fmt, kind, target, component):
        offset = len(binary)
        for value in values:
            binary.extend(struct.pack("<" + fmt, *(value if isinstance(value, tuple) else (value,))))
        gltf["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": len(binary) - offset, "target": target})
        accessor = {"bufferView": len(gltf["bufferViews"]) - 1, "componentType": component, "count": len(values), "type": kind}
        if kind == "VEC3":
            accessor["min"] = [min(v[i] for v in values) for i in range(3)]
            accessor["max"] = [max(v[i] for v in values) for i in range(3)]
        gltf["accessors"].append(accessor)
        while len(binary) % 4:
            binary.append(0)
        return len(gltf["accessors"]) - 1

    for name, (positions, normals, indices), colour in meshes:
        positions = [tuple(float(c) for c in p) for p in positions]
        normals = [tuple(float(c) for c in n) for n in normals]
        p = add(positions, "fff", "VEC3", 34962, 5126)
        n = add(normals, "fff", "VEC3", 34962, 5126)
        i = add(indices, "I", "SCALAR", 34963, 5125)
        # specularFactor 0: exactly Lambertian, as Mitsuba's diffuse BSDF (glTF's default adds a 4%
        # dielectric layer, whose Fresnel takes more of a low sun's light than of a high one's).
        gltf["materials"].append({"name": name, "pbrMetallicRoughness": {"baseColorFactor": colour + [1.0],
                                                                          "metallicFactor": 0.0, "roughnessFactor": 1.0},
                                  "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}})
        gltf["meshes"].append({"name": name, "primitives": [{"attributes": {"POSITION": p, "NORMAL": n}, "indices": i,
                                                             "material": len(gltf["materials"]) - 1}]})
        gltf["nodes"].append({"name": name, "mesh": len(gltf["meshes"]) - 1})
    eye, target = [0.8, 2.2, 7.5], [0.0, 1.0, 0.0]
    gltf["cameras"] = [{"type": "perspective", "perspective": {"yfov": math.radians(45.0), "aspectRatio": 4 / 3,
                                                               "znear": 0.01}}]
    gltf["nodes"].append({"name": "camera", "camera": 0, "translation": eye, "rotation": camera_quaternion(eye, target)})
    gltf["scenes"][0]["nodes"] = list(range(len(gltf["nodes"])))
    gltf["buffers"] = [{"uri": "envmap_scene.bin", "byteLength": len(binary)}]
    (work / "envmap_scene.bin").write_bytes(bytes(binary))
    (work / "envmap_scene.gltf").write_text(json.dumps(gltf, indent=1))
    sky = sky_map()
    mi.Bitmap(sky, pixel_format=mi.Bitmap.PixelFormat.RGB).write(str(work / "sky.exr"))
    with open(work / "sky.pfm", "wb") as file:  # PFM rows run bottom-up
        file.write(f"PF\n{sky.shape[1]} {sky.shape[0]}\n-1\n".encode())
        file.write(np.ascontiguousarray(sky[::-1]).astype("<f4").tobytes())
    print(f"wrote {work}/envmap_scene.gltf, sky.exr, sky.pfm; the sun towards {np.round(direction(SUN_U, 0.5 - SUN_ELEVATION / math.pi), 3)}")


def render(work, width, height, spp, variant, seeds):
    work = Path(work)
    to_world = {"identity": mi.ScalarTransform4f(),
                "turned": mi.ScalarTransform4f().rotate([0, 1, 0], 180),
                "mirrored": mi.ScalarTransform4f().scale([-1, 1, 1])}[variant]
    for seed in seeds:
        scene = scene_dict(work / "envmap_scene.gltf", width, height, spp, seed, work)
        scene["sky"] = {"type": "envmap", "filename": str(work / "sky.exr"), "to_world": to_world}
        image = mi.render(mi.load_dict(scene), spp=spp, seed=seed)
        out = work / (f"mitsuba_{seed}.exr" if variant == "identity" else f"mitsuba_{variant}_{seed}.exr")
        mi.util.write_bitmap(str(out), image)
        print(f"wrote {out}")


def analytic_ground(image, centred=True):
    """Radiance of an open horizontal Lambertian ground of albedo 0.5 under `image` (grey mean of
    RGB): 0.5 / pi x the irradiance, each texel's radiance over its solid angle times cos theta.
    centred: igi's texel rows, row j spanning theta in [j, j + 1] pi / H; else Mitsuba's as it
    renders (rows centred at v = j / (H - 1): row j spans [j - 1/2, j + 1/2] pi / (H - 1))."""
    height, width = image.shape[:2]
    irradiance = 0.0
    for j in range(height):
        if centred:
            t0, t1 = j / height * math.pi, (j + 1) / height * math.pi
        else:
            t0, t1 = max(0.0, (j - 0.5) / (height - 1)) * math.pi, min(1.0, (j + 0.5) / (height - 1)) * math.pi
        if t0 >= math.pi / 2:
            break
        t1 = min(t1, math.pi / 2)
        irradiance += image[j].mean(axis=-1).sum() * 0.5 * (math.sin(t1) ** 2 - math.sin(t0) ** 2) * 2 * math.pi / width
    return 0.5 / math.pi * irradiance


def ground(work, path_render, spp):
    """The ground quad alone under maps of one 5 x 3 texel sun (radiance 1500) at several
    elevations, and under the sky without its sun: each renderer's ground (the image's bottom third,
    80 x 60 pixels) over the analytic value."""
    import subprocess
    work = Path(work)
    gltf = json.loads((work / "envmap_scene.gltf").read_text())
    gltf["nodes"] = [n for n in gltf["nodes"] if n["name"] in ("ground", "camera")]
    gltf["scenes"][0]["nodes"] = list(range(len(gltf["nodes"])))
    (work / "ground.gltf").write_text(json.dumps(gltf, indent=1))
    sky = sky_map()
    maps = {}
    for row in (5, 20, 39, 55):
        image = np.zeros_like(sky)
        column = int(SUN_U * sky.shape[1])
        image[row - 1:row + 2, column - 2:column + 3] = 1500.0
        maps[f"sun at {90 - (row + 0.5) / sky.shape[0] * 180:4.1f} deg"] = image
    maps["sky without sun"] = np.where(sky.max(axis=2, keepdims=True) > 100, 0.0, sky).astype(np.float32)
    print(f"ground alone, 80 x 60, {spp} spp: the ground's mean radiance over the analytic value "
          "(igi's texel rows; Mitsuba's rows, v = j / (H - 1))")
    for k, (label, image) in enumerate(maps.items()):
        name = work / f"ground_map_{k}.exr"
        mi.Bitmap(image, pixel_format=mi.Bitmap.PixelFormat.RGB).write(str(name))
        subprocess.run([path_render, str(work / "ground.gltf"), "--environment", str(name), "--size", "80x60",
                        "--spp", str(spp), "-o", str(work / f"ground_igi_{k}.exr")], check=True, capture_output=True,
                       timeout=600)
        igi = np.array(mi.Bitmap(str(work / f"ground_igi_{k}.exr")))[40:, :, :3].mean()
        scene = scene_dict(work / "ground.gltf", 80, 60, spp, 0, work)
        scene["sky"] = {"type": "envmap", "filename": str(name)}
        mitsuba = np.array(mi.render(mi.load_dict(scene), spp=spp))[40:, :, :3].mean()
        centred, mitsuba_rows = analytic_ground(image), analytic_ground(image, centred=False)
        print(f"  {label:16}  analytic {centred:.4f} (Mitsuba's rows {mitsuba_rows:.4f})   igi {igi / centred:.4f}   "
              f"Mitsuba {mitsuba / centred:.4f} (over its rows' value {mitsuba / mitsuba_rows:.4f})", flush=True)


def main():
    if sys.argv[1] == "scene":
        write_scene(sys.argv[2])
    elif sys.argv[1] == "ground":
        ground(sys.argv[2], sys.argv[3], int(sys.argv[4]))
    else:
        render(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), sys.argv[6],
               [int(s) for s in sys.argv[7:]] or [0])


if __name__ == "__main__":
    main()
