// The extension page of `funnel paper` beyond the paper: the cone in 3D with sideways release
// velocities (does the anomaly above 45 degrees survive off-plane motion?).
#pragma once

#include "funnel/ensemble.hpp"
#include "paper_cases.hpp"
#include "paper_figures.hpp"

namespace funnel::cli {

/// Kind cone_3d_sweep: for each velocity_sd of [settings] velocity_sds (sqrt(gH)) and each angle
/// of the [grid] theta axis, a 3D disk ensemble of the figure's (first panel's) parameters with
/// that random horizontal release velocity; CSV rows (panel, velocity_sd, theta, mean and sem of
/// each observable, mean orbits, exited, trapped, collisions), drawn as a theta sweep with
/// velocity_sd as the series. The check compares the mean duration at [check] above and below
/// for every velocity_sd: the claim holds when each ratio exceeds min_ratio.
FigureData cone_3d_sweep(const FigureSpec& fig, int threads, const Progress& progress);

}  // namespace funnel::cli
