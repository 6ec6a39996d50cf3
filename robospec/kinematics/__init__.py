"""What several tools read from a robot description's structure: its kinematic tree
(:mod:`.tree`), where its links are at given joint values (:mod:`.forward`: yourdfpy's forward
kinematics for a URDF, :mod:`.urdf_poses`; MuJoCo's for an MJCF, :mod:`.mjcf_poses`; SAPIEN's
for a robot loaded in ManiSkill, :mod:`.simulated`), what kind of body it is
(:mod:`.morphology`: legs, wheels, arms), and an MJCF's bodies as written where MuJoCo's compiled
model does not keep what a tool needs (:mod:`.mjcf_model`: ManiSkill's masses come from the
geoms). ``new``, ``doc --images`` and ``optimize`` share them; only :mod:`.simulated` imports
ManiSkill, and only when asked."""
