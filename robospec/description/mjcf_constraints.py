"""What ManiSkill's MJCF loader leaves out between bodies and joints, reported at the element
when it concerns the robot (its ``_parse_mjcf`` reads none of these sections):

* RS070 — ``<equality>``: joint couplings (``<joint>``, ``<tendon>`` between two joints) and
  closed loops (``<connect>``, ``<weld>``, ``<distance>``). A coupling's mend is mechanical: a
  ``pd_joint_pos_mimic`` controller whose mimic map the hint writes out.
* RS071 — ``<tendon>``: fixed and spatial tendons (their ranges, springs and couplings).
* RS072 — ``<contact>``: ``<exclude>`` pairs collide in ManiSkill (mend: ``never_collide``),
  and ``<pair>`` contacts between geoms ManiSkill gives no collision shape are lost.
* RS077 — actuators on tendons, sites or bodies: ManiSkill loads no actuator (a spec's
  controllers drive joints), and these have no joint controller to stand for them.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Literal

from lxml import etree

from robospec.description.facts import Closure, Coupling, Mimic
from robospec.description.mjcf_loaded import LoadedMjcf
from robospec.description.mjcf_structure import names
from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import MJCF_ACTUATOR, MJCF_CONTACT, MJCF_EQUALITY, MJCF_TENDON


@dataclass(frozen=True)
class Robot:
    """The robot's names, for telling which constraints are about it."""

    joints: frozenset[str]
    bodies: frozenset[str]
    sites: dict[str, str]  # site -> body
    geoms: dict[str, str]  # geom -> body
    parents: dict[str, str]  # body -> parent body (the robot's first body has none)


def robot_names(loaded: LoadedMjcf) -> Robot:
    joints = {j.get("name", "") for body in loaded.robot for j in body.joints}
    sites: dict[str, str] = {}
    geoms: dict[str, str] = {}
    parents: dict[str, str] = {}
    for body in loaded.robot:
        for site in body.element.findall("site"):
            sites[site.get("name", "")] = body.name
        for geom in body.element.findall("geom"):
            geoms[geom.get("name", "")] = body.name
        if body.parent is not None:
            parents[body.name] = body.parent.name
    return Robot(
        frozenset(joints - {""}),
        frozenset(body.name for body in loaded.robot),
        sites,
        geoms,
        parents,
    )


def _floats(text: str | None, default: tuple[float, ...]) -> tuple[float, ...]:
    try:
        return tuple(float(v) for v in text.split()) if text else default
    except ValueError:
        return default


def _fixed_tendons(loaded: LoadedMjcf) -> dict[str, list[tuple[str, float]]]:
    """Fixed tendon name -> its (joint, coef) terms."""
    tendons: dict[str, list[tuple[str, float]]] = {}
    for section in loaded.sections("tendon"):
        for tendon in loaded.includes.find_all(section, "fixed"):
            terms = [
                (j.get("joint", ""), _floats(j.get("coef"), (1.0,))[0])
                for j in tendon.findall("joint")
            ]
            tendons[tendon.get("name", "")] = terms
    return tendons


def _number(value: float) -> str:
    return f"{value:.6g}"


def _mimic_entry(follower: str, leader: str, multiplier: float, offset: float) -> str:
    if multiplier == 1 and offset == 0:
        return f"{follower}: {leader}"
    parts = [f"joint: {leader}"]
    if multiplier != 1:
        parts.append(f"multiplier: {_number(multiplier)}")
    if offset != 0:
        parts.append(f"offset: {_number(offset)}")
    return f"{follower}: {{{', '.join(parts)}}}"


def _coupling(
    element: etree._Element, robot: Robot, tendons: dict[str, list[tuple[str, float]]]
) -> tuple[str, list[str], str | None] | None:
    """(what it is, the robot joints it ties, the mimic entry that mends it or None); None
    when it does not concern the robot."""
    poly = (*_floats(element.get("polycoef"), (0.0, 1.0)), 0.0, 0.0, 0.0, 0.0, 0.0)
    linear = all(c == 0 for c in poly[2:5])
    if element.tag == "joint":
        first, second = element.get("joint1", ""), element.get("joint2")
        if first not in robot.joints:
            return None
        if second is None:
            return f"joint '{first}' held at {_number(poly[0])}", [first], None
        if second not in robot.joints:
            return None
        entry = _mimic_entry(first, second, poly[1], poly[0]) if linear else None
        return f"'{first}' follows '{second}'", [first, second], entry
    # tendon equality: tendon1 = poly(tendon2), or tendon1 held at poly[0]
    terms = list(tendons.get(element.get("tendon1", ""), []))
    if element.get("tendon2") is not None:
        terms += [(j, -c * poly[1]) for j, c in tendons.get(element.get("tendon2", ""), [])]
    joints = [j for j, _ in terms if j in robot.joints]
    if not joints:
        return None
    what = f"tendon '{element.get('tendon1', '')}' coupling {names(joints)}"
    entry = None
    if len(terms) == 2 and len(joints) == 2 and linear and terms[1][1] != 0:
        (leader, c_leader), (follower, c_follower) = terms
        # c_leader q_leader + c_follower q_follower = poly[0]
        entry = _mimic_entry(follower, leader, -c_leader / c_follower, poly[0] / c_follower)
    return what, joints, entry


