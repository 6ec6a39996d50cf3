"""`robospec check` of the specs in specs/, each checked at most once per test process.

tests/test_check_zoo.py judges the whole result (which robots fail, with which codes, and that
ManiSkill's own agents fail the same way); tests/test_physics_checks.py reads the shipped Panda's
(each check passing), fetch's and an inspire hand's findings. Under ``--dist loadfile`` the two
modules usually run in different worker processes, so each asks only for the specs it reads:
the Panda module no longer checks the whole zoo (two minutes) for three robots. Import this
module only from modules marked ``maniskill``.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import SPECS

from robospec.physics.batch import RobotReport, check_paths

_reports: dict[Path, RobotReport] = {}  # by spec path
_whole_zoo: list[bool] = []  # [True] once every spec under specs/ was checked


def shipped_spec_reports(
    tmp_path_factory: pytest.TempPathFactory, specs: list[Path] | None = None
) -> dict[str, RobotReport]:
    """``{uid: report}`` for ``specs`` (default: every spec under specs/), checked with the
    default options; the agents are compiled into the session's temporary cache (never the
    user's)."""
    if specs is None:
        if not _whole_zoo:
            _check(tmp_path_factory, [SPECS])
            _whole_zoo.append(True)
        return {(r.uid or r.spec): r for r in _reports.values()}
    _check(tmp_path_factory, [path for path in specs if path.resolve() not in _reports])
    return {(r.uid or r.spec): r for r in (_reports[path.resolve()] for path in specs)}


def _check(tmp_path_factory: pytest.TempPathFactory, paths: list[Path]) -> None:
    if not paths:
        return
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "cache"))
        found, extra = check_paths(paths)
    assert extra == []
    _reports.update({Path(r.spec).resolve(): r for r in found})
