// The extension page of `funnel paper` beyond the paper: the cone in 3D with sideways release
// velocities (does the anomaly above 45 degrees survive off-plane motion?).
#pragma once

#include "funnel/ensemble.hpp"
#include "funnel/paper/cases.hpp"
#include "funnel/paper/figures.hpp"

namespace funnel::paper {

/// Kind cone_3d_sweep: for each velocity_sd of [settings] velocity_sds (sqrt(gH)) and each angle
/// of the [grid] theta axis, a 3D disk ensemble of the figure's (first panel's) parameters with
/// that random horizontal release velocity. CSV rows: panel, velocity_sd, theta, then mean and
/// sem of each of the figure's observables and of orbits_exited, duration, impulse,
/// energy_loss, orbits, trapped_fraction (a name ending in "_exited" is averaged over the exited samples only),
/// then exited, trapped, periodic, total_collisions; drawn as a theta sweep with velocity_sd as
/// the series. The check: the ratio of the [check] observable at `above` to `below` exceeds
/// min_ratio for velocity_sd = 0, exceeds min_ratio_off_plane for every velocity_sd > 0, and
/// does not grow with velocity_sd (in the order listed).
FigureData cone_3d_sweep(const FigureSpec& fig, int threads, const Progress& progress);

}  // namespace funnel::paper
