"""What ``robospec optimize`` is asked to do: its options, and their problems.

The shapes method is a typer choice (:class:`ShapeMethod`: the command line refuses any other
name, exit 2). What typer cannot say as well is checked here, each problem a located error at
its value on the command line: a profile or category not named (with the nearest name), the
ranges (``--max-error`` excludes 0; NaN is in no range) and the options that change only the
fast profile or primitive shapes.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Sequence
from dataclasses import dataclass

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import (
    CONTACT_OFFSET_OUT_OF_RANGE,
    MAX_ERROR_OUT_OF_RANGE,
    OPTION_FOR_OTHER_PROFILE,
    UNKNOWN_CATEGORY,
    UNKNOWN_PROFILE,
)
from robospec.maniskill.scenes import CONTACT_OFFSET


class ShapeMethod(str, enum.Enum):
    """What becomes of collision meshes (:mod:`robospec.optimize.shapes`, or nothing: keep)."""

    keep = "keep"
    convert = "convert"
    hull = "hull"
    coacd = "coacd"
    primitives = "primitives"


PROFILES = ("default", "fast")
CATEGORIES = ("manipulation", "locomotion")
# --max-error: a primitive standing off the mesh by more than 5 cm is another robot
MAX_ERROR_RANGE = (0.0, 0.05)  # exclusive, inclusive; m
DEFAULT_MAX_ERROR = 0.005
# --contact-offset: above ManiSkill's own 2 cm it is no profile for speed; below 0.1 mm PhysX
# sees contacts only once shapes touch
CONTACT_OFFSET_RANGE = (0.0001, CONTACT_OFFSET)  # inclusive; m
COMMAND_LINE = Location("<command line>")


@dataclass(frozen=True)
class OptimizeOptions:
    keep: tuple[str, ...] = ()  # links to keep although the spec does not name them
    uid: str | None = None  # the optimized spec's uid; default: the spec's, plus "_optimized"
    shapes: ShapeMethod | None = None  # what becomes of collision meshes (None: the profile's)
    max_vertices: int | None = None  # a cap on each convex shape's vertices (hull)
    samples: int = 10_000  # configurations for the collision matrix (MoveIt's default); 0: none
    seed: int = 0
    profile: str = "default"  # PROFILES: "fast" changes how the robot collides, for speed
    max_error: float | None = None  # primitives: how far one may stand off the mesh (m)
    contact_offset: float | None = None  # fast: the robot's shapes' offset (default: measured)
    category: str | None = None  # fast: manipulation or locomotion (default: by the body)
    # the command line as given (after the program name): where each option's value stands,
    # for the diagnostics about it
    arguments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        # a caller in Python may name the method as text: the enum says whether it is one
        if self.shapes is not None:
            object.__setattr__(self, "shapes", ShapeMethod(self.shapes))

    @property
    def shape_method(self) -> ShapeMethod:
        """The shapes method asked for, or the profile's: primitives for fast."""
        if self.shapes is not None:
            return self.shapes
        return ShapeMethod.primitives if self.profile == "fast" else ShapeMethod.convert

    @property
    def bound(self) -> float:
        """How far a primitive may stand off the mesh (m): --max-error, or its default."""
        return self.max_error if self.max_error is not None else DEFAULT_MAX_ERROR

    def where(self, option: str, value: object) -> Location:
        """Where ``option``'s value stands on the command line (the command line when it is not
        known)."""
        if not self.arguments:
            return COMMAND_LINE
        from robospec.diagnostics.command_line import argument_location

        return argument_location(option, _argument_text(value, self.arguments), self.arguments)


def option_problems(options: OptimizeOptions) -> list[Diagnostic]:
    """Every option problem, each located at its value on the command line: the names and the
    ranges first (in command-line order); then, when those are right, each option given that
    changes nothing of what was asked."""
    problems = _name_problems(options) + _range_problems(options)
    if problems or options.profile not in PROFILES:
        return sorted(problems, key=lambda d: d.location)
    return _ineffective(options)


def _name_problems(options: OptimizeOptions) -> list[Diagnostic]:
    from robospec.diagnostics.suggest import did_you_mean

    problems = []
    if options.profile not in PROFILES:
        problems.append(
            error(
                options.where("--profile", options.profile),
                UNKNOWN_PROFILE,
                f"unknown profile {options.profile!r}",
                did_you_mean(options.profile, PROFILES) or "profiles: " + ", ".join(PROFILES),
            )
        )
    if options.category is not None and options.category not in CATEGORIES:
        problems.append(
            error(
                options.where("--category", options.category),
                UNKNOWN_CATEGORY,
                f"unknown category {options.category!r}",
                did_you_mean(options.category, CATEGORIES)
                or "categories: " + ", ".join(CATEGORIES),
            )
        )
    return problems


def _range_problems(options: OptimizeOptions) -> list[Diagnostic]:
    problems = []
    low, high = MAX_ERROR_RANGE
    if options.max_error is not None and not (
        math.isfinite(options.max_error) and low < options.max_error <= high
    ):
        problems.append(
            error(
                options.where("--max-error", options.max_error),
                MAX_ERROR_OUT_OF_RANGE,
                f"--max-error {options.max_error:g} is out of range: a primitive may stand "
                f"off the mesh by more than 0 and at most {high:g} m",
                f"the fast profile's default is {DEFAULT_MAX_ERROR:g} m (5 mm)",
            )
        )
    low, high = CONTACT_OFFSET_RANGE
    if options.contact_offset is not None and not (
        math.isfinite(options.contact_offset) and low <= options.contact_offset <= high
    ):
        problems.append(
            error(
                options.where("--contact-offset", options.contact_offset),
                CONTACT_OFFSET_OUT_OF_RANGE,
                f"--contact-offset {options.contact_offset:g} is out of range: from {low:g} "
                f"to {high:g} m (ManiSkill's own offset)",
                "leave it out and the fast profile measures one",
            )
        )
    return problems


def _ineffective(options: OptimizeOptions) -> list[Diagnostic]:
    """RS676 for each option given that changes only a profile or shapes method not asked for."""
    primitives = options.shape_method == ShapeMethod.primitives
    given: list[tuple[str, object]] = [
        (name, value)
        for name, value in (
            ("--contact-offset", options.contact_offset),
            ("--category", options.category),
        )
        if value is not None and options.profile != "fast"
    ]
    if options.max_error is not None and not primitives:
        given.append(("--max-error", options.max_error))
    return [
        error(
            options.where(name, value),
            OPTION_FOR_OTHER_PROFILE,
            f"{name} applies only to "
            + (
                "primitive collision shapes (--shapes primitives, or --profile fast)"
                if name == "--max-error"
                else "--profile fast"
            ),
            "add --profile fast" if not primitives else None,
        )
        for name, value in given
    ]


def _argument_text(value: object, arguments: Sequence[str]) -> str:
    """A number option's value as the command line wrote it (``5e-3`` for 0.005), to locate
    it there; as Python writes it when the command line is not known."""
    if isinstance(value, float):
        for argument in arguments:
            text = argument.partition("=")[2] or argument
            try:
                if float(text) == value:
                    return text
            except ValueError:
                continue
    return str(value)
