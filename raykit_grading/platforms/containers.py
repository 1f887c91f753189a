"""The autograder zip in a real container, as Gradescope builds and runs it.

    python -m raykit_grading try-zip autograder.zip SUBMISSION... [--base-image IMAGE]
    python -m raykit_grading.platforms.containers base-image [--tag TAG] [--rootfs DIR]

Gradescope builds one image per autograder: the zip extracted into ``/autograder/source``,
``run_autograder`` copied to ``/autograder/run_autograder``, ``setup.sh`` run there as root.
It then grades each submission in a fresh container of that image, with Docker's default
seccomp profile and capabilities, 768 MB of memory and half a CPU, the submission copied to
``/autograder/submission``, ``/autograder/run_autograder`` as the command, and reads
``/autograder/results/results.json`` back. This module does the same with the ``docker``
command (no Python dependency): :func:`build_image` and :func:`grade_in_container`, used by
``try-zip`` (the check an instructor runs before uploading the zip) and by the hostile tests'
``container`` lane.

Gradescope's base image is ``gradescope/autograder-base:ubuntu-22.04`` (:data:`GRADESCOPE_BASE`).
Where no image registry is reachable, :func:`make_base_image` makes a Debian base image from
the distribution's packages with ``debootstrap`` (:data:`DEBIAN_BASE`).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shlex
import shutil
import stat
import subprocess
import sys
import tempfile
import time
import uuid
import zipfile
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from raykit_grading.assignment.seeds import (
    FILE_NAME,
    SeedFileError,
    assignment_seed,
    fingerprint,
    parse_seed,
    shown,
)

GRADESCOPE_BASE = "gradescope/autograder-base:ubuntu-22.04"
DEBIAN_BASE = "raykit/debian-bookworm-base:latest"
DEBIAN_MIRROR = "http://deb.debian.org/debian"
IMAGE_REPOSITORY = "raykit/autograder"
# Gradescope's defaults (its "Troubleshooting" page): 768 MB, half a CPU, a 10-minute timeout
MEMORY = "768m"
CPUS = "0.5"
TIMEOUT = 600.0
HOW_TO_GET_DOCKER = (
    "install Docker (apt-get install docker.io, or https://docs.docker.com/engine/install/) "
    "and start it (systemctl start docker, or dockerd as root)"
)


class ContainerError(RuntimeError):
    """Docker cannot do what was asked; the message is one line that says why."""


def docker_problem() -> str | None:
    """Why the docker command cannot run containers here (one line), or None."""
    if shutil.which("docker") is None:
        return f"no docker command: {HOW_TO_GET_DOCKER}"
    try:
        probe = subprocess.run(
            ["docker", "info", "--format", "{{.ServerVersion}}"],
            capture_output=True, text=True, timeout=30,
        )  # fmt: skip
    except subprocess.TimeoutExpired:
        return f"the Docker daemon did not answer in 30 s: {HOW_TO_GET_DOCKER}"
    if probe.returncode != 0 or not probe.stdout.strip():
        why = _last_line(probe.stderr) or "docker info failed"
        return f"cannot reach the Docker daemon ({why}): {HOW_TO_GET_DOCKER}"
    return None


def _last_line(text: str) -> str:
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else ""


def _docker(*args: str, timeout: float | None = 120, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(["docker", *args], capture_output=True, text=True, timeout=timeout, **kw)


def image_exists(image: str) -> bool:
    return _docker("image", "inspect", "--format", "{{.Id}}", image).returncode == 0


# ---- the base image --------------------------------------------------------------------------


def make_base_image(
    tag: str = DEBIAN_BASE,
    rootfs: Path | None = None,
    suite: str = "bookworm",
    mirror: str = DEBIAN_MIRROR,
    log=print,
) -> bool:
    """Make ``tag`` from Debian's packages (``debootstrap --variant=minbase``, then ``docker
    import``), unless it exists. ``rootfs``: a tree debootstrap made already. True if made now."""
    if image_exists(tag):
        log(f"base image {tag}: exists, kept")
        return False
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="raykit-rootfs-") as scratch:
        if rootfs is None:
            if shutil.which("debootstrap") is None:
                raise ContainerError("no debootstrap command: apt-get install debootstrap")
            rootfs = Path(scratch) / suite
            made = subprocess.run(
                ["debootstrap", "--variant=minbase", suite, str(rootfs), mirror],
                capture_output=True, text=True,
            )  # fmt: skip
            if made.returncode != 0:
                why = _last_line(made.stderr) or _last_line(made.stdout)
                raise ContainerError(f"debootstrap {suite} from {mirror} failed: {why}")
            log(f"debootstrap {suite}: {time.perf_counter() - start:.0f} s")
        tar = subprocess.Popen(["tar", "-C", str(rootfs), "-c", "."], stdout=subprocess.PIPE)
        imported = subprocess.run(
            ["docker", "import", "--change", "CMD [\"/bin/bash\"]", "-", tag],
            stdin=tar.stdout, capture_output=True, text=True,
        )  # fmt: skip
        tar.stdout.close()
        if tar.wait() != 0 or imported.returncode != 0:
            raise ContainerError(f"docker import failed: {_last_line(imported.stderr)}")
    trust_local_certificates(tag, log)
    log(f"base image {tag}: made in {time.perf_counter() - start:.0f} s")
    return True


LOCAL_CERTIFICATES = Path("/usr/local/share/ca-certificates")
TRUST_DOCKERFILE = """\
FROM {image}
COPY certificates/ /usr/local/share/ca-certificates/
COPY pip.conf /etc/pip.conf
"""


def trust_local_certificates(image: str, log=print) -> None:
    """Give ``image`` this machine's own certificate authorities (``LOCAL_CERTIFICATES``,
    where a network that inspects TLS puts its own), and a pip.conf that trusts the system's
    bundle: a build behind such a proxy then reaches PyPI. Once ``setup.sh`` installs
    ca-certificates they join the bundle. Nothing is done where there are none."""
    certificates = sorted(LOCAL_CERTIFICATES.glob("*.crt"))
    if not certificates:
        return
    with tempfile.TemporaryDirectory(prefix="raykit-trust-") as context:
        folder = Path(context) / "certificates"
        folder.mkdir()
        for path in certificates:
            shutil.copy(path, folder / path.name)
        (Path(context) / "pip.conf").write_text(
            "[global]\ncert = /etc/ssl/certs/ca-certificates.crt\n"
        )
        (Path(context) / "Dockerfile").write_text(TRUST_DOCKERFILE.format(image=image))
        built = _docker("build", "--force-rm", "-t", image, context, timeout=600)
    if built.returncode != 0:
        raise ContainerError(f"adding this machine's certificates: {_last_line(built.stderr)}")
    log(f"base image {image}: with this machine's {len(certificates)} certificate "
        f"authorities from {LOCAL_CERTIFICATES}")  # fmt: skip


# ---- the autograder's image --------------------------------------------------------------------


def zip_digest(archive: Path, base_image: str) -> str:
    """A hash of the zip's contents (names, modes, bytes; not its timestamps) and the base
    image's name: the same zip on the same base reuses its image."""
    digest = hashlib.sha256(f"base {base_image}\n".encode())
    with zipfile.ZipFile(archive) as opened:
        for info in sorted(opened.infolist(), key=lambda i: i.filename):
            digest.update(f"{info.filename}\0{info.external_attr >> 16:o}\0".encode())
            digest.update(hashlib.sha256(opened.read(info)).digest())
    return digest.hexdigest()