# a fixed tendon of two joints whose limited range lets the follower stray from the ratio its
# coefficients set by at most this share of the follower's own range is a coupling (the Shadow
# hand's T_FFJ1c, 0.00705 FFJ0 - 0.00805 FFJ1 in [-0.001, 0.001]: 0.28 rad of 1.57, 18 %);
# wider ones only bound a sum of angles (its T_FFJ1u: 5.2 rad, more than the whole range)
TIGHT_TENDON_SHARE = 0.25


def _rule(
    terms: list[tuple[str, float]], value: float, driven: frozenset[str]
) -> tuple[str, Mimic] | None:
    """(follower, its mimic rule) for ``c_a q_a + c_b q_b = value``: the joint an actuator
    drives leads (the other is the one ManiSkill leaves loose), else the first."""
    (first, c_first), (second, c_second) = terms
    if first not in driven and second in driven:
        (first, c_first), (second, c_second) = (second, c_second), (first, c_first)
    if c_second == 0 or first == second:
        return None
    return second, Mimic(first, -c_first / c_second, value / c_second)


def joint_couplings(
    loaded: LoadedMjcf,
    robot: Robot,
    limits: dict[str, tuple[float | None, float | None]],
    driven: frozenset[str],
) -> tuple[Coupling, ...]:
    """The pairs of the robot's joints the model ties together, each as a mimic rule: an
    ``<equality>`` between two joints, or between a tendon of two joints and nothing, and a
    fixed tendon of two joints whose range holds them to one ratio (:data:`TIGHT_TENDON_SHARE`).
    ``limits``: each joint's range; ``driven``: the joints an actuator drives."""
    tendons = _fixed_tendons(loaded)
    found: dict[str, Coupling] = {}

    def add(element: etree._Element, rule: tuple[str, Mimic] | None, what: str) -> None:
        if rule is not None and rule[0] not in found and rule[1].joint not in found:
            found[rule[0]] = Coupling(rule[0], rule[1], loaded.where(element).line, what)

    used: set[str] = set()
    for section in loaded.sections("equality"):
        for element in loaded.includes.children(section):
            poly = (*_floats(element.get("polycoef"), (0.0, 1.0)), 0.0, 0.0, 0.0, 0.0, 0.0)
            if any(c != 0 for c in poly[2:5]):
                continue  # not linear: no mimic rule says it
            if element.tag == "joint":
                first, second = element.get("joint1", ""), element.get("joint2")
                if first in robot.joints and second in robot.joints and poly[1] != 0:
                    # MuJoCo: joint1 = polycoef(joint2)
                    add(element, (first, Mimic(second, poly[1], poly[0])), f"equality '{first}'")
            elif element.tag == "tendon" and element.get("tendon2") is None:
                name = element.get("tendon1", "")
                used.add(name)
                terms = tendons.get(name, [])
                if len(terms) == 2 and all(j in robot.joints for j, _ in terms):
                    add(element, _rule(terms, poly[0], driven), f"tendon '{name}'")
    for section in loaded.sections("tendon"):
        for element in loaded.includes.find_all(section, "fixed"):
            name = element.get("name", "")
            terms = tendons.get(name, [])
            if name in used or len(terms) != 2 or not all(j in robot.joints for j, _ in terms):
                continue
            band = _floats(element.get("range"), ())
            if element.get("limited") == "false" or len(band) != 2 or band[1] < band[0]:
                continue
            rule = _rule(terms, (band[0] + band[1]) / 2, driven)
            if rule is None:
                continue
            follower, coefficient = rule[0], dict(terms)[rule[0]]
            lower, upper = limits.get(follower, (None, None))
            if lower is None or upper is None or upper <= lower:
                continue
            if (band[1] - band[0]) / abs(coefficient) <= TIGHT_TENDON_SHARE * (upper - lower):
                add(element, rule, f"tendon '{name}'")
    return tuple(found.values())


