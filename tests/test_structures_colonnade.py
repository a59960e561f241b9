"""The colonnade's geometry (issue 37, item 1): blocks, masses, inertias, bearings, head joints, the named front.

Every expected value here is computed independently of :mod:`pipeline.structures.colonnade`:
block extents and bearings from the layout rule (axis to axis, the end blocks to the capitals'
outer edges), masses from volumes, the column's inertia about its rim by quadrature over the
solid, the block's by sympy's integral over the box.
"""

import math

import pytest
import sympy as sp
from scipy.integrate import quad

from pipeline.errors import InputError
from pipeline.structures import Colonnade, named_colonnade, named_colonnades, rigid_column
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn, named_drum_column
from pipeline.structures.kinds import KINDS, example, kind_of
from pipeline.units import MARBLE_DENSITY

PAPER = Column(0.5, 0.4, 4.0)
CAPITAL = Capital(1.0, 0.4)  # c = 0.5 m
S = 2.0


def row(n, **kwargs):
    return Colonnade(DrumColumn.equal(PAPER, 3, CAPITAL), n, S, 0.5, **kwargs)


def test_a_row_of_two_has_one_block_over_both_capitals():
    two = row(2)
    assert two.n_blocks == 1
    assert two.axes() == (-1.0, 1.0)
    # from the outer edge of capital 0 (axis -1 less c 0.5) to the outer edge of capital 1
    assert two.block_extent(0) == (-1.5, 1.5)
    assert two.block_length(0) == 3.0


def test_a_row_of_six_has_five_blocks_from_axis_to_axis():
    six = row(6)
    axes = [(k - 2.5) * S for k in range(6)]
    assert six.axes() == pytest.approx(axes, abs=1e-15)
    expected = [(axes[0] - 0.5, axes[1])] + [(axes[k], axes[k + 1]) for k in (1, 2, 3)] + [(axes[4], axes[5] + 0.5)]
    for k in range(5):
        assert six.block_extent(k) == pytest.approx(expected[k], abs=1e-15), k
    # the blocks tile the row without gap or overlap: (N - 1) S + 2 c in all
    assert sum(six.block_length(k) for k in range(5)) == pytest.approx(5 * S + 1.0, rel=1e-15)
    with pytest.raises(InputError, match="blocks 0 to 4"):
        six.block_extent(5)


def test_masses_are_the_volumes_at_the_columns_density():
    six = row(6, epistyle_width=0.8, course_height=0.3)
    rho = MARBLE_DENSITY  # the columns carry no density: marble's, for the epistyle too
    assert six.density == rho
    # a block and its course: one box L x 0.8 x (0.5 + 0.3) m
    assert six.block_mass(0) == pytest.approx(rho * 2.5 * 0.8 * 0.8, rel=1e-14)
    assert six.block_mass(2) == pytest.approx(rho * 2.0 * 0.8 * 0.8, rel=1e-14)
    assert six.epistyle_mass == pytest.approx(rho * (5 * S + 1.0) * 0.8 * 0.8, rel=1e-14)
    shaft = rho * math.pi * 4.0 * (0.25 + 0.2 + 0.16) / 3.0
    capital = rho * 1.0 * 1.0 * 0.4
    assert six.column_mass == pytest.approx(shaft + capital, rel=1e-14)
    assert six.total_mass == pytest.approx(6 * (shaft + capital) + six.epistyle_mass, rel=1e-14)


def test_the_epistyle_is_as_wide_as_the_abacus_by_default():
    assert row(2).epistyle_width == 1.0
    bare = Colonnade(PAPER, 2, 1.5, 0.5)
    assert bare.epistyle_width == pytest.approx(0.8) and bare.half_abacus == pytest.approx(0.4)  # 2 r, r
    assert bare.abacus_top == 4.0 and row(2).abacus_top == pytest.approx(4.4)


