"""RS316: a task-facing member refers to the right kind of entry.

Passing::

    link_states:
      finger_poses: {links: [panda_leftfinger, panda_rightfinger]}
    proprioception: [finger_poses]

Failing (RS316: proprioception names link_states entries; there is no 'finger_pose')::

    proprioception: [finger_pose]

Also: a ``named_links`` entry holding a list where one link is needed (``tcp``, a grasping
finger, ``link_states.<name>.link``), and ``link_states.<name>.links`` naming a
``named_links`` entry that is not a list.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import HELPER_WRONG_KIND
from robospec.diagnostics.suggest import did_you_mean
from robospec.load.source_map import KeyPath


def check(context: CheckContext) -> Iterator[Diagnostic]:
    spec = context.spec
    for name, path in _one_link_places(context):
        if isinstance(spec.named_links.get(name), list):
            yield error(
                context.value(path),
                HELPER_WRONG_KIND,
                f"named link '{name}' is a list; one link is needed here",
            )
    for name, state in spec.link_states.items():
        if isinstance(state.links, str) and not isinstance(spec.named_links.get(state.links), list):
            yield error(
                context.value(("link_states", name, "links")),
                HELPER_WRONG_KIND,
                f"'{state.links}' is not a list in named_links",
                "give a list of links, or name a named_links entry holding a list",
            )
    for index, name in enumerate(spec.proprioception):
        if name not in spec.link_states:
            yield error(
                context.value(("proprioception", index)),
                HELPER_WRONG_KIND,
                f"'{name}' is not a link_states entry",
                did_you_mean(name, spec.link_states),
            )


def _one_link_places(context: CheckContext) -> Iterator[tuple[str, KeyPath]]:
    """Each name written where one link (or a named_links entry of one link) is needed."""
    spec = context.spec
    tcp = spec.tcp
    if isinstance(tcp, str):
        yield tcp, ("tcp",)
    elif tcp is not None:
        if tcp.link:
            yield tcp.link, ("tcp", "link")
        for index, name in enumerate(tcp.midpoint or ()):
            yield name, ("tcp", "midpoint", index)
        if tcp.orientation is not None and tcp.orientation != "midpoint":
            yield tcp.orientation, ("tcp", "orientation")
    for method, grasp in spec.grasping.items():
        for index, finger in enumerate(grasp.fingers):
            yield finger.link, ("grasping", method, "fingers", index, "link")
    for name, state in spec.link_states.items():
        if state.link is not None:
            yield state.link, ("link_states", name, "link")
        elif isinstance(state.links, list):
            for index, link in enumerate(state.links):
                yield link, ("link_states", name, "links", index)
