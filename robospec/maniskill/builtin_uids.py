"""The agent uids ManiSkill 3.0.1 registers itself. A spec may not reuse one: ManiSkill's
``register_agent`` would skip the spec's class with only a warning — unless the spec or the
caller says the replacement is on purpose (:func:`override_allowed`). A test keeps this list
equal to ``REGISTERED_AGENTS`` of the installed ManiSkill."""

from __future__ import annotations

Overrides = bool | frozenset[str]
"""Uids a caller lets specs take over (``register(..., override=...)``): True for any."""


def override_allowed(uid: str, declared: bool, overrides: Overrides) -> bool:
    """Whether a spec's agent may replace one already registered under ``uid``: the spec
    declares ``override: true``, or the caller allows it for this uid or for every uid."""
    return declared or overrides is True or (isinstance(overrides, frozenset) and uid in overrides)


MANISKILL_UIDS: frozenset[str] = frozenset(
    {
        "allegro_hand_left",
        "allegro_hand_right",
        "allegro_hand_right_touch",
        "anymal_c",
        "dclaw",
        "fetch",
        "fixed_inspire_hand_left",
        "fixed_inspire_hand_right",
        "floating_ability_hand_right",
        "floating_inspire_hand_left",
        "floating_inspire_hand_right",
        "floating_panda_gripper",
        "floating_robotiq_2f_85_gripper",
        "googlerobot",
        "humanoid",
        "koch-v1.1",
        "panda",
        "panda_stick",
        "panda_wristcam",
        "so100",
        "stompy",
        "trifingerpro",
        "unitree_g1",
        "unitree_g1_simplified_legs",
        "unitree_g1_simplified_upper_body",
        "unitree_g1_simplified_upper_body_right_arm",
        "unitree_g1_simplified_upper_body_with_head_camera",
        "unitree_go2",
        "unitree_go2_simplified_locomotion",
        "unitree_h1",
        "unitree_h1_simplified",
        "ur_10e",
        "widowx250s",
        "widowx250s_bridgedataset_flat_table",
        "widowx250s_bridgedataset_sink",
        "widowxai",
        "widowxai_wristcam",
        "xarm6_nogripper",
        "xarm6_nogripper_wristcam",
        "xarm6_robotiq",
        "xarm6_robotiq_wristcam",
        "xarm7_ability",
        "xlerobot",
    }
)
