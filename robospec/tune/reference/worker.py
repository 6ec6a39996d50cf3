"""The worker process of ``robospec tune --reference`` (``robospec.tune.reference.command``
starts it):

    python -m robospec.tune.reference.worker FOLDER

It reads ``FOLDER/request.pickle`` (a :class:`Request`), registers the spec's agent, makes the
reference in MuJoCo when asked, fits the gains in ManiSkill and writes ``FOLDER/result.pickle``
(an :class:`Outcome`). As in ``robospec check`` and ``tune``, ManiSkill runs here and not in
the command's process: what ManiSkill and SAPIEN print goes to ``FOLDER/job.log``, what the
worker is doing to ``FOLDER/phase``, and ``faulthandler`` writes the traceback of a fatal signal
to ``FOLDER/fault.log``, so a robot that kills the process is a diagnostic, not a lost run.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import REFERENCE_FIT_CRASH, REFERENCE_MUJOCO_UNUSABLE
from robospec.physics.one_shot import serve
from robospec.tune.reference.fit import Fit
from robospec.tune.reference.plan import Plan
from robospec.tune.reference.trajectory import Reference


@dataclass(frozen=True)
class Request:
    path: Path
    display: str
    plan: Plan
    reference: Reference | None  # None: make it in MuJoCo
    mjcf: str | None = None  # the MJCF file, for MuJoCo


@dataclass
class Outcome:
    plan: Plan
    reference: Reference | None = None
    fit: Fit | None = None
    mujoco_gains: dict[str, tuple[float, float]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    messages: list[object] = field(default_factory=list)


def main(argv: Sequence[str]) -> int:
    return serve(argv, run)


def run(request: Request, phase: object) -> Outcome:
    """Register, (make the MuJoCo reference,) replay and fit, in this process. A Python
    exception inside ManiSkill, SAPIEN or MuJoCo becomes RS650."""
    outcome = Outcome(request.plan, request.reference)
    try:
        _run(request, outcome, phase)
    except Exception as exc:
        from robospec.maniskill.crash import from_exception

        crash = from_exception(exc)
        outcome.diagnostics.append(
            error(
                Location(request.display),
                REFERENCE_FIT_CRASH,
                f"the reference fit crashed: {crash.what} ({crash.where()})",
                "run robospec check on the spec: it says which part of the robot fails",
            )
        )
    return outcome


def _run(request: Request, outcome: Outcome, phase: object) -> None:
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)
    import numpy as np

    from robospec.output.register import register
    from robospec.physics.sim import Sim
    from robospec.pipeline import compile_spec
    from robospec.tune.reference.fit import fit
    from robospec.tune.reference.replay import Replay

    say = phase if callable(phase) else (lambda doing: None)
    item = compile_spec(request.path, request.display)
    assert item.robot is not None
    say("registering the agent")
    register(request.path)
    plan = request.plan
    say(f"loading the robot in mode {plan.mode}")
    keyframe = item.robot.keyframes[0] if item.robot.keyframes else None
    with Sim(item.robot.uid, plan.mode) as sim:
        reference = request.reference
        if reference is None:
            from robospec.tune.reference.mujoco_reference import make_reference

            say("simulating the reference in MuJoCo")
            start = sim.start(keyframe)
            index = [sim.joint_names.index(j) for j in plan.joints]
            made = make_reference(
                str(request.mjcf),
                plan.joints,
                {name: float(start[i]) for i, name in enumerate(sim.joint_names)},
                sim.limits[index],
                sim.prismatic[index],
                sim.sim_dt,
                gravity=not sim.gravity_off(),
            )
            outcome.notes.extend(made.notes)
            outcome.mujoco_gains = made.actuated
            if made.reference is None:
                outcome.diagnostics.append(
                    error(
                        Location(request.display),
                        REFERENCE_MUJOCO_UNUSABLE,
                        "--reference mujoco: no joint of the mode's position controllers has a "
                        "MuJoCo position actuator of gear 1",
                        "--reference mujoco needs <position> actuators (or general ones with "
                        "the same gain and bias) on the joints",
                    )
                )
                return
            reference = made.reference
            keep = [plan.joints.index(j) for j in reference.joints]
            plan = Plan(
                plan.mode,
                reference.joints,
                tuple(plan.controllers[k] for k in keep),
                tuple(plan.groups[k] for k in keep),
            )
            outcome.plan = plan
            outcome.reference = reference
        say(f"fitting the gains in mode {plan.mode}")
        replay = Replay(sim, reference, keyframe)
        outcome.fit = fit(replay)
        if not np.all(np.isfinite(outcome.fit.errors_after)):
            outcome.notes.append("the replay went NaN for some gains tried")


if __name__ == "__main__":
    # through the module's own name, so that the pickled Outcome names
    # robospec.tune.reference.worker (not __main__) and the command's process can read it
    from robospec.tune.reference.worker import main as worker_main

    sys.exit(worker_main(sys.argv[1:]))
