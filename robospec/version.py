"""robospec's version, which ``robospec --version``, the language server and the package
metadata (pyproject.toml, kept equal by tests/test_architecture.py) all say."""

__version__ = "0.1.0"
