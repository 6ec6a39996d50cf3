"""The stable diagnostic codes. A code is never reused; retired codes stay listed.

Ranges: RS0xx reading files (spec syntax, description files), RS1xx spec schema, RS2xx references
into the robot description, RS3xx semantic checks, RS4xx `robospec import`, RS5xx physics
checks (`robospec check`), RS6xx writing files and the authoring commands (`robospec build`,
`inspect`, `new`, `doc`), RS7xx descriptions robospec derives (mends applied to a copy, parts
composed into one), RS9xx internal errors.

Each code is a constant here, and modules name it by that constant
(``error(location, UNKNOWN_JOINT, ...)``), never by its text: this list is the code's one home,
and a misspelt name fails to import where a misspelt string would report a code that is not
listed (tests/test_architecture.py holds modules to it).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Code:
    code: str
    title: str


_CODES: list[Code] = []


def _code(code: str, title: str) -> str:
    """Register a code and its title; the constant it is assigned to is how modules name it."""
    _CODES.append(Code(code, title))
    return code


# -- reading the spec
SPEC_UNREADABLE = _code("RS001", "spec file cannot be read")
SPEC_SYNTAX = _code("RS002", "spec syntax error")
DUPLICATE_KEY = _code("RS003", "duplicate key")
SPEC_NOT_A_MAPPING = _code("RS004", "spec document is empty or not a mapping")
SPEC_FILE_TYPE = _code("RS005", "unsupported spec file type")
SPEC_TOO_LARGE = _code("RS006", "spec too large, too deep or too many aliases")
BAD_EXPRESSION = _code("RS010", "invalid arithmetic expression")
STRAY_INDENTATION = _code("RS011", "YAML indentation that lines up with nothing")
TAB_INDENTATION = _code("RS012", "tab in YAML indentation")
UNQUOTED_TOML_TEXT = _code("RS013", "TOML text value without quotes")
COLON_IN_PLAIN_VALUE = _code("RS014", "': ' inside a plain YAML value")
UNBALANCED_BRACKET = _code(
    "RS015",
    "bracket, brace or quote never closed, closed by the wrong one or twice",
)
# -- reading the robot description
DESCRIPTION_NOT_FOUND = _code("RS050", "robot description file not found")
MALFORMED_XML = _code("RS051", "robot description is not well-formed XML")
INVALID_STRUCTURE = _code("RS052", "robot description structure is invalid")
XACRO_FAILED = _code("RS053", "xacro expansion failed")
XACRO_OVER_LIMIT = _code("RS054", "xacro expansion exceeded its time or memory limit")
NOT_DOWNLOADED = _code("RS055", "robot description not downloaded yet")
# -- what SAPIEN's URDF loader needs of a description's files, masses and text (RS056-RS069)
MESH_NOT_FOUND = _code("RS056", "mesh file not found")
MESH_UNREADABLE = _code("RS057", "mesh file SAPIEN cannot read")
PACKAGE_NOT_FOUND = _code("RS058", "ROS package not found")
INVALID_INERTIA = _code("RS059", "inertia SAPIEN rejects")
NEGATIVE_MASS = _code("RS060", "negative mass")
IGNORED_INERTIAL = _code("RS061", "inertial SAPIEN ignores")
TRIANGLE_INEQUALITY = _code("RS062", "inertia breaks the triangle inequality")
LEFTOVER_SUBSTITUTION = _code("RS063", "unexpanded xacro or roslaunch substitution")
BAD_TRANSMISSION = _code("RS064", "transmission SAPIEN's URDF parser cannot read")
# -- what ManiSkill's MJCF loader drops or reads differently (RS070-RS089)
MJCF_EQUALITY = _code("RS070", "MJCF equality constraint not loaded")
MJCF_TENDON = _code("RS071", "MJCF tendon not loaded")
MJCF_CONTACT = _code("RS072", "MJCF contact exclusion or pair not loaded")
MJCF_COLLISION_FILTER = _code("RS073", "MJCF contype/conaffinity not followed")
MJCF_MESH_SCALE = _code("RS074", "MJCF mesh scale from a default class not applied")
MJCF_MASSES = _code("RS075", "MJCF masses and inertias not used")
MJCF_NO_MASS = _code("RS076", "moving MJCF body loaded without mass")
MJCF_ACTUATOR = _code("RS077", "MJCF actuator that drives no joint")
MJCF_VISUAL_GROUP = _code("RS078", "MJCF geom group not drawn")
MJCF_GEOM_TYPE = _code("RS079", "MJCF geom type not loaded")
MJCF_ORIENTATION = _code("RS080", "MJCF orientation read differently")
MJCF_COLLISION_BITS = _code("RS081", "too many MJCF bodies for the loader's collision bits")
MJCF_UNREAD_INCLUDE = _code("RS082", "MJCF include not read")
MJCF_SKIPPED_WRAPPER = _code("RS083", "MJCF wrapper body's pose dropped")
MJCF_JOINT_ATTRIBUTES = _code("RS084", "MJCF joint attribute not loaded")
MJCF_MESH_UNRESOLVED = _code("RS085", "MJCF mesh the loader cannot resolve")
MJCF_DEGREES = _code("RS086", "MJCF angles in degrees by default")
MIRRORED_MESH = _code("RS087", "collision mesh mirrored by a negative scale")
MILLIMETRES = _code("RS088", "description lengths look like millimetres")
INERTIA_FOR_SIZE = _code("RS089", "inertia far too large or small for the link's shapes")
TINY_MASS = _code("RS090", "mass under a gram beside heavy links")
NO_RATE_LIMIT = _code("RS091", "joint without an effort or velocity limit")
XACRO_CONTENT = _code("RS092", "a file named as URDF is xacro: expanded as xacro")
MESH_CONTENTS = _code("RS093", "collision mesh PhysX can build no shape from")
MJCF_REPEATED_ASSET = _code("RS094", "MJCF asset name defined twice")
MJCF_UNAXED_JOINT = _code("RS095", "MJCF joint without an axis turned about x")
# -- schema
UNKNOWN_KEY = _code("RS101", "unknown key")
INVALID_VALUE = _code("RS102", "invalid value")
MISSING_FIELD = _code("RS103", "missing required field")
SPEC_VERSION = _code("RS104", "unsupported spec version")
INVALID_IDENTIFIER = _code("RS105", "invalid identifier")
OUTSIDE_PHYSICAL_RANGE = _code("RS106", "number outside its physical range")
UNKNOWN_SILENCED_CODE = _code("RS107", "silence names no robospec code")
# -- references into the description and the spec
UNKNOWN_JOINT = _code("RS201", "unknown joint")
UNKNOWN_LINK = _code("RS202", "unknown link")
UNKNOWN_GROUP = _code("RS203", "unknown group")
UNKNOWN_CONTROLLER = _code("RS204", "unknown controller")
UNKNOWN_MATERIAL = _code("RS205", "unknown material")
LINK_RULE_MATCHES_NONE = _code("RS206", "link rule matches no link")
JOINT_PATTERN_MATCHES_NONE = _code("RS207", "joint pattern matches no joint")
CIRCULAR_INHERITANCE = _code("RS208", "controller inheritance is circular")
CIRCULAR_GROUP = _code("RS209", "group definition is circular")
GROUP_NAMED_AS_JOINT = _code("RS210", "group has the name of a joint")
UNKNOWN_KEYFRAME = _code("RS211", "unknown keyframe")
UNUSABLE_PYTHON_REFERENCE = _code("RS220", "Python reference cannot be used")
# -- semantic checks
JOINT_DRIVEN_TWICE = _code("RS301", "joint driven by more than one controller")
JOINT_NOT_DRIVEN = _code("RS302", "active joint not driven in a control mode")
KEYFRAME_LENGTH = _code("RS303", "keyframe qpos has the wrong length")
KEYFRAME_OUTSIDE_LIMITS = _code("RS304", "keyframe value outside the joint limits")
INCONSISTENT_MIMIC = _code("RS305", "inconsistent mimic map")
DUPLICATE_UID = _code("RS306", "duplicate uid")
RESERVED_COLLISION_BIT = _code("RS307", "collision bit reserved by ManiSkill")
CONTROLLER_FIELD_MISSING = _code("RS308", "controller is missing a field its type needs")
URDF_MIMIC_SIMULATED = _code("RS309", "URDF mimic joint simulated by PhysX")
JOINT_LISTED_TWICE = _code("RS310", "joint listed twice in one controller")
JOINT_NOT_ACTIVE = _code("RS311", "joint is not active")
LINK_RULE_WITHOUT_MATERIAL = _code("RS312", "link rule needs a material")
KEYFRAME_SETS_JOINT_TWICE = _code("RS313", "keyframe sets a joint twice")
CAMERA_FOV_OR_INTRINSIC = _code("RS314", "camera needs exactly one of fov and intrinsic")
JOINT_WRONG_FOR_CONTROLLER = _code("RS315", "invalid joint for this controller type")
HELPER_WRONG_KIND = _code("RS316", "helper refers to the wrong kind of entry")
MEMBER_DEFINED_TWICE = _code("RS317", "agent member defined twice")
EE_CONTROLLER_TOO_WEAK = _code("RS318", "end-effector controller too weak to track")
UNBOUNDED_NORMALIZATION = _code("RS319", "actions normalized over unbounded joint limits")
NEVER_COLLIDE_TOO_FEW_LINKS = _code("RS320", "never_collide entry selects fewer than two links")
NEVER_COLLIDE_OVERREACHES = _code("RS321", "never_collide also disables pairs it does not list")
NEVER_COLLIDE_WITHOUT_EFFECT = _code(
    "RS322",
    "never_collide has no effect with disable_self_collisions",
)
NO_FREE_COLLISION_BIT = _code("RS323", "no collision-group bit free for never_collide")
LINK_RULE_ON_MJCF = _code("RS324", "link rule on an MJCF robot")
EE_CONTROLLER_WITHOUT_URDF = _code("RS325", "end-effector controller without a URDF for its IK")
RESET_WITHOUT_QPOS = _code("RS326", "reset keyframe without joint positions")
TASK_MEMBER_UNDEFINED = _code("RS330", "a task calls an agent member the spec does not define")
UNKNOWN_TASK = _code("RS331", "unknown ManiSkill task")
# -- mechanisms: closed loops, planar bases, touch sensors (RS340-RS349)
LOOP_BETWEEN_RIGID_LINKS = _code(
    "RS340",
    "closed loop between links that cannot move against each other",
)
PLANAR_BASE_NOTHING_DRIVES = _code("RS341", "planar base on a robot with nothing that drives")
PLANAR_BASE_ON_FLOATING_ROOT = _code("RS342", "planar base on a robot whose root floats")
# -- import: an existing ManiSkill agent class -> a spec (RS400-RS419)
IMPORT_TARGET_FORM = _code("RS400", "import target is not module:Class")
IMPORT_MODULE_UNIMPORTABLE = _code("RS401", "import target module cannot be imported")
IMPORT_CLASS_NOT_FOUND = _code("RS402", "import target class not found")
IMPORT_NOT_AN_AGENT = _code("RS403", "import target is not a ManiSkill agent class")
AGENT_DATA_UNREADABLE = _code("RS404", "agent class data cannot be read")
UPSTREAM_CONFIG_REJECTED = _code("RS405", "upstream config value is rejected by its config class")
UPSTREAM_UNKNOWN_LINK = _code("RS406", "upstream names a link the description does not have")
UPSTREAM_UNBOUNDED_NORMALIZATION = _code(
    "RS407",
    "upstream normalizes actions over unbounded joints",
)
UPSTREAM_POSITIONAL_GAINS = _code("RS408", "upstream gains look like arguments passed by position")
AGENT_CODE_NOT_REPRODUCED = _code("RS409", "agent code the spec does not reproduce")
DESCRIPTION_NOT_INSTALLED = _code("RS410", "robot description is not installed")
IMPORTED_UID_IS_MANISKILLS = _code("RS411", "imported uid is ManiSkill's own")
IMPORT_OUTPUT_EXISTS = _code("RS412", "import output file already exists")
UPSTREAM_INEXPRESSIBLE = _code("RS413", "upstream data a spec cannot express")
UPSTREAM_KEYFRAME_MISFIT = _code("RS414", "upstream keyframe does not fit the robot description")
UPSTREAM_JOINT_DRIVEN_TWICE = _code(
    "RS415",
    "upstream drives a joint with two controllers in one mode",
)
# -- physics checks (robospec check)
KEYFRAME_DRIFTS = _code("RS501", "keyframe drifts while held")
NAN_STATE = _code("RS502", "state goes NaN under random actions")
JOINT_LIMIT_VIOLATED = _code("RS503", "joint limit violated under random actions")
RUNAWAY_VELOCITY = _code("RS504", "runaway velocity under random actions")
TRACKS_TOO_SLOWLY = _code("RS505", "controller too slow to track a step")
UNDERDAMPED = _code("RS506", "controller unstable or underdamped")
SETTLES_OFF_TARGET = _code("RS507", "controller settles away from its target")
LINKS_TOUCH_AT_KEYFRAME = _code("RS508", "links touch each other at a keyframe")
ROBOT_NOT_LOADABLE = _code("RS510", "robot cannot be loaded for checking")
NO_CUDA_DEVICE = _code("RS511", "no CUDA device for --gpu")
NO_RENDER_DEVICE = _code("RS512", "no render device for --render")
NO_VIEWER = _code("RS513", "robospec demo cannot open the viewer")
LOAD_FAILURE = _code("RS514", "ManiSkill or SAPIEN cannot load the robot")
CHECK_KILLED = _code("RS515", "checking the robot killed the process")
CONTROL_MODE_CRASH = _code("RS516", "a control mode crashes ManiSkill")
CHECK_CRASH = _code("RS517", "a check crashed inside ManiSkill or SAPIEN")
HOVERS = _code("RS518", "floating robot hovers under gravity compensation")
WRONG_ROOT = _code("RS519", "the root ManiSkill loads is not the one the spec says")
MANISKILL_INSTALLED_TWICE = _code("RS520", "two ManiSkill distributions installed over each other")
STARTS_IN_GROUND = _code("RS521", "the robot starts inside the ground")
SIMULATOR_ERROR = _code("RS522", "ManiSkill or SAPIEN reported an error while the robot ran")
CANNOT_STAND = _code("RS523", "floating robot cannot stand at a keyframe")
TASK_NOT_REGISTERED = _code("RS524", "--task names no task ManiSkill registers")
TASK_CANNOT_RUN = _code("RS525", "a task cannot run with this robot")
BEYOND_REACH = _code("RS526", "a task's objects lie beyond the robot's reach")
TASK_CRASH = _code("RS527", "a task crashed or went NaN with this robot")
TASK_MEMBER_MISSING = _code("RS528", "a task calls an agent member the robot does not have")
LOOP_APART_AT_REST = _code("RS530", "a closed loop's two points are apart at rest")
LOOP_PULLS_APART = _code("RS531", "a closed loop pulls apart while the robot moves")
LOADED_MASS_DIFFERS = _code("RS532", "the robot loaded does not weigh what the description says")
LINK_MISPLACED = _code("RS533", "a link loaded away from where the description puts it")
RATING_BELOW_GRAVITY = _code(
    "RS534",
    "a joint's rated force cannot carry gravity where check steps it",
)
MJCF_KEYFRAME_UNHELD = _code(
    "RS535",
    "a keyframe the MJCF's own actuators cannot hold in MuJoCo either",
)
MIMIC_OUTSIDE_LIMITS = _code("RS545", "a mimic joint's relation holds it outside its own limits")
# -- what the cameras see in the pictures of robospec doc --images (RS560-RS579)
CAMERA_COVERED_BY_MOUNT = _code("RS560", "camera covered by its own mount")
CAMERA_COVERED_BY_ROBOT = _code("RS561", "camera covered by the robot")
CAMERA_SEES_NOTHING = _code("RS562", "camera sees nothing within far")
CAMERA_LOOKS_AWAY = _code("RS563", "wrist camera looks away from its tcp")
CAMERA_PREVIEW_DISAGREES = _code("RS564", "SAPIEN's camera image and the CPU preview disagree")
# -- writing files, authoring commands: robospec build, inspect, new, doc (RS600-RS619)
NOT_A_DESCRIPTION = _code("RS600", "file is not a robot description robospec reads")
SPEC_EXISTS = _code("RS601", "spec file already exists")
NOTHING_TO_CONTROL = _code("RS602", "robot has no active joints to control")
CANNOT_WRITE = _code("RS603", "output file cannot be written")
WOULD_OVERWRITE = _code("RS604", "output would overwrite a file robospec did not write")
REST_TOUCHES = _code("RS605", "scaffold's rest keyframe still has links touching")
REST_NOT_CHECKED = _code("RS606", "scaffold's rest keyframe could not be checked in ManiSkill")
CANNOT_OPTIMIZE = _code("RS607", "robospec optimize cannot optimize this robot as asked")
PYTHON_NAMED_LINK_MERGED = _code("RS608", "links named only in Python code may be merged away")
GAINS_OVER_RATING = _code("RS609", "a joint's gains need more force than its rating")
# -- robospec tune (RS620-RS639)
TUNING_TARGETS_UNMET = _code("RS620", "a controller cannot meet its tuning targets")
UNKNOWN_TUNED_CONTROLLER = _code("RS621", "--controller names no controller a control mode uses")
TUNED_GAINS_UNWRITABLE = _code("RS622", "robospec tune cannot write the new gains into the spec")
TUNED_GAINS_OVER_RATING = _code("RS623", "tuned gains need more force than a joint's rating")
# -- robospec tune --reference: fitting gains to a recorded trajectory (RS640-RS659)
REFERENCE_UNREADABLE = _code("RS640", "reference trajectory file cannot be read")
REFERENCE_MALFORMED = _code("RS641", "reference trajectory file is malformed")
REFERENCE_NOT_FINITE = _code("RS642", "reference trajectory value is not a finite number")
REFERENCE_TIME_ORDER = _code("RS643", "reference trajectory too short or out of time order")
REFERENCE_UNKNOWN_JOINT = _code("RS644", "reference joint is not a joint of the robot")
REFERENCE_JOINT_NOT_POSITION_DRIVEN = _code(
    "RS645",
    "reference joint not driven by a joint-position controller",
)
REFERENCE_JOINT_STILL = _code("RS646", "reference joint does not move")
REFERENCE_MUJOCO_UNUSABLE = _code(
    "RS647",
    "--reference mujoco needs an MJCF robot with position actuators",
)
REFERENCE_UNMATCHED = _code("RS648", "simulated robot cannot match the reference")
REFERENCE_UNDETERMINED = _code("RS649", "reference does not determine stiffness and damping each")
REFERENCE_FIT_CRASH = _code("RS650", "reference fit crashed")
# -- mends: what robospec changed in a derived copy of the description (RS700-RS729)
MENDED_XML = _code("RS700", "mended: XML text no parser accepts")
MENDED_NAMESPACES = _code("RS701", "mended: undeclared namespace prefixes")
MENDED_SUBSTITUTIONS = _code("RS702", "mended: unexpanded substitutions written as their defaults")
MENDED_MESH_URIS = _code("RS703", "mended: mesh URIs resolved to the files robospec found")
MENDED_TEXTURES = _code("RS704", "mended: empty textures removed")
MENDED_TRANSMISSIONS = _code("RS705", "mended: transmissions SAPIEN cannot read removed")
MENDED_INERTIAS = _code("RS706", "mended: inertias SAPIEN rejects")
MENDED_MASSES = _code("RS707", "mended: masses raised to the bound")
MENDED_INTEGERS = _code("RS708", "mended: integers written as decimals")
MENDED_LIMITS = _code("RS709", "mended: joint limits without lower or upper")
MENDED_MIMIC = _code("RS710", "mended: URDF mimic tags removed")
MENDED_SPHERICAL = _code("RS711", "mended: spherical joints written as three continuous joints")
MENDED_INCLUDES = _code("RS712", "mended: MJCF includes written in place")
MENDED_GEOMS = _code("RS713", "mended: MJCF geoms ManiSkill cannot load removed")
MENDED_MIRRORS = _code("RS714", "mended: mirrored collision meshes written as mirrored copies")
MENDED_MESH_NAMES = _code("RS715", "mended: unnamed MJCF meshes named as MuJoCo names them")
MENDED_MESH_SCALES = _code("RS716", "mended: MJCF mesh scales from defaults written on the meshes")
MENDED_CONTYPE = _code("RS717", "mended: MJCF geoms MuJoCo collides given a collision shape")
MENDED_FREEJOINT = _code("RS718", "mended: an MJCF free joint written as <freejoint>")
MENDED_ASSET_NAMES = _code("RS719", "mended: repeated MJCF asset definitions removed")
MENDED_BODIES = _code("RS720", "mended: MJCF bodies without joints merged into their parents")
MENDED_ORIENTATIONS = _code("RS721", "mended: MJCF frames written as MuJoCo's quat")
MENDED_SEPARATORS = _code("RS722", "mended: number lists separated by commas")
MENDED_GEOM_MESHES = _code("RS723", "mended: MJCF meshes from default classes written on the geoms")
MENDED_AXES = _code("RS724", "mended: MJCF joint axes written as MuJoCo reads them")
STALE_MEND = _code("RS725", "mend changes nothing")
MEND_FOR_OTHER_KIND = _code("RS726", "mend for another kind of description")
CANNOT_MEND = _code("RS727", "mend cannot mend an element as asked")
MENDED_ANGLES = _code("RS728", "mended: MJCF angles read as radians")
# -- what the spec's own sections change in the derived copy (RS780-RS789)
DERIVED_PLANAR_BASE = _code("RS780", "derived: a planar base added above the base link")
PLANAR_BASE_REFUSED = _code("RS781", "a planar base cannot be added where it is asked")
# -- an MJCF compiled by MuJoCo, written as a URDF (description.loader: mujoco; RS790-RS799)
MUJOCO_COMPILE_ERROR = _code("RS790", "MuJoCo cannot compile the MJCF")
MUJOCO_NOT_CARRIED = _code("RS791", "what the URDF written from MuJoCo's model does not carry")
MUJOCO_COMPILE_WARNING = _code("RS792", "MuJoCo warns while compiling the MJCF")
MUJOCO_SITE_UNWRITABLE = _code("RS793", "an MJCF site the spec names cannot be its own link")
# -- parts: robots mounted on the spec's robot, composed into one description (RS730-RS759)
UNKNOWN_MOUNT = _code("RS730", "part mounted on a link no one has")
PART_NOT_A_FIXED_TREE = _code("RS731", "part that is not one tree fixed at its root")
NAME_CLASH = _code("RS732", "name clash a prefix cannot fix")
PART_CYCLE = _code("RS733", "parts mounted on each other in a ring")
PART_INSIDE_ROBOT = _code("RS734", "part inside the robot at rest")
MIXED_FORMATS = _code("RS735", "part of another description format")
PART_PREFIXED = _code("RS736", "part names prefixed")
PART_HAS_ERRORS = _code("RS737", "part whose spec has errors")
PART_NOT_CARRIED = _code("RS738", "what a part's spec declares that does not come along")
UNKNOWN_PART_MODE = _code("RS739", "part mode the part does not have")
PARTS_WITHOUT_DESCRIPTION = _code("RS740", "parts on a robot without its own description")
NOTHING_TO_FOLD = _code("RS741", "fold_frames with no empty frame to fold")
BAD_ATTACH = _code("RS742", "--attach names no part or link robospec can mount")
OPTIMIZE_WITH_PARTS = _code("RS743", "robospec optimize of a robot with parts")
# -- robospec doc --images: drawing the pictures (RS660-RS669)
NO_RENDER_EXTRA = _code("RS660", "the render extra is not installed")
NO_OPENGL = _code("RS661", "no OpenGL to draw the pictures with")
PICTURE_MESH_UNREADABLE = _code("RS662", "mesh cannot be read for the pictures")
PICTURE_MJCF_UNLOADABLE = _code("RS663", "MuJoCo cannot load the MJCF for the pictures")
PICTURE_SCENE_FAILED = _code("RS664", "the pictures' scene cannot be built")
# -- robospec optimize --profile fast (RS670-RS689)
UNKNOWN_PROFILE = _code("RS670", "unknown optimize profile")
MAX_ERROR_OUT_OF_RANGE = _code("RS671", "--max-error out of range")
CONTACT_OFFSET_OUT_OF_RANGE = _code("RS672", "--contact-offset out of range")
NAMED_LINK_MERGED = _code("RS673", "a link the spec names would be merged away")
NO_PRIMITIVE_FITS = _code("RS674", "collision meshes fit no primitive within the bound")
UNKNOWN_CATEGORY = _code("RS675", "unknown robot category")
OPTION_FOR_OTHER_PROFILE = _code(
    "RS676",
    "an option that applies only to another profile or shapes method",
)
# -- robospec solve: ManiSkill's solutions with robospec's planner
NO_SOLUTION = _code("RS680", "no ManiSkill solution robospec runs for the task")
NO_TWO_FINGER_GRIPPER = _code("RS681", "the robot has no two-finger gripper")
SOLVER_CANNOT_DRIVE = _code("RS682", "the solver cannot drive the robot's arm or gripper")
TOO_FEW_SUCCESSES = _code("RS683", "fewer episodes succeeded than --min-success asks")
# -- internal
INTERNAL_ERROR = _code("RS900", "internal error")

CODES: dict[str, Code] = {c.code: c for c in _CODES}
