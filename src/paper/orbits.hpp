// Figures built from the geometry and the orbit theories: Fig. 1, Fig. 9, Fig. 14 and Fig. 2 explained.
#pragma once

#include "funnel/paper/cases.hpp"
#include "funnel/paper/figures.hpp"

namespace funnel::paper {

/// Fig. 1 (kind funnel_sketch): the funnel's points and symbols to scale, checked against their definitions.
FigureData funnel_sketch(const FigureSpec& fig);

/// Fig. 9 (kind period2_orbits): the period-2 orbit at theta != 45 and the rotating family at 45 degrees,
/// each run by the engine from the orbit's state for [settings] collisions and checked to stay on it.
FigureData period2_orbits(const FigureSpec& fig);

/// Fig. 14 (kind retrace_orbits): the simplest self-retracing frictionless orbits, one period each,
/// checked to return to rest at their release point.
FigureData retrace_orbits(const FigureSpec& fig, int threads);

/// Beyond the paper, Fig. 2 explained (kind retrace_windows): stability windows of the self-retracing
/// orbits in the open funnel beside the measured mean duration, and which of its peaks they explain.
FigureData retrace_windows(const FigureSpec& fig, const SweepCache& cache, int threads);

}  // namespace funnel::paper
