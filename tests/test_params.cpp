// Parameter validation and grid parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "funnel/grid.hpp"
#include "funnel/params.hpp"

namespace funnel {
namespace {

TEST(Params, DefaultsAreValidAndMatchTheModel) {
  const Params p = default_params();
  EXPECT_FALSE(validate(p).has_value());
  EXPECT_EQ(p.theta, 60.0);
  EXPECT_EQ(p.e, 0.99);
  EXPECT_EQ(p.mu, 1.0);
  EXPECT_EQ(p.beta0, 0.0);
  EXPECT_EQ(p.radius, 0.01);
  EXPECT_EQ(p.gap, 0.04);
  EXPECT_EQ(p.inertia, 0.4);
}

TEST(Params, EveryInvalidValueIsRejectedWithItsNameValueAndRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* name;
    double value;
  };
  const Case cases[] = {{"theta", 0.0},   {"theta", 90.0},  {"theta", nan},   {"e", -0.1},     {"e", 1.5},
                        {"e", nan},       {"mu", -1.0},     {"mu", inf},      {"beta0", -1.5}, {"beta0", 2.0},
                        {"radius", 0.0},  {"radius", 1.0},  {"radius", nan},  {"gap", 0.01},   {"gap", 0.02},
                        {"gap", -1.0},    {"gap", inf},     {"inertia", 0.0}, {"inertia", nan}, {"t-max", 0.0},
                        {"t-max", inf}};
  for (const Case& c : cases) {
    Params p = default_params();
    ASSERT_TRUE(set_parameter(p, c.name, c.value));
    const auto err = validate(p);
    ASSERT_TRUE(err.has_value()) << c.name << " " << c.value;
    EXPECT_EQ(err->name, c.name);
    EXPECT_NE(err->message().find(c.name), std::string::npos);
    EXPECT_NE(err->message().find("valid range"), std::string::npos);
  }
  Params p = default_params();
  p.max_collisions = 0;
  EXPECT_EQ(validate(p)->name, "max-collisions");
}

TEST(Params, ClosedFunnelTooSteepForTheParticleIsRejected) {
  Params p = default_params();
  p.gap = 0.0;
  p.radius = 0.5;
  p.theta = 70.0;  // release height 1 - a / cos(theta) < 0
  // The radius, changed from its default, is named, with the values that combine in the rule.
  ASSERT_TRUE(validate(p).has_value());
  EXPECT_EQ(validate(p)->name, "radius");
  EXPECT_NE(validate(p)->range.find("(here theta = 70, gap = 0, radius = 0.5, release-height = 1)"), std::string::npos)
      << validate(p)->range;
  p.theta = 45.0;
  EXPECT_FALSE(validate(p).has_value());
  p = default_params();  // the default radius: a low release line is named
  p.gap = 0.0;
  p.release_height = 0.005;
  EXPECT_EQ(validate(p)->name, "release-height");
}

TEST(Params, AWallSoFlatThatTheFunnelIsLostInRoundingIsRejected) {
  // Found by fuzz/fuzz_physics: a right wall at 1.2e-143 degrees reached 1e141 H along the release
  // line; the particle landed 3.4e125 H out and its contact jumped to the edge in no time.
  Params p = default_params();
  p.theta_left = 45.0;
  p.theta_right = 1.2232148717821405e-143;
  std::optional<ParamError> err = validate(p);
  ASSERT_TRUE(err.has_value());
  EXPECT_EQ(err->name, "theta-right");
  EXPECT_NE(err->range.find("half-width (H0 + spout-length + y_b)/tan(theta) at most 1e8 H"), std::string::npos)
      << err->range;
  p.theta_right = 1e-6;  // a reach of 5.7e7 H: allowed
  EXPECT_FALSE(validate(p).has_value());
  p.theta_right = 45.0;
  p.spout_length = 1e9;  // a spout raises the release line, and the reach with it: it is named
  p.gap = 1.0;
  err = validate(p);
  ASSERT_TRUE(err.has_value());
  EXPECT_EQ(err->name, "spout-length");
  p = default_params();  // a gap of 3e8 at 30 degrees: the gap, not the angle
  p.theta = 30.0;
  p.gap = 3e8;
  ASSERT_TRUE(validate(p).has_value());
  EXPECT_EQ(validate(p)->name, "gap");
  p = default_params();  // a release line 1e7 H up at 5 degrees: the release height
  p.theta = 5.0;
  p.release_height = 1e7;
  ASSERT_TRUE(validate(p).has_value());
  EXPECT_EQ(validate(p)->name, "release-height");
}

TEST(Params, AVertexSoDeepThatTheFunnelsHeightIsLostInRoundingIsRejected) {
  // Found by fuzz/fuzz_physics: a right wall within 1.4e-14 degrees of vertical over a gap of 64
  // put the vertex 5.6e16 H below the outlet, and a release exited beyond the walls.
  Params p = default_params();
  p.gap = 63.862753716063573;
  p.theta_left = 45.0;
  p.theta_right = 89.999999999999986;
  const std::optional<ParamError> err = validate(p);
  ASSERT_TRUE(err.has_value());
  EXPECT_EQ(err->name, "theta-right");
  EXPECT_NE(err->range.find("the vertex within 1e8 H of the outlet"), std::string::npos) << err->range;
  p.theta_right = 89.9;  // a steep wall is fine: its vertex is 1.8e4 H down
  EXPECT_FALSE(validate(p).has_value());
  p.theta_left = p.theta_right = 30.0;  // a huge gap at a moderate angle: the gap is named
  p.theta = 30.0;
  p.gap = 1e9;
  ASSERT_TRUE(validate(p).has_value());
  EXPECT_EQ(validate(p)->name, "gap");
  p.theta_left = p.theta_right = p.theta = 60.0;  // above 45 degrees too: the gap, not the angle
  EXPECT_EQ(validate(p)->name, "gap");
}

TEST(Grid, ParsesListsAndInclusiveRanges) {
  std::string err;
  auto v = parse_values("5:85:0.5", err);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->size(), 161u);
  EXPECT_EQ(v->front(), 5.0);
  EXPECT_EQ(v->back(), 85.0);
  EXPECT_EQ((*v)[1], 5.5);
  v = parse_values("0, 1,5", err);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(*v, (std::vector<double>{0.0, 1.0, 5.0}));
  v = parse_values("-0.31:0.31:0.31", err);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->size(), 3u);
  v = parse_values("0.1:0.3:0.1", err);  // 0.3 is included despite rounding
  EXPECT_EQ(v->size(), 3u);
  // Each value is the double of its decimal, as the same number given alone: 0.1 + 2 * 0.1 is
  // 0.30000000000000004, 0.7 + 0.1 is 0.7999999999999999, 0.5 + 7 * 0.01 0.5700000000000001.
  EXPECT_EQ(*v, (std::vector<double>{0.1, 0.2, 0.3}));
  EXPECT_EQ(*parse_values("0.7:0.9:0.1", err), (std::vector<double>{0.7, 0.8, 0.9}));
  v = parse_values("0.5:0.99:0.01", err);
  ASSERT_EQ(v->size(), 50u);
  for (std::size_t i = 0; i < v->size(); ++i) {
    char text[16];
    std::snprintf(text, sizeof text, "0.%02zu", 50 + i);
    EXPECT_EQ((*v)[i], *parse_number(text)) << text;
  }
  EXPECT_EQ(*parse_values("1e-3:5e-3:1e-3", err), (std::vector<double>{0.001, 0.002, 0.003, 0.004, 0.005}));
  EXPECT_EQ((*parse_values("40:50:1e-5", err))[3], 40.00003);
  EXPECT_EQ(*parse_values("-0.3:0.3:0.2", err), (std::vector<double>{-0.3, -0.1, 0.1, 0.3}));
}

TEST(Grid, RejectsMalformedValues) {
  for (const char* bad : {"", "abc", "1,,2", "5:85", "5:85:0", "85:5:1", "1:2:x", "nan", "inf", "1e400", "1:2:3:4"}) {
    std::string err;
    EXPECT_FALSE(parse_values(bad, err).has_value()) << bad;
    EXPECT_FALSE(err.empty()) << bad;
  }
}

TEST(Grid, CartesianProductVariesTheLastAxisFastest) {
  const auto points = expand_grid(default_params(), {{"theta", {40, 50}}, {"mu", {0, 1, 5}}});
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points[0].theta, 40.0);
  EXPECT_EQ(points[0].mu, 0.0);
  EXPECT_EQ(points[2].mu, 5.0);
  EXPECT_EQ(points[3].theta, 50.0);
}

}  // namespace
}  // namespace funnel
