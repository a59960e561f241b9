"""The contract every model of the registry holds (issue 28).

One test set, parametrised over :data:`pipeline.models.REGISTRY`: a model added with a kernel
and one entry is checked here without a test of its own being written first. Each case runs
the paper's column (R 0.5, r 0.4, h 4 m; a model of drums gets it in two drums, a model of colonnades
two of it with capitals carrying an epistyle, pipeline.structures.kinds.example) under a
one-sine pulse of 4 m/s^2 and 0.5 s, strong enough to rock it (its uplift acceleration is
g R / (h/2) ~ 2.5 m/s^2).
"""

import math
from importlib import import_module

import pytest
from numba.core.caching import NullCache

from pipeline import models
from pipeline.dataset import FLAGS, STUDY_VARIABLES, VARIABLES
from pipeline.structures.drums import DrumColumn
from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.groundmotion.synthesis import one_sine_pulse
from pipeline.models.options import OPTIONS
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.structures.kinds import example

PAPER = Column(0.5, 0.4, 4.0)
MODELS = list(models.REGISTRY.values())
NAMES = [m.name for m in MODELS]


@pytest.fixture(scope="module")
def pulse():
    return one_sine_pulse(4.0, 0.5, dt=0.005, duration=0.6, direction=0.0, record_id="contract-pulse")


def _run(model, pulse, angle=20.0, histories=True):
    # the most elaborate structure it runs: the paper's column, in two drums, or two of it carrying an epistyle
    body = example(model.bodies[-1])
    return simulate(body, pulse, Excitation(angle=angle), ModelSettings(model=model.name, tail=0.4),
                    histories=histories)


@pytest.mark.parametrize("model", MODELS, ids=NAMES)
def test_a_model_runs_a_pulse_and_its_summary_holds_its_declared_results(model, pulse):
    response = _run(model, pulse)
    summary = response.summary
    assert summary["model"] == model.name
    missing = [name for name in model.results if name not in summary]
    assert not missing, f"{model.name} declares results its summary lacks: {missing}"
    uncatalogued = [name for name in model.results if name not in STUDY_VARIABLES and name not in FLAGS]
    assert not uncatalogued, f"{model.name} declares results the catalog does not know: {uncatalogued}"
    assert summary["peak_theta_ratio"] > 0.05  # the pulse rocked it: the run did something
    assert summary["uplifted"]
    # every history is a catalog variable (named and documented once, docs/variables.md) or a flag,
    # and the run writes exactly the declared ones and the copies in degrees the catalog adds to an
    # angle (``theta_deg``)
    uncatalogued = [name for name in model.histories if name not in VARIABLES and name not in FLAGS]
    assert not uncatalogued, f"{model.name} declares histories the catalog does not know: {uncatalogued}"
    declared = set(model.histories) | {f"{n}_deg" for n in model.histories if n in VARIABLES and VARIABLES[n].degrees}
    written = set(response.histories.data_vars)
    assert written == declared, (f"{model.name} writes {sorted(written - declared)} it does not declare and "
                                 f"declares {sorted(declared - written)} it does not write")


@pytest.mark.parametrize("model", MODELS, ids=NAMES)
def test_a_models_declared_state_layout_is_its_kernels(model):
    """The names of the state vector's slots (a stack's per body) sit where the kernel's index constants say."""
    kernel = import_module(model.state.kernel)
    assert getattr(kernel, model.state.size) == len(model.state.slots), model.state.size
    for i, (name, constant) in enumerate(model.state.slots):
        assert getattr(kernel, constant) == i, (name, constant)
    assert len(set(model.state.names)) == len(model.state.names)


def _out_of_range(option):
    """A value ``option`` refuses: past its range, or not one of its words."""
    if option.kind == "choice":
        return "no-such-" + option.choices[0]
    if option.kind == "bool":
        return "yes"
    return 2 * option.hi if math.isfinite(option.hi) else option.lo - 1.0


@pytest.mark.parametrize("option", OPTIONS.values(), ids=list(OPTIONS))
def test_every_option_out_of_range_is_refused_naming_it(option):
    """Over the whole table, for every model that reads it (or the default model): the message names the option."""
    readers = [m.name for m in MODELS if option.name in m.options] or [models.DEFAULT]
    for name in readers:
        with pytest.raises(InputError, match=f"^{option.name}"):
            ModelSettings(model=name, **{option.name: _out_of_range(option)})
    assert ModelSettings(**{option.name: option.default}) == ModelSettings()  # its default is accepted


