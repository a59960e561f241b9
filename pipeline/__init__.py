"""Earthquake response of free-standing columns modelled as rigid conical frustums.

The package has two layers (see ``docs/`` and the project's ARCHITECTURE):
``pipeline.dynamics`` holds plain-array numerical kernels; everything else is the
friendly, typed layer (geometry, ground motions, simulation, studies, output).
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("frustum-pipeline")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