def extract_as_gradescope(archive: Path, source: Path) -> None:
    """Extract the zip's contents into ``source`` (its top-level entries at ``source``'s top,
    as Gradescope fills /autograder/source), keeping the modes the zip records."""
    with zipfile.ZipFile(archive) as opened:
        for info in opened.infolist():
            name = PurePosixPath(info.filename)
            if name.is_absolute() or ".." in name.parts:
                raise ContainerError(f"{archive}: {info.filename}: a path outside the zip")
            mode = info.external_attr >> 16
            if stat.S_IFMT(mode) not in (0, stat.S_IFREG, stat.S_IFDIR):
                raise ContainerError(f"{archive}: {info.filename}: not a file or a folder")
            target = source.joinpath(*name.parts)
            if info.is_dir():
                target.mkdir(parents=True, exist_ok=True)
                continue
            target.parent.mkdir(parents=True, exist_ok=True)
            with opened.open(info) as data, open(target, "wb") as out:
                shutil.copyfileobj(data, out)
            if stat.S_IMODE(mode):
                os.chmod(target, stat.S_IMODE(mode))


DOCKERFILE = """\
FROM {base}
COPY source /autograder/source
RUN cp /autograder/source/run_autograder /autograder/run_autograder \\
 && chmod 755 /autograder/run_autograder \\
 && cd /autograder/source && bash /autograder/source/setup.sh
"""


