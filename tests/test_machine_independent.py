"""Nothing raykit writes, and nothing the tests compare byte for byte, depends on the processor.

Machines differ from one run to the next (Intel with AVX-512, AMD with AVX2, ARM; BLAS picks a
kernel per processor and a thread count per machine). Two rules keep the kit's numbers the same:

* no matrix product on a path whose result is written or compared: the sums go left to right in
  :func:`raykit.rays.dot` and :func:`raykit.rays.length`, never through ``@``, ``np.dot``,
  ``einsum`` or ``np.linalg`` (BLAS's order and use of fused multiply-adds vary);
* the one vectorised transcendental the renderer takes, Blinn-Phong's power ``x ** p``, is
  numpy's own, whose last bit differs between AVX-512 and the rest; lit pictures are therefore
  compared within a stated tolerance, everything else bit for bit.

The second test runs ``tests/support/machine_outputs.py`` as other machines would: with BLAS told to
use another processor's kernels and thread counts, and with numpy's AVX-512 loops switched off.
"""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

# the code whose results reach a file, a picture or a grade; and the notebooks, whose stored
# outputs nbval compares as text
KIT_CODE = [
    "raykit",
    "raykit_grading",
    "benchmarks/scenes.py",
    "docs",
    "scenes",
    "tests/support/baselines.py",
]
BLAS_NAMES = {"dot", "vdot", "inner", "matmul", "einsum", "tensordot", "linalg", "multi_dot"}


def _sources():
    """``(where, Python source)`` of every file of KIT_CODE and every notebook's code cell
    (its IPython magics left out)."""
    for entry in KIT_CODE:
        path = REPO / entry
        for file in sorted(path.rglob("*.py")) if path.is_dir() else [path]:
            yield str(file.relative_to(REPO)), file.read_text()
    for notebook in sorted((REPO / "notebooks").glob("*.ipynb")):
        for number, cell in enumerate(json.loads(notebook.read_text())["cells"]):
            if cell["cell_type"] == "code":
                lines = "".join(cell["source"]).splitlines()
                code = "\n".join("" if line.lstrip().startswith(("%", "!")) else line
                                 for line in lines)  # fmt: skip
                yield f"{notebook.relative_to(REPO)} cell {number}", code


def test_no_matrix_product_or_linalg_in_the_kits_code():
    found = []
    for where, source in _sources():
        for node in ast.walk(ast.parse(source, where)):
            matmul = isinstance(node, ast.BinOp | ast.AugAssign) and isinstance(
                node.op, ast.MatMult
            )
            numpy_blas = (
                isinstance(node, ast.Attribute)
                and node.attr in BLAS_NAMES
                and isinstance(node.value, ast.Name)
                and node.value.id in {"np", "numpy"}
            )
            if matmul or numpy_blas:
                found.append(f"{where}:{node.lineno}")
    assert not found, "use raykit.rays.dot / length instead of BLAS at " + ", ".join(found)


def _numpy_features() -> dict[str, bool]:
    from numpy._core._multiarray_umath import __cpu_features__

    return __cpu_features__


def _machines() -> dict[str, dict[str, str]]:
    """Environments that make this process compute as other machines do."""
    machines = {
        "BLAS on one thread": {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"},
        "BLAS on two threads": {"OPENBLAS_NUM_THREADS": "2", "OMP_NUM_THREADS": "2"},
    }
    if sys.platform == "linux" and os.uname().machine == "x86_64":
        # OpenBLAS's kernels for AMD Zen / Haswell (AVX2) and for an older Sandy Bridge (AVX)
        machines["BLAS's Haswell kernels"] = {"OPENBLAS_CORETYPE": "Haswell"}
        machines["BLAS's Sandy Bridge kernels"] = {"OPENBLAS_CORETYPE": "Sandybridge"}
    avx512 = [
        name
        for name in ("X86_V4", "AVX512_SKX", "AVX512_ICL", "AVX512_SPR", "AVX512F")
        if _numpy_features().get(name)
    ]
    if avx512:  # this processor has AVX-512: compute as one without it does
        machines["numpy without AVX-512"] = {"NPY_DISABLE_CPU_FEATURES": " ".join(avx512)}
    return machines


def _outputs(tmp_path, name: str, overrides: dict[str, str]) -> dict[str, np.ndarray]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OPENBLAS_", "NPY_"))}
    env.update(overrides)
    out = tmp_path / f"{len(list(tmp_path.iterdir()))}.npz"
    subprocess.run(
        [sys.executable, str(REPO / "tests/support/machine_outputs.py"), str(out)],
        env=env,
        check=True,
        capture_output=True,
        timeout=300,
    )
    with np.load(out) as arrays:
        return {key: arrays[key] for key in arrays.files}


@pytest.mark.slow
def test_outputs_are_the_same_whatever_the_blas_kernel_threads_or_vector_width(tmp_path):
    reference = _outputs(tmp_path, "this machine", {})
    assert len(reference) > 10
    for machine, overrides in _machines().items():
        other = _outputs(tmp_path, machine, overrides)
        assert sorted(other) == sorted(reference)
        for key, expected in reference.items():
            got = other[key]
            if key.startswith("lit:") and key.endswith(".rgb"):
                # numpy's power may differ in the last bit (module docstring)
                np.testing.assert_allclose(got, expected, rtol=1e-13, atol=1e-15, err_msg=key)
                same = np.mean(np.round(got * 255) == np.round(expected * 255))
                assert same >= 0.999, (machine, key, same)
            else:
                assert got.tobytes() == expected.tobytes(), (machine, key)
