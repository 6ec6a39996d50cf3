"""``robospec new ARM --attach HAND@LINK``: the arm's scaffold with a hand (or gripper) mounted.

After ``new`` has written the arm's spec, each ``HAND@LINK`` becomes a ``parts:`` entry: HAND is
the part's spec (YAML or TOML) or its description, for which ``new`` scaffolds a spec beside the
arm's first; LINK is the arm's link to mount it on (by default its first mounting frame, the
one ``robospec inspect`` lists first: a tool flange such as ``tool0``), the pose the frame's
(identity, or an MJCF site's). Then the composed robot is compiled, and for a URDF robot the
pairs of links at the seam that touch in every pose — the flange against the palm — are found
by the collision matrix ``robospec optimize`` uses (:mod:`robospec.optimize.collision_matrix`,
in a child process) and declared in ``never_collide``.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robospec.diagnostics import Diagnostic, Location, error, has_errors
from robospec.diagnostics.codes import BAD_ATTACH

if TYPE_CHECKING:
    from robospec.authoring.commands import CommandResult
from robospec.model.names import NAME_PATTERN

SPEC_SUFFIXES = (".yaml", ".yml", ".toml")
SEAM_SAMPLES = 200
SEAM_TIMEOUT = 300  # seconds


@dataclass(frozen=True)
class Attachment:
    """One ``--attach`` argument: the part's file and the link, when given."""

    text: str
    hand: Path
    link: str | None

    @property
    def is_spec(self) -> bool:
        return self.hand.suffix.lower() in SPEC_SUFFIXES

    @property
    def name(self) -> str:
        """The part's name in the arm's spec: its file's name without the suffixes."""
        stem = self.hand.name.split(".")[0]
        stem = re.sub(r"[^A-Za-z0-9_.\-]", "_", stem) or "part"
        return stem if re.match(NAME_PATTERN, stem) else f"part_{stem}"[:64]


def parse_attach(text: str) -> Attachment:
    """``HAND@LINK`` or ``HAND``."""
    hand, _, link = text.rpartition("@") if "@" in text else (text, "", "")
    return Attachment(text, Path(hand), link or None)


def run_attach(
    arm_spec: Path,
    arm_description: Path,
    attachments: list[Attachment],
    *,
    force: bool,
    simulate: bool,
) -> CommandResult:
    """Mount ``attachments`` in the spec ``new`` wrote at ``arm_spec`` from
    ``arm_description``: the arm's spec again, to write; the parts' specs ``new`` scaffolds
    are written already (the composed robot is compiled from them, to find its seam)."""
    from robospec.authoring.commands import CommandResult, Output, run_new
    from robospec.authoring.description_file import read_description_file

    written: list[Path] = []
    diagnostics: list[Diagnostic] = []
    parts: dict[str, dict[str, Any]] = {}
    for attachment in attachments:
        spec = attachment.hand
        if not spec.is_file():
            bad = _bad(attachment, f"no file '{attachment.hand}'")
            return CommandResult(diagnostics=(bad,), written=tuple(written))
        if not attachment.is_spec:
            spec = arm_spec.parent / f"{attachment.name}.yaml"
            part = run_new(attachment.hand, spec, None, force, simulate).write()
            diagnostics.extend(part.diagnostics)
            if part.failed:
                return CommandResult(diagnostics=tuple(diagnostics), written=tuple(written))
            written.extend(f for f in part.written if f not in written)
        arm, _ = read_description_file(arm_description, keep_errors=True)
        entry = _entry(arm_spec, arm, attachment, spec)
        if isinstance(entry, Diagnostic):
            return CommandResult(diagnostics=(*diagnostics, entry), written=tuple(written))
        parts[attachment.name] = entry
    text = _with_parts(arm_spec.read_text(encoding="utf-8"), parts)
    seam, found = _seam_pairs(arm_spec, text, parts) if simulate else ([], [])
    diagnostics.extend(found)
    if seam:
        text = _with_never_collide(text, seam)
    return CommandResult(
        outputs=(Output(arm_spec, text),), diagnostics=tuple(diagnostics), written=tuple(written)
    )


def attach_parts(
    new: CommandResult,
    arm_spec: Path,
    arm_description: Path,
    attach: list[str],
    *,
    force: bool,
    simulate: bool,
) -> CommandResult:
    """``new --attach``: after ``new`` (its result, written) wrote ``arm_spec``, each
    ``HAND@LINK`` of ``attach`` mounted in it, written: every file written, the parts' and the
    arm's spec first, and every diagnostic."""
    from robospec.authoring.commands import CommandResult

    parts = [parse_attach(text) for text in attach]
    mounted = run_attach(arm_spec, arm_description, parts, force=force, simulate=simulate)
    mounted = mounted.write()
    earlier = tuple(path for path in new.written if path not in mounted.written)
    return CommandResult(
        diagnostics=(*new.diagnostics, *mounted.diagnostics), written=(*mounted.written, *earlier)
    )


def _bad(attachment: Attachment, message: str, hint: str | None = None) -> Diagnostic:
    from robospec.diagnostics.command_line import COMMAND_LINE

    return error(Location(COMMAND_LINE), BAD_ATTACH, f"--attach {attachment.text}: {message}", hint)


