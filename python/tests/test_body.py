"""Bodies, primitives, transformations, Booleans, numpy round trips, pickling."""

import math
import pickle

import numpy as np
import pytest

import hedra
from conftest import L_OUTLINE


def test_version():
    assert isinstance(hedra.__version__, str) and hedra.__version__.count(".") == 2


def test_prism_measures_against_hand_values():
    b = hedra.prism(L_OUTLINE, z=(0, 2))
    assert isinstance(b, hedra.Body)
    # L of area 4 + 2 = 6 (3 × 1 bar plus 1 × 2 leg) × height 2; area 2·6 + perimeter 14 × 2.
    assert b.volume == 12.0
    assert b.area == 40.0
    assert b.is_convex is False
    assert b.vertices.shape == (12, 3) and b.vertices.dtype == np.float64
    assert b.matrix.shape == (4, 8) and b.matrix.dtype == np.float64
    assert len(b.faces) == 8


def test_box_matrix_is_the_course_matrix():
    b = hedra.box((-1, -1, -1), (1, 1, 1))
    # Faces x=min, x=max, y=min, y=max, z=min, z=max with inner normals, d = 1.
    expected = np.array([[1, -1, 0, 0, 0, 0], [0, 0, 1, -1, 0, 0], [0, 0, 0, 0, 1, -1],
                         [1, 1, 1, 1, 1, 1]], dtype=float)
    np.testing.assert_allclose(b.matrix, expected, atol=1e-15)
    assert b.is_convex and b.volume == 8.0 and b.area == 24.0
    # Every vertex satisfies every inner half-space: (x, y, z, 1) · V >= 0.
    h = np.hstack([b.vertices, np.ones((8, 1))]) @ b.matrix
    assert (h >= -1e-15).all()


def test_numpy_round_trip_and_copies():
    b = hedra.prism(L_OUTLINE, z=(0, 2))
    v = b.vertices
    v[0, 0] = 99.0  # a copy: the body does not change
    assert b.vertices[0, 0] != 99.0
    c = hedra.Body(b.vertices, b.faces)
    assert np.array_equal(c.vertices, b.vertices)
    assert [list(f) for f in c.faces] == [list(f) for f in b.faces]
    assert c.volume == b.volume
    # Plain lists, float32 vertices and int64 faces are accepted too.
    d = hedra.Body(b.vertices.astype(np.float32).tolist(), [np.asarray(f, dtype=np.int64) for f in b.faces])
    assert d.volume == 12.0


def test_faces_with_holes_round_trip():
    plate = hedra.prism([[0, 0], [6, 0], [6, 4], [0, 4]], z=(0, 1),
                        holes=[[[1, 1], [2, 1], [2, 3], [1, 3]]])
    assert plate.volume == 24.0 - 2.0
    holed = [f for f in plate.faces if isinstance(f, list)]
    assert len(holed) == 2 and all(len(f) == 2 for f in holed)
    again = hedra.Body(plate.vertices, plate.faces)
    assert again.volume == plate.volume and again.face_count == plate.face_count


def test_from_triangles_merges_coplanar_triangles():
    b = hedra.box((0, 0, 0), (2, 3, 4))
    tris = b.triangles
    assert tris.shape == (12, 3)
    c = hedra.Body.from_triangles(b.vertices, tris)
    assert c.face_count == 6 and c.volume == 24.0


def test_transformations_against_numpy():
    b = hedra.prism(L_OUTLINE, z=(0, 2))
    t = b.translated((1, 2, 3))
    assert np.array_equal(t.vertices, b.vertices + np.array([1, 2, 3]))
    r = b.rotated((0, 0, 1), 90, about=(1, 0, 0))
    x, y = b.vertices[:, 0] - 1, b.vertices[:, 1]
    expected = np.column_stack([1 - y, x, b.vertices[:, 2]])
    np.testing.assert_allclose(r.vertices, expected, atol=1e-14)
    assert math.isclose(r.volume, 12.0, rel_tol=1e-14)
    s = b.scaled((2, 1, 0.5))
    np.testing.assert_array_equal(s.vertices, b.vertices * np.array([2, 1, 0.5]))
    assert s.volume == 12.0
    m = b.scaled(-1)  # point reflection: faces flipped so they still face outwards
    assert m.volume == 12.0
    # Row-vector convention: translation in the last row.
    T = np.eye(4)
    T[3, :3] = (5, 6, 7)
    assert np.array_equal(b.transformed(T).vertices, b.vertices + np.array([5, 6, 7]))


def test_curved_primitives_against_analytic_values():
    r, h = 2.0, 3.0
    c = hedra.cylinder(r, z=(0, h), tolerance=0.01)
    n = c.face_count - 2
    assert r * (1 - math.cos(math.pi / n)) <= 0.01  # chordal error within the tolerance
    assert math.isclose(c.volume, 0.5 * n * r * r * math.sin(2 * math.pi / n) * h, rel_tol=1e-12)
    assert c.is_smooth and c.is_convex
    s = hedra.sphere((1, 2, 3), 1.5, tolerance=0.01)
    # Within 2^-23 of the radius: snapped so that every quadrilateral is exactly planar.
    np.testing.assert_allclose(np.linalg.norm(s.vertices - [1, 2, 3], axis=1), 1.5, rtol=2.0**-23)
    assert s.volume < 4 / 3 * math.pi * 1.5 ** 3
    k = hedra.cone(1.0, z=(0, 2), tolerance=0.02)
    assert k.vertex_count == k.face_count  # n base vertices + apex; n sides + base
    assert k.classify((0, 0, 1)) == "inside" and k.classify((0, 0, 2)) == "boundary"
    assert k.classify((0, 0, 2.5)) == "outside"


