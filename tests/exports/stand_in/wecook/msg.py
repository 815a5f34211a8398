"""A stand-in for the messages of icaros-usc/wecook (``wecook.msg``), its classes generated here from a copy of
the text of its ``msg/*.msg`` files (the interface definitions, verbatim: ``DEFINITIONS`` below).

Provenance: github.com/icaros-usc/wecook, commit a29337484f3c4232559d2a2aafc3e9a0cf3b1c5a (2023-06-06), files
msg/ActionMsg.msg, msg/AgentMsg.msg, msg/ContainingMsg.msg, msg/ObjectMsg.msg, msg/SceneMsg.msg, msg/TagMsg.msg
and msg/TaskMsg.msg; BSD 3-Clause licence, Copyright (c) 2019, ICAROS. The .msg files themselves are not kept in
this repository: this parsed copy of their field lines is what the tests need.

Like genpy's classes, a message takes its fields positionally in declaration order or by keyword; unlike them, it
checks every value's type against the definition and raises TypeError on any mismatch. Every message made is
recorded in ``built``."""

DEFINITIONS = {
    "ActionMsg": "string[] pid\nstring verb\nstring[] location\nstring tool\nstring[] ingredients",
    "AgentMsg": "string pid\nstring type\nfloat64[] pose\nbool if_float",
    "ContainingMsg": "string[] pair",
    "ObjectMsg": "string name\nstring url\nfloat64[] pose",
    "SceneMsg": "ObjectMsg[] objects\nTagMsg[] tags\nContainingMsg[] containingMap\n",
    "TagMsg": "uint32 tagId\nstring objectName\nfloat64[] objectPose",
    "TaskMsg": "SceneMsg scene\nActionMsg[] actions\nAgentMsg[] agents\nstring PDDLDomain\nstring PDDLProblem\n"
               "string type\nstring motionPlannerType\nbool ifSim",
}

built = []


def fields_of(name):
    """((field, ROS type), ...) of message ``name``, in declaration order."""
    out = []
    for line in DEFINITIONS[name].splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            kind, field = line.split()
            out.append((field, kind))
    return tuple(out)


def check_value(kind, value, where):
    """Raise TypeError unless ``value`` is of ROS type ``kind``."""
    if kind.endswith("[]"):
        if not isinstance(value, (list, tuple)):
            raise TypeError(f"{where}: expected a list of {kind[:-2]}, got {value!r}")
        for k, item in enumerate(value):
            check_value(kind[:-2], item, f"{where}[{k}]")
    elif kind == "string":
        if not isinstance(value, str):
            raise TypeError(f"{where}: expected a string, got {value!r}")
    elif kind == "bool":
        if not isinstance(value, bool):
            raise TypeError(f"{where}: expected a bool, got {value!r}")
    elif kind == "float64":
        if not isinstance(value, float):
            raise TypeError(f"{where}: expected a float, got {value!r}")
    elif kind == "uint32":
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < 2 ** 32:
            raise TypeError(f"{where}: expected a uint32, got {value!r}")
    elif kind in DEFINITIONS:
        if type(value).__name__ != kind or type(value).__module__ != __name__:
            raise TypeError(f"{where}: expected a {kind}, got {value!r}")
    else:
        raise TypeError(f"{where}: unknown ROS type {kind}")


class _Message:
    _type = ""

    def __init__(self, *args, **kwargs):
        fields = fields_of(self._type)
        if args and kwargs:
            raise TypeError(f"{self._type}: give fields positionally or by keyword, not both")
        if args and len(args) != len(fields):
            raise TypeError(f"{self._type} takes {len(fields)} fields, got {len(args)}")
        unknown = set(kwargs) - {f for f, _ in fields}
        if unknown:
            raise TypeError("{} has no field {}".format(self._type, ", ".join(sorted(unknown))))
        values = dict(zip([f for f, _ in fields], args, strict=False)) if args else kwargs
        for field, kind in fields:
            if field not in values:
                raise TypeError(f"{self._type}: field {field} not given")
            check_value(kind, values[field], f"{self._type}.{field}")
            setattr(self, field, values[field])
        built.append(self)


for _name in DEFINITIONS:
    globals()[_name] = type(_name, (_Message,), {"_type": _name, "__module__": __name__})
