"""The `robospec` commands (a typer app). Exit codes: 0 no errors, 1 errors, 2 usage error.

The entry point is robospec.cli.main: it runs a plain `robospec validate` without building this
app (robospec.cli.fast_validate) and hands every other command line to it."""

from __future__ import annotations

import enum
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from robospec.cli.help_style import App
from robospec.diagnostics import Diagnostic, has_errors
from robospec.optimize.options import ShapeMethod
from robospec.reporting import Format as DiagnosticFormat
from robospec.reporting import render
from robospec.reporting.color import ColorChoice as Color
from robospec.reporting.color import use_color
from robospec.version import __version__

if TYPE_CHECKING:
    from robospec.authoring.commands import CommandResult

# Help is written for reflow: robospec/cli/help_style.py says how (App holds every command to it).
app = App(
    name="robospec",
    help="Compile declarative robot specs (YAML/TOML) into registered ManiSkill agents.",
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_enable=False,
)


def _print_version(asked: bool) -> None:
    if asked:
        typer.echo(f"robospec {__version__}")
        raise typer.Exit()


@app.callback()
def _top_level(
    version: Annotated[
        bool,
        typer.Option(
            "--version", callback=_print_version, is_eager=True, help="print the version and exit"
        ),
    ] = False,
) -> None:
    # the top level's only option: its help is App's (above), its commands follow
    pass


class ReportFormat(str, enum.Enum):
    """Formats of the commands that print a report of their own (check, inspect)."""

    text = "text"
    json = "json"


PathsArg = Annotated[
    list[Path], typer.Argument(metavar="SPEC", help="spec files, or folders to search")
]
ReportFormatOpt = Annotated[ReportFormat, typer.Option("--format", "-f", help="report format")]


class MjcfLoader(str, enum.Enum):
    """How an MJCF becomes the robot (the spec's ``description.loader``)."""

    maniskill = "maniskill"
    mujoco = "mujoco"


DiagnosticFormatOpt = Annotated[
    DiagnosticFormat,
    typer.Option(
        "--format",
        "-f",
        help="text (with source excerpts), json, github (workflow annotations) or sarif 2.1.0",
    ),
]
SilenceOpt = Annotated[
    list[str] | None,
    typer.Option(
        "--silence",
        metavar="CODE",
        help="do not report this warning code (repeatable; a spec's own list is `silence:`)",
    ),
]
ColorOpt = Annotated[
    Color,
    typer.Option(
        "--color",
        help="colour text output: auto (on a terminal, unless NO_COLOR is set; FORCE_COLOR "
        "forces it), always or never",
    ),
]


def _report(
    diagnostics: Sequence[Diagnostic],
    files: int,
    fmt: DiagnosticFormat,
    color: Color,
    err: bool = False,
) -> None:
    """Print the diagnostics in ``fmt``; colour is decided for the stream they go to."""
    colored = use_color(color.value, sys.stderr if err else sys.stdout, os.environ)
    # click strips ANSI codes from non-terminals unless told the colour is wanted
    typer.echo(render(diagnostics, files, fmt.value, color=colored), err=err, color=colored)


def _silenced_codes(silence: list[str] | None) -> frozenset[str]:
    """``--silence`` codes, each one robospec has (else a usage error)."""
    from robospec.diagnostics.codes import CODES

    for code in silence or ():
        if code not in CODES:
            raise typer.BadParameter(f"{code} is not a robospec code", param_hint="--silence")
    return frozenset(silence or ())


def _finish(result: CommandResult, fmt: DiagnosticFormat, color: Color, done: str) -> None:
    """End a command that writes files: text says ``done`` (diagnostics on stderr), the
    machine formats print the diagnostics report (on stdout) whatever happened."""
    if fmt is not DiagnosticFormat.text:
        _report(result.diagnostics, 1, fmt, color)
    else:
        if result.diagnostics:
            _report(result.diagnostics, 1, fmt, color, err=True)
        if not result.failed:
            typer.echo(done)
    raise typer.Exit(1 if result.failed else 0)


