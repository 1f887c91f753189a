"""Figures of the 3D stages, drawn from the renderer's own rays and the math's own functions.

:mod:`raykit.diagrams.camera` (the u, v, w frame, frustum and image plane),
:mod:`raykit.diagrams.rays` (a scene's primary rays in 3D, top or side view),
:mod:`raykit.diagrams.math_figures` (the ray–sphere cases, ray–plane, the dot product),
:mod:`raykit.diagrams.distributed` (stage 5: the sampled rays of one pixel, for each effect of
distributed ray tracing).
Every function takes an optional matplotlib axes and returns the figure. The line-scan
stage has its own: :mod:`raykit.linescan.diagrams`.
"""
