"""What ManiSkill and SAPIEN print is gathered, not shown: each distinct message once, with a
count, an example path and what it means (robospec.maniskill.upstream_output)."""

from __future__ import annotations

import os
import sys
import warnings

import pytest

from robospec.maniskill.upstream_output import UpstreamLog, captured_output, parse_line

SAPIEN_STL = (
    "[2026-11-24 07:20:27.678] [SAPIEN] [warning] loading multiple convex collision meshes from "
    "STL file is unsupported and can result in invalid collision meshes. Do you mean to load a "
    "single convex mesh instead?"
)


def test_each_kind_of_line_is_read_with_its_source_and_level() -> None:
    assert parse_line(SAPIEN_STL)[:2] == ("SAPIEN", "warning")  # type: ignore[index]
    maniskill = (
        "\x1b[33;1m2026-11-24 07:42:01,175 - mani_skill  - WARNING - rs_panda is not in the "
        "task's list of supported robots. Code may not run as intended\x1b[0m"
    )
    assert parse_line(maniskill) == (
        "mani_skill",
        "warning",
        "rs_panda is not in the task's list of supported robots. Code may not run as intended",
    )
    assert parse_line("plain text  ") == ("output", "", "plain text")
    assert parse_line("   ") is None


def test_messages_that_differ_only_in_a_path_count_as_one_with_the_first_path_as_example() -> None:
    log = UpstreamLog()
    log.feed(
        "[2026-11-24 05:46:46.973] [SAPIEN] [error] File not found: /robots/meshes/arm_1.STL\n"
        + SAPIEN_STL
        + "\n[2026-11-24 05:46:46.974] [SAPIEN] [error] File not found: /robots/meshes/arm_2.STL\n"
    )
    missing, stl = log.messages()
    assert (missing.text, missing.count, missing.example) == (
        "File not found: <path>",
        2,
        "/robots/meshes/arm_1.STL",
    )
    assert missing.meaning is not None and "missing collision mesh" in missing.meaning
    assert stl.count == 1 and stl.meaning is not None and "convex hull" in stl.meaning
    assert missing.describe().startswith("SAPIEN error (2x): File not found: <path> (e.g. ")


def test_words_with_a_slash_are_not_taken_for_paths() -> None:
    log = UpstreamLog()
    log.feed("ValueError: I/O operation on closed file.\nFile not found: /robots/arm.STL\n")
    closed, missing = log.messages()
    assert (closed.text, closed.example) == ("ValueError: I/O operation on closed file.", None)
    assert (missing.text, missing.example) == ("File not found: <path>", "/robots/arm.STL")


def test_captured_output_takes_file_descriptor_writes_and_warnings_off_the_terminal(
    capfd: pytest.CaptureFixture[str],
) -> None:
    with captured_output() as output:
        os.write(2, (SAPIEN_STL + "\n").encode())  # as SAPIEN's C++ logger writes
        os.write(1, (SAPIEN_STL + "\n").encode())
        print("a line on stdout")
        warnings.warn(
            "Failed to find system libvulkan. Fallback to SAPIEN builtin libvulkan.", stacklevel=1
        )
        warnings.warn("a deprecation nobody asked to see", DeprecationWarning, stacklevel=1)
        sys.stderr.write("text on stderr\n")
    shown = capfd.readouterr()
    assert shown.out == "" and shown.err == ""
    said = {(m.source, m.level, m.text): m.count for m in output.messages()}
    assert said[("SAPIEN", "warning", parse_line(SAPIEN_STL)[2])] == 2  # type: ignore[index]
    assert said[("output", "", "a line on stdout")] == 1
    assert said[("output", "", "text on stderr")] == 1
    vulkan = [m for m in output.messages() if m.source == "Python"]
    assert [(m.level, m.meaning is not None) for m in vulkan] == [("UserWarning", True)]
    # after the block, output goes where it went before
    print("after")
    assert capfd.readouterr().out == "after\n"


def test_a_logger_made_inside_a_captured_block_still_speaks_in_the_next_one(
    capfd: pytest.CaptureFixture[str],
) -> None:
    """ManiSkill makes its logger's StreamHandler when mani_skill is first imported, which the
    demo does inside a captured block: the handler takes that block's sys.stderr. After the
    block that stream is closed; a later message must still be gathered, not end in Python's
    "--- Logging error ---" traceback."""
    import logging

    logger = logging.getLogger("robospec-test-upstream")
    logger.propagate = False
    try:
        with captured_output():
            handler = logging.StreamHandler()  # as mani_skill.utils.logging_utils does
            handler.setFormatter(
                logging.Formatter("%(asctime)s - %(name)s - %(levelname)s - %(message)s")
            )
            logger.addHandler(handler)
        with captured_output() as output:
            logger.warning("rs_panda is not in the task's list of supported robots")
        shown = capfd.readouterr()
        assert "Logging error" not in shown.err + shown.out
        said = [(m.source, m.level, m.text) for m in output.messages()]
        assert said == [
            (
                "robospec-test-upstream",
                "warning",
                "rs_panda is not in the task's list of supported robots",
            )
        ]
    finally:
        logger.handlers.clear()
