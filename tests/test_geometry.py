"""robospec.geometry (plain Python, for the light core) computes what a maintained library does:
each conversion, composition and inverse equals scipy.spatial.transform.Rotation's on random
inputs. URDF's rpy is scipy's extrinsic ``'xyz'``; robospec's quaternions are wxyz, scipy's
xyzw (``scalar_first=True`` reads and writes wxyz); a quaternion and its negative are one
rotation, so quaternions compare up to sign."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from robospec import geometry
from robospec.geometry import Degenerate

ATOL = 1e-12

angle = st.floats(-math.pi, math.pi, allow_nan=False)
rpys = st.tuples(angle, angle, angle)
component = st.floats(-1.0, 1.0, allow_nan=False)
vectors = st.tuples(component, component, component)
directions = vectors.filter(lambda v: math.sqrt(sum(c * c for c in v)) > 0.1)
quaternions = (
    st.tuples(component, component, component, component)
    .filter(lambda q: math.sqrt(sum(c * c for c in q)) > 0.1)
    .map(geometry.normalized)
)
positions = st.tuples(*(st.floats(-10.0, 10.0, allow_nan=False),) * 3)
poses = st.tuples(positions, quaternions)


def scipy_rotation(q: geometry.Quaternion) -> Rotation:
    return Rotation.from_quat(q, scalar_first=True)


def assert_same_quaternion(ours: geometry.Quaternion, theirs: Rotation) -> None:
    expected = theirs.as_quat(scalar_first=True)
    sign = 1.0 if np.dot(ours, expected) >= 0 else -1.0  # q and -q: one rotation
    np.testing.assert_allclose(ours, sign * expected, atol=ATOL)


def homogeneous(pose: geometry.Pose) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, :3] = scipy_rotation(pose[1]).as_matrix()
    matrix[:3, 3] = pose[0]
    return matrix


# -- rpy


@given(rpys)
def test_an_rpy_is_scipys_extrinsic_xyz_as_a_quaternion(rpy: geometry.Vector) -> None:
    assert_same_quaternion(geometry.quaternion_from_rpy(*rpy), Rotation.from_euler("xyz", rpy))


@given(rpys)
def test_an_rpy_is_scipys_extrinsic_xyz_as_a_matrix(rpy: geometry.Vector) -> None:
    expected = Rotation.from_euler("xyz", rpy).as_matrix()
    np.testing.assert_allclose(geometry.matrix_from_rpy(*rpy), expected, atol=ATOL)


def _assert_rpy_of(rpy: geometry.Vector, rotation: Rotation) -> None:
    """``rpy`` is ``rotation``, its pitch in [-π/2, π/2]; away from gimbal lock these are
    scipy's own angles (scipy's roll and yaw at ±π may differ by sign: one angle)."""
    assert -math.pi / 2 <= rpy[1] <= math.pi / 2
    np.testing.assert_allclose(
        Rotation.from_euler("xyz", rpy).as_matrix(), rotation.as_matrix(), atol=1e-9
    )
    if abs(abs(rpy[1]) - math.pi / 2) > 1e-3:
        turns = np.asarray(rpy) - rotation.as_euler("xyz")
        np.testing.assert_allclose(np.angle(np.exp(1j * turns)), 0.0, atol=1e-9)


@given(quaternions)
def test_a_quaternions_rpy_is_scipys(q: geometry.Quaternion) -> None:
    _assert_rpy_of(geometry.rpy_from_quaternion(q), scipy_rotation(q))


@given(quaternions)
def test_a_matrixs_rpy_is_scipys(q: geometry.Quaternion) -> None:
    rotation = scipy_rotation(q)
    _assert_rpy_of(geometry.rpy_from_matrix(tuple(map(tuple, rotation.as_matrix()))), rotation)


# pitches at gimbal lock and a hair from it, where roll and yaw read off a quaternion are rounding
locked_pitch = st.sampled_from([1.0, -1.0]).flatmap(
    lambda side: st.sampled_from([0.0, 1e-12, 1e-9, 1e-7]).map(
        lambda hair: side * (math.pi / 2 - hair)
    )
)


@given(angle, locked_pitch, angle)
def test_a_quaternions_rpy_at_and_near_gimbal_lock_is_its_rotation(
    roll: float, pitch: float, yaw: float
) -> None:
    q = geometry.quaternion_from_rpy(roll, pitch, yaw)
    _assert_rpy_of(geometry.rpy_from_quaternion(q), scipy_rotation(q))


def test_a_quarter_turn_about_y_reads_as_compose_has_always_written_it() -> None:
    # its roll and yaw off the quaternion are both π, by luck right: kept (no trip through a
    # matrix), so a part mounted so is written as before
    half = math.sqrt(0.5)
    assert geometry.rpy_from_quaternion((half, 0.0, half, 0.0)) == (math.pi, math.pi / 2, math.pi)


@given(angle, st.sampled_from([math.pi / 2, -math.pi / 2]), angle)
def test_a_matrix_in_gimbal_lock_reads_with_yaw_0_and_the_same_rotation(
    roll: float, pitch: float, yaw: float
) -> None:
    locked = geometry.matrix_from_rpy(roll, pitch, yaw)
    rpy = geometry.rpy_from_matrix(locked)
    assert rpy[2] == 0.0
    assert math.isclose(rpy[1], pitch, abs_tol=1e-7)
    np.testing.assert_allclose(geometry.matrix_from_rpy(*rpy), locked, atol=1e-9)


def test_a_matrix_a_hair_from_gimbal_lock_keeps_its_yaw() -> None:
    rpy = geometry.rpy_from_matrix(geometry.matrix_from_rpy(0.25, math.pi / 2 - 1e-9, 0.5))
    assert rpy[2] != 0.0
    np.testing.assert_allclose(
        geometry.matrix_from_rpy(*rpy),
        geometry.matrix_from_rpy(0.25, math.pi / 2 - 1e-9, 0.5),
        atol=1e-12,
    )


# -- quaternions and matrices


@given(quaternions)
def test_a_quaternions_matrix_is_scipys(q: geometry.Quaternion) -> None:
    np.testing.assert_allclose(
        geometry.matrix_from_quaternion(q), scipy_rotation(q).as_matrix(), atol=ATOL
    )


@pytest.mark.parametrize(
    "q",
    [
        (1.0, 0.0, 0.0, 0.0),  # the trace largest
        (0.0, 1.0, 0.0, 0.0),  # each diagonal entry largest in turn: half turns about x, y, z
        (0.0, 0.0, 1.0, 0.0),
        (0.0, 0.0, 0.0, 1.0),
    ],
)
def test_a_matrixs_quaternion_is_scipys_whichever_entry_is_largest(
    q: geometry.Quaternion,
) -> None:
    matrix = geometry.matrix_from_quaternion(q)
    assert_same_quaternion(geometry.quaternion_from_matrix(matrix), scipy_rotation(q))


@given(quaternions)
def test_a_matrixs_quaternion_is_scipys(q: geometry.Quaternion) -> None:
    matrix = tuple(map(tuple, scipy_rotation(q).as_matrix()))
    assert_same_quaternion(geometry.quaternion_from_matrix(matrix), Rotation.from_matrix(matrix))


@given(quaternions, quaternions)
def test_multiplying_quaternions_composes_as_scipy_does(
    a: geometry.Quaternion, b: geometry.Quaternion
) -> None:
    assert_same_quaternion(geometry.multiply(a, b), scipy_rotation(a) * scipy_rotation(b))


@given(quaternions)
def test_a_quaternions_conjugate_is_its_inverse(q: geometry.Quaternion) -> None:
    assert_same_quaternion(geometry.conjugate(q), scipy_rotation(q).inv())


@given(quaternions, vectors)
def test_rotating_a_vector_is_scipys_apply(q: geometry.Quaternion, v: geometry.Vector) -> None:
    np.testing.assert_allclose(geometry.rotate(q, v), scipy_rotation(q).apply(v), atol=ATOL)


@given(directions, angle)
def test_a_turn_about_an_axis_is_scipys_rotation_vector(axis: geometry.Vector, turn: float) -> None:
    expected = Rotation.from_rotvec(np.asarray(axis) / np.linalg.norm(axis) * turn)
    assert_same_quaternion(geometry.about_axis(axis, turn), expected)


# -- poses


@given(poses, poses)
def test_composed_poses_are_the_product_of_their_matrices(
    a: geometry.Pose, b: geometry.Pose
) -> None:
    composed = geometry.compose(a, b)
    np.testing.assert_allclose(homogeneous(composed), homogeneous(a) @ homogeneous(b), atol=1e-9)


@given(poses)
def test_a_poses_inverse_is_its_matrixs(pose: geometry.Pose) -> None:
    np.testing.assert_allclose(
        homogeneous(geometry.inverse(pose)), np.linalg.inv(homogeneous(pose)), atol=1e-9
    )


# -- matrices and vectors


@given(quaternions, quaternions, vectors)
def test_matrix_products_transposes_and_turned_tensors_are_numpys(
    a: geometry.Quaternion, b: geometry.Quaternion, v: geometry.Vector
) -> None:
    ra, rb = geometry.matrix_from_quaternion(a), geometry.matrix_from_quaternion(b)
    na, nb = np.asarray(ra), np.asarray(rb)
    np.testing.assert_allclose(geometry.matmul(ra, rb), na @ nb, atol=ATOL)
    np.testing.assert_allclose(geometry.transpose(ra), na.T, atol=0)
    np.testing.assert_allclose(geometry.apply(ra, v), na @ v, atol=ATOL)
    tensor = ((3.0, 0.2, -0.1), (0.2, 2.0, 0.3), (-0.1, 0.3, 1.0))
    np.testing.assert_allclose(geometry.turned(ra, tensor), na @ tensor @ na.T, atol=ATOL)


def _point_inertia(masses: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The inertia of point masses about the origin: Σ m (|r|² E - r rᵀ)."""
    return sum(
        m * (np.dot(r, r) * np.eye(3) - np.outer(r, r)) for m, r in zip(masses, points, strict=True)
    )


