"""The mends write the values their docstrings promise, on small made-up descriptions whose
every branch is reached: the inertia policies (the bound's 2 mm radius of gyration, a box
about the shapes, the balanced mean, the diagonal; what each leaves alone and what ``new``
suggests), the sub-gram mass raised with its inertia scaled to keep the radius of gyration,
the contype a geom gets from its conaffinity (only where something touches it), and merged
MJCF bodies whose inertials combine by the parallel axis theorem.

tests/test_derive.py proves that each mend applies, notes and keeps lines on the docs'
examples; here each value is checked, so that a changed threshold, sign or clause fails.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from lxml import etree

from robospec.derive import Derived, Source, derive, suggest_mends

INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def _urdf(tmp_path: Path, mass: str, inertia: tuple[float, ...], collision: str = "") -> Source:
    """One moving link of ``mass`` and ``inertia`` (ixx, ixy, ixz, iyy, iyz, izz)."""
    values = " ".join(f'{a}="{v:g}"' for a, v in zip(INERTIA, inertia, strict=True))
    text = f"""<?xml version="1.0"?>
<robot name="arm">
  <link name="base_link"/>
  <link name="upper_arm">
    <inertial>
      <mass value="{mass}"/>
      <inertia {values}/>
    </inertial>
    {collision}
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/>
    <child link="upper_arm"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
