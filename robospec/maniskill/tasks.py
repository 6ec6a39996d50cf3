"""Which members of the agent each task of the installed ManiSkill calls, read from ManiSkill's
own source without importing it (as :mod:`.installed` reads the uids it registers).

A task is a class decorated with ``register_env("ID", ...)`` in the modules that ``import
mani_skill.envs`` imports (ManiSkill also registers its scene-builder variants of
``SceneManipulation-v1`` in a loop: exploration scenes, no task, not read here). Its members
are the attributes it reads off its agent (``self.agent.tcp.pose``,
``self.agent.is_grasping(self.cube)``), its own and its base classes' (by name, among
ManiSkill's tasks). Of those, the ones a robot must bring are the members
``BaseAgent`` does not define, or defines only to raise ``NotImplementedError``
(``is_grasping``, ``is_static``): :meth:`Scan.needed`. The scan is kept in robospec's cache
under the installation's identity, so each ManiSkill is read once. Without ManiSkill installed,
3.0.1's tasks stand in (:data:`TASKS_OF_3_0_1`, kept equal to a scan of 3.0.1 by a test).

``FAMILIES`` names sets of tasks by their folder (``--task tabletop``: the tasks of
``mani_skill/envs/tasks/tabletop``).
"""

from __future__ import annotations

import ast
import json
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from robospec.files import cache_root, write_atomically
from robospec.maniskill.installed import (
    Installed,
    executed_statements,
    imported_modules,
    installed,
)

_SCAN_FORMAT = "1"
TASKS_FOLDER = ("envs", "tasks")


@dataclass(frozen=True)
class Task:
    """One task ManiSkill registers, and what it reads off its agent."""

    id: str  # "PickCube-v1"
    family: str  # the folder under mani_skill/envs/tasks: "tabletop", "" at the top
    members: tuple[str, ...]  # every attribute it reads off self.agent, sorted


@dataclass(frozen=True)
class Scan:
    """Every task of one ManiSkill, and what its BaseAgent defines."""

    tasks: dict[str, Task]
    base_members: frozenset[str]  # what BaseAgent defines (and does not leave unimplemented)

    def needed(self, task_id: str) -> tuple[str, ...]:
        """The members ``task_id`` calls that a robot must bring itself."""
        task = self.tasks[task_id]
        return tuple(m for m in task.members if m not in self.base_members)

    def family(self, name: str) -> list[str]:
        return sorted(t.id for t in self.tasks.values() if t.family == name)

    @property
    def families(self) -> list[str]:
        return sorted({t.family for t in self.tasks.values() if t.family})


def installed_tasks() -> Scan:
    """The tasks of the installed ManiSkill (3.0.1's without ManiSkill: a spec meant for a
    task should work in the ManiSkill most users install)."""
    return _scan(installed())


@cache
def _scan(found: Installed | None) -> Scan:
    if found is None:
        return Scan(
            {k: Task(k, family, members) for k, (family, members) in TASKS_OF_3_0_1.items()},
            frozenset(),
        )
    import zlib

    key = f"{zlib.crc32(found.identity.encode()):08x}"
    cached = cache_root() / "maniskill" / f"tasks-{_SCAN_FORMAT}-{key}.json"
    try:
        return _from_json(json.loads(cached.read_text(encoding="utf-8")))
    except (OSError, ValueError, KeyError, TypeError):
        pass
    scan = scan_tasks(found.package_dir)
    try:
        write_atomically(cached, json.dumps(_to_json(scan), sort_keys=True))
    except OSError:
        pass  # a read-only cache: scan again next time
    return scan


def _to_json(scan: Scan) -> dict[str, object]:
    return {
        "tasks": {k: [t.family, list(t.members)] for k, t in scan.tasks.items()},
        "base": sorted(scan.base_members),
    }


def _from_json(data: dict) -> Scan:
    tasks = {k: Task(k, v[0], tuple(v[1])) for k, v in data["tasks"].items()}
    if not tasks:
        raise ValueError("empty scan")
    return Scan(tasks, frozenset(data["base"]))


def scan_tasks(package_dir: Path) -> Scan:
    """Read the tasks of the ManiSkill whose ``mani_skill`` package is ``package_dir``."""
    classes: dict[str, tuple[tuple[str, ...], ast.ClassDef]] = {}
    registered: list[tuple[str, tuple[str, ...], ast.ClassDef]] = []
    for name, tree in imported_modules(package_dir, ("envs",)):
        for node in executed_statements(tree):
            if not isinstance(node, ast.ClassDef):
                continue
            classes.setdefault(node.name, (name, node))
            for decorator in node.decorator_list:
                task_id = _registered_id(decorator)
                if task_id is not None:
                    registered.append((task_id, name, node))
    tasks = {}
    for task_id, module, node in registered:
        members: set[str] = set()
        _collect(node, classes, members, set())
        tasks[task_id] = Task(task_id, _family(module), tuple(sorted(members)))
    return Scan(tasks, _base_agent_members(package_dir))


