"""Masses and inertias, checked as SAPIEN loads them (robospec.description.inertia).

robospec decides without numpy what SAPIEN decides with it; the fast tests hold the closed-form
principal moments and the verdicts to numpy's (a copy of SAPIEN's own rule), and the
``maniskill`` ones prove each diagnostic against SAPIEN: the inertia it asserts on, the mass
PhysX replaces, the inertial it ignores, the impossible inertia it takes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from robospec.description.inertia import principal_moments
from robospec.description.urdf import parse_urdf

ARM = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base_link"/>
  <link name="upper_arm">
    <inertial>
      <mass value="{MASS}"/>
      <inertia ixx="{XX}" iyy="{YY}" izz="{ZZ}" ixy="{XY}" ixz="{XZ}" iyz="{YZ}"/>
    </inertial>{COLLISION}
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/>
    <child link="upper_arm"/>
    <axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
</robot>
"""
BOX = '\n    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>'
MASS_LINE, INERTIA_LINE, INERTIAL_LINE = 6, 7, 5


def arm(
    mass: float = 1.0,
    moments: tuple[float, float, float] = (0.01, 0.01, 0.002),
    products: tuple[float, float, float] = (0.0, 0.0, 0.0),
    collision: str = "",
) -> str:
    values = dict(zip(("XX", "YY", "ZZ", "XY", "XZ", "YZ"), (*moments, *products), strict=True))
    text = ARM.replace("{MASS}", repr(float(mass))).replace("{COLLISION}", collision)
    for key, value in values.items():
        text = text.replace("{" + key + "}", repr(float(value)))
    return text


def diagnostics_of(text: str) -> list[Any]:
    _description, diagnostics = parse_urdf(text, "arm.urdf")
    return diagnostics


# -- SAPIEN's rule, without numpy ----------------------------------------------------------------


def sapien_asserts(mass: float, matrix: np.ndarray) -> bool:
    """SAPIEN 3.0.3's URDFLoader._build_link: whether it asserts 'invalid moment of inertia'."""
    if mass == 0 or np.array_equal(matrix, np.zeros((3, 3))):
        return False  # the inertial is ignored
    if np.array_equal(np.diag(np.diag(matrix)), matrix):
        eigs = np.diag(matrix)
    else:
        eigs, _vectors = np.linalg.eigh(matrix)
    return not all(x > 0 for x in eigs)


def random_inertias(count: int, seed: int) -> list[np.ndarray]:
    """Symmetric matrices over 10 orders of magnitude: positive definite, indefinite (a moment
    made negative), singular up to rounding, diagonal ones and some with zero products."""
    rng = np.random.default_rng(seed)
    matrices = []
    for i in range(count):
        base = rng.normal(size=(3, 3)) * 10 ** rng.uniform(-8, 2)
        matrix = base @ base.T
        if i % 4 == 1:
            matrix[0, 0] -= rng.uniform(0.5, 2) * np.linalg.eigvalsh(matrix)[-1]
        elif i % 4 == 2:
            matrix = matrix - np.eye(3) * np.linalg.eigvalsh(matrix)[0]
        elif i % 8 == 3:
            matrix = np.diag(np.diag(matrix) * rng.choice([1, -1, 0], size=3))
        matrices.append((matrix + matrix.T) / 2)
    return matrices


def test_principal_moments_are_numpys_eigenvalues() -> None:
    for matrix in random_inertias(2000, seed=1):
        xx, yy, zz = np.diag(matrix)
        xy, xz, yz = matrix[0, 1], matrix[0, 2], matrix[1, 2]
        ours = np.array(principal_moments(xx, xy, xz, yy, yz, zz))
        theirs = np.linalg.eigvalsh(matrix)
        assert np.allclose(ours, theirs, rtol=1e-9, atol=1e-12 * np.abs(theirs).max())


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_robospec_reports_every_inertia_sapien_asserts_on_and_no_other_beyond_rounding() -> None:
    checked = 0
    for matrix in random_inertias(4000, seed=2):
        xx, yy, zz = np.diag(matrix)
        xy, xz, yz = matrix[0, 1], matrix[0, 2], matrix[1, 2]
        text = arm(1.0, (xx, yy, zz), (xy, xz, yz))
        reported = any(d.code == "RS059" for d in diagnostics_of(text))
        eigs = np.linalg.eigvalsh(matrix)
        singular = abs(eigs[0]) <= 1e-13 * abs(eigs[-1]) and np.count_nonzero(matrix) > 3
        if singular:  # eigh's rounding decides SAPIEN's verdict: robospec reports it
            assert reported
            continue
        assert reported == sapien_asserts(1.0, matrix), (matrix, eigs)
        checked += 1
    assert checked > 2500


# -- the diagnostics ----------------------------------------------------------------------------


def test_an_inertia_with_a_negative_moment_is_an_error_at_the_inertia() -> None:
    [problem] = diagnostics_of(arm(products=(0.02, 0, 0)))
    assert (problem.code, problem.location.line) == ("RS059", INERTIA_LINE)
    assert "SAPIEN asserts 'invalid moment of inertia'" in problem.message
    assert problem.hint is not None and "with ixy, ixz and iyz set to 0" in problem.hint


def test_a_singular_inertia_is_an_error_whatever_rounding_makes_of_it() -> None:
    # Unitree Go1's base (example-robot-data): all six values 1e-6
    [problem] = diagnostics_of(arm(moments=(1e-6, 1e-6, 1e-6), products=(1e-6, 1e-6, 1e-6)))
    assert problem.code == "RS059" and "the inertia is singular" in problem.message


