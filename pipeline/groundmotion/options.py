"""How each record option is given in each interface, for messages that recommend one.

A record is named in three places: the Python API (:func:`pipeline.groundmotion.load`),
the command line (``frustum simulate`` and ``frustum records show|plot``) and
study files (``[records] files``). A message that asks for an option names it
in all three, so that whoever reads it can act on it.
"""

__all__ = ["how_to_give"]

_FORMS = {
    "components": ("components=(x, y[, z])", "--components X,Y[,Z]", 'components = ["X", "Y"]'),
    "missing_y": ("missing_y='zero'", "--missing-y zero", 'missing_y = "zero"'),
    "units": ("units=U", "--units U", 'units = "U"'),
    "dt": ("dt=DT [s]", "--dt DT", "dt = DT"),
    "baseline": ("processing.baseline_correct(gm)", "--baseline linear", 'processing = [{step = "baseline"}]'),
}


def how_to_give(option, value=None):
    """``"components=(x, y[, z]) (--components X,Y[,Z]; study file: components = [...])"``.

    Parameters
    ----------
    option : {"components", "missing_y", "units", "dt", "baseline"}
    value : str, optional
        A value to show instead of the placeholder (e.g. one of the units).
    """
    api, cli, study = _FORMS[option]
    if value is not None:
        api, cli, study = f"{option}={value!r}", f"--{option.replace('_', '-')} {value}", f'{option} = "{value}"'
    return f"{api} (command line: {cli}; study file: {study})"
