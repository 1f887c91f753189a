"""The engine: speed only, never a different picture.

Everything here makes the lecture's loop (:mod:`raykit.render`) faster by skipping work a
scene does not need, and each skip is tested to give exactly the image that testing every
object gives: tiles of pixels and the objects seen in them (:mod:`~raykit.engine.tiles`,
:mod:`~raykit.engine.screen_bounds`, :mod:`~raykit.engine.pairs`), the region plumbing
(:mod:`~raykit.engine.regions`), boxes and a bounding volume hierarchy for shadow and mirror
rays (:mod:`~raykit.engine.boxes`, :mod:`~raykit.engine.bvh`), extra samples only at edges
(:mod:`~raykit.engine.adaptive`), single precision near the eye
(:mod:`~raykit.engine.precision`), and the per-scene arrays they share
(:mod:`~raykit.engine.arrays`). Beside this numpy engine, the compiled one
(:mod:`~raykit.engine.compiled`, numba, ``raykit[fast]``) runs the same loop one ray at a time
in machine code, and :mod:`~raykit.engine.choice` decides which of the two renders.

Imports: the engine may use the lecture's math (rays, spheres, billboards, camera, hits, scene,
shading); the math never imports the engine (``tests/test_layout.py`` checks both).
"""
