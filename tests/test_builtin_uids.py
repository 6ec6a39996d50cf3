from __future__ import annotations

import pytest

from robospec.maniskill.builtin_uids import MANISKILL_UIDS


@pytest.mark.usefixtures("maniskill")
def test_the_builtin_uid_list_equals_maniskills_registry() -> None:
    import mani_skill.envs  # noqa: F401  (imports every agent module)
    from mani_skill.agents.registration import REGISTERED_AGENTS

    builtin = {
        u
        for u, spec in REGISTERED_AGENTS.items()
        if spec.agent_cls.__module__.startswith("mani_skill.")
    }
    assert builtin == MANISKILL_UIDS
