"""A stand-in for the messages of icaros-usc/wecook (``wecook.msg``), built from the text of its ``msg/*.msg``
files (BSD-3; the interface definitions, verbatim). Like genpy's classes, a message takes its fields positionally
in declaration order or by keyword; unlike them, it checks every value's type against the definition and raises
TypeError on any mismatch. Every message made is recorded in ``built``."""

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
            raise TypeError("%s: expected a list of %s, got %r" % (where, kind[:-2], value))
        for k, item in enumerate(value):
            check_value(kind[:-2], item, "%s[%d]" % (where, k))
    elif kind == "string":
        if not isinstance(value, str):
            raise TypeError("%s: expected a string, got %r" % (where, value))
    elif kind == "bool":
        if not isinstance(value, bool):
            raise TypeError("%s: expected a bool, got %r" % (where, value))
    elif kind == "float64":
        if not isinstance(value, float):
            raise TypeError("%s: expected a float, got %r" % (where, value))
    elif kind == "uint32":
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < 2 ** 32:
            raise TypeError("%s: expected a uint32, got %r" % (where, value))
    elif kind in DEFINITIONS:
        if type(value).__name__ != kind or type(value).__module__ != __name__:
            raise TypeError("%s: expected a %s, got %r" % (where, kind, value))
    else:
        raise TypeError("%s: unknown ROS type %s" % (where, kind))


class _Message(object):
    _type = ""

    def __init__(self, *args, **kwargs):
        fields = fields_of(self._type)
        if args and kwargs:
            raise TypeError("%s: give fields positionally or by keyword, not both" % self._type)
        if args and len(args) != len(fields):
            raise TypeError("%s takes %d fields, got %d" % (self._type, len(fields), len(args)))
        unknown = set(kwargs) - {f for f, _ in fields}
        if unknown:
            raise TypeError("%s has no field %s" % (self._type, ", ".join(sorted(unknown))))
        values = dict(zip([f for f, _ in fields], args)) if args else kwargs
        for field, kind in fields:
            if field not in values:
                raise TypeError("%s: field %s not given" % (self._type, field))
            check_value(kind, values[field], "%s.%s" % (self._type, field))
            setattr(self, field, values[field])
        built.append(self)


for _name in DEFINITIONS:
    globals()[_name] = type(_name, (_Message,), {"_type": _name, "__module__": __name__})
