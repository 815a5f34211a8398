"""R3a: a big object's motion is judged against a fraction of the view, not only against its own size."""

from __future__ import annotations

from handmade_scenes import observations, still

from wecook_core.model import Category
from wecook_core.perception.params import Params
from wecook_core.perception.repairs.unseen import unseen_holds


def _swung_bowl():
    """A big bowl (160 x 120 px, 200 px diagonal, in a 640 x 480 view) swung 3 px a frame for a second over a
    pan, no hand seen: over half a second it moves 45 px, less than a quarter of its own size (50 px) but more
    than a twentieth of the view's diagonal (40 px)."""
    bowl = [still(0, 20, (100, 100, 260, 220)), (20, 50, (100, 100, 260, 220), (190, 100, 350, 220)),
            still(50, 70, (190, 100, 350, 220))]
    return observations(70, {"bowl": (Category.CONTAINER, bowl),
                             "pan": (Category.CONTAINER, [still(0, 70, (300, 250, 500, 420))])}, {})


def test_a_big_bowl_swung_by_less_than_a_quarter_of_its_size_is_moving():
    holds = unseen_holds(_swung_bowl(), Params())
    assert [h.obj for h in holds] == ["bowl"]
    assert holds[0].start <= 25 and holds[0].end >= 45


def test_without_the_view_cap_the_swung_bowl_is_still():
    assert unseen_holds(_swung_bowl(), Params(moving_cap_fraction=1.0)) == ()