</robot>
"""
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    return Source(str(path), path.name, "urdf", text.encode())


def _box(size: str) -> str:
    return f'<collision><geometry><box size="{size}"/></geometry></collision>'


def _inertia(derived: Derived) -> list[float]:
    element = etree.fromstring(derived.text.encode()).find("link[@name='upper_arm']/inertial")
    assert element is not None
    inertia = element.find("inertia")
    assert inertia is not None
    return [float(inertia.get(a, "")) for a in INERTIA]


def _mass(derived: Derived) -> float:
    element = etree.fromstring(derived.text.encode()).find("link[@name='upper_arm']/inertial/mass")
    assert element is not None
    return float(element.get("value", ""))


def _statuses(derived: Derived) -> list[str]:
    return [o.status for o in derived.outcomes]


# -- inertia -------------------------------------------------------------------------------------


def test_the_bound_raises_each_principal_moment_below_a_2_mm_radius_of_gyration_to_it(
    tmp_path: Path,
) -> None:
    # 2 kg, its y moment a radius of gyration of 10 µm: raised to 2 kg (2 mm)², the others kept
    source = _urdf(tmp_path, "2", (0.01, 0, 0, 2e-10, 0, 0.01))
    derived = derive(source, {"inertia": "bound"})
    assert _statuses(derived) == ["applied"]
    assert _inertia(derived) == pytest.approx([0.01, 0, 0, 2 * 0.002**2, 0, 0.01], rel=1e-9)
    # a moment at a radius of gyration above the bound (3 mm) needs nothing
    sound = _urdf(tmp_path, "2", (0.01, 0, 0, 2 * 0.003**2, 0, 0.01))
    assert _statuses(derive(sound, {"inertia": "bound"})) == ["stale"]
    # an all-zero inertia beside a mass (SAPIEN would ignore it) is given the bound
    zero = derive(_urdf(tmp_path, "0.5", (0, 0, 0, 0, 0, 0)), {"inertia": "bound"})
    assert _inertia(zero) == pytest.approx([2e-6, 0, 0, 2e-6, 0, 2e-6], rel=1e-9)
    # a nanogram says nothing: the bound of a link that light is 1e-12 kg m²
    feather = derive(_urdf(tmp_path, "1e-9", (1e-16, 0, 0, 1e-16, 0, 1e-16)), {"inertia": "bound"})
    assert _inertia(feather) == pytest.approx([1e-12, 0, 0, 1e-12, 0, 1e-12], rel=1e-9)


def test_an_inertia_or_a_mass_that_is_no_number_is_left_to_its_own_error(tmp_path: Path) -> None:
    policies = ["diagonal", "shapes", "bound", "balance"]
    unreadable = _urdf(tmp_path, "1", (0.01, 0, 0, 0.01, 0, 0.002)).data.replace(
        b'ixx="0.01"', b'ixx="heavy"'
    )
    (tmp_path / "unreadable.urdf").write_bytes(unreadable)
    source = Source(str(tmp_path / "unreadable.urdf"), "unreadable.urdf", "urdf", unreadable)
    assert _statuses(derive(source, {"inertia": policies})) == ["stale"]
    assert suggest_mends(source)[0] == {}
    massless = unreadable.replace(b'ixx="heavy"', b'ixx="1e-10"').replace(b'<mass value="1"/>', b"")
    (tmp_path / "massless.urdf").write_bytes(massless)
    source = Source(str(tmp_path / "massless.urdf"), "massless.urdf", "urdf", massless)
    assert _statuses(derive(source, {"inertia": policies})) == ["stale"]


def test_shapes_gives_a_far_too_small_inertia_a_solid_box_about_the_collision_shapes(
    tmp_path: Path,
) -> None:
    # 1.2 kg with radii of gyration of 10 µm, in a 0.1 x 0.2 x 0.3 m box: m/12 (b² + c²)...
    source = _urdf(tmp_path, "1.2", (1e-10, 0, 0, 1e-10, 0, 1e-10), _box("0.1 0.2 0.3"))
    derived = derive(source, {"inertia": "shapes"})
    assert _statuses(derived) == ["applied"] and "(shapes)" in derived.notes[0].message
    k = 1.2 / 12
    assert _inertia(derived) == pytest.approx(
        [k * (0.04 + 0.09), 0, 0, k * (0.01 + 0.09), 0, k * (0.01 + 0.04)], rel=1e-9
    )
    # small but not far too small (a radius of gyration of 1 mm, above 0.1 mm): shapes keeps it
    small = _urdf(tmp_path, "1", (1e-6, 0, 0, 1e-6, 0, 1e-6), _box("0.1 0.2 0.3"))
    assert _statuses(derive(small, {"inertia": "shapes"})) == ["stale"]
    # far too small about one axis only (its smallest principal moment): a box all the same
    rod = _urdf(tmp_path, "1.2", (1e-10, 0, 0, 0.01, 0, 0.01), _box("0.1 0.2 0.3"))
    assert _inertia(derive(rod, {"inertia": "shapes"}))[0] == pytest.approx(k * 0.13)
    # 50 µm: under the 0.1 mm no link has
    thin = _urdf(tmp_path, "1", (2.5e-9, 0, 0, 2.5e-9, 0, 2.5e-9), _box("0.1 0.2 0.3"))
    assert _statuses(derive(thin, {"inertia": "shapes"})) == ["applied"]
    # an all-zero inertia beside a mass is given one by shapes (SAPIEN would ignore it)
    zero = _urdf(tmp_path, "0.6", (0, 0, 0, 0, 0, 0), _box("0.1 0.2 0.3"))
    assert _inertia(derive(zero, {"inertia": "shapes"}))[0] == pytest.approx(0.05 * 0.13)
    # ... and left to SAPIEN by a policy that sizes nothing
    assert _statuses(derive(zero, {"inertia": "diagonal"})) == ["stale"]


def test_balance_sets_moments_that_break_the_triangle_inequality_to_their_mean(
    tmp_path: Path,
) -> None:
    # 0.001 + 0.002 < 0.01: no rigid body has these moments
    source = _urdf(tmp_path, "1", (0.01, 0, 0, 0.001, 0, 0.002))
    derived = derive(source, {"inertia": "balance"})
    assert _statuses(derived) == ["applied"]
    assert _inertia(derived) == pytest.approx([0.013 / 3, 0, 0, 0.013 / 3, 0, 0.013 / 3])
    # moments that keep the inequality are a body: nothing to balance
    sound = _urdf(tmp_path, "1", (0.01, 0, 0, 0.008, 0, 0.003))
    assert _statuses(derive(sound, {"inertia": "balance"})) == ["stale"]


def test_diagonal_drops_the_products_and_keeps_the_moments_and_a_massless_frame_is_left(
    tmp_path: Path,
) -> None:
    skewed = (0.01, 0.02, 0, 0.01, 0, 0.002)  # rejected: the products outweigh the moments
    derived = derive(_urdf(tmp_path, "1", skewed), {"inertia": "diagonal"})
    assert _inertia(derived) == [0.01, 0, 0, 0.01, 0, 0.002]
    # mass 0: SAPIEN computes the frame's mass and inertia; no policy touches it
    assert _statuses(derive(_urdf(tmp_path, "0", skewed), {"inertia": "diagonal"})) == ["stale"]
    # a negative moment: the diagonal alone is no inertia either, and nothing else was asked
    negative = _urdf(tmp_path, "1", (-0.01, 0.001, 0, 0.01, 0, 0.002))
    assert _statuses(derive(negative, {"inertia": "diagonal"})) == ["refused"]


def test_new_suggests_the_bound_or_the_shapes_for_an_inertia_far_too_small_for_its_mass(
    tmp_path: Path,
) -> None:
    tiny = (1e-10, 0, 0, 1e-10, 0, 1e-10)  # radii of gyration of 10 µm beside 1 kg
    (tmp_path / "bare").mkdir()
    (tmp_path / "boxed").mkdir()
    chosen, _ = suggest_mends(_urdf(tmp_path / "bare", "1", tiny))
    assert chosen == {"inertia": "bound"}  # no shape to measure
    chosen, _ = suggest_mends(_urdf(tmp_path / "boxed", "1", tiny, _box("0.1 0.1 0.1")))
    assert chosen == {"inertia": "shapes"}
    # 0.5 mm: small, yet a body PhysX solves; nothing to suggest
    assert suggest_mends(_urdf(tmp_path / "bare", "1", (2.5e-7, 0, 0, 2.5e-7, 0, 2.5e-7)))[0] == {}
    # 50 µm is far too small, and so is one axis at 10 µm
    thin = (2.5e-9, 0, 0, 2.5e-9, 0, 2.5e-9)
    assert suggest_mends(_urdf(tmp_path / "bare", "1", thin))[0] == {"inertia": "bound"}
    rod = (1e-10, 0, 0, 0.01, 0, 0.01)
    assert suggest_mends(_urdf(tmp_path / "bare", "1", rod))[0] == {"inertia": "bound"}
    # an all-zero inertia beside a mass loads: SAPIEN computes one from the shapes
    assert suggest_mends(_urdf(tmp_path / "bare", "1", (0,) * 6))[0] == {}
    # a negative moment the diagonal cannot mend: the bound
    negative = (-1e-9, 0.001, 0, 0.01, 0, 0.002)
    assert suggest_mends(_urdf(tmp_path / "bare", "1", negative))[0] == {"inertia": "bound"}


def test_new_suggests_every_inertia_policy_the_links_need_in_order(tmp_path: Path) -> None:
    # one link's products outweigh its moments (the diagonal mends it), another's radii of
    # gyration are 10 µm (the bound): both, the diagonal first
    text = _urdf(tmp_path, "1", (0.01, 0.02, 0, 0.01, 0, 0.002)).data.decode()
    tiny = (
        '<link name="tiny"><inertial><mass value="1"/><inertia ixx="1e-10" ixy="0" ixz="0" '
        'iyy="1e-10" iyz="0" izz="1e-10"/></inertial></link><joint name="wrist" '
        'type="revolute"><parent link="upper_arm"/><child link="tiny"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint></robot>'
    )
    path = tmp_path / "two.urdf"
    path.write_text(text.replace("</robot>", tiny))
    chosen, derived = suggest_mends(Source(str(path), path.name, "urdf", path.read_bytes()))
    assert chosen == {"inertia": ["diagonal", "bound"]} and derived.refusals == ()


# -- mass ----------------------------------------------------------------------------------------


def test_a_sub_gram_mass_is_raised_to_a_gram_its_inertia_scaled_with_it(tmp_path: Path) -> None:
    source = _urdf(tmp_path, "0.0002", (2e-8, 0, 0, 4e-8, 0, 6e-8))
    derived = derive(source, {"mass": "bound"})
    assert _mass(derived) == 0.001
    # five times the mass, five times the inertia: the radius of gyration kept
    assert _inertia(derived) == pytest.approx([1e-7, 0, 0, 2e-7, 0, 3e-7], rel=1e-9)
    assert "its inertia scaled with it" in derived.notes[0].message
    # a gram or more is no concern of the bound
    assert _statuses(derive(_urdf(tmp_path, "0.001", (1e-7,) * 6), {"mass": "bound"})) == ["stale"]


def test_a_zero_mass_beside_an_inertia_becomes_a_gram_and_a_massless_frame_is_left(
    tmp_path: Path,
) -> None:
    # SAPIEN ignores an inertial of mass 0: the gram is written, the inertia (nothing to scale
    # it from) kept as it is
    derived = derive(_urdf(tmp_path, "0", (0.01, 0, 0, 0.01, 0, 0.002)), {"mass": "bound"})
    assert _mass(derived) == 0.001
    assert _inertia(derived) == [0.01, 0, 0, 0.01, 0, 0.002]
    assert "scaled" not in derived.notes[0].message
    frame = derive(_urdf(tmp_path, "0", (0, 0, 0, 0, 0, 0)), {"mass": "bound"})
    assert _statuses(frame) == ["stale"]
    # a sub-gram mass beside an all-zero inertia is raised all the same, nothing scaled
    bare = derive(_urdf(tmp_path, "0.0002", (0, 0, 0, 0, 0, 0)), {"mass": "bound"})
    assert _mass(bare) == 0.001 and "scaled" not in bare.notes[0].message
    # a mass that is no number is its own error: the mend leaves it
    assert _statuses(derive(_urdf(tmp_path, "heavy", (0.01,) * 6), {"mass": "bound"})) == ["stale"]


def test_new_suggests_the_mass_bound_only_for_a_negative_mass(tmp_path: Path) -> None:
    inertia = (0.01, 0, 0, 0.01, 0, 0.002)
    assert suggest_mends(_urdf(tmp_path, "-0.5", inertia))[0] == {"mass": "bound"}
    assert suggest_mends(_urdf(tmp_path, "0.0002", inertia))[0] == {}  # tiny loads: warned
    assert suggest_mends(_urdf(tmp_path, "0", inertia))[0] == {}  # so does a zero one


# -- contype -------------------------------------------------------------------------------------


def _mjcf(tmp_path: Path, geoms: str) -> Source:
    """A two-body arm on a base whose box collides as MuJoCo's defaults have it (contype and
    conaffinity 1, written nowhere), and ``geoms`` on the upper body; default class ``soft``
    has a geom of contype 0 and conaffinity 1."""
    text = f"""<mujoco model="touching"><compiler angle="degree"/>
  <default><default class="soft"><geom contype="0" conaffinity="1"/></default></default>
  <worldbody>
    <body name="base">
      <geom type="box" size=".1 .1 .02"/>
      <body name="upper" pos="0 0 .1">
        <joint name="shoulder" axis="0 1 0" range="-90 90"/>
        {geoms}
      </body>
    </body>
  </worldbody>
