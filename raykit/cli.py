"""The ``raykit`` command: ``raykit render SCENE.json -o OUT.png [--samples N]``.

Bad input (a :class:`raykit.errors.SceneError`, or an output file that cannot be written) is
reported as one line on stderr with exit status 2, never as a traceback, and leaves no output
file behind.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence

MAX_SAMPLES = 32


def _samples(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None
    if not 1 <= value <= MAX_SAMPLES:
        raise argparse.ArgumentTypeError(f"must be between 1 and {MAX_SAMPLES}, got {value}")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="raykit", description="raykit: the ray-tracing lecture's renderer and figures."
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    render = commands.add_parser(
        "render",
        help="render a 3D scene (JSON, format v1) to an image",
        description="Render a balls-and-billboards scene (JSON, format v1) to an image.",
    )
    render.add_argument("scene", metavar="SCENE.json", help="the scene file")
    render.add_argument("-o", "--output", required=True, metavar="OUT.png", help="image to write")
    render.add_argument(
        "--samples",
        type=_samples,
        default=1,
        metavar="N",
        help=f"N x N rays per pixel, averaged (1..{MAX_SAMPLES}; default 1)",
    )
    render.set_defaults(run=_run_render)
    return parser


def _run_render(args: argparse.Namespace) -> None:
    from raykit.images import save_image
    from raykit.render import render
    from raykit.scene import load_scene

    start = time.perf_counter()
    scene = load_scene(args.scene)
    image = render(scene, samples=args.samples)
    save_image(image.rgb, args.output)
    seconds = time.perf_counter() - start
    camera = scene.camera
    print(
        f"wrote {args.output} ({camera.width}x{camera.height}, "
        f"{args.samples}x{args.samples} samples per pixel) in {seconds:.2f} s"
    )


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
    return 0


if __name__ == "__main__":
    sys.exit(main())
