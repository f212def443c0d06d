// The batched face-to-face step: trajectories of one funnel in the lanes of a SIMD vector, with
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

/// line_arrival_time (src/roots.cpp) for delta0 >= 0, given s = sqrt(p^2 + 2 delta0 c) where
/// delta0 != 0: one division of the operands the scalar engine divides (the same quotient).
/// `ok` is false where delta0 < 0 (behind the line: the scalar engine decides).
V line_time(D d, V delta0, V p, V c, V s, M& ok) {
  const V zero = hn::Zero(d);
  ok = hn::Ge(delta0, zero);
  const M ahead = hn::Ge(p, zero);
  const M on_line = hn::Eq(delta0, zero);
  // On the line: 2p/c, or 0 when moving inward (0/c = +0). Off it: (p + s)/c or 2 delta0/(s - p).
  const V two = hn::Set(d, 2.0);
  const V num = hn::IfThenElse(on_line, hn::IfThenElseZero(ahead, hn::Mul(two, p)),
                               hn::IfThenElse(ahead, hn::Add(p, s), hn::Mul(two, delta0)));
  const V den = hn::IfThenElse(hn::Or(on_line, ahead), c, hn::Sub(s, p));
  return hn::Div(num, den);
}

/// The argument of line_arrival_time's square root, p^2 + 2 delta0 c.
V line_root_argument(D d, V delta0, V p, V c) {
  return hn::Add(hn::Mul(p, p), hn::Mul(hn::Mul(hn::Set(d, 2.0), delta0), c));
}

V select(M m, V a, V b) { return hn::IfThenElse(m, a, b); }

}  // namespace

