"""What a batch grades: the entries of a class, each a student's submission or a reason why not.

``batch`` takes any of:

* a folder of student folders (``ada/raykit/...``), of zips (``erin.zip``: the student is the
  zip's name without ``.zip``), or both mixed;
* Gradescope's "Export Submissions" archive as downloaded (a zip), or that archive unzipped: a
  ``submission_metadata.yml`` beside one folder per submission (``submission_<id>/``), the
  YAML mapping each folder to its submitters (``:submitters:`` with ``:name:``, ``:sid:``,
  ``:email:``); the archive's files may sit in one folder (``assignment_<id>_export/``). Such
  an archive may also be one of the entries of a folder;
* a zip of any of the above.

Every entry of the folder (or archive) is a row of ``scores.csv``: graded, or said why not (a
file that is neither a folder nor a zip, a link, a submission the export's YAML names but its
folder lacks, an archive too large to take in); nothing is left out silently. A folder in the
export that its YAML does not name is graded under its folder's name.

What a zip holds is read with bounds (:data:`MAX_MEMBERS` files, :data:`MAX_BYTES` bytes per
submission, names that stay inside, no links) and written as plain files into a scratch folder;
each student's folder is then taken in by :func:`raykit_grading.grading.submissions.stage` like any
other, with its own checks. A student's zip is not opened here: it is graded as a folder
holding that zip, which the staging unpacks as it does an upload.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import stat
import zipfile
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

METADATA = "submission_metadata.yml"
MAX_MEMBERS = 5000  # files taken from an archive per submission
MAX_BYTES = 64 * 1024**2  # bytes taken from an archive per submission (or a student's zip)


@dataclass
class Entry:
    """One row of the class: ``name`` as scores.csv shows it, ``folder`` to grade (None: not
    graded, and ``why``); ``submission`` False for what is no student's submission at all (a
    stray file beside them), which the batch lists but does not count as one it could not
    grade."""

    name: str
    folder: Path | None
    why: str = ""
    submission: bool = True


def entries(submissions: Path, scratch: Path) -> list[Entry]:
    """The class in ``submissions`` (a folder or a zip), every entry of it; zips are read into
    ``scratch`` (a new, private folder)."""
    submissions = Path(submissions)
    if submissions.is_file() and zipfile.is_zipfile(submissions):
        return _from_zip(submissions, scratch / "class", submissions.name)
    if (submissions / METADATA).is_file():
        return _export_folder(submissions)
    found: list[Entry] = []
    for entry in sorted(os.scandir(submissions), key=lambda e: e.name):
        mode = entry.stat(follow_symlinks=False).st_mode
        path = Path(entry.path)
        if stat.S_ISDIR(mode):
            found.append(Entry(entry.name, path))
        elif stat.S_ISLNK(mode):
            found.append(Entry(entry.name, None, "a symbolic link: not followed"))
        elif stat.S_ISREG(mode) and entry.name.lower().endswith(".zip"):
            found += _zip_entry(path, scratch / f"{len(found)}")
        else:
            found.append(Entry(entry.name, None, "not a folder or a zip", submission=False))
    return _unique(found)


def _zip_entry(path: Path, scratch: Path) -> list[Entry]:
    """A zip in the class's folder: a student's (graded as a folder holding it), or a whole
    Gradescope export."""
    name = path.name[: -len(".zip")]
    try:
        with zipfile.ZipFile(path) as archive:
            if _metadata_member(archive) is not None:
                return _from_zip(path, scratch, path.name)
    except (zipfile.BadZipFile, OSError) as exc:
        return [Entry(name, None, f"{path.name}: not a zip that can be read ({exc})")]
    if path.stat().st_size > MAX_BYTES:
        return [Entry(name, None, f"{path.name}: larger than {MAX_BYTES // 2**20} MiB")]
    scratch.mkdir(parents=True)
    shutil.copyfile(path, scratch / path.name, follow_symlinks=False)
    return [Entry(name, scratch)]


def _from_zip(path: Path, scratch: Path, shown: str) -> list[Entry]:
    """A zip of a class: a Gradescope export, or a zip of student folders and zips."""
    try:
        with zipfile.ZipFile(path) as archive:
            metadata = _metadata_member(archive)
            prefix = "" if metadata is None else metadata[: -len(METADATA)]
            folders = _top_folders(archive, prefix)
            files = [n for n in _top_files(archive, prefix) if n != METADATA]
            scratch.mkdir(parents=True)
            refused = {}
            for name in folders + files:  # loose files: a student's zip, or not a submission
                single = name in files
                member = f"{prefix}{name}" + ("" if single else "/")
                why = _extract(archive, member, scratch / name, single=single)
                if why:
                    refused[name] = f"in {shown}: {why}"
                    _remove(scratch / name)
            if metadata is not None:
                (scratch / METADATA).write_bytes(archive.read(metadata)[:MAX_BYTES])
    except (zipfile.BadZipFile, OSError) as exc:
        return [Entry(shown, None, f"not a zip that can be read ({exc})")]
    if metadata is not None:
        return _export_folder(scratch, refused)
    found = entries(scratch, scratch / ".zips")
    return _unique(found + [Entry(name, None, why) for name, why in refused.items()])


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    else:
        path.unlink(missing_ok=True)


def _metadata_member(archive: zipfile.ZipFile) -> str | None:
    """The export's ``submission_metadata.yml``: at the top, or in the one folder there."""
    names = [n for n in archive.namelist() if PurePosixPath(n).name == METADATA]
    names = [n for n in names if n.count("/") <= 1]
    return min(names, key=len) if names else None