def _registered_id(decorator: ast.expr) -> str | None:
    if not isinstance(decorator, ast.Call):
        return None
    target = decorator.func
    name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", None)
    if name != "register_env" or not decorator.args:
        return None
    first = decorator.args[0]
    return first.value if isinstance(first, ast.Constant) and isinstance(first.value, str) else None


def _family(module: tuple[str, ...]) -> str:
    if module[: len(TASKS_FOLDER)] != TASKS_FOLDER or len(module) <= len(TASKS_FOLDER) + 1:
        return ""
    return module[len(TASKS_FOLDER)]


def _collect(
    node: ast.ClassDef,
    classes: dict[str, tuple[tuple[str, ...], ast.ClassDef]],
    members: set[str],
    seen: set[str],
) -> None:
    """The attributes ``node`` (and its bases among ManiSkill's tasks: not ``BaseEnv``, whose
    code reads ``self.agent`` for every robot) read off ``self.agent``."""
    seen.add(node.name)
    for child in ast.walk(node):
        if (
            isinstance(child, ast.Attribute)
            and isinstance(child.value, ast.Attribute)
            and child.value.attr == "agent"
            and isinstance(child.value.value, ast.Name)
            and child.value.value.id == "self"
        ):
            members.add(child.attr)
    for base in node.bases:
        name = base.attr if isinstance(base, ast.Attribute) else getattr(base, "id", None)
        if name in classes and name not in seen and _is_task_module(classes[name][0]):
            _collect(classes[name][1], classes, members, seen)


def _is_task_module(module: tuple[str, ...]) -> bool:
    return module[: len(TASKS_FOLDER)] == TASKS_FOLDER


def _base_agent_members(package_dir: Path) -> frozenset[str]:
    """What ``BaseAgent`` defines — methods, properties, attributes it assigns — less the
    methods whose body only raises ``NotImplementedError``."""
    path = package_dir / "agents" / "base_agent.py"
    try:
        tree = ast.parse(path.read_bytes(), str(path))
    except (OSError, SyntaxError, ValueError):
        return frozenset()
    base = next(
        (n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "BaseAgent"), None
    )
    if base is None:
        return frozenset()
    found: set[str] = set()
    for node in ast.walk(base):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node in base.body:
            if not _only_raises(node):
                found.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            found.add(node.target.id)
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Name) and node in base.body:
                    found.add(target.id)
                elif (
                    isinstance(target, ast.Attribute)
                    and isinstance(target.value, ast.Name)
                    and target.value.id == "self"
                ):
                    found.add(target.attr)
    return frozenset(found)


def _only_raises(function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    body = [
        s
        for s in function.body
        if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))  # a docstring
    ]
    return (
        len(body) == 1
        and isinstance(body[0], ast.Raise)
        and "NotImplementedError" in ast.unparse(body[0])
    )


