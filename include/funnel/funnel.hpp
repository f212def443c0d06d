// Any 2D funnel: two walls, each a polyline of straight segments (docs/model.md §2b). The runtime
// description the engine uses: faces (where the centre touches a segment), corners (convex
// vertices act as edges, concave ones are where two faces meet), the outlet and the release line.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "funnel/edge_contact.hpp"
#include "funnel/geometry.hpp"
#include "funnel/params.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// A user's wall profile: each side a polyline of the wall surface from its top vertex down to
/// its lower end, in the frame x horizontal, y up, units of H; optional material per side.
struct ProfileSpec {
  std::array<std::vector<Vec2>, 2> sides;           ///< left, right: surface vertices, top to bottom
  std::array<std::optional<double>, 2> e, mu, beta0;  ///< per-side material (else the parameters')
  std::optional<double> bottom;                     ///< height release-height is measured from (default: the higher lower end)
  std::string source;                               ///< where it came from (a file name), for messages and outputs
};

/// A face: where the particle's centre touches one straight segment of a wall's surface, i.e.
/// the segment shifted inward by a (its centre line), between the ends of its region.
struct Face {
  Vec2 n;                 ///< unit normal into the funnel; n.y >= 0 (no overhangs)
  Vec2 up;                ///< unit vector along the face, up the wall
  Vec2 down;              ///< -up
  Vec2 ref;               ///< a point of the centre line: the signed distance is n.(r - ref)
  Vec2 low;               ///< lower end of the region (C* at a convex corner, the meeting point at a concave one)
  Vec2 high;              ///< upper end of the region (unused for the top face)
  double length = 0.0;    ///< length of the region along `up`; infinite for the top face
  double sin_a = 0.0;     ///< sine of the segment's angle to the horizontal (0 ledge .. 1 vertical)
  double cos_a = 1.0;     ///< cosine of that angle
  bool low_convex = true; ///< the region ends at a convex corner below (the foot must be checked)
  bool high_convex = false; ///< ... above
  double surface_offset = 0.0;  ///< distance along the surface from the side's lower end to the foot of `low`
};

/// A vertex of a wall's surface.
struct Corner {
  Vec2 point;             ///< the vertex
  bool convex = true;     ///< the wall turns away from the particle: an edge (collisions, edge contacts)
  bool outlet = false;    ///< the side's lower end
  bool bottom = false;    ///< the shared lower end of a closed funnel: a sustained contact there is rest
  EdgeArc arc;            ///< convex: contact normals where the edge acts, in the side's own (left-facing) frame
  double top = 0.0;       ///< convex: highest height of the edge arc (flights above it cannot touch the edge)
};

/// One wall: faces bottom to top; corner k is the lower end of face k.
struct Side {
  std::vector<Face> faces;
  std::vector<Corner> corners;
  Material material;            ///< e, mu, beta0 of this wall (kappa and a are the particle's)
  CollisionConstants law;       ///< Walton's constants of that material
  double ws = -1.0;             ///< -1 left, +1 right: the mirror sign of the wall
};

/// The runtime description of a funnel.
struct Funnel {
  std::array<Side, 2> sides;    ///< 0 left, 1 right
  bool closed = false;          ///< the lower ends coincide: no outlet, rest at the bottom
  bool symmetric = false;       ///< the right wall is the exact mirror of the left one (and materials equal)
  bool one_face = false;        ///< each wall is one straight face over its lower end (a V without a spout)
  double y_exit = 0.0;          ///< exit level: the lower of the two lower ends (crossed downward = exited)
  /// Lower ends at unequal heights: the side of the higher one (-1 left, +1 right; 0 for equal
  /// ends or a closed funnel) and that end (units of H). A centre that crosses the vertical
  /// through it outward, below it, has passed under the higher end sideways: it has exited there.
  int side_exit = 0;
  Vec2 side_exit_end{};
  double y_bottom = 0.0;        ///< the funnel bottom: release-height is measured from it
  /// A closed funnel: the height of the vertex (where the two lowest faces' centre lines meet,
  /// the centre's lowest point), and how close above it a centre is at the vertex to the
  /// rounding of its coordinates: 2^-44 of the vertex's largest coordinate (0 for a vertex at
  /// the origin, as the V's, where the coordinates resolve a collapse to its end; 0 if open).
  double y_vertex = 0.0;
  double vertex_tolerance = 0.0;
  double y_release = 0.0;       ///< release height of the centre
  double x_release_mid = 0.0;   ///< middle of the release line
  double half_width = 0.0;      ///< half its length: x0 = mid + X half_width, X in (-1, 1)
  double skip_height = 0.0;     ///< highest top of every edge arc: a flight above it meets no edge and no exit
  double radius = 0.0;          ///< particle radius a
  std::string source;           ///< "v" (built from the parameters) or the profile's source
};

