"""The MJCF attributes that name another element, by the kind of name they take (MuJoCo's object
namespaces): what renaming an element must follow everywhere it is named (a part's prefixed
names, a body merged into its parent), and what removing one leaves naming nothing."""

from __future__ import annotations

REFERENCES: dict[str, tuple[str, ...]] = {
    "body": ("body", "body1", "body2", "target"),
    "joint": ("joint", "joint1", "joint2", "jointinparent"),
    "geom": ("geom", "geom1", "geom2"),
    "site": ("site", "site1", "site2", "cranksite", "slidersite", "refsite"),
    "mesh": ("mesh",),
    "material": ("material",),
    "texture": ("texture",),
    "hfield": ("hfield",),
    "tendon": ("tendon", "tendon1", "tendon2"),
    "class": ("class", "childclass"),
}
