"""ModelSettings: its defaults are the options table's, and one validator checks every field (issue 28)."""

import dataclasses

import pytest

from pipeline.errors import InputError
from pipeline.models.options import OPTIONS, Option
from pipeline.settings import ModelSettings

_NOT_OPTIONS = {"model", "numerics"}  # the model's name and its numerical choices: checked against its entry


def test_every_field_is_an_option_of_the_table_with_its_default():
    fields = {f.name: f.default for f in dataclasses.fields(ModelSettings)}
    assert set(fields) - _NOT_OPTIONS == set(OPTIONS)
    for name, option in OPTIONS.items():
        assert fields[name] == option.default, name


def test_values_are_normalised_once_checked():
    """A study file's floats become whole numbers, a list a tuple (settings are hashable: calibration cache)."""
    s = ModelSettings(model="3d-compliant", contact_rings=4.0, contact_sectors=16.0, joint_friction=[0.5, 0.6],
                      tail=2)
    assert s.contact_rings == 4 and isinstance(s.contact_rings, int)
    assert s.joint_friction == (0.5, 0.6) and isinstance(s.tail, float)
    hash(s)


@pytest.mark.parametrize("kwargs, message", [
    ({"damping": 200.0}, r"damping = 200.0: the viscous contact couple .* must be a number in \[0, 100\]"),
    ({"friction": 0.0}, r"friction = 0.0: .* must be a number in \(0, 10\], or inf for rolling without slip"),
    ({"contact_tilt": 1.0}, r"contact_tilt = 1.0 deg: .* \[0, 0.5\] \(or omit it: the compliance of the bed"),
    ({"contact_sectors": 25}, r"contact_sectors = 25: .* must be an even whole number in \[4, 256\]"),
    ({"joint_friction": [0.5, "x"]}, r"joint_friction\[1\] = 'x'"),
    ({"anathyrosis": []}, "anathyrosis is an empty list"),
    ({"lift_off": "no"}, "lift_off = 'no': .* must be true or false"),
    ({"model": "3d-compliant", "step": 1e-4, "integrator": "dopri5"}, "chooses its own steps"),
    ({"model": "3d-compliant", "friction": float("inf")}, "needs a finite friction"),
    ({"model": "3d-compliant", "normal_stiffness": float("inf")}, r"normal_stiffness = inf Pa/m: .* finite"),
])
def test_a_bad_value_is_refused_naming_the_field_the_value_and_the_range(kwargs, message):
    with pytest.raises(InputError, match=message):
        ModelSettings(**kwargs)


def test_the_rigid_models_take_an_infinite_friction_and_stiffness():
    s = ModelSettings(friction=float("inf"), normal_stiffness=float("inf"))
    assert s.friction == s.normal_stiffness == float("inf")


def test_an_option_help_says_its_unit_and_default():
    option = Option("x", 2.0, "s", "number", "time of something", 0.0, 10.0)
    assert option.help() == "time of something [s] (default 2)"
    assert option.check(3) == 3.0
    with pytest.raises(ValueError, match="kind"):
        Option("y", 1, "1", "count", "a thing")
