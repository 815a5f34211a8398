"""wecook's core: perception stages, plans and execution. Never imports the UI."""

__version__ = "0.1.0"