@app.command()
def inspect(
    file: Annotated[Path, typer.Argument(help="a URDF, xacro or MJCF file")],
    format: ReportFormatOpt = ReportFormat.text,
    loader: Annotated[
        MjcfLoader | None,
        typer.Option(
            "--loader",
            help="an MJCF read as MuJoCo compiles it (mujoco: what robospec new writes, "
            "wherever MuJoCo compiles the file) or as ManiSkill's own MJCF loader reads it "
            "(maniskill)",
        ),
    ] = None,
    color: ColorOpt = Color.auto,
) -> None:
    """Print a URDF/xacro/MJCF file's active joints, mimic relations and kinematic tree.

    Active joints come in qpos order with their limits (lower, upper, velocity, effort). The
    report goes to stdout, diagnostics to stderr. An MJCF is shown as the spec `robospec new`
    writes reads it: compiled by MuJoCo (its bodies named as the file names them, ball joints
    as three hinges), unless --loader maniskill asks for ManiSkill's own MJCF loader's reading.

    Example: robospec inspect robots/my_arm.urdf --format json
    """
    from robospec.authoring.commands import run_inspect

    result = run_inspect(
        file, as_json=format is ReportFormat.json, loader=None if loader is None else loader.value
    )
    if result.report is not None:
        sys.stdout.write(result.report)
    if result.diagnostics:
        _report(result.diagnostics, 1, DiagnosticFormat(format.value), color, err=True)
    raise typer.Exit(1 if result.report is None or result.failed else 0)


@app.command()
def new(
    file: Annotated[
        Path, typer.Argument(metavar="FILE", help="the robot description: URDF, xacro or MJCF")
    ],
    out: Annotated[
        Path, typer.Option("--out", "-o", metavar="SPEC", help="the spec file to write")
    ],
    uid: Annotated[
        str | None, typer.Option("--uid", help="uid of the spec (default: the robot's name)")
    ] = None,
    no_sim: Annotated[
        bool,
        typer.Option(
            "--no-sim",
            help="do not load the robot in ManiSkill: the rest keyframe is not checked for "
            "self-contact and a floating robot's standing height is not measured",
        ),
    ] = False,
    force: Annotated[bool, typer.Option("--force", help="overwrite SPEC")] = False,
    attach: Annotated[
        list[str] | None,
        typer.Option(
            "--attach",
            metavar="HAND@LINK",
            help="mount a part (its spec, or a description to scaffold a spec for) on the "
            "robot's link LINK (default: its first mounting frame, e.g. tool0); repeatable",
        ),
    ] = None,
    format: DiagnosticFormatOpt = DiagnosticFormat.text,
    color: ColorOpt = Color.auto,
) -> None:
    """Scaffold a spec from a robot description (URDF, xacro or MJCF).

    Groups are guessed (arm, gripper, legs by side, wheels, base, ...); a floating robot
    (an MJCF free joint, legs or wheels) gets a free root, no gravity compensation and a rest
    keyframe standing on the ground; a planar base gets a base controller; MJCF keyframes and
    actuator gains are kept; URDF mimic pairs become a pd_joint_pos_mimic controller. With
    ManiSkill installed, the rest keyframe is searched free of self-contact. The spec passes
    `robospec validate` as written.

    A problem with --uid is reported at `<command line>:1:COLUMN`, the column of its value in
    the command as typed.

    With --attach, each part is mounted in the spec's `parts:` (docs/composing.md), and the
    pairs of links at the seam that touch in every pose are declared in never_collide.

    Example: robospec new robots/my_arm.urdf -o specs/my_arm.yaml
    Example: robospec new go2.xml -o specs/go2.yaml --uid my_go2
    Example: robospec new xarm7.urdf -o specs/xarm7_hand.yaml --attach hand.urdf@link_eef
    """
    from robospec.authoring.commands import run_new

    description = file
    where = None
    if uid is not None:
        from robospec.diagnostics.command_line import argument_location

        where = argument_location("--uid", uid, sys.argv[1:])
    result = run_new(description, out, uid, force, not no_sim, where).write()
    if attach and not result.failed:
        from robospec.authoring.new.attach import attach_parts

        result = attach_parts(result, out, description, attach, force=force, simulate=not no_sim)
    _finish(result, format, color, "wrote " + ", ".join(str(path) for path in result.written))


