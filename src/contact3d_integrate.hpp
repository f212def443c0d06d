// The integrated sustained contact of the 3D engine (src/contact3d_integrate.cpp), for
// contact3d.cpp, which takes the closed forms where the motion stays in a meridian plane.
#pragma once

#include "funnel/contact3d.hpp"

namespace funnel::detail {

/// A sustained contact on the cone face (torus false) or the rim torus, integrated (Dormand-Prince
/// 5(4) with dense output; docs/model.md §9) from `start` until it ends.
Contact3Result integrate_contact(bool torus, const State3& start, const Cone& cone, const Material& m,
                                 const Contact3Options& opt);

}  // namespace funnel::detail
