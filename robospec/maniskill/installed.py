"""Facts about the ManiSkill installed beside robospec, read from its files without importing it
(importing ManiSkill takes seconds and torch; ``validate`` must not).

Which ManiSkill it is comes from the installed distributions, not from ``mani_skill.__version__``:
ManiSkill's nightly (the ``mani-skill-nightly`` distribution, versions like 2026.8.2.400) says
3.0.1 there too. Both distributions write the same ``mani_skill/`` folder, so a machine can hold
both, the files of whichever was installed last over the other's: :attr:`Installed.mixed`.

The uids ManiSkill registers itself are read from the source of its agents
(the modules ``import mani_skill.envs`` imports): each class decorated with ``register_agent``
and the ``uid`` it or a base class says. The scan takes about a tenth of a second and is kept in the
user cache under the installation's identity, so each ManiSkill is scanned once. Without
ManiSkill installed, the uids of ManiSkill 3.0.1 (:data:`UIDS_OF_3_0_1`) stand in: a spec that
takes one would clash with the ManiSkill most users install.
"""

from __future__ import annotations

import ast  # already imported with dataclasses: costs validate nothing
import zlib
from collections.abc import Iterator
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, warning
from robospec.diagnostics.codes import MANISKILL_INSTALLED_TWICE
from robospec.files import cache_root, write_atomically

# the distributions that install the ``mani_skill`` package
DISTRIBUTIONS = ("mani-skill", "mani-skill-nightly")
# the scan's own format: a new one rescans
_SCAN_FORMAT = "2"


@dataclass(frozen=True)
class Installed:
    """The installed ManiSkill: the distribution whose ``mani_skill/`` files are in place."""

    distribution: str  # "mani-skill" or "mani-skill-nightly"
    version: str
    record_hash: str  # of the distribution's RECORD: two installs of one version differ here
    package_dir: Path
    mixed: tuple[str, ...] = ()  # every ManiSkill distribution installed, when more than one

    @property
    def identity(self) -> str:
        """Names this installation: the register cache's salt, the uid scan's cache key."""
        others = "+".join(self.mixed)
        return f"{self.distribution}=={self.version}#{self.record_hash[:16]}" + (
            f"({others})" if others else ""
        )

    @property
    def is_nightly(self) -> bool:
        return self.distribution == "mani-skill-nightly"


@cache
def installed() -> Installed | None:
    """The installed ManiSkill, or None when no ManiSkill distribution is installed."""
    import importlib.util

    # find_spec("mani_skill") imports nothing; its dist-info lies beside it, except for an
    # editable install, which importlib.metadata finds (a slower import: validate's first
    # error waits for this)
    spec = importlib.util.find_spec("mani_skill")
    if spec is None or not spec.submodule_search_locations:
        return None
    return installed_at(Path(next(iter(spec.submodule_search_locations))))


def installed_at(package: Path) -> Installed | None:
    """The ManiSkill whose ``mani_skill`` package is the folder ``package``."""
    found = [
        (_canonical(info.name.split("-")[0]), info)
        for prefix in ("mani_skill-", "mani_skill_nightly-")
        for info in package.parent.glob(f"{prefix}*.dist-info")
    ] or _distributions_elsewhere()
    if not found:
        return None
    # with both installed, the files in place are those of the one installed last
    name, info = max(found, key=lambda item: _mtime(item[1] / "RECORD"))
    try:
        record = (info / "RECORD").read_bytes()
    except OSError:
        record = b""
    return Installed(
        distribution=name,
        version=info.name.removesuffix(".dist-info").split("-", 1)[-1],
        record_hash=f"{zlib.crc32(record):08x}",
        package_dir=package,
        mixed=tuple(sorted(n for n, _ in found)) if len(found) > 1 else (),
    )


def _distributions_elsewhere() -> list[tuple[str, Path]]:
    from importlib import metadata

    found = []
    for name in DISTRIBUTIONS:
        try:
            dist = metadata.distribution(name)
        except metadata.PackageNotFoundError:
            continue
        record = next((f for f in dist.files or () if f.name == "RECORD"), None)
        if record is not None:
            found.append((name, Path(str(dist.locate_file(record))).parent))
    return found


def _canonical(name: str) -> str:
    return name.lower().replace("_", "-")


