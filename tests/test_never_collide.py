"""never_collide: binding, packing into the fewest collision-group bits, emission, physics."""

from __future__ import annotations

import itertools
import os
from collections.abc import Collection, Iterable
from pathlib import Path

import pytest
from conftest import maniskill_assets
from hypothesis import given, settings
from hypothesis import strategies as st

from robospec.diagnostics import has_errors
from robospec.pipeline import compile_spec
from robospec.resolve.collision_packing import NEVER_USED, Pair, clique_pairs, pack, pair

PANDA = """\
robospec: 1
uid: {uid}
description: {{urdf: "{{maniskill_assets}}/robots/panda/panda_v2.urdf"}}
controllers:
  arm:
    type: pd_joint_pos
    joints: "panda_joint[1-7]"
    lower: null
    upper: null
    stiffness: 1e3
    damping: 1e2
  gripper:
    type: pd_joint_pos_mimic
    joints: [panda_finger_joint1, panda_finger_joint2]
    lower: 0
    upper: 0.04
    stiffness: 1e3
    damping: 1e2
    mimic: {{panda_finger_joint2: panda_finger_joint1}}
control_modes:
  pd_joint_pos: {{arm: arm, gripper: gripper}}
"""
NEXT_LINE = PANDA.count("\n") + 1  # the first line after the template
# A keyframe that folds the arm back onto its base: links 5 and 6 press into links 0 and 1.
FOLDED = """\
keyframes:
  folded: {qpos: [0, 1.7, 0, -3.0, 0, 2.5, 0.78, 0.04, 0.04]}
"""
FOLDED_CLIQUE = ("panda_link0", "panda_link1", "panda_link5", "panda_link6")
PANDA_SRDF_BITS = frozenset(range(7))  # panda_v2.srdf's seven "Default" pairs, none adjacent


def _compile(tmp_path: Path, extra: str, uid: str = "rs_nc"):
    path = tmp_path / f"{uid}.yaml"
    path.write_text(PANDA.format(uid=uid) + extra)
    return compile_spec(path)


def _codes(result) -> list[str]:
    return [d.code for d in result.diagnostics]


# -- packing -----------------------------------------------------------------------------------


def srdf_bit_count(pairs: Iterable[Pair], adjacent: Collection[Pair] = ()) -> int:
    """Bits SAPIEN's SRDF route spends on ``pairs``: one per pair that is not parent-child."""
    skip = {pair(a, b) for a, b in adjacent}
    return sum(1 for a, b in pairs if pair(a, b) not in skip)


def test_a_clique_of_eight_links_takes_one_bit_where_the_srdf_route_takes_28() -> None:
    links = [f"link{i}" for i in range(8)]
    pairs = list(itertools.combinations(links, 2))
    packing = pack(pairs)
    assert packing.cliques == ((0, tuple(links)),)
    assert srdf_bit_count(pairs) == 28
    assert packing.side_effects == () and packing.uncovered == ()


def test_panda_srdf_pairs_pack_into_far_fewer_bits_than_pairs() -> None:
    from lxml import etree

    from robospec.description import load_description

    assets = maniskill_assets()
    root = etree.parse(str(assets / "robots/panda/panda_v2.srdf")).getroot()
    pairs = [(e.get("link1"), e.get("link2")) for e in root.iter("disable_collisions")]
    description, _ = load_description(str(assets / "robots/panda/panda_v2.urdf"), "urdf")
    assert description is not None
    adjacent = description.adjacent_pairs()
    packing = pack(pairs, free=adjacent)
    assert len(pairs) == 38 and srdf_bit_count(pairs, adjacent) == 29
    assert len(packing.cliques) <= 4
    covered = packing.disabled_pairs() | adjacent
    assert all(pair(a, b) in covered for a, b in pairs)
    assert packing.side_effects == ()


def test_parent_and_child_need_no_bit_but_may_share_one() -> None:
    # hand-finger pairs are parent-child: one bit covers link5 with the hand and both fingers
    free = {("finger_l", "hand"), ("finger_r", "hand")}
    requested = clique_pairs(["link5", "hand", "finger_l", "finger_r"])
    packing = pack(requested, free=free)
    assert packing.cliques == ((0, ("finger_l", "finger_r", "hand", "link5")),)
    assert pack(free, free=free).cliques == ()


def test_short_of_bits_the_cheapest_merge_is_taken_and_reported() -> None:
    requested = clique_pairs("abc") | {("c", "d"), ("e", "f")}
    packing = pack(requested, available=[3, 9])
    # merging {a,b,c} with {c,d} costs a/d and b/d; any merge with {e,f} costs more
    assert packing.cliques == ((3, ("a", "b", "c", "d")), (9, ("e", "f")))
    assert packing.side_effects == (("a", "d"), ("b", "d"))


