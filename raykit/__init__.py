"""raykit: the ray-tracing lecture as code — cameras, rays, spheres, billboards, and the renderer.

The tree is the architecture, in three wings:

* **the lecture's math**, at the top, one noun a module, read in the lecture's order:
  :mod:`raykit.linescan` (stage 1, the 2D line-scan camera); :mod:`raykit.rays`,
  :mod:`raykit.planes`, :mod:`raykit.spheres` (stage 2); :mod:`raykit.camera`,
  :mod:`raykit.billboards`, :mod:`raykit.hits`, :mod:`raykit.scene` and the lecture's loops,
  :mod:`raykit.render` (image order), :mod:`raykit.object_order`, :mod:`raykit.forward` (light
  traced forward) and :mod:`raykit.pinhole` (stage 3); :mod:`raykit.lights`,
  :mod:`raykit.materials`, :mod:`raykit.surfaces`, :mod:`raykit.shading`, :mod:`raykit.shadows`,
  :mod:`raykit.mirrors` (stage 4, FOCG 4.5-4.9); and their figures, :mod:`raykit.diagrams`;
* **the engine**, :mod:`raykit.engine`: speed only, named for what it skips, never a different
  picture;
* **input and output**, :mod:`raykit.io`: scene files, textures, images.

The math imports nothing from the engine or io (``tests/test_layout.py``). Typical use::

    from raykit.io.scene_json import load_scene
    from raykit.render import render
    image = render(load_scene("scenes/classic.json"), samples=2)   # image.rgb: (H, W, 3)
"""

__version__ = "0.1.0"