@app.command()
def schema(
    out: Annotated[
        Path | None, typer.Option("--out", "-o", metavar="FILE", help="write to FILE")
    ] = None,
    for_spec: Annotated[
        Path | None,
        typer.Option(
            "--for",
            metavar="SPEC",
            help="narrow the schema to SPEC's robot: its joint, link, group, controller, ... "
            "names become the allowed values",
        ),
    ] = None,
    format: DiagnosticFormatOpt = DiagnosticFormat.text,
    color: ColorOpt = Color.auto,
) -> None:
    """Print the JSON Schema of the spec format (for editors and CI), or with --for a schema
    narrowed to one robot so editors complete its real joint and link names.

    Example: robospec schema -o schemas/robospec.schema.json
    Example: robospec schema --for specs/maniskill/panda.yaml -o panda.schema.json
    """
    from robospec.schema import schema_text

    text: str | None
    if for_spec is None:
        text = schema_text()
    else:
        from robospec.schema.command import narrowed_schema_text

        if for_spec.is_dir():
            raise typer.BadParameter("give one spec file, not a folder", param_hint="--for")
        text, diagnostics = narrowed_schema_text(for_spec)
        if text is None:
            _report(diagnostics, 1, format, color, err=format is DiagnosticFormat.text)
            raise typer.Exit(1)
    if out is None:
        sys.stdout.write(text)
    else:
        out.write_text(text, encoding="utf-8")
        typer.echo(f"wrote {out}")


@app.command()
def validate(
    paths: PathsArg,
    format: DiagnosticFormatOpt = DiagnosticFormat.text,
    color: ColorOpt = Color.auto,
    silence: SilenceOpt = None,
) -> None:
    """Check specs against their robot descriptions.

    Example: robospec validate specs/ --format json
    Example: robospec validate specs/ --format github   (annotations in GitHub Actions)
    """
    from robospec.cli.fast_validate import ValidateArgs, run

    # the same run as the plain form that skips typer (robospec.cli.fast_validate)
    codes = _silenced_codes(silence)
    raise typer.Exit(run(ValidateArgs(list(paths), format.value, color.value, codes)))


@app.command()
def doc(
    spec: Annotated[Path, typer.Argument(help="the spec of the robot")],
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            "-o",
            metavar="FILE",
            help="the Markdown card to write (default: SPEC-STEM.md in this folder)",
        ),
    ] = None,
    plots: Annotated[
        Path | None,
        typer.Option(
            "--plots",
            metavar="DIR",
            help="link the step-response plots check/tune --plot wrote under DIR",
        ),
    ] = None,
    images: Annotated[
        bool,
        typer.Option(
            "--images",
            help="draw the robot and each camera's view at each keyframe (PNG, beside the "
            "card in OUT-STEM_images/; needs the render extra, no GPU) and check the cameras",
        ),
    ] = False,
    collisions: Annotated[
        bool,
        typer.Option("--collisions", help="with --images, also draw the collision shapes"),
    ] = False,
    demos: Annotated[
        Path | None,
        typer.Option(
            "--demos",
            metavar="DIR",
            help="show each task's success rate from the episodes robospec solve -o DIR "
            "recorded for the robot",
        ),
    ] = None,
    format: DiagnosticFormatOpt = DiagnosticFormat.text,
    color: ColorOpt = Color.auto,
) -> None:
    """Write a Markdown robot card of a spec.

    The card shows the kinematic tree (a Mermaid diagram), the action layout of every control
    mode, the keyframes and the cameras; with --images, pictures of the robot and of what its
    cameras see, and warnings for a camera that is covered, sees nothing or looks away from
    its tcp. Nothing is written for a spec with errors.

    Example: robospec doc specs/maniskill/panda.yaml --images   (writes panda.md and panda_images/)
    Example: robospec doc my_arm.yaml --demos demos   (after robospec solve my_arm.yaml -o demos)
    """
    from robospec.authoring.commands import run_doc

    # a card named after its spec, where the user stands: `robospec doc SPEC --images` alone works
    out = out if out is not None else Path(f"{spec.stem}.md")
    result = run_doc(spec, out, plots, images, collisions, demos).write()
    # the card, then each picture (written before it, so that a card never lacks its pictures)
    listed = [out, *(path for path in result.written if path != out)]
    _finish(result, format, color, "\n".join(f"wrote {path}" for path in listed))


