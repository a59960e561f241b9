"""A study of imperfect drums (issue 48, item 2): the dimension seed, end to end on a tiny study.

``[imperfections]`` draws one structure per seed for the models that can; the others run once and are
repeated along ``seed``; every cell is the run simulate() gives with that seed; the draws are recorded;
fragility pools the seeds as it pools angles; what cannot run is refused naming the field.
"""

import numpy as np
import pytest

from pipeline import fragility as F
from pipeline.dataset import open_results
from pipeline.errors import InputError
from pipeline.settings import Excitation
from pipeline.simulate import simulate
from pipeline.structures.imperfections import Imperfections, draw
from pipeline.study import load_motions, load_study, run_study
from pipeline.study.grid import plan, record_intensity, scale_factors

SEEDS = """\
title = "imperfect drums"
output = "seeds.nc"

[models.rigid]
model = "3d"

[models.perfect]
model = "3d-compliant"

[models.imperfect]
model = "3d-compliant"

[[columns]]
name = "two"
R = 0.5
r = 0.4
h = 4.0
drums = 2

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 4.0, fp = 2.0, dt = 0.01, duration = 1.5}]

[excitation]
angles = [0.0]
scales = [1.0, 2.0]

[options]
tail = 0.5
contact_sectors = 16

[imperfections]
tolerance = 0.003
seeds = [5, 9]
friction_range = [0.5, 0.7]
models = ["imperfect"]
"""


@pytest.fixture(scope="module")
def seeded(tmp_path_factory):
    folder = tmp_path_factory.mktemp("seeds")
    path = folder / "seeds.toml"
    path.write_text(SEEDS, encoding="utf-8")
    study = load_study(path)
    report = run_study(study, serial=True, progress=False)
    return study, open_results(report.path)  # through the file


def test_the_seeds_are_a_dimension_of_the_results(seeded):
    study, ds = seeded
    assert study.seeds == (5, 9) and [study.seeded(m) for m in study.models] == [False, False, True]
    motions = load_motions(study)
    tasks = plan(study, scale_factors(study, [record_intensity(m, None) for m in motions]))
    # per scale: the rigid and the perfect model once, the imperfect one per seed
    assert sum(t.n_simulations for t in tasks) == 2 * (1 + 1 + 2)
    assert ds.peak_theta.dims == ("column", "record", "angle", "scale", "model", "seed")
    assert ds.joint_slip.dims == ("column", "record", "angle", "scale", "model", "seed", "joint")
    assert ds.seed.values.tolist() == [5, 9] and ds.seed.dtype == np.int64
    assert ds.seeded.values.tolist() == [0, 0, 1] and ds.seeded.attrs["flag_meanings"] == "perfect seeded"
    assert ds.attrs["imperfection_tolerance_m"] == 0.003 and ds.attrs["imperfection_models"] == "imperfect"
    assert ds.attrs["imperfection_friction_range"] == "0.5 0.7"
    assert np.all(ds.status.values == 0)
    for model in ("rigid", "perfect"):  # run once, the same along the seeds
        one = ds.peak_theta.sel(model=model)
        np.testing.assert_array_equal(one.sel(seed=5).values, one.sel(seed=9).values)
    imperfect = ds.peak_theta.sel(model="imperfect")
    assert not np.array_equal(imperfect.sel(seed=5).values, imperfect.sel(seed=9).values)


def test_every_cell_is_the_run_of_its_seed_and_its_draw_is_recorded(seeded):
    """Each imperfect cell equals simulate() with that seed to the bit, and the drawn values on (column,
    seed, joint) are the draw of that seed."""
    study, ds = seeded
    motion = load_motions(study)[0]
    column = study.columns[0].stack
    for seed in (5, 9):
        settings = study.settings("imperfect", seed=seed)
        assert settings.seed == seed and settings.imperfections == 0.003
        direct = simulate(column, motion, Excitation(scale=2.0), settings, histories=False).summary
        cell = ds.sel(model="imperfect", seed=seed, scale=2.0).isel(column=0, record=0, angle=0)
        for name in ("peak_theta", "residual_displacement", "dislocation_ratio"):
            assert float(cell[name]) == direct[name], name
        np.testing.assert_array_equal(cell.joint_slip.values, direct["joint_slip"])
        expected = draw(Imperfections(0.003, seed, (0.5, 0.7)), column)
        drawn = ds.sel(seed=seed).isel(column=0)
        np.testing.assert_array_equal(drawn.bed_tilt.values, expected.tilt)
        np.testing.assert_array_equal(drawn.bed_offset_y.values, expected.offset_y)
        np.testing.assert_array_equal(drawn.bed_friction.values, expected.friction)
    assert ds.bed_tilt.attrs["units"] == "rad" and ds.bed_offset_x.attrs["units"] == "m"


