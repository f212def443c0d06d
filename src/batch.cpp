// The batched face-to-face step: trajectories of one funnel in the lanes of two SIMD vectors, with
// run-time dispatch to the widest instruction set of the CPU (Highway: SSE4, AVX2, AVX-512), for
// their flights between the walls' top faces above every edge (src/engine.cpp batchable says
// which funnels qualify). Each lane computes exactly what the scalar engine computes for its
// trajectory (src/flight.cpp search, src/engine.cpp's event loop and face collision,
// src/walton.cpp): the same IEEE operations in the same order, no contraction into fused
// multiply-adds (-ffp-contract=off), division and square root correctly rounded in every lane.
// Lanes whose next event is anything else (an edge, the exit, a collapse, a cap, a flight that
// starts on an edge or leaves a face tangentially) go back to the scalar engine for that event.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "batch.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <cstddef>
#include <iterator>

#include "batch.hpp"

HWY_BEFORE_NAMESPACE();
namespace funnel::batch {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

/// One side's constants, broadcast.
struct SideV {
  V nx, ny, neg_nx, refx, refy, lowx, lowy, upx, upy, low_ok;
  V neg_e, mu_neg, one_plus_e, slide_factor, one_plus_beta0, neg_one_plus_beta0, reduced, kappa_a, half_1_minus_e2,
      half_reduced, radius;
};

SideV broadcast(D d, const SideConstants& s) {
  return {hn::Set(d, s.nx),
          hn::Set(d, s.ny),
          hn::Set(d, -s.nx),
          hn::Set(d, s.refx),
          hn::Set(d, s.refy),
          hn::Set(d, s.lowx),
          hn::Set(d, s.lowy),
          hn::Set(d, s.upx),
          hn::Set(d, s.upy),
          hn::Set(d, s.low_ok),
          hn::Set(d, -s.e),
          hn::Set(d, -s.mu),
          hn::Set(d, s.one_plus_e),
          hn::Set(d, s.slide_factor),
          hn::Set(d, s.one_plus_beta0),
          hn::Set(d, -s.one_plus_beta0),
          hn::Set(d, s.reduced),
          hn::Set(d, s.kappa_a),
          hn::Set(d, s.half_1_minus_e2),
          hn::Set(d, s.half_reduced),
          hn::Set(d, s.radius)};
}

// Two tracks of lanes step side by side, as pairs of vectors: every operation below is done on
// both, one after the other, so that the chain of dependent square roots and divisions of one
// track's round overlaps the other's in the CPU (one track alone waits on its divider most of the
// time). Each lane still computes exactly what it would alone.
template <class T>
struct Pair {
  T a, b;
};
using V2 = Pair<V>;
using M2 = Pair<M>;

/// Track i's part of a pair; a plain vector or mask (a constant) is both tracks'.
template <int i, class T>
HWY_INLINE T at(const T& x) {
  return x;
}
template <int i, class T>
HWY_INLINE T at(const Pair<T>& x) {
  return i == 0 ? x.a : x.b;
}

// Binary operations on pairs, or on a pair and a vector (a constant, the same for both tracks).
#define FUNNEL_PAIR_BINARY(name, op, R)                               \
  template <class X, class Y>                                         \
  HWY_INLINE R name(const X& x, const Y& y) {                         \
    return {hn::op(at<0>(x), at<0>(y)), hn::op(at<1>(x), at<1>(y))}; \
  }
FUNNEL_PAIR_BINARY(add, Add, V2)
FUNNEL_PAIR_BINARY(sub, Sub, V2)
FUNNEL_PAIR_BINARY(mul, Mul, V2)
FUNNEL_PAIR_BINARY(div, Div, V2)
FUNNEL_PAIR_BINARY(max, Max, V2)
FUNNEL_PAIR_BINARY(eq, Eq, M2)
FUNNEL_PAIR_BINARY(ne, Ne, M2)
FUNNEL_PAIR_BINARY(lt, Lt, M2)
FUNNEL_PAIR_BINARY(le, Le, M2)
FUNNEL_PAIR_BINARY(gt, Gt, M2)
FUNNEL_PAIR_BINARY(ge, Ge, M2)
FUNNEL_PAIR_BINARY(both, And, M2)
FUNNEL_PAIR_BINARY(either, Or, M2)
FUNNEL_PAIR_BINARY(but_not, AndNot, M2)  // but_not(a, b): b and not a
#undef FUNNEL_PAIR_BINARY

HWY_INLINE V2 sqrt(const V2& x) { return {hn::Sqrt(x.a), hn::Sqrt(x.b)}; }
HWY_INLINE V2 abs(const V2& x) { return {hn::Abs(x.a), hn::Abs(x.b)}; }
template <class X, class Y>
HWY_INLINE V2 choose(const M2& m, const X& x, const Y& y) {
  return {hn::IfThenElse(m.a, at<0>(x), at<0>(y)), hn::IfThenElse(m.b, at<1>(x), at<1>(y))};
}
template <class X>
HWY_INLINE V2 choose_or_zero(const M2& m, const X& x) {
  return {hn::IfThenElseZero(m.a, at<0>(x)), hn::IfThenElseZero(m.b, at<1>(x))};
}

/// line_arrival_time (src/roots.cpp) for delta0 >= 0, given s = sqrt(p^2 + 2 delta0 c) where
/// delta0 != 0: one division of the operands the scalar engine divides (the same quotient).
/// `ok` is false where delta0 < 0 (behind the line: the scalar engine decides).
V2 line_time(D d, const V2& delta0, const V2& p, V c, const V2& s, M2& ok) {
  const V zero = hn::Zero(d);
  ok = ge(delta0, zero);
  const M2 ahead = ge(p, zero);
  const M2 on_line = eq(delta0, zero);
  // On the line: 2p/c, or 0 when moving inward (0/c = +0). Off it: (p + s)/c or 2 delta0/(s - p).
  const V two = hn::Set(d, 2.0);
  const V2 num = choose(on_line, choose_or_zero(ahead, mul(two, p)), choose(ahead, add(p, s), mul(two, delta0)));
  const V2 den = choose(either(on_line, ahead), c, sub(s, p));
  return div(num, den);
}

/// The argument of line_arrival_time's square root, p^2 + 2 delta0 c.
V2 line_root_argument(D d, const V2& delta0, const V2& p, V c) {
  return add(mul(p, p), mul(mul(hn::Set(d, 2.0), delta0), c));
}

/// The constants of one call, broadcast.
struct Context {
  SideV left, right;
  V zero, one, minus_one, half, two, inf, skip, y_exit, t_max, p_c, max_collisions;
  V code_left, code_right, code_fresh;
  V y_rest, eps_rest, vertex_tolerance, spin_energy, window, slip_tol, height_tol;
  // The watch's speed is glibc's hypot, within an ulp or two of sqrt(u^2 + v^2): a lane decides
  // the slip test only outside this relative margin (and without under- or overflow).
  V below, above, tiny, huge;
  bool low_landing, closed, watch;
};

Context context(D d, const Constants& k) {
  return {broadcast(d, k.side[0]),
          broadcast(d, k.side[1]),
          hn::Zero(d),
          hn::Set(d, 1.0),
          hn::Set(d, -1.0),
          hn::Set(d, 0.5),
          hn::Set(d, 2.0),
          hn::Inf(d),
          hn::Set(d, k.skip_height),
          hn::Set(d, k.y_exit),
          hn::Set(d, k.t_max),
          hn::Set(d, k.p_c),
          hn::Set(d, k.max_collisions),
          hn::Set(d, start_left),
          hn::Set(d, start_right),
          hn::Set(d, start_fresh),
          hn::Set(d, k.y_rest),
          hn::Set(d, k.eps_rest),
          hn::Set(d, k.vertex_tolerance),
          hn::Set(d, k.spin_energy),
          hn::Set(d, k.window),
          hn::Set(d, k.slip_tol),
          hn::Set(d, k.height_tol),
          hn::Set(d, 1.0 - 1e-14),
          hn::Set(d, 1.0 + 1e-14),
          hn::Set(d, 1e-280),
          hn::Set(d, 1e280),
          k.low_landing != 0.0,
          k.closed != 0.0,
          k.watch != 0.0};
}

/// The trajectories of the two tracks, held in registers while they step.
struct Tracks {
  V2 rx, ry, vx, vy, omega, time, impulse, normal_impulse, energy_loss, collisions, start, slid;
  V2 streak, have_last, last_wall, last_x, last_y, prev_x, prev_y;  // the orbit watch's memory
  M2 busy;
};

/// Lanes [0, n) as the first track and [n, 2n) as the second, n = Lanes(d).
HWY_INLINE V2 load(D d, const double* p) { return {hn::Load(d, p), hn::Load(d, p + hn::Lanes(d))}; }

HWY_INLINE void store(D d, const V2& x, double* p) {
  hn::Store(x.a, d, p);
  hn::Store(x.b, d, p + hn::Lanes(d));
}

/// Each lane array of Lanes with the pair that holds it while the tracks step: the trajectories'
/// state, then (from watch_fields on) the orbit watch's memory, moved only with a watch.
struct Field {
  double (Lanes::*lanes)[max_lanes];
  V2 Tracks::*pair;
};
constexpr Field fields[] = {
    {&Lanes::rx, &Tracks::rx},
    {&Lanes::ry, &Tracks::ry},
    {&Lanes::vx, &Tracks::vx},
    {&Lanes::vy, &Tracks::vy},
    {&Lanes::omega, &Tracks::omega},
    {&Lanes::time, &Tracks::time},
    {&Lanes::impulse, &Tracks::impulse},
    {&Lanes::normal_impulse, &Tracks::normal_impulse},
    {&Lanes::energy_loss, &Tracks::energy_loss},
    {&Lanes::collisions, &Tracks::collisions},
    {&Lanes::start, &Tracks::start},
    {&Lanes::slid, &Tracks::slid},
    {&Lanes::streak, &Tracks::streak},
    {&Lanes::have_last, &Tracks::have_last},
    {&Lanes::last_wall, &Tracks::last_wall},
    {&Lanes::last_x, &Tracks::last_x},
    {&Lanes::last_y, &Tracks::last_y},
    {&Lanes::prev_x, &Tracks::prev_x},
    {&Lanes::prev_y, &Tracks::prev_y},
};
constexpr std::size_t watch_fields = 12;

HWY_INLINE Tracks load(D d, const Lanes& L, bool watch) {
  Tracks t;
  const V2 zero{hn::Zero(d), hn::Zero(d)};
#pragma GCC unroll 32  // constant member pointers: straight code, as if written out
  for (std::size_t i = 0; i < std::size(fields); ++i) {
    t.*fields[i].pair = watch || i < watch_fields ? load(d, L.*fields[i].lanes) : zero;
  }
  t.busy = lt(t.start, hn::Set(d, start_idle));
  return t;
}

HWY_INLINE void store(D d, const Tracks& t, Lanes& L, bool watch) {
#pragma GCC unroll 32
  for (std::size_t i = 0; i < std::size(fields); ++i) {
    if (watch || i < watch_fields) store(d, t.*fields[i].pair, L.*fields[i].lanes);
  }
}

/// One round of both tracks: every busy lane whose next event is the common one takes its flight
/// and face collision. Returns the busy lanes whose next event is not (left as they were).
HWY_INLINE M2 round(D d, const Context& c, Tracks& t) {
  const SideV& left = c.left;
  const SideV& right = c.right;
  const V zero = c.zero, one = c.one, half = c.half, two = c.two;
  // A flight that began on one face's line (FlightStart with on_face alone), or a release's
  // first flight (nothing set), is the common case.
  const M2 on_left = eq(t.start, c.code_left);
  const M2 on_right = eq(t.start, c.code_right);
  const M2 fresh = eq(t.start, c.code_fresh);  // (an idle lane has its own code)
  const M2 simple = either(either(on_left, on_right), fresh);
  // The two faces' line times (src/flight.cpp line_time): distance 0 on the face just left;
  // only the other face needs the square root, but both do for a release.
  const V2 p_left = add(mul(t.vx, left.nx), mul(t.vy, left.ny));
  const V2 p_right = add(mul(t.vx, right.nx), mul(t.vy, right.ny));
  const V2 dist_left = add(mul(left.nx, sub(t.rx, left.refx)), mul(left.ny, sub(t.ry, left.refy)));
  const V2 dist_right =
      add(mul(right.nx, sub(t.rx, right.refx)), mul(right.ny, sub(t.ry, right.refy)));
  const V2 delta_left = choose(on_left, zero, dist_left);
  const V2 delta_right = choose(on_right, zero, dist_right);
  const V2 arg_right = line_root_argument(d, delta_right, p_right, right.ny);
  const V2 root = sqrt(choose(on_left, arg_right, line_root_argument(d, delta_left, p_left, left.ny)));
  // The right face's root: `root` after the left face, its own after a release (a second
  // square root only in the rounds that hold one).
  const auto right_root = [&](M fresh_i, V arg_i, V root_i) {
    return hn::AllFalse(d, fresh_i) ? root_i : hn::IfThenElse(fresh_i, hn::Sqrt(arg_i), root_i);
  };
  const V2 root_right{right_root(fresh.a, arg_right.a, root.a), right_root(fresh.b, arg_right.b, root.b)};
  M2 ok_left, ok_right;
  const V2 t_left = line_time(d, delta_left, p_left, left.ny, root, ok_left);
  const V2 t_right = line_time(d, delta_right, p_right, right.ny, root_right, ok_right);
  // The earlier line, the left one on a tie; its face's region must be reached.
  const M2 first_left = le(t_left, t_right);
  const V2 dt = choose(first_left, t_left, t_right);
  const V2 nx = choose(first_left, left.nx, right.nx), ny = choose(first_left, left.ny, right.ny);
  const V2 ax = add(t.rx, mul(t.vx, dt));
  const V2 ay = sub(add(t.ry, mul(t.vy, dt)), mul(mul(half, dt), dt));
  const V2 along =
      add(mul(choose(first_left, left.upx, right.upx), sub(ax, choose(first_left, left.lowx, right.lowx))),
          mul(choose(first_left, left.upy, right.upy), sub(ay, choose(first_left, left.lowy, right.lowy))));
  const V2 new_time = add(t.time, dt);
  M2 common = both(both(t.busy, simple), both(ok_left, ok_right));
  common = both(common, lt(dt, c.inf));
  if (!c.closed) {
    // On the face's region; above every edge arc, ending on a face above them (the search's
    // fast path). A closed V's faces reach the vertex: no region to check, no edge, no exit.
    common = both(common, ge(along, zero));
    const M2 low_ok = eq(choose(first_left, left.low_ok, right.low_ok), one);
    if (c.low_landing) {
      // A face whose region reaches below the edge arcs: the search's slow path then finds no
      // edge (the flight starts and ends strictly above every arc's top: edge_time's first
      // test, on the same y_end = ay) and checks the exit (src/flight.cpp exit_time), which
      // must come later than the face.
      const V2 h = max(sub(t.ry, c.y_exit), zero);
      const V2 exit_root = sqrt(add(mul(t.vy, t.vy), mul(two, h)));
      const V2 t_exit = choose(ge(t.vy, zero), add(t.vy, exit_root), div(mul(two, h), sub(exit_root, t.vy)));
      const M2 high = both(gt(ay, c.skip), gt(t_exit, dt));
      common = both(common, both(gt(t.ry, c.skip), either(low_ok, high)));
    } else {
      common = both(common, both(gt(t.ry, c.skip), low_ok));
    }
  }
  // Within the time cap, and time advances.
  common = both(common, both(le(new_time, c.t_max), gt(new_time, t.time)));

  // The face collision (src/engine.cpp face_collision): the centre put on the face's line.
  const V2 fy = sub(t.vy, dt);
  const V2 delta = add(mul(nx, sub(ax, choose(first_left, left.refx, right.refx))),
                       mul(ny, sub(ay, choose(first_left, left.refy, right.refy))));
  const V2 cx = sub(ax, mul(delta, nx));
  const V2 cy = sub(ay, mul(delta, ny));
  // Walton's law (src/walton.cpp collide), t = (n_y, -n_x).
  const V2 neg_nx = choose(first_left, left.neg_nx, right.neg_nx);
  const V2 p = add(mul(t.vx, nx), mul(fy, ny));
  const V2 q = add(mul(t.vx, ny), mul(fy, neg_nx));
  const V2 slip = add(q, mul(choose(first_left, left.radius, right.radius), t.omega));
  const V2 p_after = mul(choose(first_left, left.neg_e, right.neg_e), p);
  const V2 abs_p = abs(p);
  const V2 j_n = mul(choose(first_left, left.one_plus_e, right.one_plus_e), abs_p);
  const V2 one_plus_beta0 = choose(first_left, left.one_plus_beta0, right.one_plus_beta0);
  const M2 sliding = lt(mul(choose(first_left, left.slide_factor, right.slide_factor), abs_p),
                         mul(one_plus_beta0, abs(slip)));
  const V2 sign = choose(gt(slip, zero), one, c.minus_one);
  const V2 j_slide = mul(mul(choose(first_left, left.mu_neg, right.mu_neg), j_n), sign);
  const V2 j_stick = div(mul(choose(first_left, left.neg_one_plus_beta0, right.neg_one_plus_beta0), slip),
                          choose(first_left, left.reduced, right.reduced));
  const V2 j_t = choose(sliding, j_slide, j_stick);
  const V2 q_after = add(q, j_t);
  const V2 new_vx = add(mul(p_after, nx), mul(q_after, ny));
  const V2 new_vy = add(mul(p_after, ny), mul(q_after, neg_nx));
  const V2 new_omega = add(t.omega, div(j_t, choose(first_left, left.kappa_a, right.kappa_a)));
  const V2 half_1_minus_e2 = choose(first_left, left.half_1_minus_e2, right.half_1_minus_e2);
  const V2 lost = sub(sub(mul(mul(half_1_minus_e2, p), p), mul(j_t, slip)),
                      mul(mul(choose(first_left, left.half_reduced, right.half_reduced), j_t), j_t));
  const V2 j = sqrt(add(mul(j_n, j_n), mul(j_t, j_t)));
  const V2 new_collisions = add(t.collisions, one);
  // No collapse (normal speed at least p_c) and below the collision cap.
  common = both(common, both(ge(p_after, c.p_c), lt(new_collisions, c.max_collisions)));
  if (c.closed) {
    // Energy above the bottom left (src/engine.cpp's rest test after each event).
    const V2 e = add(
        add(mul(half, add(mul(new_vx, new_vx), mul(new_vy, new_vy))), mul(mul(c.spin_energy, new_omega), new_omega)),
        cy);
    common = but_not(lt(sub(e, c.y_rest), c.eps_rest), common);
    // At the vertex to rounding the scalar engine ends the bounces (Run::at_vertex).
    common = both(common, ge(sub(cy, c.y_rest), c.vertex_tolerance));
  }
  if (c.watch) {
    // OrbitWatch::record (src/closed.cpp) for this collision: position (cx, cy), velocity
    // before (vx, fy), slip before, the wall hit.
    const V2 wall = choose(first_left, zero, one);
    const V2 s2 = add(mul(t.vx, t.vx), mul(fy, fy));
    const V2 bound = mul(c.slip_tol, sqrt(s2));
    const V2 abs_slip = abs(slip);
    const M2 sure_no_slip = le(abs_slip, mul(bound, c.below));
    const M2 sure_slip = gt(abs_slip, mul(bound, c.above));
    const M2 decided = both(either(sure_no_slip, sure_slip), both(ge(s2, c.tiny), le(s2, c.huge)));
    const M2 seen = eq(t.have_last, one);
    const M2 alternates = both(seen, ne(wall, t.last_wall));
    const M2 level = both(seen, le(abs(sub(cy, t.last_y)), mul(c.height_tol, abs(cy))));
    const V2 new_streak = choose_or_zero(both(both(alternates, sure_no_slip), level), add(t.streak, one));
    // Decided, and not yet the orbit (the scalar engine ends the run there).
    common = both(common, both(decided, lt(new_streak, c.window)));
    t.streak = choose(common, new_streak, t.streak);
    t.prev_x = choose(common, t.last_x, t.prev_x);
    t.prev_y = choose(common, t.last_y, t.prev_y);
    t.last_x = choose(common, cx, t.last_x);
    t.last_y = choose(common, cy, t.last_y);
    t.last_wall = choose(common, wall, t.last_wall);
    t.have_last = choose(common, one, t.have_last);
  }

  t.rx = choose(common, cx, t.rx);
  t.ry = choose(common, cy, t.ry);
  t.vx = choose(common, new_vx, t.vx);
  t.vy = choose(common, new_vy, t.vy);
  t.omega = choose(common, new_omega, t.omega);
  t.time = choose(common, new_time, t.time);
  t.impulse = choose(common, add(t.impulse, j), t.impulse);
  t.normal_impulse = choose(common, add(t.normal_impulse, j_n), t.normal_impulse);
  t.energy_loss = choose(common, add(t.energy_loss, lost), t.energy_loss);
  t.collisions = choose(common, new_collisions, t.collisions);
  t.slid = choose(both(common, sliding), one, t.slid);
  t.start = choose(common, choose(first_left, c.code_left, c.code_right), t.start);
  return but_not(common, t.busy);
}

/// The bits of `m` (one per lane), shifted to start at bit `offset` of face_steps' answer.
HWY_INLINE std::uint32_t lane_bits(D d, M m, std::size_t offset) {
  alignas(8) std::uint8_t bits[8] = {};
  hn::StoreMaskBits(d, m, bits);
  std::uint32_t out = 0;
  for (int b = 0; b < 4; ++b) out |= static_cast<std::uint32_t>(bits[b]) << (8 * b);
  return out << offset;
}

}  // namespace

