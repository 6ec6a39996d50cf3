"""Each mend class against the real loader: ManiSkill loads the mended robot and steps it with
finite state, and its links' poses at random configurations, masses and centres of mass equal a
sound description of the same robot's, wherever the mend does not mean to change them (where it
does, the test says what changed). And a built package of a mended robot imports and runs in a
folder where the original description is absent.

The broken descriptions are the docs' catalogue of mend examples (docs/examples/codes/RS7xx).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CODE_EXAMPLES, invoke_robospec

pytestmark = pytest.mark.maniskill

ARM = CODE_EXAMPLES / "RS725" / "arm.urdf"
GRIPPER = CODE_EXAMPLES / "RS710" / "gripper.urdf"
MJCF_DATA = Path(__file__).parent / "data" / "mjcf"

# mend class -> (broken description, policy, the sound description to compare with, what the
# mend means to change: link -> property)
CASES: dict[str, tuple[Path, Any, Path, dict[str, str]]] = {
    "xml": (CODE_EXAMPLES / "RS700/declared.urdf", "repair", ARM, {}),
    "namespaces": (CODE_EXAMPLES / "RS701/prefixed.urdf", "declare", ARM, {}),
    "substitutions": (CODE_EXAMPLES / "RS702/launched.urdf", "defaults", ARM, {}),
    "packages": (CODE_EXAMPLES / "RS703/nameless.urdf", "resolve", ARM, {}),
    "textures": (CODE_EXAMPLES / "RS704/textured.urdf", "drop", ARM, {}),
    "transmissions": (CODE_EXAMPLES / "RS705/reduction.urdf", "drop", ARM, {}),
    # the skewed inertia with its products zeroed is the sound arm's
    "inertia": (CODE_EXAMPLES / "RS706/skewed.urdf", "diagonal", ARM, {}),
    "mass": (CODE_EXAMPLES / "RS707/negative.urdf", "bound", ARM, {"upper_arm": "mass"}),
    "integers": (
        CODE_EXAMPLES / "RS708/camera.urdf",
        "round",
        CODE_EXAMPLES / "RS708/camera_ok.urdf",
        {},
    ),
    "limits": (CODE_EXAMPLES / "RS709/unlimited.urdf", "continuous", ARM, {}),
    "separators": (
        CODE_EXAMPLES / "RS722/commas.urdf",
        "spaces",
        CODE_EXAMPLES / "RS722/arm.urdf",
        {},
    ),
    "mimic": (GRIPPER, "controller", GRIPPER, {}),
    "spherical": (CODE_EXAMPLES / "RS711/ball.urdf", "hinges", ARM, {}),
    # the inertial is the file's: only the collision shape is mirrored
    "mirrors": (CODE_EXAMPLES / "RS714/mirrored.urdf", "copies", ARM, {}),
    # MJCF: ManiSkill loads the model the mend leaves as it loads the sound one
    "includes": (
        CODE_EXAMPLES / "RS712/mounted.xml",
        "inline",
        CODE_EXAMPLES / "RS712/arm.xml",
        {},
    ),
    "geoms": (CODE_EXAMPLES / "RS713/terrain.xml", "drop", CODE_EXAMPLES / "RS713/arm.xml", {}),
    "mesh_names": (
        CODE_EXAMPLES / "RS715/unnamed.xml",
        "mujoco",
        CODE_EXAMPLES / "RS715/arm.xml",
        {},
    ),
    "asset_names": (
        CODE_EXAMPLES / "RS719/repeated.xml",
        "first",
        CODE_EXAMPLES / "RS719/arm.xml",
        {},
    ),
    "geom_meshes": (
        CODE_EXAMPLES / "RS723/defaulted.xml",
        "defaults",
        CODE_EXAMPLES / "RS723/arm.xml",
        {},
    ),
    "axes": (
        CODE_EXAMPLES / "RS724/unaxed.xml",
        "mujoco",
        CODE_EXAMPLES / "RS724/arm.xml",
        {},
    ),
    "mesh_scale": (
        CODE_EXAMPLES / "RS716/scaled.xml",
        "defaults",
        CODE_EXAMPLES / "RS716/arm.xml",
        {},
    ),
    "contype": (
        CODE_EXAMPLES / "RS717/touching.xml",
        "conaffinity",
        CODE_EXAMPLES / "RS717/arm.xml",
        {},
    ),
    "freejoint": (
        CODE_EXAMPLES / "RS718/floating.xml",
        "root",
        CODE_EXAMPLES / "RS718/arm.xml",
        {},
    ),
    "orientations": (
        CODE_EXAMPLES / "RS721/turned.xml",
        "quat",
        CODE_EXAMPLES / "RS721/arm.xml",
        {},
    ),
    # the plates written as geoms of their segments by hand: 21 links where the file has 42
    "bodies": (CODE_EXAMPLES / "RS720/plated.xml", "merge", MJCF_DATA / "merged_plates.xml", {}),
}


def _spec(uid: str, description: Path, mend: dict[str, Any] | None) -> str:
    mended = f", mend: {json.dumps(mend)}" if mend else ""
    kind = "mjcf" if description.suffix == ".xml" else "urdf"
    return textwrap.dedent(
        f"""\
        robospec: 1
        uid: {uid}
        description: {{{kind}: {json.dumps(str(description))}{mended}}}
        controllers:
          all: {{type: pd_joint_pos, joints: "*", lower: null, upper: null, stiffness: 100,
                 damping: 10, force_limit: 10, normalize_action: false}}
        control_modes:
          pd_joint_pos: {{all: all}}
        """
    )


@pytest.fixture(scope="module")
def registered(tmp_path_factory: pytest.TempPathFactory, maniskill: Any) -> dict[str, str]:
    """Every case's mended robot and its sound twin, registered: name -> uid."""
    import robospec

    folder = tmp_path_factory.mktemp("mends")
    uids: dict[str, str] = {}
    for name, (broken, policy, sound, _) in CASES.items():
        for uid, path, mend in (
            (f"mended_{name}", broken, {name: policy}),
            (f"sound_{name}", sound, None),
        ):
            (folder / f"{uid}.yaml").write_text(_spec(uid, path, mend))
            uids[uid] = uid
    robospec.register(folder)
    return uids