def test_no_free_bit_leaves_the_pairs_uncovered() -> None:
    packing = pack([("a", "b")], available=[29, 30, 31])
    assert packing.cliques == () and packing.uncovered == (("a", "b"),)


def test_the_packing_is_deterministic() -> None:
    pairs = sorted(clique_pairs("abcd") | clique_pairs("defg") | {("a", "g")})
    first = pack(pairs, available=[4, 2])
    assert pack(list(reversed(pairs)), available=[2, 4]) == first
    assert pack([(b, a) for a, b in pairs], available=(2, 4)) == first


NAMES = [f"l{i}" for i in range(7)]
PAIRS = [pair(a, b) for a, b in itertools.combinations(NAMES, 2)]


@st.composite
def instances(draw: st.DrawFn) -> tuple[set, set, list[int]]:
    requested = set(draw(st.lists(st.sampled_from(PAIRS), max_size=15)))
    free = set(draw(st.lists(st.sampled_from(PAIRS), max_size=6)))
    available = draw(st.lists(st.integers(0, 31), max_size=6, unique=True))
    return requested, free, available


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@settings(max_examples=300, deadline=None)
@given(instances())
def test_packing_properties(instance: tuple[set, set, list[int]]) -> None:
    requested, free, available = instance
    packing = pack(requested, free=free, available=available)
    usable = set(available) - NEVER_USED
    need = requested - free
    bits = packing.bits
    assert len(set(bits)) == len(bits) and set(bits) <= usable and not set(bits) & NEVER_USED
    assert len(bits) <= len(usable)
    if need and not usable:
        assert set(packing.uncovered) == need and packing.cliques == ()
        return
    assert packing.uncovered == ()
    disabled = packing.disabled_pairs()
    assert need <= disabled  # every requested pair shares a bit
    assert set(packing.side_effects) == disabled - requested - free
    assert all(len(links) > 1 for _, links in packing.cliques)


def _minimum_cover_size(need: set, ok: set) -> int:
    """Brute force: the fewest cliques of the ``ok`` graph whose pairs cover ``need``."""
    nodes = sorted({x for p in need for x in p})
    cliques = [
        clique_pairs(c)
        for size in range(2, len(nodes) + 1)
        for c in itertools.combinations(nodes, size)
        if clique_pairs(c) <= ok
    ]
    for k in range(len(need) + 1):
        for chosen in itertools.combinations(cliques, k):
            if need <= set().union(*chosen):
                return k
    raise AssertionError("unreachable")


@settings(max_examples=150, deadline=None)
@given(
    st.lists(st.sampled_from(PAIRS[:15]), max_size=12),  # pairs among l0..l5
    st.lists(st.sampled_from(PAIRS[:15]), max_size=4),
)
def test_with_bits_enough_the_cover_is_minimum(requested: list, free: list) -> None:
    need, free_set = set(requested) - set(free), set(free)
    packing = pack(requested, free=free)
    assert packing.side_effects == ()
    assert len(packing.cliques) == (_minimum_cover_size(need, need | free_set) if need else 0)


# -- resolving ---------------------------------------------------------------------------------


def test_bits_avoid_the_srdf_the_spec_and_the_scenes(tmp_path: Path) -> None:
    result = _compile(
        tmp_path,
        "collision_rules: [{links: panda_hand, group: 2, bit: 7}]\n"
        "scene_collision_bits: [8, 10]\n"
        "never_collide:\n"
        "  - [panda_link0, panda_link1, panda_link5, panda_link6]\n"
        "  - [panda_link2, panda_link7]\n",
    )
    assert not has_errors(result.diagnostics), _codes(result)
    robot = result.robot
    assert robot.collision_rules[0].bit == 7  # the spec's own rule first
    packed = robot.collision_rules[1:]
    assert [(r.links, r.group, r.bit, r.value) for r in packed] == [
        (("panda_link0", "panda_link1", "panda_link5", "panda_link6"), 2, 9, 1),
        (("panda_link2", "panda_link7"), 2, 11, 1),
    ]
    assert robot.never_collide.available[:3] == (9, 11, 12)
    assert not set(robot.never_collide.available) & (PANDA_SRDF_BITS | {7, 8, 10, 29, 30, 31})


def test_pairs_that_never_collide_already_take_no_bit(tmp_path: Path) -> None:
    # link5/hand is an SRDF pair, link6/link7 parent and child, the fingers an SRDF pair
    result = _compile(
        tmp_path,
        'never_collide: [[panda_link5, panda_hand], [panda_link6, panda_link7], "panda_*finger"]\n',
    )
    assert not has_errors(result.diagnostics), _codes(result)
    assert result.robot.collision_rules == ()
    assert result.robot.never_collide.bits == ()