</mujoco>
"""
    path = tmp_path / "touching.xml"
    path.write_text(text)
    return Source(str(path), path.name, "mjcf", text.encode())


def _contypes(derived: Derived) -> dict[str, str | None]:
    root = etree.fromstring(derived.text.encode())
    return {str(g.get("name")): g.get("contype") for g in root.iter("geom") if g.get("name")}


def test_a_geom_of_contype_0_gets_its_conaffinity_as_contype_where_a_contype_touches_it(
    tmp_path: Path,
) -> None:
    geoms = (
        # conaffinity 1 as MuJoCo's default: the base's default contype 1 touches it
        '<geom name="touched" type="sphere" size=".02" contype="0"/>'
        '<geom name="classed" class="soft" type="sphere" size=".02"/>'
        # bit 2: no geom's contype has it, so MuJoCo collides it with nothing
        '<geom name="untouched" type="sphere" size=".02" contype="0" conaffinity="2"/>'
        '<geom name="visual" type="sphere" size=".02" contype="0" conaffinity="0"/>'
    )
    derived = derive(_mjcf(tmp_path, geoms), {"contype": "conaffinity"})
    assert _contypes(derived) == {"touched": "1", "classed": "1", "untouched": "0", "visual": "0"}
    assert [c.subject for o in derived.outcomes for c in o.changes] == [
        "geom 'touched' of body 'upper'",
        "geom 'classed' of body 'upper'",
    ]


def test_contype_is_suggested_only_where_a_geom_would_get_a_shape(tmp_path: Path) -> None:
    untouched = '<geom name="g" type="sphere" size=".02" contype="0" conaffinity="2"/>'
    assert suggest_mends(_mjcf(tmp_path, untouched))[0] == {}
    touched = '<geom name="g" type="sphere" size=".02" contype="0" conaffinity="1"/>'
    assert suggest_mends(_mjcf(tmp_path, touched))[0] == {"contype": "conaffinity"}


# -- bodies --------------------------------------------------------------------------------------


def _plated(tmp_path: Path, upper: str, plate: str) -> Source:
    """An arm whose upper body (``upper``: its inertial and geoms) carries a jointless plate
    (``plate``: what the plate body holds), 0.1 m out along x."""
    text = f"""<mujoco model="plated"><compiler angle="radian"/>
  <worldbody>
    <body name="base">
      <geom type="box" size=".1 .1 .02"/>
      <body name="upper" pos="0 0 .1">
        <joint name="shoulder" axis="0 1 0" range="-1 1"/>
        {upper}
        <body name="plate" pos="0.1 0 0">{plate}</body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
    path = tmp_path / "plated.xml"
    path.write_text(text)
    return Source(str(path), path.name, "mjcf", text.encode())