def _physics(uid: str, configurations: list[dict[str, float]]) -> dict[str, Any]:
    """What the loaded robot is: masses and centres of mass by link, link poses at each
    configuration (joints by name; others 0), and whether 20 random steps stay finite."""
    import torch

    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(uid)
    try:
        env.reset(seed=0)
        robot = env.unwrapped.agent.robot
        links = {link.name: link for link in robot.get_links()}
        joints = [j.name for j in robot.get_active_joints()]
        bodies = {name: link._objs[0] for name, link in links.items()}
        result: dict[str, Any] = {
            "mass": {n: float(b.mass) for n, b in bodies.items()},
            "com": {n: np.asarray(b.cmass_local_pose.p) for n, b in bodies.items()},
            "poses": [],
        }
        for configuration in configurations:
            qpos = torch.zeros((1, len(joints)))
            for i, name in enumerate(joints):
                qpos[0, i] = configuration.get(name, 0.0)
            robot.set_qpos(qpos)
            result["poses"].append(
                {n: np.asarray(link.pose.raw_pose[0]) for n, link in links.items()}
            )
        robot.set_qpos(torch.zeros((1, len(joints))))
        finite = True
        for _ in range(20):
            obs, *_ = env.step(env.action_space.sample())
            finite = finite and bool(torch.isfinite(obs).all())
        result["finite"] = finite
        return result
    finally:
        env.close()


def _configurations(name: str, rng: np.random.Generator) -> tuple[list[dict], list[dict]]:
    """Random configurations for the sound robot and the same ones for the mended one."""
    if name == "mimic":
        sound = [
            {"left": v, "right": v} for v in rng.uniform(0, 0.04, size=4)
        ]  # the coupling the mimic tag and the controller both say
        return sound, sound
    angles = rng.uniform(-3, 3, size=4)
    if name == "bodies":  # the snake's joints (30 degrees either way), three at a time
        bent = [
            {"joint1": float(a), "joint8": float(-a), "joint20": float(a / 2)}
            for a in rng.uniform(-0.5, 0.5, size=4)
        ]
        return bent, bent
    sound = [{"shoulder": float(a)} for a in angles]
    if name == "spherical":  # the ball's rotation about z alone is the hinge's
        return sound, [{"shoulder_z": float(a)} for a in angles]
    return sound, sound


@pytest.mark.parametrize("name", list(CASES))
def test_the_mended_robot_loads_steps_finite_and_is_the_sound_robot_where_not_meant_to_change(
    name: str, registered: dict[str, str]
) -> None:
    _, _, _, changed = CASES[name]
    sound_qpos, mended_qpos = _configurations(name, np.random.default_rng(7))
    sound = _physics(registered[f"sound_{name}"], sound_qpos)
    mended = _physics(registered[f"mended_{name}"], mended_qpos)
    assert mended["finite"]
    for link, mass in sound["mass"].items():
        if changed.get(link) == "mass":
            assert mended["mass"][link] == pytest.approx(0.001)  # the bound, as noted
            continue
        assert mended["mass"][link] == pytest.approx(mass, rel=1e-6), link
        assert np.allclose(mended["com"][link], sound["com"][link], atol=1e-6), link
    for at_sound, at_mended in zip(sound["poses"], mended["poses"], strict=True):
        for link, pose in at_sound.items():
            other = at_mended[link]
            assert np.allclose(other[:3], pose[:3], atol=1e-5), (link, other, pose)
            # a quaternion and its negative are one rotation
            assert (
                min(np.abs(other[3:] - pose[3:]).max(), np.abs(other[3:] + pose[3:]).max()) < 1e-5
            )


def test_a_built_package_of_a_mended_robot_runs_where_the_original_is_absent(
    tmp_path: Path, maniskill: Any
) -> None:
    original = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS705", original)
    spec = original / "mended.yaml"
    spec.write_text(_spec("moved_arm", original / "reduction.urdf", {"transmissions": "drop"}))
    built = invoke_robospec("build", str(spec), "-o", str(tmp_path / "out" / "moved_agents"))
    assert built.exit_code == 0, built.output
    elsewhere = tmp_path / "elsewhere"
    shutil.move(tmp_path / "out" / "moved_agents", elsewhere / "moved_agents")
    shutil.rmtree(original)
    script = textwrap.dedent(
        """\
        import moved_agents, torch
        from robospec.maniskill.headless import make_empty_env
        env = make_empty_env("moved_arm")
        obs, _ = env.reset(seed=0)
        for _ in range(10):
            obs, *_ = env.step(env.action_space.sample())
        links = env.unwrapped.agent.robot.get_links()
        shapes = sum(len(link._objs[0].collision_shapes) for link in links)
        print("finite", bool(torch.isfinite(obs).all()), "shapes", shapes)
        """
    )
    ran = subprocess.run(
        [sys.executable, "-c", script],
        cwd=elsewhere,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert ran.returncode == 0, ran.stderr[-2000:]
    # the mesh was copied in: the upper arm still has its collision shape
    assert "finite True shapes 1" in ran.stdout
