// The period-2 orbit of a closed funnel recognised while a trajectory runs (docs/theory.md).
#pragma once

#include <cstdint>
#include <span>

#include "funnel/engine.hpp"

namespace funnel {

/// The periodic test: `window` consecutive collisions that alternate walls, have
/// |slip before| <= slip_tol |velocity before| and repeat the previous collision's height to
/// height_tol relative (the paper's test: the orbit's two collisions are at one height in a
/// mirror-symmetric funnel), or with `two_back` the height of the one before that, on the same
/// wall (a funnel that is not mirror symmetric, where the orbit's two heights differ).
struct OrbitTest {
  int window = 20;
  double slip_tol = 1e-6;
  double height_tol = 1e-6;
  bool two_back = false;
};

/// An EventSink that watches the collisions and ends the run (finished()) once the periodic
/// test has passed `window` times in a row.
class OrbitWatch final : public EventSink {
 public:
  /// What the watch remembers between collisions (public: the batched path carries it in its
  /// lanes, src/engine.cpp).
  struct Memory {
    int streak = 0;          ///< consecutive collisions that passed the test
    bool have_last = false;  ///< a collision has been seen
    bool have_prev = false;  ///< two have (read only by the two_back test, which the lanes do not run; set on leaving them)
    Wall last_wall = Wall::Left;
    Vec2 last, prev;         ///< positions of the last two collisions
  };

  explicit OrbitWatch(const OrbitTest& test) : test_(test) {}

  void record(const Event& e) override;
  bool finished() const override { return memory_.streak >= test_.window; }

  Vec2 last() const { return memory_.last; }
  Vec2 prev() const { return memory_.prev; }
  const OrbitTest& test() const { return test_; }
  Memory& memory() { return memory_; }

 private:
  OrbitTest test_;
  Memory memory_;
};

/// simulate_many (funnel/engine.hpp) with a watch per trajectory: trajectory k reports its
/// events to watches[k] and ends when it has seen the orbit, as simulate(params, f, initial[k],
/// &watches[k]) would, bit for bit. The V's trajectories run in SIMD lanes, the watches' test
/// included.
std::int64_t simulate_many(const Params& params, const Funnel& f, std::span<const State> initial,
                           std::span<Trajectory> out, std::span<OrbitWatch> watches);

}  // namespace funnel