def test_fragility_pools_the_seeds_as_samples_of_one_structure(seeded):
    """The imperfect model's runs of both seeds are counted (2 stripes x 2 seeds), the perfect and rigid
    models' repeats along the seeds once (tests/fragility/test_seeds.py: pooled exactly as angles are)."""
    _, ds = seeded
    frag = F.fragility(ds, dislocations=())
    runs = frag.n_runs.sel(state="overturning").isel(column=0)
    assert runs.sel(model="imperfect") == 4 and runs.sel(model="perfect") == 2 and runs.sel(model="rigid") == 2
    assert frag.attrs["seeds_pooled"] == "5 9" and frag.seeded.values.tolist() == [0, 0, 1]
    assert frag.attrs["imperfection_tolerance_m"] == 0.003


@pytest.mark.parametrize("edit, field, words", [
    (('models = ["imperfect"]', 'models = ["rigid"]'), "imperfections.models[0]",
     "imperfections.models[0] = 'rigid' draws imperfect drums (beds offset and tilted within a tolerance, joint "
     "friction from a range), which only 3d-compliant runs; model 3d runs perfect structures"),
    (('models = ["imperfect"]', 'models = ["other"]'), "imperfections.models[0]",
     "'other' is not a model of the study"),
    (("seeds = [5, 9]", "seeds = [5, 5]"), "imperfections.seeds", "seed 5 is given twice"),
    (("seeds = [5, 9]", "seeds = [5, -9]"), "imperfections.seeds[1]", "must be a whole number in [0, 4294967295]"),
    (("seeds = [5, 9]", "seeds = []"), "imperfections.seeds", "must be a non-empty list of whole numbers"),
    (("tolerance = 0.003\n", ""), "imperfections.tolerance", "missing"),
    (("tolerance = 0.003", "tolerance = 0.05"), "imperfections.tolerance",
     "imperfections = 0.05 m is more than 5 % of the smallest bed diameter"),
    (("friction_range = [0.5, 0.7]", "friction_range = [0.7]"), "imperfections.friction_range",
     "must be two numbers LO,HI"),
    (("contact_sectors = 16", "contact_sectors = 16\nseed = 3"), "options.seed",
     "the study's [imperfections] draws the imperfect drums"),
    (("tolerance = 0.003", "tolerance = 0.02"), "imperfections.tolerance", None),
])
def test_what_a_study_of_imperfect_drums_cannot_run_is_refused_naming_the_field(write_study, edit, field, words):
    text = SEEDS.replace(*edit)
    if words is None:  # beds leaning past their friction angle: a range far too low for 20 mm
        text = text.replace("friction_range = [0.5, 0.7]", "friction_range = [0.001, 0.002]")
        words = "leans"
    with pytest.raises(InputError) as caught:
        load_study(write_study(text), load_records=False)
    message = str(caught.value)
    assert f"field {field}: " in message and words in message, message


def test_the_study_plot_draws_the_seeds_and_the_report_says_how_far_they_agree(seeded, tmp_path):
    """frustum study run --plot draws every seed's runs as it draws the angles' (a marker each); frustum
    report reports the study (it refused it before): what was drawn, the seeds pooled in its counts, and
    the section on the spread over seeds, whose every count is recomputed here from the dataset."""
    from pipeline.plotting import plot_study
    from pipeline.report import write_report

    _, ds = seeded
    plot_study(ds, tmp_path / "seeds.png")
    assert (tmp_path / "seeds.png").stat().st_size > 0
    out = write_report(ds, tmp_path / "report", bootstrap=0)
    text = open(out["report"], encoding="utf-8").read()
    assert ("- **Imperfect drums**: `imperfect` drew a structure for each of 2 seed(s) (5, 9): every drum's bed "
            "offset and tilted by random amounts up to 3 mm, the friction of every joint drawn from 0.5 to 0.7."
            ) in text
    assert "- 8 simulations in the dataset, 0 failed" in text  # 2 stripes x (rigid + perfect + 2 seeds)
    section = text[text.index("## Imperfect drums: do apparently identical structures differ?"):]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in section[:section.index("\n## ")].splitlines()
            if line.startswith("| two |")]
    one = ds.sel(column="two", model="imperfect")
    perfect = ds.sel(column="two", model="perfect").isel(seed=0)
    assert len(rows) == 3
    for row, scale in zip(rows, (1.0, 2.0, None)):
        pick = {} if scale is None else {"scale": [scale]}
        falls = (one["overturned"].sel(pick) == 1).sum("seed")  # of 2 seeds, over (record, angle[, scale]) cells
        alone = perfect["overturned"].sel(pick) == 1
        cells = falls.size
        expected = [str(cells)] + [str(int((falls == k).sum())) for k in (0, 2, 1)]  # all stand, all fall, divided
        assert row[1] == "imperfect" and row[3:7] == expected
        ties = int((falls == 1).sum())  # one seed of two fell: no majority
        differ = int(((falls != 1) & ((falls == 2) != alone)).sum())
        assert row[9] == f"`perfect`: {differ} of {cells}" + (f" ({ties} tied)" if ties else "")
