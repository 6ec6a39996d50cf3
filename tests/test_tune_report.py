"""What `robospec tune` prints reads as English: counts agree with their nouns, and a spec
that did not compile is said so (no `?` for its uid). No simulation: reports built by hand."""

from __future__ import annotations

from robospec.tune.report import render_text
from robospec.tune.results import ControllerTuning, Gains, Targets, Timing, TuneReport


def _report(simulations: int) -> str:
    tuning = ControllerTuning(
        "arm_pos",
        "pd_joint_pos",
        "arm",
        "position",
        ("j1",),
        "met",
        targets=Targets(0.05, 0.5, 0.02),
        before=Gains((1e3,), (1e2,), (100.0,)),
        after=Gains((1e3,), (1e2,), (100.0,)),
        before_timings=(Timing("j1", 0.01, 0.2, 0.0, 0.1),),
        after_timings=(Timing("j1", 0.01, 0.2, 0.0, 0.1),),
        simulations=simulations,
    )
    return render_text(TuneReport("spec.yaml", "rs_arm", controllers=[tuning]))


def test_one_simulation_is_singular_and_more_are_plural() -> None:
    assert "; 1 simulation, " in _report(1)
    assert "; 3 simulations, " in _report(3)


def test_a_spec_that_did_not_compile_is_said_so() -> None:
    assert render_text(TuneReport("spec.yaml", None)).splitlines()[0] == "spec.yaml: not compiled"
