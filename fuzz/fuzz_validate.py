"""Fuzz robospec's compile step (read → model → resolve → check) for longer than CI does.

Every input is written as a spec (YAML or TOML, chosen by its first byte) beside links to the
folders the shipped specs use, and compiled. A crash is any exception, an internal error
(RS900) or a diagnostic without a known code, a line and column >= 1 and a line the spec has.

    python fuzz/fuzz_validate.py --seconds 600            # atheris, if installed
    python fuzz/fuzz_validate.py --seconds 600 --hypothesis

With atheris (``pip install -e ".[fuzz]"``; Linux wheels) the run is coverage-guided, seeded with
specs/ and tests/specs/positive, and extra arguments go to libFuzzer (e.g. a corpus folder to
keep, ``-jobs=4``). Without it, or with ``--hypothesis``, the property tests of
tests/test_fuzz_properties.py run round after round, each with ``ROBOSPEC_FUZZ_SCALE``
(default 5) times their CI budget of fresh random examples, until ``--seconds`` run out. See
docs/hardening.md.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SEED_FOLDERS = [ROOT / "specs", ROOT / "tests" / "specs" / "positive"]
CRASHES = ROOT / "fuzz" / "crashes"  # libFuzzer writes each crashing input here (git-ignored)


def _arguments(argv: list[str]) -> tuple[argparse.Namespace, list[str]]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=int, default=300, help="time budget (default 300)")
    parser.add_argument(
        "--hypothesis", action="store_true", help="use the hypothesis properties, not atheris"
    )
    return parser.parse_known_args(argv)


def main(argv: list[str]) -> int:
    options, rest = _arguments(argv)
    if not options.hypothesis:
        try:
            import atheris  # noqa: F401
        except ImportError:
            print("atheris is not installed: running the hypothesis properties instead")
        else:
            return _atheris(options.seconds, rest)
    return _hypothesis(options.seconds)


def _hypothesis(seconds: int) -> int:
    """Rounds of the property tests, each with fresh random examples, until time runs out."""
    import time

    deadline = time.monotonic() + seconds
    scale = os.environ.get("ROBOSPEC_FUZZ_SCALE", "5")
    rounds = 0
    while time.monotonic() < deadline:
        left = max(int(deadline - time.monotonic()), 1)
        command = [sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider"]
        command.append(str(ROOT / "tests" / "test_fuzz_properties.py"))
        environment = {**os.environ, "ROBOSPEC_FUZZ_SCALE": scale}
        try:
            result = subprocess.run(command, cwd=ROOT, env=environment, timeout=left)
        except subprocess.TimeoutExpired:
            # pytest -x ends at the first failure, so a round still running has found none
            print("the time ran out during a round; its examples so far passed")
            break
        rounds += 1
        if result.returncode != 0:
            return result.returncode
    print(f"{rounds} round(s) of the properties at {scale}x their CI budget: no failure")
    return 0


def _atheris(seconds: int, rest: list[str]) -> int:
    import atheris

    with atheris.instrument_imports():
        from robospec.diagnostics.codes import CODES
        from robospec.pipeline import compile_spec

    CRASHES.mkdir(exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix="robospec-fuzz-"))
    for folder in SEED_FOLDERS:  # relative description paths resolve as beside the seeds
        for child in folder.iterdir():
            if child.is_dir() and not (scratch / child.name).exists():
                (scratch / child.name).symlink_to(child, target_is_directory=True)
    corpus = scratch / "corpus"
    corpus.mkdir()
    for folder in SEED_FOLDERS:
        for spec in sorted(folder.rglob("*")):
            if spec.suffix in (".yaml", ".toml") and b"robospec" in spec.read_bytes()[:400]:
                marker = b"t" if spec.suffix == ".toml" else b"y"
                (corpus / spec.name).write_bytes(marker + spec.read_bytes())

    def one_input(data: bytes) -> None:
        suffix = ".toml" if data[:1] == b"t" else ".yaml"
        raw = data[1:]
        path = scratch / ("spec" + suffix)
        path.write_bytes(raw)
        lines = max(len(raw.decode("utf-8", "replace").splitlines()), 1)
        for d in compile_spec(path).diagnostics:
            where = d.location
            if d.code not in CODES or d.code == "RS900" or where.line < 1 or where.column < 1:
                raise AssertionError(d.format_text())
            if where.file == str(path) and where.line > lines:
                raise AssertionError(f"line {where.line} of a {lines}-line spec: {d.format_text()}")

    try:
        flags = [f"-max_total_time={seconds}", f"-artifact_prefix={CRASHES}/", *rest]
        atheris.Setup([sys.argv[0], *flags, str(corpus)], one_input)
        atheris.Fuzz()
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
