"""Follower motion: the :class:`Motion` interface, the named laws, motion programs and tabulated motions."""

from ._base import Motion, evaluate
from ._hermite import HermiteMotion
from ._laws import LAWS, law
from ._program import Program, Segment

__all__ = ["LAWS", "HermiteMotion", "Motion", "Program", "Segment", "evaluate", "law"]
