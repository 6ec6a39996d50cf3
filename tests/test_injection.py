"""No injection: no text in a spec or its robot description ever becomes code.

A property test writes robots whose every free-text field holds hostile text (quotes, triple
quotes that end a literal and start an import, backslashes, newlines, ``{...}`` braces, U+2028,
NUL and any other Unicode), compiles them with the real compiler, emits the module and reads it
back with ``ast``:

- the module parses and compiles;
- every identifier in it (names, attributes, defs, keyword arguments, imports) is either a word
  of the emitter's own vocabulary (an identifier written in ``robospec/emit/*.py``, or a field
  of a controller model: ManiSkill's config keyword arguments, fixed by the model) or one of
  the identifiers robospec derives from a spec *on purpose*, each of which the model restricts
  to ``[A-Za-z0-9_.-]`` and the emitter checks with ``safe_identifier``:
  the class name, controller variables (from controller names), ``<group>_joint_names``
  and shared-gain ``<group>_stiffness`` (damping, force_limit, friction) attributes (from group
  names) and member names (``named_links`` keys);
- the hostile text itself appears only inside string constants.

Free text that reaches the module only as data: link and joint names (from the URDF, and every
spec field naming them: ``links`` rules, groups, keyframes, ``tcp``, camera mounts, collision
rules, named links), control-mode group keys, the description's path (folder names) and the
spec's own file name. A canary test then builds, imports, registers and ``gym.make``s a spec
whose strings would create a file if they were ever run as code.
"""

from __future__ import annotations

import ast
import io
import keyword
import os
import re
import subprocess
import sys
import tempfile
import tokenize
from collections.abc import Callable
from pathlib import Path

import pytest
from ast_names import identifiers
from conftest import FUZZ_SCALE, ROOT
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from lxml import etree
from pydantic import BaseModel

from robospec.emit.generate import emit_module
from robospec.model import controllers
from robospec.model.controller_kinds import CONTROLLER_KINDS
from robospec.pipeline import compile_spec

FRAGMENTS = [
    '"',
    "'",
    '"""',
    "'''",
    "\\",
    "\\n",
    "\n",
    "\r",
    "\t",
    '"""; import os; #',
    "'); __import__('os').system('touch CANARY'); ('",
    "{",
    "}",
    "{x}",
    "{{",
    "{self.__class__}",
    "\u2028",
    "\u2029",
    "\x85",
    "\ufeff",
    "\x00",
    "\x1b[31m",
    "#",
    "${2**99}",
    "$(eval 1)",
    "%s",
    "\U0001f916",
    "é",
    " ",
    "*",
    "../",
]
# a text that is hostile almost always: fragments and arbitrary (surrogate-free) Unicode
HOSTILE = st.lists(
    st.one_of(
        st.sampled_from(FRAGMENTS),
        st.text(st.characters(blacklist_categories=("Cs",)), min_size=1, max_size=3),
    ),
    min_size=1,
    max_size=6,
).map("".join)

# names the model accepts where it takes names (uid, materials, groups, keyframes, controllers,
# modes, cameras), leaning on Python words that must not become live names
NAME_WORDS = [
    "self",
    "os",
    "np",
    "import",
    "class",
    "None",
    "True",
    "lambda",
    "__init__",
    "__import__",
    "register_agent",
    "BaseAgent",
    "HERE",
    "sapien",
    "exec",
    "eval",
    "print",
    "super",
]
SPEC_NAME = st.one_of(
    st.sampled_from(NAME_WORDS),
    st.from_regex(r"\A[A-Za-z0-9_][A-Za-z0-9_.\-]{0,12}\Z"),
)
MEMBER = st.one_of(st.sampled_from(NAME_WORDS), st.from_regex(r"\A[A-Za-z_][A-Za-z0-9_]{0,12}\Z"))


def xml_legal(text: str) -> str:
    """The characters of ``text`` an XML 1.0 attribute can hold (a URDF is XML)."""
    legal = "".join(
        c
        for c in text
        if c in "\t\n\r"
        or "\x20" <= c <= "\ud7ff"
        or "\ue000" <= c <= "\ufffd"
        or c >= "\U00010000"
    )
    return legal