def _inertial(derived: Derived, body: str) -> etree._Element | None:
    root = etree.fromstring(derived.text.encode())
    found = next(b for b in root.iter("body") if b.get("name") == body)
    return found.find("inertial")


def _numbers(text: str | None) -> list[float]:
    return [float(v) for v in (text or "").split()]


def test_merged_inertials_combine_masses_centres_and_inertias_by_parallel_axes(
    tmp_path: Path,
) -> None:
    # 1 kg at the upper body's origin, and a 3 kg plate 0.1 m out, turned 90° about z (its
    # diagonal 0.01, 0.02, 0.03 becomes 0.02, 0.01, 0.03 in the upper body's frame)
    source = _plated(
        tmp_path,
        '<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>',
        '<inertial pos="0 0 0" quat="0.7071067811865476 0 0 0.7071067811865476" mass="3" '
        'diaginertia="0.01 0.02 0.03"/><geom type="box" size=".01 .01 .01"/>',
    )
    derived = derive(source, {"bodies": "merge"})
    assert _statuses(derived) == ["applied"]
    inertial = _inertial(derived, "upper")
    assert inertial is not None
    assert float(inertial.get("mass", "")) == pytest.approx(4)
    assert _numbers(inertial.get("pos")) == pytest.approx([0.075, 0, 0])
    # each centre 0.075 or 0.025 m from the joint centre along x: m d² added about y and z
    shift = 1 * 0.075**2 + 3 * 0.025**2
    xx, yy, zz, xy, xz, yz = _numbers(inertial.get("fullinertia"))
    assert [xx, yy, zz] == pytest.approx([0.01 + 0.02, 0.01 + 0.01 + shift, 0.01 + 0.03 + shift])
    assert [xy, xz, yz] == pytest.approx([0, 0, 0], abs=1e-12)