def test_a_column_with_its_capital_as_one_body_by_quadrature_over_the_solid():
    """Mass, centre height and inertia about a base rim point (about the axis across the row): the shaft by
    slices (a disc of radius rho(z) at height z contributes dm (rho^2/4 + R^2 + z^2) about the rim point),
    the capital as a box moved by parallel axes. quad's error estimate is below 1e-12 relative."""
    R, r, h, rho = 0.5, 0.4, 4.0, MARBLE_DENSITY
    radius = lambda z: R + (r - R) * z / h  # noqa: E731
    m_s = quad(lambda z: rho * math.pi * radius(z) ** 2, 0, h)[0]
    zm_s = quad(lambda z: rho * math.pi * radius(z) ** 2 * z, 0, h)[0]
    i_s = quad(lambda z: rho * math.pi * radius(z) ** 2 * (radius(z) ** 2 / 4 + R**2 + z**2), 0, h)[0]
    m_k, z_k = rho * 1.0 * 1.0 * 0.4, h + 0.2
    i_k = m_k * (1.0 + 0.16) / 12 + m_k * (R**2 + z_k**2)
    body = rigid_column(DrumColumn.equal(PAPER, 3, CAPITAL))
    assert body.mass == pytest.approx(m_s + m_k, rel=1e-12)
    assert body.z_c == pytest.approx((zm_s + m_k * z_k) / (m_s + m_k), rel=1e-12)
    assert body.inertia_pivot == pytest.approx(i_s + i_k, rel=1e-12)
    assert body.inertia_central == pytest.approx(body.inertia_pivot - body.mass * (R**2 + body.z_c**2), rel=1e-12)
    # without a capital it is the frustum of the 2d model: I_P = Iy_hat m R^2
    bare = rigid_column(PAPER)
    assert bare.inertia_pivot == pytest.approx(PAPER.inertia_transverse_hat * m_s * R**2, rel=1e-12)
    assert bare.z_c == pytest.approx(PAPER.z_cm, rel=1e-14)


def test_a_blocks_central_inertia_is_the_integral_over_its_box():
    six = row(6, epistyle_width=0.8, course_height=0.3)
    x, y, z = sp.symbols("x y z", real=True)
    L, w, H = six.block_length(0), 0.8, 0.8
    box = ((x, -L / 2, L / 2), (y, -w / 2, w / 2), (z, -H / 2, H / 2))
    rho = six.density
    expected = [float(sp.integrate(rho * f, *box)) for f in (y**2 + z**2, x**2 + z**2, x**2 + y**2)]
    assert six.block_inertia(0) == pytest.approx(expected, rel=1e-12)
    assert six.block_centre(0) == pytest.approx(((six.block_extent(0)[0] + six.block_extent(0)[1]) / 2, 0.0,
                                                 4.4 + 0.4), rel=1e-14)


def test_bearing_rectangles_are_the_overlap_of_block_and_abacus_in_the_capitals_frame():
    two = row(2)
    on0, on1 = two.bearings(0)
    assert (on0.column, on1.column) == (0, 1)
    # one block over both capitals: the whole abacus (side 1.0) under each end
    assert (on0.x0, on0.x1, on0.y0, on0.y1) == (-0.5, 0.5, -0.5, 0.5)
    assert (on1.x0, on1.x1, on1.y0, on1.y1) == (-0.5, 0.5, -0.5, 0.5)
    six = row(6, epistyle_width=0.6)
    first, second = six.bearings(0)
    assert (first.x0, first.x1) == (-0.5, 0.5) and (second.x0, second.x1) == (-0.5, 0.0)
    inner = six.bearings(2)
    assert [(b.column, b.x0, b.x1) for b in inner] == [(2, 0.0, 0.5), (3, -0.5, 0.0)]
    assert (inner[0].y0, inner[0].y1) == (-0.3, 0.3)  # a block narrower than the abacus bears on its width
    last = six.bearings(4)
    assert [(b.column, b.x0, b.x1) for b in last] == [(4, 0.0, 0.5), (5, -0.5, 0.5)]
    # every capital is covered once: its bearing areas add up to the abacus's strip under the block's width
    for j in range(6):
        area = sum(b.area for k in range(5) for b in six.bearings(k) if b.column == j)
        assert area == pytest.approx(1.0 * 0.6, rel=1e-14), j
    wide = row(3, epistyle_width=1.4).bearings(1)[0]
    assert (wide.y0, wide.y1) == (-0.5, 0.5) and not wide.on_disc  # wider than the abacus: the abacus
    bare = Colonnade(PAPER, 3, 1.5, 0.5).bearings(0)[1]
    assert bare.on_disc and (bare.x0, bare.x1) == pytest.approx((-0.4, 0.0))  # on the shaft's top disc, r = 0.4