def file_name_legal(text: str) -> str:
    name = text.replace("/", "_").replace("\x00", "_")[:40]
    return "d" + name if name in ("", ".", "..") else name


def double_quoted(text: str, control: Callable[[int], bool]) -> str:
    """``text`` in double quotes: quotes and backslashes escaped with a backslash, each code
    point that ``control`` picks (and the line and paragraph separators and the BOM, which
    editors and parsers treat as line breaks or drop) as a ``\\uXXXX`` escape."""
    out = ['"']
    for c in text:
        code = ord(c)
        if c in '"\\':
            out.append("\\" + c)
        elif control(code) or c in "\u2028\u2029\ufeff":
            out.append(f"\\u{code:04x}")
        else:
            out.append(c)
    out.append('"')
    return "".join(out)


def yaml_quoted(text: str) -> str:
    """A YAML double-quoted scalar for any text: escapes whatever YAML forbids or would fold."""
    return double_quoted(text, lambda code: code < 0x20 or 0x7F <= code <= 0x9F)


def write_urdf(path: Path, base: str, link: str, joint: str) -> None:
    robot = etree.Element("robot", name="hostile")
    etree.SubElement(robot, "link", name=base)
    child = etree.SubElement(robot, "link", name=link)
    collision = etree.SubElement(etree.SubElement(child, "collision"), "geometry")
    etree.SubElement(collision, "box", size="0.1 0.1 0.1")
    inertial = etree.SubElement(child, "inertial")
    etree.SubElement(inertial, "mass", value="1")
    etree.SubElement(
        inertial, "inertia", ixx="0.01", iyy="0.01", izz="0.01", ixy="0", ixz="0", iyz="0"
    )
    joint_element = etree.SubElement(robot, "joint", name=joint, type="revolute")
    etree.SubElement(joint_element, "parent", link=base)
    etree.SubElement(joint_element, "child", link=link)
    etree.SubElement(joint_element, "axis", xyz="0 0 1")
    etree.SubElement(joint_element, "limit", lower="-1", upper="1", effort="10", velocity="1")
    path.write_bytes(etree.tostring(robot, xml_declaration=True, encoding="utf-8"))


