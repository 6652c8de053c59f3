"""The virtual-finger metric (docs/method.md, section 5) on analytic cases and random forces."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from graspframe.common.contacts import Contact
from graspframe.common.errors import GraspframeError
from graspframe.common.transforms import make_T, transform_points
from graspframe.metrics import (
    NoContactsError,
    RealFingerContacts,
    VirtualFinger,
    best_partition,
    cohesive_index,
    compare,
    effective_cohesion,
    force_coupling,
    group_by_real_finger,
    pair_cohesion,
    virtual_finger,
    virtual_fingers_from_contacts,
    virtual_fingers_from_real_fingers,
)

X, Y, Z = np.eye(3)
TOL = 1e-12  # closed-form numbers computed in double precision


def finger(name, positions, normals, force=1.0):
    """A real finger whose contact forces push along -normal (into the object) [N]."""
    normals = np.atleast_2d(np.asarray(normals, dtype=float))
    normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    return RealFingerContacts(name, np.atleast_2d(positions), normals, -force * normals)


def finger_pushing(name, direction, position=(0.0, 0.0, 0.0)):
    """One contact whose force is along `direction` (normal opposite to it)."""
    return finger(name, [position], [-np.asarray(direction, dtype=float)])


# ----------------------------------------------------------------------------- cohesion


def test_force_coupling_and_pair_cohesion_of_basic_directions():
    assert force_coupling(X, 3 * X) == pytest.approx(1.0, abs=TOL)
    assert force_coupling(X, Y) == pytest.approx(0.0, abs=TOL)
    assert force_coupling(X, -2 * X) == pytest.approx(-1.0, abs=TOL)
    assert pair_cohesion(X, 5 * X) == pytest.approx(1.0, abs=TOL)
    assert pair_cohesion(X, -X) == 0.0


def test_a_perpendicular_pair_gives_one_half_not_zero():
    # The method's prose says "any perpendicular pair gives 0", but its formula
    # m = (1 + cos 90deg) / 2 = 0.5; only an opposed pair (cos = -1) gives 0. The formula
    # is what is implemented; this test pins what it gives.
    assert pair_cohesion(X, Y) == pytest.approx(0.5, abs=TOL)
    assert cohesive_index([X, Y]) == pytest.approx(0.5, abs=TOL)
    assert cohesive_index([X, -X]) == 0.0
    assert cohesive_index([X, X, -X]) == 0.0  # one opposed pair zeroes the geometric mean


def test_a_perpendicular_pair_can_sit_inside_the_chosen_virtual_finger():
    # a, b perpendicular, c on their bisector: m_ab = 0.5, m_ac = m_bc = (1 + cos45)/2.
    # One VF: C = (0.5 * 0.853553^2)^(1/3) = 0.714185 beats {a,c}{b}: sqrt(0.853553/2)
    # = 0.653281 and {a}{b}{c}: (1/6)^(1/3) = 0.550321. So the pair's C is not 0.
    m = (1 + math.cos(math.pi / 4)) / 2
    forces = {"a": X, "b": Y, "c": X + Y}
    partition = best_partition(forces)
    assert partition.blocks == (("a", "b", "c"),)
    assert partition.c_eff == pytest.approx((0.5 * m * m) ** (1 / 3), abs=TOL)
    assert partition.c_eff == pytest.approx(0.714185, abs=1e-6)


def test_single_real_finger_has_cohesion_one():
    assert cohesive_index([[0.3, -2.0, 1.0]]) == 1.0
    partition = best_partition({"thumb": [0.0, 0.0, -4.0]})
    assert partition.blocks == (("thumb",),)
    assert partition.cohesive_indices == (1.0,)
    assert partition.c_eff == 1.0


def test_all_parallel_forces_make_one_virtual_finger_with_cohesion_one():
    forces = {name: k * np.array([0.2, -0.5, 0.7]) for k, name in enumerate("abcde", 1)}
    partition = best_partition(forces)
    assert partition.blocks == (("a", "b", "c", "d", "e"),)
    assert partition.cohesive_indices[0] == pytest.approx(1.0, abs=TOL)
    assert partition.c_eff == pytest.approx(1.0, abs=TOL)


def test_two_opposed_groups_make_two_virtual_fingers():
    # thumb against three fingers, the fingers' forces not quite parallel.
    forces = {
        "thumb": [0.0, 3.0, 0.0],
        "index": [0.0, -1.0, 0.05],
        "middle": [0.0, -1.0, 0.0],
        "ring": [0.02, -0.8, -0.05],
    }
    partition = best_partition(forces)
    assert partition.blocks == (("index", "middle", "ring"), ("thumb",))
    assert partition.cohesive_indices[1] == 1.0
    assert partition.cohesive_indices[0] > 0.99


def test_effective_cohesion_by_hand_on_three_fingers():
    # a = x, b = 2x (parallel to a), c = y (perpendicular to both):
    # m_ab = 1, m_ac = m_bc = 0.5. The five partitions:
    #   {a,b,c}:     C = (1 * 0.5 * 0.5)^(1/3) = 0.629961;  C_eff = 0.629961
    #   {a,b}{c}:    C = 1, 1;   C_eff = (1 * 1 / 2!)^(1/2)   = 0.707107  <- best
    #   {a,c}{b}:    C = 0.5, 1; C_eff = (0.5 / 2!)^(1/2)     = 0.5
    #   {b,c}{a}:    same                                      = 0.5
    #   {a}{b}{c}:   C_eff = (1 / 3!)^(1/3)                   = 0.550321
    forces = {"a": X, "b": 2 * X, "c": Y}
    assert cohesive_index(list(forces.values())) == pytest.approx(0.25 ** (1 / 3), abs=TOL)
    assert effective_cohesion([0.25 ** (1 / 3)]) == pytest.approx(0.629961, abs=1e-6)
    assert effective_cohesion([1.0, 1.0]) == pytest.approx(0.707107, abs=1e-6)
    assert effective_cohesion([0.5, 1.0]) == pytest.approx(0.5, abs=TOL)
    assert effective_cohesion([1.0, 1.0, 1.0]) == pytest.approx(0.550321, abs=1e-6)
    partition = best_partition(forces)
    assert partition.blocks == (("a", "b"), ("c",))
    assert partition.c_eff == pytest.approx(math.sqrt(0.5), abs=TOL)


def test_ties_go_to_fewest_virtual_fingers_then_lexicographic():
    # Two forces at angle arccos(sqrt(2) - 1) = 65.5 deg: one VF has C_eff = m =
    # (1 + sqrt(2) - 1)/2 = sqrt(0.5), two VFs have (1/2!)^(1/2) = sqrt(0.5): a tie, and
    # the fewest virtual fingers win.
    angle = math.acos(math.sqrt(2) - 1)
    forces = {"b": X, "a": [math.cos(angle), math.sin(angle), 0.0]}
    partition = best_partition(forces)
    assert partition.blocks == (("a", "b"),)
    assert partition.c_eff == pytest.approx(math.sqrt(0.5), abs=TOL)
    # a and c 150 deg apart, b on their bisector (75 deg from each): {a,b}{c} and {a}{b,c}
    # tie at sqrt(m/2), m = (1 + cos 75deg)/2 -> 0.561 (all singletons 0.550, one VF 0.298).
    # Sorted blocks: (("a",), ("b", "c")) < (("a", "b"), ("c",)) since ("a",) < ("a", "b").
    a, b, c = np.radians([0.0, 75.0, 150.0])
    forces = {n: [math.cos(t), math.sin(t), 0.0] for n, t in (("c", c), ("b", b), ("a", a))}
    partition = best_partition(forces)
    assert partition.blocks == (("a",), ("b", "c"))
    m = (1 + math.cos(math.radians(75.0))) / 2
    assert partition.c_eff == pytest.approx(math.sqrt(m / 2), abs=TOL)


# ----------------------------------------------------------------------------- brute force


def all_partitions(items):
    """Every set partition of `items` (written independently of more_itertools)."""
    if not items:
        yield []
        return
    first, rest = items[0], items[1:]
    for partition in all_partitions(rest):
        yield [[first], *partition]
        for i in range(len(partition)):
            yield [*partition[:i], [first, *partition[i]], *partition[i + 1 :]]


def c_eff_by_definition(forces, blocks):
    """C_eff straight from the method's formula (docs/method.md, section 5): cosines,
    m_ij, geometric means, 1/N!, N-th root."""
    cohesions = []
    for block in blocks:
        pairs = [(i, j) for k, i in enumerate(block) for j in block[k + 1 :]]
        product = 1.0
        for i, j in pairs:
            cos = forces[i] @ forces[j] / (np.linalg.norm(forces[i]) * np.linalg.norm(forces[j]))
            product *= (1 + min(1.0, max(-1.0, cos))) / 2
        cohesions.append(product ** (1 / len(pairs)) if pairs else 1.0)
    n = len(blocks)
    return (math.prod(cohesions) / math.factorial(n)) ** (1 / n)


def test_own_partition_generator_counts_bell_numbers():
    bell = [1, 1, 2, 5, 15, 52, 203]
    for n in range(7):
        assert sum(1 for _ in all_partitions(list(range(n)))) == bell[n]


coordinate = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
force_vector = st.tuples(coordinate, coordinate, coordinate).filter(
    lambda v: np.linalg.norm(v) > 1e-3
)
force_sets = st.lists(force_vector, min_size=1, max_size=6)


@settings(derandomize=True, max_examples=150, deadline=None)
@given(force_sets)
def test_chosen_partition_is_the_maximum_over_all_partitions(vectors):
    forces = {f"r{i}": np.array(v) for i, v in enumerate(vectors)}
    names = sorted(forces)
    best_by_brute_force = max(
        c_eff_by_definition(forces, blocks) for blocks in all_partitions(names)
    )
    partition = best_partition(forces)
    assert partition.c_eff == pytest.approx(best_by_brute_force, abs=1e-9)
    assert c_eff_by_definition(forces, partition.blocks) == pytest.approx(partition.c_eff, abs=1e-9)
    assert sorted(n for block in partition.blocks for n in block) == names


@settings(derandomize=True, max_examples=60, deadline=None)
@given(force_sets, st.integers(0, 2**32 - 1))
def test_partition_does_not_depend_on_order_or_on_the_frame(vectors, seed):
    forces = {f"r{i}": np.array(v) for i, v in enumerate(vectors)}
    partition = best_partition(forces)
    reversed_forces = dict(reversed(list(forces.items())))
    assert best_partition(reversed_forces).blocks == partition.blocks
    R = Rotation.random(random_state=seed).as_matrix()
    rotated = best_partition({name: R @ f for name, f in forces.items()})
    assert rotated.blocks == partition.blocks
    assert rotated.c_eff == pytest.approx(partition.c_eff, abs=1e-9)


# ----------------------------------------------------------------------------- poses


def test_virtual_finger_pose_averages_every_contact():
    index = finger("index", [[0.0, 0.0, 0.0], [0.02, 0.0, 0.0]], [Z, Z])
    middle = finger("middle", [[0.04, 0.03, 0.0]], [Y + Z])
    vf = virtual_finger([middle, index])
    assert vf.members == ("index", "middle")
    assert vf.contact_count == 3  # T(V_k): a mean over 3 contacts, not over 2 fingers
    np.testing.assert_allclose(vf.position, [0.02, 0.01, 0.0], atol=TOL)
    mean_normal = (2 * Z + (Y + Z) / math.sqrt(2)) / 3
    np.testing.assert_allclose(vf.normal, mean_normal / np.linalg.norm(mean_normal), atol=TOL)
    assert vf.cohesive_index == pytest.approx(pair_cohesion(index.force, middle.force), abs=TOL)


def test_contacts_become_virtual_fingers_in_the_object_frame():
    T_world_object = make_T(Rotation.from_euler("z", 90, degrees=True).as_matrix(), [1, 2, 0.5])
    p_object = np.array([[0.05, 0.0, 0.0], [0.05, 0.01, 0.0], [-0.05, 0.0, 0.0]])
    n_object = np.array([X, X, -X])
    owners = ["index", "middle", "thumb"]
    contacts = [
        Contact(
            link=f"{owner}_tip",
            real_finger=owner,
            p=transform_points(T_world_object, p),
            n=T_world_object[:3, :3] @ n,
            f=T_world_object[:3, :3] @ (-2.0 * n),
        )
        for owner, p, n in zip(owners, p_object, n_object, strict=True)
    ]
    fingers = group_by_real_finger(contacts, T_world_object)
    assert [f.name for f in fingers] == ["index", "middle", "thumb"]
    grasp = virtual_fingers_from_contacts(contacts, T_world_object)
    assert grasp.partition.blocks == (("index", "middle"), ("thumb",))
    assert grasp.touching_real_fingers == ("index", "middle", "thumb")
    fingers_vf, thumb_vf = grasp.virtual_fingers
    np.testing.assert_allclose(fingers_vf.position, [0.05, 0.005, 0.0], atol=1e-12)
    np.testing.assert_allclose(fingers_vf.normal, X, atol=1e-12)
    np.testing.assert_allclose(thumb_vf.normal, -X, atol=1e-12)
    assert grasp.c_eff == pytest.approx(math.sqrt(0.5), abs=TOL)
    json.dumps(grasp.to_dict())
    # The same contacts given in the object frame need no object pose and give the same.
    in_object = [c.in_object_frame(T_world_object) for c in contacts]
    assert all(c.frame == "object" for c in in_object)
    same = virtual_fingers_from_contacts(in_object)
    np.testing.assert_allclose(same.virtual_fingers[0].position, fingers_vf.position, atol=1e-12)


def test_contact_frames_are_checked():
    world = Contact("tip", "index", np.zeros(3), X, -X)
    with pytest.raises(GraspframeError, match="need T_world_object"):
        group_by_real_finger([world])
    with pytest.raises(GraspframeError, match="not the world frame"):
        world.in_object_frame(np.eye(4)).in_object_frame(np.eye(4))
    with pytest.raises(GraspframeError, match=r"'camera' is not one of \('world', 'object'\)"):
        Contact("tip", "index", np.zeros(3), X, -X, frame="camera")


def test_real_fingers_without_force_are_ignored_and_reported():
    touching = finger_pushing("index", X)
    limp = RealFingerContacts("ring", [[0.0, 0.0, 0.0]], [Z], [[0.0, 0.0, 0.0]])
    weak = RealFingerContacts("pinky", [[0.0, 0.0, 0.0]], [Z], [[0.0, 0.0, -0.01]])
    grasp = virtual_fingers_from_real_fingers([touching, limp, weak], min_force=0.1)
    assert grasp.partition.blocks == (("index",),)
    assert grasp.ignored_real_fingers == ("pinky", "ring")
    with pytest.raises(NoContactsError, match="no real finger has a net force"):
        virtual_fingers_from_real_fingers([limp])


# ----------------------------------------------------------------------------- comparison


def grasp_of(fingers):
    return virtual_fingers_from_real_fingers(fingers)


def three_finger_grasp(offset=(0.0, 0.0, 0.0), R=None):
    """Thumb against index+middle, normals in the y-z plane; contacts shifted/rotated."""
    offset = np.asarray(offset)
    R = np.eye(3) if R is None else R
    specs = [
        ("thumb", [[0.0, -0.04, 0.01]], [-Y]),
        ("index", [[0.01, 0.04, 0.0]], [(Y + Z) / math.sqrt(2)]),
        ("middle", [[-0.01, 0.04, 0.0]], [(Y + Z) / math.sqrt(2)]),
    ]
    fingers = []
    for name, positions, normals in specs:
        base = finger(name, positions, normals)  # forces fixed by the unrotated normals
        rotated = np.asarray(normals) @ R.T
        fingers.append(RealFingerContacts(name, base.positions + offset, rotated, base.forces))
    return grasp_of(fingers)


def test_identical_contact_sets_give_zero_error():
    result = compare(three_finger_grasp(), three_finger_grasp())
    assert result.position_err_mm == pytest.approx(0.0, abs=1e-9)
    assert result.orientation_err_deg == pytest.approx(0.0, abs=1e-5)  # arccos near 1
    assert (result.robot_count, result.human_count) == (2, 2)
    assert not result.is_lower_bound
    assert result.note == ""
    assert result.unmatched_robot == result.unmatched_human == ()


def test_identical_grasps_on_differently_placed_objects_give_zero_error():
    # The same grasp in object coordinates, with the object at two world poses.
    def contacts_on(T_world_object):
        return [
            Contact("tip", "index", transform_points(T_world_object, [0.03, 0, 0]),
                    T_world_object[:3, :3] @ X, T_world_object[:3, :3] @ -X),
            Contact("tip", "thumb", transform_points(T_world_object, [-0.03, 0, 0]),
                    T_world_object[:3, :3] @ -X, T_world_object[:3, :3] @ X),
        ]  # fmt: skip

    T_a = make_T(p=[0.5, 0.0, 0.1])
    T_b = make_T(Rotation.from_euler("xyz", [10, 20, 30], degrees=True).as_matrix(), [0, 1, 0])
    robot = virtual_fingers_from_contacts(contacts_on(T_a), T_a)
    human = virtual_fingers_from_contacts(contacts_on(T_b), T_b)
    result = compare(robot, human)
    assert result.position_err_mm == pytest.approx(0.0, abs=1e-9)
    assert result.orientation_err_deg == pytest.approx(0.0, abs=1e-5)


def test_a_translation_of_all_robot_contacts_is_that_error_in_mm():
    human = three_finger_grasp()
    robot = three_finger_grasp(offset=(0.003, 0.0, -0.004))  # 5 mm
    result = compare(robot, human)
    assert result.position_err_mm == pytest.approx(5.0, abs=1e-9)
    assert result.orientation_err_deg == pytest.approx(0.0, abs=1e-5)
    for pair in result.pairs:
        assert pair.robot_index == pair.human_index  # same finger groups, same order
        assert pair.position_err_mm == pytest.approx(5.0, abs=1e-9)


def test_a_rotation_of_the_normals_is_that_angle_in_deg():
    human = three_finger_grasp()
    robot = three_finger_grasp(R=Rotation.from_euler("x", 25, degrees=True).as_matrix())
    result = compare(robot, human)
    assert result.position_err_mm == pytest.approx(0.0, abs=1e-9)
    # every normal lies in the y-z plane, perpendicular to the x axis: each turns by 25 deg
    assert result.orientation_err_deg == pytest.approx(25.0, abs=1e-9)


def test_different_counts_match_the_best_pairs_and_report_a_lower_bound():
    human = [
        VirtualFinger(("thumb",), [0.0, -0.04, 0.0], -Y, 1, 1.0),
        VirtualFinger(("index", "middle"), [0.0, 0.04, 0.0], Y, 2, 1.0),
    ]
    robot = [
        VirtualFinger(("f1",), [0.0, 0.041, 0.0], Y, 1, 1.0),  # 1 mm from human[1]
        VirtualFinger(("f2",), [0.03, 0.0, 0.0], X, 1, 1.0),  # extra, off to the side
        VirtualFinger(("f3",), [0.0, -0.038, 0.0], -Y, 1, 1.0),  # 2 mm from human[0]
    ]
    result = compare(robot, human, robot_real_fingers=["palm", "f1", "f2", "f3"])
    assert (result.robot_count, result.human_count) == (3, 2)
    assert [(p.robot_index, p.human_index) for p in result.pairs] == [(0, 1), (2, 0)]
    assert result.unmatched_robot == (1,)
    assert result.unmatched_human == ()
    assert result.position_err_mm == pytest.approx(1.5, abs=1e-9)
    assert result.orientation_err_deg == pytest.approx(0.0, abs=1e-9)
    assert result.is_lower_bound
    assert "lower bound" in result.note and "3" in result.note and "2" in result.note
    assert result.robot_untouched == ("palm",)
    assert result.human_untouched is None
    json.dumps(result.to_dict())


def test_weights_decide_between_position_and_orientation():
    human = [
        VirtualFinger(("a",), [0.0, 0.0, 0.0], Z, 1, 1.0),
        VirtualFinger(("b",), [0.01, 0.0, 0.0], X, 1, 1.0),
    ]
    # robot[0] sits on human[0] but points like human[1]; robot[1] the other way round.
    robot = [
        VirtualFinger(("a",), [0.0, 0.0, 0.0], X, 1, 1.0),
        VirtualFinger(("b",), [0.01, 0.0, 0.0], Z, 1, 1.0),
    ]
    by_position = compare(robot, human, weight_per_mm=1.0, weight_per_deg=0.0)
    by_angle = compare(robot, human, weight_per_mm=0.0, weight_per_deg=1.0)
    assert [(p.robot_index, p.human_index) for p in by_position.pairs] == [(0, 0), (1, 1)]
    assert [(p.robot_index, p.human_index) for p in by_angle.pairs] == [(0, 1), (1, 0)]
    assert by_position.orientation_err_deg == pytest.approx(90.0, abs=1e-9)
    assert by_angle.position_err_mm == pytest.approx(10.0, abs=1e-9)


def test_real_fingers_that_did_not_touch_are_listed_in_hand_order():
    robot = three_finger_grasp()
    human = three_finger_grasp()
    hand = ["palm", "thumb", "index", "middle", "ring", "pinky"]
    result = compare(robot, human, robot_real_fingers=hand, human_real_fingers=hand)
    assert result.robot_untouched == ("palm", "ring", "pinky")
    assert result.human_untouched == ("palm", "ring", "pinky")
    with pytest.raises(GraspframeError, match="not in robot_real_fingers"):
        compare(robot, human, robot_real_fingers=["palm", "thumb"])


# ----------------------------------------------------------------------------- bad inputs


def test_empty_sides_raise_no_contacts_error():
    T = np.eye(4)
    with pytest.raises(NoContactsError, match="no contacts"):
        virtual_fingers_from_contacts([], T)
    with pytest.raises(NoContactsError):
        best_partition({})
    with pytest.raises(NoContactsError, match="human side has no virtual fingers"):
        compare(three_finger_grasp(), [])
    assert issubclass(NoContactsError, GraspframeError)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"positions": [[0, 0]], "normals": [Z], "forces": [Z]}, r"shape \(N,3\)"),
        ({"positions": np.zeros((0, 3)), "normals": [Z], "forces": [Z]}, "N >= 1"),
        ({"positions": [[0, np.nan, 0]], "normals": [Z], "forces": [Z]}, "NaN or infinite"),
        ({"positions": [[0, 0, 0]], "normals": [2 * Z], "forces": [Z]}, "unit vectors"),
        ({"positions": [[0, 0, 0]], "normals": [Z, Z], "forces": [Z]}, "must have 1 rows"),
        ({"positions": [[0, 0, 0]], "normals": [Z], "forces": [["a", 0, 0]]}, "must be numbers"),
    ],
)
def test_bad_real_finger_arrays_raise(kwargs, message):
    with pytest.raises(GraspframeError, match=message):
        RealFingerContacts("index", **kwargs)


def test_bad_values_raise_graspframe_error():
    with pytest.raises(GraspframeError, match="zero force"):
        force_coupling(X, [0.0, 0.0, 0.0])
    with pytest.raises(GraspframeError, match="3-vector"):
        force_coupling(X, [1.0, 2.0])
    with pytest.raises(GraspframeError, match="zero force"):
        cohesive_index([X, np.zeros(3)])
    with pytest.raises(GraspframeError, match="zero force"):
        best_partition({"a": X, "b": np.zeros(3)})
    with pytest.raises(GraspframeError, match="at least one"):
        effective_cohesion([])
    with pytest.raises(GraspframeError, match=r"\[0, 1\]"):
        effective_cohesion([1.2])
    with pytest.raises(GraspframeError, match="non-empty string"):
        RealFingerContacts("", [[0, 0, 0]], [Z], [Z])
    with pytest.raises(GraspframeError, match="4x4"):
        group_by_real_finger([], np.eye(3))
    with pytest.raises(GraspframeError, match=r"expected graspframe\.common\.contacts\.Contact"):
        group_by_real_finger([("index", X)], np.eye(4))
    with pytest.raises(GraspframeError, match="distinct"):
        virtual_fingers_from_real_fingers([finger_pushing("a", X), finger_pushing("a", Y)])
    with pytest.raises(GraspframeError, match="min_force"):
        virtual_fingers_from_real_fingers([finger_pushing("a", X)], min_force=-1.0)
    with pytest.raises(GraspframeError, match="cancel out"):
        virtual_finger([finger("a", [[0, 0, 0], [0, 0, 0.01]], [Z, -Z])])
    with pytest.raises(GraspframeError, match="unit vectors"):
        VirtualFinger(("a",), [0, 0, 0], [0, 0, 3], 1, 1.0)
    grasp = three_finger_grasp()
    with pytest.raises(GraspframeError, match="weight_per_mm"):
        compare(grasp, grasp, weight_per_mm=-1.0)
    with pytest.raises(GraspframeError, match="both be 0"):
        compare(grasp, grasp, weight_per_mm=0.0, weight_per_deg=0.0)
    with pytest.raises(GraspframeError, match="not one string"):
        compare(grasp, grasp, robot_real_fingers="thumb")


def test_arrays_are_read_only_copies():
    positions = np.zeros((1, 3))
    f = RealFingerContacts("index", positions, [Z], [-Z])
    positions[0, 0] = 1.0
    assert f.positions[0, 0] == 0.0
    with pytest.raises(ValueError, match="read-only"):
        f.forces[0, 0] = 2.0
