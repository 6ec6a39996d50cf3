"""The description checks on robots nobody here wrote: what robospec reports about a public
description is what SAPIEN does with it, and what robospec mends loads in full.

Needs the ``corpus`` extra (pybullet, example-robot-data, rtb-data: tests/corpus.py, whose
``install_folder`` finds each distribution's files); a missing distribution fails the test, as
a missing ManiSkill does. The fast tests run ``robospec``'s description checks on the real
files; the ``maniskill`` ones load the same files in SAPIEN.
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from corpus import CorpusMissing, install_folder

from robospec.description import load_description
from robospec.pipeline import compile_spec

ERD = "cmeel.prefix/share/example-robot-data/robots"


def corpus_file(distribution: str, path: str) -> Path:
    try:
        found = install_folder(distribution) / path
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    if not found.is_file():
        pytest.fail(f"{distribution} has no {path}: the corpus extra pins the version that has")
    return found


@dataclass(frozen=True)
class Finding:
    """What robospec reports on a corpus description, and what SAPIEN does with it."""

    id: str
    distribution: str
    path: str
    code: str
    words: str  # in the diagnostic's message
    sapien_says: str  # in the exception SAPIEN's loader raises on the description
    visuals: bool = False  # whether SAPIEN must read the visuals to meet it


FINDINGS = [
    *(
        Finding(
            name,
            "example-robot-data",
            f"{ERD}/{path}",
            "RS059",
            f"link '{link}'",
            "invalid moment of inertia",
        )
        for name, path, link in (
            ("go1_base_all_1e-6", "go1_description/urdf/go1.urdf", "base"),
            ("anymal_c_hatch", "anymal_c_simple_description/urdf/anymal.urdf", "hatch"),
            ("anymal_b_base", "anymal_b_simple_description/robots/anymal.urdf", "base"),
            ("b1_base", "b1_description/urdf/b1.urdf", "base"),
            ("hyq_base", "hyq_description/robots/hyq_no_sensors.urdf", "base_link"),
            ("icub_head", "icub_description/robots/icub.urdf", "head"),
            ("tiago_antenna", "tiago_description/robots/tiago.urdf", "base_antenna_left_link"),
        )
    ),
    Finding(
        "xarm6_reduction",
        "pybullet",
        "pybullet_data/xarm/xarm6_robot.urdf",
        "RS064",
        "'reduction' is not a number",
        "could not convert string to float: 'reduction'",
    ),
    Finding(
        "pr2_transmission_type_attribute",
        "example-robot-data",
        f"{ERD}/pr2_description/urdf/pr2.urdf",
        "RS064",
        "has no <type> element",
        "'NoneType' object has no attribute 'text'",
    ),
    Finding(
        "husky_optenv",
        "pybullet",
        "pybullet_data/husky/husky.urdf",
        "RS063",
        "$(optenv HUSKY_IMU_",
        "could not be read to its end",
    ),
    Finding(
        "racecar_differential_scale",
        "pybullet",
        "pybullet_data/racecar/racecar_differential.urdf",
        "RS052",
        'scale="1 1 1 1" is not 3 numbers',
        "incompatible constructor arguments",
    ),
    Finding(
        "romeo_laas_small_empty_texture",
        "example-robot-data",
        f"{ERD}/romeo_description/urdf/romeo_laas_small.urdf",
        "RS052",
        "<texture> without filename",
        "Missing required attribute filename",
        visuals=True,
    ),
    Finding(
        "ur3_robot_without_name",
        "example-robot-data",
        f"{ERD}/ur_description/urdf/ur3.urdf",
        "RS052",
        "<robot> has no name",
        "Missing required attribute name",
    ),
]
FINDING_IDS = [f.id for f in FINDINGS]


@pytest.mark.parametrize("finding", FINDINGS, ids=FINDING_IDS)
def test_robospec_reports_the_finding_as_an_error_at_its_element(finding: Finding) -> None:
    path = corpus_file(finding.distribution, finding.path)
    _description, diagnostics = load_description(str(path), "urdf")
    found = [d for d in diagnostics if d.code == finding.code and finding.words in d.message]
    assert found, [d.format_text() for d in diagnostics]
    assert found[0].is_error and found[0].location.line > 1


def sapien_stops(path: Path, *, visuals: bool) -> BaseException | None:
    """The exception SAPIEN 3.0.3 raises loading ``path`` as ManiSkill does (visuals left out,
    as without a render device, unless ``visuals``: then its parser reads them first)."""
    import sapien
    from lxml import etree
    from sapien.wrapper.urchin import URDF

    from robospec.maniskill.headless import strip_urdf_visuals

    text = path.read_bytes().decode()
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    try:
        if visuals:
            URDF._from_xml(etree.fromstring(text.encode()), str(path.parent), lazy_load_meshes=True)
        loader = scene.create_urdf_loader()
        loader.urdf_dir, loader.package_dir, loader.ignore_pairs = str(path.parent), None, []
        articulation_builders, _actors, _cameras = loader._parse_urdf(strip_urdf_visuals(text))
        articulation_builders[0].build()
    except Exception as stopped:  # what SAPIEN raises is what the test is about
        return stopped
    finally:
        del scene
    return None


@pytest.mark.usefixtures("maniskill")
@pytest.mark.parametrize("finding", FINDINGS, ids=FINDING_IDS)
def test_sapien_stops_where_robospec_said_it_would(finding: Finding) -> None:
    path = corpus_file(finding.distribution, finding.path)
    stopped = sapien_stops(path, visuals=finding.visuals)
    assert stopped is not None and finding.sapien_says in str(stopped), repr(stopped)


@pytest.mark.usefixtures("maniskill")
def test_go1_loads_once_its_base_inertia_is_mended_as_the_hint_says(tmp_path: Path) -> None:
    source = corpus_file("example-robot-data", f"{ERD}/go1_description/urdf/go1.urdf")
    _description, diagnostics = load_description(str(source), "urdf")
    [base] = [d for d in diagnostics if d.code == "RS059"]
    assert base.hint is not None and "with ixy, ixz and iyz set to 0" in base.hint
    lines = source.read_text().splitlines(keepends=True)
    line = lines[base.location.line - 1]
    for product in ("ixy", "ixz", "iyz"):
        start = line.index(f'{product}="') + len(product) + 2
        line = line[:start] + "0" + line[line.index('"', start) :]
    lines[base.location.line - 1] = line
    mended = tmp_path / "go1.urdf"
    mended.write_text("".join(lines))
    assert [d.code for d in load_description(str(mended), "urdf")[1] if d.is_error] == []
    assert sapien_stops(mended, visuals=False) is None


# -- package:// and xacro: what robospec finds is what the agent loads -----------------------------


def spec_for(tmp_path: Path, uid: str, description: str) -> Path:
    spec = tmp_path / f"{uid}.yaml"
    spec.write_text(
        textwrap.dedent(
            f"""\
            robospec: 1
            uid: {uid}
            description: {description}
            controllers:
              all: {{type: pd_joint_pos, joints: "*", lower: null, upper: null, stiffness: 100,
                    damping: 10, normalize_action: false}}
            control_modes:
              pd_joint_pos: {{all: all}}
            """
        )
    )
    return spec


def collision_counts(urdf_text: str) -> dict[str, int]:
    from lxml import etree

    root = etree.fromstring(urdf_text.encode())
    return {link.get("name"): len(link.findall("collision")) for link in root.iter("link")}


def loaded_counts(uid: str) -> dict[str, int]:
    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(uid)
    try:
        links = env.unwrapped.agent.robot.links
        return {link.name: len(link._objs[0].collision_shapes) for link in links}
    finally:
        env.close()


KR16 = "rtbdata/xacro/kuka_description/kuka_kr16"


def test_kr16_names_a_package_only_the_spec_can_place(tmp_path: Path) -> None:
    urdf = corpus_file("rtb-data", f"{KR16}/urdf/kr16_2.urdf")
    diagnostics = compile_spec(spec_for(tmp_path, "kr16", f"{{urdf: {urdf}}}")).diagnostics
    [problem] = [d for d in diagnostics if d.is_error]  # beside RS091: its efforts are 0
    assert problem.code == "RS058" and "'kuka_kr16_support'" in problem.message
    placed = spec_for(
        tmp_path, "kr16", f"{{urdf: {urdf}, packages: {{kuka_kr16_support: {urdf.parent.parent}}}}}"
    )
    assert compile_spec(placed).ok


@dataclass(frozen=True)
class Carried:
    """A corpus robot whose meshes SAPIEN alone would not find from where it loads them."""

    id: str
    kind: str
    path: str
    packages: str = ""


CARRIED = [
    Carried("kr16_packages_map", "urdf", f"{KR16}/urdf/kr16_2.urdf", f"kuka_kr16_support: {KR16}"),
    Carried("wx250s_xacro", "xacro", "rtbdata/xacro/trossen_descriptions/urdf/wx250s.urdf.xacro"),
    Carried(
        "puma560_xacro",
        "xacro",
        "rtbdata/xacro/unimation_puma560_description/urdf/puma560_robot.urdf.xacro",
    ),
    Carried(
        "ridgeback_package_xml",
        "xacro",
        "rtbdata/xacro/clearpath_ridgeback_description/urdf/ridgeback.urdf.xacro",
    ),
]


@pytest.mark.usefixtures("maniskill")
@pytest.mark.parametrize("robot", CARRIED, ids=[c.id for c in CARRIED])
def test_a_registered_corpus_robot_has_every_collision_shape(
    robot: Carried, tmp_path: Path
) -> None:
    import robospec

    folder = install_folder("rtb-data")
    path = corpus_file("rtb-data", robot.path)
    packages = ""
    if robot.packages:
        name, _, relative = robot.packages.partition(": ")
        packages = f", packages: {{{name}: {folder / relative}}}"
    uid = f"rs_corpus_{robot.id}"
    spec = spec_for(tmp_path, uid, f"{{{robot.kind}: {path}{packages}}}")
    agents: dict[str, Any] = robospec.register(spec, cache_dir=tmp_path / "cache")
    carried = Path(agents[uid].urdf_path)
    assert carried.parent != path.parent  # loaded from the cache, not beside the original
    want = collision_counts(carried.read_text())
    loaded = loaded_counts(uid)
    assert sum(loaded.values()) > 0
    assert loaded == {name: want[name] for name in loaded}
