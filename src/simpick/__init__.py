"""simpick: which physics engine reproduces a mobile robot best, how fast, at what cost."""

__version__ = "0.1.0"
