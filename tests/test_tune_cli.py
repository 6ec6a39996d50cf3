"""robospec tune's command line without simulation: a --controller the spec does not use is
RS621, before any worker starts."""

from __future__ import annotations

from conftest import PANDA_SPEC, invoke_robospec


def test_an_unknown_controller_is_rs621_listing_the_specs_controllers() -> None:
    result = invoke_robospec("tune", str(PANDA_SPEC), "--controller", "arm_post")
    assert result.exit_code == 1
    assert "<command line>:1:1: error[RS621] --controller 'arm_post'" in result.output
    assert "arm_pos" in result.output
