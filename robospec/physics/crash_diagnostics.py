"""RS514-RS517: a robot, a control mode or a check that crashed ManiSkill or SAPIEN, as a located
diagnostic instead of a traceback (or a dead process) that loses every other robot's results.

- RS514: ManiSkill cannot load the robot: every control mode fails the same way while the
  description is read (SAPIEN's ``invalid moment of inertia`` assertion, a ``<transmission>``
  its URDF parser cannot read, an MJCF height field). At the description element the loader
  was reading when it can be told, else at the spec's ``description:``.
- RS515: checking the robot killed the process (a segmentation fault or an abort in SAPIEN's or
  PhysX's native code). ``robospec check`` runs each robot in a worker process, so the others
  are still checked; the diagnostic says what the check was doing, the last ManiSkill/SAPIEN
  frame, and what SAPIEN said before it died (missing mesh files, for example).
- RS516: one control mode cannot be made (its controllers crash ManiSkill) while the others
  load: at the mode, and the other modes are still checked.
- RS517: a check crashed inside ManiSkill or SAPIEN while stepping the robot: at the mode it
  was running.

Each names the ManiSkill/SAPIEN file and line (relative to the package) and whether the crash is
upstream's code or robospec's own (then it asks for a report).
"""

from __future__ import annotations

from collections.abc import Sequence

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import CHECK_CRASH, CHECK_KILLED, CONTROL_MODE_CRASH
from robospec.maniskill.crash import USER, Crash
from robospec.maniskill.upstream_output import UpstreamMessage
from robospec.output.load_errors import load_failure as _load_failure

OTHERS_CHECKED = "every other robot was still checked"


def load_failure(context: CheckContext, uid: str, crash: Crash) -> Diagnostic:
    """RS514, as check and tune report it (robospec.output.load_errors makes it)."""
    return _load_failure(context, uid, crash, OTHERS_CHECKED)


def process_died(
    context: CheckContext,
    uid: str,
    crash: Crash,
    doing: str,
    said: Sequence[UpstreamMessage] = (),
) -> Diagnostic:
    # Python code cannot kill the process: native code did, below the last Python frame
    frame = crash.frame
    if frame is None:
        where = "in native code"
    elif crash.upstream:
        where = f"in native code below {frame.owner}'s {frame.describe()}: upstream's crash"
    elif frame.owner == USER:
        where = f"in native code below {frame.describe()}, the spec's own code (a hook)"
    else:
        owner = f"{frame.owner}'s " if frame.owner else ""
        where = f"in native code below {owner}{frame.describe()}"
    last_words = _last_words(said)
    return error(
        context.key(("description",)),
        CHECK_KILLED,
        f"checking '{uid}' killed the check process: {crash.what} while {doing}, {where}"
        + (f"; before it: {last_words}" if last_words else ""),
        "what SAPIEN said before the crash often names its cause (a missing mesh, an invalid "
        f"inertia); {OTHERS_CHECKED}",
    )


def _last_words(said: Sequence[UpstreamMessage]) -> str:
    """SAPIEN's and ManiSkill's errors (else warnings) before the crash, most said first."""
    for levels in (("error", "critical"), ("warning",)):
        chosen = [m for m in said if m.level in levels]
        if chosen:
            chosen.sort(key=lambda m: -m.count)
            shown = "; ".join(
                f"{m.source} {m.level}: {m.text}"
                + (f" (e.g. {m.example})" if m.example else "")
                + (f" ({m.count}x)" if m.count > 1 else "")
                for m in chosen[:3]
            )
            return shown + (f"; and {len(chosen) - 3} more" if len(chosen) > 3 else "")
    return ""


def mode_failure(context: CheckContext, mode: str, crash: Crash) -> Diagnostic:
    return error(
        context.key(("control_modes", mode)),
        CONTROL_MODE_CRASH,
        f"control mode '{mode}' cannot be made: {crash.what} ({crash.where()})",
        "ManiSkill crashes building this mode's controllers; the other modes were checked",
    )


def check_failure(context: CheckContext, check: str, mode: str | None, crash: Crash) -> Diagnostic:
    where = context.key(("control_modes", mode)) if mode else context.key(("description",))
    in_mode = f" in mode {mode}" if mode else ""
    return error(
        where,
        CHECK_CRASH,
        f"the {check} check crashed{in_mode}: {crash.what} ({crash.where()})",
        "ManiSkill or SAPIEN raised while stepping the robot; the other checks were run",
    )
