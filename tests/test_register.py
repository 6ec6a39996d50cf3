"""Import-time registration: returns and registers the classes, compiles once and then loads
from the cache, and raises SpecError (registering nothing) on bad specs or a taken uid.

What the cache trusts and rebuilds (damaged, stale or unwritable entries) is
tests/test_cache_safety.py's."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import MISSPELLED_JOINT_SPEC, PANDA_SPEC

import robospec
from robospec import SpecError

pytestmark = pytest.mark.maniskill


@pytest.fixture
def panda_spec(tmp_path: Path) -> Path:
    """A panda spec under a fresh uid, so each test registers its own agent."""
    text = PANDA_SPEC.read_text()
    path = tmp_path / "panda.yaml"
    path.write_text(text.replace("uid: rs_panda", f"uid: rs_panda_{tmp_path.name[-12:]}"))
    return path


def test_register_returns_the_registered_class(panda_spec: Path, tmp_path: Path) -> None:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    classes = robospec.register(panda_spec, cache_dir=tmp_path / "cache")
    ((uid, cls),) = classes.items()
    assert REGISTERED_AGENTS[uid].agent_cls is cls
    assert cls.__name__.startswith("RsPanda")


def test_a_warm_cache_does_not_recompile(panda_spec: Path, tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    robospec.register(panda_spec, cache_dir=cache)
    # a new process with the compiler made unimportable must still register from the cache
    probe = (
        "import sys\n"
        "sys.modules['robospec.pipeline'] = None\n"
        "import mani_skill.envs, robospec\n"
        f"print(list(robospec.register({str(panda_spec)!r}, cache_dir={str(cache)!r})))\n"
        "heavy = ('pydantic', 'ruamel.yaml', 'robospec.model')\n"
        "print('LIGHT', [m for m in heavy if m in sys.modules])\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    assert "rs_panda_" in result.stdout
    assert "LIGHT []" in result.stdout


def test_errors_raise_spec_error_with_the_diagnostics_and_register_nothing(tmp_path: Path) -> None:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    before = set(REGISTERED_AGENTS)
    with pytest.raises(SpecError) as caught:
        robospec.register(MISSPELLED_JOINT_SPEC, cache_dir=tmp_path / "cache")
    (diagnostic,) = caught.value.diagnostics
    assert (diagnostic.code, diagnostic.location.line, diagnostic.location.column) == (
        "RS201",
        6,
        51,
    )
    assert set(REGISTERED_AGENTS) == before


def test_a_uid_registered_by_other_code_is_an_error_not_a_silent_skip(
    panda_spec: Path, tmp_path: Path
) -> None:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    robospec.register(panda_spec, cache_dir=tmp_path / "a")
    uid = next(u for u in REGISTERED_AGENTS if u.startswith("rs_panda_" + tmp_path.name[-12:]))
    other = tmp_path / "copy" / "panda.yaml"
    other.parent.mkdir()
    other.write_text(panda_spec.read_text() + "\n# a different spec, same uid\n")
    with pytest.raises(SpecError) as caught:
        robospec.register(other, cache_dir=tmp_path / "b")
    assert caught.value.diagnostics[0].code == "RS306"
    assert uid in str(caught.value)


def test_a_spec_edited_and_registered_again_replaces_its_own_agent(
    panda_spec: Path, tmp_path: Path
) -> None:
    # a notebook's loop: register, edit the spec, register again — the new agent, not RS306
    from mani_skill.agents.registration import REGISTERED_AGENTS

    cache = tmp_path / "cache"
    (first,) = robospec.register(panda_spec, cache_dir=cache).values()
    panda_spec.write_text(panda_spec.read_text().replace("stiffness: 1e3", "stiffness: 2e3"))
    classes = robospec.register(panda_spec, cache_dir=cache)
    ((uid, second),) = classes.items()
    assert second is not first
    assert REGISTERED_AGENTS[uid].agent_cls is second
    assert (first.arm_stiffness, second.arm_stiffness) == (1e3, 2e3)


def test_a_robot_maniskill_cannot_load_raises_a_located_spec_error_when_an_env_loads_it(
    tmp_path: Path,
) -> None:
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)

    data = Path(__file__).parent / "data" / "check"
    shutil.copy(data / "tendon.urdf", tmp_path / "tendon.urdf")
    spec = tmp_path / "specs" / "tendon.yaml"
    spec.parent.mkdir()
    uid = f"rs_tendon_{tmp_path.name[-12:]}"
    text = (data / "isolation" / "b_tendon.yaml").read_text()
    spec.write_text(text.replace("uid: rs_test_tendon", f"uid: {uid}"))
    robospec.register(spec, cache_dir=tmp_path / "cache")
    with pytest.raises(SpecError) as raised:
        gym.make(
            "Empty-v1",
            robot_uids=uid,
            obs_mode="state",
            sim_backend="physx_cpu",
            render_backend="none",
        )
    # what check says of it (RS514), at the joint whose <mimic> PhysX refused as a tendon
    (diagnostic,) = raised.value.diagnostics
    assert diagnostic.code == "RS514" and diagnostic.location.file.endswith("tendon.urdf")
    line = next(
        n
        for n, text in enumerate((tmp_path / "tendon.urdf").read_text().splitlines(), 1)
        if '<joint name="j2"' in text
    )
    assert diagnostic.location.line == line
    assert "failed to create tendon" in diagnostic.message
    assert "upstream's code, not robospec's" in diagnostic.message
    assert isinstance(raised.value.__cause__, RuntimeError)


def test_a_built_package_of_a_robot_maniskill_cannot_load_raises_the_same_located_error(
    tmp_path: Path,
) -> None:
    from conftest import invoke_robospec

    data = Path(__file__).parent / "data" / "check"
    shutil.copy(data / "tendon.urdf", tmp_path / "tendon.urdf")
    spec = tmp_path / "specs" / "tendon.yaml"
    spec.parent.mkdir()
    text = (data / "isolation" / "b_tendon.yaml").read_text()
    spec.write_text(text.replace("uid: rs_test_tendon", "uid: rs_built_tendon"))
    built = invoke_robospec("build", str(spec), "-o", str(tmp_path / "tendon_agents"))
    assert built.exit_code == 0, built.output
    script = (
        "import tendon_agents, robospec\n"
        "from robospec.maniskill.headless import make_empty_env\n"
        "try:\n"
        "    make_empty_env('rs_built_tendon')\n"
        "except robospec.SpecError as exc:\n"
        "    (d,) = exc.diagnostics\n"
        "    print('LOCATED', d.code, d.location.file.split('/')[-1], d.location.line)\n"
        "    print('CAUSE', type(exc.__cause__).__name__)\n"
    )
    ran = subprocess.run(
        [sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert ran.returncode == 0, ran.stderr[-2000:]
    urdf = tmp_path / "tendon.urdf"
    lines = urdf.read_text().splitlines()
    line = next(n for n, t in enumerate(lines, 1) if '<joint name="j2"' in t)
    assert f"LOCATED RS514 tendon.urdf {line}" in ran.stdout, ran.stdout + ran.stderr[-2000:]
    assert "CAUSE RuntimeError" in ran.stdout
