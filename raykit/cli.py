"""The ``raykit`` command.

    raykit render SCENE.json -o OUT.png [--samples N | --spp N] [--engine auto|numpy|compiled]
    raykit scan SCENE2D.json -o strip.png [--diagram rays.png]   one line-scan
    raykit sweep SCENE2D.json -o sweep.png [--scans M]           M line-scans stacked
    raykit sweep SCENE.json -o sweep.png --scans M               the same, a 3D camera 1 pixel high
    raykit diagram SCENE.json -o rays.png [--view 3d|top|side|camera] [--rays K]

Bad input (a :class:`raykit.io.errors.SceneError`, or an output file that cannot be written) is
reported as one line on stderr with exit status 2, never as a traceback, and leaves no output
file behind. Output paths are checked (folder, permission, suffix) before any rendering, so a
long render is never thrown away for a typo in ``-o``.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

MAX_SAMPLES = 32
MOST_SPP = 4096  # a distributed render's samples per pixel, as the scene format allows


def _samples(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None
    if not 1 <= value <= MAX_SAMPLES:
        raise argparse.ArgumentTypeError(f"must be between 1 and {MAX_SAMPLES}, got {value}")
    return value


def _command(
    commands, name: str, *, summary: str, description: str, scene: str, output: str, samples: str
) -> argparse.ArgumentParser:
    """A subcommand with the arguments all share: the scene, -o and --samples."""
    parser = commands.add_parser(name, help=summary, description=description, allow_abbrev=False)
    parser.add_argument("scene", metavar=scene, help="the scene file")
    parser.add_argument("-o", "--output", required=True, metavar=output, help="image to write")
    parser.add_argument(
        "--samples",
        type=_samples,
        default=1,
        metavar="N",
        help=f"{samples} per pixel, averaged (1..{MAX_SAMPLES}; default 1)",
    )
    return parser


def build_parser() -> argparse.ArgumentParser:
    # allow_abbrev=False everywhere: "--sample 4" is an error, not a silent "--samples 4"
    parser = argparse.ArgumentParser(
        prog="raykit",
        description="raykit: the ray-tracing lecture's renderer and figures.",
        allow_abbrev=False,
    )
    parser.add_argument("--version", action=_VersionAction)
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    render = _command(
        commands,
        "render",
        summary="render a 3D scene (JSON, format v1, or NFF) to an image",
        description="Render a balls-and-billboards scene (JSON, format v1; or an NFF file of "
        "the Standard Procedural Databases) to an image.",
        scene="SCENE.json",
        output="OUT.png",
        samples="N x N rays",
    )
    render.add_argument(
        "--width",
        type=_positive,
        metavar="W",
        help="render W pixels wide, the height in the scene's proportion (default: the "
        "scene's own size; a projector wants 1200 wide or 675 high)",
    )
    render.add_argument(
        "--adaptive",
        action="store_true",
        help="take the N x N samples only at edges, where neighbouring pixels differ",
    )
    render.add_argument(
        "--spp",
        type=_spp,
        metavar="N",
        help="distributed ray tracing with N samples per pixel in place of the scene's "
        "render.samples_per_pixel, by its sampler (a square for jittered, a power of two for "
        f"sobol; 1..{MOST_SPP}): a quick preview of a stage 5 scene, or a converged picture",
    )
    _engine_option(render, "which engine renders")
    render.set_defaults(run=_run_render)

    scan = _command(
        commands,
        "scan",
        summary="one scan of a line-scan scene (JSON) as a strip image, and its ray diagram",
        description="Take one scan of a 2D line-scan scene: a strip of N pixels.",
        scene="SCENE2D.json",
        output="strip.png",
        samples="N rays",
    )
    scan.add_argument("--diagram", metavar="rays.png", help="also draw the ray diagram here")
    scan.add_argument(
        "--height",
        type=_positive,
        default=1,
        metavar="H",
        help="repeat the scan H times down the strip image, to see it better (default 1)",
    )
    scan.add_argument(
        "--scale",
        type=_positive,
        default=1,
        metavar="K",
        help="draw each pixel as a K x K block, so a short scan can be seen (default 1)",
    )
    scan.set_defaults(run=_run_scan)

    sweep = _command(
        commands,
        "sweep",
        summary="M scans of a moving line-scan scene (2D, or 3D one pixel high), stacked",
        description="Take M scans while camera and objects move. A 2D line-scan scene: scan m "
        "is image row m. A 3D scene (format v1) whose camera is one pixel high, its objects "
        'moving by their "velocity": scan m is image column m (a car driving through the '
        "camera's plane of view comes out as a picture of the car).",
        scene="SCENE.json",
        output="sweep.png",
        samples="N rays",
    )
    sweep.add_argument(
        "--scans",
        type=_positive,
        metavar="M",
        help='how many scans (default: a 2D scene\'s "scans"; a 3D scene needs it)',
    )
    sweep.add_argument(
        "--diagram",
        metavar="sweep_rays.png",
        help="also draw the world at three scan times above the growing image (2D scenes)",
    )
    _engine_option(sweep, "which engine renders a 3D scene's scans")
    sweep.set_defaults(run=_run_sweep)

    diagram = commands.add_parser(
        "diagram",
        help="draw a 3D scene's primary rays, or its camera",
        description="Draw a 3D scene (JSON, format v1) and the rays of every K-th pixel, from "
        "the eye to what they hit, in 3D or in a top or side view; or draw its camera "
        "(--view camera: perspective and orthographic side by side).",
        allow_abbrev=False,
    )
    diagram.add_argument("scene", metavar="SCENE.json", help="the scene file")
    diagram.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="rays.png",
        help="figure to write (.png, .svg, .pdf)",
    )
    diagram.add_argument(
        "--view",
        choices=("3d", "top", "side", "camera"),
        default="3d",
        help="what to draw (default 3d)",
    )
    diagram.add_argument(
        "--rays",
        type=_positive,
        metavar="K",
        help="draw the ray of every K-th pixel across and down (default: at most 8 a side)",
    )
    diagram.set_defaults(run=_run_diagram)

    bench = commands.add_parser(
        "bench",
        help="run the benchmarks (from a clone of the repository)",
        description="Run benchmarks/render_speed.py, time_vs_error.py, shading_cost.py, "
        "mitsuba_compare.py (Mitsuba 3 when installed), object_order.py, "
        "forward_backward.py and engines.py (numpy against compiled, and what auto "
        "chooses): tables of medians side by side, and with --plots, the plots.",
        allow_abbrev=False,
    )
    bench.add_argument("--quick", action="store_true", help="small images, a short run")
    bench.add_argument("--repeats", type=_positive, default=3, help="runs per variant (median)")
    bench.add_argument("--plots", metavar="FOLDER", help="write the plots into this folder")
    _engine_option(
        bench,
        "the engine of the raykit rows (mitsuba_compare.py times numpy and compiled side by side)",
    )
    bench.set_defaults(run=_run_bench)
    return parser


def _engine_option(parser: argparse.ArgumentParser, what: str) -> None:
    parser.add_argument(
        "--engine",
        choices=("auto", "numpy", "compiled"),  # raykit.engine.choice.ENGINES, which imports numpy
        default="auto",
        help=f"{what}: numpy, compiled (the same picture, faster; "
        + (
            "needs 'pip install \"raykit[fast]\"')"
            if (Path(__file__).parent / "engine" / "compiled").exists()
            else "not in the starter kit)"
        )
        + ", or auto, compiled only where it pays (default)",
    )


def _check_engine(engine: str) -> None:
    """Refuse ``--engine compiled`` without numba before any work, naming the fix."""
    from raykit.engine.choice import compiled_available, compiled_missing

    if engine == "compiled" and not compiled_available():
        raise ValueError(f"--engine compiled {compiled_missing()}")


class _VersionAction(argparse.Action):
    """``--version``: print the installed version and exit. The version is looked up only when
    asked: importing importlib.metadata is slow, and argparse's own version action would pay
    for it at each ``raykit render``."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS) -> None:
        super().__init__(
            option_strings,
            dest,
            default=argparse.SUPPRESS,
            nargs=0,
            help="show the version and exit",
        )

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        print(f"raykit {_version()}")
        parser.exit()