def test_a_merged_full_inertia_keeps_its_products(tmp_path: Path) -> None:
    source = _plated(
        tmp_path,
        '<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.015 0.02"/>',
        '<inertial pos="0.01 0.02 0.03" mass="1" fullinertia="0.01 0.02 0.03 0.001 0.002 0.003"/>',
    )
    inertial = _inertial(derive(source, {"bodies": "merge"}), "upper")
    assert inertial is not None
    # the plate's centre at (0.11, 0.02, 0.03): the two centres d = ±(0.055, 0.01, 0.015)
    # from their common one, each adding m (|d|² E - d dᵀ)
    assert _numbers(inertial.get("pos")) == pytest.approx([0.055, 0.01, 0.015])
    d = (0.055, 0.01, 0.015)
    square = sum(v * v for v in d)
    shift = [[2 * ((square if i == j else 0.0) - d[i] * d[j]) for j in range(3)] for i in range(3)]
    own = [[0.02, 0.001, 0.002], [0.001, 0.035, 0.003], [0.002, 0.003, 0.05]]
    total = [[own[i][j] + shift[i][j] for j in range(3)] for i in range(3)]
    expected = [total[0][0], total[1][1], total[2][2], total[0][1], total[0][2], total[1][2]]
    assert _numbers(inertial.get("fullinertia")) == pytest.approx(expected)
    # grams weigh as kilograms do: 0.2 kg and a 0.3 kg plate 0.1 m out
    (tmp_path / "light").mkdir()
    light = _plated(
        tmp_path / "light",
        '<inertial pos="0 0 0" mass="0.2" diaginertia="0.001 0.001 0.001"/>',
        '<inertial pos="0 0 0" mass="0.3" diaginertia="0.001 0.001 0.001"/>',
    )
    inertial = _inertial(derive(light, {"bodies": "merge"}), "upper")
    assert inertial is not None and float(inertial.get("mass", "")) == pytest.approx(0.5)
    assert _numbers(inertial.get("pos")) == pytest.approx([0.06, 0, 0])