def _mtime(path: Path) -> float:
    try:
        return path.stat().st_mtime
    except OSError:
        return 0.0


def mixed_install_problem(found: Installed | None) -> Diagnostic | None:
    """RS520 where both ManiSkill distributions are installed: pip put one's files over the
    other's in one ``mani_skill/`` folder, and uninstalling either breaks the other."""
    if found is None or not found.mixed:
        return None
    others = [name for name in found.mixed if name != found.distribution]
    return warning(
        Location(str(found.package_dir)),
        MANISKILL_INSTALLED_TWICE,
        f"both {' and '.join(found.mixed)} are installed; mani_skill/ holds the files of "
        f"{found.distribution} {found.version}, installed over {', '.join(others)}'s (files "
        "only the other one has stay behind, and uninstalling either removes the other's)",
        "pip uninstall -y " + " ".join(found.mixed) + f", then pip install {found.distribution}"
        " (robospec's scripts/setup installs one or the other: the extras maniskill and "
        "maniskill-nightly)",
    )


def registered_uids() -> frozenset[str]:
    """The agent uids the installed ManiSkill registers itself (3.0.1's without ManiSkill)."""
    return _registered_uids(installed())


@cache
def _registered_uids(found: Installed | None) -> frozenset[str]:
    if found is None:
        return UIDS_OF_3_0_1
    cached = cache_root() / "maniskill" / f"uids-{_SCAN_FORMAT}-{_file_key(found.identity)}.txt"
    try:
        read = frozenset(cached.read_text(encoding="utf-8").split())
    except (OSError, ValueError):
        read = frozenset()
    if read:  # an empty file is a write that did not finish: scan again
        return read
    uids = scan_registered_uids(found.package_dir)
    try:
        write_atomically(cached, "".join(f"{uid}\n" for uid in sorted(uids)))
    except OSError:
        pass  # a read-only cache: scan again next time
    return uids


def _file_key(identity: str) -> str:
    return f"{zlib.crc32(identity.encode()):08x}"


def scan_registered_uids(package_dir: Path) -> frozenset[str]:
    """The uids of the classes decorated with ``register_agent`` in the modules that
    ``import mani_skill.envs`` imports (a module left out of its package's ``__init__`` registers
    nothing); a class without its own ``uid`` takes its base class's (by name)."""
    classes: dict[str, ast.ClassDef] = {}
    registered: list[ast.ClassDef] = []
    for _, tree in imported_modules(package_dir, ("envs",)):
        for node in executed_statements(tree):
            if isinstance(node, ast.ClassDef):
                classes.setdefault(node.name, node)
                if any(_is_register_agent(d) for d in node.decorator_list):
                    registered.append(node)
    uids = (_uid_of(node, classes, set()) for node in registered)
    return frozenset(uid for uid in uids if uid is not None)


def imported_modules(
    package_dir: Path, start: tuple[str, ...]
) -> list[tuple[tuple[str, ...], ast.Module]]:
    """The parsed modules of the package at ``package_dir`` that importing ``start`` (a module
    path inside it) imports, following its imports of itself, relative and absolute: (the
    module's path inside the package, its tree)."""
    root = package_dir.name
    parsed: list[tuple[tuple[str, ...], ast.Module]] = []
    seen: set[tuple[str, ...]] = set()
    queue = [start]
    while queue:
        module = queue.pop()
        # importing a module runs its packages' __init__ first
        for depth in range(len(module) + 1):
            name = module[:depth]
            if name in seen:
                continue
            seen.add(name)
            path = _module_file(package_dir, name)
            if path is None:
                continue
            try:
                tree = ast.parse(path.read_bytes(), str(path))
            except (OSError, SyntaxError, ValueError):
                continue
            parsed.append((name, tree))
            is_package = path.name == "__init__.py"
            queue.extend(_imports_of(tree, name, is_package, root, package_dir))
    return parsed


def _module_file(package_dir: Path, name: tuple[str, ...]) -> Path | None:
    base = package_dir.joinpath(*name)
    candidates = [base / "__init__.py", *([base.with_suffix(".py")] if name else [])]
    return next((path for path in candidates if path.is_file()), None)