@pytest.mark.parametrize("model", MODELS, ids=NAMES)
def test_a_models_options_are_declared_ones(model):
    """``model.options`` are the table's declarations, so that its defaults and units are the settings'."""
    for name, option in model.options.items():
        assert option is OPTIONS[name]
        assert getattr(ModelSettings(model=model.name), name) == option.default


@pytest.mark.parametrize("model", MODELS, ids=NAMES)
def test_bad_options_are_refused_with_the_options_name(model):
    with pytest.raises(InputError, match="numerics: 'no_such_choice' is not a numerical choice"):
        ModelSettings(model=model.name, numerics=(("no_such_choice", 1.0),))
    for name in model.numerics:
        ModelSettings(model=model.name, numerics=((name, model.numerics[name]),))  # its default is accepted
        with pytest.raises(InputError, match=f"numerics: {name}"):
            ModelSettings(model=model.name, numerics=((name, -1.0),))
    with pytest.raises(InputError, match="tail = -1"):
        ModelSettings(model=model.name, tail=-1.0)


def test_an_unknown_model_is_refused_with_the_choices():
    with pytest.raises(InputError, match="model = 'nope' is unknown; choose one of " + ", ".join(NAMES)):
        ModelSettings(model="nope")


@pytest.mark.parametrize("model", MODELS, ids=NAMES)
def test_a_model_is_angle_invariant_exactly_when_it_says_so(model, pulse):
    """The sweep runs an angle-invariant model once per angle set and repeats it: that must
    change no number. A model that is not must see the direction (37 deg is no symmetry of
    the contact points' 24 sectors)."""
    at_0 = _run(model, pulse, angle=0.0, histories=False).summary["peak_theta"]
    at_37 = _run(model, pulse, angle=37.0, histories=False).summary["peak_theta"]
    if model.angle_invariant:
        assert at_37 == pytest.approx(at_0, rel=1e-12)
    else:
        assert abs(at_37 - at_0) > 1e-4 * at_0


@pytest.mark.parametrize("model", MODELS, ids=NAMES)
def test_a_models_compiled_entry_points_are_cached_kernels(model):
    """What the sweep compiles before its workers start and looks up in numba's cache."""
    assert model.entry_points
    for module, function in model.entry_points:
        kernel = getattr(import_module(module), function)
        assert hasattr(kernel, "_cache") and not isinstance(kernel._cache, NullCache), (module, function)


def test_a_planar_model_names_the_3d_model_it_is_the_counterpart_of():
    for model in MODELS:
        if model.planar:
            assert models.get(model.planar_of).planar is False
    assert models.planar_pair(NAMES) is not None


def test_the_integrators_a_model_declares_are_its_kernels():
    """The registry names the compliant model's integrators without importing its kernels (the
    command's help stays free of numba); they must be the fixed-step one and the kernels' methods."""
    from pipeline.dynamics.compliant import adaptive

    assert models.get("3d-compliant").integrators == ("semi-implicit",) + tuple(adaptive.METHODS)
    with pytest.raises(InputError, match="integrator = 'rk4' is unknown; choose one of semi-implicit"):
        ModelSettings(model="3d-compliant", integrator="rk4")


def test_a_model_of_monoliths_refuses_drums_naming_the_models_that_run_them(pulse):
    monoliths = [m for m in MODELS if not m.drums]
    drum_models = ", ".join(m.name for m in MODELS if m.drums)
    for model in monoliths:
        with pytest.raises(InputError, match=f"a column of 3 drum\\(s\\) needs one of {drum_models}"):
            simulate(DrumColumn.equal(PAPER, 3), pulse, Excitation(), ModelSettings(model=model.name))


@pytest.mark.parametrize("model", models.names())
def test_a_model_runs_of_a_column_what_its_entry_says_simulate_and_a_study_alike(model):
    """Issue 47, item 4: Model.structure, the one rule simulate and a study share: the colonnade if the model
    runs colonnades, the drums if it runs drums, else the shaft alone; and its checker passes what it gets."""
    entry = models.REGISTRY[model]
    row = example("colonnade")
    shaft, stack = row.column.column, row.column
    given = entry.structure(shaft, stack, row)
    assert given is (row if entry.runs("colonnade") else stack if entry.drums else shaft)
    assert entry.structure(shaft, None, None) is shaft and entry.structure(shaft, stack, None) is (
        stack if entry.drums else shaft)
    entry.check(given, ModelSettings(model=model))
