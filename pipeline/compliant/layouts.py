"""The layout of any structure the compliant model runs: a column, a column of drums or a colonnade.

The one place that tells the kinds apart, above the modules that build each
(:mod:`pipeline.compliant.parts`, :mod:`pipeline.compliant.colonnade`), so that neither imports the other back.
"""

from pipeline.compliant.colonnade import colonnade_layout, is_colonnade
from pipeline.compliant.parts import Layout, as_stack, stack_layout
from pipeline.structures.column import Column

__all__ = ["layout_of", "outline_of"]


def outline_of(structure, whole=False):
    """The column of a structure (a colonnade's: each of its columns): its shaft's outline as one
    :class:`Column` with its density, or with ``whole`` the :class:`DrumColumn` itself."""
    stack = structure.column if is_colonnade(structure) else as_stack(structure)
    if whole:
        return stack
    return Column(stack.column.R, stack.column.r, stack.column.h, density=stack.density)


def layout_of(structure, settings):
    """The :class:`Layout` of a structure: a Column, a DrumColumn or a Colonnade (a Layout is its own:
    any bodies on any joints, as the tests build them)."""
    if isinstance(structure, Layout):
        return structure
    if is_colonnade(structure):
        return colonnade_layout(structure, settings)
    return stack_layout(structure, settings)
