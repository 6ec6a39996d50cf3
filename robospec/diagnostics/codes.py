"""The stable diagnostic codes. A code is never reused; retired codes stay listed.

Ranges: RS0xx reading files (spec syntax, description files), RS1xx spec schema, RS2xx references
into the robot description, RS3xx semantic checks, RS4xx `robospec import`, RS5xx physics
checks (`robospec check`), RS6xx writing files and the authoring commands (`robospec build`,
`inspect`, `new`, `doc`), RS9xx internal errors.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Code:
    code: str
    title: str


_CODES = [
    # -- reading the spec
    Code("RS001", "spec file cannot be read"),
    Code("RS002", "spec syntax error"),
    Code("RS003", "duplicate key"),
    Code("RS004", "spec document is empty or not a mapping"),
    Code("RS005", "unsupported spec file type"),
    Code("RS006", "spec too large, too deep or too many aliases"),
    Code("RS010", "invalid arithmetic expression"),
    # -- reading the robot description
    Code("RS050", "robot description file not found"),
    Code("RS051", "robot description is not well-formed XML"),
    Code("RS052", "robot description structure is invalid"),
    Code("RS053", "xacro expansion failed"),
    Code("RS054", "xacro expansion exceeded its time or memory limit"),
    Code("RS055", "robot description not downloaded yet"),
    # -- what SAPIEN's URDF loader needs of a description's files, masses and text (RS056-RS069)
    Code("RS056", "mesh file not found"),
    Code("RS057", "mesh file SAPIEN cannot read"),
    Code("RS058", "ROS package not found"),
    Code("RS059", "inertia SAPIEN rejects"),
    Code("RS060", "negative mass"),
    Code("RS061", "inertial SAPIEN ignores"),
    Code("RS062", "inertia breaks the triangle inequality"),
    Code("RS063", "unexpanded xacro or roslaunch substitution"),
    Code("RS064", "transmission SAPIEN's URDF parser cannot read"),
    # -- what ManiSkill's MJCF loader drops or reads differently (RS070-RS089)
    Code("RS070", "MJCF equality constraint not loaded"),
    Code("RS071", "MJCF tendon not loaded"),
    Code("RS072", "MJCF contact exclusion or pair not loaded"),
    Code("RS073", "MJCF contype/conaffinity not followed"),
    Code("RS074", "MJCF mesh scale from a default class not applied"),
    Code("RS075", "MJCF masses and inertias not used"),
    Code("RS076", "moving MJCF body loaded without mass"),
    Code("RS077", "MJCF actuator that drives no joint"),
    Code("RS078", "MJCF geom group not drawn"),
    Code("RS079", "MJCF geom type not loaded"),
    Code("RS080", "MJCF orientation read differently"),
    Code("RS081", "too many MJCF bodies for the loader's collision bits"),
    Code("RS082", "MJCF include not read"),
    Code("RS083", "MJCF wrapper body's pose dropped"),
    Code("RS084", "MJCF joint attribute not loaded"),
    Code("RS085", "MJCF mesh the loader cannot resolve"),
    # -- schema
    Code("RS101", "unknown key"),
    Code("RS102", "invalid value"),
    Code("RS103", "missing required field"),
    Code("RS104", "unsupported spec version"),
    Code("RS105", "invalid identifier"),
    # -- references into the description and the spec
    Code("RS201", "unknown joint"),
    Code("RS202", "unknown link"),
    Code("RS203", "unknown group"),
    Code("RS204", "unknown controller"),
    Code("RS205", "unknown material"),
    Code("RS206", "link rule matches no link"),
    Code("RS207", "joint pattern matches no joint"),
    Code("RS208", "controller inheritance is circular"),
    Code("RS209", "group definition is circular"),
    Code("RS210", "group has the name of a joint"),
    Code("RS220", "Python reference cannot be used"),
    # -- semantic checks
    Code("RS301", "joint driven by more than one controller"),
    Code("RS302", "active joint not driven in a control mode"),
    Code("RS303", "keyframe qpos has the wrong length"),
    Code("RS304", "keyframe value outside the joint limits"),
    Code("RS305", "inconsistent mimic map"),
    Code("RS306", "duplicate uid"),
    Code("RS307", "collision bit reserved by ManiSkill"),
    Code("RS308", "controller is missing a field its type needs"),
    Code("RS309", "URDF mimic joint simulated by PhysX"),
    Code("RS310", "joint listed twice in one controller"),
    Code("RS311", "joint is not active"),
    Code("RS312", "link rule needs a material"),
    Code("RS313", "keyframe sets a joint twice"),
    Code("RS314", "camera needs exactly one of fov and intrinsic"),
    Code("RS315", "invalid joint for this controller type"),
    Code("RS316", "helper refers to the wrong kind of entry"),
    Code("RS317", "agent member defined twice"),
    Code("RS318", "end-effector controller too weak to track"),
    Code("RS319", "actions normalized over unbounded joint limits"),
    Code("RS320", "never_collide entry selects fewer than two links"),
    Code("RS321", "never_collide also disables pairs it does not list"),
    Code("RS322", "never_collide has no effect with disable_self_collisions"),
    Code("RS323", "no collision-group bit free for never_collide"),
    Code("RS324", "link rule on an MJCF robot"),
    Code("RS325", "end-effector controller without a URDF for its IK"),
    # -- import: an existing ManiSkill agent class -> a spec (RS400-RS419)
    Code("RS400", "import target is not module:Class"),
    Code("RS401", "import target module cannot be imported"),
    Code("RS402", "import target class not found"),
    Code("RS403", "import target is not a ManiSkill agent class"),
    Code("RS404", "agent class data cannot be read"),
    Code("RS405", "upstream config value is rejected by its config class"),
    Code("RS406", "upstream names a link the description does not have"),
    Code("RS407", "upstream normalizes actions over unbounded joints"),
    Code("RS408", "upstream gains look like arguments passed by position"),
    Code("RS409", "agent code the spec does not reproduce"),
    Code("RS410", "robot description is not installed"),
    Code("RS411", "imported uid is ManiSkill's own"),
    Code("RS412", "import output file already exists"),
    Code("RS413", "upstream data a spec cannot express"),
    Code("RS414", "upstream keyframe does not fit the robot description"),
    Code("RS415", "upstream drives a joint with two controllers in one mode"),
    # -- physics checks (robospec check)
    Code("RS501", "keyframe drifts while held"),
    Code("RS502", "state goes NaN under random actions"),
    Code("RS503", "joint limit violated under random actions"),
    Code("RS504", "runaway velocity under random actions"),
    Code("RS505", "controller too slow to track a step"),
    Code("RS506", "controller unstable or underdamped"),
    Code("RS507", "controller settles away from its target"),
    Code("RS508", "links touch each other at a keyframe"),
    Code("RS510", "robot cannot be loaded for checking"),
    Code("RS511", "no CUDA device for --gpu"),
    Code("RS512", "no render device for --render"),
    Code("RS513", "robospec demo cannot open the viewer"),
    Code("RS514", "ManiSkill or SAPIEN cannot load the robot"),
    Code("RS515", "checking the robot killed the process"),
    Code("RS516", "a control mode crashes ManiSkill"),
    Code("RS517", "a check crashed inside ManiSkill or SAPIEN"),
    Code("RS518", "floating robot hovers under gravity compensation"),
    Code("RS519", "the root ManiSkill loads is not the one the spec says"),
    Code("RS520", "two ManiSkill distributions installed over each other"),
    # -- writing files, authoring commands: robospec build, inspect, new, doc (RS600-RS619)
    Code("RS600", "file is not a robot description robospec reads"),
    Code("RS601", "spec file already exists"),
    Code("RS602", "robot has no active joints to control"),
    Code("RS603", "output file cannot be written"),
    Code("RS604", "output would overwrite a file robospec did not write"),
    Code("RS605", "scaffold's rest keyframe still has links touching"),
    Code("RS606", "scaffold's rest keyframe could not be checked in ManiSkill"),
    Code("RS607", "robospec optimize cannot optimize this robot as asked"),
    Code("RS608", "links named only in Python code may be merged away"),
    # -- robospec tune (RS620-RS639)
    Code("RS620", "a controller cannot meet its tuning targets"),
    Code("RS621", "--controller names no controller a control mode uses"),
    Code("RS622", "robospec tune cannot write the new gains into the spec"),
    # -- robospec tune --reference: fitting gains to a recorded trajectory (RS640-RS659)
    Code("RS640", "reference trajectory file cannot be read"),
    Code("RS641", "reference trajectory file is malformed"),
    Code("RS642", "reference trajectory value is not a finite number"),
    Code("RS643", "reference trajectory too short or out of time order"),
    Code("RS644", "reference joint is not a joint of the robot"),
    Code("RS645", "reference joint not driven by a joint-position controller"),
    Code("RS646", "reference joint does not move"),
    Code("RS647", "--reference mujoco needs an MJCF robot with position actuators"),
    Code("RS648", "simulated robot cannot match the reference"),
    Code("RS649", "reference does not determine stiffness and damping each"),
    Code("RS650", "reference fit crashed"),
    # -- robospec optimize --profile fast (RS670-RS689)
    Code("RS670", "unknown optimize profile"),
    Code("RS671", "--max-error out of range"),
    Code("RS672", "--contact-offset out of range"),
    Code("RS673", "a link the spec names would be merged away"),
    Code("RS674", "collision meshes fit no primitive within the bound"),
    Code("RS675", "unknown robot category"),
    Code("RS676", "an option that applies only to another profile or shapes method"),
    # -- internal
    Code("RS900", "internal error"),
]

CODES: dict[str, Code] = {c.code: c for c in _CODES}