def test_head_joints_sit_over_the_inner_axes_with_a_horizontal_normal():
    six = row(6)
    joints = six.head_joints()
    assert [(j.left, j.right, j.column) for j in joints] == [(0, 1, 1), (1, 2, 2), (2, 3, 3), (3, 4, 4)]
    assert [j.x for j in joints] == pytest.approx(six.axes()[1:5])
    assert all(j.normal == (1.0, 0.0, 0.0) for j in joints)
    assert (joints[0].y0, joints[0].y1, joints[0].z0, joints[0].z1) == pytest.approx((-0.5, 0.5, 4.4, 4.9))
    assert row(2).head_joints() == ()  # one block: no head joint


@pytest.mark.parametrize("kwargs, fragments", [
    (dict(n_columns=1), ["colonnade columns = 1", "at least 2"]),
    (dict(n_columns=True), ["colonnade columns = True", "whole number"]),
    (dict(n_columns=2.5), ["colonnade columns = 2.5", "whole number"]),
    (dict(interaxial=0.9), ["colonnade interaxial = 0.9 m", "abacus side 1 m", "capitals would overlap",
                            "at least 1 m"]),
    (dict(interaxial=-1.0), ["colonnade interaxial = -1.0 m", "positive"]),
    (dict(interaxial="two"), ["colonnade interaxial = 'two'", "give it in m"]),
    (dict(epistyle_height=0.0), ["colonnade epistyle_height = 0.0 m", "positive"]),
    (dict(epistyle_height=math.nan), ["colonnade epistyle_height = nan m", "positive finite"]),
    (dict(epistyle_width=-0.5), ["colonnade epistyle_width = -0.5 m", "positive"]),
    (dict(course_height=-0.1), ["colonnade course_height = -0.1 m", "0 or more"]),
    # issue 47, item 4: plausibility limits, each with its reason (the paper's column: base diameter 1 m,
    # abacus 1 m, 4.4 m to the abacus top)
    (dict(interaxial=100.0), ["colonnade interaxial = 100 m is more than 10 m", "Artemision's west front",
                              "at most 10 m"]),
    (dict(interaxial=5.5, epistyle_height=1.0), ["colonnade interaxial = 5.5 m is more than 5 base diameters (5 m)",
                                                  "araeostyle", "or a thicker column"]),
    (dict(epistyle_height=50.0), ["colonnade epistyle_height = 50 m is more than 0.5 of the columns' height 4.4 m",
                                  "at most 2.2 m high"]),
    (dict(epistyle_height=0.001), ["colonnade epistyle_height = 0.001 m is less than 1/10 of its span (interaxial "
                                   "2 m)", "at least 0.2 m high"]),
    (dict(epistyle_width=0.01), ["colonnade epistyle_width = 0.01 m is outside 0.5 to 2 times the abacus side 1 m",
                                 "stand on a strip of their capitals", "from 0.5 to 2 m"]),
    (dict(epistyle_width=2.5), ["colonnade epistyle_width = 2.5 m is outside", "overhang their capitals"]),
])
def test_bad_rows_are_refused_naming_the_field_and_the_fix(kwargs, fragments):
    given = dict(column=DrumColumn(PAPER, capital=CAPITAL), n_columns=2, interaxial=S, epistyle_height=0.5)
    with pytest.raises(InputError) as err:
        Colonnade(**{**given, **kwargs})
    for fragment in fragments:
        assert fragment in str(err.value)


