"""Nothing lost: a killed, concurrent or obstructed `robospec build` never leaves a broken folder.

Real `robospec build` processes are killed with SIGKILL at random moments and run two at a time;
the output folder must always hold one complete build (the previous one or the new one), and
files that robospec did not write (including symbolic links and what they point at) stay as they
were.
"""

from __future__ import annotations

import os
import random
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT, SAME_ON_EVERY_MANISKILL

from robospec.output.package import MANIFEST

pytestmark = [
    pytest.mark.minutes,
    pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL and flock are POSIX"),
    SAME_ON_EVERY_MANISKILL,
]


def build_command(specs: Path, out: Path) -> list[str]:
    return [sys.executable, "-m", "robospec.cli", "build", str(specs), "-o", str(out)]


def build(specs: Path, out: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        build_command(specs, out), cwd=ROOT, capture_output=True, text=True, timeout=120
    )


def snapshot(folder: Path) -> dict[str, bytes]:
    """The build as a reader sees it: every plain file (bytecode caches aside)."""
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def leftovers(out: Path) -> list[str]:
    return sorted(p.name for p in out.parent.iterdir() if p.name != out.name)


@pytest.fixture
def versions(tmp_path: Path) -> tuple[Path, Path]:
    """Two spec folders whose builds differ: v2 changes a module, and adds one (a TOML + xacro
    spec and a YAML spec in both)."""
    old, new = tmp_path / "v1", tmp_path / "v2"
    for folder in (old, new):
        shutil.copytree(ROOT / "specs/robots/twolink", folder / "robots/twolink")
        shutil.copy(ROOT / "specs/twolink.toml", folder / "twolink.toml")
        shutil.copy(ROOT / "tests/specs/positive/minimal.yaml", folder / "minimal.yaml")
    minimal = new / "minimal.yaml"
    minimal.write_text(minimal.read_text().replace("stiffness: 1e3", "stiffness: 2e3"))
    (new / "extra.yaml").write_text(minimal.read_text().replace("uid: rs_test", "uid: rs_extra"))
    return old, new


@pytest.fixture
def built(versions: tuple[Path, Path], tmp_path: Path) -> dict[str, dict[str, bytes]]:
    """The complete output of each version, built once, undisturbed."""
    states = {}
    for version in versions:
        out = tmp_path / "reference" / version.name / "agents"
        result = build(version, out)
        assert result.returncode == 0, result.stdout + result.stderr
        states[version.name] = snapshot(out)
    assert states["v1"] != states["v2"]
    return states