std::uint32_t FaceSteps(const Constants& k, Lanes& L) {
  const D d;
  const Context c = context(d, k);
  Tracks t = load(d, L, c.watch);
  std::uint32_t need = 0;
  for (;;) {
    const M2 rest = round(d, c, t);
    if (!hn::AllFalse(d, hn::Or(rest.a, rest.b)) || hn::AllFalse(d, hn::Or(t.busy.a, t.busy.b))) {
      need = lane_bits(d, rest.a, 0) | lane_bits(d, rest.b, hn::Lanes(d));
      break;
    }
  }
  store(d, t, L, c.watch);
  return need;
}

int VectorLanes() { return static_cast<int>(hn::Lanes(D())); }

}  // namespace HWY_NAMESPACE
}  // namespace funnel::batch
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace funnel::batch {

HWY_EXPORT(FaceSteps);
HWY_EXPORT(VectorLanes);

std::uint32_t face_steps(const Constants& k, Lanes& lanes) { return HWY_DYNAMIC_DISPATCH(FaceSteps)(k, lanes); }

int vector_lanes() { return HWY_DYNAMIC_DISPATCH(VectorLanes)(); }

int width() { return tracks * vector_lanes(); }

}  // namespace funnel::batch
#endif

#if HWY_ONCE
#include <atomic>
#include <cstdlib>
#include <mutex>

