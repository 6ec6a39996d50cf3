"""`robospec check` over every spec in specs/, run once per test session.

tests/test_check_zoo.py judges the whole result (which robots fail, with which codes, and that
ManiSkill's own agents fail the same way); tests/test_physics_checks.py reads the shipped Panda's
(each check passing), fetch's and an inspire hand's findings from it rather than checking those
robots a second time. Import this module only from modules marked ``maniskill``.
"""

from __future__ import annotations

import pytest
from conftest import SPECS

from robospec.physics.batch import RobotReport, check_paths

_reports: dict[str, RobotReport] = {}


def shipped_spec_reports(tmp_path_factory: pytest.TempPathFactory) -> dict[str, RobotReport]:
    """``{uid: report}`` for every spec under specs/, checked with the default options; the
    agents are compiled into the session's temporary cache (never the user's)."""
    if not _reports:
        with pytest.MonkeyPatch.context() as patch:
            patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "cache"))
            found, extra = check_paths([SPECS])
        assert extra == []
        _reports.update({r.uid or r.spec: r for r in found})
    return _reports
