"""Stage 1 of the lecture: the 2D line-scan camera.

Read in this order: :mod:`raykit.linescan.camera` (e, w, u, D, pixel positions, rays),
:mod:`raykit.linescan.objects` (balls and billboards, with the 3D math reused in 2D),
:mod:`raykit.linescan.scene` (the JSON format and motion), :mod:`raykit.linescan.scan` (scans and
sweeps), :mod:`raykit.linescan.diagrams` (the pictures).
"""
