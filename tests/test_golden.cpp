// Regression guard: a fixed set of trajectories must reproduce their recorded outputs, so that
// no optimisation changes results (tests/data/make_golden.sh regenerates the data).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/grid.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(item);
    return out;
  };
  if (std::getline(in, line)) header = split(line);
  while (std::getline(in, line)) {
    const auto fields = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

double num(const std::map<std::string, std::string>& row, const std::string& key) {
  return *parse_number(row.at(key));
}

TEST(Golden, RecordedTrajectoriesAreReproduced) {
  const auto rows = read_csv(FUNNEL_TEST_DATA_DIR "/golden_trajectories.csv");
  ASSERT_GE(rows.size(), 20u);
  for (const auto& row : rows) {
    Params p = default_params();
    for (const std::string& name : sweep_parameter_names()) {
      std::string key = name;
      for (char& c : key) c = c == '-' ? '_' : c;
      if (row.count(key) != 0) {  // older files: defaults
        ASSERT_TRUE(set_parameter(p, name, num(row, key)));
      }
    }
    ASSERT_FALSE(validate(p).has_value());
    const Trajectory t = simulate_release(p, make_geometry(p), num(row, "release"));
    const std::string where = "theta " + row.at("theta") + " release " + row.at("release");
    EXPECT_EQ(to_string(t.status), row.at("status")) << where;
    EXPECT_EQ(t.collisions, static_cast<std::int64_t>(num(row, "collisions"))) << where;
    EXPECT_EQ(t.edge_collisions, static_cast<std::int64_t>(num(row, "edge_collisions"))) << where;
    EXPECT_EQ(t.contacts, static_cast<std::int64_t>(num(row, "contacts"))) << where;
    EXPECT_TRUE(near(t.duration, num(row, "duration"), 1e-12)) << where;
    EXPECT_TRUE(near(t.impulse, num(row, "impulse"), 1e-12)) << where;
    EXPECT_TRUE(near(t.normal_impulse, num(row, "normal_impulse"), 1e-12)) << where;
    EXPECT_TRUE(near(t.energy_loss, num(row, "energy_loss"), 1e-12, 1e-14)) << where;
    EXPECT_TRUE(near(t.contact_time, num(row, "contact_time"), 1e-12)) << where;
  }
}

}  // namespace
}  // namespace funnel