def _version() -> str:
    """The installed distribution's version (pyproject.toml's), from its metadata."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("raykit")
    except PackageNotFoundError:  # run from a source tree that was never installed
        return "(not installed)"


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None
    if not 1 <= value <= 16384:
        raise argparse.ArgumentTypeError(f"must be between 1 and 16384, got {value}")
    return value


def _spp(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None
    if not 1 <= value <= MOST_SPP:
        raise argparse.ArgumentTypeError(f"must be between 1 and {MOST_SPP}, got {value}")
    return value


def _with_spp(scene, spp: int, samples: int):
    """``scene`` rendered with ``spp`` samples per pixel of its own sampler (``--spp``), or a
    one-line ValueError where its sampler cannot take that many, or with ``--samples``."""
    from dataclasses import replace
    from math import isqrt

    if samples != 1:
        raise ValueError(
            f"--spp {spp} and --samples {samples}: --spp samples each pixel at random points "
            "(distributed ray tracing), --samples on an n x n grid; give one of them"
        )
    sampler = scene.sampling.sampler
    if sampler == "jittered" and isqrt(spp) ** 2 != spp:
        raise ValueError(
            f"--spp {spp}: {scene.source}'s sampler, jittered, takes n x n samples per pixel (a "
            f"square: 1, 4, 9, 16, ...), got {spp}"
        )
    if sampler == "sobol" and spp & (spp - 1):
        raise ValueError(
            f"--spp {spp}: {scene.source}'s sampler, sobol, takes a power of two samples per "
            f"pixel (1, 2, 4, 8, ...), got {spp}"
        )
    return replace(scene, sampling=replace(scene.sampling, samples_per_pixel=spp))


def _load_3d(path: str):
    """A 3D scene from JSON (format v1) or, for a .nff file, from NFF (raykit.io.nff)."""
    if path.lower().endswith(".nff"):
        from raykit.io.nff import load_nff

        return load_nff(path)
    from raykit.io.scene_json import load_scene

    return load_scene(path)


def _run_render(args: argparse.Namespace) -> None:
    from raykit.io.images import check_image_path, save_image
    from raykit.render import render

    _check_engine(args.engine)
    check_image_path(args.output)  # before the render, not after it is thrown away
    from raykit.engine.choice import choose
    from raykit.io.progress import progress_bar

    start = time.perf_counter()
    scene = _load_3d(args.scene)
    if args.width:  # the same view in more (or fewer) pixels of the same shape
        from dataclasses import replace

        height = max(1, round(args.width * scene.camera.height / scene.camera.width))
        scene = replace(scene, camera=replace(scene.camera, width=args.width, height=height))
    if args.spp is not None:
        scene = _with_spp(scene, args.spp, args.samples)
    elif scene.distributed and args.samples != 1:
        raise ValueError(
            f"{scene.source}: a distributed scene takes its samples from "
            f"render.samples_per_pixel, not --samples {args.samples}: --spp N renders it with N"
        )
    camera = scene.camera
    engine = choose(args.engine, scene, args.samples)
    # on a terminal, a bar of pixels done, tile by tile, once the render has taken a second
    with progress_bar(camera.width * camera.height, "render", "px") as advance:
        image = render(
            scene, samples=args.samples, adaptive=args.adaptive, progress=advance, engine=engine,
            hits=False,  # the PNG is the picture alone
        )  # fmt: skip
    save_image(image.rgb, args.output)
    seconds = time.perf_counter() - start
    sampling = scene.sampling
    samples = (
        f"{sampling.samples_per_pixel} {sampling.sampler} samples per pixel, seed {sampling.seed}"
        if scene.distributed
        else f"{args.samples}x{args.samples} samples per pixel"
    )
    print(
        f"wrote {args.output} ({camera.width}x{camera.height}, {samples}, {engine} engine) "
        f"in {seconds:.2f} s"
    )


def _run_scan(args: argparse.Namespace) -> None:
    import numpy as np

    from raykit.io.images import check_figure_path, check_image_path, save_image
    from raykit.io.linescan_json import load_line_scene
    from raykit.linescan.scan import scan

    check_image_path(args.output)
    if args.diagram:
        check_figure_path(args.diagram)

    start = time.perf_counter()
    scene = load_line_scene(args.scene)
    strip = scan(scene, samples=args.samples).colors
    rows = np.repeat(strip[None], args.height, axis=0)
    save_image(np.repeat(np.repeat(rows, args.scale, axis=0), args.scale, axis=1), args.output)
    wrote = [f"{args.output} ({scene.camera.pixels} pixels)"]
    if args.diagram:
        _save_figure("raykit.linescan.diagrams", "ray_diagram", scene, args.diagram)
        wrote.append(args.diagram)
    print(f"wrote {' and '.join(wrote)} in {time.perf_counter() - start:.2f} s")


def _run_sweep(args: argparse.Namespace) -> None:
    from raykit.io.fields import read_json_file, scene_kind
    from raykit.io.images import check_figure_path, check_image_path, save_image
    from raykit.io.linescan_json import load_line_scene
    from raykit.io.progress import progress_bar
    from raykit.linescan.scan import sweep

    check_image_path(args.output)
    if args.diagram:
        check_figure_path(args.diagram)
    if scene_kind(read_json_file(args.scene)[0]) == "3d":
        _run_sweep_3d(args)
        return

    start = time.perf_counter()
    scene = load_line_scene(args.scene)
    scans = args.scans or scene.scans
    with progress_bar(scans, "sweep", "scan") as advance:  # on a terminal, after a second
        taken = sweep(scene, scans, samples=args.samples, progress=advance)
    save_image(taken.image, args.output)
    wrote = [f"{args.output} ({scans} scans x {scene.camera.pixels} pixels)"]
    if args.diagram:
        _save_figure("raykit.linescan.diagrams", "sweep_diagram", scene, args.diagram, scans=scans)
        wrote.append(args.diagram)
    print(f"wrote {' and '.join(wrote)} in {time.perf_counter() - start:.2f} s")


def _run_sweep_3d(args: argparse.Namespace) -> None:
    """``raykit sweep`` of a 3D scene: one render of its one-pixel-high camera a scan."""
    from raykit.engine.choice import choose
    from raykit.io.images import save_image
    from raykit.io.progress import progress_bar
    from raykit.io.scene_json import load_scene
    from raykit.linescan.sweep3d import check_line_camera, sweep_3d

    if args.diagram:
        raise ValueError("--diagram: the sweep diagram is drawn for 2D line-scan scenes only")
    _check_engine(args.engine)
    start = time.perf_counter()
    scene = load_scene(args.scene)
    check_line_camera(scene)
    if args.scans is None:
        raise ValueError(f"{args.scene}: a 3D scene has no scans field: give --scans M")
    engine = choose(args.engine, scene, args.samples)
    with progress_bar(args.scans, "sweep", "scan") as advance:
        taken = sweep_3d(scene, args.scans, args.samples, progress=advance, engine=engine)
    save_image(taken.image, args.output)
    print(
        f"wrote {args.output} ({scene.camera.width} pixels x {args.scans} scans, "
        f"{engine} engine) in {time.perf_counter() - start:.2f} s"
    )


def _run_diagram(args: argparse.Namespace) -> None:
    from raykit.io.images import check_figure_path

    check_figure_path(args.output)
    start = time.perf_counter()
    scene = _load_3d(args.scene)
    if args.view == "camera":
        _save_figure("raykit.diagrams.camera", "camera_diagrams", scene.camera, args.output)
    else:
        _save_figure(
            "raykit.diagrams.rays",
            "ray_diagram",
            scene,
            args.output,
            view=args.view,
            every=args.rays,
        )
    print(f"wrote {args.output} in {time.perf_counter() - start:.2f} s")


def _run_bench(args: argparse.Namespace) -> None:
    import subprocess
    from pathlib import Path

    _check_engine(args.engine)
    folder = Path(__file__).resolve().parent.parent / "benchmarks"
    if not (folder / "render_speed.py").is_file():
        raise ValueError(
            "raykit bench runs from a clone of the repository: benchmarks/ is "
            f"not beside the installed package ({folder})"
        )
    scripts = (
        ("render_speed.py", "time_vs_objects.png"),
        ("time_vs_error.py", "time_vs_error.png"),
        ("shading_cost.py", "shading_cost.png"),
        ("mitsuba_compare.py", "mitsuba_compare.png"),
        ("object_order.py", "object_order.png"),
        ("forward_backward.py", "forward_backward.png"),
        ("engines.py", "engines.png"),
    )
    for number, (script, plot) in enumerate(scripts, 1):  # every script draws a plot
        command = [sys.executable, str(folder / script), "--repeats", str(args.repeats)]
        command += ["--quick"] if args.quick else []
        if script == "mitsuba_compare.py":  # the others time the numpy engine's own skips
            command += ["--engine", args.engine]
        if args.plots:
            Path(args.plots).mkdir(parents=True, exist_ok=True)
            command += ["--plot", str(Path(args.plots) / plot)]
        # a line as each script starts and ends, on stderr: the tables on stdout stay clean
        said = f"raykit bench: [{number}/{len(scripts)}] benchmarks/{script}"
        print(f"{said} ...", file=sys.stderr, flush=True)
        start = time.perf_counter()
        sys.stdout.flush()
        if subprocess.run(command).returncode != 0:
            raise ValueError(f"benchmarks/{script} failed")
        seconds = time.perf_counter() - start
        print(f"{said}: done in {seconds:.0f} s", file=sys.stderr, flush=True)
        print(flush=True)


def _save_figure(module: str, function: str, subject, path: str, **options) -> None:
    """Draw ``module.function(subject, **options)`` and write it to ``path``, whole or not."""
    import importlib

    import matplotlib

    matplotlib.use("Agg")  # files only: no window, works headless
    import matplotlib.pyplot as plt

    from raykit.io.images import save_figure

    figure = getattr(importlib.import_module(module), function)(subject, **options)
    try:
        save_figure(figure, path)
    finally:
        plt.close(figure)


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        args.run(args)
    except (ValueError, OSError) as exc:  # SceneError is a ValueError
        message = (
            str(exc)
            if not isinstance(exc, OSError) or not exc.filename
            else (f"{exc.filename}: {exc.strerror}")
        )
        print(f"raykit: error: {message}", file=sys.stderr)
        return 2
    except NotImplementedError as exc:  # the starter kit, before its functions are written
        print(f"raykit: error: not written yet: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C: outputs are written whole or not at all
        print("raykit: interrupted", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
