"""A hook that ends the process the way a native crash in SAPIEN or PhysX does (SIGABRT), for
tests/test_check_isolation.py: no small robot description makes SAPIEN crash reliably."""

from __future__ import annotations

import os
from typing import Any


def abort_process(agent: Any) -> None:
    os.abort()


class _TcpLost(RuntimeError):
    pass


def _lost_tcp(agent: Any) -> Any:
    raise _TcpLost("this robot's tcp link was never found")


# an agent member a task reads at reset (PushCube-v1 reads agent.tcp for its observation) that
# raises: the task crashes inside ManiSkill's reset, for tests/test_tasks_scaffold.py (RS527)
lost_tcp = property(_lost_tcp)
