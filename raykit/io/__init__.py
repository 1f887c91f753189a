"""Input and output: files in, images out.

Scene files (:mod:`~raykit.io.scene_json` for the 3D format, :mod:`~raykit.io.linescan_json`
for the 2D one, :mod:`~raykit.io.nff` for NFF), read field by field with one-line errors
that name the file and the field (:mod:`~raykit.io.fields`, :mod:`~raykit.io.errors`,
``schemas/``); textures decoded from image files (:mod:`~raykit.io.textures`); images written
whole or not at all (:mod:`~raykit.io.images`).

Imports: io builds the lecture's objects (scene, spheres, billboards, camera, lights); the
math never imports io (``tests/test_layout.py`` checks it).
"""
