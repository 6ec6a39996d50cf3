"""RS320: a ``never_collide`` entry selects two links or more.

Passing::

    never_collide: [[panda_link0, panda_link6]]

Failing (RS320: one link, twice)::

    never_collide: [[panda_hand, panda_hand]]

An entry lists links no two of which may collide; one link alone says nothing.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import NEVER_COLLIDE_TOO_FEW_LINKS


def check(context: CheckContext) -> Iterator[Diagnostic]:
    record = context.robot.never_collide
    if record is None:
        return
    for index, links in enumerate(record.entries):
        path = ("never_collide", index)
        if context.links_at(path) is not None and len(links) < 2:
            chosen = f"only '{links[0]}'" if links else "no link"
            yield error(
                context.value(path),
                NEVER_COLLIDE_TOO_FEW_LINKS,
                f"never_collide entry selects {chosen}: an entry names two links or more, no "
                "two of which may collide",
                "write a pair, e.g. [panda_link5, panda_hand], or a glob matching several links",
            )
