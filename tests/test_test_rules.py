"""The rules tests/conftest.py sets for the suite itself, proved on small suites run in a child
pytest with the same conftest and a stand-in ``mani_skill`` package (quick to import, or one
that fails to import like a missing install):

- the fast loop deselects a test that asks for the ``maniskill`` fixture, does not even import a
  module marked ``maniskill``, and fails an unmarked test that imports ManiSkill;
- without ManiSkill, a test that needs it fails, whether it asks for the fixture or calls
  ``pytest.importorskip``: nothing is skipped in silence;
- pytest-xdist (``--dist loadfile``) starts the modules marked ``minutes`` first, whatever
  their number of tests.
"""

from __future__ import annotations

import pytest
from conftest import ROOT

pytest_plugins = ["pytester"]

FAST = ("-m", "not maniskill and not slow")

SUITE = {
    "test_needs_fixture.py": """
        def test_uses_maniskill(maniskill):
            assert maniskill.__name__ == "mani_skill"
    """,
    "test_whole_module.py": """
        import pytest

        pytestmark = pytest.mark.maniskill
        raise RuntimeError("imported although every test here is deselected")
    """,
    "test_unmarked.py": """
        def test_plain():
            assert True

        def test_imports_maniskill_unmarked():
            import mani_skill.envs  # noqa: F401
    """,
    "test_importorskip.py": """
        import pytest

        def test_skips_for_maniskill():
            pytest.importorskip("mani_skill")
    """,
}


@pytest.fixture
def suite(pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch) -> pytest.Pytester:
    pytester.makeconftest((ROOT / "tests" / "conftest.py").read_text(encoding="utf-8"))
    # the plugin the conftest loads (where the run's time went)
    pytester.makepyfile(durations=(ROOT / "tests" / "durations.py").read_text(encoding="utf-8"))
    pytester.makeini(
        "[pytest]\nmarkers =\n    maniskill\n    slow\n    minutes\n"
        "asyncio_default_fixture_loop_scope = function\n"
    )
    pytester.makepyfile(**SUITE)
    monkeypatch.setenv("PYTHONPATH", str(pytester.path))  # the stand-in comes first
    return pytester


def stand_in(pytester: pytest.Pytester, body: str) -> None:
    package = pytester.mkpydir("mani_skill")
    (package / "__init__.py").write_text(body)
    (package / "envs.py").write_text("")


@pytest.mark.slow
def test_the_fast_loop_leaves_out_maniskill_tests_and_fails_an_unmarked_import(
    suite: pytest.Pytester,
) -> None:
    stand_in(suite, "")
    result = suite.runpytest_subprocess(*FAST, "-p", "no:cacheprovider", "-rA")
    result.assert_outcomes(passed=1, failed=2, deselected=1)
    result.stdout.fnmatch_lines(
        [
            "*test_skips_for_maniskill imported mani_skill but is not marked 'maniskill'*",
            "*test_imports_maniskill_unmarked imported mani_skill but is not marked 'maniskill'*",
        ]
    )
    assert "imported although every test here is deselected" not in result.stdout.str()


@pytest.mark.slow
def test_without_maniskill_the_tests_that_need_it_fail_instead_of_skipping(
    suite: pytest.Pytester,
) -> None:
    # what importing a package that is not installed raises
    # (were the real ManiSkill imported instead, these tests would pass: the counts below say
    # the stand-in was the one found)
    stand_in(
        suite, "raise ModuleNotFoundError(\"No module named 'mani_skill'\", name='mani_skill')"
    )
    (suite.path / "test_whole_module.py").unlink()  # its import fails by design
    suite.makepyfile(
        test_module_importorskip="""
        import pytest

        pytestmark = pytest.mark.maniskill
        pytest.importorskip("mani_skill")

        def test_never_collected():
            pass
        """
    )
    result = suite.runpytest_subprocess(
        "-p", "no:cacheprovider", "-rA", "--continue-on-collection-errors"
    )
    # the fixture fails in setup and the module's importorskip in collection (errors);
    # importorskip and the plain import in a test's call (failures)
    result.assert_outcomes(passed=1, failed=2, errors=2)
    assert result.stdout.str().count("the maniskill extra is not installed") >= 3
    assert "SKIPPED" not in result.stdout.str()


@pytest.mark.slow  # two more child runs; the fast loop's own rules are proved above
def test_the_rules_read_the_mark_expression_not_a_fixed_string(suite: pytest.Pytester) -> None:
    # "not maniskill" alone is a fast run too; "maniskill or not maniskill" is not
    stand_in(suite, "")
    fast = suite.runpytest_subprocess("-m", "not maniskill", "-p", "no:cacheprovider")
    fast.assert_outcomes(passed=1, failed=2, deselected=1)
    every = suite.runpytest_subprocess(
        "-m",
        "maniskill or not maniskill",
        "-p",
        "no:cacheprovider",
        "--ignore",
        "test_whole_module.py",
    )
    every.assert_outcomes(passed=4)


@pytest.mark.slow
def test_xdist_starts_the_modules_of_minutes_first_whatever_their_number_of_tests(
    suite: pytest.Pytester,
) -> None:
    # xdist's own order would start the module with the most tests first
    stand_in(suite, "")
    order = suite.path / "order.txt"
    record = (
        f"def record(name):\n    with open({str(order)!r}, 'a') as handle:\n"
        "        handle.write(name + '\\n')\n"
    )
    suite.makepyfile(
        test_many=record + "".join(f"def test_{i}():\n    record('many')\n" for i in range(5)),
        test_long=record
        + "import pytest\npytestmark = pytest.mark.minutes\ndef test_long():\n    record('long')\n",
    )
    result = suite.runpytest_subprocess(
        "-n", "1", "--dist", "loadfile", "-p", "no:cacheprovider", "test_many.py", "test_long.py"
    )
    result.assert_outcomes(passed=6)
    assert order.read_text().split() == ["long"] + ["many"] * 5