def emitter_vocabulary() -> frozenset[str]:
    """Every identifier written in the emitter's source: code, templates and strings alike."""
    words: set[str] = set()
    for source in sorted((ROOT / "robospec/emit").glob("*.py")):
        for token in tokenize.generate_tokens(io.StringIO(source.read_text()).readline):
            if token.type == tokenize.NAME:
                words.add(token.string)
            elif token.type == tokenize.STRING:
                words.update(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", token.string))
    # controller configs are called with keyword arguments named by the model's fields (a spec
    # cannot add a field: the models forbid unknown keys)
    for model in vars(controllers).values():
        if isinstance(model, type) and issubclass(model, BaseModel):
            words.update(model.model_fields)
    # the config classes the emitter imports are named by the controller-kind registry
    words.update(kind.config_class for kind in CONTROLLER_KINDS)
    return frozenset(words - CODE_RUNNERS)


# names that run or reach code; the emitter's own source mentions some (``compile(..., "exec")``,
# ``importlib`` for hooks, ``from pathlib import Path``), but no module generated from the specs
# below may use them: these specs name no Python
CODE_RUNNERS = frozenset(
    {
        "exec",
        "eval",
        "compile",
        "__import__",
        "__builtins__",
        "builtins",
        "open",
        "getattr",
        "setattr",
        "globals",
        "importlib",
        "import_module",
        "pathlib",
        "Path",
        "subprocess",
        "system",
        "shutil",
    }
)
VOCABULARY = emitter_vocabulary()


def derived_identifiers(names: dict[str, list[str]]) -> set[str]:
    """The identifiers robospec may derive from spec names on purpose (see the module doc)."""
    allowed = set(names["class"]) | set(names["members"])
    for controller in names["controllers"]:
        base = re.sub(r"\W", "_", controller)
        allowed |= {base + suffix + "_" * n for suffix in ("", "_config") for n in range(4)}
    allowed |= {f"controller_{i}" + "_" * n for i in range(4) for n in range(4)}
    # class attributes named after groups: joint lists and the gains controllers share
    suffixes = ("_joint_names", "_stiffness", "_damping", "_force_limit", "_friction")
    allowed |= {
        re.sub(r"\W", "_", group) + suffix + "_" * n
        for group in names["groups"]
        for suffix in suffixes
        for n in range(3)
    }
    return {name for name in allowed if name.isidentifier() and not keyword.iskeyword(name)}


def check_module(source: str, derived: set[str], data_texts: list[str]) -> None:
    tree = ast.parse(source)
    compile(source, "<generated>", "exec")
    strange = identifiers(tree) - VOCABULARY - derived
    assert not strange, f"identifiers from nowhere: {sorted(strange)}"
    for name in identifiers(tree) & derived:  # derived names are plain ASCII identifiers
        assert name.isascii() and name.isidentifier() and not keyword.iskeyword(name)
    constants = [n.value for n in ast.walk(tree) if isinstance(n, ast.Constant)]
    strings = [c for c in constants if isinstance(c, str)]
    for text in data_texts:
        # data reaches the module as a whole string constant (or inside one: docstrings, paths)
        assert any(text in s for s in strings), f"{text!r} is not in any string constant"


@st.composite
def hostile_robots(draw: st.DrawFn) -> dict[str, object]:
    link = xml_legal(draw(HOSTILE)) or "L"
    joint = xml_legal(draw(HOSTILE)) or "J"
    base = "base" if link != "base" else "root"
    return {
        "link": link,
        "joint": joint if joint != link else joint + "_j",
        "base": base,
        "folder": file_name_legal(draw(HOSTILE)),
        "spec_file": file_name_legal(draw(HOSTILE)),
        "mode_key": draw(HOSTILE),
        "uid": draw(st.from_regex(r"\A[A-Za-z0-9][A-Za-z0-9_.\-]{0,12}\Z")),
        "class": draw(st.one_of(st.none(), MEMBER)),
        "material": draw(SPEC_NAME),
        "group": draw(SPEC_NAME),
        "keyframe": draw(SPEC_NAME),
        "controller": draw(SPEC_NAME),
        "mode": draw(SPEC_NAME),
        "camera": draw(SPEC_NAME),
        "member": draw(MEMBER),
    }


def spec_text(robot: dict[str, object], *, cameras: bool = True) -> str:
    q = {key: yaml_quoted(str(value)) for key, value in robot.items()}
    lines = [
        "robospec: 1",
        f"uid: {q['uid']}",
        f"description: {{urdf: {yaml_quoted(str(robot['folder']) + '/robot.urdf')}}}",
        f"materials: {{{q['material']}: {{static_friction: 1, dynamic_friction: 1}}}}",
        f"links: {{{q['link']}: {{material: {q['material']}}}}}",
        f"groups: {{{q['group']}: [{q['joint']}]}}",
        f"keyframes: {{{q['keyframe']}: {{qpos: {{{q['joint']}: 0.5}}}}}}",
        "controllers:",
        f"  {q['controller']}: {{type: pd_joint_pos, joints: {q['group']}, lower: -1,"
        " upper: 1, stiffness: 10, damping: 1}",
        f"control_modes: {{{q['mode']}: {{{q['mode_key']}: {q['controller']}}}}}",
        *(
            [f"cameras: {{{q['camera']}: {{mount: {q['link']}, width: 8, height: 8, fov: 1}}}}"]
            if cameras
            else []
        ),
        f"named_links: {{{q['member']}: {q['link']}}}",
        f"collision_rules: [{{links: [{q['link']}], group: 2, bit: 30}}]",
        f"tcp: {q['link']}",
    ]
    if robot["class"] is not None:
        lines.append(f"class_name: {q['class']}")
    return "\n".join(lines) + "\n"


def toml_quoted(text: str) -> str:
    """A TOML basic string for any text: escapes quotes, backslashes and control characters."""
    return double_quoted(text, lambda code: code < 0x20 or code == 0x7F)


def toml_spec_text(robot: dict[str, object]) -> str:
    """The same robot as :func:`spec_text`, written in TOML (cameras included)."""
    q = {key: toml_quoted(str(value)) for key, value in robot.items()}
    lines = ["robospec = 1", f"uid = {q['uid']}", f"tcp = {q['link']}"]
    if robot["class"] is not None:
        lines.append(f"class_name = {q['class']}")
    lines += [
        "[description]",
        f"urdf = {toml_quoted(str(robot['folder']) + '/robot.urdf')}",
        f"[materials.{q['material']}]",
        "static_friction = 1",
        "dynamic_friction = 1",
        f"[links.{q['link']}]",
        f"material = {q['material']}",
        "[groups]",
        f"{q['group']} = [{q['joint']}]",
        f"[keyframes.{q['keyframe']}.qpos]",
        f"{q['joint']} = 0.5",
        f"[controllers.{q['controller']}]",
        'type = "pd_joint_pos"',
        f"joints = {q['group']}",
        "lower = -1",
        "upper = 1",
        "stiffness = 10",
        "damping = 1",
        f"[control_modes.{q['mode']}]",
        f"{q['mode_key']} = {q['controller']}",
        f"[cameras.{q['camera']}]",
        f"mount = {q['link']}",
        "width = 8",
        "height = 8",
        "fov = 1",
        "[named_links]",
        f"{q['member']} = {q['link']}",
        "[[collision_rules]]",
        f"links = [{q['link']}]",
        "group = 2",
        "bit = 30",
    ]
    return "\n".join(lines) + "\n"


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@settings(
    # ROBOSPEC_INJECTION_EXAMPLES overrides; otherwise scaled like every property test (the
    # fast loop draws a fifth)
    max_examples=int(os.environ.get("ROBOSPEC_INJECTION_EXAMPLES", max(int(300 * FUZZ_SCALE), 20))),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(hostile_robots(), st.sampled_from(["yaml", "toml"]))
def test_hostile_text_in_any_field_reaches_the_module_only_as_string_constants(
    robot: dict[str, object], spec_format: str
) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / str(robot["folder"])
        folder.mkdir()
        names = (str(robot["base"]), str(robot["link"]), str(robot["joint"]))
        write_urdf(folder / "robot.urdf", *names)
        spec_path = Path(tmp) / f"{robot['spec_file']}.{spec_format}"
        text = spec_text(robot) if spec_format == "yaml" else toml_spec_text(robot)
        spec_path.write_text(text, encoding="utf-8")
        result = compile_spec(spec_path)
        assert not [d for d in result.diagnostics if d.code == "RS900"], [
            d.format_text() for d in result.diagnostics
        ]
        if result.robot is None:
            codes = ",".join(sorted({d.code for d in result.diagnostics if d.is_error}))
            event(f"{spec_format}: refused by the compiler ({codes})")
            return  # refused with diagnostics: nothing is emitted, nothing to inject into
        try:
            source = emit_module(result.robot, Path(tmp) / "out")
        except ValueError as exc:  # UnsafeIdentifier: build and register report RS105
            assert "not a valid Python identifier" in str(exc)
            event(f"{spec_format}: refused by the emitter")
            return
        event(f"{spec_format}: emitted")
        derived = derived_identifiers(
            {
                "class": [result.robot.class_name],
                "members": [str(robot["member"])],
                "controllers": [str(robot["controller"])],
                "groups": [str(robot["group"])],
            }
        )
        data = [str(robot["link"]), str(robot["joint"]), str(robot["mode_key"])]
        check_module(source, derived, data)


@pytest.mark.parametrize(
    "leak",
    [
        "__import__('os').system('touch CANARY')",
        "exec('1')",
        "self.CANARY = 1",
        "CANARY = 1",
        "def CANARY(self): pass",
        "x = 'fine'; y = CANARY",
    ],
)
def test_the_module_check_fails_when_spec_text_became_code(leak: str) -> None:
    with pytest.raises(AssertionError, match="identifiers from nowhere"):
        check_module(f"import numpy as np\n{leak}\n", set(), [])


def test_the_module_check_fails_when_data_is_not_a_constant() -> None:
    with pytest.raises(AssertionError, match="not in any string constant"):
        check_module("uid = 'a' + 'b'\n", set(), ["ab"])


# -- the canary --------------------------------------------------------------------------------

CANARY = "__import__('pathlib').Path('CANARY').touch()"
# each string, if evaluated, exec'd, formatted or spliced into code, would create ./CANARY
CANARY_TEXTS = {
    "link": f"L'); {CANARY}; ('",
    "joint": f'J"""; {CANARY}; """',
    "mode_key": "{" + CANARY + "}\n" + CANARY + "\u2028#",
    "folder": f"d'+{CANARY}+'",
    "spec_file": f"s{{{CANARY}}}",
}


@pytest.mark.maniskill
def test_canary_strings_never_run_at_build_import_register_or_make(tmp_path: Path) -> None:
    pytest.importorskip("mani_skill")
    robot: dict[str, object] = {
        "base": "base",
        "uid": "rs_canary",
        "class": None,
        "material": "m",
        "group": "arm",
        "keyframe": "rest",
        "controller": "c",
        "mode": "pd_joint_pos",
        "camera": "cam",
        "member": "hand",
        **CANARY_TEXTS,
    }
    work = tmp_path / "work"
    folder = work / str(robot["folder"])
    folder.mkdir(parents=True)
    write_urdf(folder / "robot.urdf", "base", str(robot["link"]), str(robot["joint"]))
    spec_path = work / (str(robot["spec_file"]) + ".yaml")
    # no camera: this machine cannot render (the property test covers camera configs)
    spec_path.write_text(spec_text(robot, cameras=False), encoding="utf-8")
    # every step runs with ./CANARY's folder as the working directory, in a fresh process
    probe = f"""
import sys, warnings
warnings.simplefilter("ignore")
sys.path.insert(0, {str(tmp_path)!r})
import gymnasium as gym
import mani_skill.envs
import built_agents                                  # import: registers through the package
from mani_skill.agents.registration import REGISTERED_AGENTS
del REGISTERED_AGENTS["rs_canary"]
import robospec                                      # import-time registration, cold then warm
robospec.register({str(spec_path)!r}, cache_dir={str(tmp_path / "cache")!r})
del REGISTERED_AGENTS["rs_canary"]
cls = robospec.register({str(spec_path)!r}, cache_dir={str(tmp_path / "cache")!r})["rs_canary"]
env = gym.make("Empty-v1", robot_uids="rs_canary", obs_mode="state",
               sim_backend="physx_cpu", render_backend="none")
env.reset(seed=0)
print("MODES", list(env.unwrapped.agent.controllers))
env.close()
"""
    build = subprocess.run(
        [
            sys.executable,
            "-m",
            "robospec.cli",
            "build",
            str(spec_path),
            "-o",
            str(tmp_path / "built_agents"),
        ],
        cwd=work,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert build.returncode == 0, build.stdout + build.stderr
    generated = ast.parse((tmp_path / "built_agents" / "rs_canary.py").read_text())
    strings = {n.value for n in ast.walk(generated) if isinstance(n, ast.Constant)}
    assert {CANARY_TEXTS["link"], CANARY_TEXTS["joint"], CANARY_TEXTS["mode_key"]} <= strings
    run = subprocess.run(
        [sys.executable, "-c", probe], cwd=work, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr[-3000:]
    assert "MODES ['pd_joint_pos']" in run.stdout, run.stdout
    assert not list(tmp_path.rglob("CANARY")), "spec text ran as code"
    assert not (ROOT / "CANARY").exists()