def _top_folders(archive: zipfile.ZipFile, prefix: str) -> list[str]:
    tops = {n[len(prefix) :].split("/")[0] for n in archive.namelist() if n.startswith(prefix)}
    nested = {t for t in tops if any(n.startswith(f"{prefix}{t}/") for n in archive.namelist())}
    return sorted(t for t in nested if t not in ("", ".", "..", "__MACOSX") and "\\" not in t)


def _top_files(archive: zipfile.ZipFile, prefix: str) -> list[str]:
    names = {n[len(prefix) :] for n in archive.namelist() if n.startswith(prefix)}
    return sorted(n for n in names if "/" not in n and "\\" not in n and n not in ("", ".", ".."))


def _extract(archive: zipfile.ZipFile, prefix: str, target: Path, single: bool = False) -> str:
    """Write the members under ``prefix`` (or the one member ``prefix``) as plain files into
    ``target``, within the bounds; "" or why not."""
    members = [
        info
        for info in archive.infolist()
        if (info.filename == prefix if single else info.filename.startswith(prefix))
    ]
    if len(members) > MAX_MEMBERS:
        return f"more than {MAX_MEMBERS} files"
    if sum(info.file_size for info in members) > MAX_BYTES:
        return f"larger than {MAX_BYTES // 2**20} MiB"
    if not single:
        target.mkdir(parents=True)
    for info in members:
        relative = PurePosixPath(info.filename[len(prefix) :] if not single else target.name)
        if info.is_dir() or not relative.parts:
            continue
        if relative.is_absolute() or ".." in relative.parts or "\\" in info.filename:
            return f"a file name that leaves its folder: {info.filename!r}"
        if stat.S_ISLNK(info.external_attr >> 16):
            continue  # a link is never made (the staging would leave it out too)
        destination = target.parent / target.name if single else target / relative
        destination.parent.mkdir(parents=True, exist_ok=True)
        with archive.open(info) as source, open(destination, "xb") as sink:
            left = MAX_BYTES
            while chunk := source.read(min(2**20, left + 1)):
                left -= len(chunk)
                if left < 0:
                    return f"larger than {MAX_BYTES // 2**20} MiB"
                sink.write(chunk)
    return ""