def _located(result) -> set[tuple[str, int, int]]:
    return {(d.code, d.location.line, d.location.column) for d in result.diagnostics}


def _column(line: str, text: str) -> int:
    return line.index(text) + 1


def test_an_entry_with_one_link_is_rs320(tmp_path: Path) -> None:
    line = "never_collide: [[panda_hand, panda_hand], panda_link*0]"
    result = _compile(tmp_path, line + "\n")
    expected = {
        ("RS320", NEXT_LINE, _column(line, "[panda_hand")),
        ("RS320", NEXT_LINE, _column(line, "panda_link*")),
    }
    assert expected <= _located(result)


def test_unknown_links_and_empty_globs_are_located(tmp_path: Path) -> None:
    line = "never_collide: [[panda_hand, panda_lnk3], [panda_x*, panda_hand]]"
    result = _compile(tmp_path, line + "\n")
    expected = {
        ("RS202", NEXT_LINE, _column(line, "panda_lnk3")),
        ("RS206", NEXT_LINE, _column(line, "panda_x*")),
    }
    assert expected <= _located(result)
    assert "RS320" not in _codes(result)  # one error per entry is enough


def test_disable_self_collisions_makes_never_collide_a_no_op(tmp_path: Path) -> None:
    result = _compile(
        tmp_path,
        "loader: {disable_self_collisions: true}\nnever_collide: [[panda_link0, panda_link6]]\n",
    )
    assert "RS322" in _codes(result)
    assert result.robot is not None and result.robot.collision_rules == ()


def test_no_free_bit_is_rs323(tmp_path: Path) -> None:
    bits = list(range(7, 29))
    result = _compile(
        tmp_path, f"scene_collision_bits: {bits}\nnever_collide: [[panda_link0, panda_link6]]\n"
    )
    assert "RS323" in _codes(result) and has_errors(result.diagnostics)


def test_side_effects_are_warned_at_the_entry(tmp_path: Path) -> None:
    bits = list(range(7, 28))
    result = _compile(
        tmp_path,
        f"scene_collision_bits: {bits}\n"
        "never_collide: [[panda_link1, panda_link3], [panda_link2, panda_link6]]\n",
    )
    (warning,) = [d for d in result.diagnostics if d.code == "RS321"]
    assert (warning.location.line, warning.location.column) == (NEXT_LINE + 1, 17)
    assert "panda_link1/panda_link6, panda_link3/panda_link6" in warning.message
    assert result.robot.collision_rules[0].bit == 28


def test_mjcf_body_bits_are_left_alone(tmp_path: Path) -> None:
    path = tmp_path / "humanoid.yaml"
    path.write_text(
        "robospec: 1\nuid: rs_nc_humanoid\n"
        'description: {mjcf: "{maniskill_assets}/robots/humanoid/humanoid.xml"}\n'
        "loader: {fix_root_link: false}\n"
        "controllers:\n  all: {type: pd_joint_pos, joints: '*', lower: -1, upper: 1, "
        "stiffness: 100, damping: 10}\n"
        "control_modes: {pd_joint_pos: all}\n"
        "never_collide: [[left_hand, right_hand], [left_foot, right_foot]]\n"
    )
    result = compile_spec(path)
    assert not has_errors(result.diagnostics), [d.format_text() for d in result.diagnostics]
    assert result.description.loader_collision_bits[-1][0] == 15  # one bit per body, 0-15
    assert result.robot.never_collide.bits == (16, 17)


def test_the_emitted_agent_sets_the_packed_bits(tmp_path: Path) -> None:
    from robospec.output.package import plan_package

    result = _compile(tmp_path, f"never_collide: [{list(FOLDED_CLIQUE)}]\n", uid="rs_nc_emit")
    files = plan_package([result], tmp_path / "agents")
    text = next(text for name, text in files.items() if name.endswith("rs_nc_emit.py"))
    assert (
        'for link_name in ["panda_link0", "panda_link1", "panda_link5", "panda_link6"]:\n'
        "            self.robot.links_map[link_name].set_collision_group_bit(group=2, bit_idx=7, "
        "bit=1)"
    ) in text


# -- SAPIEN ------------------------------------------------------------------------------------


def _bundled_descriptions() -> list[tuple[str, str, str]]:
    import mani_skill.envs  # noqa: F401
    from mani_skill.agents.registration import REGISTERED_AGENTS

    found = []
    for uid, entry in REGISTERED_AGENTS.items():
        cls = entry.agent_cls
        if not cls.__module__.startswith("mani_skill."):
            continue
        urdf, mjcf = getattr(cls, "urdf_path", None), getattr(cls, "mjcf_path", None)
        path = urdf or mjcf
        if path and os.path.exists(path):
            found.append((uid, "urdf" if urdf else "mjcf", str(path)))
    return found


