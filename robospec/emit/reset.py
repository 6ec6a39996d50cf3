"""Generate the agent's ``reset()``: every episode starts at the spec's reset keyframe.

``BaseEnv.reset`` calls ``agent.reset()`` with no joint positions (``BaseAgent.reset`` then keeps
the joints where they are) and only the scene builders set the joints of the robots they list
by uid, so without this a robospec robot would start each episode where the last one ended.
A caller that passes joint positions (a scene builder resetting a robot it knows, a user) gets
them, as from ``BaseAgent.reset``.

The noise is drawn from a generator of the agent's own per environment, seeded from the
environment's episode seed whenever the environment seeds a new episode RNG (a seeded reset; every
reset under enhanced determinism): a seeded reset repeats it, an unseeded one draws on, and the
same seeds give the same noise on CPU and GPU. It never draws from the environment's episode
RNG, so the task's own randomness is what it would be with ManiSkill's robot, and where a scene
builder resets the robot itself (a spec standing in under a uid ManiSkill's scenes know), the
builder's draws and the state it sets are exactly those ManiSkill's robot gets. The code works
on batches (the GPU simulation resets several environments at once) and is the same on CPU.
"""

from __future__ import annotations

import ast

from robospec.emit.members import function
from robospec.emit.values import const
from robospec.resolve.resolved import ResolvedReset

# the members this module defines: no derived attribute may take these names
RESET_MEMBERS = ("reset", "_keyframe_noise", "_noise_generators")
# the noise's generator is seeded by (episode seed, NOISE_STREAM): a stream of its own, apart
# from the ones the episode seed starts for the task
NOISE_STREAM = 0x5EED


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
    keep = "noise[:, QUIET] = 0  # drawn for every joint, kept on some" if quiet else ""
    method = function(
        "_keyframe_noise",
        f'''
        def _keyframe_noise(self):
            """DOCSTRING"""
            frame = inspect.currentframe()
            env = None
            while frame is not None and env is None:
                caller = frame.f_locals.get("self")
                ours = getattr(caller, "scene", None) is self.scene
                if ours and hasattr(caller, "_batched_episode_rng"):
                    env = caller
                frame = frame.f_back
            if env is None:
                return np.zeros(DOF)
            env_idx = np.flatnonzero(common.to_numpy(self.scene._reset_mask))
            generators = self.__dict__.setdefault("_noise_generators", {{}})
            noise = np.zeros((len(env_idx), DOF))
            for row in range(len(env_idx)):
                i = int(env_idx[row])
                episode_rng = env._batched_episode_rng[i]
                if generators.get(i, [None])[0] is not episode_rng:
                    seed = [int(env._episode_seed[i]), STREAM]
                    generators[i] = [episode_rng, np.random.RandomState(seed)]
                noise[row] = generators[i][1].normal(0, STD, DOF)
            {keep}
            return noise
        ''',
        DOF=ast.Constant(reset.dof),
        STD=const(reset.qpos_noise),
        QUIET=ast.List([ast.Constant(i) for i in quiet], ast.Load()),
        STREAM=ast.Constant(NOISE_STREAM),
    )
    doc = method.body[0]
    assert isinstance(doc, ast.Expr) and isinstance(doc.value, ast.Constant)
    doc.value.value = (
        "Gaussian noise on the keyframe's joint positions, one row per environment being\n"
        "reset, from a generator of the agent's own per environment, seeded from the episode\n"
        "seed whenever the environment seeds a new episode RNG (none when no environment\n"
        "resets the agent: a call by hand starts at the keyframe itself). The agent holds no\n"
        "reference to its environment: it is the caller whose scene this is (BaseEnv.reset)."
    )
    return method
