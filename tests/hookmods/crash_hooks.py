"""A hook that ends the process the way a native crash in SAPIEN or PhysX does (SIGABRT), for
tests/test_check_isolation.py: no small robot description makes SAPIEN crash reliably."""

from __future__ import annotations

import os
from typing import Any


def abort_process(agent: Any) -> None:
    os.abort()