@given(st.integers(0, 2**32 - 1), positions)
def test_an_inertia_shifted_off_the_centre_of_mass_is_the_bodys_about_that_point(
    seed: int, point: geometry.Vector
) -> None:
    rng = np.random.default_rng(seed)
    masses, points = rng.uniform(0.1, 2.0, 5), rng.uniform(-1.0, 1.0, (5, 3))
    centre = masses @ points / masses.sum()
    about_centre = _point_inertia(masses, points - centre)
    offset = tuple(centre - np.asarray(point))
    expected = _point_inertia(masses, points - np.asarray(point))
    shifted = geometry.shifted(tuple(map(tuple, about_centre)), float(masses.sum()), offset)
    np.testing.assert_allclose(shifted, expected, atol=1e-9)


@given(vectors, directions)
def test_dot_cross_and_unit_are_numpys(a: geometry.Vector, b: geometry.Vector) -> None:
    assert math.isclose(geometry.dot(a, b), float(np.dot(a, b)), abs_tol=ATOL)
    np.testing.assert_allclose(geometry.cross(a, b), np.cross(a, b), atol=ATOL)
    np.testing.assert_allclose(geometry.unit(b), np.asarray(b) / np.linalg.norm(b), atol=ATOL)


def test_a_zero_vector_axis_or_quaternion_is_no_direction() -> None:
    with pytest.raises(Degenerate):
        geometry.unit((0.0, 0.0, 0.0))
    with pytest.raises(Degenerate):
        geometry.about_axis((0.0, 0.0, 0.0), 1.0)
    with pytest.raises(Degenerate):
        geometry.normalized((0.0, 0.0, 0.0, 0.0))