@dataclass
class Built:
    image: str
    cached: bool
    seconds: float
    log: Path | None


def build_image(
    archive: Path,
    base_image: str = GRADESCOPE_BASE,
    network: str | None = None,
    log_dir: Path | None = None,
) -> Built:
    """The image Gradescope would build from ``archive`` on ``base_image``, tagged by
    :func:`zip_digest` (an image built before from the same zip is reused). ``network``:
    ``docker build --network`` (for the build only; never the graded run)."""
    archive = Path(archive)
    with zipfile.ZipFile(archive) as opened:
        names = set(opened.namelist())
    missing = [n for n in ("setup.sh", "run_autograder") if n not in names]
    if missing:
        raise ContainerError(
            f"{archive}: no {' or '.join(missing)} at the zip's top, where Gradescope looks"
        )
    image = f"{IMAGE_REPOSITORY}:{zip_digest(archive, base_image)[:16]}"
    if image_exists(image):
        return Built(image, True, 0.0, None)
    with tempfile.TemporaryDirectory(prefix="raykit-image-") as context:
        extract_as_gradescope(archive, Path(context) / "source")
        (Path(context) / "Dockerfile").write_text(DOCKERFILE.format(base=base_image))
        return docker_build(
            Path(context), image, [], f"raykit.zip={archive.name}", str(archive), base_image,
            network, log_dir,
        )  # fmt: skip


def docker_build(
    context: Path,
    image: str,
    build_args: list[str],
    label: str,
    what: str,
    base_image: str,
    network: str | None = None,
    log_dir: Path | None = None,
) -> Built:
    """``docker build`` of ``context`` into ``image``, its log kept in ``log_dir``; a build
    that fails raises :class:`ContainerError` with the log's last lines."""
    start = time.perf_counter()
    command = ["docker", "build", "--force-rm", "-t", image, "--label", label, *build_args]
    if network:
        command += ["--network", network]
    log_dir = Path(log_dir or tempfile.gettempdir())
    log_dir.mkdir(parents=True, exist_ok=True)
    log = log_dir / f"raykit-image-build-{image.split(':')[1]}.log"
    with open(log, "w") as out:
        built = subprocess.run([*command, str(context)], stdout=out, stderr=subprocess.STDOUT)
    if built.returncode != 0:
        legacy = (
            "DEPRECATED: The legacy builder",
            "Install the buildx",
            "https://docs.docker.com/go/buildx",
        )
        lines = log.read_text(errors="replace").splitlines()
        tail = [li for li in lines if li.strip() and not li.strip().startswith(legacy)][-15:]
        raise ContainerError(
            f"building the image from {what} on {base_image} failed (the whole log: {log}):\n"
            + "\n".join(tail)
        )
    return Built(image, False, time.perf_counter() - start, log)


# ---- one grading ------------------------------------------------------------------------------


@dataclass
class Graded:
    status: int | None  # run_autograder's exit status (None: stopped at the timeout)
    results: dict | None  # results.json, parsed (None: none was written, or not JSON)
    results_path: Path | None
    output: str  # what run_autograder printed
    seconds: float
    problem: str | None = None  # why results is None
    container: str = ""  # the container's name (removed by now)


def grade_in_container(
    image: str,
    submission: Path,
    out_dir: Path,
    env: dict[str, str] | None = None,
    memory: str = MEMORY,
    cpus: str = CPUS,
    timeout: float = TIMEOUT,
) -> Graded:
    """Grade ``submission`` (a folder: its contents; a file: itself) in a fresh container of
    ``image`` with Gradescope's defaults, and copy its results.json to ``out_dir``. The
    container is removed whatever happens."""
    submission = Path(submission)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    name = f"raykit-grade-{uuid.uuid4().hex[:12]}"
    command = ["create", "--name", name, "--memory", memory, "--memory-swap", memory,
               "--cpus", cpus]  # fmt: skip
    for key, value in (env or {}).items():
        command += ["-e", f"{key}={value}"]
    start = time.perf_counter()
    try:
        created = _docker(*command, image, "/autograder/run_autograder")
        if created.returncode != 0:
            raise ContainerError(f"docker create failed: {_last_line(created.stderr)}")
        if submission.is_dir():
            copied = _docker("cp", f"{submission}/.", f"{name}:/autograder/submission")
        else:
            copied = _make_folder_and_copy(name, submission)
        if copied.returncode != 0:
            raise ContainerError(f"docker cp of the submission failed: {_last_line(copied.stderr)}")
        status, output = _start_until(name, timeout)
        path = out_dir / "results.json"
        path.unlink(missing_ok=True)
        fetched = _docker("cp", f"{name}:/autograder/results/results.json", str(path))
        seconds = time.perf_counter() - start
        if fetched.returncode != 0:
            return Graded(status, None, None, output, seconds, "no results.json was written", name)
        try:
            results = json.loads(path.read_text())
        except (OSError, ValueError) as exc:  # UnicodeDecodeError is a ValueError
            why = f"results.json is not JSON: {exc}"
            return Graded(status, None, path, output, seconds, why, name)
        return Graded(status, results, path, output, seconds, None, name)
    finally:
        _docker("rm", "--force", "--volumes", name)