@pytest.mark.usefixtures("maniskill")
def test_loader_bits_match_what_sapien_sets_for_every_bundled_agent() -> None:
    from robospec.description import load_description
    from robospec.maniskill.headless import headless_loading, make_empty_env

    agents = _bundled_descriptions()
    assert len(agents) == 24
    env = make_empty_env("panda")
    mismatches = []
    try:
        scene = env.unwrapped.scene
        for uid, kind, path in agents:
            description, _ = load_description(path, kind)  # type: ignore[arg-type]
            assert description is not None, uid
            with headless_loading():
                loader = (
                    scene.create_urdf_loader() if kind == "urdf" else scene.create_mjcf_loader()
                )
                builder = loader.parse(path)["articulation_builders"][0]
            sapien_bits: dict[int, set[str]] = {}
            for link in builder.link_builders:
                for bit in range(32):
                    if link.collision_groups[2] >> bit & 1:
                        sapien_bits.setdefault(bit, set()).add(link.name)
            ours = {bit: set(links) for bit, links in description.loader_collision_bits}
            if ours != sapien_bits:
                mismatches.append(f"{uid}: {ours} != {sapien_bits}")
    finally:
        env.close()
    assert mismatches == []


def _contact_pairs(uid: str, keyframe: str) -> set[tuple[str, str]]:
    """Pairs of the robot's links in contact one physics step after holding ``keyframe``."""
    import torch

    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(uid)
    try:
        env.reset(seed=0)
        agent = env.unwrapped.agent
        robot = agent.robot
        robot.set_qpos(torch.tensor(agent.keyframes[keyframe].qpos, dtype=torch.float32)[None])
        robot.set_qvel(torch.zeros_like(robot.get_qvel()))
        scene = env.unwrapped.scene
        scene.px.step()
        names = {link._objs[0].entity: link.name for link in robot.links}
        found = set()
        for contact in scene.get_contacts():
            a, b = (names.get(body.entity) for body in contact.bodies)
            if a and b and any(point.separation < 0 for point in contact.points):
                found.add(pair(a, b))
        return found
    finally:
        env.close()


@pytest.mark.usefixtures("maniskill")
def test_never_collide_stops_the_contacts_of_a_folded_arm(tmp_path: Path) -> None:
    import robospec

    without = tmp_path / "without.yaml"
    without.write_text(PANDA.format(uid=f"rs_nc_fold_{tmp_path.name[-8:]}") + FOLDED)
    with_rule = tmp_path / "with.yaml"
    with_rule.write_text(
        PANDA.format(uid=f"rs_nc_fold_nc_{tmp_path.name[-8:]}")
        + FOLDED
        + f"never_collide: [{list(FOLDED_CLIQUE)}]\n"
    )
    classes = robospec.register([without, with_rule], cache_dir=tmp_path / "cache")
    plain_uid, packed_uid = sorted(classes, key=len)
    # parent-child pairs (0/1, 5/6) never collide anyway; the other four do
    listed = clique_pairs(FOLDED_CLIQUE) - {
        ("panda_link0", "panda_link1"),
        ("panda_link5", "panda_link6"),
    }
    before = _contact_pairs(plain_uid, "folded")
    assert listed <= before  # links 5 and 6 press into links 0 and 1
    after = _contact_pairs(packed_uid, "folded")
    assert not after & listed


@pytest.mark.usefixtures("maniskill")
def test_two_robots_share_group_2_bits() -> None:
    """What docs/spec.md says about several robots in one scene: group 3 stays 0 on every
    shape, so a bit set on both robots' links also stops the robots colliding with each other."""
    import sapien

    from robospec.maniskill.headless import headless_loading

    urdf = str(maniskill_assets() / "robots/panda/panda_v2.urdf")

    def contacts_between_robots(bit: int | None) -> int:
        scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
        with headless_loading():
            loader = scene.create_urdf_loader()
            loader.fix_root_link = True
            a, b = loader.load(urdf), loader.load(urdf)
        b.set_root_pose(sapien.Pose([0.03, 0, 0]))  # the two arms overlap
        for link in (*a.links, *b.links):
            for shape in link.collision_shapes:
                groups = shape.get_collision_groups()
                assert groups[3] == 0
                if bit is not None:
                    groups[2] |= 1 << bit
                    shape.set_collision_groups(groups)
        scene.step()
        ours, theirs = {link.entity for link in a.links}, {link.entity for link in b.links}
        return sum(
            {c.bodies[0].entity, c.bodies[1].entity} & ours != set()
            and {c.bodies[0].entity, c.bodies[1].entity} & theirs != set()
            for c in scene.get_contacts()
        )

    assert contacts_between_robots(None) > 0
    assert contacts_between_robots(12) == 0