#include "funnel/simd.hpp"

namespace funnel {

namespace {

struct PathName {
  const char* name;
  std::int64_t target;  // Highway's target bit; 0 for the scalar engine
};

constexpr PathName path_names[] = {
    {"scalar", 0}, {"sse4", HWY_SSE4}, {"avx2", HWY_AVX2}, {"avx512", HWY_AVX3}};

/// The CPU's targets, read before any choice restricts Highway's dispatch.
std::int64_t cpu_targets() {
  static const std::int64_t targets = hwy::SupportedTargets();
  return targets;
}

bool available(const PathName& p) { return p.target == 0 || ((cpu_targets() & HWY_TARGETS & p.target) != 0); }

/// The chosen path's index in path_names; -1 until the first use.
std::atomic<int> chosen{-1};

int choose(std::string_view name) {
  for (int i = 0; i < static_cast<int>(std::size(path_names)); ++i) {
    if (name == path_names[i].name && available(path_names[i])) return i;
  }
  return -1;
}

void apply(int index) {
  // Highway then dispatches to this target only (or, for "scalar", the batch is not used).
  const std::int64_t target = path_names[index].target;
  hwy::SetSupportedTargetsForTest(target == 0 ? 0 : target);
  chosen.store(index);
}

/// The default, once: FUNNEL_SIMD if it names an available path, else the widest available.
void initialise() {
  int index = -1;
  const char* env = std::getenv("FUNNEL_SIMD");
  if (env != nullptr && *env != '\0') index = choose(env);
  for (int i = static_cast<int>(std::size(path_names)) - 1; i >= 0 && index < 0; --i) {
    if (available(path_names[i])) index = i;
  }
  apply(index);
}

int current() {
  static std::once_flag once;
  std::call_once(once, initialise);
  return chosen.load();
}

}  // namespace

std::vector<std::string> simd_paths() {
  std::vector<std::string> out;
  for (const PathName& p : path_names) {
    if (available(p)) out.emplace_back(p.name);
  }
  return out;
}

std::string simd_path() { return path_names[current()].name; }

bool set_simd_path(std::string_view name) {
  current();  // the default first, so that a later first use does not override this choice
  const int index = choose(name);
  if (index < 0) return false;
  apply(index);
  return true;
}

int simd_lanes() { return path_names[current()].target == 0 ? 1 : batch::vector_lanes(); }

}  // namespace funnel
#endif