def _entry(
    arm_spec: Path, arm: Any, attachment: Attachment, spec: Path
) -> dict[str, Any] | Diagnostic:
    """The ``parts:`` entry: the part's spec (relative to the arm's), the link and the pose."""
    import os

    from robospec.authoring.mounting import mounting_frames

    link, pose = attachment.link, None
    if arm is not None:
        frames = [f for f in mounting_frames(arm) if f.role == "flange"]
        if link is None and frames:
            link, pose = frames[0].at, frames[0].pose_yaml()
        elif link is not None:
            if arm.description.link(link) is None:
                from robospec.diagnostics.suggest import did_you_mean

                return _bad(
                    attachment,
                    f"the robot has no link '{link}'",
                    did_you_mean(link, arm.description.link_names),
                )
            pose = next((f.pose_yaml() for f in frames if f.at == link), None)
    if link is None:
        return _bad(
            attachment,
            "the robot has no mounting frame robospec recognizes",
            "name the link: --attach HAND@LINK (robospec inspect lists the links)",
        )
    relative = Path(os.path.relpath(spec.resolve(), arm_spec.resolve().parent)).as_posix()
    entry: dict[str, Any] = {"spec": relative, "at": link}
    if pose is not None:
        entry["pose"] = pose
    return entry


def _with_parts(text: str, parts: dict[str, dict[str, Any]]) -> str:
    """The scaffold's text with ``parts:`` after its description, each entry on one line."""
    lines = text.splitlines(keepends=True)
    start = next((i for i, line in enumerate(lines) if line.startswith("description:")), None)
    end = len(lines)
    if start is not None:
        end = next(
            (i for i in range(start + 1, len(lines)) if lines[i][:1] not in (" ", "\n", "")),
            len(lines),
        )
        while end > start + 1 and not lines[end - 1].strip():
            end -= 1
    block = [
        "\n",
        "parts: # robots mounted on this one; robospec writes the combined description\n",
    ]
    block += [f"  {name}: {_flow(entry)}\n" for name, entry in parts.items()]
    return "".join([*lines[:end], *block, *lines[end:]])


def _with_never_collide(text: str, pairs: list[tuple[str, str]]) -> str:
    block = [
        "\n",
        "# the seam: these links of the robot and its parts touch in every pose (the collision\n",
        "# matrix of robospec optimize, sampled by robospec new --attach)\n",
        "never_collide:\n",
        *(f"  - [{_flow(a)}, {_flow(b)}]\n" for a, b in pairs),
    ]
    return text.rstrip("\n") + "\n" + "".join(block)


def _flow(value: Any) -> str:
    """``value`` as YAML flow text."""
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_flow(v) for v in value) + "]"
    if isinstance(value, float):
        return f"{value:g}"
    text = str(value)
    plain = re.fullmatch(r"[A-Za-z_./][A-Za-z0-9_./\-]*", text) is not None
    return (
        text if plain and text not in ("true", "false", "null", "yes", "no") else json.dumps(text)
    )


def _seam_pairs(
    arm_spec: Path, text: str, parts: dict[str, dict[str, Any]]
) -> tuple[list[tuple[str, str]], list[Diagnostic]]:
    """Pairs across the seam of each part that touch in every sampled pose (found in a child
    process, on the composed URDF of the arm's spec ``text``); none for an MJCF robot (the
    matrix loads URDF)."""
    from robospec.output.modules import carried_urdf
    from robospec.pipeline import compile_spec

    compiled = compile_spec(arm_spec, text=text.encode("utf-8"))
    if compiled.robot is None or has_errors(compiled.diagnostics):
        return [], list(compiled.diagnostics)
    robot = compiled.robot
    if robot.description_kind != "urdf" or not robot.parts:
        return [], []
    with tempfile.TemporaryDirectory(prefix="robospec-attach-") as folder:
        urdf = Path(folder) / "composed.urdf"
        urdf.write_text(carried_urdf(robot.description, Path(folder)))
        request = {
            "urdf": str(urdf),
            "samples": SEAM_SAMPLES,
            "keyframes": [
                dict(zip(robot.active_joints, k.qpos, strict=True))
                for k in robot.keyframes
                if k.qpos is not None
            ],
            "parts": {p.name: list(p.links) for p in robot.parts},
        }
        try:
            done = subprocess.run(
                [sys.executable, "-m", "robospec.authoring.new.attach"],
                input=json.dumps(request),
                capture_output=True,
                text=True,
                timeout=SEAM_TIMEOUT,
            )
            answer = json.loads(done.stdout.strip().splitlines()[-1])
        except (subprocess.TimeoutExpired, json.JSONDecodeError, IndexError):
            return [], []  # check and optimize find the pairs later; the scaffold stands
    if "error" in answer:
        return [], []
    return [tuple(pair) for pair in answer["pairs"]], []


def seam_pairs(request: dict[str, Any]) -> list[list[str]]:
    """In the child: the collision matrix of the composed URDF, its always-touching pairs that
    have one link in a part and the other outside it."""
    from robospec.optimize.collision_matrix import sample_collision_matrix

    matrix = sample_collision_matrix(
        request["urdf"], samples=request["samples"], keyframes=request["keyframes"]
    )
    owner = {link: part for part, links in request["parts"].items() for link in links}
    return [[a, b] for a, b in sorted(matrix.always) if owner.get(a) != owner.get(b)]


def main() -> int:
    request = json.loads(sys.stdin.read())
    try:
        answer: dict[str, Any] = {"pairs": seam_pairs(request)}
    except Exception as exc:  # the robot could not be loaded: the parent goes on without
        answer = {"error": f"{type(exc).__name__}: {exc}"}
    sys.stdout.write("\n" + json.dumps(answer) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
