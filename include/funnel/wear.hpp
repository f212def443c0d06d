// Where the walls wear: collisions and impulses binned along each wall (docs/model.md §7).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "funnel/contact.hpp"
#include "funnel/funnel.hpp"

namespace funnel {

/// Wear of one wall: per bin of distance along the wall's surface, and at its lower edge.
struct WallWear {
  std::vector<double> collisions;      ///< face collisions per bin
  std::vector<double> normal_impulse;  ///< normal impulse per bin (collisions + contacts), units m sqrt(gH)
  std::vector<double> impulse;         ///< total impulse |J| per bin (collisions + contacts), units m sqrt(gH)
  double edge_collisions = 0.0;        ///< collisions with the edge point
  double edge_normal_impulse = 0.0;    ///< normal impulse on the edge (collisions + edge contacts)
  double edge_impulse = 0.0;           ///< total impulse on the edge (collisions + edge contacts)
};

/// Wear of both walls in `bins` equal bins of distance s along each wall's surface, measured
/// from its lower end (the edge point) up to the release height (for the V: width =
/// H0 / sin(theta) / bins). Contacts above the release height (possible only for upward
/// releases) are counted in the last bin.
struct Wear {
  int bins = 0;              ///< number of bins per wall (0: wear is not recorded)
  std::array<WallWear, 2> walls;  ///< indexed by wall: 0 left, 1 right
  std::array<double, 2> widths{};  ///< bin width of each wall, units of H

  /// Empty wear record for a funnel.
  static Wear make(const Funnel& f, int bins);

  WallWear& operator[](Wall w) { return walls[w == Wall::Left ? 0 : 1]; }
  const WallWear& operator[](Wall w) const { return walls[w == Wall::Left ? 0 : 1]; }
  /// The bin width of a wall, units of H (the walls of an asymmetric funnel differ in length).
  double width(Wall w) const { return widths[w == Wall::Left ? 0 : 1]; }

  /// A face collision at distance s up the face, with normal impulse j_n and |J| = j.
  void add_collision(Wall wall, double s, double j_n, double j);
  /// An edge collision, or (count = false) an edge contact's impulses.
  void add_edge(Wall wall, double j_n, double j, bool count);
  /// A phase of sustained face contact with constant acceleration: its impulses are spread over
  /// the bins in proportion to the time spent in each (normal force cos(theta), friction force).
  void add_face_phase(Wall wall, const FacePhase& phase, double cos_theta, double offset);

  /// Adds another record of the same binning; with `mirror`, that of its mirror image (left and
  /// right swapped, as merge(other.mirrored()) without the copy).
  void merge(const Wear& other, bool mirror = false);
  /// Sets every entry to 0, keeping the binning (a record reused from trajectory to trajectory).
  void clear();
  /// Multiplies every entry by `factor` (e.g. 1/N for per-sample means).
  void scale(double factor);
  /// The record of the mirror-image trajectory: left and right swapped.
  Wear mirrored() const;
};

}  // namespace funnel
