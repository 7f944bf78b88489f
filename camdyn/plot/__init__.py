"""Figures, one function per figure, each drawing on a matplotlib ``ax`` from a result: a notebook user can
call them as the reports do (``plot_feasible_region(ax, size_spring(case))``)."""

from .jumpmap import plot_jump_map, save_png
from .parts import plot_contact, plot_drive, plot_spring
from .springs import PLOT_COLORS, plot_feasible_region

__all__ = ["PLOT_COLORS", "plot_contact", "plot_drive", "plot_feasible_region", "plot_jump_map", "plot_spring", "save_png"]
