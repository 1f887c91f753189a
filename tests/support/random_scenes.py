"""Random scene files of every kind the scene format allows, from a seeded numpy Generator, for
the two engines' agreement campaign (``benchmarks/engine_agreement.py``) and its test
(``tests/compiled/test_render.py``).

:func:`random_scene` gives a scene file's contents (read by ``scene_from_dict``, whose checks
it passes), the render's options and the kinds of thing the scene has; :func:`make_textures`
writes the PNG files its billboards name. What the scenes span is listed in the benchmark's
docstring.
"""

from __future__ import annotations

import math

import numpy as np

from raykit.camera import Camera
from raykit.rays import dot, normalize

PRIMES = [p for p in range(2, 294) if all(p % k for k in range(2, int(p**0.5) + 1))]
ODD_SIZES = [(1, 1), (1, 37), (37, 1), (97, 3), (3, 97), (2, 2), (293, 2)]
PIXEL_BUDGET = 30000  # pixels x samples per scene at most: the numpy engine's time
# (lower bound, upper bound) of the object count's buckets, and how often each is drawn
COUNT_BUCKETS = [(0, 0), (1, 8), (9, 64), (65, 400), (401, 1500)]
COUNT_WEIGHTS = [0.08, 0.3, 0.27, 0.2, 0.15]
GEOMETRY = ("center", "radius", "color", "upper_left", "lower_left", "upper_right", "image")


def _unit(rng: np.random.Generator) -> np.ndarray:
    return normalize(rng.normal(size=3))


def _decades(rng: np.random.Generator, low: float, high: float) -> float:
    """10 to a power drawn uniformly from [low, high) (math.pow: the same bits on every
    processor, which numpy's vectorised power does not promise)."""
    return math.pow(10.0, rng.uniform(low, high))


def _color(rng: np.random.Generator) -> list[float]:
    """A colour, now and then with exact 0 and 1 channels."""
    c = rng.uniform(size=3)
    if rng.uniform() < 0.2:
        c = rng.choice([0.0, 1.0], size=3)
    return c.tolist()


def make_textures(rng: np.random.Generator, folder, count: int = 10) -> list[str]:
    """``count`` small random PNG files in ``folder``, from 1x1 to 16x16 texels: RGBA with
    holes (alpha 0, 127, 128, 255 and random), RGB, grey with alpha; their names."""
    from PIL import Image

    folder.mkdir(parents=True, exist_ok=True)
    names = []
    for k in range(count):
        height, width = (int(x) for x in rng.integers(1, 17, size=2))
        if k < 2:
            height, width = [(1, 1), (1, 7)][k]
        rgba = rng.integers(0, 256, size=(height, width, 4), dtype=np.uint8)
        rgba[..., 3] = rng.choice(
            [0, 127, 128, 255, *rng.integers(0, 256, size=2)], (height, width)
        )
        mode = ["RGBA", "RGBA", "RGB", "LA"][k % 4]
        image = Image.fromarray(rgba, "RGBA").convert(mode)
        name = f"texture_{k}_{mode}_{width}x{height}.png"
        image.save(folder / name)
        names.append(name)
    return names


