// The 3D engine's face time for many flights at once: the fixed point of cone_face_time
// (src/flight3d.cpp) in the lanes of a SIMD vector, with Highway's run-time dispatch (the path
// chosen for the 2D batch, src/batch.cpp). Each lane performs exactly the scalar iteration's IEEE
// operations in its order (no contraction into fused multiply-adds, -ffp-contract=off; division
// and square root correctly rounded in every lane), so each lane's result is the same bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "batch3d.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "batch3d.hpp"

HWY_BEFORE_NAMESPACE();
namespace funnel::batch {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

/// The lanes [first, first + Lanes(d)) of the flights, as vectors.
struct Group {
  V rx, ry, rz, vx, vy, vz, bx, bz, bx_start, bz_start, t_best, iterations;
  M on_face, active, fallback;
};

Group load(D d, const FaceFlights& f, std::size_t first) {
  Group g;
  g.rx = hn::LoadU(d, f.rx + first);
  g.ry = hn::LoadU(d, f.ry + first);
  g.rz = hn::LoadU(d, f.rz + first);
  g.vx = hn::LoadU(d, f.vx + first);
  g.vy = hn::LoadU(d, f.vy + first);
  g.vz = hn::LoadU(d, f.vz + first);
  g.bx = hn::LoadU(d, f.bx + first);
  g.bz = hn::LoadU(d, f.bz + first);
  g.bx_start = g.bx;
  g.bz_start = g.bz;
  g.t_best = hn::Inf(d);
  g.iterations = hn::Zero(d);
  const V one = hn::Set(d, 1.0);
  g.on_face = hn::Eq(hn::LoadU(d, f.on_face + first), one);
  g.active = hn::Eq(hn::LoadU(d, f.active + first), one);
  g.fallback = hn::FirstN(d, 0);
  return g;
}

/// One iteration of cone_face_time's fixed point in the active lanes (face_step, src/flight3d.cpp).
void iterate(D d, const FaceConstants& k, Group& g) {
  const V zero = hn::Zero(d);
  const V one = hn::Set(d, 1.0);
  const V two = hn::Set(d, 2.0);
  const V neg_sin = hn::Set(d, -k.sin_t), sin_t = hn::Set(d, k.sin_t), cos_t = hn::Set(d, k.cos_t);
  // cone_normal(c, b) = (-sin b_x, cos, -sin b_z); p = v.n; the generator's distance n.r.
  const V nx = hn::Mul(neg_sin, g.bx), nz = hn::Mul(neg_sin, g.bz);
  const V p = hn::Add(hn::Add(hn::Mul(g.vx, nx), hn::Mul(g.vy, cos_t)), hn::Mul(g.vz, nz));
  const V distance = hn::Add(hn::Add(hn::Mul(nx, g.rx), hn::Mul(cos_t, g.ry)), hn::Mul(nz, g.rz));
  const M same = hn::And(g.on_face, hn::And(hn::Eq(g.bx, g.bx_start), hn::Eq(g.bz, g.bz_start)));
  V delta0 = hn::IfThenZeroElse(same, distance);
  // A negative distance up the face from C* (anywhere, if closed) is rounding: 0.
  M snap = hn::Lt(delta0, zero);
  if (!k.closed) {
    const V rho = hn::Add(hn::Mul(g.bx, g.rx), hn::Mul(g.bz, g.rz));
    const V up = hn::Add(hn::Mul(cos_t, hn::Sub(rho, hn::Set(d, k.x_face_end))),
                         hn::Mul(sin_t, hn::Sub(g.ry, hn::Set(d, k.y_face_end))));
    snap = hn::And(snap, hn::Ge(up, zero));
  }
  delta0 = hn::IfThenZeroElse(snap, delta0);
  // line_arrival_time(delta0, p, cos) (src/roots.cpp), its three cases in lanes.
  const M on_line = hn::Eq(delta0, zero);
  const M behind = hn::Lt(delta0, zero);
  const M ahead = hn::Ge(p, zero);
  const V argument = hn::Add(hn::Mul(p, p), hn::Mul(hn::Mul(two, delta0), cos_t));
  const V root = hn::Sqrt(argument);  // NaN where negative: such lanes are `never` below
  const V p_plus_root = hn::Add(p, root);
  const V off_line = hn::IfThenElse(hn::Or(behind, ahead), p_plus_root, hn::Mul(two, delta0));
  const V num = hn::IfThenElse(on_line, hn::IfThenElseZero(ahead, hn::Mul(two, p)), off_line);
  const V den = hn::IfThenElse(hn::Or(hn::Or(on_line, ahead), behind), cos_t, hn::Sub(root, p));
  const M unreachable = hn::And(behind, hn::Or(hn::Le(p, zero), hn::Lt(argument, zero)));
  const V t = hn::IfThenElse(unreachable, hn::Inf(d), hn::Div(num, den));
  // Ends where the generator is never reached or no progress is made.
  const M progress = hn::And(g.active, hn::And(hn::Ne(t, hn::Inf(d)), hn::Lt(t, g.t_best)));
  g.t_best = hn::IfThenElse(progress, t, g.t_best);
  // meridian_direction(advance(s, t).r) (src/cone.cpp).
  const V x = hn::Add(g.rx, hn::Mul(g.vx, t)), z = hn::Add(g.rz, hn::Mul(g.vz, t));
  const V inv = hn::Div(one, hn::Sqrt(hn::Add(hn::Mul(x, x), hn::Mul(z, z))));
  const M z_zero = hn::Eq(z, zero), x_zero = hn::Eq(x, zero);
  const V sign_x = hn::IfThenElse(hn::Gt(x, zero), one, hn::Set(d, -1.0));
  const V bx = hn::IfThenElse(z_zero, hn::IfThenElse(x_zero, one, sign_x), hn::Mul(x, inv));
  const V bz = hn::IfThenElse(z_zero, hn::IfThenElse(x_zero, zero, z), hn::Mul(z, inv));
  // Ends at a fixed point; otherwise the next half-plane, up to the iteration cap.
  const M moved = hn::And(progress, hn::Not(hn::And(hn::Eq(bx, g.bx), hn::Eq(bz, g.bz))));
  g.bx = hn::IfThenElse(moved, bx, g.bx);
  g.bz = hn::IfThenElse(moved, bz, g.bz);
  g.iterations = hn::IfThenElse(moved, hn::Add(g.iterations, one), g.iterations);
  const M capped = hn::And(moved, hn::Eq(g.iterations, hn::Set(d, static_cast<double>(k.max_iterations))));
  g.fallback = hn::Or(g.fallback, capped);
  g.active = hn::AndNot(capped, moved);
}

void store(D d, const Group& g, FaceFlights& f, std::size_t first) {
  hn::StoreU(g.t_best, d, f.t_best + first);
  hn::StoreU(hn::IfThenElseZero(g.fallback, hn::Set(d, 1.0)), d, f.fallback + first);
}

}  // namespace

void FaceTimes(const FaceConstants& k, FaceFlights& f) {
  const D d;
  const std::size_t w = hn::Lanes(d);
  // All groups advance together, one iteration of each in turn (independent dependency chains).
  Group groups[max_flights];
  std::size_t n = 0;
  for (std::size_t first = 0; first < f.n; first += w) groups[n++] = load(d, f, first);
  for (bool any = true; any;) {
    any = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (hn::AllFalse(d, groups[i].active)) continue;
      iterate(d, k, groups[i]);
      any = true;
    }
  }
  for (std::size_t i = 0; i < n; ++i) store(d, groups[i], f, i * w);
}

}  // namespace HWY_NAMESPACE
}  // namespace funnel::batch
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace funnel::batch {

HWY_EXPORT(FaceTimes);

void face_times(const FaceConstants& k, FaceFlights& f) { HWY_DYNAMIC_DISPATCH(FaceTimes)(k, f); }

}  // namespace funnel::batch
#endif
