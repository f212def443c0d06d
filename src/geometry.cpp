// Funnel geometry derived from the parameters (docs/model.md §2).
#include "funnel/geometry.hpp"

#include <cmath>
#include <numbers>

namespace funnel {

Geometry make_geometry(const Params& params) {
  Geometry g;
  const double rad = params.theta * std::numbers::pi / 180.0;
  g.sin_t = std::sin(rad);
  g.cos_t = std::cos(rad);
  g.tan_t = std::tan(rad);
  g.radius = params.radius;
  g.half_gap = 0.5 * params.gap;
  g.closed = params.gap == 0.0;
  g.y_bottom = g.half_gap * g.tan_t - params.radius / g.cos_t;
  g.y_release = g.y_bottom + params.release_height;
  g.half_width = g.y_release / g.tan_t;
  if (g.closed) {
    // The faces meet at the vertex; contact is possible on all of each face above it.
    g.y_face_end = 0.0;
    g.x_face_end = 0.0;
  } else {
    // C*_R = E_R + a n_R: the centre line is tangent to the edge circle there.
    g.x_face_end = g.half_gap - params.radius * g.sin_t;
    g.y_face_end = g.y_bottom + params.radius * g.cos_t;
  }
  return g;
}

}  // namespace funnel