# The tasks ManiSkill 3.0.1 registers, with their family and the members a robot must bring:
# where no ManiSkill is installed to read them from. tests/test_installed_maniskill.py keeps
# this equal to a scan of 3.0.1.
TASKS_OF_3_0_1: dict[str, tuple[str, tuple[str, ...]]] = {
    "AnymalC-Reach-v1": ("quadruped", ("is_fallen",)),
    "AnymalC-Spin-v1": ("quadruped", ("is_fallen",)),
    "AssemblingKits-v1": ("tabletop", ("tcp",)),
    "DrawSVG-v1": ("drawing", ("tcp",)),
    "DrawTriangle-v1": ("drawing", ("tcp",)),
    "Empty-v1": ("", ()),
    "FMBAssembly1Easy-v1": ("fmb", ("tcp",)),
    "InsertFlower-v1": ("dexterity", ()),
    "LiftPegUpright-v1": ("tabletop", ("is_grasping", "tcp")),
    "MS-AntRun-v1": ("control", ()),
    "MS-AntWalk-v1": ("control", ()),
    "MS-CartpoleBalance-v1": ("control", ()),
    "MS-CartpoleSwingUp-v1": ("control", ()),
    "MS-HopperHop-v1": ("control", ("robot_mass",)),
    "MS-HopperStand-v1": ("control", ("robot_mass",)),
    "MS-HumanoidRun-v1": ("control", ()),
    "MS-HumanoidStand-v1": ("control", ()),
    "MS-HumanoidWalk-v1": ("control", ()),
    "OpenCabinetDoor-v1": ("mobile_manipulation", ("tcp",)),
    "OpenCabinetDrawer-v1": ("mobile_manipulation", ("tcp",)),
    "PegInsertionSide-v1": ("tabletop", ("is_grasping", "tcp")),
    "PickClutterYCB-v1": ("tabletop", ()),
    "PickCube-v1": ("tabletop", ("is_grasping", "is_static", "tcp_pose")),
    "PickCubeSO100-v1": ("tabletop", ("is_grasping", "is_static", "tcp_pose")),
    "PickCubeWidowXAI-v1": ("tabletop", ("is_grasping", "is_static", "tcp_pose")),
    "PickSingleYCB-v1": ("tabletop", ("is_grasping", "is_static", "tcp")),
    "PlaceSphere-v1": ("tabletop", ("is_grasping", "is_static", "tcp")),
    "PlugCharger-v1": ("tabletop", ("tcp",)),
    "PokeCube-v1": ("tabletop", ("is_grasping", "is_static", "tcp")),
    "PullCube-v1": ("tabletop", ("tcp",)),
    "PullCubeTool-v1": ("tabletop", ("is_grasping", "tcp")),
    "PushCube-v1": ("tabletop", ("tcp",)),
    "PushT-v1": ("tabletop", ("tcp",)),
    "PutCarrotOnPlateInScene-v1": ("digital_twins", ("is_grasping",)),
    "PutEggplantInBasketScene-v1": ("digital_twins", ("is_grasping",)),
    "PutSpoonOnTableClothInScene-v1": ("digital_twins", ("is_grasping",)),
    "RoboCasaKitchen-v1": ("mobile_manipulation", ()),
    "RollBall-v1": ("tabletop", ("tcp",)),
    "RotateSingleObjectInHandLevel0-v1": ("dexterity", ("tip_links",)),
    "RotateSingleObjectInHandLevel1-v1": ("dexterity", ("tip_links",)),
    "RotateSingleObjectInHandLevel2-v1": ("dexterity", ("tip_links",)),
    "RotateSingleObjectInHandLevel3-v1": ("dexterity", ("tip_links",)),
    "RotateValveLevel0-v1": ("dexterity", ("root_joint_indices", "tip_poses")),
    "RotateValveLevel1-v1": ("dexterity", ("root_joint_indices", "tip_poses")),
    "RotateValveLevel2-v1": ("dexterity", ("root_joint_indices", "tip_poses")),
    "RotateValveLevel3-v1": ("dexterity", ("root_joint_indices", "tip_poses")),
    "RotateValveLevel4-v1": ("dexterity", ("root_joint_indices", "tip_poses")),
    "SO100GraspCube-v1": (
        "digital_twins",
        ("finger1_link", "finger2_link", "is_grasping", "tcp_pos", "tcp_pose"),
    ),
    "SceneManipulation-v1": ("", ("torso_lift_link",)),
    "StackCube-v1": ("tabletop", ("is_grasping", "tcp")),
    "StackGreenCubeOnYellowCubeBakedTexInScene-v1": ("digital_twins", ("is_grasping",)),
    "StackPyramid-v1": ("tabletop", ("is_grasping", "tcp")),
    "TableTopFreeDraw-v1": ("drawing", ("tcp",)),
    "TriFingerRotateCubeLevel0-v1": ("", ("tip_poses",)),
    "TriFingerRotateCubeLevel1-v1": ("", ("tip_poses",)),
    "TriFingerRotateCubeLevel2-v1": ("", ("tip_poses",)),
    "TriFingerRotateCubeLevel3-v1": ("", ("tip_poses",)),
    "TriFingerRotateCubeLevel4-v1": ("", ("tip_poses",)),
    "TurnFaucet-v1": ("tabletop", ("tcp",)),
    "TwoRobotPickCube-v1": ("tabletop", ("agents",)),
    "TwoRobotStackCube-v1": ("tabletop", ("agents",)),
    "UnitreeG1PlaceAppleInBowl-v1": (
        "humanoid",
        ("right_hand_dist_to_open_grasp", "right_hand_is_grasping", "right_tcp"),
    ),
    "UnitreeG1Stand-v1": ("humanoid", ("is_fallen", "is_standing")),
    "UnitreeG1TransportBox-v1": ("humanoid", ("left_tcp", "right_tcp")),
    "UnitreeGo2-Reach-v1": ("quadruped", ("is_fallen",)),
    "UnitreeH1Stand-v1": ("humanoid", ("is_fallen", "is_standing")),
}
