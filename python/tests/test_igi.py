"""Tests of the Python module igi, against the module built from this tree and igi-render."""
import gc
import json
import os
import re
import subprocess
import threading
from pathlib import Path

import numpy as np
import pytest

import igi

REPOSITORY = Path(__file__).resolve().parents[2]
ANIMATED = REPOSITORY / "tests" / "data" / "animated" / "deforming.gltf"
IGI_RENDER = os.environ.get("IGI_RENDER", "")
# Small images keep each render (and igi-render run) well under a second.
SMALL = {"width": 48, "height": 36}
# The statistics that are measured times, different in every run.
TIMINGS = {"ms_per_frame", "fps", "mrays_per_s", "vpl_ms", "temporal_ms"}

needs_igi_render = pytest.mark.skipif(not Path(IGI_RENDER).is_file(),
                                      reason="IGI_RENDER does not name the igi-render program (built with IGI_BUILD_EXAMPLES)")


def read_pfm(path):
    """The linear RGB image of a PFM file, rows from the top (PFM stores them from the bottom)."""
    data = Path(path).read_bytes()
    header = data.split(b"\n", 3)
    assert header[0] == b"PF", "a colour PFM"
    width, height = map(int, header[1].split())
    scale = float(header[2])
    pixels = np.frombuffer(header[3], dtype="<f4" if scale < 0 else ">f4", count=width * height * 3)
    return pixels.reshape(height, width, 3)[::-1]


def keyword_arguments(options):
    """igi-render's command-line arguments for Renderer keyword arguments (the module's own mapping, written out)."""
    arguments = []
    for keyword, value in options.items():
        option = "--" + keyword.replace("_", "-")
        if value is True:
            arguments.append(option)
        elif keyword not in ("width", "height"):
            arguments += [option, str(value)]
    return arguments + ["--size", f"{options['width']}x{options['height']}"]