@app.command(needs=("maniskill",))
def check(
    paths: PathsArg,
    steps: Annotated[
        int | None,
        typer.Option(
            "--steps",
            "-n",
            min=1,
            metavar="N",
            help="control steps for keyframe holds and random actions",
        ),
    ] = None,
    format: ReportFormatOpt = ReportFormat.text,
    gpu: Annotated[
        bool, typer.Option("--gpu", help="run on physx_cuda with many parallel envs")
    ] = False,
    num_envs: Annotated[
        int, typer.Option("--num-envs", min=1, metavar="N", help="parallel envs with --gpu")
    ] = 64,
    render: Annotated[
        Path | None,
        typer.Option(
            "--render", metavar="DIR", help="save each camera's image under DIR (needs a GPU)"
        ),
    ] = None,
    plot: Annotated[
        Path | None,
        typer.Option(
            "--plot",
            metavar="DIR",
            help="save each controller's step response as DIR/<uid>/<controller>.png",
        ),
    ] = None,
    task: Annotated[
        list[str] | None,
        typer.Option(
            "--task",
            metavar="TASK",
            help="also run the robot in this ManiSkill task (reset, 50 random steps); a folder "
            "of tasks (tabletop) runs each; repeat for several",
        ),
    ] = None,
    solve: Annotated[
        int,
        typer.Option(
            "--solve",
            min=0,
            metavar="N",
            help="with --task: also run ManiSkill's solution of each task for N episodes "
            "(robospec solve); fails under 90% success",
        ),
    ] = 0,
    silence: SilenceOpt = None,
) -> None:
    """Run headless physics checks on each robot (exit 1 when a check fails).

    The checks: the ground under each start, keyframe hold, self-contact, step response per
    controller, random actions per mode, and the action layout of every mode; with --task,
    the robot in ManiSkill's tasks.

    Example: robospec check specs/maniskill/panda.yaml --steps 100 --format json
    Example: robospec check specs/my_arm.yaml --task PickCube-v1 --task PushCube-v1
    Example: robospec check specs/my_arm.yaml --task PickCube-v1 --solve 5
    """
    from robospec.physics.command import run_check

    codes = _silenced_codes(silence)
    code, text = run_check(
        paths,
        steps,
        format.value,
        gpu,
        num_envs,
        render,
        plot,
        task or [],
        sys.argv[1:],
        codes,
        solve,
    )
    typer.echo(text)
    raise typer.Exit(code)