def test_booleans_against_inclusion_exclusion():
    a = hedra.box((0, 0, 0), (2, 2, 2))
    b = hedra.box((1, 1, 1), (3, 3, 3))
    assert hedra.unite(a, b).volume == 8 + 8 - 1
    assert hedra.subtract(a, b).volume == 7
    assert hedra.intersect(a, b).volume == 1
    assert hedra.subtract(a, hedra.box((-1, -1, -1), (4, 4, 4))) is None
    assert hedra.intersect(a, hedra.box((5, 5, 5), (6, 6, 6))) is None


def test_boolean_results_keep_their_exact_solid():
    # Rotated operands: the results' rounded volumes add up only within rounding, their exact
    # solids (and the operands' exact images) exactly.
    plate = hedra.box((-2, -2, 0), (2, 2, 1)).rotated((1, 2, 3), 37)
    drill = hedra.cylinder(0.5, z=(-1, 2), tolerance=0.01).rotated((1, 2, 3), 37)
    drilled, plug = hedra.subtract(plate, drill), hedra.intersect(plate, drill)
    assert drilled.has_exact_solid and plug.has_exact_solid
    # A moved box, and a moved sphere (its quadrilaterals exactly planar), are the exact images
    # of their corners; a box in place, and a moved body whose quadrilaterals are planar only
    # within rounding (the moved box's rounded corners), keep no exact solid.
    assert plate.has_exact_solid
    assert hedra.sphere((0, 0, 0), 1).rotated((1, 2, 3), 37).has_exact_solid
    assert not hedra.box((0, 0, 0), (1, 1, 1)).has_exact_solid
    assert not hedra.Body(plate.vertices, plate.faces).rotated((3, 1, 2), 20).has_exact_solid
    assert hedra.exact_volume_sign([(1, drilled), (1, plug), (-1, plate)]) == 0
    assert hedra.exact_volume_sign([(1, drilled)]) == 1
    rounded = hedra.Body(drilled.vertices, drilled.faces)
    assert not rounded.has_exact_solid
    assert hedra.exact_volume_sign([(1, rounded), (1, plug), (-1, plate)]) != 0


def test_frustum_keeps_its_exact_top():
    # The top a third of the way to the apex: its corners are not doubles. The frustum's exact
    # solid is the pyramid cut at z1 by a Boolean (CGAL's corefinement), exactly, also after a
    # pickle; its rounding alone is not.
    star = [(2 * math.cos(math.pi * i / 5) * (1 if i % 2 == 0 else 0.4),
             2 * math.sin(math.pi * i / 5) * (1 if i % 2 == 0 else 0.4)) for i in range(10)]
    f = hedra.frustum(star, 0, (0.3, 0.2, 3), 1)
    assert f.has_exact_solid and f.face_count == 12
    cut = hedra.intersect(hedra.pyramid(star, 0, (0.3, 0.2, 3)), hedra.box((-5, -5, -1), (5, 5, 1)))
    assert hedra.exact_volume_sign([(1, f), (-1, cut)]) == 0
    assert hedra.exact_volume_sign([(1, pickle.loads(pickle.dumps(f))), (-1, cut)]) == 0
    assert hedra.exact_volume_sign([(1, hedra.Body(f.vertices, f.faces)), (-1, cut)]) != 0
    # Half way with power-of-two coordinates: every top corner is a double, the body exact.
    assert not hedra.frustum([(0, 0), (2, 0), (2, 2), (0, 2)], 0, (1, 1, 2), 1).has_exact_solid


def test_invalid_bodies_raise_invalid_input():
    with pytest.raises(hedra.InvalidInput, match=r"^face 3 refers to vertex 7, out of range \(the body has 4 vertices\)$"):
        hedra.Body([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 7]])
    with pytest.raises(ValueError):  # InvalidInput is a ValueError
        hedra.box((0, 0, 0), (0, 1, 1))
    with pytest.raises(hedra.InvalidInput, match="vertices"):
        hedra.Body([[0, 0], [1, 1]], [[0, 1]])


def test_pickle_round_trips_bit_for_bit():
    bodies = [hedra.prism(L_OUTLINE, z=(0, 2)).rotated((1, 2, 3), 37.5, about=(0.1, 0.2, 0.3)),
              hedra.sphere((0.1, 0.2, 0.3), 1 / 3, tolerance=1e-3),
              hedra.prism([[0, 0], [6, 0], [6, 4], [0, 4]], z=(0, 1), holes=[[[1, 1], [2, 1], [2, 3], [1, 3]]])]
    # The exact solid travels too: a rotated Boolean's volume identity stays exact.
    plate = hedra.box((-2, -2, 0), (2, 2, 1)).rotated((1, 2, 3), 37)
    drill = hedra.cylinder(0.5, z=(-1, 2), tolerance=0.01).rotated((1, 2, 3), 37)
    drilled = pickle.loads(pickle.dumps(hedra.subtract(plate, drill)))
    assert drilled.has_exact_solid
    assert hedra.exact_volume_sign([(1, drilled), (1, hedra.intersect(plate, drill)), (-1, plate)]) == 0
    assert pickle.loads(pickle.dumps(plate)).has_exact_solid  # a pending image
    for b in bodies:
        c = pickle.loads(pickle.dumps(b))
        assert c.vertices.tobytes() == b.vertices.tobytes()
        assert c.matrix.tobytes() == b.matrix.tobytes()
        assert c.volume == b.volume and c.face_count == b.face_count
