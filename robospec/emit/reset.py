"""Generate the agent's ``reset()``: every episode starts at the spec's reset keyframe.

``BaseEnv.reset`` calls ``agent.reset()`` with no joint positions (``BaseAgent.reset`` then keeps
the joints where they are) and only the scene builders set the joints of the robots they list
by uid, so without this a robospec robot would start each episode where the last one ended.
A caller that passes joint positions (a scene builder resetting a robot it knows, a user) gets
them, as from ``BaseAgent.reset``.

The noise is drawn exactly as ManiSkill's ``TableSceneBuilder`` draws its robots': from the
resetting environment's episode RNG (the batched one under enhanced determinism), for every
joint of each environment being reset, in float64, then kept on the noisy joints only. A seeded
reset therefore repeats it, and the draws leave the episode RNG where the scene builder's
would have, so the task's own randomness is the same as with ManiSkill's robot. The code works
on batches (the GPU simulation resets several environments at once) and is the same on CPU.
"""

from __future__ import annotations

import ast

from robospec.emit.members import function
from robospec.emit.values import const
from robospec.resolve.resolved import ResolvedReset

# the members this module defines: no derived attribute may take these names
RESET_MEMBERS = ("reset", "_keyframe_noise")


def generate_reset(reset: ResolvedReset) -> list[ast.stmt]:
    start = "self.keyframes[KEYFRAME].qpos"
    noisy = reset.qpos_noise > 0
    if noisy:
        start += " + self._keyframe_noise()"
    if reset.with_qvel:
        body = f"""
            if init_qpos is not None:
                super().reset(init_qpos)
                return
            super().reset({start})
            self.robot.set_qvel(self.keyframes[KEYFRAME].qvel)
        """
    else:
        body = f"""
            if init_qpos is None:
                init_qpos = {start}
            super().reset(init_qpos)
        """
    method = function(
        "reset",
        f'''
        def reset(self, init_qpos=None):
            """DOCSTRING"""
        {body}
        ''',
        KEYFRAME=ast.Constant(reset.keyframe),
    )
    doc = method.body[0]
    assert isinstance(doc, ast.Expr) and isinstance(doc.value, ast.Constant)
    doc.value.value = (
        f"Each episode starts at keyframe {reset.keyframe!r} (ManiSkill's tasks reset the "
        "joints\nonly of the robots their scene builders know); given joint positions win."
    )
    return [method, _noise(reset)] if noisy else [method]


def _noise(reset: ResolvedReset) -> ast.FunctionDef:
    quiet = [i for i in range(reset.dof) if i not in set(reset.noise_columns)]
    keep = (
        "noise[:, QUIET] = 0  # drawn for every joint, as the scene builders do, kept on some"
        if quiet
        else ""
    )
    method = function(
        "_keyframe_noise",
        f'''
        def _keyframe_noise(self):
            """DOCSTRING"""
            frame = inspect.currentframe()
            env = None
            while frame is not None and env is None:
                caller = frame.f_locals.get("self")
                if getattr(caller, "scene", None) is self.scene and hasattr(caller, "_episode_rng"):
                    env = caller
                frame = frame.f_back
            if env is None:
                return np.zeros(DOF)
            env_idx = np.flatnonzero(common.to_numpy(self.scene._reset_mask))
            if env._enhanced_determinism:
                noise = env._batched_episode_rng[env_idx].normal(0, STD, DOF)
            else:
                noise = env._episode_rng.normal(0, STD, [len(env_idx), DOF])
            {keep}
            return noise
        ''',
        DOF=ast.Constant(reset.dof),
        STD=const(reset.qpos_noise),
        QUIET=ast.List([ast.Constant(i) for i in quiet], ast.Load()),
    )
    doc = method.body[0]
    assert isinstance(doc, ast.Expr) and isinstance(doc.value, ast.Constant)
    doc.value.value = (
        "Gaussian noise on the keyframe's joint positions, one row per environment being\n"
        "reset, from the resetting environment's episode RNG (none when no environment resets\n"
        "the agent: a call by hand starts at the keyframe itself). The agent holds no\n"
        "reference to its environment: it is the caller whose scene this is (BaseEnv.reset)."
    )
    return method