@app.command()
def build(
    paths: PathsArg,
    out: Annotated[
        Path, typer.Option("--out", "-o", metavar="DIR", help="package folder to write")
    ],
    check: Annotated[
        bool, typer.Option("--check", help="exit 1 if DIR is stale; write nothing")
    ] = False,
    format: DiagnosticFormatOpt = DiagnosticFormat.text,
    color: ColorOpt = Color.auto,
    silence: SilenceOpt = None,
) -> None:
    """Write an importable package with one generated agent module per spec.

    Example: robospec build specs/ -o my_robots   (then: import my_robots)
    """
    from robospec.output.package import build_package
    from robospec.pipeline import compile_all

    compiled, diagnostics = compile_all(paths, silence=_silenced_codes(silence))
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    if has_errors(diagnostics) or not compiled:
        _report(diagnostics, len(compiled), format, color, err=format is DiagnosticFormat.text)
        raise typer.Exit(1)
    result = build_package(compiled, out, check=check)
    diagnostics.extend(result.diagnostics)
    if has_errors(diagnostics):
        _report(diagnostics, len(compiled), format, color)
        raise typer.Exit(1)
    if format is not DiagnosticFormat.text:
        _report(diagnostics, len(compiled), format, color)
    elif check:
        state = "stale: " + ", ".join(result.changed) if result.changed else "up to date"
        typer.echo(f"{out}: {state}")
    else:
        verb = f"wrote {len(result.changed)} file(s)" if result.changed else "up to date"
        typer.echo(f"{out}: {verb} ({len(compiled)} agent(s))")
    raise typer.Exit(1 if check and result.changed else 0)


@app.command(needs=("maniskill",))
def solve(
    spec: Annotated[Path, typer.Argument(help="the spec of an arm with a two-finger gripper")],
    task: Annotated[
        str, typer.Option("--task", metavar="TASK", help="the ManiSkill task whose solution to run")
    ] = "PickCube-v1",
    count: Annotated[
        int, typer.Option("--count", "-n", min=1, metavar="N", help="episodes to run")
    ] = 10,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out", "-o", metavar="DIR", help="write the trajectories to DIR/TASK.h5 and .json"
        ),
    ] = None,
    num_procs: Annotated[
        int,
        typer.Option(
            "--num-procs", min=1, metavar="N", help="processes to spread the episodes over"
        ),
    ] = 1,
    seed: Annotated[
        int, typer.Option("--seed", min=0, metavar="N", help="the first episode's seed")
    ] = 0,
    min_success: Annotated[
        float | None,
        typer.Option(
            "--min-success",
            min=0,
            max=1,
            metavar="FRACTION",
            help="exit 1 when fewer episodes succeed (0 to 1)",
        ),
    ] = None,
    format: ReportFormatOpt = ReportFormat.text,
) -> None:
    """Run ManiSkill's own motion-planning solution of a task with the robot, planned by
    robospec from the spec, and write the episodes as ManiSkill trajectories (exit 1 when the
    solution cannot apply, or under --min-success).

    Each episode's success is the task's own (info["success"]); replay and convert the file
    with ManiSkill's replay_trajectory (docs/solve.md).

    Example: robospec solve specs/maniskill/panda.yaml --task PickCube-v1 -n 100 -o demos
    Example: robospec solve my_arm.yaml --task StackCube-v1 -n 1000 --num-procs 8 -o demos
    """
    from robospec.diagnostics import has_errors
    from robospec.solve.command import below_min_success, render_report, run_solve

    report = run_solve(
        spec, task, count, out, num_procs, seed, sys.argv[1:], progress=sys.stderr.isatty()
    )
    short = below_min_success(report, min_success, sys.argv[1:])
    if short is not None:
        report.diagnostics.append(short)
    typer.echo(render_report(report, format.value))
    raise typer.Exit(1 if has_errors(report.diagnostics) else 0)


