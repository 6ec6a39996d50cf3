"""One section of docs/performance.md: a fixed title and the measured Markdown under it."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Section:
    title: str  # fixed per benchmark: tests/test_benchmarks.py checks the doc has every one
    body: str
    meets_target: bool = True

    def markdown(self) -> str:
        return f"## {self.title}\n\n{self.body.strip()}\n"
