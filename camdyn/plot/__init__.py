"""Figures, one function per figure, each drawing on a matplotlib ``ax`` (or the ``axes`` of one figure) from
a result: a notebook user can call them as the reports do, e.g. ``plot_feasible_region(ax, size_spring(case))``,
``plot_cam_profile(ax, run_check(case).geometry)`` or ``plot_force_vs_speed(ax, design_review(case, check))``."""

from ._common import PALETTE, deg_ticks, flight_spans, legend_above_data, legend_clear, mark_breaks, shade_separations
from .cam import (
    check_colour,
    face_extremes,
    follower_pose,
    plot_cam_profile,
    plot_curvature,
    plot_face_contact,
    plot_follower,
    plot_pressure_angle,
    square_face,
)
from .dynamics import (
    flight_summary,
    flights_by_gap,
    plot_contact_force,
    plot_displacement,
    plot_force_vs_speed,
    plot_vibration,
)
from .groove import (
    flank_names,
    plot_cam_pressure_angles,
    plot_flank_force,
    plot_groove_cam,
    plot_impact_histogram,
    plot_impact_map,
    plot_impact_speed,
    plot_wall_curvature,
    save_impact_histogram_png,
    save_impact_png,
    save_preload_png,
)
from .jumpmap import plot_jump_map, save_png
from .mechanism import mechanism_bounds, mechanism_frames, plot_mechanism, plot_path, plot_path_error
from .motion import display_scale, display_unit, plot_fit, plot_svaj, svaj_quantities
from .optimization import plot_motion_before_after, plot_speed_before_after
from .parts import plot_contact, plot_drive, plot_spring
from .springs import PLOT_COLORS, plot_feasible_region
from .tolerance import plot_jump_speed_histogram, plot_tolerance_tornado, save_tolerance_png
from .valvetrain import plot_rocker_ratio, plot_seating_velocity, plot_valve_lift, plot_valve_velocity

__all__ = [
    "flank_names",
    "plot_cam_pressure_angles",
    "plot_flank_force",
    "plot_groove_cam",
    "plot_impact_histogram",
    "plot_impact_map",
    "plot_impact_speed",
    "plot_wall_curvature",
    "save_impact_histogram_png",
    "save_impact_png",
    "save_preload_png",
    "plot_seating_velocity",
    "plot_rocker_ratio",
    "plot_valve_lift",
    "plot_valve_velocity",
    "plot_motion_before_after",
    "plot_speed_before_after",
    "PALETTE",
    "PLOT_COLORS",
    "check_colour",
    "deg_ticks",
    "display_scale",
    "display_unit",
    "face_extremes",
    "flights_by_gap",
    "follower_pose",
    "mark_breaks",
    "mechanism_bounds",
    "mechanism_frames",
    "plot_cam_profile",
    "plot_contact",
    "plot_contact_force",
    "plot_curvature",
    "plot_displacement",
    "plot_drive",
    "plot_face_contact",
    "plot_feasible_region",
    "plot_fit",
    "plot_follower",
    "plot_force_vs_speed",
    "plot_jump_map",
    "plot_mechanism",
    "plot_path",
    "plot_path_error",
    "plot_pressure_angle",
    "plot_spring",
    "plot_svaj",
    "plot_vibration",
    "save_png",
    "shade_separations",
    "square_face",
    "svaj_quantities",
    "flight_spans",
    "flight_summary",
    "legend_above_data",
    "legend_clear",
    "plot_jump_speed_histogram",
    "plot_tolerance_tornado",
    "save_tolerance_png",
]
