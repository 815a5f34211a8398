"""The skill library without the simulator: loading, TSR specs, actuation paths."""

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.execution.skills.library import Half, actuation_path, evaluate, load_skills, object_kind, skill_name
from wecook_core.execution.skills.tsr import contains
from wecook_core.model import VERBS, Category


@pytest.fixture(scope="module")
def library():
    return load_skills()


def test_every_verb_has_engage_and_actuate(library):
    for verb in (*VERBS, "transfer_tipping", "transfer_by_hand"):
        steps = library.skills[verb].steps
        assert [s.primitive for s in steps][:2] == ["engage", "actuate"], verb


def test_tsr_spec_orientation_is_a_right_handed_rotation(library):
    for specs in library.grasps.values():
        for spec in specs:
            R = spec.rotation()
            assert np.allclose(R.T @ R, np.eye(3)) and np.isclose(np.linalg.det(R), 1.0)
    top_down = library.grasps["tool"][0].rotation()
    assert np.allclose(top_down[:, 2], [0, 0, -1])  # approach straight down


def test_grasp_tsr_puts_the_gripper_on_the_handle(library):
    spec = library.grasps["tool"][0]
    frame = np.eye(4)
    frame[:3, 3] = [0.2, 0.1, 0.0125]
    region = spec.tsr(frame, {"f": Half(0.1, 0.015, 0.0125)})
    pose = region.T0_w @ region.Tw_e
    assert np.allclose(pose[:3, 3], [0.2 - 0.055, 0.1, 0.0125 + 0.0045])
    assert contains(region, pose)


def test_expressions_use_half_extents():
    assert evaluate("0.5*t.hx + i.hz", {"t": Half(0.1, 0, 0), "i": Half(0, 0, 0.02)}) == pytest.approx(0.07)
    assert evaluate(0.3, {}) == 0.3


def test_saw_descends_by_depth_and_strokes_along_the_axis():
    E = np.eye(4)
    path = actuation_path("saw", {"down": 0.03, "depth": 0.02, "strokes": 3, "amplitude": 0.03}, E, np.eye(3))
    z = np.array([w.pose[2, 3] for w in path])
    x = np.array([w.pose[0, 3] for w in path])
    assert z.min() == pytest.approx(-0.05)
    assert x.max() == pytest.approx(0.03) and x.min() == pytest.approx(-0.03)
    assert np.allclose(path[-1].pose, E)  # back where it started


def test_circle_stays_on_its_radius_and_tilt_turns_by_its_angle():
    E = np.eye(4)
    path = actuation_path("circle", {"down": 0.05, "radius": 0.03, "turns": 1}, E, np.eye(3))
    centre = np.array([0.0, 0.0])
    ring = [w.pose[:2, 3] for w in path[1:-2]]
    assert all(np.linalg.norm(p - centre) == pytest.approx(0.03) for p in ring)
    tilt = actuation_path("tilt", {"angle": 90, "hold": 1.0}, E, np.eye(3))
    assert tilt[0].hold == 1.0
    assert np.allclose(tilt[0].pose[:3, 2], [-1, 0, 0], atol=1e-9)  # the top tips away from the arm (-x)


def test_skill_choice_and_object_kinds():
    assert skill_name("transfer", None, None) == "transfer_by_hand"
    assert skill_name("transfer", "bowl", Category.CONTAINER) == "transfer_tipping"
    assert skill_name("transfer", "spoon", Category.TOOL) == "transfer"
    assert object_kind(Category.CONTAINER, (0.3, 0.2, 0.02), False) == "flat_container"
    assert object_kind(Category.INGREDIENT, (0.05, 0.05, 0.14), False) == "tall"


def test_bad_library_names_the_place(tmp_path, library):
    text = (load_skills.__globals__["SKILLS_PATH"]).read_text().replace("motion: saw", "motion: chop")
    bad = tmp_path / "skills.yaml"
    bad.write_text(text)
    with pytest.raises(InputError, match=r"verbs.cut.steps\[1\].motion"):
        load_skills(bad)


def test_contact_pairs_are_read_and_checked(library, tmp_path):
    scoop = library.skills["transfer"].steps[1]
    assert scoop.contacts == (("tool", "source"), ("tool", "ingredient")) and scoop.contact == ("tool", "source")
    assert library.skills["cut"].steps[1].contacts == (("tool", "ingredient"),)
    text = (load_skills.__globals__["SKILLS_PATH"]).read_text().replace("[[tool, source], [tool, ingredient]]",
                                                                       "[[tool, source], [tool, lid]]")
    bad = tmp_path / "skills.yaml"
    bad.write_text(text)
    with pytest.raises(InputError, match=r"verbs.transfer.steps\[1\].contact\[1\].*'lid'"):
        load_skills(bad)


@pytest.mark.parametrize(("old", "new", "place"), [
    ("crowded: {x: [-0.04, 0.04], yaw: [-45, 45]}}", "crowded: {x: [-0.01, 0.04]}}",
     r"grasps.tool\[0\].crowded.x: a crowded table's bounds must contain the bounds"),
    ("crowded: {x: [-0.04, 0.04], yaw: [-45, 45]}}", "crowded: {spin: [-1, 1]}}",
     r"grasps.tool\[0\].crowded.spin: unknown bound"),
    ("crowded: {x: [-0.04, 0.04], yaw: [-45, 45]}}", "crowded: [-0.04, 0.04]}",
     r"grasps.tool\[0\].crowded: expected a mapping"),
    ("bounds: {x: [-0.01, 0.01], yaw: [-100, 100]}}}", "bounds: {yaw: [-100, 100]}, crowded: {yaw: [-180, 180]}}}",
     r"verbs.cut.steps\[0\].tsr.crowded: only a grasp"),
])
def test_bad_bounds_for_a_crowded_table_name_the_place(tmp_path, old, new, place):
    """Only a grasp has bounds for a crowded table, each containing its own bound."""
    text = (load_skills.__globals__["SKILLS_PATH"]).read_text()
    assert old in text
    bad = tmp_path / "skills.yaml"
    bad.write_text(text.replace(old, new, 1))
    with pytest.raises(InputError, match=place):
        load_skills(bad)