std::uint32_t FaceSteps(const Constants& k, Lanes& L) {
  const D d;
  const SideV left = broadcast(d, k.side[0]);
  const SideV right = broadcast(d, k.side[1]);
  const V zero = hn::Zero(d);
  const V one = hn::Set(d, 1.0);
  const V minus_one = hn::Set(d, -1.0);
  const V half = hn::Set(d, 0.5);
  const V two = hn::Set(d, 2.0);
  const V inf = hn::Inf(d);
  const V skip = hn::Set(d, k.skip_height);
  const bool low_landing = k.low_landing != 0.0;
  const V y_exit = hn::Set(d, k.y_exit);
  const V t_max = hn::Set(d, k.t_max);
  const V p_c = hn::Set(d, k.p_c);
  const V max_collisions = hn::Set(d, k.max_collisions);
  const V code_left = hn::Set(d, start_left);
  const V code_right = hn::Set(d, start_right);
  const V code_fresh = hn::Set(d, start_fresh);
  const bool closed = k.closed != 0.0;
  const bool watch = k.watch != 0.0;
  const V y_rest = hn::Set(d, k.y_rest), eps_rest = hn::Set(d, k.eps_rest), spin_energy = hn::Set(d, k.spin_energy);
  const V window = hn::Set(d, k.window), slip_tol = hn::Set(d, k.slip_tol), height_tol = hn::Set(d, k.height_tol);
  // The watch's speed is glibc's hypot, within an ulp or two of sqrt(u^2 + v^2): a lane decides
  // the slip test only outside this relative margin (and without under- or overflow).
  const V below = hn::Set(d, 1.0 - 1e-14), above = hn::Set(d, 1.0 + 1e-14);
  const V tiny = hn::Set(d, 1e-280), huge = hn::Set(d, 1e280);

  V rx = hn::Load(d, L.rx), ry = hn::Load(d, L.ry), vx = hn::Load(d, L.vx), vy = hn::Load(d, L.vy);
  V omega = hn::Load(d, L.omega), time = hn::Load(d, L.time), impulse = hn::Load(d, L.impulse);
  V normal_impulse = hn::Load(d, L.normal_impulse), energy_loss = hn::Load(d, L.energy_loss);
  V collisions = hn::Load(d, L.collisions), start = hn::Load(d, L.start), slid = hn::Load(d, L.slid);
  V streak = hn::Load(d, L.streak), have_last = hn::Load(d, L.have_last), last_wall = hn::Load(d, L.last_wall);
  V last_x = hn::Load(d, L.last_x), last_y = hn::Load(d, L.last_y), prev_x = hn::Load(d, L.prev_x),
    prev_y = hn::Load(d, L.prev_y);
  const M busy = hn::Lt(start, hn::Set(d, start_idle));

  std::uint32_t need = 0;
  for (;;) {
    // A flight that began on one face's line (FlightStart with on_face alone), or a release's
    // first flight (nothing set), is the common case.
    const M on_left = hn::Eq(start, code_left);
    const M on_right = hn::Eq(start, code_right);
    const M fresh = hn::Eq(start, code_fresh);  // (an idle lane has its own code)
    const M simple = hn::Or(hn::Or(on_left, on_right), fresh);
    // The two faces' line times (src/flight.cpp line_time): distance 0 on the face just left;
    // only the other face needs the square root, but both do for a release.
    const V p_left = hn::Add(hn::Mul(vx, left.nx), hn::Mul(vy, left.ny));
    const V p_right = hn::Add(hn::Mul(vx, right.nx), hn::Mul(vy, right.ny));
    const V dist_left = hn::Add(hn::Mul(left.nx, hn::Sub(rx, left.refx)), hn::Mul(left.ny, hn::Sub(ry, left.refy)));
    const V dist_right =
        hn::Add(hn::Mul(right.nx, hn::Sub(rx, right.refx)), hn::Mul(right.ny, hn::Sub(ry, right.refy)));
    const V delta_left = select(on_left, zero, dist_left);
    const V delta_right = select(on_right, zero, dist_right);
    const V arg_right = line_root_argument(d, delta_right, p_right, right.ny);
    const V root = hn::Sqrt(select(on_left, arg_right, line_root_argument(d, delta_left, p_left, left.ny)));
    // The right face's root: `root` after the left face, its own after a release (a second
    // square root only in the rounds that hold one).
    const V root_right = hn::AllFalse(d, fresh) ? root : select(fresh, hn::Sqrt(arg_right), root);
    M ok_left, ok_right;
    const V t_left = line_time(d, delta_left, p_left, left.ny, root, ok_left);
    const V t_right = line_time(d, delta_right, p_right, right.ny, root_right, ok_right);
    // The earlier line, the left one on a tie; its face's region must be reached.
    const M first_left = hn::Le(t_left, t_right);
    const V dt = select(first_left, t_left, t_right);
    const V nx = select(first_left, left.nx, right.nx), ny = select(first_left, left.ny, right.ny);
    const V ax = hn::Add(rx, hn::Mul(vx, dt));
    const V ay = hn::Sub(hn::Add(ry, hn::Mul(vy, dt)), hn::Mul(hn::Mul(half, dt), dt));
    const V along = hn::Add(hn::Mul(select(first_left, left.upx, right.upx), hn::Sub(ax, select(first_left, left.lowx, right.lowx))),
                            hn::Mul(select(first_left, left.upy, right.upy), hn::Sub(ay, select(first_left, left.lowy, right.lowy))));
    const V new_time = hn::Add(time, dt);
    M common = hn::And(hn::And(busy, simple), hn::And(ok_left, ok_right));
    common = hn::And(common, hn::Lt(dt, inf));
    if (!closed) {
      // On the face's region; above every edge arc, ending on a face above them (the search's
      // fast path). A closed V's faces reach the vertex: no region to check, no edge, no exit.
      common = hn::And(common, hn::Ge(along, zero));
      const M low_ok = hn::Eq(select(first_left, left.low_ok, right.low_ok), one);
      if (low_landing) {
        // A face whose region reaches below the edge arcs: the search's slow path then finds no
        // edge (the flight starts and ends strictly above every arc's top: edge_time's first
        // test, on the same y_end = ay) and checks the exit (src/flight.cpp exit_time), which
        // must come later than the face.
        const V h = hn::Max(hn::Sub(ry, y_exit), zero);
        const V exit_root = hn::Sqrt(hn::Add(hn::Mul(vy, vy), hn::Mul(two, h)));
        const V t_exit = select(hn::Ge(vy, zero), hn::Add(vy, exit_root), hn::Div(hn::Mul(two, h), hn::Sub(exit_root, vy)));
        const M high = hn::And(hn::Gt(ay, skip), hn::Gt(t_exit, dt));
        common = hn::And(common, hn::And(hn::Gt(ry, skip), hn::Or(low_ok, high)));
      } else {
        common = hn::And(common, hn::And(hn::Gt(ry, skip), low_ok));
      }
    }
    // Within the time cap, and time advances.
    common = hn::And(common, hn::And(hn::Le(new_time, t_max), hn::Gt(new_time, time)));

    // The face collision (src/engine.cpp face_collision): the centre put on the face's line.
    const V fy = hn::Sub(vy, dt);
    const V delta = hn::Add(hn::Mul(nx, hn::Sub(ax, select(first_left, left.refx, right.refx))),
                            hn::Mul(ny, hn::Sub(ay, select(first_left, left.refy, right.refy))));
    const V cx = hn::Sub(ax, hn::Mul(delta, nx));
    const V cy = hn::Sub(ay, hn::Mul(delta, ny));
    // Walton's law (src/walton.cpp collide), t = (n_y, -n_x).
    const V neg_nx = select(first_left, left.neg_nx, right.neg_nx);
    const V p = hn::Add(hn::Mul(vx, nx), hn::Mul(fy, ny));
    const V q = hn::Add(hn::Mul(vx, ny), hn::Mul(fy, neg_nx));
    const V slip = hn::Add(q, hn::Mul(select(first_left, left.radius, right.radius), omega));
    const V p_after = hn::Mul(select(first_left, left.neg_e, right.neg_e), p);
    const V abs_p = hn::Abs(p);
    const V j_n = hn::Mul(select(first_left, left.one_plus_e, right.one_plus_e), abs_p);
    const V one_plus_beta0 = select(first_left, left.one_plus_beta0, right.one_plus_beta0);
    const M sliding = hn::Lt(hn::Mul(select(first_left, left.slide_factor, right.slide_factor), abs_p),
                             hn::Mul(one_plus_beta0, hn::Abs(slip)));
    const V sign = select(hn::Gt(slip, zero), one, minus_one);
    const V j_slide = hn::Mul(hn::Mul(select(first_left, left.mu_neg, right.mu_neg), j_n), sign);
    const V j_stick = hn::Div(hn::Mul(select(first_left, left.neg_one_plus_beta0, right.neg_one_plus_beta0), slip),
                              select(first_left, left.reduced, right.reduced));
    const V j_t = select(sliding, j_slide, j_stick);
    const V q_after = hn::Add(q, j_t);
    const V new_vx = hn::Add(hn::Mul(p_after, nx), hn::Mul(q_after, ny));
    const V new_vy = hn::Add(hn::Mul(p_after, ny), hn::Mul(q_after, neg_nx));
    const V new_omega = hn::Add(omega, hn::Div(j_t, select(first_left, left.kappa_a, right.kappa_a)));
    const V half_1_minus_e2 = select(first_left, left.half_1_minus_e2, right.half_1_minus_e2);
    const V lost = hn::Sub(hn::Sub(hn::Mul(hn::Mul(half_1_minus_e2, p), p), hn::Mul(j_t, slip)),
                           hn::Mul(hn::Mul(select(first_left, left.half_reduced, right.half_reduced), j_t), j_t));
    const V j = hn::Sqrt(hn::Add(hn::Mul(j_n, j_n), hn::Mul(j_t, j_t)));
    const V new_collisions = hn::Add(collisions, one);
    // No collapse (normal speed at least p_c) and below the collision cap.
    common = hn::And(common, hn::And(hn::Ge(p_after, p_c), hn::Lt(new_collisions, max_collisions)));
    if (closed) {
      // Energy above the bottom left (src/engine.cpp's rest test after each event).
      const V e = hn::Add(hn::Add(hn::Mul(half, hn::Add(hn::Mul(new_vx, new_vx), hn::Mul(new_vy, new_vy))),
                                  hn::Mul(hn::Mul(spin_energy, new_omega), new_omega)),
                          cy);
      common = hn::AndNot(hn::Lt(hn::Sub(e, y_rest), eps_rest), common);
    }
    if (watch) {
      // OrbitWatch::record (src/closed.cpp) for this collision: position (cx, cy), velocity
      // before (vx, fy), slip before, the wall hit.
      const V wall = select(first_left, zero, one);
      const V s2 = hn::Add(hn::Mul(vx, vx), hn::Mul(fy, fy));
      const V bound = hn::Mul(slip_tol, hn::Sqrt(s2));
      const V abs_slip = hn::Abs(slip);
      const M sure_no_slip = hn::Le(abs_slip, hn::Mul(bound, below));
      const M sure_slip = hn::Gt(abs_slip, hn::Mul(bound, above));
      const M decided = hn::And(hn::Or(sure_no_slip, sure_slip), hn::And(hn::Ge(s2, tiny), hn::Le(s2, huge)));
      const M seen = hn::Eq(have_last, one);
      const M alternates = hn::And(seen, hn::Ne(wall, last_wall));
      const M level = hn::And(seen, hn::Le(hn::Abs(hn::Sub(cy, last_y)), hn::Mul(height_tol, hn::Abs(cy))));
      const V new_streak = hn::IfThenElseZero(hn::And(hn::And(alternates, sure_no_slip), level), hn::Add(streak, one));
      // Decided, and not yet the orbit (the scalar engine ends the run there).
      common = hn::And(common, hn::And(decided, hn::Lt(new_streak, window)));
      streak = select(common, new_streak, streak);
      prev_x = select(common, last_x, prev_x);
      prev_y = select(common, last_y, prev_y);
      last_x = select(common, cx, last_x);
      last_y = select(common, cy, last_y);
      last_wall = select(common, wall, last_wall);
      have_last = select(common, one, have_last);
    }

    rx = select(common, cx, rx);
    ry = select(common, cy, ry);
    vx = select(common, new_vx, vx);
    vy = select(common, new_vy, vy);
    omega = select(common, new_omega, omega);
    time = select(common, new_time, time);
    impulse = select(common, hn::Add(impulse, j), impulse);
    normal_impulse = select(common, hn::Add(normal_impulse, j_n), normal_impulse);
    energy_loss = select(common, hn::Add(energy_loss, lost), energy_loss);
    collisions = select(common, new_collisions, collisions);
    slid = select(hn::And(common, sliding), one, slid);
    start = select(common, select(first_left, code_left, code_right), start);

    const M rest = hn::AndNot(common, busy);
    if (!hn::AllFalse(d, rest) || hn::AllFalse(d, busy)) {
      alignas(8) std::uint8_t bits[8] = {};
      hn::StoreMaskBits(d, rest, bits);
      for (int b = 0; b < 4; ++b) need |= static_cast<std::uint32_t>(bits[b]) << (8 * b);
      break;
    }
  }
  hn::Store(rx, d, L.rx);
  hn::Store(ry, d, L.ry);
  hn::Store(vx, d, L.vx);
  hn::Store(vy, d, L.vy);
  hn::Store(omega, d, L.omega);
  hn::Store(time, d, L.time);
  hn::Store(impulse, d, L.impulse);
  hn::Store(normal_impulse, d, L.normal_impulse);
  hn::Store(energy_loss, d, L.energy_loss);
  hn::Store(collisions, d, L.collisions);
  hn::Store(start, d, L.start);
  hn::Store(slid, d, L.slid);
  if (watch) {
    hn::Store(streak, d, L.streak);
    hn::Store(have_last, d, L.have_last);
    hn::Store(last_wall, d, L.last_wall);
    hn::Store(last_x, d, L.last_x);
    hn::Store(last_y, d, L.last_y);
    hn::Store(prev_x, d, L.prev_x);
    hn::Store(prev_y, d, L.prev_y);
  }
  return need;
}

int Width() { return static_cast<int>(hn::Lanes(D())); }

}  // namespace HWY_NAMESPACE
}  // namespace funnel::batch
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace funnel::batch {

HWY_EXPORT(FaceSteps);
HWY_EXPORT(Width);

std::uint32_t face_steps(const Constants& k, Lanes& lanes) { return HWY_DYNAMIC_DISPATCH(FaceSteps)(k, lanes); }

int width() { return HWY_DYNAMIC_DISPATCH(Width)(); }

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

int simd_lanes() { return path_names[current()].target == 0 ? 1 : batch::width(); }

}  // namespace funnel
#endif