class View:
    """Where a scene's camera looks: ``eye``, unit ``w`` (toward lookat), ``distance`` to
    lookat, ``fov`` and ``projection``, and the camera itself (to aim at pixel centres)."""

    def __init__(self, rng, tags, offset, size):
        self.eye = offset + rng.normal(size=3) * size
        w = _unit(rng)
        if rng.uniform() < 0.2:  # along an axis, the up exactly square to it
            w = np.zeros(3)
            w[rng.integers(3)] = rng.choice([-1.0, 1.0])
        self.w = w
        self.distance = size * _decades(rng, -1, 1)
        self.up = _unit(rng) if rng.uniform() < 0.6 else np.array([0.0, 1.0, 0.0])
        if abs(dot(normalize(self.up), w)) > 0.99:
            self.up = np.cross(w, _unit(rng))
        extreme = rng.uniform() < 0.25
        self.fov = float(rng.choice([1.0, 2.5, 160.0, 179.0]) if extreme else rng.uniform(5, 150))
        if extreme:
            tags.add("fov_angle 1, 2.5, 160 or 179 degrees")
        self.projection = "orthographic" if rng.uniform() < 0.3 else "perspective"
        tags.add(f"{self.projection} camera")
        self.camera = None

    def half_height(self, depth: float) -> float:
        """Half the height the camera sees at ``depth`` along w."""
        across = depth if self.projection == "perspective" else self.distance
        return math.tan(math.radians(self.fov) / 2) * abs(across)

    def place(self, rng, behind=False):
        """``(point, half_height)``: a point in (or near) the camera's view, or behind it,
        and half the height seen at its depth."""
        depth = self.distance * _decades(rng, -1, 1) * (-1 if behind else 1)
        h = self.half_height(depth)
        return self.eye + self.w * depth + rng.normal(size=3) * h * 0.7, h

    def on_a_pixel_ray(self, rng):
        """A point on the ray through a random pixel's centre, and that ray's direction."""
        from raykit.camera import rays_through

        c = self.camera
        x = np.array([rng.integers(c.width) + 0.5])
        y = np.array([rng.integers(c.height) + 0.5])
        origins, directions = rays_through(c, x, y)
        depth = self.distance * _decades(rng, -1, 1)
        return origins[0] + depth * directions[0], directions[0]


def _image_size(rng, samples, tags):
    if rng.uniform() < 0.2:
        width, height = ODD_SIZES[rng.integers(len(ODD_SIZES))]
        tags.add("odd image size (1x1, 1x37, 97x3, ...)")
        return width, height
    area = PIXEL_BUDGET / samples**2 * rng.uniform(0.05, 1)
    aspect = _decades(rng, -0.7, 0.7)
    # primes, so that no tile side divides them
    width, height = (_prime_near(x) for x in (math.sqrt(area * aspect), math.sqrt(area / aspect)))
    return width, height


def _prime_near(x: float) -> int:
    return min(PRIMES, key=lambda p: abs(p - x))


def _material(rng, textured: bool) -> dict:
    if rng.uniform() < 0.35:
        return {}
    out = {}
    if not textured and rng.uniform() < 0.3:
        out["diffuse"] = _color(rng)
    if rng.uniform() < 0.5:
        out["specular"] = _color(rng)
    if rng.uniform() < 0.6:
        out["shininess"] = float(
            rng.choice([1.0, 32.0, 0.5, *(_decades(rng, -1, 3) for _ in range(2))])
        )
    if rng.uniform() < 0.3:
        out["mirror"] = [1.0, 1.0, 1.0] if rng.uniform() < 0.3 else _color(rng)
    return out


def _billboard(rng, tags, view, crowd, textures):
    behind = rng.uniform() < 0.08
    corner, h = view.place(rng, behind)
    extent = h * _decades(rng, -1.5, -0.2) * crowd
    a, b = _unit(rng) * extent, _unit(rng) * extent * _decades(rng, -0.5, 0.5)
    kind = rng.uniform()
    if kind < 0.15:  # edge-on: the eye in its plane
        b = (view.eye - corner) + rng.uniform(-1, 1) * a
        tags.add("billboard edge-on to the eye")
    elif kind < 0.3:  # square to an axis, a ground or a wall
        axes = rng.permutation(3)[:2]
        a, b = np.zeros(3), np.zeros(3)
        a[axes[0]], b[axes[1]] = extent, extent * rng.choice([-1.0, 1.0])
    if behind:
        tags.add("object behind the camera")
    if abs(np.cross(a, b)).max() <= 1e-9 * max(abs(a).max(), abs(b).max()) ** 2:
        b = b + _unit(rng) * extent  # collinear edges: the loader refuses those
    board = {
        "upper_left": corner.tolist(),
        "lower_left": (corner + b).tolist(),
        "upper_right": (corner + a).tolist(),
    }
    textured = rng.uniform() < 0.5
    if textured:
        board["image"] = "textures/" + textures[rng.integers(len(textures))]
        tags.add("textured billboard (holes)")
    else:
        board["color"] = _color(rng)
    return board


