"""raykit: the ray-tracing lecture as code — cameras, rays, spheres, billboards, and the renderer.

Read in the lecture's order: :mod:`raykit.rays`, :mod:`raykit.planes`, :mod:`raykit.spheres`,
:mod:`raykit.billboards`, :mod:`raykit.camera`, :mod:`raykit.scene`, :mod:`raykit.render`.
Typical use::

    from raykit.scene import load_scene
    from raykit.render import render
    image = render(load_scene("scenes/classic.json"), samples=2)   # image.rgb: (H, W, 3)
"""

__version__ = "0.1.0"
