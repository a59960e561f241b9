"""The rigid planar frame of a colonnade (``"2d-frame"``): Makris & Vassiliou's array of free-standing
columns capped by a freely supported rigid beam, with frustum columns and capitals, run as one rocking
block by the planar kernel (:func:`pipeline.frame.simulate_frame`, :mod:`pipeline.dynamics.rigid.run2d`)."""

from types import MappingProxyType

from pipeline.models.rigid import HISTORIES_2D, NUMERICS, PLANAR_ROCKING, RESULTS, STATE_2D
from pipeline.models.spec import Model, ModelDescription, read

__all__ = ["RIGID_FRAME"]

RIGID_FRAME = Model(
    name="2d-frame",
    description=ModelDescription(
        title="2D rigid frame of a colonnade",
        body="a colonnade as a rigid planar frame: its columns, each with its capital one rigid body, rock in "
        "unison about the rims of their bases in the plane of the row, and the epistyle, one rigid beam resting on "
        "the capitals' top edges opposite the pivots, translates with them (Makris and Vassiliou 2013, with "
        "frustum columns and capitals): one rocking block, whose slenderness, size and restitution follow from "
        "the frame's energy (docs/model.md)",
        follows=("rocking of the whole frame in the plane of the row, every column alike, driven by the component "
                 "of the record along the row", "sliding of the frame on its column bases and slip of the pivots",
                 "uplift and flight of the whole frame", "overturning"),
        contact="The column bases are flat faces of stone on a bed: the frame stays at rest, slides on them, or, "
        "once tipped, rocks on the base rims on one side, whose points slip when the friction needed exceeds "
        "Coulomb's `friction` times the bases' normal force; when the ground would have to pull, the whole frame "
        "flies and lands again with a plastic impact. Every base carries an equal share of the epistyle; its bed's "
        "compliance (`normal_stiffness`) gives its patch the rolling damping of the 2d model. Energy is lost at "
        "landings (angular momentum about the new pivots is kept, with the epistyle's impulse at the new top "
        "edges, or the `restitution` given), to friction, in the patches' dashpots and in the optional viscous "
        "couple (`damping`, at every base). The epistyle never leaves the capitals' edges nor slides on them.",
        sliding_onset="the frame slid on its column bases or their rims slipped (friction reached mu N); the motion "
        "follows it",
        lift_off="the whole frame lifted off into flight (the bases' normal force reached zero); the motion follows it",
        cite="Makris and Vassiliou 2013",
        reference="Makris N., Vassiliou M.F. (2013), Planar rocking response and stability analysis of an array of "
        "free-standing columns capped with a freely supported rigid beam, Earthquake Engineering and Structural "
        "Dynamics 42(3), 431-449 (the rigid frame of frustum columns with capitals: docs/model.md, 'The rigid "
        "planar frame')",
    ),
    in_short="a colonnade rocking in its plane as a rigid frame (columns in unison, the epistyle translating), "
    "run as one block",
    bodies=("colonnade",),
    angle_invariant=False,  # it rocks in the plane of its row: the angle turns the record against it
    planar=True,
    # its 3D counterpart: the colonnade as an assembly of bodies on joints (issue 37, item 3)
    planar_of="3d-compliant",
    numeric_options=NUMERICS,
    state=STATE_2D,
    # the 2d model's, the epistyle's translation, and the forces and energy in SI (the frame's density is
    # always known: the columns', marble's by default)
    histories=HISTORIES_2D + ("epistyle_dx", "epistyle_dz", "normal_force", "tangential_force", "energy"),
    results=RESULTS,
    entry_points=PLANAR_ROCKING.entry_points,
    runner="pipeline.frame:simulate_frame",
    style=MappingProxyType(dict(ls=":", marker="v", filled=True, band_alpha=0.07)),
    # the 2d model's options, each on the frame's terms (pipeline.frame.frame_options)
    options=PLANAR_ROCKING.options,
    # a colonnade whose columns would lie down before the frame tips, refused before simulate or a study computes
    checker="pipeline.frame:check_frame",
)
