"""``python -m robospec.cli``: the `robospec` command."""

from robospec.cli import main

main()