def _start_until(name: str, timeout: float) -> tuple[int | None, str]:
    """Start the container ``name`` attached: (its exit status, or None if it was killed at
    ``timeout``; what it printed)."""
    try:
        run = _docker("start", "--attach", name, timeout=timeout)
        return run.returncode, run.stdout + run.stderr
    except subprocess.TimeoutExpired as exc:
        _docker("kill", name)
        return None, _text(exc.stdout) + _text(exc.stderr) + f"\n(stopped after {timeout:g} s)"


def _make_folder_and_copy(name: str, path: Path) -> subprocess.CompletedProcess:
    """A file (a zip) put into /autograder/submission/ (docker cp cannot make the folder)."""
    with tempfile.TemporaryDirectory() as folder:
        shutil.copy(path, Path(folder) / path.name)
        return _docker("cp", f"{folder}/.", f"{name}:/autograder/submission")


def _text(data) -> str:
    if data is None:
        return ""
    return data.decode(errors="replace") if isinstance(data, bytes) else data


# ---- PrairieLearn --------------------------------------------------------------------------
# PrairieLearn's grader host (apps/grader-host/src/index.ts, lib/config.ts): 2 GiB of memory
# and no swap, 90 % of a CPU, 1024 processes, no core dumps, a private IPC namespace, no
# network unless the question enables it, the job's folder bound at /grade, and the results
# kept only if the entrypoint exits 0 and results.json is at most 1 MiB
PL_MEMORY = "2g"
PL_CPUS = "0.9"
PL_PIDS = "1024"
PL_RESULTS_LIMIT = 1024 * 1024
PL_IMAGE_REPOSITORY = "raykit/prairielearn-grader"


def folder_digest(folder: Path, base_image: str) -> str:
    """A hash of a build folder's files (names, modes, bytes) and the base image's name: the
    same folder on the same base reuses its image."""
    digest = hashlib.sha256(f"base {base_image}\n".encode())
    for path in sorted(p for p in Path(folder).rglob("*") if p.is_file()):
        mode = stat.S_IMODE(path.stat().st_mode)
        digest.update(f"{path.relative_to(folder).as_posix()}\0{mode:o}\0".encode())
        digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def build_folder_image(
    folder: Path, base_image: str, network: str | None = None, log_dir: Path | None = None
) -> Built:
    """The image of a build folder holding a Dockerfile whose base is the ``BASE_IMAGE`` build
    argument (``prairielearn -o DIR`` writes ``DIR/grader-image/``), tagged by
    :func:`folder_digest` (an image built before from the same folder is reused)."""
    folder = Path(folder)
    if not (folder / "Dockerfile").is_file():
        raise ContainerError(f"{folder}: no Dockerfile")
    image = f"{PL_IMAGE_REPOSITORY}:{folder_digest(folder, base_image)[:16]}"
    if image_exists(image):
        return Built(image, True, 0.0, None)
    return docker_build(
        folder, image, ["--build-arg", f"BASE_IMAGE={base_image}"],
        f"raykit.grader-image={folder}", str(folder), base_image, network, log_dir,
    )  # fmt: skip


