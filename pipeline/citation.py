"""The paper the model comes from: the one place its reference is written.

Every output that names the paper (netCDF ``references`` attributes, reports,
the README and data files checked by ``tests/test_citation.py``) takes it from
here.
"""

#: Authors as they are cited in running text.
AUTHORS_SHORT = "Stefanou, Vardoulakis & Mavraganis"

#: Year of publication.
YEAR = 2011

#: The full reference.
REFERENCE = (
    "Stefanou I., Vardoulakis I., Mavraganis A. (2011), Dynamic motion of a conical frustum over a rough "
    "horizontal plane, International Journal of Non-Linear Mechanics 46(1), 114-124"
)

#: In running text: "Stefanou, Vardoulakis & Mavraganis 2011".
CITE = f"{AUTHORS_SHORT} {YEAR}"

__all__ = ["AUTHORS_SHORT", "YEAR", "REFERENCE", "CITE"]