def equalities(loaded: LoadedMjcf, robot: Robot) -> Iterator[Diagnostic]:
    """RS070: the robot's couplings in one warning, its closed loops in another."""
    tendons = _fixed_tendons(loaded)
    couplings: list[tuple[etree._Element, str, str | None]] = []
    loops: list[tuple[etree._Element, str]] = []
    for section in loaded.sections("equality"):
        for element in loaded.includes.children(section):
            if element.tag in ("joint", "tendon"):
                found = _coupling(element, robot, tendons)
                if found is not None:
                    couplings.append((element, found[0], found[2]))
            elif element.tag in ("connect", "weld", "distance"):
                bodies = _loop_bodies(element, robot)
                if bodies:
                    loops.append((element, f"{element.tag} {' - '.join(bodies)}"))
    if couplings:
        entries = [entry for _, _, entry in couplings if entry is not None]
        hint = (
            "drive these joints with one pd_joint_pos_mimic controller: mimic: {"
            + ", ".join(entries)
            + "}"
            if entries
            else "ManiSkill cannot couple joints this way: drive them with separate controllers"
        )
        yield warning(
            loaded.where(couplings[0][0]),
            MJCF_EQUALITY,
            f"ManiSkill's MJCF loader does not load <equality> constraints: "
            f"{len(couplings)} joint coupling(s) are lost ("
            + "; ".join(what for _, what, _ in couplings[:6])
            + ("; ..." if len(couplings) > 6 else "")
            + "): ManiSkill moves these joints independently",
            hint,
        )
    if loops:
        yield warning(
            loaded.where(loops[0][0]),
            MJCF_EQUALITY,
            f"ManiSkill's MJCF loader does not load <equality> constraints: {len(loops)} closed "
            "loop(s) are open in ManiSkill ("
            + "; ".join(what for _, what in loops[:6])
            + ("; ..." if len(loops) > 6 else "")
            + ")",
            "a PhysX articulation is a tree: close each loop with the spec's loops: (robospec "
            "new writes them from these equalities), its other joints passive",
        )


def closures(loaded: LoadedMjcf, robot: Robot) -> tuple[Closure, ...]:
    """The robot's closed loops: each ``<connect>`` and ``<weld>`` between two of its bodies
    (or sites on them; a site's position is its point)."""
    sites = {
        site.get("name", ""): _floats(site.get("pos"), (0.0, 0.0, 0.0))
        for body in loaded.robot
        for site in body.element.findall("site")
    }
    found: list[Closure] = []
    for section in loaded.sections("equality"):
        for element in loaded.includes.children(section):
            if element.tag not in ("connect", "weld"):
                continue
            first, second = element.get("body1"), element.get("body2")
            anchor = _floats(element.get("anchor"), (0.0, 0.0, 0.0))
            if first is None and element.get("site1") is not None:
                first = robot.sites.get(element.get("site1", ""))
                second = robot.sites.get(element.get("site2", ""))
                anchor = sites.get(element.get("site1", ""), anchor)
            if first not in robot.bodies or second not in robot.bodies or len(anchor) != 3:
                continue
            point = (anchor[0], anchor[1], anchor[2])
            kind: Literal["connect", "weld"] = "connect" if element.tag == "connect" else "weld"
            found.append(Closure(kind, first, second, point, loaded.where(element).line))
    return tuple(found)


def mocap_welds(loaded: LoadedMjcf, robot: Robot) -> tuple[str, ...]:
    """The robot's bodies a ``<weld>`` holds to a mocap body (outside the robot's tree): MuJoCo
    moves such a body with the mocap, and with it the joints between it and the root."""
    mocap: set[str] = set()
    pending = [loaded.worldbody]
    while pending:
        for child in loaded.includes.children(pending.pop()):
            if child.tag == "body":
                if child.get("mocap") == "true":
                    mocap.add(child.get("name", ""))
                pending.append(child)
    mocap.discard("")
    found: list[str] = []
    for section in loaded.sections("equality"):
        for element in loaded.includes.find_all(section, "weld"):
            ends = [element.get("body1"), element.get("body2")]
            for this, other in (ends, ends[::-1]):
                if this in robot.bodies and other in mocap and this not in found:
                    found.append(this)
    return tuple(found)


def _loop_bodies(element: etree._Element, robot: Robot) -> list[str]:
    bodies = [element.get("body1"), element.get("body2")]
    bodies += [robot.sites.get(element.get(site) or "") for site in ("site1", "site2")]
    found = [b for b in bodies if b in robot.bodies]
    return found