def test_a_merged_inertial_moves_up_alone_only_where_the_parent_has_nothing_to_weigh(
    tmp_path: Path,
) -> None:
    plate = '<inertial pos="0.01 0 0" mass="2" diaginertia="0.01 0.02 0.03"/>'
    (tmp_path / "bare").mkdir()
    (tmp_path / "shaped").mkdir()
    # the upper body has no inertial and no geom: the plate's inertial is its whole mass
    bare = derive(_plated(tmp_path / "bare", "", plate), {"bodies": "merge"})
    inertial = _inertial(bare, "upper")
    assert inertial is not None
    assert float(inertial.get("mass", "")) == 2
    assert _numbers(inertial.get("pos")) == pytest.approx([0.11, 0, 0])
    assert _numbers(inertial.get("fullinertia")) == pytest.approx([0.01, 0.02, 0.03, 0, 0, 0])
    # a geom of its own: MuJoCo weighs the geoms, and ManiSkill reads no inertial at all
    geom = '<geom type="sphere" size=".02"/>'
    shaped = derive(_plated(tmp_path / "shaped", geom, plate), {"bodies": "merge"})
    assert _inertial(shaped, "upper") is None


def _bodies(derived: Derived) -> list[str]:
    return [str(b.get("name")) for b in etree.fromstring(derived.text.encode()).iter("body")]


def _model(tmp_path: Path, worldbody: str, extra: str = "") -> Source:
    text = f"""<mujoco model="m"><compiler angle="radian"/>
  <default>
    <default class="pad"><geom rgba="1 0 0 1"/></default>
    <default class="other"><geom rgba="0 1 0 1"/></default>
    <default class="offset"><geom pos="0.01 0 0"/></default>
  </default>
  <worldbody>
    {worldbody}
  </worldbody>
  {extra}
</mujoco>
"""
    path = tmp_path / "m.xml"
    path.write_text(text)
    return Source(str(path), path.name, "mjcf", text.encode())