def _export_folder(folder: Path, refused: dict[str, str] | None = None) -> list[Entry]:
    """An unzipped Gradescope export: one entry per submission its YAML names (the students
    who submitted it), and any other folder under its own name. ``refused``: the folders that
    could not be taken from the archive, and why."""
    refused = refused or {}
    named = read_metadata((folder / METADATA).read_text(encoding="utf-8", errors="replace"))
    found = []
    for key, submitters in named.items():
        name = " & ".join(submitters) or key
        path = folder / key
        if key in refused:
            found.append(Entry(name, None, refused[key]))
        elif path.is_dir() and not path.is_symlink() and PurePosixPath(key).name == key:
            found.append(Entry(name, path))
        else:
            found.append(Entry(name, None, f"{METADATA} names {key}, which is not in the export"))
    for entry in sorted(os.scandir(folder), key=lambda e: e.name):
        if entry.name in named or entry.name == METADATA:
            continue
        if entry.is_dir(follow_symlinks=False):
            found.append(Entry(entry.name, Path(entry.path)))
        else:
            found.append(
                Entry(entry.name, None, "not a submission folder of the export", submission=False)
            )
    found += [Entry(k, None, why) for k, why in refused.items() if k not in named]
    return _unique(found)


_KEY = re.compile(r"^(?P<indent> *)(?P<dash>- +)?(?P<key>:?[^\s:][^:]*):(?: +(?P<value>.*))?$")


def read_metadata(text: str) -> dict[str, list[str]]:
    """``submission_metadata.yml`` as Gradescope writes it (Ruby's YAML: symbol keys with a
    colon in front), read for what a batch needs: each submission folder's submitters' names
    (their SID or email where a name is missing), in the file's order. Only this shape is
    read: top-level keys, and in each the ``:submitters:`` list of mappings."""
    named: dict[str, list[str]] = {}
    folder = None
    child = None  # the indent of a submission's own keys
    block = None  # the indent of the ":submitters:" key we are in
    person: dict[str, str] = {}

    def close() -> None:
        if folder is not None and person:
            named[folder].append(
                person.get(":name") or person.get(":sid") or person.get(":email") or "?"
            )

    for line in text.splitlines():
        if not line.strip() or line.lstrip().startswith("#") or line.startswith("---"):
            continue
        match = _KEY.match(line)
        indent = len(line) - len(line.lstrip(" "))
        if indent == 0 and match and not match["dash"]:
            close()
            folder, child, block, person = _scalar(match["key"]), None, None, {}
            named[folder] = []
            continue
        if folder is None:
            continue
        child = indent if child is None else child
        if match and match["key"] == ":submitters" and not match["dash"] and indent == child:
            close()
            block, person = indent, {}
            continue
        if block is None:
            continue
        if indent < block or (indent == block and not (match and match["dash"])):
            close()
            block, person = None, {}
            continue
        if match is None:
            continue
        if match["dash"]:
            close()
            person = {}
        person[match["key"]] = _scalar(match["value"] or "")
    close()
    return named


def _scalar(text: str) -> str:
    text = text.strip()
    if len(text) >= 2 and text[0] == text[-1] == "'":
        return text[1:-1].replace("''", "'")
    if len(text) >= 2 and text[0] == text[-1] == '"':
        try:
            return json.loads(text)  # YAML's double-quoted escapes, as far as JSON has them
        except ValueError:
            return text[1:-1]
    return text


def _unique(found: list[Entry]) -> list[Entry]:
    """Names a file system and scores.csv can hold, each once (a later one gets a number)."""
    seen: set[str] = set()
    for entry in found:
        name = entry.name.replace("/", "_").replace("\0", "_").lstrip(".") or "_"
        base, number = name, 2
        while name in seen:
            name, number = f"{base} ({number})", number + 1
        seen.add(name)
        entry.name = name
    return found