def tendons(loaded: LoadedMjcf, robot: Robot) -> Iterator[Diagnostic]:
    """RS071: the robot's tendons in one warning (those an equality uses are RS070's)."""
    used = {
        element.get(attribute)
        for section in loaded.sections("equality")
        for element in loaded.includes.find_all(section, "tendon")
        for attribute in ("tendon1", "tendon2")
    }
    found: list[tuple[etree._Element, str]] = []
    for section in loaded.sections("tendon"):
        for tendon in loaded.includes.children(section):
            name = tendon.get("name", "")
            if tendon.tag not in ("fixed", "spatial") or name in used:
                continue
            if tendon.tag == "fixed":
                mine = any(j.get("joint") in robot.joints for j in tendon.findall("joint"))
            else:
                mine = any(s.get("site") in robot.sites for s in tendon.findall("site"))
            if mine:
                found.append((tendon, name or f"a {tendon.tag} tendon"))
    if found:
        yield warning(
            loaded.where(found[0][0]),
            MJCF_TENDON,
            f"ManiSkill's MJCF loader does not load tendons: {len(found)} of the robot's are "
            f"lost ({names([what for _, what in found])}), with their ranges, springs and the "
            "couplings they make",
            "ManiSkill has no tendons: where a fixed tendon makes joints move together, a "
            "pd_joint_pos_mimic controller can",
        )


def contacts(loaded: LoadedMjcf, robot: Robot) -> Iterator[Diagnostic]:
    """RS072: excluded body pairs that collide in ManiSkill; contact pairs it loses."""
    colliding = {geom.body.name for geom in loaded.geoms() if geom.collides}
    shapeless = {geom.element.get("name", "") for geom in loaded.geoms() if not geom.collides} - {
        ""
    }
    excluded: list[tuple[etree._Element, tuple[str, str]]] = []
    pairs: list[tuple[etree._Element, str]] = []
    for section in loaded.sections("contact"):
        for element in loaded.includes.children(section):
            if element.tag == "exclude":
                a, b = element.get("body1", ""), element.get("body2", "")
                adjacent = robot.parents.get(a) == b or robot.parents.get(b) == a
                if a in colliding and b in colliding and a != b and not adjacent:
                    excluded.append((element, (a, b)))
            elif element.tag == "pair":
                a, b = element.get("geom1", ""), element.get("geom2", "")
                lost = [g for g in (a, b) if g in shapeless]
                if lost and (a in robot.geoms or b in robot.geoms):
                    pairs.append((element, f"{a} - {b}"))
    if excluded:
        listed = ", ".join(f"[{a}, {b}]" for _, (a, b) in excluded)
        yield warning(
            loaded.where(excluded[0][0]),
            MJCF_CONTACT,
            f"ManiSkill's MJCF loader does not load <contact><exclude>: {len(excluded)} "
            "excluded body pair(s) collide in ManiSkill",
            f"never_collide: [{listed}]",
        )
    if pairs:
        yield warning(
            loaded.where(pairs[0][0]),
            MJCF_CONTACT,
            f"ManiSkill's MJCF loader does not load <contact><pair>: {len(pairs)} contact "
            f"pair(s) between geoms it gives no collision shape (contype 0) are lost "
            f"({names([what for _, what in pairs])})",
        )


def actuators(loaded: LoadedMjcf, robot: Robot) -> Iterator[Diagnostic]:
    """RS077: actuators with no joint, which no joint controller stands for."""
    tendon_joints = _fixed_tendons(loaded)
    found: list[tuple[etree._Element, str, list[str]]] = []
    for section in loaded.sections("actuator"):
        for element in loaded.includes.children(section):
            if not isinstance(element.tag, str) or element.get("joint") is not None:
                continue
            target = next(
                (a for a in ("tendon", "site", "body", "jointinparent") if element.get(a)), None
            )
            if target is None or target == "jointinparent":
                continue
            joints = [j for j, _ in tendon_joints.get(element.get("tendon", ""), [])]
            mine = (
                any(j in robot.joints for j in joints)
                or robot.sites.get(element.get("site", "")) is not None
                or element.get("body") in robot.bodies
            )
            if mine:
                label = element.get("name") or f"{element.tag} on {target} '{element.get(target)}'"
                found.append((element, label, joints))
    if found:
        moved = sorted({j for _, _, joints in found for j in joints if j in robot.joints})
        yield warning(
            loaded.where(found[0][0]),
            MJCF_ACTUATOR,
            f"{len(found)} actuator(s) drive tendons, sites or bodies "
            f"({names([label for _, label, _ in found])}): ManiSkill loads no actuators, "
            "and a spec's controllers drive joints one by one"
            + (f"; the joints these move: {names(moved)}" if moved else ""),
            "give those joints controllers; joints a tendon moves together can share one "
            "pd_joint_pos_mimic controller",
        )