def test_a_jointless_body_robospec_cannot_move_is_refused_and_the_others_still_merged(
    tmp_path: Path,
) -> None:
    source = _model(
        tmp_path,
        '<body name="base"><geom type="box" size=".1 .1 .02"/>'
        '<body name="upper" pos="0 0 .1"><joint name="j" axis="0 1 0"/>'
        '<geom type="sphere" size=".02"/>'
        '<body name="replicated"><replicate count="2" offset="0 0 .01">'
        '<geom type="sphere" size=".01"/></replicate></body>'
        '<body name="unread" pos="0 0"><geom type="sphere" size=".01"/></body>'
        '<body name="plate" pos=".1 0 0"><geom type="box" size=".01 .01 .01"/></body>'
        "</body></body>",
    )
    derived = derive(source, {"bodies": "merge"})
    refused = sorted(r.message for r in derived.refusals)
    assert len(refused) == 2
    assert "cannot merge body 'replicated'" in refused[0] and "<replicate>" in refused[0]
    assert "cannot read the pose of body 'unread'" in refused[1]
    assert _bodies(derived) == ["base", "upper", "replicated", "unread"]  # the plate merged


def test_a_wrapper_body_is_skipped_to_the_robots_first_link_which_is_not_merged(
    tmp_path: Path,
) -> None:
    # ManiSkill's loader makes the wrapper's one body (no geom, no joint beside it) the robot's
    # first link: that body stays, what is welded below it goes
    source = _model(
        tmp_path,
        '<body name="wrapper"><body name="base"><geom type="box" size=".1 .1 .02"/>'
        '<body name="plate" pos=".1 0 0"><geom type="box" size=".01 .01 .01"/></body>'
        '<body name="upper" pos="0 0 .1"><joint name="j" axis="0 1 0"/>'
        '<geom type="sphere" size=".02"/></body></body></body>',
    )
    assert _bodies(derive(source, {"bodies": "merge"})) == ["wrapper", "base", "upper"]
    # a wrapper with a geom of its own is the first link: its jointless body is merged
    source = _model(
        tmp_path,
        '<body name="wrapper"><geom type="sphere" size=".01"/><body name="base">'
        '<geom type="box" size=".1 .1 .02"/><body name="upper" pos="0 0 .1">'
        '<joint name="j" axis="0 1 0"/><geom type="sphere" size=".02"/></body></body></body>',
    )
    assert _bodies(derive(source, {"bodies": "merge"})) == ["wrapper", "upper"]
    # so is a wrapper of a joint and a body: the body is welded to it, and merges into it
    source = _model(
        tmp_path,
        '<body name="wrapper"><joint name="w" axis="0 0 1"/><body name="base">'
        '<geom type="box" size=".1 .1 .02"/><body name="upper" pos="0 0 .1">'
        '<joint name="j" axis="0 1 0"/><geom type="sphere" size=".02"/></body></body></body>',
    )
    assert _bodies(derive(source, {"bodies": "merge"})) == ["wrapper", "upper"]
    # and a wrapper of two bodies: both are welded to it, and merge into it
    source = _model(
        tmp_path,
        '<body name="wrapper"><body name="base"><geom type="box" size=".1 .1 .02"/>'
        '<body name="upper" pos="0 0 .1"><joint name="j" axis="0 1 0"/>'
        '<geom type="sphere" size=".02"/></body></body><body name="plate">'
        '<geom type="sphere" size=".01"/></body></body>',
    )
    assert _bodies(derive(source, {"bodies": "merge"})) == ["wrapper", "upper"]


