// Figures beyond the paper for funnel and hopper designers: where the walls wear.
#pragma once

#include "funnel/ensemble.hpp"
#include "funnel/paper/cases.hpp"
#include "funnel/paper/figures.hpp"

namespace funnel::paper {

/// Kind wear_profiles: per angle of `thetas`, the per-particle wear of a wall (collisions,
/// normal and total impulse per unit length of wall) against the height above the funnel
/// bottom, from an ensemble with [settings] bins; the check compares the total impulse per
/// particle just above and just below 45 degrees (the paper's anomaly, seen as wall wear).
FigureData wear_profiles(const FigureSpec& fig, int threads, const Progress& progress);

}  // namespace funnel::paper
