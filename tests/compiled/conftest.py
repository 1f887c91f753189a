"""The compiled engine's tests need numba, the ``fast`` extra (``pip install -e ".[fast]"``, the
README's fast lane): without it each module here is skipped, saying so, before it is imported
(each imports :mod:`raykit.engine.compiled`, which imports numba)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

WITHOUT_NUMBA = 'numba is not installed: pip install -e ".[fast]"'


class SkippedWithoutNumba(pytest.Module):
    """A test module of this folder, not imported: numba is missing."""

    def collect(self):
        pytest.skip(WITHOUT_NUMBA)


def pytest_pycollect_makemodule(module_path: Path, parent) -> pytest.Module | None:
    if importlib.util.find_spec("numba") is None:
        return SkippedWithoutNumba.from_parent(parent, path=module_path)
    return None