@app.command(needs=("maniskill",))
def tune(
    spec: Annotated[Path, typer.Argument(help="the spec of the robot to tune")],
    uid: Annotated[
        str | None,
        typer.Option("--uid", help="with --write, also give the written spec this uid"),
    ] = None,
    controller: Annotated[
        list[str] | None,
        typer.Option(
            "--controller", "-c", metavar="NAME", help="tune only this controller (repeatable)"
        ),
    ] = None,
    write: Annotated[
        bool, typer.Option("--write", help="write the new gains into the spec")
    ] = False,
    plot: Annotated[
        Path | None,
        typer.Option(
            "--plot",
            metavar="DIR",
            help="save each controller's step, before and after, under DIR/<uid>/",
        ),
    ] = None,
    reference: Annotated[
        str | None,
        typer.Option(
            "--reference",
            metavar="FILE|mujoco",
            help="fit to a recorded trajectory instead (a CSV or NPZ file, or 'mujoco')",
        ),
    ] = None,
    format: ReportFormatOpt = ReportFormat.text,
) -> None:
    """Find stiffness and damping (and force_limit where a drive saturates) per controller.

    Each controller's step response is measured as robospec check measures it, and its gains
    searched until every joint meets the spec's checks.tune targets (by default overshoot
    <= 5%, settling <= 0.5 s, steady-state error <= 2% of the step). Prints a before/after
    table; exit 1 when a target cannot be met, saying why. --write changes only the gain
    values in the spec (comments, order and style stay).

    Example: robospec tune specs/maniskill/panda.yaml --controller arm_pos --write --plot plots
    """
    from robospec.tune.command import run_tune

    code, text = run_tune(spec, uid, tuple(controller or ()), write, plot, format.value, reference)
    if text:
        typer.echo(text)
    raise typer.Exit(code)


@app.command(needs=("maniskill",))
def optimize(
    spec: Annotated[Path, typer.Argument(help="the spec of the robot to optimize")],
    out: Annotated[
        Path, typer.Option("--out", "-o", metavar="FILE", help="the optimized spec to write")
    ],
    uid: Annotated[
        str | None,
        typer.Option("--uid", help="the optimized spec's uid (default: the spec's + _optimized)"),
    ] = None,
    keep: Annotated[
        list[str] | None,
        typer.Option(
            "--keep", metavar="LINK", help="a link to keep although the spec does not name it"
        ),
    ] = None,
    shapes: Annotated[
        ShapeMethod | None,
        typer.Option(
            "--shapes",
            metavar="METHOD",
            help="collision meshes: keep, convert (STL to what SAPIEN simulates, no warning; "
            "the default), hull, coacd (convex decomposition) or primitives (the fast "
            "profile's)",
        ),
    ] = None,
    max_vertices: Annotated[
        int | None,
        typer.Option(
            "--max-vertices", min=4, metavar="N", help="cap each convex shape's vertices (hull)"
        ),
    ] = None,
    samples: Annotated[
        int,
        typer.Option(
            "--samples",
            metavar="N",
            min=0,
            help="random configurations for the self-collision matrix (0: no never_collide)",
        ),
    ] = 10_000,
    profile: Annotated[
        str,
        typer.Option(
            "--profile",
            metavar="PROFILE",
            help="default (the same robot) or fast (it collides differently, for speed: "
            "primitive shapes, small contact offsets, a recommended sim config)",
        ),
    ] = "default",
    max_error: Annotated[
        float | None,
        typer.Option(
            "--max-error",
            metavar="M",
            help="how far a primitive collision shape may stand off the mesh, in m "
            "(primitives; default 0.005)",
        ),
    ] = None,
    contact_offset: Annotated[
        float | None,
        typer.Option(
            "--contact-offset",
            metavar="M",
            help="the robot's shapes' contact offset, in m (fast; default: measured, at "
            "most 0.001)",
        ),
    ] = None,
    category: Annotated[
        str | None,
        typer.Option(
            "--category",
            metavar="CATEGORY",
            help="manipulation (15 solver iterations) or locomotion (4) (fast; default: "
            "locomotion for a robot with a free root, unless it rolls on wheels with no legs)",
        ),
    ] = None,
    format: ReportFormatOpt = ReportFormat.text,
) -> None:
    """Write a spec (--out FILE) of the same robot with a description that simulates faster.

    Fixed joints are merged into their parent links (every link the spec names is kept),
    collision meshes are made what SAPIEN simulates well, and link pairs that touch in no
    sampled configuration are declared never_collide. The optimized URDF is written beside
    FILE; nothing robospec did not write is overwritten. --profile fast also changes how
    the robot collides, for speed, and says so in FILE's simulation section.

    Example: robospec optimize specs/maniskill/fetch.yaml -o out/fetch_fast.yaml
    """
    from robospec.optimize.command import run_optimize
    from robospec.optimize.options import OptimizeOptions

    options = OptimizeOptions(
        keep=tuple(keep or ()),
        uid=uid,
        shapes=shapes,
        max_vertices=max_vertices,
        samples=samples,
        profile=profile,
        max_error=max_error,
        contact_offset=contact_offset,
        category=category,
        arguments=tuple(sys.argv[1:]),
    )
    result = run_optimize(spec, out, options)
    typer.echo(result.render(format.value))
    raise typer.Exit(result.exit_code)