def test_bases_may_not_overlap_either():
    """Without a capital the shaft's top (r) is narrower than its base (R): the bases bound the spacing."""
    with pytest.raises(InputError, match="interaxial = 0.9 m is less than the base diameter 1 m"):
        Colonnade(PAPER, 2, 0.9, 0.5)


def test_the_named_parthenon_front_is_8_columns_carrying_7_blocks():
    front = named_colonnade("parthenon-east")
    entry = named_colonnades()["parthenon-east"]
    assert entry["source"] and "assumed" in entry["source"].lower()
    assert front.n_columns == 8 and front.n_blocks == 7
    assert front.interaxial == 4.3 and front.epistyle_height == 1.35
    assert front.column == named_drum_column("parthenon-peristyle")
    assert front.column.n_drums == 11 and front.capital.side == 2.0
    # the epistyle's mass: 7 intervals of 4.3 m and the two overhangs of 1 m, 2 m wide, 1.35 m high
    assert front.epistyle_mass == pytest.approx(MARBLE_DENSITY * (7 * 4.3 + 2.0) * 2.0 * 1.35, rel=1e-14)
    with pytest.raises(InputError, match="'nope' is not a named colonnade; known: parthenon-east"):
        named_colonnade("nope")


def test_the_limits_keep_every_colonnade_the_project_names_and_their_edges():
    """The named front and the rows of the studies stand inside the limits; each limit holds at its edge and
    refuses just past it (the paper's column: base diameter 1 m, abacus 1 m, 4.4 m to the abacus top)."""
    front = named_colonnade("parthenon-east")
    assert front.interaxial / front.epistyle_height < 10 and front.epistyle_height < 0.5 * front.abacus_top
    column = DrumColumn(PAPER, capital=CAPITAL)
    for kwargs in (dict(interaxial=5.0, epistyle_height=0.5), dict(interaxial=2.0, epistyle_height=0.2),
                   dict(interaxial=2.0, epistyle_height=2.2), dict(interaxial=2.0, epistyle_height=0.5,
                                                                   epistyle_width=0.5),
                   dict(interaxial=2.0, epistyle_height=0.5, epistyle_width=2.0)):
        Colonnade(column, 2, **kwargs)
    for kwargs in (dict(interaxial=5.0 + 1e-9, epistyle_height=0.5), dict(interaxial=2.0, epistyle_height=0.2 - 1e-9),
                   dict(interaxial=2.0, epistyle_height=2.2 + 1e-9),
                   dict(interaxial=2.0, epistyle_height=0.5, epistyle_width=0.5 - 1e-9)):
        with pytest.raises(InputError):
            Colonnade(column, 2, **kwargs)


def test_a_named_colonnade_takes_a_course_and_nothing_else_changes():
    front, crowned = named_colonnade("parthenon-east"), named_colonnade("parthenon-east", course_height=1.9)
    assert front.course_height == 0.0 and crowned.course_height == 1.9
    assert (crowned.n_columns, crowned.interaxial, crowned.epistyle_height, crowned.epistyle_width, crowned.column) == \
        (front.n_columns, front.interaxial, front.epistyle_height, front.epistyle_width, front.column)
    # the course rides on the blocks as mass of the epistyle's width and density: (1.35 + 1.9) / 1.35 as heavy
    assert crowned.epistyle_mass == pytest.approx(front.epistyle_mass * (1.35 + 1.9) / 1.35, rel=1e-14)


def test_every_kind_of_structure_is_named_and_has_an_example():
    assert KINDS == ("column", "drums", "colonnade")
    for kind in KINDS:
        assert kind_of(example(kind)) == kind
    with pytest.raises(InputError, match="got str"):
        kind_of("column")
