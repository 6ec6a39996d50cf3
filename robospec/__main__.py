"""``python -m robospec``: the `robospec` command."""

from robospec.cli import main

main()
