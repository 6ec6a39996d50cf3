from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SPECS = ROOT / "specs"


@pytest.fixture(autouse=True)
def _isolated_cache(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch):
    # never touch the user's ~/.cache from tests
    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "cache"))