def test_a_diagonal_with_a_zero_moment_is_an_error() -> None:
    [problem] = diagnostics_of(arm(moments=(0.01, 0.01, 0.0)))
    assert problem.code == "RS059" and "SAPIEN asserts" in problem.message


def test_a_negative_mass_is_an_error_at_the_mass() -> None:
    [problem] = diagnostics_of(arm(mass=-1.0))
    assert (problem.code, problem.location.line) == ("RS060", MASS_LINE)


def test_an_inertial_sapien_ignores_is_a_warning_unless_it_is_a_massless_frame() -> None:
    [mass_only] = diagnostics_of(arm(mass=2.0, moments=(0, 0, 0)))
    [inertia_only] = diagnostics_of(arm(mass=0.0))
    assert (mass_only.code, mass_only.location.line) == ("RS061", INERTIAL_LINE)
    assert not mass_only.is_error and "mass 2 included" in mass_only.message
    assert inertia_only.code == "RS061" and "an inertia included" in inertia_only.message
    assert diagnostics_of(arm(mass=0.0, moments=(0, 0, 0))) == []


def test_impossible_inertias_are_one_warning_for_the_description() -> None:
    one = arm(moments=(0.002, 0.002, 0.01))
    text = one.replace("</robot>", "") + one[one.index("  <link name=") :].replace(
        "upper_arm", "forearm"
    ).replace("base_link", "upper_arm").replace('<link name="upper_arm"/>\n', "").replace(
        '"shoulder"', '"elbow"'
    )
    [problem] = diagnostics_of(text)
    assert (problem.code, problem.location.line) == ("RS062", INERTIA_LINE)
    assert not problem.is_error
    assert "0.002 + 0.002 < 0.01" in problem.message
    assert "so do the inertias of links 'forearm'" in problem.message


def test_a_thin_plate_at_the_limit_is_not_impossible() -> None:
    assert diagnostics_of(arm(moments=(0.005, 0.005, 0.01))) == []
    assert diagnostics_of(arm(moments=(0.005, 0.005, 0.010004))) == []  # rounding


# -- against SAPIEN -----------------------------------------------------------------------------


def sapien_link(text: str) -> tuple[Any, Any]:
    """(the upper arm SAPIEN loads from ``text``, its scene): loaded as ManiSkill's loader does,
    then stepped once so that PhysX has taken its mass."""
    import sapien

    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    loader = scene.create_urdf_loader()
    loader.urdf_dir, loader.package_dir, loader.ignore_pairs = ".", None, []
    articulation_builders, _actors, _cameras = loader._parse_urdf(text)
    articulation = articulation_builders[0].build()
    scene.step()
    return articulation.links[1], scene


@pytest.mark.usefixtures("maniskill")
def test_sapien_asserts_on_the_inertias_robospec_rejects() -> None:
    for text in (
        arm(products=(0.02, 0, 0)),
        arm(moments=(1e-6, 1e-6, 1e-6), products=(1e-6, 1e-6, 1e-6)),
        arm(moments=(0.01, 0.01, 0.0)),
    ):
        with pytest.raises(AssertionError, match="invalid moment of inertia"):
            sapien_link(text)
    link, _scene = sapien_link(arm())
    assert link.mass == pytest.approx(1.0)


@pytest.mark.usefixtures("maniskill")
def test_physx_replaces_a_negative_mass_with_one_kilogram() -> None:
    link, _scene = sapien_link(arm(mass=-1.0, moments=(0.01, 0.02, 0.03)))
    assert link.mass == pytest.approx(1.0)


@pytest.mark.usefixtures("maniskill")
def test_sapien_ignores_an_inertial_with_mass_or_inertia_zero() -> None:
    with_box, _scene = sapien_link(arm(mass=5.0, moments=(0, 0, 0), collision=BOX))
    assert with_box.mass == pytest.approx(1.0)  # the 0.1 m box at 1000 kg/m^3, not 5 kg
    bare, _scene2 = sapien_link(arm(mass=5.0, moments=(0, 0, 0)))
    assert bare.mass == pytest.approx(1e-6)
    ignored, _scene3 = sapien_link(arm(mass=0.0))
    assert ignored.mass == pytest.approx(1e-6)


@pytest.mark.usefixtures("maniskill")
def test_sapien_takes_an_inertia_that_breaks_the_triangle_inequality() -> None:
    link, _scene = sapien_link(arm(moments=(0.002, 0.002, 0.01)))
    assert sorted(link.inertia) == pytest.approx([0.002, 0.002, 0.01])


def test_descriptions_maniskill_ships_get_no_physics_warnings_but_a_copy_does(
    tmp_path: Path,
) -> None:
    from conftest import MANISKILL_SPECS, maniskill_assets

    from robospec.pipeline import compile_spec

    shipped = compile_spec(MANISKILL_SPECS / "fetch.yaml")
    physics = {"RS061", "RS062"}
    assert shipped.ok and not [d for d in shipped.diagnostics if d.code in physics]
    assets = maniskill_assets()
    copy = tmp_path / "fetch.yaml"
    copy.write_text(
        (MANISKILL_SPECS / "fetch.yaml").read_text().replace("{maniskill_assets}", str(assets))
    )
    [warning] = [d for d in compile_spec(copy).diagnostics if d.code in physics]
    assert (warning.code, warning.is_error) == ("RS062", False)
    assert "r_gripper_finger_link" in warning.message
