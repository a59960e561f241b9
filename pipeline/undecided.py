"""How a run still able to fall at the cap of its simulated time counts: the stated choice, in one place.

A run goes on after its record and tail, the ground still, until the structure stands for good or
falls, at most ``settle_limit`` seconds (docs/model.md, "The end of a run"). One still able to fall
then is *undecided*: it neither stood nor fell. Fits, counts, comparisons and reports count it as
one of :data:`UNDECIDED_CHOICES`, by default :data:`DEFAULT_UNDECIDED` (it had not fallen when the
cap ran out), and the report states what the other way moves (:mod:`pipeline.report_undecided`).
Plain constants, so that the command line offers them without importing the fitting code.
"""

__all__ = ["UNDECIDED_CHOICES", "DEFAULT_UNDECIDED"]

#: As a run that stood, as one that overturned, or left out (the rule before issue 47, kept to
#: measure what the choice moves).
UNDECIDED_CHOICES = ("standing", "overturned", "excluded")
DEFAULT_UNDECIDED = "standing"