def _sphere(rng, tags, view, crowd):
    behind = rng.uniform() < 0.08
    if behind:
        tags.add("object behind the camera")
    center, h = view.place(rng, behind)
    radius = h * _decades(rng, -1.7, -0.4) * crowd
    return {"center": center.tolist(), "radius": float(radius), "color": _color(rng)}


def _special_spheres(rng, tags, view, size):
    """Now and then: tiny spheres on pixels' rays (radius 1e-4 of the scene, and 1e-4 across
    if the scene is large), a huge sphere, the camera inside a sphere."""
    out = []
    if rng.uniform() < 0.2:
        for _ in range(int(rng.integers(1, 6))):
            center, _ = view.on_a_pixel_ray(rng)
            radius = 1e-4 * min(size, 1.0) * _decades(rng, -1, 0)
            out.append({"center": center.tolist(), "radius": radius, "color": _color(rng)})
        tags.add("tiny spheres on pixels' rays (radius 1e-5 to 1e-4)")
    if rng.uniform() < 0.08:
        radius = view.distance * _decades(rng, 2, 3)
        center = view.eye + _unit(rng) * radius * rng.uniform(1.0, 1.5)
        out.append({"center": center.tolist(), "radius": radius, "color": _color(rng)})
        tags.add("huge sphere (100 to 1000 times the view's distance)")
    if rng.uniform() < 0.08:
        radius = view.distance * _decades(rng, -0.5, 1)
        inside = view.eye + _unit(rng) * radius * rng.uniform(0, 0.95)
        out.append({"center": inside.tolist(), "radius": radius, "color": _color(rng)})
        tags.add("camera inside a sphere")
    return out


def _lights(rng, tags, view, spheres, boards):
    lights = []
    for _ in range(int(rng.integers(0, 5))):
        kind = rng.uniform()
        light: dict = {"type": "point", "color": (rng.uniform(0, 1.5, size=3)).tolist()}
        if kind < 0.25:
            light["type"], light["direction"] = "directional", _unit(rng).tolist()
            tags.add("directional light")
        elif kind < 0.35:
            direction = np.zeros(3)
            direction[rng.integers(3)] = rng.choice([-1.0, 1.0]) * _decades(rng, -3, 3)
            light["type"], light["direction"] = "directional", direction.tolist()
            tags.add("directional light")
        elif kind < 0.5 and spheres:
            s = spheres[rng.integers(len(spheres))]
            light["position"] = s["center"]
            tags.add("point light inside an object")
        elif kind < 0.65 and spheres:
            s = spheres[rng.integers(len(spheres))]
            light["position"] = (np.array(s["center"]) + s["radius"] * _unit(rng)).tolist()
            tags.add("point light on a surface")
        elif kind < 0.72 and boards:
            b = boards[rng.integers(len(boards))]
            ul, ll, ur = (np.array(b[k]) for k in ("upper_left", "lower_left", "upper_right"))
            light["position"] = (
                ul + rng.uniform() * (ur - ul) + rng.uniform() * (ll - ul)
            ).tolist()
            tags.add("point light on a surface")
        elif kind < 0.77:
            light["position"] = view.eye.tolist()
            tags.add("point light at the eye")
        else:
            light["position"] = view.place(rng, rng.uniform() < 0.3)[0].tolist()
        lights.append(light)
    return lights


