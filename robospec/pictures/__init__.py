"""Pictures of a robot without a GPU: ``robospec doc --images``.

The robot at each keyframe from standard viewpoints, and what each of its cameras sees from
its mount (alone, and at a table with a cube), drawn by MuJoCo's renderer on whatever OpenGL
the machine has — Mesa's EGL (llvmpipe) on a machine without a GPU. Then the cameras are
judged from a segmentation render of the same views (:mod:`.camera_checks`).

The stages, data flowing one way:

- :mod:`.gl` — MuJoCo, imported to draw offscreen (EGL unless ``MUJOCO_GL`` says otherwise);
- :mod:`.meshes` — a mesh file as coloured triangle sets (trimesh reads .dae/.glb/.obj/.stl/
  .ply; MuJoCo reads STL and OBJ only), kept in robospec's cache folder;
- :mod:`.posed` — the robot's shapes placed in the world at a keyframe, each link where the
  format's own forward kinematics puts it (:mod:`robospec.kinematics.forward`: yourdfpy for a
  URDF, MuJoCo for an MJCF);
- :mod:`.views` — where each picture is taken from and how it projects (SAPIEN's camera
  conventions);
- :mod:`.stage` — the ground, the table and the cube;
- :mod:`.renderer` — one MuJoCo model of all of it, drawn per view (colour or segmentation);
- :mod:`.album` — every picture of a card, and the camera findings.

Needs the ``render`` extra (mujoco, trimesh, pycollada) and an OpenGL that works offscreen
(Debian's ``libegl1``); without them ``doc --images`` says so (RS660, RS661).
"""