@app.command("import", needs=("maniskill",))
def import_(
    target: Annotated[
        str, typer.Argument(metavar="MODULE:CLASS", help="a ManiSkill agent class to import")
    ],
    uid: Annotated[
        str | None, typer.Option("--uid", help="uid of the spec (default: the class's uid)")
    ] = None,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out", "-o", metavar="FILE", help="write the spec to FILE (default: stdout)"
        ),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="overwrite FILE")] = False,
    format: DiagnosticFormatOpt = DiagnosticFormat.text,
    color: ColorOpt = Color.auto,
) -> None:
    """Write a spec (YAML) from an existing ManiSkill agent class.

    Problems found in the class are printed as diagnostics (on stderr).

    Example: robospec import mani_skill.agents.robots.panda.panda:Panda --uid rs_panda -o panda.yaml
    """
    from robospec.importer.command import run_import

    text, diagnostics = run_import(target, uid, out, force)
    if text is not None and out is None:
        sys.stdout.write(text)
    _report(diagnostics, 1, format, color, err=True)
    if text is not None and out is not None:
        typer.echo(f"wrote {out}")
    raise typer.Exit(1 if has_errors(diagnostics) else 0)


@app.command(needs=("maniskill",))
def demo(
    spec: Annotated[Path, typer.Argument(help="the spec of the robot to show")],
    control_mode: Annotated[
        str | None,
        typer.Option("--control-mode", "-c", metavar="MODE", help="default: the spec's first"),
    ] = None,
    keyframe: Annotated[
        str | None,
        typer.Option("--keyframe", "-k", metavar="NAME", help="default: the spec's first"),
    ] = None,
    random_actions: Annotated[
        bool, typer.Option("--random-actions", help="send random actions")
    ] = False,
    keyframe_actions: Annotated[
        bool, typer.Option("--keyframe-actions", help="command the keyframe's joint positions")
    ] = False,
) -> None:
    """Show the robot in ManiSkill's viewer (demo_robot) — for people with a screen.

    Example: robospec demo specs/maniskill/panda.yaml -c pd_joint_delta_pos --random-actions
    """
    from robospec.demo.viewer import run_demo

    if random_actions and keyframe_actions:
        raise typer.BadParameter("give at most one of --random-actions and --keyframe-actions")
    actions = "random" if random_actions else "keyframe" if keyframe_actions else "none"
    diagnostics = run_demo(spec, control_mode, keyframe, actions)
    if diagnostics:
        _report(diagnostics, 1, DiagnosticFormat.text, Color.auto, err=True)
        raise typer.Exit(1)


@app.command(needs=("lsp",))
def lsp() -> None:
    """Run the robospec Language Server on stdin/stdout, for editors.

    While you type, the editor shows robospec validate's diagnostics (on the unsaved text, in the
    URDF/MJCF too), completes the robot's joint, link, group and controller names, shows a
    joint's limits or a controller's fields on hover and jumps into the URDF. Needs pygls:
    pip install 'robospec[lsp]'. See docs/editors.md.

    Example: robospec lsp   (started by the editor, not by hand)
    """
    from robospec.lsp.server import main

    main()


__all__ = ["app"]
