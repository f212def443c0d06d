// Against another program: DynamO's rough-wall trajectory (shared/validation/dynamo-rough-v45.csv).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "funnel/engine.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

struct Row {
  int k;
  double t, x, y, u, v, omega;
};

std::vector<Row> read_rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'k') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    Row r{};
    fields >> r.k >> r.t >> r.x >> r.y >> r.u >> r.v >> r.omega;
    rows.push_back(r);
  }
  return rows;
}

TEST(Validation, FirstTenCollisionsAgreeWithDynamO) {
  const std::vector<Row> rows = read_rows(FUNNEL_VALIDATION_DIR "/dynamo-rough-v45.csv");
  ASSERT_EQ(rows.size(), 10u);
  // The file's parameters: always-sticking Walton law (mu -> infinity), closed V.
  Params p = default_params();
  p.theta = 45.0;
  p.e = 0.99;
  p.beta0 = 0.5;
  p.mu = 1e12;
  p.radius = 0.5;
  p.inertia = 0.4;
  p.gap = 0.0;
  p.max_collisions = 10;
  const Geometry g = make_geometry(p);
  // The file's frame has the wall planes through its origin: its y is ours + a / cos(theta).
  const double shift = p.radius / std::cos(45.0 * 3.14159265358979323846 / 180.0);
  State start;
  start.r = {0.3, 5.0 - shift};
  EventLog log;
  const Trajectory t = simulate(p, g, start, &log);
  ASSERT_EQ(t.collisions, 10);
  ASSERT_EQ(log.events.size(), 10u);
  const char* walls = "RLLRLLRLLR";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Event& e = log.events[i];
    const Row& r = rows[i];
    EXPECT_EQ(e.kind, EventKind::Face);
    EXPECT_EQ(*e.wall, walls[i] == 'L' ? Wall::Left : Wall::Right) << "collision " << r.k;
    EXPECT_TRUE(near(e.time, r.t, 1e-10)) << "collision " << r.k;
    EXPECT_TRUE(near(e.position.x, r.x, 1e-10)) << "collision " << r.k;
    EXPECT_TRUE(near(e.position.y + shift, r.y, 1e-10)) << "collision " << r.k;
    EXPECT_TRUE(near(e.velocity_after.x, r.u, 1e-10)) << "collision " << r.k;
    EXPECT_TRUE(near(e.velocity_after.y, r.v, 1e-10)) << "collision " << r.k;
    EXPECT_TRUE(near(e.omega_after, r.omega, 1e-10)) << "collision " << r.k;
  }
}

}  // namespace
}  // namespace funnel