def random_scene(rng: np.random.Generator, textures: list[str]) -> tuple[dict, dict, set[str]]:
    """A random scene file's contents, the render's options (samples, adaptive), and the
    kinds of thing it has, ``tags``. ``textures``: names of PNG files under ``textures/``."""
    tags: set[str] = set()
    far = rng.uniform() < 0.3
    offset = _unit(rng) * _decades(rng, 5, 6) if far else np.zeros(3)
    tags.add("far away (1e5 to 1e6 from the origin)" if far else "near the origin")
    size = _decades(rng, -3, 3) if rng.uniform() < 0.4 else 1.0
    view = View(rng, tags, offset, size)
    samples = int(rng.choice([1, 1, 1, 2, 2, 3, 4, 5, 8]))
    adaptive = samples > 1 and rng.uniform() < 0.4
    width, height = _image_size(rng, samples, tags)
    view.camera = Camera(view.eye, view.eye + view.w * view.distance, view.up, view.fov,
                         width, height, view.projection)  # fmt: skip
    low, high = COUNT_BUCKETS[rng.choice(len(COUNT_BUCKETS), p=COUNT_WEIGHTS)]
    count = int(rng.integers(low, high + 1))
    tags.add(f"{low:,}" + (f" to {high:,}" if high > low else "") + " objects")
    crowd = math.sqrt(min(1.0, 10 / max(count, 1)))  # smaller objects in a crowd: most stay seen
    board_count = int(round(count * rng.choice([0.0, 0.1, 0.3, 0.7, 1.0])))
    spheres = [_sphere(rng, tags, view, crowd) for _ in range(count - board_count)]
    boards = [_billboard(rng, tags, view, crowd, textures) for _ in range(board_count)]
    for special in _special_spheres(rng, tags, view, size) if count else ():
        spheres.insert(int(rng.integers(len(spheres) + 1)), special)
    shading = rng.choice(["flat", "materials without lights", "lit"], p=[0.3, 0.1, 0.6])
    for objects in (spheres, boards):
        if objects and rng.uniform() < 0.3:  # exact ties: repeats, another colour, anywhere
            for _ in range(int(rng.integers(1, 1 + max(1, len(objects) // 4)))):
                copy = {**objects[rng.integers(len(objects))]}
                if "color" in copy:
                    copy["color"] = _color(rng)
                objects.insert(int(rng.integers(len(objects) + 1)), copy)
            tags.add("repeated objects (exact ties)")
    for objects in (spheres, boards):
        for k, thing in enumerate(objects):
            if shading != "flat":
                objects[k] = {**thing, **_material(rng, "image" in thing)}
            else:
                objects[k] = {key: v for key, v in thing.items() if key in GEOMETRY}
    data: dict = {
        "camera": {
            "eye": view.eye.tolist(),
            "lookat": (view.eye + view.w * view.distance).tolist(),
            "up": view.up.tolist(),
            "fov_angle": view.fov,
            "width": width,
            "height": height,
            "projection": view.projection,
        },
        "background": _color(rng),
    }
    if spheres:
        data["spheres"] = spheres
    if boards:
        data["billboards"] = boards
    if shading == "lit":
        data["lights"] = _lights(rng, tags, view, spheres, boards)
        if rng.uniform() < 0.6 or not data["lights"]:
            data["ambient"] = rng.uniform(0, 0.5, size=3).tolist()
        data["shadows"] = bool(rng.uniform() < 0.7)
        tags.add("shadows on" if data["shadows"] else "shadows off")
    if shading != "flat":  # materials: mirrors too, with or without lights
        data["max_depth"] = int(rng.integers(0, 5))
        mirrors = any("mirror" in o for o in spheres + boards)
        tags.add(f"mirrors, max_depth {data['max_depth']}" if mirrors else "no mirrors")
    tags.add("flat colours (no lights, no materials)" if shading == "flat" else
             "materials, no lights nor ambient" if shading != "lit" else "lit")  # fmt: skip
    tags.add(f"{samples}x{samples} samples" + (", adaptive" if adaptive else ""))
    return data, {"samples": samples, "adaptive": adaptive}, tags