def grade_in_prairielearn_container(
    image: str,
    student: Path,
    question_tests: Path,
    out_dir: Path,
    entrypoint: str,
    timeout: float,
    env: dict[str, str] | None = None,
) -> Graded:
    """Grade as PrairieLearn's grader host does: a job folder laid out as its docs say
    (``student/`` the submitted files, ``tests/`` the question's ``tests/``, ``data/data.json``)
    bound at ``/grade`` of a fresh container with its limits and no network, ``entrypoint``
    run, killed at ``timeout``; its ``results/results.json`` is copied to ``out_dir`` and kept
    only as PrairieLearn keeps it (exit status 0, at most 1 MiB). ``student``: a folder whose
    files are the submitted files."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    name = f"raykit-pl-{uuid.uuid4().hex[:12]}"
    job = Path(tempfile.mkdtemp(prefix="raykit-pl-job-"))
    try:
        subprocess.run(["cp", "-a", f"{student}/.", str(job / "student")], check=True)
        shutil.copytree(question_tests, job / "tests", symlinks=True)
        files = [{"name": p.name} for p in sorted((job / "student").iterdir())]
        (job / "data").mkdir()
        (job / "data/data.json").write_text(json.dumps({
            "params": {}, "correct_answers": {}, "submitted_answers": {"_files": files},
            "format_errors": {}, "partial_scores": {}, "score": 0, "feedback": {},
            "variant_seed": 1, "options": {}, "raw_submitted_answers": {},
            "editable": False, "panel": "question", "extensions": {}, "num_valid_submissions": 0,
        }))  # fmt: skip
        command, *arguments = shlex.split(entrypoint)
        create = ["create", "--name", name, "--network", "none", "--memory", PL_MEMORY,
                  "--memory-swap", PL_MEMORY, "--cpus", PL_CPUS, "--pids-limit", PL_PIDS,
                  "--ulimit", "core=0", "--ipc", "private", "-v", f"{job}:/grade",
                  "--entrypoint", command]  # fmt: skip
        for key, value in (env or {}).items():
            create += ["-e", f"{key}={value}"]
        created = _docker(*create, image, *arguments)  # made before the clock starts
        if created.returncode != 0:
            raise ContainerError(f"docker create failed: {_last_line(created.stderr)}")
        start = time.perf_counter()
        status, output = _start_until(name, timeout)
        seconds = time.perf_counter() - start
        written = job / "results" / "results.json"
        path = out_dir / "results.json"
        path.unlink(missing_ok=True)
        if status != 0:  # PrairieLearn keeps no results then
            why = "timed out" if status is None else f"the entrypoint exited {status}"
            return Graded(status, None, None, output, seconds, why, name)
        if not written.is_file():
            return Graded(status, None, None, output, seconds, "no results.json was written", name)
        shutil.copy(written, path)
        if path.stat().st_size > PL_RESULTS_LIMIT:
            why = "results.json is larger than 1 MB (PrairieLearn refuses it)"
            return Graded(status, None, path, output, seconds, why, name)
        try:
            results = json.loads(path.read_text())
        except (OSError, ValueError) as exc:
            why = f"results.json is not JSON: {exc}"
            return Graded(status, None, path, output, seconds, why, name)
        return Graded(status, results, path, output, seconds, None, name)
    finally:
        _docker("rm", "--force", "--volumes", name)
        shutil.rmtree(job, ignore_errors=True)


# ---- try-zip ------------------------------------------------------------------------------------


def try_zip(
    archive: Path,
    submissions: list[Path],
    base_image: str = GRADESCOPE_BASE,
    output: Path = Path("try-zip"),
    env: dict[str, str] | None = None,
    assignment: Path | None = None,
) -> int:
    """``python -m raykit_grading try-zip``: build the image from ``archive`` and grade each
    submission in a fresh container, printing its score and where its results.json is.
    It first prints the fingerprint of the seed in the zip, and warns if it is not the seed of
    the assignment found here (``assignment``, or from the current folder): then ``grade`` and
    ``batch`` here grade on other inputs than the zip does.
    0: every submission graded; 2: cannot try here (said in one line); 3: some submission
    not graded (no results.json, or run_autograder failed)."""
    problem = docker_problem()
    if problem:
        print(f"raykit_grading: error: try-zip runs the zip in Docker, as Gradescope does: "
              f"{problem}", file=sys.stderr)  # fmt: skip
        return 2
    for path in (archive, *submissions):
        if not Path(path).exists():
            print(f"raykit_grading: error: {path}: no such file or folder", file=sys.stderr)
            return 2
    if not zipfile.is_zipfile(archive):
        print(f"raykit_grading: error: {archive}: not a zip", file=sys.stderr)
        return 2
    try:
        say_seeds(archive, assignment)
    except SeedFileError as exc:
        print(f"raykit_grading: error: {exc}", file=sys.stderr)
        return 2
    print(f"building the image from {archive} on {base_image} (setup.sh runs now, as on "
          "Gradescope; minutes the first time) ...", flush=True)  # fmt: skip
    try:
        if base_image != DEBIAN_BASE or image_exists(base_image):
            built = build_image(archive, base_image, log_dir=Path(output))
        else:  # the debootstrap base: made here if missing
            make_base_image(base_image)
            built = build_image(archive, base_image, log_dir=Path(output))
    except ContainerError as exc:
        print(f"raykit_grading: error: {exc}", file=sys.stderr)
        if base_image == GRADESCOPE_BASE:
            print(f"raykit_grading: where Docker Hub cannot be reached, make a Debian base "
                  f"image (python -m raykit_grading.platforms.containers base-image) and pass "
                  f"--base-image {DEBIAN_BASE}", file=sys.stderr)  # fmt: skip
        return 3
    how = (
        "reused (built before from the same zip)"
        if built.cached
        else f"built in {built.seconds:.0f} s"
    )
    print(f"image {built.image}: {how}")
    failed = 0
    for index, submission in enumerate(submissions):
        submission = Path(submission)
        out_dir = Path(output) / f"{index + 1:02d}-{submission.name or 'submission'}"
        try:
            graded = grade_in_container(built.image, submission, out_dir, env=env)
        except ContainerError as exc:
            failed += 1
            print(f"{submission}: NOT GRADED ({exc})")
            continue
        if graded.results is None or graded.status != 0:
            failed += 1
            why = graded.problem or f"run_autograder exited {graded.status}"
            tail = "\n  ".join(graded.output.strip().splitlines()[-10:])
            print(f"{submission}: NOT GRADED ({why}) in {graded.seconds:.0f} s"
                  + (f"; results.json: {graded.results_path}" if graded.results_path else "")
                  + (f"\n  {tail}" if tail else ""))  # fmt: skip
            continue
        results = graded.results
        total = sum(t.get("max_score", 0) for t in results.get("tests", []))
        sandbox = results.get("extra_data", {}).get("sandbox", "?")
        print(f"{submission}: {results.get('score', 0):g} of {total:g} points in "
              f"{graded.seconds:.0f} s (sandbox: {sandbox}); results.json: "
              f"{graded.results_path}")  # fmt: skip
    return 3 if failed else 0


def say_seeds(archive: Path, assignment: Path | None) -> None:
    """Print the zip's seed's fingerprint, and a warning if the assignment found here has
    another (one line each, on stderr). Raises SeedFileError for a zip with no seed in it,
    or an ``assignment`` with none."""
    with zipfile.ZipFile(archive) as opened:
        try:
            text = opened.read(FILE_NAME).decode("utf-8", "replace")
        except KeyError:
            raise SeedFileError(
                f"{archive}: no {FILE_NAME} in it (build it with python -m raykit_grading "
                "gradescope)"
            ) from None
    zipped = fingerprint(parse_seed(text, f"{archive}: {FILE_NAME}"))
    print(f"raykit_grading: assignment seed {zipped} ({archive}: {FILE_NAME})", file=sys.stderr)
    try:
        here = assignment_seed(assignment, make=False)
    except SeedFileError:
        if assignment is not None:
            raise
        return  # no assignment folder here to compare with
    if here.fingerprint != zipped:
        print(f"raykit_grading: warning: the zip's seed {zipped} is not this assignment's "
              f"{here.fingerprint} ({shown(here.file)}): grade and batch here grade on other "
              "inputs than the zip", file=sys.stderr)  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    """``python -m raykit_grading.platforms.containers base-image``: make the Debian base image."""
    parser = argparse.ArgumentParser(prog="python -m raykit_grading.platforms.containers")
    commands = parser.add_subparsers(dest="command", required=True)
    base = commands.add_parser("base-image", help="make a Debian base image with debootstrap")
    base.add_argument("--tag", default=DEBIAN_BASE)
    base.add_argument("--suite", default="bookworm")
    base.add_argument("--mirror", default=DEBIAN_MIRROR)
    base.add_argument("--rootfs", type=Path, help="a tree debootstrap made already")
    args = parser.parse_args(argv)
    problem = docker_problem()
    if problem:
        print(f"raykit_grading: error: {problem}", file=sys.stderr)
        return 2
    try:
        make_base_image(args.tag, args.rootfs, args.suite, args.mirror)
    except ContainerError as exc:
        print(f"raykit_grading: error: {exc}", file=sys.stderr)
        return 3
    return 0


if __name__ == "__main__":
    sys.exit(main())