def igi_render(tmp_path, scene_arguments, options, output="out.pfm", stats=False):
    """Runs igi-render with the same options; returns its stdout."""
    command = [IGI_RENDER, *scene_arguments, "-o", str(tmp_path / output), *keyword_arguments(options)]
    if stats:
        command += ["--stats", "json"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout


@pytest.fixture(scope="module")
def cornell():
    return igi.builtin("cornell")


def test_the_package_has_a_version_and_a_packet_width():
    assert igi.__version__.count(".") == 2
    assert igi.packet_width in (4, 8, 16)  # one register of floats: SSE, AVX2 or AVX-512


def test_a_frame_has_images_of_the_documented_shapes_and_types(cornell):
    frame = igi.Renderer(cornell, **SMALL, vpls=8, seed=0).render(frame=0)
    assert frame.hdr.shape == (36, 48, 3) and frame.hdr.dtype == np.float32
    assert frame.rgb8.shape == (36, 48, 3) and frame.rgb8.dtype == np.uint8
    assert frame.albedo.shape == (36, 48, 3) and frame.albedo.dtype == np.float32
    assert frame.normal.shape == (36, 48, 3) and frame.normal.dtype == np.float32
    assert frame.depth.shape == (36, 48) and frame.depth.dtype == np.float32
    assert np.isfinite(frame.hdr).all() and frame.hdr.max() > 0.0
    assert frame.rgb8.max() > 0
    # Where the primary ray hit (positive depth): unit normals and some albedo; elsewhere zeros.
    hit = frame.depth > 0.0
    assert hit.mean() > 0.5  # the box fills most of the view
    lengths = np.linalg.norm(frame.normal, axis=2)
    assert np.allclose(lengths[hit], 1.0, atol=1e-4)  # float rounding of a normalised vector
    assert (lengths[~hit] == 0.0).all()
    assert (frame.albedo[hit].max(axis=1) > 0.0).all()


def test_arrays_share_the_frames_memory_and_keep_it_alive(cornell):
    frame = igi.Renderer(cornell, **SMALL, vpls=4).render()
    first, second = frame.hdr, frame.hdr
    assert first.__array_interface__["data"][0] == second.__array_interface__["data"][0]
    assert np.shares_memory(first, second)
    copy = first.copy()
    depth = frame.depth
    del frame, second
    gc.collect()
    np.testing.assert_array_equal(first, copy)  # the array still holds the frame
    assert depth.shape == (36, 48)


@needs_igi_render
@pytest.mark.parametrize("backend", ["embree", "reference"])
@pytest.mark.parametrize("options", [
    {"vpls": 8, "seed": 3},
    {"vpls": 4, "aa": 2, "filter": "atrous", "point_textures": True, "clamp": 0.05},
    {"integrator": "path", "spp": 3, "frames": 2, "seed": 5},
], ids=["igi", "igi-options", "path"])
def test_hdr_equals_igi_renders_pfm_bit_for_bit(tmp_path, cornell, backend, options):
    options = {**SMALL, **options, "backend": backend, "aov": True}
    frame = igi.Renderer(cornell, **options).render(frame=0)
    igi_render(tmp_path, ["--builtin", "cornell"], options)
    reference = read_pfm(tmp_path / "out.pfm")
    assert reference.shape == frame.hdr.shape
    assert np.array_equal(frame.hdr, reference)
    # igi-render --aov writes the G-buffer the frame holds.
    assert np.array_equal(frame.albedo, read_pfm(tmp_path / "out_albedo.pfm"))
    assert np.array_equal(frame.normal, read_pfm(tmp_path / "out_normal.pfm"))
    depth = read_pfm(tmp_path / "out_depth.pfm")
    assert np.array_equal(depth[..., 0], frame.depth) and np.array_equal(depth[..., 2], frame.depth)


@needs_igi_render
def test_an_animated_sequence_and_a_files_animation_equal_igi_render(tmp_path, cornell):
    options = {**SMALL, "vpls": 4, "animate": "object", "frames": 3, "temporal": 0}  # frames by themselves
    renderer = igi.Renderer(cornell, **{k: v for k, v in options.items() if k != "frames"})
    frames = [renderer.render(frame=i).hdr.copy() for i in range(3)]
    igi_render(tmp_path, ["--builtin", "cornell"], options, output="seq.pfm")
    for i, hdr in enumerate(frames):
        assert np.array_equal(hdr, read_pfm(tmp_path / f"seq_{i:04d}.pfm")), f"frame {i}"
    assert not np.array_equal(frames[0], frames[2])  # the object moved
    averaged = {**SMALL, "vpls": 4, "temporal": 4, "frames": 3}  # igi-render writes the last of its frames
    renderer = igi.Renderer(cornell, **{k: v for k, v in averaged.items() if k != "frames"})
    last = [renderer.render(frame=i) for i in range(3)][-1]
    igi_render(tmp_path, ["--builtin", "cornell"], averaged, output="averaged.pfm")
    assert np.array_equal(last.hdr, read_pfm(tmp_path / "averaged.pfm"))
    timed = {**SMALL, "vpls": 4, "time": 0.5}
    frame = igi.Renderer(igi.load(str(ANIMATED)), **timed).render()
    igi_render(tmp_path, [str(ANIMATED)], timed, output="timed.pfm")
    assert np.array_equal(frame.hdr, read_pfm(tmp_path / "timed.pfm"))


@needs_igi_render
def test_a_walk_along_a_camera_path_equals_igi_render(tmp_path):
    room_path = REPOSITORY / "bench" / "walkthrough" / "paths" / "room.gltf"
    window = igi.builtin("window")
    options = {**SMALL, "vpls": 4, "camera_path": str(room_path), "fps": 2, "frames": 3, "temporal": 0}
    renderer = igi.Renderer(window, **{k: v for k, v in options.items() if k != "frames"})
    frames = [renderer.render(frame=i).hdr.copy() for i in range(3)]
    igi_render(tmp_path, ["--builtin", "window"], options, output="walk.pfm")
    # Up to float rounding: the module and igi-render are compiled apart, and GCC may fuse
    # multiplies and adds differently in each as it inlines, so a frame can differ in its last bits
    # (frames 0 and 1 by up to 2.8e-6 relative on an AMD EPYC with AVX2, frame 2 not at all).
    for i, hdr in enumerate(frames):
        assert np.allclose(hdr, read_pfm(tmp_path / f"walk_{i:04d}.pfm"), rtol=1e-5, atol=1e-7), f"frame {i}"
    assert not np.allclose(frames[0], frames[2], rtol=1e-3)  # the view moved along the path


@needs_igi_render
def test_statistics_are_igi_renders_stats_json(tmp_path, cornell):
    options = {**SMALL, "vpls": 8, "temporal": 0}  # the Renderer's default; igi-render's is 32
    statistics = igi.Renderer(cornell, **options).render().statistics
    printed = json.loads(igi_render(tmp_path, ["--builtin", "cornell"], options, stats=True))
    assert set(statistics) == set(printed)
    for name in set(printed) - TIMINGS - {"output"}:
        assert statistics[name] == printed[name], name
    assert statistics["ms_per_frame"] > 0.0


@needs_igi_render
def test_temporal_reuse_is_off_unless_asked_where_igi_render_has_it_on(tmp_path, cornell):
    assert igi.Renderer(cornell, **SMALL).render().statistics["temporal_frames"] == 0
    assert igi.Renderer(cornell, **SMALL, temporal=8).render().statistics["temporal_frames"] == 8
    assert json.loads(igi_render(tmp_path, ["--builtin", "cornell"], SMALL, stats=True))["temporal_frames"] == 32


@needs_igi_render
def test_every_igi_render_option_is_a_keyword(cornell):
    help_text = subprocess.run([IGI_RENDER, "--help"], capture_output=True, text=True, timeout=60).stdout
    options = sorted(set(re.findall(r"--([a-z][a-z0-9-]+)", help_text)) - {"help"})
    assert "vpls" in options and "integrator" in options
    for option in options:
        keyword = option.replace("-", "_")
        for value in (True, "no such value"):
            try:
                igi.Renderer(cornell, width=8, height=8, **{keyword: value})
            except TypeError as error:
                assert "unexpected keyword" not in str(error), error
            except (ValueError, igi.Error, KeyError):
                pass


def test_an_unknown_keyword_is_a_type_error_naming_it(cornell):
    with pytest.raises(TypeError, match="vplz"):
        igi.Renderer(cornell, vplz=16)


@pytest.mark.parametrize("keywords, message", [
    ({"vpls": "many"}, "vpls"),
    ({"filter": "blurry"}, "filter"),
    ({"interleave": 0}, "interleave"),
    ({"backend": "saarcor"}, "saarcor"),
    ({"size": "10x"}, "WIDTHxHEIGHT"),
    ({"camera": "nowhere"}, "nowhere"),
    ({"width": 0}, "size"),
])
def test_a_bad_argument_is_a_value_error_with_igis_message(cornell, keywords, message):
    with pytest.raises(ValueError, match=message):
        igi.Renderer(cornell, **keywords)


def test_bad_files_raise_igis_errors(tmp_path):
    with pytest.raises(igi.SceneError, match="missing.gltf"):
        igi.load(str(tmp_path / "missing.gltf"))
    broken = tmp_path / "broken.gltf"
    broken.write_text("{ not json")
    with pytest.raises(igi.SceneError, match="broken.gltf"):
        igi.load(str(broken))
    with pytest.raises(ValueError, match="no built-in scene"):
        igi.builtin("attic")
    with pytest.raises(igi.ImageError):
        igi.read_image(str(tmp_path / "missing.exr"))


def test_the_path_tracer_converges_towards_what_igi_renders(cornell):
    igi_frame = igi.Renderer(cornell, **SMALL, vpls=16).render()
    few = igi.Renderer(cornell, **SMALL, integrator="path", spp=1).render()
    many = igi.Renderer(cornell, **SMALL, integrator="path", spp=16).render()
    assert few.statistics["spp_total"] == 1 and many.statistics["spp_total"] == 16
    assert igi.rmse(igi_frame.hdr, many.hdr) < igi.rmse(igi_frame.hdr, few.hdr)


def test_the_path_tracers_g_buffer_is_the_igi_frames(cornell):
    igi_frame = igi.Renderer(cornell, **SMALL, vpls=4, aa=1).render()
    path_frame = igi.Renderer(cornell, **SMALL, integrator="path", spp=1).render()
    igi_hit, path_hit = igi_frame.depth > 0.0, path_frame.depth > 0.0
    # The same camera rays, made a packet at a time by the pipeline and one by one by the path
    # tracer, through Embree's packet and single-ray kernels: equal up to float rounding (bit for
    # bit with AVX-512's 16 lanes, measured), which can send a ray past a silhouette; 1 % of the
    # pixels is 17 of them here, about the pixels the box's silhouettes cross.
    assert (igi_hit != path_hit).mean() <= 0.01
    both = igi_hit & path_hit
    assert both.mean() > 0.5
    # Rounding in the last bits of a direction moves a hit by about 1e-7 of its distance (the
    # normals and albedos, interpolated at the hit, by as little); 1e-5 is a hundred such steps.
    np.testing.assert_allclose(path_frame.depth[both], igi_frame.depth[both], rtol=1e-5)
    np.testing.assert_allclose(path_frame.normal[both], igi_frame.normal[both], atol=1e-5)
    np.testing.assert_allclose(path_frame.albedo[both], igi_frame.albedo[both], atol=1e-5)


def test_cameras_by_name_by_look_at_and_by_field_of_view(cornell):
    renderer = igi.Renderer(cornell, **SMALL, vpls=4)
    default = renderer.render().hdr
    assert renderer.camera.name == cornell.cameras[0].name
    assert np.array_equal(renderer.render(camera=cornell.cameras[0].name).hdr, default)
    origin = np.array(cornell.cameras[0].position)
    forward = -cornell.cameras[0].to_world[:3, 2]  # cameras look down their -Z
    camera = igi.look_at(origin=origin, target=origin + forward, fov=60)
    assert camera.fov == pytest.approx(60.0)
    wide = renderer.render(camera=camera).hdr
    camera.fov = 30
    narrow = renderer.render(camera=camera).hdr
    assert wide.max() > 0.0 and narrow.max() > 0.0
    assert not np.array_equal(wide, narrow) and not np.array_equal(wide, default)
    with pytest.raises(KeyError):
        renderer.render(camera="nowhere")
    with pytest.raises(ValueError):
        igi.look_at(origin=(0, 0, 0), target=(0, 0, 0))


def test_moving_an_instance_changes_the_image_and_moving_it_back_restores_it(cornell):
    renderer = igi.Renderer(cornell, **SMALL, vpls=4)
    before = renderer.render(frame=0).hdr.copy()
    name = cornell.instances[-1]
    original = cornell.instance_transform(name)
    moved = original.copy()
    moved[0, 3] += 100.0  # along x, in the box's millimetre-sized units
    renderer.set_instance_transform(name, moved)
    assert not np.array_equal(renderer.render(frame=0).hdr, before)
    renderer.set_instance_transform(name, original)
    np.testing.assert_array_equal(renderer.render(frame=0).hdr, before)
    with pytest.raises(IndexError):
        renderer.set_instance_transform(len(cornell.instances), original)


def test_a_brighter_light_brightens_the_image():
    scene = igi.builtin("window")
    assert scene.lights, "the window room has a sun"
    renderer = igi.Renderer(scene, **SMALL, vpls=4)
    before = renderer.render().hdr.mean()
    light = scene.lights[0]
    light.intensity *= 4.0
    renderer.set_light(0, light)
    assert renderer.render().hdr.mean() > before


def test_the_environment_lights_the_scene():
    scene = igi.builtin("window-sky")
    lit = igi.Renderer(scene, **SMALL, vpls=4).render().hdr.mean()
    dark = igi.Renderer(scene, **SMALL, vpls=4, environment="none").render().hdr.mean()
    assert dark < lit


def test_the_files_animation_at_a_time():
    scene = igi.load(str(ANIMATED))
    assert scene.animations
    renderer = igi.Renderer(scene, **SMALL, vpls=4)
    start, later = renderer.render(time=0.0).hdr.copy(), renderer.render(time=0.5).hdr
    assert not np.array_equal(start, later)
    with pytest.raises(ValueError, match="has no animation"):  # a time the scene cannot play, as igi-render's usage error
        igi.Renderer(igi.builtin("cornell"), **SMALL, time=0.5)


def test_metrics_are_the_usual_formulas():
    rng = np.random.default_rng(1)
    reference = rng.random((20, 30, 3), dtype=np.float32)
    test = reference + rng.normal(0.0, 0.1, reference.shape).astype(np.float32)
    assert igi.rmse(reference, reference) == 0.0
    # igi sums in double in another order than numpy: agreement to float precision.
    expected_rmse = np.sqrt(np.mean((test.astype(np.float64) - reference) ** 2))
    assert igi.rmse(test, reference) == pytest.approx(expected_rmse, rel=1e-6)
    expected_relmse = np.mean((test.astype(np.float64) - reference) ** 2 / (reference.astype(np.float64) ** 2 + 0.01))
    assert igi.relmse(test, reference) == pytest.approx(expected_relmse, rel=1e-6)
    assert igi.ssim(reference, reference) == pytest.approx(1.0)
    with pytest.raises(ValueError):
        igi.rmse(test, reference[:10])


def test_frames_write_png_exr_and_pfm(tmp_path, cornell):
    frame = igi.Renderer(cornell, **SMALL, vpls=4).render()
    for name in ("frame.png", "frame.exr", "frame.pfm"):
        frame.write(str(tmp_path / name))
    assert (tmp_path / "frame.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert np.array_equal(read_pfm(tmp_path / "frame.pfm"), frame.hdr)
    assert np.array_equal(igi.read_image(str(tmp_path / "frame.pfm")), frame.hdr)
    assert igi.read_image(str(tmp_path / "frame.exr")).shape == frame.hdr.shape
    igi.write_image(str(tmp_path / "albedo.pfm"), frame.albedo)
    assert np.array_equal(read_pfm(tmp_path / "albedo.pfm"), frame.albedo)
    with pytest.raises(igi.ImageError):
        frame.write(str(tmp_path / "frame.bmp"))


def test_rendering_releases_the_gil(cornell):
    renderer = igi.Renderer(cornell, width=320, height=240, vpls=16, aa=4, backend="reference")
    thread = threading.Thread(target=renderer.render)
    thread.start()
    turns = 0
    while thread.is_alive():
        turns += 1
        threading.Event().wait(0.001)
    thread.join()
    # Held through the render (hundreds of milliseconds), the GIL would let this loop run once or twice.
    assert turns > 20


def test_threads_may_share_a_renderer(cornell):
    renderer = igi.Renderer(cornell, **SMALL, vpls=4)
    expected = renderer.render(frame=1).hdr.copy()
    results = [None] * 4

    def render(slot):
        results[slot] = renderer.render(frame=1).hdr

    threads = [threading.Thread(target=render, args=(slot,)) for slot in range(len(results))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for hdr in results:
        assert np.array_equal(hdr, expected)