/// The funnel of a parameter set: the paper's V (theta, gap), an asymmetric V (theta-left,
/// theta-right), a V with a spout (spout-length), or params.profile. Throws std::invalid_argument
/// for a profile that validate_profile() would reject (callers validate first).
Funnel make_funnel(const Params& params);

/// Checks a profile against the particle and the parameters: walls that do not cross, no
/// overhangs, segments longer than rounding, an outlet wider than 2a (unless closed), a release
/// line inside the funnel. The error names the side and the vertex or segment.
std::optional<ParamError> validate_profile(const ProfileSpec& spec, const Params& params);

/// The surface of wall `side` (0 left, 1 right) as vertices from the top down to its lower end,
/// the top segment cut at height y_top (for drawing and outputs).
std::vector<Vec2> wall_surface(const Funnel& f, int side, double y_top);

/// Height up to which a drawing shows the walls: 0.1 above the release line or the highest
/// corner, whichever is higher.
double drawing_top(const Funnel& f);

/// Distance from p to the segment [a, b].
double segment_distance(Vec2 p, Vec2 a, Vec2 b);

/// A symmetric profile: `left` as given and its mirror image x -> -x as the right side.
ProfileSpec mirrored_profile(std::vector<Vec2> left);

/// The mirror image x -> -x of a profile: its sides and their materials swapped.
ProfileSpec mirror_image(const ProfileSpec& spec);

/// One wall as a geometry file or a Python dict gives it: its vertices (none on the right of a
/// mirrored funnel) and its optional material.
struct WallSpec {
  std::optional<std::vector<Vec2>> vertices;
  std::optional<double> e, mu, beta0;
};

/// The profile of a geometry file's layout (docs/cli.md, "Geometry files"): the left wall, the
/// right one or `mirror` (the left mirrored, with the left's materials unless `right` gives its
/// own). Throws std::invalid_argument naming what is missing or contradictory.
ProfileSpec assemble_profile(const std::optional<WallSpec>& left, const std::optional<WallSpec>& right, bool mirror);

/// Release position of the centre for X = fraction in (-1, 1) on the release line.
inline Vec2 release_point(const Funnel& f, double fraction) {
  return {f.x_release_mid + fraction * f.half_width, f.y_release};
}

/// Signed distance of a centre position from a face's centre line, positive inside the funnel.
inline double face_distance(const Face& face, Vec2 r) {
  return face.n.x * (r.x - face.ref.x) + face.n.y * (r.y - face.ref.y);
}

/// Position of the foot of r along a face, measured up from the lower end of its region.
inline double along_face(const Face& face, Vec2 r) {
  return face.up.x * (r.x - face.low.x) + face.up.y * (r.y - face.low.y);
}

/// The mirror image x -> -x of a state. Written 0 - x, not -x: a zero stays +0, as the direct
/// simulation of a mirror release has it.
inline State mirror(State s) {
  s.r.x = 0.0 - s.r.x;
  s.v.x = 0.0 - s.v.x;
  s.omega = 0.0 - s.omega;
  return s;
}

}  // namespace funnel