def _imports_of(
    tree: ast.Module, module: tuple[str, ...], is_package: bool, root: str, package_dir: Path
) -> list[tuple[str, ...]]:
    """The modules of the package that ``tree`` imports when it is imported (not the imports
    inside its functions, which run later if ever)."""
    here = module if is_package else module[:-1]
    found: list[tuple[str, ...]] = []
    for node in executed_statements(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                parts = tuple(alias.name.split("."))
                if parts[0] == root:
                    found.append(parts[1:])
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - (node.level - 1)] if node.level > 1 else here
                target = base + tuple(node.module.split(".")) if node.module else base
            elif node.module and node.module.split(".")[0] == root:
                target = tuple(node.module.split("."))[1:]
            else:
                continue
            found.append(target)
            # ``from . import a`` imports the submodule a
            found.extend(
                (*target, alias.name)
                for alias in node.names
                if _module_file(package_dir, (*target, alias.name)) is not None
            )
    return found


def executed_statements(tree: ast.Module) -> Iterator[ast.stmt]:
    """The statements importing the module runs: its top level, into the blocks of ``if``,
    ``try`` and ``with`` but not into functions or classes (a walk of every node of every
    module took seconds)."""
    pending = list(reversed(tree.body))
    while pending:
        statement = pending.pop()
        yield statement
        if isinstance(statement, (ast.If, ast.Try, ast.With)):
            blocks = [statement.body, getattr(statement, "orelse", [])]
            blocks += [getattr(statement, "finalbody", [])]
            blocks += [h.body for h in getattr(statement, "handlers", [])]
            pending.extend(reversed([s for block in blocks for s in block]))


def _is_register_agent(decorator: ast.expr) -> bool:
    target = decorator.func if isinstance(decorator, ast.Call) else decorator
    name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", None)
    return name == "register_agent"


def _uid_of(node: ast.ClassDef, classes: dict[str, ast.ClassDef], seen: set[str]) -> str | None:
    for statement in node.body:
        targets = (
            statement.targets
            if isinstance(statement, ast.Assign)
            else [statement.target]
            if isinstance(statement, ast.AnnAssign)
            else []
        )
        value = getattr(statement, "value", None)
        for target in targets:
            if isinstance(target, ast.Name) and target.id == "uid":
                if isinstance(value, ast.Constant) and isinstance(value.value, str):
                    return value.value
    seen.add(node.name)
    for base in node.bases:
        name = base.attr if isinstance(base, ast.Attribute) else getattr(base, "id", None)
        if name in classes and name not in seen:
            uid = _uid_of(classes[name], classes, seen)
            if uid is not None:
                return uid
    return None


# The uids ManiSkill 3.0.1 registers: where no ManiSkill is installed to read them from.
# tests/test_installed_maniskill.py keeps this equal to a scan of 3.0.1.
UIDS_OF_3_0_1: frozenset[str] = frozenset(
    {
        "allegro_hand_left",
        "allegro_hand_right",
        "allegro_hand_right_touch",
        "anymal_c",
        "dclaw",
        "fetch",
        "fixed_inspire_hand_left",
        "fixed_inspire_hand_right",
        "floating_ability_hand_right",
        "floating_inspire_hand_left",
        "floating_inspire_hand_right",
        "floating_panda_gripper",
        "floating_robotiq_2f_85_gripper",
        "googlerobot",
        "humanoid",
        "koch-v1.1",
        "panda",
        "panda_stick",
        "panda_wristcam",
        "so100",
        "stompy",
        "trifingerpro",
        "unitree_g1",
        "unitree_g1_simplified_legs",
        "unitree_g1_simplified_upper_body",
        "unitree_g1_simplified_upper_body_right_arm",
        "unitree_g1_simplified_upper_body_with_head_camera",
        "unitree_go2",
        "unitree_go2_simplified_locomotion",
        "unitree_h1",
        "unitree_h1_simplified",
        "ur_10e",
        "widowx250s",
        "widowx250s_bridgedataset_flat_table",
        "widowx250s_bridgedataset_sink",
        "widowxai",
        "widowxai_wristcam",
        "xarm6_nogripper",
        "xarm6_nogripper_wristcam",
        "xarm6_robotiq",
        "xarm6_robotiq_wristcam",
        "xarm7_ability",
        "xlerobot",
    }
)
