"""One description per model, the only place reports, plots and help say what a model is.

A table keyed by model name (``pipeline.simulate.MODELS``): what the column is in that model,
what motion it follows, its contact law and energy losses, what its ``sliding_onset`` and
``lift_off`` flags count, and its reference. :mod:`pipeline.report` writes a study's
assumptions from the entries of the models the study ran, and only those; the plots take the
titles from here. Plain data: the model registry of the redesign (``models/spec.py``,
docs/ARCHITECTURE) is to take these entries over as they are.

What the rigid models follow is :mod:`pipeline.dynamics.rigid` (docs/model.md, "The physical
contact"); the compliant model is :mod:`pipeline.compliant` (docs/model.md, "The
compliant-contact model").
"""

from typing import NamedTuple

from pipeline.citation import CITE, REFERENCE


class ModelDescription(NamedTuple):
    """What one model is, in words for people who do not program.

    Attributes
    ----------
    title : str
        Display name, e.g. in figure titles and the report's list of models.
    body : str
        What the column is in this model.
    follows : tuple of str
        The motions the model follows (computes), not merely flags.
    contact : str
        The contact law and where energy is lost.
    sliding_onset : str
        What a run counted by the ``sliding_onset`` flag did ("in N of M runs ...").
    lift_off : str
        What a run counted by the ``lift_off`` flag did.
    cite : str
        Where the model comes from, in running text.
    reference : str
        Where the model comes from, in full (the report's references).
    angle_invariant : bool
        Its results are the same at every incidence angle (computed once per angle set).
    """

    title: str
    body: str
    follows: tuple
    contact: str
    sliding_onset: str
    lift_off: str
    cite: str
    reference: str
    angle_invariant: bool = False


_RIGID_CONTACT = (  # {pivot}: what the tipped column turns on, {rim}: where it touches
    "The base is a flat face of stone on a bed: it stays at rest with the ground, slides flat on it or, once "
    "tipped, {pivot}, whose point of contact slips when the friction needed exceeds "
    "Coulomb's `friction` times the normal force; when the ground would have to pull, the column flies and lands "
    "again with a plastic impact that sticks or slides. The bed's compliance (`normal_stiffness`) gives the "
    "patch under the {rim} its rolling damping and drilling friction. Energy is lost at landings (angular momentum "
    "about the new pivot is kept, or the `restitution` given; passages close to a landing lose part of it), to "
    "friction while sliding or slipping, in the patch's dashpots and in the optional viscous contact couple "
    "(`damping`).")

MODELS = {
    "3d": ModelDescription(
        title="3D rolling frustum",
        body="one rigid, homogeneous conical frustum (a cone with its tip cut off) standing free on its base",
        follows=("rocking and wobbling: rolling on the rim of the base, the contact point travelling around it",
                 "spin about its own axis", "sliding of the base and slip of the rim on the ground",
                 "uplift and flight", "overturning"),
        contact=_RIGID_CONTACT.format(pivot="rolls on the rim of the base", rim="rim")
        + " The column is axisymmetric, so its results do not depend on the incidence angle.",
        sliding_onset="the base slid or the rim slipped on the ground (friction reached mu N); the motion follows it",
        lift_off="the column lifted off into flight (the normal force reached zero); the motion follows it",
        cite=CITE,
        reference=f"{REFERENCE} (the 3D rolling frustum; its contact: docs/model.md)",
        angle_invariant=True,
    ),
    "2d": ModelDescription(
        title="2D planar rocking",
        body="the same rigid frustum, held in the vertical plane of the incidence angle (classical planar "
        "rocking)",
        follows=("rocking on one edge of the base and the other, driven by the component of the record along the "
                 "incidence angle", "sliding of the base and slip of the edge on the ground", "uplift and flight",
                 "overturning"),
        contact=_RIGID_CONTACT.format(pivot="rocks on an edge of the base", rim="edge")
        + " It neither wobbles nor spins.",
        sliding_onset="the base slid or its edge slipped on the ground (friction reached mu N); the motion follows it",
        lift_off="the column lifted off into flight (the normal force reached zero); the motion follows it",
        cite="Housner 1963",
        reference="Housner G.W. (1963), The behavior of inverted pendulum structures during earthquakes, Bulletin "
        "of the Seismological Society of America 53(2), 403-417 (the 2D planar rocking; its contact: "
        "docs/model.md)",
    ),
    "3d-compliant": ModelDescription(
        title="3D compliant drums on joints",
        body="rigid bodies with six degrees of freedom each: one monolith, or a stack of drums (conical "
        "frustums, bottom first) with an optional square capital on top; the base on the ground and every bed "
        "joint between two bodies are joints of contact points (rings times sectors over the face)",
        follows=("rocking and wobbling of every body", "sliding of the base on the ground and of each drum on the "
                 "one below", "uplift and flight of the whole column or of the bodies above a joint",
                 "drum dislocations: the residual slip, twist, tilt and opening of every joint",
                 "overturning of the column or of any body above a joint"),
        contact="Joint law, at every contact point: a normal spring-dashpot that acts in compression only (a joint "
        "never pulls), and a shear spring capped by Coulomb friction (the point sticks inside the friction cone "
        "and slips on it). There is no impact law: landings are taken by the springs and dashpots. Energy is lost "
        "in the normal dashpots (damping calibrated to a planar restitution unless `contact_damping` is given) and "
        "to friction where points slip.",
        sliding_onset="the mobilized friction |F_t|/N of the base reached mu (the base slid on the ground)",
        lift_off="every contact point of the base lost contact (the column flew)",
        cite="docs/model.md",
        reference="docs/model.md, 'The compliant-contact model' (joints of contact points in the manner of DEM "
        "codes; the 3D compliant drums on joints)",
    ),
}


def describe(model):
    """The description of a model; an unknown name gets a placeholder that says so, not an error."""
    return MODELS.get(model) or ModelDescription(
        title=model, body=f"model {model!r} (no description)", follows=(), contact="", sliding_onset="the flag was set",
        lift_off="the flag was set", cite="", reference="")


def title(model):
    """Display name of a model (``"3D rolling frustum"``), or the name itself if unknown."""
    return describe(model).title


def markdown(model):
    """The model's description as one Markdown bullet (the report's assumptions)."""
    d = describe(model)
    follows = "; ".join(d.follows)
    source = f", {d.cite}" if d.cite else ""
    return f"- **{d.title}** (`{model}`{source}): {d.body}. It follows {follows}. {d.contact}".rstrip()


__all__ = ["ModelDescription", "MODELS", "describe", "title", "markdown"]