def kill_after(command: list[str], delay: float) -> None:
    process = subprocess.Popen(
        command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    time.sleep(delay)
    process.send_signal(signal.SIGKILL)
    process.wait()


def build_seconds(specs: Path, out: Path) -> float:
    start = time.monotonic()
    assert build(specs, out).returncode == 0
    return time.monotonic() - start


class KillDelays:
    """Delays that home in on the moment a build finishes, whatever the machine's speed.

    One timed build is only a first guess: on a loaded CI machine later builds may take twice as
    long, and kills timed from the guess would all land while compiling. So this is a staircase:
    after a kill that left the old output the next delay is longer, after one that left the new
    output shorter. The delays settle around the renames, where the interesting kills are, and
    land on both sides of them however far off the first guess was.
    """

    STEP = 1.2

    def __init__(self, first_guess: float, seed: int) -> None:
        self.centre = first_guess
        self.rng = random.Random(seed)

    def next(self) -> float:
        return self.centre * self.rng.uniform(0.8, 1.1)

    def landed(self, *, finished: bool) -> None:
        self.centre = self.centre / self.STEP if finished else self.centre * self.STEP


def killed_builds(
    versions: tuple[Path, Path],
    built: dict[str, dict[str, bytes]],
    out: Path,
    tmp_path: Path,
    *,
    rounds: int,
    seed: int,
) -> Iterator[dict[str, bytes]]:
    """Build the new version into `out` and kill it, `rounds` times; yield what each kill left.

    A round whose build finished before its kill is followed by a build of the old version, so
    every round kills a real old-to-new build.
    """
    old, new = versions
    delays = KillDelays(build_seconds(new, tmp_path / "timing" / "agents"), seed=seed)
    for _ in range(rounds):
        kill_after(build_command(new, out), delays.next())
        state = snapshot(out)
        finished = all(state.get(name) == data for name, data in built["v2"].items())
        yield state
        delays.landed(finished=finished)
        if finished:
            assert build(old, out).returncode == 0


@pytest.mark.slow  # rounds of real builds, killed or raced
def test_a_build_killed_at_any_moment_leaves_the_old_or_the_new_output_complete(
    versions: tuple[Path, Path], built: dict[str, dict[str, bytes]], tmp_path: Path
) -> None:
    old, new = versions
    out = tmp_path / "run" / "agents"
    assert build(old, out).returncode == 0
    seen: list[str] = []
    for state in killed_builds(versions, built, out, tmp_path, rounds=24, seed=6):
        # the folder must exist and hold one whole build
        assert state in (built["v1"], built["v2"]), sorted(state)
        seen.append("new" if state == built["v2"] else "old")
    # the next build recovers: the new output, and nothing left beside it
    assert build(new, out).returncode == 0
    assert snapshot(out) == built["v2"]
    assert leftovers(out) == []
    assert "old" in seen and "new" in seen, seen  # the kills did land on both sides


@pytest.mark.slow  # rounds of real builds, killed or raced
def test_a_killed_build_beside_the_users_files_keeps_them_and_every_file_whole(
    versions: tuple[Path, Path], built: dict[str, dict[str, bytes]], tmp_path: Path
) -> None:
    old, new = versions
    out = tmp_path / "run" / "agents"
    assert build(old, out).returncode == 0
    (out / "NOTES.txt").write_text("mine\n")
    for state in killed_builds(versions, built, out, tmp_path, rounds=12, seed=7):
        assert state.pop("NOTES.txt") == b"mine\n"
        assert_whole_and_listed(state, built)
    assert build(new, out).returncode == 0  # the next build completes the job
    state = snapshot(out)
    assert state.pop("NOTES.txt") == b"mine\n"
    assert state == built["v2"]
    assert leftovers(out) == []


def assert_whole_and_listed(state: dict[str, bytes], built: dict[str, dict[str, bytes]]) -> None:
    """What a build beside the user's files left: each file whole, as in one build or the
    other, nothing of the old build missing, and every file of ours listed in the manifest
    (which may list the old build's and the new one's, mid-way), so the next build owns them."""
    listed = set(state.pop(MANIFEST).decode().splitlines()[1:])
    for name, data in state.items():
        assert data in (built["v1"].get(name), built["v2"].get(name)), name
    assert set(built["v1"]) - {MANIFEST} <= set(state)
    assert set(state) <= listed


@pytest.mark.slow
def test_a_build_cut_short_beside_the_users_files_is_finished_by_the_next(
    versions: tuple[Path, Path], built: dict[str, dict[str, bytes]], tmp_path: Path
) -> None:
    # Every moment a build beside the user's files can stop at, in turn: each file it puts in
    # place is a rename, and the process dies at the n-th (the kill tests hit these by chance).
    from robospec.output import package
    from robospec.pipeline import compile_all

    compiled = {v.name: compile_all([v])[0] for v in versions}
    renames = 0
    real_replace = os.replace
    for cut in range(1, 20):
        out = tmp_path / f"cut{cut}" / "agents"
        assert not package.build_package(compiled["v1"], out, check=False).diagnostics
        (out / "NOTES.txt").write_text("mine\n")
        dying_replace = _dying_at(cut, real_replace)

        try:
            with pytest.MonkeyPatch.context() as patch:
                patch.setattr(package.os, "replace", dying_replace)
                package.build_package(compiled["v2"], out, check=False)
        except _Killed:
            renames = max(renames, cut)
        else:
            break  # the build made fewer renames than `cut`: every moment was tried
        state = snapshot(out)
        assert state.pop("NOTES.txt") == b"mine\n"
        assert_whole_and_listed(state, built)
        result = package.build_package(compiled["v2"], out, check=False)
        assert not result.diagnostics, [d.format_text() for d in result.diagnostics]
        state = snapshot(out)
        assert state.pop("NOTES.txt") == b"mine\n"
        assert state == built["v2"]
        assert leftovers(out) == []
    assert renames >= 4  # the manifest twice, a changed module, a new one


def _dying_at(cut: int, real_replace: Callable[[Any, Any], None]) -> Callable[[Any, Any], None]:
    """``os.replace`` for a process that dies at its ``cut``-th rename."""
    calls = 0

    def dying_replace(src: Any, dst: Any) -> None:
        nonlocal calls
        calls += 1
        if calls == cut:
            raise _Killed
        real_replace(src, dst)

    return dying_replace


class _Killed(BaseException):
    """The build's process dies here (not an OSError: nothing is reported, nothing tidied)."""


@pytest.mark.slow
def test_a_build_killed_between_its_two_renames_is_put_back_by_the_next(
    versions: tuple[Path, Path], built: dict[str, dict[str, bytes]], tmp_path: Path
) -> None:
    # Where renameat2 cannot swap the folders, the old folder is moved aside, then the new one
    # into place. A kill between the two leaves exactly this: no output, the old one aside.
    old, _ = versions
    out = tmp_path / "run" / "agents"
    assert build(old, out).returncode == 0
    os.replace(out, out.with_name(".agents.robospec-k1ll3d.old"))
    (out.parent / ".agents.robospec-st4g3").mkdir()  # a staging folder it was filling
    result = build(old, out)
    assert result.returncode == 0, result.stdout
    assert "up to date" in result.stdout  # recovered the previous build: nothing to rewrite
    assert snapshot(out) == built["v1"]
    assert leftovers(out) == []


@pytest.mark.slow  # rounds of real builds, killed or raced
def test_two_concurrent_builds_of_one_folder_leave_one_complete_build(
    versions: tuple[Path, Path], built: dict[str, dict[str, bytes]], tmp_path: Path
) -> None:
    old, new = versions
    for round_ in range(8):
        out = tmp_path / f"round{round_}" / "agents"
        if round_ % 2:  # half the rounds start from an existing build, half from nothing
            assert build(old, out).returncode == 0
        processes = [
            subprocess.Popen(
                build_command(specs, out),
                cwd=ROOT,
                stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT,
                text=True,
            )
            for specs in (old, new)
        ]
        outputs = [p.communicate(timeout=120)[0] for p in processes]
        assert [p.returncode for p in processes] == [0, 0], outputs
        assert snapshot(out) in (built["v1"], built["v2"])
        assert leftovers(out) == []


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_a_symlink_in_the_output_folder_is_never_followed_or_replaced(
    versions: tuple[Path, Path], tmp_path: Path
) -> None:
    old, _ = versions
    out = tmp_path / "run" / "agents"
    assert build(old, out).returncode == 0
    elsewhere = tmp_path / "elsewhere.py"
    elsewhere.write_text("# the user's\n")
    # the user replaced a generated module by a link to their own file
    (out / "twolink.py").unlink()
    (out / "twolink.py").symlink_to(elsewhere)
    (out / "data").symlink_to(tmp_path)  # and keeps a link to a folder there
    result = build(old, out)
    assert result.returncode == 1
    assert "RS604" in result.stdout and "twolink.py" in result.stdout
    assert (out / "twolink.py").is_symlink() and os.readlink(out / "twolink.py") == str(elsewhere)
    assert elsewhere.read_text() == "# the user's\n"
    assert (out / "data").is_symlink()


@pytest.mark.slow
def test_a_link_to_the_output_folder_is_kept_and_its_target_built(
    versions: tuple[Path, Path], built: dict[str, dict[str, bytes]], tmp_path: Path
) -> None:
    old, _ = versions
    real = tmp_path / "real" / "agents"
    real.mkdir(parents=True)
    link = tmp_path / "linked" / "agents"
    link.parent.mkdir()
    link.symlink_to(real)
    assert build(old, link).returncode == 0
    assert link.is_symlink()
    assert snapshot(real) == built["v1"]
    assert build(old, link).returncode == 0  # again, with our files there: a folder swap
    assert link.is_symlink() and snapshot(real) == built["v1"]


def test_an_output_folder_that_cannot_be_written_is_a_diagnostic(
    versions: tuple[Path, Path], tmp_path: Path
) -> None:
    old, _ = versions
    blocker = tmp_path / "afile"
    blocker.write_text("not a folder\n")
    result = build(old, blocker / "agents")
    assert result.returncode == 1
    assert "error[RS603]" in result.stdout
    assert "Traceback" not in result.stdout + result.stderr
