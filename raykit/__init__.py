"""raykit: the ray-tracing lecture as code — cameras, rays, spheres, billboards, and the renderer.

Read in the lecture's order:

1. the line-scan camera: :mod:`raykit.linescan` (camera, objects, scene, scan, diagrams);
2. the math: :mod:`raykit.rays`, :mod:`raykit.planes`, :mod:`raykit.spheres`;
3. the renderer: :mod:`raykit.billboards`, :mod:`raykit.camera`, :mod:`raykit.scene`,
   :mod:`raykit.render`, and its figures in :mod:`raykit.diagrams`.

Beside the renderer, named for what they skip: :mod:`raykit.tiles` and
:mod:`raykit.screen_bounds` (objects a tile cannot see), :mod:`raykit.adaptive` (extra rays in
flat areas). Typical use::

    from raykit.scene import load_scene
    from raykit.render import render
    image = render(load_scene("scenes/classic.json"), samples=2)   # image.rgb: (H, W, 3)
"""

__version__ = "0.1.0"