def test_a_merged_body_keeps_its_default_class_on_what_it_held_and_names_move_to_its_parent(
    tmp_path: Path,
) -> None:
    source = _model(
        tmp_path,
        '<body name="base"><geom type="box" size=".1 .1 .02"/>'
        '<body name="upper" pos="0 0 .1"><joint name="j" axis="0 1 0"/>'
        '<geom type="sphere" size=".02"/>'
        '<body name="plate" childclass="pad" pos=".1 0 0" euler="0 0 1.5707963267948966">'
        '<geom name="pad" type="box" size=".01 .01 .01" pos=".01 0 0"/>'
        '<geom name="rod" type="capsule" size=".005" fromto=".001 .002 .003 .02 .004 .005"/>'
        '<site name="tip" pos="0 .01 0"/><geom name="own" class="other" size=".01"/>'
        '<geom name="shifted" class="offset" size=".01"/>'
        '<body name="finger"><joint name="k" axis="0 1 0"/><geom type="sphere" size=".01"/>'
        '</body><body name="thumb" childclass="other"><joint name="t" axis="0 1 0"/>'
        '<geom type="sphere" size=".01"/></body></body></body></body>',
        '<contact><exclude body1="plate" body2="finger"/><exclude body1="upper" body2="plate"/>'
        '</contact><sensor><framepos objtype="body" objname="plate"/>'
        '<framepos objtype="xbody" objname="plate"/><framepos objtype="body" objname="finger"/>'
        '<framepos objtype="site" objname="tip"/></sensor>',
    )
    root = etree.fromstring(derive(source, {"bodies": "merge"}).text.encode())
    upper = next(b for b in root.iter("body") if b.get("name") == "upper")
    geoms = {g.get("name"): g for g in upper.findall("geom") if g.get("name")}
    # the plate's class goes with its geoms and the bodies below it
    assert geoms["pad"].get("class") == "pad"
    assert geoms["own"].get("class") == "other"  # its own class kept
    children = {b.get("name"): b.get("childclass") for b in upper.findall("body")}
    assert children == {"finger": "pad", "thumb": "other"}
    # posed in the upper body's frame: turned 90° about z, 0.1 m out along x
    assert _numbers(geoms["pad"].get("pos")) == pytest.approx([0.1, 0.01, 0])
    assert _numbers(geoms["shifted"].get("pos")) == pytest.approx([0.1, 0.01, 0])  # its class's
    assert _numbers(geoms["rod"].get("fromto")) == pytest.approx(
        [0.098, 0.001, 0.003, 0.096, 0.02, 0.005]
    )
    assert _numbers(upper.find("site").get("pos")) == pytest.approx([0.09, 0, 0])
    # what named the plate names the upper body; the exclusion of the two is gone
    assert [(e.get("body1"), e.get("body2")) for e in root.iter("exclude")] == [("upper", "finger")]
    # a sensor of the plate's frame (body or xbody) is one of the upper body's
    named = [(f.get("objtype"), f.get("objname")) for f in root.iter("framepos")]
    assert named == [("body", "upper"), ("xbody", "upper"), ("body", "finger"), ("site", "tip")]


def test_a_merged_body_of_its_parents_class_adds_no_class(tmp_path: Path) -> None:
    source = _model(
        tmp_path,
        '<body name="base"><geom type="box" size=".1 .1 .02"/>'
        '<body name="upper" childclass="pad" pos="0 0 .1"><joint name="j" axis="0 1 0"/>'
        '<geom type="sphere" size=".02"/><body name="plate" childclass="pad">'
        '<geom name="pad" type="box" size=".01 .01 .01"/><body name="finger">'
        '<joint name="k" axis="0 1 0"/><geom type="sphere" size=".01"/></body>'
        "</body></body></body>",
    )
    root = etree.fromstring(derive(source, {"bodies": "merge"}).text.encode())
    pad = next(g for g in root.iter("geom") if g.get("name") == "pad")
    finger = next(b for b in root.iter("body") if b.get("name") == "finger")
    assert (pad.get("class"), finger.get("childclass")) == (None, None)


def test_a_body_with_a_free_joint_is_no_jointless_body(tmp_path: Path) -> None:
    source = _model(
        tmp_path,
        '<body name="base"><freejoint/><geom type="box" size=".1 .1 .02"/>'
        '<body name="upper" pos="0 0 .1"><joint name="j" axis="0 1 0"/>'
        '<geom type="sphere" size=".02"/><body name="loose"><freejoint/>'
        '<geom type="sphere" size=".01"/></body></body></body>',
    )
    derived = derive(source, {"bodies": "merge"})
    assert _bodies(derived) == ["base", "upper", "loose"] and derived.refusals == ()
