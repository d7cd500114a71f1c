"""igi: interactive global illumination (instant radiosity with SIMD ray packets) from Python.

    import igi
    scene = igi.load("scene.gltf")                      # or igi.builtin("cornell")
    renderer = igi.Renderer(scene, width=640, height=480, vpls=16)  # igi-render's options by name
    frame = renderer.render(frame=0)
    frame.hdr, frame.rgb8, frame.albedo, frame.normal, frame.depth, frame.statistics

docs/python.md describes the whole interface.
"""
from ._igi import *  # noqa: F401,F403 - the compiled module is the package's interface
from ._igi import __version__  # noqa: F401 - not among the names * brings
